# rubble.compare, rubble.solvers and rubble.devices give the commands' tables: every number is
# compared as the command prints it (%.6e) against its CSV.
import csv

import numpy as np
import pytest

import rubble
from conftest import run_command


def csv_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def printed(value):
    return "%.6e" % value


def test_compare_gives_the_commands_table(tmp_path, rubble_binary):
    scene = rubble.example_scene("stack_10")
    out = tmp_path / "cmp.csv"
    run_command(rubble_binary, "compare", scene, "--steps", 30, "--a", "solver=pgs",
                "--b", "solver=jacobi", "iterations=20", "--csv", out)
    expected = csv_rows(out)
    table = rubble.compare(scene, a={"solver": "pgs"}, b={"solver": "jacobi", "iterations": 20},
                           steps=30, as_frame=False)
    assert list(table) == list(expected[0])  # the same columns, in order
    assert len(table["step"]) == len(expected) == 31
    for i, row in enumerate(expected):
        for key, text in row.items():
            value = table[key][i]
            if key in ("step", "contacts_a", "contacts_b"):
                assert str(int(value)) == text, (key, i)
            elif key == "time":
                assert "%.6f" % value == text, (key, i)
            else:
                assert printed(value) == text, (key, i)
    # The sides diverge: jacobi is not pgs.
    assert table["position_max"][-1] > 0


def test_compare_returns_a_frame_when_pandas_is_there():
    pd = pytest.importorskip("pandas")
    frame = rubble.compare(rubble.example_scene("box_rest"), a={}, b={"dt": 1 / 120}, steps=5)
    assert isinstance(frame, pd.DataFrame) and len(frame) == 6


@pytest.mark.parametrize("flags, keywords", [
    ([], {}),
    (["--frictionless", "--iterations", "20"], {"frictionless": True, "iterations": 20}),
])
def test_solvers_gives_the_commands_table(tmp_path, rubble_binary, flags, keywords):
    scene = rubble.example_scene("stack_10")
    out = tmp_path / "solvers.csv"
    run_command(rubble_binary, "solvers", scene, "--step", 30, "--csv", out, *flags)
    expected = csv_rows(out)
    table = rubble.solvers(scene, step=30, as_frame=False, **keywords)
    assert len(table["solver"]) == len(expected)
    for i, row in enumerate(expected):
        assert table["solver"][i] == row["solver"] and table["backend"][i] == row["backend"]
        assert int(table["iteration"][i]) == int(row["iteration"])
        assert printed(table["residual"][i]) == row["residual"]
        assert printed(table["complementarity"][i]) == row["complementarity"]
        v, text = table["velocity_error"][i], row["velocity_error"]
        if text == "":  # no lemke answer to measure against
            assert np.isnan(v)
        elif row["solver"] == "lemke":  # the reference itself, written as 0
            assert text == "0" and v == 0
        else:
            assert printed(v) == text
    assert table.attrs["contacts"] == 40
    assert ("lemke/cpu" in table.attrs["skipped"]) == (not keywords.get("frictionless"))


def test_solvers_on_a_step_without_contacts_names_the_step():
    with pytest.raises(rubble.SceneError, match="has no contacts"):
        rubble.solvers(rubble.example_scene("pendulum"), step=3)


def test_devices_are_the_commands(rubble_binary):
    listed = run_command(rubble_binary, "devices").stdout.strip().splitlines()
    devices = rubble.devices()
    assert len(devices) == len(listed) >= 1
    for d, line in zip(devices, listed):
        assert line.startswith(f"{d['index']}: {d['name']} (platform {d['platform']};")


def test_solver_suite_gives_the_commands_rows(tmp_path, rubble_binary):
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in ("stack_20", "light_under_heavy"):
        src = rubble.example_scene("stack_10").replace("stack_10.json", "solver/%s.json" % name)
        (scenes / ("%s.json" % name)).write_text(open(src).read())
    out = tmp_path / "suite.csv"
    run_command(rubble_binary, "solvers", "--suite", scenes, "--steps", 4, "--paths", "cpu",
                "--csv", out)
    expected = csv_rows(out)
    table = rubble.solver_suite(scenes, steps=4, paths=["cpu"], as_frame=False)
    assert list(table) == list(expected[0])
    assert len(expected) == 8  # 2 scenes x 4 solvers
    for i, row in enumerate(expected):
        assert table["scene"][i] == row["scene"] and table["solver"][i] == row["solver"]
        assert int(table["steps"][i]) == int(row["steps"]) == 4
        assert table["stands"][i] == row["stands"] == "yes"
        assert "%.4g" % table["penetration"][i] == row["penetration"]
