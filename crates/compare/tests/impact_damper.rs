//! The impact damper — a primary body on a spring and a dashpot, forced, with a free body in a
//! clearance of it — checked against Masri & Caughey's symmetric two-impact motion in closed
//! form ([`rattle_compare::references::impact_damper`]), which neither solver computes: the
//! analytic solver's `0+ 0-` orbits, stable and unstable, and the simulator's steady state and
//! Newton orbits.

use nalgebra::DVector;
use rattle_analytic::{sequence_orbits, ImpactSequence};
use rattle_compare::references::impact_damper::{ImpactDamper, SymmetricOrbit};
use rattle_compare::scene::simulator::{polished_cycle, run_structure};
use rattle_compare::scene::structure::{Structure, StructureScene};
use rattle_compare::verdict::structure::structure_cross_check;
use rattle_event_driven::{periodic_orbit, simulate, SimulationOptions, Start};
use std::f64::consts::TAU;

/// The closed form and the analytic solver's cycle equations solve the same equations in
/// different ways (a quadratic in closed form; Newton on the exact flow): they agree to a few
/// thousand roundings of the state.
const CLOSED_FORM: f64 = 1e-10;

/// The simulator's periodic orbit is polished by its Newton to its tolerance (1e-12 relative by
/// default); its impact times and velocities follow to that order, its multipliers to a few
/// times it.
const SIMULATED: f64 = 1e-9;

/// The amplitudes of the closed form are maxima on a grid of `T/2¹⁷`: a parabola's top is
/// missed by at most `(ωT/2¹⁷)²/8 ≈ 3e-10` of the amplitude.
const GRID_AMPLITUDE: f64 = 1e-8;

/// The damper with clearance `gap` (each side): `F = 0.1` on a primary `m = k = 1`,
/// `c = 0.05`, free mass `0.1`, restitution `0.6`, the force's phase `0.4`.
fn scene(gap: f64) -> String {
    format!(
        r#"{{"name": "impact-damper",
            "structure": {{
              "bodies":   [{{"name": "primary", "mass": 1.0}}, {{"name": "ball", "mass": 0.1}}],
              "springs":  [{{"between": ["frame", "primary"], "stiffness": 1.0}}],
              "dashpots": [{{"between": ["frame", "primary"], "damping": 0.05}}],
              "stops":    [{{"between": ["primary", "ball"], "gap": {gap}, "restitution": 0.6}}]}},
            "forcing": {{"forces": [{{"on": "primary", "amplitude": 0.1, "phase": 0.4}}]}},
            "observe": "primary"}}"#
    )
}

fn structure(gap: f64) -> Structure {
    let scene: StructureScene = serde_json::from_str(&scene(gap)).expect("the scene parses");
    scene.structure().expect("the structure is valid")
}

fn closed_form(gap: f64) -> ImpactDamper {
    ImpactDamper {
        mass: 1.0,
        damping: 0.05,
        stiffness: 1.0,
        force: 0.1,
        phase: 0.4,
        free_mass: 0.1,
        gap,
        restitution: 0.6,
    }
}

fn phase_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

fn moduli(list: &[[f64; 2]]) -> Vec<f64> {
    let mut m: Vec<f64> = list.iter().map(|[re, im]| re.hypot(*im)).collect();
    m.sort_by(|a, b| b.total_cmp(a));
    m
}

/// The viable symmetric orbits at `omega`, the stable one first.
fn viable(gap: f64, omega: f64) -> Vec<SymmetricOrbit> {
    let mut orbits: Vec<SymmetricOrbit> = closed_form(gap)
        .symmetric_orbits(omega)
        .unwrap()
        .into_iter()
        .filter(|o| o.viable)
        .collect();
    orbits.sort_by_key(|o| !o.stable);
    orbits
}

/// At ω = 1, a clearance of 0.8 has a stable symmetric motion and 0.6 an unstable one (the
/// other root of each is not a motion: the free body would leave the wall outward). The
/// analytic solver's `0+ 0-` finds each with the closed form's phase, displacement, velocities,
/// amplitude, viability, stability and multipliers.
#[test]
fn the_analytic_solver_finds_the_symmetric_motions() {
    let omega = 1.0;
    for (gap, stable) in [(0.8, true), (0.6, false)] {
        let reference = viable(gap, omega);
        assert_eq!(reference.len(), 1, "{gap}: {reference:?}");
        let r = &reference[0];
        assert_eq!(r.stable, stable, "{gap}: {r:?}");
        let model = structure(gap).analytic_model().unwrap();
        let sequence = ImpactSequence::parse("0+ 0-", 1).unwrap();
        let found = sequence_orbits(&model, omega, &sequence).unwrap();
        let a = found
            .iter()
            .filter(|o| o.viable)
            .min_by(|p, q| {
                let d = |o: &rattle_analytic::SequenceOrbit| {
                    phase_distance(o.alpha + 0.4, r.forcing_phase)
                };
                d(p).total_cmp(&d(q))
            })
            .unwrap_or_else(|| panic!("{gap}: no viable analytic orbit among {found:?}"));
        assert!(
            phase_distance(a.alpha + 0.4, r.forcing_phase) < CLOSED_FORM,
            "{gap}: {} {r:?}",
            a.alpha + 0.4
        );
        // The state before the side-1 impact: (x, y, ẋ, ẏ).
        let before = &a.states_before_impacts[0];
        assert!(
            (before[0] - r.primary_displacement).abs() < CLOSED_FORM * r.primary_displacement.abs(),
            "{gap}: {before:?} {r:?}"
        );
        let relative = before[3] - before[2];
        assert!(
            (relative - r.relative_velocity_before).abs() < CLOSED_FORM * relative.abs(),
            "{gap}: {relative} {r:?}"
        );
        assert_eq!((a.viable, a.stable), (r.viable, r.stable), "{gap}: {r:?}");
        let mu: Vec<[f64; 2]> = a.floquet_multipliers.iter().map(|m| [m.re, m.im]).collect();
        for (m, e) in moduli(&mu).iter().zip(moduli(&r.multipliers)) {
            assert!(
                (m - e).abs() < CLOSED_FORM * e.max(1.0),
                "{gap}: {mu:?} {r:?}"
            );
        }
        assert!(
            (a.amplitudes[0] - r.primary_amplitude).abs() < GRID_AMPLITUDE * r.primary_amplitude,
            "{gap}: {} {r:?}",
            a.amplitudes[0]
        );
    }
}

/// The simulator started near the stable motion settles on it (its polished cycle has the
/// closed form's impact times and velocities), and its Newton started on the unstable one
/// converges to it and reports a multiplier outside the unit circle.
#[test]
fn the_simulator_finds_the_symmetric_motions() {
    let omega = 1.0;
    let period = TAU / omega;
    for (gap, stable) in [(0.8, true), (0.6, false)] {
        let s = structure(gap);
        let r = &viable(gap, omega)[0];
        // The state just after the side-1 impact, from the closed form.
        let after = {
            let mu = 0.1;
            let gamma = (1.0 + 2.0 * mu - 0.6) / 1.6;
            let v = r.free_speed;
            DVector::from_vec(vec![
                r.primary_displacement,
                r.primary_displacement + gap,
                (2.0 * mu - gamma) * v,
                -v,
            ])
        };
        let start = Start {
            state: after,
            time: r.impact_time,
        };
        let model = s.event_model(omega).unwrap();
        let options = SimulationOptions::default();
        if stable {
            let sim = run_structure(&s, omega, &start, &options).unwrap();
            let orbit = sim.steady.orbit.as_deref().expect("a polished orbit");
            let cycle = polished_cycle(&model, omega, orbit, &options).unwrap();
            assert_eq!(cycle.impacts.len(), 2, "{gap}");
            let plus = cycle
                .impacts
                .iter()
                .find(|i| i.side == 1)
                .expect("an impact on side +");
            let time = plus.time.rem_euclid(period);
            let dt = (time - r.impact_time).abs();
            assert!(dt.min(period - dt) < SIMULATED * period, "{time} {r:?}");
            let relative = plus.state_before[3] - plus.state_before[2];
            assert!(
                (relative - r.relative_velocity_before).abs() < SIMULATED * relative,
                "{relative} {r:?}"
            );
            assert!(
                (sim.outer_amplitude - r.primary_amplitude).abs()
                    < GRID_AMPLITUDE * r.primary_amplitude,
                "{} {r:?}",
                sim.outer_amplitude
            );
            let largest = moduli(&r.multipliers)[0];
            let found = orbit
                .floquet_multipliers
                .iter()
                .map(|m| m.norm())
                .fold(0.0, f64::max);
            assert!(
                (found - largest).abs() < SIMULATED * largest,
                "{found} {r:?}"
            );
        } else {
            // One period on from the closed form's state: close to the orbit still (it grows
            // away by the largest multiplier per period).
            let one = SimulationOptions {
                fixed_periods: Some(1),
                ..SimulationOptions::default()
            };
            let mid = simulate(&model, omega, &start, &one).unwrap().final_state;
            let found = periodic_orbit(&model, omega, &mid, 1, &options).unwrap();
            assert_eq!(found.impact_sides.len(), 2);
            let largest = found
                .floquet_multipliers
                .iter()
                .map(|m| m.norm())
                .fold(0.0, f64::max);
            let expected = moduli(&r.multipliers)[0];
            assert!(
                largest > 1.0 && (largest - expected).abs() < SIMULATED * expected,
                "{largest} {expected}"
            );
        }
    }
}

/// `rattle compare`'s cross-check on the damper's gallery clearance: the simulator from rest
/// and the analytic solver seeded from it agree.
#[test]
fn both_solvers_agree_on_the_damper() {
    let s = structure(0.8);
    for omega in [0.9, 1.0, 1.1] {
        let check = structure_cross_check(&s, omega, &SimulationOptions::default()).unwrap();
        assert_eq!(
            check.class.name(),
            "agreement",
            "{omega}: {:?}",
            check.class
        );
    }
}
