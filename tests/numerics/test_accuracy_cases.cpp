// Inputs that once broke the 2-ulp bound, each checked against MPFR (mpfr_oracle.hpp) on
// its own: they stay fixed whatever the sweeps of test_accuracy.cpp happen to sample.
#include "../common/harness.hpp"
#include "mpfr_oracle.hpp"

#include <plume/numerics/exp_log.hpp>
#include <plume/numerics/trig.hpp>

#include <cstdio>

using namespace plume;

namespace {

template <class S>
void check_case(char const* fn, S x, S y, S got, long double want) {
  long double const err = test::ulp_error(got, want);
  std::printf("  %-5s %-6s (%a, %a) = %a, exact %La: %.3Lf ulp\n", fn,
              sizeof(S) == 4 ? "float" : "double", double(x), double(y), double(got), want, err);
  INFO(fn << "(" << x << ", " << y << ") = " << got << ", exact " << double(want) << ": "
          << double(err) << " ulp");
  CHECK(err <= 2.0L);
}

template <class S>
void pow_case(S x, S y) {
  test::mpfr_oracle mp;
  check_case("pow", x, y, plume::pow(x, y), mp(mpfr_pow, x, y));
}

template <class S>
void atan2_case(S y, S x) {
  test::mpfr_oracle mp;
  check_case("atan2", y, x, plume::atan2(y, x), mp(mpfr_atan2, y, x));
}

} // namespace

TEST_CASE("pow near 1 with a huge exponent and a result in range", "[numerics][accuracy]") {
  // Once the low word of y log2|x| was dropped for |y| >= 1e6: 50 ulp, 44 ulp and 87 ulp.
  pow_case(1.00002f, 4e6f);
  pow_case(1.00002f, 999999.0f);
  pow_case(1.00001, 1e7);
  pow_case(1.000000001, 3e11);
  pow_case(1.00002f, -4e6f);
  pow_case(0.99999, 5e7);
}

TEST_CASE("pow of a negative base to an odd integer in [2^(p-1), 2^p)", "[numerics][accuracy]") {
  // Such y were taken for even (every float from 2^(p-1) up is an integer, but not every
  // one is even): the result had the wrong sign.
  pow_case(-0x1.ffff8p-1f, -9081007.0f);
  pow_case(-0x1.8p-148f, -9343241.0f);
  pow_case(-1.0000001f, 8388609.0f);
  pow_case(-0x1.fffffffffffffp-1, 4503599627370497.0);
  pow_case(-1.5, 6755399441055745.0);
}

TEST_CASE("atan2 of a tiny numerator over a moderate denominator", "[numerics][accuracy]") {
  // The exact product behind the quotient's low word underflowed: 4,620 ulp, 571 ulp and
  // 1.2e7 ulp.
  atan2_case(0x1.77p-138f, 0x1.c5f2e8p-13f);
  atan2_case(3.1415926e-41f, 3.3333333e-9f);
  atan2_case(3.14159265e-315, 7.7777777777777e-20);
  atan2_case(-0x1.77p-138f, 0x1.c5f2e8p-13f);
  atan2_case(0x1.5p-1030, 0x1.3p-9);
}

TEST_CASE("atan2 of two subnormals near a pivot edge", "[numerics][accuracy]") {
  // A first draft of the one-division atan2 chose its segment from n > 0.34375 d: for
  // subnormal d the product rounds to a whole unit of 2^-149, the ratio 1/2 fell to the
  // polynomial's segment far outside its range (312 ulp) and 7/19 just outside (2.04 ulp).
  atan2_case(0x1p-149f, 0x1p-148f);
  atan2_case(0x7p-149f, 0x13p-149f);
  atan2_case(0x5p-149f, 0xep-149f);
  atan2_case(0x1p-1074, 0x1p-1073);
  atan2_case(0x7p-1074, 0x13p-1074);
  atan2_case(-0x1p-149f, -0x3p-149f);
}
