// plume/math/aabb2.hpp - GAabb2<T>: a 2D axis-aligned box [min, max]. Same conventions as
// GAabb3 (closed containment, touching boxes intersect, EMPTY for merging).
#pragma once

#include <plume/math/iso2.hpp>

#include <span>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
struct GAabb2 {
  using element_type = T;
  GVec2<T> min, max;

  constexpr GAabb2() noexcept
      : min(GVec2<T>::splat(plume::infinity<T>())), max(GVec2<T>::splat(-plume::infinity<T>())) {}
  constexpr GAabb2(GVec2<T> const& lo, GVec2<T> const& hi) noexcept : min(lo), max(hi) {}

  static GAabb2 const EMPTY;

  static GAabb2 from_center_half_extents(GVec2<T> const& c, GVec2<T> const& h) noexcept {
    return {c - h, c + h};
  }
  static GAabb2 from_points(std::span<GVec2<T> const> points) noexcept {
    GAabb2 b;
    for (auto const& p : points)
      b = b.grow_to(p);
    return b;
  }
  /// An oriented box of the given half extents at a pose.
  static GAabb2 from_obb(GIso2<T> const& pose, GVec2<T> const& h) noexcept {
    T const c = plume::abs(pose.rotation.cos), s = plume::abs(pose.rotation.sin);
    return from_center_half_extents(pose.translation, {c * h.x + s * h.y, s * h.x + c * h.y});
  }
  GVec2<T> center() const noexcept { return (min + max) * plume::half<T>(); }
  GVec2<T> half_extents() const noexcept { return (max - min) * plume::half<T>(); }
  GVec2<T> size() const noexcept { return max - min; }
  T area() const noexcept { return size().element_product(); }
  T perimeter() const noexcept { return plume::two<T>() * size().element_sum(); }
  mask_t<T> is_valid() const noexcept {
    return min.cmple(max).all() & min.is_finite() & max.is_finite();
  }
  GAabb2 merge(GAabb2 const& b) const noexcept { return {min.min(b.min), max.max(b.max)}; }
  GAabb2 grow(T amount) const noexcept {
    GVec2<T> const a = GVec2<T>::splat(amount);
    return {min - a, max + a};
  }
  GAabb2 grow_to(GVec2<T> const& p) const noexcept { return {min.min(p), max.max(p)}; }
  mask_t<T> contains(GVec2<T> const& p) const noexcept {
    return min.cmple(p).all() & p.cmple(max).all();
  }
  mask_t<T> intersects(GAabb2 const& b) const noexcept {
    return min.cmple(b.max).all() & b.min.cmple(max).all();
  }
};

template <Float T>
inline GAabb2<T> const GAabb2<T>::EMPTY = {};

using Aabb2 = GAabb2<float>;
using DAabb2 = GAabb2<double>;
using Aabb2xN = GAabb2<f32xN>;

} // namespace plume

PLUME_MASK_CODE_END
