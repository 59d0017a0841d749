#!/usr/bin/env bash
# Builds the fuzz targets (preset fuzz: clang, libFuzzer, AddressSanitizer and
# UndefinedBehaviorSanitizer, build/fuzz) and runs each for a bounded time.
#
#   bash tools/fuzz.sh [options] [seconds per target, default 20] [target ...]
#   bash tools/fuzz.sh [options] --runs <executions per target> [target ...]
#
# Options (before the rest):
#   --build <dir>  run the targets of a build configured elsewhere with PLUME_FUZZ=ON (CI's
#                  clang build, tests/run_all.sh) instead of configuring the fuzz preset;
#                  the build is brought up to date, its logs and artifacts go under <dir>
#   --jobs <n>     run up to n targets at a time (default 1; each target is one process)
#
# Each target starts from its committed seeds (tests/fuzz/corpus/<target>, read only) and
# keeps what it finds in <build>/corpus/<target>, so a later run continues from there.
# --runs (CI's form) runs a fixed number of executions from the committed seeds only, with a
# fixed random seed, no corpus reload and no address randomisation, so that runs on one
# machine of one build mostly repeat (not always: docs/fuzzing.md), and a slow machine takes
# longer instead of testing less. A failure's input is kept, and it reproduces from that.
# A crash, a sanitizer report or a broken property stops that target and leaves the input in
# <build>/artifacts/; copy it into tests/fuzz/corpus/<target>/regress-<what> once fixed,
# and the ordinary tests run it from then on. Exit status 0 only if every target ran clean.
# Prints each target's executions and coverage (libFuzzer's last status line).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/variants.sh

build=""
jobs=1
while [ $# -gt 0 ]; do
  case "$1" in
  --build)
    build=${2:?--build needs a build folder}
    shift 2
    ;;
  --jobs)
    jobs=${2:?--jobs needs a count}
    shift 2
    ;;
  *) break ;;
  esac
done
runs=""
if [ "${1:-}" = --runs ]; then
  runs=${2:?--runs needs a count}
  shift 2
  secs=""
else
  secs=${1:-20}
  shift || true
fi

if [ -z "$build" ]; then
  if ! echo 'extern "C" int LLVMFuzzerTestOneInput(const char*, unsigned long) { return 0; }' |
    clang++ -x c++ -fsanitize=fuzzer - -o /dev/null 2>/dev/null; then
    echo "fuzz: clang++ cannot link libFuzzer here; on Debian: apt-get install clang-14 libclang-rt-14-dev" >&2
    exit 1
  fi
  build=build/fuzz
  plume_configure fuzz "$build" -DCMAKE_COMPILE_WARNING_AS_ERROR=ON
elif ! grep -q '^PLUME_FUZZ:BOOL=ON' "$build/CMakeCache.txt" 2>/dev/null; then
  echo "fuzz: $build is not a build configured with PLUME_FUZZ=ON" >&2
  exit 1
fi
isa=$(sed -n 's/^PLUME_SIMD:[A-Z]*=//p' "$build/CMakeCache.txt")
if ! plume_cpu_runs "$isa"; then
  echo "fuzz: skipped (the build is $isa and this CPU lacks it)"
  exit 0
fi
plume_build "$build"

targets=("$@")
if [ ${#targets[@]} -eq 0 ]; then
  for f in "$build"/tests/fuzz/plume_fuzz_*; do
    [[ -x "$f" && "$f" != *_inputs ]] && targets+=("${f##*/plume_fuzz_}")
  done
fi
mkdir -p "$build/artifacts"

# run_target <target>: runs it, prints one line (or the failure and its log's tail), and
# leaves <build>/<target>.failed on failure.
run_target() {
  local t=$1 log="$build/$1.log" out bound fixed start_t done_runs cov
  rm -f "$build/$t.failed"
  if [ -n "$runs" ]; then
    # A fresh output folder each time: what an earlier run kept must not change this one.
    out="$build/corpus-ci/$t"
    rm -rf "$out"
    mkdir -p "$out"
    # Also no corpus reload (-reload=0: libFuzzer rereads the output folder every second,
    # which makes a run depend on the machine's speed) and no address randomisation
    # (setarch -R: coverage features that depend on addresses differ from run to run).
    bound=(-runs="$runs" -seed=1 -reload=0)
  else
    out="$build/corpus/$t"
    mkdir -p "$out"
    bound=(-max_total_time="$secs")
  fi
  start_t=$(date +%s)
  # (setarch -R needs the personality system call, which some containers refuse: tried first.)
  fixed=(env)
  [ -n "$runs" ] && setarch "$(uname -m)" -R true 2>/dev/null && fixed=(setarch "$(uname -m)" -R)
  if ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
    "${fixed[@]}" "$build/tests/fuzz/plume_fuzz_$t" "${bound[@]}" -rss_limit_mb=2048 -timeout=10 \
    -print_final_stats=1 -artifact_prefix="$build/artifacts/$t-" \
    "$out" "tests/fuzz/corpus/$t" >"$log" 2>&1; then
    done_runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || true)
    cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 || true)
    printf 'fuzz %-22s %10s executions in %ss, %s\n' "$t" "${done_runs:-?}" \
      "$(($(date +%s) - start_t))" "${cov:-cov: ?}"
  else
    # One write, so that targets running side by side do not interleave their reports.
    printf 'fuzz %s FAILED (log: %s):\n%s\n' "$t" "$log" "$(tail -n 30 "$log")"
    touch "$build/$t.failed"
  fi
}

running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then
    wait -n || true
    running=$((running - 1))
  fi
  run_target "$t" &
  running=$((running + 1))
done
wait || true

failed=()
for t in "${targets[@]}"; do
  [ -f "$build/$t.failed" ] && failed+=("$t")
done
if [ ${#failed[@]} -ne 0 ]; then
  printf 'fuzz: FAILED: %s\n' "${failed[@]}"
  exit 1
fi
