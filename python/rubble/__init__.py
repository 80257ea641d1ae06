"""rubble: rigid-body simulation on the CPU and on OpenCL devices, from Python.

    import rubble
    w = rubble.World.load(rubble.example_scene("stack_10"), solver="pgs", iterations=20)
    w.step(120)                  # the GIL is released while it steps
    w.positions                  # (N, 3) float32, one row per body

See docs/python.md in the rubble repository for a tour.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Union

from rubble._errors import (DeviceError, Error, IoError, LimitError, NotSupportedError,
                            NumericalError, SceneError, StepInterrupted)
from rubble._core import World, __version__
from rubble import _core
from rubble._tables import Table, make_table

SceneSource = Union[str, "os.PathLike[str]", Mapping[str, Any]]

__all__ = [
    "World", "compare", "solvers", "solver_suite", "devices", "example_scene", "example_scenes", "sweep",
    "Table", "Error", "SceneError", "NotSupportedError", "DeviceError", "NumericalError",
    "LimitError", "StepInterrupted", "IoError", "__version__",
]

_SCENES = Path(__file__).resolve().parent / "scenes"


def example_scenes() -> List[str]:
    """The names of the installed example scenes (those of scenes/ and scenes/bench/)."""
    names = [p.stem for p in _SCENES.glob("*.json")] + [p.stem for p in _SCENES.glob("bench/*.json")]
    return sorted(names)


def example_scene(name: str) -> str:
    """The path of an installed example scene: "pendulum", "stack_10", "debris_1k", ...

    Raises KeyError listing the names there are."""
    for candidate in (_SCENES / f"{name}.json", _SCENES / "bench" / f"{name}.json"):
        if candidate.is_file():
            return str(candidate)
    raise KeyError(f"no example scene named {name!r} (there are: {', '.join(example_scenes())})")


def _scene_args(base_dir: Optional[Union[str, "os.PathLike[str]"]],
                label: Optional[str]) -> Dict[str, Any]:
    return {"base_dir": os.fspath(base_dir) if base_dir is not None else "",
            "label": label or ""}


def compare(scene: SceneSource, a: Optional[Mapping[str, Any]] = None,
            b: Optional[Mapping[str, Any]] = None, steps: int = 60, *,
            base_dir: Optional[Union[str, "os.PathLike[str]"]] = None,
            label: Optional[str] = None, as_frame: Optional[bool] = None):
    """Runs one scene on two sets of options side by side, as ``rubble compare``.

    a, b: options of each side, as World.load's keywords or the command's KEY=VALUE keys
        (backend, collision, solver, iterations, integrator, particle_spacing, dt, device,
        deterministic); a side left empty keeps the scene's settings.
    steps: compared steps; the table has steps + 1 rows (step 0 is the scene as loaded).

    Returns the table of ``rubble compare --csv`` (columns step, time, position_max,
    position_rms, angle_max, angle_rms, then kinetic_energy, linear_momentum,
    angular_momentum, largest_penetration, residual and contacts of each side, suffixed _a and
    _b): a pandas DataFrame when pandas is installed (or as_frame=True), else a rubble.Table of
    NumPy arrays. Raises rubble.SceneError for bad input, rubble.NumericalError when a side
    blows up, rubble.DeviceError for OpenCL failures.
    """
    columns = _core.compare(scene, dict(a or {}), dict(b or {}), steps,
                            **_scene_args(base_dir, label))
    return make_table(columns, {"a": dict(a or {}), "b": dict(b or {})}, as_frame)


def solvers(scene: SceneSource, step: int = 30, iterations: int = 50, *,
            collision: Optional[str] = None, frictionless: bool = False,
            device: Optional[Union[int, str]] = None, kernel_dir: Optional[str] = None,
            base_dir: Optional[Union[str, "os.PathLike[str]"]] = None,
            label: Optional[str] = None, as_frame: Optional[bool] = None):
    """Freezes the contact set of one step and runs every solver on it, as ``rubble solvers``.

    Returns the table of ``rubble solvers --csv``: one row per solver, backend and iteration
    (columns solver, backend, iteration, residual, complementarity, velocity_error; lemke's row,
    when it has an answer, gives its pivot count as the iteration), with ``attrs`` holding
    collision, contacts, rows, frictionless and skipped ({"solver/backend": reason}).
    Raises rubble.SceneError for bad input or a step without contacts.
    """
    options: Dict[str, Any] = {}
    if collision is not None:
        options["collision"] = collision
    if device is not None:
        options["device"] = device
    if kernel_dir is not None:
        options["kernel_dir"] = kernel_dir
    columns, info = _core.solvers(scene, step, iterations, options, frictionless,
                                  **_scene_args(base_dir, label))
    return make_table(columns, info, as_frame)


def solver_suite(scenes: Optional[Union[str, "os.PathLike[str]", List[str]]] = None,
                 steps: int = 300, passes: int = 10, relax: int = 1,
                 paths: Optional[List[str]] = None, *,
                 device: Optional[Union[int, str]] = None, as_frame: Optional[bool] = None):
    """Runs the solver test set as ``rubble solvers --suite``: every scene with pgs, jacobi,
    lcp-jacobi and soft-step on the CPU, and pgs and soft-step on the device's colored and
    blocked paths, at equal constraint passes (soft step: passes // (1 + relax) substeps).

    scenes: scene files, or a folder of them (default: the repository's scenes/solver).
    paths: any of "cpu", "device-colored", "device-blocks" (default all three).
    Returns the table of ``rubble solvers --suite --csv`` (columns scene, solver, path,
    settings, steps, stands, top_drift, top_creep, penetration, energy_gained, joint_error, ms_per_step,
    skipped). Raises rubble.SceneError for a scene that does not load or bad counts.
    """
    if scenes is None:
        scenes = _SCENES / "solver"
    if isinstance(scenes, (str, os.PathLike)):
        folder = os.fspath(scenes)
        scenes = ([os.path.join(folder, f) for f in sorted(os.listdir(folder))
                   if f.endswith(".json")] if os.path.isdir(folder) else [folder])
    options: Dict[str, Any] = {}
    if device is not None:
        options["device"] = device
    columns = _core.solver_suite([os.fspath(s) for s in scenes], steps, passes, relax,
                                 list(paths or ["cpu", "device-colored", "device-blocks"]),
                                 options)
    return make_table(columns, {}, as_frame)


def devices() -> List[Dict[str, Any]]:
    """The OpenCL devices of every platform, as dicts (index, platform, name, version, driver,
    compute_units, global_memory, max_allocation); the index is what ``device=`` takes.
    Raises rubble.NotSupportedError when there is no OpenCL platform."""
    return _core.devices()


from rubble._sweep import sweep  # noqa: E402  (dask is imported when a sweep runs)
