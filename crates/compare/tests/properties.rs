//! Properties over random valid scenes and frequencies: no panic, finite numbers, no
//! penetration, no energy gained at impacts, the half-period symmetry of symmetric orbits, and
//! stable viable orbits held by the simulator when started on them. Each property counts the
//! cases and items it checked and fails when too few were: a property that passes on a solver
//! error, or on nothing, is not a property.

use nalgebra::{Vector2, Vector4};
use proptest::prelude::*;
use proptest::test_runner::{TestCaseError, TestRunner};
use rattle_analytic::symmetric_orbits;
use rattle_analytic::ForcedFlow;
use rattle_compare::scene::simulator::{model, run};
use rattle_compare::scene::{BaseSpec, DampingSpec, Scene, StopsSpec, UnitSpec};
use rattle_compare::verdict::{compare, Starts};
use rattle_event_driven::{SimulationOptions, Start};
use std::cell::Cell;

/// `cases` random scenes from a fixed seed, so that CI runs the same cases every time; set
/// `PROPTEST_RNG_SEED` to explore others.
fn config(cases: u32) -> ProptestConfig {
    let seed = std::env::var("PROPTEST_RNG_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0x007a_771e);
    ProptestConfig {
        cases,
        rng_seed: proptest::test_runner::RngSeed::Fixed(seed),
        ..ProptestConfig::default()
    }
}

fn scenes() -> impl Strategy<Value = (Scene, f64)> {
    (
        (0.5f64..5.0, 0.5f64..5.0, 0.5f64..10.0, 0.5f64..10.0),
        0.1f64..3.0,
        (0.05f64..2.0, 0.0f64..=1.0),
        proptest::option::of((0.0f64..0.5, 0.0f64..0.5)),
        0.3f64..5.0,
    )
        .prop_map(|((mo, mi, ko, ki), ug, (gap, e), damping, omega)| {
            let scene = Scene {
                name: "random".into(),
                unit: UnitSpec {
                    outer_mass: mo,
                    inner_mass: mi,
                    outer_stiffness: ko,
                    inner_stiffness: ki,
                },
                base: BaseSpec::fundamental(ug),
                stops: Some(StopsSpec::rigid(gap, e)),
                damping: damping.map(|(outer, inner)| DampingSpec { outer, inner }),
                cells: None,
                chain: None,
            };
            (scene, omega)
        })
}

/// Runs `property` on `cases` random scenes; a case the property rejects with `prop_assume!`
/// (the solver declined the scene) is not counted as checked. Returns how many cases were
/// checked, after failing on the first counter-example.
fn check(
    cases: u32,
    property: impl Fn((Scene, f64)) -> Result<usize, TestCaseError>,
) -> (usize, usize) {
    let mut runner = TestRunner::new(config(cases));
    let (checked, items) = (Cell::new(0usize), Cell::new(0usize));
    runner
        .run(&scenes(), |case| {
            let n = property(case)?;
            checked.set(checked.get() + 1);
            items.set(items.get() + n);
            Ok(())
        })
        .unwrap();
    (checked.get(), items.get())
}

#[test]
fn analytic_orbits_are_finite_and_half_period_symmetric() {
    let (checked, orbits) = check(48, |(scene, omega)| {
        let unit = scene.unit_model();
        let stops = scene.stops_model().unwrap();
        let orbits = symmetric_orbits(&unit, &stops, omega);
        prop_assume!(
            orbits.is_ok(),
            "the analytic solver declined: {:?}",
            orbits.err()
        );
        let orbits = orbits.unwrap();
        let flow = ForcedFlow::new(&unit, omega);
        for o in &orbits {
            prop_assert!(o.alpha.is_finite() && o.outer_amplitude.is_finite());
            prop_assert!(o
                .floquet_multipliers
                .iter()
                .all(|m| m.re.is_finite() && m.im.is_finite()));
            // u(t + T/2) = −u(t): half a period after the side-1 impact the state is minus the
            // state before it.
            let p0 = Vector2::new(o.alpha.cos(), o.alpha.sin());
            let (x, _) = flow
                .transition(0.5 * flow.period())
                .apply(&o.state_after_impact, &p0);
            let scale = o.state_before_impact.norm().max(o.gap).max(1.0);
            let residual: Vector4<f64> = x + o.state_before_impact;
            prop_assert!(
                residual.norm() < 1e-10 * scale,
                "residual {:e}",
                residual.norm()
            );
        }
        Ok(orbits.len())
    });
    // Every scene of the fixed seed is solved, and they offer orbits to check.
    assert_eq!(checked, 48);
    assert!(orbits >= 20, "only {orbits} orbits checked");
}

#[test]
fn simulation_is_finite_never_penetrates_and_never_gains_energy() {
    let (checked, impacts) = check(48, |(scene, omega)| {
        let options = SimulationOptions {
            fixed_periods: Some(20),
            record_trajectory: true,
            ..SimulationOptions::default()
        };
        // A solver error fails the property: every valid scene must simulate.
        let sim = run(&scene, omega, &Start::rest(2), &options)
            .map_err(|e| TestCaseError::fail(format!("simulation failed: {e}")))?;
        prop_assert!(sim.outer_amplitude.is_finite());
        let gap = scene.stops.unwrap().gap;
        let size = sim.steady.amplitudes.iter().fold(gap, |a, b| a.max(*b));
        for (t, x) in sim.steady.trajectory.as_ref().unwrap() {
            let r = x[1] - x[0];
            prop_assert!(
                r.abs() <= gap + 1e-9 * size,
                "t = {t}: |r| = {} > {gap}",
                r.abs()
            );
        }
        let m = model(&scene, omega).unwrap();
        let (mo, mi) = (scene.unit.outer_mass, scene.unit.inner_mass);
        for imp in &sim.steady.cycle_impacts {
            let before = imp.state_before.rows(2, 2).into_owned();
            let after = m.impact_velocities(0, &before, None);
            let energy = |v: &nalgebra::DVector<f64>| 0.5 * (mo * v[0] * v[0] + mi * v[1] * v[1]);
            let momentum = |v: &nalgebra::DVector<f64>| mo * v[0] + mi * v[1];
            prop_assert!(energy(&after) <= energy(&before) * (1.0 + 1e-12));
            prop_assert!(
                (momentum(&after) - momentum(&before)).abs()
                    <= 1e-12 * (1.0 + momentum(&before).abs())
            );
        }
        Ok(sim.steady.cycle_impacts.len())
    });
    assert_eq!(checked, 48);
    assert!(impacts >= 20, "only {impacts} impacts checked");
}

#[test]
fn stable_viable_orbits_are_held_when_started_on_them() {
    let (checked, held) = check(24, |(scene, omega)| {
        let options = SimulationOptions {
            max_periods: 6000,
            ..SimulationOptions::default()
        };
        let p = compare(&scene, omega, &options, Starts::RestAndOrbits)
            .map_err(|e| TestCaseError::fail(format!("a solver failed: {e}")))?;
        let mut decidable = 0;
        for t in &p.trials {
            let (_, orbit) = p
                .analytic
                .orbits
                .iter()
                .find(|(b, _)| *b == t.branch)
                .unwrap();
            let slowest = orbit
                .floquet_multipliers
                .iter()
                .map(|m| m.norm())
                .fold(0.0, f64::max);
            // Decidable within the cap: the start perturbation (1e-7) decays below the
            // periodicity tolerance in well under 6000 periods.
            if orbit.stable && slowest < 0.99 {
                prop_assert!(
                    t.held,
                    "ω = {omega}, branch {}: {:?}",
                    t.branch,
                    t.difference
                );
                decidable += 1;
            }
        }
        Ok(decidable)
    });
    assert_eq!(checked, 24);
    // The fixed seed offers stable viable orbits to start on; if a change of the strategy
    // leaves none, this property checks nothing and must say so.
    assert!(held >= 3, "only {held} stable viable orbits checked");
}

/// Found by the property above: after a release from sticking, contacts were ignored until the
/// release's time *within the period*, also in the next period — the inner mass passed through
/// a stop. Kept as a fixed case.
#[test]
fn regression_release_grace_does_not_leak_into_the_next_period() {
    let scene = Scene {
        name: "regression".into(),
        unit: UnitSpec {
            outer_mass: 0.5,
            inner_mass: 4.923754389828173,
            outer_stiffness: 4.289977251413697,
            inner_stiffness: 0.5,
        },
        base: BaseSpec::fundamental(0.1),
        stops: Some(StopsSpec::rigid(0.05, 0.48946877913933634)),
        damping: None,
        cells: None,
        chain: None,
    };
    let options = SimulationOptions {
        fixed_periods: Some(20),
        record_trajectory: true,
        ..SimulationOptions::default()
    };
    let sim = run(&scene, 0.3, &Start::rest(2), &options).unwrap();
    for (t, x) in sim.steady.trajectory.as_ref().unwrap() {
        assert!((x[1] - x[0]).abs() <= 0.05 * (1.0 + 1e-10), "t = {t}");
    }
}
