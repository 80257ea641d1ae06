#!/usr/bin/python3
"""Figures of a bench/run results CSV (matplotlib from Debian's python3-matplotlib).

  bench/plot.py bench/results/<machine>/<run>.csv --out docs/images/

writes
  bench_ms_per_step.png  median ms/step against body count on log axes for every configuration
                         and peer, with the fitted growth exponent of each (ms ~ bodies^k);
  bench_stages.png       where a step's time goes, stage by stage (mean ms/step over the run), for
                         each rubble configuration on each debris pile: the CPU stages of the cpu
                         backend beside the device stages of the opencl backend.
With --table, prints the results as a Markdown table instead (the tables of docs/BENCHMARKS.md);
a run with --repeat gives one row per scene and configuration, the medians over its runs.
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


def read_results(path):
    """The rows of a CSV that bench/run wrote; exits naming the file when it is not one."""
    try:
        with open(path) as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            columns = reader.fieldnames or []
    except OSError as e:
        sys.exit("bench/plot.py: %s: %s" % (path, e.strerror))
    missing = [c for c in ("scene", "config", "status") if c not in columns]
    if missing:
        sys.exit("bench/plot.py: %s is not a CSV of bench/run (no column %s)" % (
            path, ", ".join(missing)))
    return rows


# The figures of a row that a run over repetitions gives as medians.
FIGURES = ["bodies", "median_ms", "p90_ms", "mean_ms", "peak_mib", "sunk", "floor_penetration_m",
           "mean_drift_m_per_s", "kinetic_energy_j", "moving", "asleep", "ratio_to_reference"]


def median_rows(rows):
    """One row per scene, seed and configuration of a run with --repeat: each figure the median
    of the runs that finished (`runs`: finished/all); a group none of whose runs finished keeps
    its first failure."""
    groups = {}
    for r in rows:
        groups.setdefault((r["scene"], r.get("seed", ""), r["config"]), []).append(r)
    out = []
    for group in groups.values():
        ok = [r for r in group if r["status"] == "ok"]
        merged = dict(ok[0] if ok else group[0])
        merged["runs"] = "%d/%d" % (len(ok), len(group))
        for key in FIGURES:
            values = sorted(float(r[key]) for r in ok if r.get(key, "") not in ("", None))
            n = len(values)
            merged[key] = "%r" % ((values[n // 2] + values[(n - 1) // 2]) / 2.0) if n else ""
        out.append(merged)
    return out


def print_table(path):
    """Every row of the CSV, failures included, as Markdown; a run with --repeat as the medians
    of each scene and configuration."""
    rows = read_results(path)
    repeated = any(r.get("repeat") for r in rows)
    if repeated:
        rows = median_rows(rows)

    def num(key, fmt, scale=1.0):
        def cell(r):
            v = r.get(key, "")
            return fmt % (float(v) * scale) if v not in ("", None) else "-"
        return cell

    def text(key):
        return lambda r: r.get(key, "-") or "-"

    # The columns after scene and config: a title and its cell of an ok row.
    columns = [
        ("bodies", num("bodies", "%d")), ("median ms", num("median_ms", "%.3g")),
        ("p90 ms", num("p90_ms", "%.3g")), ("mean ms", num("mean_ms", "%.3g")),
        ("peak MiB", num("peak_mib", "%.0f")), ("sunk", num("sunk", "%g")),
        ("floor pen. mm", num("floor_penetration_m", "%.1f", 1000.0)),
        ("drift m/s", num("mean_drift_m_per_s", "%.3f")),
        ("energy J", num("kinetic_energy_j", "%.3g")), ("moving", num("moving", "%g")),
        ("asleep", num("asleep", "%g")), ("ratio", num("ratio_to_reference", "%.2f")),
    ]
    if repeated:
        columns.insert(0, ("runs", text("runs")))
    line = lambda cells: print("| " + " | ".join(cells) + " |")
    line(["scene", "config"] + [title for title, _ in columns])
    line(["---", "---"] + ["---:"] * len(columns))
    for r in rows:
        # A run with --seeds names each row's seed after its scene.
        scene = r["scene"] + (" seed %s" % r["seed"] if r.get("seed") else "")
        if r["status"] != "ok":
            # The reason in the median's column, the other figures empty.
            cells = [r.get("runs", "") if title == "runs" else "" for title, _ in columns]
            cells[[title for title, _ in columns].index("median ms")] = (
                r["status"].split("(")[0].strip()[:90])
            print("| %s | %s |" % (scene, r["config"]) +
                  "".join(" %s |" % c if c else " |" for c in cells))
            continue
        line([scene, r["config"]] + [cell(r) for _, cell in columns])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="a CSV written by bench/run")
    ap.add_argument("--out", default="docs/images", help="folder for the PNG files")
    ap.add_argument("--prefix", default="bench", help="file name prefix")
    ap.add_argument("--table", action="store_true", help="print a Markdown table of the CSV and stop")
    args = ap.parse_args()
    if args.table:
        print_table(args.results)
        return
    rows = [r for r in read_results(args.results)
            if r["status"] == "ok" and r["scene"].startswith("debris_")]
    if not rows:
        sys.exit("bench/plot.py: %s has no successful debris_* rows to plot" % args.results)
    if any(r.get("seed") for r in rows):
        sys.exit("bench/plot.py: %s is a run over seeds (bench/run --seeds), one row per seed: "
                 "plot a run without --seeds, or print it with --table" % args.results)
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
    plot_stages(rows, args)


STAGE_COLUMNS = ["apply_forces", "integrate_velocities", "broad_phase", "narrow_phase", "build_contact_rows",
                 "solve", "integrate_positions", "solve_positions", "islands", "sleep"]


def plot_stages(rows, args):
    """One panel per debris scene; one stacked bar per rubble configuration."""
    staged = [r for r in rows if any(r.get("stage_%s_ms" % c) not in (None, "") for c in STAGE_COLUMNS)]
    if not staged:
        print("bench/plot.py: no per-stage columns in %s; skipping the stage plot" % args.results)
        return
    scenes = sorted({r["scene"] for r in staged}, key=lambda s: min(int(r["bodies"]) for r in staged
                                                                     if r["scene"] == s))
    fig, axes = plt.subplots(len(scenes), 1, figsize=(8, 1.2 + 1.3 * len(scenes)), dpi=110, squeeze=False)
    colours = plt.get_cmap("tab10")
    for ax, scene in zip(axes[:, 0], scenes):
        order = ["opencl-particles-jacobi", "cpu-particles-jacobi", "cpu-sat-pgs"]
        mine = sorted((r for r in staged if r["scene"] == scene),
                      key=lambda r: order.index(r["config"]) if r["config"] in order else -1)
        for y, r in enumerate(mine):
            left = 0.0
            for i, c in enumerate(STAGE_COLUMNS):
                v = float(r.get("stage_%s_ms" % c) or 0.0)
                if v <= 0:
                    continue
                ax.barh(y, v, left=left, color=colours(i), label=c)
                left += v
        ax.set_yticks(range(len(mine)))
        ax.set_yticklabels([r["config"] for r in mine], fontsize=8)
        ax.set_title("%s (%s bodies)" % (scene, mine[0]["bodies"]), fontsize=9)
        ax.set_xlabel("mean ms/step", fontsize=8)
        ax.grid(True, axis="x", alpha=0.3)
    # One legend for all panels, each stage once.
    handles, labels = [], []
    for ax in axes[:, 0]:
        for h, l in zip(*ax.get_legend_handles_labels()):
            if l not in labels:
                handles.append(h)
                labels.append(l)
    fig.legend(handles, labels, loc="lower center", ncol=5, fontsize=7)
    fig.tight_layout(rect=(0, 0.08, 1, 1))
    path = os.path.join(args.out, args.prefix + "_stages.png")
    fig.savefig(path)
    print("wrote", path)


if __name__ == "__main__":
    main()
