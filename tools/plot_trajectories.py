#!/usr/bin/python3
"""Pictures of character trajectories: one PNG per scenario CSV.

The controller tests write one CSV per scenario when PLUME_TRAJECTORY_DIR is set:

    PLUME_TRAJECTORY_DIR=out build/<variant>/tests/plume_character_tests "[controller]"
    /usr/bin/python3 tools/plot_trajectories.py out   # writes out/<scenario>.png (Debian python)

Each picture has a top view (x, z) and a side view (x, y) of the path, coloured by the ground
state of each frame, with the contact planes the move touched (a short line along each normal
from its point), and the ground state over time, so jitter, a bump or a lost ground shows at a
glance. Needs matplotlib (python3-matplotlib; tools/install_deps.sh installs it).
"""
import csv
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

STATES = ["on ground", "on steep ground", "not supported", "in air"]
COLOURS = ["tab:green", "tab:orange", "tab:red", "tab:blue"]


def load(path):
    frames, planes = [], []
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            if row["kind"] == "frame":
                frames.append(row)
            else:
                planes.append(row)
    return frames, planes


def plot(path, out):
    frames, planes = load(path)
    if not frames:
        return False
    t = [int(r["frame"]) for r in frames]
    x = [float(r["x"]) for r in frames]
    y = [float(r["y"]) for r in frames]
    z = [float(r["z"]) for r in frames]
    s = [int(r["state"]) for r in frames]
    fig, (top, side, state) = plt.subplots(3, 1, figsize=(8, 10),
                                           gridspec_kw={"height_ratios": [3, 3, 1.2]})
    for ax, (u, v, label) in ((top, (x, z, "z (m)")), (side, (x, y, "y (m)"))):
        ax.plot(u, v, color="0.7", linewidth=0.8, zorder=1)
        for k, name in enumerate(STATES):
            pts = [(a, b) for a, b, g in zip(u, v, s) if g == k]
            if pts:
                ax.scatter(*zip(*pts), s=6, color=COLOURS[k], label=name, zorder=2)
        ax.set_xlabel("x (m)")
        ax.set_ylabel(label)
        ax.set_aspect("equal", adjustable="datalim")
        ax.grid(True, linewidth=0.3)
    for p in planes:
        px, py, pz = float(p["x"]), float(p["y"]), float(p["z"])
        nx, ny, nz = float(p["nx"]), float(p["ny"]), float(p["nz"])
        top.plot([px, px + 0.15 * nx], [pz, pz + 0.15 * nz], color="k", linewidth=0.4)
        side.plot([px, px + 0.15 * nx], [py, py + 0.15 * ny], color="k", linewidth=0.4)
    top.set_title(pathlib.Path(path).stem + ": top view (contact normals in black)")
    side.set_title("side view")
    top.legend(loc="best", fontsize=7, markerscale=2)
    state.step(t, s, where="post", color="k", linewidth=0.8)
    state.set_yticks(range(len(STATES)))
    state.set_yticklabels(STATES, fontsize=7)
    state.invert_yaxis()
    state.set_xlabel("frame")
    state.set_title("ground state")
    fig.tight_layout()
    fig.savefig(out, dpi=90)
    plt.close(fig)
    return True


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_trajectories.py <directory of scenario CSVs>")
    folder = pathlib.Path(sys.argv[1])
    made = 0
    for path in sorted(folder.glob("*.csv")):
        if plot(path, path.with_suffix(".png")):
            made += 1
    print(f"{made} pictures in {folder}")


if __name__ == "__main__":
    main()
