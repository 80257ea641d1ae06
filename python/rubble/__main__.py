"""``python3 -m rubble sweep SWEEP.json ...``: the package's commands (``rubble sweep`` hands
its arguments here)."""

import sys

from rubble._sweep import main


def _main(argv):
    if not argv or argv[0] != "sweep":
        print("usage: python3 -m rubble sweep SWEEP.json [--workers N] [--scheduler ADDRESS] "
              "[--out FILE.csv]", file=sys.stderr)
        return 2
    return main(argv[1:])


if __name__ == "__main__":
    sys.exit(_main(sys.argv[1:]))
