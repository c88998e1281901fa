#!/usr/bin/env python3
"""A compliant stop's contacts: `rattle simulate` against scipy's solve_ivp on the same scene,
at rising contact stiffness, in the same run. A peer for timing, not part of rattle or its
tests.

The scene: the gallery's compliant oscillator (`data/scenes/compliant-oscillator.json`: a
unit mass on a unit spring and a 0.1 dashpot to the frame, forced by cos ωt, a stop at
x = 0.5) with its contact stiffness set to each of --stiffness and its contact damping
matched to the restitution --restitution of the isolated mass,
c_c = 2 ζ √k_c, ζ = −ln e / √(π² + ln² e). Each run starts from rest at --omega: rattle's
runs until its motion is periodic (its own test) and reports the periods it ran; scipy's
then runs that many periods.

scipy the way a careful user would write it for a stiff piecewise system: the free flight and
the contact (the spring k_c and dashpot c_c while the penetration δ = x − gap > 0) as two
right-hand sides, a terminal event at δ = 0 rising (entry) in flight and falling (exit) in
contact, and the integration restarted in the other phase at each; --method (Radau by
default: the contact is stiff, ω_c = √k_c up to 1e3 times the spring's rate and more) with
rtol --rtol and atol 1e-3 × rtol. Its time is the integration loop's alone.

rattle: `rattle simulate SCENE --omega W --json`, whole process (start-up, the run to its
steady state, the Newton polish of its cycle and the document included), on a scene file
written with each stiffness.

Before timing, the two must agree: a period-1 motion with the same number of contacts in the
last period, and max |x| over the last period (scipy's from its dense output on 2000 points)
within --agree (1e-6) of rattle's steady amplitude, relative.

Usage: python3 scipy_compliant.py --rattle target/release/rattle [--stiffness 1e2,1e4,1e6]
       [--omega W] [--repeats R] [--method Radau|LSODA|DOP853]
Prints one JSON document: per stiffness, both solvers' median times and their ratio.
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import tempfile
import time

import numpy as np
from scipy.integrate import solve_ivp

#: The scene's numbers (the gallery's compliant oscillator).
MASS, STIFFNESS, DAMPING, FORCE, GAP = 1.0, 1.0, 0.1, 1.0, 0.5


def matched_damping(k_c, e):
    """The contact damping that gives the isolated unit mass the restitution e."""
    l = math.log(e)
    zeta = -l / math.sqrt(math.pi**2 + l * l)
    return 2.0 * zeta * math.sqrt(k_c * MASS)


def scene_text(k_c, c_c):
    return json.dumps(
        {
            "name": "compliant-oscillator",
            "structure": {
                "bodies": [{"name": "x", "mass": MASS}],
                "springs": [{"between": ["frame", "x"], "stiffness": STIFFNESS}],
                "dashpots": [{"between": ["frame", "x"], "damping": DAMPING}],
                "stops": [
                    {
                        "between": ["frame", "x"],
                        "gap_plus": GAP,
                        "contact_stiffness": k_c,
                        "contact_damping": c_c,
                    }
                ],
            },
            "forcing": {"forces": [{"on": "x", "amplitude": FORCE, "phase": 0.0}]},
            "observe": "x",
        }
    )


def scipy_run(k_c, c_c, omega, periods, method, rtol):
    """From rest over `periods` periods: the contacts' entry times, the final period's dense
    samples and the loop's wall time."""
    end = periods * 2.0 * math.pi / omega

    def free(t, y):
        x, v = y
        return [v, (FORCE * math.cos(omega * t) - STIFFNESS * x - DAMPING * v) / MASS]

    def pressed(t, y):
        x, v = y
        contact = k_c * (x - GAP) + c_c * v
        return [v, (FORCE * math.cos(omega * t) - STIFFNESS * x - DAMPING * v - contact) / MASS]

    def entry(t, y):
        return y[0] - GAP

    entry.terminal, entry.direction = True, 1.0

    def exit_(t, y):
        return y[0] - GAP

    exit_.terminal, exit_.direction = True, -1.0

    t, y, in_contact = 0.0, np.zeros(2), False
    entries, pieces = [], []
    start = time.perf_counter()
    while t < end:
        rhs, event = (pressed, exit_) if in_contact else (free, entry)
        sol = solve_ivp(
            rhs, (t, end), y, method=method, rtol=rtol, atol=1e-3 * rtol,
            events=event, dense_output=True,
        )
        pieces.append((t, sol.t[-1], sol.sol))
        if sol.status == 1:
            t, y = sol.t_events[0][0], sol.y_events[0][0].copy()
            y[0] = GAP
            if not in_contact:
                entries.append(t)
            in_contact = not in_contact
        else:
            t = end
    elapsed = time.perf_counter() - start
    period = 2.0 * math.pi / omega
    samples = np.linspace(end - period, end, 2000)
    xs = []
    for s in samples:
        for a, b, dense in pieces:
            if a <= s <= b:
                xs.append(dense(s)[0])
                break
    return entries, max(abs(x) for x in xs), elapsed


def rattle_run(rattle, path, omega):
    start = time.perf_counter()
    out = subprocess.run(
        [rattle, "simulate", path, "--omega", repr(omega), "--json"],
        check=True, capture_output=True, text=True,
    )
    elapsed = time.perf_counter() - start
    return json.loads(out.stdout), elapsed


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--rattle", default=os.environ.get("RATTLE_BIN", "target/release/rattle"))
    p.add_argument("--stiffness", default="1e2,1e4,1e6")
    p.add_argument("--restitution", type=float, default=0.8)
    p.add_argument("--omega", type=float, default=1.2)
    p.add_argument("--repeats", type=int, default=3)
    p.add_argument("--method", default="Radau")
    p.add_argument("--rtol", type=float, default=1e-10)
    p.add_argument("--agree", type=float, default=1e-6)
    a = p.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k_c in [float(s) for s in a.stiffness.split(",")]:
            c_c = matched_damping(k_c, a.restitution)
            path = os.path.join(tmp, "scene.json")
            with open(path, "w") as f:
                f.write(scene_text(k_c, c_c))
            ours = [rattle_run(a.rattle, path, a.omega) for _ in range(a.repeats)]
            doc = ours[0][0]
            periods = doc["periods_run"]
            if doc["period"] != 1:
                raise SystemExit(f"k_c = {k_c}: rattle's motion is not of period 1: {doc}")
            theirs = [
                scipy_run(k_c, c_c, a.omega, periods, a.method, a.rtol)
                for _ in range(a.repeats)
            ]
            entries, amplitude, _ = theirs[0]
            period = 2.0 * math.pi / a.omega
            last = sum(1 for t in entries if t >= (periods - 1) * period)
            ours_amplitude = doc["body_amplitudes"]["x"]
            difference = abs(amplitude - ours_amplitude) / abs(ours_amplitude)
            if difference > a.agree or last != round(doc["contacts_per_period"] or 0):
                raise SystemExit(
                    f"k_c = {k_c}: the solvers disagree: max|x| {ours_amplitude} against "
                    f"{amplitude} ({difference:.1e}); contacts in the last period "
                    f"{doc['contacts_per_period']} against {last}"
                )
            rattle_s = statistics.median(t for _, t in ours)
            scipy_s = statistics.median(t for _, _, t in theirs)
            rows.append(
                {
                    "contact_stiffness": k_c,
                    "contact_damping": c_c,
                    "periods": periods,
                    "contacts": len(entries),
                    "max_x_rattle": ours_amplitude,
                    "max_x_scipy": amplitude,
                    "relative_difference": difference,
                    "rattle_s": rattle_s,
                    "scipy_s": scipy_s,
                    "ratio": scipy_s / rattle_s,
                }
            )
    print(json.dumps({"omega": a.omega, "method": a.method,
                      "rtol": a.rtol, "runs": rows}, indent=1))


if __name__ == "__main__":
    main()
