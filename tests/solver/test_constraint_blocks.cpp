// Constraint blocks: every constraint lands in exactly one lane, colours in order with their
// constraints in index order, padding lanes cleared, the overflow first and one at a time.
#include "../common/types.hpp"

#include <plume/solver/constraint_blocks.hpp>

#include <catch2/catch.hpp>

#include <cstdint>
#include <random>
#include <vector>

using namespace plume;

namespace {

/// A stand-in constraint: per lane, the constraint index it holds (-1 cleared, -2 never set).
template <class T>
struct GProbe {
  std::array<std::int64_t, lanes_v<T>> item;
  GProbe() { item.fill(-2); }
};

} // namespace

TEMPLATE_LIST_TEST_CASE("constraint blocks: one lane per constraint, in the solver's order",
                        "[solver][blocks]", test::f32_types) {
  using T = TestType;
  constexpr std::size_t W = lanes_v<T>;
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    std::size_t const n = std::size_t(rng() % 200);
    std::vector<int> colors(n);
    for (int& c : colors) { // colours 0..6, the overflow (-1), a stray value (99: overflow)
      int const v = int(rng() % 9) - 1;
      c = v == 7 ? 99 : v;
    }
    GConstraintBlocks<GProbe, T> blocks;
    blocks.pack(
        colors,
        [&]<class U>(GProbe<U>& c, std::size_t lane, std::uint32_t i) {
          CHECK(c.item[lane] == -2);
          c.item[lane] = i;
        },
        [&](GProbe<T>& c, std::size_t lane) {
          CHECK(c.item[lane] == -2);
          c.item[lane] = -1;
        });
    // The solver's order: overflow entries (index order), then colour 0, 1, ... in blocks.
    std::vector<std::int64_t> order, expected;
    for (std::size_t i = 0; i < n; ++i)
      if (colors[i] < 0 || colors[i] >= ConstraintGraph::color_count) expected.push_back(i);
    std::size_t padding = 0;
    for (int c = 0; c < ConstraintGraph::color_count; ++c) {
      std::size_t count = 0;
      for (std::size_t i = 0; i < n; ++i)
        if (colors[i] == c) {
          expected.push_back(i);
          ++count;
        }
      CHECK(blocks.color_sizes()[std::size_t(c)] == count);
      padding += (W - count % W) % W;
    }
    blocks.for_each([&](auto& c) {
      for (std::int64_t i : c.item)
        if (i != -1) order.push_back(i);
    });
    CHECK(order == expected);
    CHECK(blocks.overflow_count() == blocks.color_sizes()[ConstraintGraph::color_count]);
    // Every filled lane once, and nothing but padding left empty.
    std::size_t lanes_seen = 0, cleared = 0;
    blocks.for_each_lane([&](auto const& c, std::size_t lane, std::uint32_t i) {
      CHECK(c.item[lane] == std::int64_t(i));
      ++lanes_seen;
    });
    blocks.for_each([&](auto& c) {
      for (std::int64_t i : c.item) {
        CHECK(i != -2);
        cleared += i == -1;
      }
    });
    CHECK(lanes_seen == n);
    CHECK(cleared == padding);
  }
}
