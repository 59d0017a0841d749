#!/usr/bin/env bash
# The README's main command: the width benchmark report.
#
#   bash bench/report.sh
#
# Installs missing Debian packages (as root), then builds the scalar, sse2, avx2 and avx512
# variants (those this CPU runs) with their benchmarks in build/report-<variant>, runs every
# benchmark binary with repetitions, and prints two tables:
#   across builds      plume's scalar build (x1) against each wide build at its widest width
#   within one build   the widest build: every width and the peers (std, Eigen, SLEEF, xsimd)
#                      with ratios to x1 measured in the same run
# Output: build/report/width_report.md, width_report.png (chart) and the raw JSON.
# PLUME_REPORT_REPS (default 5) and PLUME_REPORT_MIN_TIME (seconds, default 0.1) tune the run.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

bash tools/install_deps.sh

has() { grep -qw "$1" /proc/cpuinfo; }
variants=(scalar sse2)
has avx2 && variants+=(avx2)
has avx512f && has avx512bw && has avx512dq && has avx512cd && has avx512vl && variants+=(avx512)
widest=${variants[${#variants[@]} - 1]}

out=build/report
mkdir -p "$out"
rm -f "$out"/*.json
args=()
for v in "${variants[@]}"; do
  dir=build/report-$v
  echo "plume: building the $v variant in $dir"
  cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLUME_SIMD="$v" \
    -DPLUME_BUILD_TESTS=OFF -DPLUME_BUILD_BENCH=ON >/dev/null
  cmake --build "$dir" -j "$(nproc 2>/dev/null || echo 2)" >/dev/null
  # The peers are measured once, in the widest build; the other builds run plume only.
  filter=.
  [ "$v" = "$widest" ] || filter=/plume/
  for b in "$dir"/bench/plume_bench_*; do
    [ -x "$b" ] || continue
    json="$out/$v.$(basename "$b").json"
    echo "plume: running $v/$(basename "$b")"
    "$b" --benchmark_filter="$filter" --benchmark_repetitions="${PLUME_REPORT_REPS:-5}" \
      --benchmark_report_aggregates_only=true --benchmark_min_time="${PLUME_REPORT_MIN_TIME:-0.1}" \
      --benchmark_out="$json" --benchmark_out_format=json >/dev/null
    args+=("$v=$json")
  done
done
py=python3
[ -x /usr/bin/python3 ] && py=/usr/bin/python3 # the distribution's, with python3-matplotlib
"$py" bench/report.py "$out" "$widest" "${args[@]}"
