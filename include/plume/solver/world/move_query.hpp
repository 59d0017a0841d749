// plume/solver/world/move_query.hpp - the world as a scene for move_and_slide (a MoveQuery,
// solver/character/move_and_slide.hpp): casts through World::shape_cast, contact planes
// through World::contact_query, both through the world's trees and its QueryFilter.
//
//   WorldMoveQuery scene(world);
//   auto r = move_and_slide(scene, BodyShape{Capsule{0.5f, 0.5f}}, pose, velocity, dt, {},
//                           QueryFilter{.exclude = own_body});
//
// move_and_slide_lanes casts its characters' sweeps together through cast_lanes. The
// character is usually not a body of the world (a kinematic character moves itself); if
// it is, exclude its own body in the filter. The world must outlive the query object, and
// is only read (the first query after an edit may update the trees: World's query rules).
#pragma once

#include <plume/solver/character/move_and_slide.hpp>
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

namespace plume {

class WorldMoveQuery {
public:
  using collider_id = ColliderId; ///< a body's collider, or a standalone one
  using shape_type = BodyShape;
  using filter_type = QueryFilter;

  explicit WorldMoveQuery(World const& world) noexcept : world_(&world) {}

  World const& world() const noexcept { return *world_; }

  /// The first collider the shape touches moving by t * motion, t in [0, 1]; colliders it overlaps
  /// at the start are ignored when the motion leaves them (for cores that overlap, along the
  /// contact manifold's normal); the normal is always unit.
  std::optional<MoveCastHit<ColliderId>> cast(BodyShape const& shape, Iso3 const& pose,
                                              Vec3 const& motion, QueryFilter const& filter) const {
    std::optional<WorldShapeHit> const h =
        world_->shape_cast(shape, pose, motion, cast_config(), filter);
    if (h && !(h->normal.length_squared() > 0.0f))
      return resolve_overlap(shape, pose, motion, filter, *h);
    return as_move_hit(h);
  }

  /// cast() for many shapes at once, through World::shape_cast (its batch form: shapes near
  /// each other are cast in lanes); each out[i] is cast(shapes[i], poses[i], motions[i]).
  /// std::invalid_argument when the spans differ in length (nothing written).
  void cast_lanes(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                  std::span<Vec3 const> motions, QueryFilter const& filter,
                  std::span<std::optional<MoveCastHit<ColliderId>>> out) const {
    if (out.size() != shapes.size())
      throw std::invalid_argument("WorldMoveQuery::cast_lanes: out and shapes differ in length");
    std::vector<std::optional<WorldShapeHit>> hits(shapes.size());
    world_->shape_cast(shapes, poses, motions, cast_config(), hits, filter);
    for (std::size_t i = 0; i < shapes.size(); ++i) {
      std::optional<WorldShapeHit> const& h = hits[i];
      out[i] = h && !(h->normal.length_squared() > 0.0f)
                   ? resolve_overlap(shapes[i], poses[i], motions[i], filter, *h)
                   : as_move_hit(h);
    }
  }

  /// The deepest point of each collider's manifold with the shape within `distance`.
  template <class Sink>
  void contacts(BodyShape const& shape, Iso3 const& pose, float distance, QueryFilter const& filter,
                Sink&& sink) const {
    world_->contact_query(
        shape, pose, distance,
        [&](ColliderId id, Manifold const& m) {
          GContactPoint<float> const* deepest = m.begin();
          for (auto const& c : m)
            if (c.separation < deepest->separation) deepest = &c;
          return bool(
              sink(MoveContact<ColliderId>{id, deepest->point_a, m.normal, deepest->separation}));
        },
        filter);
  }

private:
  /// The casts move_and_slide asks for: t in [0, 1], starts in contact ignored when the motion
  /// leaves them (one place, so that cast() and cast_lanes() cannot differ).
  static ShapeCastConfig cast_config() noexcept {
    ShapeCastConfig cfg;
    cfg.max_toi = 1.0f;
    cfg.stop_at_penetration = false;
    return cfg;
  }
  /// A hit with no normal: the cores overlapped at the start. The contact manifolds with that
  /// body (EPA's normals) give one: the one the motion runs into most steeply; a start the
  /// motion leaves or runs along (within 1e-3 rad) for every manifold is ignored as any other,
  /// and the cast goes on without that body.
  std::optional<MoveCastHit<ColliderId>> resolve_overlap(BodyShape const& shape, Iso3 const& pose,
                                                         Vec3 const& motion,
                                                         QueryFilter const& filter,
                                                         WorldShapeHit first) const {
    std::vector<ColliderId> skipped;
    std::optional<WorldShapeHit> h = first;
    // Each round skips one more collider: a bounded loop.
    for (int round = 0; round < 64 && h && !(h->normal.length_squared() > 0.0f); ++round) {
      ColliderId const met = h->collider;
      QueryFilter only = filter;
      only.predicate = [&](ColliderId id) {
        return id == met && (!filter.predicate || filter.predicate(id));
      };
      // Every manifold of the body (a mesh gives one per group of triangles): the one the
      // motion runs into most steeply is the hit; the body is left only when the motion
      // leaves or runs along all of them.
      std::optional<Vec3> normal;
      Vec3 point{};
      float steepest = 0.0f;
      world_->contact_query(
          shape, pose, 0.0f,
          [&](ColliderId, Manifold const& m) {
            if (m.empty() || !(m.normal.length_squared() > 0.0f)) return true;
            float const out = m.normal.dot(motion);
            if (out < steepest && moves_into_surface(-out, motion.length_squared())) {
              steepest = out;
              normal = m.normal;
              point = m.begin()->point_a;
            }
            return true;
          },
          only);
      if (normal) return MoveCastHit<ColliderId>{met, h->toi, point, *normal};
      skipped.push_back(met);
      QueryFilter rest = filter;
      rest.predicate = [&](ColliderId id) {
        return std::find(skipped.begin(), skipped.end(), id) == skipped.end() &&
               (!filter.predicate || filter.predicate(id));
      };
      h = world_->shape_cast(shape, pose, motion, cast_config(), rest);
    }
    if (h && !(h->normal.length_squared() > 0.0f)) return std::nullopt;
    return as_move_hit(h);
  }
  static std::optional<MoveCastHit<ColliderId>> as_move_hit(std::optional<WorldShapeHit> const& h) {
    if (!h) return std::nullopt;
    return MoveCastHit<ColliderId>{h->collider, h->toi, h->point, h->normal};
  }

  World const* world_;
};

static_assert(LaneMoveQuery<WorldMoveQuery>);

} // namespace plume
