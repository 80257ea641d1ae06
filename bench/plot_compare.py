#!/usr/bin/python3
"""Figures of `rubble compare` and `rubble solvers` CSV files (matplotlib from Debian's
python3-matplotlib; run with /usr/bin/python3).

  bench/plot_compare.py compare.csv compare.png   # per-step divergence, energy, momentum,
                                                  # penetration and residual of sides a and b
  bench/plot_compare.py solvers.csv solvers.png   # residual against iterations per solver

`rubble compare --plot FILE.png` runs the first form itself. Exit status 3 when matplotlib is
missing, 2 for a CSV this script does not know.
"""
import csv
import math
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.stderr.write("bench/plot_compare.py: matplotlib is missing; install python3-matplotlib "
                     "(apt-get install python3-matplotlib) and run this with /usr/bin/python3\n")
    sys.exit(3)


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.stderr.write(f"bench/plot_compare.py: {path} has no rows\n")
        sys.exit(2)
    return rows


def number(text):
    return float(text) if text not in ("", None) else math.nan


def positive(values):
    """Zeros and negatives cannot be drawn on a log axis: they become gaps."""
    return [v if v > 0 else math.nan for v in values]


def plot_compare(rows, out):
    t = [number(r["time"]) for r in rows]
    fig, axes = plt.subplots(2, 3, figsize=(15, 8), constrained_layout=True)
    fig.suptitle("rubble compare: side a against side b", fontsize=10)

    ax = axes[0][0]
    for key, label in (("position_max", "max"), ("position_rms", "rms")):
        ax.plot(t, positive([number(r[key]) for r in rows]), label=label)
    ax.set_yscale("log")
    ax.set_title("position divergence (m)")

    ax = axes[0][1]
    for key, label in (("angle_max", "max"), ("angle_rms", "rms")):
        ax.plot(t, positive([number(r[key]) for r in rows]), label=label)
    ax.set_yscale("log")
    ax.set_title("orientation divergence (rad)")

    panels = ((axes[0][2], "kinetic_energy", "kinetic energy (J)", False),
              (axes[1][0], "linear_momentum", "|linear momentum| (kg m/s)", False),
              (axes[1][1], "largest_penetration", "largest penetration (m)", False),
              (axes[1][2], "residual", "solver residual (N s)", True))
    for ax, key, title, log in panels:
        for side in ("a", "b"):
            values = [number(r[f"{key}_{side}"]) for r in rows]
            ax.plot(t, positive(values) if log else values, label=side)
        if log:
            ax.set_yscale("log")
        ax.set_title(title)
    for ax in axes.flat:
        ax.set_xlabel("time (s)")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.savefig(out, dpi=100)


def plot_solvers(rows, out):
    fig, axes = plt.subplots(1, 2, figsize=(13, 5), constrained_layout=True)
    series = {}
    exact = []
    for r in rows:
        name = f"{r['solver']} ({r['backend']})"
        if r["solver"] == "lemke":
            exact.append((name, number(r["residual"]), int(r["iteration"])))
            continue
        series.setdefault(name, []).append(
            (int(r["iteration"]), number(r["residual"]), number(r["velocity_error"])))
    for name, points in series.items():
        points.sort()
        k = [p[0] for p in points]
        dashed = "opencl" in name
        style = dict(linestyle="--" if dashed else "-", linewidth=1.2 if dashed else 1.8)
        axes[0].plot(k, positive([p[1] for p in points]), label=name, **style)
        if not all(math.isnan(p[2]) for p in points):
            axes[1].plot(k, positive([p[2] for p in points]), label=name, **style)
    for name, residual, pivots in exact:
        if residual > 0:
            axes[0].axhline(residual, color="black", linewidth=1,
                            label=f"{name}: {pivots} pivots")
        else:
            axes[0].plot([], [], color="black", label=f"{name}: exact, {pivots} pivots")
    axes[0].set_title("residual max |min(A_ii lambda_i, w_i)| (m/s)")
    axes[1].set_title("contact velocity error against lemke, max |w - w*| (m/s)")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("iteration")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    if not axes[1].lines:
        axes[1].text(0.5, 0.5, "no lemke reference (friction, or too many rows)",
                     ha="center", va="center", transform=axes[1].transAxes)
    fig.savefig(out, dpi=100)


def main():
    if len(sys.argv) != 3:
        sys.stderr.write(__doc__)
        sys.exit(2)
    rows = read(sys.argv[1])
    if "solver" in rows[0]:
        plot_solvers(rows, sys.argv[2])
    elif "position_max" in rows[0]:
        plot_compare(rows, sys.argv[2])
    else:
        sys.stderr.write(f"bench/plot_compare.py: {sys.argv[1]} is neither a rubble compare nor "
                         "a rubble solvers CSV\n")
        sys.exit(2)


if __name__ == "__main__":
    main()
