// plume/numerics/trig.hpp - trigonometric functions for every Real element type.
//
//   sin cos tan, sincos (both at once), asin acos atan, atan2(y, x)     radians
//
// Written once over T. sin, cos and tan work on |x| (then restore the sign where the function
// is odd): for |x| <= 8000 (float) or 1e8 (double), a Cody-Waite reduction by pi/2 whose
// first three steps are exact and whose last rounding error is carried as a low word, then
// minimax polynomials on [-pi/4, pi/4]. Lanes beyond that range (and inf/NaN) take a slow
// path - a five-part compensated reduction, and exact Payne-Hanek beyond it, lane by lane by
// the same scalar routine in every width - entered only when some lane needs it and merged
// by select: the value of each lane never depends on its neighbours or on the branch.
// Accuracy (tests/numerics, printed by the accuracy test): every function within 2 ulp of
// the exact result over its whole domain for float and double, most within 1. Exhaustive
// float check (every float with |x| <= 8000, against double libm): sin 0.98 ulp, cos 1.03.
//
// Special values (C99 Annex F): sin/tan/asin/atan keep the sign of zero; sin, cos, tan of
// +-inf are NaN; asin/acos outside [-1, 1] are NaN; atan(+-inf) = +-pi/2; atan2 follows
// Annex F for zeros and infinities (atan2(+-0, -0) = +-pi, atan2(+-inf, -inf) = +-3pi/4, ...);
// NaN in, NaN out. No function loops, traps or reads other lanes.
#pragma once

#include <plume/numerics/detail/coefficients.hpp>
#include <plume/numerics/detail/payne_hanek.hpp>
#include <plume/numerics/detail/poly.hpp>
#include <plume/numerics/functions.hpp>

#include <limits>

PLUME_MASK_CODE_BEGIN

namespace plume {
namespace detail {

/// x = q * pi/2 + (hi + lo), q mod 4 as a float value in {0, 1, 2, 3}.
template <Float T>
struct quadrant_reduction {
  T hi, lo, q;
};

/// The full reduction of any x: a five-part Cody-Waite sum for |x| <= trig_fast_limit,
/// Payne-Hanek beyond. The slow path of reduce_abs_half_pi.
template <Float T>
PLUME_INLINE quadrant_reduction<T> reduce_half_pi(T x) noexcept {
  using S = scalar_t<T>;
  using C = math_constants<S>;
  T const rm = splat<T>(C::round_magic);
  // t = x*2/pi + 1.5*2^m rounds to an integer whose low bits hold q mod 4.
  T const t = x * frac_2_pi<T>() + rm;
  T const q = t - rm;
  T const qm =
      bit_or(bit_and(t, bit_pattern<T>(3)), bit_pattern<T>(C::two_p_bits)) - splat<T>(C::two_p);
  // The first two products and differences are exact (parts of 11/26 bits, Sterbenz); the
  // rest are accumulated as hi + lo so that the reduced argument keeps ~2p bits even when
  // it is not small.
  T r = x - q * splat<T>(C::pio2_parts[0]);
  r = r - q * splat<T>(C::pio2_parts[1]);
  T hi = r, lo = zero<T>();
  for (int k = 2; k < 5; ++k) {
    T const p = q * splat<T>(C::pio2_parts[k]);
    T const s = hi - p;
    lo = lo + ((hi - s) - p); // exact error of hi - p (|hi| >= |p|)
    hi = s;
  }
  T const h2 = hi + lo;
  lo = lo - (h2 - hi);
  hi = h2;
  T qq = qm;
  auto const huge = (plume::abs(x) > splat<T>(C::trig_fast_limit)) & plume::is_finite(x);
  if (plume::any(huge)) [[unlikely]] {
    // Only the lanes that need it; the others keep the values computed above.
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      if constexpr (is_batch_v<T>) {
        if (!plume::lane(huge, i)) continue;
      }
      huge_reduction const h = reduce_half_pi_huge(static_cast<double>(plume::lane(x, i)));
      S const h_hi = static_cast<S>(h.hi);
      S const h_lo = static_cast<S>((h.hi - static_cast<double>(h_hi)) + h.lo);
      if constexpr (is_batch_v<T>) {
        hi = plume::with_lane(hi, i, h_hi);
        lo = plume::with_lane(lo, i, h_lo);
        qq = plume::with_lane(qq, i, static_cast<S>(h.quadrant));
      } else {
        hi = h_hi;
        lo = h_lo;
        qq = static_cast<S>(h.quadrant);
      }
    }
  }
  return {hi, lo, qq};
}

/// a = q * pi/2 + (hi + lo) for a = |x|, with the quadrant q mod 4 in the low two bits of
/// `quadrant`.
template <Float T>
struct abs_reduction {
  T hi, lo;
  bits_t<T> quadrant;
};

/// Reduction of a >= 0 (or NaN). For a <= trig_fast_limit (the usual case): two exact
/// Cody-Waite steps, a third whose rounding error goes to lo (Fast2Sum), and the tail of
/// pi/2 subtracted from lo; the quadrant comes from the bits of the rounding sum. Other
/// lanes (huge, inf, NaN) take reduce_half_pi. The value of each lane depends on that lane
/// alone: the branch only skips work no lane needs.
template <Float T>
PLUME_INLINE abs_reduction<T> reduce_abs_half_pi(T a) noexcept {
  using S = scalar_t<T>;
  using C = math_constants<S>;
  using B = bits_t<T>;
  T const rm = splat<T>(C::round_magic);
  T const t = a * frac_2_pi<T>() + rm;
  T const q = t - rm;
  T const r1 = a - q * splat<T>(C::pio2_parts[0]);  // exact
  T const r2 = r1 - q * splat<T>(C::pio2_parts[1]); // exact
  T const p3 = q * splat<T>(C::pio2_parts[2]);      // exact
  T hi = r2 - p3;
  T lo = ((r2 - hi) - p3) - q * splat<T>(C::pio2_tail);
  B quadrant = plume::to_bits(t);
  auto const fast = a <= splat<T>(C::trig_fast_limit); // false for NaN
  if (!plume::all(fast)) [[unlikely]] {
    auto const full = reduce_half_pi(a);
    hi = plume::select(fast, hi, full.hi);
    lo = plume::select(fast, lo, full.lo);
    quadrant = plume::select(mask_cast<B>(fast), quadrant, plume::to_bits(full.q + rm));
  }
  return {hi, lo, quadrant};
}

/// The lanes whose bit k of b is clear, as a mask of T (two instructions: and, compare).
template <Float T>
PLUME_INLINE mask_t<T> bit_clear(bits_t<T> b, int k) noexcept {
  using B = bits_t<T>;
  using U = scalar_t<B>;
  if constexpr (is_batch_v<T>)
    return mask_cast<T>((b & splat<B>(static_cast<U>(U(1) << k))) == splat<B>(U(0)));
  else
    return ((b >> k) & 1u) == 0;
}

/// Bit k of b, xor the sign bit of x, at the sign bit position (other bits clear), as T.
template <Float T>
PLUME_INLINE T bit_to_sign(bits_t<T> b, int k, T x = zero<T>()) noexcept {
  using B = bits_t<T>;
  using U = scalar_t<B>;
  constexpr int top = 8 * sizeof(U) - 1;
  return from_bits<T>(((b << (top - k)) ^ plume::to_bits(x)) &
                      splat<B>(static_cast<U>(sign_mask_v<T>)));
}

/// sin(hi + lo) for |hi| <= pi/4 + tiny, |lo| <= ulp(hi).
template <Float T>
PLUME_INLINE T sin_kernel(T hi, T lo, T z) noexcept {
  using C = math_constants<scalar_t<T>>;
  T const tail = hi * z * detail::horner(z, C::sin_poly);
  return hi + (tail + lo);
}

/// cos(hi + lo); compensated 1 - z/2 so that the result is within ~0.5 ulp.
template <Float T>
PLUME_INLINE T cos_kernel(T hi, T lo, T z) noexcept {
  using C = math_constants<scalar_t<T>>;
  T const hz = half<T>() * z;
  T const w = one<T>() - hz;
  return w + (((one<T>() - w) - hz) + (z * z * detail::horner(z, C::cos_poly) - hi * lo));
}

/// atan(a + a_lo) for a >= 0 (or NaN), |a_lo| <= ulp(a); branch-free 3-range reduction with the
/// reduced argument carried in double-word and a compensated final sum (<= ~1 ulp).
template <Float T>
PLUME_INLINE T atan_nonneg(T a, T a_lo) noexcept {
  using C = math_constants<scalar_t<T>>;
  auto const big = a > splat<T>(C::tan_3pi_8);
  auto const mid = a > splat<T>(C::tan_pi_8);
  // mid: t = (a - 1)/(a + 1); big: t = -1/a. Numerator and denominator exactly, as hi + lo.
  dw<T> const num =
      two_sum(plume::select(big, -one<T>(), a), plume::select(big, zero<T>(), -one<T>()));
  dw<T> const den = two_sum(a, plume::select(big, zero<T>(), one<T>()));
  T const num_lo = plume::select(big, zero<T>(), num.lo + a_lo);
  T const den_lo = den.lo + a_lo;
  T const tq = num.hi / den.hi;
  dw<T> const pr = two_prod(tq, den.hi);
  // (big: -1/a needs no low word, and Dekker's split of a huge a would overflow)
  T const tq_lo =
      plume::select(big, zero<T>(), (((num.hi - pr.hi) - pr.lo) + num_lo - tq * den_lo) / den.hi);
  auto const reduce = big | mid;
  T const t = plume::select(reduce, tq, a);
  T const t_lo = plume::select(reduce, tq_lo, a_lo);
  T const y_hi =
      plume::select(big, splat<T>(C::pio2_hi), plume::select(mid, splat<T>(C::pio4_hi), zero<T>()));
  T const y_lo =
      plume::select(big, splat<T>(C::pio2_lo), plume::select(mid, splat<T>(C::pio4_lo), zero<T>()));
  T const z = t * t;
  // atan(t + t_lo) = t + t z P(z) + t_lo / (1 + z)
  T const p = t * z * detail::horner(z, C::atan_poly) + t_lo * (one<T>() - z);
  dw<T> const u = fast_two_sum(t, p + y_lo);
  dw<T> const v = two_sum(y_hi, u.hi);
  return v.hi + (v.lo + u.lo);
}

/// atan2(y, x) before y's sign, from ax = |x|, ay = |y| (x for its sign). With n = min and
/// d = max of ax, ay and r = n / d, atan(r) is atan(c) + atan(q) about the pivot c = 0, 1/2
/// or 1 nearest r, q = (r - c) / (1 + r c), so |q| <= 0.36 - one division, of numerator and
/// denominator formed from n and d: q = n / d (r < 0.348), (2n - d) / (2d + n) (r < 0.615),
/// (n - d) / (n + d). The numerators are exact (Sterbenz), so q is within ~2 roundings, and
/// the result k pi/2 +- (atan(c) + atan(q)) is summed as hi + (lo +- atan(q)), hi exact. Safe:
/// max(ax, ay) <= atan2_huge, neither NaN nor both infinite; otherwise (the general path) n
/// and d are scaled by 1/4 in the pivot formulas and both-infinite gives q = 0, c = 1.
template <bool Safe, Float T>
PLUME_INLINE T atan2_abs(T ax, T ay, T x) noexcept {
  using S = scalar_t<T>;
  using C = math_constants<S>;
  auto const steep = ay > ax;
  T const n = plume::min_select(ax, ay), d = plume::max_select(ay, ax); // n <= d
  // Pivot 1 for r > 1/1.625, 1/2 for r > 1/2.875. n * k > d misjudges r only by its rounding
  // (subnormal n: half a unit), which moves a segment's edge by at most ~3%.
  auto seg1 = n * splat<T>(S(1.625)) > d;
  auto seg_half = n * splat<T>(S(2.875)) > d;
  T const m = plume::select(seg1, one<T>(), two<T>());
  T num, den;
  if constexpr (Safe) {
    num = m * n - d;
    den = m * d + n;
  } else {
    auto const inf2 = n == infinity<T>();
    seg1 = seg1 | inf2;
    seg_half = seg_half | inf2;
    T const ns = n * splat<T>(S(0.25)), ds = d * splat<T>(S(0.25));
    num = plume::select(inf2, zero<T>(), m * ns - ds);
    den = plume::select(inf2, one<T>(), m * ds + ns);
  }
  // The least subnormal as the smallest divisor: 0 / 0 (both zero) gives 0, no other q moves.
  T const q = plume::select(seg_half, num, n) /
              plume::max_select(plume::select(seg_half, den, d),
                                splat<T>(std::numeric_limits<S>::denorm_min()));
  T const z = q * q;
  T P;
  if constexpr (std::size(C::atan2_poly) > 6)
    P = detail::estrin(z, C::atan2_poly);
  else
    P = detail::horner(z, C::atan2_poly);
  T const p = q + q * z * P;
  // k pi/2 +- atan(c): k = 1 (steep), 2 (x < 0, incl. -0) or 0; minus when steep xor x < 0.
  T const k_hi = plume::select(steep, splat<T>(C::atan2_pio2_hi),
                               plume::select_sign(x, splat<T>(C::atan2_pi_hi), zero<T>()));
  T const k_lo = plume::select(steep, splat<T>(C::atan2_pio2_lo),
                               plume::select_sign(x, splat<T>(C::atan2_pi_lo), zero<T>()));
  T const c_hi = plume::keep_if(
      seg_half, plume::select(seg1, splat<T>(C::atan2_pio4_hi), splat<T>(C::atan2_half_hi)));
  T const c_lo = plume::keep_if(
      seg_half, plume::select(seg1, splat<T>(C::atan2_pio4_lo), splat<T>(C::atan2_half_lo)));
  T const sign = bit_pattern<T>(sign_mask_v<T>);
  T const minus = bit_xor(bit_and(x, sign), plume::keep_if(steep, sign));
  return (k_hi + bit_xor(c_hi, minus)) + ((k_lo + bit_xor(c_lo, minus)) + bit_xor(p, minus));
}

/// asin's kernel R(u) = z P(z), u = 4z, z <= 1/4 (asin(s) = s + s R), with a short
/// dependency chain: float's five coefficients as (c4 u + c3 u^2) + u^3 (c2 + c1 u + c0 u^2),
/// double's twelve as u times Estrin's scheme.
template <Float T>
PLUME_INLINE T asin_kernel(T u) noexcept {
  using C = math_constants<scalar_t<T>>;
  constexpr auto& c = C::asin_poly;
  if constexpr (std::size(c) == 5) {
    T const u2 = u * u, u3 = u2 * u;
    T const low = plume::mul_add(splat<T>(c[3]), u2, splat<T>(c[4]) * u);
    T const high =
        plume::mul_add(splat<T>(c[0]), u2, plume::mul_add(splat<T>(c[1]), u, splat<T>(c[2])));
    return plume::mul_add(high, u3, low);
  } else {
    return u * estrin(u, c);
  }
}

} // namespace detail

/// sin(x) and cos(x) together, for the cost of about one of them.
template <Float T>
struct sin_cos_result {
  T sin;
  T cos;
};

template <Float T>
PLUME_INLINE sin_cos_result<T> sincos(T x) noexcept {
  // On |x|: cos is even and sin odd, so sin takes the sign of x (sin(-0) = -0).
  T const a = plume::abs(x);
  auto const red = detail::reduce_abs_half_pi(a);
  T const z = red.hi * red.hi;
  T const s = detail::sin_kernel(red.hi, red.lo, z);
  T const c = detail::cos_kernel(red.hi, red.lo, z);
  auto const even = detail::bit_clear<T>(red.quadrant, 0);
  // sin is negative in quadrants 2 and 3 (bit 1 of q) and takes the sign of x; cos is
  // negative in quadrants 1 and 2 (bit 1 of q + 1).
  T const sin_sign = detail::bit_to_sign<T>(red.quadrant, 1, x);
  T const cos_sign = detail::bit_to_sign<T>(
      red.quadrant + splat<bits_t<T>>(static_cast<scalar_t<bits_t<T>>>(1)), 1);
  return {detail::bit_xor(plume::select(even, s, c), sin_sign),
          detail::bit_xor(plume::select(even, c, s), cos_sign)};
}

template <Float T>
PLUME_INLINE T sin(T x) noexcept {
  return plume::sincos(x).sin;
}

template <Float T>
PLUME_INLINE T cos(T x) noexcept {
  return plume::sincos(x).cos;
}

template <Float T>
PLUME_INLINE T tan(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  // tan is odd: evaluated on |x|, then given the sign of x (tan(-0) = -0).
  auto const red = detail::reduce_abs_half_pi(plume::abs(x));
  T const hi = red.hi;
  T const z = hi * hi;
  // float: a polynomial (7 coefficients); double: cephes' rational function (3 + 4
  // coefficients and a division cost less than the 16-coefficient polynomial it replaced:
  // docs/performance.md).
  T small;
  if constexpr (std::is_same_v<scalar_t<T>, double>)
    small = hi * (z * (detail::estrin(z, C::tan_p) / detail::estrin(z, C::tan_q))) + red.lo;
  else
    small = hi * z * detail::estrin(z, C::tan_poly) + red.lo;
  T const t = hi + small;
  T const t_lo = small - (t - hi); // t + t_lo = plume::tan(hi + lo) to ~2^-2p
  // Odd quadrants: -1/tan, with the low word folded in: -1/(t + e) = y + e y^2. (One
  // division for both, -Q / (hi Q + hi z P + lo Q), rounds three times: 1.85 ulp seen,
  // about 2.4 possible.)
  T const y = -plume::recip(t);
  T const cot = y + t_lo * y * y;
  auto const even = detail::bit_clear<T>(red.quadrant, 0);
  return detail::bit_xor(plume::select(even, t, cot),
                         detail::bit_and(x, detail::bit_pattern<T>(detail::sign_mask_v<T>)));
}

template <Float T>
PLUME_INLINE T asin(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  // One path for every lane, as in cephes: u = 4z with z = x^2 (|x| <= 1/2) or (1 - |x|)/2,
  // R = z P(z) (detail::asin_kernel), asin|x| = |x| + |x| R or pi/2 - 2 asin(s), s = sqrt(z).
  // 2s is sqrt(u) exactly, and 2sR = sqrt(u) R.
  T const a = plume::abs(x);
  auto const big = a > half<T>();
  T const a2 = a + a;
  T const u = plume::select(big, two<T>() - a2, a2 * a2); // 2 - 2|x| is exact
  T const R = detail::asin_kernel(u);
  T const sign = detail::bit_and(x, detail::bit_pattern<T>(detail::sign_mask_v<T>));
  if constexpr (!is_batch_v<T>) {
    if (!big) return detail::bit_xor(a + a * R, sign); // select()'s pick, without the sqrt
  }
  // |x| > 1/2: pi/2 - 2s - 2sR as asin_pio2_part + ((asin_one_up - 2s) + (pio2_lo - 2sR)).
  // asin_one_up - 2s is exact for 2s >= 1/2 (|x| <= 7/8) and within 1/4 ulp of the result
  // beyond; the inner sum is at most 0.43, so its rounding is at most 1/4 ulp of the result.
  // What is left: sqrt's rounding (at most 0.58 ulp of the result, where the result is
  // 0.52) and the last sum's. Every float with |x| > 1/2: within 1.32 ulp. No division:
  // fdlibm's split of s into f + c carries sqrt's rounding, for a division. At |x| = 1 the
  // sum is asin_pio2_part + asin_one_up = pio2_hi, pi/2 correctly rounded.
  T const w = plume::select(big, plume::sqrt(u), a);
  T const p = w * R;
  T const big_abs =
      splat<T>(C::asin_pio2_part) + ((splat<T>(C::asin_one_up) - w) + (splat<T>(C::pio2_lo) - p));
  return detail::bit_xor(plume::select(big, big_abs, w + p), sign);
}

template <Float T>
PLUME_INLINE T acos(T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  // asin's kernel and u. |x| <= 1/2: pi/2 - (x + xR); x < -1/2: pi - 2s - 2sR; x > 1/2:
  // 2s + 2sR, with 2s = sqrt(u). The first two are hi - (v + (vR - lo)) with v = x or 2s
  // and hi + lo = pi/2 or pi; the third is v + vR.
  T const a = plume::abs(x);
  auto const big = a > half<T>();
  auto const pos = x > half<T>();
  T const a2 = a + a;
  T const u = plume::select(big, two<T>() - a2, a2 * a2);
  T const R = detail::asin_kernel(u);
  T const hi = plume::select(big, splat<T>(C::pi_hi), splat<T>(C::pio2_hi));
  T const lo =
      plume::select(pos, zero<T>(), plume::select(big, splat<T>(C::pi_lo), splat<T>(C::pio2_lo)));
  if constexpr (!is_batch_v<T>) {
    if (!big) return hi - (x + (x * R - lo)); // what select() below picks, without the sqrt
  }
  T const v = plume::select(big, plume::sqrt(u), x);
  T const t = v + (v * R - lo);
  return plume::select(pos, t, hi - t);
}

template <Float T>
PLUME_INLINE T atan(T x) noexcept {
  return plume::copysign(detail::atan_nonneg(plume::abs(x), zero<T>()), x);
}

template <Float T>
PLUME_INLINE T atan2(T y, T x) noexcept {
  using C = detail::math_constants<scalar_t<T>>;
  T const ax = plume::abs(x), ay = plume::abs(y);
  T theta = detail::atan2_abs<true>(ax, ay, x);
  // Lanes with a huge, infinite or NaN argument (ax + ay is NaN or over atan2_huge) take the
  // general path, merged by select; the other lanes keep the first result whether or not it
  // runs, so no lane depends on another.
  auto const tame = ax + ay <= splat<T>(C::atan2_huge);
  if (!plume::all(tame)) [[unlikely]] {
    T const general = detail::atan2_abs<false>(ax, ay, x);
    theta = plume::select(tame, theta,
                          plume::select(plume::is_nan(x) | plume::is_nan(y), x + y, general));
  }
  // theta >= 0 (or a NaN): y's sign bit gives the lower half-plane, +-0 included.
  return detail::bit_or(theta, detail::bit_and(y, detail::bit_pattern<T>(detail::sign_mask_v<T>)));
}

} // namespace plume

PLUME_MASK_CODE_END
