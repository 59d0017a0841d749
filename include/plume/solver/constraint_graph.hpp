// plume/solver/constraint_graph.hpp - graph colouring of constraints, so that one colour can
// be solved W constraints at a time: no dynamic body appears twice in a colour.
//
// Greedy, with one body bitset per colour (Box2D v3's scheme). A constraint between two
// dynamic bodies takes the lowest colour where both bits are free, among the first
// `dynamic_colors`; a constraint with one dynamic body searches from the top colour down
// (static and kinematic bodies take no bits, never written by the solver, so they may
// appear in a colour any number of times; solved last, such constraints get the last word).
// A constraint that fits nowhere (or joins two non-dynamic bodies) goes to the overflow,
// which the solver runs one constraint at a time. Colours stay with a constraint for its life
// (release() when it ends), so the colouring is persistent across steps; it depends only on
// the order of add/release calls, never on the SIMD width.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace plume {

class ConstraintGraph {
public:
  static constexpr int color_count = 24;    ///< colours, solved in order 0..23
  static constexpr int dynamic_colors = 20; ///< colours open to dynamic–dynamic constraints
  static constexpr int overflow = -1;       ///< the colour of a constraint that fits nowhere

  /// Room for bodies 0..body_count-1 (grows on demand).
  explicit ConstraintGraph(std::size_t body_count = 0) { reserve(body_count); }

  void reserve(std::size_t body_count) {
    std::size_t const words = (body_count + 63) / 64;
    for (auto& c : colors_)
      if (c.size() < words) c.resize(words, 0);
  }

  /// The colour for a constraint between bodies a and b (dynamic_a / dynamic_b: whether each
  /// is a dynamic body), marking the bits; overflow when none fits.
  int add(std::uint32_t a, std::uint32_t b, bool dynamic_a, bool dynamic_b) {
    reserve(std::size_t(std::max(a, b)) + 1);
    if (dynamic_a && dynamic_b) {
      for (int c = 0; c < dynamic_colors; ++c) {
        if (test(c, a) || test(c, b)) continue;
        set(c, a, true);
        set(c, b, true);
        return c;
      }
    } else if (dynamic_a || dynamic_b) {
      std::uint32_t const d = dynamic_a ? a : b;
      for (int c = color_count - 1; c >= 1; --c) {
        if (test(c, d)) continue;
        set(c, d, true);
        return c;
      }
    }
    return overflow;
  }

  /// Frees the bits a constraint of colour `color` took (no-op for overflow).
  void release(int color, std::uint32_t a, std::uint32_t b, bool dynamic_a, bool dynamic_b) {
    if (color < 0 || color >= color_count) return;
    if (dynamic_a) set(color, a, false);
    if (dynamic_b) set(color, b, false);
  }

  /// Whether body `body` has a constraint in colour `color`.
  bool test(int color, std::uint32_t body) const noexcept {
    auto const& w = colors_[std::size_t(color)];
    std::size_t const i = body / 64;
    return i < w.size() && ((w[i] >> (body % 64)) & 1u) != 0;
  }

  void clear() {
    for (auto& c : colors_)
      std::fill(c.begin(), c.end(), 0);
  }

private:
  void set(int color, std::uint32_t body, bool on) {
    auto& w = colors_[std::size_t(color)][body / 64];
    std::uint64_t const bit = std::uint64_t(1) << (body % 64);
    w = on ? (w | bit) : (w & ~bit);
  }

  std::array<std::vector<std::uint64_t>, color_count> colors_;
};

} // namespace plume
