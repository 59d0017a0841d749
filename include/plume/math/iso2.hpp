// plume/math/iso2.hpp - GIso2<T>: a 2D rigid transform (rotation, then translation).
// Same API as GIso3: transform_point/vector, inverse, inverse_transform_point, mul, inv_mul.
#pragma once

#include <plume/math/rot2.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
struct GIso2 {
  using element_type = T;
  GRot2<T> rotation;
  GVec2<T> translation;

  GIso2() noexcept = default;
  GIso2(GRot2<T> const& r, GVec2<T> const& t) noexcept : rotation(r), translation(t) {}

  static GIso2 const IDENTITY;

  static GIso2 from_translation(GVec2<T> const& t) noexcept { return {GRot2<T>::IDENTITY, t}; }
  static GIso2 from_rotation(GRot2<T> const& r) noexcept {
    return {r, GVec2<T>::splat(plume::zero<T>())};
  }
  GVec2<T> transform_point(GVec2<T> const& p) const noexcept { return rotation * p + translation; }
  GVec2<T> transform_vector(GVec2<T> const& v) const noexcept { return rotation * v; }
  GVec2<T> inverse_transform_point(GVec2<T> const& p) const noexcept {
    return rotation.inverse_mul_vec2(p - translation);
  }
  GVec2<T> inverse_transform_vector(GVec2<T> const& v) const noexcept {
    return rotation.inverse_mul_vec2(v);
  }
  GIso2 inverse() const noexcept {
    return {rotation.inverse(), -rotation.inverse_mul_vec2(translation)};
  }
  GIso2 mul_iso(GIso2 const& b) const noexcept {
    return {rotation * b.rotation, rotation * b.translation + translation};
  }
  GIso2 inv_mul(GIso2 const& b) const noexcept {
    return {rotation.inverse() * b.rotation,
            rotation.inverse_mul_vec2(b.translation - translation)};
  }
  static GIso2 select(mask_t<T> m, GIso2 const& a, GIso2 const& b) noexcept {
    return {GRot2<T>::select(m, a.rotation, b.rotation),
            GVec2<T>::select(m, a.translation, b.translation)};
  }
  friend GIso2 operator*(GIso2 const& a, GIso2 const& b) noexcept { return a.mul_iso(b); }
  friend GVec2<T> operator*(GIso2 const& a, GVec2<T> const& p) noexcept {
    return a.transform_point(p);
  }
};

template <Float T>
inline GIso2<T> const GIso2<T>::IDENTITY = {};

using Iso2 = GIso2<float>;
using DIso2 = GIso2<double>;
using Iso2xN = GIso2<f32xN>;

template <Float T>
PLUME_INLINE GIso2<scalar_t<T>> lane(GIso2<T> const& a, std::size_t i) noexcept {
  return {plume::lane(a.rotation, i), plume::lane(a.translation, i)};
}

} // namespace plume

PLUME_MASK_CODE_END
