"""Parameter sweeps on Dask distributed: every combination of a grid of scene fields and
options, times a list of seeds, each run as a task that builds a world in a worker process,
steps it and returns its metrics (and, if asked, writes its trajectory to a shared folder).

``rubble.sweep(...)`` from Python; ``rubble sweep SWEEP.json`` or
``python3 -m rubble sweep SWEEP.json`` from the shell (the file's format is in docs/python.md).
"""

from __future__ import annotations

import argparse
import copy
import itertools
import json
import math
import os
import sys
import time
from pathlib import Path
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from rubble import _core
from rubble._errors import Error, NumericalError, SceneError
from rubble._tables import Table, make_table

# World.load's keywords: a grid key among them is an option, any other a path into the scene.
OPTION_KEYS = _core.OPTION_KEYS
_TOP_KEYS = _core.SCENE_KEYS
_VECTOR_METRICS = ("linear_momentum", "angular_momentum", "centre_of_mass", "lo", "hi")
_SCALAR_METRICS = ("time", "step", "bodies", "dynamic_bodies", "asleep_bodies",
                   "kinetic_energy", "potential_energy", "max_speed", "contacts",
                   "largest_penetration", "solver_residual", "step_ms")
#: What a sweep may record per run: World.metrics()'s numbers (vectors as _x, _y, _z), the
#: run's wall time of stepping, s, and its ms per step.
METRICS = (_SCALAR_METRICS + tuple(f"{v}_{c}" for v in _VECTOR_METRICS for c in "xyz")
           + ("wall_s", "ms_per_step"))
DEFAULT_METRICS = ("kinetic_energy", "potential_energy", "max_speed", "asleep_bodies",
                   "largest_penetration", "centre_of_mass_y", "wall_s")


def _bad_input(file: str, field: str, message: str) -> SceneError:
    """A SceneError at ``file: field``, as the scene reader words its own."""
    return SceneError(f"{file}: {field}: {message}", where=f"{file}: {field}", kind="BadInput",
                      file=file, field=field)


def set_field(doc: Dict[str, Any], key: str, value: Any, label: str) -> None:
    """Sets a field of a scene document by a dotted path: ``solver.iterations`` (a key of
    ``simulation`` may leave ``simulation.`` out), ``materials.default.friction``,
    ``bodies.crate.mass`` (a list's element by index or by its ``name``). Missing objects on
    the way are made; the scene reader then rejects a misspelt key, naming it."""
    parts = key.split(".")
    if parts[0] not in _TOP_KEYS:
        parts = ["simulation"] + parts
    node: Any = doc
    for depth, part in enumerate(parts):
        last = depth == len(parts) - 1
        here = ".".join(parts[:depth + 1])
        if isinstance(node, list):
            index = _element(node, part)
            if index is None:
                raise _bad_input(label, here, "no element with that index or name")
            if last:
                node[index] = value
            else:
                node = node[index]
        elif isinstance(node, dict):
            if last:
                node[part] = value
            else:
                node = node.setdefault(part, {})
        else:
            raise _bad_input(label, here, f"{'.'.join(parts[:depth])} is not an object")


def _element(items: List[Any], part: str) -> Optional[int]:
    if part.lstrip("-").isdigit() and -len(items) <= int(part) < len(items):
        return int(part) % len(items)
    for i, item in enumerate(items):
        if isinstance(item, dict) and item.get("name") == part:
            return i
    return None


def _set_seed(doc: Dict[str, Any], seed: int, label: str) -> None:
    grids = [g for g in doc.get("generators", []) if isinstance(g, dict) and g.get("type") == "grid"]
    if not grids:
        raise _bad_input(label, "seeds", "the scene has no grid generator whose seed could vary "
                         "(a seed sets generators[*].seed)")
    for g in grids:
        g["seed"] = int(seed)


def _scene_and_options(base: Dict[str, Any], params: Mapping[str, Any], seed: Optional[int],
                       label: str) -> Tuple[Dict[str, Any], Dict[str, Any]]:
    """The base scene document and options with a run's grid values and seed applied: a grid
    key among World.load's options sets the option, any other the scene field it names."""
    doc = copy.deepcopy(base["doc"])
    options = dict(base["options"])
    for key, value in params.items():
        if key in OPTION_KEYS:
            options[key] = value
        else:
            set_field(doc, key, value, label)
    if seed is not None:
        _set_seed(doc, seed, label)
    return doc, options


def _flatten_metrics(m: Mapping[str, Any]) -> Dict[str, float]:
    out: Dict[str, float] = {k: m[k] for k in _SCALAR_METRICS}
    for v in _VECTOR_METRICS:
        for c, x in zip("xyz", m[v]):
            out[f"{v}_{c}"] = x
    return out


def run_one(base: Dict[str, Any], task: Dict[str, Any]) -> Dict[str, Any]:
    """One run of a sweep, in whatever process calls it (a Dask worker): the base scene with
    the task's fields, options and seed, stepped task["steps"] times; returns its row."""
    from rubble import World

    label = f"{base['label']} (run {task['run']})"
    doc, options = _scene_and_options(base, task["params"], task["seed"], label)
    world = World.load(doc, base_dir=base["base_dir"], label=label, **options)
    steps = task["steps"] if task["steps"] is not None else world.options["steps"]
    every = base["trajectory_every"]
    frames: Dict[str, List[np.ndarray]] = {"time": [], "positions": [], "orientations": [],
                                           "velocities": [], "angular_velocities": []}

    def record() -> None:
        frames["time"].append(np.array(world.time))
        for name in ("positions", "orientations", "velocities", "angular_velocities"):
            frames[name].append(getattr(world, name))

    error = ""
    start = time.perf_counter()
    try:
        if base["trajectory_dir"]:
            record()
            done = 0
            while done < steps:
                n = min(every, steps - done)
                world.step(n)
                done += n
                record()
        else:
            world.step(steps)
    except NumericalError as e:
        error = str(e)
    wall = time.perf_counter() - start
    row: Dict[str, Any] = {"run": task["run"], **task["params"]}
    if task["seed"] is not None:
        row["seed"] = task["seed"]
    values = _flatten_metrics(world.metrics())
    values["wall_s"] = wall
    values["ms_per_step"] = 1e3 * wall / world.step_count if world.step_count else math.nan
    for name in base["metrics"]:
        row[name] = values[name]
    row["error"] = error
    if base["trajectory_dir"]:
        path = Path(base["trajectory_dir"]) / f"run_{task['run']:05d}.npz"
        np.savez_compressed(path, names=np.array(world.names),
                            params=np.array(json.dumps({**task["params"], "seed": task["seed"]})),
                            **{k: np.stack(v) for k, v in frames.items()})
        row["trajectory"] = str(path)
    return row


def _grid_lists(grid: Mapping[str, Iterable[Any]]) -> Dict[str, List[Any]]:
    """The grid's values as lists, read once (a generator is not read again by the plan)."""
    for k, values in grid.items():
        if isinstance(values, (str, bytes)) or not isinstance(values, Iterable):
            raise SceneError(f"grid: {k}: expected a list of values", where=f"grid: {k}",
                             kind="BadInput")
    return {k: list(values) for k, values in grid.items()}


def _plan(grid: Mapping[str, List[Any]], seeds: Optional[List[int]],
          steps: Optional[int]) -> List[Dict[str, Any]]:
    """The tasks: every combination of the grid's values, each with every seed, in that order."""
    keys = list(grid)
    combos = itertools.product(itertools.product(*grid.values()),
                               seeds if seeds is not None else [None])
    return [{"run": run, "params": dict(zip(keys, combo)), "seed": seed, "steps": steps}
            for run, (combo, seed) in enumerate(combos)]


def _check(base: Dict[str, Any], grid: Mapping[str, List[Any]],
           seeds: Optional[List[int]]) -> None:
    """Reads the scene once per grid value (no world is built), so that a bad key or value is
    an error before any task runs."""
    seed = seeds[0] if seeds else None
    probes = [{}] + [{key: v} for key, values in grid.items() for v in values]
    for params in probes:
        doc, options = _scene_and_options(base, params, seed, base["label"])
        _core.check_scene(doc, options, base_dir=base["base_dir"], label=base["label"])


def _load_doc(scene: Union[str, "os.PathLike[str]", Mapping[str, Any]],
              base_dir: Optional[Union[str, "os.PathLike[str]"]]) -> Tuple[Dict[str, Any], str, str]:
    if isinstance(scene, Mapping):
        folder = os.path.abspath(os.fspath(base_dir)) if base_dir is not None else os.getcwd()
        return copy.deepcopy(dict(scene)), "<scene dict>", folder
    path = os.fspath(scene)
    _core.check_scene(path, {})  # the file's own errors, named as the command names them
    with open(path, encoding="utf-8") as f:
        doc = json.load(f)
    folder = os.path.abspath(os.fspath(base_dir)) if base_dir is not None else \
        os.path.dirname(os.path.abspath(path))
    return doc, path, folder


def sweep(scene: Union[str, "os.PathLike[str]", Mapping[str, Any]],
          grid: Optional[Mapping[str, Sequence[Any]]] = None,
          seeds: Optional[Iterable[int]] = None,
          metrics: Optional[Sequence[str]] = None, *,
          steps: Optional[int] = None,
          options: Optional[Mapping[str, Any]] = None,
          client: Any = None, scheduler: Optional[str] = None, workers: Optional[int] = None,
          trajectory_dir: Optional[Union[str, "os.PathLike[str]"]] = None,
          trajectory_every: int = 10,
          base_dir: Optional[Union[str, "os.PathLike[str]"]] = None,
          as_frame: Optional[bool] = None):
    """Runs every combination of ``grid`` (times ``seeds``) as a Dask task and returns one table.

    scene: a scene file or a dict in the scene format.
    grid: {key: [values]}; a key is one of World.load's options (``iterations``, ``solver``,
        ``backend``, ...) or a dotted path into the scene (``solver.iterations``,
        ``materials.default.friction``, ``bodies.crate.mass``, ``gravity``).
    seeds: each seed sets the seed of the scene's grid generators (their rotation jitter);
        None runs each combination once as the scene is.
    metrics: names from rubble.sweep.METRICS (default DEFAULT_METRICS).
    steps: steps per run (default the scene's simulation.steps, or an ``steps`` option).
    options: World.load options for every run (overridden by grid keys of the same name).
    client: a dask.distributed.Client to run on; else ``scheduler`` ("tcp://host:8786") to
        connect to; else a local cluster of ``workers`` processes (default: the CPU count),
        one thread each, closed at the end.
    trajectory_dir: a folder every worker can write (shared, on a cluster): each run writes
        run_NNNNN.npz (time, positions, orientations, velocities, angular_velocities every
        ``trajectory_every`` steps, names, params); the table's ``trajectory`` column names it.

    Returns a table with a row per run, in run order: run, the grid keys, seed (when seeds are
    given), the metrics, and error (the message of a run that blew up, its metrics those of
    its last state; empty otherwise). A pandas DataFrame when pandas is installed, else a
    rubble.Table. Raises rubble.SceneError for a bad key, value, metric or scene before any
    run starts.
    """
    grid = _grid_lists(grid or {})
    metrics = list(metrics or DEFAULT_METRICS)
    unknown = [m for m in metrics if m not in METRICS]
    if unknown:
        raise SceneError(f"metrics: unknown {', '.join(map(repr, unknown))} (expected some of "
                         f"{', '.join(METRICS)})", where="metrics", kind="BadInput")
    if trajectory_every < 1:
        raise SceneError("trajectory_every: must be 1 or more", where="trajectory_every",
                         kind="BadInput")
    doc, label, folder = _load_doc(scene, base_dir)
    traj = os.path.abspath(os.fspath(trajectory_dir)) if trajectory_dir is not None else ""
    if traj:
        os.makedirs(traj, exist_ok=True)
    base = {"doc": doc, "label": label, "base_dir": folder, "options": dict(options or {}),
            "metrics": metrics, "trajectory_dir": traj, "trajectory_every": trajectory_every}
    seed_list = [int(s) for s in seeds] if seeds is not None else None
    _check(base, grid, seed_list)
    tasks = _plan(grid, seed_list, steps)

    rows = _run_on_dask(base, tasks, client, scheduler, workers)  # in the tasks' order
    columns: Dict[str, np.ndarray] = {}
    for name in rows[0] if rows else []:
        values = [r[name] for r in rows]
        columns[name] = np.array(values, dtype=object if isinstance(values[0], str) else None)
    attrs = {"scene": label, "runs": len(rows), "steps": steps, "options": dict(options or {})}
    return make_table(columns, attrs, as_frame)


def _run_on_dask(base: Dict[str, Any], tasks: List[Dict[str, Any]], client: Any,
                 scheduler: Optional[str], workers: Optional[int]) -> List[Dict[str, Any]]:
    try:
        from dask.distributed import Client, LocalCluster
    except ImportError as e:
        raise ImportError("rubble.sweep needs Dask distributed: pip install 'dask[distributed]' "
                          "(or the package's extra: pip install '.[sweep]')") from e
    owned: List[Any] = []
    try:
        if client is None and scheduler:
            client = Client(scheduler)
            owned.append(client)
        elif client is None:
            import logging

            cluster = LocalCluster(n_workers=workers or os.cpu_count() or 1, threads_per_worker=1,
                                   processes=True, dashboard_address=None,
                                   silence_logs=logging.WARNING)
            owned.append(cluster)
            client = Client(cluster)
            owned.insert(0, client)
        # The scene goes to every worker once; each task carries its own fields. (In a list: a
        # dict would be scattered as one datum per key, under its keys' names.)
        [shared] = client.scatter([base], broadcast=True)
        futures = client.map(run_one, [shared] * len(tasks), tasks, pure=False)
        return client.gather(futures)
    finally:
        for o in owned:
            o.close()


# The command line: rubble sweep SWEEP.json, python3 -m rubble sweep SWEEP.json.

_SWEEP_KEYS = ("scene", "steps", "grid", "seeds", "metrics", "options", "trajectory",
               "workers", "scheduler", "out")


def _from_file(path: str) -> Dict[str, Any]:
    """The keyword arguments of sweep() from a sweep file (docs/python.md); paths in it are
    relative to its folder. Raises SceneError naming the file and the field."""
    def bad(field: str, message: str) -> SceneError:
        return _bad_input(path, field, message)

    def whole(value: Any, field: str, least: int) -> int:
        if not isinstance(value, int) or isinstance(value, bool) or value < least:
            raise bad(field, f"expected a whole number of {least} or more")
        return value

    try:
        with open(path, encoding="utf-8") as f:
            spec = json.load(f)
    except FileNotFoundError:
        raise SceneError(f"{path}: sweep file not found", where=path, kind="BadInput",
                         file=path) from None
    except json.JSONDecodeError as e:
        raise SceneError(f"{path}: malformed JSON at line {e.lineno}, column {e.colno}: {e.msg}",
                         where=path, kind="BadInput", file=path) from None
    if not isinstance(spec, dict):
        raise bad("(top level)", "expected an object")
    for key in spec:
        if key not in _SWEEP_KEYS:
            raise bad(key, f"unknown key (expected {', '.join(_SWEEP_KEYS)})")
    if "scene" not in spec or not isinstance(spec["scene"], str):
        raise bad("scene", "required: the scene file, relative to the sweep file")
    folder = os.path.dirname(os.path.abspath(path))
    kwargs: Dict[str, Any] = {"scene": os.path.join(folder, spec["scene"])}
    if "steps" in spec:
        kwargs["steps"] = whole(spec["steps"], "steps", 0)
    if "grid" in spec:
        if not isinstance(spec["grid"], dict):
            raise bad("grid", "expected an object of lists")
        for k, v in spec["grid"].items():
            if not isinstance(v, list) or not v:
                raise bad(f"grid.{k}", "expected a non-empty list of values")
        kwargs["grid"] = spec["grid"]
    if "seeds" in spec:
        s = spec["seeds"]
        if isinstance(s, int) and not isinstance(s, bool) and s >= 1:
            kwargs["seeds"] = range(s)
        elif isinstance(s, list) and s and all(isinstance(x, int) and not isinstance(x, bool) for x in s):
            kwargs["seeds"] = s
        else:
            raise bad("seeds", "expected a count (1 or more) or a list of whole numbers")
    if "metrics" in spec:
        if not isinstance(spec["metrics"], list) or not all(isinstance(m, str) for m in spec["metrics"]):
            raise bad("metrics", "expected a list of names")
        unknown = [m for m in spec["metrics"] if m not in METRICS]
        if unknown:
            raise bad("metrics", f"unknown {', '.join(unknown)} (expected some of {', '.join(METRICS)})")
        kwargs["metrics"] = spec["metrics"]
    if "options" in spec:
        if not isinstance(spec["options"], dict):
            raise bad("options", "expected an object of World.load options")
        kwargs["options"] = spec["options"]
    if "trajectory" in spec:
        t = spec["trajectory"]
        if not isinstance(t, dict) or "folder" not in t or set(t) - {"folder", "every"}:
            raise bad("trajectory", 'expected {"folder": "...", "every": K}')
        kwargs["trajectory_dir"] = os.path.join(folder, t["folder"])
        if "every" in t:
            kwargs["trajectory_every"] = whole(t["every"], "trajectory.every", 1)
    if "workers" in spec:
        kwargs["workers"] = whole(spec["workers"], "workers", 1)
    if "scheduler" in spec:
        if not isinstance(spec["scheduler"], str):
            raise bad("scheduler", 'expected an address, "tcp://host:port"')
        kwargs["scheduler"] = spec["scheduler"]
    if "out" in spec:
        if not isinstance(spec["out"], str):
            raise bad("out", "expected a file name")
        kwargs["out"] = os.path.join(folder, spec["out"])
    return kwargs


def _write_csv(table: Table, out: Any) -> None:
    """The table's columns, floats as their shortest repr (they read back to the same number)."""
    import csv

    writer = csv.writer(out, lineterminator="\n")
    writer.writerow(list(table))
    for row in zip(*table.values()):
        writer.writerow([repr(float(v)) if isinstance(v, (float, np.floating)) else v
                         for v in row])


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``rubble sweep SWEEP.json [--workers N] [--scheduler ADDRESS] [--out FILE.csv]``: runs
    the sweep and writes its table as CSV (stdout by default). Exit status 0 done, 1 a device
    or cluster failure, 2 bad input."""
    parser = argparse.ArgumentParser(prog="rubble sweep", description=main.__doc__)
    parser.add_argument("sweep", help="sweep file (JSON, docs/python.md)")
    parser.add_argument("--workers", type=int, help="workers of the local Dask cluster")
    parser.add_argument("--scheduler", help="a Dask scheduler, tcp://host:port")
    parser.add_argument("--out", help="write the table as CSV here instead of stdout")
    args = parser.parse_args(argv)
    try:
        kwargs = _from_file(args.sweep)
        if args.workers is not None:
            if args.workers < 1:
                raise SceneError("--workers: must be 1 or more", where="--workers",
                                 kind="BadInput")
            kwargs["workers"] = args.workers
        if args.scheduler:
            kwargs["scheduler"] = args.scheduler
        out = kwargs.pop("out", None)
        out = args.out or out
        start = time.perf_counter()
        table = sweep(**kwargs, as_frame=False)
        seconds = time.perf_counter() - start
    except (SceneError, ValueError) as e:
        print(f"rubble: {e}", file=sys.stderr)
        return 2
    except (Error, OSError, ImportError) as e:
        print(f"rubble: {e}", file=sys.stderr)
        return 1
    if out:
        with open(out, "w", encoding="utf-8", newline="") as f:
            _write_csv(table, f)
    else:
        _write_csv(table, sys.stdout)
    runs = table.attrs["runs"]
    failed = int(sum(1 for e in table.get("error", []) if e))
    where = kwargs.get("scheduler") or f"a local cluster of {kwargs.get('workers') or os.cpu_count()} workers"
    print(f"rubble: sweep of {runs} runs on {where} in {seconds:.2f} s"
          f"{f', {failed} blew up' if failed else ''}{f', wrote {out}' if out else ''}",
          file=sys.stderr)
    return 0
