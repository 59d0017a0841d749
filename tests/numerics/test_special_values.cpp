// Special values of the transcendental functions (C99 Annex F), on every element type.
#include "../common/functors.hpp"
#include "../common/harness.hpp"
#include "../common/types.hpp"

using namespace plume;

namespace {
template <class T, class F>
void expect1(char const* name, F f, scalar_t<T> x, scalar_t<T> want) {
  auto const out = to_array(f(splat<T>(x)));
  INFO(name << "(" << x << ") = " << out[0] << ", expected " << want);
  for (auto o : out)
    CHECK(test::same_bits(o, want));
}
template <class T, class F>
void expect2(char const* name, F f, scalar_t<T> x, scalar_t<T> y, scalar_t<T> want) {
  auto const out = to_array(f(splat<T>(x), splat<T>(y)));
  INFO(name << "(" << x << ", " << y << ") = " << out[0] << ", expected " << want);
  for (auto o : out)
    CHECK(test::same_bits(o, want));
}
} // namespace

TEMPLATE_LIST_TEST_CASE("special values of the transcendental functions", "[numerics][special]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  S const inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
  S const pi = std::numbers::pi_v<S>, pio2 = pi / 2, pio4 = pi / 4;
#define F1(name)                                                                                   \
  test::fn::name {}
#define F2(name)                                                                                   \
  test::fn::name {}
  for (S z : {S(0), S(-0.0)}) {
    expect1<T>("sin", F1(sin), z, z);
    expect1<T>("tan", F1(tan), z, z);
    expect1<T>("asin", F1(asin), z, z);
    expect1<T>("atan", F1(atan), z, z);
    expect1<T>("expm1", F1(expm1), z, z);
    expect1<T>("log1p", F1(log1p), z, z);
    expect1<T>("cos", F1(cos), z, S(1));
    expect1<T>("exp", F1(exp), z, S(1));
    expect1<T>("exp2", F1(exp2), z, S(1));
    expect1<T>("log", F1(log), z, -inf);
    expect1<T>("log2", F1(log2), z, -inf);
  }
  for (S v : {inf, -inf, nan}) {
    expect1<T>("sin", F1(sin), v, nan);
    expect1<T>("cos", F1(cos), v, nan);
    expect1<T>("tan", F1(tan), v, nan);
  }
  expect1<T>("asin", F1(asin), S(1.5), nan);
  expect1<T>("acos", F1(acos), S(-1.5), nan);
  expect1<T>("asin", F1(asin), S(1), pio2);
  expect1<T>("asin", F1(asin), S(-1), -pio2);
  expect1<T>("acos", F1(acos), S(1), S(0));
  expect1<T>("acos", F1(acos), S(-1), pi);
  expect1<T>("atan", F1(atan), inf, pio2);
  expect1<T>("atan", F1(atan), -inf, -pio2);
  expect1<T>("atan", F1(atan), S(1), pio4);
  expect1<T>("exp", F1(exp), -inf, S(0));
  expect1<T>("exp", F1(exp), inf, inf);
  expect1<T>("exp", F1(exp), S(1000), inf);
  expect1<T>("exp", F1(exp), S(-1000), S(0));
  expect1<T>("exp", F1(exp), nan, nan);
  expect1<T>("exp2", F1(exp2), S(10), S(1024));
  expect1<T>("exp2", F1(exp2), S(-3), S(0.125));
  expect1<T>("exp2", F1(exp2), -inf, S(0));
  expect1<T>("exp2", F1(exp2), S(2000), inf);
  expect1<T>("expm1", F1(expm1), -inf, S(-1));
  expect1<T>("expm1", F1(expm1), inf, inf);
  expect1<T>("expm1", F1(expm1), S(-100), S(-1));
  expect1<T>("log", F1(log), S(1), S(0));
  expect1<T>("log", F1(log), S(-1), nan);
  expect1<T>("log", F1(log), inf, inf);
  expect1<T>("log", F1(log), -inf, nan);
  expect1<T>("log2", F1(log2), S(8), S(3));
  expect1<T>("log2", F1(log2), S(0.25), S(-2));
  expect1<T>("log2", F1(log2), std::numeric_limits<S>::denorm_min(),
             S(std::numeric_limits<S>::min_exponent - std::numeric_limits<S>::digits));
  expect1<T>("log1p", F1(log1p), S(-1), -inf);
  expect1<T>("log1p", F1(log1p), S(-2), nan);
  expect1<T>("log1p", F1(log1p), inf, inf);
  // atan2, Annex F
  expect2<T>("atan2", F2(atan2), S(0), S(-0.0), pi);
  expect2<T>("atan2", F2(atan2), S(-0.0), S(-0.0), -pi);
  expect2<T>("atan2", F2(atan2), S(0), S(0), S(0));
  expect2<T>("atan2", F2(atan2), S(-0.0), S(0), S(-0.0));
  expect2<T>("atan2", F2(atan2), S(0), S(-1), pi);
  expect2<T>("atan2", F2(atan2), S(-0.0), S(-1), -pi);
  expect2<T>("atan2", F2(atan2), S(1), S(0), pio2);
  expect2<T>("atan2", F2(atan2), S(-1), S(-0.0), -pio2);
  expect2<T>("atan2", F2(atan2), S(1), -inf, pi);
  expect2<T>("atan2", F2(atan2), S(-1), inf, S(-0.0));
  expect2<T>("atan2", F2(atan2), inf, S(5), pio2);
  expect2<T>("atan2", F2(atan2), inf, -inf, S(3 * std::numbers::pi_v<long double> / 4));
  expect2<T>("atan2", F2(atan2), -inf, inf, -pio4);
  expect2<T>("atan2", F2(atan2), nan, S(1), nan);
  expect2<T>("atan2", F2(atan2), S(1), nan, nan);
  // pow, Annex F
  expect2<T>("pow", F2(pow), nan, S(0), S(1));
  expect2<T>("pow", F2(pow), S(1), nan, S(1));
  expect2<T>("pow", F2(pow), S(-1), inf, S(1));
  expect2<T>("pow", F2(pow), S(-1), -inf, S(1));
  expect2<T>("pow", F2(pow), S(-2), S(0.5), nan);
  expect2<T>("pow", F2(pow), S(-2), S(3), S(-8));
  expect2<T>("pow", F2(pow), S(-2), S(-2), S(0.25));
  expect2<T>("pow", F2(pow), S(-0.0), S(-3), -inf);
  expect2<T>("pow", F2(pow), S(0), S(-3), inf);
  expect2<T>("pow", F2(pow), S(-0.0), S(-2), inf);
  expect2<T>("pow", F2(pow), S(-0.0), S(3), S(-0.0));
  expect2<T>("pow", F2(pow), S(-0.0), S(2), S(0));
  expect2<T>("pow", F2(pow), S(0.5), -inf, inf);
  expect2<T>("pow", F2(pow), S(2), -inf, S(0));
  expect2<T>("pow", F2(pow), S(0.5), inf, S(0));
  expect2<T>("pow", F2(pow), S(2), inf, inf);
  expect2<T>("pow", F2(pow), -inf, S(-3), S(-0.0));
  expect2<T>("pow", F2(pow), -inf, S(-2), S(0));
  expect2<T>("pow", F2(pow), -inf, S(3), -inf);
  expect2<T>("pow", F2(pow), -inf, S(2), inf);
  expect2<T>("pow", F2(pow), inf, S(-1), S(0));
  expect2<T>("pow", F2(pow), inf, S(0.5), inf);
  expect2<T>("pow", F2(pow), S(2), S(10), S(1024));
  expect2<T>("pow", F2(pow), S(9), S(0.5), S(3));
  expect2<T>("pow", F2(pow), S(2), S(5000), inf);
  expect2<T>("pow", F2(pow), S(2), S(-5000), S(0));
  expect2<T>("pow", F2(pow), S(2), S(1e30), inf);
  expect2<T>("pow", F2(pow), S(-0.5), S(1e30), S(0));
  // sincos gives exactly what sin and cos give
  for (S x : test::random_values<S>(500, 21)) {
    auto const sc = plume::sincos(splat<T>(x));
    CHECK(test::same_bits(lane(sc.sin, 0), lane(plume::sin(splat<T>(x)), 0)));
    CHECK(test::same_bits(lane(sc.cos, 0), lane(plume::cos(splat<T>(x)), 0)));
  }
#undef F1
#undef F2
}
