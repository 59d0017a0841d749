// cpu_gate <isa> <program> [args...]: runs <program> if this CPU has the instruction set the
// build variant <isa> needs, else prints why it is skipped and exits 77 (ctest's
// SKIP_RETURN_CODE). Compiled without any ISA flags, so it runs on every x86-64 CPU; the
// gated program (compiled with e.g. -mavx512f) is never started on a CPU that lacks it.
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
} // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: cpu_gate <isa> <program> [args...]\n");
    return 2;
  }
  if (!has(argv[1])) {
    std::printf("SKIPPED: this CPU lacks the %s instructions the %s build needs\n", argv[1],
                argv[1]);
    return 77;
  }
  execv(argv[2], argv + 2);
  std::perror("cpu_gate: exec");
  return 2;
}
