//! The two solvers against each other on cases whose answer is known independently.

use rattle_analytic::symmetric_orbits;
use rattle_compare::scene::simulator::{run, Regime};
use rattle_compare::scene::{DampingSpec, Scene};
use rattle_compare::verdict::{compare, difference, Class, Starts, MATCH_TOLERANCE};
use rattle_event_driven::{SimulationOptions, Start};

fn damped() -> Scene {
    let mut s = Scene::paper();
    s.damping = Some(DampingSpec {
        outer: 0.1,
        inner: 0.05,
    });
    s
}

#[test]
fn damped_steady_state_is_the_analytic_stable_viable_orbit() {
    let scene = damped();
    let options = SimulationOptions::default();
    for omega in [2.0, 3.0] {
        let orbits =
            symmetric_orbits(&scene.unit_model(), &scene.stops_model().unwrap(), omega).unwrap();
        let stable: Vec<_> = orbits.iter().filter(|o| o.viable && o.stable).collect();
        assert_eq!(
            stable.len(),
            1,
            "ω={omega}: one stable viable orbit expected"
        );
        let sim = run(&scene, omega, &Start::rest(2), &options).unwrap();
        assert_eq!(sim.regime, Regime::TwoImpact, "ω={omega}");
        let d = difference(&sim, stable[0]).unwrap();
        // The simulator stops when the stroboscopic map repeats to its periodicity tolerance;
        // the agreement cannot be better than that, and must not be much worse.
        assert!(
            d.largest() < 100.0 * options.periodicity_tolerance,
            "ω={omega}: {d:?}"
        );
    }
}

#[test]
fn classification_of_hand_checked_frequencies() {
    let scene = Scene::paper();
    let options = SimulationOptions::default();
    // ω = 2: the analytic crate gives one stable viable symmetric orbit (branch 1, X_o ≈ 0.849)
    // and the simulator from rest lands on it.
    let p = compare(&scene, 2.0, &options, Starts::RestAndOrbits).unwrap();
    assert_eq!(p.class, Class::Agreement);
    assert!(p.difference.unwrap() < MATCH_TOLERANCE);
    // ω = 0.5: the linear motion clears the stops (|u_i − u_o| = 0.104 < Δ = 0.5) and nothing
    // damps the free vibration started from rest: no steady state, beyond the model.
    let p = compare(&scene, 0.5, &options, Starts::RestAndOrbits).unwrap();
    assert!(matches!(p.class, Class::Beyond(_)), "{:?}", p.class);
    assert_eq!(p.from_rest.regime, Regime::NoDissipation);
    // ω = 1: no symmetric orbit is viable (both penetrate), the simulator settles on four
    // impacts per period, and the analytic orbit of that signature agrees with it.
    let p = compare(&scene, 1.0, &options, Starts::RestAndOrbits).unwrap();
    assert!(p.analytic.orbits.iter().all(|(_, o)| !o.viable));
    assert_eq!(p.from_rest.steady.impacts_per_period, 4.0);
    assert_eq!(p.class, Class::Agreement, "{:?}", p.class);
    let signature = p.cross.signature.as_ref().unwrap();
    assert_eq!((signature.impacts(), signature.period()), (4, 1));
    assert!(p.difference.unwrap() < MATCH_TOLERANCE);
    // ω = 2.9: the symmetric orbit has lost stability (viable, unstable) and the simulator
    // settles on an asymmetric two-impact orbit (the side-2 impact off half a period).
    let p = compare(&scene, 2.9, &options, Starts::RestAndOrbits).unwrap();
    assert!(p.analytic.orbits.iter().any(|(_, o)| o.viable && !o.stable));
    assert_eq!(p.class, Class::Agreement, "{:?}", p.class);
    let orbit = p.cross.analytic.as_ref().unwrap();
    assert_eq!(orbit.signature.to_string(), "+-");
    assert!(
        (orbit.impact_phases[1] - 0.5).abs() > 1e-3,
        "{:?}",
        orbit.impact_phases
    );
}
