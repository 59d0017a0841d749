#!/usr/bin/env python3
"""plume's width report, from Google Benchmark JSON files of several build variants.

Benchmark names follow  <case...>/<type>/<implementation>/x<width>  (see bench/*/); with
several files of one variant (rounds), the fastest round is used (a round's median where it
has repetitions): on a shared machine interference only ever slows a run down (a whole round
can read 40% slow for one build), so the fastest is the closest to the code's own speed.
Usage:
    report.py OUT_DIR WIDEST VARIANT=RESULT.json [VARIANT=RESULT.json ...]
Prints and writes OUT_DIR/width_report.md with two tables:
  across builds     plume x1 of the scalar build, and plume at the widest width of every
                    other build, with the speed-up over the scalar build
  within one build  every implementation and width of the WIDEST build, with the ratio to
                    plume x1 measured in the same run (the figure to quote on a noisy machine)
and, when matplotlib is available, OUT_DIR/width_report.png (the across-builds speed-ups).
"""
import json
import os
import sys
from collections import OrderedDict, defaultdict


def load(paths):
    runs = defaultdict(list)  # (case, impl, width) -> [items/s]
    context = None
    for path in paths:
        if not os.path.exists(path):
            continue
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
            for suffix in ("/manual_time", "/real_time"):  # timing-mode tags, not the width
                if name.endswith(suffix):
                    name = name[: -len(suffix)]
            parts = name.split("/")
            if len(parts) < 4 or not parts[-1].startswith("x"):
                continue
            case = "/".join(parts[:-2])
            runs[(case, parts[-2], int(parts[-1][1:]))].append(float(ips))
    table = OrderedDict()
    for (case, impl, width), vals in runs.items():
        table.setdefault(case, {})[(impl, width)] = max(vals)
    return table, context or {}


def human(v):
    for unit, scale in (("G", 1e9), ("M", 1e6), ("k", 1e3)):
        if v >= scale:
            return f"{v / scale:.3g}{unit}"
    return f"{v:.3g}"


def table_lines(table, cols, base_of, fmt_base):
    lines = ["| case | " + " | ".join(fmt_base(c) for c in cols) + " |",
             "|" + "---|" * (len(cols) + 1)]
    for case, row in table.items():
        base = base_of(case)
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
    return lines


def main():
    if len(sys.argv) < 4:
        print(__doc__)
        return 2
    out_dir, widest = sys.argv[1], sys.argv[2]
    by_variant = defaultdict(list)
    for arg in sys.argv[3:]:
        v, _, path = arg.partition("=")
        by_variant[v].append(path)
    order = [v for v in ("scalar", "sse2", "avx2", "avx512", "native") if v in by_variant]
    tables, ctx = {}, {}
    for v in order:
        tables[v], c = load(by_variant[v])
        ctx = ctx or c
    os.makedirs(out_dir, exist_ok=True)
    host = ctx.get("host_name", "?")
    lines = ["# plume width report", "",
             f"Machine: {host}, {ctx.get('num_cpus', '?')} CPUs at {ctx.get('mhz_per_cpu', '?')} MHz; "
             f"{ctx.get('date', '')}. Figures are items/s (the fastest of the rounds).", ""]

    # Across builds: scalar x1 against each wide build's widest plume width.
    across = OrderedDict()
    across_cols = []
    for v in order:
        # Each build at its widest plume width for the case (x4 for f32 and x2 for f64 in
        # the sse2 build, ...); the column is named after the f32 width.
        t = tables[v]
        col = None
        for case, row in t.items():
            widths = sorted(w for (i, w) in row if i == "plume")
            if not widths:
                continue
            col = col or (v, max(w for row2 in t.values() for (i, w) in row2 if i == "plume"))
            across.setdefault(case, {})[col] = row[("plume", widths[-1])]
        if col:
            across_cols.append(col)
    lines.append("## Across builds (speed-up over the scalar build)")
    lines.append("")
    lines += table_lines(across, across_cols,
                         lambda case: across[case].get(("scalar", 1)),
                         lambda c: f"{c[0]} build" + ("" if c[0] == "scalar" else " (widest)"))
    lines.append("")

    # Within the widest build: every width and the peers, one run.
    within = tables.get(widest, {})
    cols = sorted({k for row in within.values() for k in row},
                  key=lambda k: (k[0] != "plume", k[0], k[1]))
    lines.append(f"## Within the {widest} build (ratio to plume x1 of the same run)")
    lines.append("")
    lines += table_lines(within, cols, lambda case: within[case].get(("plume", 1)),
                         lambda c: f"{c[0]} x{c[1]}")
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
    cases = [c for c in across if ("scalar", 1) in across[c]]
    if not cases:
        return 0
    fig, ax = plt.subplots(figsize=(max(8, 0.6 * len(cases)), 5))
    bw = 0.8 / max(1, len(across_cols))
    for j, c in enumerate(across_cols):
        ys = [across[k].get(c, 0) / across[k][("scalar", 1)] for k in cases]
        ax.bar([i + j * bw for i in range(len(cases))], ys, bw, label=f"{c[0]} build" + ("" if c[0] == "scalar" else f" (x{c[1]} f32)"))
    ax.set_xticks([i + 0.4 - bw / 2 for i in range(len(cases))])
    ax.set_xticklabels(cases, rotation=60, ha="right", fontsize=8)
    ax.set_ylabel("speed-up over the scalar build")
    ax.set_title(f"plume: throughput by build variant and width ({host})")
    ax.legend()
    fig.tight_layout()
    png = os.path.join(out_dir, "width_report.png")
    fig.savefig(png, dpi=110)
    print(f"chart: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
