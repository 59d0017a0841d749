#!/usr/bin/env bash
# The README's main command: the width benchmark report.
#
#   bash bench/report.sh
#
# Installs missing Debian packages (as root), then builds the scalar, sse2, avx2 and avx512
# variants (those this CPU runs) with their benchmarks in build/report-<variant> and the
# dispatch variant's plume_bench_dispatch in build/report-dispatch, runs every benchmark binary
# of every build in rounds, and prints three tables:
#   across builds      plume's scalar build (x1) against each wide build at its widest width
#   within one build   the widest build: every width and the peers (std, Eigen, SLEEF, xsimd)
#                      with ratios to x1 measured in the same run
#   dispatched         each dispatched entry point in the one binary, per instruction set,
#                      against the same kernel in the static build of that set
# Each figure is the fastest of the rounds (bench/report.py says why). A round runs each
# benchmark binary in every build one after the other, so the builds compared across are
# measured seconds apart, and a slow phase of a shared machine (its clock drifts by 20-40%
# for minutes) falls on all of them rather than on the one build that happened to run then.
# Output: build/report/width_report.md, width_report.png (chart) and the raw JSON.
# PLUME_REPORT_ROUNDS (default 5), PLUME_REPORT_REPS (repetitions per round, default 1) and
# PLUME_REPORT_MIN_TIME (seconds, default 0.1) tune the run; PLUME_REPORT_VARIANTS (e.g.
# "scalar avx2") keeps only those of the runnable variants.
# Each build is its CMakePresets.json preset with the tests off; which variants this CPU
# runs is decided in one place, tools/cpu_gate.cpp (via tools/variants.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
source tools/variants.sh

bash tools/install_deps.sh

mapfile -t variants < <(plume_runnable_variants)
if [ -n "${PLUME_REPORT_VARIANTS:-}" ]; then # a subset, e.g. "scalar avx2" (a quicker report)
  chosen=()
  for v in "${variants[@]}"; do
    [[ " $PLUME_REPORT_VARIANTS " == *" $v "* ]] && chosen+=("$v")
  done
  [ ${#chosen[@]} -gt 0 ] || { echo "plume: none of PLUME_REPORT_VARIANTS ($PLUME_REPORT_VARIANTS) runs here"; exit 1; }
  variants=("${chosen[@]}")
fi
widest=${variants[${#variants[@]} - 1]}

out=build/report
mkdir -p "$out"
rm -f "$out"/*.json
args=()
for v in "${variants[@]}"; do
  dir=build/report-$v
  echo "plume: building the $v variant in $dir"
  plume_configure "$v" "$dir" -DPLUME_BUILD_TESTS=OFF
  plume_build "$dir" >/dev/null
done
# The dispatch build (one binary, kernels per instruction set chosen at run time): only its
# plume_bench_dispatch, whose dispatched/<isa> figures the report sets beside the static
# builds' static/<isa> ones.
ddir=build/report-dispatch
if plume_cpu_runs sse2; then
  echo "plume: building the dispatch variant's plume_bench_dispatch in $ddir"
  plume_configure dispatch "$ddir" -DPLUME_BUILD_TESTS=OFF
  cmake --build "$ddir" -j "$(nproc 2>/dev/null || echo 2)" --target plume_bench_dispatch >/dev/null
fi
rounds=${PLUME_REPORT_ROUNDS:-5}
for ((r = 1; r <= rounds; r++)); do
  echo "plume: round $r of $rounds"
  for bin in build/report-"$widest"/bench/plume_bench_*; do
    [ -x "$bin" ] || continue
    name=$(basename "$bin")
    for v in "${variants[@]}"; do
      b=build/report-$v/bench/$name
      [ -x "$b" ] || continue
      # The peers are measured in the widest build only; the other builds run plume only
      # (plume_bench_dispatch has no peers: every build runs all of it).
      filter=.
      [ "$v" = "$widest" ] || [ "$name" = plume_bench_dispatch ] || filter=/plume/
      json="$out/$v.$name.r$r.json"
      "$b" --benchmark_filter="$filter" --benchmark_repetitions="${PLUME_REPORT_REPS:-1}" \
        --benchmark_report_aggregates_only=true --benchmark_min_time="${PLUME_REPORT_MIN_TIME:-0.1}" \
        --benchmark_out="$json" --benchmark_out_format=json >/dev/null
      args+=("$v=$json")
    done
    if [ "$name" = plume_bench_dispatch ] && [ -x "$ddir/bench/$name" ]; then
      json="$out/dispatch.$name.r$r.json"
      "$ddir/bench/$name" --benchmark_repetitions="${PLUME_REPORT_REPS:-1}" \
        --benchmark_report_aggregates_only=true --benchmark_min_time="${PLUME_REPORT_MIN_TIME:-0.1}" \
        --benchmark_out="$json" --benchmark_out_format=json >/dev/null
      args+=("dispatch=$json")
    fi
  done
done
py=python3
[ -x /usr/bin/python3 ] && py=/usr/bin/python3 # the distribution's, with python3-matplotlib
"$py" bench/report.py "$out" "$widest" "${args[@]}"
