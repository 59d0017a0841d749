// plume/math/aabb3.hpp - GAabb3<T>: an axis-aligned bounding box [min, max].
//
// A box is valid when min <= max in every component and both are finite; EMPTY (min = +inf,
// max = -inf) is the identity of merge() and is not valid. Point containment is closed
// (points on the faces are inside); intersects() is true for boxes that touch.
// Pose helpers: from_obb(pose, half_extents) bounds an oriented box, transformed(pose) bounds
// this box carried by a pose, from_sphere/from_capsule bound those shapes.
#pragma once

#include <plume/math/iso3.hpp>

#include <span>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
struct GAabb3 {
  using element_type = T;
  using scalar_type = scalar_t<T>;

  GVec3<T> min, max;

  /// EMPTY.
  constexpr GAabb3() noexcept
      : min(GVec3<T>::splat(plume::infinity<T>())), max(GVec3<T>::splat(-plume::infinity<T>())) {}
  constexpr GAabb3(GVec3<T> const& lo, GVec3<T> const& hi) noexcept : min(lo), max(hi) {}

  static GAabb3 const EMPTY;

  static GAabb3 from_min_max(GVec3<T> const& lo, GVec3<T> const& hi) noexcept { return {lo, hi}; }
  static GAabb3 from_center_half_extents(GVec3<T> const& c, GVec3<T> const& h) noexcept {
    return {c - h, c + h};
  }
  /// The smallest box holding every point (EMPTY for none).
  static GAabb3 from_points(std::span<GVec3<T> const> points) noexcept {
    GAabb3 b;
    for (auto const& p : points)
      b = b.grow_to(p);
    return b;
  }
  static GAabb3 from_sphere(GVec3<T> const& center, T radius) noexcept {
    return from_center_half_extents(center, GVec3<T>::splat(radius));
  }
  /// Capsule: the segment a-b swept by radius.
  static GAabb3 from_capsule(GVec3<T> const& a, GVec3<T> const& b, T radius) noexcept {
    GVec3<T> const r = GVec3<T>::splat(radius);
    return {a.min(b) - r, a.max(b) + r};
  }
  /// An oriented box of the given half extents at a pose: half extents |R| h.
  static GAabb3 from_obb(GIso3<T> const& pose, GVec3<T> const& half_extents) noexcept {
    GMat3<T> const r = pose.rotation_matrix().abs();
    return from_center_half_extents(pose.translation, r * half_extents);
  }

  GVec3<T> center() const noexcept { return (min + max) * plume::half<T>(); }
  GVec3<T> half_extents() const noexcept { return (max - min) * plume::half<T>(); }
  GVec3<T> size() const noexcept { return max - min; }
  T surface_area() const noexcept {
    GVec3<T> const s = size();
    return plume::two<T>() * ((s.x * s.y + s.y * s.z) + s.z * s.x);
  }
  T volume() const noexcept { return size().element_product(); }
  mask_t<T> is_valid() const noexcept {
    return min.cmple(max).all() & min.is_finite() & max.is_finite();
  }

  GAabb3 merge(GAabb3 const& b) const noexcept { return {min.min(b.min), max.max(b.max)}; }
  /// Enlarged by amount on every side (negative shrinks).
  GAabb3 grow(T amount) const noexcept {
    GVec3<T> const a = GVec3<T>::splat(amount);
    return {min - a, max + a};
  }
  GAabb3 grow_to(GVec3<T> const& p) const noexcept { return {min.min(p), max.max(p)}; }
  mask_t<T> contains(GVec3<T> const& p) const noexcept {
    return min.cmple(p).all() & p.cmple(max).all();
  }
  mask_t<T> contains_aabb(GAabb3 const& b) const noexcept {
    return min.cmple(b.min).all() & b.max.cmple(max).all();
  }
  mask_t<T> intersects(GAabb3 const& b) const noexcept {
    return min.cmple(b.max).all() & b.min.cmple(max).all();
  }
  /// Bounds of this box moved by a pose.
  GAabb3 transformed(GIso3<T> const& pose) const noexcept {
    GMat3<T> const r = pose.rotation_matrix();
    return from_center_half_extents(pose.transform_point(center()), r.abs() * half_extents());
  }

  static GAabb3 select(mask_t<T> m, GAabb3 const& a, GAabb3 const& b) noexcept {
    return {GVec3<T>::select(m, a.min, b.min), GVec3<T>::select(m, a.max, b.max)};
  }
};

template <Float T>
inline GAabb3<T> const GAabb3<T>::EMPTY = {};

using Aabb3 = GAabb3<float>;
using DAabb3 = GAabb3<double>;
using Aabb3xN = GAabb3<f32xN>;

template <Float T>
PLUME_INLINE GAabb3<scalar_t<T>> lane(GAabb3<T> const& b, std::size_t i) noexcept {
  return {plume::lane(b.min, i), plume::lane(b.max, i)};
}

template <Float T>
std::ostream& operator<<(std::ostream& os, GAabb3<T> const& b) {
  return os << "aabb(" << b.min << ", " << b.max << ')';
}

} // namespace plume

PLUME_MASK_CODE_END
