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

#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

namespace plume {

class WorldMoveQuery {
public:
  using collider_id = BodyId;
  using shape_type = BodyShape;
  using filter_type = QueryFilter;

  explicit WorldMoveQuery(World const& world) noexcept : world_(&world) {}

  World const& world() const noexcept { return *world_; }

  /// The first body the shape touches moving by t * motion, t in [0, 1]; bodies it overlaps
  /// at the start are ignored when the motion leaves them.
  std::optional<MoveCastHit<BodyId>> cast(BodyShape const& shape, Iso3 const& pose,
                                          Vec3 const& motion, QueryFilter const& filter) const {
    return as_move_hit(world_->shape_cast(shape, pose, motion, cast_config(), filter));
  }

  /// cast() for many shapes at once, through World::shape_cast (its batch form: shapes near
  /// each other are cast in lanes); each out[i] is cast(shapes[i], poses[i], motions[i]).
  /// std::invalid_argument when the spans differ in length (nothing written).
  void cast_lanes(std::span<BodyShape const> shapes, std::span<Iso3 const> poses,
                  std::span<Vec3 const> motions, QueryFilter const& filter,
                  std::span<std::optional<MoveCastHit<BodyId>>> out) const {
    if (out.size() != shapes.size())
      throw std::invalid_argument("WorldMoveQuery::cast_lanes: out and shapes differ in length");
    std::vector<std::optional<WorldShapeHit>> hits(shapes.size());
    world_->shape_cast(shapes, poses, motions, cast_config(), hits, filter);
    for (std::size_t i = 0; i < shapes.size(); ++i)
      out[i] = as_move_hit(hits[i]);
  }

  /// The deepest point of each body's manifold with the shape within `distance`.
  template <class Sink>
  void contacts(BodyShape const& shape, Iso3 const& pose, float distance, QueryFilter const& filter,
                Sink&& sink) const {
    world_->contact_query(
        shape, pose, distance,
        [&](BodyId id, Manifold const& m) {
          GContactPoint<float> const* deepest = m.begin();
          for (auto const& c : m)
            if (c.separation < deepest->separation) deepest = &c;
          return bool(
              sink(MoveContact<BodyId>{id, deepest->point_a, m.normal, deepest->separation}));
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
  static std::optional<MoveCastHit<BodyId>> as_move_hit(std::optional<WorldShapeHit> const& h) {
    if (!h) return std::nullopt;
    return MoveCastHit<BodyId>{h->body, h->toi, h->point, h->normal};
  }

  World const* world_;
};

static_assert(LaneMoveQuery<WorldMoveQuery>);

} // namespace plume
