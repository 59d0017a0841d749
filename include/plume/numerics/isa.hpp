// plume/numerics/isa.hpp - the instruction set behind plume's dispatched entry points: which
// sets a binary carries, which this CPU runs, and the choice among them.
//
// A build configured with PLUME_DISPATCH=ON compiles its dispatched entry points once per
// instruction set of its list (sse2, avx2, avx512: cmake/PlumeDispatch.cmake), everything else
// for the sse2 baseline, and picks a set at run time: the widest the CPU supports, the
// operating system included (AVX and AVX-512 need the OS to save their registers, which
// CPUID's OSXSAVE and XCR0 report). Any other build carries one set, its own (PLUME_SIMD;
// `native` counts as the widest family it enables), and the same entry points run that one.
// The dispatched entry points: World::step, the batch World::ray_cast and World::shape_cast,
// the math functions over spans (<plume/numerics/spans.hpp>) and the batch velocity
// projection, project_velocities (<plume/solver/character/project_velocities.hpp>).
//
// Choosing:
//  - by default, best_isa(): the widest carried set the CPU runs;
//  - the environment variable PLUME_ISA=sse2|avx2|avx512 (read once, at the first call of a
//    dispatched entry point, active_isa or set_isa): a set that is unknown, not carried or not
//    supported by this CPU is refused with one warning on stderr, and the default is used;
//  - set_isa(isa) at any time: refuses (returns the reason, changes nothing) a set that is not
//    carried or that the CPU lacks. A call that has started finishes on the set it began with,
//    the next one uses the new set (the switch itself is an atomic store).
//
// Determinism: with PLUME_DETERMINISTIC=ON (the default) every instruction set gives the same
// bits, so switching changes speed, never results.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

namespace plume {

/// An instruction set family, as plume's builds name them. `scalar` is the scalar build's
/// (no batches); a dispatched binary carries sse2, avx2 and avx512.
enum class Isa : std::uint8_t { scalar, sse2, avx2, avx512 };

/// "scalar", "sse2", "avx2", "avx512".
std::string_view isa_name(Isa isa) noexcept;
/// The Isa of a name isa_name gives; nullopt for anything else (case matters).
std::optional<Isa> isa_from_name(std::string_view name) noexcept;

/// True if this CPU and its operating system run code compiled for `isa`: every CPUID
/// feature the build's flags for it enable (avx2: SSE3..SSE4.2, POPCNT, XSAVE, AVX, AVX2;
/// avx512: those, FMA and F16C, which clang's -mavx512f enables, and AVX-512 F, CD, DQ, BW,
/// VL), and for avx2/avx512 the OS saving the
/// registers (XCR0's SSE and AVX state; for avx512 also the opmask and both ZMM parts).
bool cpu_has(Isa isa) noexcept;

/// The instruction sets this binary carries, narrowest first.
std::span<Isa const> compiled_isas() noexcept;
/// The widest compiled set this CPU runs (the default choice).
Isa best_isa() noexcept;
/// The set the array entry points use now.
Isa active_isa() noexcept;

enum class IsaError : std::uint8_t {
  none,
  not_compiled, ///< this binary does not carry that instruction set
  cpu_lacks,    ///< this CPU (or its operating system) cannot run it
};
std::string_view to_string(IsaError e) noexcept;

/// Makes `isa` the set the array entry points use. Refused (nothing changes) with
/// not_compiled or cpu_lacks.
[[nodiscard]] IsaError set_isa(Isa isa) noexcept;

namespace detail {
/// What CPUID and XGETBV report, reduced to what cpu_has needs (tests feed made-up CPUs).
struct CpuFeatures {
  bool sse2 = false, sse3 = false, ssse3 = false, sse41 = false, sse42 = false, popcnt = false;
  bool xsave = false, osxsave = false, avx = false, avx2 = false, fma = false, f16c = false;
  bool avx512f = false, avx512cd = false, avx512dq = false, avx512bw = false, avx512vl = false;
  std::uint64_t xcr0 = 0; ///< 0 when OSXSAVE is off (XGETBV not allowed)
};
/// This CPU's features (CPUID leaves 1 and 7, XGETBV when OSXSAVE is set).
CpuFeatures cpu_features() noexcept;
/// cpu_has for a given CPU.
bool cpu_runs(CpuFeatures const& cpu, Isa isa) noexcept;
/// The choice the environment variable's value makes: `value` (nullptr if unset) against the
/// compiled sets and the CPU. Returns the set to use and, when the value is refused, the
/// warning to print (empty otherwise).
struct EnvChoice {
  Isa isa;
  std::string_view warning_reason; ///< empty: accepted or unset
};
EnvChoice isa_from_environment(char const* value, std::span<Isa const> compiled,
                               CpuFeatures const& cpu) noexcept;
/// Lanes of the float batches the active span kernels run on (1, 4, 8 or 16): what tests
/// check to see that a switch changed the code that runs.
unsigned active_f32_lanes() noexcept;
/// For a floor's dispatched entry points: the position of active_isa() in compiled_isas(),
/// which is also the position of its kernel table in the floor's list (PLUME_DISPATCH_LIST).
std::size_t active_isa_index() noexcept;
} // namespace detail

} // namespace plume
