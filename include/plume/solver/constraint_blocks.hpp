// plume/solver/constraint_blocks.hpp - constraints packed for the wide solver: the overflow
// (constraints the colouring could not place, solved one at a time as Constraint<float>) and
// then every colour in order, as blocks of W = lanes_v<T> constraints (Constraint<T>), the
// last block of a colour padded with empty lanes.
//
//   GConstraintBlocks<GContactConstraint, T> blocks;
//   blocks.pack(colors, prepare, clear);        // colors[i]: constraint i's colour
//   blocks.for_each([&](auto& c) { solve_contacts(c, ...); });  // overflow, then the blocks
//   blocks.for_each_lane([&](auto const& c, std::size_t lane, std::uint32_t i) { ... });
//
// No constraint appears twice and no dynamic body appears twice in a block (the colouring's
// rule), so a block's lanes are independent; the order of for_each is the solver's order and
// does not depend on W, which is what keeps every width's result bitwise the same. Contacts
// use it now; joints will be packed the same way, with their own blocks.
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
    std::array<std::vector<std::uint32_t>, color_count + 1> buckets; // [color_count]: overflow
    for (std::uint32_t i = 0; i < colors.size(); ++i) {
      int const c = colors[i];
      bool const colored = c >= 0 && c < color_count;
      buckets[colored ? std::size_t(c) : std::size_t(color_count)].push_back(i);
    }
    std::size_t block_count = 0;
    for (std::size_t c = 0; c <= color_count; ++c) {
      sizes_[c] = buckets[c].size();
      if (c < color_count) block_count += (buckets[c].size() + lanes - 1) / lanes;
    }
    blocks_.assign(block_count, Constraint<T>{});
    block_items_.assign(block_count * lanes, empty_lane);
    std::size_t b = 0;
    for (std::size_t c = 0; c < color_count; ++c)
      for (std::size_t k = 0; k < buckets[c].size(); k += lanes, ++b)
        for (std::size_t lane = 0; lane < lanes; ++lane) {
          if (k + lane < buckets[c].size()) {
            std::uint32_t const i = buckets[c][k + lane];
            prepare(blocks_[b], lane, i);
            block_items_[b * lanes + lane] = i;
          } else {
            clear(blocks_[b], lane);
          }
        }
    overflow_items_ = std::move(buckets[color_count]);
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
};

} // namespace plume
