# The docs' tables of figures are made from bench/results by a command quoted above each one,
# `<!-- table: bench/plot.py RESULTS.csv --table ... -->` (or bench/plot_suite.py for the solver
# suite's results): each command is run again and its output must be the table that follows it,
# and any lines it prints after the table must follow it in the doc too, so a doc cannot drift
# from its results file; in the reference docs (opencl.md, BENCHMARKS.md, solvers.md) every table
# of figures has such a command.
import re
import shlex
import subprocess
import sys

import pytest

from conftest import REPO

MARK = "<!-- table:"
# The docs whose every table of figures is made this way, and so must quote at least one.
MADE_FROM_RESULTS = ["docs/opencl.md", "docs/BENCHMARKS.md", "docs/solvers.md"]
# The table tools a doc may quote.
TOOLS = ["bench/plot.py", "bench/plot_suite.py"]


def quoted_tables(path):
    """(line number, command, table lines, the doc's lines after the table) for every table
    command in a Markdown file."""
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
        found.append((i + 1, command, table, lines[i + 1 + len(table):]))
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
    return [pytest.param(path, line, command, table, rest, id=f"{path.name}:{line}")
            for path in docs for line, command, table, rest in quoted_tables(path)]


def test_the_reference_docs_make_their_tables_from_results():
    for name in MADE_FROM_RESULTS:
        assert quoted_tables(REPO / name), f"{name} quotes no table command"
        for line, made in tables_of_figures(REPO / name):
            assert made, f"{name}:{line}: a table of figures without its command above it"


@pytest.mark.parametrize("path,line,command,table,rest", commands())
def test_a_quoted_table_is_what_its_command_prints(path, line, command, table, rest):
    words = shlex.split(command)
    # Only the table tools, on a results file in the repository: the docs run nothing else.
    assert words[0] in TOOLS and "--table" in words, f"{path.name}:{line}: {command}"
    assert words[1].startswith("bench/results/"), f"{path.name}:{line}: {command}"
    assert table, f"{path.name}:{line}: no table right below the command"
    done = subprocess.run([sys.executable, str(REPO / words[0]), *words[1:]],
                          capture_output=True, text=True, cwd=REPO, timeout=60)
    assert done.returncode == 0, f"{path.name}:{line}: {command}\n{done.stderr}"
    printed = done.stdout.splitlines()
    assert printed[:len(table)] == table, (
        f"{path.name}:{line}: the table is not what `{command}` prints; print it again")
    after = printed[len(table):]
    assert rest[:len(after)] == after, (
        f"{path.name}:{line}: the lines `{command}` prints after its table are not the doc's")
