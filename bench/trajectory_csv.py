"""Reading trajectory files (.csv, `rubble run --out`) in the bench scripts. Python 3 standard
library only."""
import csv


def trajectory_rows(f, path, names):
    """(header, {name: column}, reader over the rows after the header) of the open file f; a
    ValueError naming `path` when it is empty or has no column of one of `names`."""
    rows = csv.reader(f)
    header = next(rows, None)
    if header is None:
        raise ValueError("%s: empty file" % path)
    try:
        at = {name: header.index(name) for name in names}
    except ValueError as e:
        raise ValueError("%s: not a trajectory (.csv from rubble run --out): %s" % (path, e))
    return header, at, rows
