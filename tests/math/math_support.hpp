// Helpers for the math tests: random generic vectors/quaternions/matrices whose lanes differ,
// bitwise comparison of whole math values, and tolerances derived from the operation.
#pragma once

#include "../common/harness.hpp"
#include "../common/types.hpp"

#include <plume/math.hpp>

#include <random>
#include <sstream>
#include <tuple>

namespace plume::test {

/// Deterministic random element values: every lane drawn separately.
struct rng {
  std::mt19937_64 gen;
  explicit rng(std::uint64_t seed) : gen(seed) {}
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * (double(gen() >> 11) * 0x1.0p-53);
  }
  template <class T>
  T elem(double lo, double hi) {
    std::array<scalar_t<T>, lanes_v<T>> a;
    for (auto& v : a)
      v = static_cast<scalar_t<T>>(uniform(lo, hi));
    return from_array<T>(a);
  }
  template <class T>
  GVec3<T> vec3(double lo = -10, double hi = 10) {
    return {elem<T>(lo, hi), elem<T>(lo, hi), elem<T>(lo, hi)};
  }
  /// A unit vector per lane (normalised in double, then rounded).
  template <class T>
  GVec3<T> unit3() {
    GVec3<T> v;
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double x, y, z, n;
      do {
        x = uniform(-1, 1), y = uniform(-1, 1), z = uniform(-1, 1);
        n = std::sqrt(x * x + y * y + z * z);
      } while (n < 0.1 || n > 1);
      using S = scalar_t<T>;
      v = plume::with_lane(v, i, GVec3<S>{S(x / n), S(y / n), S(z / n)});
    }
    return v;
  }
  template <class T>
  GQuat<T> quat() {
    GQuat<T> q;
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      double c[4], n;
      do {
        n = 0;
        for (auto& v : c) {
          v = uniform(-1, 1);
          n += v * v;
        }
        n = std::sqrt(n);
      } while (n < 0.1 || n > 1);
      using S = scalar_t<T>;
      q = plume::with_lane(q, i, GQuat<S>{S(c[0] / n), S(c[1] / n), S(c[2] / n), S(c[3] / n)});
    }
    return q;
  }
  template <class T>
  GMat3<T> mat3(double lo = -1, double hi = 1) {
    return {vec3<T>(lo, hi), vec3<T>(lo, hi), vec3<T>(lo, hi)};
  }
};

template <class S>
constexpr double eps_v = std::numeric_limits<S>::epsilon();

// Bitwise equality of whole values (NaN = NaN), for the lane-exactness checks: numbers,
// masks, vectors, quaternions, matrices and arrays of them. One template, so that no
// implicit conversion can pick a wrong overload.
template <class A>
bool same(A const& a, A const& b) {
  if constexpr (std::is_same_v<A, bool>)
    return a == b;
  else if constexpr (std::is_floating_point_v<A>)
    return same_bits(a, b);
  else if constexpr (requires { a.w_axis; })
    return same(a.x_axis, b.x_axis) && same(a.y_axis, b.y_axis) && same(a.z_axis, b.z_axis) &&
           same(a.w_axis, b.w_axis);
  else if constexpr (requires { a.z_axis; })
    return same(a.x_axis, b.x_axis) && same(a.y_axis, b.y_axis) && same(a.z_axis, b.z_axis);
  else if constexpr (requires { a.x_axis; })
    return same(a.x_axis, b.x_axis) && same(a.y_axis, b.y_axis);
  else if constexpr (requires { a.rotation; })
    return same(a.rotation, b.rotation) && same(a.translation, b.translation);
  else if constexpr (requires { a.cos; })
    return same(a.cos, b.cos) && same(a.sin, b.sin);
  else if constexpr (requires { a.w; })
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z) && same(a.w, b.w);
  else if constexpr (requires { a.z; })
    return same(a.x, b.x) && same(a.y, b.y) && same(a.z, b.z);
  else if constexpr (requires { a.y; })
    return same(a.x, b.x) && same(a.y, b.y);
  else {
    for (std::size_t k = 0; k < a.size(); ++k)
      if (!same(a[k], b[k])) return false;
    return true;
  }
}

// Lane i of any math value (numbers and masks through plume::lane).
template <class V>
auto lane_of(V const& v, std::size_t i) {
  if constexpr (requires { plume::lane(v, i); })
    return plume::lane(v, i);
  else if constexpr (requires { v.size(); }) {
    std::array<decltype(lane_of(v[0], i)), std::tuple_size_v<V>> out;
    for (std::size_t k = 0; k < out.size(); ++k)
      out[k] = lane_of(v[k], i);
    return out;
  }
}

/// The lane-exactness check for math values, shared by every math test: for each case k,
/// make(k) returns a tuple of wide inputs; every lane of f(inputs...) must equal, bitwise,
/// f applied to that lane of each input. Reports the first three differing lanes with their
/// inputs.
template <class T, class Make, class F>
void check_lanes(char const* name, std::size_t cases, Make make, F f) {
  std::size_t failures = 0;
  for (std::size_t k = 0; k < cases; ++k) {
    auto const in = make(k);
    auto const wide = std::apply(f, in);
    for (std::size_t i = 0; i < lanes_v<T>; ++i) {
      auto const want = std::apply([&](auto const&... w) { return f(lane_of(w, i)...); }, in);
      if (!same(lane_of(wide, i), want) && failures++ < 3) {
        std::ostringstream os;
        std::apply([&](auto const&... w) { ((os << lane_of(w, i) << "; "), ...); }, in);
        FAIL_CHECK(name << ": lane " << i << " of " << lanes_v<T> << " differs for inputs "
                        << os.str());
      }
    }
  }
  CHECK(failures == 0);
}

/// Wide values whose lanes come from a pool of adversarial values (0, -0, subnormals, +-inf,
/// NaN, 1e30, ...) and three times as many ordinary random ones, so that neighbouring lanes
/// of an ordinary lane are often extreme. pick(k) is a different mix for every k.
template <class T>
struct lane_pool {
  std::vector<scalar_t<T>> pool;
  explicit lane_pool(std::uint32_t seed) : pool(adversarial<scalar_t<T>>()) {
    auto const rnd = random_values<scalar_t<T>>(200, seed);
    for (int k = 0; k < 3; ++k)
      pool.insert(pool.end(), rnd.begin(), rnd.end());
  }
  std::size_t size() const { return pool.size(); }
  T pick(std::size_t k) const {
    std::array<scalar_t<T>, lanes_v<T>> a;
    for (std::size_t i = 0; i < lanes_v<T>; ++i)
      a[i] = pool[(k * 13 + i * 7) % pool.size()];
    return from_array<T>(a);
  }
};

} // namespace plume::test
