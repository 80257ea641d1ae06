# bench/column_lean.py: the lean of each column of a grid pile (its top crate's centre against
# its bottom crate's, across the floor), as medians over the columns at the edge and inside,
# from a trajectory written by hand; a file that is no trajectory is refused by name.
import subprocess
import sys

from conftest import REPO

SCRIPT = REPO / "bench" / "column_lean.py"
HEADER = "step,time,body,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n"


def run(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *map(str, args)], capture_output=True,
                          text=True, cwd=REPO, timeout=60)


def pile(step, lean_of):
    """A 3 x 2 x 3 grid (two layers): the top crate of column (x, z) moved by lean_of(x, z)
    along x from above its bottom crate."""
    rows = []
    for z in range(3):
        for y in range(2):
            for x in range(3):
                i = x + 3 * y + 6 * z
                px = 1.2 * x + (lean_of(x, z) if y == 1 else 0.0)
                rows.append("%d,0,d%d,%g,%g,%g,1,0,0,0,0,0,0,0,0,0\n" % (step, i, px, 0.5 + y,
                                                                         1.2 * z))
    return "".join(rows)


def test_the_leans_of_edge_and_inner_columns(tmp_path):
    path = tmp_path / "t.csv"
    # The middle column (1, 1) leans 0.3 m; the eight around it 0.1 m at step 0, 0.2 m at step 5.
    path.write_text(HEADER + "0,0,floor,0,0,0,1,0,0,0,0,0,0,0,0,0\n" +
                    pile(0, lambda x, z: 0.3 if (x, z) == (1, 1) else 0.1) +
                    pile(5, lambda x, z: 0.3 if (x, z) == (1, 1) else 0.2))
    done = run(path, "--grid", 3, 2, 3)
    assert done.returncode == 0, done.stderr
    lines = [l.split() for l in done.stdout.splitlines()[1:]]
    assert [l[1:] for l in lines] == [["0", "9", "0.100", "0.100", "0.300", "0.300"],
                                      ["5", "9", "0.200", "0.200", "0.300", "0.300"]]
    only = run(path, "--grid", 3, 2, 3, "--steps", "5")
    assert [l.split()[1] for l in only.stdout.splitlines()[1:]] == ["5"]


def test_a_file_that_is_no_trajectory_is_named(tmp_path):
    path = tmp_path / "notes.csv"
    path.write_text("a,b\n1,2\n")
    done = run(path, "--grid", 3, 2, 3)
    assert done.returncode == 2
    assert "notes.csv: not a trajectory" in done.stderr


def test_each_sides_lean_away_from_the_pile(tmp_path):
    # Every column leans 0.1 m toward +x: the +x side leans out 0.1, the -x side in (-0.1), the
    # z sides not at all; the one inner column's mean lean is (0.1, 0).
    path = tmp_path / "t.csv"
    path.write_text(HEADER + pile(0, lambda x, z: 0.1))
    done = run(path, "--grid", 3, 2, 3, "--sides")
    assert done.returncode == 0, done.stderr
    assert done.stdout.splitlines()[1].split()[1:] == ["0", "-0.100", "0.100", "0.000", "0.000",
                                                       "0.1000", "0.0000"]
