//! Continuation on a model with contact pairs: a chain of one cell must give the unit's
//! branch (every point the unit solver's orbit at its frequency, the same events at the same
//! frequencies), and on a 2-cell chain every point of a branch must be an orbit of the
//! sequence solver at its frequency, each cell's outer amplitude its, with a Neimark–Sacker
//! event where the solver's multipliers cross the unit circle, and a grazing and a vanishing
//! impact where its verdict on that pair changes.

use nalgebra::Complex;
use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::*;

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// `(α, φ₂ … φₙ)` of a point, the sequence solver's guess.
fn guess_of(p: &ContinuationPoint) -> Vec<f64> {
    let mut guess = vec![p.alpha];
    guess.extend_from_slice(&p.impact_phases[1..]);
    guess
}

/// The asymmetric `+-` orbit of the paper unit at ω = 2.9 with its side-2 impact at
/// `β ≈ 0.43` (found by the multi-start; viable; its branch has a grazing within
/// `[2.5, 3.0]`, see `tests/continuation.rs`).
fn asymmetric_start() -> SignatureOrbit {
    let signature = Signature::parse("+-", 1).unwrap();
    signature_orbits(&paper_unit(), &paper_stops(), 2.9, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.43).abs() < 0.01)
        .expect("the asymmetric orbit at β ≈ 0.43")
}

/// Largest distance between two lists of multipliers, each matched to its nearest.
fn multiplier_distance(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    a.iter()
        .map(|x| {
            b.iter()
                .map(|y| (x - y).norm())
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

/// Agreement of the unknowns and amplitudes of a continuation point with the orbit solver's
/// at the same frequency, where the fixed-frequency problem is well conditioned: the
/// corrector's fallback acceptance ([`CORRECTOR_ACCEPTANCE`]) relative to the
/// motion's size (both solvers stop at `1e-13` of it otherwise).
const AGREEMENT: f64 = CORRECTOR_ACCEPTANCE;

/// Agreement of two computations of the Floquet multipliers (the issue's `1e-8`): the
/// eigenvalues of a non-normal monodromy are less well conditioned than the orbit.
const MULTIPLIER_AGREEMENT: f64 = 1e-8;

/// Events located on two runs (their zero bracketed to `1e-13` of a step of at most
/// `max_step = 0.05`) agree to this in `ω`.
const EVENT_AGREEMENT: f64 = 1e-12;

/// At a branch point and a fold the fixed-frequency Jacobian `R_x` is singular, and Newton at
/// fixed `ω` pins the unknowns only to about `tolerance / σ_min(R_x)`: points within this of
/// one (rad/s) are compared by the solver's convergence alone.
const SINGULAR_NEIGHBOURHOOD: f64 = 1e-3;

/// Whether `omega` lies within [`SINGULAR_NEIGHBOURHOOD`] of a branch point or fold of `c`.
fn near_singular<L>(c: &Continuation<L>, omega: f64) -> bool {
    c.events.iter().any(|e| {
        matches!(e.kind, EventKind::BranchPoint | EventKind::Fold)
            && (e.omega - omega).abs() < SINGULAR_NEIGHBOURHOOD
    }) || c
        .ends
        .iter()
        .any(|e| e.reason == EndReason::Joins && (e.omega - omega).abs() < SINGULAR_NEIGHBOURHOOD)
}

#[test]
fn a_chain_of_one_cell_follows_the_units_branch_with_the_same_events() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(2.5, 3.0)
    };
    let of_unit = continue_orbit(&unit, &stops, &start, &settings).unwrap();
    let model = LinearModel::unit(&unit, &stops).unwrap();
    let sequence = ImpactSequence::from_signature(&start.signature);
    let mut guess = vec![start.alpha];
    guess.extend_from_slice(&start.impact_phases[1..]);
    let chain_start = solve_sequence(&model, start.omega, &sequence, &guess).unwrap();
    let of_chain = continue_sequence(&model, &chain_start, &settings).unwrap();

    // The same events, in the same order, at the same frequencies; but a branch that runs
    // onto its own mirror image ends where a step first passes onto it, so an event within
    // the last step of such an end (here the pitchfork where it meets its image) is reached
    // on one run and not on the other.
    let at_join_end = |omega: f64| {
        of_unit.ends.iter().chain(&of_chain.ends).any(|e| {
            e.reason == EndReason::Joins && (e.omega - omega).abs() < SINGULAR_NEIGHBOURHOOD
        })
    };
    let unit_events: Vec<&Event> = of_unit
        .events
        .iter()
        .filter(|e| !at_join_end(e.omega))
        .collect();
    let chain_events: Vec<&Event<ImpactSequence>> = of_chain
        .events
        .iter()
        .filter(|e| !at_join_end(e.omega))
        .collect();
    assert_eq!(
        unit_events.iter().map(|e| e.kind).collect::<Vec<_>>(),
        chain_events.iter().map(|e| e.kind).collect::<Vec<_>>()
    );
    assert!(unit_events.len() >= 2, "{} events", unit_events.len());
    for (e, f) in unit_events.iter().zip(&chain_events) {
        assert!(
            (e.omega - f.omega).abs() <= EVENT_AGREEMENT,
            "{:?}: {} vs {}",
            e.kind,
            e.omega,
            f.omega
        );
        assert_eq!(
            f.signature_after.as_ref().map(ToString::to_string),
            e.signature_after
                .as_ref()
                .map(|s| ImpactSequence::from_signature(s).to_string())
        );
    }
    let reasons = |ends: &[BranchEnd]| ends.iter().map(|e| e.reason).collect::<Vec<_>>();
    assert_eq!(reasons(&of_unit.ends), reasons(&of_chain.ends));

    // Every point of the chain's branch is the unit's orbit at its frequency.
    let signature = &of_unit.branches[0].signature;
    let points = &of_chain.branches[0].points;
    assert!(points.len() > 20, "{} points", points.len());
    for p in points {
        let o = solve_signature(&unit, &stops, p.omega, signature, &guess_of(p)).unwrap();
        assert_eq!(p.cell_outer_amplitudes, vec![p.outer_amplitude]);
        if near_singular(&of_unit, p.omega) {
            continue;
        }
        let context = format!("ω = {}", p.omega);
        assert!(
            o.newton_iterations <= 1,
            "{context}: {} iterations",
            o.newton_iterations
        );
        assert!(wrap(o.alpha - p.alpha).abs() <= AGREEMENT, "{context}");
        assert!(
            (o.impact_phases[1] - p.impact_phases[1]).abs() <= AGREEMENT,
            "{context}"
        );
        let amplitude = (o.outer_amplitude - p.outer_amplitude).abs() / o.outer_amplitude;
        assert!(amplitude <= AGREEMENT, "{context}: {amplitude:e}");
        let mu = multiplier_distance(&o.floquet_multipliers, &p.floquet_multipliers);
        assert!(mu <= MULTIPLIER_AGREEMENT, "{context}: {mu:e}");
        assert_eq!(o.viable, p.viable, "{context}");
    }
}

/// The damped 2-cell chain's `0+ 1- 0- 1+` branch through its viable orbit at ω = 3.3
/// (`tests/sequence_orbits.rs`), followed over `[2.8, 4.0]` without switching.
fn two_cell_branch() -> (LinearModel, ImpactSequence, Continuation<ImpactSequence>) {
    let model = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2).unwrap();
    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap();
    let orbits = sequence_orbits(&model, 3.3, &sequence).unwrap();
    let start = orbits.iter().find(|o| o.viable).expect("a viable orbit");
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(2.8, 4.0)
    };
    let c = continue_sequence(&model, start, &settings).unwrap();
    (model, sequence, c)
}

#[test]
fn two_cell_chain_points_are_orbits_of_the_sequence_solver() {
    let (model, sequence, c) = two_cell_branch();
    let points = &c.branches[0].points;
    assert!(points.len() > 20, "{} points", points.len());
    assert_eq!(c.branches[0].signature, sequence);
    let mut compared = 0;
    for p in points {
        let o = solve_sequence(&model, p.omega, &sequence, &guess_of(p)).unwrap();
        let context = format!("ω = {}", p.omega);
        assert_eq!(p.cell_outer_amplitudes.len(), 2, "{context}");
        assert_eq!(p.outer_amplitude, p.cell_outer_amplitudes[1], "{context}");
        if near_singular(&c, p.omega) {
            continue;
        }
        assert!(
            o.newton_iterations <= 1,
            "{context}: {} iterations",
            o.newton_iterations
        );
        compared += 1;
        assert!(wrap(o.alpha - p.alpha).abs() <= AGREEMENT, "{context}");
        for (a, b) in o.impact_phases.iter().zip(&p.impact_phases) {
            assert!((a - b).abs() <= AGREEMENT, "{context}");
        }
        for (a, b) in o.cell_outer_amplitudes.iter().zip(&p.cell_outer_amplitudes) {
            assert!((a - b).abs() <= AGREEMENT * a, "{context}: {a} vs {b}");
        }
        let mu = multiplier_distance(&o.floquet_multipliers, &p.floquet_multipliers);
        assert!(mu <= MULTIPLIER_AGREEMENT, "{context}: {mu:e}");
        assert_eq!((o.viable, o.stable), (p.viable, p.stable), "{context}");
    }
    assert!(compared > 20, "{compared} points compared");
}

#[test]
fn a_neimark_sacker_event_of_the_chain_is_where_the_solvers_stability_changes() {
    let (model, sequence, c) = two_cell_branch();
    let points = &c.branches[0].points;
    let torus: Vec<&Event<ImpactSequence>> = c
        .events
        .iter()
        .filter(|e| e.kind == EventKind::NeimarkSacker)
        .collect();
    assert!(!torus.is_empty(), "no Neimark–Sacker event on the branch");
    for e in torus {
        // The two consecutive points of the branch around the event, re-solved by the orbit
        // solver at their own frequencies: a complex pair of its multipliers has crossed the
        // unit circle, two more (or fewer) outside it.
        let pair = points
            .windows(2)
            .find(|w| (w[0].omega - e.omega) * (w[1].omega - e.omega) < 0.0)
            .expect("points on both sides of the event");
        let outside = |p: &ContinuationPoint| {
            let o = solve_sequence(&model, p.omega, &sequence, &guess_of(p)).unwrap();
            o.floquet_multipliers
                .iter()
                .filter(|m| m.norm() > 1.0)
                .count() as i64
        };
        let change = outside(&pair[1]) - outside(&pair[0]);
        assert_eq!(change.abs(), 2, "ω = {}", e.omega);
        // At the event a complex pair sits on the unit circle.
        assert!(e
            .point
            .floquet_multipliers
            .iter()
            .any(|m| m.im.abs() > 1e-9 && (m.norm() - 1.0).abs() < 1e-6));
    }
}

/// `|a − p| + |p − b| − |a − b|` in `(α, φ₂ … φₙ, ω)` for the step `[a, b]` and a point `p`:
/// zero when `p` lies on the chord.
fn detour(step: &[ContinuationPoint], p: &ContinuationPoint) -> f64 {
    let d = |u: &ContinuationPoint, v: &ContinuationPoint| {
        let phases: f64 = u
            .impact_phases
            .iter()
            .zip(&v.impact_phases)
            .map(|(x, y)| (x - y).powi(2))
            .sum();
        (wrap(u.alpha - v.alpha).powi(2) + phases + (u.omega - v.omega).powi(2)).sqrt()
    };
    d(&step[0], p) + d(p, &step[1]) - d(&step[0], &step[1])
}

#[test]
fn a_grazing_and_a_vanishing_impact_of_the_chain_are_where_the_solvers_verdict_on_the_pair_changes()
{
    // The branch that leaves the 2-cell branch's branch point at 3.33878 rad/s (switched onto
    // at depth 1) has, within [2.5, 4.0], a vanishing impact and a grazing of pair 0 (as
    // `rattle continue` finds them; the test follows the branch itself).
    let model = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2).unwrap();
    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap();
    let orbits = sequence_orbits(&model, 3.3, &sequence).unwrap();
    let start = orbits.iter().find(|o| o.viable).expect("a viable orbit");
    let settings = ContinuationSettings {
        max_depth: 1,
        ..ContinuationSettings::new(2.5, 4.0)
    };
    let c = continue_sequence(&model, start, &settings).unwrap();
    let mut checked = Vec::new();
    for e in &c.events {
        if !matches!(e.kind, EventKind::Grazing | EventKind::VanishingImpact) {
            continue;
        }
        let pair = e.pair.expect("the pair of a grazing or vanishing impact");
        assert!(pair < 2);
        let branch = &c.branches[e.branch];
        // The consecutive points around the event (the step whose chord passes closest to
        // it), re-solved by the orbit solver at their own frequencies: on one side only does
        // the solver find the pair's excursion beyond a stop (grazing) or an impact of the
        // pair approached from outside (vanishing impact).
        let around = branch
            .points
            .windows(2)
            .min_by(|v, w| detour(v, &e.point).total_cmp(&detour(w, &e.point)))
            .expect("a step of the branch");
        let kind = e.kind;
        let viable = |p: &ContinuationPoint| {
            let o = solve_sequence(&model, p.omega, &branch.signature, &guess_of(p)).unwrap();
            !o.violations.iter().any(|v| match *v {
                SequenceViolation::Penetration { pair: q, .. }
                | SequenceViolation::ExtraImpact { pair: q, .. } => {
                    kind == EventKind::Grazing && q == pair
                }
                SequenceViolation::WrongApproach { pair: q, .. } => {
                    kind == EventKind::VanishingImpact && q == pair
                }
            })
        };
        assert_ne!(
            viable(&around[0]),
            viable(&around[1]),
            "{:?} at ω = {}",
            e.kind,
            e.omega
        );
        if e.kind == EventKind::Grazing {
            // The new sequence has one more impact, of the grazing pair.
            let after = e.signature_after.as_ref().expect("the grazed sequence");
            assert_eq!(after.impacts().len(), branch.signature.impacts().len() + 1);
            let count = |s: &ImpactSequence| s.impacts().iter().filter(|i| i.pair == pair).count();
            assert_eq!(count(after), count(&branch.signature) + 1);
        }
        checked.push(e.kind);
    }
    assert!(checked.contains(&EventKind::Grazing), "{checked:?}");
    assert!(checked.contains(&EventKind::VanishingImpact), "{checked:?}");
}
