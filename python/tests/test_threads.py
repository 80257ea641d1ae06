# step() releases the GIL: another Python thread runs while a world steps, and a second call
# into the same world from that thread is refused instead of racing the first.
import threading

import pytest

import rubble


def test_other_threads_run_while_a_world_steps():
    w = rubble.World.load(rubble.example_scene("debris_1k"))
    ticks, stop, stepping, refused = [0], threading.Event(), threading.Event(), []
    started = threading.Event()

    def spin():
        started.set()
        while not stop.is_set():
            ticks[0] += 1
            # Reads before the step took the world succeed; one during it is refused.
            if stepping.is_set() and not refused:
                try:
                    w.positions
                except RuntimeError as e:
                    refused.append(str(e))

    t = threading.Thread(target=spin)
    t.start()
    started.wait()
    before = ticks[0]
    stepping.set()
    w.step(30)  # tens of milliseconds at least: the thread counts meanwhile
    during = ticks[0] - before
    stop.set()
    t.join()
    assert during > 1000, f"the other thread ran {during} times while the world stepped"
    assert refused and "another thread is using this world" in refused[0]
