# The peer engines' runners (bench/peers) write rubble's metrics format; Bullet's and Box3D's also
# count the bodies they put to sleep, as rubble's engines do, so that bench/run's `asleep` column
# compares them. Bullet's tests are skipped where its runner is not built (libbullet-dev
# missing), except in CI; Box3D's wherever its runner is not built. The scenes of Box3D's
# benchmark are checked against the script that writes them and against Box3D's counts.
import csv
import json
import os
import subprocess
import sys

import pytest

from conftest import REPO


@pytest.mark.parametrize("steps, asleep", [(60, 0), (300, 10)])
def test_bullet_counts_the_bodies_it_put_to_sleep(rubble_binary, tmp_path, steps, asleep):
    runner = rubble_binary.parent / "bench" / "peers" / "rubble-bullet"
    if not runner.exists():
        # CI installs libbullet-dev (scripts/setup.sh): a runner missing there is a failure.
        if os.environ.get("CI"):
            pytest.fail("Bullet's runner is missing at %s" % runner)
        pytest.skip("Bullet's runner is not built at %s" % runner)
    metrics = tmp_path / "m.json"
    subprocess.run([str(runner), str(REPO / "scenes" / "stack_10.json"), "--steps", str(steps),
                    "--metrics", str(metrics)], check=True, capture_output=True, timeout=120)
    m = json.loads(metrics.read_text())
    # Bullet sleeps a body after 2 s below its thresholds: stack_10 is awake at 1 s and asleep
    # whole at 5 s.
    assert m["asleep"]["last"] == asleep
    assert m["quality"]["moving"] == 0


# Box3D's runner (bench/peers/box3d_runner.cpp): built where Box3D was found at configure time
# (FETCHCONTENT_SOURCE_DIR_BOX3D or the download), so skipped where it is not, CI included.
def box3d_runner(rubble_binary):
    runner = rubble_binary.parent / "bench" / "peers" / "rubble-box3d"
    if not runner.exists():
        pytest.skip("Box3D's runner is not built at %s (configure with "
                    "-DFETCHCONTENT_SOURCE_DIR_BOX3D=...)" % runner)
    return runner


def run_box3d(runner, scene, tmp_path, *args):
    metrics = tmp_path / "m.json"
    subprocess.run([str(runner), str(scene), "--metrics", str(metrics)] + list(args), check=True,
                   capture_output=True, timeout=300)
    return json.loads(metrics.read_text())


@pytest.mark.parametrize("sleep, asleep", [(True, 10), (False, 0)])
def test_box3d_sleeps_as_the_scene_says(rubble_binary, tmp_path, sleep, asleep):
    runner = box3d_runner(rubble_binary)
    doc = json.loads((REPO / "scenes" / "stack_10.json").read_text())
    doc["simulation"]["sleep"] = sleep
    scene = tmp_path / "stack.json"
    scene.write_text(json.dumps(doc))
    m = run_box3d(runner, scene, tmp_path, "--steps", "300")
    # Still after 5 s either way; asleep only where the scene lets it sleep.
    assert m["asleep"]["last"] == asleep
    assert m["quality"]["moving"] == 0
    assert m["quality"]["sunk"] == 0
    assert m["quality"]["floor_penetration"] < 0.01


def test_box3d_steps_the_same_with_any_number_of_workers(rubble_binary, tmp_path):
    # Box3D's multithreaded step is deterministic: a pool of any size gives the same bytes, so a
    # task the pool ran twice, or not at all, shows.
    runner = box3d_runner(rubble_binary)
    scene = REPO / "scenes" / "pyramid_20.json"
    trajectories = []
    for workers in ("1", "2", "3"):
        out = tmp_path / ("w%s.csv" % workers)
        m = run_box3d(runner, scene, tmp_path, "--steps", "60", "--workers", workers,
                      "--out", str(out), "--every", "10")
        assert m["device"] == "box3d, %s worker%s" % (workers, "" if workers == "1" else "s")
        trajectories.append(out.read_bytes())
    assert trajectories[0] == trajectories[1] == trajectories[2]


def test_box3d_scenes_are_as_the_script_writes_them():
    done = subprocess.run([sys.executable, str(REPO / "bench" / "box3d_scenes.py"), "--check"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode == 0, done.stderr


@pytest.mark.parametrize("name, bodies", [("junkyard", 10584), ("many_pyramids", 10780),
                                          ("large_pyramid", 5050)])
def test_box3d_scenes_hold_box3ds_counts(name, bodies):
    # shared/benchmarks.c's release sizes: 24 x 21 x 21 rocks, 14 x 14 pyramids of 55 boxes, one
    # pyramid of base 100.
    doc = json.loads((REPO / "scenes" / "bench" / (name + ".json")).read_text())
    count = sum(g["count"][0] * g["count"][1] * g["count"][2] for g in doc["generators"])
    assert count == bodies
    assert doc["simulation"]["sleep"] == (name == "junkyard")


def test_bench_run_says_a_missing_peer_is_not_built(rubble_binary, tmp_path):
    # A build folder with the command and no peer runner: the peer's rows say so, the run goes on.
    build = tmp_path / "build"
    build.mkdir()
    (build / "rubble").symlink_to(rubble_binary)
    out = tmp_path / "r.csv"
    done = subprocess.run([sys.executable, str(REPO / "bench" / "run"), "--build", str(build),
                           "--scenes", "stack_10", "--configs", "box3d-1,box3d", "--steps", "5",
                           "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(out.open()))
    assert [r["status"] for r in rows] == ["not built (bench/peers/rubble-box3d)"] * 2
