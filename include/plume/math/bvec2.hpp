// plume/math/bvec2.hpp - GBVec2<M>: two masks, the result of comparing two GVec2<T>.
// Same conventions as GBVec3 (any/all/none fold the components per lane).
#pragma once

#include <plume/numerics.hpp>

#include <cstdint>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Mask M>
struct GBVec2 {
  M x, y;

  GBVec2() = default;
  constexpr GBVec2(M x_, M y_) noexcept : x(x_), y(y_) {}
  static GBVec2 splat(M m) noexcept { return {m, m}; }

  M any() const noexcept { return x | y; }
  M all() const noexcept { return x & y; }
  M none() const noexcept { return !any(); }
  std::uint32_t bitmask() const noexcept requires std::same_as<M, bool> {
    return static_cast<std::uint32_t>(x) | (static_cast<std::uint32_t>(y) << 1);
  }

  friend GBVec2 operator&(GBVec2 const& a, GBVec2 const& b) noexcept {
    return {a.x & b.x, a.y & b.y};
  }
  friend GBVec2 operator|(GBVec2 const& a, GBVec2 const& b) noexcept {
    return {a.x | b.x, a.y | b.y};
  }
  friend GBVec2 operator^(GBVec2 const& a, GBVec2 const& b) noexcept {
    return {a.x ^ b.x, a.y ^ b.y};
  }
  friend GBVec2 operator!(GBVec2 const& a) noexcept { return {!a.x, !a.y}; }
};

using BVec2 = GBVec2<bool>;

} // namespace plume

PLUME_MASK_CODE_END
