#!/usr/bin/env python3
"""plume's width report, from Google Benchmark JSON files of several build variants.

Benchmark names follow  <case...>/<type>/<implementation>/x<width>  (see bench/*/); with
several files of one variant (rounds), the fastest round is used (a round's median where it
has repetitions): on a shared machine interference only ever slows a run down (a whole round
can read 40% slow for one build), so the fastest is the closest to the code's own speed.
Usage:
    report.py OUT_DIR WIDEST VARIANT=RESULT.json [VARIANT=RESULT.json ...]
Prints and writes OUT_DIR/width_report.md with three tables:
  across builds     plume x1 of the scalar build, and plume at the widest width of every
                    other build, with the speed-up over the scalar build
  within one build  every implementation and width of the WIDEST build, with the ratio to
                    plume x1 measured in the same run (the figure to quote on a noisy machine)
  dispatched        (with dispatch=RESULT.json files) each dispatched entry point of the
                    dispatch build, the set chosen by set_isa, against the same kernel in the
                    static build of that set (plume_bench_dispatch)
and, when matplotlib is available, OUT_DIR/width_report.png: one panel per floor (the
benchmark binary's floor), horizontal bars of plume's widths and each peer at its fastest
width within the WIDEST build, as speed-ups over plume x1 of the same run.
"""
import json
import os
import sys
from collections import OrderedDict, defaultdict


# The floor each benchmark binary measures (docs/architecture.md), in the chart's order.
FLOORS = OrderedDict([
    ("numerics", ["plume_bench_numerics"]),
    ("math", ["plume_bench_math"]),
    ("collision", ["plume_bench_collision", "plume_bench_gjk", "plume_bench_ray_scene"]),
    ("spatial", ["plume_bench_spatial"]),
    ("character", ["plume_bench_character", "plume_bench_character_move"]),
    ("solver", ["plume_bench_solver"]),
    ("world", ["plume_bench_world"]),
])
FLOOR_OF = {b: f for f, bins in FLOORS.items() for b in bins}


def floor_of_path(path):
    """report.sh names its files <variant>.<binary>.r<round>.json."""
    parts = os.path.basename(path).split(".")
    return FLOOR_OF.get(parts[1] if len(parts) > 2 else "", "other")


CASE_FLOOR = {}  # case -> floor, filled by load()
# Benchmarks whose name does not end in a width (x<N>), e.g. spatial_build/.../plume/bvh or
# spatial_tree/stress10k/reinsert: variant -> name -> fastest items/s, filled by load().
UNWIDE = defaultdict(dict)


def is_width(part):
    return part.startswith("x") and part[1:].isdigit()


def load(paths, variant=None):
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
            if not is_width(parts[-1]):
                if variant is not None:
                    best = UNWIDE[variant]
                    best[name] = max(best.get(name, 0.0), float(ips))
                continue
            if len(parts) < 4:
                continue
            case = "/".join(parts[:-2])
            CASE_FLOOR[case] = floor_of_path(path)
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


def chart_rows(within, floor):
    """The bars of one floor's panel: per case, plume at every width, then each peer at its
    fastest width, as (case, label, impl, items/s, ratio to plume x1)."""
    rows = []
    for case, row in within.items():
        if CASE_FLOOR.get(case, "other") != floor:
            continue
        base = row.get(("plume", 1))
        if not base:
            continue
        bars = [(f"plume x{w}", "plume", v) for (i, w), v in sorted(row.items()) if i == "plume"]
        best = {}
        for (i, w), v in row.items():
            if i != "plume" and v > best.get(i, (0, 0))[1]:
                best[i] = (w, v)
        bars += [(f"{i} x{w}", i, v) for i, (w, v) in sorted(best.items())]
        rows.append((case, [(label, impl, v, v / base) for label, impl, v in bars]))
    return rows


def draw_chart(plt, within, widest, host, png):
    """One panel per floor, horizontal bars: the speed-up over plume x1 of the same run for
    plume's widths and each peer at its fastest width, the throughput written at each bar."""
    panels = [(f, chart_rows(within, f)) for f in list(FLOORS) + ["other"]]
    panels = [(f, rows) for f, rows in panels if rows]
    if not panels:
        return False
    bar_h, gap = 0.16, 0.22  # inches per bar, and between cases
    height = {f: 0.9 + sum(len(b) * bar_h + gap for _, b in rows) for f, rows in panels}
    columns = [[], []]  # two columns of panels, each floor to the shorter one
    for f, rows in sorted(panels, key=lambda p: -height[p[0]]):
        col = min(columns, key=lambda c: sum(height[x] for x, _ in c))
        col.append((f, rows))
    order = [f for f, _ in panels]
    for c in columns:
        c.sort(key=lambda p: order.index(p[0]))
    total = max(sum(height[f] for f, _ in c) for c in columns)
    fig = plt.figure(figsize=(15, total + 1.0))
    impls = sorted({impl for _, rows in panels for _, bars in rows for _, impl, _, _ in bars},
                   key=lambda i: (i != "plume", i))
    cmap = plt.get_cmap("tab10")
    color = {i: cmap(k % 10) for k, i in enumerate(impls)}
    shades = {}  # plume's widths: darker for wider
    for k, c in enumerate(columns):
        top = 1.0 - 0.7 / (total + 1.0)
        for f, rows in c:
            h = height[f] / (total + 1.0)
            ax = fig.add_axes([0.16 + 0.5 * k, top - h + 0.5 / (total + 1.0), 0.3, h - 0.75 / (total + 1.0)])
            top -= h
            y, ticks, labels = 0.0, [], []
            for case, bars in rows:
                ticks.append(y + (len(bars) - 1) * bar_h / 2)
                labels.append(case)
                for label, impl, v, ratio in bars:
                    if impl == "plume":
                        w = int(label.split("x")[-1])
                        shade = shades.setdefault(w, 0.35 + 0.15 * len(shades))
                        col = plt.get_cmap("Blues")(min(1.0, shade + 0.2))
                    else:
                        col = color[impl]
                    ax.barh(y, ratio, height=bar_h * 0.9, color=col)
                    ax.text(ratio, y, f" {label} {human(v)}/s", va="center", fontsize=6.5)
                    y += bar_h
                y += gap
            ax.set_yticks(ticks)
            ax.set_yticklabels(labels, fontsize=8)
            ax.invert_yaxis()
            ax.axvline(1.0, color="grey", lw=0.6)
            ax.set_xlabel("speed-up over plume x1 (same run)", fontsize=8)
            ax.tick_params(axis="x", labelsize=7)
            ax.set_title(f"{f}", fontsize=10, loc="left", fontweight="bold")
            ax.set_xlim(0, max(r for _, b in rows for _, _, _, r in b) * 1.45)
    fig.suptitle(f"plume width report: the {widest} build, plume's widths and the peers ({host})",
                 fontsize=11, y=1.0 - 0.25 / (total + 1.0))
    fig.savefig(png, dpi=100)
    return True


def dispatch_lines(dispatch_paths):
    """The dispatched column: plume_bench_dispatch's dispatch/<case>/dispatched/<isa> in the
    dispatch build (one binary, the set chosen by set_isa) against dispatch/<case>/static/<isa>
    in the static build of that set, measured in the same rounds."""
    if not dispatch_paths:
        return []
    load(dispatch_paths, "dispatch")
    cases, isas = OrderedDict(), []
    for name, v in sorted(UNWIDE.get("dispatch", {}).items()):
        parts = name.split("/")
        if len(parts) < 4 or parts[0] != "dispatch" or parts[-2] != "dispatched":
            continue
        case, isa = "/".join(parts[1:-2]), parts[-1]
        if isa not in isas:
            isas.append(isa)
        static = UNWIDE.get(isa, {}).get(f"dispatch/{case}/static/{isa}")
        cases.setdefault(case, {})[isa] = (v, static)
    if not cases:
        return []
    missing = [i for i in ("sse2", "avx2", "avx512") if i not in isas]
    canonical = ["scalar", "sse2", "avx2", "avx512"]
    isas.sort(key=lambda i: canonical.index(i) if i in canonical else len(canonical))
    lines = ["", "## Dispatched: one binary against the static build of each set (items/s)", "",
             "Each cell: the dispatch build (PLUME_DISPATCH=ON) with the set chosen by set_isa, "
             "then the same kernel in the static build of that set, and their ratio "
             "(dispatched / static; 1.00 is no overhead).", "",
             "| case | " + " | ".join(f"{i} dispatched / static" for i in isas) + " |",
             "|" + "---|" * (len(isas) + 1)]
    for case, row in cases.items():
        cells = []
        for i in isas:
            if i not in row:
                cells.append("")
                continue
            v, static = row[i]
            cells.append(f"{human(v)} / {human(static)} ({v / static:.2f}x)" if static
                         else f"{human(v)} / (no static build)")
        lines.append(f"| {case} | " + " | ".join(cells) + " |")
    if missing:
        lines += ["", "Sets the dispatch build carries that this CPU does not run (no column): "
                  + ", ".join(missing) + "."]
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
        tables[v], c = load(by_variant[v], v)
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
    # Measures without widths (builds, tree optimisation): items/s in the widest build.
    unwide = {k: v for k, v in UNWIDE.get(widest, {}).items() if not k.startswith("dispatch/")}
    if unwide:
        lines.append("")
        lines.append(f"## Without widths, {widest} build (items/s)")
        lines.append("")
        lines += ["| benchmark | items/s |", "|---|---|"]
        lines += [f"| {name} | {human(v)} |" for name, v in sorted(unwide.items())]
    lines += dispatch_lines(by_variant.get("dispatch"))
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
    png = os.path.join(out_dir, "width_report.png")
    if draw_chart(plt, within, widest, host, png):
        print(f"chart: {png}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
