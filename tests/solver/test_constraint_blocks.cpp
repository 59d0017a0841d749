// Constraint blocks: every constraint lands in exactly one lane, colours in order with their
// constraints in index order (pack_grouped: by key, then index), padding lanes cleared at a
// colour's end, the overflow first and one at a time in index order.
#include "../common/types.hpp"

#include <plume/solver/constraint_blocks.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
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

/// Packs `colors` (with `key` when KeyCount > 0: pack_grouped<KeyCount>, else pack) and
/// checks the solver's order: overflow entries in index order, then colour 0, 1, ... in
/// blocks, each colour by key (index order within a key), padding only at a colour's end.
template <class T, std::size_t KeyCount>
void check_pack(std::vector<int> const& colors, std::vector<std::uint32_t> const& key) {
  constexpr std::size_t W = lanes_v<T>;
  std::size_t const n = colors.size();
  GConstraintBlocks<GProbe, T> blocks;
  auto const prepare = [&]<class U>(GProbe<U>& c, std::size_t lane, std::uint32_t i) {
    CHECK(c.item[lane] == -2);
    c.item[lane] = i;
  };
  auto const clear = [&](GProbe<T>& c, std::size_t lane) {
    CHECK(c.item[lane] == -2);
    c.item[lane] = -1;
  };
  if constexpr (KeyCount == 0)
    blocks.pack(colors, prepare, clear);
  else
    blocks.template pack_grouped<KeyCount>(
        colors, [&](std::uint32_t i) { return key[i]; }, prepare, clear);
  std::size_t const keys = KeyCount == 0 ? 1 : KeyCount;
  auto const key_of = [&](std::size_t i) {
    return KeyCount == 0 ? std::size_t(0) : std::min(std::size_t(key[i]), keys - 1);
  };
  std::vector<std::int64_t> order, expected;
  for (std::size_t i = 0; i < n; ++i)
    if (colors[i] < 0 || colors[i] >= ConstraintGraph::color_count) expected.push_back(i);
  std::size_t padding = 0;
  for (int c = 0; c < ConstraintGraph::color_count; ++c) {
    std::size_t count = 0;
    for (std::size_t k = 0; k < keys; ++k)
      for (std::size_t i = 0; i < n; ++i)
        if (colors[i] == c && key_of(i) == k) {
          expected.push_back(i);
          ++count;
        }
    CHECK(blocks.color_sizes()[std::size_t(c)] == count);
    padding += (W - count % W) % W;
  }
  // Padding lanes sit at the end of a colour's last block: no block holds two colours, and
  // the lanes of a block after the first padding lane are all padding.
  std::size_t blocks_seen = 0;
  blocks.for_each([&](auto& c) {
    bool padded = false;
    int color = -1;
    for (std::int64_t i : c.item) {
      if (i == -1) {
        padded = true;
        continue;
      }
      CHECK_FALSE(padded);
      order.push_back(i);
      if (c.item.size() > 1) { // a block (the overflow's entries hold one constraint)
        if (color < 0) color = colors[std::size_t(i)];
        CHECK(colors[std::size_t(i)] == color);
      }
    }
    ++blocks_seen;
  });
  CHECK(order == expected);
  CHECK(blocks.overflow_count() == blocks.color_sizes()[ConstraintGraph::color_count]);
  CHECK(blocks_seen == blocks.overflow_count() + blocks.block_count());
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

/// Colours 0..6, the overflow (-1) and a stray value (99: overflow).
std::vector<int> random_colors(std::mt19937& rng, std::size_t n) {
  std::vector<int> colors(n);
  for (int& c : colors) {
    int const v = int(rng() % 9) - 1;
    c = v == 7 ? 99 : v;
  }
  return colors;
}

} // namespace

TEMPLATE_LIST_TEST_CASE("constraint blocks: one lane per constraint, in the solver's order",
                        "[solver][blocks]", test::f32_types) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial)
    check_pack<TestType, 0>(random_colors(rng, std::size_t(rng() % 200)), {});
}

TEMPLATE_LIST_TEST_CASE("constraint blocks: pack_grouped orders each colour by key, the "
                        "overflow by index",
                        "[solver][blocks]", test::f32_types) {
  std::mt19937 rng(6);
  for (int trial = 0; trial < 50; ++trial) {
    std::size_t const n = std::size_t(rng() % 200);
    std::vector<int> const colors = random_colors(rng, n);
    std::vector<std::uint32_t> key(n);
    for (auto& k : key) // 0..6: 5 and 6 are beyond KeyCount 5 and join key 4
      k = std::uint32_t(rng() % 7);
    check_pack<TestType, 5>(colors, key);
    check_pack<TestType, 1>(colors, key); // one key: pack()'s order
  }
}
