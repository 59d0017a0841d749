// numerics/isa.cpp - the choice of instruction set for every floor's dispatched entry points
// (include/plume/numerics/isa.hpp): the CPU's features, the environment, set_isa.
//
// Compiled with the build's baseline flags (sse2 in a PLUME_DISPATCH=ON build): nothing here
// may need more than the CPU every x86-64 has. The carried sets are those of the numerics
// floor's span kernel tables, in the order of PLUME_DISPATCH_LIST, which every floor's tables
// follow.
#include "span_kernels.hpp"

#include <plume/numerics/isa.hpp>
#include <plume_dispatch_list.hpp>

#if defined(__x86_64__) || defined(__i386__)
#include <cpuid.h>
#define PLUME_X86 1
#else
#define PLUME_X86 0
#endif

#include <array>
#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <mutex>

#define PLUME_DECLARE_TABLE(suffix)                                                                \
  extern "C" plume::detail::SpanKernels const* plume_numerics_table_##suffix() noexcept;
PLUME_DISPATCH_LIST(PLUME_DECLARE_TABLE)
#undef PLUME_DECLARE_TABLE

namespace plume {
namespace {

using Accessor = detail::SpanKernels const* (*)() noexcept;
#define PLUME_ACCESSOR(suffix) &plume_numerics_table_##suffix,
constexpr Accessor accessors[] = {PLUME_DISPATCH_LIST(PLUME_ACCESSOR)};
#undef PLUME_ACCESSOR
constexpr std::size_t carried_count = std::size(accessors);

// The carried sets, read from the tables (an accessor only returns an address: calling the
// avx512 one is safe on any CPU, and tools/check_isa_leaks.py checks that it has no AVX
// instruction).
std::array<Isa, carried_count> const& carried() noexcept {
  static std::array<Isa, carried_count> const list = [] {
    std::array<Isa, carried_count> l{};
    for (std::size_t i = 0; i < carried_count; ++i)
      l[i] = accessors[i]()->isa;
    return l;
  }();
  return list;
}

int index_of(Isa isa) noexcept {
  for (std::size_t i = 0; i < carried_count; ++i)
    if (carried()[i] == isa) return static_cast<int>(i);
  return -1;
}

std::atomic<int> active_index{-1};

Isa best_of(std::span<Isa const> list, detail::CpuFeatures const& cpu) noexcept {
  Isa best = list.front(); // the narrowest: sse2 in a dispatched binary, which every x86-64 runs
  for (Isa i : list)
    if (detail::cpu_runs(cpu, i)) best = i;
  return best;
}

// The first call of anything dispatched: the environment's choice, or the best set.
int initialize() noexcept {
  static std::once_flag once;
  std::call_once(once, [] {
    char const* value = std::getenv("PLUME_ISA");
    detail::EnvChoice const c =
        detail::isa_from_environment(value, carried(), detail::cpu_features());
    if (!c.warning_reason.empty())
      std::fprintf(stderr, "plume: PLUME_ISA=%s refused (%.*s); using %.*s\n", value,
                   static_cast<int>(c.warning_reason.size()), c.warning_reason.data(),
                   static_cast<int>(isa_name(c.isa).size()), isa_name(c.isa).data());
    // set_isa calls initialize() first, so nothing has chosen yet.
    active_index.store(index_of(c.isa), std::memory_order_release);
  });
  return active_index.load(std::memory_order_acquire);
}

} // namespace

// ------------------------------------------------------------------------------- the CPU
namespace detail {

CpuFeatures cpu_features() noexcept {
  CpuFeatures f;
#if PLUME_X86
  unsigned a = 0, b = 0, c = 0, d = 0;
  if (__get_cpuid(1, &a, &b, &c, &d) == 0) return f;
  f.sse2 = (d >> 26) & 1;
  f.sse3 = (c >> 0) & 1;
  f.ssse3 = (c >> 9) & 1;
  f.sse41 = (c >> 19) & 1;
  f.sse42 = (c >> 20) & 1;
  f.popcnt = (c >> 23) & 1;
  f.xsave = (c >> 26) & 1;
  f.osxsave = (c >> 27) & 1;
  f.avx = (c >> 28) & 1;
  f.fma = (c >> 12) & 1;
  f.f16c = (c >> 29) & 1;
  if (__get_cpuid_count(7, 0, &a, &b, &c, &d) != 0) {
    f.avx2 = (b >> 5) & 1;
    f.avx512f = (b >> 16) & 1;
    f.avx512dq = (b >> 17) & 1;
    f.avx512cd = (b >> 28) & 1;
    f.avx512bw = (b >> 30) & 1;
    f.avx512vl = (b >> 31) & 1;
  }
  if (f.osxsave) {
    // XGETBV with ECX = 0 reads XCR0, the register state the OS saves (written as an asm
    // statement: the intrinsic needs -mxsave, which the baseline flags do not enable).
    std::uint32_t lo = 0, hi = 0;
    __asm__ volatile("xgetbv" : "=a"(lo), "=d"(hi) : "c"(0));
    f.xcr0 = (std::uint64_t(hi) << 32) | lo;
  }
#endif
  return f; // not x86: no set but scalar (the scalar build's)
}

bool cpu_runs(CpuFeatures const& f, Isa isa) noexcept {
  constexpr std::uint64_t sse_avx_state = 0x6; // XCR0 bits 1 (SSE) and 2 (AVX)
  constexpr std::uint64_t avx512_state = 0xe0; // bits 5..7: opmask, ZMM0-15 high, ZMM16-31
  bool const avx2 = f.sse2 && f.sse3 && f.ssse3 && f.sse41 && f.sse42 && f.popcnt && f.xsave &&
                    f.osxsave && f.avx && f.avx2 && (f.xcr0 & sse_avx_state) == sse_avx_state;
  switch (isa) {
  case Isa::scalar:
    return true;
  case Isa::sse2:
    return f.sse2;
  case Isa::avx2:
    return avx2;
  case Isa::avx512:
    return avx2 && f.fma && f.f16c && f.avx512f && f.avx512cd && f.avx512dq && f.avx512bw &&
           f.avx512vl && (f.xcr0 & avx512_state) == avx512_state;
  }
  return false;
}

EnvChoice isa_from_environment(char const* value, std::span<Isa const> list,
                               CpuFeatures const& cpu) noexcept {
  Isa const best = best_of(list, cpu);
  if (value == nullptr || *value == '\0') return {best, {}};
  std::optional<Isa> const wanted = isa_from_name(value);
  if (!wanted) return {best, "not an instruction set: sse2, avx2 or avx512"};
  bool found = false;
  for (Isa i : list)
    found = found || i == *wanted;
  if (!found) return {best, "this binary does not carry it"};
  if (!cpu_runs(cpu, *wanted)) return {best, "this CPU or its operating system lacks it"};
  return {*wanted, {}};
}

std::size_t active_isa_index() noexcept {
  int const i = active_index.load(std::memory_order_acquire);
  return static_cast<std::size_t>(i >= 0 ? i : initialize());
}

SpanKernels const& span_kernels() noexcept { return *accessors[active_isa_index()](); }

unsigned active_f32_lanes() noexcept { return span_kernels().f32_lanes; }

} // namespace detail

// --------------------------------------------------------------------------- the choice
std::string_view isa_name(Isa isa) noexcept {
  switch (isa) {
  case Isa::scalar:
    return "scalar";
  case Isa::sse2:
    return "sse2";
  case Isa::avx2:
    return "avx2";
  case Isa::avx512:
    return "avx512";
  }
  return "unknown";
}

std::optional<Isa> isa_from_name(std::string_view name) noexcept {
  for (Isa i : {Isa::scalar, Isa::sse2, Isa::avx2, Isa::avx512})
    if (name == isa_name(i)) return i;
  return std::nullopt;
}

bool cpu_has(Isa isa) noexcept {
  static detail::CpuFeatures const cpu = detail::cpu_features();
  return detail::cpu_runs(cpu, isa);
}

std::span<Isa const> compiled_isas() noexcept { return carried(); }

Isa best_isa() noexcept {
  static Isa const best = best_of(carried(), detail::cpu_features());
  return best;
}

Isa active_isa() noexcept { return carried()[detail::active_isa_index()]; }

std::string_view to_string(IsaError e) noexcept {
  switch (e) {
  case IsaError::none:
    return "none";
  case IsaError::not_compiled:
    return "set_isa: this binary does not carry that instruction set";
  case IsaError::cpu_lacks:
    return "set_isa: this CPU (or its operating system) cannot run that instruction set";
  }
  return "set_isa: unknown error";
}

IsaError set_isa(Isa isa) noexcept {
  initialize(); // the environment is read once, before any explicit choice
  int const i = index_of(isa);
  if (i < 0) return IsaError::not_compiled;
  if (!cpu_has(isa)) return IsaError::cpu_lacks;
  active_index.store(i, std::memory_order_release);
  return IsaError::none;
}

} // namespace plume
