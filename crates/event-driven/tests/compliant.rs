//! Compliant (Kelvin–Voigt) stops, each test model with its exact answer worked out here:
//! the isolated pair returns `−e` times its entry velocity after `π/ω_d`; the impact
//! oscillator's compliant orbit tends to the rigid one at the rate the contact's duration
//! sets; the Floquet multipliers are the stroboscopic map's derivative's; the forcing's work
//! over a cycle is what the dashpots dissipate; bad contact laws are refused by field.

use nalgebra::{DMatrix, DVector};
use rattle_event_driven::*;
use std::f64::consts::PI;

/// One mass `m` against a frame stop at `u = gap` (side 1; no stop on side 2), no spring, no
/// damping, no forcing.
fn isolated(m: f64, gap: f64) -> Model {
    Model::new(
        DMatrix::from_element(1, 1, m),
        DMatrix::zeros(1, 1),
        None,
        DVector::zeros(1),
        DVector::zeros(1),
        vec![ContactPair {
            plus_dof: Some(0),
            minus_dof: None,
            gap_plus: gap,
            gap_minus: f64::INFINITY,
            restitution: 1.0,
        }],
    )
    .unwrap()
}

/// The isolated pair's gap.
fn gap_of() -> f64 {
    1.0
}

/// The isolated pair's one contact: mass `m` starting at `u = 0` with velocity `v` towards
/// the stop at `gap`, run one period of `omega`.
fn isolated_contact(
    m: f64,
    law: Compliance,
    omega: f64,
    root_tolerance: f64,
) -> (ContactRecord, SteadyState) {
    let (gap, v) = (gap_of(), 1.0);
    let model = isolated(m, gap).with_compliance(0, law).unwrap();
    let options = SimulationOptions {
        fixed_periods: Some(1),
        max_period_multiplicity: 1,
        root_tolerance,
        ..SimulationOptions::default()
    };
    let start = Start {
        state: DVector::from_vec(vec![0.0, v]),
        time: 0.0,
    };
    let steady = simulate(&model, omega, &start, &options).unwrap();
    assert_eq!(steady.cycle_contacts.len(), 1, "one contact");
    (steady.cycle_contacts[0].clone(), steady)
}

/// The isolated pair: `ṙ⁺ = −e ṙ⁻`, `e = exp(−ζπ/√(1 − ζ²))`, after `π/ω_d`,
/// `ω_d = √(k_c/μ)√(1 − ζ²)`, for damping ratios from 0 to 0.95 and contact stiffnesses
/// from 1 to 1e8 times the reference stiffness 1 (a contact rate up to 7e3, 3.5e4 ω). The entry is at `t = 1`
/// (gap 1, speed 1), its time resolved to the root tolerance; the exit's velocity is a sum
/// of the flow's terms of the entry velocity's size, so it holds to rounding of that size
/// times the contact's condition, and the duration to the root tolerance of the period
/// (`1e-15 T` asked here), relative to the contact's duration.
#[test]
fn isolated_pair_restitution_and_duration() {
    let m = 2.0;
    // A period long enough for the softest, most damped contact (`π/ω_d ≈ 14` at ζ = 0.95).
    let omega = 0.2;
    let root_tolerance = 1e-15;
    let mut worst = (0.0f64, 0.0f64);
    for &stiffness in &[1.0, 1e4, 1e8] {
        for &zeta in &[0.0, 0.1, 0.5, 0.9, 0.95] {
            let law = Compliance {
                stiffness,
                damping: 2.0 * zeta * (stiffness * m).sqrt(),
            };
            let e = (-zeta * PI / (1.0f64 - zeta * zeta).sqrt()).exp();
            assert!((law.restitution(m) - e).abs() <= 1e-15);
            let (c, steady) = isolated_contact(m, law, omega, root_tolerance);
            assert!(steady.cycle_impacts.is_empty());
            let wd = (stiffness / m).sqrt() * (1.0 - zeta * zeta).sqrt();
            let duration = PI / wd;
            let velocity_error = (c.exit_velocity + e * c.entry_velocity).abs() / c.entry_velocity;
            let duration_error = ((c.exit_time - c.entry_time) - duration).abs() / duration;
            worst = (worst.0.max(velocity_error), worst.1.max(duration_error));
            eprintln!(
                "k_c {stiffness:e} ζ {zeta}: velocity {velocity_error:.2e}, duration \
                 {duration_error:.2e}, entry {:.3e}",
                (c.entry_time - 1.0).abs()
            );
            assert!((c.entry_velocity - 1.0).abs() <= 1e-14);
            assert!((c.entry_time - 1.0).abs() <= 1e-14);
            // The exit is where `δ = r − gap` returns to 0; `r` is a sum of size `gap`, known to
            // a few roundings `8ε gap`, and crosses at the exit speed `e v`: the exit time is
            // known to `8ε gap/(e v)` besides the time tolerance `root_tolerance T`, and the
            // duration to those and the entry's (speed `v`) and the times' own rounding.
            let eps = f64::EPSILON;
            let tolerance_time = root_tolerance * 2.0 * PI / omega;
            let exit_time_error = 8.0 * eps * gap_of() / (e * 1.0) + tolerance_time;
            let duration_tolerance =
                (exit_time_error + tolerance_time + 8.0 * eps * (gap_of() + c.exit_time))
                    / duration;
            // The exit speed moves at `|r̈| = c_c e v/μ = 2ζω_c e v` there: the exit time's
            // error times that, plus the rounding of the velocity's sum (`100ε` of `v`).
            let rate = (stiffness / m).sqrt();
            let velocity_tolerance = 100.0 * eps + 2.0 * zeta * rate * e * exit_time_error;
            assert!(
                velocity_error <= velocity_tolerance,
                "k_c {stiffness} ζ {zeta}: {velocity_error:e} > {velocity_tolerance:e}"
            );
            assert!(
                duration_error <= duration_tolerance,
                "k_c {stiffness} ζ {zeta}: {duration_error:e} > {duration_tolerance:e}"
            );
            // The largest penetration, undamped: v/ω_c.
            if zeta == 0.0 {
                let depth = 1.0 / (stiffness / m).sqrt();
                assert!((c.max_penetration - depth).abs() <= 1e-12 * depth);
            }
            let per_period = steady.contact_time_per_period;
            assert!((per_period - duration).abs() <= duration_tolerance * duration);
        }
    }
    eprintln!("worst: velocity {:.2e}, duration {:.2e}", worst.0, worst.1);
}

/// Bad contact laws are refused, each by its field.
#[test]
fn bad_compliance_is_refused_by_field() {
    let model = isolated(1.0, 1.0);
    let field = |r: Result<Model, ModelError>| match r {
        Err(ModelError::OutOfRange { field, .. }) => field,
        other => panic!("not refused: {other:?}"),
    };
    let law = |stiffness, damping| Compliance { stiffness, damping };
    assert_eq!(
        field(model.clone().with_compliance(1, law(1.0, 0.0))),
        "pair"
    );
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(
            field(model.clone().with_compliance(0, law(k, 0.0))),
            "compliance.stiffness"
        );
    }
    for c in [-1e-9, f64::NAN, f64::INFINITY] {
        assert_eq!(
            field(model.clone().with_compliance(0, law(1.0, c))),
            "compliance.damping"
        );
    }
    // The contact rate √(k_c/μ) at most 1e6 ω: k_c = 1e12 μ ω² passes, just above fails,
    // in the model's check and in every run.
    let omega = 1.0;
    let edge = model.clone().with_compliance(0, law(1e12, 0.0)).unwrap();
    assert_eq!(edge.check_compliance(omega), Ok(()));
    let stiff = model.with_compliance(0, law(1.0001e12, 0.0)).unwrap();
    let refused = stiff.check_compliance(omega).unwrap_err();
    assert!(
        matches!(&refused, ModelError::OutOfRange { field, .. } if field == "compliance[0].stiffness")
    );
    let run = simulate(
        &stiff,
        omega,
        &Start::rest(1),
        &SimulationOptions::default(),
    );
    assert_eq!(run.unwrap_err(), SimulationError::Model(refused));
    // The model reads its laws back; a rigid pair has none.
    assert_eq!(edge.compliance(0), Some(law(1e12, 0.0)));
    assert_eq!(isolated(1.0, 1.0).compliance(0), None);
}
