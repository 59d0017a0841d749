// plume/numerics/constants.hpp - constants for every element type, one spelling.
//
// Every constant is a function template `name<T>()` that returns the value in every lane
// of T, for scalars and batches alike (xsimd batches have no constexpr constructors, so a
// variable template could not serve both). Values are the nearest representable ones.
//
//   zero one neg_one two half                       any Num (neg_one: Signed)
//   min_value max_value                             lowest and highest finite value
//   min_positive                                    smallest positive normal (Float)
//   epsilon infinity neg_infinity nan               Float
//   pi tau e frac_pi_2 frac_pi_3 frac_pi_4 frac_pi_6 frac_pi_8 frac_1_pi frac_2_pi
//   frac_2_sqrt_pi sqrt2 frac_1_sqrt2 ln2 ln10 log2_e log10_e log2_10 log10_2     Real
#pragma once

#include <plume/numerics/concepts.hpp>

#include <limits>
#include <numbers>

namespace plume {

#define PLUME_CONSTANT(name, concept_, value)                                                      \
  template <concept_ T>                                                                            \
  PLUME_INLINE constexpr T name() noexcept {                                                       \
    using S = scalar_t<T>;                                                                         \
    return splat<T>(value);                                                                        \
  }

PLUME_CONSTANT(zero, Num, S(0))
PLUME_CONSTANT(one, Num, S(1))
PLUME_CONSTANT(two, Num, S(2))
PLUME_CONSTANT(neg_one, Signed, S(-1))
PLUME_CONSTANT(half, Real, S(0.5))
PLUME_CONSTANT(min_value, Num, std::numeric_limits<S>::lowest())
PLUME_CONSTANT(max_value, Num, std::numeric_limits<S>::max())
PLUME_CONSTANT(min_positive, Float, std::numeric_limits<S>::min())
PLUME_CONSTANT(epsilon, Float, std::numeric_limits<S>::epsilon())
PLUME_CONSTANT(infinity, Float, std::numeric_limits<S>::infinity())
PLUME_CONSTANT(neg_infinity, Float, -std::numeric_limits<S>::infinity())
PLUME_CONSTANT(nan, Float, std::numeric_limits<S>::quiet_NaN())
PLUME_CONSTANT(pi, Real, std::numbers::pi_v<S>)
PLUME_CONSTANT(tau, Real, S(2) * std::numbers::pi_v<S>)
PLUME_CONSTANT(e, Real, std::numbers::e_v<S>)
PLUME_CONSTANT(frac_pi_2, Real, std::numbers::pi_v<S> / S(2))
PLUME_CONSTANT(frac_pi_3, Real, static_cast<S>(std::numbers::pi_v<long double> / 3))
PLUME_CONSTANT(frac_pi_4, Real, std::numbers::pi_v<S> / S(4))
PLUME_CONSTANT(frac_pi_6, Real, static_cast<S>(std::numbers::pi_v<long double> / 6))
PLUME_CONSTANT(frac_pi_8, Real, std::numbers::pi_v<S> / S(8))
PLUME_CONSTANT(frac_1_pi, Real, std::numbers::inv_pi_v<S>)
PLUME_CONSTANT(frac_2_pi, Real, static_cast<S>(2 * std::numbers::inv_pi_v<long double>))
PLUME_CONSTANT(frac_2_sqrt_pi, Real, static_cast<S>(2 * std::numbers::inv_sqrtpi_v<long double>))
PLUME_CONSTANT(sqrt2, Real, std::numbers::sqrt2_v<S>)
PLUME_CONSTANT(frac_1_sqrt2, Real, static_cast<S>(1 / std::numbers::sqrt2_v<long double>))
PLUME_CONSTANT(ln2, Real, std::numbers::ln2_v<S>)
PLUME_CONSTANT(ln10, Real, std::numbers::ln10_v<S>)
PLUME_CONSTANT(log2_e, Real, std::numbers::log2e_v<S>)
PLUME_CONSTANT(log10_e, Real, std::numbers::log10e_v<S>)
PLUME_CONSTANT(log2_10, Real,
               static_cast<S>(1 / std::numbers::log10e_v<long double> /
                              std::numbers::ln2_v<long double>))
PLUME_CONSTANT(log10_2, Real,
               static_cast<S>(std::numbers::ln2_v<long double> / std::numbers::ln10_v<long double>))
#undef PLUME_CONSTANT

} // namespace plume
