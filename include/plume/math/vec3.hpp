// plume/math/vec3.hpp - GVec3<T>: a 3-vector whose components are any element type.
//
// `GVec3<float>` (alias Vec3) is an ordinary vector; `GVec3<f32x8>` holds eight of
// them in structure-of-arrays form, lane i of x, y, z being the i-th vector. Every method is
// the same code for both and lane i of a wide result equals, bit for bit, the scalar method
// on lane i's inputs. Methods that can fail for some lanes return a value and a mask, never
// branch on values.
//
// Conventions (glam's, where glam has the method):
//  - Sums are evaluated left to right: dot(a, b) = (a.x b.x + a.y b.y) + a.z b.z.
//  - normalize() of a zero or non-finite vector gives NaN components; normalize_or(f) gives
//    f instead, normalize_or_zero() gives zero; try_normalize() gives {zero, false}.
//    A length is usable when 1/length is finite and > 0.
//  - clamp_length* scale v by bound / |v| where its length crosses the bound: right for any
//    finite v (a squared length that overflows is rescaled first), an infinite component
//    clamps along the infinite components, NaN in v gives v (detail/clamp_length.hpp).
//  - angle_between uses atan2(|a x b|, a . b): accurate near 0 and pi, unlike acos of the
//    normalised dot; 0 if either vector is zero.
//  - Comparisons are cmpeq/cmpne/cmplt/cmple/cmpgt/cmpge and return GBVec3 masks; `==` is
//    not defined (for wide vectors there is no single answer).
//  - NAN and INFINITY are <cmath> macros, so those constants are spelled QNAN and INF.
#pragma once

#include <plume/math/bvec3.hpp>
#include <plume/math/detail/clamp_length.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cstddef>
#include <ostream>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Num T>
struct GVec3 {
  using element_type = T;
  using scalar_type = scalar_t<T>;
  using mask_type = GBVec3<mask_t<T>>;
  static constexpr std::size_t dim = 3;

  T x, y, z;

  /// Zero.
  PLUME_INLINE constexpr GVec3() noexcept
      : x(plume::zero<T>()), y(plume::zero<T>()), z(plume::zero<T>()) {}
  constexpr GVec3(T x_, T y_, T z_) noexcept : x(x_), y(y_), z(z_) {}
  /// Every lane set to the scalar vector v (wide vectors only).
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GVec3(GVec3<U> const& v) noexcept
      : x(v.x), y(v.y), z(v.z) {}

  static constexpr GVec3 splat(T v) noexcept { return {v, v, v}; }
  static GVec3 from_array(std::array<T, 3> const& a) noexcept { return {a[0], a[1], a[2]}; }
  std::array<T, 3> to_array() const noexcept { return {x, y, z}; }

  // Constants (defined below the class). NAN/INFINITY are <cmath> macros: QNAN, INF.
  // For scalar T they are constant-initialised; for batches they are initialised before
  // main in unspecified order: do not read them from other static initialisers.
  // The named constants. plume's own templates over T spell them out instead
  // (splat(zero<T>()), {one<T>(), zero<T>(), zero<T>()}): for a batch T each constant is
  // initialized when the program starts, and in a PLUME_DISPATCH=ON build that start-up code,
  // in a wider instruction set's kernels, would run on every CPU (the build refuses it:
  // cmake/PlumeIsolateObject.cmake).
  static GVec3 const ZERO, ONE, NEG_ONE, X, Y, Z, NEG_X, NEG_Y, NEG_Z, MIN, MAX, QNAN, INF, NEG_INF;
  static GVec3 const AXES[3];

  /// mask ? a : b, per component and lane.
  static GVec3 select(mask_type const& m, GVec3 const& a, GVec3 const& b) noexcept {
    return {plume::select(m.x, a.x, b.x), plume::select(m.y, a.y, b.y),
            plume::select(m.z, a.z, b.z)};
  }
  /// mask ? a : b with one mask for the whole vector.
  static GVec3 select(mask_t<T> m, GVec3 const& a, GVec3 const& b) noexcept {
    return {plume::select(m, a.x, b.x), plume::select(m, a.y, b.y), plume::select(m, a.z, b.z)};
  }

  // ------------------------------------------------------------------------- operators
  friend GVec3 operator+(GVec3 const& a, GVec3 const& b) noexcept {
    return {a.x + b.x, a.y + b.y, a.z + b.z};
  }
  friend GVec3 operator-(GVec3 const& a, GVec3 const& b) noexcept {
    return {a.x - b.x, a.y - b.y, a.z - b.z};
  }
  friend GVec3 operator*(GVec3 const& a, GVec3 const& b) noexcept {
    return {a.x * b.x, a.y * b.y, a.z * b.z};
  }
  friend GVec3 operator/(GVec3 const& a, GVec3 const& b) noexcept requires Real<T> {
    return {a.x / b.x, a.y / b.y, a.z / b.z};
  }
  friend GVec3 operator*(GVec3 const& a, T s) noexcept { return {a.x * s, a.y * s, a.z * s}; }
  friend GVec3 operator*(T s, GVec3 const& a) noexcept { return {s * a.x, s * a.y, s * a.z}; }
  friend GVec3 operator/(GVec3 const& a, T s) noexcept requires Real<T> {
    return {a.x / s, a.y / s, a.z / s};
  }
  friend GVec3 operator/(T s, GVec3 const& a) noexcept requires Real<T> {
    return {s / a.x, s / a.y, s / a.z};
  }
  friend GVec3 operator+(GVec3 const& a, T s) noexcept { return {a.x + s, a.y + s, a.z + s}; }
  friend GVec3 operator-(GVec3 const& a, T s) noexcept { return {a.x - s, a.y - s, a.z - s}; }
  friend GVec3 operator-(GVec3 const& a) noexcept requires Signed<T> { return {-a.x, -a.y, -a.z}; }
  // With a plain scalar on a wide vector (splatted).
  friend GVec3 operator*(GVec3 const& a, scalar_type s) noexcept requires is_batch_v<T> {
    return a * T(s);
  }
  friend GVec3 operator*(scalar_type s, GVec3 const& a) noexcept requires is_batch_v<T> {
    return T(s) * a;
  }
  friend GVec3 operator/(GVec3 const& a, scalar_type s) noexcept requires(is_batch_v<T>&& Real<T>) {
    return a / T(s);
  }
  GVec3& operator+=(GVec3 const& b) noexcept { return *this = *this + b; }
  GVec3& operator-=(GVec3 const& b) noexcept { return *this = *this - b; }
  GVec3& operator*=(GVec3 const& b) noexcept { return *this = *this * b; }
  GVec3& operator/=(GVec3 const& b) noexcept { return *this = *this / b; }
  GVec3& operator*=(T s) noexcept { return *this = *this * s; }
  GVec3& operator/=(T s) noexcept { return *this = *this / s; }

  // ----------------------------------------------------------------------- comparisons
  mask_type cmpeq(GVec3 const& b) const noexcept { return {x == b.x, y == b.y, z == b.z}; }
  mask_type cmpne(GVec3 const& b) const noexcept { return {x != b.x, y != b.y, z != b.z}; }
  mask_type cmplt(GVec3 const& b) const noexcept { return {x < b.x, y < b.y, z < b.z}; }
  mask_type cmple(GVec3 const& b) const noexcept { return {x <= b.x, y <= b.y, z <= b.z}; }
  mask_type cmpgt(GVec3 const& b) const noexcept { return {x > b.x, y > b.y, z > b.z}; }
  mask_type cmpge(GVec3 const& b) const noexcept { return {x >= b.x, y >= b.y, z >= b.z}; }
  mask_type is_nan_mask() const noexcept requires Float<T> {
    return {plume::is_nan(x), plume::is_nan(y), plume::is_nan(z)};
  }
  /// Per lane: every component finite / some component NaN.
  mask_t<T> is_finite() const noexcept requires Float<T> {
    return (plume::is_finite(x) & plume::is_finite(y)) & plume::is_finite(z);
  }
  mask_t<T> is_nan() const noexcept requires Float<T> { return is_nan_mask().any(); }
  /// Per lane: |a - b| <= max_abs_diff in every component.
  mask_t<T> abs_diff_eq(GVec3 const& b, T max_abs_diff) const noexcept requires Real<T> {
    return (*this - b).abs().cmple(splat(max_abs_diff)).all();
  }

  // ------------------------------------------------------------------- per component
  GVec3 min(GVec3 const& b) const noexcept {
    return {plume::min(x, b.x), plume::min(y, b.y), plume::min(z, b.z)};
  }
  GVec3 max(GVec3 const& b) const noexcept {
    return {plume::max(x, b.x), plume::max(y, b.y), plume::max(z, b.z)};
  }
  /// Per component clamp (plume::clamp's rule: NaN anywhere gives NaN; lo > hi gives hi).
  GVec3 clamp(GVec3 const& lo, GVec3 const& hi) const noexcept { return max(lo).min(hi); }
  T min_element() const noexcept { return plume::min(plume::min(x, y), z); }
  T max_element() const noexcept { return plume::max(plume::max(x, y), z); }
  T element_sum() const noexcept { return (x + y) + z; }
  T element_product() const noexcept { return (x * y) * z; }
  GVec3 abs() const noexcept requires Signed<T> {
    return {plume::abs(x), plume::abs(y), plume::abs(z)};
  }
  GVec3 signum() const noexcept requires Signed<T> {
    return {plume::signum(x), plume::signum(y), plume::signum(z)};
  }
#define PLUME_VEC3_MAP(name)                                                                       \
  GVec3 name() const noexcept requires Float<T> {                                                  \
    return {plume::name(x), plume::name(y), plume::name(z)};                                       \
  }
  PLUME_VEC3_MAP(floor)
  PLUME_VEC3_MAP(ceil)
  PLUME_VEC3_MAP(round)
  PLUME_VEC3_MAP(trunc)
  PLUME_VEC3_MAP(fract)
  PLUME_VEC3_MAP(recip)
#undef PLUME_VEC3_MAP
  GVec3 copysign(GVec3 const& s) const noexcept requires Float<T> {
    return {plume::copysign(x, s.x), plume::copysign(y, s.y), plume::copysign(z, s.z)};
  }
  /// a * b + c per component (plume::mul_add: fused only in PLUME_FMA builds).
  GVec3 mul_add(GVec3 const& b, GVec3 const& c) const noexcept requires Real<T> {
    return {plume::mul_add(x, b.x, c.x), plume::mul_add(y, b.y, c.y), plume::mul_add(z, b.z, c.z)};
  }

  // -------------------------------------------------------------------------- geometry
  T dot(GVec3 const& b) const noexcept { return (x * b.x + y * b.y) + z * b.z; }
  /// dot product in every component.
  GVec3 dot_into_vec(GVec3 const& b) const noexcept { return splat(dot(b)); }
  GVec3 cross(GVec3 const& b) const noexcept {
    return {y * b.z - z * b.y, z * b.x - x * b.z, x * b.y - y * b.x};
  }
  T length_squared() const noexcept { return dot(*this); }
  T length() const noexcept requires Real<T> { return plume::sqrt(length_squared()); }
  /// 1 / length (inf for the zero vector).
  T length_recip() const noexcept requires Real<T> { return plume::one<T>() / length(); }
  T distance(GVec3 const& b) const noexcept requires Real<T> { return (*this - b).length(); }
  T distance_squared(GVec3 const& b) const noexcept { return (*this - b).length_squared(); }

  /// Unit vector in this direction; NaN components for zero or non-finite vectors.
  GVec3 normalize() const noexcept requires Real<T> { return *this * length_recip(); }
  /// {unit vector, true} where the length is usable (1/length finite and > 0), else
  /// {zero, false}.
  struct normalized {
    GVec3 value;
    mask_t<T> valid;
  };
  normalized try_normalize() const noexcept requires Float<T> {
    T const r = length_recip();
    mask_t<T> const ok = plume::is_finite(r) & (r > plume::zero<T>());
    return {select(ok, *this * r, splat(plume::zero<T>())), ok};
  }
  GVec3 normalize_or(GVec3 const& fallback) const noexcept requires Float<T> {
    T const r = length_recip();
    return select(plume::is_finite(r) & (r > plume::zero<T>()), *this * r, fallback);
  }
  GVec3 normalize_or_zero() const noexcept requires Float<T> {
    return normalize_or(splat(plume::zero<T>()));
  }
  /// {unit vector, length} where the length is usable, else {X, 0} (glam's choice: the
  /// result is always a unit vector).
  struct normalized_length {
    GVec3 value;
    T length;
  };
  normalized_length normalize_and_length() const noexcept requires Float<T> {
    T const len = length();
    T const r = plume::one<T>() / len;
    mask_t<T> const ok = plume::is_finite(r) & (r > plume::zero<T>());
    return {select(ok, *this * r, GVec3{plume::one<T>(), plume::zero<T>(), plume::zero<T>()}),
            plume::select(ok, len, plume::zero<T>())};
  }
  /// Per lane: |length^2 - 1| <= 2e-4 (glam's tolerance; about 1e-4 relative in length).
  mask_t<T> is_normalized() const noexcept requires Real<T> {
    return plume::abs(length_squared() - plume::one<T>()) <= plume::splat<T>(scalar_type(2e-4));
  }

  /// The component of this along b (b need not be unit; zero b gives NaN).
  GVec3 project_onto(GVec3 const& b) const noexcept requires Real<T> {
    return b * (dot(b) / b.length_squared());
  }
  /// This minus its projection onto b: the part perpendicular to b.
  GVec3 reject_from(GVec3 const& b) const noexcept requires Real<T> {
    return *this - project_onto(b);
  }
  /// As above for a unit b (cheaper; b not unit gives a wrong answer, not NaN).
  GVec3 project_onto_normalized(GVec3 const& b) const noexcept { return b * dot(b); }
  GVec3 reject_from_normalized(GVec3 const& b) const noexcept {
    return *this - project_onto_normalized(b);
  }
  /// Mirror image across the plane with unit normal n: v - 2 (v . n) n.
  GVec3 reflect(GVec3 const& n) const noexcept requires Real<T> {
    return *this - n * (plume::two<T>() * dot(n));
  }
  /// Refraction of the unit incident direction through the surface with unit normal n and
  /// ratio of indices eta; zero on total internal reflection (as glam and GLSL).
  GVec3 refract(GVec3 const& n, T eta) const noexcept requires Real<T> {
    T const ndi = n.dot(*this);
    T const k = plume::one<T>() - eta * eta * (plume::one<T>() - ndi * ndi);
    T const root = plume::sqrt(plume::max(k, plume::zero<T>()));
    GVec3 const r = *this * eta - n * (eta * ndi + root);
    return select(k >= plume::zero<T>(), r, splat(plume::zero<T>()));
  }
  /// Unsigned angle in [0, pi] between this and b, in radians; 0 if either is zero.
  T angle_between(GVec3 const& b) const noexcept requires Float<T> {
    return plume::atan2(cross(b).length(), dot(b));
  }
  // any_ortho* and clamp_length* are PLUME_INLINE: wide loops that call them must not call
  // out of line (docs/performance.md, "GVec3").
  /// Some vector perpendicular to this, of comparable length (not normalised); zero for
  /// the zero vector.
  PLUME_INLINE GVec3 any_orthogonal_vector() const noexcept requires Float<T> {
    mask_t<T> const xbig = plume::abs(x) > plume::abs(y);
    return {plume::select(xbig, -z, plume::zero<T>()), plume::select(xbig, plume::zero<T>(), z),
            plume::select(xbig, x, -y)};
  }
  /// A unit vector perpendicular to this unit vector (Duff et al. 2017, "Building an
  /// Orthonormal Basis, Revisited": branch-free, continuous except at z = -0/+0).
  PLUME_INLINE GVec3 any_orthonormal_vector() const noexcept requires Float<T> {
    T const sign = plume::copysign(plume::one<T>(), z);
    T const a = -plume::one<T>() / (sign + z);
    T const b = x * y * a;
    return {b, sign + y * y * a, -y};
  }
  /// Two unit vectors that make a right-handed orthonormal basis with this unit vector.
  PLUME_INLINE std::array<GVec3, 2> any_orthonormal_pair() const noexcept requires Float<T> {
    T const sign = plume::copysign(plume::one<T>(), z);
    T const a = -plume::one<T>() / (sign + z);
    T const b = x * y * a;
    return {GVec3{plume::one<T>() + sign * x * x * a, sign * b, -sign * x},
            GVec3{b, sign + y * y * a, -y}};
  }

  /// The clamp_length family (detail/clamp_length.hpp): v scaled by bound / |v| where its
  /// length crosses the bound, else v; right for any finite v (squared lengths that overflow
  /// are rescaled by the largest |component|), an infinite component clamps along the infinite
  /// components, NaN in v gives v. Bounds are lengths, lo <= hi, both >= 0.
  /// Length clamped to [lo, hi] (NaN bounds give NaN, lo > hi gives hi); zero stays zero.
  PLUME_INLINE GVec3 clamp_length(T lo, T hi) const noexcept requires Float<T> {
    return detail::clamp_length(*this, lo, hi);
  }
  /// Length at most hi (NaN hi gives v).
  PLUME_INLINE GVec3 clamp_length_max(T hi) const noexcept requires Float<T> {
    return detail::clamp_length_max(*this, hi);
  }
  /// Length at least lo (NaN lo gives v); zero stays zero.
  PLUME_INLINE GVec3 clamp_length_min(T lo) const noexcept requires Float<T> {
    return detail::clamp_length_min(*this, lo);
  }

  /// this + t (b - this) per component (plume::lerp: exact at t = 0).
  GVec3 lerp(GVec3 const& b, T t) const noexcept requires Real<T> {
    return {plume::lerp(x, b.x, t), plume::lerp(y, b.y, t), plume::lerp(z, b.z, t)};
  }
  GVec3 midpoint(GVec3 const& b) const noexcept requires Real<T> {
    return (*this + b) * plume::half<T>();
  }
  /// Moves towards b by at most d (d >= 0); returns b when within d (or within 1e-4).
  GVec3 move_towards(GVec3 const& b, T d) const noexcept requires Real<T> {
    GVec3 const a = b - *this;
    T const len = a.length();
    mask_t<T> const arrive = (len <= d) | (len <= plume::splat<T>(scalar_type(1e-4)));
    return select(arrive, b, *this + a * (d / len));
  }
  /// Spherical interpolation by angle and linear in length, from this (t = 0) to b (t = 1).
  /// Nearly parallel: lerp. Nearly opposite: rotation about any_orthogonal_vector().
  GVec3 slerp(GVec3 const& b, T t) const noexcept requires Float<T> {
    T const la = length(), lb = b.length();
    T const c = dot(b) / (la * lb);
    T const target_len = plume::lerp(la, lb, t);
    T const limit =
        plume::splat<T>(scalar_type(1) - scalar_type(sizeof(scalar_type) == 4 ? 3e-7 : 1e-15));
    mask_t<T> const general_case = plume::abs(c) < limit, opposite = c < plume::zero<T>();
    // Nearly parallel: lerp. Scalars compute only the branch they take (the value select()
    // picks for wide lanes, bit for bit).
    GVec3 const near = lerp(b, t);
    if constexpr (ScalarReal<T>) {
      if (!general_case && !opposite) return near;
    }
    // Opposite: rotate this by pi t about a unit axis k perpendicular to it (Rodrigues with
    // k . v = 0: v cos + (k x v) sin).
    GVec3 const k = any_orthogonal_vector().normalize();
    T const ang = plume::pi<T>() * t;
    GVec3 const rotated =
        (*this * plume::cos(ang) + k.cross(*this) * plume::sin(ang)) * (target_len / la);
    if constexpr (ScalarReal<T>) {
      if (!general_case) return rotated;
    }
    // General case; the angle from atan2(|a x b|, a . b), accurate near 0 and pi where acos
    // of the rounded cosine is not.
    T const theta = plume::atan2(cross(b).length(), dot(b));
    T const s = plume::sin(theta);
    T const w0 = plume::sin(theta * (plume::one<T>() - t)) / s;
    T const w1 = plume::sin(theta * t) / s;
    GVec3 const general = (*this * (target_len / la)) * w0 + (b * (target_len / lb)) * w1;
    return select(general_case, general, select(opposite, rotated, near));
  }
};

template <Num T>
inline GVec3<T> const GVec3<T>::ZERO = GVec3<T>::splat(plume::zero<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::ONE = GVec3<T>::splat(plume::one<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::NEG_ONE = GVec3<T>::splat(-plume::one<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::X = {plume::one<T>(), plume::zero<T>(), plume::zero<T>()};
template <Num T>
inline GVec3<T> const GVec3<T>::Y = {plume::zero<T>(), plume::one<T>(), plume::zero<T>()};
template <Num T>
inline GVec3<T> const GVec3<T>::Z = {plume::zero<T>(), plume::zero<T>(), plume::one<T>()};
template <Num T>
inline GVec3<T> const GVec3<T>::NEG_X = {-plume::one<T>(), plume::zero<T>(), plume::zero<T>()};
template <Num T>
inline GVec3<T> const GVec3<T>::NEG_Y = {plume::zero<T>(), -plume::one<T>(), plume::zero<T>()};
template <Num T>
inline GVec3<T> const GVec3<T>::NEG_Z = {plume::zero<T>(), plume::zero<T>(), -plume::one<T>()};
template <Num T>
inline GVec3<T> const GVec3<T>::MIN = GVec3<T>::splat(plume::min_value<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::MAX = GVec3<T>::splat(plume::max_value<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::QNAN = GVec3<T>::splat(plume::nan<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::INF = GVec3<T>::splat(plume::infinity<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::NEG_INF = GVec3<T>::splat(-plume::infinity<T>());
template <Num T>
inline GVec3<T> const GVec3<T>::AXES[3] = {{plume::one<T>(), plume::zero<T>(), plume::zero<T>()},
                                           {plume::zero<T>(), plume::one<T>(), plume::zero<T>()},
                                           {plume::zero<T>(), plume::zero<T>(), plume::one<T>()}};

// Aliases: one per element type.
using Vec3 = GVec3<float>;
using DVec3 = GVec3<double>;
using IVec3 = GVec3<std::int32_t>;
using Vec3xN = GVec3<f32xN>;
using DVec3xN = GVec3<f64xN>;

/// Lane i of a wide vector as a scalar vector (a scalar vector is its own lane 0).
template <Num T>
PLUME_INLINE GVec3<scalar_t<T>> lane(GVec3<T> const& v, std::size_t i) noexcept {
  return {plume::lane(v.x, i), plume::lane(v.y, i), plume::lane(v.z, i)};
}
/// v with lane i replaced by s.
template <Num T>
PLUME_INLINE GVec3<T> with_lane(GVec3<T> const& v, std::size_t i,
                                GVec3<scalar_t<T>> const& s) noexcept {
  return {plume::with_lane(v.x, i, s.x), plume::with_lane(v.y, i, s.y),
          plume::with_lane(v.z, i, s.z)};
}
template <Mask M>
PLUME_INLINE GBVec3<bool> lane(GBVec3<M> const& m, std::size_t i) noexcept {
  return {plume::lane(m.x, i), plume::lane(m.y, i), plume::lane(m.z, i)};
}

/// Prints (x, y, z); wide vectors print every lane: [(x0, y0, z0), (x1, y1, z1), ...].
template <Num T>
std::ostream& operator<<(std::ostream& os, GVec3<T> const& v) {
  if constexpr (is_batch_v<T>) {
    os << '[';
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      os << (i ? ", " : "") << plume::lane(v, i);
    return os << ']';
  } else {
    return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
  }
}

} // namespace plume

PLUME_MASK_CODE_END
