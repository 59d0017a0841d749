// plume/numerics/exp_log.hpp - exponentials, logarithms and powers for every Real element type.
//
//   exp exp2 expm1 (= e^x - 1, accurate near 0)     log log2 log1p (= log(1 + x))     pow(x, y)
//
// One code path over T. exp/exp2/expm1 reduce by ln 2 (Cody-Waite, two-part constant) and
// scale by 2^n; log/log2/log1p split x into 2^e (1+f) and evaluate log(1+f) = 2 atanh(f/(2+f))
// (fdlibm's scheme). pow evaluates y * log2|x| to about twice the type's precision before
// exp2, so it is accurate for large y too: float pow in double (the lanes widened into two
// double batches, one rounding back; within 0.54 ulp), double pow in double-word (hi + lo).
// exp, exp2 and log have a fast path for the usual inputs - exp/exp2 whose result is a
// normal number (2^n added to the exponent field), log of a positive normal x (split in
// integer steps). Other lanes (overflow, subnormal results or inputs, 0, negatives, inf,
// NaN) take the general path: clamping and two-step scaling, so that results that overflow
// give +inf and subnormal results are rounded once; the subnormal split and the special
// values of log. The general path runs only when some lane needs it and is merged by
// select; it gives the same bits as the fast path wherever both apply, so no lane depends on
// its neighbours or on the branch. Accuracy, printed by the accuracy test: within 2 ulp
// everywhere for float and double; most within 1. Exhaustive float check against double
// libm: exp 1.05 ulp (1.50 for subnormal results), log 0.84 ulp.
//
// Special values (C99 Annex F): exp(-inf) = 0, exp(+inf) = +inf, expm1(-inf) = -1,
// expm1(+-0) = +-0; log(0) = -inf, log(x < 0) = NaN, log(+inf) = +inf, log1p(-1) = -inf,
// log1p(+-0) = +-0; pow(x, +-0) = 1 and pow(1, y) = 1 even for NaN, pow(-1, +-inf) = 1,
// pow(negative finite, non-integer) = NaN, pow(+-0, negative odd) = +-inf, and the rest of
// Annex F's list. NaN in, NaN out otherwise.
#pragma once

#include <plume/numerics/detail/coefficients.hpp>
#include <plume/numerics/detail/poly.hpp>
#include <plume/numerics/functions.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {
namespace detail {

/// x = 2^e * (1 + f) with 1 + f in [sqrt(1/2), sqrt(2)); x > 0 finite (subnormals included).
/// Other inputs give garbage the callers replace.
template <Float T>
struct log_split {
  T e, f;
};

template <Float T>
PLUME_INLINE log_split<T> split_log(T x) noexcept {
  using S = scalar_t<T>;
  using C = math_constants<S>;
  using U = scalar_t<bits_t<T>>;
  auto const sub = x < min_positive<T>();
  x = plume::select(sub, x * splat<T>(C::subnormal_scale), x);
  T const bias_adj = plume::select(sub, splat<T>(C::subnormal_scale_log2), zero<T>());
  bits_t<T> const b = plume::to_bits(x);
  // Biased exponent as a float: put it in the low mantissa bits of 2^p and subtract 2^p.
  T const ef = from_bits<T>((b >> C::mant_bits) | splat<bits_t<T>>(static_cast<U>(C::two_p_bits))) -
               splat<T>(C::two_p);
  U const mant_mask = (U(1) << C::mant_bits) - 1;
  T m = from_bits<T>((b & splat<bits_t<T>>(mant_mask)) | plume::to_bits(one<T>())); // [1, 2)
  auto const adj = m > splat<T>(C::sqrt2);
  m = plume::select(adj, m * half<T>(), m);
  T const e = ef - splat<T>(S(C::exp_bias)) - bias_adj + plume::select(adj, one<T>(), zero<T>());
  return {e, m - one<T>()};
}

/// split_log for positive normal finite x, in integer steps (other inputs give garbage the
/// callers replace): m = x / 2^e in (sqrt2/2, sqrt2] from the bits of x, the same e and f as
/// split_log gives there.
template <Float T>
PLUME_INLINE log_split<T> split_log_normal(T x) noexcept {
  using S = scalar_t<T>;
  using C = math_constants<S>;
  using U = scalar_t<bits_t<T>>;
  using B = bits_t<T>;
  // bits of the smallest m kept: m in [off, 2 off) as bits, i.e. (sqrt2/2, sqrt2].
  constexpr U off = std::bit_cast<U>(C::sqrt2) - (U(1) << C::mant_bits) + 1;
  constexpr U one_bits = std::bit_cast<U>(S(1));
  constexpr U mant_mask = (U(1) << C::mant_bits) - 1;
  // t's exponent field is e + bias, and its mantissa field is the offset of m above off.
  B const t = plume::to_bits(x) + splat<B>(static_cast<U>(one_bits - off));
  T const e = from_bits<T>((t >> C::mant_bits) | splat<B>(static_cast<U>(C::two_p_bits))) -
              splat<T>(S(C::two_p + S(C::exp_bias)));
  T const m = from_bits<T>((t & splat<B>(mant_mask)) + splat<B>(off));
  return {e, m - one<T>()};
}

/// Pieces of log(1 + f): log(1+f) = f - (hfsq - s (hfsq + R)).
template <Float T>
struct log_kernel_parts {
  T hfsq, s, R;
};
template <Float T>
PLUME_INLINE log_kernel_parts<T> log_kernel(T f) noexcept {
  using C = math_constants<scalar_t<T>>;
  T const s = f / (two<T>() + f);
  T const z = s * s;
  T const R = z * detail::horner(z, C::log_poly);
  return {half<T>() * f * f, s, R};
}

/// Replace the core result by log's special values: 0 -> -inf, < 0 -> NaN, +inf, NaN.
template <Float T>
PLUME_INLINE T log_specials(T x, T core) noexcept {
  T r = plume::select(x == zero<T>(), neg_infinity<T>(), core);
  r = plume::select(x < zero<T>(), nan<T>(), r);
  r = plume::select(x == infinity<T>(), x, r);
  return plume::select(plume::is_nan(x), x, r);
}

/// x limited to [lo, hi] for finite lo <= hi, NaN kept: the x86 minps/maxps semantics
/// (a < b ? a : b, a > b ? a : b), which are one instruction each on batches and the same
/// comparison on scalars, so the two agree bit for bit. Cheaper than plume::clamp, whose
/// IEEE 754-2019 rule (-0 < +0, symmetric NaN) is not needed for a range limit.
template <Float T>
PLUME_INLINE T clamp_range(T x, T lo, T hi) noexcept {
  if constexpr (is_batch_v<T>) {
    return xsimd::min(hi, xsimd::max(lo, x)); // maxps(lo, x) returns x if x is NaN
  } else {
    T const m = lo > x ? lo : x;
    return hi < m ? hi : m;
  }
}

/// log2(x) in double-word for x > 0 finite (relative error ~2^(7-2p)); for pow.
template <Float T>
PLUME_INLINE dw<T> log2_dw(T x) noexcept {
  using C = math_constants<scalar_t<T>>;
  auto const [e, f] = split_log(x);
  // s = f / (2 + f) in double-word.
  dw<T> const d = fast_two_sum(two<T>(), f);
  T const s_hi = f / d.hi;
  dw<T> const p = two_prod(s_hi, d.hi);
  T const s_lo = (((f - p.hi) - p.lo) - s_hi * d.lo) / d.hi;
  dw<T> const s{s_hi, s_lo};
  // log(1+f) = 2s + s^3 (2/3 + z Q2(z)), z = s^2
  dw<T> const z = dw_mul(s, s);
  dw<T> const s3 = dw_mul(s, z);
  T const q2 = z.hi * detail::horner(z.hi, C::logpow_poly);
  dw<T> const q = fast_two_sum(splat<T>(C::two_thirds_hi), q2 + splat<T>(C::two_thirds_lo));
  dw<T> const tail = dw_mul(s3, q);
  dw<T> const ln1pf = dw_add(dw<T>{two<T>() * s.hi, two<T>() * s.lo}, tail);
  dw<T> const l2 = dw_mul(ln1pf, dw<T>{splat<T>(C::log2e), splat<T>(C::log2e_lo)});
  return dw_add(dw<T>{e, zero<T>()}, l2);
}

/// 2^(h - n + lo) for the integer n nearest h: 1 + r P(r), r = (h - n) + lo (h - n exact).
template <Float T>
PLUME_INLINE T exp2_reduced(T h, T lo, T n) noexcept {
  using C = math_constants<scalar_t<T>>;
  T const r = (h - n) + lo;
  return one<T>() + r * detail::horner(r, C::exp2_poly);
}

/// e^(x - n ln2) for the integer n nearest x log2 e: 1 + (r + r^2 P(r)), r reduced by the
/// two-part ln 2.
template <Float T>
PLUME_INLINE T exp_reduced(T x, T n) noexcept {
  using C = math_constants<scalar_t<T>>;
  T const r = (x - n * splat<T>(C::ln2_hi)) - n * splat<T>(C::ln2_lo);
  return one<T>() + (r + r * r * detail::horner(r, C::exp_poly));
}

/// log(2^e (1 + f)) for |f| < sqrt2 - 1 (fdlibm's summation order).
template <Float T>
PLUME_INLINE T log_core(log_split<T> const& ef) noexcept {
  using C = math_constants<scalar_t<T>>;
  auto const [hfsq, s, R] = log_kernel(ef.f);
  return ef.e * splat<T>(C::ln2_hi) -
         ((hfsq - (s * (hfsq + R) + ef.e * splat<T>(C::ln2_lo))) - ef.f);
}

/// 2^(hi + lo) for |lo| <= ulp(hi); overflow gives inf, underflow 0, NaN stays NaN.
template <Float T>
PLUME_INLINE T exp2_dw(T hi, T lo) noexcept {
  using C = math_constants<scalar_t<T>>;
  // Normal results (|hi| <= exp2_fast_limit) scale through the exponent field; the rest
  // clamp and scale in two steps (same bits where both apply; see exp).
  T const rm = splat<T>(C::round_magic);
  T const t = hi + rm;
  T const n = t - rm;
  T res = scale_pow2_normal(exp2_reduced(hi, lo, n), t);
  auto const fast = plume::abs(hi) <= splat<T>(C::exp2_fast_limit);
  if (!plume::all(fast)) [[unlikely]] {
    T const h = clamp_range(hi, splat<T>(C::exp2_clamp_lo), splat<T>(C::exp2_clamp_hi));
    T const nc = round_small(h);
    res = plume::select(fast, res, scale_pow2(exp2_reduced(h, lo, nc), nc));
  }
  return res;
}

/// Float pow's core, in double (D is double or a double batch): 2^(y log2 a) for a float
/// value a > 0 finite (subnormals included: they are normal doubles) and any float value y,
/// t = y log2 a clamped to +-powf_t_limit (NaN stays NaN). log2 a to ~2^-37 relative
/// (s = f / (2 + f) in double, s Q(s^2)), so t is within ~2^-30 wherever the float result
/// is in range, and 2^t within ~2^-28.5: rounded once to float, within 0.53 ulp.
template <Float D>
PLUME_INLINE D powf_core(D a, D y) noexcept {
  using Cf = math_constants<float>;
  using Cd = math_constants<double>;
  auto const [e, f] = split_log_normal(a);
  D const s = f / (two<D>() + f);
  D t = y * (e + s * detail::horner(s * s, Cf::powf_log2_poly));
  t = clamp_range(t, splat<D>(-Cf::powf_t_limit), splat<D>(Cf::powf_t_limit));
  D const rm = splat<D>(Cd::round_magic);
  D const tt = t + rm;
  D const n = tt - rm; // round(t)
  D const r = t - n;
  return scale_pow2_normal(one<D>() + r * detail::horner(r, Cf::powf_exp2_poly), tt);
}

/// pow's rules for a negative base and its overrides, applied to r = |x|^y: the sign for an
/// odd integer y, NaN for a finite negative x and a non-integer y, and 1 for pow(-1, +-inf),
/// pow(x, +-0) and pow(1, y), even for NaN.
template <Float T>
PLUME_INLINE T pow_signs(T x, T y, T r) noexcept {
  T const ty = plume::trunc(y);
  auto const y_int = ty == y; // true for +-inf and |y| >= 2^p too (even integers)
  // Odd: y/2 (exact) is not an integer. That holds up to 2^p, beyond the 2^(p-1) from which
  // every float is an integer, and is false for +-inf and every |y| >= 2^p.
  T const hy = y * half<T>();
  auto const y_odd = y_int & (plume::trunc(hy) != hy);
  r = plume::select(plume::is_sign_negative(x) & y_odd, -r, r);
  r = plume::select((x < zero<T>()) & plume::is_finite(x) & !y_int, nan<T>(), r);
  r = plume::select((x == neg_one<T>()) & plume::is_infinite(y), one<T>(), r);
  return plume::select((y == zero<T>()) | (x == one<T>()), one<T>(), r);
}

/// pow's special values, for r = 2^(y log2|x|) computed with |x| replaced by 1 where it is 0,
/// inf or NaN (finite_pos false): there log2|x| = -inf or +inf, so |x|^y is inf or 0 by the
/// sign of y log2|x| (y = 0: NaN, which pow_signs replaces by 1); NaN in, NaN out; then
/// pow_signs.
template <Float T>
PLUME_INLINE T pow_specials(T x, T y, T ax, mask_t<T> finite_pos, T r) noexcept {
  T const v = y * plume::select(ax == zero<T>(), neg_infinity<T>(), infinity<T>());
  T const r_inf = plume::select(v > zero<T>(), infinity<T>(),
                                plume::select(v < zero<T>(), zero<T>(), nan<T>()));
  r = plume::select(finite_pos, r, r_inf);
  r = plume::select(plume::is_nan(x) | plume::is_nan(y), x + y, r);
  return pow_signs(x, y, r);
}

/// pow for float lanes: the core in double (two double batches per float batch), rounded
/// once. Lanes with x <= 0, x inf or NaN, or y inf or NaN take pow_specials.
template <Float T>
PLUME_INLINE T pow_float(T x, T y) noexcept {
  T const ax = plume::abs(x);
  auto const finite_pos = (ax > zero<T>()) & (ax < infinity<T>());
  T const a = plume::select(finite_pos, ax, one<T>());
  T r;
  if constexpr (is_batch_v<T>)
    r = narrow(powf_core(widen_lo(a), widen_lo(y)), powf_core(widen_hi(a), widen_hi(y)));
  else
    r = static_cast<T>(powf_core(static_cast<double>(a), static_cast<double>(y)));
  // x > 0 finite and y finite (the usual case): r is the result (y = 0 and x = 1 give 2^0).
  auto const plain = (x > zero<T>()) & (x < infinity<T>()) & plume::is_finite(y);
  if (!plume::all(plain)) [[unlikely]]
    r = plume::select(plain, r, pow_specials(x, y, ax, finite_pos, r));
  return r;
}

} // namespace detail

template <Float T>
PLUME_INLINE T exp(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  // |x| <= exp_fast_limit (the usual case): the result is normal, and 2^n is added to the
  // exponent field directly. Other lanes (overflow, subnormal results, inf, NaN) take the
  // clamped path with its two-step scaling; it gives the same bits on the lanes both cover,
  // so the branch only skips work and no lane depends on another.
  T const rm = splat<T>(C::round_magic);
  T const t = x * splat<T>(C::log2e) + rm;
  T const n = t - rm; // round(x log2 e)
  T res = detail::scale_pow2_normal(detail::exp_reduced(x, n), t);
  auto const fast = plume::abs(x) <= splat<T>(C::exp_fast_limit); // false for NaN
  if (!plume::all(fast)) [[unlikely]] {
    T const xc = detail::clamp_range(x, splat<T>(C::exp_clamp_lo), splat<T>(C::exp_clamp_hi));
    T const nc = detail::round_small(xc * splat<T>(C::log2e));
    res = plume::select(fast, res, detail::scale_pow2(detail::exp_reduced(xc, nc), nc));
  }
  return res;
}

template <Float T>
PLUME_INLINE T exp2(T x) noexcept {
  return detail::exp2_dw(x, zero<T>());
}

template <Float T>
PLUME_INLINE T expm1(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  T const xc = detail::clamp_range(x, splat<T>(C::expm1_clamp_lo), splat<T>(C::exp_clamp_hi));
  T const n = detail::round_small(xc * splat<T>(C::log2e));
  T const r_hi = xc - n * splat<T>(C::ln2_hi); // exact
  T const r_lo = n * splat<T>(C::ln2_lo);
  T const r = r_hi - r_lo;
  T const c = (r_hi - r) - r_lo; // r + c = reduced argument to ~2^-2p
  // expm1(r + c) = r + r^2 P(r) + c (1 + r), as em_hi + em_lo
  T const t = r * r * detail::horner(r, C::exp_poly) + c * (one<T>() + r);
  detail::dw<T> const em = detail::fast_two_sum(r, t);
  // expm1(x) = 2^n (expm1(r) + 1 - 2^-n); 1 - 2^-n is exact while n < p, and ~1 beyond.
  T const one_minus = one<T>() - detail::scale_pow2(one<T>(), -n);
  detail::dw<T> const sum = detail::two_sum(one_minus, em.hi);
  T const v = sum.hi + (sum.lo + em.lo);
  T res = detail::scale_pow2(v, n);
  res = plume::select(n == zero<T>(), em.hi + em.lo, res);
  res = plume::select(x == zero<T>(), x, res); // keeps -0
  return plume::select(plume::is_nan(x), x, res);
}

template <Float T>
PLUME_INLINE T log(T x) noexcept {
  // Positive normal x (the usual case) splits in integer steps; other lanes (0, subnormal,
  // negative, inf, NaN) take the full split and the special values. Both give the same bits
  // where both apply, so the branch only skips work and no lane depends on another.
  T res = detail::log_core(detail::split_log_normal(x));
  auto const normal = (x >= min_positive<T>()) & (x <= max_value<T>());
  if (!plume::all(normal)) [[unlikely]]
    res =
        plume::select(normal, res, detail::log_specials(x, detail::log_core(detail::split_log(x))));
  return res;
}

template <Float T>
PLUME_INLINE T log2(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  auto const [e, f] = detail::split_log(x);
  auto const [hfsq, s, R] = detail::log_kernel(f);
  // log(1+f) = hi + lo with hi's low bits cleared so that hi * ivln2_hi is exact.
  T const hi = detail::bit_and(f - hfsq, detail::bit_pattern<T>(C::hi_half_mask));
  T const lo = ((f - hi) - hfsq) + s * (hfsq + R);
  T const val_hi = hi * splat<T>(C::ivln2_hi);
  T val_lo = (lo + hi) * splat<T>(C::ivln2_lo) + lo * splat<T>(C::ivln2_hi);
  T const w = e + val_hi;
  val_lo = val_lo + ((e - w) + val_hi);
  return detail::log_specials(x, val_lo + w);
}

template <Float T>
PLUME_INLINE T log1p(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  detail::dw<T> const u = detail::two_sum(one<T>(), x); // 1 + x = u.hi + u.lo exactly
  auto const [e, f] = detail::split_log(u.hi);
  auto const [hfsq, s, R] = detail::log_kernel(f);
  T const corr = u.lo / u.hi; // plume::log(u.hi + u.lo) = plume::log(u.hi) + u.lo / u.hi
  T const core =
      e * splat<T>(C::ln2_hi) - ((hfsq - (s * (hfsq + R) + (e * splat<T>(C::ln2_lo) + corr))) - f);
  T res = detail::log_specials(u.hi, core);
  res = plume::select(x == infinity<T>(), x, res);
  res = plume::select(x == zero<T>(), x, res); // keeps -0
  return plume::select(plume::is_nan(x), x, res);
}

template <Float T>
PLUME_INLINE T pow(T x, T y) noexcept {
  if constexpr (std::is_same_v<scalar_t<T>, float>) {
    return detail::pow_float(x, y);
  } else {
    using S = scalar_t<T>;
    using C = detail::math_constants<S>;
    T const ax = plume::abs(x);
    auto const finite_pos = (ax > zero<T>()) & (ax < infinity<T>());
    detail::dw<T> l = detail::log2_dw(plume::select(finite_pos, ax, one<T>()));
    // log2 of 0 and inf as plain values (lo = 0).
    l.hi = plume::select(finite_pos, l.hi, plume::select(ax == zero<T>(), neg_infinity<T>(), ax));
    l.lo = plume::select(finite_pos, l.lo, zero<T>());
    // t = y * log2|x| in double-word wherever the result can be in range, which is where
    // |y log2|x|| < pow_dw_limit however large y is (x near 1: pow(1.00001, 1e7) needs the low
    // word as much as pow(2, 100) does). Beyond, the result over/underflows and y * l.hi alone
    // decides. The exact product cannot overflow there: |log2|x|| >= ~2^-p for x != 1, so
    // |y| < pow_dw_limit 2^p (x = 1 is replaced below).
    auto const tame = plume::abs(y * l.hi) < splat<T>(C::pow_dw_limit);
    detail::dw<T> const yl =
        detail::two_prod(plume::select(tame, y, zero<T>()), plume::select(tame, l.hi, zero<T>()));
    T const t_hi = plume::select(tame, yl.hi, y * l.hi);
    T const t_lo = plume::select(tame, yl.lo + y * l.lo, zero<T>());
    detail::dw<T> const t = detail::fast_two_sum(t_hi, plume::select(tame, t_lo, zero<T>()));
    T r = detail::exp2_dw(t.hi, plume::select(plume::is_finite(t.hi), t.lo, zero<T>()));
    return detail::pow_signs(x, y, r);
  }
}

} // namespace plume

PLUME_MASK_CODE_END
