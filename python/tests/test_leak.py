# No leak over 10,000 steps: neither Python objects (tracemalloc) nor native memory (the
# process's resident set) grow while a world steps and is read every 100 steps.
import gc
import tracemalloc

import rubble


def resident_bytes():
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096


def test_ten_thousand_steps_do_not_grow_memory():
    w = rubble.World.load(rubble.example_scene("stack_10"))

    def run(steps):
        for _ in range(steps // 100):
            w.step(100)
            w.positions, w.orientations, w.velocities, w.angular_velocities
            w.contacts()
            w.metrics()

    run(1000)  # warm: the caches of the solver and the contact sets are at their size
    gc.collect()
    tracemalloc.start()
    before_python = tracemalloc.take_snapshot()
    before_rss = resident_bytes()
    run(10_000)
    gc.collect()
    after_python = tracemalloc.take_snapshot()
    after_rss = resident_bytes()
    tracemalloc.stop()
    grown = sum(s.size_diff for s in after_python.compare_to(before_python, "filename"))
    assert w.step_count == 11_000
    assert grown < 16 * 1024, f"Python allocations grew by {grown} bytes"
    assert after_rss - before_rss < 1024 * 1024, \
        f"the resident set grew by {(after_rss - before_rss) / 1024:.0f} KiB"
