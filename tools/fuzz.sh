#!/usr/bin/env bash
# Builds the fuzz targets (preset fuzz: clang, libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer, build/fuzz) and runs each for a bounded time.
#
#   bash tools/fuzz.sh [seconds per target, default 20] [target ...]
#   bash tools/fuzz.sh --runs <executions per target> [target ...]
#
# Each target starts from its committed seeds (tests/fuzz/corpus/<target>, read only) and
# keeps what it finds in build/fuzz/corpus/<target>, so a later run continues from there.
# --runs (CI's form) runs a fixed number of executions from the committed seeds only, with a
# fixed random seed, no corpus reload and no address randomisation, so that runs on one
# machine mostly repeat (not always: docs/fuzzing.md), and a slow machine takes longer
# instead of testing less. A failure's input is kept, and it reproduces from that.
# A crash, a sanitizer report or a broken property stops that target and leaves the input in
# build/fuzz/artifacts/; copy it into tests/fuzz/corpus/<target>/regress-<what> once fixed,
# and the ordinary tests run it from then on. Exit status 0 only if every target ran clean.
# Prints each target's executions and coverage (libFuzzer's last status line).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/variants.sh

if ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
  clang++ -x c++ -fsanitize=fuzzer - -o /dev/null 2>/dev/null; then
  echo "fuzz: clang++ cannot link libFuzzer here; on Debian: apt-get install clang-14 libclang-rt-14-dev" >&2
  exit 1
fi
runs=""
if [ "${1:-}" = --runs ]; then
  runs=${2:?--runs needs a count}
  shift 2
  secs=""
else
  secs=${1:-20}
  shift || true
fi
if ! plume_cpu_runs avx2; then
  echo "fuzz: skipped (the fuzz build is avx2 and this CPU lacks it)"
  exit 0
fi
plume_configure fuzz build/fuzz -DCMAKE_COMPILE_WARNING_AS_ERROR=ON
plume_build build/fuzz

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in build/fuzz/tests/fuzz/plume_fuzz_*; do
    [[ -x "$f" && "$f" != *_inputs ]] && targets+=("${f##*/plume_fuzz_}")
  done
fi
mkdir -p build/fuzz/artifacts
failed=()
for t in "${targets[@]}"; do
  log="build/fuzz/$t.log"
  if [ -n "$runs" ]; then
    # A fresh output folder each time: what an earlier run kept must not change this one.
    rm -rf "build/fuzz/corpus-ci/$t"
    mkdir -p "build/fuzz/corpus-ci/$t"
    # Also no corpus reload (-reload=0: libFuzzer rereads the output folder every second,
    # which makes a run depend on the machine's speed) and no address randomisation
    # (setarch -R: coverage features that depend on addresses differ from run to run).
    bound=(-runs="$runs" -seed=1 -reload=0)
    out="build/fuzz/corpus-ci/$t"
  else
    mkdir -p "build/fuzz/corpus/$t"
    bound=(-max_total_time="$secs")
    out="build/fuzz/corpus/$t"
  fi
  start_t=$(date +%s)
  # (setarch -R needs the personality system call, which some containers refuse: tried first.)
  fixed=(env)
  [ -n "$runs" ] && setarch "$(uname -m)" -R true 2>/dev/null && fixed=(setarch "$(uname -m)" -R)
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "${fixed[@]}" "build/fuzz/tests/fuzz/plume_fuzz_$t" "${bound[@]}" -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="build/fuzz/artifacts/$t-" \
    "$out" "tests/fuzz/corpus/$t" >"$log" 2>&1; then
    done_runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 || true)
    printf 'fuzz %-22s %10s executions in %ss, %s\n' "$t" "${done_runs:-?}" \
      "$(($(date +%s) - start_t))" "${cov:-cov: ?}"
  else
    echo "fuzz $t FAILED (log: $log):"
    tail -n 30 "$log"
    failed+=("$t")
  fi
done
if [ ${#failed[@]} -ne 0 ]; then
  printf 'fuzz: FAILED: %s\n' "${failed[@]}"
  exit 1
fi
