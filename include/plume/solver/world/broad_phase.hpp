// plume/solver/world/broad_phase.hpp - the world's broad phase: which pairs of bodies have
// overlapping bounding boxes. One class, so that a bounding volume hierarchy can take its
// place behind the same call.
//
// SortAndSweep sorts the boxes on their minimum x (ties by body index) and sweeps: each box
// is tested against the following boxes whose minimum x is at most its maximum x. Cost
// O(n log n + n k) per call for k overlaps along x, every body every step (nothing is kept
// between calls but the buffer). Boxes touching on a face overlap (closed intervals).
// A box with a NaN coordinate overlaps nothing it would not overlap with that coordinate
// removed from the comparisons (every comparison with NaN is false); the world never passes
// one (non-finite bodies are frozen first).
#pragma once

#include <plume/math/aabb3.hpp>

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

} // namespace plume
