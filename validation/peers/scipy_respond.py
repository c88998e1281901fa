#!/usr/bin/env python3
"""`rattle respond` on a recorded base motion against scipy's solve_ivp (DOP853) on the same
record and scene, in the same run. A peer for timing, not part of rattle or its tests.

The record: a multisine of LINES lines with random phases in [LO, HI] rad/s (numpy's
generator seeded with --seed), its RMS --rms, sampled every --step s over --duration s,
shifted so that u_g(0) = 0, and written as `t,u_g` with every float's shortest repr (rattle
reads the same doubles). Both solvers see the same signal: the linear interpolation of those
samples, u_g' the slope of the sample interval.

scipy the way a careful user would write it: DOP853 (rtol --rtol, atol 1e-3 × rtol) on the
unit's first-order system, the forcing k_o u_g + c_o u_g' from the samples (the interval by
bisection), terminal events on r = u_i - u_o = +gap (rising) and -gap (falling), the
restitution map at each (momentum kept, r'+ = -e r'-) and the integration restarted, and a
restart at every sample too (u_g' jumps there, so a step across one would spoil DOP853's
order and its error estimate). With --across-samples, the restarts at samples are left out
(the integrator steps across the kinks, its error control shortening the steps there), which
is quicker and less accurate; the same agreement is required. Its time is the integration
loop's alone (no start-up, no imports).

rattle: `rattle respond SCENE --signal RECORD.csv --duration T --json`, whole process (start-up,
reading the record and writing the document included).

Before timing, the two must agree: the same number of impacts, and the final state
(displacements and velocities) within --agree (1e-5) of its largest entry. scipy's impact
times are those of its dense output, about 1e-8 s off rattle's at first; the motion amplifies
such a difference at each slow impact, to about 1e-6 of the state over the default 40 s (and
past a whole impact over 100 s).

Usage: python3 scipy_respond.py --rattle target/release/rattle [--duration T] [--step H]
       [--repeats N] [--scene SCENE.json] [--across-samples]
Prints one JSON document: both solvers' median times, samples/s and impacts/s, the ratio.
"""
import argparse
import bisect
import json
import math
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

#: The record's band, rad/s, and its number of lines: around the unit's two natural
#: frequencies (1.0 and 2.4 rad/s for the paper's unit), so that it impacts.
LO, HI, LINES = 0.5, 3.0, 40


def make_record(duration, step, rms, seed):
    """The sampled multisine: times j·step and values, u_g(0) = 0."""
    rng = np.random.default_rng(seed)
    omega = np.linspace(LO, HI, LINES)
    phase = rng.uniform(0.0, 2.0 * math.pi, LINES)
    amplitude = rms * math.sqrt(2.0 / LINES)
    count = int(round(duration / step))
    times = [j * step for j in range(count + 1)]
    values = []
    for t in times:
        values.append(float(amplitude * (np.cos(omega * t + phase) - np.cos(phase)).sum()))
    return times, values


def scipy_run(scene, times, values, duration, rtol, restart=True):
    """The impacts and the final state [u_o, u_i, v_o, v_i] of scipy's integration, and the
    loop's wall time; `restart`: a restart at every sample, else only at impacts."""
    unit = scene["unit"]
    mo, mi = unit["outer_mass"], unit["inner_mass"]
    ko, ki = unit["outer_stiffness"], unit["inner_stiffness"]
    damping = scene.get("damping", {})
    co, ci = damping.get("outer", 0.0), damping.get("inner", 0.0)
    gap, e = scene["stops"]["gap"], scene["stops"]["restitution"]
    last = len(times) - 1

    def forcing(t):
        i = min(max(bisect.bisect_right(times, t) - 1, 0), last - 1)
        if t >= times[last]:
            return values[last], 0.0
        slope = (values[i + 1] - values[i]) / (times[i + 1] - times[i])
        return values[i] + slope * (t - times[i]), slope

    def field(t, y):
        ug, vg = forcing(t)
        base = ko * ug + co * vg
        spring = ki * (y[1] - y[0]) + ci * (y[3] - y[2])
        return [y[2], y[3], (base - ko * y[0] - co * y[2] + spring) / mo, -spring / mi]

    def side1(t, y):
        return y[1] - y[0] - gap

    side1.terminal, side1.direction = True, 1.0

    def side2(t, y):
        return y[1] - y[0] + gap

    side2.terminal, side2.direction = True, -1.0

    t, y = 0.0, np.zeros(4)
    impacts = 0
    start = time.perf_counter()
    node = 1
    while t < duration:
        while node <= last and times[node] <= t:
            node += 1
        stop = min(times[node], duration) if restart and node <= last else duration
        sol = solve_ivp(field, (t, stop), y, method="DOP853", rtol=rtol, atol=rtol * 1e-3,
                        events=(side1, side2))
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.status == 1:  # an impact: restitution along r, momentum conserved
            rdot = y[3] - y[2]
            jump = (1 + e) * rdot * mo * mi / (mo + mi)
            y[2] += jump / mo
            y[3] -= jump / mi
            impacts += 1
    return impacts, list(y), time.perf_counter() - start


def rattle_run(rattle, scene_path, record, duration):
    """rattle's document and the whole process's wall time."""
    start = time.perf_counter()
    out = subprocess.run(
        [rattle, "respond", scene_path, "--signal", record, "--duration", repr(duration),
         "--json"],
        check=True, capture_output=True, text=True)
    elapsed = time.perf_counter() - start
    return json.loads(out.stdout), elapsed


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--scene", default="data/scenes/paper-damped.json")
    parser.add_argument("--rattle", default=os.environ.get("RATTLE_BIN", "target/release/rattle"))
    parser.add_argument("--duration", type=float, default=40.0)
    parser.add_argument("--step", type=float, default=0.01)
    parser.add_argument("--rms", type=float, default=0.4)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--rtol", type=float, default=1e-10)
    parser.add_argument("--agree", type=float, default=1e-5)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--across-samples", action="store_true")
    args = parser.parse_args()
    with open(args.scene) as f:
        scene = json.load(f)
    times, values = make_record(args.duration, args.step, args.rms, args.seed)
    with tempfile.TemporaryDirectory() as directory:
        record = os.path.join(directory, "record.csv")
        with open(record, "w") as f:
            f.write("t,u_g\n")
            for t, v in zip(times, values):
                f.write(f"{t!r},{v!r}\n")
        document, _ = rattle_run(args.rattle, args.scene, record, args.duration)
        restart = not args.across_samples
        impacts, state, _ = scipy_run(scene, times, values, args.duration, args.rtol, restart)
        final = document["final_state"]
        expected = final["displacements"] + final["velocities"]
        size = max(abs(x) for x in expected)
        difference = max(abs(a - b) for a, b in zip(state, expected))
        agree = impacts == document["summary"]["impacts"] and difference <= args.agree * size
        if not agree:
            raise SystemExit(
                f"the solvers disagree: impacts {impacts} (scipy) against "
                f"{document['summary']['impacts']} (rattle), final state off by {difference:e} "
                f"of {size:e}")
        rattle_times = [rattle_run(args.rattle, args.scene, record, args.duration)[1]
                        for _ in range(max(5, args.repeats))]
        scipy_times = [scipy_run(scene, times, values, args.duration, args.rtol, restart)[2]
                       for _ in range(args.repeats)]
    samples = len(times)
    r, s = statistics.median(rattle_times), statistics.median(scipy_times)
    print(json.dumps({
        "scene": args.scene,
        "record": {"samples": samples, "step": args.step, "duration": args.duration,
                   "band": [LO, HI], "lines": LINES, "rms": args.rms, "seed": args.seed},
        "impacts": impacts,
        "final_state_difference": difference,
        "final_state_size": size,
        "rattle": {"what": "rattle respond --json, whole process",
                   "runs": len(rattle_times), "median_seconds": round(r, 5),
                   "samples_per_second": round(samples / r), "impacts_per_second": round(impacts / r)},
        "scipy": {"what": f"solve_ivp DOP853 rtol {args.rtol}, restarts at impacts"
                          + (" and samples" if restart else "") + ", loop only",
                  "runs": len(scipy_times), "median_seconds": round(s, 3),
                  "samples_per_second": round(samples / s), "impacts_per_second": round(impacts / s)},
        "ratio": round(s / r, 1),
    }, indent=2))


if __name__ == "__main__":
    main()
