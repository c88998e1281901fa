"""The computations release the GIL: another Python thread keeps running during a call.

A timing check (two simulations on two threads against the same two in a row, beside a
GIL-free control) fails on a busy machine whatever the code does: speed claims live in
benchmarks, not in tests. The check below needs no timing."""

import threading
import time

import rattle


def test_other_python_threads_run_during_a_call():
    """While a simulation runs, a pure-Python thread keeps counting (it would be stalled for
    the whole call if the GIL were held)."""
    scene = rattle.Scene.paper()
    done = threading.Event()
    ticks = []

    def count():
        while not done.is_set():
            ticks.append(time.perf_counter())
            time.sleep(0.001)

    counter = threading.Thread(target=count)
    counter.start()
    time.sleep(0.01)
    before = len(ticks)
    rattle.simulate(scene, 2.0, periods=400_000)
    during = len(ticks) - before
    done.set()
    counter.join()
    assert during > 10, during
