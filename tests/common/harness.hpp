// Shared test harness: bit comparison, adversarial inputs, the lane-exactness check and
// ulp measurement.
#pragma once

#include <plume/numerics.hpp>

#include <catch2/catch.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace plume::test {

/// Bitwise equality, any NaN equal to any NaN (the determinism contract's comparison).
template <class S>
bool same_bits(S a, S b) {
  if constexpr (std::is_floating_point_v<S>) {
    if (a != a && b != b) return true;
    return std::bit_cast<bits_t<S>>(a) == std::bit_cast<bits_t<S>>(b);
  } else {
    return a == b;
  }
}

/// Values that break careless kernels: zeros, subnormals, extremes, NaN, inf, ties.
template <class S>
std::vector<S> adversarial() {
  using L = std::numeric_limits<S>;
  std::vector<S> v = {S(0),
                      -S(0),
                      L::denorm_min(),
                      -L::denorm_min(),
                      L::min(),
                      -L::min(),
                      L::max(),
                      L::lowest(),
                      L::infinity(),
                      -L::infinity(),
                      L::quiet_NaN(),
                      -L::quiet_NaN(),
                      L::epsilon(),
                      S(1),
                      S(-1),
                      S(0.5),
                      S(-0.5),
                      S(1.5),
                      S(2.5),
                      S(-2.5),
                      S(1e-30),
                      S(-1e-30),
                      S(1e30),
                      S(-1e30),
                      S(3.14159265358979),
                      S(1.5707963267948966),
                      S(-1.5707963267948966),
                      S(8000),
                      S(8001),
                      S(1e8),
                      S(2e8),
                      S(88.7),
                      S(-103.9),
                      S(709.7),
                      S(-745.1),
                      S(0.9999999),
                      S(1.0000001),
                      S(16777216),
                      S(16777217),
                      S(4503599627370496.0),
                      S(1e22),
                      S(-1e15),
                      S(2),
                      S(3)};
  return v;
}

/// Random values spread over magnitudes (log-uniform) with random signs, plus uniform ones.
template <class S>
std::vector<S> random_values(std::size_t n, std::uint32_t seed, double max_log10 = 0) {
  std::mt19937_64 rng(seed);
  if (max_log10 == 0) max_log10 = std::is_same_v<S, float> ? 38 : 300;
  std::uniform_real_distribution<double> mag(-max_log10, max_log10), uni(-10, 10);
  std::vector<S> v;
  v.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    double const x = (i % 2) ? std::pow(10.0, mag(rng)) * ((rng() & 1) ? 1 : -1) : uni(rng);
    v.push_back(static_cast<S>(x));
  }
  return v;
}

template <class T>
T make_lanes(std::vector<scalar_t<T>> const& pool, std::size_t start) {
  std::array<scalar_t<T>, lanes_v<T>> a;
  for (std::size_t i = 0; i < lanes_v<T>; ++i)
    a[i] = pool[(start + i * 7) % pool.size()];
  return from_array<T>(a);
}

/// Lane-exactness of a unary kernel f on the wide type T: each input is placed in every lane
/// position with adversarial and random neighbours, and every lane must equal f(scalar).
template <class T, class F>
void check_lane_exact(char const* name, F f, std::vector<scalar_t<T>> inputs) {
  using S = scalar_t<T>;
  auto const adv = adversarial<S>();
  inputs.insert(inputs.end(), adv.begin(), adv.end());
  std::size_t failures = 0;
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    T const x = make_lanes<T>(inputs, k);
    auto const out = to_array(f(x));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      S const xi = lane(x, i);
      auto const want = f(xi);
      if (!same_bits(out[i], want) && failures++ < 5) {
        FAIL_CHECK(name << ": lane " << i << " of " << lanes_v<T> << " for x = " << xi << " gives "
                        << out[i] << ", scalar gives " << want);
      }
    }
  }
  CHECK(failures == 0);
}

/// Binary version: pairs (x[k], y[k]) with neighbours from other pairs.
template <class T, class F>
void check_lane_exact2(char const* name, F f, std::vector<scalar_t<T>> xs,
                       std::vector<scalar_t<T>> ys) {
  using S = scalar_t<T>;
  auto const adv = adversarial<S>();
  for (S a : adv)
    for (S b : adv) {
      xs.push_back(a);
      ys.push_back(b);
    }
  std::size_t failures = 0;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    T const x = make_lanes<T>(xs, k), y = make_lanes<T>(ys, k * 3 + 1);
    auto const out = to_array(f(x, y));
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      S const xi = lane(x, i), yi = lane(y, i);
      auto const want = f(xi, yi);
      if (!same_bits(out[i], want) && failures++ < 5) {
        FAIL_CHECK(name << ": lane " << i << " for (" << xi << ", " << yi << ") gives " << out[i]
                        << ", scalar gives " << want);
      }
    }
  }
  CHECK(failures == 0);
}

/// Error of `got` against the exact value `want` (long double), in ulps of S at want.
template <class S>
long double ulp_error(S got, long double want) {
  if (std::isnan(want)) return std::isnan(got) ? 0 : 1e30L;
  if (std::isinf(want)) {
    // An exact result beyond S's range must overflow; a finite `want` rounding to inf is fine.
    return (std::isinf(got) && (got > 0) == (want > 0)) ? 0 : 1e30L;
  }
  if (std::isnan(got) || std::isinf(got)) {
    // want is finite: inf is right only when want rounds to it.
    return static_cast<S>(want) == got ? 0 : 1e30L;
  }
  int e;
  std::frexp(want, &e); // want = m 2^e, m in [0.5, 1)
  int const digits = std::numeric_limits<S>::digits;
  int const min_e = std::numeric_limits<S>::min_exponent; // subnormals: fixed ulp
  if (e < min_e) e = min_e;
  long double const ulp = std::ldexp(1.0L, e - digits);
  return std::fabs(static_cast<long double>(got) - want) / ulp;
}

struct ulp_report {
  long double max_ulp = 0;
  long double at_x = 0, at_y = 0;
  void add(long double err, long double x, long double y = 0) {
    if (err > max_ulp) {
      max_ulp = err;
      at_x = x;
      at_y = y;
    }
  }
};

} // namespace plume::test
