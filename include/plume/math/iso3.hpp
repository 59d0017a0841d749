// plume/math/iso3.hpp - GIso3<T>: a rigid transform (rotation, then translation), the pose of
// a shape. p_world = rotation * p_local + translation. Wide isometries hold one per lane.
// The rotation is assumed unit; inverse() uses its conjugate.
#pragma once

#include <plume/math/quat.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
struct GIso3 {
  using element_type = T;
  using scalar_type = scalar_t<T>;

  GQuat<T> rotation;
  GVec3<T> translation;

  /// The identity.
  GIso3() noexcept = default;
  GIso3(GQuat<T> const& r, GVec3<T> const& t) noexcept : rotation(r), translation(t) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GIso3(GIso3<U> const& i) noexcept
      : rotation(GQuat<T>(i.rotation)), translation(GVec3<T>(i.translation)) {}

  static GIso3 const IDENTITY;

  static GIso3 from_rotation_translation(GQuat<T> const& r, GVec3<T> const& t) noexcept {
    return {r, t};
  }
  static GIso3 from_translation(GVec3<T> const& t) noexcept { return {GQuat<T>::IDENTITY, t}; }
  static GIso3 from_rotation(GQuat<T> const& r) noexcept {
    return {r, GVec3<T>::splat(plume::zero<T>())};
  }

  /// rotation * p + translation
  GVec3<T> transform_point(GVec3<T> const& p) const noexcept { return rotation * p + translation; }
  /// rotation * v (directions and offsets ignore the translation)
  GVec3<T> transform_vector(GVec3<T> const& v) const noexcept { return rotation * v; }
  /// rotation^-1 (p - translation)
  GVec3<T> inverse_transform_point(GVec3<T> const& p) const noexcept {
    return rotation.conjugate() * (p - translation);
  }
  GVec3<T> inverse_transform_vector(GVec3<T> const& v) const noexcept {
    return rotation.conjugate() * v;
  }
  GIso3 inverse() const noexcept {
    GQuat<T> const ri = rotation.conjugate();
    return {ri, -(ri * translation)};
  }
  /// this * b: apply b, then this.
  GIso3 mul_iso(GIso3 const& b) const noexcept {
    return {rotation * b.rotation, rotation * b.translation + translation};
  }
  /// this^-1 * b, without forming the inverse: b relative to this.
  GIso3 inv_mul(GIso3 const& b) const noexcept {
    GQuat<T> const ri = rotation.conjugate();
    return {ri * b.rotation, ri * (b.translation - translation)};
  }
  GMat3<T> rotation_matrix() const noexcept { return GMat3<T>::from_quat(rotation); }

  static GIso3 select(mask_t<T> m, GIso3 const& a, GIso3 const& b) noexcept {
    return {GQuat<T>::select(m, a.rotation, b.rotation),
            GVec3<T>::select(m, a.translation, b.translation)};
  }
  mask_t<T> is_finite() const noexcept { return rotation.is_finite() & translation.is_finite(); }

  friend GIso3 operator*(GIso3 const& a, GIso3 const& b) noexcept { return a.mul_iso(b); }
  friend GVec3<T> operator*(GIso3 const& a, GVec3<T> const& p) noexcept {
    return a.transform_point(p);
  }
};

template <Float T>
inline GIso3<T> const GIso3<T>::IDENTITY = {};

using Iso3 = GIso3<float>;
using DIso3 = GIso3<double>;
using Iso3xN = GIso3<f32xN>;
using DIso3xN = GIso3<f64xN>;

template <Float T>
PLUME_INLINE GIso3<scalar_t<T>> lane(GIso3<T> const& a, std::size_t i) noexcept {
  return {plume::lane(a.rotation, i), plume::lane(a.translation, i)};
}
template <Float T>
PLUME_INLINE GIso3<T> with_lane(GIso3<T> const& a, std::size_t i,
                                GIso3<scalar_t<T>> const& s) noexcept {
  return {plume::with_lane(a.rotation, i, s.rotation),
          plume::with_lane(a.translation, i, s.translation)};
}

template <Float T>
std::ostream& operator<<(std::ostream& os, GIso3<T> const& a) {
  return os << "iso(" << a.rotation << ", " << a.translation << ')';
}

} // namespace plume

PLUME_MASK_CODE_END
