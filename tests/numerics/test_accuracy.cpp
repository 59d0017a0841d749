// Accuracy of the transcendental functions: dense sweeps of each domain against a
// higher-precision reference (double libm for float, long double libm for double). Prints
// the maximum error in ulp per function and fails above the documented bound (2 ulp).
// Wide types are covered by lane-exactness (test_lane_exact.cpp): each lane is the scalar.
#include "../common/harness.hpp"

#include <plume/numerics/exp_log.hpp>
#include <plume/numerics/trig.hpp>

#include <cstdio>
#include <functional>

using namespace plume;

namespace {
constexpr long double bound_ulp = 2.0L;

template <class S>
using ref_fn = std::function<long double(long double)>;

/// Sweep of [lo, hi] (both > 0) by stepping through the bit patterns, n points; both signs
/// when `both_signs`.
template <class S>
std::vector<S> sweep(S lo, S hi, std::size_t n, bool both_signs) {
  using B = bits_t<S>;
  B const a = std::bit_cast<B>(lo), b = std::bit_cast<B>(hi);
  B const step = std::max<B>(1, (b - a) / B(n));
  std::vector<S> v;
  for (B k = a; k <= b && k >= a; k += step) {
    S const x = std::bit_cast<S>(k);
    v.push_back(x);
    if (both_signs) v.push_back(-x);
  }
  return v;
}
template <class S>
std::vector<S> uniform(S lo, S hi, std::size_t n, std::uint32_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<long double> d(lo, hi);
  std::vector<S> v;
  for (std::size_t i = 0; i < n; ++i)
    v.push_back(static_cast<S>(d(rng)));
  return v;
}
template <class S>
std::vector<S> cat(std::vector<S> a, std::vector<S> const& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

template <class S, class F, class R>
void measure(char const* name, F f, R ref, std::vector<S> const& xs) {
  test::ulp_report rep;
  for (S x : xs)
    rep.add(test::ulp_error(f(x), ref(static_cast<long double>(x))), x);
  std::printf("  %-6s %-6s max error %.3f ulp (at x = %.9Lg) over %zu points\n", name,
              std::is_same_v<S, float> ? "float" : "double", double(rep.max_ulp), rep.at_x,
              xs.size());
  INFO(name << ": max error " << double(rep.max_ulp) << " ulp at x = " << double(rep.at_x));
  CHECK(rep.max_ulp <= bound_ulp);
}
template <class S, class F, class R>
void measure2(char const* name, F f, R ref, std::vector<S> const& xs, std::vector<S> const& ys) {
  test::ulp_report rep;
  for (std::size_t i = 0; i < xs.size(); ++i)
    rep.add(test::ulp_error(f(xs[i], ys[i]),
                            ref(static_cast<long double>(xs[i]), static_cast<long double>(ys[i]))),
            xs[i], ys[i]);
  std::printf("  %-6s %-6s max error %.3f ulp (at %.9Lg, %.9Lg) over %zu points\n", name,
              std::is_same_v<S, float> ? "float" : "double", double(rep.max_ulp), rep.at_x,
              rep.at_y, xs.size());
  INFO(name << ": max error " << double(rep.max_ulp) << " ulp at (" << double(rep.at_x) << ", "
            << double(rep.at_y) << ")");
  CHECK(rep.max_ulp <= bound_ulp);
}

// Reference: the next wider type's libm, evaluated on the exact input.
template <class S>
struct ref {
  using W = std::conditional_t<std::is_same_v<S, float>, double, long double>;
  template <class G>
  static auto of(G g) {
    return [g](long double x) { return static_cast<long double>(g(static_cast<W>(x))); };
  }
  template <class G>
  static auto of2(G g) {
    return [g](long double x, long double y) {
      return static_cast<long double>(g(static_cast<W>(x), static_cast<W>(y)));
    };
  }
};

template <class S>
void accuracy_suite() {
  using W = typename ref<S>::W;
  constexpr bool F32 = std::is_same_v<S, float>;
  std::size_t const n = F32 ? 400000 : 200000;
  S const maxv = std::numeric_limits<S>::max();
  S const tiny = std::numeric_limits<S>::denorm_min();
  auto const trig_in = cat(
      cat(uniform<S>(-10, 10, n, 1), uniform<S>(-S(F32 ? 8000 : 1e8), S(F32 ? 8000 : 1e8), n, 2)),
      sweep<S>(tiny, maxv, n / 4, true));
  measure<S>(
      "sin", [](S x) { return plume::sin(x); }, ref<S>::of([](W x) { return std::sin(x); }),
      trig_in);
  measure<S>(
      "cos", [](S x) { return plume::cos(x); }, ref<S>::of([](W x) { return std::cos(x); }),
      trig_in);
  measure<S>(
      "tan", [](S x) { return plume::tan(x); }, ref<S>::of([](W x) { return std::tan(x); }),
      trig_in);
  // sincos gives exactly sin's and cos's bits (checked in test_special_values.cpp).
  auto const unit = cat(uniform<S>(-1, 1, n, 3), sweep<S>(tiny, S(1), n / 4, true));
  measure<S>(
      "asin", [](S x) { return plume::asin(x); }, ref<S>::of([](W x) { return std::asin(x); }),
      unit);
  measure<S>(
      "acos", [](S x) { return plume::acos(x); }, ref<S>::of([](W x) { return std::acos(x); }),
      unit);
  auto const all_mag = cat(sweep<S>(tiny, maxv, n, true), uniform<S>(-4, 4, n / 2, 4));
  measure<S>(
      "atan", [](S x) { return plume::atan(x); }, ref<S>::of([](W x) { return std::atan(x); }),
      all_mag);
  auto const ys = cat(uniform<S>(-10, 10, n / 2, 5), test::random_values<S>(n / 2, 6));
  auto const xs2 = cat(uniform<S>(-10, 10, n / 2, 7), test::random_values<S>(n / 2, 8));
  measure2<S>(
      "atan2", [](S y, S x) { return plume::atan2(y, x); },
      ref<S>::of2([](W y, W x) { return std::atan2(y, x); }), ys, xs2);
  S const elo = F32 ? S(-104) : S(-746), ehi = F32 ? S(89) : S(710);
  auto const exp_in = cat(uniform<S>(elo, ehi, n, 10), uniform<S>(-1, 1, n / 2, 11));
  measure<S>(
      "exp", [](S x) { return plume::exp(x); }, ref<S>::of([](W x) { return std::exp(x); }),
      exp_in);
  auto const exp2_in = cat(uniform<S>(F32 ? S(-150) : S(-1075), F32 ? S(128) : S(1024), n, 12),
                           uniform<S>(-1, 1, n / 2, 13));
  measure<S>(
      "exp2", [](S x) { return plume::exp2(x); }, ref<S>::of([](W x) { return std::exp2(x); }),
      exp2_in);
  auto const em1_in =
      cat(cat(uniform<S>(F32 ? S(-20) : S(-40), ehi, n, 14), uniform<S>(-1, 1, n / 2, 15)),
          sweep<S>(tiny, S(1), n / 4, true));
  measure<S>(
      "expm1", [](S x) { return plume::expm1(x); }, ref<S>::of([](W x) { return std::expm1(x); }),
      em1_in);
  auto const pos = cat(sweep<S>(tiny, maxv, n, false), uniform<S>(S(0.5), S(2), n / 2, 16));
  measure<S>(
      "log", [](S x) { return plume::log(x); }, ref<S>::of([](W x) { return std::log(x); }), pos);
  measure<S>(
      "log2", [](S x) { return plume::log2(x); }, ref<S>::of([](W x) { return std::log2(x); }),
      pos);
  auto const l1p = cat(cat(sweep<S>(tiny, maxv, n / 2, false), uniform<S>(-1, 1, n / 2, 17)),
                       sweep<S>(tiny, S(1), n / 4, true));
  measure<S>(
      "log1p", [](S x) { return plume::log1p(x); }, ref<S>::of([](W x) { return std::log1p(x); }),
      l1p);
  // pow: bases over magnitudes with exponents that keep results mostly in range, and
  // bases near 1 with large exponents (where a plain exp(y log x) loses digits).
  std::vector<S> px, py;
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> lx(-20, 20), yy(-30, 30), near1(-1e-3, 1e-3),
      bigy(-1e4, 1e4);
  for (std::size_t i = 0; i < n / 2; ++i) {
    px.push_back(static_cast<S>(std::pow(2.0, lx(rng))));
    py.push_back(static_cast<S>(yy(rng)));
    px.push_back(static_cast<S>(1 + near1(rng)));
    py.push_back(static_cast<S>(bigy(rng) * (F32 ? 1 : 30)));
    px.push_back(-static_cast<S>(std::round(std::pow(2.0, lx(rng) / 4))));
    py.push_back(static_cast<S>(std::round(yy(rng))));
  }
  measure2<S>(
      "pow", [](S x, S y) { return plume::pow(x, y); },
      ref<S>::of2([](W x, W y) { return std::pow(x, y); }), px, py);
}
} // namespace

/// The 2k + 1 values of S nearest to v (k ulps either side), for both signs if asked.
template <class S>
std::vector<S> around(S v, int k, bool both_signs) {
  std::vector<S> out;
  S lo = v, hi = v;
  for (int i = 0; i < k; ++i) {
    lo = std::nextafter(lo, S(0));
    hi = std::nextafter(hi, std::numeric_limits<S>::infinity());
  }
  for (S x = lo; x <= hi; x = std::nextafter(x, std::numeric_limits<S>::infinity())) {
    out.push_back(x);
    if (both_signs) out.push_back(-x);
  }
  return out;
}

/// sin/cos/tan, exp/exp2 and log switch from their fast path to the general one at fixed
/// limits (detail/coefficients.hpp); both sides of each edge must meet the bound.
template <class S>
void fast_path_edges() {
  using W = typename ref<S>::W;
  using C = detail::math_constants<S>;
  auto const trig = around<S>(C::trig_fast_limit, 3000, true);
  measure<S>(
      "sin", [](S x) { return plume::sin(x); }, ref<S>::of([](W x) { return std::sin(x); }), trig);
  measure<S>(
      "cos", [](S x) { return plume::cos(x); }, ref<S>::of([](W x) { return std::cos(x); }), trig);
  measure<S>(
      "tan", [](S x) { return plume::tan(x); }, ref<S>::of([](W x) { return std::tan(x); }), trig);
  measure<S>(
      "exp", [](S x) { return plume::exp(x); }, ref<S>::of([](W x) { return std::exp(x); }),
      around<S>(C::exp_fast_limit, 3000, true));
  measure<S>(
      "exp2", [](S x) { return plume::exp2(x); }, ref<S>::of([](W x) { return std::exp2(x); }),
      around<S>(C::exp2_fast_limit, 3000, true));
  auto const tiny = around<S>(std::numeric_limits<S>::min(), 3000, false);
  measure<S>(
      "log", [](S x) { return plume::log(x); }, ref<S>::of([](W x) { return std::log(x); }), tiny);
  measure<S>(
      "log2", [](S x) { return plume::log2(x); }, ref<S>::of([](W x) { return std::log2(x); }),
      tiny);
}

TEST_CASE("fast-path edges are within 2 ulp on both sides", "[numerics][accuracy]") {
  std::printf("Around the fast paths' limits:\n");
  fast_path_edges<float>();
  fast_path_edges<double>();
}

TEST_CASE("transcendental functions are within 2 ulp (float)", "[numerics][accuracy]") {
  std::printf("Accuracy against double libm:\n");
  accuracy_suite<float>();
}

TEST_CASE("transcendental functions are within 2 ulp (double)", "[numerics][accuracy]") {
  std::printf("Accuracy against long double libm:\n");
  accuracy_suite<double>();
}
