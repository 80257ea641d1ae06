# The docs' tables of figures are made from bench/results by a command quoted above each one,
# `<!-- table: bench/plot.py RESULTS.csv --table ... -->`: each command is run again and its output
# must be the table that follows it, so a doc cannot drift from its results file; in the reference
# docs (opencl.md, BENCHMARKS.md) every table of figures has such a command.
import re
import shlex
import subprocess
import sys

import pytest

from conftest import REPO

MARK = "<!-- table:"
# The docs whose every table of figures is made this way, and so must quote at least one.
MADE_FROM_RESULTS = ["docs/opencl.md", "docs/BENCHMARKS.md"]


def quoted_tables(path):
    """(line number, command, table lines) for every table command in a Markdown file."""
    lines = path.read_text().splitlines()
    found = []
    for i, line in enumerate(lines):
        if not line.startswith(MARK):
            continue
        assert line.rstrip().endswith("-->"), f"{path}:{i + 1}: a table comment on one line"
        command = line[len(MARK):].rstrip()[:-len("-->")].strip()
        table = []
        for after in lines[i + 1:]:
            if not after.startswith("|"):
                break
            table.append(after.rstrip())
        found.append((i + 1, command, table))
    return found


def tables_of_figures(path):
    """(line number, whether a table command is right above) for every Markdown table whose body
    holds a figure (a cell that is a decimal number)."""
    lines = path.read_text().splitlines()
    found, i = [], 0
    while i < len(lines):
        if not lines[i].startswith("|"):
            i += 1
            continue
        start = i
        while i < len(lines) and lines[i].startswith("|"):
            i += 1
        cells = [c.strip() for row in lines[start + 2:i] for c in row.strip("|").split("|")]
        if any(re.fullmatch(r"-?[0-9]+\.[0-9]+", c) for c in cells):
            found.append((start + 1, start > 0 and lines[start - 1].startswith(MARK)))
    return found


def commands():
    docs = sorted((REPO / "docs").glob("*.md")) + [REPO / "README.md"]
    return [pytest.param(path, line, command, table, id=f"{path.name}:{line}")
            for path in docs for line, command, table in quoted_tables(path)]


def test_the_reference_docs_make_their_tables_from_results():
    for name in MADE_FROM_RESULTS:
        assert quoted_tables(REPO / name), f"{name} quotes no table command"
        for line, made in tables_of_figures(REPO / name):
            assert made, f"{name}:{line}: a table of figures without its command above it"


@pytest.mark.parametrize("path,line,command,table", commands())
def test_a_quoted_table_is_what_its_command_prints(path, line, command, table):
    words = shlex.split(command)
    # Only the table tool, on a results file in the repository: the docs run nothing else.
    assert words[0] == "bench/plot.py" and "--table" in words, f"{path.name}:{line}: {command}"
    assert words[1].startswith("bench/results/"), f"{path.name}:{line}: {command}"
    assert table, f"{path.name}:{line}: no table right below the command"
    done = subprocess.run([sys.executable, str(REPO / "bench" / "plot.py"), *words[1:]],
                          capture_output=True, text=True, cwd=REPO, timeout=60)
    assert done.returncode == 0, f"{path.name}:{line}: {command}\n{done.stderr}"
    assert done.stdout.splitlines() == table, (
        f"{path.name}:{line}: the table is not what `{command}` prints; print it again")
