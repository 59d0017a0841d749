#!/usr/bin/env python3
"""plume's width report: reads Google Benchmark JSON files and prints, for every benchmark
case, items/s of each implementation and width and the ratio to plume's scalar (x1) figure
measured in the same run.

Benchmark names follow  <case...>/<type>/<implementation>/x<width>  (see bench/*/); with
repetitions the median is used. Usage:
    report.py OUT_DIR RESULT.json [RESULT.json ...]
writes OUT_DIR/width_report.md (the table also goes to stdout) and, when matplotlib is
available, OUT_DIR/width_report.png (speed-up over plume x1 per case and width).
"""
import json
import os
import statistics
import sys
from collections import OrderedDict, defaultdict


def load(paths):
    runs = defaultdict(list)  # (case, impl, width) -> [items/s]
    context = None
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        context = context or data.get("context", {})
        for b in data.get("benchmarks", []):
            if b.get("run_type") == "aggregate" and b.get("aggregate_name") != "median":
                continue
            ips = b.get("items_per_second")
            if ips is None:
                continue
            name = b.get("run_name", b["name"])
            parts = name.split("/")
            if len(parts) < 4 or not parts[-1].startswith("x"):
                continue
            case = "/".join(parts[:-2])
            runs[(case, parts[-2], int(parts[-1][1:]))].append(float(ips))
    table = OrderedDict()
    for (case, impl, width), vals in runs.items():
        table.setdefault(case, {})[(impl, width)] = statistics.median(vals)
    return table, context or {}


def human(v):
    for unit, scale in (("G", 1e9), ("M", 1e6), ("k", 1e3)):
        if v >= scale:
            return f"{v / scale:.3g}{unit}"
    return f"{v:.3g}"


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    out_dir = sys.argv[1]
    table, ctx = load(sys.argv[2:])
    os.makedirs(out_dir, exist_ok=True)
    cols = sorted({k for row in table.values() for k in row},
                  key=lambda k: (k[0] != "plume", k[0], k[1]))
    lines = []
    host = ctx.get("host_name", "?")
    lines.append(f"# plume width report\n")
    lines.append(f"Machine: {host}, {ctx.get('num_cpus', '?')} CPUs at "
                 f"{ctx.get('mhz_per_cpu', '?')} MHz; {ctx.get('date', '')}. Figures are "
                 "items/s (median of the repetitions); in brackets the ratio to plume x1 "
                 "of the same case in the same run.\n")
    header = "| case | " + " | ".join(f"{i} x{w}" for i, w in cols) + " |"
    lines.append(header)
    lines.append("|" + "---|" * (len(cols) + 1))
    for case, row in table.items():
        base = row.get(("plume", 1))
        cells = []
        for c in cols:
            v = row.get(c)
            if v is None:
                cells.append("")
            elif base:
                cells.append(f"{human(v)} ({v / base:.2f}x)")
            else:
                cells.append(human(v))
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    text = "\n".join(lines) + "\n"
    print(text)
    with open(os.path.join(out_dir, "width_report.md"), "w") as f:
        f.write(text)
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("(matplotlib not available: no chart)")
        return 0
    plume_cols = [c for c in cols if c[0] == "plume"]
    cases = [c for c in table if ("plume", 1) in table[c]]
    if not cases:
        return 0
    fig, ax = plt.subplots(figsize=(max(8, 0.6 * len(cases)), 5))
    width = 0.8 / max(1, len(plume_cols))
    for j, c in enumerate(plume_cols):
        ys = [table[k].get(c, 0) / table[k][("plume", 1)] for k in cases]
        ax.bar([i + j * width for i in range(len(cases))], ys, width, label=f"plume x{c[1]}")
    ax.set_xticks([i + 0.4 - width / 2 for i in range(len(cases))])
    ax.set_xticklabels(cases, rotation=60, ha="right", fontsize=8)
    ax.set_ylabel("speed-up over plume x1 (same run)")
    ax.set_title(f"plume: throughput by width ({host})")
    ax.legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out_dir, "width_report.png"), dpi=110)
    print(f"chart: {os.path.join(out_dir, 'width_report.png')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
