// Continuous collision of the world's step (include/plume/solver/world/world.hpp, WorldConfig::
// continuous): fast dynamic bodies are swept from where the step began to where it ended and put
// back at the first time of impact, as Box2D v3 does after its solver.
//
// Each sweep is a translation of the body's shape at its final orientation, cast with the same
// per-body shape cast as World::shape_cast. Bodies without the bullet flag are swept against
// static bodies (frozen ones included: they act as static), which no sweep moves, so their order
// does not matter; bullets go after them, against the final poses of every body that is not a
// bullet. Both passes run in body index order, and every hit is reduced to the smallest time of
// impact (ties: the lower body index, met first), so the result is the same in every width and
// build.
#include <plume/solver/world/world.hpp>

#include <algorithm>

namespace plume {

bool World::solve_continuous() {
  if (fast_.empty()) return false;
  ShapeCastConfig cfg;
  cfg.max_toi = 1.0f;
  cfg.target_distance = config_.ccd_distance();
  cfg.stop_at_penetration = false; // a start moving out of (or along) a body is no hit

  std::vector<std::uint32_t> near;
  auto const sweep = [&](FastBody const& f, bool bullet) {
    Body& b = bodies_[f.index];
    Vec3 const motion = b.center - f.start;
    Iso3 const from{b.pose.rotation, b.pose.translation - motion};
    Aabb3 const box = aabb(BodyId{f.index, b.generation})
                          .merge(std::visit([&](auto const& s) { return s.aabb(from); }, b.shape));
    candidates(box.grow(cfg.target_distance), QueryFilter{}, near);
    BodyShape const core = Sphere{0.25f * b.min_extent};
    Iso3 const core_from = Iso3::from_translation(f.start);
    float first = 1.0f;
    bool hit = false;
    for (std::uint32_t j : near) {
      Body const& o = bodies_[j];
      if (j == f.index || o.sensor || !o.layers.interacts(b.layers)) continue;
      bool const still = o.type == BodyType::static_body || o.frozen;
      if (bullet ? (o.bullet && o.is_dynamic()) : !still) continue;
      if (!no_collide_pairs_.empty() && jointed_no_collide(f.index, j)) continue;
      auto h = detail::cast_against(o.shape, o.pose, b.shape, from, motion, cfg);
      // Touching at the start (resting on a floor, grazing a wall): the shape's own cast
      // cannot tell whether the path goes through; the core's can.
      if (h && h->toi <= 0.0f)
        h = detail::cast_against(o.shape, o.pose, core, core_from, motion, cfg);
      if (h && h->toi > 0.0f && h->toi < first) {
        first = h->toi;
        hit = true;
      }
    }
    if (!hit) return false;
    b.center = f.start + motion * first;
    b.pose.translation = b.center - b.pose.rotation * b.local_center;
    events_.continuous_stops.push_back(BodyId{f.index, b.generation});
    return true;
  };

  bool bullets = false;
  for (FastBody const& f : fast_) {
    if (bodies_[f.index].bullet)
      bullets = true;
    else
      sweep(f, false); // the static tree is current: no sync needed
  }
  if (!bullets) return false;
  // Bullets meet the other bodies where the step (and the first pass) left them.
  trees_synced_ = false;
  all_moving_stale_ = true;
  stale_moving_.clear();
  sync_trees();
  for (FastBody const& f : fast_)
    if (bodies_[f.index].bullet && sweep(f, true)) {
      mark_stale_moving(f.index);
      trees_synced_ = false;
    }
  std::sort(events_.continuous_stops.begin(), events_.continuous_stops.end(),
            [](BodyId a, BodyId b) { return a.index < b.index; });
  return true;
}

} // namespace plume
