# Sweeps on a local Dask cluster of two worker processes: the table, its physics, the same
# numbers as a run in this process, trajectories, and `rubble sweep SWEEP.json` from the shell.
import csv
import json
import math
import os
import stat
import sys

import numpy as np
import pytest

import rubble
from rubble import _sweep
from conftest import run_command

pytest.importorskip("dask.distributed")

SLOPE = rubble.example_scene("slope_below_friction")  # a crate on a 20 degree ramp
STEPS = 90  # 1.5 s


def slope_sweep(**kwargs):
    return rubble.sweep(SLOPE, grid={"materials.default.friction": [0.1, 0.2, 0.6],
                                     "iterations": [10, 20]},
                        metrics=["max_speed", "centre_of_mass_x", "kinetic_energy"],
                        steps=STEPS, as_frame=False, **kwargs)


@pytest.fixture(scope="module")
def cluster_client():
    from dask.distributed import Client, LocalCluster
    import logging

    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.WARNING) as cluster, Client(cluster) as client:
        yield client


def test_sweep_on_two_workers_gives_one_row_per_run_with_the_physics(cluster_client, tmp_path):
    table = slope_sweep(client=cluster_client, trajectory_dir=tmp_path, trajectory_every=30)
    assert list(table["run"]) == list(range(6))
    assert list(table["materials.default.friction"]) == [0.1, 0.1, 0.2, 0.2, 0.6, 0.6]
    assert list(table["iterations"]) == [10, 20] * 3
    assert set(table["error"]) == {""}
    # Both worker processes took part.
    assert len(cluster_client.scheduler_info()["workers"]) == 2
    # Below tan(20 deg) = 0.36 the crate slides with a = g (sin 20 - mu cos 20); above, it stays.
    g, theta, t = 9.81, math.radians(20), STEPS / 60
    for mu, speed in zip(table["materials.default.friction"], table["max_speed"]):
        if mu < math.tan(theta):
            assert speed == pytest.approx(g * (math.sin(theta) - mu * math.cos(theta)) * t,
                                          rel=0.05)
        else:
            assert speed < 0.02
    # Trajectories: 4 frames (steps 0, 30, 60, 90) of the two bodies.
    data = np.load(table["trajectory"][0])
    assert data["positions"].shape == (4, 2, 3) and data["orientations"].shape == (4, 2, 4)
    np.testing.assert_allclose(data["time"], [0, 0.5, 1.0, 1.5])
    assert json.loads(str(data["params"]))["materials.default.friction"] == 0.1


def test_a_workers_run_is_the_same_as_a_run_here(cluster_client):
    table = slope_sweep(client=cluster_client)
    doc, label, folder = _sweep._load_doc(SLOPE, None)
    base = {"doc": doc, "label": label, "base_dir": folder, "options": {},
            "metrics": ["max_speed", "centre_of_mass_x", "kinetic_energy"],
            "trajectory_dir": "", "trajectory_every": 10}
    here = _sweep.run_one(base, {"run": 2, "params": {"materials.default.friction": 0.2,
                                                      "iterations": 10},
                                 "seed": None, "steps": STEPS})
    for key in ("max_speed", "centre_of_mass_x", "kinetic_energy"):
        assert table[key][2] == here[key]  # deterministic: the same bytes in any process


def test_seeds_vary_the_generator_and_bad_keys_fail_before_running(cluster_client):
    scene = {"format": "rubble-scene", "version": 1, "simulation": {"dt": 1 / 60},
             "shapes": {"floor": {"type": "plane", "normal": [0, 1, 0]},
                        "crate": {"type": "box", "half_extents": [0.25, 0.25, 0.25]}},
             "bodies": [{"name": "floor", "shape": "floor", "static": True}],
             "generators": [{"type": "grid", "shape": "crate", "mass": 1.0, "count": [2, 2, 1],
                             "origin": [0, 1, 0], "spacing": [0.6, 0.6, 0.6],
                             "rotation_jitter": 0.5}]}
    table = rubble.sweep(scene, seeds=range(3), metrics=["kinetic_energy", "centre_of_mass_x"],
                         steps=30, client=cluster_client, as_frame=False)
    assert list(table["seed"]) == [0, 1, 2]
    assert len(set(table["centre_of_mass_x"])) == 3  # three different jitters, three piles
    with pytest.raises(rubble.SceneError, match="simulation.solver.iteration"):
        rubble.sweep(scene, grid={"solver.iteration": [5]}, client=cluster_client)
    with pytest.raises(rubble.SceneError, match="metrics"):
        rubble.sweep(scene, metrics=["happiness"], client=cluster_client)
    with pytest.raises(rubble.SceneError, match="no grid generator"):
        rubble.sweep(SLOPE, seeds=[1, 2], client=cluster_client)


def test_a_grid_is_read_once_and_must_be_lists(cluster_client):
    # A generator is read once: the pre-check and the plan see the same values.
    table = rubble.sweep(SLOPE, grid={"iterations": (k for k in (10, 20))}, metrics=["max_speed"],
                         steps=1, client=cluster_client, as_frame=False)
    assert list(table["iterations"]) == [10, 20]
    # A string is not a list of values (not the values "1" and "0").
    with pytest.raises(rubble.SceneError, match="grid: iterations: expected a list of values"):
        rubble.sweep(SLOPE, grid={"iterations": "10"}, client=cluster_client)


def test_the_sweep_command_writes_the_same_table(tmp_path, rubble_binary, cluster_client):
    spec = {"scene": os.path.relpath(SLOPE, tmp_path), "steps": STEPS,
            "grid": {"materials.default.friction": [0.1, 0.2, 0.6], "iterations": [10, 20]},
            "metrics": ["max_speed", "centre_of_mass_x", "kinetic_energy"]}
    (tmp_path / "sweep.json").write_text(json.dumps(spec))
    env = dict(os.environ, RUBBLE_PYTHON=sys.executable)
    out = tmp_path / "table.csv"
    done = run_command(rubble_binary, "sweep", tmp_path / "sweep.json", "--workers", 2,
                       "--out", out, env=env)
    assert "sweep of 6 runs on a local cluster of 2 workers" in done.stderr
    with open(out, newline="") as f:
        rows = list(csv.DictReader(f))
    table = slope_sweep(client=cluster_client)
    assert len(rows) == 6
    for i, row in enumerate(rows):
        assert float(row["max_speed"]) == table["max_speed"][i]
        assert float(row["materials.default.friction"]) == table["materials.default.friction"][i]


def test_the_sweep_command_says_when_the_package_is_missing(tmp_path, rubble_binary):
    # An interpreter without site-packages cannot import the installed package.
    python = tmp_path / "python-without-rubble"
    python.write_text(f"#!/bin/sh\nexec {sys.executable} -S \"$@\"\n")
    python.chmod(python.stat().st_mode | stat.S_IEXEC)
    (tmp_path / "sweep.json").write_text('{"scene": "x.json"}')
    done = run_command(rubble_binary, "sweep", tmp_path / "sweep.json", check=False,
                       env=dict(os.environ, RUBBLE_PYTHON=str(python)))
    assert done.returncode == 1
    assert "the Python package rubble is not installed" in done.stderr
    assert "docs/python.md" in done.stderr


def test_a_bad_sweep_file_names_the_field(tmp_path, rubble_binary):
    path = tmp_path / "sweep.json"
    path.write_text(json.dumps({"scene": os.path.relpath(SLOPE, tmp_path), "grids": {}}))
    done = run_command(rubble_binary, "sweep", path, check=False,
                       env=dict(os.environ, RUBBLE_PYTHON=sys.executable))
    assert done.returncode == 2
    assert f"{path}: grids: unknown key" in done.stderr
