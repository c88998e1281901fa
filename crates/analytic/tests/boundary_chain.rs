//! Boundary curves on a model with contact pairs: a chain of one cell gives the unit's curve
//! (the same ω re-solved at the same parameter values), and every point of a 2-cell chain's
//! curve is an orbit of the sequence solver with the event's multipliers, where the
//! one-parameter continuation of the chain finds the event.

use rattle_analytic::test_models::{damped_paper_unit, paper_stops, paper_unit};
use rattle_analytic::*;

/// The paper unit with its stops' gap set to `gap`.
fn paper_at_gap(gap: f64) -> Result<(Unit, Stops), UnitError> {
    let stops = Stops {
        gap,
        ..paper_stops()
    };
    stops.validate()?;
    Ok((paper_unit(), stops))
}

/// The paper unit as a chain of one cell, its stops' gap set to `gap`.
fn one_cell_at_gap(gap: f64) -> Result<LinearModel, ModelError> {
    let stops = Stops {
        gap,
        ..paper_stops()
    };
    LinearModel::unit(&paper_unit(), &stops)
}

/// The damped 2-cell chain with both cells' restitution set to `restitution`.
fn two_cells_at_restitution(restitution: f64) -> Result<LinearModel, ModelError> {
    let stops = Stops {
        restitution,
        ..paper_stops()
    };
    LinearModel::chain(&damped_paper_unit(), &stops, 2)
}

/// `(α, φ₂ … φₙ)` of a curve point.
fn guess_of(p: &BoundaryPoint) -> Vec<f64> {
    let mut guess = vec![p.alpha];
    guess.extend_from_slice(&p.impact_phases[1..]);
    guess
}

/// The events of `kind` on the branch of `start` within `[omega_min, omega_max]`, nearest
/// the start first.
fn sequence_events(
    model: &LinearModel,
    start: &SequenceOrbit,
    kind: EventKind,
    omega_min: f64,
    omega_max: f64,
) -> Vec<Event<ImpactSequence>> {
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(omega_min, omega_max)
    };
    let c = continue_sequence(model, start, &settings).unwrap();
    let mut events: Vec<_> = c
        .events
        .into_iter()
        .filter(|e| e.branch == 0 && e.kind == kind)
        .collect();
    events.sort_by(|a, b| {
        (a.omega - start.omega)
            .abs()
            .total_cmp(&(b.omega - start.omega).abs())
    });
    events
}

#[test]
fn a_chain_of_one_cell_gives_the_units_period_doubling_curve() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let signature = Signature::parse("+-", 1).unwrap();
    let start = signature_orbits(&unit, &stops, 2.9, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.43).abs() < 0.01)
        .expect("the asymmetric orbit at β ≈ 0.43");
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(2.8, 3.0)
    };
    let event = continue_orbit(&unit, &stops, &start, &settings)
        .unwrap()
        .events
        .into_iter()
        .find(|e| e.kind == EventKind::PeriodDoubling)
        .unwrap();
    let range = BoundarySettings::new(0.45, 0.55);
    let of_unit = follow_boundary(
        &BoundaryStart {
            unit_at: paper_at_gap,
            signature: &start.signature,
            event: &event,
            param: stops.gap,
            at: &[],
        },
        &range,
    )
    .unwrap();
    // The chain's curve solved at every fifth parameter value of the unit's points.
    let values: Vec<f64> = of_unit
        .points
        .iter()
        .step_by(5)
        .map(|p| p.param_value)
        .collect();
    let model = one_cell_at_gap(stops.gap).unwrap();
    let sequence = ImpactSequence::from_signature(&start.signature);
    let mut guess = vec![start.alpha];
    guess.extend_from_slice(&start.impact_phases[1..]);
    let chain_start = solve_sequence(&model, start.omega, &sequence, &guess).unwrap();
    let chain_event =
        sequence_events(&model, &chain_start, EventKind::PeriodDoubling, 2.8, 3.0).remove(0);
    let of_chain = follow_sequence_boundary(
        &SequenceBoundaryStart {
            model_at: one_cell_at_gap,
            sequence: &sequence,
            event: &chain_event,
            param: stops.gap,
            at: &values,
        },
        &range,
    )
    .unwrap();
    assert_eq!(of_chain.at.len(), values.len(), "{:?}", of_chain.at);
    for (at, p) in of_chain.at.iter().zip(of_unit.points.iter().step_by(5)) {
        assert_eq!(at.param_value, p.param_value);
        assert!(
            (at.omega - p.omega).abs() < 1e-10,
            "gap {}: chain {} vs unit {}",
            p.param_value,
            at.omega,
            p.omega
        );
    }
    assert_eq!(
        of_chain.ends.map(|e| e.reason),
        of_unit.ends.map(|e| e.reason)
    );
    for (a, b) in of_chain.ends.iter().zip(&of_unit.ends) {
        assert!((a.omega - b.omega).abs() < 1e-10, "{a:?} vs {b:?}");
    }
    let kinds = |b: &[BoundarySpecialPoint]| b.iter().map(|s| s.kind).collect::<Vec<_>>();
    assert_eq!(
        kinds(&of_chain.special_points),
        kinds(&of_unit.special_points)
    );
}

#[test]
fn a_two_cell_chains_neimark_sacker_curve_is_where_its_solver_and_continuation_put_it() {
    let model = two_cells_at_restitution(paper_stops().restitution).unwrap();
    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap();
    let orbits = sequence_orbits(&model, 3.3, &sequence).unwrap();
    let start = orbits.iter().find(|o| o.viable).expect("a viable orbit");
    let events = sequence_events(&model, start, EventKind::NeimarkSacker, 2.8, 4.0);
    let event = events
        .first()
        .expect("a Neimark–Sacker point on the branch");
    let boundary = follow_sequence_boundary(
        &SequenceBoundaryStart {
            model_at: two_cells_at_restitution,
            sequence: &sequence,
            event,
            param: paper_stops().restitution,
            at: &[0.78, 0.8, 0.82],
        },
        &BoundarySettings::new(0.76, 0.84),
    )
    .unwrap();
    assert!(
        boundary.points.len() > 5,
        "{} points",
        boundary.points.len()
    );
    // Every point: an orbit of the sequence solver with a complex pair on the unit circle.
    for p in &boundary.points {
        let model = two_cells_at_restitution(p.param_value).unwrap();
        let orbit = solve_sequence(&model, p.omega, &sequence, &guess_of(p)).unwrap();
        let on_circle = orbit
            .floquet_multipliers
            .iter()
            .filter(|m| m.im.abs() > 1e-6)
            .map(|m| (m.norm() - 1.0).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            on_circle < 1e-8,
            "||μ| − 1| = {on_circle:e} at e = {}",
            p.param_value
        );
    }
    continuation_agrees(&boundary, &sequence);
}

/// At each `at` value of `boundary` (a curve over the 2-cell chain's restitution) the
/// chain's one-parameter continuation, started 0.01 from the curve on its orbit, finds an
/// event of the curve's kind at the curve's ω to 1e-8.
fn continuation_agrees(boundary: &Boundary<ImpactSequence>, sequence: &ImpactSequence) {
    assert_eq!(boundary.at.len(), 3, "{:?}", boundary.at);
    for at in &boundary.at {
        let model = two_cells_at_restitution(at.param_value).unwrap();
        let point = boundary
            .points
            .iter()
            .min_by(|a, b| {
                let d =
                    |p: &BoundaryPoint| (p.param_value - at.param_value).hypot(p.omega - at.omega);
                d(a).total_cmp(&d(b))
            })
            .unwrap();
        let start = solve_sequence(&model, at.omega + 0.01, sequence, &guess_of(point))
            .or_else(|_| solve_sequence(&model, at.omega - 0.01, sequence, &guess_of(point)))
            .unwrap();
        let found = sequence_events(
            &model,
            &start,
            boundary.kind,
            at.omega - 0.05,
            at.omega + 0.05,
        );
        let nearest = found
            .iter()
            .map(|e| (e.omega - at.omega).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-8, "e = {}: |Δω| = {nearest:e}", at.param_value);
    }
}

#[test]
fn a_two_cell_chains_grazing_curve_is_where_its_continuation_finds_it() {
    // The branch that leaves the 2-cell branch's branch point at 3.33878 rad/s has a grazing
    // of pair 0 within [2.5, 4.0] (`tests/continuation_chain.rs`).
    let model = two_cells_at_restitution(paper_stops().restitution).unwrap();
    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap();
    let orbits = sequence_orbits(&model, 3.3, &sequence).unwrap();
    let start = orbits.iter().find(|o| o.viable).expect("a viable orbit");
    let settings = ContinuationSettings {
        max_depth: 1,
        ..ContinuationSettings::new(2.5, 4.0)
    };
    let c = continue_sequence(&model, start, &settings).unwrap();
    let event = c
        .events
        .iter()
        .find(|e| e.kind == EventKind::Grazing)
        .expect("a grazing");
    let sequence = c.branches[event.branch].signature.clone();
    let boundary = follow_sequence_boundary(
        &SequenceBoundaryStart {
            model_at: two_cells_at_restitution,
            sequence: &sequence,
            event,
            param: paper_stops().restitution,
            at: &[0.78, 0.8, 0.82],
        },
        &BoundarySettings::new(0.76, 0.84),
    )
    .unwrap();
    assert!(
        boundary.points.len() > 5,
        "{} points",
        boundary.points.len()
    );
    continuation_agrees(&boundary, &sequence);
}
