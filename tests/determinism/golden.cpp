// plume_golden: the cross-build determinism check.
//
// Evaluates a fixed battery of plume functions on fixed inputs (its own generator, no
// library randomness) with float, double and every wide type of this build, hashes the bits
// of the results (FNV-1a; every NaN hashed as one pattern) and prints one line per battery.
//   plume_golden               print the hashes
//   plume_golden --check FILE  compare with FILE's hashes; exit 1 on any difference
// Every deterministic build (scalar, sse2, avx2, avx512) must print the same hashes, and
// every wide type must hash like the scalar one (lane-exactness); tests/determinism/golden.txt
// holds the expected lines. After an intended change of results, regenerate it with
// `plume_golden > tests/determinism/golden.txt` and say why in the commit.
#include <plume/plume.hpp>

#include <fixtures/scenes.hpp>

#include <cmath>

#include <algorithm>
#include <bit>
#include <cinttypes>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

using namespace plume;
using namespace plume::scenes;

namespace plume {
/// a*b + a, so that the battery covers mul_add with two operands.
template <class T>
PLUME_INLINE T mul_add_self(T a, T b) noexcept {
  return plume::mul_add(a, b, a);
}
} // namespace plume

namespace {

/// The element "type" of the batteries that run the dispatched entry points (World::step, the
/// batch casts, the span functions, project_velocities) with the instruction set set_isa chose.
struct dispatched {};

/// One step of 1/60 s: World::step_with<T>, or World::step for `dispatched`.
template <class T>
void advance(World& w) {
  if constexpr (std::is_same_v<T, dispatched>)
    w.step(1.0f / 60.0f);
  else
    w.template step_with<T>(1.0f / 60.0f);
}

struct fnv {
  std::uint64_t h = 1469598103934665603ull;
  template <class S>
  void add(S v) {
    std::uint64_t b;
    if (v != v)
      b = 0x7ff8dead; // any NaN
    else if constexpr (sizeof(S) == 4)
      b = std::bit_cast<std::uint32_t>(v);
    else
      b = std::bit_cast<std::uint64_t>(v);
    for (int i = 0; i < 8; ++i) {
      h ^= (b >> (8 * i)) & 0xff;
      h *= 1099511628211ull;
    }
  }
};

template <class S>
std::vector<S> inputs(double scale) {
  std::vector<S> v;
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  for (int i = 0; i < 4096; ++i) {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    double const u = double(s >> 11) * 0x1.0p-53; // [0, 1)
    double const x = (i % 3 == 0)
                         ? (u - 0.5) * 2 * scale
                         : std::ldexp(u + 0.5, int(s % 200) - 100) * ((s >> 40) & 1 ? 1 : -1);
    v.push_back(static_cast<S>(x));
  }
  for (double a : {0.0, -0.0, 1.0, -1.0, 0.5, 1e30, -1e30, 1e-40, 3.0e38, 1e300, 1e22, 8001.0, 2e8})
    v.push_back(static_cast<S>(a));
  v.push_back(std::numeric_limits<S>::infinity());
  v.push_back(-std::numeric_limits<S>::infinity());
  v.push_back(std::numeric_limits<S>::quiet_NaN());
  v.push_back(std::numeric_limits<S>::denorm_min());
  while (v.size() % 16)
    v.push_back(S(0.25));
  return v;
}

template <class T, class F>
void run_unary(fnv& h, std::vector<scalar_t<T>> const& in, F f) {
  for (std::size_t i = 0; i < in.size(); i += lanes_v<T>) {
    auto const out = to_array(f(load<T>(in.data() + i)));
    for (auto o : out)
      h.add(o);
  }
}
template <class T, class F>
void run_binary(fnv& h, std::vector<scalar_t<T>> const& a, std::vector<scalar_t<T>> const& b, F f) {
  for (std::size_t i = 0; i < a.size(); i += lanes_v<T>) {
    auto const out = to_array(f(load<T>(a.data() + i), load<T>(b.data() + i)));
    for (auto o : out)
      h.add(o);
  }
}

template <class T>
std::uint64_t numerics_battery() {
  using S = scalar_t<T>;
  fnv h;
  auto const x = inputs<S>(10), y = inputs<S>(3);
  std::vector<S> y2(y.rbegin(), y.rend());
#define U(fn)                                                                                      \
  run_unary<T>(h, x, [](auto v) { return plume::fn(v); });                                         \
  run_unary<T>(h, y, [](auto v) { return plume::fn(v); })
#define B(fn) run_binary<T>(h, x, y2, [](auto a, auto b) { return plume::fn(a, b); })
  U(sin);
  U(cos);
  U(tan);
  U(asin);
  U(acos);
  U(atan);
  U(exp);
  U(exp2);
  U(expm1);
  U(log);
  U(log2);
  U(log1p);
  U(sqrt);
  U(floor);
  U(ceil);
  U(round);
  U(round_ties_even);
  U(trunc);
  U(fract);
  U(abs);
  U(signum);
  U(recip);
  B(atan2);
  B(pow);
  B(min);
  B(max);
  B(hypot);
  B(copysign);
  B(mul_add_self);
#undef U
#undef B
  return h.h;
}

/// Velocity projection (3D with multipliers, 2D), brute force and depenetration on 256 fixed
/// problems with 0..15 planes each (lanes of a wide group have different counts).
template <class T>
std::uint64_t solver_battery() {
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>, P = 256, K = 15;
  fnv h;
  auto const r = inputs<double>(1); // 4096 + values; the first few hundred are ordinary
  std::size_t at = 0;
  auto next = [&] {
    double x;
    do
      x = r[at++ % 4000];
    while (!(std::abs(x) <= 1));
    return x;
  };
  auto unit3 = [&] {
    double x, y, z, n;
    do {
      x = next(), y = next(), z = next();
      n = std::sqrt(x * x + y * y + z * z);
    } while (n < 0.1 || n > 1);
    return GVec3<S>{S(x / n), S(y / n), S(z / n)};
  };
  std::vector<GVec3<S>> v(P), n(P * K);
  std::vector<S> depth(P * K);
  std::vector<std::size_t> count(P);
  for (std::size_t p = 0; p < P; ++p) {
    GVec3<S> const dir = unit3(); // two statements: operand order is unspecified
    v[p] = dir * S(1 + 4 * std::abs(next()));
    count[p] = p % (K + 1);
    for (std::size_t i = 0; i < count[p]; ++i) {
      n[p * K + i] = unit3();
      depth[p * K + i] = S(0.3 * next());
    }
  }
  for (std::size_t g = 0; g < P; g += L) {
    GVec3<T> wv;
    std::vector<GVec3<T>> wn(K);
    std::vector<GVec2<T>> wn2(K);
    std::vector<GPenetration<GVec3<T>>> pen(K);
    for (std::size_t l = 0; l < L; ++l) {
      wv = with_lane(wv, l, v[g + l]);
      for (std::size_t i = 0; i < K; ++i) {
        GVec3<S> const ni = n[(g + l) * K + i]; // zero beyond the problem's count
        wn[i] = with_lane(wn[i], l, ni);
        wn2[i] = with_lane(wn2[i], l, GVec2<S>{ni.x, ni.y});
        pen[i].normal = wn[i];
        pen[i].depth = with_lane(pen[i].depth, l, depth[(g + l) * K + i]);
      }
    }
    std::vector<T> lambda(K);
    auto const r3 = project_velocity<T>(wv, wn, lambda);
    auto const bf = project_velocity_bruteforce<T>(wv, wn);
    auto const r2 = project_velocity<T>(GVec2<T>{wv.x, wv.y}, wn2);
    auto const dp = depenetrate(pen);
    // Problem by problem, so that every width hashes in the same order.
    for (std::size_t l = 0; l < L; ++l) {
      auto add3 = [&](GVec3<T> const& a) {
        auto const x = lane(a, l);
        h.add(x.x), h.add(x.y), h.add(x.z);
      };
      add3(r3.velocity);
      h.add(lane(r3.steps, l));
      for (auto const& x : lambda)
        h.add(lane(x, l));
      add3(bf.velocity);
      h.add(lane(r2.velocity.x, l)), h.add(lane(r2.velocity.y, l));
      add3(dp.correction);
      h.add(lane(dp.passes, l));
    }
  }
  return h.h;
}

/// A fixed stream of numbers in [-1, 1] (from inputs(), skipping its special values).
struct stream {
  std::vector<double> r = inputs<double>(1);
  std::size_t at = 0;
  double next() {
    double x;
    do
      x = r[at++ % 4000];
    while (!(std::abs(x) <= 1));
    return x;
  }
  template <class S>
  GVec3<S> vec3(double scale) {
    double const x = next(), y = next(), z = next(); // separate: operand order is unspecified
    return {S(x * scale), S(y * scale), S(z * scale)};
  }
  template <class S>
  GQuat<S> quat() {
    double q[4], n;
    do {
      n = 0;
      for (auto& c : q) {
        c = next();
        n += c * c;
      }
      n = std::sqrt(n);
    } while (n < 0.1 || n > 1);
    return {S(q[0] / n), S(q[1] / n), S(q[2] / n), S(q[3] / n)};
  }
};

/// The wide collision queries on 256 fixed problems: GJK closest points (capsule vs hull),
/// shape casts (sphere vs hull), GJK ray casts (hull) and the closed-form ray casts; lanes
/// hold different hulls (packed), poses, sizes and rays.
template <class T>
std::uint64_t collision_battery() {
  using S = scalar_t<T>;
  constexpr std::size_t L = lanes_v<T>, P = 256, V = 12;
  fnv h;
  stream st;
  std::vector<GVec3<S>> hull_pts(P * V);
  std::vector<GIso3<S>> pa(P), pb(P);
  std::vector<GVec3<S>> motion(P), origin(P), dir(P), ext(P);
  std::vector<S> radius(P), hh(P);
  for (std::size_t p = 0; p < P; ++p) {
    std::vector<GVec3<S>> pts;
    for (std::size_t k = 0; k < V; ++k)
      pts.push_back(st.vec3<S>(1));
    auto const built = GConvexHull<S>::build(pts);
    auto const hv = built.hull.vertices();
    for (std::size_t k = 0; k < V; ++k)
      hull_pts[p * V + k] = hv[k < hv.size() ? k : hv.size() - 1];
    GQuat<S> const qa = st.quat<S>();
    pa[p] = {qa, st.vec3<S>(3)};
    GQuat<S> const qb = st.quat<S>();
    pb[p] = {qb, st.vec3<S>(1)};
    motion[p] = st.vec3<S>(4);
    origin[p] = st.vec3<S>(4);
    dir[p] = st.vec3<S>(1);
    ext[p] = st.vec3<S>(1).abs();
    radius[p] = S(std::abs(st.next()));
    hh[p] = S(std::abs(st.next()));
  }
  for (std::size_t g = 0; g < P; g += L) {
    std::vector<GVec3<T>> verts(V);
    GIso3<T> wa, wb;
    GVec3<T> wm, wo, wd, we;
    T wr{}, wh{};
    for (std::size_t l = 0; l < L; ++l) {
      for (std::size_t k = 0; k < V; ++k)
        verts[k] = with_lane(verts[k], l, hull_pts[(g + l) * V + k]);
      wa = with_lane(wa, l, pa[g + l]), wb = with_lane(wb, l, pb[g + l]);
      wm = with_lane(wm, l, motion[g + l]), wo = with_lane(wo, l, origin[g + l]);
      wd = with_lane(wd, l, dir[g + l]), we = with_lane(we, l, ext[g + l]);
      wr = with_lane(wr, l, radius[g + l]), wh = with_lane(wh, l, hh[g + l]);
    }
    GConvexPolytope<T> const hull{verts};
    auto const cp = closest_points(GCapsule<T>{wh, wr}, wa, hull, wb);
    ShapeCastConfig cfg;
    cfg.max_toi = 2;
    auto const sc = shape_cast(GSphere<T>{wr}, wa, wm, hull, wb, cfg);
    GRay3<T> const ray{wo, wd};
    T const inf = infinity<T>();
    auto const rg = ray_cast_gjk(hull, wb, ray, inf);
    auto const r1 = ray_cast(GCapsule<T>{wh, wr}, wb, ray, inf);
    auto const r2 = ray_cast(GCuboid<T>{we}, wb, ray, inf, false);
    auto const r3 = ray_cast(GCylinder<T>{wh, wr}, wb, ray, inf);
    auto const r4 = ray_cast_local(GTriangle<T>{verts[0], verts[1], verts[2]}, ray, inf);
    // Spheres solid and hollow (the solid cast has its own entry-root path), a solid cuboid
    // (the folded hit test).
    auto const r5 = ray_cast(GSphere<T>{wr + wh}, wb, ray, inf);
    auto const r6 = ray_cast(GSphere<T>{wr + wh}, wb, ray, inf, false);
    auto const r7 = ray_cast(GCuboid<T>{we}, wb, ray, inf);
    for (std::size_t l = 0; l < L; ++l) {
      auto add3 = [&](GVec3<T> const& a) {
        auto const x = lane(a, l);
        h.add(x.x), h.add(x.y), h.add(x.z);
      };
      h.add(lane(cp.distance, l)), add3(cp.point_a), add3(cp.normal), h.add(lane(cp.iterations, l));
      h.add(lane(sc.toi, l)), add3(sc.normal), add3(sc.point_b);
      for (auto const* r : {&rg, &r1, &r2, &r3, &r4, &r5, &r6, &r7})
        h.add(lane(r->toi, l)), add3(r->normal), h.add(lane(r->feature, l));
    }
  }
  return h.h;
}

/// The scalar collision pieces: quickhull, mass properties, EPA and manifolds on 128 fixed
/// pairs.
template <class S>
std::uint64_t contact_battery() {
  fnv h;
  stream st;
  auto add3 = [&](GVec3<S> const& x) { h.add(x.x), h.add(x.y), h.add(x.z); };
  for (int p = 0; p < 128; ++p) {
    std::vector<GVec3<S>> pa, pb;
    for (int k = 0; k < 8 + p % 20; ++k)
      pa.push_back(st.vec3<S>(1));
    for (int k = 0; k < 6 + p % 13; ++k)
      pb.push_back(st.vec3<S>(0.7));
    auto const ha = GConvexHull<S>::build(pa), hb = GConvexHull<S>::build(pb);
    for (auto const* b : {&ha, &hb}) {
      h.add(S(b->hull.faces().size()));
      for (auto const& v : b->hull.vertices())
        add3(v);
      auto const mp = b->hull.mass_properties(S(2));
      h.add(mp.mass), add3(mp.center), add3(mp.inertia.x_axis), add3(mp.inertia.y_axis);
    }
    GQuat<S> const qa = st.quat<S>();
    GIso3<S> const posa{qa, st.vec3<S>(0.8)};
    GQuat<S> const qb = st.quat<S>();
    GIso3<S> const posb{qb, st.vec3<S>(0.8)};
    auto const pen = penetration(ha.hull, posa, hb.hull, posb);
    h.add(pen.depth), add3(pen.normal), add3(pen.point_a), h.add(S(pen.iterations));
    auto const m1 = contact_manifold(GCuboid<S>{pa[0].abs() + GVec3<S>::splat(S(0.2))}, posa,
                                     GCuboid<S>{pb[0].abs() + GVec3<S>::splat(S(0.2))}, posb);
    auto const m2 = contact_manifold(GCapsule<S>{S(0.5), S(0.2)}, posa, hb.hull, posb);
    auto const m3 = contact_manifold(ha.hull, posa, GHalfSpace<S>{GVec3<S>::Y}, posb);
    for (auto const* m : {&m1, &m2, &m3}) {
      add3(m->normal);
      h.add(S(m->count));
      for (auto const& c : *m) {
        add3(c.point_a), add3(c.point_b), h.add(c.separation);
        h.add(S(double(c.id % 1000003)));
      }
    }
  }
  return h.h;
}

/// The rigid-body world: a small pyramid, a stack, a ramp and one body of every shape kind
/// (with restitution, damping and a kinematic pusher), 150 steps solved lanes_v<T> contacts
/// at a time; the hash of every pose and velocity.
template <class T>
std::uint64_t world_battery() {
  World w;
  add_ground(w);
  add_box_pyramid(w, 5);
  add_box_stack(w, 4, 0.5f);
  add_ramp(w, 0.3f, {8.0f, 2.0f, 0.0f}, 8.0f, 3.0f);
  stream st;
  std::vector<Vec3> cloud;
  for (int k = 0; k < 20; ++k)
    cloud.push_back(st.vec3<float>(0.4));
  BodyShape const shapes[] = {Sphere{0.3f}, Capsule{0.4f, 0.2f}, Cuboid{{0.3f, 0.2f, 0.4f}},
                              Cylinder{0.3f, 0.25f}, GConvexHull<float>::build(cloud).hull};
  for (int i = 0; i < 10; ++i) {
    BodyDef def;
    def.shape = shapes[i % 5];
    def.pose =
        Iso3{st.quat<float>(), Vec3{6.0f + 0.4f * float(i), 3.0f + float(i), 0.2f * float(i % 3)}};
    def.linear_velocity = st.vec3<float>(2);
    def.angular_velocity = st.vec3<float>(3);
    def.restitution = i % 2 == 0 ? 0.4f : 0.0f;
    def.linear_damping = 0.1f;
    def.angular_damping = 0.2f;
    w.create_body(def);
  }
  BodyDef pusher;
  pusher.type = BodyType::kinematic;
  pusher.shape = Cuboid{Vec3::splat(0.5f)};
  pusher.pose = Iso3::from_translation({-4.0f, 0.5f, 0.0f});
  pusher.linear_velocity = {1.0f, 0.0f, 0.0f};
  w.create_body(pusher);
  for (int s = 0; s < 150; ++s)
    advance<T>(w);
  return w.state_hash();
}

/// Joints: two ragdolls falling on the ground, a chain with a heavy end, a car driving on
/// motorised hinges, a prismatic lift and a spring, with a joint destroyed, a motor retargeted
/// and a joint broken mid-run; 150 steps solved lanes_v<T> joints and contacts at a time.
template <class T>
std::uint64_t joint_battery() {
  World w;
  add_ground(w);
  add_ragdoll(w, {0.0f, 1.3f, 0.0f});
  Jointed const doll = add_ragdoll(w, {1.2f, 2.0f, 0.6f});
  w.set_velocity(doll.bodies[4], {1.0f, 0.0f, 2.0f}, {});
  Jointed const chain = add_chain(w, {-4.0f, 7.0f, 0.0f}, 10, 0.5f, 20.0f);
  Jointed const car = add_car(w, {4.0f, 0.62f, 2.0f});
  for (JointId j : car.joints)
    w.set_motor_targets(j, -4.0f, 0.0f);
  BodyId const post = w.create_body({.type = BodyType::static_body,
                                     .pose = Iso3::from_translation({-2.0f, 3.0f, -3.0f}),
                                     .shape = Sphere{0.05f}})
                          .id;
  BodyId const lift = w.create_body({.pose = Iso3::from_translation({-2.0f, 2.0f, -3.0f}),
                                     .shape = Cuboid{Vec3::splat(0.2f)}})
                          .id;
  w.create_joint({.body_a = post,
                  .body_b = lift,
                  .frame_a = w.joint_frame(post, {-2.0f, 2.0f, -3.0f}, Vec3::Y),
                  .frame_b = w.joint_frame(lift, {-2.0f, 2.0f, -3.0f}, Vec3::Y),
                  .type = PrismaticJoint{.limit_enabled = true,
                                         .lower_translation = -1.0f,
                                         .upper_translation = 0.5f,
                                         .motor = Motor::velocity_control(1.0f, 500.0f)}});
  BodyId const bob =
      w.create_body({.pose = Iso3::from_translation({-2.0f, 2.0f, -5.0f}), .shape = Sphere{0.2f}})
          .id;
  w.create_joint(
      {.body_a = post,
       .body_b = bob,
       .frame_a = w.joint_frame(post, {-2.0f, 3.0f, -3.0f}, Vec3::X),
       .frame_b = w.joint_frame(bob, {-2.0f, 2.0f, -5.0f}, Vec3::X),
       .type = DistanceJoint{
           .rest_length = 1.5f, .spring_enabled = true, .frequency = 2.0f, .damping_ratio = 0.3f}});
  BodyId const weight = w.create_body({.pose = Iso3::from_translation({3.0f, 5.0f, -3.0f}),
                                       .shape = Cuboid{Vec3::splat(0.3f)}})
                            .id;
  BodyId const hook = w.create_body({.type = BodyType::static_body,
                                     .pose = Iso3::from_translation({3.0f, 5.5f, -3.0f}),
                                     .shape = Sphere{0.05f}})
                          .id;
  w.create_joint({.body_a = hook,
                  .body_b = weight,
                  .frame_a = w.joint_frame(hook, {3.0f, 5.5f, -3.0f}, Vec3::X),
                  .frame_b = w.joint_frame(weight, {3.0f, 5.5f, -3.0f}, Vec3::X),
                  .type = FixedJoint{},
                  .break_force = 3000.0f});
  std::uint64_t broken = 0;
  for (int s = 0; s < 150; ++s) {
    if (s == 50) w.destroy_joint(chain.joints[5]);
    if (s == 70)
      for (JointId j : car.joints)
        w.set_motor_targets(j, 2.0f, 0.0f);
    if (s == 90) w.set_velocity(weight, {0.0f, -30.0f, 0.0f}, {}); // breaks its weld
    advance<T>(w);
    broken += w.events().joint_broken.size() * std::uint64_t(s + 1);
  }
  return (w.state_hash() ^ broken) * 1099511628211ull;
}

/// Destroying and creating bodies and standalone colliders mid-run (slots reused at their next
/// generation; a collider teleported, one destroyed), then the world's queries: the state and
/// the rays' hits (collider, toi bits) hashed together.
template <class T>
std::uint64_t world_edit_battery() {
  World w;
  add_ground(w);
  std::vector<BodyId> const boxes = add_box_pyramid(w, 5);
  stream st;
  for (int s = 0; s < 40; ++s)
    advance<T>(w);
  for (std::size_t k = 0; k < boxes.size(); k += 3)
    w.destroy_body(boxes[k]);
  // Standalone colliders take freed slots: a tilted slab, a post and a trigger.
  ColliderId const slab =
      w.create_collider({.pose = Iso3{Quat::from_rotation_z(0.2f), {-1.0f, 2.5f, 0.0f}},
                         .shape = Cuboid{{1.0f, 0.1f, 1.0f}}})
          .id;
  ColliderId const post = w.create_collider({.pose = Iso3::from_translation({1.5f, 3.0f, 0.0f}),
                                             .shape = Capsule{0.5f, 0.2f}})
                              .id;
  w.create_collider(
      {.pose = Iso3::from_translation({0.0f, 4.0f, 0.0f}), .shape = Sphere{1.0f}, .sensor = true});
  for (int s = 0; s < 30; ++s)
    advance<T>(w);
  w.set_collider_pose(slab, Iso3{Quat::from_rotation_z(-0.2f), {-0.5f, 4.5f, 0.2f}});
  w.destroy_collider(post);
  for (int i = 0; i < 6; ++i) {
    BodyDef def;
    def.shape = i % 2 ? BodyShape{Sphere{0.3f}} : BodyShape{Cuboid{{0.3f, 0.2f, 0.4f}}};
    def.pose =
        Iso3{st.quat<float>(), Vec3{0.5f * float(i) - 1.5f, 6.0f + float(i), 0.1f * float(i)}};
    def.linear_velocity = st.vec3<float>(1);
    w.create_body(def);
  }
  for (int s = 0; s < 90; ++s)
    advance<T>(w);
  std::uint64_t h = w.state_hash();
  for (int k = 0; k < 16; ++k) {
    auto const hit =
        w.ray_cast({{float(k) * 0.5f - 4.0f, 10.0f, 0.25f}, {0.05f, -1.0f, 0.0f}}, 50.0f);
    std::uint32_t const bits =
        hit ? std::bit_cast<std::uint32_t>(hit->toi) ^ (hit->collider.index << 20) : 0u;
    h = (h ^ bits) * 1099511628211ull;
  }
  return h;
}

/// A dynamic tree through an edit sequence (inserts, moves, removes, every optimisation mode,
/// a bulk insert), hashed node by node (structure and boxes), then rays and box queries through
/// its wide copy at width T: the same operations give the same tree in every build, and every
/// width finds the same leaves.
template <class T>
std::uint64_t tree_battery() {
  stream st;
  AabbTree tree;
  std::vector<ProxyId> ids;
  auto const box = [&](double spread) {
    Vec3 const c = st.vec3<float>(spread);
    Vec3 const e = st.vec3<float>(0.5).abs() + Vec3::splat(0.01f);
    return Aabb3{c - e, c + e};
  };
  for (int i = 0; i < 300; ++i)
    ids.push_back(tree.insert(box(20.0), std::uint64_t(i)));
  TreeOptimization const modes[] = {TreeOptimization::reinsert, TreeOptimization::partial_rebuild,
                                    TreeOptimization::full_rebuild, TreeOptimization::adaptive};
  for (int round = 0; round < 8; ++round) {
    for (std::size_t k = std::size_t(round); k < ids.size(); k += 3)
      tree.move(ids[k], box(20.0));
    tree.optimize(modes[round % 4]);
  }
  for (std::size_t k = 0; k < ids.size(); k += 5)
    tree.remove(ids[k]);
  std::vector<Aabb3> bulk;
  for (int i = 0; i < 100; ++i)
    bulk.push_back(box(30.0));
  tree.insert_all(bulk);
  tree.optimize();
  // The other builder too: PLOC over the same leaves.
  TreeConfig ploc;
  ploc.builder = TreeBuilder::ploc;
  AabbTree other(ploc);
  std::vector<Aabb3> leaves;
  for (ProxyId id : tree.proxy_ids())
    leaves.push_back(tree.tight_box(id));
  other.insert_all(leaves);
  fnv h;
  for (auto const& node : other.nodes()) {
    h.add(std::bit_cast<float>(node.left));
    h.add(node.box.min.x + node.box.max.y - node.box.min.z);
  }
  for (auto const& node : tree.nodes()) {
    h.add(float(node.height));
    h.add(std::bit_cast<float>(node.left));
    h.add(std::bit_cast<float>(node.proxy));
    for (float v : {node.box.min.x, node.box.min.y, node.box.min.z, node.box.max.x, node.box.max.y,
                    node.box.max.z})
      h.add(v);
  }
  GWideBvh<T> const wide(tree);
  for (int k = 0; k < 32; ++k) {
    Ray3 const ray{st.vec3<float>(40.0), st.vec3<float>(1.0)};
    TreeRayHit const hit = wide.ray_cast(ray, 100.0f, [&](ProxyId id, float max_toi) {
      return plume::detail::ray_box_entry(ray, tree.tight_box(id), max_toi); // the tight box
    });
    h.add(std::bit_cast<float>(hit.proxy));
    h.add(hit.toi);
    int met = 0;
    wide.query(box(20.0), [&](ProxyId id) { return h.add(std::bit_cast<float>(id)), ++met, true; });
    h.add(float(met));
  }
  return h.h;
}

/// Bodies dropped on a terrain mesh and a terrain height field side by side (contacts with
/// corrected internal edges, several manifolds per pair), then rays, casts and contact
/// queries against both.
template <class T>
std::uint64_t world_mesh_battery() {
  auto const height = [](float x, float z) {
    // plume's own sin and cos: libm's may differ between machines.
    return 0.6f * plume::sin(0.8f * x) * plume::cos(0.6f * z) + 0.15f * plume::sin(2.1f * x + z);
  };
  constexpr std::uint32_t n = 12; // cells a side, 1 m each
  std::vector<Vec3> verts;
  std::vector<float> heights;
  for (std::uint32_t z = 0; z <= n; ++z)
    for (std::uint32_t x = 0; x <= n; ++x) {
      verts.push_back({float(x), height(float(x), float(z)), float(z)});
      heights.push_back(height(float(x), float(z)));
    }
  std::vector<std::uint32_t> idx;
  for (std::uint32_t z = 0; z < n; ++z)
    for (std::uint32_t x = 0; x < n; ++x) {
      std::uint32_t const a = z * (n + 1) + x, b = a + 1, c = a + n + 1, d = c + 1;
      idx.insert(idx.end(), {a, c, b, b, c, d});
    }
  auto mesh = TriangleMesh::build(verts, idx);
  auto field = HeightField::build(n + 1, n + 1, heights, 1.0f, 1.0f);
  if (!mesh.ok() || !field.ok()) {
    std::printf("world_mesh: the terrain did not build\n");
    std::exit(1);
  }
  World w;
  w.create_body({.type = BodyType::static_body,
                 .pose = Iso3::from_translation({-12.0f, 0.0f, -6.0f}),
                 .shape = MeshShape{std::make_shared<TriangleMesh const>(std::move(mesh.mesh))}});
  w.create_body(
      {.type = BodyType::static_body,
       .pose = Iso3{Quat::from_axis_angle(Vec3::Y, 0.3f), {1.0f, 0.0f, -6.0f}},
       .shape = HeightFieldShape{std::make_shared<HeightField const>(std::move(field.field))}});
  stream st;
  for (int i = 0; i < 16; ++i) {
    BodyDef def;
    def.shape = i % 3 == 0   ? BodyShape{Sphere{0.3f}}
                : i % 3 == 1 ? BodyShape{Cuboid{{0.3f, 0.2f, 0.4f}}}
                             : BodyShape{Capsule{0.25f, 0.2f}};
    def.pose = Iso3{st.quat<float>(), Vec3{1.4f * float(i) - 11.0f, 2.0f + 0.1f * float(i),
                                           0.3f * float(i % 5) - 0.5f}};
    def.linear_velocity = st.vec3<float>(1);
    w.create_body(def);
  }
  std::size_t most = 0; // the scene must hold a pair with several contacts
  for (int s = 0; s < 120; ++s) {
    advance<T>(w);
    std::map<std::uint64_t, std::size_t> per_pair;
    for (Contact const& c : w.contacts())
      most = std::max(most, ++per_pair[body_pair_key(c.body_a, c.body_b)]);
  }
  if (most < 2) {
    std::printf("world_mesh: no pair ever had two contacts\n");
    std::exit(1);
  }
  std::uint64_t h = w.state_hash();
  auto const mix = [&](float x) { h = (h ^ std::bit_cast<std::uint32_t>(x)) * 1099511628211ull; };
  for (int k = 0; k < 16; ++k) {
    Vec3 const o{1.5f * float(k) - 12.0f, 5.0f, 0.4f * float(k % 4)};
    auto const ray = w.ray_cast({o, {0.1f, -1.0f, 0.05f}}, 50.0f);
    mix(ray ? ray->toi : -1.0f);
    auto const cast =
        w.shape_cast(Cuboid{{0.2f, 0.2f, 0.2f}}, Iso3::from_translation(o), {0.0f, -8.0f, 0.1f});
    mix(cast ? cast->toi : -1.0f);
    w.contact_query(Sphere{0.5f}, Iso3::from_translation({o.x, 0.3f, o.z}), 0.05f,
                    [&](ColliderId, Manifold const& m) {
                      for (ContactPoint const& c : m)
                        mix(c.separation);
                      return true;
                    });
  }
  // The batch forms: a fan of 37 rays and 19 shape casts of three kinds, lanes_v<T> at a time
  // (or the dispatched width).
  std::vector<Ray3> rays;
  for (int k = 0; k < 37; ++k)
    rays.push_back({{0.5f * float(k) - 9.0f, 4.0f, 0.2f * float(k % 7) - 6.5f},
                    {0.02f * float(k % 5) - 0.04f, -1.0f, 0.03f * float(k % 3)}});
  std::vector<BodyShape> shapes;
  std::vector<Iso3> poses;
  std::vector<Vec3> motions;
  for (int k = 0; k < 19; ++k) {
    if (k % 3 == 0)
      shapes.emplace_back(Sphere{0.25f});
    else if (k % 3 == 1)
      shapes.emplace_back(Capsule{0.3f, 0.2f});
    else
      shapes.emplace_back(Cuboid{{0.2f, 0.15f, 0.3f}});
    poses.push_back(
        Iso3{st.quat<float>(), {0.9f * float(k) - 9.0f, 3.0f, 0.3f * float(k % 4) - 5.0f}});
    motions.push_back({0.1f * float(k % 3), -6.0f, 0.05f});
  }
  std::vector<std::optional<WorldRayHit>> ray_hits(rays.size());
  std::vector<std::optional<WorldShapeHit>> shape_hits(shapes.size());
  if constexpr (std::is_same_v<T, dispatched>) {
    w.ray_cast(rays, 50.0f, ray_hits);
    w.shape_cast(shapes, poses, motions, ShapeCastConfig{}, shape_hits);
  } else {
    w.template ray_cast_with<T>(rays, 50.0f, ray_hits);
    w.template shape_cast_with<T>(shapes, poses, motions, ShapeCastConfig{}, shape_hits);
  }
  for (auto const& r : ray_hits) {
    mix(r ? r->toi : -1.0f);
    mix(r ? r->normal.y : -1.0f);
  }
  for (auto const& c : shape_hits) {
    mix(c ? c->toi : -1.0f);
    mix(c ? c->normal.y : -1.0f);
    mix(c ? c->point.x : -1.0f);
  }
  return h;
}

/// The math functions over spans (numerics/spans.hpp) on the battery's inputs, against the
/// same functions element by element: T is S (the templates, one element at a time) or
/// `dispatched` (the span calls of the chosen set).
template <class T, class S>
std::uint64_t spans_battery() {
  fnv h;
  auto const x = inputs<S>(10), y = inputs<S>(3);
  std::vector<S> y2(y.rbegin(), y.rend()), out(x.size()), out2(x.size());
  auto const add = [&](std::vector<S> const& v) {
    for (S e : v)
      h.add(e);
  };
#define U(fn)                                                                                      \
  if constexpr (std::is_same_v<T, dispatched>)                                                     \
    (void)plume::fn(std::span<S const>(x), std::span<S>(out));                                     \
  else                                                                                             \
    std::transform(x.begin(), x.end(), out.begin(), [](S v) { return plume::fn(v); });             \
  add(out)
#define B(fn)                                                                                      \
  if constexpr (std::is_same_v<T, dispatched>)                                                     \
    (void)plume::fn(std::span<S const>(x), std::span<S const>(y2), std::span<S>(out));             \
  else                                                                                             \
    std::transform(x.begin(), x.end(), y2.begin(), out.begin(),                                    \
                   [](S a, S b) { return plume::fn(a, b); });                                      \
  add(out)
  U(sin);
  U(cos);
  U(tan);
  U(asin);
  U(acos);
  U(atan);
  U(exp);
  U(exp2);
  U(expm1);
  U(log);
  U(log2);
  U(log1p);
  U(sqrt);
  B(atan2);
  B(pow);
  B(hypot);
#undef U
#undef B
  if constexpr (std::is_same_v<T, dispatched>) {
    (void)plume::sincos(std::span<S const>(x), std::span<S>(out), std::span<S>(out2));
  } else {
    for (std::size_t i = 0; i < x.size(); ++i) {
      auto const r = plume::sincos(x[i]);
      out[i] = r.sin;
      out2[i] = r.cos;
    }
  }
  add(out);
  add(out2);
  return h.h;
}

/// Batches of velocity projections (project_velocities, 3D and 2D, with multipliers) against
/// the single call problem by problem: T is float or `dispatched`.
template <class T>
std::uint64_t projection_batch_battery() {
  fnv h;
  stream st;
  constexpr std::size_t P = 301;
  auto const run = [&]<class Vec>(Vec) {
    std::vector<Vec> v, n;
    std::vector<std::uint32_t> offsets{0};
    for (std::size_t p = 0; p < P; ++p) {
      GVec3<float> const a = st.vec3<float>(4);
      if constexpr (Vec::dim == 3)
        v.push_back(a);
      else
        v.push_back({a.x, a.y});
      for (std::size_t i = 0; i < (p * 7) % 13; ++i) {
        GVec3<float> c = st.vec3<float>(1);
        if (c.dot(a) > 0.0f) c = c * -1.0f; // facing the velocity: planes that bind
        if constexpr (Vec::dim == 3)
          n.push_back(c);
        else
          n.push_back({c.x, c.y});
      }
      offsets.push_back(static_cast<std::uint32_t>(n.size()));
    }
    std::vector<GVelocityProjection<Vec>> out(P);
    std::vector<float> lambda(n.size());
    if constexpr (std::is_same_v<T, dispatched>) {
      if (project_velocities(std::span<Vec const>(v), std::span<Vec const>(n), offsets, out,
                             lambda) != ProjectVelocitiesError::none)
        std::exit(2);
    } else {
      for (std::size_t p = 0; p < P; ++p)
        out[p] = project_velocity<float>(
            v[p], std::span<Vec const>(n.data() + offsets[p], offsets[p + 1] - offsets[p]),
            std::span<float>(lambda.data() + offsets[p], offsets[p + 1] - offsets[p]));
    }
    for (auto const& r : out) {
      h.add(r.velocity.x), h.add(r.velocity.y), h.add(r.steps);
      if constexpr (Vec::dim == 3) h.add(r.velocity.z);
      h.add(float(r.converged) + 2.0f * float(r.invalid_input));
    }
    for (float l : lambda)
      h.add(l);
  };
  run(Vec3{});
  run(Vec2{});
  return h.h;
}

} // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::uint64_t> got;
  bool lanes_ok = true;
  auto record = [&](char const* name, std::uint64_t scalar_hash,
                    std::vector<std::uint64_t> const& wide) {
    got[name] = scalar_hash;
    for (auto w : wide)
      if (w != scalar_hash) {
        std::printf("LANE MISMATCH in %s: a wide type hashes %016" PRIx64 ", scalar %016" PRIx64
                    "\n",
                    name, w, scalar_hash);
        lanes_ok = false;
      }
  };
  // Each battery's hash for the scalar type, then for every width of the build.
  auto battery = [&]<class List>(char const* name, List, auto run) {
    std::vector<std::uint64_t> wide;
    for_each_type<List>([&]<class T>() { wide.push_back(run.template operator()<T>()); });
    record(name, run.template operator()<float>(), wide);
  };
  auto battery64 = [&]<class List>(char const* name, List, auto run) {
    std::vector<std::uint64_t> wide;
    for_each_type<List>([&]<class T>() { wide.push_back(run.template operator()<T>()); });
    record(name, run.template operator()<double>(), wide);
  };
  battery("numerics_f32", f32_widths{}, []<class T>() { return numerics_battery<T>(); });
  battery64("numerics_f64", f64_widths{}, []<class T>() { return numerics_battery<T>(); });
  battery("solver_f32", f32_widths{}, []<class T>() { return solver_battery<T>(); });
  battery64("solver_f64", f64_widths{}, []<class T>() { return solver_battery<T>(); });
  battery("collision_f32", f32_widths{}, []<class T>() { return collision_battery<T>(); });
  battery64("collision_f64", f64_widths{}, []<class T>() { return collision_battery<T>(); });
  record("contact_f32", contact_battery<float>(), {});
  battery("world_f32", f32_widths{}, []<class T>() { return world_battery<T>(); });
  battery("world_edit_f32", f32_widths{}, []<class T>() { return world_edit_battery<T>(); });
  battery("joints_f32", f32_widths{}, []<class T>() { return joint_battery<T>(); });
  battery("world_mesh_f32", f32_widths{}, []<class T>() { return world_mesh_battery<T>(); });
  battery("tree_f32", f32_widths{}, []<class T>() { return tree_battery<T>(); });
  record("contact_f64", contact_battery<double>(), {});
  record("spans_f32", spans_battery<float, float>(), {});
  record("spans_f64", spans_battery<double, double>(), {});
  record("projection_batch_f32", projection_batch_battery<float>(), {});
  // The dispatched entry points once per instruction set the binary carries (one in a static
  // build, sse2, avx2 and avx512 in a PLUME_DISPATCH=ON build) and this CPU runs, each against
  // the scalar hash above: every set gives the same bits, in one process.
  std::string ran, skipped;
  for (Isa const isa : compiled_isas()) {
    if (!cpu_has(isa)) {
      skipped += ' ';
      skipped += isa_name(isa);
      continue;
    }
    if (set_isa(isa) != IsaError::none) {
      std::printf("set_isa(%s) refused a set the CPU runs\n", std::string(isa_name(isa)).c_str());
      return 1;
    }
    ran += ' ';
    ran += isa_name(isa);
    auto const same_as = [&](char const* name, std::uint64_t hash) {
      if (hash == got.at(name)) return;
      std::printf("ISA MISMATCH in %s: %s hashes %016" PRIx64 ", scalar %016" PRIx64 "\n", name,
                  std::string(isa_name(isa)).c_str(), hash, got.at(name));
      lanes_ok = false;
    };
    same_as("world_f32", world_battery<dispatched>());
    same_as("world_edit_f32", world_edit_battery<dispatched>());
    same_as("joints_f32", joint_battery<dispatched>());
    same_as("world_mesh_f32", world_mesh_battery<dispatched>());
    same_as("spans_f32", spans_battery<dispatched, float>());
    same_as("spans_f64", spans_battery<dispatched, double>());
    same_as("projection_batch_f32", projection_batch_battery<dispatched>());
  }
  (void)set_isa(best_isa());
  // stderr: stdout is compared across builds, which carry different sets.
  std::fprintf(stderr, "plume_golden: dispatched batteries ran on%s%s%s\n", ran.c_str(),
               skipped.empty() ? "" : "; skipped (this CPU lacks them):", skipped.c_str());
  if (argc == 3 && !std::strcmp(argv[1], "--check")) {
    std::ifstream f(argv[2]);
    std::string name, hex;
    int bad = lanes_ok ? 0 : 1, seen = 0;
    std::map<std::string, bool> checked;
    while (f >> name >> hex) {
      ++seen;
      checked[name] = true;
      auto const it = got.find(name);
      std::uint64_t const want = std::stoull(hex, nullptr, 16);
      if (it == got.end()) continue;
      std::printf("%-14s %016" PRIx64 " %s (golden %016" PRIx64 ", build %s)\n", name.c_str(),
                  it->second, it->second == want ? "OK" : "DIFFERS", want, plume::simd_name);
      if (it->second != want) bad = 1;
    }
    // A battery without a line in the file would never be checked: that is a failure too.
    for (auto const& [battery_name, hash] : got)
      if (!checked.count(battery_name)) {
        std::printf("%-14s %016" PRIx64 " MISSING from %s\n", battery_name.c_str(), hash, argv[2]);
        bad = 1;
      }
    if (seen == 0) {
      std::printf("no golden hashes in %s\n", argv[2]);
      return 1;
    }
    return bad;
  }
  for (auto const& [name, hash] : got)
    std::printf("%s %016" PRIx64 "\n", name.c_str(), hash);
  return lanes_ok ? 0 : 1;
}
