// plume/math/mat2.hpp - GMat2<T>: a 2x2 matrix, column-major (x_axis, y_axis), any Real T.
// Same conventions as GMat3: inverse() of a singular matrix gives inf/NaN, try_inverse()
// gives {inverse, true} or {zero, false}, inverse_or_zero().
#pragma once

#include <plume/math/vec2.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Real T>
struct GMat2 {
  using element_type = T;
  using scalar_type = scalar_t<T>;

  GVec2<T> x_axis, y_axis;

  /// The zero matrix.
  constexpr GMat2() noexcept = default;
  constexpr GMat2(GVec2<T> const& x, GVec2<T> const& y) noexcept : x_axis(x), y_axis(y) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GMat2(GMat2<U> const& m) noexcept
      : x_axis(m.x_axis), y_axis(m.y_axis) {}

  static GMat2 const IDENTITY, ZERO;

  static GMat2 from_cols(GVec2<T> const& x, GVec2<T> const& y) noexcept { return {x, y}; }
  static GMat2 from_diagonal(GVec2<T> const& d) noexcept {
    return {{d.x, plume::zero<T>()}, {plume::zero<T>(), d.y}};
  }
  static GMat2 from_scale(GVec2<T> const& s) noexcept { return from_diagonal(s); }
  /// Counter-clockwise rotation by angle radians.
  static GMat2 from_angle(T angle) noexcept requires Float<T> {
    auto const [s, c] = plume::sincos(angle);
    return {{c, s}, {-s, c}};
  }

  T at(std::size_t i, std::size_t j) const noexcept {
    GVec2<T> const& c = j == 0 ? x_axis : y_axis;
    return i == 0 ? c.x : c.y;
  }
  GVec2<T> row(std::size_t i) const noexcept { return {at(i, 0), at(i, 1)}; }
  GVec2<T> diagonal() const noexcept { return {x_axis.x, y_axis.y}; }
  GMat2 transpose() const noexcept { return {{x_axis.x, y_axis.x}, {x_axis.y, y_axis.y}}; }
  T determinant() const noexcept { return x_axis.x * y_axis.y - y_axis.x * x_axis.y; }
  GMat2 inverse() const noexcept {
    T const inv = plume::one<T>() / determinant();
    return {{y_axis.y * inv, -x_axis.y * inv}, {-y_axis.x * inv, x_axis.x * inv}};
  }
  struct inverted {
    GMat2 value;
    mask_t<T> valid;
  };
  inverted try_inverse() const noexcept requires Float<T> {
    T const det = determinant();
    mask_t<T> const ok = (det != plume::zero<T>()) & plume::is_finite(det);
    return {select(ok, inverse(), GMat2{}), ok};
  }
  GMat2 inverse_or_zero() const noexcept requires Float<T> { return try_inverse().value; }
  static GMat2 select(mask_t<T> m, GMat2 const& a, GMat2 const& b) noexcept {
    return {GVec2<T>::select(m, a.x_axis, b.x_axis), GVec2<T>::select(m, a.y_axis, b.y_axis)};
  }
  GVec2<T> mul_vec2(GVec2<T> const& v) const noexcept { return x_axis * v.x + y_axis * v.y; }
  GVec2<T> mul_transpose_vec2(GVec2<T> const& v) const noexcept {
    return {x_axis.dot(v), y_axis.dot(v)};
  }
  GMat2 mul_mat2(GMat2 const& b) const noexcept { return {mul_vec2(b.x_axis), mul_vec2(b.y_axis)}; }
  GMat2 abs() const noexcept { return {x_axis.abs(), y_axis.abs()}; }
  mask_t<T> abs_diff_eq(GMat2 const& b, T d) const noexcept {
    return x_axis.abs_diff_eq(b.x_axis, d) & y_axis.abs_diff_eq(b.y_axis, d);
  }

  friend GMat2 operator+(GMat2 const& a, GMat2 const& b) noexcept {
    return {a.x_axis + b.x_axis, a.y_axis + b.y_axis};
  }
  friend GMat2 operator-(GMat2 const& a, GMat2 const& b) noexcept {
    return {a.x_axis - b.x_axis, a.y_axis - b.y_axis};
  }
  friend GMat2 operator*(GMat2 const& a, T s) noexcept { return {a.x_axis * s, a.y_axis * s}; }
  friend GMat2 operator*(GMat2 const& a, GMat2 const& b) noexcept { return a.mul_mat2(b); }
  friend GVec2<T> operator*(GMat2 const& a, GVec2<T> const& v) noexcept { return a.mul_vec2(v); }
};

template <Real T>
inline GMat2<T> const GMat2<T>::IDENTITY = {{plume::one<T>(), plume::zero<T>()},
                                            {plume::zero<T>(), plume::one<T>()}};
template <Real T>
inline GMat2<T> const GMat2<T>::ZERO = {};

using Mat2 = GMat2<float>;
using DMat2 = GMat2<double>;
using Mat2xN = GMat2<f32xN>;

template <Real T>
PLUME_INLINE GMat2<scalar_t<T>> lane(GMat2<T> const& m, std::size_t i) noexcept {
  return {plume::lane(m.x_axis, i), plume::lane(m.y_axis, i)};
}
template <Real T>
std::ostream& operator<<(std::ostream& os, GMat2<T> const& m) {
  return os << "[x: " << m.x_axis << ", y: " << m.y_axis << ']';
}

} // namespace plume

PLUME_MASK_CODE_END
