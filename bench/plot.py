#!/usr/bin/python3
"""Figures of a bench/run results CSV (matplotlib from Debian's python3-matplotlib).

  bench/plot.py bench/results/<machine>/<run>.csv --out docs/images/

writes
  bench_ms_per_step.png  median ms/step against body count on log axes for every configuration
                         and peer, with the fitted growth exponent of each (ms ~ bodies^k);
  bench_stages.png       where a step's time goes, stage by stage (mean ms/step over the run), for
                         each rubble configuration on each debris pile: the CPU stages of the cpu
                         backend beside the device stages of the opencl backend.

  bench/plot.py RESULTS.csv --table [--columns A,B,...] [--scenes ...] [--configs ...]
                [--where KEY=V,...] [--median-by KEYS] [--ratio-to CONFIG] [--pivot COLUMN]

prints the results as a Markdown table instead: every run of the file, or the columns asked for,
medians over groups of runs (the seeds of a scene), or one figure per scene and configuration.
The tables of the docs are made this way; each is quoted above its table in a comment
`<!-- table: bench/plot.py ... -->`, and python/tests/test_docs_tables.py checks that the table
is what the command prints. The table needs no matplotlib.
"""
import argparse
import csv
import math
import os
import sys

def pyplot():
    """matplotlib's pyplot, drawing to files; exits saying how to install it when missing."""
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("bench/plot.py: matplotlib is missing; install python3-matplotlib "
                 "(scripts/setup.sh does) and run this with /usr/bin/python3")
    return plt


def fit_exponent(xs, ys):
    """Least-squares slope of log y against log x."""
    lx = [math.log(x) for x in xs]
    ly = [math.log(y) for y in ys]
    n = len(lx)
    mx, my = sum(lx) / n, sum(ly) / n
    var = sum((a - mx) ** 2 for a in lx)
    return sum((a - mx) * (b - my) for a, b in zip(lx, ly)) / var if var > 0 else float("nan")


# ---- Markdown tables (--table); these need no matplotlib.


def fail(message):
    """Bad input: the message on stderr, exit status 2."""
    sys.stderr.write("bench/plot.py: %s\n" % message)
    sys.exit(2)


def read_csv(path):
    """The rows and column names of any CSV; exits naming the file when it cannot be read."""
    try:
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            columns = list(reader.fieldnames or [])
    except OSError as e:
        fail("%s: %s" % (path, e.strerror))
    return rows, columns


def read_results(path):
    """The rows of a CSV that bench/run wrote; exits naming the file when it is not one."""
    rows, columns = read_csv(path)
    missing = [c for c in ("scene", "config", "status") if c not in columns]
    if missing:
        fail("%s is not a CSV of bench/run (no column %s)" % (path, ", ".join(missing)))
    return rows


def median(values):
    """The median as bench/run takes it (the mean of the two middle values of an even count)."""
    values = sorted(values)
    n = len(values)
    return (values[n // 2] + values[(n - 1) // 2]) / 2.0 if n else None


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


# The short names of bench/run's columns: name -> (title, CSV column, format, scale). Any other
# column of the file is shown under its own name.
KNOWN = {
    "median_ms": ("median ms", "median_ms", "%.3g", 1.0),
    "p90_ms": ("p90 ms", "p90_ms", "%.3g", 1.0),
    "mean_ms": ("mean ms", "mean_ms", "%.3g", 1.0),
    "body_steps_per_s": ("body-steps/s", "body_steps_per_s", "%.0f", 1.0),
    "peak_mib": ("peak MiB", "peak_mib", "%.0f", 1.0),
    "sunk": ("sunk", "sunk", "%g", 1.0),
    "floor_mm": ("floor pen. mm", "floor_penetration_m", "%.1f", 1000.0),
    "drift": ("drift m/s", "mean_drift_m_per_s", "%.3f", 1.0),
    "energy": ("energy J", "kinetic_energy_j", "%.3g", 1.0),
    "max_speed": ("max speed m/s", "max_speed_m_per_s", "%.3g", 1.0),
    "moving": ("moving", "moving", "%g", 1.0),
    "asleep": ("asleep", "asleep", "%g", 1.0),
    "bodies": ("bodies", "bodies", "%g", 1.0),
    "ratio": ("ratio", "ratio_to_reference", "%.2f", 1.0),
}
# What `--table` shows when no --columns are given: every run of the file.
DEFAULT_COLUMNS = ["scene", "config", "bodies", "median_ms", "p90_ms", "mean_ms", "peak_mib", "sunk",
                   "floor_mm", "drift", "energy", "moving", "asleep", "ratio"]
# Columns shown as text (names, labels), left-aligned.
TEXT_COLUMNS = ("scene", "config", "seed", "status", "device", "backend")


class Column:
    """One column of a table: its title, where its value comes from and how it is written."""

    def __init__(self, spec, columns, path, ratio_to, strict=True):
        # NAME, each:NAME or either with =TITLE, a title of the caller's.
        spec, _, title = spec.partition("=")
        self.spec = spec
        self.each = spec.startswith("each:")
        name = spec[len("each:"):] if self.each else spec
        self.name = name
        if name == "runs":
            self.title, self.source, self.fmt, self.scale = "runs", None, None, 1.0
        elif name == "ratio" and ratio_to:
            self.title, self.source, self.fmt, self.scale = "ratio to " + ratio_to, "_ratio", "%.2f", 1.0
        elif name in KNOWN:
            self.title, self.source, self.fmt, self.scale = KNOWN[name]
        elif name.startswith("stage_") and name.endswith("_ms"):
            self.title, self.source, self.fmt, self.scale = (
                name[len("stage_"):-len("_ms")].replace("_", " ") + " ms", name, "%.2f", 1.0)
        else:
            self.title, self.source, self.fmt, self.scale = name, name, None, 1.0
        if strict and self.source not in (None, "_ratio") and self.source not in columns:
            fail("%s has no column %s (its columns: %s)" % (path, self.source, ", ".join(columns)))
        if self.each:
            self.title += " per run"
        if title.strip():
            self.title = title.strip()

    def text_of(self, value):
        """A value as a cell: formatted when a number, as written otherwise, '-' when empty."""
        if value in (None, ""):
            return "-"
        if self.name in TEXT_COLUMNS:
            return str(value)
        v = number(value)
        if v is None:
            return str(value)
        v *= self.scale
        if self.fmt:
            return self.fmt % v
        return "%g" % v if v == int(v) else "%.3g" % v

    def numeric(self):
        return self.name not in TEXT_COLUMNS


def ok(row):
    return row.get("status", "ok") == "ok"


def cell(text):
    return str(text).replace("|", "\\|")


def print_markdown(header, right, body):
    """A Markdown table: the header, the alignment row (numbers right), the body; one write."""
    line = lambda cells: "| " + " | ".join(cell(c) for c in cells) + " |\n"
    text = line(header) + "| " + " | ".join("---:" if r else "---" for r in right) + " |\n"
    sys.stdout.write(text + "".join(line(cells) for cells in body))


def select(rows, columns, args):
    """The rows that --scenes, --configs and --where keep, in the order those lists give."""
    def values(text):
        return [v.strip() for v in text.split(",") if v.strip()]

    wanted = []
    if args.scenes:
        wanted.append(("scene", values(args.scenes)))
    if args.configs:
        wanted.append(("config", values(args.configs)))
    for clause in args.where or []:
        key, eq, text = clause.partition("=")
        if not eq or not key:
            fail("--where %s: give KEY=VALUE[,VALUE...]" % clause)
        wanted.append((key.strip(), values(text)))
    for key, vals in wanted:
        if key not in columns:
            fail("%s has no column %s (its columns: %s)" % (args.results, key, ", ".join(columns)))
        present = {r[key] for r in rows}
        for v in vals:
            if v not in present:
                fail("%s has no row whose %s is %s" % (args.results, key, v))
        rows = [r for r in rows if r[key] in vals]
    # A stable sort: by the lists' orders, the file's order within.
    return sorted(rows, key=lambda r: [vals.index(r[key]) for key, vals in wanted])


def add_ratios(rows, config, path):
    """Each row's median over that of `config`'s run of the same scene, seed and sweeps."""
    reference = {}
    for r in rows:
        if r.get("config") == config and ok(r) and number(r.get("median_ms")):
            reference[(r.get("scene"), r.get("seed", ""), r.get("iterations", ""))] = float(r["median_ms"])
    if not reference:
        fail("%s has no successful run of configuration %s to take ratios to" % (path, config))
    for r in rows:
        ref = reference.get((r.get("scene"), r.get("seed", ""), r.get("iterations", "")))
        m = number(r.get("median_ms"))
        r["_ratio"] = "%r" % (m / ref) if ok(r) and ref and m is not None else ""


def group(rows, keys, specs):
    """One row per value of `keys` (in the order of first appearance): each number the median
    over the group's successful runs, `runs` how many succeeded of how many, `each:NAME` every
    run's value in the file's order ('x' for a run that failed)."""
    groups = {}
    for r in rows:
        groups.setdefault(tuple(r.get(k, "") for k in keys), []).append(r)
    out = []
    for key, members in groups.items():
        good = [r for r in members if ok(r)]
        row = {"status": "ok"}
        row.update(zip(keys, key))
        for c in specs:
            if c.name in keys and not c.each:
                continue
            if c.name == "runs":
                row["runs"] = "%d/%d" % (len(good), len(members))
            elif c.each:
                row[c.spec] = " ".join(c.text_of(r.get(c.source)) if ok(r) else "x" for r in members)
            else:
                vals = [r.get(c.source, "") for r in good if r.get(c.source, "") != ""]
                nums = [number(v) for v in vals]
                if vals and all(n is not None for n in nums):
                    row[c.source] = "%r" % median(nums)
                else:
                    row[c.source] = vals[0] if vals and all(v == vals[0] for v in vals) else ""
        out.append(row)
    return out


def value_of(row, c, show_seed):
    if c.name == "runs" or c.each:
        return row.get(c.spec, "-")
    text = c.text_of(row.get(c.source))
    # A run over seeds names each row's seed after its scene, unless a column shows the seed.
    if c.name == "scene" and show_seed and row.get("seed"):
        text += " seed %s" % row["seed"]
    return text


def print_table(args):
    """The table that --table and its options ask for, as Markdown on stdout."""
    # Without --columns the table is bench/run's (its columns); --pivot needs scenes and
    # configurations. Other CSVs (bench/explosion.sh's, bench/sweep_scaling.py's) name columns.
    rows, columns = read_csv(args.results)
    if not args.columns or args.pivot or args.scenes or args.configs:
        read_results(args.results)
    if args.pivot and args.columns:
        fail("--pivot gives the table's columns (one per configuration): leave out --columns")
    if args.ratio_to:
        add_ratios(rows, args.ratio_to, args.results)
    rows = select(rows, columns, args)
    names = [n.strip() for n in (args.columns or "").split(",") if n.strip()]
    if args.pivot:
        names = ["scene", "config", args.pivot]
    # The default columns are shown as '-' where an older CSV lacks them.
    specs = [Column(n, columns, args.results, args.ratio_to, strict=bool(names))
             for n in names or DEFAULT_COLUMNS]
    if args.median_by:
        keys = [k.strip() for k in args.median_by.split(",") if k.strip()]
        for k in keys:
            if k not in columns:
                fail("%s has no column %s (its columns: %s)" % (args.results, k, ", ".join(columns)))
        # The grouped rows carry their medians under the columns they come from.
        rows = group(rows, keys, specs)
    if args.pivot:
        print_pivot(rows, specs[2], args)
        return
    show_seed = "seed" not in names and not args.median_by
    body = []
    for r in rows:
        if not ok(r):
            # A run that failed: its labels, then the reason where its first figure would be.
            cells, said = [], False
            for c in specs:
                v = r.get(c.source, "") if c.source else ""
                if v != "" and c.name in TEXT_COLUMNS:
                    cells.append(value_of(r, c, show_seed))
                elif not said:
                    cells.append(r["status"].split("(")[0].strip()[:90])
                    said = True
                else:
                    cells.append("")
            body.append(cells)
            continue
        body.append([value_of(r, c, show_seed) for c in specs])
    print_markdown([c.title for c in specs], [c.numeric() and not c.each for c in specs], body)


def print_pivot(rows, c, args):
    """Scenes down, configurations across, one figure in each cell."""
    scenes, configs, cells = [], [], {}
    for r in rows:
        s, k = r["scene"], r["config"]
        if s not in scenes:
            scenes.append(s)
        if k not in configs:
            configs.append(k)
        if (s, k) in cells:
            fail("%s has several runs of %s on %s (a run over seeds): add --median-by scene,config"
                 % (args.results, k, s))
        cells[(s, k)] = value_of(r, c, False) if ok(r) else "failed"
    body = [[s] + [cells.get((s, k), "") for k in configs] for s in scenes]
    print_markdown([c.title] + configs, [False] + [True] * len(configs), body)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("results", help="a CSV written by bench/run (or, with --table --columns, any CSV)")
    ap.add_argument("--out", default="docs/images", help="folder for the PNG files")
    ap.add_argument("--prefix", default="bench", help="file name prefix")
    ap.add_argument("--table", action="store_true", help="print a Markdown table of the CSV and stop")
    table = ap.add_argument_group("the table (with --table)")
    table.add_argument("--columns", help="comma-separated columns: a CSV column, or one of %s, "
                       "stage_NAME_ms, runs (with --median-by), each:NAME (every run's value, "
                       "with --median-by); NAME=TITLE gives the column a title" % ", ".join(["scene", "config", "seed"] + list(KNOWN)))
    table.add_argument("--scenes", help="only these scenes, in this order")
    table.add_argument("--configs", help="only these configurations, in this order")
    table.add_argument("--where", action="append", metavar="KEY=V[,V...]",
                       help="only rows whose column KEY is one of the values (repeatable)")
    table.add_argument("--median-by", metavar="KEYS",
                       help="one row per value of these columns, each figure the median over "
                       "its successful runs (scene,config: over the seeds of bench/run --seeds)")
    table.add_argument("--ratio-to", metavar="CONFIG",
                       help="the ratio column as each run's median over CONFIG's on the same "
                       "scene and seed (default: the CSV's, over cpu-sat-pgs)")
    table.add_argument("--pivot", metavar="COLUMN",
                       help="scenes down, configurations across, COLUMN in each cell")
    args = ap.parse_args()
    if args.table:
        print_table(args)
        return
    if args.columns or args.scenes or args.configs or args.where or args.median_by or \
            args.ratio_to or args.pivot:
        fail("--columns, --scenes, --configs, --where, --median-by, --ratio-to and --pivot "
             "shape the table: give --table too")
    plt = pyplot()
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
    plot_stages(plt, rows, args)


STAGE_COLUMNS = ["apply_forces", "integrate_velocities", "broad_phase", "narrow_phase", "build_contact_rows",
                 "solve", "integrate_positions", "solve_positions", "islands", "sleep"]


def plot_stages(plt, rows, args):
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
