// plume/numerics/functions.hpp - per-element functions, one name for every element type.
//
// Every function works lane by lane and gives, on every lane of a batch, exactly the bits the
// scalar function gives for that lane's input (the lane-exactness contract), in every build.
//
// min / max: the IEEE 754-2019 minimum/maximum rule, in every path: if either argument is
//   NaN the result is NaN; -0 is smaller than +0; otherwise the smaller/larger value. Both are
//   symmetric (min(a, b) == min(b, a) bit for bit, NaN payloads aside). Costs 3 (min) or
//   6 (max) instructions on batches instead of the 1 of minps/maxps, whose result depends on
//   argument order when a NaN or a signed zero is involved.
// clamp(x, lo, hi) = min(max(x, lo), hi): NaN in any argument gives NaN; lo > hi gives hi.
// Integer min/max/clamp/abs are the ordinary ones (abs of the most negative value wraps).
//
// Rounding: floor, ceil, trunc, round (half away from zero, like std::round),
//   round_ties_even (ties to even, the IEEE default). All keep the sign of zero
//   (floor(-0.5) = -1, ceil(-0.5) = -0, round(-0.4) = -0) and return NaN/inf unchanged.
// fract(x) = x - trunc(x) (sign of x; Rust's f32::fract); inf gives NaN.
// signum(x): 1 for x >= +0, -1 for x <= -0 (sign bit), NaN for NaN (Rust's signum).
// copysign(x, s): |x| with the sign bit of s.
// sqrt: correctly rounded; sqrt(-x) = NaN, sqrt(-0) = -0.   recip(x) = 1 / x.
// mul_add(a, b, c) = a*b + c, rounded twice; fused (rounded once) only when the build sets
//   PLUME_FMA (PLUME_DETERMINISTIC must then be off).
// hypot(x, y): in <plume/numerics/hypot.hpp> (it needs the double-word helpers).
// lerp(a, b, t) = a + t*(b - a): exact at t = 0, monotonic in t when a, b are finite.
#pragma once

#include <plume/numerics/bits.hpp>
#include <plume/numerics/concepts.hpp>
#include <plume/numerics/constants.hpp>
#include <plume/numerics/mask.hpp>

#include <cmath>
#include <cstdlib>
#if PLUME_FMA
#include <immintrin.h>
#endif

PLUME_MASK_CODE_BEGIN

namespace plume {

// ---------------------------------------------------------------------------------- sign
template <Signed T>
PLUME_INLINE T abs(T x) noexcept {
  if constexpr (is_batch_v<T>)
    return xsimd::abs(x);
  else if constexpr (Float<T>)
    return detail::bit_andnot(x, detail::bit_pattern<T>(detail::sign_mask_v<T>));
  else
    return x < 0 ? T(-x) : x;
}

template <Float T>
PLUME_INLINE T copysign(T x, T s) noexcept {
  T const m = detail::bit_pattern<T>(detail::sign_mask_v<T>);
  return detail::bit_or(detail::bit_andnot(x, m), detail::bit_and(s, m));
}

template <Float T>
PLUME_INLINE T signum(T x) noexcept {
  return plume::select(plume::is_nan(x), x, plume::copysign(one<T>(), x));
}

template <Signed T>
requires Int<T> PLUME_INLINE T signum(T x)
noexcept { return plume::select(x > T(0), T(1), plume::select(x < T(0), T(-1), T(0))); }

// ------------------------------------------------------------------------------ min / max
template <Num T>
PLUME_INLINE T min(T a, T b) noexcept {
  if constexpr (Float<T>) {
    if constexpr (is_batch_v<T>) {
      // minps(a, b) returns its second operand when the pair is unordered or equal; or-ing
      // both orders gives NaN (a NaN or-ed with anything is NaN) and -0 for {-0, +0}.
      return xsimd::min(a, b) | xsimd::min(b, a);
    } else {
      if (a != a || b != b) return a + b;      // NaN
      if (a == b) return detail::bit_or(a, b); // -0 if either is -0
      return a < b ? a : b;
    }
  } else {
    if constexpr (is_batch_v<T>)
      return xsimd::min(a, b);
    else
      return b < a ? b : a;
  }
}

template <Num T>
PLUME_INLINE T max(T a, T b) noexcept {
  if constexpr (Float<T>) {
    if constexpr (is_batch_v<T>) {
      // and-ing both orders gives +0 for {-0, +0}; unordered pairs are patched to NaN.
      T const m = xsimd::max(a, b) & xsimd::max(b, a);
      return xsimd::select(plume::is_nan(a) | plume::is_nan(b), a + b, m);
    } else {
      if (a != a || b != b) return a + b;       // NaN
      if (a == b) return detail::bit_and(a, b); // +0 unless both are -0
      return a < b ? b : a;
    }
  } else {
    if constexpr (is_batch_v<T>)
      return xsimd::max(a, b);
    else
      return a < b ? b : a;
  }
}

template <Num T>
PLUME_INLINE T clamp(T x, T lo, T hi) noexcept {
  return plume::min(plume::max(x, lo), hi);
}

// min_select(a, b) is exactly select(a < b, a, b), max_select(a, b) exactly
// select(a > b, a, b): the second argument when the pair is unordered (a NaN) or equal (so
// the order of -0 and +0 matters). One instruction on every path (minps/maxps, minss/maxss),
// where a select is a compare and a blend on batches: for kernels whose NaN lanes are masked
// out anyway or whose inputs are finite. clamp_select(x, lo, hi) = min_select(max_select(x,
// lo), hi) (a NaN x gives lo).
template <Real T>
PLUME_INLINE T min_select(T a, T b) noexcept {
  if constexpr (is_batch_v<T>)
    return xsimd::min(a, b); // MINPS: a < b ? a : b
  else
    return a < b ? a : b;
}
template <Real T>
PLUME_INLINE T max_select(T a, T b) noexcept {
  if constexpr (is_batch_v<T>)
    return xsimd::max(a, b); // MAXPS: a > b ? a : b
  else
    return a > b ? a : b;
}
template <Real T>
PLUME_INLINE T clamp_select(T x, T lo, T hi) noexcept {
  return plume::min_select(plume::max_select(x, lo), hi);
}

// ----------------------------------------------------------------------------- rounding
namespace detail {
/// 2^(mantissa bits): every float at or above it in magnitude is an integer.
template <Float T>
PLUME_INLINE T integral_threshold() noexcept {
  return splat<T>(sizeof(scalar_t<T>) == 4 ? 8388608.0 : 4503599627370496.0);
}
/// Round to nearest, ties to even, with additions only (exact for every input, sign kept).
/// Used where the CPU has no rounding instruction (SSE2); gives the same bits as roundps.
template <Float T>
PLUME_INLINE T round_ties_even_portable(T x) noexcept {
  T const a = plume::abs(x);
  T const big = integral_threshold<T>();
  T const r = (a + big) - big;
  return plume::select(a < big, plume::copysign(r, x), x);
}
} // namespace detail

template <Float T>
PLUME_INLINE T round_ties_even(T x) noexcept {
#if defined(__SSE4_1__)
  if constexpr (is_batch_v<T>)
    return xsimd::nearbyint(x);
  else
    return std::nearbyint(x);
#else
  return detail::round_ties_even_portable(x);
#endif
}

template <Float T>
PLUME_INLINE T trunc(T x) noexcept {
#if defined(__SSE4_1__)
  if constexpr (is_batch_v<T>)
    return xsimd::trunc(x);
  else
    return std::trunc(x);
#else
  T const a = plume::abs(x);
  T const r = detail::round_ties_even_portable(a);
  T const t = r - plume::select(r > a, one<T>(), zero<T>());
  return plume::select(a < detail::integral_threshold<T>(), plume::copysign(t, x), x);
#endif
}

template <Float T>
PLUME_INLINE T floor(T x) noexcept {
#if defined(__SSE4_1__)
  if constexpr (is_batch_v<T>)
    return xsimd::floor(x);
  else
    return std::floor(x);
#else
  T const t = plume::trunc(x);
  return t - plume::select(t > x, one<T>(), zero<T>());
#endif
}

template <Float T>
PLUME_INLINE T ceil(T x) noexcept {
#if defined(__SSE4_1__)
  if constexpr (is_batch_v<T>)
    return xsimd::ceil(x);
  else
    return std::ceil(x);
#else
  return -plume::floor(-x);
#endif
}

template <Float T>
PLUME_INLINE T round(T x) noexcept {
  // trunc(x) + (|x - trunc(x)| >= 0.5 ? sign(x) : 0); x - trunc(x) is exact.
  T const t = plume::trunc(x);
  T const bump = plume::select(plume::abs(x - t) >= half<T>(), one<T>(), zero<T>());
  return plume::copysign(plume::abs(t) + bump, x);
}

template <Float T>
PLUME_INLINE T fract(T x) noexcept {
  return x - plume::trunc(x);
}

// ---------------------------------------------------------------------------- arithmetic
template <Real T>
PLUME_INLINE T sqrt(T x) noexcept {
  if constexpr (is_batch_v<T>)
    return xsimd::sqrt(x);
  else
    return std::sqrt(x);
}

template <Real T>
PLUME_INLINE T recip(T x) noexcept {
  return one<T>() / x;
}

template <Real T>
PLUME_INLINE T mul_add(T a, T b, T c) noexcept {
#if PLUME_FMA
  if constexpr (is_batch_v<T>) {
    using S = scalar_t<T>;
    constexpr std::size_t bytes = sizeof(S) * lanes_v<T>;
    if constexpr (std::is_same_v<S, float> && bytes == 16)
      return T(_mm_fmadd_ps(a, b, c));
    else if constexpr (std::is_same_v<S, double> && bytes == 16)
      return T(_mm_fmadd_pd(a, b, c));
    else if constexpr (std::is_same_v<S, float> && bytes == 32)
      return T(_mm256_fmadd_ps(a, b, c));
    else if constexpr (std::is_same_v<S, double> && bytes == 32)
      return T(_mm256_fmadd_pd(a, b, c));
#if PLUME_HAS_AVX512
    else if constexpr (std::is_same_v<S, float> && bytes == 64)
      return T(_mm512_fmadd_ps(a, b, c));
    else if constexpr (std::is_same_v<S, double> && bytes == 64)
      return T(_mm512_fmadd_pd(a, b, c));
#endif
  } else {
    return std::fma(a, b, c);
  }
#else
  return a * b + c;
#endif
}

template <Real T>
PLUME_INLINE T lerp(T a, T b, T t) noexcept {
  return plume::mul_add(t, b - a, a);
}

} // namespace plume

PLUME_MASK_CODE_END
