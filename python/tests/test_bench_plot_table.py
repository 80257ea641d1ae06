# bench/plot.py --table: a bench/run CSV written by hand printed as Markdown, every run or the
# columns asked for, medians over seeds, ratios to another configuration and scenes against
# configurations; bad requests refused by name with exit status 2.
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "bench" / "plot.py"
HEADER = "scene,seed,iterations,config,status,bodies,steps,median_ms,floor_penetration_m,moving," \
         "ratio_to_reference,stage_solve_ms\n"


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, cwd=REPO, timeout=60)


def table(*args):
    done = run(*args)
    assert done.returncode == 0, done.stderr
    return [[c.strip() for c in line.strip("|").split("|")] for line in done.stdout.splitlines()]


def seeds_csv(tmp_path):
    """Three seeds of one pile on two configurations; the device's second seed failed."""
    path = tmp_path / "seeds.csv"
    path.write_text(HEADER +
                    "pile,1,,cpu,ok,100,300,10.0,0.0081,7,1.0,4.0\n"
                    "pile,1,,dev,ok,100,300,6.0,0.0090,3,0.6,2.0\n"
                    "pile,2,,cpu,ok,100,300,12.0,0.0085,24,1.0,5.0\n"
                    "pile,2,,dev,failed: out of memory (pairs),,,,,,,\n"
                    "pile,3,,cpu,ok,100,300,11.0,0.0079,17,1.0,6.0\n"
                    "pile,3,,dev,ok,100,300,5.5,0.0070,11,0.5,3.0\n")
    return path


def test_every_run_with_a_failure_in_place_of_its_figures(tmp_path):
    rows = table(seeds_csv(tmp_path), "--table")
    assert rows[0][:4] == ["scene", "config", "bodies", "median ms"]
    assert rows[1][:3] == ["---", "---", "---:"]
    assert rows[2][:4] == ["pile seed 1", "cpu", "100", "10"]
    assert rows[2][rows[0].index("floor pen. mm")] == "8.1"
    # The failed run keeps its labels and says why where its first figure would be.
    assert rows[5][:3] == ["pile seed 2", "dev", "failed: out of memory"]
    assert all(c == "" for c in rows[5][3:])
    assert len(rows) == 2 + 6


def test_medians_over_the_seeds(tmp_path):
    rows = table(seeds_csv(tmp_path), "--table", "--median-by", "scene,config", "--columns",
                 "scene,config,runs,median_ms,floor_mm,moving,each:moving,ratio,stage_solve_ms")
    assert rows[0] == ["scene", "config", "runs", "median ms", "floor pen. mm", "moving",
                       "moving per run", "ratio", "solve ms"]
    # Odd count: the middle value; even count (one seed failed): the mean of the middle two.
    assert rows[2] == ["pile", "cpu", "3/3", "11", "8.1", "17", "7 24 17", "1.00", "5.00"]
    assert rows[3] == ["pile", "dev", "2/3", "5.75", "8.0", "7", "3 x 11", "0.55", "2.50"]


def test_ratios_to_another_configuration(tmp_path):
    rows = table(seeds_csv(tmp_path), "--table", "--ratio-to", "dev", "--configs", "cpu",
                 "--columns", "scene,seed,config,ratio")
    assert rows[0] == ["scene", "seed", "config", "ratio to dev"]
    # Seed 2 has no device run to divide by.
    assert [r[3] for r in rows[2:]] == ["1.67", "-", "2.00"]
    over = table(seeds_csv(tmp_path), "--table", "--ratio-to", "cpu", "--configs", "dev",
                 "--median-by", "scene,config", "--columns", "scene,config,ratio")
    assert over[2] == ["pile", "dev", "0.55"]


def test_scenes_against_configurations(tmp_path):
    path = tmp_path / "full.csv"
    path.write_text(HEADER +
                    "stack,,,cpu,ok,11,600,0.5,0.003,0,1.0,\n"
                    "stack,,,dev,ok,11,600,0.25,0.002,0,0.5,\n"
                    "pile,,,cpu,ok,100,300,10.0,0.008,7,1.0,\n"
                    "pile,,,dev,failed: no device,,,,,,,\n")
    rows = table(path, "--table", "--pivot", "median_ms", "--configs", "dev,cpu")
    assert rows == [["median ms", "dev", "cpu"], ["---", "---:", "---:"],
                    ["stack", "0.25", "0.5"], ["pile", "failed", "10"]]
    only = table(path, "--table", "--pivot", "moving", "--scenes", "pile")
    assert only[2:] == [["pile", "7", "failed"]]


def test_a_pivot_over_seeds_asks_for_medians(tmp_path):
    done = run(seeds_csv(tmp_path), "--table", "--pivot", "median_ms")
    assert done.returncode == 2
    assert "several runs of cpu on pile" in done.stderr and "--median-by scene,config" in done.stderr
    rows = table(seeds_csv(tmp_path), "--table", "--pivot", "median_ms", "--median-by",
                 "scene,config")
    assert rows[2] == ["pile", "11", "5.75"]


def test_any_csv_by_its_columns(tmp_path):
    path = tmp_path / "sweep.csv"
    path.write_text("repeat,workers,sweep_s\n0,1,8.0\n0,2,5.0\n1,2,7.0\n1,1,9.0\n2,1,30.0\n")
    rows = table(path, "--table", "--median-by", "workers", "--columns",
                 "workers,runs,sweep_s=sweep s,each:sweep_s")
    assert rows == [["workers", "runs", "sweep s", "sweep_s per run"], ["---:", "---:", "---:", "---"],
                    ["1", "3/3", "9", "8 9 30"], ["2", "2/2", "6", "5 7"]]
    # Without columns the table is bench/run's, which this file is not.
    done = run(path, "--table")
    assert done.returncode == 2 and "is not a CSV of bench/run" in done.stderr


def test_bad_requests_are_named(tmp_path):
    path = seeds_csv(tmp_path)
    for args, words in ((["--table", "--columns", "scene,speed"], "has no column speed"),
                        (["--table", "--scenes", "heap"], "has no row whose scene is heap"),
                        (["--table", "--ratio-to", "gpu"], "no successful run of configuration gpu"),
                        (["--table", "--where", "seed"], "--where seed: give KEY=VALUE"),
                        (["--table", "--pivot", "moving", "--columns", "scene"], "leave out --columns"),
                        (["--columns", "scene"], "give --table too"),
                        ([tmp_path / "missing.csv", "--table"], "missing.csv: No such file")):
        done = run(*(args if args[0] != "--table" and args[0] != "--columns" else [path] + args))
        assert done.returncode == 2, (args, done.stderr)
        assert words in done.stderr, (args, done.stderr)
        assert "Traceback" not in done.stderr
