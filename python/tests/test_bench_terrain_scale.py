# bench/terrain_scale.py --at-rest: each pile is dropped once, then its last state becomes a scene
# of crates at rest with sleep off, timed on its own; the rows say which phase they are and the
# ratio to the plane is taken within a phase.
import csv
import json
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "bench" / "terrain_scale.py"


def test_at_rest_times_the_dropped_piles_awake_and_still(rubble_binary, tmp_path):
    out, work = tmp_path / "rest.csv", tmp_path / "work"
    done = subprocess.run([sys.executable, str(SCRIPT), "--rubble", str(rubble_binary),
                           "--quads", "20", "--size", "20", "--crates", "3,2,3", "--steps", "90",
                           "--at-rest", "12", "--repeat", "2", "--work", str(work),
                           "--out", str(out)], capture_output=True, text=True, cwd=REPO,
                          timeout=300)
    assert done.returncode == 0, done.stderr
    rows = list(csv.DictReader(out.open()))
    assert [(r["phase"], r["scene"], r["repeat"]) for r in rows] == [
        ("drop", "pile_on_plane", "0"), ("drop", "pile_on_terrain_mesh", "0"),
        ("rest", "pile_on_plane", "0"), ("rest", "pile_on_terrain_mesh", "0"),
        ("rest", "pile_on_plane", "1"), ("rest", "pile_on_terrain_mesh", "1")]
    for r in rows:
        assert r["steps"] == ("90" if r["phase"] == "drop" else "12")
        for column in ("stage_build_rows_ms", "stage_solve_ms", "contacts"):
            assert float(r[column]) >= 0.0
    # Sleep is off at rest, so no crate sleeps however still it lies.
    assert all(r["asleep"] == "0" for r in rows if r["phase"] == "rest")

    for scene in ("pile_on_plane", "pile_on_terrain_mesh"):
        drop = [r for r in rows if r["scene"] == scene and r["phase"] == "drop"][0]
        rest = [r for r in rows if r["scene"] == scene and r["phase"] == "rest"]
        assert all(r["bodies"] == drop["bodies"] for r in rest)
        # The rest scene: the crates where the drop left them, without velocity, sleep off.
        with open(work / (scene + "_at_rest.json")) as f:
            rest_scene = json.load(f)
        assert rest_scene["simulation"]["sleep"] is False
        assert "generators" not in rest_scene
        with open(work / (scene + "_drop.csv")) as f:
            last = {r["body"]: r for r in csv.DictReader(f) if r["step"] == "90"}
        crates = [b for b in rest_scene["bodies"] if b["name"].startswith("d")]
        assert len(crates) == 18
        for b in crates:
            s = last[b["name"]]
            assert b["position"] == [float(s[k]) for k in ("px", "py", "pz")]
            assert b["orientation"] == [float(s[k]) for k in ("qw", "qx", "qy", "qz")]
            assert "linear_velocity" not in b and "angular_velocity" not in b

    # Each phase against its own plane runs.
    for phase in ("drop", "rest"):
        plane = sorted(float(r["median_ms"]) for r in rows
                       if r["phase"] == phase and r["scene"] == "pile_on_plane")
        plane = plane[len(plane) // 2]
        for r in rows:
            if r["phase"] == phase:
                assert float(r["ratio_to_plane"]) == float(r["median_ms"]) / plane
