// plume/numerics/hypot.hpp - hypot(x, y) = sqrt(x^2 + y^2), for every Real T.
//
// No overflow or underflow of the squares: both arguments are scaled by the power of two
// of the larger one (exact), and the result is scaled back. The square root of the rounded
// sum of squares is then corrected once with the exact residual (x^2 + y^2 - h^2, from
// Dekker products), as in C. Borges, "An Improved Algorithm for hypot(a, b)" (2019), so
// the result is within 1 ulp (measured: see the tests; nearly always correctly rounded).
// hypot(+-inf, anything) = +inf, also with NaN (IEEE 754 / C); otherwise NaN if either
// argument is NaN. hypot(0, 0) = +0. Symmetric in its arguments and in their signs.
#pragma once

#include <plume/numerics/detail/poly.hpp>
#include <plume/numerics/functions.hpp>

PLUME_MASK_CODE_BEGIN

namespace plume {

template <Float T>
PLUME_INLINE T hypot(T x, T y) noexcept {
  using S = scalar_t<T>;
  T const ax = plume::abs(x), ay = plume::abs(y);
  T const big = plume::max(ax, ay);
  std::uint64_t const exp_mask = sizeof(S) == 4 ? 0x7f800000ull : 0x7ff0000000000000ull;
  // The power of two at or below the larger argument (at least the smallest normal), and
  // its reciprocal (also a power of two, so both scalings are exact).
  T const unit =
      plume::max(detail::bit_and(big, detail::bit_pattern<T>(exp_mask)), min_positive<T>());
  T const s = plume::recip(unit);
  T const xs = ax * s, ys = ay * s; // the larger is in [1, 2)
  T const h = plume::sqrt(xs * xs + ys * ys);
  // One Newton step on h^2 = xs^2 + ys^2 with the residual computed from exact products.
  auto const px = detail::two_prod(xs, xs), py = detail::two_prod(ys, ys),
             ph = detail::two_prod(h, h);
  T const r = ((ph.hi - px.hi) - py.hi) + ((ph.lo - px.lo) - py.lo);
  T const corrected = h - (r * half<T>()) / plume::select(h > zero<T>(), h, one<T>());
  T const out = corrected * unit;
  return plume::select(plume::is_infinite(ax) | plume::is_infinite(ay), infinity<T>(), out);
}

} // namespace plume

PLUME_MASK_CODE_END
