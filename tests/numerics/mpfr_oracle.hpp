// The accuracy tests' oracle: MPFR, evaluated on the exact input at 64 bits and rounded once
// to long double (64-bit significand, wide exponent range). So the reference is within 2^-64
// of the exact value relative, 2^-11 ulp of a double and 2^-40 ulp of a float, everywhere:
// also where long double libm is not (huge trigonometric arguments, pow near 1 with huge y,
// tiny quotients in atan2) and beyond double's exponent range (results that overflow or
// underflow are seen as such, not as a libm's inf or 0).
#pragma once

#include <mpfr.h>

namespace plume::test {

class mpfr_oracle {
public:
  mpfr_oracle() { mpfr_inits2(64, a_, b_, r_, static_cast<mpfr_ptr>(nullptr)); }
  ~mpfr_oracle() { mpfr_clears(a_, b_, r_, static_cast<mpfr_ptr>(nullptr)); }
  mpfr_oracle(mpfr_oracle const&) = delete;
  mpfr_oracle& operator=(mpfr_oracle const&) = delete;

  using unary_fn = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_rnd_t);
  using binary_fn = int (*)(mpfr_ptr, mpfr_srcptr, mpfr_srcptr, mpfr_rnd_t);

  /// f(x), x exact (every float and double is a long double).
  long double operator()(unary_fn f, long double x) {
    mpfr_set_ld(a_, x, MPFR_RNDN);
    f(r_, a_, MPFR_RNDN);
    return mpfr_get_ld(r_, MPFR_RNDN);
  }
  /// f(x, y) in MPFR's argument order (mpfr_atan2(r, y, x), mpfr_pow(r, x, y)).
  long double operator()(binary_fn f, long double x, long double y) {
    mpfr_set_ld(a_, x, MPFR_RNDN);
    mpfr_set_ld(b_, y, MPFR_RNDN);
    f(r_, a_, b_, MPFR_RNDN);
    return mpfr_get_ld(r_, MPFR_RNDN);
  }
  /// pi * num / den to 64 bits.
  long double pi_times(long num, long den) {
    mpfr_const_pi(r_, MPFR_RNDN);
    mpfr_mul_si(r_, r_, num, MPFR_RNDN);
    mpfr_div_si(r_, r_, den, MPFR_RNDN);
    return mpfr_get_ld(r_, MPFR_RNDN);
  }

private:
  mpfr_t a_, b_, r_;
};

} // namespace plume::test
