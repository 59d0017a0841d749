// plume/math/mat4.hpp - GMat4<T>: a 4x4 matrix, column-major (x_axis .. w_axis), any Real T.
//
// Affine helpers treat column w as the translation: transform_point3(p) = M (p, 1),
// transform_vector3(v) = M (v, 0), project_point3(p) divides by the resulting w.
// inverse() is the adjugate over the determinant via 2x2 minors (Laplace expansion);
// singular matrices give inf/NaN, try_inverse() gives {inverse, true} or {zero, false}.
#pragma once

#include <plume/math/mat3.hpp>
#include <plume/math/quat.hpp>
#include <plume/math/vec4.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Real T>
struct GMat4 {
  using element_type = T;
  using scalar_type = scalar_t<T>;

  GVec4<T> x_axis, y_axis, z_axis, w_axis;

  /// The zero matrix.
  constexpr GMat4() noexcept = default;
  constexpr GMat4(GVec4<T> const& x, GVec4<T> const& y, GVec4<T> const& z,
                  GVec4<T> const& w) noexcept
      : x_axis(x), y_axis(y), z_axis(z), w_axis(w) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GMat4(GMat4<U> const& m) noexcept
      : x_axis(m.x_axis), y_axis(m.y_axis), z_axis(m.z_axis), w_axis(m.w_axis) {}

  static GMat4 const IDENTITY, ZERO;

  static GMat4 from_cols(GVec4<T> const& x, GVec4<T> const& y, GVec4<T> const& z,
                         GVec4<T> const& w) noexcept {
    return {x, y, z, w};
  }
  static GMat4 from_diagonal(GVec4<T> const& d) noexcept {
    T const o = plume::zero<T>();
    return {{d.x, o, o, o}, {o, d.y, o, o}, {o, o, d.z, o}, {o, o, o, d.w}};
  }
  /// The rotation/scale m in the upper 3x3, no translation.
  static GMat4 from_mat3(GMat3<T> const& m) noexcept {
    T const o = plume::zero<T>();
    return {GVec4<T>::extend(m.x_axis, o),
            GVec4<T>::extend(m.y_axis, o),
            GVec4<T>::extend(m.z_axis, o),
            {o, o, o, plume::one<T>()}};
  }
  static GMat4 from_scale(GVec3<T> const& s) noexcept {
    return from_diagonal({s.x, s.y, s.z, plume::one<T>()});
  }
  static GMat4 from_translation(GVec3<T> const& t) noexcept {
    GMat4 m = IDENTITY_value();
    m.w_axis = GVec4<T>::extend(t, plume::one<T>());
    return m;
  }
  static GMat4 from_quat(GQuat<T> const& q) noexcept requires Float<T> {
    return from_mat3(GMat3<T>::from_quat(q));
  }
  static GMat4 from_rotation_translation(GQuat<T> const& q,
                                         GVec3<T> const& t) noexcept requires Float<T> {
    GMat4 m = from_quat(q);
    m.w_axis = GVec4<T>::extend(t, plume::one<T>());
    return m;
  }
  /// Scale, then rotate, then translate.
  static GMat4 from_scale_rotation_translation(GVec3<T> const& s, GQuat<T> const& q,
                                               GVec3<T> const& t) noexcept requires Float<T> {
    GMat3<T> const r = GMat3<T>::from_quat(q);
    GMat4 m = from_mat3({r.x_axis * s.x, r.y_axis * s.y, r.z_axis * s.z});
    m.w_axis = GVec4<T>::extend(t, plume::one<T>());
    return m;
  }

  GVec4<T> const& col(std::size_t j) const noexcept {
    return j == 0 ? x_axis : (j == 1 ? y_axis : (j == 2 ? z_axis : w_axis));
  }
  T at(std::size_t i, std::size_t j) const noexcept {
    GVec4<T> const& c = col(j);
    return i == 0 ? c.x : (i == 1 ? c.y : (i == 2 ? c.z : c.w));
  }
  GVec4<T> row(std::size_t i) const noexcept { return {at(i, 0), at(i, 1), at(i, 2), at(i, 3)}; }
  GMat4 transpose() const noexcept { return {row(0), row(1), row(2), row(3)}; }

  T determinant() const noexcept {
    minors const m = compute_minors();
    return m.det;
  }
  GMat4 inverse() const noexcept {
    minors const k = compute_minors();
    T const inv = plume::one<T>() / k.det;
    auto a = [this](std::size_t i, std::size_t j) { return at(i, j); };
    // Column j of the inverse holds inv(0..3, j).
    GVec4<T> const c0{(a(1, 1) * k.c5 - a(1, 2) * k.c4 + a(1, 3) * k.c3) * inv,
                      (-a(1, 0) * k.c5 + a(1, 2) * k.c2 - a(1, 3) * k.c1) * inv,
                      (a(1, 0) * k.c4 - a(1, 1) * k.c2 + a(1, 3) * k.c0) * inv,
                      (-a(1, 0) * k.c3 + a(1, 1) * k.c1 - a(1, 2) * k.c0) * inv};
    GVec4<T> const c1{(-a(0, 1) * k.c5 + a(0, 2) * k.c4 - a(0, 3) * k.c3) * inv,
                      (a(0, 0) * k.c5 - a(0, 2) * k.c2 + a(0, 3) * k.c1) * inv,
                      (-a(0, 0) * k.c4 + a(0, 1) * k.c2 - a(0, 3) * k.c0) * inv,
                      (a(0, 0) * k.c3 - a(0, 1) * k.c1 + a(0, 2) * k.c0) * inv};
    GVec4<T> const c2{(a(3, 1) * k.s5 - a(3, 2) * k.s4 + a(3, 3) * k.s3) * inv,
                      (-a(3, 0) * k.s5 + a(3, 2) * k.s2 - a(3, 3) * k.s1) * inv,
                      (a(3, 0) * k.s4 - a(3, 1) * k.s2 + a(3, 3) * k.s0) * inv,
                      (-a(3, 0) * k.s3 + a(3, 1) * k.s1 - a(3, 2) * k.s0) * inv};
    GVec4<T> const c3{(-a(2, 1) * k.s5 + a(2, 2) * k.s4 - a(2, 3) * k.s3) * inv,
                      (a(2, 0) * k.s5 - a(2, 2) * k.s2 + a(2, 3) * k.s1) * inv,
                      (-a(2, 0) * k.s4 + a(2, 1) * k.s2 - a(2, 3) * k.s0) * inv,
                      (a(2, 0) * k.s3 - a(2, 1) * k.s1 + a(2, 2) * k.s0) * inv};
    return {c0, c1, c2, c3};
  }
  struct inverted {
    GMat4 value;
    mask_t<T> valid;
  };
  inverted try_inverse() const noexcept requires Float<T> {
    T const det = determinant();
    mask_t<T> const ok = (det != plume::zero<T>()) & plume::is_finite(det);
    return {select(ok, inverse(), GMat4{}), ok};
  }
  GMat4 inverse_or_zero() const noexcept requires Float<T> { return try_inverse().value; }
  static GMat4 select(mask_t<T> m, GMat4 const& a, GMat4 const& b) noexcept {
    return {GVec4<T>::select(m, a.x_axis, b.x_axis), GVec4<T>::select(m, a.y_axis, b.y_axis),
            GVec4<T>::select(m, a.z_axis, b.z_axis), GVec4<T>::select(m, a.w_axis, b.w_axis)};
  }

  GVec4<T> mul_vec4(GVec4<T> const& v) const noexcept {
    return ((x_axis * v.x + y_axis * v.y) + z_axis * v.z) + w_axis * v.w;
  }
  GMat4 mul_mat4(GMat4 const& b) const noexcept {
    return {mul_vec4(b.x_axis), mul_vec4(b.y_axis), mul_vec4(b.z_axis), mul_vec4(b.w_axis)};
  }
  GVec3<T> transform_point3(GVec3<T> const& p) const noexcept {
    return (((x_axis * p.x + y_axis * p.y) + z_axis * p.z) + w_axis).truncate();
  }
  GVec3<T> transform_vector3(GVec3<T> const& v) const noexcept {
    return ((x_axis * v.x + y_axis * v.y) + z_axis * v.z).truncate();
  }
  GVec3<T> project_point3(GVec3<T> const& p) const noexcept {
    GVec4<T> const h = ((x_axis * p.x + y_axis * p.y) + z_axis * p.z) + w_axis;
    return h.truncate() / h.w;
  }
  mask_t<T> abs_diff_eq(GMat4 const& b, T d) const noexcept {
    return ((x_axis.abs_diff_eq(b.x_axis, d) & y_axis.abs_diff_eq(b.y_axis, d)) &
            z_axis.abs_diff_eq(b.z_axis, d)) &
           w_axis.abs_diff_eq(b.w_axis, d);
  }

  friend GMat4 operator+(GMat4 const& a, GMat4 const& b) noexcept {
    return {a.x_axis + b.x_axis, a.y_axis + b.y_axis, a.z_axis + b.z_axis, a.w_axis + b.w_axis};
  }
  friend GMat4 operator-(GMat4 const& a, GMat4 const& b) noexcept {
    return {a.x_axis - b.x_axis, a.y_axis - b.y_axis, a.z_axis - b.z_axis, a.w_axis - b.w_axis};
  }
  friend GMat4 operator*(GMat4 const& a, T s) noexcept {
    return {a.x_axis * s, a.y_axis * s, a.z_axis * s, a.w_axis * s};
  }
  friend GMat4 operator*(GMat4 const& a, GMat4 const& b) noexcept { return a.mul_mat4(b); }
  friend GVec4<T> operator*(GMat4 const& a, GVec4<T> const& v) noexcept { return a.mul_vec4(v); }

private:
  static GMat4 IDENTITY_value() noexcept {
    T const o = plume::zero<T>(), l = plume::one<T>();
    return {{l, o, o, o}, {o, l, o, o}, {o, o, l, o}, {o, o, o, l}};
  }
  struct minors {
    T s0, s1, s2, s3, s4, s5, c0, c1, c2, c3, c4, c5, det;
  };
  /// 2x2 minors of rows 0-1 (s) and rows 2-3 (c), and the determinant from them.
  minors compute_minors() const noexcept {
    auto a = [this](std::size_t i, std::size_t j) { return at(i, j); };
    minors k;
    k.s0 = a(0, 0) * a(1, 1) - a(1, 0) * a(0, 1);
    k.s1 = a(0, 0) * a(1, 2) - a(1, 0) * a(0, 2);
    k.s2 = a(0, 0) * a(1, 3) - a(1, 0) * a(0, 3);
    k.s3 = a(0, 1) * a(1, 2) - a(1, 1) * a(0, 2);
    k.s4 = a(0, 1) * a(1, 3) - a(1, 1) * a(0, 3);
    k.s5 = a(0, 2) * a(1, 3) - a(1, 2) * a(0, 3);
    k.c5 = a(2, 2) * a(3, 3) - a(3, 2) * a(2, 3);
    k.c4 = a(2, 1) * a(3, 3) - a(3, 1) * a(2, 3);
    k.c3 = a(2, 1) * a(3, 2) - a(3, 1) * a(2, 2);
    k.c2 = a(2, 0) * a(3, 3) - a(3, 0) * a(2, 3);
    k.c1 = a(2, 0) * a(3, 2) - a(3, 0) * a(2, 2);
    k.c0 = a(2, 0) * a(3, 1) - a(3, 0) * a(2, 1);
    k.det =
        ((((k.s0 * k.c5 - k.s1 * k.c4) + k.s2 * k.c3) + k.s3 * k.c2) - k.s4 * k.c1) + k.s5 * k.c0;
    return k;
  }
};

template <Real T>
inline GMat4<T> const GMat4<T>::IDENTITY = GMat4<T>::IDENTITY_value();
template <Real T>
inline GMat4<T> const GMat4<T>::ZERO = {};

using Mat4 = GMat4<float>;
using DMat4 = GMat4<double>;
using Mat4xN = GMat4<f32xN>;

template <Real T>
PLUME_INLINE GMat4<scalar_t<T>> lane(GMat4<T> const& m, std::size_t i) noexcept {
  return {plume::lane(m.x_axis, i), plume::lane(m.y_axis, i), plume::lane(m.z_axis, i),
          plume::lane(m.w_axis, i)};
}
template <Real T>
std::ostream& operator<<(std::ostream& os, GMat4<T> const& m) {
  return os << "[x: " << m.x_axis << ", y: " << m.y_axis << ", z: " << m.z_axis
            << ", w: " << m.w_axis << ']';
}

} // namespace plume

PLUME_MASK_CODE_END
