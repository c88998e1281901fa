#!/usr/bin/env python3
"""The impacting unit integrated the way most scipy users would: solve_ivp with DOP853,
terminal events on r = +gap and r = -gap, and a restart after each impact with the restitution
map (momentum conserved, rdot+ = -e rdot-). A peer for timing, not part of rattle.

Usage: python3 scipy_dop853.py [SCENE.json] [--omega W] [--periods N] [--rtol R]
Prints impacts, wall time, impacts/s and X_o = max|u_o| over the last period.
"""
import argparse
import json
import math
import time

import numpy as np
from scipy.integrate import solve_ivp


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("scene", nargs="?", default="data/scenes/paper-damped.json")
    parser.add_argument("--omega", type=float, default=2.0)
    parser.add_argument("--periods", type=int, default=2000)
    parser.add_argument("--rtol", type=float, default=1e-10)
    args = parser.parse_args()
    with open(args.scene) as f:
        scene = json.load(f)
    unit = scene["unit"]
    mo, mi = unit["outer_mass"], unit["inner_mass"]
    ko, ki = unit["outer_stiffness"], unit["inner_stiffness"]
    ug = scene["base"]["amplitude"]
    damping = scene.get("damping", {})
    co, ci = damping.get("outer", 0.0), damping.get("inner", 0.0)
    gap, e = scene["stops"]["gap"], scene["stops"]["restitution"]
    w = args.omega

    def field(t, y):
        base = ko * ug * math.cos(w * t) - co * ug * w * math.sin(w * t)
        spring = ki * (y[1] - y[0]) + ci * (y[3] - y[2])
        return [y[2], y[3], (base - ko * y[0] - co * y[2] + spring) / mo, -spring / mi]

    def side1(t, y):
        return y[1] - y[0] - gap

    side1.terminal, side1.direction = True, 1.0

    def side2(t, y):
        return y[1] - y[0] + gap

    side2.terminal, side2.direction = True, -1.0

    period = 2 * math.pi / w
    end = args.periods * period
    last = end - period
    t, y = 0.0, np.zeros(4)
    impacts = 0
    amplitude = 0.0
    start = time.perf_counter()
    while t < end:
        sol = solve_ivp(field, (t, end), y, method="DOP853", rtol=args.rtol,
                        atol=args.rtol * 1e-3, events=(side1, side2),
                        dense_output=t >= last - period)
        if sol.sol is not None:
            ts = np.linspace(max(sol.t[0], last), sol.t[-1], 2000)
            if ts[-1] > ts[0]:
                amplitude = max(amplitude, np.abs(sol.sol(ts)[0]).max())
        t, y = sol.t[-1], sol.y[:, -1].copy()
        if sol.status == 1:  # an impact: restitution along r, momentum conserved
            rdot = y[3] - y[2]
            jump = (1 + e) * rdot * mo * mi / (mo + mi)
            y[2] += jump / mo
            y[3] -= jump / mi
            impacts += 1
    elapsed = time.perf_counter() - start
    print(json.dumps({
        "solver": "scipy solve_ivp DOP853, terminal events + restarts",
        "omega": w, "periods": args.periods, "rtol": args.rtol,
        "impacts": impacts, "seconds": round(elapsed, 4),
        "impacts_per_second": round(impacts / elapsed, 1),
        "outer_amplitude": amplitude,
    }, indent=2))


if __name__ == "__main__":
    main()
