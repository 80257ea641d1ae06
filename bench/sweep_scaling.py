#!/usr/bin/env python3
"""bench/sweep_scaling.py: one parameter sweep on local Dask clusters of 1 and 2 workers, side
by side and repeated (alternating which goes first), with the cluster's start-up, the sweep's
wall time, the runs' own stepping time and the overhead per task (docs/BENCHMARKS.md,
"Parameter sweeps on Dask"). Needs the Python package with its sweep extra.

usage: python3 bench/sweep_scaling.py [--repeats R] [--steps N] [--seeds S] [--csv FILE]
The sweep: scenes/bench/debris_1k.json (1,024 crates falling into a pile), N steps (default 60)
per run, solver.iterations in {5, 10, 20} x materials.default.friction in {0.2, 0.5} x S seeds
(default 4): 24 runs.
"""

import argparse
import csv
import logging
import statistics
import sys
import time

import rubble


def one(workers, steps, seeds):
    from dask.distributed import Client, LocalCluster

    start = time.perf_counter()
    with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                      dashboard_address=None, silence_logs=logging.WARNING) as cluster, \
            Client(cluster) as client:
        client.wait_for_workers(workers)
        up = time.perf_counter() - start
        start = time.perf_counter()
        table = rubble.sweep(rubble.example_scene("debris_1k"),
                             grid={"solver.iterations": [5, 10, 20],
                                   "materials.default.friction": [0.2, 0.5]},
                             seeds=range(seeds), metrics=["wall_s", "kinetic_energy"],
                             steps=steps, client=client, as_frame=False)
        wall = time.perf_counter() - start
    runs = len(table["run"])
    busy = float(sum(table["wall_s"]))
    return {"workers": workers, "runs": runs, "cluster_start_s": up, "sweep_s": wall,
            "run_steps_s": busy, "overhead_per_task_ms": 1e3 * (wall * workers - busy) / runs}


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--repeats", type=int, default=5)
    p.add_argument("--steps", type=int, default=60)
    p.add_argument("--seeds", type=int, default=4)
    p.add_argument("--csv")
    args = p.parse_args()
    rows = []
    for r in range(args.repeats):
        for workers in ((1, 2) if r % 2 == 0 else (2, 1)):
            row = {"repeat": r, **one(workers, args.steps, args.seeds)}
            rows.append(row)
            print(" ".join(f"{k}={v:.3f}" if isinstance(v, float) else f"{k}={v}"
                           for k, v in row.items()), file=sys.stderr)
    med = {w: {k: statistics.median(row[k] for row in rows if row["workers"] == w)
               for k in ("cluster_start_s", "sweep_s", "run_steps_s", "overhead_per_task_ms")}
           for w in (1, 2)}
    print(f"sweep of {rows[0]['runs']} runs (debris_1k, {args.steps} steps each), medians of "
          f"{args.repeats}:")
    print(f"{'workers':>8} {'start s':>8} {'sweep s':>8} {'steps s':>8} {'ovh ms/task':>12}")
    for w in (1, 2):
        m = med[w]
        print(f"{w:>8} {m['cluster_start_s']:>8.2f} {m['sweep_s']:>8.2f} {m['run_steps_s']:>8.2f} "
              f"{m['overhead_per_task_ms']:>12.1f}")
    ratios = [a["sweep_s"] / b["sweep_s"] for a, b in
              zip([r for r in rows if r["workers"] == 1], [r for r in rows if r["workers"] == 2])]
    print(f"speed-up 1 -> 2 workers: {med[1]['sweep_s'] / med[2]['sweep_s']:.2f} (ratio of "
          f"medians); per repeat {', '.join(f'{x:.2f}' for x in ratios)}")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)


if __name__ == "__main__":
    main()
