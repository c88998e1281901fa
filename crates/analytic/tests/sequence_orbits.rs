//! Orbits of any impact sequence on a general linear model: on the unit they must be the
//! fixed-size solvers' orbits (symmetric `+-`, `++--` from `solve_signature`, the whole
//! multi-start list); on a 2-cell chain an orbit must satisfy its own equations when stepped
//! independently with the model's flow and impact map, balance its energy and obey Liouville's
//! formula; a deliberate extra contact is reported as `extra_impact`; bad input is refused.

use nalgebra::{Complex, DVector};
use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::*;

/// Agreement asked of two exact solvers of the same orbit (the 1e-12).
const AGREEMENT: f64 = 1e-12;

/// Agreement asked of two computations of the Floquet multipliers (the 1e-8): the
/// eigenvalues of a non-normal monodromy are less well conditioned than the orbit itself.
const MULTIPLIER_AGREEMENT: f64 = 1e-8;

/// Offset of the Newton guess from a known orbit, in radians of `α` and in fractions of the
/// cycle: well outside rounding, well inside the basin.
const PERTURBATION: f64 = 1e-3;

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
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

fn max_difference(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn plus_minus() -> ImpactSequence {
    ImpactSequence::from_signature(&Signature::parse("+-", 1).unwrap())
}

#[test]
fn plus_minus_on_the_unit_is_the_symmetric_orbit() {
    let stops = paper_stops();
    let sequence = plus_minus();
    let mut compared = 0;
    for unit in [paper_unit(), damped_paper_unit()] {
        let model = LinearModel::unit(&unit, &stops).unwrap();
        for omega in [0.8, 1.2, 2.0, 2.6, 3.3] {
            for o in symmetric_orbits(&unit, &stops, omega).unwrap() {
                let guess = [o.alpha + PERTURBATION, 0.5 - PERTURBATION];
                let g = solve_sequence(&model, omega, &sequence, &guess)
                    .unwrap_or_else(|e| panic!("ω = {omega}: {e}"));
                let scale = o.state_after_impact.amax().max(1.0);
                let checks = [
                    ("alpha", wrap(g.alpha - o.alpha).abs()),
                    ("beta", (g.impact_phases[1] - 0.5).abs()),
                    (
                        "after",
                        max_difference(&g.state_after_impact, o.state_after_impact.as_slice())
                            / scale,
                    ),
                    (
                        "before side 2",
                        max_difference(
                            &g.states_before_impacts[1],
                            o.state_before_side2.as_slice(),
                        ) / scale,
                    ),
                    (
                        "amplitude",
                        (g.outer_amplitude - o.outer_amplitude).abs() / o.outer_amplitude,
                    ),
                    // dB: 20/ln 10 ≈ 8.7 dB per unit of relative amplitude.
                    (
                        "transmittance",
                        (g.transmittance_db - o.transmittance_db).abs()
                            / (20.0 / std::f64::consts::LN_10),
                    ),
                ];
                for (name, d) in checks {
                    assert!(
                        d <= AGREEMENT,
                        "ω = {omega}, α = {}: {name} differs by {d:e}",
                        o.alpha
                    );
                }
                let d = multiplier_distance(&g.floquet_multipliers, &o.floquet_multipliers);
                assert!(d <= MULTIPLIER_AGREEMENT, "ω = {omega}: multipliers {d:e}");
                assert_eq!((g.viable, g.stable), (o.viable, o.stable), "ω = {omega}");
                assert!(g.newton_iterations > 0);
                compared += 1;
            }
        }
    }
    assert!(compared >= 12, "only {compared} symmetric orbits compared");
}

/// `g` (general path) and `f` (fixed-size path) are the same orbit of the unit.
fn assert_same_orbit(g: &SequenceOrbit, f: &SignatureOrbit, context: &str) {
    let scale = f.state_after_impact.amax().max(1.0);
    let checks = [
        ("alpha", wrap(g.alpha - f.alpha).abs()),
        ("phases", max_difference(&g.impact_phases, &f.impact_phases)),
        (
            "after",
            max_difference(&g.state_after_impact, f.state_after_impact.as_slice()) / scale,
        ),
        (
            "amplitude",
            (g.outer_amplitude - f.outer_amplitude).abs() / f.outer_amplitude,
        ),
    ];
    for (name, d) in checks {
        assert!(d <= AGREEMENT, "{context}: {name} differs by {d:e}");
    }
    for (b, c) in g.states_before_impacts.iter().zip(&f.states_before_impacts) {
        let d = max_difference(b, c.as_slice()) / scale;
        assert!(d <= AGREEMENT, "{context}: state before an impact {d:e}");
    }
    let d = multiplier_distance(&g.floquet_multipliers, &f.floquet_multipliers);
    assert!(d <= MULTIPLIER_AGREEMENT, "{context}: multipliers {d:e}");
    assert_eq!(
        (g.viable, g.stable),
        (f.viable, f.stable),
        "{context}: verdicts"
    );
    // The same violations, kind by kind and side by side, on pair 0.
    let kinds = |v: &[Violation]| {
        let mut k: Vec<(u8, u8)> = v
            .iter()
            .map(|v| match v {
                Violation::Penetration { side, .. } => (0, side.number()),
                Violation::WrongApproach { side, .. } => (1, side.number()),
                Violation::ExtraImpact { side, .. } => (2, side.number()),
            })
            .collect();
        k.sort_unstable();
        k
    };
    let general: Vec<(u8, u8)> = {
        let mut k: Vec<(u8, u8)> = g
            .violations
            .iter()
            .map(|v| match *v {
                SequenceViolation::Penetration { pair, side, .. } => {
                    assert_eq!(pair, 0);
                    (0, side)
                }
                SequenceViolation::WrongApproach { pair, side, .. } => {
                    assert_eq!(pair, 0);
                    (1, side)
                }
                SequenceViolation::ExtraImpact { pair, side, .. } => {
                    assert_eq!(pair, 0);
                    (2, side)
                }
            })
            .collect();
        k.sort_unstable();
        k
    };
    assert_eq!(general, kinds(&f.violations), "{context}: violations");
    assert!(
        g.energy_residual <= 1e-10,
        "{context}: energy {:e}",
        g.energy_residual
    );
    // The same balance (one set of energy forms, each path on its own flights): every term
    // equal to the rounding of the motion's energy.
    let (m, u) = (&g.energy, &f.energy);
    let scale = m
        .forcing_work
        .abs()
        .max(m.dashpot_dissipation)
        .max(m.impact_losses)
        .max(ENERGY_EXCHANGE_FRACTION * m.exchange_bound);
    for (name, a, b) in [
        ("work", m.forcing_work, u.forcing_work),
        ("dissipation", m.dashpot_dissipation, u.dashpot_dissipation),
        ("impact losses", m.impact_losses, u.impact_losses),
        ("exchange bound", m.exchange_bound, u.exchange_bound),
    ] {
        let differ = (a - b).abs() / scale;
        assert!(differ <= 1e-10, "{context}: {name} differ by {differ:e}");
    }
}

#[test]
fn plus_plus_minus_minus_on_the_unit_is_solve_signatures_orbit() {
    let stops = paper_stops();
    let signature = Signature::parse("++--", 1).unwrap();
    let sequence = ImpactSequence::from_signature(&signature);
    let mut compared = 0;
    for unit in [paper_unit(), damped_paper_unit()] {
        let model = LinearModel::unit(&unit, &stops).unwrap();
        for omega in [1.3, 1.5, 1.8] {
            for f in signature_orbits(&unit, &stops, omega, &signature) {
                let mut guess = f.impact_phases.clone();
                guess[0] = f.alpha + PERTURBATION;
                for phase in &mut guess[1..] {
                    *phase -= PERTURBATION * 1e-2;
                }
                let fixed = solve_signature(&unit, &stops, omega, &signature, &guess)
                    .unwrap_or_else(|e| panic!("fixed, ω = {omega}: {e}"));
                let general = solve_sequence(&model, omega, &sequence, &guess)
                    .unwrap_or_else(|e| panic!("general, ω = {omega}: {e}"));
                assert_same_orbit(&general, &fixed, &format!("++-- at ω = {omega}"));
                compared += 1;
            }
        }
    }
    assert!(compared >= 4, "only {compared} ++-- orbits compared");
}

#[test]
fn unit_multi_start_equals_the_fixed_size_multi_start() {
    let stops = paper_stops();
    for (unit, name) in [(paper_unit(), "undamped"), (damped_paper_unit(), "damped")] {
        let model = LinearModel::unit(&unit, &stops).unwrap();
        for omega in [1.2, 2.0, 2.6, 3.3] {
            let signature = Signature::parse("+-", 1).unwrap();
            let fixed = signature_orbits(&unit, &stops, omega, &signature);
            let general = sequence_orbits(&model, omega, &plus_minus()).unwrap();
            assert_eq!(
                general.len(),
                fixed.len(),
                "{name} ω = {omega}: number of orbits"
            );
            assert!(!fixed.is_empty(), "{name} ω = {omega}: no orbit to compare");
            for (g, f) in general.iter().zip(&fixed) {
                assert_same_orbit(g, f, &format!("{name} +- at ω = {omega}"));
            }
        }
    }
}

/// The damped paper cell twice in series.
fn two_cells() -> LinearModel {
    LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2).unwrap()
}

/// Each pair `+-` in the order pair 0 on side 1, pair 1 on side 2, pair 0 on side 2, pair 1
/// on side 1: at `ω = 3.3` the multi-start finds viable orbits of this sequence on the damped
/// 2-cell chain (the test searches for them rather than storing them).
const CHAIN_SEQUENCE: &str = "0+ 1- 0- 1+";
const CHAIN_OMEGA: f64 = 3.3;

fn x_of(u: &[f64]) -> DVector<f64> {
    DVector::from_column_slice(u)
}

/// Steps the orbit flight by flight with the model's own transition and impact map (not the
/// solver's products), checking each contact, each stored state and periodicity; returns the
/// largest defect relative to the motion's size.
fn own_equations_defect(model: &LinearModel, o: &SequenceOrbit) -> f64 {
    let impacts = o.sequence.impacts();
    let m = impacts.len();
    let n = model.dofs();
    let cycle = f64::from(o.period) * std::f64::consts::TAU / o.omega;
    let scale = o
        .state_after_impact
        .iter()
        .fold(1.0, |a: f64, v| a.max(v.abs()));
    let mut x = x_of(&o.state_after_impact);
    let mut p = DVector::from_vec(vec![o.alpha.cos(), o.alpha.sin()]);
    let mut defect: f64 = 0.0;
    for j in 0..m {
        let end = if j + 1 < m {
            o.impact_phases[j + 1]
        } else {
            1.0
        };
        let flight = model.transition(o.omega, (end - o.impact_phases[j]) * cycle);
        let (x1, p1) = flight.apply(&x, &p);
        let next = impacts[(j + 1) % m];
        let pair = &model.pairs()[next.pair];
        let stop = if next.side == 1 {
            pair.gap_side1
        } else {
            -pair.gap_side2
        };
        let r = pair.direction.dot(&x1.rows(0, n));
        defect = defect.max((r - stop).abs() / scale);
        defect = defect.max((&x1 - x_of(&o.states_before_impacts[(j + 1) % m])).amax() / scale);
        // Restitution along the pair: ṙ⁺ = −e ṙ⁻.
        let after = model.impact_state(next.pair, &x1);
        let rdot = |x: &DVector<f64>| pair.direction.dot(&x.rows(n, n));
        defect = defect.max((rdot(&after) + pair.restitution * rdot(&x1)).abs() / scale);
        x = after;
        p = p1;
    }
    defect = defect.max((&x - x_of(&o.state_after_impact)).amax() / scale);
    defect.max((p - DVector::from_vec(vec![o.alpha.cos(), o.alpha.sin()])).amax())
}

#[test]
fn two_cell_chain_orbit_satisfies_its_own_equations() {
    let model = two_cells();
    let sequence = ImpactSequence::parse(CHAIN_SEQUENCE, 1).unwrap();
    assert_eq!(sequence.to_string(), CHAIN_SEQUENCE);
    let orbits = sequence_orbits(&model, CHAIN_OMEGA, &sequence).unwrap();
    let viable: Vec<&SequenceOrbit> = orbits.iter().filter(|o| o.viable).collect();
    assert!(!viable.is_empty(), "no viable orbit of {CHAIN_SEQUENCE}");
    // tr A = −tr(M⁻¹C) = −(0.25/2 + 0.05 + 0.15/2 + 0.05) = −0.3 by hand; det S = e² each.
    let trace = -0.3;
    let e: f64 = 0.8;
    for o in &orbits {
        let context = format!("α = {}", o.alpha);
        let defect = own_equations_defect(&model, o);
        assert!(defect <= AGREEMENT, "{context}: own equations {defect:e}");
        assert!(
            o.energy_residual <= 1e-10,
            "{context}: {:e}",
            o.energy_residual
        );
        let cycle = std::f64::consts::TAU / o.omega;
        let liouville = e.powi(2 * 4) * (trace * cycle).exp();
        let det = o.monodromy.determinant();
        assert!(
            (det - liouville).abs() <= 1e-10 * liouville,
            "{context}: det {det:e} vs {liouville:e}"
        );
        let product: Complex<f64> = o.floquet_multipliers.iter().product();
        assert!((product.re - liouville).abs() <= 1e-10 * liouville && product.im.abs() < 1e-12);
        assert_eq!(o.pair_signatures.len(), 2);
        for s in &o.pair_signatures {
            assert_eq!(s.as_ref().map(ToString::to_string).as_deref(), Some("+-"));
        }
        assert_eq!(o.cell_outer_amplitudes.len(), 2);
        assert_eq!(o.outer_amplitude, o.cell_outer_amplitudes[1]);
        assert_eq!(o.outer_amplitude, o.amplitudes[2]);
        assert_eq!(o.cell_outer_amplitudes[0], o.amplitudes[0]);
    }
    // Distinct orbits only.
    for (i, a) in orbits.iter().enumerate() {
        for b in &orbits[i + 1..] {
            let d = wrap(a.alpha - b.alpha)
                .abs()
                .max(max_difference(&a.impact_phases, &b.impact_phases));
            assert!(d > 1e-8, "duplicate orbits at α = {}", a.alpha);
        }
    }
}

/// Samples the viable chain orbit densely with the model's own transition: every pair stays
/// within its stops, and the amplitudes from rigorous extrema bound every sample and are
/// approached by them.
#[test]
fn two_cell_chain_viability_and_amplitudes_hold_between_samples() {
    let model = two_cells();
    let sequence = ImpactSequence::parse(CHAIN_SEQUENCE, 1).unwrap();
    let orbits = sequence_orbits(&model, CHAIN_OMEGA, &sequence).unwrap();
    let o = orbits.iter().find(|o| o.viable).expect("a viable orbit");
    let n = model.dofs();
    let m = o.impact_phases.len();
    let cycle = std::f64::consts::TAU / o.omega;
    let mut sampled = vec![0.0f64; n];
    let p0 = DVector::from_vec(vec![o.alpha.cos(), o.alpha.sin()]);
    for j in 0..m {
        let end = if j + 1 < m {
            o.impact_phases[j + 1]
        } else {
            1.0
        };
        let t0 = o.impact_phases[j] * cycle;
        let duration = (end - o.impact_phases[j]) * cycle;
        let before = x_of(&o.states_before_impacts[j]);
        let after = model.impact_state(o.sequence.impacts()[j].pair, &before);
        let (_, pj) = model
            .transition(o.omega, t0)
            .apply(&DVector::zeros(2 * n), &p0);
        let samples = 400;
        for k in 0..=samples {
            let t = duration * k as f64 / samples as f64;
            let (x, _) = model.transition(o.omega, t).apply(&after, &pj);
            for (q, pair) in model.pairs().iter().enumerate() {
                let r = pair.direction.dot(&x.rows(0, n));
                assert!(
                    r <= pair.gap_side1 * (1.0 + 1e-9) && r >= -pair.gap_side2 * (1.0 + 1e-9),
                    "pair {q} at r = {r}"
                );
            }
            for (s, v) in sampled.iter_mut().zip(x.rows(0, n).iter()) {
                *s = s.max(v.abs());
            }
        }
    }
    for (k, (amplitude, sample)) in o.amplitudes.iter().zip(&sampled).enumerate() {
        assert!(
            *amplitude >= sample - 1e-13 && amplitude - sample < 1e-3,
            "coordinate {k}: {amplitude} vs sampled {sample}"
        );
    }
}

/// The unit's viable `+-` orbit at `ω = 3.3` on a model with a second pair along the same
/// coordinate with gaps 0.3: the second pair does not enter the dynamics (it is not in the
/// sequence), so the orbit is the unit's, and `r` reaches `±0.5` at the impacts, `0.2` beyond
/// the second pair's stops on both sides: two `extra_impact`s on pair 1, excess exactly 0.2.
#[test]
fn a_contact_outside_the_sequence_is_an_extra_impact() {
    let unit = damped_paper_unit();
    let stops = paper_stops();
    let plain = LinearModel::unit(&unit, &stops).unwrap();
    let inner = ContactPair {
        gap_side1: 0.3,
        gap_side2: 0.3,
        ..plain.pairs()[0].clone()
    };
    let model = LinearModel::new(
        plain.mass().clone(),
        plain.damping().clone(),
        plain.stiffness().clone(),
        plain.forcing().clone(),
        vec![plain.pairs()[0].clone(), inner],
    )
    .unwrap();
    let omega = 3.3;
    let reference = symmetric_orbits(&unit, &stops, omega)
        .unwrap()
        .into_iter()
        .find(|o| o.viable)
        .expect("the unit's viable +- orbit at ω = 3.3");
    let o = solve_sequence(
        &model,
        omega,
        &plus_minus(),
        &[reference.alpha + PERTURBATION, 0.5],
    )
    .unwrap();
    assert!(
        (o.outer_amplitude - reference.outer_amplitude).abs()
            <= AGREEMENT * reference.outer_amplitude
    );
    assert!(!o.viable);
    let mut sides = Vec::new();
    for v in &o.violations {
        match *v {
            SequenceViolation::ExtraImpact {
                pair, side, excess, ..
            } => {
                assert_eq!(pair, 1, "{v:?}");
                assert!((excess - 0.2).abs() <= AGREEMENT, "{v:?}");
                sides.push(side);
            }
            _ => panic!("unexpected violation {v:?}"),
        }
    }
    sides.sort_unstable();
    sides.dedup();
    assert_eq!(sides, vec![1, 2]);
    let json = serde_json::to_value(&o).unwrap();
    assert_eq!(json["violations"][0]["kind"], "extra_impact");
    assert_eq!(json["violations"][0]["pair"], 1);
}

#[test]
fn bad_input_is_refused_with_errors() {
    let model = two_cells();
    let omega = 3.0;
    // A pair the model lacks.
    let sequence = ImpactSequence::parse("0+ 2-", 1).unwrap();
    let error = solve_sequence(&model, omega, &sequence, &[0.0, 0.5]).unwrap_err();
    assert_eq!(
        error,
        SequenceOrbitError::Sequence(SequenceError::Pair { pair: 2, pairs: 2 })
    );
    assert!(error.to_string().contains("pair 2"), "{error}");
    assert!(sequence_orbits(&model, omega, &sequence).is_err());
    // Sequences that are not sequences never get that far.
    assert!(ImpactSequence::parse("", 1).is_err());
    assert!(ImpactSequence::parse("0+ 1x", 1).is_err());
    assert!(ImpactSequence::parse("0+ 1-", 0).is_err());
    // Frequencies and guesses.
    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let e = solve_sequence(&model, bad, &sequence, &[0.0, 0.2, 0.5, 0.7]).unwrap_err();
        assert!(
            matches!(e, SequenceOrbitError::InvalidFrequency { .. })
                && e.to_string().contains("omega"),
            "{bad}: {e}"
        );
    }
    for guess in [
        vec![0.0, 0.2, 0.5],
        vec![0.0, 0.5, 0.2, 0.7],
        vec![0.0, 0.2, 0.5, 1.0],
        vec![f64::NAN, 0.2, 0.5, 0.7],
    ] {
        let e = solve_sequence(&model, omega, &sequence, &guess).unwrap_err();
        assert!(
            matches!(e, SequenceOrbitError::InvalidGuess { impacts: 4, .. }),
            "{guess:?}: {e}"
        );
    }
}

#[test]
fn orbit_serialises_with_the_units_field_names() {
    let model = two_cells();
    let sequence = ImpactSequence::parse(CHAIN_SEQUENCE, 1).unwrap();
    let orbits = sequence_orbits(&model, CHAIN_OMEGA, &sequence).unwrap();
    let json = serde_json::to_value(&orbits[0]).unwrap();
    for key in [
        "sequence",
        "pair_signatures",
        "period",
        "impact_phases",
        "alpha",
        "state_after_impact",
        "outer_amplitude",
        "cell_outer_amplitudes",
        "transmittance_db",
        "viable",
        "violations",
        "floquet_multipliers",
        "stable",
        "energy_residual",
    ] {
        assert!(json.get(key).is_some(), "missing {key}");
    }
    assert_eq!(json["sequence"], CHAIN_SEQUENCE);
    assert_eq!(json["pair_signatures"][1], "+-");
    assert_eq!(json["floquet_multipliers"].as_array().unwrap().len(), 8);
    assert!(json.get("monodromy").is_none());
}

/// Other signatures of the unit, searched on the same grid by both paths: the same orbits.
/// A coarse explicit grid (12 intervals) keeps the four-impact searches short; the default
/// grids agree too (checked by hand: `++--` at `ω = 1.5`, 7 orbits each, `+-+-` over 2
/// periods, 61 and 53 orbits, undamped and damped).
#[test]
fn other_signatures_of_the_unit_equal_the_fixed_size_search() {
    let stops = paper_stops();
    let mut compared = 0;
    for (unit, name) in [(paper_unit(), "undamped"), (damped_paper_unit(), "damped")] {
        let model = LinearModel::unit(&unit, &stops).unwrap();
        for (text, period, omega, grid) in [
            ("+", 1, 2.0, None),
            ("+", 2, 1.0, None),
            ("++--", 1, 1.5, Some(12)),
            ("+-+-", 2, 1.5, Some(12)),
        ] {
            let signature = Signature::parse(text, period).unwrap();
            let sequence = ImpactSequence::from_signature(&signature);
            let (fixed, general) = match grid {
                None => (
                    signature_orbits(&unit, &stops, omega, &signature),
                    sequence_orbits(&model, omega, &sequence).unwrap(),
                ),
                Some(g) => (
                    signature_orbits_on_grid(&unit, &stops, omega, &signature, g),
                    sequence_orbits_on_grid(&model, omega, &sequence, g).unwrap(),
                ),
            };
            let context = format!("{name} {text}/{period} at ω = {omega}");
            assert_eq!(general.len(), fixed.len(), "{context}: number of orbits");
            for (g, f) in general.iter().zip(&fixed) {
                assert_same_orbit(g, f, &context);
                compared += 1;
            }
        }
    }
    assert!(compared >= 20, "only {compared} orbits compared");
}

/// Undamped models (`tr A = 0`): the monodromy has determinant `e^{2m}` exactly (Liouville),
/// and with elastic stops (`e = 1`, the unit's `+-` orbits) energy is conserved: the forcing's
/// work over the cycle is zero to rounding, measured against the energy floor.
#[test]
fn undamped_orbits_obey_liouville_and_conserve_energy() {
    let mut checked = 0;
    let sequence = ImpactSequence::parse(CHAIN_SEQUENCE, 1).unwrap();
    let chain = LinearModel::chain(&paper_unit(), &paper_stops(), 2).unwrap();
    let elastic = Stops {
        restitution: 1.0,
        ..paper_stops()
    };
    let unit = LinearModel::unit(&paper_unit(), &elastic).unwrap();
    let cases = [
        (&chain, &sequence, 3.0, 0.8f64),
        (&chain, &sequence, CHAIN_OMEGA, 0.8),
        (&unit, &plus_minus(), 2.6, 1.0),
        (&unit, &plus_minus(), 3.3, 1.0),
    ];
    for (model, sequence, omega, restitution) in cases {
        for o in sequence_orbits(model, omega, sequence).unwrap() {
            let context = format!("{sequence} at ω = {omega}, α = {}", o.alpha);
            let m = o.impact_phases.len() as i32;
            let expected = restitution.powi(2 * m);
            let det = o.monodromy.determinant();
            assert!((det - expected).abs() <= 1e-10, "{context}: det {det}");
            assert!(own_equations_defect(model, &o) <= AGREEMENT, "{context}");
            assert!(
                o.energy_residual <= 1e-10,
                "{context}: {:e}",
                o.energy_residual
            );
            if restitution == 1.0 {
                assert_eq!(o.energy.impact_losses, 0.0);
                assert_eq!(o.energy.dashpot_dissipation, 0.0);
            }
            checked += 1;
        }
    }
    assert!(checked >= 4, "only {checked} orbits checked");
}

/// A sequence of more impacts than the grid's minimum (20 > 16 intervals): the search keeps at
/// least one grid point per impact and uses the axis neighbourhood, and returns (regression:
/// the tuple count once underflowed for grids smaller than the impact count).
#[test]
fn many_impact_sequences_are_searched_without_failure() {
    let model = two_cells();
    let sequence = ImpactSequence::parse(&"0+ 1+ 0- 1- ".repeat(5), 1).unwrap();
    assert_eq!(sequence.impacts().len(), 20);
    let orbits = sequence_orbits(&model, 3.0, &sequence).unwrap();
    for o in &orbits {
        assert!(own_equations_defect(&model, o) <= AGREEMENT);
    }
    assert!(sequence_orbits_on_grid(&model, 3.0, &sequence, 19)
        .unwrap()
        .is_empty());
}
