# The arrays the package reads are the numbers the command writes: the same scene run by
# `rubble run --out x.csv` and by World.step gives the same float32 values, bit for bit.
import csv

import numpy as np
import pytest

import rubble
from conftest import run_command


def read_csv(path):
    """step -> (names, positions, orientations, velocities, angular velocities) as float32."""
    steps = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            steps.setdefault(int(row["step"]), []).append(row)
    out = {}
    for step, rows in steps.items():
        cols = lambda *keys: np.array([[float(r[k]) for k in keys] for r in rows], dtype=np.float32)
        out[step] = ([r["body"] for r in rows], cols("px", "py", "pz"),
                     cols("qw", "qx", "qy", "qz"), cols("vx", "vy", "vz"), cols("wx", "wy", "wz"))
    return out


@pytest.mark.parametrize("scene, options", [
    ("stack_10", {}),
    ("pyramid_20", {"solver": "jacobi", "collision": "particles", "particle_spacing": 0.25}),
    ("ragdoll", {"iterations": 20}),
])
def test_arrays_match_the_commands_csv(tmp_path, rubble_binary, scene, options):
    path = rubble.example_scene(scene)
    steps, every = 60, 20
    flags = [f"--{k.replace('_', '-')}={v}" for k, v in options.items()]
    out = tmp_path / "run.csv"
    run_command(rubble_binary, "run", path, "--steps", steps, "--every", every, "--out", out,
                "--quiet", *flags)
    expected = read_csv(out)
    w = rubble.World.load(path, **options)
    for step in range(0, steps + 1, every):
        if step:
            w.step(every)
        names, x, q, v, omega = expected[step]
        assert w.names == names
        np.testing.assert_array_equal(w.positions, x, err_msg=f"{scene} step {step}")
        np.testing.assert_array_equal(w.orientations, q, err_msg=f"{scene} step {step}")
        np.testing.assert_array_equal(w.velocities, v, err_msg=f"{scene} step {step}")
        np.testing.assert_array_equal(w.angular_velocities, omega, err_msg=f"{scene} step {step}")


def test_arrays_are_fresh_float32_copies_in_body_order():
    w = rubble.World.load(rubble.example_scene("stack_10"))
    a = w.positions
    assert a.dtype == np.float32 and a.shape == (len(w), 3) and a.flags.c_contiguous
    assert w.orientations.shape == (len(w), 4)
    a[:] = 0  # the caller's copy: the world is not touched
    assert np.any(w.positions != 0)
    i = w.find_body(w.names[3])
    assert i == 3


def test_debris_added_from_python_joins_the_arrays():
    w = rubble.World.load(rubble.example_scene("box_rest"))
    first = w.add_debris("crate", [[0, 3, 0], [0, 5, 0]], mass=2.0,
                         velocities=[[1, 0, 0], [0, 0, 0]])
    assert first == 2 and len(w) == 4 and w.names[2:] == ["debris0", "debris1"]
    np.testing.assert_array_equal(w.positions[2:], [[0, 3, 0], [0, 5, 0]])
    np.testing.assert_array_equal(w.velocities[2], [1, 0, 0])
    w.step(240)
    # All three crates end on the floor or on each other, none below it.
    assert np.all(w.positions[1:, 1] > 0.45)
    # A box around debris1 alone: debris0 goes, the scene's bodies stay, debris1 moves down.
    kept = w.positions[3].copy()
    assert w.remove_debris_outside(kept - 0.01, kept + 0.01) == 1
    assert len(w) == 3 and w.names[2] == "debris1"
    np.testing.assert_array_equal(w.positions[2], kept)
