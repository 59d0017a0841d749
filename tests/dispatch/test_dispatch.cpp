// The dispatched array entry points (plume/dispatch.hpp): every function on every instruction
// set this binary carries and this CPU runs, against the scalar templates element by element;
// the choice of instruction set (CPU features, the environment, set_isa); bad spans.
#include "each_isa.hpp"

#include <plume/numerics.hpp>
#include <plume/numerics/isa.hpp>
#include <plume/numerics/spans.hpp>

#include <catch2/catch.hpp>

#include <bit>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <string>
#include <unistd.h>
#include <vector>

using namespace plume;

namespace {

// Inputs that cover each function's domain: specials, the edges of the fast paths, random
// values in a few ranges and random bit patterns (every binade, subnormals, NaNs).
template <class S>
std::vector<S> inputs(std::size_t n, std::uint32_t seed) {
  using Bits = std::conditional_t<sizeof(S) == 4, std::uint32_t, std::uint64_t>;
  std::vector<S> v = {S(0),
                      -S(0),
                      S(1),
                      S(-1),
                      S(0.5),
                      S(2),
                      S(1e-3),
                      S(100),
                      S(-100),
                      std::numeric_limits<S>::infinity(),
                      -std::numeric_limits<S>::infinity(),
                      std::numeric_limits<S>::quiet_NaN(),
                      std::numeric_limits<S>::denorm_min(),
                      std::numeric_limits<S>::min(),
                      std::numeric_limits<S>::max(),
                      S(1e30),
                      S(-3e7),
                      S(0.999999),
                      S(1.000001)};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<S> small(S(-4), S(4)), wide(S(-1e4), S(1e4));
  while (v.size() < n) {
    switch (rng() % 3) {
    case 0:
      v.push_back(small(rng));
      break;
    case 1:
      v.push_back(wide(rng));
      break;
    default:
      v.push_back(std::bit_cast<S>(static_cast<Bits>(rng())));
    }
  }
  v.resize(n);
  return v;
}

template <class S>
bool same(S a, S b) {
  return (a != a && b != b) || std::memcmp(&a, &b, sizeof(S)) == 0;
}

// The first index where got differs from the scalar function, or -1.
template <class S, class F>
long first_mismatch(std::vector<S> const& x, std::vector<S> const& got, F f) {
  for (std::size_t i = 0; i < x.size(); ++i)
    if (!same(got[i], f(x[i]))) return static_cast<long>(i);
  return -1;
}

// Lengths around every batch width (1..16 lanes) and a long one; `offset` shifts every span
// by that many elements off its allocation's alignment.
constexpr std::size_t lengths[] = {1, 2, 3, 4, 5, 7, 8, 9, 15, 16, 17, 31, 33, 1027};

template <class S>
void check_all_functions(Isa isa) {
  for (std::size_t const n : lengths) {
    for (std::size_t const offset : {0u, 1u}) {
      auto const xs = inputs<S>(n + offset, static_cast<std::uint32_t>(n * 7 + offset));
      auto const ys = inputs<S>(n + offset, static_cast<std::uint32_t>(n * 13 + offset + 1));
      std::vector<S> x(xs.begin() + offset, xs.end()), y(ys.begin() + offset, ys.end());
      std::vector<S> buf(n + offset), buf2(n + offset);
      std::span<S> out(buf.data() + offset, n), out2(buf2.data() + offset, n);
      std::span<S const> xin(xs.data() + offset, n), yin(ys.data() + offset, n);
      INFO("isa " << isa_name(isa) << ", " << sizeof(S) * 8 << "-bit, n " << n << ", offset "
                  << offset);
#define PLUME_CHECK_UNARY(name)                                                                    \
  {                                                                                                \
    INFO(#name);                                                                                   \
    std::fill(buf.begin(), buf.end(), S(7));                                                       \
    REQUIRE(plume::name(xin, out) == SpanError::none);                                             \
    std::vector<S> const got(out.begin(), out.end());                                              \
    long const bad = first_mismatch(x, got, [](S v) { return plume::name(v); });                   \
    CAPTURE(bad);                                                                                  \
    CHECK(bad == -1);                                                                              \
  }
      PLUME_CHECK_UNARY(sin)
      PLUME_CHECK_UNARY(cos)
      PLUME_CHECK_UNARY(tan)
      PLUME_CHECK_UNARY(asin)
      PLUME_CHECK_UNARY(acos)
      PLUME_CHECK_UNARY(atan)
      PLUME_CHECK_UNARY(exp)
      PLUME_CHECK_UNARY(exp2)
      PLUME_CHECK_UNARY(expm1)
      PLUME_CHECK_UNARY(log)
      PLUME_CHECK_UNARY(log2)
      PLUME_CHECK_UNARY(log1p)
      PLUME_CHECK_UNARY(sqrt)
#undef PLUME_CHECK_UNARY
#define PLUME_CHECK_BINARY(name)                                                                   \
  {                                                                                                \
    INFO(#name);                                                                                   \
    std::fill(buf.begin(), buf.end(), S(7));                                                       \
    REQUIRE(plume::name(xin, yin, out) == SpanError::none);                                        \
    long bad = -1;                                                                                 \
    for (std::size_t i = 0; i < n && bad < 0; ++i)                                                 \
      if (!same(out[i], plume::name(x[i], y[i]))) bad = static_cast<long>(i);                      \
    CAPTURE(bad);                                                                                  \
    CHECK(bad == -1);                                                                              \
  }
      PLUME_CHECK_BINARY(atan2)
      PLUME_CHECK_BINARY(pow)
      PLUME_CHECK_BINARY(hypot)
#undef PLUME_CHECK_BINARY
      REQUIRE(plume::sincos(xin, out, out2) == SpanError::none);
      long bad = -1;
      for (std::size_t i = 0; i < n && bad < 0; ++i) {
        auto const r = plume::sincos(x[i]);
        if (!same(out[i], r.sin) || !same(out2[i], r.cos)) bad = static_cast<long>(i);
      }
      CAPTURE(bad);
      CHECK(bad == -1);
    }
  }
}

Isa const all_isas[] = {Isa::scalar, Isa::sse2, Isa::avx2, Isa::avx512};

bool carried(Isa isa) {
  for (Isa i : compiled_isas())
    if (i == isa) return true;
  return false;
}

} // namespace

TEST_CASE("dispatch: every carried instruction set gives the scalar functions' bits",
          "[dispatch]") {
  int const ran = test::for_each_runnable_isa([](Isa isa) {
    unsigned const lanes[] = {1, 4, 8, 16};
    CHECK(detail::active_f32_lanes() == lanes[static_cast<int>(isa)]);
    check_all_functions<float>(isa);
    check_all_functions<double>(isa);
  });
  CHECK(ran >= 1);
}

TEST_CASE("dispatch: the list of sets, the best one and set_isa's refusals", "[dispatch]") {
  test::RestoreBest const restore;
  auto const list = compiled_isas();
  REQUIRE(!list.empty());
  for (std::size_t i = 1; i < list.size(); ++i)
    CHECK(static_cast<int>(list[i - 1]) < static_cast<int>(list[i])); // narrowest first
  Isa const best = best_isa();
  CHECK(carried(best));
  CHECK(cpu_has(best));
  for (Isa const i : list)
    if (static_cast<int>(i) > static_cast<int>(best)) CHECK_FALSE(cpu_has(i));
  CHECK(cpu_has(Isa::scalar));
  CHECK(cpu_has(Isa::sse2)); // every x86-64 CPU
#if PLUME_DISPATCH
  CHECK(list.size() == 3);
  CHECK(list.front() == Isa::sse2);
#else
  CHECK(list.size() == 1);
#endif
  for (Isa const isa : all_isas) {
    Isa const before = active_isa();
    IsaError const e = set_isa(isa);
    if (!carried(isa)) {
      CHECK(e == IsaError::not_compiled);
      CHECK(active_isa() == before);
    } else if (!cpu_has(isa)) {
      CHECK(e == IsaError::cpu_lacks);
      CHECK(active_isa() == before);
    } else {
      CHECK(e == IsaError::none);
      CHECK(active_isa() == isa);
    }
  }
  CHECK(to_string(IsaError::cpu_lacks).find("CPU") != std::string_view::npos);
  for (Isa const isa : all_isas)
    CHECK(isa_from_name(isa_name(isa)) == isa);
  CHECK(!isa_from_name("AVX2"));
  CHECK(!isa_from_name(""));
  CHECK(!isa_from_name("avx"));
}

TEST_CASE("dispatch: what a CPU runs needs its features and the OS's register state",
          "[dispatch]") {
  detail::CpuFeatures full;
  full.sse2 = full.sse3 = full.ssse3 = full.sse41 = full.sse42 = full.popcnt = true;
  full.xsave = full.osxsave = full.avx = full.avx2 = full.fma = full.f16c = true;
  full.avx512f = full.avx512cd = full.avx512dq = full.avx512bw = full.avx512vl = true;
  full.xcr0 = 0xe7; // x87, SSE, AVX, opmask, ZMM high halves, ZMM16-31
  CHECK(detail::cpu_runs(full, Isa::avx512));
  CHECK(detail::cpu_runs(full, Isa::avx2));

  // AVX-512F on the CPU but the OS does not save the opmask and ZMM state: avx2 at most.
  for (std::uint64_t const lacking : {0x20u, 0x40u, 0x80u}) {
    detail::CpuFeatures cpu = full;
    cpu.xcr0 &= ~lacking;
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx512));
    CHECK(detail::cpu_runs(cpu, Isa::avx2));
  }
  // The OS does not save the AVX state (or XSAVE is off): sse2 only.
  {
    detail::CpuFeatures cpu = full;
    cpu.xcr0 = 0x3;
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx2));
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx512));
    CHECK(detail::cpu_runs(cpu, Isa::sse2));
    cpu = full;
    cpu.osxsave = false;
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx2));
  }
  // Each feature the flags enable is needed.
  bool detail::CpuFeatures::*const avx2_needs[] = {
      &detail::CpuFeatures::sse3,  &detail::CpuFeatures::ssse3,  &detail::CpuFeatures::sse41,
      &detail::CpuFeatures::sse42, &detail::CpuFeatures::popcnt, &detail::CpuFeatures::xsave,
      &detail::CpuFeatures::avx,   &detail::CpuFeatures::avx2};
  for (auto const f : avx2_needs) {
    detail::CpuFeatures cpu = full;
    cpu.*f = false;
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx2));
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx512));
  }
  bool detail::CpuFeatures::*const avx512_needs[] = {
      &detail::CpuFeatures::fma,      &detail::CpuFeatures::f16c,
      &detail::CpuFeatures::avx512f,  &detail::CpuFeatures::avx512cd,
      &detail::CpuFeatures::avx512dq, &detail::CpuFeatures::avx512bw,
      &detail::CpuFeatures::avx512vl};
  for (auto const f : avx512_needs) {
    detail::CpuFeatures cpu = full;
    cpu.*f = false;
    CHECK_FALSE(detail::cpu_runs(cpu, Isa::avx512));
    CHECK(detail::cpu_runs(cpu, Isa::avx2));
  }
  detail::CpuFeatures const none;
  CHECK_FALSE(detail::cpu_runs(none, Isa::sse2));
  CHECK(detail::cpu_runs(none, Isa::scalar));

  // This machine: what CPUID says agrees with what the compiler's runtime says.
  detail::CpuFeatures const here = detail::cpu_features();
  __builtin_cpu_init();
  CHECK(here.sse2);
  CHECK(detail::cpu_runs(here, Isa::avx2) == (__builtin_cpu_supports("avx2") != 0));
  CHECK(detail::cpu_runs(here, Isa::avx512) ==
        (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512cd") &&
         __builtin_cpu_supports("avx512vl")));
}

TEST_CASE("dispatch: the environment's choice", "[dispatch]") {
  Isa const three[] = {Isa::sse2, Isa::avx2, Isa::avx512};
  detail::CpuFeatures avx2_cpu;
  avx2_cpu.sse2 = avx2_cpu.sse3 = avx2_cpu.ssse3 = avx2_cpu.sse41 = avx2_cpu.sse42 = true;
  avx2_cpu.popcnt = avx2_cpu.xsave = avx2_cpu.osxsave = avx2_cpu.avx = avx2_cpu.avx2 = true;
  avx2_cpu.xcr0 = 0x7;
  using detail::isa_from_environment;
  CHECK(isa_from_environment(nullptr, three, avx2_cpu).isa == Isa::avx2);
  CHECK(isa_from_environment(nullptr, three, avx2_cpu).warning_reason.empty());
  CHECK(isa_from_environment("", three, avx2_cpu).isa == Isa::avx2);
  auto const sse2 = isa_from_environment("sse2", three, avx2_cpu);
  CHECK(sse2.isa == Isa::sse2);
  CHECK(sse2.warning_reason.empty());
  auto const lacking = isa_from_environment("avx512", three, avx2_cpu);
  CHECK(lacking.isa == Isa::avx2);
  CHECK(lacking.warning_reason.find("CPU") != std::string_view::npos);
  auto const unknown = isa_from_environment("avx3", three, avx2_cpu);
  CHECK(unknown.isa == Isa::avx2);
  CHECK(!unknown.warning_reason.empty());
  auto const not_carried = isa_from_environment("scalar", three, avx2_cpu);
  CHECK(not_carried.isa == Isa::avx2);
  CHECK(not_carried.warning_reason.find("carry") != std::string_view::npos);
  Isa const one[] = {Isa::sse2};
  CHECK(isa_from_environment("avx2", one, avx2_cpu).isa == Isa::sse2);
}

// Run by ctest with PLUME_ISA set (tests/CMakeLists.txt): the first call of the process reads
// it. Expected: the named set when this CPU runs it and the binary carries it, else the best.
TEST_CASE("dispatch: PLUME_ISA in the environment picks the set", "[dispatch_env]") {
  char const* value = std::getenv("PLUME_ISA");
  REQUIRE(value != nullptr);
  // The process's first call reads the variable; its warning (if any) goes to stderr, caught
  // here in a file.
  std::FILE* caught = std::tmpfile();
  REQUIRE(caught != nullptr);
  std::fflush(stderr);
  int const saved = dup(2);
  dup2(fileno(caught), 2);
  Isa const active = active_isa();
  std::fflush(stderr);
  dup2(saved, 2);
  close(saved);
  std::rewind(caught);
  std::string warning;
  for (int c; (c = std::fgetc(caught)) != EOF;)
    warning += char(c);
  std::fclose(caught);
  CAPTURE(value, warning);
  auto const wanted = isa_from_name(value);
  if (wanted && carried(*wanted) && cpu_has(*wanted)) {
    CHECK(active == *wanted);
    CHECK(warning.empty());
  } else {
    CHECK(active == best_isa());
    CHECK(warning.find("refused") != std::string::npos);
  }
  // Read once: a later change of the variable changes nothing.
  setenv("PLUME_ISA", "sse2", 1);
  CHECK(active_isa() == active);
}

TEST_CASE("dispatch: bad spans are refused and nothing is written", "[dispatch]") {
  std::vector<float> x(64, 0.5f), y(64, 2.0f), out(64, 7.0f), out2(64, 7.0f);
  auto const untouched = [](std::vector<float> const& v) {
    return std::all_of(v.begin(), v.end(), [](float f) { return f == 7.0f; });
  };
  std::span<float const> const xs(x), ys(y);
  // Lengths.
  CHECK(plume::sin(xs, std::span<float>(out).first(63)) == SpanError::length_mismatch);
  CHECK(plume::pow(xs, ys.first(10), out) == SpanError::length_mismatch);
  CHECK(plume::pow(xs.first(10), ys, std::span<float>(out).first(10)) ==
        SpanError::length_mismatch);
  CHECK(plume::sincos(xs, out, std::span<float>(out2).first(5)) == SpanError::length_mismatch);
  CHECK(untouched(out));
  CHECK(untouched(out2));
  // Overlap in part: refused; the same span (in place): computed.
  std::vector<double> d(100, 0.25);
  std::span<double> const all(d);
  CHECK(plume::exp(std::span<double const>(all.first(50)), all.subspan(1, 50)) ==
        SpanError::overlap);
  CHECK(plume::exp(std::span<double const>(all.subspan(10, 50)), all.first(50)) ==
        SpanError::overlap);
  CHECK(std::all_of(d.begin(), d.end(), [](double v) { return v == 0.25; }));
  std::vector<double> const other(40, 1.0);
  CHECK(plume::atan2(std::span<double const>(other), std::span<double const>(all.first(40)),
                     all.subspan(39, 40)) == SpanError::overlap); // the second input overlaps
  CHECK(plume::atan2(std::span<double const>(all.first(40)), std::span<double const>(other),
                     all.subspan(39, 40)) == SpanError::overlap); // the first
  CHECK(std::all_of(d.begin(), d.end(), [](double v) { return v == 0.25; }));
  std::vector<float> s(64, 7.0f);
  CHECK(plume::sincos(xs, std::span<float>(s).first(32), std::span<float>(s).last(32)) ==
        SpanError::length_mismatch);
  CHECK(plume::sincos(xs.first(32), std::span<float>(s).first(32),
                      std::span<float>(s).subspan(16, 32)) == SpanError::overlap);
  CHECK(plume::sincos(xs.first(32), std::span<float>(s).first(32), std::span<float>(s).first(32)) ==
        SpanError::overlap);
  CHECK(untouched(s));
  // Adjacent but not overlapping: fine.
  CHECK(plume::exp(std::span<double const>(all.first(50)), all.last(50)) == SpanError::none);
  CHECK(d[50] == plume::exp(0.25));
  // In place.
  std::vector<float> inplace(37, 0.5f);
  CHECK(plume::sin(std::span<float const>(inplace), std::span<float>(inplace)) == SpanError::none);
  CHECK(std::all_of(inplace.begin(), inplace.end(), [](float v) { return v == plume::sin(0.5f); }));
  std::vector<float> base(21, 2.0f), expo(21, 3.0f);
  CHECK(plume::pow(std::span<float const>(base), std::span<float const>(expo),
                   std::span<float>(expo)) == SpanError::none);
  CHECK(expo[20] == 8.0f);
  std::vector<float> sc(19, 1.0f), cs(19);
  CHECK(plume::sincos(std::span<float const>(sc), std::span<float>(sc), std::span<float>(cs)) ==
        SpanError::none);
  CHECK(sc[18] == plume::sin(1.0f));
  CHECK(cs[18] == plume::cos(1.0f));
  // Empty spans (null data included).
  CHECK(plume::log(std::span<float const>(), std::span<float>()) == SpanError::none);
  CHECK(plume::hypot(std::span<double const>(), std::span<double const>(), std::span<double>()) ==
        SpanError::none);
  CHECK(plume::sincos(std::span<double const>(), std::span<double>(), std::span<double>()) ==
        SpanError::none);
  CHECK(to_string(SpanError::overlap).find("overlap") != std::string_view::npos);
}
