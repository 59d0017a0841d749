// plume/math/vec4.hpp - GVec4<T>: a 4-vector whose components are any element type, and
// GBVec4<M>, its mask. Same conventions as GVec3 (see vec3.hpp): lane-exact wide forms,
// value + mask for checked operations, left-to-right sums ((x + y) + z) + w, QNAN/INF.
#pragma once

#include <plume/math/vec3.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Mask M>
struct GBVec4 {
  M x, y, z, w;
  GBVec4() = default;
  constexpr GBVec4(M x_, M y_, M z_, M w_) noexcept : x(x_), y(y_), z(z_), w(w_) {}
  M any() const noexcept { return ((x | y) | z) | w; }
  M all() const noexcept { return ((x & y) & z) & w; }
  M none() const noexcept { return !any(); }
  friend GBVec4 operator&(GBVec4 const& a, GBVec4 const& b) noexcept {
    return {a.x & b.x, a.y & b.y, a.z & b.z, a.w & b.w};
  }
  friend GBVec4 operator|(GBVec4 const& a, GBVec4 const& b) noexcept {
    return {a.x | b.x, a.y | b.y, a.z | b.z, a.w | b.w};
  }
  friend GBVec4 operator^(GBVec4 const& a, GBVec4 const& b) noexcept {
    return {a.x ^ b.x, a.y ^ b.y, a.z ^ b.z, a.w ^ b.w};
  }
  friend GBVec4 operator!(GBVec4 const& a) noexcept { return {!a.x, !a.y, !a.z, !a.w}; }
};
using BVec4 = GBVec4<bool>;

template <Num T>
struct GVec4 {
  using element_type = T;
  using scalar_type = scalar_t<T>;
  using mask_type = GBVec4<mask_t<T>>;
  static constexpr std::size_t dim = 4;

  T x, y, z, w;

  constexpr GVec4() noexcept
      : x(plume::zero<T>()), y(plume::zero<T>()), z(plume::zero<T>()), w(plume::zero<T>()) {}
  constexpr GVec4(T x_, T y_, T z_, T w_) noexcept : x(x_), y(y_), z(z_), w(w_) {}
  template <class U>
  requires(is_batch_v<T>&& std::same_as<U, scalar_type>) explicit GVec4(GVec4<U> const& v) noexcept
      : x(v.x), y(v.y), z(v.z), w(v.w) {}

  static constexpr GVec4 splat(T v) noexcept { return {v, v, v, v}; }
  static GVec4 from_array(std::array<T, 4> const& a) noexcept { return {a[0], a[1], a[2], a[3]}; }
  std::array<T, 4> to_array() const noexcept { return {x, y, z, w}; }
  /// (v.x, v.y, v.z, w)
  static GVec4 extend(GVec3<T> const& v, T w_) noexcept { return {v.x, v.y, v.z, w_}; }
  /// (x, y, z)
  GVec3<T> truncate() const noexcept { return {x, y, z}; }

  static GVec4 const ZERO, ONE, NEG_ONE, X, Y, Z, W, QNAN, INF;

  static GVec4 select(mask_type const& m, GVec4 const& a, GVec4 const& b) noexcept {
    return {plume::select(m.x, a.x, b.x), plume::select(m.y, a.y, b.y),
            plume::select(m.z, a.z, b.z), plume::select(m.w, a.w, b.w)};
  }
  static GVec4 select(mask_t<T> m, GVec4 const& a, GVec4 const& b) noexcept {
    return {plume::select(m, a.x, b.x), plume::select(m, a.y, b.y), plume::select(m, a.z, b.z),
            plume::select(m, a.w, b.w)};
  }

  friend GVec4 operator+(GVec4 const& a, GVec4 const& b) noexcept {
    return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w};
  }
  friend GVec4 operator-(GVec4 const& a, GVec4 const& b) noexcept {
    return {a.x - b.x, a.y - b.y, a.z - b.z, a.w - b.w};
  }
  friend GVec4 operator*(GVec4 const& a, GVec4 const& b) noexcept {
    return {a.x * b.x, a.y * b.y, a.z * b.z, a.w * b.w};
  }
  friend GVec4 operator/(GVec4 const& a, GVec4 const& b) noexcept requires Real<T> {
    return {a.x / b.x, a.y / b.y, a.z / b.z, a.w / b.w};
  }
  friend GVec4 operator*(GVec4 const& a, T s) noexcept {
    return {a.x * s, a.y * s, a.z * s, a.w * s};
  }
  friend GVec4 operator*(T s, GVec4 const& a) noexcept { return a * s; }
  friend GVec4 operator/(GVec4 const& a, T s) noexcept requires Real<T> {
    return {a.x / s, a.y / s, a.z / s, a.w / s};
  }
  friend GVec4 operator*(GVec4 const& a, scalar_type s) noexcept requires is_batch_v<T> {
    return a * T(s);
  }
  friend GVec4 operator+(GVec4 const& a, T s) noexcept {
    return {a.x + s, a.y + s, a.z + s, a.w + s};
  }
  friend GVec4 operator-(GVec4 const& a, T s) noexcept {
    return {a.x - s, a.y - s, a.z - s, a.w - s};
  }
  friend GVec4 operator-(GVec4 const& a) noexcept requires Signed<T> {
    return {-a.x, -a.y, -a.z, -a.w};
  }
  GVec4& operator+=(GVec4 const& b) noexcept { return *this = *this + b; }
  GVec4& operator-=(GVec4 const& b) noexcept { return *this = *this - b; }
  GVec4& operator*=(T s) noexcept { return *this = *this * s; }

  mask_type cmpeq(GVec4 const& b) const noexcept {
    return {x == b.x, y == b.y, z == b.z, w == b.w};
  }
  mask_type cmplt(GVec4 const& b) const noexcept { return {x < b.x, y < b.y, z < b.z, w < b.w}; }
  mask_type cmple(GVec4 const& b) const noexcept {
    return {x <= b.x, y <= b.y, z <= b.z, w <= b.w};
  }
  mask_type cmpne(GVec4 const& b) const noexcept {
    return {x != b.x, y != b.y, z != b.z, w != b.w};
  }
  mask_type cmpgt(GVec4 const& b) const noexcept { return {x > b.x, y > b.y, z > b.z, w > b.w}; }
  mask_type cmpge(GVec4 const& b) const noexcept {
    return {x >= b.x, y >= b.y, z >= b.z, w >= b.w};
  }
  mask_t<T> is_finite() const noexcept requires Float<T> {
    return ((plume::is_finite(x) & plume::is_finite(y)) & plume::is_finite(z)) &
           plume::is_finite(w);
  }
  mask_t<T> is_nan() const noexcept requires Float<T> {
    return ((plume::is_nan(x) | plume::is_nan(y)) | plume::is_nan(z)) | plume::is_nan(w);
  }
  mask_t<T> abs_diff_eq(GVec4 const& b, T d) const noexcept requires Real<T> {
    return (*this - b).abs().cmple(splat(d)).all();
  }
  GVec4 min(GVec4 const& b) const noexcept {
    return {plume::min(x, b.x), plume::min(y, b.y), plume::min(z, b.z), plume::min(w, b.w)};
  }
  GVec4 max(GVec4 const& b) const noexcept {
    return {plume::max(x, b.x), plume::max(y, b.y), plume::max(z, b.z), plume::max(w, b.w)};
  }
  GVec4 abs() const noexcept requires Signed<T> {
    return {plume::abs(x), plume::abs(y), plume::abs(z), plume::abs(w)};
  }
  GVec4 clamp(GVec4 const& lo, GVec4 const& hi) const noexcept { return max(lo).min(hi); }
  T min_element() const noexcept { return plume::min(plume::min(plume::min(x, y), z), w); }
  T max_element() const noexcept { return plume::max(plume::max(plume::max(x, y), z), w); }
  T element_product() const noexcept { return ((x * y) * z) * w; }
  GVec4 signum() const noexcept requires Signed<T> {
    return {plume::signum(x), plume::signum(y), plume::signum(z), plume::signum(w)};
  }
#define PLUME_VEC4_MAP(name)                                                                       \
  GVec4 name() const noexcept requires Float<T> {                                                  \
    return {plume::name(x), plume::name(y), plume::name(z), plume::name(w)};                       \
  }
  PLUME_VEC4_MAP(floor)
  PLUME_VEC4_MAP(ceil)
  PLUME_VEC4_MAP(round)
  PLUME_VEC4_MAP(trunc)
  PLUME_VEC4_MAP(fract)
  PLUME_VEC4_MAP(recip)
#undef PLUME_VEC4_MAP
  GVec4 copysign(GVec4 const& s) const noexcept requires Float<T> {
    return {plume::copysign(x, s.x), plume::copysign(y, s.y), plume::copysign(z, s.z),
            plume::copysign(w, s.w)};
  }
  T element_sum() const noexcept { return ((x + y) + z) + w; }
  T dot(GVec4 const& b) const noexcept { return ((x * b.x + y * b.y) + z * b.z) + w * b.w; }
  T length_squared() const noexcept { return dot(*this); }
  T length() const noexcept requires Real<T> { return plume::sqrt(length_squared()); }
  GVec4 normalize() const noexcept requires Real<T> { return *this * (plume::one<T>() / length()); }
  T length_recip() const noexcept requires Real<T> { return plume::one<T>() / length(); }
  T distance(GVec4 const& b) const noexcept requires Real<T> { return (*this - b).length(); }
  T distance_squared(GVec4 const& b) const noexcept { return (*this - b).length_squared(); }
  struct normalized {
    GVec4 value;
    mask_t<T> valid;
  };
  /// {unit vector, true} where 1/length is finite and > 0, else {zero, false}.
  normalized try_normalize() const noexcept requires Float<T> {
    T const r = length_recip();
    mask_t<T> const ok = plume::is_finite(r) & (r > plume::zero<T>());
    return {select(ok, *this * r, splat(plume::zero<T>())), ok};
  }
  GVec4 normalize_or(GVec4 const& fallback) const noexcept requires Float<T> {
    T const r = length_recip();
    return select(plume::is_finite(r) & (r > plume::zero<T>()), *this * r, fallback);
  }
  GVec4 normalize_or_zero() const noexcept requires Float<T> {
    return normalize_or(splat(plume::zero<T>()));
  }
  mask_t<T> is_normalized() const noexcept requires Real<T> {
    return plume::abs(length_squared() - plume::one<T>()) <= plume::splat<T>(scalar_type(2e-4));
  }
  GVec4 project_onto(GVec4 const& b) const noexcept requires Real<T> {
    return b * (dot(b) / b.length_squared());
  }
  GVec4 reject_from(GVec4 const& b) const noexcept requires Real<T> {
    return *this - project_onto(b);
  }
  GVec4 midpoint(GVec4 const& b) const noexcept requires Real<T> {
    return (*this + b) * plume::half<T>();
  }
  GVec4 move_towards(GVec4 const& b, T d) const noexcept requires Real<T> {
    GVec4 const a = b - *this;
    T const len = a.length();
    mask_t<T> const arrive = (len <= d) | (len <= plume::splat<T>(scalar_type(1e-4)));
    return select(arrive, b, *this + a * (d / len));
  }
  /// Length clamped to [lo, hi]: as GVec3's (right for any finite v, see
  /// detail/clamp_length.hpp).
  PLUME_INLINE GVec4 clamp_length(T lo, T hi) const noexcept requires Float<T> {
    return detail::clamp_length(*this, lo, hi);
  }
  GVec4 lerp(GVec4 const& b, T t) const noexcept requires Real<T> {
    return {plume::lerp(x, b.x, t), plume::lerp(y, b.y, t), plume::lerp(z, b.z, t),
            plume::lerp(w, b.w, t)};
  }
};

template <Num T>
inline GVec4<T> const GVec4<T>::ZERO = GVec4<T>::splat(plume::zero<T>());
template <Num T>
inline GVec4<T> const GVec4<T>::ONE = GVec4<T>::splat(plume::one<T>());
template <Num T>
inline GVec4<T> const GVec4<T>::NEG_ONE = GVec4<T>::splat(-plume::one<T>());
template <Num T>
inline GVec4<T> const GVec4<T>::X = {plume::one<T>(), plume::zero<T>(), plume::zero<T>(),
                                     plume::zero<T>()};
template <Num T>
inline GVec4<T> const GVec4<T>::Y = {plume::zero<T>(), plume::one<T>(), plume::zero<T>(),
                                     plume::zero<T>()};
template <Num T>
inline GVec4<T> const GVec4<T>::Z = {plume::zero<T>(), plume::zero<T>(), plume::one<T>(),
                                     plume::zero<T>()};
template <Num T>
inline GVec4<T> const GVec4<T>::W = {plume::zero<T>(), plume::zero<T>(), plume::zero<T>(),
                                     plume::one<T>()};
template <Num T>
inline GVec4<T> const GVec4<T>::QNAN = GVec4<T>::splat(plume::nan<T>());
template <Num T>
inline GVec4<T> const GVec4<T>::INF = GVec4<T>::splat(plume::infinity<T>());

using Vec4 = GVec4<float>;
using DVec4 = GVec4<double>;
using Vec4xN = GVec4<f32xN>;

template <Num T>
PLUME_INLINE GVec4<scalar_t<T>> lane(GVec4<T> const& v, std::size_t i) noexcept {
  return {plume::lane(v.x, i), plume::lane(v.y, i), plume::lane(v.z, i), plume::lane(v.w, i)};
}
template <Num T>
std::ostream& operator<<(std::ostream& os, GVec4<T> const& v) {
  if constexpr (is_batch_v<T>) {
    os << '[';
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      os << (i ? ", " : "") << plume::lane(v, i);
    return os << ']';
  } else {
    return os << '(' << v.x << ", " << v.y << ", " << v.z << ", " << v.w << ')';
  }
}

} // namespace plume

PLUME_MASK_CODE_END
