# bench/first_difference.py: two runs of the same scene and settings are the same bits through
# their last step; a run with fewer solver sweeps parts from it at the first step with contacts,
# and names how many bodies differ; a file that is not a trajectory is named.
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "bench" / "first_difference.py"
SCENE = REPO / "scenes" / "stack_10.json"


def trajectory(rubble_binary, path, *extra):
    subprocess.run([str(rubble_binary), "run", str(SCENE), "--steps", "20", "--out", str(path),
                    "--quiet", *extra], check=True, timeout=120)
    return path


def first_difference(*paths):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, paths)], capture_output=True,
                          text=True, timeout=60)


def test_the_same_run_is_the_same_bits(tmp_path, rubble_binary):
    a = trajectory(rubble_binary, tmp_path / "a.csv")
    b = trajectory(rubble_binary, tmp_path / "b.csv")
    done = first_difference(a, b)
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("the same bits through step 20 (11 bodies)")


def test_fewer_sweeps_part_at_a_step_with_contacts(tmp_path, rubble_binary):
    a = trajectory(rubble_binary, tmp_path / "a.csv")
    b = trajectory(rubble_binary, tmp_path / "b.csv", "--iterations", "2")
    done = first_difference(a, b)
    assert done.returncode == 1, done.stdout + done.stderr
    # stack_10's crates start resting on each other: the solve differs from the first step.
    assert done.stdout.startswith("part at step 1: ")
    assert "of 11 bodies differ" in done.stdout


def test_a_file_that_is_not_a_trajectory_is_named(tmp_path, rubble_binary):
    a = trajectory(rubble_binary, tmp_path / "a.csv")
    bad = tmp_path / "bad.csv"
    bad.write_text("step,time\n0,0\n")
    done = first_difference(a, bad)
    assert done.returncode == 2
    assert "bad.csv: not a trajectory" in done.stderr
    done = first_difference(a, tmp_path / "missing.csv")
    assert done.returncode == 2
    assert "missing.csv: cannot be read" in done.stderr
