// The lane-exactness contract for every numerics function: lane i of the wide result equals
// the scalar result on lane i's input, bitwise (NaN = NaN), whatever the other lanes hold.
#include "../common/harness.hpp"
#include "../common/types.hpp"

using namespace plume;

PLUME_WIDE_TEST_CASE("every numerics function is lane-exact", "[numerics][lanes]",
                     test::wide_real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  auto const xs = test::random_values<S>(3000, 42);
  auto const ys = test::random_values<S>(3000, 43);
  auto const small = test::random_values<S>(3000, 44, 3);
#define L1(fn, in)                                                                                 \
  test::check_lane_exact<T>(                                                                       \
      #fn, [](auto v) { return plume::fn(v); }, in)
#define L2(fn)                                                                                     \
  test::check_lane_exact2<T>(                                                                      \
      #fn, [](auto a, auto b) { return plume::fn(a, b); }, xs, ys)
  L1(sin, xs);
  L1(cos, xs);
  L1(tan, xs);
  L1(asin, small);
  L1(acos, small);
  L1(atan, xs);
  L1(exp, small);
  L1(exp2, small);
  L1(expm1, small);
  L1(log, xs);
  L1(log2, xs);
  L1(log1p, xs);
  L1(sin, small);
  L1(tan, small);
  L1(abs, xs);
  L1(signum, xs);
  L1(floor, xs);
  L1(ceil, xs);
  L1(round, xs);
  L1(round_ties_even, xs);
  L1(trunc, xs);
  L1(fract, xs);
  L1(sqrt, xs);
  L1(recip, xs);
  L2(atan2);
  L2(pow);
  L2(min);
  L2(max);
  L2(min_select);
  L2(max_select);
  L2(hypot);
  L2(copysign);
  test::check_lane_exact2<T>(
      "pow small", [](auto a, auto b) { return plume::pow(a, b); }, small, small);
  test::check_lane_exact2<T>(
      "lerp", [](auto a, auto b) { return plume::lerp(a, b, splat<decltype(a)>(0.3)); }, xs, ys);
  test::check_lane_exact2<T>(
      "mul_add", [](auto a, auto b) { return plume::mul_add(a, b, b); }, xs, ys);
  test::check_lane_exact2<T>(
      "clamp", [](auto a, auto b) { return plume::clamp(a, -plume::abs(b), plume::abs(b)); }, xs,
      ys);
#undef L1
#undef L2
}
