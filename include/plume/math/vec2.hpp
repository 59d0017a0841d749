// plume/math/vec2.hpp - GVec2<T>: a 2-vector whose components are any element type.
//
// The 2D counterpart of GVec3 with the same conventions (see vec3.hpp): lane-exact wide
// forms, value + mask for checked operations, left-to-right sums, QNAN/INF for the NaN and
// infinity constants. 2D specifics: perp() = (-y, x) (counter-clockwise quarter turn),
// perp_dot(b) = x b.y - y b.x (the z of the 3D cross product), from_angle/to_angle in
// radians from +x, rotate(b) multiplies as complex numbers, angle_to(b) is signed in
// (-pi, pi] (atan2 of perp_dot and dot: accurate near 0 and pi).
#pragma once

#include <plume/math/bvec2.hpp>
#include <plume/math/detail/clamp_length.hpp>
#include <plume/numerics.hpp>

#include <array>
#include <cstddef>
#include <ostream>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Num T>
struct GVec2 {
  using element_type = T;
  using scalar_type = scalar_t<T>;
  using mask_type = GBVec2<mask_t<T>>;
  static constexpr std::size_t dim = 2;

  T x, y;

  constexpr GVec2() noexcept : x(plume::zero<T>()), y(plume::zero<T>()) {}
  constexpr GVec2(T x_, T y_) noexcept : x(x_), y(y_) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GVec2(GVec2<U> const& v) noexcept
      : x(v.x), y(v.y) {}

  static constexpr GVec2 splat(T v) noexcept { return {v, v}; }
  static GVec2 from_array(std::array<T, 2> const& a) noexcept { return {a[0], a[1]}; }
  std::array<T, 2> to_array() const noexcept { return {x, y}; }

  static GVec2 const ZERO, ONE, NEG_ONE, X, Y, NEG_X, NEG_Y, MIN, MAX, QNAN, INF, NEG_INF;
  static GVec2 const AXES[2];

  static GVec2 select(mask_type const& m, GVec2 const& a, GVec2 const& b) noexcept {
    return {plume::select(m.x, a.x, b.x), plume::select(m.y, a.y, b.y)};
  }
  static GVec2 select(mask_t<T> m, GVec2 const& a, GVec2 const& b) noexcept {
    return {plume::select(m, a.x, b.x), plume::select(m, a.y, b.y)};
  }

  friend GVec2 operator+(GVec2 const& a, GVec2 const& b) noexcept { return {a.x + b.x, a.y + b.y}; }
  friend GVec2 operator-(GVec2 const& a, GVec2 const& b) noexcept { return {a.x - b.x, a.y - b.y}; }
  friend GVec2 operator*(GVec2 const& a, GVec2 const& b) noexcept { return {a.x * b.x, a.y * b.y}; }
  friend GVec2 operator/(GVec2 const& a, GVec2 const& b) noexcept requires Real<T> {
    return {a.x / b.x, a.y / b.y};
  }
  friend GVec2 operator*(GVec2 const& a, T s) noexcept { return {a.x * s, a.y * s}; }
  friend GVec2 operator*(T s, GVec2 const& a) noexcept { return {s * a.x, s * a.y}; }
  friend GVec2 operator/(GVec2 const& a, T s) noexcept requires Real<T> {
    return {a.x / s, a.y / s};
  }
  friend GVec2 operator+(GVec2 const& a, T s) noexcept { return {a.x + s, a.y + s}; }
  friend GVec2 operator-(GVec2 const& a, T s) noexcept { return {a.x - s, a.y - s}; }
  friend GVec2 operator-(GVec2 const& a) noexcept requires Signed<T> { return {-a.x, -a.y}; }
  friend GVec2 operator*(GVec2 const& a, scalar_type s) noexcept requires is_batch_v<T> {
    return a * T(s);
  }
  friend GVec2 operator*(scalar_type s, GVec2 const& a) noexcept requires is_batch_v<T> {
    return T(s) * a;
  }
  GVec2& operator+=(GVec2 const& b) noexcept { return *this = *this + b; }
  GVec2& operator-=(GVec2 const& b) noexcept { return *this = *this - b; }
  GVec2& operator*=(T s) noexcept { return *this = *this * s; }

  mask_type cmpeq(GVec2 const& b) const noexcept { return {x == b.x, y == b.y}; }
  mask_type cmpne(GVec2 const& b) const noexcept { return {x != b.x, y != b.y}; }
  mask_type cmplt(GVec2 const& b) const noexcept { return {x < b.x, y < b.y}; }
  mask_type cmple(GVec2 const& b) const noexcept { return {x <= b.x, y <= b.y}; }
  mask_type cmpgt(GVec2 const& b) const noexcept { return {x > b.x, y > b.y}; }
  mask_type cmpge(GVec2 const& b) const noexcept { return {x >= b.x, y >= b.y}; }
  mask_t<T> is_finite() const noexcept requires Float<T> {
    return plume::is_finite(x) & plume::is_finite(y);
  }
  mask_t<T> is_nan() const noexcept requires Float<T> {
    return plume::is_nan(x) | plume::is_nan(y);
  }
  mask_t<T> abs_diff_eq(GVec2 const& b, T max_abs_diff) const noexcept requires Real<T> {
    return (*this - b).abs().cmple(splat(max_abs_diff)).all();
  }

  GVec2 min(GVec2 const& b) const noexcept { return {plume::min(x, b.x), plume::min(y, b.y)}; }
  GVec2 max(GVec2 const& b) const noexcept { return {plume::max(x, b.x), plume::max(y, b.y)}; }
  GVec2 clamp(GVec2 const& lo, GVec2 const& hi) const noexcept { return max(lo).min(hi); }
  T min_element() const noexcept { return plume::min(x, y); }
  T max_element() const noexcept { return plume::max(x, y); }
  T element_sum() const noexcept { return x + y; }
  T element_product() const noexcept { return x * y; }
  GVec2 abs() const noexcept requires Signed<T> { return {plume::abs(x), plume::abs(y)}; }
  GVec2 signum() const noexcept requires Signed<T> { return {plume::signum(x), plume::signum(y)}; }
#define PLUME_VEC2_MAP(name)                                                                       \
  GVec2 name() const noexcept requires Float<T> { return {plume::name(x), plume::name(y)}; }
  PLUME_VEC2_MAP(floor)
  PLUME_VEC2_MAP(ceil)
  PLUME_VEC2_MAP(round)
  PLUME_VEC2_MAP(trunc)
  PLUME_VEC2_MAP(fract)
  PLUME_VEC2_MAP(recip)
#undef PLUME_VEC2_MAP
  GVec2 copysign(GVec2 const& s) const noexcept requires Float<T> {
    return {plume::copysign(x, s.x), plume::copysign(y, s.y)};
  }

  T dot(GVec2 const& b) const noexcept { return x * b.x + y * b.y; }
  /// x b.y - y b.x: |a||b| sin(angle from a to b).
  T perp_dot(GVec2 const& b) const noexcept { return x * b.y - y * b.x; }
  /// (-y, x): this turned a quarter counter-clockwise.
  GVec2 perp() const noexcept requires Signed<T> { return {-y, x}; }
  T length_squared() const noexcept { return dot(*this); }
  T length() const noexcept requires Real<T> { return plume::sqrt(length_squared()); }
  T length_recip() const noexcept requires Real<T> { return plume::one<T>() / length(); }
  T distance(GVec2 const& b) const noexcept requires Real<T> { return (*this - b).length(); }
  T distance_squared(GVec2 const& b) const noexcept { return (*this - b).length_squared(); }
  GVec2 normalize() const noexcept requires Real<T> { return *this * length_recip(); }
  struct normalized {
    GVec2 value;
    mask_t<T> valid;
  };
  normalized try_normalize() const noexcept requires Float<T> {
    T const r = length_recip();
    mask_t<T> const ok = plume::is_finite(r) & (r > plume::zero<T>());
    return {select(ok, *this * r, splat(plume::zero<T>())), ok};
  }
  GVec2 normalize_or(GVec2 const& fallback) const noexcept requires Float<T> {
    T const r = length_recip();
    return select(plume::is_finite(r) & (r > plume::zero<T>()), *this * r, fallback);
  }
  GVec2 normalize_or_zero() const noexcept requires Float<T> {
    return normalize_or(splat(plume::zero<T>()));
  }
  mask_t<T> is_normalized() const noexcept requires Real<T> {
    return plume::abs(length_squared() - plume::one<T>()) <= plume::splat<T>(scalar_type(2e-4));
  }
  GVec2 project_onto(GVec2 const& b) const noexcept requires Real<T> {
    return b * (dot(b) / b.length_squared());
  }
  GVec2 reject_from(GVec2 const& b) const noexcept requires Real<T> {
    return *this - project_onto(b);
  }
  GVec2 project_onto_normalized(GVec2 const& b) const noexcept { return b * dot(b); }
  GVec2 reject_from_normalized(GVec2 const& b) const noexcept {
    return *this - project_onto_normalized(b);
  }
  GVec2 reflect(GVec2 const& n) const noexcept requires Real<T> {
    return *this - n * (plume::two<T>() * dot(n));
  }

  /// (cos a, sin a).
  static GVec2 from_angle(T angle) noexcept requires Float<T> {
    auto const [s, c] = plume::sincos(angle);
    return {c, s};
  }
  /// Angle from +x in (-pi, pi]; 0 for the zero vector.
  T to_angle() const noexcept requires Float<T> { return plume::atan2(y, x); }
  /// Signed angle from this to b in (-pi, pi] (counter-clockwise positive).
  T angle_to(GVec2 const& b) const noexcept requires Float<T> {
    return plume::atan2(perp_dot(b), dot(b));
  }
  /// Complex multiplication: rotates (and scales) b by this: (x b.x - y b.y, y b.x + x b.y).
  GVec2 rotate(GVec2 const& b) const noexcept { return {x * b.x - y * b.y, y * b.x + x * b.y}; }

  GVec2 lerp(GVec2 const& b, T t) const noexcept requires Real<T> {
    return {plume::lerp(x, b.x, t), plume::lerp(y, b.y, t)};
  }
  GVec2 midpoint(GVec2 const& b) const noexcept requires Real<T> {
    return (*this + b) * plume::half<T>();
  }
  GVec2 move_towards(GVec2 const& b, T d) const noexcept requires Real<T> {
    GVec2 const a = b - *this;
    T const len = a.length();
    mask_t<T> const arrive = (len <= d) | (len <= plume::splat<T>(scalar_type(1e-4)));
    return select(arrive, b, *this + a * (d / len));
  }
  /// The clamp_length family: as GVec3's (right for any finite v, see detail/clamp_length.hpp).
  PLUME_INLINE GVec2 clamp_length(T lo, T hi) const noexcept requires Float<T> {
    return detail::clamp_length(*this, lo, hi);
  }
  PLUME_INLINE GVec2 clamp_length_max(T hi) const noexcept requires Float<T> {
    return detail::clamp_length_max(*this, hi);
  }
  PLUME_INLINE GVec2 clamp_length_min(T lo) const noexcept requires Float<T> {
    return detail::clamp_length_min(*this, lo);
  }
};

template <Num T>
inline GVec2<T> const GVec2<T>::ZERO = GVec2<T>::splat(plume::zero<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::ONE = GVec2<T>::splat(plume::one<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::NEG_ONE = GVec2<T>::splat(-plume::one<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::X = {plume::one<T>(), plume::zero<T>()};
template <Num T>
inline GVec2<T> const GVec2<T>::Y = {plume::zero<T>(), plume::one<T>()};
template <Num T>
inline GVec2<T> const GVec2<T>::NEG_X = {-plume::one<T>(), plume::zero<T>()};
template <Num T>
inline GVec2<T> const GVec2<T>::NEG_Y = {plume::zero<T>(), -plume::one<T>()};
template <Num T>
inline GVec2<T> const GVec2<T>::MIN = GVec2<T>::splat(plume::min_value<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::MAX = GVec2<T>::splat(plume::max_value<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::QNAN = GVec2<T>::splat(plume::nan<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::INF = GVec2<T>::splat(plume::infinity<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::NEG_INF = GVec2<T>::splat(-plume::infinity<T>());
template <Num T>
inline GVec2<T> const GVec2<T>::AXES[2] = {{plume::one<T>(), plume::zero<T>()},
                                           {plume::zero<T>(), plume::one<T>()}};

using Vec2 = GVec2<float>;
using DVec2 = GVec2<double>;
using Vec2xN = GVec2<f32xN>;
using DVec2xN = GVec2<f64xN>;

template <Num T>
PLUME_INLINE GVec2<scalar_t<T>> lane(GVec2<T> const& v, std::size_t i) noexcept {
  return {plume::lane(v.x, i), plume::lane(v.y, i)};
}
template <Num T>
PLUME_INLINE GVec2<T> with_lane(GVec2<T> const& v, std::size_t i,
                                GVec2<scalar_t<T>> const& s) noexcept {
  return {plume::with_lane(v.x, i, s.x), plume::with_lane(v.y, i, s.y)};
}
template <Mask M>
PLUME_INLINE GBVec2<bool> lane(GBVec2<M> const& m, std::size_t i) noexcept {
  return {plume::lane(m.x, i), plume::lane(m.y, i)};
}

template <Num T>
std::ostream& operator<<(std::ostream& os, GVec2<T> const& v) {
  if constexpr (is_batch_v<T>) {
    os << '[';
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      os << (i ? ", " : "") << plume::lane(v, i);
    return os << ']';
  } else {
    return os << '(' << v.x << ", " << v.y << ')';
  }
}

} // namespace plume

PLUME_MASK_CODE_END
