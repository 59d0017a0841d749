// plume/math/bvec3.hpp - GBVec3<M>: three masks, the result of comparing two GVec3<T>.
//
// M is the mask of the element type: `bool` for scalar vectors, an xsimd batch_bool for wide
// ones (`GBVec3<mask_t<T>>` is `GVec3<T>::mask_type`). Components combine with & | ^ !; the
// reductions any/all/none fold the three components and return one M (for wide vectors:
// one answer per lane, not per batch). `bitmask()` packs x, y, z into bits 0, 1, 2 (scalar
// vectors only; for wide vectors use plume::bitmask on a component or on any()/all()).
#pragma once

#include <plume/numerics.hpp>

#include <cstdint>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Mask M>
struct GBVec3 {
  M x, y, z;

  GBVec3() = default;
  constexpr GBVec3(M x_, M y_, M z_) noexcept : x(x_), y(y_), z(z_) {}
  /// All three components set to m.
  static GBVec3 splat(M m) noexcept { return {m, m, m}; }

  /// Per lane: at least one / every / no component set.
  M any() const noexcept { return (x | y) | z; }
  M all() const noexcept { return (x & y) & z; }
  M none() const noexcept { return !any(); }

  /// Bits 0, 1, 2 = x, y, z (scalar masks only).
  std::uint32_t bitmask() const noexcept requires std::same_as<M, bool> {
    return static_cast<std::uint32_t>(x) | (static_cast<std::uint32_t>(y) << 1) |
           (static_cast<std::uint32_t>(z) << 2);
  }

  friend GBVec3 operator&(GBVec3 const& a, GBVec3 const& b) noexcept {
    return {a.x & b.x, a.y & b.y, a.z & b.z};
  }
  friend GBVec3 operator|(GBVec3 const& a, GBVec3 const& b) noexcept {
    return {a.x | b.x, a.y | b.y, a.z | b.z};
  }
  friend GBVec3 operator^(GBVec3 const& a, GBVec3 const& b) noexcept {
    return {a.x ^ b.x, a.y ^ b.y, a.z ^ b.z};
  }
  friend GBVec3 operator!(GBVec3 const& a) noexcept { return {!a.x, !a.y, !a.z}; }
  GBVec3& operator&=(GBVec3 const& b) noexcept { return *this = *this & b; }
  GBVec3& operator|=(GBVec3 const& b) noexcept { return *this = *this | b; }
  GBVec3& operator^=(GBVec3 const& b) noexcept { return *this = *this ^ b; }
};

using BVec3 = GBVec3<bool>;

} // namespace plume

PLUME_MASK_CODE_END
