#!/usr/bin/python3
"""The solver suite's results (`rubble solvers --suite --csv FILE`) as a table or a figure.

  bench/plot_suite.py bench/results/<machine>/solver_suite.csv --table
      prints the Markdown table of docs/solvers.md ("The solver test set"): a row per scene, a
      column per solver and path, each cell "stands · top drift / creep · deepest penetration ·
      energy gained · joint error (scenes with joints) · ms/step";
  bench/plot_suite.py bench/results/<machine>/solver_suite.csv --out docs/images/solver_suite.png
      draws the top body's drift, the deepest penetration and the energy gained of every scene,
      one bar per solver and path, on log axes, zeros drawn at 1e-6 (matplotlib from Debian's
      python3-matplotlib).
"""
import argparse
import csv
import math
import sys

COLUMNS = ["scene", "solver", "path", "settings", "steps", "stands", "top_drift", "top_creep",
           "penetration", "energy_gained", "joint_error", "ms_per_step", "skipped"]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if rows and list(rows[0].keys()) != COLUMNS:
        sys.exit("%s: expected the columns %s" % (path, ",".join(COLUMNS)))
    return rows


def cell(r):
    """One run in a cell: stands (or -), top drift / creep (cm), deepest penetration (mm), energy
    gained (J), the largest joint error (mm) when the scene has joints, ms/step."""
    if r["skipped"] and r["steps"] == "0":
        return "skipped: " + short(r["skipped"])
    stands = r["stands"] if not r["skipped"] else "stopped at step " + r["steps"]
    parts = [stands, "%.3g / %.3g cm" % (100 * float(r["top_drift"]), 100 * float(r["top_creep"])),
             "%.3g mm" % (1000 * float(r["penetration"])), "%.3g J" % float(r["energy_gained"])]
    if float(r["joint_error"]) > 0:
        parts.append("joint %.3g mm" % (1000 * float(r["joint_error"])))
    parts.append("%.3g ms" % float(r["ms_per_step"]))
    return " · ".join(parts)


def table(rows):
    """One row per scene, one column per solver and path."""
    configs = []
    for r in rows:
        key = (r["solver"], r["path"], r["settings"])
        if key not in configs:
            configs.append(key)
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    # A configuration that ran nowhere is a note under the table, not a column.
    notes = []
    for c in list(configs):
        mine = [r for r in rows if (r["solver"], r["path"], r["settings"]) == c]
        if all(r["steps"] == "0" for r in mine):
            notes.append("%s on %s: skipped everywhere (%s)." % (c[0], c[1], short(mine[0]["skipped"])))
            configs.remove(c)
    head = "| scene | " + " | ".join("%s, %s (%s)" % c for c in configs) + " |"
    out = [head, "| --- |" + " --- |" * len(configs)]
    for s in scenes:
        cells = []
        for c in configs:
            found = [r for r in rows if r["scene"] == s and (r["solver"], r["path"],
                                                             r["settings"]) == c]
            cells.append(cell(found[0]) if found else "")
        out.append("| %s | %s |" % (s, " | ".join(cells)))
    if notes:
        out.append("")
        out.extend(notes)
    return "\n".join(out)


def short(reason):
    """The reason's first clause, without the file and field it names: enough to tell no joint
    rows from too many rows or no device."""
    parts = reason.split(": ")
    while len(parts) > 1 and (parts[0].endswith(".json") or parts[0].startswith("simulation.")
                              or parts[0].startswith("step ")):
        parts = parts[1:]
    text = ": ".join(parts)
    for stop in (" (", ";", ", and"):
        text = text.split(stop)[0]
    return text[:80]


def plot(rows, out):
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("bench/plot_suite.py: matplotlib is missing; install python3-matplotlib "
                 "(scripts/setup.sh does) and run this with /usr/bin/python3")
    ran = [r for r in rows if r["steps"] != "0"]
    scenes = sorted({r["scene"] for r in ran})
    configs = sorted({(r["solver"], r["path"]) for r in ran})
    metrics = [("top_drift", "top body drift (m)"), ("penetration", "deepest penetration (m)"),
               ("energy_gained", "energy gained (J)")]
    fig, axes = plt.subplots(len(metrics), 1, figsize=(12, 9), sharex=True)
    width = 0.8 / max(len(configs), 1)
    for ax, (key, label) in zip(axes, metrics):
        for k, config in enumerate(configs):
            xs, ys = [], []
            for i, s in enumerate(scenes):
                for r in ran:
                    if r["scene"] == s and (r["solver"], r["path"]) == config:
                        xs.append(i + (k - (len(configs) - 1) / 2) * width)
                        ys.append(max(float(r[key]), 1e-6))
            ax.bar(xs, ys, width, label="%s, %s" % config)
        ax.set_yscale("log")
        ax.set_ylabel(label)
    axes[-1].set_xticks(range(len(scenes)))
    axes[-1].set_xticklabels(scenes, rotation=30, ha="right")
    axes[0].legend(fontsize=7, ncol=3)
    fig.tight_layout()
    fig.savefig(out, dpi=90)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("csv")
    ap.add_argument("--table", action="store_true", help="print the Markdown table")
    ap.add_argument("--out", help="write the figure to this PNG")
    args = ap.parse_args()
    rows = read(args.csv)
    if args.table:
        print(table(rows))
    if args.out:
        plot(rows, args.out)
    if not args.table and not args.out:
        ap.error("give --table or --out")


if __name__ == "__main__":
    main()
