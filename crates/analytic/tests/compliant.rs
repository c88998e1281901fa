//! Orbits with compliant (Kelvin–Voigt) contact phases: the impact oscillator's compliant
//! orbit tends to its rigid orbit as the contact stiffens at matched restitution, at the rate
//! of the contact's duration; the energy balance closes with the contact dashpots; the
//! notation reads and prints; bad input is refused by field.

use nalgebra::{Complex, DMatrix, DVector};
use rattle_analytic::*;

/// The impact oscillator: one mass `m = 1` on a spring `k = 1` and dashpot `c = 0.1` to the
/// frame, driven by `cos ωt`, with one stop against the frame at `u = 1` (restitution `e`).
fn impact_oscillator(restitution: f64) -> LinearModel {
    driven_oscillator(restitution, 1.0)
}

/// [`impact_oscillator`] driven by `force · cos ωt`.
fn driven_oscillator(restitution: f64, force: f64) -> LinearModel {
    let one = |v: f64| DMatrix::from_element(1, 1, v);
    LinearModel::new(
        one(1.0),
        one(0.1),
        one(1.0),
        HarmonicForcing {
            cosine: DVector::from_element(1, force),
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

/// Largest distance from a multiplier of `a` to the nearest of `b`, both ways.
fn multiplier_distance(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    let one_way = |a: &[Complex<f64>], b: &[Complex<f64>]| {
        a.iter()
            .map(|x| {
                b.iter()
                    .map(|y| (x - y).norm())
                    .fold(f64::INFINITY, f64::min)
            })
            .fold(0.0, f64::max)
    };
    one_way(a, b).max(one_way(b, a))
}

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The compliant stop's contact frequency over the structure's fastest rate (the bound
/// `½(c + √(c² + 4k))` of [`MAX_CONTACT_FREQUENCY_RATIO`]'s): `√k_c / 1.0512…`.
fn frequency_ratio(stiffness: f64) -> f64 {
    let structure = 0.5 * (0.1 + (0.01f64 + 4.0).sqrt());
    stiffness.sqrt() / structure
}

/// As the stop stiffens at matched restitution the compliant orbit tends to the rigid one.
/// During a contact of duration `τ_c = π/ω_d ∝ k_c^{-1/2}` the spring, dashpot and forcing of
/// the structure act on the mass, which a rigid impact does not let them do: the orbit moves
/// at first order in `τ_c`, so its distance from the rigid orbit falls like `k_c^{-1/2}`, and
/// the next order (`τ_c²`) makes the slope per decade of `k_c` `−½ + O(k_c^{-1/2})`, its
/// deviation from `−½` shrinking by `√10` per decade. Asserted from `k_c = 1e4` (the contact
/// 1 % of the structure's period) to `1e8`: the slope of the base phase's error within `0.01`
/// of `−½` on every decade and its deviation shrinking by a factor in `[2.5, 4]` (`√10 ≈ 3.16`)
/// from decade to decade; the exit velocity's deviation from `−e` times the entry's (exact
/// for an isolated pair) falls at the same rate. Each orbit balances its energy to the
/// rounding of a stiff contact's velocities, `ε ω_c/ω_s` of the motion's energy (the
/// velocities are `ω_c` times the penetration, the balanced flow's states rounded to `ε` of
/// the gap), with a factor 8 for the sums.
#[test]
fn compliant_orbit_tends_to_the_rigid_orbit() {
    let rigid = rigid_orbit();
    let rigid_velocity = rigid.states_before_impacts[0][1];
    let stiffnesses = [1e4, 1e5, 1e6, 1e7, 1e8];
    let mut alpha_errors = Vec::new();
    let mut exit_errors = Vec::new();
    let mut multiplier_errors = Vec::new();
    for &k in &stiffnesses {
        let orbit = compliant_orbit(k);
        assert_eq!(orbit.contacts.len(), 1);
        let contact = orbit.contacts[0];
        let alpha = wrap(orbit.alpha - rigid.alpha).abs();
        let velocity = (contact.entry_velocity - rigid_velocity).abs();
        let exit = (contact.exit_velocity + RESTITUTION * contact.entry_velocity).abs();
        println!(
            "k_c = {k:e}: alpha error {alpha:e}, entry velocity error {velocity:e}, exit \
             identity error {exit:e}, duration {:e}, penetration {:e}, energy residual {:e}, \
             multipliers {:?} (rigid {:?})",
            contact.duration,
            contact.max_penetration,
            orbit.energy_residual,
            orbit.floquet_multipliers,
            rigid.floquet_multipliers
        );
        let rounding = 8.0 * f64::EPSILON * frequency_ratio(k).max(1.0);
        assert!(
            orbit.energy_residual <= rounding,
            "k_c = {k:e}: energy residual {:e} above {rounding:e}",
            orbit.energy_residual
        );
        assert!(orbit.energy.contact_dissipation > 0.0);
        assert!(orbit.stable, "k_c = {k:e}: the rigid orbit is stable");
        alpha_errors.push(alpha);
        exit_errors.push(exit);
        multiplier_errors.push(multiplier_distance(
            &orbit.floquet_multipliers,
            &rigid.floquet_multipliers,
        ));
    }
    let slopes = |errors: &[f64]| -> Vec<f64> {
        (0..errors.len() - 1)
            .map(|w| (errors[w + 1] / errors[w]).log10())
            .collect()
    };
    let alpha_slopes = slopes(&alpha_errors);
    let exit_slopes = slopes(&exit_errors);
    let multiplier_slopes = slopes(&multiplier_errors);
    println!(
        "slopes per decade: alpha {alpha_slopes:?}, exit {exit_slopes:?}, multipliers \
         {multiplier_slopes:?}"
    );
    for (w, slope) in alpha_slopes.iter().enumerate() {
        assert!(
            (slope + 0.5).abs() <= 0.01,
            "alpha slope {slope} on decade {w}"
        );
        assert!(
            (exit_slopes[w] + 0.5).abs() <= 0.01,
            "exit slope on decade {w}"
        );
        assert!(
            (multiplier_slopes[w] + 0.5).abs() <= 0.01,
            "multiplier slope on decade {w}"
        );
    }
    for w in 0..alpha_slopes.len() - 1 {
        let shrink = (alpha_slopes[w] + 0.5) / (alpha_slopes[w + 1] + 0.5);
        assert!(
            (2.5..=4.0).contains(&shrink),
            "deviation shrinks by {shrink}"
        );
    }
}

/// A contact phase reads and prints as `<pair><side>c`; the canonical rotation puts pair 0's
/// first; a sequence must use contact phases on compliant pairs and impacts on rigid ones.
#[test]
fn contact_phases_read_print_and_match_the_contact_law() {
    let sequence = ImpactSequence::parse("1- 0+c 0-c", 1).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sequence.to_string(), "0+c 0-c 1-");
    assert_eq!(sequence.impacts()[0], PairImpact::compliant(0, 1));
    assert_eq!(sequence.impacts()[2], PairImpact::rigid(1, -1));
    assert!(sequence.has_contact_phases());
    let again = ImpactSequence::parse(&sequence.to_string(), 1).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(again, sequence);
    assert!(
        ImpactSequence::parse("+c", 1).is_err(),
        "a contact phase names its pair"
    );
    for bad in ["0c+", "0+cc", "0+ 1c", "0+C"] {
        assert!(
            matches!(
                ImpactSequence::parse(bad, 1),
                Err(SequenceError::BadToken { .. })
            ),
            "{bad} is refused"
        );
    }
    let rigid = impact_oscillator(RESTITUTION);
    let compliant = compliant_oscillator(1e4);
    let contact = ImpactSequence::parse("0+c", 1).unwrap_or_else(|e| panic!("{e}"));
    let impact = ImpactSequence::parse("0+", 1).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(
        contact.check(&rigid),
        Err(SequenceError::ContactOnRigid { pair: 0 })
    );
    assert_eq!(
        impact.check(&compliant),
        Err(SequenceError::ImpactOnCompliant { pair: 0 })
    );
    assert_eq!(contact.check(&compliant), Ok(()));
    assert!(matches!(
        solve_sequence(&compliant, OMEGA, &impact, &[0.0]),
        Err(SequenceOrbitError::Sequence(
            SequenceError::ImpactOnCompliant { pair: 0 }
        ))
    ));
    assert!(matches!(
        sequence_orbits(&rigid, OMEGA, &contact),
        Err(SequenceOrbitError::Sequence(
            SequenceError::ContactOnRigid { pair: 0 }
        ))
    ));
    // A contact phase is two events: the guess has an entry and an exit.
    assert!(matches!(
        solve_sequence(&compliant, OMEGA, &contact, &[0.0]),
        Err(SequenceOrbitError::InvalidGuess { impacts: 2, len: 1 })
    ));
}

/// `with_compliance` refuses a pair the model lacks, a stiffness not finite and `> 0` or so
/// stiff that the contact frequency exceeds [`MAX_CONTACT_FREQUENCY_RATIO`] times the
/// structure's fastest rate, and a damping not finite and `≥ 0`, each naming its field; the
/// reader gives back the law.
#[test]
fn bad_contact_laws_are_refused_by_field() {
    let model = impact_oscillator(RESTITUTION);
    let field_of = |pair: usize, stiffness: f64, damping: f64| match model
        .clone()
        .with_compliance(pair, Compliance { stiffness, damping })
    {
        Err(ModelError::OutOfRange { field, .. }) => field,
        other => panic!("k_c = {stiffness}, c_c = {damping}: {other:?}"),
    };
    assert_eq!(field_of(1, 1e4, 1.0), "compliances[1]");
    for k in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert_eq!(field_of(0, k, 1.0), "compliances[0].stiffness");
    }
    for c in [-1e-3, f64::NAN, f64::INFINITY] {
        assert_eq!(field_of(0, 1e4, c), "compliances[0].damping");
    }
    // The structure's rate is `½(0.1 + √4.01) ≈ 1.0512`: the bound is `k_c ≈ 1.105e12`.
    let limit = (MAX_CONTACT_FREQUENCY_RATIO * frequency_ratio(1.0).recip()).powi(2);
    assert_eq!(field_of(0, 1.01 * limit, 1.0), "compliances[0].stiffness");
    let law = Compliance {
        stiffness: 0.99 * limit,
        damping: 0.0,
    };
    let stiff = model
        .clone()
        .with_compliance(0, law)
        .unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(stiff.compliance(0), Some(law));
    assert_eq!(model.compliance(0), None);
    assert_eq!(stiff.compliance(1), None);
}

/// Continuation follows rigid impacts only: an orbit with contact phases is refused, not
/// continued with a rigid cycle's events.
#[test]
fn contact_phases_are_not_continued() {
    let orbit = compliant_orbit(1e4);
    let model = compliant_oscillator(1e4);
    let settings = ContinuationSettings::new(0.5, 1.0);
    assert!(matches!(
        continue_sequence(&model, &orbit, &settings),
        Err(ContinuationError::Sequence(SequenceError::ContinuedContact))
    ));
}

/// The impact oscillator with a stop of restitution 0, driven by `2 cos θ`: a sticking phase
/// (`0+s`) holds the mass on its stop (`u = 1`, `u̇ = 0`) while the force exceeds the spring's,
/// `2 cos θ > k · 1`, and releases it where they balance with the force falling: at
/// `θ = π/3` exactly (mod 2π). Asserted to `1e-12` rad on every orbit found; the held state is
/// `(1, 0)` at the release, the orbit balances its energy (the landing loses `½ṙ²`, the stop
/// does no work while the mass is at rest), and its Floquet multipliers are exactly 0: the
/// landing forgets the velocity, the stop the position, and the release depends on the phase
/// alone.
#[test]
fn sticking_phase_releases_where_the_force_balances_the_spring() {
    let model = driven_oscillator(0.0, 2.0);
    let sequence = ImpactSequence::parse("0+s", 1).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(sequence.to_string(), "0+s");
    let found = sequence_orbits(&model, OMEGA, &sequence).unwrap_or_else(|e| panic!("{e}"));
    let viable: Vec<&SequenceOrbit> = found.iter().filter(|o| o.viable).collect();
    assert!(!viable.is_empty(), "a viable sticking orbit: {found:?}");
    let cycle = std::f64::consts::TAU / OMEGA;
    for orbit in viable {
        let stick = orbit.contacts[0];
        assert_eq!(stick.kind, ImpactKind::Stick);
        let release = orbit.impact_phases[1];
        let theta = wrap(orbit.alpha + OMEGA * release * cycle);
        let error = (theta - std::f64::consts::FRAC_PI_3).abs();
        println!(
            "alpha {}, release at theta = {theta} (error {error:e}), held {:e} of the cycle, \
             landing at {}, energy residual {:e}, multipliers {:?}",
            orbit.alpha,
            stick.duration / cycle,
            stick.entry_velocity,
            orbit.energy_residual,
            orbit.floquet_multipliers
        );
        assert!(error <= 1e-12, "release phase error {error:e}");
        let held = &orbit.states_before_impacts[1];
        assert!(
            (held[0] - 1.0).abs() <= 1e-12 && held[1].abs() <= 1e-12,
            "{held:?}"
        );
        // The landing takes the velocity to zero and the held flow keeps the mass at rest:
        // every perturbation is forgotten, the multipliers are 0.
        for mu in &orbit.floquet_multipliers {
            assert!(mu.norm() <= 1e-12, "multiplier {mu}");
        }
        assert!(orbit.energy_residual <= 1e-12);
        assert!(stick.entry_velocity > 0.0 && stick.duration > 0.0);
    }
    // Only a rigid pair of restitution 0 sticks.
    assert_eq!(
        sequence.check(&impact_oscillator(RESTITUTION)),
        Err(SequenceError::StickWithRebound { pair: 0 })
    );
    assert_eq!(
        sequence.check(&compliant_oscillator(1e4)),
        Err(SequenceError::StickWithRebound { pair: 0 })
    );
}
