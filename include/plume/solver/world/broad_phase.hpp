// plume/solver/world/broad_phase.hpp - the world's broad phase: which pairs of bodies have
// overlapping bounding boxes. Two implementations with the same result (the same pairs, as
// sorted body_pair_key()s), chosen by WorldConfig::broad_phase:
//
// BvhBroadPhase (the default) keeps the bodies in bounding volume hierarchies
// (spatial/aabb_tree.hpp), one per kind as Avian's: static, kinematic, dynamic and standalone
// colliders (colliders without a body), plus one for sleeping dynamic bodies (ProxyKind), and
// a list of unbounded ones (half-spaces: a box with
// an infinite coordinate). Pairs persist between
// steps, as Box2D v3's: a candidate pair is kept while the two fat boxes (a tree leaf's box,
// grown by the tree's margin; an unbounded body's own box) overlap, and only bodies whose fat
// box changed this step (moved out of it, new, or of a new kind) query the trees for new
// candidates: a dynamic body asks every tree and the unbounded list, a kinematic one the
// dynamic and sleeping trees, a sleeping one the dynamic and kinematic trees, any other body
// the dynamic tree (and each the unbounded bodies it pairs with). A body that stays inside its fat
// box, static or not, costs one exact box test per candidate pair and no query. Each step's pairs
// are the candidates whose exact boxes overlap and that keep() accepts, so they are the same as a
// brute-force loop's. The static tree is rebuilt (binned SAH) only in a step after static
// bodies were added or moved; the kinematic, dynamic and standalone trees are optimised each
// step (TreeOptimization::adaptive).
//
// SortAndSweep sorts the boxes on their minimum x (ties by body index) and sweeps: each box
// is tested against the following boxes whose minimum x is at most its maximum x. Cost
// O(n log n + n k) per call for k overlaps along x, every body every step (nothing is kept
// between calls but the buffer). Kept as the baseline the BVH is measured against.
//
// Boxes touching on a face overlap (closed intervals). A box with a NaN coordinate overlaps
// nothing it would not overlap with that coordinate removed from the comparisons (every
// comparison with NaN is false); the world never passes one (non-finite bodies are frozen
// first).
#pragma once

#include <plume/math/aabb3.hpp>
#include <plume/spatial/aabb_tree.hpp>
#include <plume/spatial/wide_bvh.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <span>
#include <vector>

namespace plume {

class TaskSystem; // solver/world/tasks.hpp

/// A body pair as one sortable key: the smaller index in the high 32 bits.
constexpr std::uint64_t body_pair_key(std::uint32_t a, std::uint32_t b) noexcept {
  return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}
constexpr std::uint32_t body_pair_first(std::uint64_t key) noexcept {
  return std::uint32_t(key >> 32);
}
constexpr std::uint32_t body_pair_second(std::uint64_t key) noexcept { return std::uint32_t(key); }

class SortAndSweep {
public:
  /// The pairs (i, j) of boxes[i] and boxes[j] that overlap and for which keep(i, j) holds,
  /// as body_pair_key()s in increasing order, written to `pairs` (cleared first).
  template <class Keep>
  void find_pairs(std::span<Aabb3 const> boxes, Keep&& keep, std::vector<std::uint64_t>& pairs) {
    sort(boxes);
    pairs.clear();
    std::size_t const n = proxies_.size();
    for (std::size_t i = 0; i < n; ++i) {
      Proxy const& p = proxies_[i];
      for (std::size_t j = i + 1; j < n && proxies_[j].box.min.x <= p.box.max.x; ++j) {
        Proxy const& q = proxies_[j];
        if (p.box.max.y < q.box.min.y || q.box.max.y < p.box.min.y || p.box.max.z < q.box.min.z ||
            q.box.max.z < p.box.min.z)
          continue;
        if (!keep(p.index, q.index)) continue;
        pairs.push_back(body_pair_key(p.index, q.index));
      }
    }
    std::sort(pairs.begin(), pairs.end());
  }

private:
  struct Proxy {
    Aabb3 box;
    std::uint32_t index;
  };
  void sort(std::span<Aabb3 const> boxes);
  std::vector<Proxy> proxies_; ///< the boxes by (min.x, index)
};

/// What a body is to the BVH broad phase: which tree holds it and what it pairs with (a pair
/// needs at least one dynamic body, or a sleeping and a kinematic one; the caller's keep()
/// refines that, e.g. for frozen bodies). standalone: a collider without a body (pairs as a
/// static body, in a tree of its own). sleeping: a dynamic body asleep, in a tree of its own:
/// it pairs with dynamic and kinematic bodies (which may wake it) but not with static ones,
/// so that a sleeping pile costs the broad phase nothing per step.
enum class ProxyKind : std::uint8_t { static_body, kinematic, dynamic, standalone, sleeping };
/// The number of trees (one per ProxyKind).
inline constexpr std::size_t proxy_kind_count = 5;
/// Whether bodies of these kinds pair (given overlapping boxes and the caller's keep()).
constexpr bool kinds_pair(ProxyKind a, ProxyKind b) noexcept {
  return a == ProxyKind::dynamic || b == ProxyKind::dynamic ||
         (a == ProxyKind::sleeping && b == ProxyKind::kinematic) ||
         (a == ProxyKind::kinematic && b == ProxyKind::sleeping);
}

/// The BVH broad phase (see above), over bodies numbered by the world's slots.
class BvhBroadPhase {
public:
  BvhBroadPhase();

  std::size_t body_count() const noexcept { return slots_.size(); }
  /// Body `index` leaves the broad phase and its pairs (nothing if it is not in it).
  void remove(std::uint32_t index);
  /// Body `index` now has the (grown) box `box` and kind `kind`. A box that is not a valid
  /// tree box (an infinite coordinate, as a half-space's; or NaN, or min > max) puts the body
  /// on the unbounded list instead of a tree. The body counts as moved (find_pairs() queries
  /// for it) when it is new, changes kind or its box leaves its tree's fat box.
  void set_box(std::uint32_t index, Aabb3 const& box, ProxyKind kind);
  /// The pairs (i, j) whose boxes overlap, of kinds that pair (kinds_pair), for which keep(i, j)
  /// holds, as body_pair_key()s in increasing order, written to `pairs` (cleared first).
  /// Optimises the trees first; then queries the trees for the moved bodies only, in chunks
  /// run through `tasks` when given (solver/world/tasks.hpp; the same pairs either way).
  template <class Keep>
  void find_pairs(Keep&& keep, std::vector<std::uint64_t>& pairs, TaskSystem* tasks = nullptr);

  /// The box body `index` last got (the exact box the pairs are checked on).
  Aabb3 const& box(std::uint32_t index) const { return slots_.at(index).box; }
  /// The bodies on the unbounded list, by index.
  std::span<std::uint32_t const> unbounded() const noexcept { return unbounded_; }
  AabbTree const& tree(ProxyKind kind) const noexcept { return trees_[std::size_t(kind)]; }
  /// The five trees (static, kinematic, dynamic, standalone, sleeping), for queries over
  /// every body.
  std::array<AabbTree const*, proxy_kind_count> trees() const noexcept {
    return {&trees_[0], &trees_[1], &trees_[2], &trees_[3], &trees_[4]};
  }
  /// A wide copy of the static tree (WideBvh: stored_lanes children per node, at least 4,
  /// read at f32xR by the queries below), rebuilt with
  /// it: null while static bodies changed since the last optimize() (use tree() then). The
  /// same leaves as the static tree, found in fewer, wider steps.
  WideBvh const* static_wide() const noexcept { return wide_fresh_ ? &static_wide_ : nullptr; }
  /// f(ProxyId) for every static leaf whose fat box meets `box`, through the wide copy when it
  /// is fresh (in another order than the tree's); f returns false to stop.
  template <class F>
  void query_static(Aabb3 const& box, F&& f) const {
    if (wide_fresh_)
      static_wide_.template query<f32xR>(box, f);
    else
      trees_[std::size_t(ProxyKind::static_body)].query(box, f);
  }
  /// ray_query on the static leaves, through the wide copy when it is fresh.
  template <class F>
  void ray_static(Ray3 const& ray, float max_toi, F&& f) const {
    if (wide_fresh_)
      static_wide_.template ray_query<f32xR>(ray, max_toi, f);
    else
      trees_[std::size_t(ProxyKind::static_body)].ray_query(ray, max_toi, f);
  }
  /// Rebuilds the static tree and its wide copy if static bodies changed (optimize() does
  /// this too; the world calls it before queries between steps).
  void refresh_static();
  /// What the last optimisation of the kinematic, dynamic and standalone trees ran.
  TreeOptimization last_optimization(ProxyKind kind) const noexcept {
    return last_[std::size_t(kind)];
  }
  /// Candidate pairs kept between steps (fat boxes overlapping, of kinds that pair).
  std::size_t candidate_count() const noexcept { return candidates_.size(); }
  /// Bodies queried by the last find_pairs() (the moved ones).
  std::size_t last_query_count() const noexcept { return last_queries_; }

  /// Rebuilds the static tree if statics changed, optimises the other trees
  /// (find_pairs does this first; call it when the trees serve queries only).
  void optimize();

private:
  struct Slot {
    bool live = false, unbounded = false;
    ProxyKind kind = ProxyKind::static_body;
    ProxyId proxy = null_proxy;
    Aabb3 box;
  };
  AabbTree& tree_of(Slot const& s) noexcept { return trees_[std::size_t(s.kind)]; }
  /// The box a body's pairs are kept on: its tree's fat box, or its box when unbounded.
  Aabb3 const& fat(std::uint32_t i) const {
    Slot const& s = slots_[i];
    return s.unbounded ? s.box : trees_[std::size_t(s.kind)].fat_box(s.proxy);
  }
  void mark_moved(std::uint32_t i);
  void update_candidates(TaskSystem* tasks);

  std::array<AabbTree, proxy_kind_count> trees_; ///< by ProxyKind
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> unbounded_;
  std::vector<std::uint32_t> moved_;              ///< bodies to query for new pairs, each once
  std::vector<char> is_moved_;                    ///< by body: in moved_
  std::vector<std::uint64_t> candidates_, fresh_; ///< sorted keys; this step's new ones
  std::vector<std::vector<std::uint64_t>> fresh_chunks_; ///< new keys per chunk of moved_
  std::size_t last_queries_ = 0;
  bool static_changed_ = false;
  WideBvh static_wide_;
  bool wide_fresh_ = false;
  std::array<TreeOptimization, proxy_kind_count> last_{};
};

template <class Keep>
void BvhBroadPhase::find_pairs(Keep&& keep, std::vector<std::uint64_t>& pairs, TaskSystem* tasks) {
  optimize();
  update_candidates(tasks);
  pairs.clear();
  for (std::uint64_t k : candidates_) {
    std::uint32_t const i = body_pair_first(k), j = body_pair_second(k);
    if (bool(slots_[i].box.intersects(slots_[j].box)) && keep(i, j)) pairs.push_back(k);
  }
}

} // namespace plume
