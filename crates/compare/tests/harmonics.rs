//! Scenes whose base motion and forces carry higher harmonics, checked against answers known
//! without either solver's harmonic code: the two solvers against each other on the same
//! periodic motion, a harmonic of amplitude zero against the scene without it, a base harmonic
//! against the force it exerts, and the motion without impacts against the linear response
//! summed harmonic by harmonic in closed form.

use rattle_compare::api::{self, Comparison, Simulation};
use rattle_compare::scene::{AnyScene, SceneError};
use rattle_event_driven::SimulationOptions;
use std::f64::consts::TAU;

/// The simulator polishes its cycle by Newton to about `1e-12` relative
/// ([`SimulationOptions::root_tolerance`]), the analytic solver its cycle equations to
/// rounding: the same periodic motion from both agrees to well within `1e-10`.
const BOTH_SOLVERS: f64 = 1e-10;

fn parse(text: &str) -> AnyScene {
    AnyScene::parse(text, "test").unwrap_or_else(|e| panic!("{e}"))
}

fn unit(base: &str, damping: &str) -> String {
    format!(
        r#"{{"name": "paper-harmonics",
            "unit": {{"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0}},
            "base": {base},
            "stops": {{"gap": 0.5, "restitution": 0.8}}{damping}}}"#
    )
}

/// The cross-check's record on `scene` at `omega`, asserted to be agreement within
/// [`BOTH_SOLVERS`] in every body's amplitude and, where the simulator's Newton confirms the
/// analytic orbit, in its state.
fn assert_agreement(scene: &AnyScene, omega: f64) {
    let check = api::compare(scene, omega, &SimulationOptions::default()).expect("runs");
    let Comparison::Structure(record) = check else {
        panic!("a scene with harmonics runs as a structure");
    };
    assert_eq!(
        record.class, "agreement",
        "ω = {omega}: {}",
        record.class_detail
    );
    let d = record.relative_difference.expect("a difference");
    assert!(d <= BOTH_SOLVERS, "ω = {omega}: amplitudes differ by {d:e}");
    if let Some(state) = record.confirmation.and_then(|c| c.state_difference) {
        assert!(
            state <= BOTH_SOLVERS,
            "ω = {omega}: states differ by {state:e}"
        );
    }
    assert!(record.at.effects.contains(&"harmonics"));
    assert!(!record.at.harmonics.is_empty());
}

#[test]
fn a_two_harmonic_base_motion_is_the_same_periodic_motion_from_both_solvers() {
    let base = r#"{"amplitude": 1.0, "harmonics": [{"order": 2, "amplitude": 0.3, "phase": 0.5},
                                                 {"order": 3, "amplitude": 0.1, "phase": -1.0}]}"#;
    let damped = unit(base, r#", "damping": {"outer": 0.1, "inner": 0.05}"#);
    // Period 3, 1, 4 and 1 with impacts, and one without (4.5 rad/s): the linear response.
    for omega in [0.8, 1.3, 2.2, 3.0, 4.5] {
        assert_agreement(&parse(&damped), omega);
    }
    // Without dashpots only the impacts dissipate: at 3 rad/s the transient still decays.
    assert_agreement(&parse(&unit(base, "")), 3.0);
}

#[test]
fn a_chain_and_a_structure_with_harmonic_forces_agree_between_the_solvers() {
    let chain = r#"{"name": "chain-harmonics",
        "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
        "base": {"amplitude": 0.5, "harmonics": [{"order": 2, "amplitude": 0.2, "phase": 1.0}]},
        "stops": {"gap": 0.3, "restitution": 0.7},
        "damping": {"outer": 0.2, "inner": 0.1},
        "cells": 3}"#;
    assert_agreement(&parse(chain), 1.5);
    // The base's and a force's harmonics of the same order at different phases, and a force's
    // harmonic of an order the base does not have.
    let structure = r#"{"name": "oscillator-harmonics",
        "structure": {
          "bodies":   [{"name": "x", "mass": 1.0}],
          "springs":  [{"between": ["base", "x"], "stiffness": 1.0}],
          "dashpots": [{"between": ["base", "x"], "damping": 0.1}],
          "stops":    [{"between": ["frame", "x"], "gap_plus": 0.5, "restitution": 0.8}]},
        "forcing": {
          "base": {"amplitude": 0.7, "harmonics": [{"order": 2, "amplitude": 0.2, "phase": 0.3}]},
          "forces": [{"on": "x", "amplitude": 0.2, "phase": 0.4,
                      "harmonics": [{"order": 2, "amplitude": 0.1, "phase": -0.7},
                                    {"order": 3, "amplitude": 0.05, "phase": 2.0}]}]}}"#;
    for omega in [0.9, 1.4] {
        assert_agreement(&parse(structure), omega);
    }
}

/// The simulated steady state of `scene` at `omega`: every body's amplitude.
fn amplitudes(scene: &AnyScene, omega: f64) -> Vec<f64> {
    match api::simulate(scene, omega, &SimulationOptions::default()).expect("runs") {
        Simulation::Structure { point, .. } | Simulation::Cells { point, .. } => {
            point.steady.amplitudes.clone()
        }
    }
}

#[test]
fn a_harmonic_of_amplitude_zero_is_the_unit_on_its_own_road() {
    // With a harmonic the scene runs as a structure, without it on the unit's own road: two
    // models of the unit built apart, the same motion.
    let zero = parse(&unit(
        r#"{"amplitude": 1.0, "harmonics": [{"order": 2, "amplitude": 0.0}]}"#,
        r#", "damping": {"outer": 0.1, "inner": 0.05}"#,
    ));
    let own = parse(&unit(
        r#"{"amplitude": 1.0}"#,
        r#", "damping": {"outer": 0.1, "inner": 0.05}"#,
    ));
    assert!(matches!(zero, AnyScene::Structure(_)));
    assert!(matches!(own, AnyScene::Cells(_)));
    for omega in [1.3, 2.0, 3.0] {
        let (a, b) = (amplitudes(&zero, omega), amplitudes(&own, omega));
        for (x, y) in a.iter().zip(&b) {
            assert!(
                (x - y).abs() <= 1e-9 * y.abs(),
                "ω = {omega}: {a:?} against {b:?}"
            );
        }
    }
}

#[test]
fn a_base_harmonic_through_a_dashpot_is_the_force_it_exerts() {
    // `a cos(kωt + φ)` through `k_s` and `c` pushes with `a √(k_s² + (ckω)²) cos(kωt + φ + δ)`,
    // `δ = atan2(ckω, k_s)`: at one ω the base's harmonic and that force are the same forcing.
    let (k_s, c, a, phi, omega): (f64, f64, f64, f64, f64) = (1.0, 0.1, 0.2, 0.3, 1.4);
    let r = a * k_s.hypot(c * 2.0 * omega);
    let delta = (c * 2.0 * omega).atan2(k_s);
    let scene = |harmonics: &str| {
        format!(
            r#"{{"structure": {{
                  "bodies":   [{{"name": "x", "mass": 1.0}}],
                  "springs":  [{{"between": ["base", "x"], "stiffness": {k_s}}}],
                  "dashpots": [{{"between": ["base", "x"], "damping": {c}}}],
                  "stops":    [{{"between": ["frame", "x"], "gap_plus": 0.5, "restitution": 0.8}}]}},
                "forcing": {harmonics}}}"#
        )
    };
    let by_base = parse(&scene(&format!(
        r#"{{"base": {{"amplitude": 0.7, "harmonics": [{{"order": 2, "amplitude": {a}, "phase": {phi}}}]}}}}"#
    )));
    let by_force = parse(&scene(&format!(
        r#"{{"base": {{"amplitude": 0.7}},
             "forces": [{{"on": "x", "amplitude": 0.0,
                          "harmonics": [{{"order": 2, "amplitude": {r}, "phase": {}}}]}}]}}"#,
        phi + delta
    )));
    let (a, b) = (amplitudes(&by_base, omega), amplitudes(&by_force, omega));
    assert!((a[0] - b[0]).abs() <= 1e-12 * b[0], "{a:?} against {b:?}");
}

#[test]
fn the_motion_clear_of_the_stops_is_the_linear_response_summed_harmonic_by_harmonic() {
    // `m ẍ + c ẋ + k x = Σ F_k cos(kωt + φ_k)` in closed form: each order's response is
    // `F_k / (k − m(kω)² + i c kω)`, their sum's amplitude `max |x(t)|` found over the period.
    let (m, c, k, omega) = (1.0, 0.1, 1.0, 0.7);
    let forces = [(1, 0.5, 0.2), (2, 0.3, 0.5), (5, 0.2, -1.2)];
    let x = |t: f64| -> f64 {
        forces
            .iter()
            .map(|&(order, f, phase)| {
                let w = f64::from(order) * omega;
                let (re, im) = (k - m * w * w, c * w);
                let (gain, lag) = (f / re.hypot(im), im.atan2(re));
                gain * (w * t + phase - lag).cos()
            })
            .sum()
    };
    let period = TAU / omega;
    let samples = 20_000;
    let peak_at = (0..samples)
        .map(|i| period * f64::from(i) / f64::from(samples))
        .max_by(|a, b| x(*a).abs().total_cmp(&x(*b).abs()))
        .expect("samples");
    // Golden-section on |x| around the best sample.
    let (mut lo, mut hi) = (peak_at - period / 1e4, peak_at + period / 1e4);
    let g = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..200 {
        let (a, b) = (hi - g * (hi - lo), lo + g * (hi - lo));
        if x(a).abs() > x(b).abs() {
            hi = b;
        } else {
            lo = a;
        }
    }
    let exact = x(0.5 * (lo + hi)).abs();
    let harmonics: Vec<String> = forces[1..]
        .iter()
        .map(|(order, f, phase)| {
            format!(r#"{{"order": {order}, "amplitude": {f}, "phase": {phase}}}"#)
        })
        .collect();
    let scene = parse(&format!(
        r#"{{"structure": {{
              "bodies":   [{{"name": "x", "mass": {m}}}],
              "springs":  [{{"between": ["frame", "x"], "stiffness": {k}}}],
              "dashpots": [{{"between": ["frame", "x"], "damping": {c}}}],
              "stops":    [{{"between": ["frame", "x"], "gap": 100.0, "restitution": 0.8}}]}},
            "forcing": {{"forces": [{{"on": "x", "amplitude": {}, "phase": {},
                                      "harmonics": [{}]}}]}}}}"#,
        forces[0].1,
        forces[0].2,
        harmonics.join(", ")
    ));
    let simulated = amplitudes(&scene, omega)[0];
    assert!(
        (simulated - exact).abs() <= 1e-9 * exact,
        "simulated {simulated}, closed form {exact}"
    );
    let check = api::compare(&scene, omega, &SimulationOptions::default()).expect("runs");
    assert_eq!(check.class(), "agreement");
}

#[test]
fn harmonics_out_of_range_are_refused_naming_the_field() {
    let cases = [
        (
            r#"[{"order": 1, "amplitude": 0.1}]"#,
            "base.harmonics[0].order",
            "2..=16",
        ),
        (
            r#"[{"order": 17, "amplitude": 0.1}]"#,
            "base.harmonics[0].order",
            "2..=16",
        ),
        (
            r#"[{"order": 2, "amplitude": 0.1}, {"order": 2, "amplitude": 0.2}]"#,
            "base.harmonics[1].order",
            "repeated",
        ),
        (
            r#"[{"order": 2, "amplitude": 1e999}]"#,
            "base.harmonics[0].amplitude",
            "",
        ),
        (
            r#"[{"order": 2.5, "amplitude": 0.1}]"#,
            "base.harmonics[0].order",
            "",
        ),
        (
            r#"[{"order": 2, "amplitude": 0.1, "phse": 0.1}]"#,
            "base.harmonics[0]",
            "phse",
        ),
    ];
    for (harmonics, field, reason) in cases {
        let text = unit(
            &format!(r#"{{"amplitude": 1.0, "harmonics": {harmonics}}}"#),
            "",
        );
        let e = AnyScene::parse(&text, "test")
            .expect_err(harmonics)
            .to_string();
        assert!(e.contains(field) && e.contains(reason), "{harmonics}: {e}");
    }
    let text = r#"{"structure": {"bodies": [{"name": "x", "mass": 1.0}],
                                 "springs": [{"between": ["frame", "x"], "stiffness": 1.0}]},
                   "forcing": {"forces": [{"on": "x", "amplitude": 1.0,
                               "harmonics": [{"order": 0, "amplitude": 0.1}]}]}}"#;
    let e = AnyScene::parse(text, "test")
        .expect_err("order 0")
        .to_string();
    assert!(e.contains("forcing.forces[0].harmonics[0].order"), "{e}");
    // The unit's own road takes the fundamental alone, and says where a harmonic scene goes.
    let text = unit(
        r#"{"amplitude": 1.0, "harmonics": [{"order": 2, "amplitude": 0.1}]}"#,
        "",
    );
    let e = rattle_compare::scene::Scene::parse(&text, "test").expect_err("harmonics");
    assert!(matches!(e, SceneError::CellsHarmonics { .. }), "{e}");
    assert!(e.to_string().contains("structure form"), "{e}");
}

/// Each solver's own tangent flow gives the orbit's Floquet multipliers: the analytic one
/// differentiates its cycle equations, the simulator integrates its variational flow with
/// saltations. Both are polished to about `1e-12`; their multipliers agree to `1e-8` of the
/// largest (the simulator's Newton stops at its tolerance, the derivatives follow it).
const MULTIPLIERS: f64 = 1e-8;

#[test]
fn every_orbit_of_a_sequence_under_two_harmonics_is_the_simulators_periodic_orbit() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/paper-two-harmonics.json"
    ))
    .expect("the gallery scene");
    let AnyScene::Structure(form) = parse(&text) else {
        panic!("a unit with harmonics runs as a structure");
    };
    let s = &form.structure;
    let model = s.analytic_model().expect("an analytic model");
    let options = SimulationOptions::default();
    let mut checked = 0;
    for (signature, omega) in [("+-", 2.95), ("+-", 3.0), ("+-", 3.4), ("+-", 4.0)] {
        let sequence = s.sequence(signature, 1).expect("a sequence");
        let orbits = rattle_analytic::sequence_orbits(&model, omega, &sequence).expect("solves");
        assert!(orbits.iter().any(|o| o.viable), "{signature} at {omega}");
        let event = s.event_model(omega).expect("an event model");
        // A viable orbit is a motion of the structure (no penetration, no impact but its own):
        // the simulator's map has it as a fixed point, stable or not.
        for orbit in orbits.iter().filter(|o| o.viable) {
            // The state midway through the first flight, from the analytic orbit's own flow;
            // the simulator's Newton on its stroboscopic map starts there.
            let cycle = TAU / omega;
            let t = 0.5 * orbit.impact_phases.get(1).copied().unwrap_or(1.0) * cycle;
            let phases = rattle_analytic::phase_state(&model.forcing().orders(), orbit.alpha);
            let (mid, _) = model.transition(omega, t).apply(
                &nalgebra::DVector::from_column_slice(&orbit.state_after_impact),
                &nalgebra::DVector::from_vec(phases),
            );
            let start = rattle_event_driven::Start {
                state: mid.clone(),
                time: t + orbit.alpha / omega,
            };
            let found = rattle_event_driven::periodic_orbit(&event, omega, &start, 1, &options)
                .unwrap_or_else(|e| panic!("{signature} at {omega}: {e}"));
            let d = (&found.state - &mid).amax() / mid.amax();
            assert!(
                d <= BOTH_SOLVERS,
                "{signature} at {omega}: states differ by {d:e}"
            );
            let moduli = |m: &[nalgebra::Complex<f64>]| {
                let mut v: Vec<f64> = m.iter().map(|z| z.norm()).collect();
                v.sort_by(f64::total_cmp);
                v
            };
            let (a, b) = (
                moduli(&orbit.floquet_multipliers),
                moduli(&found.floquet_multipliers),
            );
            let largest = a.last().copied().unwrap_or(1.0).max(1.0);
            for (x, y) in a.iter().zip(&b) {
                assert!(
                    (x - y).abs() <= MULTIPLIERS * largest,
                    "{signature} at {omega}: multipliers {a:?} against {b:?}"
                );
            }
            checked += 1;
        }
    }
    assert!(checked >= 4, "{checked} orbits checked");
}
