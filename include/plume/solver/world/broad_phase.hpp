// plume/solver/world/broad_phase.hpp - the world's broad phase: which pairs of bodies have
// overlapping bounding boxes. Two implementations with the same result (the same pairs, as
// sorted body_pair_key()s), chosen by WorldConfig::broad_phase:
//
// BvhBroadPhase (the default) keeps the bodies in bounding volume hierarchies
// (spatial/aabb_tree.hpp): one tree for static bodies, one for kinematic and dynamic ones,
// and a list of unbounded bodies (half-spaces: a box with an infinite coordinate). Each step
// only the moving bodies' boxes are updated (a leaf moves when its box leaves the fat box,
// grown by the tree's margin), each querying body (dynamic or kinematic, not frozen) asks
// the static tree (dynamic bodies only), the moving tree and the unbounded list, and every
// candidate is checked on the exact boxes. A static body costs nothing per step; the static
// tree is rebuilt (binned SAH) only in a step after static bodies were added or moved, and the
// moving tree is optimised each step (TreeOptimization::adaptive).
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

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace plume {

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

/// The BVH broad phase (see above), over bodies numbered by the world's slots.
class BvhBroadPhase {
public:
  BvhBroadPhase();

  std::size_t body_count() const noexcept { return slots_.size(); }
  /// Body `index` leaves the broad phase (nothing if it is not in it).
  void remove(std::uint32_t index);
  /// Body `index` now has the (grown) box `box`; `moving`: kinematic or dynamic. A box that
  /// is not a valid tree box (an infinite coordinate, as a half-space's; or NaN, or min > max)
  /// puts the body on the unbounded list: it never queries, and each querier tests it exactly.
  void set_box(std::uint32_t index, Aabb3 const& box, bool moving);
  /// The pairs (i, j) whose boxes overlap and for which keep(i, j) holds, found from the
  /// querying bodies (dynamic ones, which ask every tree, and kinematic ones, which skip the
  /// static tree; frozen bodies query nothing), as body_pair_key()s in increasing order,
  /// written to `pairs` (cleared first). Optimises the trees first.
  template <class Keep>
  void find_pairs(std::span<std::uint32_t const> dynamic, std::span<std::uint32_t const> kinematic,
                  Keep&& keep, std::vector<std::uint64_t>& pairs);

  /// The box body `index` last got (the exact box the pairs are checked on).
  Aabb3 const& box(std::uint32_t index) const { return slots_.at(index).box; }
  /// The bodies on the unbounded list, by index.
  std::span<std::uint32_t const> unbounded() const noexcept { return unbounded_; }
  AabbTree const& static_tree() const noexcept { return static_; }
  AabbTree const& moving_tree() const noexcept { return moving_; }
  /// What the moving tree's last optimisation ran.
  TreeOptimization last_optimization() const noexcept { return last_; }

  /// Rebuilds the static tree if statics changed, optimises the moving tree (find_pairs
  /// does this first; call it when the trees serve queries only).
  void optimize();

private:
  enum class Where : std::uint8_t { none, static_tree, moving_tree, unbounded };
  struct Slot {
    Where where = Where::none;
    ProxyId proxy = null_proxy;
    Aabb3 box;
  };

  AabbTree static_, moving_;
  std::vector<Slot> slots_;
  std::vector<std::uint32_t> unbounded_;
  std::vector<char> querier_;
  bool static_changed_ = false;
  TreeOptimization last_ = TreeOptimization::reinsert;
};

template <class Keep>
void BvhBroadPhase::find_pairs(std::span<std::uint32_t const> dynamic,
                               std::span<std::uint32_t const> kinematic, Keep&& keep,
                               std::vector<std::uint64_t>& pairs) {
  optimize();
  pairs.clear();
  querier_.assign(slots_.size(), 0);
  for (auto const list : {dynamic, kinematic})
    for (std::uint32_t i : list)
      if (slots_[i].where == Where::moving_tree) querier_[i] = 1;
  auto const query_from = [&](std::uint32_t i, bool ask_static) {
    if (!querier_[i]) return;
    Aabb3 const& box = slots_[i].box;
    auto const consider = [&](std::uint32_t j) {
      if (bool(box.intersects(slots_[j].box)) && keep(i, j)) pairs.push_back(body_pair_key(i, j));
    };
    if (ask_static)
      static_.query(box, [&](ProxyId p) {
        consider(std::uint32_t(static_.user(p)));
        return true;
      });
    moving_.query(box, [&](ProxyId p) {
      std::uint32_t const j = std::uint32_t(moving_.user(p));
      if (j != i && (!querier_[j] || i < j)) consider(j); // a pair of queriers once
      return true;
    });
    for (std::uint32_t j : unbounded_)
      consider(j);
  };
  for (std::uint32_t i : dynamic)
    query_from(i, true);
  for (std::uint32_t i : kinematic)
    query_from(i, false);
  std::sort(pairs.begin(), pairs.end());
}

} // namespace plume
