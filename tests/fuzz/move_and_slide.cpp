// tests/fuzz/move_and_slide.cpp - fuzzes move_and_slide and move_and_slide_lanes
// (solver/character/move_and_slide.hpp) over a few static colliders: a ColliderSetQuery
// (solver/character/collider_set.hpp: spheres, capsules, boxes, cylinders, hulls, thin
// triangular prisms, in layers, with a filter) for a capsule, sphere or box character, or a
// WorldMoveQuery (solver/world/move_query.hpp) over a World of static bodies and standalone
// colliders (the same shapes, a mesh of a triangle or two, a half-space floor). Pose, velocity, dt
// (0, negative, NaN, huge), the configuration, user planes and the hit callback's answers (accept,
// ignore, abort; changed normals, velocities, positions, extra planes) are decoded from the bytes.
// Properties:
//  - non-finite pose, velocity or dt, or a negative dt: invalid_input, the input returned
//    unchanged, nothing queried, no callback;
//  - otherwise a finite position and velocity; at most cfg.iterations sweeps, each one cast
//    (sweeps counts the sweeps cast), iterations + 2 x max_depenetration_queries contact
//    queries, max_planes planes; a call moves at most iterations x max_move plus its
//    depenetrations; dt = 0 sweeps nothing; deep_start sweeps nothing; nothing after an abort;
//  - every hit the callback sees: a collider the scene has, a unit normal, finite point,
//    position, velocity, distance (>= 0) and separation, its iteration in range, touching as
//    documented (sweep hits always; contacts within skin + touch_tolerance); the result keeps
//    exactly the accepted hits (as the callback left them), up to max_hits, counting the rest;
//  - the character does not end deeper in any collider it sees than it was in the deepest at
//    the start, plus a tolerance (measured with collision/epa.hpp's penetration), unless the
//    callback moved it or a depenetration did not converge;
//  - move_and_slide_lanes gives each lane exactly what move_and_slide gives it, bit for bit.
#include "fuzz_input.hpp"

#include <plume/character.hpp>
#include <plume/collision/epa.hpp>
#include <plume/world.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <type_traits>
#include <variant>
#include <vector>

namespace {

using plume::Iso3;
using plume::Quat;
using plume::Vec3;
using plume::fuzz::Input;

bool unit(Vec3 const& n) { return plume::fuzz::finite(n) && std::abs(n.length() - 1.0f) <= 1e-3f; }
bool same(float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(Vec3 const& a, Vec3 const& b) {
  return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
}

// ------------------------------------------------------------------------ the scene

/// A convex hull: a thin prism over a triangle (a "triangle" with some thickness), or a few
/// random points (retried as a box's corners when the points are flat).
plume::ConvexHull make_hull(Input& in) {
  std::vector<Vec3> pts;
  if (in.flag()) {
    Vec3 const a = in.vec3(-1, 1), b = in.vec3(-1, 1), c = in.vec3(-1, 1);
    Vec3 const n = (b - a).cross(c - a).normalize_or(Vec3::Y) * in.real(0.02f, 0.2f);
    for (Vec3 const& p : {a, b, c}) {
      pts.push_back(p);
      pts.push_back(p + n);
    }
  } else {
    int const k = in.integer(4, 8);
    for (int i = 0; i < k; ++i)
      pts.push_back(in.vec3(-1, 1));
  }
  plume::HullBuild r = plume::ConvexHull::build(std::span<Vec3 const>(pts));
  if (r) return std::move(r.hull);
  std::vector<Vec3> box;
  for (int i = 0; i < 8; ++i)
    box.push_back({(i & 1) ? 0.5f : -0.5f, (i & 2) ? 0.5f : -0.5f, (i & 4) ? 0.5f : -0.5f});
  return std::move(plume::ConvexHull::build(std::span<Vec3 const>(box)).hull);
}

/// A collider's convex shape (a ColliderShape alternative, also a BodyShape one).
template <class Variant>
Variant convex_shape(Input& in) {
  std::uint8_t const k = in.byte();
  switch (k % 6) {
  case 0:
    return plume::Sphere{in.real(0.05f, 1.5f)};
  case 1:
    return plume::Capsule{in.real(0, 1.5f), in.real(0.05f, 1)};
  case 2:
  case 3:
    return plume::Cuboid{Vec3{in.real(0.02f, 3), in.real(0.02f, 1), in.real(0.02f, 3)}};
  case 4:
    return plume::Cylinder{in.real(0.05f, 1.5f), in.real(0.05f, 1.5f)};
  default:
    return make_hull(in);
  }
}

Iso3 collider_pose(Input& in) {
  Iso3 p{in.flag() ? in.rotation() : Quat::IDENTITY, in.vec3(-3, 3)};
  if ((in.byte() & 7) == 0)
    p.translation = Vec3{float(in.integer(-3, 3)), float(in.integer(-3, 3)), 0};
  return p;
}

/// How deep a shape is in another: penetration depth, negative apart; `sure` unless EPA was
/// capped (collision/epa.hpp's approximate: a lower bound) and the two argument orders disagree.
struct Depth {
  float d = -std::numeric_limits<float>::infinity();
  bool sure = true;
  void add(Depth const& o) {
    d = std::max(d, o.d);
    sure = sure && o.sure;
  }
};

template <class A, class B>
Depth penetration_depth(A const& a, Iso3 const& pa, B const& b, Iso3 const& pb) {
  plume::PenetrationResult const r1 = plume::penetration(a, pa, b, pb);
  plume::PenetrationResult const r2 = plume::penetration(b, pb, a, pa);
  if (r1.status == plume::PenetrationStatus::failed ||
      r2.status == plume::PenetrationStatus::failed)
    return {};
  bool const capped = r1.status == plume::PenetrationStatus::approximate ||
                      r2.status == plume::PenetrationStatus::approximate;
  return {std::max(r1.depth, r2.depth), !capped || std::abs(r1.depth - r2.depth) <= 1e-3f};
}

/// How deep shape a (at pa) is in b (at pb).
template <class A, class B>
Depth depth_of(A const& a, Iso3 const& pa, B const& b, Iso3 const& pb) {
  if constexpr (std::is_same_v<B, plume::HalfSpace>) {
    Vec3 const n = pb.rotation * b.normal;
    Vec3 const deepest = pa.transform_point(a.support(pa.inverse_transform_vector(-n)));
    return {-n.dot(deepest - pb.translation), true};
  } else if constexpr (std::is_same_v<B, plume::MeshShape>) {
    Depth d;
    for (std::uint32_t t = 0; t < b.mesh->triangle_count(); ++t)
      d.add(penetration_depth(a, pa, b.mesh->triangle(t), pb));
    return d;
  } else if constexpr (std::is_same_v<B, plume::HeightFieldShape>) {
    return {}; // never built here
  } else {
    return penetration_depth(a, pa, b, pb);
  }
}

// ------------------------------------------------------------------------ the callback

/// Answers hits from a decoded plan and checks what it is shown.
template <class Id>
struct Responder {
  std::vector<std::uint8_t> plan;
  std::vector<Vec3> values; ///< velocities, normals and positions the plan may set
  plume::MoveAndSlideConfig const* cfg = nullptr;
  std::function<bool(Id)> valid_id;
  std::size_t calls = 0;
  bool aborted = false, moved = false;
  std::vector<plume::MoveHit<Id>> kept; ///< accepted hits as the callback left them

  plume::HitResponse operator()(plume::MoveHit<Id>& h) {
    PLUME_FUZZ_CHECK(!aborted); // nothing after an abort
    PLUME_FUZZ_CHECK(valid_id(h.collider));
    PLUME_FUZZ_CHECK(h.iteration >= 0 && h.iteration < cfg->iterations);
    PLUME_FUZZ_CHECK(unit(h.normal));
    PLUME_FUZZ_CHECK(plume::fuzz::finite(h.point) && plume::fuzz::finite(h.position) &&
                     plume::fuzz::finite(h.velocity));
    PLUME_FUZZ_CHECK(std::isfinite(h.distance) && h.distance >= 0.0f);
    PLUME_FUZZ_CHECK(std::isfinite(h.separation));
    if (h.kind == plume::MoveHitKind::sweep) {
      PLUME_FUZZ_CHECK(h.touching);
      PLUME_FUZZ_CHECK(h.distance <= cfg->max_move * 1.0001f);
    } else {
      PLUME_FUZZ_CHECK(h.touching == (h.separation <= cfg->skin + cfg->touch_tolerance));
      PLUME_FUZZ_CHECK(h.separation <= cfg->plane_distance + 1e-3f);
    }
    std::uint8_t const p = plan.empty() ? 0 : plan[calls % plan.size()];
    Vec3 const v = values.empty() ? Vec3{} : values[calls % values.size()];
    ++calls;
    plume::HitResponse const answer = (p & 7) == 7   ? plume::HitResponse::abort
                                      : (p & 7) == 6 ? plume::HitResponse::ignore
                                                     : plume::HitResponse::accept;
    switch ((p >> 3) & 7) {
    case 1:
      h.velocity = v; // any value, NaN included: a non-finite one is not followed
      break;
    case 2:
      h.normal = v.normalize_or(h.normal); // another plane
      break;
    case 3:
      h.extra_normal = v.normalize_or(Vec3{});
      break;
    case 4:
      if (p & 0x40) {
        h.position = h.position + v * 0.1f; // a teleport: the depth property no longer applies
        moved = moved || plume::fuzz::finite(v);
      }
      break;
    default:
      break;
    }
    if (answer == plume::HitResponse::abort) aborted = true;
    if (answer == plume::HitResponse::accept && (h.kind == plume::MoveHitKind::sweep || h.touching))
      kept.push_back(h);
    return answer;
  }
};

/// A scene wrapped to count its queries and check its answers (MoveQuery's contract): a cast hit
/// names a collider the scene has, at toi in [0, 1], with a finite point and a unit normal; a
/// contact the same, with a finite separation within the distance asked for.
template <class Q>
struct Counting {
  using collider_id = typename Q::collider_id;
  using shape_type = typename Q::shape_type;
  using filter_type = typename Q::filter_type;
  Q const* q;
  std::function<bool(collider_id)> const* valid;
  mutable int casts = 0, contact_queries = 0;
  std::optional<plume::MoveCastHit<collider_id>>
  cast(shape_type const& s, Iso3 const& pose, Vec3 const& motion, filter_type const& f) const {
    ++casts;
    std::optional<plume::MoveCastHit<collider_id>> const h = q->cast(s, pose, motion, f);
    if (h) {
      PLUME_FUZZ_CHECK((*valid)(h->collider));
      PLUME_FUZZ_CHECK(h->toi >= 0.0f && h->toi <= 1.0f);
      PLUME_FUZZ_CHECK(plume::fuzz::finite(h->point));
      PLUME_FUZZ_CHECK(unit(h->normal));
    }
    return h;
  }
  template <class Sink>
  void contacts(shape_type const& s, Iso3 const& pose, float distance, filter_type const& f,
                Sink&& sink) const {
    ++contact_queries;
    q->contacts(s, pose, distance, f, [&](plume::MoveContact<collider_id> const& c) {
      PLUME_FUZZ_CHECK((*valid)(c.collider));
      PLUME_FUZZ_CHECK(plume::fuzz::finite(c.point) && std::isfinite(c.separation));
      PLUME_FUZZ_CHECK(c.separation <= distance + 1e-3f);
      PLUME_FUZZ_CHECK(unit(c.normal));
      return bool(sink(c));
    });
  }
};

template <class Id>
bool same_hit(plume::MoveHit<Id> const& a, plume::MoveHit<Id> const& b) {
  return a.collider == b.collider && a.kind == b.kind && a.iteration == b.iteration &&
         same(a.point, b.point) && same(a.normal, b.normal) && same(a.position, b.position) &&
         same(a.velocity, b.velocity) && same(a.distance, b.distance) &&
         same(a.separation, b.separation) && a.touching == b.touching &&
         same(a.extra_normal, b.extra_normal);
}

template <class Id>
bool same_result(plume::MoveAndSlideResult<Id> const& a, plume::MoveAndSlideResult<Id> const& b) {
  if (!(same(a.position, b.position) && same(a.velocity, b.velocity) && a.sweeps == b.sweeps &&
        a.aborted == b.aborted && a.invalid_input == b.invalid_input &&
        a.depenetrated == b.depenetrated && a.deep_start == b.deep_start && a.planes == b.planes &&
        a.planes_overflowed == b.planes_overflowed && a.hit_count == b.hit_count &&
        a.hits_dropped == b.hits_dropped))
    return false;
  for (std::size_t i = 0; i < a.hit_count; ++i)
    if (!same_hit(a.hits[i], b.hits[i])) return false;
  return true;
}

// ------------------------------------------------------------------------ one move

struct Move {
  Iso3 pose;
  Vec3 velocity;
  float dt;
};

Move decode_move(Input& in) {
  Move m;
  std::uint8_t const k = in.byte();
  m.pose = Iso3{(k & 1) ? in.rotation() : Quat::IDENTITY, in.vec3(-3, 3)};
  if ((k & 0x0e) == 0x0e) m.pose.translation.x = in.any_float();
  if ((k & 0x70) == 0x70) m.pose.rotation.w = std::numeric_limits<float>::quiet_NaN();
  m.velocity = (k & 0x80) ? in.maybe_bad_vec3(-20, 20) : in.vec3(-10, 10);
  std::uint8_t const d = in.byte();
  switch (d % 8) {
  case 0:
    m.dt = 0.0f;
    break;
  case 1:
    m.dt = (d & 8) ? -in.real(0, 1) : in.any_float();
    break;
  case 2:
    m.dt = (d & 8) ? 1e30f : in.real(0, 100);
    break;
  default:
    m.dt = in.real(0, 0.5f);
    break;
  }
  return m;
}

plume::MoveAndSlideConfig decode_config(Input& in, std::vector<Vec3>& user_planes) {
  plume::MoveAndSlideConfig cfg;
  std::uint8_t const k = in.byte();
  if (k & 1) cfg.iterations = in.integer(0, 8);
  if (k & 2) {
    cfg.skin = in.real(0, 0.05f);
    cfg.plane_distance = 2.0f * cfg.skin;
    cfg.touch_tolerance = in.real(0, 0.005f);
  }
  if (k & 4) cfg.min_sweep = in.real(0, 0.01f);
  if (k & 8) cfg.max_move = in.real(0.05f, 100);
  if (k & 16) {
    cfg.depenetration.iterations = in.integer(1, 32);
    cfg.depenetration.rejection_threshold = in.real(0.05f, 1);
  }
  if (k & 32) cfg.planes.max_planes = std::size_t(in.integer(1, 24));
  if (k & 64) {
    int const n = in.integer(1, 2);
    for (int i = 0; i < n; ++i)
      user_planes.push_back(in.vec3(-1, 1).normalize_or(Vec3::Y));
    cfg.user_planes = user_planes;
  }
  return cfg;
}

/// Checks one move_and_slide call on scene q; returns the result.
template <class Q, class Shape, class Deepest>
plume::MoveAndSlideResult<typename Q::collider_id>
check_move(Q const& q, Shape const& shape, Move const& m, plume::MoveAndSlideConfig const& cfg,
           typename Q::filter_type const& filter, Responder<typename Q::collider_id>& on_hit,
           std::size_t colliders, Deepest const& deepest) {
  Counting<Q> const counted{&q, &on_hit.valid_id};
  plume::MoveAndSlideResult<typename Q::collider_id> const r =
      plume::move_and_slide(counted, shape, m.pose, m.velocity, m.dt, cfg, filter, on_hit);
  bool const bad = !bool(m.pose.is_finite()) || !plume::fuzz::finite(m.velocity) ||
                   !std::isfinite(m.dt) || !(m.dt >= 0.0f);
  PLUME_FUZZ_CHECK(r.invalid_input == bad);
  if (bad) {
    PLUME_FUZZ_CHECK(same(r.position, m.pose.translation) && same(r.velocity, m.velocity));
    PLUME_FUZZ_CHECK(r.sweeps == 0 && r.hit_count == 0 && !r.aborted);
    PLUME_FUZZ_CHECK(counted.casts == 0 && counted.contact_queries == 0 && on_hit.calls == 0);
    return r;
  }
  PLUME_FUZZ_CHECK(plume::fuzz::finite(r.position) && plume::fuzz::finite(r.velocity));
  // Every loop is bounded.
  PLUME_FUZZ_CHECK(r.sweeps >= 0 && r.sweeps <= std::max(cfg.iterations, 0));
  PLUME_FUZZ_CHECK(counted.casts == r.sweeps); // "sweeps cast"
  PLUME_FUZZ_CHECK(counted.contact_queries <= r.sweeps + 2 * plume::max_depenetration_queries);
  PLUME_FUZZ_CHECK(r.planes <= cfg.planes.max_planes);
  PLUME_FUZZ_CHECK(on_hit.calls <= std::size_t(r.sweeps) * (colliders + 1));
  if (m.dt == 0.0f || r.deep_start) PLUME_FUZZ_CHECK(r.sweeps == 0 && on_hit.calls == 0);
  PLUME_FUZZ_CHECK(r.aborted == on_hit.aborted);
  // The accepted hits, as the callback left them.
  PLUME_FUZZ_CHECK(r.hit_count + r.hits_dropped == on_hit.kept.size());
  PLUME_FUZZ_CHECK(r.hit_count == std::min(on_hit.kept.size(), r.hits.size()));
  for (std::size_t i = 0; i < r.hit_count; ++i)
    PLUME_FUZZ_CHECK(same_hit(r.hits[i], on_hit.kept[i]));
  // Untouched: no hit, no user plane, so nothing clips the velocity.
  if (on_hit.calls == 0 && cfg.user_planes.empty()) PLUME_FUZZ_CHECK(same(r.velocity, m.velocity));
  // At most iterations x max_move, plus the two depenetrations (and the rounding of far
  // coordinates, one ulp per addition).
  float const push = 2.0f * plume::max_depenetration_move(cfg);
  float const far =
      std::max(m.pose.translation.abs().max_element(), r.position.abs().max_element());
  float const ulps = 4.0f * float(r.sweeps + 3) * far * std::numeric_limits<float>::epsilon();
  if (!on_hit.moved)
    PLUME_FUZZ_CHECK((r.position - m.pose.translation).length() <=
                     (float(r.sweeps) * cfg.max_move + push) * 1.001f + 1e-3f + ulps);
  // Not deeper in anything than in the deepest thing at the start (where the start depths are
  // known: a capped EPA only bounds them from below), when the depenetrations converged (pairs
  // that cannot all be satisfied get the mean of the fixes, which may go deeper into one).
  if (!on_hit.moved && r.depenetrated) {
    Depth const before = deepest(m.pose);
    Depth const after = deepest(Iso3{m.pose.rotation, r.position});
    float const tol = 2e-3f + 1e-4f * r.position.abs().max_element();
    if (before.sure) PLUME_FUZZ_CHECK(!(after.d > std::max(before.d, 0.0f) + tol));
  }
  return r;
}

/// One plan and one set of values for a callback.
template <class Id>
Responder<Id> decode_responder(Input& in, plume::MoveAndSlideConfig const& cfg,
                               std::function<bool(Id)> valid) {
  Responder<Id> r;
  r.cfg = &cfg;
  r.valid_id = std::move(valid);
  int const n = in.integer(0, 6);
  for (int i = 0; i < n; ++i)
    r.plan.push_back(in.byte());
  if (n > 0)
    for (int i = 0; i < 2; ++i)
      r.values.push_back(in.maybe_bad_vec3(-5, 5));
  return r;
}

/// The lanes form against the scalar one, lane by lane.
template <class Q, class Shape>
void check_lanes(Q const& q, std::vector<Shape> const& shapes, std::vector<Move> const& moves,
                 float dt, plume::MoveAndSlideConfig const& cfg,
                 typename Q::filter_type const& filter,
                 std::vector<Responder<typename Q::collider_id>> const& fresh) {
  using T = plume::f32xN;
  constexpr std::size_t W = plume::lanes_v<T>;
  using Id = typename Q::collider_id;
  std::array<Quat, W> rot;
  std::array<Vec3, W> at, vel;
  for (std::size_t k = 0; k < W; ++k) {
    rot[k] = moves[k].pose.rotation;
    at[k] = moves[k].pose.translation;
    vel[k] = moves[k].velocity;
  }
  std::vector<Responder<Id>> lane_hits = fresh;
  auto const on_hit = [&](std::size_t lane, plume::MoveHit<Id>& h) {
    PLUME_FUZZ_CHECK(lane < W);
    return lane_hits[lane](h);
  };
  plume::MoveAndSlideLanes<T, Id> const got = plume::move_and_slide_lanes<T>(
      q, std::span<Shape const>(shapes),
      plume::GIso3<T>{plume::pack<T>(rot.data()), plume::pack<T>(at.data())},
      plume::pack<T>(vel.data()), dt, cfg, filter, on_hit);
  std::array<Vec3, W> pos, vout;
  plume::unpack(got.position, pos.data());
  plume::unpack(got.velocity, vout.data());
  for (std::size_t k = 0; k < W; ++k) {
    Responder<Id> alone = fresh[k];
    plume::MoveAndSlideResult<Id> const want =
        plume::move_and_slide(q, shapes[k], Iso3{rot[k], at[k]}, vel[k], dt, cfg, filter, alone);
    PLUME_FUZZ_CHECK(same_result(got.lanes[k], want));
    PLUME_FUZZ_CHECK(same(pos[k], want.position) && same(vout[k], want.velocity));
    PLUME_FUZZ_CHECK(lane_hits[k].calls == alone.calls);
  }
  // shapes.size() != W is refused.
  if (W > 1) {
    bool threw = false;
    try {
      auto const none = on_hit;
      (void)plume::move_and_slide_lanes<T>(
          q, std::span<Shape const>(shapes).first(W - 1),
          plume::GIso3<T>{plume::pack<T>(rot.data()), plume::pack<T>(at.data())},
          plume::pack<T>(vel.data()), dt, cfg, filter, none);
    } catch (std::invalid_argument const&) {
      threw = true;
    }
    PLUME_FUZZ_CHECK(threw);
  }
}

// ------------------------------------------------------------------------ the two scenes

template <class Shape>
Shape character(Input& in) {
  if constexpr (std::is_same_v<Shape, plume::Capsule>)
    return plume::Capsule{in.real(0, 1), in.real(0.05f, 0.6f)};
  else if constexpr (std::is_same_v<Shape, plume::Sphere>)
    return plume::Sphere{in.real(0.05f, 0.8f)};
  else
    return plume::Cuboid{Vec3{in.real(0.05f, 0.6f), in.real(0.05f, 1), in.real(0.05f, 0.6f)}};
}

template <class Shape>
void run_collider_set(Input& in) {
  std::vector<plume::Collider> colliders;
  int const n = in.integer(0, 8);
  for (int i = 0; i < n; ++i) {
    plume::ColliderShape s = convex_shape<plume::ColliderShape>(in);
    Iso3 const pose = collider_pose(in);
    std::uint32_t const layers = (in.byte() & 3) == 0 ? 2u : 1u;
    colliders.push_back({std::move(s), pose, layers});
  }
  if (!colliders.empty() && (in.byte() & 15) == 0) // a collider with a bad pose is never hit
    colliders.back().pose.translation.y = std::numeric_limits<float>::quiet_NaN();
  plume::ColliderSetQuery<Shape> const scene{std::span<plume::Collider const>(colliders)};
  std::vector<std::uint32_t> exclude;
  plume::ColliderFilter filter;
  std::uint8_t const f = in.byte();
  if (f & 1) filter.mask = 1u;
  if ((f & 2) && n > 0) {
    exclude.push_back(std::uint32_t(in.byte()) % std::uint32_t(n));
    filter.exclude = exclude;
  }
  auto const seen = [&](std::uint32_t i) {
    return (colliders[i].layers & filter.mask) != 0 &&
           std::find(exclude.begin(), exclude.end(), i) == exclude.end() &&
           bool(colliders[i].pose.is_finite());
  };
  std::vector<Vec3> user_planes;
  plume::MoveAndSlideConfig const cfg = decode_config(in, user_planes);
  std::function<bool(std::uint32_t)> const valid = [&](std::uint32_t i) {
    return i < colliders.size() && seen(i);
  };

  Shape const shape = character<Shape>(in);
  auto const deepest = [&](Iso3 const& pose) {
    Depth d;
    for (std::uint32_t i = 0; i < colliders.size(); ++i)
      if (seen(i))
        d.add(std::visit([&](auto const& s) { return depth_of(shape, pose, s, colliders[i].pose); },
                         colliders[i].shape));
    return d;
  };
  Move const m = decode_move(in);
  Responder<std::uint32_t> on_hit = decode_responder(in, cfg, valid);
  Responder<std::uint32_t> const fresh = on_hit;
  (void)check_move(scene, shape, m, cfg, filter, on_hit, colliders.size(), deepest);

  // The lanes: this move in lane 0, others beside it.
  if (in.flag()) {
    constexpr std::size_t W = plume::lanes_v<plume::f32xN>;
    std::vector<Shape> shapes{shape};
    std::vector<Move> moves{m};
    std::vector<Responder<std::uint32_t>> plans{fresh};
    for (std::size_t k = 1; k < W; ++k) {
      shapes.push_back((in.byte() & 1) ? character<Shape>(in) : shape);
      Move mk = decode_move(in);
      moves.push_back(mk);
      plans.push_back(decode_responder(in, cfg, valid));
    }
    check_lanes(scene, shapes, moves, m.dt, cfg, filter, plans);
  }
}

void run_world(Input& in) {
  plume::World world;
  struct Body {
    plume::ColliderId id; ///< a static body's, or a standalone collider (0x40 of its byte)
    plume::BodyShape shape;
    Iso3 pose;
    std::uint32_t layers;
  };
  std::vector<Body> bodies;
  int const n = in.integer(0, 8);
  for (int i = 0; i < n; ++i) {
    std::uint8_t const k = in.byte();
    plume::BodyDef def;
    def.type = plume::BodyType::static_body;
    def.pose = collider_pose(in);
    def.layers.memberships = (k & 0x30) == 0 ? 2u : 1u;
    if (k % 8 == 0) { // a triangle or two
      std::vector<Vec3> v;
      for (int j = 0; j < 4; ++j)
        v.push_back(in.vec3(-3, 3));
      std::vector<std::uint32_t> idx{0, 1, 2};
      if (k & 8) idx.insert(idx.end(), {2, 1, 3});
      plume::MeshBuildResult r = plume::TriangleMesh::build(v, idx);
      if (!r.ok()) continue;
      def.shape = plume::MeshShape{std::make_shared<plume::TriangleMesh const>(std::move(r.mesh))};
    } else if (k % 8 == 1) {
      def.shape = plume::HalfSpace{in.vec3(-1, 1).normalize_or(Vec3::Y)};
    } else {
      def.shape = convex_shape<plume::BodyShape>(in);
    }
    plume::ColliderId id;
    if (k & 0x40) {
      plume::CreateColliderResult const c =
          world.create_collider({.pose = def.pose, .shape = def.shape, .layers = def.layers});
      PLUME_FUZZ_CHECK(bool(c));
      id = c.id;
    } else {
      plume::CreateBodyResult const c = world.create_body(def);
      PLUME_FUZZ_CHECK(bool(c));
      id = c.id;
    }
    bodies.push_back({id, def.shape, world.pose(id), def.layers.memberships});
  }
  plume::WorldMoveQuery const scene(world);
  plume::QueryFilter filter;
  std::vector<plume::BodyId> exclude;
  std::uint8_t const f = in.byte();
  if (f & 1) filter.mask = 1u;
  if ((f & 2) && !bodies.empty()) { // a standalone collider's slot excludes nothing
    plume::ColliderId const c = bodies[std::size_t(in.byte()) % bodies.size()].id;
    exclude.push_back(plume::BodyId{c.index, c.generation});
    filter.exclude = exclude;
  }
  if (f & 4) filter.predicate = [](plume::ColliderId id) { return id.index % 3 != 2; };
  auto const seen = [&](Body const& b) {
    return (b.layers & filter.mask) != 0 &&
           std::find(exclude.begin(), exclude.end(), b.id.body()) == exclude.end() &&
           (!filter.predicate || filter.predicate(b.id));
  };
  std::vector<Vec3> user_planes;
  plume::MoveAndSlideConfig const cfg = decode_config(in, user_planes);
  std::function<bool(plume::ColliderId)> const valid = [&](plume::ColliderId id) {
    for (Body const& b : bodies)
      if (b.id == id) return world.is_alive(id) && seen(b);
    return false;
  };
  std::uint8_t const ck = in.byte();
  plume::BodyShape const shape = ck % 3 == 0   ? plume::BodyShape{character<plume::Capsule>(in)}
                                 : ck % 3 == 1 ? plume::BodyShape{character<plume::Sphere>(in)}
                                               : plume::BodyShape{character<plume::Cuboid>(in)};
  auto const deepest = [&](Iso3 const& pose) {
    Depth d;
    for (Body const& b : bodies)
      if (seen(b))
        d.add(std::visit(
            [&](auto const& c) {
              using C = std::decay_t<decltype(c)>;
              if constexpr (plume::is_triangle_shape_v<C> || std::is_same_v<C, plume::HalfSpace>)
                return Depth{};
              else
                return std::visit([&](auto const& s) { return depth_of(c, pose, s, b.pose); },
                                  b.shape);
            },
            shape));
    return d;
  };
  Move const m = decode_move(in);
  Responder<plume::ColliderId> on_hit = decode_responder(in, cfg, valid);
  Responder<plume::ColliderId> const fresh = on_hit;
  (void)check_move(scene, shape, m, cfg, filter, on_hit, bodies.size(), deepest);

  if (in.flag()) {
    constexpr std::size_t W = plume::lanes_v<plume::f32xN>;
    std::vector<plume::BodyShape> shapes{shape};
    std::vector<Move> moves{m};
    std::vector<Responder<plume::ColliderId>> plans{fresh};
    for (std::size_t k = 1; k < W; ++k) {
      shapes.push_back((in.byte() & 1) ? plume::BodyShape{character<plume::Capsule>(in)} : shape);
      moves.push_back(decode_move(in));
      plans.push_back(decode_responder(in, cfg, valid));
    }
    check_lanes(scene, shapes, moves, m.dt, cfg, filter, plans);
  }
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(std::uint8_t const* data, std::size_t size) {
  Input in(data, size);
  switch (in.byte() % 4) {
  case 0:
    run_collider_set<plume::Capsule>(in);
    break;
  case 1:
    run_collider_set<plume::Sphere>(in);
    break;
  case 2:
    run_collider_set<plume::Cuboid>(in);
    break;
  default:
    run_world(in);
    break;
  }
  return 0;
}
