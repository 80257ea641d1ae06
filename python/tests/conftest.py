# Shared fixtures of the Python package's tests: the repository, and the rubble command built by
# CMake (build/rubble, or RUBBLE_BINARY), whose output the package's must match.
import os
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def rubble_binary() -> Path:
    path = Path(os.environ.get("RUBBLE_BINARY", REPO / "build" / "rubble"))
    if not path.is_file():
        # In CI the command is always built first: its absence there is a failure.
        if os.environ.get("CI"):
            pytest.fail(f"the rubble command is missing at {path} (set RUBBLE_BINARY)")
        pytest.skip(f"the rubble command is not built at {path} (set RUBBLE_BINARY)")
    return path


def run_command(binary, *args, cwd=REPO, env=None, check=True):
    """Runs the rubble command and returns its completed process (text mode)."""
    done = subprocess.run([str(binary), *map(str, args)], cwd=cwd, env=env,
                          capture_output=True, text=True, timeout=600)
    if check and done.returncode != 0:
        raise AssertionError(f"rubble {' '.join(map(str, args))} failed ({done.returncode}):\n"
                             f"{done.stderr}")
    return done
