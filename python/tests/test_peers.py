# The peer engines' runners (bench/peers) write rubble's metrics format; Bullet's also counts the
# bodies it put to sleep, as rubble's engines do, so that bench/run's `asleep` column compares
# them. Skipped where Bullet's runner is not built (libbullet-dev missing), except in CI.
import json
import os
import subprocess

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
