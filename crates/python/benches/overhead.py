"""Import time of `rattle` and the per-call cost of `rattle.simulate(Scene.paper(), 2.0,
periods=100)`, beside the native call alone and its JSON decoding; compare with
`cargo bench --bench simulate` (the bare Rust call). Run with the package installed:

    python crates/python/benches/overhead.py
"""

import statistics
import subprocess
import sys
import timeit

#: Calls per timing and timings per measure: about a second of calls in all.
NUMBER, REPEAT = 200, 15


def best_and_median(statement, setup):
    times = timeit.repeat(statement, setup, number=NUMBER, repeat=REPEAT)
    per_call = [t / NUMBER * 1e6 for t in times]
    return min(per_call), statistics.median(per_call)


def import_time(module, before=""):
    code = (
        f"{before}; import time; t = time.perf_counter(); import {module}; "
        "print(time.perf_counter() - t)"
    )
    runs = [
        float(subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                             check=True).stdout)
        for _ in range(7)
    ]
    return min(runs) * 1e3, statistics.median(runs) * 1e3


setup = """
import json, rattle
from rattle import _rattle
scene = rattle.Scene.paper()
native = scene._native
d = rattle.DEFAULTS
text, _ = _rattle.simulate(native, 2.0, 100, d["tol"], d["steady_tol"], d["max_periods"], d["max_oscillations"], None, None)
"""
for label, module, before in [
    ("import numpy", "numpy", "pass"),
    ("import rattle (numpy included)", "rattle", "pass"),
    ("import rattle (numpy already imported)", "rattle", "import numpy"),
]:
    print("%-45s best %8.1f ms, median %8.1f ms" % ((label,) + import_time(module, before)))
for label, statement in [
    ("rattle.simulate(scene, 2.0, periods=100)", "rattle.simulate(scene, 2.0, periods=100)"),
    ("native call (JSON text out)", "_rattle.simulate(native, 2.0, 100, d['tol'], d['steady_tol'], d['max_periods'], d['max_oscillations'], None, None)"),
    ("json.loads + Simulation(...)", "rattle.Simulation(json.loads(text))"),
    ("boundary alone (GIL release, panic guard)", "_rattle._boundary_check('none')"),
]:
    print("%-45s best %8.2f us, median %8.2f us" % ((label,) + best_and_median(statement, setup)))
