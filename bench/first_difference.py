#!/usr/bin/env python3
"""Where two trajectories part: the first step at which any body's state (position, orientation,
velocities) differs between two trajectory files (.csv, `rubble run --out`), how many bodies
differ there and by how much at most. Python 3 standard library only.

  rubble run scenes/pyramid_20.json --steps 120 --out cpu.csv
  rubble run scenes/pyramid_20.json --steps 120 --backend opencl --collision sat --out dev.csv
  bench/first_difference.py cpu.csv dev.csv

The values are compared as the files write them (shortest round-trip text of each float), so
"the same" is the same bits. Exit status: 0 the same through the last step both files hold,
1 they part, 2 a file is missing or not a trajectory, or the two hold other bodies or steps."""
import argparse
import sys

from trajectory_csv import trajectory_rows

FIELDS = ("px", "py", "pz", "qw", "qx", "qy", "qz", "vx", "vy", "vz", "wx", "wy", "wz")


def read_steps(path):
    """[(step, {body: (text of each field)})] in file order."""
    steps = []
    try:
        with open(path, newline="") as f:
            header, at, rows = trajectory_rows(f, path, ("step", "body") + FIELDS)
            for line, row in enumerate(rows, start=2):
                if len(row) != len(header):
                    raise ValueError("%s:%d: %d fields, the header has %d" %
                                     (path, line, len(row), len(header)))
                step = int(row[at["step"]])
                if not steps or steps[-1][0] != step:
                    steps.append((step, {}))
                steps[-1][1][row[at["body"]]] = tuple(row[at[name]] for name in FIELDS)
    except OSError as e:
        raise ValueError("%s: cannot be read: %s" % (path, e.strerror))
    return steps


def first_difference(a, b):
    """(step, differing bodies, largest |difference|, its body and field), or None."""
    for (step_a, bodies_a), (step_b, bodies_b) in zip(a, b):
        if step_a != step_b:
            raise ValueError("the files hold other steps: %d against %d" % (step_a, step_b))
        if bodies_a.keys() != bodies_b.keys():
            raise ValueError("step %d: the files hold other bodies" % step_a)
        differing, largest, where = 0, 0.0, None
        for body, values in bodies_a.items():
            other = bodies_b[body]
            if values == other:
                continue
            differing += 1
            for field, x, y in zip(FIELDS, values, other):
                gap = abs(float(x) - float(y))
                if x != y and (where is None or gap > largest):
                    largest, where = gap, (body, field)
        if differing:
            return step_a, differing, len(bodies_a), largest, where
    return None


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("a", help="trajectory file (.csv)")
    parser.add_argument("b", help="trajectory file (.csv)")
    args = parser.parse_args(argv)
    try:
        a, b = read_steps(args.a), read_steps(args.b)
        found = first_difference(a, b)
    except ValueError as e:
        print("first_difference: %s" % e, file=sys.stderr)
        return 2
    if found is None:
        last = min(a[-1][0], b[-1][0]) if a and b else 0
        print("the same bits through step %d (%d bodies)" % (last, len(a[0][1]) if a else 0))
        return 0
    step, differing, bodies, largest, (body, field) = found
    print("part at step %d: %d of %d bodies differ, largest difference %.3g (%s %s)" %
          (step, differing, bodies, largest, body, field))
    return 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
