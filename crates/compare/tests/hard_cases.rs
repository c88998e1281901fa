//! The hard-case suite: every scene of `validation/hard-cases/` through both solvers, with the
//! behaviour each must keep (see that folder's README).

use rattle_analytic::{linear_response, symmetric_orbits};
use rattle_compare::scene::simulator::{run, Regime};
use rattle_compare::scene::Scene;
use rattle_compare::verdict::{compare, Class, Starts, MATCH_TOLERANCE};
use rattle_event_driven::{SimulationOptions, Start, Status};
use std::path::Path;

fn scene(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../validation/hard-cases")
        .join(format!("{name}.json"));
    Scene::load(&path).unwrap()
}

fn finite_simulation(s: &Scene, omega: f64) -> rattle_compare::scene::simulator::SimulatedPoint {
    let sim = run(s, omega, &Start::rest(2), &SimulationOptions::default()).unwrap();
    assert!(
        sim.outer_amplitude.is_finite(),
        "{}: X_o not finite",
        s.name
    );
    assert!(sim.steady.impacts_per_period.is_finite());
    sim
}

#[test]
fn beta_half_symmetric_orbit_is_found_and_reached() {
    let s = scene("beta-half");
    let p = compare(
        &s,
        2.0,
        &SimulationOptions::default(),
        Starts::RestAndOrbits,
    )
    .unwrap();
    assert_eq!(p.class, Class::Agreement);
    assert!(p.difference.unwrap() < MATCH_TOLERANCE);
}

#[test]
fn exact_resonance_stays_finite() {
    let s = scene("exact-resonance");
    let w = 1.5f64.sqrt();
    let lin = linear_response(&s.unit_model(), w);
    assert!(lin.unbounded);
    let orbits = symmetric_orbits(&s.unit_model(), &s.stops_model().unwrap(), w).unwrap();
    assert!(!orbits.is_empty());
    assert!(orbits
        .iter()
        .all(|o| o.outer_amplitude.is_finite() && o.alpha.is_finite()));
    finite_simulation(&s, w);
}

#[test]
fn internal_resonance_is_continuous_and_finite() {
    let s = scene("internal-resonance");
    let w = 1.5f64.sqrt();
    let (unit, stops) = (s.unit_model(), s.stops_model().unwrap());
    let at = symmetric_orbits(&unit, &stops, w).unwrap();
    for d in [-1e-7, 1e-7] {
        let near = symmetric_orbits(&unit, &stops, w + d).unwrap();
        assert_eq!(near.len(), at.len());
        for (a, b) in at.iter().zip(&near) {
            assert!((a.outer_amplitude - b.outer_amplitude).abs() < 1e-4 * a.outer_amplitude);
        }
    }
    finite_simulation(&s, w);
}

#[test]
fn grazing_is_caught_and_the_run_stays_bounded() {
    // The gap is the linear motion's relative amplitude less 1e-8 of it: started on the linear
    // steady state, the first period already holds a graze of width ~1e-4 of the period.
    let s = scene("grazing");
    let w = 0.9;
    let lin = linear_response(&s.unit_model(), w);
    let v = |a: nalgebra::Complex<f64>| (a * nalgebra::Complex::new(0.0, w)).re;
    let start = Start {
        state: nalgebra::DVector::from_vec(vec![
            lin.outer.re,
            lin.inner.re,
            v(lin.outer),
            v(lin.inner),
        ]),
        time: 0.0,
    };
    let one = SimulationOptions {
        fixed_periods: Some(1),
        ..SimulationOptions::default()
    };
    let sim = run(&s, w, &start, &one).unwrap();
    assert!(sim.steady.impacts >= 1, "graze missed");
    // From rest the near-grazing dynamics need not settle, but the run ends with finite numbers.
    finite_simulation(&s, w);
}

#[test]
fn chatter_ends_in_sticking() {
    let sim = finite_simulation(&scene("chatter"), 0.6);
    assert!(sim.steady.sticking);
}

#[test]
fn plastic_impacts_stick() {
    let sim = finite_simulation(&scene("plastic"), 0.8);
    assert!(sim.steady.sticking);
    assert!(sim.steady.impacts_per_period <= 4.0);
}

#[test]
fn no_dissipation_is_reported() {
    let sim = finite_simulation(&scene("no-dissipation"), 2.0);
    assert_eq!(sim.regime, Regime::NoDissipation);
    assert!(sim.steady.periods_run <= 1000);
    assert!(sim.transmittance_db.is_none());
}

#[test]
fn long_run_of_the_linear_unit() {
    let s = scene("long-run");
    assert!(s.stops.is_none());
    let options = SimulationOptions {
        fixed_periods: Some(1_000_000),
        ..SimulationOptions::default()
    };
    let sim = run(&s, 1.1, &Start::rest(2), &options).unwrap();
    assert_eq!(sim.steady.periods_run, 1_000_000);
    assert_eq!(sim.steady.status, Status::Periodic);
    // From rest, a million periods of light damping leave the linear steady state.
    let lin = linear_response(&s.unit_model(), 1.1);
    assert!((sim.outer_amplitude - lin.outer_amplitude).abs() < 1e-9 * lin.outer_amplitude);
}

#[test]
fn coexisting_attractors_are_named() {
    let s = scene("coexistence");
    let p = compare(
        &s,
        1.86,
        &SimulationOptions::default(),
        Starts::RestAndOrbits,
    )
    .unwrap();
    // From rest the unit settles on a periodic motion of another signature, which the analytic
    // orbit of that signature matches; a stable symmetric orbit holds when started on it.
    assert_eq!(p.class, Class::Agreement, "{:?}", p.class);
    assert!(p.coexisting);
    assert!(p.trials.iter().any(|t| t.held));
    assert_ne!(p.from_rest.regime, Regime::TwoImpact);
}

#[test]
fn forcing_far_below_the_natural_frequencies_stops_at_the_oscillation_cap() {
    // e = 0, undamped, ω = 0.001: about 2400 oscillations of the fastest mode (√6 rad/s) per
    // forcing period, and no steady state to reach. The run is bounded by the oscillation cap,
    // not by 20 000 periods, and says so.
    let s = Scene::parse(
        r#"{"name": "plastic-undamped",
            "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
            "base": {"amplitude": 1.0}, "stops": {"gap": 0.5, "restitution": 0.0}}"#,
        "test",
    )
    .unwrap();
    let omega = 0.001;
    let options = SimulationOptions {
        max_oscillations: Some(2e5),
        ..SimulationOptions::default()
    };
    let sim = run(&s, omega, &Start::rest(2), &options).unwrap();
    assert_eq!(
        sim.steady.stopped,
        rattle_event_driven::Stop::OscillationCap
    );
    let fastest = 6.0f64.sqrt(); // k_o = 6, m_o = 2, k_i = 3, m_i = 1: ω² = 1.5 and 6
    assert_eq!(
        sim.steady.periods_run,
        (2e5 * omega / fastest).floor() as u64
    );
    assert!(sim.outer_amplitude.is_finite());
}

#[test]
fn a_unit_far_from_its_stops_is_judged_on_its_own_scale() {
    // Gap 1e6, undamped, ω = 1000: the motion (~1e-6) never comes near the stops and its free
    // oscillation never decays. Measured against the gap it would "repeat" at once; measured
    // against itself it does not, and nothing can dissipate it.
    let s = Scene::parse(
        r#"{"name": "gap-1e6",
            "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
            "base": {"amplitude": 1.0}, "stops": {"gap": 1e6, "restitution": 0.8}}"#,
        "test",
    )
    .unwrap();
    let sim = run(&s, 1000.0, &Start::rest(2), &SimulationOptions::default()).unwrap();
    assert_eq!(sim.steady.status, Status::NoDissipation);
    assert_eq!(sim.steady.impacts, 0);
}

#[test]
fn extreme_scenes_finish_with_an_honest_status() {
    // `validation/extreme-scenes/`: e = 0 and e = 1 undamped, gap 1e-9 and 1e6, base amplitude
    // 1e6, at very low, moderate and very high ω. Smaller caps than the defaults keep the test
    // short; the command-line defaults are timed on the performance page (docs/performance.md).
    let options = SimulationOptions {
        max_periods: 2000,
        max_events: Some(200_000),
        max_oscillations: Some(2e5),
        ..SimulationOptions::default()
    };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation/extreme-scenes");
    let mut scenes = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let s = Scene::load(&entry.unwrap().path()).unwrap();
        scenes += 1;
        for omega in [0.001, 2.0, 1000.0] {
            let sim = run(&s, omega, &Start::rest(2), &options)
                .unwrap_or_else(|e| panic!("{} at {omega}: {e}", s.name));
            let what = format!("{} at ω = {omega}", s.name);
            assert!(sim.outer_amplitude.is_finite(), "{what}");
            assert!(sim.steady.impacts_per_period.is_finite(), "{what}");
            assert!(sim.transmittance_db.is_none_or(f64::is_finite), "{what}");
            // Periodic only with something to dissipate; otherwise the run says why it ended.
            if sim.steady.status == Status::Periodic {
                assert!(
                    s.damping.is_some()
                        || s.stops
                            .as_ref()
                            .is_some_and(|st| st.rigid_restitution() < 1.0),
                    "{what}"
                );
            }
            assert!(sim.steady.periods_run <= 2000, "{what}");
        }
    }
    assert_eq!(scenes, 5);
}

#[test]
fn floquet_multipliers_where_the_plain_eigenvalue_iteration_cycles() {
    // At this point of a map the monodromy of a symmetric orbit made nalgebra's unbounded
    // Schur iteration cycle forever (the map hung); the multipliers must come out finite.
    let s = Scene::parse(
        r#"{"name": "map point",
            "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
            "base": {"amplitude": 1.0},
            "stops": {"gap": 0.6833333333333333, "restitution": 0.23076923076923078},
            "damping": {"outer": 0.1, "inner": 0.05}}"#,
        "test",
    )
    .unwrap();
    let point = rattle_compare::scene::analytic::analyse(
        &s,
        2.7488721804511274,
        rattle_compare::scene::analytic::OrbitSearch::Symmetric,
    )
    .unwrap();
    assert!(!point.orbits.is_empty());
    for (_, orbit) in &point.orbits {
        assert!(orbit
            .floquet_multipliers
            .iter()
            .all(|m| m.re.is_finite() && m.im.is_finite()));
    }
}
