// tests/fuzz/ray_cast.cpp - fuzzes the closed-form ray casts of collision/ray_cast.hpp
// (sphere, capsule, cuboid, cylinder, half-space, triangle at a pose; a world AABB) and the
// GJK ray cast of collision/gjk.hpp (convex hulls, and the primitives as a cross-check), solid
// and hollow, with random rays, rays aimed at an interior point, rays from far outside
// pointing away, rays from inside, and hostile rays (NaN, infinities, huge, zero directions,
// NaN max_toi). Properties:
//  - bad input (ray_cast.hpp: a non-finite origin or direction or a NaN max_toi; gjk.hpp: the
//    same): a miss; a miss is hit false, toi +inf, zero normal, feature -1;
//  - a hit: toi in [0, max_toi], not NaN; the feature one the conventions list; a solid cast
//    from inside hits at 0 with a zero normal and feature -1; otherwise a unit normal, facing
//    against the ray when entering and along it when leaving (hollow, from inside);
//  - reasonable input: the hit point origin + toi dir lies on the surface (signed distance
//    within a rounding tolerance); the normal is outward there (the shape's extent along it
//    is reached at the hit point) and matches the feature (box face, capsule part, cylinder
//    side or cap, triangle side); a smaller max_toi only drops hits beyond it (same toi);
//    a ray from outside aimed at an interior point hits by then; a ray from outside the
//    bounding sphere pointing away never hits; the GJK cast is never later than the closed
//    form and its hit point is within tolerance of the surface.
#include "fuzz_input.hpp"
#include "fuzz_shapes.hpp"

#include <plume/collision/convex_hull.hpp>
#include <plume/collision/gjk.hpp>
#include <plume/collision/ray_cast.hpp>
#include <plume/math/aabb3.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace {

using namespace plume;
using namespace plume::fuzz;

enum class RKind : std::uint8_t {
  sphere,
  capsule,
  cuboid,
  cylinder,
  half_space,
  triangle,
  aabb,
  hull
};
constexpr int rkind_count = 8;

/// The shape cast against; `aabb` is in world space (pose unused).
struct Target {
  RKind kind = RKind::sphere;
  Sphere sphere{};
  Capsule capsule{};
  Cuboid cuboid{};
  Cylinder cylinder{};
  HalfSpace half_space{};
  Triangle triangle{};
  Aabb3 box{};
  ConvexHull hull;
  bool in_domain = true; ///< sizes finite and >= 0 (the casts' stated domain)
  float size = 0;        ///< bounding radius around the local origin (the box's centre)
};

bool ok_size(float v) { return std::isfinite(v) && v >= 0; }

Target make_target(Input& in, RKind k, bool hostile) {
  ValueSource src{in, hostile};
  Target t;
  t.kind = k;
  switch (k) {
  case RKind::sphere:
    t.sphere = {src.size(2)};
    t.in_domain = ok_size(t.sphere.radius);
    t.size = t.sphere.radius;
    break;
  case RKind::capsule:
    t.capsule = {src.size(2), src.size(1)};
    t.in_domain = ok_size(t.capsule.half_height) && ok_size(t.capsule.radius);
    t.size = t.capsule.half_height + t.capsule.radius;
    break;
  case RKind::cuboid:
    t.cuboid = {{src.size(2), src.size(2), src.size(2)}};
    t.in_domain = ok_size(t.cuboid.half_extents.x) && ok_size(t.cuboid.half_extents.y) &&
                  ok_size(t.cuboid.half_extents.z);
    t.size = norm(t.cuboid.half_extents);
    break;
  case RKind::cylinder:
    t.cylinder = {src.size(2), src.size(1.5f)};
    t.in_domain = ok_size(t.cylinder.half_height) && ok_size(t.cylinder.radius);
    t.size = t.cylinder.half_height + t.cylinder.radius;
    break;
  case RKind::half_space:
    t.half_space = {unit_vector(in)};
    break;
  case RKind::triangle: {
    Vec3 const a = src.vec3(-2, 2), b = src.vec3(-2, 2);
    Vec3 c = src.vec3(-2, 2);
    if ((in.byte() & 7) == 0) c = a + (b - a) * in.real(-1, 2); // zero area: rays miss it
    t.triangle = {a, b, c};
    t.in_domain = finite(a) && finite(b) && finite(c);
    t.size = std::max({norm(a), norm(b), norm(c)});
    break;
  }
  case RKind::aabb: {
    Vec3 const c = src.vec3(-4, 4);
    Vec3 const e{src.size(2), src.size(2), src.size(2)};
    t.box = {c - e, c + e};
    t.in_domain = finite(c) && ok_size(e.x) && ok_size(e.y) && ok_size(e.z) && finite(t.box.min) &&
                  finite(t.box.max);
    t.size = norm(e);
    break;
  }
  case RKind::hull: {
    int const n = in.integer(4, 12);
    std::vector<Vec3> pts;
    for (int i = 0; i < n; ++i)
      pts.push_back(in.vec3(-1.5f, 1.5f));
    HullBuild built = ConvexHull::build(pts);
    if (!built) {
      std::vector<Vec3> const tet{{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
      built = ConvexHull::build(tet);
    }
    t.hull = std::move(built.hull);
    for (auto const& p : t.hull.vertices())
      t.size = std::max(t.size, norm(p));
    break;
  }
  }
  if (!t.in_domain) t.size = INFINITY;
  return t;
}

// ------------------------------------------------------------------ geometry in double

D3 rotate(Quat const& q, D3 v, bool inverse) {
  D3 const u = inverse ? D3(-double(q.x), -double(q.y), -double(q.z))
                       : D3(double(q.x), double(q.y), double(q.z));
  double const w = q.w;
  D3 const t = u.cross(v) * 2.0;
  return v + t * w + u.cross(t);
}
D3 to_local(Iso3 const& pose, D3 p) {
  return rotate(pose.rotation, p - D3(pose.translation), true);
}

double box_sdf(D3 p, D3 e) {
  D3 const q{std::abs(p.x) - e.x, std::abs(p.y) - e.y, std::abs(p.z) - e.z};
  D3 const out{std::max(q.x, 0.0), std::max(q.y, 0.0), std::max(q.z, 0.0)};
  return out.length() + std::min(std::max({q.x, q.y, q.z}), 0.0);
}

/// Distance from p to triangle abc (Ericson, Real-Time Collision Detection 5.1.5).
double triangle_distance(D3 p, D3 a, D3 b, D3 c) {
  D3 const ab = b - a, ac = c - a, ap = p - a;
  double const d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return ap.length();
  D3 const bp = p - b;
  double const d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return bp.length();
  double const vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return (p - (a + ab * (d1 / (d1 - d3)))).length();
  D3 const cp = p - c;
  double const d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return cp.length();
  double const vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return (p - (a + ac * (d2 / (d2 - d6)))).length();
  double const va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return (p - (b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))))).length();
  double const den = 1 / (va + vb + vc);
  return (p - (a + ab * (vb * den) + ac * (vc * den))).length();
}

/// Signed distance of a local point (world for the AABB; for hulls the largest face-plane
/// distance, which is the distance near a face and a lower bound elsewhere; for triangles the
/// unsigned distance).
double sdf(Target const& t, D3 p) {
  switch (t.kind) {
  case RKind::sphere:
    return p.length() - t.sphere.radius;
  case RKind::capsule: {
    double const h = t.capsule.half_height;
    return (p - D3(0, std::clamp(p.y, -h, h), 0)).length() - t.capsule.radius;
  }
  case RKind::cuboid:
    return box_sdf(p, D3(t.cuboid.half_extents));
  case RKind::cylinder: {
    double const dx = std::sqrt(p.x * p.x + p.z * p.z) - t.cylinder.radius;
    double const dy = std::abs(p.y) - t.cylinder.half_height;
    return std::min(std::max(dx, dy), 0.0) +
           std::sqrt(std::max(dx, 0.0) * std::max(dx, 0.0) + std::max(dy, 0.0) * std::max(dy, 0.0));
  }
  case RKind::half_space:
    return D3(t.half_space.normal).dot(p);
  case RKind::triangle:
    return triangle_distance(p, D3(t.triangle.a), D3(t.triangle.b), D3(t.triangle.c));
  case RKind::aabb: {
    D3 const lo(t.box.min), hi(t.box.max);
    return box_sdf(p - (lo + hi) * 0.5, (hi - lo) * 0.5);
  }
  case RKind::hull:
    break;
  }
  double m = -INFINITY;
  for (auto const& f : t.hull.faces())
    m = std::max(m, D3(f.normal).dot(p) - double(f.offset));
  return m;
}

/// A local point well inside the shape (nothing for triangles, half-spaces and shapes too
/// thin to have one): `ok` false then.
struct Interior {
  D3 p;
  bool ok;
};
Interior interior_point(Input& in, Target const& t) {
  double const u = in.real(-0.8f, 0.8f), v = in.real(-0.8f, 0.8f), w = in.real(-0.8f, 0.8f);
  D3 p{};
  switch (t.kind) {
  case RKind::sphere:
    p = D3(u, v, w) * (t.sphere.radius * 0.5);
    break;
  case RKind::capsule:
    p = D3(u * 0.5 * t.capsule.radius, v * t.capsule.half_height, w * 0.5 * t.capsule.radius);
    break;
  case RKind::cuboid:
    p = D3(u * t.cuboid.half_extents.x, v * t.cuboid.half_extents.y, w * t.cuboid.half_extents.z);
    break;
  case RKind::cylinder:
    p = D3(u * 0.6 * t.cylinder.radius, v * t.cylinder.half_height, w * 0.6 * t.cylinder.radius);
    break;
  case RKind::aabb: {
    D3 const lo(t.box.min), hi(t.box.max);
    p = (lo + hi) * 0.5 + D3(u * (hi.x - lo.x), v * (hi.y - lo.y), w * (hi.z - lo.z)) * 0.5;
    break;
  }
  case RKind::hull: {
    D3 c{};
    for (auto const& q : t.hull.vertices())
      c = c + D3(q);
    c = c * (1.0 / double(t.hull.vertices().size()));
    // Towards a vertex from the centroid, not all the way.
    auto const& q =
        t.hull.vertices()[std::size_t(in.integer(0, int(t.hull.vertices().size()) - 1))];
    p = c + (D3(q) - c) * (0.5 * (u + 0.8));
    break;
  }
  default:
    return {{}, false};
  }
  return {p, sdf(t, p) < -1e-3};
}

Vec3 to_vec3(D3 p) { return {float(p.x), float(p.y), float(p.z)}; }

// ------------------------------------------------------------------------ the casts

RayHit cast(Target const& t, Iso3 const& pose, Ray3 const& ray, float max_toi, bool solid) {
  switch (t.kind) {
  case RKind::sphere:
    return ray_cast(t.sphere, pose, ray, max_toi, solid);
  case RKind::capsule:
    return ray_cast(t.capsule, pose, ray, max_toi, solid);
  case RKind::cuboid:
    return ray_cast(t.cuboid, pose, ray, max_toi, solid);
  case RKind::cylinder:
    return ray_cast(t.cylinder, pose, ray, max_toi, solid);
  case RKind::half_space:
    return ray_cast(t.half_space, pose, ray, max_toi, solid);
  case RKind::triangle:
    return ray_cast(t.triangle, pose, ray, max_toi, solid);
  case RKind::aabb:
    return ray_cast(t.box, ray, max_toi, solid);
  case RKind::hull:
    break;
  }
  return ray_cast_gjk(t.hull, pose, ray, max_toi, solid);
}

/// The GJK cast of a primitive (none for half-spaces, triangles and AABBs: `ok` false).
struct GjkCast {
  RayHit hit;
  bool ok;
};
GjkCast cast_gjk(Target const& t, Iso3 const& pose, Ray3 const& ray, float max_toi, bool solid) {
  switch (t.kind) {
  case RKind::sphere:
    return {ray_cast_gjk(t.sphere, pose, ray, max_toi, solid), true};
  case RKind::capsule:
    return {ray_cast_gjk(t.capsule, pose, ray, max_toi, solid), true};
  case RKind::cuboid:
    return {ray_cast_gjk(t.cuboid, pose, ray, max_toi, solid), true};
  case RKind::cylinder:
    return {ray_cast_gjk(t.cylinder, pose, ray, max_toi, solid), true};
  case RKind::hull:
    return {ray_cast_gjk(t.hull, pose, ray, max_toi, solid), true};
  default:
    return {{}, false};
  }
}

bool is_miss(RayHit const& h) {
  return !h.hit && h.toi == INFINITY && h.normal.x == 0 && h.normal.y == 0 && h.normal.z == 0 &&
         h.feature == -1;
}

/// The local outward normal the feature names, for the shapes with faces; checks it.
void check_feature(Target const& t, RayHit const& h, D3 n_local, D3 p_local, double tol) {
  float const f = h.feature;
  switch (t.kind) {
  case RKind::sphere:
  case RKind::half_space:
    PLUME_FUZZ_CHECK(f == 0);
    break;
  case RKind::cuboid:
  case RKind::aabb: {
    PLUME_FUZZ_CHECK(f == 0 || f == 1 || f == 2 || f == 3 || f == 4 || f == 5);
    int const axis = int(f) / 2;
    double const sign = (int(f) & 1) ? 1.0 : -1.0;
    D3 const want{axis == 0 ? sign : 0.0, axis == 1 ? sign : 0.0, axis == 2 ? sign : 0.0};
    PLUME_FUZZ_CHECK((n_local - want).length() <= 1e-5);
    break;
  }
  case RKind::capsule: {
    PLUME_FUZZ_CHECK(f == 0 || f == 1 || f == 2);
    double const hh = t.capsule.half_height;
    if (f == 0) PLUME_FUZZ_CHECK(std::abs(p_local.y) <= hh + tol);
    if (f == 1) PLUME_FUZZ_CHECK(p_local.y >= hh - tol);
    if (f == 2) PLUME_FUZZ_CHECK(p_local.y <= -hh + tol);
    break;
  }
  case RKind::cylinder:
    PLUME_FUZZ_CHECK(f == 0 || f == 1 || f == 2);
    if (f == 0) PLUME_FUZZ_CHECK(std::abs(n_local.y) <= 1e-5);
    if (f == 1) PLUME_FUZZ_CHECK((n_local - D3(0, 1, 0)).length() <= 1e-5);
    if (f == 2) PLUME_FUZZ_CHECK((n_local - D3(0, -1, 0)).length() <= 1e-5);
    break;
  case RKind::triangle:
    PLUME_FUZZ_CHECK(f == 0 || f == 1);
    break;
  case RKind::hull:
    PLUME_FUZZ_CHECK(f == -1); // GJK casts name no feature
    break;
  }
}

/// The shape's extent along a local unit direction (from its support point).
double local_extent(Target const& t, D3 n) {
  Vec3 const u = to_vec3(n);
  switch (t.kind) {
  case RKind::sphere:
    return D3(t.sphere.support(u)).dot(n);
  case RKind::capsule:
    return D3(t.capsule.support(u)).dot(n);
  case RKind::cuboid:
    return D3(t.cuboid.support(u)).dot(n);
  case RKind::cylinder:
    return D3(t.cylinder.support(u)).dot(n);
  case RKind::triangle:
    return D3(t.triangle.support(u)).dot(n);
  case RKind::hull:
    return D3(t.hull.support(u)).dot(n);
  case RKind::aabb: {
    D3 const lo(t.box.min), hi(t.box.max);
    return std::max(lo.x * n.x, hi.x * n.x) + std::max(lo.y * n.y, hi.y * n.y) +
           std::max(lo.z * n.z, hi.z * n.z);
  }
  case RKind::half_space:
    break;
  }
  return 0; // a half-space's extent along its normal (checked separately)
}

/// The properties every result has; `reasonable`: the geometric ones too.
void check_hit(Target const& t, Iso3 const& pose, Ray3 const& ray, float max_toi, bool solid,
               RayHit const& h, bool gjk, bool reasonable) {
  bool const ray_ok = finite(ray.origin) && finite(ray.dir) && !std::isnan(max_toi);
  if (!t.in_domain) return; // unspecified hit: survival only
  if (!ray_ok) {
    PLUME_FUZZ_CHECK(is_miss(h));
    return;
  }
  if (!h.hit) {
    PLUME_FUZZ_CHECK(is_miss(h));
    return;
  }
  PLUME_FUZZ_CHECK(!std::isnan(h.toi) && h.toi >= 0 && h.toi <= max_toi);
  PLUME_FUZZ_CHECK(std::isfinite(h.toi));
  bool const bare = h.normal.x == 0 && h.normal.y == 0 && h.normal.z == 0;
  double const scale = 1.0 + double(norm(ray.origin)) + double(h.toi) * double(norm(ray.dir)) +
                       double(norm(pose.translation)) + double(t.size);
  D3 const p_world = D3(ray.origin) + D3(ray.dir) * double(h.toi);
  bool const aabb = t.kind == RKind::aabb;
  D3 const p = aabb ? p_world : to_local(pose, p_world);
  D3 const o_local = aabb ? D3(ray.origin) : to_local(pose, D3(ray.origin));
  double const tol = (gjk ? 1e-4 : 2e-6) * scale;
  if (!reasonable) {
    // Huge but finite input (rounding can then lose the normal): a hit that is one, with a
    // finite normal.
    PLUME_FUZZ_CHECK(finite(h.normal));
    return;
  }
  // A zero radius has no normal (ray_cast.hpp): a hit on such a sphere, capsule or
  // cylinder side carries a zero normal with its feature.
  bool const no_normal = !gjk && h.feature >= 0 &&
                         ((t.kind == RKind::sphere && t.sphere.radius == 0) ||
                          (t.kind == RKind::capsule && t.capsule.radius == 0) ||
                          (t.kind == RKind::cylinder && t.cylinder.radius == 0 && h.feature == 0));
  if (bare && !no_normal) {
    // Only a solid cast from inside hits without a normal: at toi 0, feature -1 (a GJK cast
    // also at a degenerate start on the surface).
    PLUME_FUZZ_CHECK(solid && t.kind != RKind::triangle);
    PLUME_FUZZ_CHECK(h.toi == 0 && h.feature == -1);
    PLUME_FUZZ_CHECK(sdf(t, o_local) <= tol);
    return;
  }
  if (bare) {
    PLUME_FUZZ_CHECK(std::abs(sdf(t, p)) <= tol);
    return;
  }
  D3 const n_world(h.normal);
  // Unit: a normalised float vector is within a few 1e-7 of length 1; 1e-4 leaves room.
  PLUME_FUZZ_CHECK(std::abs(n_world.length() - 1.0) <= 1e-4);
  D3 const n = aabb ? n_world : rotate(pose.rotation, n_world, true);
  // On the surface (within the rounding of the coordinates in play).
  double const s = sdf(t, p);
  PLUME_FUZZ_CHECK(std::abs(s) <= tol);
  // Facing: against the ray entering, along it leaving (hollow from inside); not decided for
  // an origin within the tolerance of the surface, nor on the side of a zero-radius cylinder
  // (a segment: every direction across it is an outward normal).
  D3 const d(ray.dir);
  double const so = sdf(t, o_local);
  double const nd = n_world.dot(d) / d.length();
  bool const segment = t.kind == RKind::cylinder && t.cylinder.radius == 0 && h.feature == 0;
  bool const leaving = !solid && so < -tol && t.kind != RKind::triangle && !segment;
  bool const entering = (so > tol || t.kind == RKind::triangle) && !segment;
  if (leaving) PLUME_FUZZ_CHECK(nd >= -1e-4);
  if (entering) PLUME_FUZZ_CHECK(nd <= 1e-4);
  // Outward: the shape's extent along the normal is reached at the hit point.
  if (t.kind == RKind::half_space) {
    PLUME_FUZZ_CHECK((n - D3(t.half_space.normal)).length() <= 1e-5);
  } else if (t.kind != RKind::triangle) {
    PLUME_FUZZ_CHECK(std::abs(local_extent(t, n) - n.dot(p)) <=
                     (gjk ? 1e-3 * scale : 1e-4 * scale));
  } else {
    // The geometric normal turned to the ray, up to the rounding of float's cross product
    // (relative to |b - a| |c - a| / |(b - a) x (c - a)|: large for slivers).
    D3 const ab(t.triangle.b - t.triangle.a), ac(t.triangle.c - t.triangle.a);
    D3 const tn = ab.cross(ac);
    D3 const unit = tn * (1.0 / tn.length());
    bool const front = h.feature == 0;
    double const cond = ab.length() * ac.length() / tn.length();
    PLUME_FUZZ_CHECK((n - (front ? unit : unit * -1.0)).length() <= 1e-4 + 1e-6 * cond);
  }
  if (!gjk)
    check_feature(t, h, n, p, tol);
  else
    PLUME_FUZZ_CHECK(h.feature == -1);
}

enum class Mode : std::uint8_t { random, aimed, away, from_inside, hostile };
constexpr int mode_count = 5;

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  auto const mode = Mode(in.integer(0, mode_count - 1));
  auto const kind = RKind(in.integer(0, rkind_count - 1));
  bool const hostile_shape = mode == Mode::hostile && in.flag();
  Target const t = make_target(in, kind, hostile_shape);
  Iso3 const pose = make_pose(in, 4, false);
  bool const solid = in.flag();
  float max_toi = (in.byte() & 3) == 0 ? INFINITY : in.real(0, 20);
  bool const aabb = kind == RKind::aabb;
  auto const world = [&](D3 p) { return aabb ? to_vec3(p) : pose.transform_point(to_vec3(p)); };
  D3 const centre = aabb ? (D3(t.box.min) + D3(t.box.max)) * 0.5 : D3(pose.translation);

  Ray3 ray{in.vec3(-8, 8), in.vec3(-2, 2)};
  bool must_hit = false, must_miss = false;
  switch (mode) {
  case Mode::random:
    if ((in.byte() & 15) == 0) ray.dir = {}; // a zero direction
    break;
  case Mode::aimed: {
    // From outside, towards an interior point reached at toi 1.
    Interior const target = interior_point(in, t);
    Vec3 const o = ray.origin;
    if (target.ok) {
      Vec3 const goal = world(target.p);
      ray.dir = goal - o;
      D3 const ol = aabb ? D3(o) : to_local(pose, D3(o));
      must_hit = sdf(t, ol) > 1e-3 && norm(ray.dir) > 1e-3f;
      max_toi = INFINITY;
    }
    break;
  }
  case Mode::away: {
    // Outside the bounding sphere, moving away from its centre: never hits a bounded shape.
    Vec3 const u = unit_vector(in);
    double const r = (double(t.size) + 1.0) * double(in.real(1.01f, 3));
    ray.origin = to_vec3(centre + D3(u) * r);
    if (ray.dir.dot(u) < 0) ray.dir = ray.dir - u * (2 * ray.dir.dot(u));
    must_miss = kind != RKind::half_space && t.in_domain;
    break;
  }
  case Mode::from_inside: {
    Interior const start = interior_point(in, t);
    if (start.ok) ray.origin = world(start.p);
    break;
  }
  case Mode::hostile:
    ray = {in.maybe_bad_vec3(-8, 8), in.maybe_bad_vec3(-2, 2)};
    if ((in.byte() & 3) == 0) max_toi = in.any_float();
    break;
  }
  bool const reasonable = mode != Mode::hostile;

  RayHit const h = cast(t, pose, ray, max_toi, solid);
  check_hit(t, pose, ray, max_toi, solid, h, kind == RKind::hull, reasonable);
  if (must_hit) {
    PLUME_FUZZ_CHECK(h.hit);
    PLUME_FUZZ_CHECK(h.toi <= 1.0f + 1e-4f);
  }
  if (must_miss) PLUME_FUZZ_CHECK(!h.hit);

  if (reasonable && kind != RKind::hull) {
    // A smaller max_toi only drops the hits beyond it.
    float const limit = in.real(0, 20);
    RayHit const full = max_toi == INFINITY ? h : cast(t, pose, ray, INFINITY, solid);
    RayHit const cut = cast(t, pose, ray, limit, solid);
    PLUME_FUZZ_CHECK(cut.hit == (full.hit && full.toi <= limit));
    if (cut.hit) PLUME_FUZZ_CHECK(cut.toi == full.toi);
  }

  // The GJK cast of the same shape: the contract's bad-input rule, its own hit properties, a
  // miss where nothing can be hit, and never later than the closed form (solid, from outside).
  GjkCast const g = cast_gjk(t, pose, ray, max_toi, solid);
  if (g.ok && kind != RKind::hull) {
    check_hit(t, pose, ray, max_toi, solid, g.hit, true, reasonable);
    if (must_miss) PLUME_FUZZ_CHECK(!g.hit.hit);
    if (reasonable && solid && g.hit.hit && h.hit && h.toi > 0) {
      double const dl = double(norm(ray.dir));
      double const scale = 1.0 + double(norm(ray.origin)) + double(h.toi) * dl +
                           double(norm(pose.translation)) + double(t.size);
      PLUME_FUZZ_CHECK(double(g.hit.toi) * dl <= double(h.toi) * dl + 1e-4 * scale);
    }
  }
  return 0;
}
