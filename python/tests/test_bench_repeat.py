# bench/run --repeat: every configuration runs N times on a scene, in turn, each run a row of the
# CSV named by its repetition, with medians over the runs at the end; bench/plot.py --table gives
# such a run as one row per scene and configuration, the medians of its runs.
import csv
import statistics
import subprocess
import sys

import pytest

from conftest import REPO

SCRIPT = REPO / "bench" / "run"


def test_three_runs_in_turn_and_their_medians(rubble_binary, tmp_path):
    out = tmp_path / "repeat.csv"
    done = subprocess.run([sys.executable, str(SCRIPT), "--build", str(rubble_binary.parent),
                           "--scenes", "stack_10", "--configs", "cpu-sat-pgs", "--repeat", "3",
                           "--steps", "5", "--out", str(out)], capture_output=True, text=True,
                          cwd=REPO, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "over 3 runs each, medians:" in done.stdout
    rows = list(csv.DictReader(out.open()))
    assert [r["repeat"] for r in rows] == ["1", "2", "3"]
    assert all(r["status"] == "ok" and r["steps"] == "5" for r in rows)

    plot = ["/usr/bin/python3", str(REPO / "bench" / "plot.py")]
    table = subprocess.run(plot + [str(out), "--table", "--median-by", "scene,config", "--columns",
                                   "scene,config,runs,bodies,median_ms"],
                           capture_output=True, text=True)
    assert table.returncode == 0, table.stderr
    lines = [l for l in table.stdout.splitlines() if l.startswith("| stack_10 ")]
    assert len(lines) == 1, table.stdout
    cells = [c.strip() for c in lines[0].strip("|").split("|")]
    assert cells[:4] == ["stack_10", "cpu-sat-pgs", "3/3", "11"]
    assert cells[4] == "%.3g" % statistics.median(float(r["median_ms"]) for r in rows)


def test_repeat_must_be_one_or_more(rubble_binary):
    done = subprocess.run([sys.executable, str(SCRIPT), "--build", str(rubble_binary.parent),
                           "--repeat", "0"], capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "--repeat 0" in done.stderr


def test_two_binaries_in_turn_each_its_own_rows(rubble_binary, tmp_path):
    # The same executable under two names: each rubble configuration runs once per binary in
    # each repetition, in turn, its rows named by the label and its ratio to the reference run
    # of the same binary.
    out = tmp_path / "binaries.csv"
    done = subprocess.run([sys.executable, str(SCRIPT), "--scenes", "stack_10",
                           "--configs", "cpu-sat-pgs,cpu-sat-soft-step",
                           "--binaries", "%s,%s" % (rubble_binary, rubble_binary),
                           "--labels", "old,new", "--repeat", "2", "--steps", "5",
                           "--out", str(out)], capture_output=True, text=True, cwd=REPO,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(out.open()))
    assert [(r["repeat"], r["config"], r["binary"]) for r in rows] == [
        (k, c, b) for k in ("1", "2") for c in ("cpu-sat-pgs", "cpu-sat-soft-step")
        for b in ("old", "new")]
    assert all(r["status"] == "ok" for r in rows)
    for r in rows:
        reference = next(q for q in rows if q["repeat"] == r["repeat"] and q["binary"] == r["binary"]
                         and q["config"] == "cpu-sat-pgs")
        assert float(r["ratio_to_reference"]) == pytest.approx(
            float(r["median_ms"]) / float(reference["median_ms"]))
    assert "cpu-sat-soft-step new" in done.stdout


def test_labels_must_match_the_binaries(rubble_binary):
    done = subprocess.run([sys.executable, str(SCRIPT), "--binaries", str(rubble_binary),
                           "--labels", "old,new"], capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "2 labels for 1 --binaries" in done.stderr
