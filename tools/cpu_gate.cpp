// cpu_gate: the one place that decides which build variants this CPU can run.
//
//   cpu_gate --list                  prints the variants this CPU runs (scalar sse2 avx2
//                                    avx512), one per line, narrowest first
//   cpu_gate <variant>               exit 0 if this CPU runs it, else prints why and exits 77
//   cpu_gate <variant> <program> [args...]
//                                    runs <program> if this CPU runs <variant>, else prints
//                                    why it is skipped and exits 77 (ctest's SKIP_RETURN_CODE)
//
// <variant> is a PLUME_SIMD value (scalar, sse2, avx2, avx512, native) or avx2-fma. Compiled
// without ISA flags, so it runs on every x86-64 CPU; the gated program (compiled with e.g.
// -mavx512f) is never started on a CPU that lacks it. The scripts (tests/run_all.sh,
// bench/report.sh) compile it on their own before any CMake build (tools/variants.sh);
// the tests' CMake build compiles it as plume_cpu_gate.
#include <cstdio>
#include <cstring>
#include <unistd.h>

namespace {

bool has(char const* isa) {
  __builtin_cpu_init();
  if (!std::strcmp(isa, "scalar") || !std::strcmp(isa, "sse2")) return true;
  if (!std::strcmp(isa, "avx2")) return __builtin_cpu_supports("avx2");
  if (!std::strcmp(isa, "avx2-fma"))
    return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  if (!std::strcmp(isa, "avx512"))
    return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
           __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
           __builtin_cpu_supports("avx512vl");
  return true; // native: built for this machine
}

constexpr char const* variants[] = {"scalar", "sse2", "avx2", "avx512"};

} // namespace

int main(int argc, char** argv) {
  if (argc == 2 && !std::strcmp(argv[1], "--list")) {
    for (char const* v : variants)
      if (has(v)) std::puts(v);
    return 0;
  }
  if (argc < 2) {
    std::fprintf(stderr, "usage: cpu_gate --list | <variant> [<program> [args...]]\n");
    return 2;
  }
  if (!has(argv[1])) {
    std::printf("SKIPPED: this CPU lacks the %s instructions the %s build needs\n", argv[1],
                argv[1]);
    return 77;
  }
  if (argc == 2) return 0;
  execv(argv[2], argv + 2);
  std::perror("cpu_gate: exec");
  return 2;
}
