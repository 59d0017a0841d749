#!/usr/bin/env bash
# The README's main command: the width benchmark report.
#
#   bash bench/report.sh [extra Google Benchmark flags]
#
# Installs missing Debian packages (as root), builds the widest variant this CPU runs
# (avx512, else avx2, else sse2) with its benchmarks, runs every benchmark binary with
# repetitions, and prints the report: items/s for the same work at every width and for the
# peers (std, Eigen, SLEEF, xsimd), with ratios to plume x1 measured in the same run.
# Output: build/report/width_report.md, width_report.png and the raw JSON.
# PLUME_REPORT_REPS (default 5) and PLUME_REPORT_MIN_TIME (default 0.1 s) tune the run.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

bash tools/install_deps.sh

if grep -q avx512bw /proc/cpuinfo && grep -q avx512vl /proc/cpuinfo && grep -q avx512dq /proc/cpuinfo; then
  variant=avx512
elif grep -q avx2 /proc/cpuinfo; then
  variant=avx2
else
  variant=sse2
fi
dir=build/report-$variant
out=build/report
echo "plume: building the $variant variant in $dir"
cmake -S "$root" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DPLUME_SIMD=$variant \
  -DPLUME_BUILD_TESTS=OFF -DPLUME_BUILD_BENCH=ON >/dev/null
cmake --build "$dir" -j "$(nproc 2>/dev/null || echo 2)"

mkdir -p "$out"
rm -f "$out"/*.json
results=()
for b in "$dir"/bench/plume_bench_*; do
  [ -x "$b" ] || continue
  json="$out/$(basename "$b").json"
  echo "plume: running $(basename "$b")"
  "$b" --benchmark_repetitions="${PLUME_REPORT_REPS:-5}" --benchmark_report_aggregates_only=true \
    --benchmark_min_time="${PLUME_REPORT_MIN_TIME:-0.1}" --benchmark_out="$json" \
    --benchmark_out_format=json "$@" >/dev/null
  results+=("$json")
done
py=python3
[ -x /usr/bin/python3 ] && py=/usr/bin/python3 # the distribution's, with python3-matplotlib
"$py" bench/report.py "$out" "${results[@]}"
