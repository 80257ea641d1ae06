#!/usr/bin/env python3
"""How far the columns of a debris pile lean: for each column of a grid generator's crates, the
horizontal distance from its bottom crate's centre to its top crate's, at each step a trajectory
file (.csv, `rubble run --out`) holds; printed as medians and 90th percentiles over the columns
at the pile's edge and inside it.

  bench/column_lean.py t.csv --grid 64 16 64
  bench/column_lean.py cpu.csv device.csv --grid 32 16 32 --steps 150,200
  bench/column_lean.py cpu.csv device.csv --grid 64 16 64 --steps 300 --sides

A column that leans faster topples sooner; over thousands of columns the figure changes little
from seed to seed, where the count of crates still moving at one step does. The crates are named
PREFIX + index, the index running along x first, then up the layers, then along z (the `grid`
generator's order, scenes/bench/README.md)."""
import argparse
import math
import sys

from trajectory_csv import trajectory_rows


def parse_steps(text):
    try:
        return sorted({int(s) for s in text.split(",") if s.strip()})
    except ValueError:
        raise argparse.ArgumentTypeError("--steps: %r is not a list of step numbers" % text)


def read_columns(path, grid, prefix, steps):
    """{step: {(x, z): {layer: (px, pz)}}} for the bottom and top layers of every column."""
    nx, ny, nz = grid
    top = ny - 1
    out = {}
    with open(path, newline="") as f:
        _, at, rows = trajectory_rows(f, path, ("step", "body", "px", "pz"))
        for row in rows:
            name = row[at["body"]]
            if not name.startswith(prefix) or not name[len(prefix):].isdigit():
                continue
            step = int(row[at["step"]])
            if steps and step not in steps:
                continue
            i = int(name[len(prefix):])
            layer = (i // nx) % ny
            if layer not in (0, top) or i >= nx * ny * nz:
                continue
            column = (i % nx, i // (nx * ny))
            pos = (float(row[at["px"]]), float(row[at["pz"]]))
            out.setdefault(step, {}).setdefault(column, {})[layer] = pos
    return out


def quantile(values, q):
    values = sorted(values)
    if not values:
        return float("nan")
    return values[min(len(values) - 1, int(q * (len(values) - 1) + 0.5))]


def offsets(columns, grid):
    """(x, z, dx, dz) of every column with both ends: its top crate's offset from its bottom
    one across the floor, m."""
    top = grid[1] - 1
    for (x, z), ends in columns.items():
        if 0 in ends and top in ends:
            yield x, z, ends[top][0] - ends[0][0], ends[top][1] - ends[0][1]


def leans(columns, grid):
    """(edge, interior): the leans of the columns at the pile's edge and inside it, m."""
    nx, _, nz = grid
    edge, inside = [], []
    for x, z, dx, dz in offsets(columns, grid):
        (edge if x in (0, nx - 1) or z in (0, nz - 1) else inside).append(math.hypot(dx, dz))
    return edge, inside


def side_leans(columns, grid):
    """{side: mean lean away from the pile} for the columns of each side (-x, +x, -z, +z; a
    corner column counts on both of its sides), and 'inner': the inner columns' mean lean
    (x, z), m: an order of the solve that drifts shows as a mean lean inside and a side leaning
    out further than its opposite."""
    nx, _, nz = grid
    sides = {"-x": [], "+x": [], "-z": [], "+z": []}
    inner = []
    for x, z, dx, dz in offsets(columns, grid):
        if x == 0:
            sides["-x"].append(-dx)
        if x == nx - 1:
            sides["+x"].append(dx)
        if z == 0:
            sides["-z"].append(-dz)
        if z == nz - 1:
            sides["+z"].append(dz)
        if 0 < x < nx - 1 and 0 < z < nz - 1:
            inner.append((dx, dz))
    mean = lambda v: sum(v) / len(v) if v else float("nan")
    out = {k: mean(v) for k, v in sides.items()}
    out["inner"] = (mean([d[0] for d in inner]), mean([d[1] for d in inner]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("trajectories", nargs="+", help="rubble run --out files (.csv)")
    ap.add_argument("--grid", nargs=3, type=int, required=True, metavar=("X", "Y", "Z"),
                    help="the grid generator's count (crates along x, layers, along z)")
    ap.add_argument("--prefix", default="d", help="the generator's name_prefix (default d)")
    ap.add_argument("--steps", type=parse_steps, default=None,
                    help="steps to report, comma separated (default: every step in the file)")
    ap.add_argument("--sides", action="store_true",
                    help="print each side's mean outward lean and the inner columns' mean lean")
    args = ap.parse_args(argv)
    if min(args.grid) < 1 or args.grid[1] < 2:
        ap.error("--grid: at least one crate along x and z and two layers")
    tables = []
    for path in args.trajectories:
        try:
            by_step = read_columns(path, args.grid, args.prefix, set(args.steps or []))
        except (OSError, ValueError) as e:
            print("bench/column_lean.py: %s" % e, file=sys.stderr)
            return 2
        if not by_step:
            print("bench/column_lean.py: %s: no crate named %s<index> at those steps" %
                  (path, args.prefix), file=sys.stderr)
            return 2
        tables.append((path, by_step))
    if args.sides:
        print("%-28s %6s %7s %7s %7s %7s %8s %8s" % ("file", "step", "-x", "+x", "-z", "+z",
                                                     "inner x", "inner z"))
        for path, by_step in tables:
            for step in sorted(by_step):
                m = side_leans(by_step[step], args.grid)
                print("%-28s %6d %7.3f %7.3f %7.3f %7.3f %8.4f %8.4f" % (
                    path[-28:], step, m["-x"], m["+x"], m["-z"], m["+z"], m["inner"][0],
                    m["inner"][1]))
        return 0
    print("%-28s %6s %7s %11s %10s %11s %10s" % ("file", "step", "columns", "edge median",
                                                 "edge p90", "inner median", "inner p90"))
    for path, by_step in tables:
        for step in sorted(by_step):
            edge, inside = leans(by_step[step], args.grid)
            print("%-28s %6d %7d %11.3f %10.3f %11.3f %10.3f" % (
                path[-28:], step, len(edge) + len(inside), quantile(edge, 0.5),
                quantile(edge, 0.9), quantile(inside, 0.5), quantile(inside, 0.9)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
