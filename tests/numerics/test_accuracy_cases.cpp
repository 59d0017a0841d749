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
