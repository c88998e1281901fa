//! The simulator's own Newton on its stroboscopic map against the analytic orbits: the fixed
//! point is the analytic orbit's state, and the simulator's Floquet multipliers (eigenvalues of
//! its flight propagators and impact saltation matrices) are the analytic crate's, for stable,
//! unstable and undamped elastic orbits alike.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_analytic::Orbit;
use rattle_compare::scene::analytic::{analyse, orbit_state, OrbitSearch};
use rattle_compare::scene::simulator::{model, run, start_on_orbit, START_PERTURBATION};
use rattle_compare::scene::Scene;
use rattle_event_driven::{
    periodic_orbit, stroboscopic_map, PeriodicOrbit, SimulationOptions, Start, Status,
};
use std::path::Path;

/// Multipliers agree to this (absolute; they are of order one).
const MULTIPLIER_TOLERANCE: f64 = 1e-8;

/// States agree to this, relative to `max(|x|, gap)`: the analytic orbit's equations are met
/// to about `1e-10` of the state, the simulator's map to its root tolerance.
const STATE_TOLERANCE: f64 = 1e-9;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("../../data/scenes/{name}.json"));
    Scene::load(&path).unwrap()
}

/// Sorted by modulus, then argument.
fn sorted(m: &[Complex<f64>]) -> Vec<Complex<f64>> {
    let mut m = m.to_vec();
    m.sort_by(|a, b| {
        a.norm()
            .total_cmp(&b.norm())
            .then(a.arg().total_cmp(&b.arg()))
    });
    m
}

/// The largest difference between two sets of multipliers, each of `a` matched to the nearest
/// unmatched one of `b` (in `a`'s order sorted by modulus and argument): on the unit circle the
/// moduli are equal to rounding, so a plain sort would pair them by chance.
fn multiplier_difference(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    assert_eq!(a.len(), b.len());
    let mut left = sorted(b);
    sorted(a)
        .iter()
        .map(|x| {
            let (i, d) = left
                .iter()
                .map(|y| (x - y).norm())
                .enumerate()
                .min_by(|p, q| p.1.total_cmp(&q.1))
                .unwrap();
            left.remove(i);
            d
        })
        .fold(0.0, f64::max)
}

/// Newton from the analytic orbit's state mid-way through its first flight; checks the fixed
/// point against the analytic state there and the multipliers against the analytic ones.
/// Returns the orbit and the largest multiplier difference.
fn confirm(scene: &Scene, orbit: &Orbit, perturbation: f64) -> (PeriodicOrbit, f64) {
    let omega = orbit.omega;
    let m = model(scene, omega).unwrap();
    let start = start_on_orbit(scene, orbit, perturbation);
    let found = periodic_orbit(&m, omega, &start, 1, &SimulationOptions::default())
        .unwrap_or_else(|e| panic!("ω = {omega}: {e}"));
    let period = std::f64::consts::TAU / omega;
    let t_mid = 0.5 * orbit.beta * period;
    let exact = orbit_state(scene, orbit, t_mid);
    let exact = DVector::from_column_slice(exact.as_slice());
    let scale = exact.norm().max(orbit.gap);
    let state_error = (&found.state - &exact).norm() / scale;
    let difference = multiplier_difference(&found.floquet_multipliers, &orbit.floquet_multipliers);
    eprintln!(
        "ω = {omega}: {} iterations, residual {:.1e}, state error {state_error:.1e}, \
         multiplier difference {difference:.1e}, |μ| = {:?}",
        found.iterations,
        found.residual,
        sorted(&found.floquet_multipliers)
            .iter()
            .map(|m| m.norm())
            .collect::<Vec<_>>()
    );
    assert!(
        state_error < STATE_TOLERANCE,
        "ω = {omega}: {state_error:e}"
    );
    assert!(
        difference < MULTIPLIER_TOLERANCE,
        "ω = {omega}: {difference:e}\n{:?}\n{:?}",
        sorted(&found.floquet_multipliers),
        sorted(&orbit.floquet_multipliers)
    );
    // A two-impact orbit: one impact on each side per period.
    assert_eq!(found.impact_sides.len(), 2);
    assert_ne!(found.impact_sides[0], found.impact_sides[1]);
    (found, difference)
}

#[test]
fn newton_converges_quadratically_to_the_stable_damped_orbit() {
    let scene = scene("paper-damped");
    let omega = 2.0;
    let point = analyse(&scene, omega, OrbitSearch::Symmetric).unwrap();
    let stable: Vec<_> = point.stable_viable_orbits().collect();
    assert_eq!(stable.len(), 1);
    let orbit = stable[0].1;
    // Hand-rolled Newton on the public map from a guess 1e-4 off the orbit: the residual
    // squares at each step until it reaches the rounding of the map.
    let m = model(&scene, omega).unwrap();
    let options = SimulationOptions::default();
    let mut guess = start_on_orbit(&scene, orbit, 1e3 * START_PERTURBATION);
    let mut residuals = Vec::new();
    for _ in 0..6 {
        let map = stroboscopic_map(&m, omega, &guess, 1, &options).unwrap();
        let step = &map.state - &guess.state;
        let residual = step.norm() / guess.state.norm().max(orbit.gap);
        residuals.push(residual);
        if residual < 1e-14 {
            break;
        }
        let a = map.jacobian - DMatrix::<f64>::identity(4, 4);
        guess.state -= a.lu().solve(&step).unwrap();
    }
    eprintln!("residuals: {residuals:?}");
    assert!(residuals[0] > 1e-6, "{residuals:?}");
    // Quadratic: each residual above the rounding floor is within a modest factor of the
    // square of the one before; three steps reach the floor from 1e-4.
    for w in residuals.windows(2) {
        if w[0] > 1e-7 {
            assert!(w[1] < 10.0 * w[0] * w[0], "{residuals:?}");
        }
    }
    assert!(
        residuals.len() <= 4 && *residuals.last().unwrap() < 1e-13,
        "{residuals:?}"
    );

    // The library's Newton from the same guess: the analytic state and multipliers.
    let (found, difference) = confirm(&scene, orbit, 1e3 * START_PERTURBATION);
    assert!(found.iterations <= 3, "{}", found.iterations);
    assert!(found.floquet_multipliers.iter().all(|m| m.norm() < 1.0));
    eprintln!("stable damped orbit: multiplier difference {difference:.1e}");

    // And the polished orbit a run from rest ends on is the same orbit.
    let sim = run(&scene, omega, &Start::rest(2), &options).unwrap();
    assert_eq!(sim.steady.status, Status::Periodic);
    let polished = sim.steady.orbit.expect("polished");
    eprintln!(
        "run from rest: polished in {} iterations, residual {:.1e}",
        polished.iterations, polished.residual
    );
    let d = multiplier_difference(&polished.floquet_multipliers, &orbit.floquet_multipliers);
    assert!(d < MULTIPLIER_TOLERANCE, "{d:e}");
}

#[test]
fn newton_holds_an_unstable_orbit_no_run_can_reach() {
    let scene = Scene::paper();
    let mut confirmed = 0;
    let mut largest: f64 = 0.0;
    for omega in [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0] {
        let point = analyse(&scene, omega, OrbitSearch::Symmetric).unwrap();
        for (_, orbit) in point.orbits.iter().filter(|(_, o)| o.viable && !o.stable) {
            let (found, difference) = confirm(&scene, orbit, START_PERTURBATION);
            assert!(found.floquet_multipliers.iter().any(|m| m.norm() > 1.0));
            largest = largest.max(difference);
            confirmed += 1;
        }
    }
    eprintln!(
        "unstable orbits confirmed: {confirmed}, largest multiplier difference {largest:.1e}"
    );
    assert!(confirmed >= 1);
}

#[test]
fn newton_confirms_undamped_elastic_orbits() {
    let scene = scene("paper-elastic");
    let mut confirmed = 0;
    let mut largest: f64 = 0.0;
    for omega in [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 5.0] {
        let point = analyse(&scene, omega, OrbitSearch::Symmetric).unwrap();
        for (_, orbit) in point.orbits.iter().filter(|(_, o)| o.viable) {
            let (found, difference) = confirm(&scene, orbit, START_PERTURBATION);
            // Nothing dissipates: det DP = 1, and the multipliers come in pairs μ, 1/μ̄ on or
            // off the unit circle.
            let product: Complex<f64> = found.floquet_multipliers.iter().product();
            assert!((product - 1.0).norm() < 1e-10, "{product}");
            largest = largest.max(difference);
            confirmed += 1;
        }
    }
    eprintln!("elastic orbits confirmed: {confirmed}, largest multiplier difference {largest:.1e}");
    assert!(confirmed >= 1);
}
