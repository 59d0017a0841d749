// plume/numerics/detail/poly.hpp - polynomial evaluation and double-word arithmetic used by
// the transcendental functions. Internal.
#pragma once

#include <plume/numerics/functions.hpp>

#include <bit>
#include <cstddef>
#include <iterator>

PLUME_MASK_CODE_BEGIN

namespace plume::detail {

/// c[0] x^(N-1) + ... + c[N-1], Horner's scheme with mul_add.
template <class T, class S, std::size_t N>
PLUME_INLINE T horner(T x, S const (&c)[N]) noexcept {
  T r = splat<T>(c[0]);
  for (std::size_t i = 1; i < N; ++i)
    r = plume::mul_add(r, x, splat<T>(c[i]));
  return r;
}

/// Coefficients B .. B+N-1 from the lowest degree of c (highest first) as a polynomial in x,
/// Estrin's scheme: low part + x^m high part, m the largest power of two <= (N+1)/2, with
/// pw[k] = x^(2^k).
template <std::size_t B, std::size_t N, class T, class S, std::size_t M>
PLUME_INLINE T estrin_part(T const* pw, S const (&c)[M]) noexcept {
  if constexpr (N == 1) {
    return splat<T>(c[M - 1 - B]);
  } else {
    constexpr std::size_t m = std::bit_floor((N + 1) / 2);
    constexpr int k = std::countr_zero(m);
    return plume::mul_add(estrin_part<B + m, N - m>(pw, c), pw[k], estrin_part<B, m>(pw, c));
  }
}

/// c[0] x^(N-1) + ... + c[N-1] by Estrin's scheme: the same operation count as Horner's give
/// or take the powers of x, but a dependency chain of about log2(N) multiply-adds instead of
/// N - 1 (rounded differently from horner, so the two are not interchangeable).
template <class T, class S, std::size_t N>
PLUME_INLINE T estrin(T x, S const (&c)[N]) noexcept {
  T pw[std::bit_width((N + 1) / 2)];
  pw[0] = x;
  for (std::size_t k = 1; k < std::size(pw); ++k)
    pw[k] = pw[k - 1] * pw[k - 1];
  return estrin_part<0, N>(pw, c);
}

/// Lanes of T scaled by 2^n for integer-valued n in the range of the exponent field
/// (|n| <= bias - 1): builds 2^n from bits, exact.
template <Float T>
PLUME_INLINE T pow2_int(T n) noexcept {
  using C = math_constants<scalar_t<T>>;
  using U = scalar_t<bits_t<T>>;
  // (n + magic) holds n in its low mantissa bits: bits - magic_bits + bias, shifted up.
  bits_t<T> b = plume::to_bits(n + splat<T>(C::round_magic));
  b = b +
      splat<bits_t<T>>(static_cast<U>(static_cast<U>(C::exp_bias) - static_cast<U>(C::magic_bits)));
  return from_bits<T>(b << C::mant_bits);
}

/// x * 2^n for integer-valued n with |n| <= 2 (bias - 1): two exact steps, so a result in
/// the subnormal range is rounded once, and overflow gives inf.
template <Float T>
PLUME_INLINE T scale_pow2(T x, T n) noexcept {
  using C = math_constants<scalar_t<T>>;
  T const rm = splat<T>(C::round_magic);
  T const n1 = (n * half<T>() + rm) - rm; // plume::round(n/2)
  return (x * pow2_int(n1)) * pow2_int(n - n1);
}

/// p * 2^n where t = n + round_magic (the sum whose low mantissa bits hold the integer n):
/// adds n to p's exponent field. Exact, and equal to scale_pow2(p, n), when p * 2^n is a
/// normal number (callers check the range); garbage otherwise.
template <Float T>
PLUME_INLINE T scale_pow2_normal(T p, T t) noexcept {
  using C = math_constants<scalar_t<T>>;
  using U = scalar_t<bits_t<T>>;
  bits_t<T> const n = plume::to_bits(t) - splat<bits_t<T>>(static_cast<U>(C::magic_bits));
  return from_bits<T>(plume::to_bits(p) + (n << C::mant_bits));
}

/// Round to the nearest integer (ties to even) for |v| < 2^(p-2), as a float value.
template <Float T>
PLUME_INLINE T round_small(T v) noexcept {
  T const rm = splat<T>(math_constants<scalar_t<T>>::round_magic);
  return (v + rm) - rm;
}

// ----- double-word (hi + lo) arithmetic, exact error terms without FMA -----
template <Float T>
struct dw {
  T hi, lo;
};
/// a + b = s + e exactly (Knuth).
template <Float T>
PLUME_INLINE dw<T> two_sum(T a, T b) noexcept {
  T const s = a + b;
  T const bb = s - a;
  return {s, (a - (s - bb)) + (b - bb)};
}
/// a + b = s + e exactly, for |a| >= |b| (Dekker).
template <Float T>
PLUME_INLINE dw<T> fast_two_sum(T a, T b) noexcept {
  T const s = a + b;
  return {s, b - (s - a)};
}
/// a * b = p + e exactly (Dekker/Veltkamp; fma when the build fuses). |a|, |b| < 2^(emax-p/2).
template <Float T>
PLUME_INLINE dw<T> two_prod(T a, T b) noexcept {
  T const p = a * b;
#if PLUME_FMA
  return {p, plume::mul_add(a, b, -p)};
#else
  T const f = splat<T>(math_constants<scalar_t<T>>::split_factor);
  T const ca = f * a, cb = f * b;
  T const ah = ca - (ca - a), al = a - ah;
  T const bh = cb - (cb - b), bl = b - bh;
  return {p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
#endif
}
/// (a.hi + a.lo) * (b.hi + b.lo), relative error ~ 2^(2-2p).
template <Float T>
PLUME_INLINE dw<T> dw_mul(dw<T> a, dw<T> b) noexcept {
  dw<T> const p = two_prod(a.hi, b.hi);
  return fast_two_sum(p.hi, p.lo + (a.hi * b.lo + a.lo * b.hi));
}
/// (a.hi + a.lo) + (b.hi + b.lo), for |a| >= |b| or same signs.
template <Float T>
PLUME_INLINE dw<T> dw_add(dw<T> a, dw<T> b) noexcept {
  dw<T> const s = two_sum(a.hi, b.hi);
  return fast_two_sum(s.hi, s.lo + (a.lo + b.lo));
}

} // namespace plume::detail

PLUME_MASK_CODE_END
