// plume/solver/character/collider_set.hpp - a user's own colliders as a scene for
// move_and_slide (a MoveQuery), with no world: a span of convex shapes at poses.
//
//   std::vector<Collider> level = {{Cuboid{{10, 0.5f, 10}}, Iso3::from_translation({0, -1.5f, 0})},
//                                  {Cuboid{{0.5f, 2, 4}}, Iso3::from_translation({3, 0, 0})}};
//   ColliderSetQuery<Capsule> const scene(level);   // the character's shape type
//   auto r = move_and_slide(scene, Capsule{0.5f, 0.5f}, pose, velocity, dt);
//
// Every query tests every collider (a bounding-box check, then the exact cast or manifold):
// linear in the number of colliders, meant for the few hundred around a character that a
// game has already gathered. For a whole level use the world (WorldMoveQuery), whose queries
// go through its trees. Ids are indices into the span; ties go to the lower index; contacts
// are reported in index order. The span is not copied: it must outlive the query object.
//
// Bad input: a collider with a non-finite pose or shape is never hit (the pair queries fail
// and are skipped); a non-finite query finds nothing.
#pragma once

#include <plume/collision/convex_hull.hpp>
#include <plume/collision/gjk.hpp>
#include <plume/collision/manifold.hpp>
#include <plume/collision/shapes.hpp>
#include <plume/solver/character/move_and_slide.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <span>
#include <variant>

namespace plume {

/// The convex shapes a ColliderSetQuery collider can have.
using ColliderShape = std::variant<Sphere, Capsule, Cuboid, Cylinder, ConvexHull>;

/// A collider: a shape at a pose, in collision layers (a query sees it when
/// (layers & ColliderFilter::mask) != 0).
struct Collider {
  ColliderShape shape;
  Iso3 pose{};
  std::uint32_t layers = 1;
};

/// Which colliders a ColliderSetQuery sees: those in a layer of `mask`, not in `exclude`
/// (indices).
struct ColliderFilter {
  std::uint32_t mask = 0xffffffffu;
  std::span<std::uint32_t const> exclude{};
};

/// A span of colliders as a MoveQuery, for a character of shape type Shape (any convex shape
/// of collision/shapes.hpp or a ConvexHull).
template <class Shape = Capsule>
class ColliderSetQuery {
public:
  using collider_id = std::uint32_t;
  using shape_type = Shape;
  using filter_type = ColliderFilter;

  explicit ColliderSetQuery(std::span<Collider const> colliders) noexcept : colliders_(colliders) {}

  std::span<Collider const> colliders() const noexcept { return colliders_; }

  /// The first collider the shape touches moving by t * motion, t in [0, 1]; colliders it
  /// overlaps at the start are ignored when the motion leaves them or runs along them (for
  /// cores that overlap, along the contact manifold's normal); the normal is always unit.
  std::optional<MoveCastHit<std::uint32_t>> cast(Shape const& shape, Iso3 const& pose,
                                                 Vec3 const& motion,
                                                 ColliderFilter const& filter) const {
    if (!bool(pose.is_finite()) || !bool(motion.is_finite())) return std::nullopt;
    Aabb3 const sweep =
        shape.aabb(pose).merge(shape.aabb(Iso3{pose.rotation, pose.translation + motion}));
    ShapeCastConfig cfg;
    cfg.max_toi = 1.0f;
    cfg.stop_at_penetration = false;
    std::optional<MoveCastHit<std::uint32_t>> best;
    for (std::uint32_t i = 0; i < colliders_.size(); ++i) {
      Collider const& c = colliders_[i];
      if (!sees(i, filter) || !bool(aabb_of(c).intersects(sweep))) continue;
      std::visit(
          [&](auto const& s) {
            ShapeCastHit const h = shape_cast(shape, pose, motion, s, c.pose, cfg);
            if (!h.hit || h.failed) return;
            Vec3 normal = -h.normal, point = h.point_b;
            if (normal.length_squared() == 0.0f) {
              // Cores overlapping at the start: the cast has no normal. The contact manifold's
              // (EPA's) gives one, and the start is ignored as any other when the motion
              // leaves the collider or runs along it.
              ManifoldConfig mcfg;
              mcfg.prediction = 0.0f;
              Manifold const m = contact_manifold(s, c.pose, shape, pose, mcfg);
              if (m.empty() || m.failed || !(m.normal.length_squared() > 0.0f)) return;
              if (!moves_into_surface(-m.normal.dot(motion), motion.length_squared())) return;
              normal = m.normal;
              point = m.begin()->point_a;
            }
            if (!best || h.toi < best->toi)
              best = MoveCastHit<std::uint32_t>{i, h.toi, point, normal};
          },
          c.shape);
    }
    return best;
  }

  /// The deepest point of each collider's manifold with the shape within `distance`.
  template <class Sink>
  void contacts(Shape const& shape, Iso3 const& pose, float distance, ColliderFilter const& filter,
                Sink&& sink) const {
    if (!bool(pose.is_finite()) || !(distance >= 0.0f) || !std::isfinite(distance)) return;
    Aabb3 const box = shape.aabb(pose).grow(distance);
    ManifoldConfig cfg;
    cfg.prediction = distance;
    for (std::uint32_t i = 0; i < colliders_.size(); ++i) {
      Collider const& c = colliders_[i];
      if (!sees(i, filter) || !bool(aabb_of(c).intersects(box))) continue;
      Manifold const m = std::visit(
          [&](auto const& s) { return contact_manifold(s, c.pose, shape, pose, cfg); }, c.shape);
      if (m.empty() || m.failed) continue;
      GContactPoint<float> const* deepest = m.begin();
      for (auto const& p : m)
        if (p.separation < deepest->separation) deepest = &p;
      if (!bool(
              sink(MoveContact<std::uint32_t>{i, deepest->point_a, m.normal, deepest->separation})))
        return;
    }
  }

private:
  bool sees(std::uint32_t i, ColliderFilter const& f) const noexcept {
    return (colliders_[i].layers & f.mask) != 0 &&
           std::find(f.exclude.begin(), f.exclude.end(), i) == f.exclude.end();
  }
  static Aabb3 aabb_of(Collider const& c) {
    return std::visit([&](auto const& s) { return s.aabb(c.pose); }, c.shape);
  }

  std::span<Collider const> colliders_;
};

static_assert(MoveQuery<ColliderSetQuery<Capsule>>);

} // namespace plume
