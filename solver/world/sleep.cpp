// Sleeping: sleep timers, islands, putting islands to sleep and waking them
// (include/plume/solver/world/world.hpp has the rules).
#include <plume/solver/world/world.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace plume {

namespace {

constexpr std::uint32_t no_island = ~std::uint32_t(0);

bool nonzero(Vec3 const& v) { return v.x != 0.0f || v.y != 0.0f || v.z != 0.0f; }

/// The root of i's set (path halving); parent[i] == i at a root.
std::uint32_t find_root(std::vector<std::uint32_t>& parent, std::uint32_t i) {
  while (parent[i] != i) {
    parent[i] = parent[parent[i]];
    i = parent[i];
  }
  return i;
}

/// Joins the sets of a and b under the lower root index, so that each set's root is its
/// lowest body index whatever the order of the joins.
void join(std::vector<std::uint32_t>& parent, std::uint32_t a, std::uint32_t b) {
  std::uint32_t const ra = find_root(parent, a), rb = find_root(parent, b);
  if (ra < rb)
    parent[rb] = ra;
  else if (rb < ra)
    parent[ra] = rb;
}

} // namespace

bool World::moving_kinematic(std::uint32_t i) const noexcept {
  Body const& b = bodies_[i];
  return b.moves() && b.type == BodyType::kinematic &&
         (nonzero(states_[i].linear_velocity) || nonzero(states_[i].angular_velocity));
}

void World::sleep_islands(std::vector<std::vector<std::uint32_t>> const& groups) {
  if (groups.empty()) return;
  flush_woken(); // the contact lists and touching pairs must be whole before they split
  // The trees must hold the bodies' final boxes before they leave moving_bodies_ (a full
  // refit only visits moving_bodies_).
  if (!trees_synced_) sync_trees();
  std::vector<std::uint32_t> members;
  for (std::vector<std::uint32_t> const& group : groups) {
    std::uint32_t k;
    if (!free_islands_.empty()) {
      k = free_islands_.back();
      free_islands_.pop_back();
    } else {
      k = std::uint32_t(islands_.size());
      islands_.emplace_back();
    }
    islands_[k].bodies = group;
    for (std::uint32_t i : group) {
      Body& b = bodies_[i];
      b.sleeping = true;
      b.island = k;
      b.sleep_time = 0.0f;
      states_[i].linear_velocity = Vec3{};
      states_[i].angular_velocity = Vec3{};
    }
    members.insert(members.end(), group.begin(), group.end());
  }
  std::sort(members.begin(), members.end());
  for (std::uint32_t i : members) {
    pending_.fell_asleep.push_back(BodyId{i, bodies_[i].generation});
    bvh_.set_box(i, grown_aabb(i), ProxyKind::sleeping); // its static pairs end there
  }
  sleeping_count_ += members.size();
  std::erase_if(moving_bodies_, [&](std::uint32_t i) { return bodies_[i].sleeping; });
  cache_.sleep(members);
  // Their touching pairs are now kept by the sleeping contacts; the events' diff sees only
  // awake pairs.
  std::erase_if(touching_now_, [&](std::uint64_t key) {
    return bodies_[body_pair_first(key)].sleeping || bodies_[body_pair_second(key)].sleeping;
  });
}

void World::wake(std::uint32_t i) {
  if (i >= bodies_.size() || !bodies_[i].alive || !bodies_[i].sleeping) return;
  std::vector<std::uint32_t> one{bodies_[i].island};
  wake_islands(one);
}

void World::wake_islands(std::vector<std::uint32_t>& islands) {
  if (islands.empty()) return;
  std::sort(islands.begin(), islands.end());
  islands.erase(std::unique(islands.begin(), islands.end()), islands.end());
  std::vector<std::uint32_t> members;
  for (std::uint32_t k : islands) {
    members.insert(members.end(), islands_[k].bodies.begin(), islands_[k].bodies.end());
    islands_[k].bodies = {};
    free_islands_.push_back(k);
  }
  std::sort(members.begin(), members.end());
  for (std::uint32_t m : members) {
    Body& b = bodies_[m];
    b.sleeping = false;
    b.island = no_island;
    b.sleep_time = 0.0f;
    pending_.woke_up.push_back(BodyId{m, b.generation});
    bvh_.set_box(m, grown_aabb(m), ProxyKind::dynamic); // queries for its pairs anew
  }
  sleeping_count_ -= members.size();
  std::size_t const old = moving_bodies_.size();
  moving_bodies_.insert(moving_bodies_.end(), members.begin(), members.end());
  std::inplace_merge(moving_bodies_.begin(), moving_bodies_.begin() + std::ptrdiff_t(old),
                     moving_bodies_.end());
  // Their contacts follow in one pass for every wake since the last (flush_woken): many
  // wakes between two steps (an explosion's impulses) scan the sleeping contacts once.
  woken_.insert(woken_.end(), members.begin(), members.end());
}

void World::flush_woken() {
  if (woken_.empty()) return;
  std::sort(woken_.begin(), woken_.end());
  // Their contacts are touching pairs again, for the events' diff and the solver.
  std::size_t const old_keys = touching_now_.size();
  for (Contact const& c : cache_.sleeping_contacts())
    if (std::binary_search(woken_.begin(), woken_.end(), c.body_a) ||
        std::binary_search(woken_.begin(), woken_.end(), c.body_b))
      touching_now_.push_back(body_pair_key(c.body_a, c.body_b));
  std::sort(touching_now_.begin() + std::ptrdiff_t(old_keys), touching_now_.end());
  std::inplace_merge(touching_now_.begin(), touching_now_.begin() + std::ptrdiff_t(old_keys),
                     touching_now_.end());
  touching_now_.erase(std::unique(touching_now_.begin(), touching_now_.end()), touching_now_.end());
  cache_.wake(woken_);
  woken_.clear();
}

void World::wake_around(std::uint32_t i) {
  if (sleeping_count_ == 0) return;
  // An awake body's contacts are awake: only the sleeping contacts can name a sleeper.
  std::vector<std::uint32_t> others;
  for (Contact const& c : cache_.sleeping_contacts())
    if (c.body_a == i || c.body_b == i) others.push_back(c.body_a == i ? c.body_b : c.body_a);
  for (Joint const& j : joints_)
    if (j.alive && (j.def.body_a.index == i || j.def.body_b.index == i))
      others.push_back(j.def.body_a.index == i ? j.def.body_b.index : j.def.body_a.index);
  // A sensor's overlaps with sleeping bodies are kept as they were while it stays put.
  for (std::uint64_t k : sensor_now_)
    if (body_pair_first(k) == i || body_pair_second(k) == i)
      others.push_back(body_pair_first(k) == i ? body_pair_second(k) : body_pair_first(k));
  others.push_back(i);
  std::vector<std::uint32_t> islands;
  for (std::uint32_t o : others)
    if (bodies_[o].alive && bodies_[o].sleeping) islands.push_back(bodies_[o].island);
  wake_islands(islands);
}

void World::wake_in(std::uint32_t i) {
  if (sleeping_count_ == 0) return;
  std::vector<std::uint32_t> near;
  if (config_.broad_phase == BroadPhaseKind::bvh) {
    candidates(grown_aabb(i), QueryFilter{}, near); // (a half-space's infinite box is clamped)
  } else {
    // Sort and sweep keeps the trees for queries only, and syncing them after a static edit
    // rebuilds the static tree: a level loaded body by body would rebuild it per body.
    Aabb3 const box = grown_aabb(i);
    for (Island const& island : islands_)
      for (std::uint32_t j : island.bodies)
        if (bool(grown_aabb(j).intersects(box))) near.push_back(j);
  }
  std::vector<std::uint32_t> islands;
  for (std::uint32_t j : near)
    if (j != i && bodies_[j].sleeping && bodies_[j].layers.interacts(bodies_[i].layers) &&
        (no_collide_pairs_.empty() || !jointed_no_collide(i, j)))
      islands.push_back(bodies_[j].island);
  wake_islands(islands);
}

void World::join_islands(std::vector<std::uint32_t>& parent) const {
  for (Contact const& c : cache_.contacts())
    if (bodies_[c.body_a].active() && bodies_[c.body_b].active()) join(parent, c.body_a, c.body_b);
  for (Joint const& j : joints_)
    if (j.alive && !j.broken && bodies_[j.def.body_a.index].active() &&
        bodies_[j.def.body_b.index].active())
      join(parent, j.def.body_a.index, j.def.body_b.index);
}

std::vector<std::uint32_t> World::island_of(std::uint32_t i) const {
  std::vector<std::uint32_t> parent(bodies_.size());
  for (std::uint32_t k = 0; k < parent.size(); ++k)
    parent[k] = k;
  join_islands(parent);
  std::uint32_t const root = find_root(parent, i);
  std::vector<std::uint32_t> out;
  for (std::uint32_t k : moving_bodies_)
    if (bodies_[k].active() && find_root(parent, k) == root) out.push_back(k);
  return out;
}

void World::update_sleep(float dt) {
  if (!config_.sleep) return;
  // Timers: the speed of each awake body's farthest point against its threshold.
  bool kinematics = false; // a kinematic body with a velocity: the loops below have work
  for (std::uint32_t i : moving_bodies_) {
    Body& b = bodies_[i];
    kinematics = kinematics || moving_kinematic(i);
    if (!b.active()) continue;
    BodyState const& s = states_[i];
    float const speed = s.linear_velocity.length() + s.angular_velocity.length() * b.max_extent;
    if (b.sleep_enabled && speed <= b.sleep_threshold)
      b.sleep_time += dt;
    else
      b.sleep_time = 0.0f;
  }
  // A body that a moving kinematic body touches or holds stays awake.
  auto const kinematic_keeps = [&](std::uint32_t a, std::uint32_t b) {
    if (bodies_[b].active() && moving_kinematic(a)) bodies_[b].sleep_time = 0.0f;
    if (bodies_[a].active() && moving_kinematic(b)) bodies_[a].sleep_time = 0.0f;
  };
  if (kinematics) {
    for (Contact const& c : cache_.contacts())
      kinematic_keeps(c.body_a, c.body_b);
    for (Joint const& j : joints_)
      if (j.alive && !j.broken) kinematic_keeps(j.def.body_a.index, j.def.body_b.index);
  }

  // Islands: the awake bodies joined by contacts and joints, each rooted at its lowest index.
  float const limit = config_.time_to_sleep;
  bool any = false;
  parent_.resize(bodies_.size());
  island_time_.resize(bodies_.size());
  island_slot_.resize(bodies_.size());
  for (std::uint32_t i : moving_bodies_)
    if (bodies_[i].active()) {
      parent_[i] = i;
      any = any || (bodies_[i].sleep_time >= limit && bodies_[i].sleep_time > 0.0f);
    }
  if (!any) return; // no body can sleep, so no island can
  join_islands(parent_);
  // An island's time is its members' least (a root comes first in index order).
  for (std::uint32_t i : moving_bodies_) {
    if (!bodies_[i].active()) continue;
    std::uint32_t const r = find_root(parent_, i);
    island_time_[r] =
        r == i ? bodies_[i].sleep_time : std::min(island_time_[r], bodies_[i].sleep_time);
  }
  std::vector<std::vector<std::uint32_t>> sleepers;
  for (std::uint32_t i : moving_bodies_) {
    if (!bodies_[i].active()) continue;
    std::uint32_t const r = find_root(parent_, i);
    // (> 0 too: every member below its threshold in this step, whatever time_to_sleep is)
    if (!(island_time_[r] >= limit && island_time_[r] > 0.0f)) continue;
    if (r == i) {
      island_slot_[r] = std::uint32_t(sleepers.size());
      sleepers.emplace_back();
    }
    sleepers[island_slot_[r]].push_back(i);
  }
  sleep_islands(sleepers); // each group sorted: gathered in index order
}

void World::wake_touched() {
  if (sleeping_count_ == 0) return;
  std::array<Manifold, max_mesh_manifolds> ms;
  std::vector<std::uint32_t> islands;
  for (;;) {
    islands.clear();
    for (std::uint64_t const pair : pairs_) {
      std::uint32_t const a = body_pair_first(pair), b = body_pair_second(pair);
      Body const& x = bodies_[a];
      Body const& y = bodies_[b];
      if (x.sleeping == y.sleeping) continue; // both awake (or, never here, both asleep)
      std::uint32_t const other = x.sleeping ? b : a;
      if (!bodies_[other].active() && !moving_kinematic(other)) continue;
      int const n = detail::collide(x.shape, x.pose, y.shape, y.pose, config_.manifold, ms);
      bool touch = false;
      for (int k = 0; k < n; ++k)
        touch = touch || ms[std::size_t(k)].count > 0;
      if (touch) islands.push_back(x.sleeping ? x.island : y.island);
    }
    // A kinematic body that moves drags what it is jointed to (such a pair has no contact).
    for (Joint const& j : joints_) {
      if (!j.alive || j.broken) continue;
      std::uint32_t const a = j.def.body_a.index, b = j.def.body_b.index;
      if (bodies_[a].sleeping && moving_kinematic(b)) islands.push_back(bodies_[a].island);
      if (bodies_[b].sleeping && moving_kinematic(a)) islands.push_back(bodies_[b].island);
    }
    if (islands.empty()) break;
    wake_islands(islands);
    flush_woken();
    // The woken bodies' pairs with static bodies and with each other: found again (the
    // pairs of a body pair do not depend on when they are asked for).
    find_pairs();
    split_sensor_pairs();
  }
  std::erase_if(pairs_, [&](std::uint64_t k) {
    return bodies_[body_pair_first(k)].sleeping || bodies_[body_pair_second(k)].sleeping;
  });
}

BodyError World::set_awake(BodyId id, bool awake) {
  if (!is_alive(id)) return BodyError::bad_body;
  std::uint32_t const i = id.index;
  if (awake) {
    wake(i);
  } else if (config_.sleep && bodies_[i].active()) {
    flush_woken(); // island_of reads the awake contacts
    std::vector<std::uint32_t> members = island_of(i);
    bool const may = std::all_of(members.begin(), members.end(),
                                 [&](std::uint32_t m) { return bodies_[m].sleep_enabled; });
    if (may) sleep_islands({std::move(members)});
  }
  return BodyError::none;
}

void World::wake_all() {
  std::vector<std::uint32_t> islands;
  for (std::uint32_t k = 0; k < islands_.size(); ++k)
    if (!islands_[k].bodies.empty()) islands.push_back(k);
  wake_islands(islands);
}

BodyError World::set_sleep_enabled(BodyId id, bool enabled) {
  if (!is_alive(id)) return BodyError::bad_body;
  if (!enabled) wake(id.index);
  bodies_[id.index].sleep_enabled = enabled;
  if (!enabled) bodies_[id.index].sleep_time = 0.0f;
  return BodyError::none;
}

BodyError World::set_sleep_threshold(BodyId id, float threshold) {
  if (!is_alive(id)) return BodyError::bad_body;
  if (!std::isfinite(threshold)) return BodyError::non_finite;
  if (threshold < 0.0f) return BodyError::bad_material;
  wake(id.index);
  bodies_[id.index].sleep_threshold = threshold;
  return BodyError::none;
}

} // namespace plume
