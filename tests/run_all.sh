#!/usr/bin/env bash
# The README's test command: builds every variant and runs every test.
#
#   bash tests/run_all.sh
#
# 1. installs the Debian packages that are missing (as root; see tools/install_deps.sh);
# 2. configures, builds (warnings are errors here) and tests the scalar, sse2, avx2 and
#    avx512 variants - tests of an instruction set this CPU lacks are reported as skipped;
#    the sse2 variant is the dispatch build (one binary, kernels per instruction set), which
#    also runs its dispatch tests and install;
# 3. an AddressSanitizer + UndefinedBehaviorSanitizer build (avx2), tests only;
#    a ThreadSanitizer build of the threaded step's test (sse2);
#    a clang build (avx2), tests only, which also builds the fuzz targets and runs each for a
#    fixed number of executions (tools/fuzz.sh --runs);
# 4. the cross-build determinism check: every deterministic build that ran (g++ and clang)
#    must print the same golden hashes (each also compares with tests/determinism/golden.txt);
# 5. every benchmark binary of the scalar and the widest variant, once, with a tiny time budget,
#    and the dispatch build's plume_bench_dispatch (every set this CPU runs);
# 6. the generated code of the hot wide kernels (tools/kernel_loops.py): no calls out of line.
# Every build is a preset of CMakePresets.json (build folder build/ci-<preset>), and which
# variants this CPU runs is decided in one place, tools/cpu_gate.cpp (via tools/variants.sh).
# Exit status 0 only if everything passed.
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/variants.sh

bash tools/install_deps.sh

jobs=$(nproc 2>/dev/null || echo 2)
variants=(scalar sse2 avx2 avx512)
failed=()
start=$(date +%s)

# Each stage's heading gives the time since the start and the CPU time (user, system) of
# everything run so far, which a busy machine changes much less than the elapsed time.
step() {
  local cpu
  times >build/.times # a builtin with a redirection runs in this shell, not a subshell
  cpu=$(tail -n 1 build/.times)
  printf '\n=== %s (%ds; cpu so far %s; %s free on disk, builds %s)\n' "$*" $(($(date +%s) - start)) \
    "$cpu" "$(df -h --output=avail build | tail -n 1 | tr -d ' ')" "$(du -sh build | cut -f1)"
}

# prune <build dir>: once a build's tests have run, its precompiled headers and object files
# go (the later stages use only its linked programs and build.ninja). They are nine tenths of
# a build folder (about 1.1 of 1.2 GB, mostly the test targets' precompiled headers), and the
# seven builds kept whole took 8.2 GB, more than a CI machine had free once. The next run of
# this command rebuilds what it removed; PLUME_KEEP_OBJECTS=1 keeps them for incremental runs.
prune() {
  [ "${PLUME_KEEP_OBJECTS:-0}" = 1 ] && return 0
  find "$1" \( -name '*.gch' -o -name '*.o' \) -type f -delete
}

configure_build() { # <preset> [cmake args...]: build/ci-<preset>, warnings are errors
  local preset=$1
  shift
  configure_build_in "$preset" "build/ci-$preset" "$@"
}

configure_build_in() { # <preset> <dir> [cmake args...]: warnings are errors
  local preset=$1 dir=$2
  shift 2
  plume_configure "$preset" "$dir" -DCMAKE_COMPILE_WARNING_AS_ERROR=ON "$@" && plume_build "$dir"
}

configure_build_target() { # <preset> <target>: build/ci-<preset>, only that test target
  plume_configure "$1" "build/ci-$1" -DCMAKE_COMPILE_WARNING_AS_ERROR=ON &&
    cmake --build "build/ci-$1" -j "$jobs" --target plume_cpu_gate "$2" # ctest runs tests through the gate
}

mkdir -p build
# The benchmarks run in the scalar build and the widest build this CPU runs (stage 5); the
# variants between would compile the same benchmark sources and never run them, so they
# leave them out of their build. A variant this CPU cannot run builds them: its only check
# is that everything compiles.
widest=scalar
for v in "${variants[@]}"; do
  plume_cpu_runs "$v" && widest=$v
done
for v in "${variants[@]}"; do
  step "variant $v: build"
  # Each wide variant tests its own width (tests/common/types.hpp): every width is tested in
  # the build whose width it is, the scalar types in the scalar build.
  # The examples (docs/examples) are built and run once, in the scalar variant.
  examples=OFF
  [ "$v" = scalar ] && examples=ON
  skip_bench=OFF
  [ "$v" != scalar ] && [ "$v" != "$widest" ] && plume_cpu_runs "$v" && skip_bench=ON
  # The sse2 variant is built as the dispatch build (preset dispatch: the sse2 build, plus
  # World::step, the batch casts and the math functions over spans compiled once more for
  # sse2, avx2 and avx512, chosen at run time). Its tests run with PLUME_ISA=sse2, so every
  # dispatched call takes the sse2 kernels and the variant tests what the sse2 build would;
  # then its dispatch tests run every carried set this CPU runs against the scalar path in one
  # process (the others reported as skipped), install it into the consumer project (static
  # and shared) and check that no AVX instruction sits outside its per-set kernels. The avx512
  # kernels compile (and are isolated) on any machine.
  preset=$v
  [ "$v" = sse2 ] && preset=dispatch
  if ! configure_build_in "$preset" "build/ci-$v" -DPLUME_TEST_TYPES=native \
    -DPLUME_BUILD_EXAMPLES=$examples -DPLUME_BENCH_EXCLUDE_FROM_ALL=$skip_bench; then
    failed+=("$v build")
    continue
  fi
  # The dispatch build's one benchmark, the width report's dispatched column (stage 5 runs it).
  if [ "$preset" = dispatch ] && ! cmake --build "build/ci-$v" -j "$jobs" --target plume_bench_dispatch; then
    failed+=("$v plume_bench_dispatch build")
  fi
  step "variant $v: tests"
  if [ "$preset" = dispatch ]; then
    PLUME_ISA=sse2 ctest --test-dir "build/ci-$v" --output-on-failure -j "$jobs" -E dispatch ||
      failed+=("$v tests")
    ctest --test-dir "build/ci-$v" --output-on-failure -j "$jobs" -R dispatch || failed+=("dispatch tests")
  else
    ctest --test-dir "build/ci-$v" --output-on-failure -j "$jobs" || failed+=("$v tests")
  fi
  prune "build/ci-$v"
done

step "sanitizers (address, undefined): build"
# The preset builds at -O0 -g1: optimising the sanitizers' instrumentation of the
# lane-exactness tests takes ten times longer (over 8 minutes per math test file at -O1 on
# 2 cores); at -O0 PLUME_INLINE does not force inlining (config.hpp), and -g1 keeps line
# numbers in reports.
if configure_build sanitize; then
  step "sanitizers: tests"
  ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    ctest --test-dir build/ci-sanitize --output-on-failure -j "$jobs" || failed+=("sanitize tests")
  prune build/ci-sanitize
else
  failed+=("sanitize build")
fi

step "thread sanitizer: build (the threaded step's test)"
# Only plume_thread_tests and the libraries (tests/world/test_threads.cpp): the world stepped
# on 1, 2 and 8 threads and by random range orders, and the pool under several callers. A race
# halts the test with TSan's report. The sse2 variant: every x86-64 CPU runs it, so the
# stage never skips.
if configure_build_target tsan plume_thread_tests; then
  step "thread sanitizer: tests"
  TSAN_OPTIONS="halt_on_error=1 exitcode=66" \
    ctest --test-dir build/ci-tsan -R '^threads$' --output-on-failure || failed+=("tsan tests")
  prune build/ci-tsan
else
  failed+=("tsan build")
fi

step "clang (avx2): build, with the fuzz targets"
# Tests only, for the widest widths (each lane checked against clang's scalar path): the
# clang build looks for what another compiler rejects or computes differently; the g++
# builds cover the benchmarks and the scalar types' own tests. The same build carries the
# fuzz targets (PLUME_FUZZ=ON: libFuzzer's coverage instrumentation in every target, which
# changes no result), so that fuzzing costs no build of its own: the fuzz preset's
# AddressSanitizer and UndefinedBehaviorSanitizer at -O1 made every compilation 4-5 times
# longer (docs/performance.md, "CI time"), and the sanitizer stage above replays every
# committed input under both.
if command -v clang++ >/dev/null &&
  configure_build clang-avx2 -DPLUME_TEST_TYPES=native -DPLUME_BUILD_BENCH=OFF -DPLUME_FUZZ=ON; then
  step "clang (avx2): tests"
  ctest --test-dir build/ci-clang-avx2 --output-on-failure -j "$jobs" || failed+=("clang tests")
  step "fuzzing: a fixed number of executions per target"
  # From the committed corpus with a fixed seed (tools/fuzz.sh), two targets at a time. A
  # failure leaves its input in build/ci-clang-avx2/artifacts/ (docs/fuzzing.md: what to do).
  bash tools/fuzz.sh --build build/ci-clang-avx2 --jobs "$jobs" --runs "${PLUME_CI_FUZZ_RUNS:-20000}" ||
    failed+=("fuzzing")
  prune build/ci-clang-avx2
else
  failed+=("clang build")
fi

step "cross-build determinism"
ref=""
for v in "${variants[@]}" clang-avx2; do
  g=build/ci-$v/tests/plume_golden
  [ -x "$g" ] || continue
  if ! plume_cpu_runs "${v#clang-}"; then
    echo "determinism: $v skipped (this CPU lacks its instruction set)"
    continue
  fi
  "$g" >"build/ci-$v/golden.txt"
  if [ -z "$ref" ]; then
    ref=$v
    echo "determinism: $v is the reference"
  elif diff -u "build/ci-$ref/golden.txt" "build/ci-$v/golden.txt"; then
    echo "determinism: $v matches $ref"
  else
    failed+=("determinism $ref vs $v")
  fi
done

step "benchmarks, once each"
# The scalar build and the widest build this CPU runs (found above): every benchmark binary
# once. The variants between compile the same benchmark sources, so running them would add
# time and no code path; the sse2 variant (the dispatch build) has built only its own,
# plume_bench_dispatch.
bench_variants=(scalar)
[ "$widest" != scalar ] && bench_variants+=("$widest")
bench_bins=()
for v in "${bench_variants[@]}"; do
  bench_bins+=(build/ci-$v/bench/plume_bench_*)
done
# The dispatch build (the sse2 variant) built only its own benchmark.
[ "$widest" != sse2 ] && plume_cpu_runs sse2 && bench_bins+=(build/ci-sse2/bench/plume_bench_dispatch)
# Two at a time on two cores (each runs on one thread but the world's two-thread cases): the
# run checks that every benchmark runs, not its figures.
rm -f build/.bench_failed
for b in "${bench_bins[@]}"; do
  if [ -x "$b" ]; then printf '%s\0' "$b"; fi
done | xargs -0 -r -P "$jobs" -I{} sh -c \
  'echo "bench: $1"; "$1" --benchmark_min_time=0.001 --benchmark_format=json >"$1.smoke.json" ||
     echo "$1" >>build/.bench_failed' _ {}
if [ -f build/.bench_failed ]; then
  while read -r b; do failed+=("$b"); done <build/.bench_failed
fi

step "kernel loops: the generated code of the hot kernels"
# Instructions, stack references and calls per iteration of each hot wide kernel, compiled
# with the avx2 and avx512 builds' flags; a wide kernel that calls out of line fails.
for v in avx2 avx512; do
  [ -f "build/ci-$v/build.ninja" ] || continue
  echo "kernel loops: $v"
  python3 tools/kernel_loops.py "build/ci-$v" --no-calls || failed+=("kernel loops $v")
done

step "done"
if [ ${#failed[@]} -ne 0 ]; then
  printf 'FAILED: %s\n' "${failed[@]}"
  exit 1
fi
echo "all variants built, all tests passed"
