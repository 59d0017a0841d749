// plume/math/dir3.hpp - GDir3<T>: a 3-vector known to be unit length (a direction or normal).
//
// Checked construction: GDir3<T>::try_new(v) gives {direction, valid mask} (invalid lanes
// hold X); for scalars GDir3<S>::new_checked(v) gives std::optional. from_unchecked(v)
// trusts the caller. A direction is valid when v's length is finite and non-zero; it is then
// normalised. renormalize() corrects the drift of a nearly unit vector (one Newton step on
// 1/|v|: v (3 - |v|^2) / 2, enough when | |v| - 1 | < 1e-3).
#pragma once

#include <plume/math/quat.hpp>

#include <optional>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
class GDir3 {
public:
  using element_type = T;
  using scalar_type = scalar_t<T>;

  /// +X.
  constexpr GDir3() noexcept : v_(plume::one<T>(), plume::zero<T>(), plume::zero<T>()) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GDir3(GDir3<U> const& d) noexcept
      : v_(GVec3<T>(d.as_vec3())) {}

  struct checked {
    GDir3 value;
    mask_t<T> valid;
  };
  /// v normalised where its length is finite and non-zero; elsewhere X and valid = false.
  static checked try_new(GVec3<T> const& v) noexcept {
    auto const n = v.try_normalize();
    return {from_unchecked(GVec3<T>::select(
                n.valid, n.value, GVec3<T>{plume::one<T>(), plume::zero<T>(), plume::zero<T>()})),
            n.valid};
  }
  /// Scalar convenience: std::nullopt for a zero or non-finite vector.
  static std::optional<GDir3> new_checked(GVec3<T> const& v) noexcept requires ScalarReal<T> {
    auto const c = try_new(v);
    if (!c.valid) return std::nullopt;
    return c.value;
  }
  /// The caller promises |v| = 1.
  static constexpr GDir3 from_unchecked(GVec3<T> const& v) noexcept {
    GDir3 d;
    d.v_ = v;
    return d;
  }

  static GDir3 const X, Y, Z, NEG_X, NEG_Y, NEG_Z;

  GVec3<T> const& as_vec3() const noexcept { return v_; }
  T x() const noexcept { return v_.x; }
  T y() const noexcept { return v_.y; }
  T z() const noexcept { return v_.z; }

  GDir3 renormalize() const noexcept {
    T const l2 = v_.length_squared();
    return from_unchecked(v_ * ((splat<T>(scalar_type(3)) - l2) * plume::half<T>()));
  }
  /// Spherical interpolation at constant angular speed (GVec3::slerp on unit vectors).
  GDir3 slerp(GDir3 const& b, T t) const noexcept { return from_unchecked(v_.slerp(b.v_, t)); }
  T dot(GDir3 const& b) const noexcept { return v_.dot(b.v_); }

  static GDir3 select(mask_t<T> m, GDir3 const& a, GDir3 const& b) noexcept {
    return from_unchecked(GVec3<T>::select(m, a.v_, b.v_));
  }

  friend GDir3 operator-(GDir3 const& d) noexcept { return from_unchecked(-d.v_); }
  friend GVec3<T> operator*(GDir3 const& d, T s) noexcept { return d.v_ * s; }
  friend GVec3<T> operator*(T s, GDir3 const& d) noexcept { return d.v_ * s; }
  /// Rotating a direction keeps it a direction.
  friend GDir3 operator*(GQuat<T> const& q, GDir3 const& d) noexcept {
    return from_unchecked(q * d.v_);
  }

private:
  GVec3<T> v_;
};

template <Float T>
inline GDir3<T> const GDir3<T>::X = GDir3<T>::from_unchecked(GVec3<T>{
    plume::one<T>(), plume::zero<T>(), plume::zero<T>()});
template <Float T>
inline GDir3<T> const GDir3<T>::Y = GDir3<T>::from_unchecked(GVec3<T>{
    plume::zero<T>(), plume::one<T>(), plume::zero<T>()});
template <Float T>
inline GDir3<T> const GDir3<T>::Z = GDir3<T>::from_unchecked(GVec3<T>{
    plume::zero<T>(), plume::zero<T>(), plume::one<T>()});
template <Float T>
inline GDir3<T> const GDir3<T>::NEG_X = GDir3<T>::from_unchecked(GVec3<T>{
    -plume::one<T>(), plume::zero<T>(), plume::zero<T>()});
template <Float T>
inline GDir3<T> const GDir3<T>::NEG_Y = GDir3<T>::from_unchecked(GVec3<T>{
    plume::zero<T>(), -plume::one<T>(), plume::zero<T>()});
template <Float T>
inline GDir3<T> const GDir3<T>::NEG_Z = GDir3<T>::from_unchecked(GVec3<T>{
    plume::zero<T>(), plume::zero<T>(), -plume::one<T>()});

using Dir3 = GDir3<float>;
using DDir3 = GDir3<double>;
using Dir3xN = GDir3<f32xN>;
using DDir3xN = GDir3<f64xN>;

template <Float T>
PLUME_INLINE GDir3<scalar_t<T>> lane(GDir3<T> const& d, std::size_t i) noexcept {
  return GDir3<scalar_t<T>>::from_unchecked(plume::lane(d.as_vec3(), i));
}

template <Float T>
std::ostream& operator<<(std::ostream& os, GDir3<T> const& d) {
  return os << "dir" << d.as_vec3();
}

} // namespace plume

PLUME_MASK_CODE_END
