// Per-element functions: each against an independent oracle (the C library on scalars) and
// its documented rule for NaN, signed zeros and infinities, on every element type.
#include "../common/harness.hpp"
#include "../common/types.hpp"

#include <plume/numerics/approx.hpp>
#include <plume/numerics/bits.hpp>
#include <plume/numerics/detail/coefficients.hpp>
#include <plume/numerics/detail/poly.hpp>
#include <plume/numerics/functions.hpp>
#include <plume/numerics/hypot.hpp>

using namespace plume;

namespace {
// Applies f to a T holding x in every lane and checks every lane equals want (bitwise).
template <class T, class F>
void expect_all_lanes(F f, scalar_t<T> x, scalar_t<T> want, char const* what) {
  auto const out = to_array(f(splat<T>(x)));
  for (auto o : out) {
    INFO(what << "(" << x << ") = " << o << ", expected " << want);
    CHECK(test::same_bits(o, want));
  }
}
template <class T, class F>
void expect_all_lanes2(F f, scalar_t<T> x, scalar_t<T> y, scalar_t<T> want, char const* what) {
  auto const out = to_array(f(splat<T>(x), splat<T>(y)));
  for (auto o : out) {
    INFO(what << "(" << x << ", " << y << ") = " << o << ", expected " << want);
    CHECK(test::same_bits(o, want));
  }
}
} // namespace

TEMPLATE_LIST_TEST_CASE("rounding and sign functions match the C library bit for bit",
                        "[numerics][functions]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  auto values = test::random_values<S>(4000, 11, 9);
  auto const adv = test::adversarial<S>();
  values.insert(values.end(), adv.begin(), adv.end());
  for (S v : {S(0.49999997), S(-0.49999997), S(0.5), S(1.5), S(2.5), S(-2.5), S(-0.3), S(8388607.5),
              S(4503599627370495.5)})
    values.push_back(v);
  for (S x : values) {
    expect_all_lanes<T>([](auto v) { return plume::floor(v); }, x, std::floor(x), "floor");
    expect_all_lanes<T>([](auto v) { return plume::ceil(v); }, x, std::ceil(x), "ceil");
    expect_all_lanes<T>([](auto v) { return plume::trunc(v); }, x, std::trunc(x), "trunc");
    expect_all_lanes<T>([](auto v) { return plume::round(v); }, x, std::round(x), "round");
    expect_all_lanes<T>([](auto v) { return plume::round_ties_even(v); }, x, std::nearbyint(x),
                        "round_ties_even");
    expect_all_lanes<T>([](auto v) { return plume::abs(v); }, x, std::fabs(x), "abs");
    expect_all_lanes<T>([](auto v) { return plume::sqrt(v); }, x, std::sqrt(x), "sqrt");
    expect_all_lanes<T>([](auto v) { return plume::fract(v); }, x, x - std::trunc(x), "fract");
    expect_all_lanes<T>([](auto v) { return plume::recip(v); }, x, S(1) / x, "recip");
    S const sg = std::isnan(x) ? x : std::copysign(S(1), x);
    expect_all_lanes<T>([](auto v) { return plume::signum(v); }, x, sg, "signum");
    expect_all_lanes<T>([](auto v) { return plume::copysign(splat<decltype(v)>(3), v); }, x,
                        std::copysign(S(3), x), "copysign");
    CHECK(plume::bitmask(plume::is_nan(splat<T>(x))) ==
          (std::isnan(x) ? (std::uint64_t(1) << lanes_v<T>)-1 : 0u));
    CHECK(plume::all(plume::is_finite(splat<T>(x))) == std::isfinite(x));
    CHECK(plume::all(plume::is_infinite(splat<T>(x))) == std::isinf(x));
    CHECK(plume::all(plume::is_sign_negative(splat<T>(x))) == std::signbit(x));
    CHECK(test::same_bits(lane(from_bits<T>(to_bits(splat<T>(x))), 0), x));
  }
}

TEMPLATE_LIST_TEST_CASE("min and max: IEEE 754-2019 minimum/maximum in every path",
                        "[numerics][functions]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  S const nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  auto mn = [](auto a, auto b) { return plume::min(a, b); };
  auto mx = [](auto a, auto b) { return plume::max(a, b); };
  expect_all_lanes2<T>(mn, S(1), S(2), S(1), "min");
  expect_all_lanes2<T>(mn, S(2), S(1), S(1), "min");
  expect_all_lanes2<T>(mx, S(1), S(2), S(2), "max");
  expect_all_lanes2<T>(mn, S(-0.0), S(0), S(-0.0), "min");
  expect_all_lanes2<T>(mn, S(0), S(-0.0), S(-0.0), "min");
  expect_all_lanes2<T>(mx, S(-0.0), S(0), S(0), "max");
  expect_all_lanes2<T>(mx, S(0), S(-0.0), S(0), "max");
  expect_all_lanes2<T>(mx, S(-0.0), S(-0.0), S(-0.0), "max");
  for (S v : {S(1), -inf, inf, S(0)}) {
    expect_all_lanes2<T>(mn, nan, v, nan, "min");
    expect_all_lanes2<T>(mn, v, nan, nan, "min");
    expect_all_lanes2<T>(mx, nan, v, nan, "max");
    expect_all_lanes2<T>(mx, v, nan, nan, "max");
  }
  expect_all_lanes2<T>(mn, -inf, S(3), -inf, "min");
  expect_all_lanes2<T>(mx, -inf, inf, inf, "max");
  auto cl = [](auto x) {
    using V = decltype(x);
    return plume::clamp(x, splat<V>(-1), splat<V>(1));
  };
  expect_all_lanes<T>(cl, S(5), S(1), "clamp");
  expect_all_lanes<T>(cl, S(-5), S(-1), "clamp");
  expect_all_lanes<T>(cl, S(0.25), S(0.25), "clamp");
  expect_all_lanes<T>(cl, nan, nan, "clamp");
  // lo > hi gives hi
  expect_all_lanes<T>(
      [](auto x) {
        using V = decltype(x);
        return plume::clamp(x, splat<V>(2), splat<V>(1));
      },
      S(0), S(1), "clamp");
}

TEMPLATE_LIST_TEST_CASE("min_select and max_select are the selects they name, NaN and zeros too",
                        "[numerics][functions]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  S const nan = std::numeric_limits<S>::quiet_NaN(), inf = std::numeric_limits<S>::infinity();
  auto mn = [](auto a, auto b) { return plume::min_select(a, b); };
  auto mx = [](auto a, auto b) { return plume::max_select(a, b); };
  // The second argument on unordered or equal pairs: order matters, unlike min/max.
  expect_all_lanes2<T>(mn, S(1), S(2), S(1), "min_select");
  expect_all_lanes2<T>(mn, S(2), S(1), S(1), "min_select");
  expect_all_lanes2<T>(mn, S(-0.0), S(0), S(0), "min_select");
  expect_all_lanes2<T>(mn, S(0), S(-0.0), S(-0.0), "min_select");
  expect_all_lanes2<T>(mx, S(-0.0), S(0), S(0), "max_select");
  expect_all_lanes2<T>(mx, S(0), S(-0.0), S(-0.0), "max_select");
  expect_all_lanes2<T>(mn, nan, S(1), S(1), "min_select");
  expect_all_lanes2<T>(mn, S(1), nan, nan, "min_select");
  expect_all_lanes2<T>(mx, nan, -inf, -inf, "max_select");
  expect_all_lanes2<T>(mx, inf, nan, nan, "max_select");
  expect_all_lanes2<T>(mx, -inf, inf, inf, "max_select");
  auto cl = [](auto x) {
    using V = decltype(x);
    return plume::clamp_select(x, splat<V>(-1), splat<V>(1));
  };
  expect_all_lanes<T>(cl, S(5), S(1), "clamp_select");
  expect_all_lanes<T>(cl, S(-0.5), S(-0.5), "clamp_select");
  expect_all_lanes<T>(cl, nan, S(-1), "clamp_select");
}

TEMPLATE_LIST_TEST_CASE("mul_add, lerp and hypot", "[numerics][functions]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  // mul_add is unfused in deterministic builds: 1 + e and 1 - e multiply to 1 - e^2, whose
  // e^2 is lost when rounded before the add and kept when fused.
  S const eps = std::numeric_limits<S>::epsilon();
  T const r = plume::mul_add(splat<T>(1 + eps), splat<T>(1 - eps), splat<T>(-1));
  S const want = plume::fused_mul_add ? -eps * eps : S(0);
  CHECK(test::same_bits(lane(r, 0), want));
  CHECK(lane(plume::lerp(splat<T>(2), splat<T>(6), splat<T>(0.25)), 0) == S(3));
  CHECK(lane(plume::lerp(splat<T>(2), splat<T>(6), splat<T>(0)), 0) == S(2));
  S const inf = std::numeric_limits<S>::infinity(), nan = std::numeric_limits<S>::quiet_NaN();
  auto hy = [](auto a, auto b) { return plume::hypot(a, b); };
  expect_all_lanes2<T>(hy, S(3), S(4), S(5), "hypot");
  expect_all_lanes2<T>(hy, S(-3), S(0), S(3), "hypot");
  expect_all_lanes2<T>(hy, S(0), S(-0.0), S(0), "hypot");
  expect_all_lanes2<T>(hy, inf, nan, inf, "hypot");
  expect_all_lanes2<T>(hy, nan, -inf, inf, "hypot");
  expect_all_lanes2<T>(hy, nan, S(1), nan, "hypot");
  // No overflow or underflow of the squares.
  S const big = std::numeric_limits<S>::max() / 2;
  CHECK(lane(plume::hypot(splat<T>(big), splat<T>(big)), 0) ==
        Approx(big * std::sqrt(2.0)).epsilon(1e-6));
  S const tiny = std::numeric_limits<S>::denorm_min() * 3;
  CHECK(lane(plume::hypot(splat<T>(tiny), splat<T>(tiny * 4 / 3)), 0) > 0);
  // Accuracy against long double on random pairs.
  test::ulp_report rep;
  auto const xs = test::random_values<S>(20000, 5), ys = test::random_values<S>(20000, 6);
  for (std::size_t i = 0; i < xs.size(); ++i) {
    long double const want_h =
        std::hypot(static_cast<long double>(xs[i]), static_cast<long double>(ys[i]));
    rep.add(test::ulp_error(lane(plume::hypot(splat<T>(xs[i]), splat<T>(ys[i])), 0), want_h), xs[i],
            ys[i]);
  }
  INFO("hypot max error " << double(rep.max_ulp) << " ulp at (" << double(rep.at_x) << ", "
                          << double(rep.at_y) << ")");
  CHECK(rep.max_ulp <= 1.0L);
}

TEMPLATE_LIST_TEST_CASE("approximate reciprocal and rsqrt meet their bound", "[numerics][approx]",
                        test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  for (S x : test::random_values<S>(2000, 3, 30)) {
    S const ax = std::fabs(x);
    if (ax < S(1e-30) || ax > S(1e30)) continue;
    double const r = double(lane(plume::recip_approx(splat<T>(x)), 0));
    CHECK(std::fabs(r * double(x) - 1) <= 1.5 / 4096);
    double const q = double(lane(plume::rsqrt_approx(splat<T>(ax)), 0));
    CHECK(std::fabs(q * std::sqrt(double(ax)) - 1) <= 1.5 / 4096);
  }
  CHECK(std::isinf(lane(plume::recip_approx(zero<T>()), 0)));
  CHECK(std::isnan(lane(plume::rsqrt_approx(splat<T>(-1)), 0)));
}

TEMPLATE_LIST_TEST_CASE("double-word helpers are exact", "[numerics][detail]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  auto const xs = test::random_values<S>(5000, 31), ys = test::random_values<S>(5000, 32);
  for (std::size_t k = 0; k < xs.size(); ++k) {
    S const a = xs[k], b = ys[k];
    if (!std::isfinite(a) || !std::isfinite(b) || std::abs(a) > S(1e30) || std::abs(b) > S(1e30))
      continue;
    auto const s = detail::two_sum(splat<T>(a), splat<T>(b));
    auto const p = detail::two_prod(splat<T>(a), splat<T>(b));
    // hi + lo equals the exact sum/product (checked in long double, exact for float; for
    // double the product check is the rounding of the exact value, compared exactly).
    long double const es = (long double)a + (long double)b;
    CHECK(test::same_bits(lane(s.hi, 0), S(es)));
    CHECK((long double)lane(s.hi, 0) + (long double)lane(s.lo, 0) == es);
    if constexpr (sizeof(S) == 4) {
      long double const ep = (long double)a * (long double)b;
      // Dekker's product is exact while the product neither overflows nor underflows.
      if (std::abs(ep) > 1e-30L && std::abs(ep) < (long double)std::numeric_limits<S>::max() / 4)
        CHECK((long double)lane(p.hi, 0) + (long double)lane(p.lo, 0) == ep);
    } else {
      CHECK(test::same_bits(lane(p.hi, 0), a * b));
    }
  }
}

namespace {
// The polynomial c[0] x^(N-1) + ... + c[N-1] in long double, Horner's order.
template <class S, std::size_t N>
long double exact_poly(long double x, S const (&c)[N]) {
  long double r = 0;
  for (S const k : c)
    r = r * x + (long double)k;
  return r;
}

template <class T, std::size_t N>
void check_estrin(scalar_t<T> const (&c)[N], scalar_t<T> range) {
  using S = scalar_t<T>;
  std::mt19937 rng(std::uint32_t(40 + N));
  std::uniform_real_distribution<double> in(-double(range), double(range));
  std::vector<S> xs(400);
  for (S& x : xs)
    x = S(in(rng));
  xs[0] = 0;
  xs[1] = range;
  xs[2] = -range;
  for (std::size_t k = 0; k + lanes_v<T> <= xs.size(); k += lanes_v<T>) {
    T const x = test::make_lanes<T>(xs, k);
    T const e = detail::estrin(x, c);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      S const xi = lane(x, i);
      INFO("N = " << N << ", x = " << xi);
      // Lane-exact: the scalar call on the lane's input.
      REQUIRE(test::same_bits(lane(e, i), detail::estrin(xi, c)));
      // The value: within a few roundings per term of the exact polynomial (the tables below
      // are dominated by their constant term for |x| <= range: no cancellation).
      long double const want = exact_poly((long double)xi, c);
      REQUIRE(std::abs((long double)lane(e, i) - want) <=
              4 * N * (long double)std::numeric_limits<S>::epsilon() * std::abs(want));
    }
  }
}
} // namespace

TEMPLATE_LIST_TEST_CASE("estrin evaluates the polynomial, lane-exact, for every length",
                        "[numerics][detail][poly]", test::real_types) {
  using T = TestType;
  using S = scalar_t<T>;
  // Positive coefficients falling with the degree, |x| <= 1/2: the constant term dominates.
  S const c1[] = {S(1.5)};
  S const c2[] = {S(0.75), S(1)};
  S const c3[] = {S(0.3), S(0.6), S(1)};
  S const c5[] = {S(0.1), S(0.2), S(0.3), S(0.4), S(1)};
  S const c8[] = {S(0.01), S(0.02), S(0.05), S(0.1), S(0.2), S(0.3), S(0.5), S(1)};
  S const c12[] = {S(1e-4), S(2e-4), S(5e-4), S(1e-3), S(2e-3), S(5e-3),
                   S(0.01), S(0.02), S(0.05), S(0.1),  S(0.3),  S(1)};
  S const c16[] = {S(1e-6), S(2e-6), S(5e-6), S(1e-5), S(2e-5), S(5e-5), S(1e-4), S(2e-4),
                   S(5e-4), S(1e-3), S(2e-3), S(5e-3), S(0.01), S(0.05), S(0.2),  S(1)};
  check_estrin<T>(c1, S(0.5));
  check_estrin<T>(c2, S(0.5));
  check_estrin<T>(c3, S(0.5));
  check_estrin<T>(c5, S(0.5));
  check_estrin<T>(c8, S(0.5));
  check_estrin<T>(c12, S(0.5));
  check_estrin<T>(c16, S(0.5));
  S const c4[] = {S(0.2), S(0.3), S(0.6), S(1)};
  S const c6[] = {S(0.05), S(0.1), S(0.2), S(0.3), S(0.6), S(1)};
  S const c7[] = {S(0.02), S(0.05), S(0.1), S(0.2), S(0.3), S(0.6), S(1)};
  check_estrin<T>(c4, S(0.5));
  check_estrin<T>(c6, S(0.5));
  check_estrin<T>(c7, S(0.5));
  // The tables it runs on, over their kernels' ranges: asin's (u in [0, 1]); tan's (z = r^2,
  // |r| <= pi/4); float pow's, evaluated in double (s^2 <= 0.03 for log2, |r| <= 1/2 for 2^r).
  using C = detail::math_constants<S>;
  check_estrin<T>(C::asin_poly, S(1));
  if constexpr (std::is_same_v<S, float>) {
    check_estrin<T>(C::tan_poly, S(0.62));
  } else {
    check_estrin<T>(C::tan_p, S(0.62));
    check_estrin<T>(C::tan_q, S(0.62));
    check_estrin<T>(C::atan2_poly, S(0.13)); // q^2, |q| <= 0.36
    using Cf = detail::math_constants<float>;
    check_estrin<T>(Cf::powf_log2_poly, S(0.03));
    check_estrin<T>(Cf::powf_exp2_poly, S(0.5));
  }
}
