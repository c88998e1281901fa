"""The computations release the GIL: two simulations on two threads finish in about half the
time of the same two run one after the other, on two cores.

Timings on a shared machine vary, so each measurement is repeated and the best (shortest) of
each kind is kept: the best time is the one least disturbed by other work, and a held GIL
cannot make the threaded pair beat the serial pair however the load falls (the two calls
would run one after the other either way: ratio about 1). Released, on two free cores, the
ratio is about 0.5; the test asks for below 0.8 (measured 0.64–0.78 with the machine's load
average at 6 on its two cores). That the GIL is released at all is also checked without
timing the calls: another Python thread keeps running during one."""

import os
import threading
import time

import pytest
import rattle

#: Forcing periods of each simulation: at 2.0 rad/s about 0.25 s on this machine, long enough
#: that starting threads and timer resolution are negligible.
PERIODS = 200_000
#: Best threaded pair over best serial pair: about 1 when the GIL is held, 0.5 on two free
#: cores.
LIMIT = 0.8
#: Repetitions of each measurement: at least the first few, more while the best ratio is
#: still above the limit (a burst of load elsewhere), up to the last.
REPETITIONS = (3, 6)


def _one(scene):
    rattle.simulate(scene, 2.0, periods=PERIODS)


def _timed(work):
    start = time.perf_counter()
    work()
    return time.perf_counter() - start


@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="needs two cores")
def test_two_threads_take_half_the_time_of_two_calls_in_a_row():
    scene = rattle.Scene.paper()

    def serial():
        _one(scene)
        _one(scene)

    def threaded():
        ready = threading.Barrier(2)

        def run():
            ready.wait()
            _one(scene)

        threads = [threading.Thread(target=run) for _ in range(2)]
        for t in threads:
            t.start()
        for t in threads:
            t.join()

    _one(scene)  # warm up: first-call costs are not the GIL's
    serial_times, threaded_times = [], []
    least, most = REPETITIONS
    for k in range(most):
        # Interleaved, so that a change of load touches both kinds alike.
        serial_times.append(_timed(serial))
        threaded_times.append(_timed(threaded))
        if k + 1 >= least and min(threaded_times) / min(serial_times) < LIMIT:
            break
    ratio = min(threaded_times) / min(serial_times)
    assert ratio < LIMIT, (ratio, serial_times, threaded_times)


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
    _one(scene)
    during = len(ticks) - before
    done.set()
    counter.join()
    assert during > 10, during
