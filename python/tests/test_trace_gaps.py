# bench/trace_gaps.py reads the device's idle time out of a `rubble run --trace` file: exact on a
# trace laid out by hand, and in agreement with the run's metrics on a real one.
import importlib.util
import json
import os
import random
import subprocess
import sys

import pytest

from conftest import REPO, run_command

SCRIPT = REPO / "bench" / "trace_gaps.py"


def load_script():
    spec = importlib.util.spec_from_file_location("trace_gaps", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def command(name, stage, ts, dur, step):
    return {"name": name, "cat": stage, "ph": "X", "ts": ts, "dur": dur, "pid": 1, "tid": 1,
            "args": {"step": step, "queued_to_start_us": 1.0, "submit_to_start_us": 0.5}}


def test_gaps_of_a_trace_laid_out_by_hand():
    # One step (us): status write 0-10, a read 15-20, the host colors, an upload 100-102, the
    # rows 110-130, two sweeps 133-143 and 150-160; the second step the same 1000 us later.
    layout = [("(write to device)", "apply_forces", 0, 10),
              ("(read from device)", "build_contact_rows", 15, 5),
              ("(write to device)", "build_contact_rows", 100, 2),
              ("buildPgsRows", "build_contact_rows", 110, 20),
              ("solvePgs", "solve", 133, 10),
              ("solvePgs", "solve", 150, 10)]
    events = [command(n, s, ts + 1000 * (step - 1), dur, step)
              for step in (1, 2) for n, s, ts, dur in layout]
    random.Random(7).shuffle(events)  # the script orders them by start itself
    # World::step on the host: 0-170 and 990-1170 us.
    for step, ts, dur in ((1, 0, 170), (2, 990, 180)):
        events.append({"name": f"step {step}", "cat": "host", "ph": "X", "ts": ts, "dur": dur,
                       "pid": 1, "tid": 2, "args": {"step": step}})
    events.append({"name": "thread_name", "ph": "M", "pid": 1, "tid": 1, "args": {"name": "q"}})
    result = load_script().analyse({"traceEvents": events})
    assert [r["step"] for r in result["steps"]] == [1, 2]
    m = result["median"]
    assert m["commands"] == 6
    assert m["busy_ms"] == pytest.approx(0.057)
    assert m["span_ms"] == pytest.approx(0.160)
    assert m["idle_ms"] == pytest.approx(0.103)
    assert m["between_steps_ms"] == pytest.approx(0.840)
    assert m["idle_before_buildPgsRows_ms"] == pytest.approx(0.088)  # 80 + 8 us
    assert m["solvePgs_launches"] == 2
    # The host enqueued the upload (queued 99 us) after the read had ended (20 us): it waited.
    assert m["blocking_reads"] == 1
    assert m["gaps_before_solvePgs_ms"] == pytest.approx(0.010)  # 3 + 7 us
    assert m["stage build_contact_rows first_gap_ms"] == pytest.approx(0.005)
    assert m["stage build_contact_rows all_gaps_ms"] == pytest.approx(0.093)
    assert m["stage solve first_gap_ms"] == pytest.approx(0.003)
    assert m["stage solve all_gaps_ms"] == pytest.approx(0.010)
    assert "stage apply_forces first_gap_ms" not in m  # the step's first command: between steps
    # The 840 us between the steps: 10 in the first World::step after its last command, 820
    # between the two calls, 10 in the second before its first command.
    assert m["last_command_to_host_end_ms"] == pytest.approx(0.010)
    assert m["between_host_steps_ms"] == pytest.approx(0.820)
    assert [r["host_begin_to_first_command_ms"] for r in result["steps"]] == \
        pytest.approx([0.0, 0.010])


def test_a_real_trace_agrees_with_the_metrics(tmp_path, rubble_binary):
    trace, metrics = tmp_path / "t.json", tmp_path / "m.json"
    done = run_command(rubble_binary, "run", REPO / "scenes" / "stack_10.json", "--steps", 8,
                       "--backend", "opencl", "--collision", "sat", "--quiet",
                       "--trace", trace, "--metrics", metrics, check=False)
    if done.returncode != 0 and "OpenCL platform" in done.stderr and not os.environ.get("CI"):
        pytest.skip(f"no OpenCL platform (and CI is unset): {done.stderr.strip()}")
    assert done.returncode == 0, done.stderr
    data = json.loads(trace.read_text())
    result = load_script().analyse(data)
    assert len(result["steps"]) == 8
    for row in result["steps"]:
        mine = [e for e in data["traceEvents"]
                if e["ph"] == "X" and e["tid"] == 1 and e["args"]["step"] == row["step"]]
        assert row["commands"] == len(mine)
        assert row["busy_ms"] == pytest.approx(sum(e["dur"] for e in mine) / 1e3)
        assert 0 <= row["idle_ms"] <= row["span_ms"]
        assert row["solvePgs_launches"] == sum(e["name"] == "solvePgs" for e in mine) > 0
        assert row["idle_before_buildPgsRows_ms"] >= 0
        # The step's commands run inside its World::step on the host (within 50 us of slack
        # for the clocks' relation).
        assert row["host_begin_to_first_command_ms"] > -0.05
        assert row["last_command_to_host_end_ms"] > -0.05
    # The busy time is the step's device time, whose median the metrics give (within their
    # histogram's 0.5 %).
    m = json.loads(metrics.read_text())
    assert result["median"]["busy_ms"] == pytest.approx(m["device_ms_per_step"]["median"],
                                                        rel=0.01)
    printed = subprocess.run([sys.executable, str(SCRIPT), str(trace)], capture_output=True,
                             text=True, check=True).stdout
    for label in ("device busy", "idle within the step", "gap between steps",
                  "the caller between two World::step",
                  "idle from the last read to buildPgsRows", "sum of the gaps before solvePgs"):
        assert label in printed, printed


def test_an_unreadable_trace_names_the_file(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text("{not json")
    done = subprocess.run([sys.executable, str(SCRIPT), str(bad)], capture_output=True, text=True)
    assert done.returncode != 0 and str(bad) in done.stderr
