// plume/math/rot2.hpp - GRot2<T>: a 2D rotation stored as (cos, sin) of its angle.
//
// Counter-clockwise positive, radians. r * v rotates v; r1 * r2 rotates by r2, then r1
// (angles add). The stored pair is assumed unit; normalize() restores it after drift (a
// zero pair normalises to IDENTITY). angle() is in (-pi, pi]. slerp(b, t) turns by t times
// the signed shortest angle from this to b.
#pragma once

#include <plume/math/mat2.hpp>
#include <plume/math/vec2.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
struct GRot2 {
  using element_type = T;
  using scalar_type = scalar_t<T>;

  T cos, sin;

  GRot2() noexcept : cos(plume::one<T>()), sin(plume::zero<T>()) {}
  GRot2(T c, T s) noexcept : cos(c), sin(s) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GRot2(GRot2<U> const& r) noexcept
      : cos(r.cos), sin(r.sin) {}

  static GRot2 const IDENTITY;

  static GRot2 from_angle(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle);
    return {c, s};
  }
  static GRot2 from_sin_cos(T s, T c) noexcept { return {c, s}; }
  T angle() const noexcept { return plume::atan2(sin, cos); }
  GRot2 inverse() const noexcept { return {cos, -sin}; }
  T length_squared() const noexcept { return cos * cos + sin * sin; }
  GRot2 normalize() const noexcept {
    auto const n = GVec2<T>{cos, sin}.try_normalize();
    return select(n.valid, GRot2{n.value.x, n.value.y}, GRot2{}); // GRot2{}: the identity
  }
  mask_t<T> is_normalized() const noexcept {
    return plume::abs(length_squared() - plume::one<T>()) <= plume::splat<T>(scalar_type(2e-4));
  }
  GVec2<T> mul_vec2(GVec2<T> const& v) const noexcept {
    return {cos * v.x - sin * v.y, sin * v.x + cos * v.y};
  }
  GVec2<T> inverse_mul_vec2(GVec2<T> const& v) const noexcept {
    return {cos * v.x + sin * v.y, cos * v.y - sin * v.x};
  }
  GRot2 mul_rot(GRot2 const& b) const noexcept {
    return {cos * b.cos - sin * b.sin, sin * b.cos + cos * b.sin};
  }
  /// Signed angle from this to b in (-pi, pi].
  T angle_to(GRot2 const& b) const noexcept {
    GRot2 const d = inverse().mul_rot(b);
    return plume::atan2(d.sin, d.cos);
  }
  GRot2 slerp(GRot2 const& b, T t) const noexcept { return mul_rot(from_angle(angle_to(b) * t)); }
  GMat2<T> to_mat2() const noexcept { return {{cos, sin}, {-sin, cos}}; }
  static GRot2 select(mask_t<T> m, GRot2 const& a, GRot2 const& b) noexcept {
    return {plume::select(m, a.cos, b.cos), plume::select(m, a.sin, b.sin)};
  }

  friend GRot2 operator*(GRot2 const& a, GRot2 const& b) noexcept { return a.mul_rot(b); }
  friend GVec2<T> operator*(GRot2 const& a, GVec2<T> const& v) noexcept { return a.mul_vec2(v); }
};

template <Float T>
inline GRot2<T> const GRot2<T>::IDENTITY = {};

using Rot2 = GRot2<float>;
using DRot2 = GRot2<double>;
using Rot2xN = GRot2<f32xN>;

template <Float T>
PLUME_INLINE GRot2<scalar_t<T>> lane(GRot2<T> const& r, std::size_t i) noexcept {
  return {plume::lane(r.cos, i), plume::lane(r.sin, i)};
}
template <Float T>
std::ostream& operator<<(std::ostream& os, GRot2<T> const& r) {
  return os << "rot2(cos " << r.cos << ", sin " << r.sin << ')';
}

} // namespace plume

PLUME_MASK_CODE_END
