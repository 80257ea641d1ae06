# bench/identity: a build against itself keeps every compared trajectory to the byte, a run whose
# arguments change the physics on one side only is reported as different (exit 1), and a path
# that is not a rubble binary is refused by name.
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "bench" / "identity"


def identity(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, cwd=REPO, timeout=300)


def test_a_build_against_itself_is_the_same(rubble_binary):
    done = identity(rubble_binary, rubble_binary, "--only", "cpu-stack_10")
    assert done.returncode == 0, done.stdout + done.stderr
    assert done.stdout.startswith("same") and "cpu-stack_10" in done.stdout


def test_other_physics_on_one_side_differs(rubble_binary):
    # Three solver sweeps instead of the scene's ten, on the base's side only.
    done = identity(rubble_binary, rubble_binary, "--only", "cpu-stack_10",
                    "--extra-base=--iterations", "--extra-base=3")
    assert done.returncode == 1, done.stdout + done.stderr
    assert "DIFFERENT" in done.stdout and "trajectories differ" in done.stdout


def test_a_missing_binary_is_named(tmp_path, rubble_binary):
    done = identity(tmp_path / "nothing", rubble_binary)
    assert done.returncode != 0
    assert "nothing is not an executable rubble binary" in done.stderr
