# bench/run --seeds and --iterations: the seed list parsed or refused with the option named, the
# scene copies carrying the seed and the sweeps (and nothing else changed), and a run over two
# seeds giving one row per seed whose piles differ.
import csv
import importlib.machinery
import importlib.util
import json
import os
import subprocess
import sys

import pytest

from conftest import REPO, run_command

SCRIPT = REPO / "bench" / "run"
SCENE = "scenes/bench/debris_1k.json"


def load_script():
    loader = importlib.machinery.SourceFileLoader("bench_run", str(SCRIPT))
    spec = importlib.util.spec_from_loader("bench_run", loader)
    module = importlib.util.module_from_spec(spec)
    loader.exec_module(module)
    return module


def test_seed_lists():
    bench = load_script()
    assert bench.parse_seeds("1-7") == [1, 2, 3, 4, 5, 6, 7]
    assert bench.parse_seeds("1,3,5") == [1, 3, 5]
    assert bench.parse_seeds("4, 1-3, 2") == [4, 1, 2, 3]
    for bad in ("7-1", "x", "", "1,", "-3", "1-"):
        with pytest.raises(ValueError):
            bench.parse_seeds(bad)


def test_a_variant_changes_the_seed_and_the_sweeps_only(tmp_path):
    bench = load_script()
    original = json.loads((REPO / SCENE).read_text())
    assert bench.scene_variant("debris_1k", SCENE, None, None, str(tmp_path)) == SCENE
    path = bench.scene_variant("debris_1k", SCENE, 5, 14, str(tmp_path))
    variant = json.loads(open(path).read())
    assert variant["name"] == "debris_1k_seed5_it14"
    assert [g["seed"] for g in variant["generators"]] == [5] * len(original["generators"])
    assert variant["simulation"]["solver"]["iterations"] == 14
    # Everything else as in the file.
    for g in variant["generators"] + original["generators"]:
        g.pop("seed")
    variant["simulation"]["solver"].pop("iterations")
    original["simulation"]["solver"].pop("iterations")
    variant.pop("name")
    original.pop("name")
    assert variant == original


def test_the_refusals_name_the_option():
    for args, words in ((["--seeds", "3-1"], "--seeds 3-1"),
                        (["--seeds", "1", "--scenes", "pyramid_20"], "has no generators"),
                        (["--iterations", "0"], "--iterations 0")):
        done = subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True,
                              text=True, cwd=REPO, timeout=60)
        assert done.returncode != 0
        assert words in done.stderr


def test_two_seeds_two_piles(rubble_binary, tmp_path):
    out = tmp_path / "seeds.csv"
    done = subprocess.run(
        [sys.executable, str(SCRIPT), "--build", str(rubble_binary.parent), "--scenes",
         "debris_1k", "--configs", "cpu-sat-pgs", "--seeds", "1,2", "--iterations", "3",
         "--steps", "40", "--out", str(out)],
        capture_output=True, text=True, cwd=REPO, timeout=600)
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(open(out)))
    assert [(r["seed"], r["iterations"], r["status"]) for r in rows] == [
        ("1", "3", "ok"), ("2", "3", "ok")]
    assert "over seeds 1,2, medians:" in done.stdout
    # Other jitter, another pile: the crates' kinetic energy after the first landings differs.
    assert rows[0]["kinetic_energy_j"] != rows[1]["kinetic_energy_j"]
    # The same variant run directly gives the first row's pile.
    bench = load_script()
    scene = bench.scene_variant("debris_1k", SCENE, 1, 3, str(tmp_path))
    run_command(rubble_binary, "run", scene, "--steps", "40", "--metrics", tmp_path / "m.json",
                "--quiet")
    metrics = json.loads((tmp_path / "m.json").read_text())
    assert float(rows[0]["kinetic_energy_j"]) == pytest.approx(
        metrics["quality"]["kinetic_energy"], rel=1e-9)
    # The bodies asleep at the end come from the metrics too.
    assert int(rows[0]["asleep"]) == metrics["asleep"]["last"]


def test_the_plots_take_a_run_over_seeds_as_a_table_only(rubble_binary, tmp_path):
    plot = ["/usr/bin/python3", str(REPO / "bench" / "plot.py")]
    probe = subprocess.run(plot[:1] + ["-c", "import matplotlib"], capture_output=True)
    if probe.returncode != 0:
        # CI installs python3-matplotlib (scripts/setup.sh): missing there, it is a failure.
        if os.environ.get("CI"):
            pytest.fail("bench/plot.py needs Debian's python3-matplotlib under /usr/bin/python3")
        pytest.skip("bench/plot.py needs Debian's python3-matplotlib under /usr/bin/python3")
    out = tmp_path / "seeds.csv"
    subprocess.run([sys.executable, str(SCRIPT), "--build", str(rubble_binary.parent),
                    "--scenes", "debris_1k", "--configs", "cpu-sat-pgs", "--seeds", "3-4",
                    "--steps", "5", "--out", str(out)], check=True, capture_output=True,
                   cwd=REPO, timeout=600)
    table = subprocess.run(plot + [str(out), "--table"], capture_output=True, text=True)
    assert table.returncode == 0, table.stderr
    assert "| debris_1k seed 3 | cpu-sat-pgs |" in table.stdout
    assert "| debris_1k seed 4 | cpu-sat-pgs |" in table.stdout
    figures = subprocess.run(plot + [str(out), "--out", str(tmp_path / "images")],
                             capture_output=True, text=True)
    assert figures.returncode != 0 and "bench/run --seeds" in figures.stderr
    assert not (tmp_path / "images").exists()
    # A CSV that bench/run did not write is refused by name, not with a traceback.
    other = tmp_path / "other.csv"
    other.write_text("workers,seconds\n1,2.0\n")
    refused = subprocess.run(plot + [str(other), "--table"], capture_output=True, text=True)
    assert refused.returncode != 0 and "is not a CSV of bench/run" in refused.stderr
