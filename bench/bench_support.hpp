// bench/bench_support.hpp - what every plume benchmark suite shares: the timing loop with
// items per iteration, the list of f32 widths of the build, and Google Benchmark's main.
#pragma once

#include <plume/numerics.hpp>

#include <benchmark/benchmark.h>

#include <chrono>

#include <cstdint>

/// Forces a kernel lambda inline into the timed loop: `[](T v) PLUME_BENCH_INLINE { ... }`.
/// Without it g++ may keep a large lambda out of line, and the loop then times a call that
/// reloads every constant per batch instead of the kernel.
#define PLUME_BENCH_INLINE __attribute__((always_inline))

namespace plume::bench {

/// The timed loop: body() once per iteration; items_per_second counts `items` per iteration.
template <class F>
void run_items(benchmark::State& st, std::int64_t items, F&& body) {
  for (auto _ : st)
    body();
  st.SetItemsProcessed(std::int64_t(st.iterations()) * items);
}

/// run_items() for work spread over threads: items_per_second from the wall-clock time of the
/// iterations (Google Benchmark's own rate is per CPU second of the calling thread, which
/// misses the other threads' work; UseRealTime() would fix that but renames the benchmark
/// with a "/real_time" suffix).
template <class F>
void run_items_wall(benchmark::State& st, std::int64_t items, F&& body) {
  double seconds = 0.0;
  for (auto _ : st) {
    auto const t0 = std::chrono::steady_clock::now();
    body();
    seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  if (seconds > 0.0)
    st.counters["items_per_second"] =
        benchmark::Counter(double(std::int64_t(st.iterations()) * items) / seconds);
}

/// Calls reg.template operator()<T>() for float and for every f32 width the build has
/// (f32x4, f32x8, f32x16), in that order.
template <class R>
void for_each_f32_width(R&& reg) {
  for_each_type<f32_types>(reg);
}

/// Google Benchmark's main body, after the suite has registered its benchmarks.
inline int run_benchmarks(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

} // namespace plume::bench
