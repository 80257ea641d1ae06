#!/usr/bin/python3
"""Figures of a bench/run results CSV (matplotlib from Debian's python3-matplotlib).

  bench/plot.py bench/results/<machine>/<run>.csv --out docs/images/

writes bench_ms_per_step.png: median ms/step against body count on log axes for every
configuration, with the fitted growth exponent of each (ms ~ bodies^k) in the legend.
"""
import argparse
import csv
import math
import os
import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    sys.exit("bench/plot.py: matplotlib is missing; install python3-matplotlib "
             "(scripts/setup.sh does) and run this with /usr/bin/python3")


def fit_exponent(xs, ys):
    """Least-squares slope of log y against log x."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    var = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / var if var > 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="a CSV written by bench/run")
    ap.add_argument("--out", default="docs/images", help="folder for the PNG files")
    ap.add_argument("--prefix", default="bench", help="file name prefix")
    args = ap.parse_args()
    with open(args.results) as f:
        rows = [r for r in csv.DictReader(f) if r["status"] == "ok" and r["scene"].startswith("debris_")]
    if not rows:
        sys.exit("bench/plot.py: %s has no successful debris_* rows to plot" % args.results)
    os.makedirs(args.out, exist_ok=True)

    fig, ax = plt.subplots(figsize=(7, 4.5), dpi=110)
    for config in sorted({r["config"] for r in rows}):
        pts = sorted((int(r["bodies"]), float(r["median_ms"])) for r in rows if r["config"] == config)
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        label = config
        if len(pts) >= 2:
            label += "  (k = %.2f)" % fit_exponent(xs, ys)
        ax.plot(xs, ys, marker="o", label=label)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("bodies")
    ax.set_ylabel("median ms/step")
    ax.set_title("Debris piles, dt 1/60 s, 10 iterations (%s)" % os.path.basename(os.path.dirname(args.results)))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    path = os.path.join(args.out, args.prefix + "_ms_per_step.png")
    fig.savefig(path)
    print("wrote", path)


if __name__ == "__main__":
    main()
