#!/usr/bin/env python3
"""The rattle unit in Siconos, as a peer of rattle's two solvers.

Models the impacting mass-in-mass unit of a rattle scene in Siconos 4.4 (Debian's
`python3-siconos`) and runs it with Siconos's two schemes:

- event-driven: `EventDriven` with `LsodarOSI` between events and two LCPs (impact and
  smooth acceleration), its event tolerance raised with `setToleranceED`;
- Moreau–Jean time stepping: `TimeStepping` with `MoreauJeanOSI(theta)` and an LCP.

The unit: `q = (u_o, u_i, u_b)`, a `LagrangianLinearTIDS` with `M = diag(m_o, m_i, 1)`; the
outer mass hangs from the base by `k_o` and `c_o`, the masses are tied by `k_i` and `c_i`.
Two unilateral constraints (`LagrangianLinearTIR`, Newton impact law with restitution `e`):
`y₁ = Δ − (u_i − u_o) ≥ 0` (side 1, `r = +Δ`) and `y₂ = Δ + (u_i − u_o) ≥ 0` (side 2).

The base moves as `u_g cos ωt`. A time-dependent external force would need a C plug-in to be
fast (a Python callback is called at every right-hand side); instead the base is a third,
kinematic coordinate `u_b` with its own row `ü_b + ω² u_b = 0`, started at `(u_g, 0)`, which
drives the outer mass through `k_o` and `c_o` (`K` and `C` are not symmetric: nothing acts
back on the base). The system is then linear and time invariant, and both schemes integrate
the base's motion with their own accuracy.

Writes one JSON document (default `data/peers/siconos.json`) with:

- `work_precision`: the case of rattle's work-precision figure (damped paper scene, ω = 2,
  300 periods from rest): each scheme over its accuracy knob (Lsodar's tolerance, the time
  step), the outer amplitude over the last period, impacts, seconds (minimum of repeats);
- `steady_states`: at a few frequencies, rattle's steady state (`rattle simulate --json`) and
  Siconos's (each scheme) after the same number of periods from rest, with the time of each;
- `hard_cases`: a grazing and a sticking case: what each scheme does, with the Moreau–Jean
  penetration depth.

Times are CPU time (user + system), so that a shared machine's load does not count: Siconos's
simulation loop (driven from Python event by event or step by step; the import and the model's
construction excluded), rattle's whole process. Each Siconos run is a child process (`--run`),
so that a crash or a hang of Siconos is recorded as that run's failure and the others still
run.

Usage: `/usr/bin/python3 crates/compare/peers/siconos_unit.py --rattle target/release/rattle`
(`cargo xtask peers` does this). Needs numpy and Siconos (`apt-get install python3-siconos`).
"""

import argparse
import json
import math
import os
import platform
import resource
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..", ".."))

# The work-precision case of `cargo xtask figures` (xtask/src/figures.rs).
WP_SCENE = "data/scenes/paper-damped.json"
WP_OMEGA = 2.0
WP_PERIODS = 300
# Lsodar's relative (and absolute, in metres) tolerances, and Moreau–Jean's time steps (s).
LSODAR_TOLERANCES = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12]
TIME_STEPS = [1e-2, 3e-3, 1e-3]
# Siconos's event tolerance: at its default (machine precision) the event-driven scheme stops
# with "output of level 0 must be positive".
TOLERANCE_ED = 1e-8
# Output points per period of the event-driven scheme (the times it stops at besides events).
ED_OUTPUTS_PER_PERIOD = 16
# Moreau–Jean's theta (0.5: the midpoint rule between impacts).
THETA = 0.5
# Frequencies of the steady-state table, rad/s, on the damped paper scene: where rattle's
# motion from rest repeats (`++--`, `++++++------`, `+-` three times); at 1.8, 2.4, 2.5, 2.7,
# 3.5 and 4 rad/s it does not within 20 000 periods, and there is no steady state to compare.
STEADY_OMEGAS = [1.0, 1.5, 2.0, 2.2, 3.0]
# Most periods from rest of a steady-state run (rattle's motion must repeat before).
STEADY_MAX_PERIODS = 2000
# Timed runs of the `rattle` command (milliseconds each: more repeats than Siconos's).
RATTLE_REPEATS = 7
# Settings of the steady-state and hard-case runs.
STEADY_TOLERANCE = 1e-10
STEADY_TIME_STEP = 3e-3
# Hard cases (validation/hard-cases): the linear motion grazing the stops, and chatter that
# ends in sticking.
HARD_CASES = [
    ("grazing", "validation/hard-cases/grazing.json", 0.9, 100),
    ("sticking", "validation/hard-cases/chatter.json", 0.6, 50),
]
# A run is stopped (and recorded as failed) after this many seconds.
RUN_TIMEOUT = 300.0
# The event-driven scheme is stopped (and the run recorded as failed) after this many events.
MAX_EVENTS = 2_000_000


def load_scene(path):
    """The unit of a rattle scene file as a dict of floats (no damping: zeros)."""
    with open(os.path.join(ROOT, path)) as f:
        scene = json.load(f)
    unit, damping = scene["unit"], scene.get("damping") or {}
    return {
        "name": scene["name"],
        "mo": unit["outer_mass"],
        "mi": unit["inner_mass"],
        "ko": unit["outer_stiffness"],
        "ki": unit["inner_stiffness"],
        "ug": scene["base"]["amplitude"],
        "gap": scene["stops"]["gap"],
        "e": scene["stops"]["restitution"],
        "co": damping.get("outer", 0.0),
        "ci": damping.get("inner", 0.0),
    }


def matrices(u, omega):
    """M, K, C of the three coordinates (u_o, u_i, u_b)."""
    import numpy as np

    mass = np.diag([u["mo"], u["mi"], 1.0])
    stiffness = np.array(
        [
            [u["ko"] + u["ki"], -u["ki"], -u["ko"]],
            [-u["ki"], u["ki"], 0.0],
            [0.0, 0.0, omega * omega],
        ]
    )
    damping = np.array(
        [
            [u["co"] + u["ci"], -u["ci"], -u["co"]],
            [-u["ci"], u["ci"], 0.0],
            [0.0, 0.0, 0.0],
        ]
    )
    return mass, stiffness, damping


def build(u, omega, t_end):
    """The unit in Siconos, at rest with the base at u_g: (system, nsds, interactions)."""
    import numpy as np
    import siconos.kernel as sk

    mass, stiffness, damping = matrices(u, omega)
    ds = sk.LagrangianLinearTIDS([0.0, 0.0, u["ug"]], [0.0, 0.0, 0.0], mass, stiffness, damping)
    nsds = sk.NonSmoothDynamicalSystem(0.0, t_end)
    nsds.insertDynamicalSystem(ds)
    interactions = []
    for row in ([1.0, -1.0, 0.0], [-1.0, 1.0, 0.0]):
        relation = sk.LagrangianLinearTIR(np.array([row]), [u["gap"]])
        interaction = sk.Interaction(sk.NewtonImpactNSL(u["e"]), relation)
        nsds.link(interaction, ds)
        interactions.append(interaction)
    return ds, nsds, interactions


def flow_matrix(u, omega):
    """A of x' = A x, x = (q, v), between impacts."""
    import numpy as np

    mass, stiffness, damping = matrices(u, omega)
    minv = np.linalg.inv(mass)
    a = np.zeros((6, 6))
    a[:3, 3:] = np.eye(3)
    a[3:, :3] = -minv @ stiffness
    a[3:, 3:] = -minv @ damping
    return a


def propagate(a, x, s):
    """exp(A s) x by its Taylor series (s is at most a sixteenth of a period here)."""
    term, total = x.copy(), x.copy()
    for n in range(1, 40):
        term = (a @ term) * (s / n)
        total = total + term
        if abs(term).max() <= 1e-17 * abs(total).max():
            break
    return total


def outer_extremum(a, x, length):
    """The largest |u_o| on [0, length] of the free flight from x, by Newton on u̇_o = 0."""
    end = propagate(a, x, length)
    best = max(abs(x[0]), abs(end[0]))
    if x[3] * end[3] >= 0.0:
        return best
    lo, hi = 0.0, length
    s = length * x[3] / (x[3] - end[3])
    for _ in range(60):
        y = propagate(a, x, s)
        if y[3] * x[3] > 0.0:
            lo = s
        else:
            hi = s
        accel = (a @ y)[3]
        step = -y[3] / accel if accel != 0.0 else math.inf
        s_new = s + step
        if not lo < s_new < hi:
            s_new = 0.5 * (lo + hi)
        if abs(s_new - s) <= 1e-15 * length:
            s = s_new
            break
        s = s_new
    return max(best, abs(propagate(a, x, s)[0]))


def run_event_driven(u, omega, periods, tolerance, tail_periods):
    """Siconos's event-driven scheme from rest for `periods` periods."""
    import numpy as np
    import siconos.kernel as sk

    period = 2.0 * math.pi / omega
    t_end = periods * period
    ds, nsds, _ = build(u, omega, t_end)
    osi = sk.LsodarOSI()
    osi.setTol(1, tolerance, tolerance)
    sim = sk.EventDriven(nsds, sk.TimeDiscretisation(0.0, period / ED_OUTPUTS_PER_PERIOD))
    sim.insertIntegrator(osi)
    sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_IMPACT)
    sim.insertNonSmoothProblem(sk.LCP(), sk.SICONOS_OSNSP_ED_SMOOTH_ACC)
    sim.setToleranceED(TOLERANCE_ED)
    events = sim.eventsManager()
    q, v = ds.q(), ds.velocity()
    tail_start = t_end - tail_periods * period
    impacts, steps, tail = 0, 0, []
    start = time.process_time()
    try:
        while sim.hasNextEvent():
            sim.advanceToEvent()
            if events.nextEvent().getType() == 2:
                impacts += 1
            sim.processEvents()
            steps += 1
            t = sim.startingTime()
            if t >= tail_start - 1e-12 * t_end:
                tail.append((t, np.concatenate([q, v])))
            if steps >= MAX_EVENTS:
                raise RuntimeError(f"{MAX_EVENTS} events")
    except Exception as error:  # Siconos's own failure: a result, not an error of ours
        return {
            "seconds": time.process_time() - start,
            "impacts": impacts,
            "events": steps,
            "failure": f"{error} (at t = {sim.startingTime():.6g} s, period "
            f"{sim.startingTime() / period:.2f}, after {impacts} impacts)",
        }
    seconds = time.process_time() - start
    a = flow_matrix(u, omega)
    amplitude = 0.0
    for (t0, x0), (t1, _) in zip(tail, tail[1:]):
        if t1 > t0:
            amplitude = max(amplitude, outer_extremum(a, x0, t1 - t0))
    return {"seconds": seconds, "impacts": impacts, "events": steps, "outer_amplitude": amplitude}


def run_moreau_jean(u, omega, periods, time_step, tail_periods):
    """Siconos's Moreau–Jean scheme from rest for `periods` periods."""
    import siconos.kernel as sk

    period = 2.0 * math.pi / omega
    t_end = periods * period
    ds, nsds, interactions = build(u, omega, t_end)
    sim = sk.TimeStepping(nsds, sk.TimeDiscretisation(0.0, time_step))
    sim.insertIntegrator(sk.MoreauJeanOSI(THETA))
    sim.insertNonSmoothProblem(sk.LCP())
    q = ds.q()
    gap = u["gap"]
    tail_start = t_end - tail_periods * period
    impacts, steps, amplitude, penetration = 0, 0, 0.0, -math.inf
    in_contact = [False, False]
    start = time.process_time()
    while sim.hasNextEvent():
        sim.computeOneStep()
        steps += 1
        for k, interaction in enumerate(interactions):
            impulse = interaction.lambda_(1)[0]
            if impulse > 0.0 and not in_contact[k]:
                impacts += 1
            in_contact[k] = impulse > 0.0
        penetration = max(penetration, abs(q[1] - q[0]) - gap)
        if sim.nextTime() >= tail_start:
            amplitude = max(amplitude, abs(q[0]))
        sim.nextStep()
    seconds = time.process_time() - start
    return {
        "seconds": seconds,
        "impacts": impacts,
        "steps": steps,
        "outer_amplitude": amplitude,
        "penetration": max(penetration, 0.0),
    }


def child(spec):
    """Runs one Siconos run described by `spec` (JSON) and prints its result as JSON."""
    u = load_scene(spec["scene"])
    if spec["scheme"] == "event-driven":
        out = run_event_driven(u, spec["omega"], spec["periods"], spec["knob"], spec["tail"])
    else:
        out = run_moreau_jean(u, spec["omega"], spec["periods"], spec["knob"], spec["tail"])
    print(json.dumps(out))


def siconos_run(scene, scheme, omega, periods, knob, tail=1, repeats=1):
    """One Siconos run in a child process; the minimum time of `repeats`; failures as values."""
    spec = {"scene": scene, "scheme": scheme, "omega": omega, "periods": periods}
    spec.update({"knob": knob, "tail": tail})
    best = None
    for _ in range(repeats):
        try:
            done = subprocess.run(
                [sys.executable, __file__, "--run", json.dumps(spec)],
                capture_output=True,
                text=True,
                timeout=RUN_TIMEOUT,
            )
        except subprocess.TimeoutExpired:
            return {"knob": knob, "failure": f"no end within {RUN_TIMEOUT:.0f} s"}
        if done.returncode != 0:
            lines = [l for l in (done.stderr + done.stdout).splitlines() if l.strip()]
            reason = lines[-1] if lines else f"exit {done.returncode}"
            return {"knob": knob, "failure": reason[:300]}
        out = json.loads(done.stdout.strip().splitlines()[-1])
        out["knob"] = knob
        if out.get("failure"):
            return out
        out["failure"] = None
        if best is None or out["seconds"] < best["seconds"]:
            best = out
    return best


def rattle_simulate(rattle, scene, omega, periods=None, repeats=1):
    """`rattle simulate SCENE --omega W --json [--periods P]`: its document and its CPU time
    (user + system of the whole process, minimum of `repeats`)."""
    args = [rattle, "simulate", os.path.join(ROOT, scene), "--omega", str(omega), "--json"]
    if periods is not None:
        args += ["--periods", str(periods)]
    best, doc = math.inf, None
    for _ in range(repeats):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        done = subprocess.run(args, capture_output=True, text=True, check=True)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (after.ru_utime + after.ru_stime) - (before.ru_utime + before.ru_stime)
        best = min(best, cpu)
        doc = json.loads(done.stdout)
    return doc, best


def progress(message):
    print(message, file=sys.stderr, flush=True)


def work_precision(repeats):
    """Both schemes over their knobs on the work-precision case."""
    out = {"scene": WP_SCENE, "omega": WP_OMEGA, "periods": WP_PERIODS}
    for scheme, knobs in (("event-driven", LSODAR_TOLERANCES), ("moreau-jean", TIME_STEPS)):
        points = []
        for knob in knobs:
            progress(f"work-precision: {scheme} at {knob:g}")
            # The time steps from 1e-3 s down take ten seconds and more: one run.
            r = repeats if scheme == "event-driven" or knob > 1e-3 else 1
            points.append(siconos_run(WP_SCENE, scheme, WP_OMEGA, WP_PERIODS, knob, 1, r))
        out[scheme.replace("-", "_")] = points
    return out


def steady_states(rattle, repeats):
    """rattle's steady state beside Siconos's at each of STEADY_OMEGAS."""
    rows = []
    for omega in STEADY_OMEGAS:
        progress(f"steady state at {omega} rad/s")
        steady, _ = rattle_simulate(rattle, WP_SCENE, omega)
        cycle = max(int(steady.get("period") or 1), 1)
        # The same number of periods from rest for everyone: rattle's own run to periodicity,
        # at least the work-precision case's 300.
        periods = max(int(steady["periods_run"]) + 20, WP_PERIODS)
        if steady["status"] != "periodic" or periods > STEADY_MAX_PERIODS:
            raise SystemExit(f"rattle's motion at {omega} rad/s does not repeat: no steady state")
        fixed, seconds = rattle_simulate(rattle, WP_SCENE, omega, periods, RATTLE_REPEATS)
        rows.append(
            {
                "omega": omega,
                "periods": periods,
                "cycle_periods": cycle,
                "rattle": {
                    "status": steady["status"],
                    "signature": steady.get("signature"),
                    "outer_amplitude": steady["outer_amplitude"],
                    "fixed_periods_outer_amplitude": fixed["outer_amplitude"],
                    "impacts": fixed["impacts"],
                    "seconds": seconds,
                },
                "event_driven": siconos_run(
                    WP_SCENE, "event-driven", omega, periods, STEADY_TOLERANCE, cycle, 1
                ),
                "moreau_jean": siconos_run(
                    WP_SCENE, "moreau-jean", omega, periods, STEADY_TIME_STEP, cycle, 1
                ),
            }
        )
    return rows


def hard_cases(rattle):
    """What each scheme does on a grazing and a sticking case."""
    rows = []
    for case, scene, omega, periods in HARD_CASES:
        progress(f"hard case {case}")
        doc, seconds = rattle_simulate(rattle, scene, omega, periods, RATTLE_REPEATS)
        rows.append(
            {
                "case": case,
                "scene": scene,
                "omega": omega,
                "periods": periods,
                "rattle": {
                    "status": doc["status"],
                    "outer_amplitude": doc["outer_amplitude"],
                    "impacts": doc["impacts"],
                    "seconds": seconds,
                },
                "event_driven": siconos_run(
                    scene, "event-driven", omega, periods, STEADY_TOLERANCE
                ),
                "moreau_jean": siconos_run(scene, "moreau-jean", omega, periods, STEADY_TIME_STEP),
            }
        )
    return rows


def per_impact(run):
    """Microseconds per impact of a run, as text."""
    if run.get("failure") or not run.get("impacts"):
        return "failed" if run.get("failure") else "-"
    return f"{run['seconds'] / run['impacts'] * 1e6:.1f} us"


def summary(doc):
    """The steady states and hard cases, one line each, on standard output."""
    print("omega  rattle X_o  Siconos ED X_o  Siconos MJ X_o  per impact: rattle / ED / MJ")
    for row in doc["steady_states"]:
        ed, mj, rattle = row["event_driven"], row["moreau_jean"], row["rattle"]
        rattle_per_impact = rattle["seconds"] / max(rattle["impacts"], 1) * 1e6
        print(
            f"{row['omega']:<6} {rattle['outer_amplitude']:<11.8g} "
            f"{ed.get('outer_amplitude') or float('nan'):<15.8g} "
            f"{mj.get('outer_amplitude') or float('nan'):<15.8g} "
            f"{rattle_per_impact:.1f} us / {per_impact(ed)} / {per_impact(mj)}"
        )
    for row in doc["hard_cases"]:
        for scheme in ("event_driven", "moreau_jean"):
            run = row[scheme]
            what = run["failure"] or f"ran, {run['impacts']} impacts"
            if run.get("penetration") is not None:
                what += f", deepest penetration {run['penetration']:.2e} m"
            print(f"{row['case']}: {scheme}: {what}")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rattle", default=os.path.join(ROOT, "target/release/rattle"))
    parser.add_argument("--out", default=os.path.join(ROOT, "data/peers/siconos.json"))
    parser.add_argument("--repeats", type=int, default=3, help="runs timed per point (minimum)")
    parser.add_argument("--run", help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.run:
        child(json.loads(args.run))
        return
    import siconos  # noqa: F401  (fails here, before any work, when Siconos is missing)

    version = subprocess.run(
        ["dpkg-query", "-W", "-f=${Version}", "python3-siconos"], capture_output=True, text=True
    ).stdout.strip()
    def write(doc):
        os.makedirs(os.path.dirname(os.path.abspath(args.out)), exist_ok=True)
        with open(args.out, "w") as f:
            json.dump(doc, f, indent=1)
            f.write("\n")

    doc = {
        "siconos": version or "unknown",
        "python": platform.python_version(),
        "machine": f"{platform.machine()}, {os.cpu_count()} cores",
        "settings": {
            "tolerance_ed": TOLERANCE_ED,
            "ed_outputs_per_period": ED_OUTPUTS_PER_PERIOD,
            "theta": THETA,
            "steady_tolerance": STEADY_TOLERANCE,
            "steady_time_step": STEADY_TIME_STEP,
        },
        "work_precision": work_precision(args.repeats),
        "steady_states": [],
        "hard_cases": [],
    }
    # Written after each part, so that a long run interrupted keeps what it measured.
    write(doc)
    doc["steady_states"] = steady_states(args.rattle, args.repeats)
    write(doc)
    doc["hard_cases"] = hard_cases(args.rattle)
    write(doc)
    summary(doc)
    progress(f"wrote {args.out}")


if __name__ == "__main__":
    main()
