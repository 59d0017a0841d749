# Sourced by tests/run_all.sh and bench/report.sh: which build variants this CPU runs, and
# how a variant is configured and built (through CMakePresets.json).
#
#   plume_cpu_gate                 path of the cpu_gate program (tools/cpu_gate.cpp), compiled
#                                  here on first use, before any CMake build
#   plume_runnable_variants        the variants this CPU runs, narrowest first
#   plume_cpu_runs <variant>       status 0 if this CPU runs it
#   plume_configure <preset> <dir> [cmake args...]   cmake --preset <preset> -B <dir> ...
#   plume_build <dir>              cmake --build <dir> with one job per core

plume_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
plume_gate_bin=$plume_root/build/cpu_gate

plume_cpu_gate() {
  if [ ! -x "$plume_gate_bin" ] || [ "$plume_root/tools/cpu_gate.cpp" -nt "$plume_gate_bin" ]; then
    mkdir -p "$plume_root/build"
    c++ -O1 -o "$plume_gate_bin" "$plume_root/tools/cpu_gate.cpp" >&2 || return 1
  fi
  echo "$plume_gate_bin"
}

plume_runnable_variants() { "$(plume_cpu_gate)" --list; }

plume_cpu_runs() { "$(plume_cpu_gate)" "$1" >/dev/null; }

plume_configure() { # <preset> <dir> [cmake args...]
  local preset=$1 dir=$2
  shift 2
  mkdir -p "$(dirname "$dir")"
  cmake --preset "$preset" -S "$plume_root" -B "$dir" "$@" >"$dir.configure.log" 2>&1 || {
    cat "$dir.configure.log"
    return 1
  }
}

plume_build() { cmake --build "$1" -j "$(nproc 2>/dev/null || echo 2)"; }
