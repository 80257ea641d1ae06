#!/usr/bin/env python3
"""bench/trace_gaps.py: where the OpenCL device sits idle, from a trace of `rubble run --trace`
(docs/opencl.md, "Reading a trace"). Python 3 standard library only.

usage: python3 bench/trace_gaps.py TRACE.json [--kernel NAME] [--before NAME] [--skip N]

A gap is the time between one command's end and the next command's start on the device's
in-order queue, in which the device ran nothing of rubble's. Prints, as medians over the
steps (ms): the device's busy time, the span from the step's first start to its last end, the
idle time within the step (span - busy), the gap between steps (the last end of one to the
first start of the next), the idle time from the last read from the device before the step's
first --before kernel (buildPgsRows: the host colors the rows in it) to that kernel's start,
and the sum of the gaps before the --kernel launches (solvePgs); then per stage the gap before
its first command in the step and the sum of the gaps before all of its commands (the step's
first command has none: the gap before it is the one between steps). Also the blocking reads
per step: reads after which the host enqueued the step's next command only once the read had
ended (it waited for it), and how many steps have any. --skip drops the first N steps (the
first launches of a kernel on PoCL compile it).
"""
import argparse
import json
import statistics
import sys

READ = "(read from device)"


def steps_of(trace):
    """The device's commands, grouped by step in start order: {step: [event, ...]}."""
    steps = {}
    for e in trace["traceEvents"]:
        if e.get("ph") != "X" or e.get("cat") == "host":
            continue
        steps.setdefault(e["args"]["step"], []).append(e)
    for events in steps.values():
        events.sort(key=lambda e: e["ts"])
    return dict(sorted(steps.items()))


def host_steps_of(trace):
    """The host's World::step spans, by step: {step: event} (none when the trace has no clock
    relation)."""
    return {e["args"]["step"]: e for e in trace["traceEvents"]
            if e.get("ph") == "X" and e.get("cat") == "host"}


def gaps(events):
    """The gap before each command of a step (us), None for its first."""
    out = [None]
    for a, b in zip(events, events[1:]):
        out.append(max(0.0, b["ts"] - (a["ts"] + a["dur"])))
    return out


def blocking_reads(events):
    """The reads of a step the host waited for: the next command of the step was enqueued
    (CL_PROFILING_COMMAND_QUEUED, ts - queued_to_start_us) no earlier than the read's end."""
    count = 0
    for a, b in zip(events, events[1:]):
        queued = b["ts"] - b["args"].get("queued_to_start_us", 0.0)
        if a["name"] == READ and queued >= a["ts"] + a["dur"]:
            count += 1
    return count


def analyse(trace, kernel="solvePgs", before="buildPgsRows", skip=0):
    """Per-step figures (ms) of a trace, and their medians: a dict with "steps" (one dict per
    step) and "median" (each figure's median over the steps that have it)."""
    all_steps = steps_of(trace)
    host = host_steps_of(trace)
    numbers = list(all_steps)
    rows = []
    for i, step in enumerate(numbers):
        events = all_steps[step]
        g = gaps(events)
        busy = sum(e["dur"] for e in events)
        span = events[-1]["ts"] + events[-1]["dur"] - events[0]["ts"]
        row = {"step": step, "commands": len(events), "busy_ms": busy / 1e3,
               "span_ms": span / 1e3, "idle_ms": (span - busy) / 1e3,
               "blocking_reads": blocking_reads(events)}
        if i > 0:
            last = all_steps[numbers[i - 1]][-1]
            row["between_steps_ms"] = (events[0]["ts"] - (last["ts"] + last["dur"])) / 1e3
        # The gap between steps on the host's side: the end of the last step's World::step after
        # its last command, the caller's time between two World::step calls, the start of this
        # one before its first command.
        h = host.get(step)
        if h is not None:
            row["host_begin_to_first_command_ms"] = (events[0]["ts"] - h["ts"]) / 1e3
            end = events[-1]["ts"] + events[-1]["dur"]
            row["last_command_to_host_end_ms"] = (h["ts"] + h["dur"] - end) / 1e3
            previous = host.get(numbers[i - 1]) if i > 0 else None
            if previous is not None:
                row["between_host_steps_ms"] = (h["ts"] - previous["ts"] - previous["dur"]) / 1e3
        launches = [j for j, e in enumerate(events) if e["name"] == kernel]
        row[kernel + "_launches"] = len(launches)
        row["gaps_before_" + kernel + "_ms"] = sum(g[j] or 0.0 for j in launches) / 1e3
        first = next((j for j, e in enumerate(events) if e["name"] == before), None)
        if first is not None:
            read = max((j for j in range(first) if events[j]["name"] == READ), default=None)
            if read is not None:
                idle = sum(g[j] for j in range(read + 1, first + 1))
                row["idle_before_" + before + "_ms"] = idle / 1e3
        stages = {}
        for j, e in enumerate(events):
            if g[j] is None:
                continue
            s = stages.setdefault(e["cat"], {"first": g[j], "all": 0.0})
            s["all"] += g[j]
        for name, s in stages.items():
            row["stage " + name + " first_gap_ms"] = s["first"] / 1e3
            row["stage " + name + " all_gaps_ms"] = s["all"] / 1e3
        rows.append(row)
    rows = rows[skip:]
    keys = []
    for r in rows:
        keys += [k for k in r if k not in keys and k != "step"]
    median = {k: statistics.median(r[k] for r in rows if k in r) for k in keys}
    return {"steps": rows, "median": median}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("trace")
    parser.add_argument("--kernel", default="solvePgs",
                        help="sum the gaps before this kernel's launches (default solvePgs)")
    parser.add_argument("--before", default="buildPgsRows",
                        help="the idle time from the last read to this kernel (default "
                             "buildPgsRows)")
    parser.add_argument("--skip", type=int, default=0, help="drop the first N steps")
    args = parser.parse_args(argv)
    try:
        with open(args.trace) as f:
            trace = json.load(f)
    except (OSError, json.JSONDecodeError) as e:
        sys.exit(f"bench/trace_gaps.py: {args.trace}: {e}")
    result = analyse(trace, args.kernel, args.before, args.skip)
    if not result["steps"]:
        sys.exit(f"bench/trace_gaps.py: {args.trace}: no device commands")
    m = result["median"]
    waited = sum(1 for r in result["steps"] if r["blocking_reads"] > 0)
    other = trace.get("otherData", {})
    print(f"{args.trace}: {other.get('scene', '?')} on {other.get('device', '?')}, "
          f"{len(result['steps'])} steps")
    print("per step, median over the steps (ms):")
    lines = [("commands", m["commands"], "%.0f"),
             ("device busy", m["busy_ms"], "%.3f"),
             ("span (first start to last end)", m["span_ms"], "%.3f"),
             ("idle within the step", m["idle_ms"], "%.3f"),
             ("gap between steps", m.get("between_steps_ms"), "%.3f")]
    if "between_host_steps_ms" in m:
        lines += [("  of it: World::step's end after its last command",
                   m["last_command_to_host_end_ms"], "%.3f"),
                  ("  the caller between two World::step", m["between_host_steps_ms"], "%.3f"),
                  ("  World::step's start before its first command",
                   m["host_begin_to_first_command_ms"], "%.3f")]
    lines += [("blocking reads", m["blocking_reads"], "%.0f"),
              ("  steps with any", f"{waited} of {len(result['steps'])}", "%s")]
    lines += [(f"idle from the last read to {args.before}",
               m.get(f"idle_before_{args.before}_ms"), "%.3f"),
              (f"{args.kernel} launches", m[args.kernel + "_launches"], "%.0f"),
              (f"sum of the gaps before {args.kernel}", m["gaps_before_" + args.kernel + "_ms"],
               "%.3f")]
    for label, value, form in lines:
        print(f"  {label:52s} {'-' if value is None else form % value}")
    print("per stage (ms): the gap before its first command, the sum before all of them")
    for key in m:
        if key.startswith("stage ") and key.endswith(" first_gap_ms"):
            stage = key[len("stage "):-len(" first_gap_ms")]
            print(f"  {stage:52s} {m[key]:.3f}  {m['stage ' + stage + ' all_gaps_ms']:.3f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
