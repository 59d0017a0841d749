// plume_bench_numerics: throughput of plume's transcendental functions at every width of the
// build, next to the peers the distribution ships, on the same inputs.
//
// Every benchmark evaluates one function on N = 4096 inputs (a fixed, reproducible set in
// the function's usual domain) and reports items_per_second = evaluations per second, so
// the figures of different widths and libraries read as direct ratios. Names are
//   <function>/<f32|f64>/<implementation>/<width>
// with implementation one of
//   plume   plume's function at T = float/double (x1) and at every batch width of the build
//   std     the C library (glibc libm), one value at a time
//   xsimd   xsimd 8.1's own batch function, at each width the build enables
//   sleef   SLEEF 3.5, 1.0-ulp (u10) versions, at each width the build enables
//   sleef_u35  SLEEF's 3.5-ulp versions where SLEEF has them (not exp, pow, sqrt)
//   eigen   Eigen 3.4 array functions (its own vectorisation at the build's flags)
// The x1 loops evaluate one value at a time: the benchmarks are compiled without the
// auto-vectoriser (bench/CMakeLists.txt), so x1 is the scalar cost and the width ratios are
// what explicit batching buys. (Explicit SIMD - plume's batches, Eigen, xsimd - is unaffected.)
// bench/report.py reads the JSON output and prints the ratios to plume x1.
// The per-element lambdas are forced inline (PLUME_BENCH_INLINE): g++ otherwise keeps a
// large one out of line and the loop pays a call and reloads every constant per batch, which
// measured the wrapper, not the function (plume's f32x8 sin read 0.80 G/s instead of 0.99).
#include <plume/numerics.hpp>

#include "../bench_support.hpp"
#include <Eigen/Core>

#include <benchmark/benchmark.h>
#include <sleef.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <new>
#include <string>
#include <vector>

namespace {

constexpr std::size_t N = 4096;

template <class S>
struct aligned_buffer {
  S* p;
  aligned_buffer() : p(new (std::align_val_t(64)) S[N]) {}
  ~aligned_buffer() { ::operator delete[](p, std::align_val_t(64)); }
  aligned_buffer(aligned_buffer const&) = delete;
  aligned_buffer& operator=(aligned_buffer const&) = delete;
};

/// N values in [lo, hi], from a fixed xorshift sequence.
template <class S>
void fill(S* p, double lo, double hi, std::uint64_t seed) {
  std::uint64_t s = seed * 0x9E3779B97F4A7C15ull + 1;
  for (std::size_t i = 0; i < N; ++i) {
    s ^= s << 13;
    s ^= s >> 7;
    s ^= s << 17;
    p[i] = static_cast<S>(lo + (hi - lo) * (double(s >> 11) * 0x1.0p-53));
  }
}

struct domain {
  double lo, hi;
};

template <class S>
struct inputs {
  aligned_buffer<S> x, y, out;
  inputs(domain dx, domain dy) {
    fill(x.p, dx.lo, dx.hi, 1);
    fill(y.p, dy.lo, dy.hi, 2);
  }
};

/// Runs f over the inputs T lanes at a time (f takes and returns T).
template <class T, class F>
void unary(benchmark::State& st, domain d, F f) {
  using S = plume::scalar_t<T>;
  inputs<S> in(d, d);
  for (auto _ : st) {
    for (std::size_t i = 0; i < N; i += plume::lanes_v<T>)
      plume::store_aligned(in.out.p + i, f(plume::load_aligned<T>(in.x.p + i)));
    benchmark::DoNotOptimize(in.out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}

template <class T, class F>
void binary(benchmark::State& st, domain dx, domain dy, F f) {
  using S = plume::scalar_t<T>;
  inputs<S> in(dx, dy);
  for (auto _ : st) {
    for (std::size_t i = 0; i < N; i += plume::lanes_v<T>)
      plume::store_aligned(
          in.out.p + i, f(plume::load_aligned<T>(in.x.p + i), plume::load_aligned<T>(in.y.p + i)));
    benchmark::DoNotOptimize(in.out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}

/// Eigen evaluates a whole array expression at once.
template <class S, class F>
void eigen_unary(benchmark::State& st, domain d, F f) {
  inputs<S> in(d, d);
  using A = Eigen::Array<S, Eigen::Dynamic, 1>;
  Eigen::Map<A const, Eigen::Aligned64> x(in.x.p, N);
  Eigen::Map<A, Eigen::Aligned64> out(in.out.p, N);
  for (auto _ : st) {
    out = f(x);
    benchmark::DoNotOptimize(in.out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}

template <class S, class F>
void eigen_binary(benchmark::State& st, domain dx, domain dy, F f) {
  inputs<S> in(dx, dy);
  using A = Eigen::Array<S, Eigen::Dynamic, 1>;
  Eigen::Map<A const, Eigen::Aligned64> x(in.x.p, N), y(in.y.p, N);
  Eigen::Map<A, Eigen::Aligned64> out(in.out.p, N);
  for (auto _ : st) {
    out = f(x, y);
    benchmark::DoNotOptimize(in.out.p);
    benchmark::ClobberMemory();
  }
  st.SetItemsProcessed(static_cast<std::int64_t>(st.iterations() * N));
}

std::string name(char const* fn, char const* ty, char const* impl, std::size_t width) {
  return std::string(fn) + "/" + ty + "/" + impl + "/x" + std::to_string(width);
}

// ------------------------------------------------------------------------ registration
// One macro per function shape keeps the list below readable: FN is the plume/std/xsimd
// name, SL the SLEEF stem (sin -> Sleef_sinf8_u10), EIGEN an Eigen array expression or
// nothing.

template <class T>
char const* type_name() {
  return sizeof(plume::scalar_t<T>) == 4 ? "f32" : "f64";
}

#define PLUME_BENCH_PLUME_UNARY(FN, T, D)                                                          \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "plume", plume::lanes_v<T>).c_str(), [](benchmark::State& st) {    \
        unary<T>(st, D, [](T v) PLUME_BENCH_INLINE { return plume::FN(v); });                      \
      })
#define PLUME_BENCH_PLUME_BINARY(FN, T, DX, DY)                                                    \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "plume", plume::lanes_v<T>).c_str(), [](benchmark::State& st) {    \
        binary<T>(st, DX, DY, [](T a, T b) PLUME_BENCH_INLINE { return plume::FN(a, b); });        \
      })

template <class S>
void register_std_unary(char const* fn, domain d, S (*f)(S)) {
  benchmark::RegisterBenchmark(name(fn, type_name<S>(), "std", 1).c_str(),
                               [d, f](benchmark::State& st) { unary<S>(st, d, f); });
}
template <class S>
void register_std_binary(char const* fn, domain dx, domain dy, S (*f)(S, S)) {
  benchmark::RegisterBenchmark(name(fn, type_name<S>(), "std", 1).c_str(),
                               [dx, dy, f](benchmark::State& st) { binary<S>(st, dx, dy, f); });
}

// Domains: the ranges a physics engine feeds these functions.
constexpr domain angles{-10.0, 10.0};
constexpr domain unit{-1.0, 1.0};
constexpr domain exps{-20.0, 20.0};
constexpr domain positive{1e-3, 1e3};
constexpr domain coords{-100.0, 100.0};
constexpr domain bases{0.01, 10.0};
constexpr domain powers{-4.0, 4.0};

template <class T>
void register_plume_width() {
  PLUME_BENCH_PLUME_UNARY(sin, T, angles);
  PLUME_BENCH_PLUME_UNARY(cos, T, angles);
  PLUME_BENCH_PLUME_UNARY(tan, T, angles);
  PLUME_BENCH_PLUME_UNARY(asin, T, unit);
  PLUME_BENCH_PLUME_UNARY(acos, T, unit);
  PLUME_BENCH_PLUME_BINARY(atan2, T, coords, coords);
  PLUME_BENCH_PLUME_UNARY(exp, T, exps);
  PLUME_BENCH_PLUME_UNARY(log, T, positive);
  PLUME_BENCH_PLUME_BINARY(pow, T, bases, powers);
  PLUME_BENCH_PLUME_UNARY(sqrt, T, positive);
}

#if PLUME_HAS_BATCHES
// xsimd's own functions on plume's batch types (they are xsimd batches).
#define PLUME_BENCH_XSIMD_UNARY(FN, T, D)                                                          \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "xsimd", plume::lanes_v<T>).c_str(), [](benchmark::State& st) {    \
        unary<T>(st, D, [](T v) PLUME_BENCH_INLINE { return xsimd::FN(v); });                      \
      })
#define PLUME_BENCH_XSIMD_BINARY(FN, T, DX, DY)                                                    \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "xsimd", plume::lanes_v<T>).c_str(), [](benchmark::State& st) {    \
        binary<T>(st, DX, DY, [](T a, T b) PLUME_BENCH_INLINE { return xsimd::FN(a, b); });        \
      })
template <class T>
void register_xsimd_width() {
  PLUME_BENCH_XSIMD_UNARY(sin, T, angles);
  PLUME_BENCH_XSIMD_UNARY(cos, T, angles);
  PLUME_BENCH_XSIMD_UNARY(tan, T, angles);
  PLUME_BENCH_XSIMD_UNARY(asin, T, unit);
  PLUME_BENCH_XSIMD_UNARY(acos, T, unit);
  PLUME_BENCH_XSIMD_BINARY(atan2, T, coords, coords);
  PLUME_BENCH_XSIMD_UNARY(exp, T, exps);
  PLUME_BENCH_XSIMD_UNARY(log, T, positive);
  PLUME_BENCH_XSIMD_BINARY(pow, T, bases, powers);
  PLUME_BENCH_XSIMD_UNARY(sqrt, T, positive);
}

// SLEEF's vector functions take and return the raw registers, which xsimd batches convert
// to and from.
#define PLUME_BENCH_SLEEF_UNARY(FN, T, SLEEF_FN, D)                                                \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "sleef", plume::lanes_v<T>).c_str(), [](benchmark::State& st) {    \
        unary<T>(st, D, [](T v) PLUME_BENCH_INLINE { return T(SLEEF_FN(v)); });                    \
      })
#define PLUME_BENCH_SLEEF_BINARY(FN, T, SLEEF_FN, DX, DY)                                          \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "sleef", plume::lanes_v<T>).c_str(), [](benchmark::State& st) {    \
        binary<T>(st, DX, DY, [](T a, T b) PLUME_BENCH_INLINE { return T(SLEEF_FN(a, b)); });      \
      })
#define PLUME_BENCH_SLEEF_U35_UNARY(FN, T, SLEEF_FN, D)                                            \
  benchmark::RegisterBenchmark(name(#FN, type_name<T>(), "sleef_u35", plume::lanes_v<T>).c_str(),  \
                               [](benchmark::State& st) {                                          \
                                 unary<T>(st, D,                                                   \
                                          [](T v) PLUME_BENCH_INLINE { return T(SLEEF_FN(v)); });  \
                               })
#define PLUME_BENCH_SLEEF_U35_BINARY(FN, T, SLEEF_FN, DX, DY)                                      \
  benchmark::RegisterBenchmark(                                                                    \
      name(#FN, type_name<T>(), "sleef_u35", plume::lanes_v<T>).c_str(),                           \
      [](benchmark::State& st) {                                                                   \
        binary<T>(st, DX, DY, [](T a, T b) PLUME_BENCH_INLINE { return T(SLEEF_FN(a, b)); });      \
      })
// SLEEF has 3.5-ulp versions of these (exp and pow exist only as u10).
#define PLUME_BENCH_SLEEF_U35(T, F)                                                                \
  PLUME_BENCH_SLEEF_U35_UNARY(sin, T, Sleef_sin##F##_u35, angles);                                 \
  PLUME_BENCH_SLEEF_U35_UNARY(cos, T, Sleef_cos##F##_u35, angles);                                 \
  PLUME_BENCH_SLEEF_U35_UNARY(tan, T, Sleef_tan##F##_u35, angles);                                 \
  PLUME_BENCH_SLEEF_U35_UNARY(asin, T, Sleef_asin##F##_u35, unit);                                 \
  PLUME_BENCH_SLEEF_U35_UNARY(acos, T, Sleef_acos##F##_u35, unit);                                 \
  PLUME_BENCH_SLEEF_U35_BINARY(atan2, T, Sleef_atan2##F##_u35, coords, coords);                    \
  PLUME_BENCH_SLEEF_U35_UNARY(log, T, Sleef_log##F##_u35, positive)
#define PLUME_BENCH_SLEEF_ALL(T, F, D4)                                                            \
  PLUME_BENCH_SLEEF_UNARY(sin, T, Sleef_sin##F##_u10, angles);                                     \
  PLUME_BENCH_SLEEF_UNARY(cos, T, Sleef_cos##F##_u10, angles);                                     \
  PLUME_BENCH_SLEEF_UNARY(tan, T, Sleef_tan##F##_u10, angles);                                     \
  PLUME_BENCH_SLEEF_UNARY(asin, T, Sleef_asin##F##_u10, unit);                                     \
  PLUME_BENCH_SLEEF_UNARY(acos, T, Sleef_acos##F##_u10, unit);                                     \
  PLUME_BENCH_SLEEF_BINARY(atan2, T, Sleef_atan2##F##_u10, coords, coords);                        \
  PLUME_BENCH_SLEEF_UNARY(exp, T, Sleef_exp##F##_u10, exps);                                       \
  PLUME_BENCH_SLEEF_UNARY(log, T, Sleef_log##F##_u10, positive);                                   \
  PLUME_BENCH_SLEEF_BINARY(pow, T, Sleef_pow##F##_u10, bases, powers);                             \
  PLUME_BENCH_SLEEF_UNARY(sqrt, T, Sleef_sqrt##F##_u05, positive)
#endif

template <class S>
void register_peers_scalar() {
  register_std_unary<S>("sin", angles, [](S v) { return std::sin(v); });
  register_std_unary<S>("cos", angles, [](S v) { return std::cos(v); });
  register_std_unary<S>("tan", angles, [](S v) { return std::tan(v); });
  register_std_unary<S>("asin", unit, [](S v) { return std::asin(v); });
  register_std_unary<S>("acos", unit, [](S v) { return std::acos(v); });
  register_std_binary<S>("atan2", coords, coords, [](S a, S b) { return std::atan2(a, b); });
  register_std_unary<S>("exp", exps, [](S v) { return std::exp(v); });
  register_std_unary<S>("log", positive, [](S v) { return std::log(v); });
  register_std_binary<S>("pow", bases, powers, [](S a, S b) { return std::pow(a, b); });
  register_std_unary<S>("sqrt", positive, [](S v) { return std::sqrt(v); });

  using A = Eigen::Array<S, Eigen::Dynamic, 1>;
  using M = Eigen::Map<A const, Eigen::Aligned64>;
  constexpr std::size_t w = Eigen::internal::packet_traits<S>::size;
  char const* ty = sizeof(S) == 4 ? "f32" : "f64";
  auto reg = [&](char const* fn, auto body) {
    benchmark::RegisterBenchmark(name(fn, ty, "eigen", w).c_str(), body);
  };
  reg("sin",
      [](benchmark::State& st) { eigen_unary<S>(st, angles, [](M const& x) { return x.sin(); }); });
  reg("cos",
      [](benchmark::State& st) { eigen_unary<S>(st, angles, [](M const& x) { return x.cos(); }); });
  reg("tan",
      [](benchmark::State& st) { eigen_unary<S>(st, angles, [](M const& x) { return x.tan(); }); });
  reg("asin",
      [](benchmark::State& st) { eigen_unary<S>(st, unit, [](M const& x) { return x.asin(); }); });
  reg("exp",
      [](benchmark::State& st) { eigen_unary<S>(st, exps, [](M const& x) { return x.exp(); }); });
  reg("log", [](benchmark::State& st) {
    eigen_unary<S>(st, positive, [](M const& x) { return x.log(); });
  });
  reg("pow", [](benchmark::State& st) {
    eigen_binary<S>(st, bases, powers, [](M const& x, M const& y) { return x.pow(y); });
  });
  reg("sqrt", [](benchmark::State& st) {
    eigen_unary<S>(st, positive, [](M const& x) { return x.sqrt(); });
  });
}

void register_all() {
  register_plume_width<float>();
  register_plume_width<double>();
  register_peers_scalar<float>();
  register_peers_scalar<double>();
#if PLUME_HAS_BATCHES
  register_plume_width<plume::f32x4>();
  register_plume_width<plume::f64x2>();
  register_xsimd_width<plume::f32x4>();
  register_xsimd_width<plume::f64x2>();
  PLUME_BENCH_SLEEF_ALL(plume::f32x4, f4, 0);
  PLUME_BENCH_SLEEF_ALL(plume::f64x2, d2, 0);
  PLUME_BENCH_SLEEF_U35(plume::f32x4, f4);
  PLUME_BENCH_SLEEF_U35(plume::f64x2, d2);
#if PLUME_HAS_AVX2
  register_plume_width<plume::f32x8>();
  register_plume_width<plume::f64x4>();
  register_xsimd_width<plume::f32x8>();
  register_xsimd_width<plume::f64x4>();
  PLUME_BENCH_SLEEF_ALL(plume::f32x8, f8, 0);
  PLUME_BENCH_SLEEF_ALL(plume::f64x4, d4, 0);
  PLUME_BENCH_SLEEF_U35(plume::f32x8, f8);
  PLUME_BENCH_SLEEF_U35(plume::f64x4, d4);
#endif
#if PLUME_HAS_AVX512
  register_plume_width<plume::f32x16>();
  register_plume_width<plume::f64x8>();
  register_xsimd_width<plume::f32x16>();
  register_xsimd_width<plume::f64x8>();
  PLUME_BENCH_SLEEF_ALL(plume::f32x16, f16, 0);
  PLUME_BENCH_SLEEF_ALL(plume::f64x8, d8, 0);
  PLUME_BENCH_SLEEF_U35(plume::f32x16, f16);
  PLUME_BENCH_SLEEF_U35(plume::f64x8, d8);
#endif
#endif
}

} // namespace

int main(int argc, char** argv) {
  register_all();
  return plume::bench::run_benchmarks(argc, argv);
}
