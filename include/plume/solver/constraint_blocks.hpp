// plume/solver/constraint_blocks.hpp - constraints packed for the wide solver: the overflow
// (constraints the colouring could not place, solved one at a time as Constraint<float>) and
// then every colour in order, as blocks of W = lanes_v<T> constraints (Constraint<T>), the
// last block of a colour padded with empty lanes.
//
//   GConstraintBlocks<GContactConstraint, T> blocks;
//   blocks.pack(colors, prepare, clear);        // colors[i]: constraint i's colour
//   blocks.pack_grouped<5>(colors, key, prepare, clear);  // within a colour, by key(i)
//   blocks.for_each([&](auto& c) { solve_contacts(c, ...); });  // overflow, then the blocks
//   blocks.for_each_by_color(run, f);           // each colour's blocks as one range task
//   blocks.for_each_lane([&](auto const& c, std::size_t lane, std::uint32_t i) { ... });
//
// No constraint appears twice and no dynamic body appears twice in a block (the colouring's
// rule), so a block's lanes are independent; the order of for_each is the solver's order and
// does not depend on W, which is what keeps every width's result bitwise the same. Contacts
// and joints (one set of blocks per kind) use it.
//
// Within a colour the order of constraints does not change any result (they share no body
// the solver writes), so pack_grouped() may sort a colour by a small key: constraints with
// the same work shape (contacts: the point count) then share blocks, and a block's kernel
// runs only the work its lanes need. The overflow always keeps index order (it is solved
// one constraint after another, so its order matters).
#pragma once

#include <plume/numerics.hpp>
#include <plume/solver/constraint_graph.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace plume {

template <template <class> class Constraint, Real T>
class GConstraintBlocks {
public:
  static constexpr std::size_t lanes = lanes_v<T>;
  static constexpr int color_count = ConstraintGraph::color_count;
  static constexpr std::uint32_t empty_lane = ~std::uint32_t(0);

  /// Packs constraints 0..colors.size()-1: constraint i goes to colour colors[i] (0 ..
  /// color_count-1) or, for any other value (ConstraintGraph::overflow), to the overflow.
  /// Within a colour, constraints keep their index order. prepare(c, lane, i) fills lane
  /// `lane` of c (a Constraint<T> block or a Constraint<float> overflow entry) from
  /// constraint i; clear(block, lane) empties a padding lane.
  template <class Prepare, class Clear>
  void pack(std::span<int const> colors, Prepare&& prepare, Clear&& clear) {
    pack(colors, prepare, clear, serial_ranges);
  }
  /// pack(), with the blocks' lanes prepared through run(n, g) (see pack_grouped()).
  template <class Prepare, class Clear, class Run>
  void pack(std::span<int const> colors, Prepare&& prepare, Clear&& clear, Run&& run) {
    pack_grouped<1>(
        colors, [](std::uint32_t) { return 0u; }, prepare, clear, run);
  }

  /// pack(), with each colour ordered by key(i) (an integer below KeyCount; ascending, index
  /// order within a key). A colour's constraints of one key fill whole blocks before the next
  /// key's begin, so at most KeyCount - 1 blocks per colour hold two keys. The overflow keeps
  /// index order. A key outside [0, KeyCount) is taken as KeyCount - 1.
  template <std::size_t KeyCount, class Key, class Prepare, class Clear>
  void pack_grouped(std::span<int const> colors, Key&& key, Prepare&& prepare, Clear&& clear) {
    pack_grouped<KeyCount>(colors, key, prepare, clear, serial_ranges);
  }

  /// pack_grouped(), with the blocks' lanes prepared through run(n, g): g(begin, end) over
  /// sub-ranges of blocks [0, n) covering each once, in any order and on any thread (a
  /// task system's parallel_for); prepare and clear then must only write the block they are
  /// given. The overflow is prepared on the calling thread, after the blocks.
  template <std::size_t KeyCount, class Key, class Prepare, class Clear, class Run>
  void pack_grouped(std::span<int const> colors, Key&& key, Prepare&& prepare, Clear&& clear,
                    Run&& run) {
    static_assert(KeyCount >= 1);
    // Buckets colour-major, key-minor; the last one is the overflow.
    std::vector<std::vector<std::uint32_t>>& buckets = buckets_;
    buckets.resize(color_count * KeyCount + 1);
    for (auto& b : buckets)
      b.clear();
    std::size_t const overflow_bucket = color_count * KeyCount;
    for (std::uint32_t i = 0; i < colors.size(); ++i) {
      int const c = colors[i];
      if (c < 0 || c >= color_count) {
        buckets[overflow_bucket].push_back(i);
        continue;
      }
      std::size_t k = std::size_t(key(i));
      if (k >= KeyCount) k = KeyCount - 1;
      buckets[std::size_t(c) * KeyCount + k].push_back(i);
    }
    std::size_t block_count = 0;
    for (std::size_t c = 0; c < color_count; ++c) {
      std::size_t n = 0;
      for (std::size_t k = 0; k < KeyCount; ++k)
        n += buckets[c * KeyCount + k].size();
      sizes_[c] = n;
      color_begin_[c] = block_count;
      block_count += (n + lanes - 1) / lanes;
    }
    color_begin_[color_count] = block_count;
    sizes_[color_count] = buckets[overflow_bucket].size();
    blocks_.assign(block_count, Constraint<T>{});
    block_items_.assign(block_count * lanes, empty_lane);
    std::size_t slot = 0; // lane slots filled so far, over every block
    for (std::size_t c = 0; c < color_count; ++c) {
      for (std::size_t k = 0; k < KeyCount; ++k)
        for (std::uint32_t const i : buckets[c * KeyCount + k])
          block_items_[slot++] = i;
      slot = (slot + lanes - 1) / lanes * lanes; // the colour's last block: padding lanes
    }
    run(std::uint32_t(block_count), [&](std::uint32_t begin, std::uint32_t end) {
      for (std::size_t b = begin; b < end; ++b)
        for (std::size_t lane = 0; lane < lanes; ++lane)
          if (std::uint32_t const i = block_items_[b * lanes + lane]; i != empty_lane)
            prepare(blocks_[b], lane, i);
          else
            clear(blocks_[b], lane);
    });
    overflow_items_.assign(buckets[overflow_bucket].begin(), buckets[overflow_bucket].end());
    overflow_.assign(overflow_items_.size(), Constraint<float>{});
    for (std::size_t k = 0; k < overflow_.size(); ++k)
      prepare(overflow_[k], 0, overflow_items_[k]);
  }

  /// f(c) for every overflow constraint and then every block, in the solver's order.
  template <class F>
  void for_each(F&& f) {
    for (auto& c : overflow_)
      f(c);
    for (auto& c : blocks_)
      f(c);
  }

  /// for_each(), with each colour's blocks run through run(n, g) as pack_grouped()'s: the
  /// overflow one constraint after another on the calling thread, then the colours in order,
  /// each colour's blocks in any order and on any thread (they share no body the solver
  /// writes, so the result is the same as for_each()'s).
  template <class Run, class F>
  void for_each_by_color(Run&& run, F&& f) {
    for (auto& c : overflow_)
      f(c);
    for (std::size_t c = 0; c < color_count; ++c) {
      std::size_t const first = color_begin_[c];
      if (std::size_t const n = color_begin_[c + 1] - first; n != 0)
        run(std::uint32_t(n), [&](std::uint32_t begin, std::uint32_t end) {
          for (std::size_t b = begin; b < end; ++b)
            f(blocks_[first + b]);
        });
    }
  }

  /// f(c, lane, i) for every filled lane: c holds constraint i in lane `lane`.
  template <class F>
  void for_each_lane(F&& f) const {
    for (std::size_t k = 0; k < overflow_.size(); ++k)
      f(overflow_[k], std::size_t(0), overflow_items_[k]);
    for (std::size_t b = 0; b < blocks_.size(); ++b)
      for (std::size_t lane = 0; lane < lanes; ++lane)
        if (std::uint32_t const i = block_items_[b * lanes + lane]; i != empty_lane)
          f(blocks_[b], lane, i);
  }

  /// Constraints per colour of the last pack(); index color_count is the overflow.
  std::array<std::size_t, color_count + 1> const& color_sizes() const noexcept { return sizes_; }
  std::size_t block_count() const noexcept { return blocks_.size(); }
  std::size_t overflow_count() const noexcept { return overflow_.size(); }

private:
  std::vector<Constraint<T>> blocks_;
  std::vector<std::uint32_t> block_items_; ///< lanes per block: constraint index or empty_lane
  std::vector<Constraint<float>> overflow_;
  std::vector<std::uint32_t> overflow_items_;
  std::array<std::size_t, color_count + 1> sizes_{};
  std::array<std::size_t, color_count + 1> color_begin_{}; ///< colour c: blocks from [c] to [c + 1]
  /// pack()'s run when none is given: every block on the calling thread.
  static constexpr auto serial_ranges = [](std::uint32_t n, auto&& g) { g(std::uint32_t(0), n); };
  std::vector<std::vector<std::uint32_t>> buckets_; ///< pack's scratch, kept for its capacity
};

} // namespace plume
