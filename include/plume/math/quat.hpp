// plume/math/quat.hpp - GQuat<T>: a rotation quaternion (x, y, z, w) of any Float element type.
//
// Unit quaternions represent rotations; q and -q are the same rotation. q * v rotates v,
// q1 * q2 rotates by q2 first, then q1. Angles are in radians, right-handed.
//
// Degenerate input (each documented result is the same for scalar and wide lanes):
//  - from_scaled_axis(zero) = IDENTITY; to_axis_angle of (near) IDENTITY = {X, 0}.
//  - from_rotation_arc(a, b) of opposite vectors: a half turn about a.any_orthonormal_vector().
//  - slerp of identical quaternions: q to rounding (f32: the series weights, smooth through
//    angle 0; f64: the normalised lerp, no 0/0); of opposite ones (q, -q): takes the shortest
//    path, so the result is q at every t.
//  - normalize() of the zero quaternion gives NaN (as glam); inverse() is the conjugate
//    (exact for unit quaternions, which is what rotations are).
// Euler angles: from_euler(order, a, b, c) = R(first axis, a) R(second, b) R(third, c)
// (intrinsic rotations in the order named, glam's convention); to_euler returns a, c in
// [-pi, pi] and b in [-pi/2, pi/2]; in gimbal lock (cos b <= 16 eps) it sets c = 0.
#pragma once

#include <plume/math/mat3.hpp>
#include <plume/math/vec3.hpp>

#include <array>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

PLUME_MASK_CODE_BEGIN

namespace plume {

#if defined(__SSE2__)
namespace detail {
/// The lanes of v in the order Imm (_MM_SHUFFLE): one PSHUFD without AVX, SHUFPS with AVX
/// (the cheaper form for each; docs/performance.md, "GQuat").
template <int Imm>
PLUME_INLINE __m128 swizzle_ps(__m128 v) noexcept {
#if defined(__AVX__)
  return _mm_shuffle_ps(v, v, Imm);
#else
  return _mm_castsi128_ps(_mm_shuffle_epi32(_mm_castps_si128(v), Imm));
#endif
}
} // namespace detail
#endif

/// Orders of Euler angles: the axes of the three rotations, first to last.
enum class EulerRot { XYZ, XZY, YXZ, YZX, ZXY, ZYX };

namespace detail {
/// sin(t a) / sin(a) for cos a = 1 - y, by multiplies and adds only: the series
/// sum_i c_i(t) y^i, c_0 = t, c_i = c_(i-1) (i^2 - t^2) / (i (2i + 1)) (Eberly, "A Fast and
/// Accurate Algorithm for Computing SLERP", 2011), cut after i = 7 with that last term scaled
/// by 1 + mu, mu balancing the truncation error over t in [0, 1] at y = 1 - cos(pi/4).
/// Meant for a in [0, pi/4] (y in [0, 0.2929]), where the truncation error, measured in long
/// double on a 301 x 101 grid, is <= 1.0e-9 for t in [0, 1] and <= 4.8e-9 for t in [-2, 3] (slerp
/// uses [-1, 2]); it grows quickly for larger |t| (the c_i are polynomials of degree 2i + 1) and
/// for larger y. y2, y4 are y^2, y^4 (shared by the weights of a slerp).
template <Float T>
PLUME_INLINE T sin_ratio_series(T t, T y, T y2, T y4) noexcept {
  using S = scalar_t<T>;
  constexpr int n = 7;
  constexpr double last = 1.152781554; // 1 + mu, on the term of c_n
  // k_i = (i^2 - t^2) / (i (2i + 1)) = a_i - t^2 r_i, so that c_i = c_(i-1) k_i.
  constexpr auto r = [] {
    std::array<S, n + 1> v{};
    for (int i = 1; i <= n; ++i)
      v[i] = static_cast<S>((i == n ? last : 1.0) / (double(i) * (2 * i + 1)));
    return v;
  }();
  constexpr auto a = [] {
    std::array<S, n + 1> v{};
    for (int i = 1; i <= n; ++i)
      v[i] = static_cast<S>((i == n ? last : 1.0) * i / (2 * i + 1));
    return v;
  }();
  T const u = t * t;
  std::array<T, n + 1> k{}, c{};
  for (int i = 1; i <= n; ++i)
    k[i] = plume::mul_add(u, splat<T>(-r[i]), splat<T>(a[i]));
  // The odd c_i along a chain of products of pairs k_(i-1) k_i, the even ones off it.
  c[0] = t;
  c[1] = t * k[1];
  for (int i = 3; i <= n; i += 2)
    c[i] = c[i - 2] * (k[i - 1] * k[i]);
  for (int i = 2; i < n; i += 2)
    c[i] = c[i - 1] * k[i];
  // Estrin's scheme in y: 3 levels of a + b y^(2^l) instead of 7 of Horner's.
  T const e0 = plume::mul_add(c[1], y, c[0]), e1 = plume::mul_add(c[3], y, c[2]);
  T const e2 = plume::mul_add(c[5], y, c[4]), e3 = plume::mul_add(c[7], y, c[6]);
  return plume::mul_add(plume::mul_add(e3, y2, e2), y4, plume::mul_add(e1, y2, e0));
}
} // namespace detail

template <Float T>
struct GQuat {
  using element_type = T;
  using scalar_type = scalar_t<T>;

  T x, y, z, w;

  /// The identity rotation.
  constexpr GQuat() noexcept
      : x(plume::zero<T>()), y(plume::zero<T>()), z(plume::zero<T>()), w(plume::one<T>()) {}
  constexpr GQuat(T x_, T y_, T z_, T w_) noexcept : x(x_), y(y_), z(z_), w(w_) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GQuat(GQuat<U> const& q) noexcept
      : x(q.x), y(q.y), z(q.z), w(q.w) {}

  static GQuat const IDENTITY, QNAN;

  static GQuat from_xyzw(T x, T y, T z, T w) noexcept { return {x, y, z, w}; }
  static GQuat from_array(std::array<T, 4> const& a) noexcept { return {a[0], a[1], a[2], a[3]}; }
  std::array<T, 4> to_array() const noexcept { return {x, y, z, w}; }
  /// The vector part (x, y, z).
  GVec3<T> xyz() const noexcept { return {x, y, z}; }

  /// Rotation by angle about a unit axis.
  static GQuat from_axis_angle(GVec3<T> const& axis, T angle) noexcept {
    auto const [s, c] = plume::sincos(angle * plume::half<T>());
    return {axis.x * s, axis.y * s, axis.z * s, c};
  }
  /// Rotation about v's direction by |v| radians; zero gives IDENTITY.
  static GQuat from_scaled_axis(GVec3<T> const& v) noexcept {
    T const angle = v.length();
    mask_t<T> const zero = angle == plume::zero<T>();
    GVec3<T> const axis = v / plume::select(zero, plume::one<T>(), angle);
    return select(zero, GQuat{}, from_axis_angle(axis, angle)); // GQuat{}: the identity
  }
  static GQuat from_rotation_x(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle * plume::half<T>());
    return {s, plume::zero<T>(), plume::zero<T>(), c};
  }
  static GQuat from_rotation_y(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle * plume::half<T>());
    return {plume::zero<T>(), s, plume::zero<T>(), c};
  }
  static GQuat from_rotation_z(T angle) noexcept {
    auto const [s, c] = plume::sincos(angle * plume::half<T>());
    return {plume::zero<T>(), plume::zero<T>(), s, c};
  }
  static GQuat from_rotation_axis(int axis, T angle) noexcept {
    return axis == 0 ? from_rotation_x(angle)
                     : (axis == 1 ? from_rotation_y(angle) : from_rotation_z(angle));
  }

  /// The axes (0 = x, 1 = y, 2 = z) of an Euler order, first to last.
  static constexpr std::array<int, 3> euler_axes(EulerRot order) noexcept {
    switch (order) {
    case EulerRot::XYZ:
      return {0, 1, 2};
    case EulerRot::XZY:
      return {0, 2, 1};
    case EulerRot::YXZ:
      return {1, 0, 2};
    case EulerRot::YZX:
      return {1, 2, 0};
    case EulerRot::ZXY:
      return {2, 0, 1};
    case EulerRot::ZYX:
      return {2, 1, 0};
    }
    return {0, 1, 2};
  }
  static GQuat from_euler(EulerRot order, T a, T b, T c) noexcept {
    auto const ax = euler_axes(order);
    return from_rotation_axis(ax[0], a) * from_rotation_axis(ax[1], b) *
           from_rotation_axis(ax[2], c);
  }
  /// The angles {a, b, c} with from_euler(order, a, b, c) == +-this (unit quaternion).
  std::array<T, 3> to_euler(EulerRot order) const noexcept {
    auto const ax = euler_axes(order);
    int const i = ax[0], j = ax[1], k = ax[2];
    // Cyclic orders (XYZ, YZX, ZXY) have parity +1.
    T const s = ((j - i + 3) % 3 == 1) ? plume::one<T>() : -plume::one<T>();
    GMat3<T> const m = GMat3<T>::from_quat(*this);
    // b from atan2 of sin b against cos b = |(M[i][i], M[i][j])|: well conditioned even at
    // the poles, where asin of a rounded sine would lose half the digits.
    T const cos_b = plume::hypot(m.at(i, i), m.at(i, j));
    T const b = plume::atan2(s * m.at(i, k), cos_b);
    mask_t<T> const lock = cos_b <= splat<T>(scalar_type(16)) * plume::epsilon<T>();
    T const a_free = plume::atan2(-s * m.at(j, k), m.at(k, k));
    T const c_free = plume::atan2(-s * m.at(i, j), m.at(i, i));
    T const a_lock = plume::atan2(s * m.at(k, j), m.at(j, j));
    return {plume::select(lock, a_lock, a_free), b, plume::select(lock, plume::zero<T>(), c_free)};
  }

  /// The rotation of a rotation matrix (orthonormal, determinant +1). Shepperd's method:
  /// the largest of w, x, y, z is computed from the diagonal, the others from the
  /// off-diagonal terms; all four candidates are computed and selected per lane.
  static GQuat from_mat3(GMat3<T> const& m) noexcept {
    T const m00 = m.x_axis.x, m11 = m.y_axis.y, m22 = m.z_axis.z;
    T const m01 = m.y_axis.x, m10 = m.x_axis.y, m02 = m.z_axis.x, m20 = m.x_axis.z,
            m12 = m.z_axis.y, m21 = m.y_axis.z;
    T const h = plume::half<T>(), one = plume::one<T>();
    T const tw = (one + m00) + (m11 + m22), tx = (one + m00) - (m11 + m22),
            ty = (one - m00) + (m11 - m22), tz = (one - m00) - (m11 - m22);
    // 4 q_i^2 = t_i; q_i = sqrt(t_i)/2, and 1/(4 q_i) = (1/2)/sqrt(t_i).
    T const max_t = plume::max(plume::max(tw, tx), plume::max(ty, tz));
    mask_t<T> const use_w = tw == max_t, use_x = !use_w & (tx == max_t),
                    use_y = !use_w & !use_x & (ty == max_t);
    T const t = plume::select(use_w, tw, plume::select(use_x, tx, plume::select(use_y, ty, tz)));
    T const r = plume::sqrt(t);
    T const big = r * h, f = h / r;
    GQuat const qw{(m21 - m12) * f, (m02 - m20) * f, (m10 - m01) * f, big};
    GQuat const qx{big, (m01 + m10) * f, (m02 + m20) * f, (m21 - m12) * f};
    GQuat const qy{(m01 + m10) * f, big, (m12 + m21) * f, (m02 - m20) * f};
    GQuat const qz{(m02 + m20) * f, (m12 + m21) * f, big, (m10 - m01) * f};
    return select(use_w, qw, select(use_x, qx, select(use_y, qy, qz)));
  }
  /// The shortest rotation taking unit vector from to unit vector to.
  static GQuat from_rotation_arc(GVec3<T> const& from, GVec3<T> const& to) noexcept {
    T const d = from.dot(to);
    T const limit = plume::one<T>() - plume::two<T>() * plume::epsilon<T>();
    GVec3<T> const c = from.cross(to);
    GQuat const general = GQuat{c.x, c.y, c.z, plume::one<T>() + d}.normalize();
    GQuat const half_turn = from_axis_angle(from.any_orthonormal_vector(), plume::pi<T>());
    return select(d > limit, GQuat{}, select(d < -limit, half_turn, general));
  }

  struct axis_angle {
    GVec3<T> axis;
    T angle;
  };
  /// {unit axis, angle in [0, 2 pi)}; {X, 0} when the vector part is below 1e-8 (IDENTITY).
  axis_angle to_axis_angle() const noexcept {
    GVec3<T> const v = xyz();
    T const len = v.length();
    mask_t<T> const ok = len >= splat<T>(scalar_type(1e-8));
    T const safe = plume::select(ok, len, plume::one<T>());
    return {GVec3<T>::select(ok, v / safe,
                             GVec3<T>{plume::one<T>(), plume::zero<T>(), plume::zero<T>()}),
            plume::select(ok, plume::two<T>() * plume::atan2(len, w), plume::zero<T>())};
  }
  /// axis * angle.
  GVec3<T> to_scaled_axis() const noexcept {
    auto const aa = to_axis_angle();
    return aa.axis * aa.angle;
  }

  GQuat conjugate() const noexcept { return {-x, -y, -z, w}; }
  /// The inverse rotation: the conjugate (exact for unit quaternions).
  GQuat inverse() const noexcept { return conjugate(); }
  T dot(GQuat const& b) const noexcept { return ((x * b.x + y * b.y) + z * b.z) + w * b.w; }
  T length_squared() const noexcept { return dot(*this); }
  T length() const noexcept { return plume::sqrt(length_squared()); }
  T length_recip() const noexcept { return plume::one<T>() / length(); }
  GQuat normalize() const noexcept { return *this * length_recip(); }
  mask_t<T> is_normalized() const noexcept {
    return plume::abs(length_squared() - plume::one<T>()) <= splat<T>(scalar_type(2e-4));
  }
  /// Per lane: the rotation angle is below about 0.0028 rad (glam's threshold).
  mask_t<T> is_near_identity() const noexcept {
    T const angle = plume::two<T>() * plume::acos(plume::min(plume::abs(w), plume::one<T>()));
    return angle < splat<T>(scalar_type(0.0028471446));
  }
  mask_t<T> is_finite() const noexcept {
    return ((plume::is_finite(x) & plume::is_finite(y)) & plume::is_finite(z)) &
           plume::is_finite(w);
  }
  mask_t<T> is_nan() const noexcept {
    return ((plume::is_nan(x) | plume::is_nan(y)) | plume::is_nan(z)) | plume::is_nan(w);
  }
  mask_t<T> abs_diff_eq(GQuat const& b, T max_abs_diff) const noexcept {
    return ((plume::abs(x - b.x) <= max_abs_diff) & (plume::abs(y - b.y) <= max_abs_diff)) &
           ((plume::abs(z - b.z) <= max_abs_diff) & (plume::abs(w - b.w) <= max_abs_diff));
  }
  /// The angle in [0, pi] of the rotation taking this to b (unit quaternions):
  /// 2 atan2(|vector part of this^-1 b|, |its w|), accurate for small angles.
  T angle_between(GQuat const& b) const noexcept {
    GQuat const d = conjugate() * b;
    return plume::two<T>() * plume::atan2(d.xyz().length(), plume::abs(d.w));
  }

  /// Rotates v: v + w t + u x t with u = (x, y, z), t = 2 u x v.
  GVec3<T> mul_vec3(GVec3<T> const& v) const noexcept {
    GVec3<T> const u = xyz();
    GVec3<T> const t = u.cross(v) * plume::two<T>();
    return (v + t * w) + u.cross(t);
  }
  /// Hamilton product: rotation by b, then by this. Each component is two pairs of products,
  /// each pair summed, then the pairs combined:
  ///   x = (w bx + y bz) + (x bw - z by)      y = (w by + y bw) - (x bz - z bx)
  ///   z = (w bz - y bx) + (x by + z bw)      w = (w bw - y by) - (x bx + z bz)
  /// (two additions deep after the products, where a chain is three). For float it is one
  /// SSE register per quaternion, with the same products and sums per component, so the
  /// bits are those of the generic line, signed zeros included; the lane-exactness tests
  /// compare the two. PLUME_INLINE, as the products below.
  PLUME_INLINE GQuat mul_quat(GQuat const& b) const noexcept {
#if defined(__SSE2__)
    if constexpr (std::is_same_v<T, float>) {
      // In lanes (x, y, z, w), with b' = (bx, by, -bz, -bw) and the exact rewrites
      // p - (-q) = p + q and p * (-q) = -(p * q) (IEEE 754; a sum is never negated, since
      // -(p + q) and (-p) + (-q) differ when p + q is an exact zero):
      //   l = w (bx by bz bw) - y (b'z b'w b'x b'y)  =  the first pair of every component
      //   m = x (bw bz by bx) - z (b'y b'x b'w b'z)  =  the second pair, in lanes x and z,
      //                                                 and the pair subtracted, in y and w
      //   result = l + (+, -, +, -) m
      using detail::swizzle_ps;
      __m128 const a = _mm_loadu_ps(&x), bb = _mm_loadu_ps(&b.x);
      __m128 const flip_zw =
          _mm_castsi128_ps(_mm_set_epi32(int(0x80000000u), int(0x80000000u), 0, 0));
      __m128 const flip_yw =
          _mm_castsi128_ps(_mm_set_epi32(int(0x80000000u), 0, int(0x80000000u), 0));
      __m128 const bf = _mm_xor_ps(bb, flip_zw);
      __m128 const l = _mm_sub_ps(_mm_mul_ps(swizzle_ps<_MM_SHUFFLE(3, 3, 3, 3)>(a), bb),
                                  _mm_mul_ps(swizzle_ps<_MM_SHUFFLE(1, 1, 1, 1)>(a),
                                             swizzle_ps<_MM_SHUFFLE(1, 0, 3, 2)>(bf)));
      __m128 const m = _mm_sub_ps(_mm_mul_ps(swizzle_ps<_MM_SHUFFLE(0, 0, 0, 0)>(a),
                                             swizzle_ps<_MM_SHUFFLE(0, 1, 2, 3)>(bb)),
                                  _mm_mul_ps(swizzle_ps<_MM_SHUFFLE(2, 2, 2, 2)>(a),
                                             swizzle_ps<_MM_SHUFFLE(2, 3, 0, 1)>(bf)));
      GQuat out;
      _mm_storeu_ps(&out.x, _mm_add_ps(l, _mm_xor_ps(m, flip_yw)));
      return out;
    }
#endif
    return {(w * b.x + y * b.z) + (x * b.w - z * b.y), (w * b.y + y * b.w) - (x * b.z - z * b.x),
            (w * b.z - y * b.x) + (x * b.y + z * b.w), (w * b.w - y * b.y) - (x * b.x + z * b.z)};
  }

  static GQuat select(mask_t<T> m, GQuat const& a, GQuat const& b) noexcept {
    return {plume::select(m, a.x, b.x), plume::select(m, a.y, b.y), plume::select(m, a.z, b.z),
            plume::select(m, a.w, b.w)};
  }

  /// Normalised linear interpolation along the shorter arc.
  GQuat lerp(GQuat const& end, T t) const noexcept {
    T const sign = plume::select(dot(end) < plume::zero<T>(), -plume::one<T>(), plume::one<T>());
    GQuat const e = end * sign;
    return GQuat{plume::lerp(x, e.x, t), plume::lerp(y, e.y, t), plume::lerp(z, e.z, t),
                 plume::lerp(w, e.w, t)}
        .normalize();
  }
  /// Spherical linear interpolation along the shorter arc, at constant angular speed: the
  /// weights sin((1 - t) a) / sin a and sin(t a) / sin a, a the angle between the quaternions
  /// (unit quaternions; the result is unit to rounding). t in [0, 1] interpolates, others
  /// extrapolate.
  ///  - f32, t in [-1/2, 3/2]: the weights are polynomials in t and 1 - cos(a/2)
  ///    (detail::sin_ratio_series): a square root and a division, no acos or sincos, no branch,
  ///    and smooth through a = 0, so identical inputs need no special case. Measured against
  ///    long double on 2e6 random pairs: components within 4.3 * 2^-24 for t in [0, 1]
  ///    (acos/sincos: 3.6) and 6.8 * 2^-24 for t in [-1/2, 3/2] (5.4).
  ///  - f64, and f32 lanes with other t: a = acos(d) and one sincos; nearly parallel inputs
  ///    (cos a > 1 - eps) use the normalised lerp instead.
  /// Bad input: a NaN or infinite component or t gives NaN in that lane. Inputs a few ulp off
  /// unit length behave as unit ones (|dot| > 1 counts as parallel); far from unit length the
  /// result is not a rotation (normalise first).
  PLUME_INLINE GQuat slerp(GQuat const& end, T t) const noexcept {
    T const d = dot(end);
    GQuat const e = select(d < plume::zero<T>(), -end, end);
    if constexpr (std::is_same_v<scalar_t<T>, float>) {
      mask_t<T> const series_ok = (t >= -half<T>()) & (t <= splat<T>(scalar_t<T>(1.5)));
      if (!plume::all(series_ok)) [[unlikely]]
        return select(series_ok, slerp_series(e, plume::abs(d), t), slerp_trig(e, d, t));
      return slerp_series(e, plume::abs(d), t);
    } else {
      return slerp_trig(e, d, t);
    }
  }
  /// Rotates towards b by at most max_angle (radians); b itself when within 1e-4 rad. A
  /// negative max_angle turns away from b by up to its magnitude (as glam).
  GQuat rotate_towards(GQuat const& b, T max_angle) const noexcept {
    T const angle = angle_between(b);
    mask_t<T> const arrive = angle <= splat<T>(scalar_type(1e-4));
    T const f = plume::clamp(max_angle / plume::select(arrive, plume::one<T>(), angle),
                             -plume::one<T>(), plume::one<T>());
    return select(arrive, b, slerp(b, f));
  }

private:
  /// slerp towards e (dot(e) = ad >= 0) by series weights on half the angle: with
  /// h = (this + e) / (2 cos(a/2)) the midpoint, slerp(t) is slerp(2t) from this to h for
  /// t <= 1/2 and slerp(2t - 1) from h to e after, both over the angle a/2 <= pi/4, where the
  /// series needs 8 terms. The half is chosen by j = 0 or 1 in products, not selects: scalar
  /// selects compile to branches, which random t would mispredict. Inputs a little off unit
  /// length (ad > 1) give a y a little below 0, where the series is as good.
  PLUME_INLINE GQuat slerp_series(GQuat const& e, T ad, T t) const noexcept {
    T const ch = plume::sqrt((plume::one<T>() + ad) * half<T>()); // cos(a/2)
    T const yh = plume::one<T>() - ch, y2 = yh * yh, y4 = y2 * y2;
    T const inv = half<T>() / ch;                               // 1 / |this + e|
    T const j = plume::keep_if(t > half<T>(), plume::one<T>()); // the second half
    T const nj = plume::one<T>() - j;
    T const s = (t + t) - j; // exact
    T const ws = detail::sin_ratio_series(s, yh, y2, y4);
    T const wr = detail::sin_ratio_series(plume::one<T>() - s, yh, y2, y4);
    // The weight through h goes to both ends, the other one to its own end (x * 1 + y * 0 is
    // x exactly: the weights are finite, or NaN together).
    T const wh = (ws * nj + wr * j) * inv;
    return *this * (wh + wr * nj) + e * (wh + ws * j);
  }
  /// slerp towards e by acos and sincos; d is the dot product with the unflipped end.
  GQuat slerp_trig(GQuat const& e, T d, T t) const noexcept {
    d = plume::abs(d);
    mask_t<T> const near = d > plume::one<T>() - plume::epsilon<T>();
    if constexpr (ScalarReal<T>) {
      // Scalars skip the branch they do not take; the value is the one select() would pick.
      if (near) return lerp(e, t);
    }
    // theta = acos(d); sin(theta) = sqrt((1 - d)(1 + d)) (1 - d is exact); the weights
    // sin((1 - t) theta) / sin(theta) = cos(t theta) - d s1 and s1 = sin(t theta) / sin(theta)
    // need one sincos instead of three sines.
    T const dc = plume::min(d, plume::one<T>());
    T const theta = plume::acos(dc);
    T const s = plume::select(near, plume::one<T>(),
                              plume::sqrt((plume::one<T>() - dc) * (plume::one<T>() + dc)));
    auto const [st, ct] = plume::sincos(theta * t);
    T const s1 = st / s, s0 = ct - dc * s1;
    GQuat const general = *this * s0 + e * s1;
    return select(near, lerp(e, t), general);
  }

public:
  // The products, slerp and its series path are PLUME_INLINE so that wide loops do not call
  // them out of line; slerp's trig path stays out of line, cold (docs/performance.md, "GQuat").
  PLUME_INLINE friend GQuat operator*(GQuat const& a, GQuat const& b) noexcept {
    return a.mul_quat(b);
  }
  PLUME_INLINE friend GVec3<T> operator*(GQuat const& q, GVec3<T> const& v) noexcept {
    return q.mul_vec3(v);
  }
  friend GQuat operator*(GQuat const& q, T s) noexcept {
    return {q.x * s, q.y * s, q.z * s, q.w * s};
  }
  friend GQuat operator/(GQuat const& q, T s) noexcept {
    return {q.x / s, q.y / s, q.z / s, q.w / s};
  }
  friend GQuat operator+(GQuat const& a, GQuat const& b) noexcept {
    return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
  }
  friend GQuat operator-(GQuat const& a, GQuat const& b) noexcept {
    return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w};
  }
  friend GQuat operator-(GQuat const& q) noexcept { return {-q.x, -q.y, -q.z, -q.w}; }
  GQuat& operator*=(GQuat const& b) noexcept { return *this = *this * b; }
};

static_assert(sizeof(GQuat<float>) == 4 * sizeof(float), "mul_quat loads x, y, z, w as one __m128");

template <Float T>
inline GQuat<T> const GQuat<T>::IDENTITY = {};
template <Float T>
inline GQuat<T> const GQuat<T>::QNAN = {plume::nan<T>(), plume::nan<T>(), plume::nan<T>(),
                                        plume::nan<T>()};

using Quat = GQuat<float>;
using DQuat = GQuat<double>;
using QuatxN = GQuat<f32xN>;
using DQuatxN = GQuat<f64xN>;

template <Float T>
PLUME_INLINE GQuat<scalar_t<T>> lane(GQuat<T> const& q, std::size_t i) noexcept {
  return {plume::lane(q.x, i), plume::lane(q.y, i), plume::lane(q.z, i), plume::lane(q.w, i)};
}
template <Float T>
PLUME_INLINE GQuat<T> with_lane(GQuat<T> const& q, std::size_t i,
                                GQuat<scalar_t<T>> const& s) noexcept {
  return {plume::with_lane(q.x, i, s.x), plume::with_lane(q.y, i, s.y),
          plume::with_lane(q.z, i, s.z), plume::with_lane(q.w, i, s.w)};
}

template <Float T>
std::ostream& operator<<(std::ostream& os, GQuat<T> const& q) {
  if constexpr (is_batch_v<T>) {
    os << '[';
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      os << (i ? ", " : "") << plume::lane(q, i);
    return os << ']';
  } else {
    return os << "quat(" << q.x << ", " << q.y << ", " << q.z << ", " << q.w << ')';
  }
}

} // namespace plume

PLUME_MASK_CODE_END
