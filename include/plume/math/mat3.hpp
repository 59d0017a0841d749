// plume/math/mat3.hpp - GMat3<T>: a 3x3 matrix, column-major, of any Real element type.
//
// Stored as three column vectors x_axis, y_axis, z_axis (glam's layout): m * v =
// x_axis v.x + y_axis v.y + z_axis v.z. `m.col(j)[i]`, `m.row(i)` and `m.at(i, j)` read
// row i, column j. Wide matrices hold one matrix per lane.
//
// Inverses use the adjugate over the determinant. inverse() of a singular matrix gives
// inf/NaN entries (as glam); try_inverse() returns {inverse, true} where the determinant is
// non-zero and finite and {zero matrix, false} elsewhere; inverse_or_zero() gives the zero
// matrix there. Inertia tensors: from_symmetric(), rotate_inertia(R) = R I R^T.
#pragma once

#include <plume/math/vec3.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Real T>
struct GMat3 {
  using element_type = T;
  using scalar_type = scalar_t<T>;
  using vec_type = GVec3<T>;

  GVec3<T> x_axis, y_axis, z_axis;

  /// The zero matrix.
  constexpr GMat3() noexcept = default;
  constexpr GMat3(GVec3<T> const& x, GVec3<T> const& y, GVec3<T> const& z) noexcept
      : x_axis(x), y_axis(y), z_axis(z) {}
  /// Every lane set to the scalar matrix m (wide matrices only).
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GMat3(GMat3<U> const& m) noexcept
      : x_axis(m.x_axis), y_axis(m.y_axis), z_axis(m.z_axis) {}

  static GMat3 from_cols(GVec3<T> const& x, GVec3<T> const& y, GVec3<T> const& z) noexcept {
    return {x, y, z};
  }
  /// From 9 values in column-major order.
  static GMat3 from_cols_array(std::array<T, 9> const& a) noexcept {
    return {{a[0], a[1], a[2]}, {a[3], a[4], a[5]}, {a[6], a[7], a[8]}};
  }
  std::array<T, 9> to_cols_array() const noexcept {
    return {x_axis.x, x_axis.y, x_axis.z, y_axis.x, y_axis.y,
            y_axis.z, z_axis.x, z_axis.y, z_axis.z};
  }
  static GMat3 from_diagonal(GVec3<T> const& d) noexcept {
    T const o = plume::zero<T>();
    return {{d.x, o, o}, {o, d.y, o}, {o, o, d.z}};
  }
  /// Non-uniform scale along the axes.
  static GMat3 from_scale(GVec3<T> const& s) noexcept { return from_diagonal(s); }
  /// Rotation about a unit axis by angle radians (right-handed).
  static GMat3 from_axis_angle(GVec3<T> const& axis, T angle) noexcept {
    auto const [s, c] = plume::sincos(angle);
    T const t = plume::one<T>() - c;
    GVec3<T> const a = axis;
    return {{a.x * a.x * t + c, a.x * a.y * t + a.z * s, a.x * a.z * t - a.y * s},
            {a.x * a.y * t - a.z * s, a.y * a.y * t + c, a.y * a.z * t + a.x * s},
            {a.x * a.z * t + a.y * s, a.y * a.z * t - a.x * s, a.z * a.z * t + c}};
  }
  /// The rotation matrix of a unit quaternion (any type with members x, y, z, w of type T,
  /// i.e. GQuat<T>; a template so that mat3.hpp need not include quat.hpp).
  template <class Q>
  static GMat3 from_quat(Q const& q) noexcept {
    T const x2 = q.x + q.x, y2 = q.y + q.y, z2 = q.z + q.z;
    T const xx = q.x * x2, xy = q.x * y2, xz = q.x * z2;
    T const yy = q.y * y2, yz = q.y * z2, zz = q.z * z2;
    T const wx = q.w * x2, wy = q.w * y2, wz = q.w * z2;
    T const l = plume::one<T>();
    return {{l - (yy + zz), xy + wz, xz - wy},
            {xy - wz, l - (xx + zz), yz + wx},
            {xz + wy, yz - wx, l - (xx + yy)}};
  }
  static GMat3 from_rotation_x(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle);
    T const o = plume::zero<T>(), l = plume::one<T>();
    return {{l, o, o}, {o, c, s}, {o, -s, c}};
  }
  static GMat3 from_rotation_y(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle);
    T const o = plume::zero<T>(), l = plume::one<T>();
    return {{c, o, -s}, {o, l, o}, {s, o, c}};
  }
  static GMat3 from_rotation_z(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle);
    T const o = plume::zero<T>(), l = plume::one<T>();
    return {{c, s, o}, {-s, c, o}, {o, o, l}};
  }
  /// The symmetric matrix [[xx xy xz] [xy yy yz] [xz yz zz]] (an inertia tensor).
  static GMat3 from_symmetric(T xx, T yy, T zz, T xy, T xz, T yz) noexcept {
    return {{xx, xy, xz}, {xy, yy, yz}, {xz, yz, zz}};
  }
  /// The cross-product matrix [v]x: [v]x * w = v x w.
  static GMat3 skew(GVec3<T> const& v) noexcept {
    T const o = plume::zero<T>();
    return {{o, v.z, -v.y}, {-v.z, o, v.x}, {v.y, -v.x, o}};
  }
  /// a b^T.
  static GMat3 outer(GVec3<T> const& a, GVec3<T> const& b) noexcept {
    return {a * b.x, a * b.y, a * b.z};
  }

  static GMat3 const IDENTITY, ZERO, QNAN;

  /// Element at row i, column j (0-based).
  T at(std::size_t i, std::size_t j) const noexcept {
    GVec3<T> const& c = col(j);
    return i == 0 ? c.x : (i == 1 ? c.y : c.z);
  }
  GVec3<T> const& col(std::size_t j) const noexcept {
    return j == 0 ? x_axis : (j == 1 ? y_axis : z_axis);
  }
  GVec3<T> row(std::size_t i) const noexcept { return {at(i, 0), at(i, 1), at(i, 2)}; }
  GVec3<T> diagonal() const noexcept { return {x_axis.x, y_axis.y, z_axis.z}; }
  T trace() const noexcept { return (x_axis.x + y_axis.y) + z_axis.z; }

  GMat3 transpose() const noexcept {
    return {{x_axis.x, y_axis.x, z_axis.x},
            {x_axis.y, y_axis.y, z_axis.y},
            {x_axis.z, y_axis.z, z_axis.z}};
  }
  /// x_axis . (y_axis x z_axis)
  T determinant() const noexcept { return z_axis.dot(x_axis.cross(y_axis)); }

  /// Adjugate / determinant. Singular: inf/NaN entries (see try_inverse).
  GMat3 inverse() const noexcept {
    GVec3<T> const t0 = y_axis.cross(z_axis), t1 = z_axis.cross(x_axis), t2 = x_axis.cross(y_axis);
    T const inv_det = plume::one<T>() / z_axis.dot(t2);
    return GMat3{t0 * inv_det, t1 * inv_det, t2 * inv_det}.transpose();
  }
  struct inverted {
    GMat3 value;
    mask_t<T> valid;
  };
  /// {inverse, true} where the determinant is non-zero and finite, {zero, false} elsewhere.
  inverted try_inverse() const noexcept requires Float<T> {
    T const det = determinant();
    mask_t<T> const ok = (det != plume::zero<T>()) & plume::is_finite(det);
    return {select(ok, inverse(), GMat3{}), ok};
  }
  GMat3 inverse_or_zero() const noexcept requires Float<T> { return try_inverse().value; }

  static GMat3 select(mask_t<T> m, GMat3 const& a, GMat3 const& b) noexcept {
    return {GVec3<T>::select(m, a.x_axis, b.x_axis), GVec3<T>::select(m, a.y_axis, b.y_axis),
            GVec3<T>::select(m, a.z_axis, b.z_axis)};
  }

  /// m * v
  GVec3<T> mul_vec3(GVec3<T> const& v) const noexcept {
    return (x_axis * v.x + y_axis * v.y) + z_axis * v.z;
  }
  /// m^T * v (rows dotted with v): the inverse rotation for a rotation matrix.
  GVec3<T> mul_transpose_vec3(GVec3<T> const& v) const noexcept {
    return {x_axis.dot(v), y_axis.dot(v), z_axis.dot(v)};
  }
  GMat3 mul_mat3(GMat3 const& b) const noexcept {
    return {mul_vec3(b.x_axis), mul_vec3(b.y_axis), mul_vec3(b.z_axis)};
  }
  /// R I R^T: an inertia tensor I given in the frame of rotation R, expressed in the world.
  GMat3 rotate_inertia(GMat3 const& r) const noexcept {
    return r.mul_mat3(*this).mul_mat3(r.transpose());
  }
  /// Per lane: equal to its transpose within max_abs_diff.
  mask_t<T> is_symmetric(T max_abs_diff) const noexcept {
    return (plume::abs(x_axis.y - y_axis.x) <= max_abs_diff) &
           (plume::abs(x_axis.z - z_axis.x) <= max_abs_diff) &
           (plume::abs(y_axis.z - z_axis.y) <= max_abs_diff);
  }
  GMat3 abs() const noexcept { return {x_axis.abs(), y_axis.abs(), z_axis.abs()}; }
  mask_t<T> is_finite() const noexcept requires Float<T> {
    return (x_axis.is_finite() & y_axis.is_finite()) & z_axis.is_finite();
  }
  mask_t<T> is_nan() const noexcept requires Float<T> {
    return (x_axis.is_nan() | y_axis.is_nan()) | z_axis.is_nan();
  }
  mask_t<T> abs_diff_eq(GMat3 const& b, T max_abs_diff) const noexcept {
    return (x_axis.abs_diff_eq(b.x_axis, max_abs_diff) &
            y_axis.abs_diff_eq(b.y_axis, max_abs_diff)) &
           z_axis.abs_diff_eq(b.z_axis, max_abs_diff);
  }

  friend GMat3 operator+(GMat3 const& a, GMat3 const& b) noexcept {
    return {a.x_axis + b.x_axis, a.y_axis + b.y_axis, a.z_axis + b.z_axis};
  }
  friend GMat3 operator-(GMat3 const& a, GMat3 const& b) noexcept {
    return {a.x_axis - b.x_axis, a.y_axis - b.y_axis, a.z_axis - b.z_axis};
  }
  friend GMat3 operator-(GMat3 const& a) noexcept { return {-a.x_axis, -a.y_axis, -a.z_axis}; }
  friend GMat3 operator*(GMat3 const& a, T s) noexcept {
    return {a.x_axis * s, a.y_axis * s, a.z_axis * s};
  }
  friend GMat3 operator*(T s, GMat3 const& a) noexcept { return a * s; }
  friend GMat3 operator*(GMat3 const& a, GMat3 const& b) noexcept { return a.mul_mat3(b); }
  friend GVec3<T> operator*(GMat3 const& a, GVec3<T> const& v) noexcept { return a.mul_vec3(v); }
  GMat3& operator+=(GMat3 const& b) noexcept { return *this = *this + b; }
  GMat3& operator-=(GMat3 const& b) noexcept { return *this = *this - b; }
  GMat3& operator*=(GMat3 const& b) noexcept { return *this = *this * b; }
  GMat3& operator*=(T s) noexcept { return *this = *this * s; }
};

template <Real T>
inline GMat3<T> const GMat3<T>::IDENTITY = {{plume::one<T>(), plume::zero<T>(), plume::zero<T>()},
                                            {plume::zero<T>(), plume::one<T>(), plume::zero<T>()},
                                            {plume::zero<T>(), plume::zero<T>(), plume::one<T>()}};
template <Real T>
inline GMat3<T> const GMat3<T>::ZERO = {};
template <Real T>
inline GMat3<T> const GMat3<T>::QNAN = {GVec3<T>::splat(plume::nan<T>()),
                                        GVec3<T>::splat(plume::nan<T>()),
                                        GVec3<T>::splat(plume::nan<T>())};

using Mat3 = GMat3<float>;
using DMat3 = GMat3<double>;
using Mat3xN = GMat3<f32xN>;
using DMat3xN = GMat3<f64xN>;

template <Real T>
PLUME_INLINE GMat3<scalar_t<T>> lane(GMat3<T> const& m, std::size_t i) noexcept {
  return {plume::lane(m.x_axis, i), plume::lane(m.y_axis, i), plume::lane(m.z_axis, i)};
}
template <Real T>
PLUME_INLINE GMat3<T> with_lane(GMat3<T> const& m, std::size_t i,
                                GMat3<scalar_t<T>> const& s) noexcept {
  return {plume::with_lane(m.x_axis, i, s.x_axis), plume::with_lane(m.y_axis, i, s.y_axis),
          plume::with_lane(m.z_axis, i, s.z_axis)};
}

/// Prints the columns: [x_axis, y_axis, z_axis] (every lane of each, for wide matrices).
template <Real T>
std::ostream& operator<<(std::ostream& os, GMat3<T> const& m) {
  return os << "[x: " << m.x_axis << ", y: " << m.y_axis << ", z: " << m.z_axis << ']';
}

} // namespace plume

PLUME_MASK_CODE_END
