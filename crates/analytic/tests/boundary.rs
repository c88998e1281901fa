//! Boundary curves of events in (ω, parameter): at fixed parameter values on the curve the
//! one-parameter continuation finds the same event at the curve's ω; every point of a curve
//! is an orbit of its signature with the event's property, checked with the cycle solver's
//! own multipliers and the rigorous extrema of the flow, not with the boundary's code.

use nalgebra::{Complex, Vector2, Vector4};
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::*;
use rattle_analytic::{join, Augmented, ForcedFlow};

mod common;

/// The paper unit with its stops' gap set to `gap`.
fn paper_at_gap(gap: f64) -> Result<(Unit, Stops), UnitError> {
    let stops = Stops {
        gap,
        ..paper_stops()
    };
    stops.validate()?;
    Ok((paper_unit(), stops))
}

/// The paper unit with its stops' restitution set to `restitution`.
fn paper_at_restitution(restitution: f64) -> Result<(Unit, Stops), UnitError> {
    let stops = Stops {
        restitution,
        ..paper_stops()
    };
    stops.validate()?;
    Ok((paper_unit(), stops))
}

/// The orbit of `signature` at `omega` from the guess `(α, φ₂ … φₙ)` of a continuation point.
fn guess_of(alpha: f64, phases: &[f64]) -> Vec<f64> {
    let mut guess = vec![alpha];
    guess.extend_from_slice(&phases[1..]);
    guess
}

/// The curve of `event` on the orbits of `signature`, followed from `param` over the parameter
/// `unit_at` varies within `range` with the default settings, its ω solved at `at`.
fn curve(
    unit_at: fn(f64) -> Result<(Unit, Stops), UnitError>,
    signature: &Signature,
    event: &Event,
    param: f64,
    at: &[f64],
    range: (f64, f64),
) -> Boundary {
    follow_boundary(
        &BoundaryStart {
            unit_at,
            signature,
            event,
            param,
            at,
        },
        &BoundarySettings::new(range.0, range.1),
    )
    .unwrap()
}

/// The first event of `kind` on the branch of `start` within `[omega_min, omega_max]`.
fn event_of(
    unit: &Unit,
    stops: &Stops,
    start: &SignatureOrbit,
    kind: EventKind,
    omega_min: f64,
    omega_max: f64,
) -> Option<Event> {
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(omega_min, omega_max)
    };
    let c = continue_orbit(unit, stops, start, &settings).ok()?;
    c.events
        .into_iter()
        .filter(|e| e.branch == 0 && e.kind == kind)
        .min_by(|a, b| {
            let d = |e: &Event| (e.omega - start.omega).abs();
            d(a).total_cmp(&d(b))
        })
}

/// The asymmetric `+-` orbit of the paper unit at ω = 2.9 with its side-2 impact at
/// `β ≈ 0.43` (the start of the continuation tests' period doubling and grazing).
fn asymmetric_start() -> SignatureOrbit {
    let signature = Signature::parse("+-", 1).unwrap();
    signature_orbits(&paper_unit(), &paper_stops(), 2.9, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.43).abs() < 0.01)
        .expect("the asymmetric orbit at β ≈ 0.43")
}

/// The symmetric `+-` orbit of the paper unit at ω = 0.75 (the continuation tests' fold).
fn symmetric_start() -> SignatureOrbit {
    let signature = Signature::parse("+-", 1).unwrap();
    let mut symmetric: Vec<SignatureOrbit> =
        signature_orbits(&paper_unit(), &paper_stops(), 0.75, &signature)
            .into_iter()
            .filter(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9)
            .collect();
    symmetric.sort_by_key(|o| !o.viable);
    symmetric.into_iter().next().expect("a symmetric orbit")
}

/// The point of the curve nearest `at` in (p, ω).
fn nearest_to<'a>(boundary: &'a Boundary, at: &BoundaryAt) -> &'a BoundaryPoint {
    let d = |p: &BoundaryPoint| (p.param_value - at.param_value).hypot(p.omega - at.omega);
    boundary
        .points
        .iter()
        .min_by(|a, b| d(a).total_cmp(&d(b)))
        .unwrap()
}

/// At each `--at` value the one-parameter continuation of the unit built there, started
/// `offset` away in ω from the curve on the curve's orbit, finds an event of the curve's kind
/// at the curve's ω to 1e-8.
fn one_parameter_agrees<F>(boundary: &Boundary, unit_at: F, offset: f64)
where
    F: Fn(f64) -> Result<(Unit, Stops), UnitError>,
{
    // Each of these curves is a graph over the parameter: one crossing per value.
    assert_eq!(boundary.at.len(), 3, "{:?}", boundary.at);
    crossings_agree(boundary, unit_at, offset);
}

/// [`one_parameter_agrees`] for any number of crossings.
fn crossings_agree<F>(boundary: &Boundary, unit_at: F, offset: f64)
where
    F: Fn(f64) -> Result<(Unit, Stops), UnitError>,
{
    for at in &boundary.at {
        let (unit, stops) = unit_at(at.param_value).unwrap();
        let point = nearest_to(boundary, at);
        let guess = guess_of(point.alpha, &point.impact_phases);
        // The orbit `offset` above the crossing, or below where the branch has none above.
        let start = solve_signature(
            &unit,
            &stops,
            at.omega + offset,
            &boundary.signature,
            &guess,
        )
        .or_else(|_| {
            solve_signature(
                &unit,
                &stops,
                at.omega - offset,
                &boundary.signature,
                &guess,
            )
        })
        .unwrap();
        let event = event_of(
            &unit,
            &stops,
            &start,
            boundary.kind,
            at.omega - 0.05,
            at.omega + 0.05,
        )
        .unwrap_or_else(|| {
            panic!(
                "no {:?} near ω = {} at {}",
                boundary.kind, at.omega, at.param_value
            )
        });
        assert!(
            (event.omega - at.omega).abs() < 1e-8,
            "{:?} at p = {}: continuation {} vs curve {}",
            boundary.kind,
            at.param_value,
            event.omega,
            at.omega
        );
    }
}

/// `min |μ − target|` over the cycle solver's own multipliers at a curve point.
fn multiplier_distance(
    unit_at: &dyn Fn(f64) -> Result<(Unit, Stops), UnitError>,
    signature: &Signature,
    p: &BoundaryPoint,
    target: f64,
) -> f64 {
    let (unit, stops) = unit_at(p.param_value).unwrap();
    let guess = guess_of(p.alpha, &p.impact_phases);
    let orbit = solve_signature(&unit, &stops, p.omega, signature, &guess).unwrap();
    orbit
        .floquet_multipliers
        .iter()
        .map(|m| (m - Complex::new(target, 0.0)).norm())
        .fold(f64::INFINITY, f64::min)
}

#[test]
fn period_doubling_curve_over_the_gap_is_where_continuation_finds_it() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let event = event_of(&unit, &stops, &start, EventKind::PeriodDoubling, 2.8, 3.0).unwrap();
    let boundary = curve(
        paper_at_gap,
        &start.signature,
        &event,
        stops.gap,
        &[0.47, 0.5, 0.53],
        (0.45, 0.55),
    );
    assert!(
        boundary.points.len() > 5,
        "{} points",
        boundary.points.len()
    );
    // At the start's own value the curve passes through the event itself.
    let here = boundary.at.iter().find(|a| a.param_value == 0.5).unwrap();
    assert!(
        (here.omega - event.omega).abs() < 1e-9,
        "{here:?} vs {}",
        event.omega
    );
    one_parameter_agrees(&boundary, paper_at_gap, 0.01);
    // Every point: an orbit of `+-` (the cycle solver converges there) with a multiplier at
    // −1, to the 1e-8 the continuation's own doubling test is held to.
    for p in boundary.points.iter().step_by(5) {
        let d = multiplier_distance(&paper_at_gap, &boundary.signature, p, -1.0);
        assert!(d < 1e-8, "|μ + 1| = {d:e} at gap {}", p.param_value);
        assert!(p.residual <= CORRECTOR_ACCEPTANCE);
    }
    assert_eq!(boundary.ends.len(), 2);
}

#[test]
fn fold_curve_over_the_restitution_is_where_continuation_finds_it() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = symmetric_start();
    let event = event_of(&unit, &stops, &start, EventKind::Fold, 0.6, 0.8).unwrap();
    let boundary = curve(
        paper_at_restitution,
        &start.signature,
        &event,
        stops.restitution,
        &[0.75, 0.8, 0.85],
        (0.7, 0.9),
    );
    one_parameter_agrees(&boundary, paper_at_restitution, 0.01);
    for p in boundary.points.iter().step_by(5) {
        let d = multiplier_distance(&paper_at_restitution, &boundary.signature, p, 1.0);
        assert!(d < 1e-8, "|μ − 1| = {d:e} at e = {}", p.param_value);
    }
}

#[test]
fn grazing_curve_over_the_gap_touches_the_stop_with_zero_relative_velocity() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let event = event_of(&unit, &stops, &start, EventKind::Grazing, 2.5, 3.0).unwrap();
    let boundary = curve(
        paper_at_gap,
        &start.signature,
        &event,
        stops.gap,
        &[0.48, 0.5, 0.52],
        (0.46, 0.54),
    );
    one_parameter_agrees(&boundary, paper_at_gap, 0.01);
    let phase = event.phase.unwrap();
    let f = (0..2)
        .rev()
        .find(|&f| event.point.impact_phases[f] <= phase)
        .unwrap();
    for p in &boundary.points {
        let (unit, stops) = paper_at_gap(p.param_value).unwrap();
        let guess = guess_of(p.alpha, &p.impact_phases);
        let orbit = solve_signature(&unit, &stops, p.omega, &boundary.signature, &guess).unwrap();
        let (r, r_dot) = graze(&unit, &stops, &orbit, f);
        assert!(
            (r.abs() - stops.gap).abs() < 1e-10 * stops.gap,
            "|r| = {r} vs gap {} at ω = {}",
            stops.gap,
            p.omega
        );
        assert!(r_dot.abs() < 1e-10, "ṙ = {r_dot:e} at ω = {}", p.omega);
    }
}

/// `r` and `ṙ` at the interior extremum of largest `|r|` over flight `f` of `orbit`, by the
/// rigorous extrema of the exact flow.
fn graze(unit: &Unit, stops: &Stops, orbit: &SignatureOrbit, f: usize) -> (f64, f64) {
    let flow = ForcedFlow::new(unit, orbit.omega);
    let cycle = flow.period() * orbit.period as f64;
    let n = orbit.impact_phases.len();
    let end = if f + 1 < n {
        orbit.impact_phases[f + 1]
    } else {
        1.0
    };
    let before = orbit.states_before_impacts[f];
    let v = stops.impact_map(unit) * Vector2::new(before[2], before[3]);
    let after = Vector4::new(before[0], before[1], v[0], v[1]);
    let alpha = orbit.alpha + orbit.omega * orbit.impact_phases[f] * cycle;
    let start = join(&after, &Vector2::new(alpha.cos(), alpha.sin()));
    let r = Augmented::new(-1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
    let ext = flow.critical_extrema(&start, (end - orbit.impact_phases[f]) * cycle, &[r])[0];
    let t = if ext.max >= -ext.min {
        ext.argmax
    } else {
        ext.argmin
    };
    let (x, _) = flow
        .transition(t)
        .apply(&after, &Vector2::new(alpha.cos(), alpha.sin()));
    (x[1] - x[0], x[3] - x[2])
}

#[test]
fn bad_settings_name_the_field() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let event = event_of(&unit, &stops, &start, EventKind::PeriodDoubling, 2.8, 3.0).unwrap();
    let mut request = BoundaryStart {
        unit_at: paper_at_gap,
        signature: &start.signature,
        event: &event,
        param: stops.gap,
        at: &[],
    };
    let bad = follow_boundary(&request, &BoundarySettings::new(0.55, 0.45)).unwrap_err();
    assert!(bad.to_string().starts_with("--max = 0.45"), "{bad}");
    request.at = &[0.7];
    let bad = follow_boundary(&request, &BoundarySettings::new(0.45, 0.55)).unwrap_err();
    assert!(bad.to_string().starts_with("--at = 0.7"), "{bad}");
}

/// The viable symmetric `+-` orbit of the paper unit at `omega` and the branch point on its
/// branch within `[omega_min, omega_max]`, where the asymmetric orbits leave it.
fn symmetric_branch_point(omega: f64, omega_min: f64, omega_max: f64) -> (SignatureOrbit, Event) {
    let (unit, stops) = (paper_unit(), paper_stops());
    let signature = Signature::parse("+-", 1).unwrap();
    let start = signature_orbits(&unit, &stops, omega, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9 && o.viable)
        .expect("a viable symmetric orbit");
    let event = event_of(
        &unit,
        &stops,
        &start,
        EventKind::BranchPoint,
        omega_min,
        omega_max,
    )
    .unwrap();
    (start, event)
}

/// The branch points near ω = 2.922 (from the viable symmetric orbit at 2.9) and 2.1925686
/// (the one `solve_branch_point` locates to 2.2e-15; from the viable symmetric
/// orbit at 2.2), each followed over the gap and over the restitution.
#[test]
fn branch_point_curves_over_the_gap_and_the_restitution_are_where_continuation_finds_them() {
    for (omega, omega_min, omega_max) in [(2.9, 2.85, 3.0), (2.2, 2.1, 2.3)] {
        let (start, event) = symmetric_branch_point(omega, omega_min, omega_max);
        branch_point_curves_agree(&start, &event);
    }
}

/// The curves of the branch point `event` on the branch of `start` over the gap and over the
/// restitution: through the event, where the one-parameter continuation finds it at three
/// values, a multiplier at +1 on the points.
fn branch_point_curves_agree(start: &SignatureOrbit, event: &Event) {
    let stops = paper_stops();
    type UnitAt = fn(f64) -> Result<(Unit, Stops), UnitError>;
    let cases: [(UnitAt, f64, [f64; 3], f64, f64); 2] = [
        (paper_at_gap, stops.gap, [0.47, 0.5, 0.53], 0.45, 0.55),
        (
            paper_at_restitution,
            stops.restitution,
            [0.78, 0.8, 0.82],
            0.76,
            0.84,
        ),
    ];
    for (unit_at, param, at, min, max) in cases {
        let boundary = follow_boundary(
            &BoundaryStart {
                unit_at,
                signature: &start.signature,
                event,
                param,
                at: &at,
            },
            &BoundarySettings::new(min, max),
        )
        .unwrap();
        assert!(
            boundary.points.len() > 5,
            "{} points",
            boundary.points.len()
        );
        // At the start's own value the curve passes through the event itself, located to
        // rounding by the one-parameter continuation's own extended system.
        let here = boundary.at.iter().find(|a| a.param_value == param).unwrap();
        assert!(
            (here.omega - event.omega).abs() < 1e-9,
            "{here:?} vs {}",
            event.omega
        );
        one_parameter_agrees(&boundary, unit_at, 0.01);
        // Every point: a multiplier at +1 by the cycle solver's own multipliers.
        for p in boundary.points.iter().step_by(3) {
            let d = multiplier_distance(&unit_at, &boundary.signature, p, 1.0);
            assert!(d < 1e-8, "|μ − 1| = {d:e} at {}", p.param_value);
        }
    }
}

#[test]
fn neimark_sacker_curve_over_the_restitution_keeps_a_complex_pair_on_the_unit_circle() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let signature = Signature::parse("+-", 1).unwrap();
    let start = signature_orbits(&unit, &stops, 2.9, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9 && o.viable)
        .expect("the viable symmetric orbit at 2.9");
    let event = event_of(&unit, &stops, &start, EventKind::NeimarkSacker, 2.9, 3.5).unwrap();
    let boundary = curve(
        paper_at_restitution,
        &start.signature,
        &event,
        stops.restitution,
        &[0.78, 0.8, 0.82],
        (0.76, 0.84),
    );
    one_parameter_agrees(&boundary, paper_at_restitution, 0.01);
    for p in boundary.points.iter().step_by(3) {
        let (unit, stops) = paper_at_restitution(p.param_value).unwrap();
        let guess = guess_of(p.alpha, &p.impact_phases);
        let orbit = solve_signature(&unit, &stops, p.omega, &boundary.signature, &guess).unwrap();
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
}

#[test]
fn vanishing_impact_curve_over_the_gap_has_zero_relative_velocity() {
    let (unit, stops) = (paper_unit(), paper_stops());
    // The symmetric orbit at ω = 3.5 that is not a motion (the continuation test's).
    let signature = Signature::parse("+-", 1).unwrap();
    let start = signature_orbits(&unit, &stops, 3.5, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9 && !o.viable)
        .expect("a non-viable symmetric orbit at 3.5");
    let event = event_of(&unit, &stops, &start, EventKind::VanishingImpact, 3.0, 3.7).unwrap();
    let boundary = curve(
        paper_at_gap,
        &start.signature,
        &event,
        stops.gap,
        &[0.48, 0.5, 0.52],
        (0.46, 0.54),
    );
    one_parameter_agrees(&boundary, paper_at_gap, 0.01);
    let phase = event.phase.unwrap();
    let j = event
        .point
        .impact_phases
        .iter()
        .position(|p| (p - phase).abs() < 1e-9)
        .unwrap();
    for p in &boundary.points {
        let (unit, stops) = paper_at_gap(p.param_value).unwrap();
        let guess = guess_of(p.alpha, &p.impact_phases);
        let orbit = solve_signature(&unit, &stops, p.omega, &boundary.signature, &guess).unwrap();
        let x = orbit.states_before_impacts[j];
        // Relative to the velocity scale ω Δ of the motion.
        let rdot = (x[3] - x[2]) / (p.omega * stops.gap);
        assert!(
            rdot.abs() < 1e-10,
            "ṙ⁻/(ωΔ) = {rdot:e} at gap {}",
            p.param_value
        );
    }
}

#[test]
fn grazing_curve_over_the_restitution_passes_its_turning_point() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let event = event_of(&unit, &stops, &start, EventKind::Grazing, 2.5, 3.0).unwrap();
    // Measured with `rattle boundary` (this curve): it turns back in e near e = 0.559,
    // ω = 2.452, so that e = 0.7 is crossed twice, once on either side of the turn.
    let boundary = curve(
        paper_at_restitution,
        &start.signature,
        &event,
        stops.restitution,
        &[0.7],
        (0.5, 0.9),
    );
    let e: Vec<f64> = boundary.points.iter().map(|p| p.param_value).collect();
    let turns = e
        .windows(3)
        .filter(|w| (w[1] - w[0]) * (w[2] - w[1]) < 0.0)
        .count();
    assert_eq!(turns, 1, "{e:?}");
    assert_eq!(
        boundary.ends.map(|e| e.reason),
        [BoundaryEndReason::ParamMax; 2]
    );
    assert_eq!(boundary.at.len(), 2, "{:?}", boundary.at);
    assert!((boundary.at[0].omega - boundary.at[1].omega).abs() > 0.1);
    // The lower crossing (ω = 2.2304) lies 7e-4 above the branch point where this asymmetric
    // branch leaves the symmetric orbit (2.2297 at e = 0.7): the start is taken closer.
    crossings_agree(&boundary, paper_at_restitution, 2e-4);
}

/// The special point of `kind` on `boundary` (the only one of its name).
fn special<'a>(boundary: &'a Boundary, name: &str) -> Vec<&'a BoundarySpecialPoint> {
    boundary
        .special_points
        .iter()
        .filter(|s| s.kind.name() == name)
        .collect()
}

/// The first event of `kind` found by the one-parameter continuation at `param` on the orbit
/// of the curve point `point`, started `offset` above (or below) its ω.
fn event_at<F>(
    unit_at: F,
    signature: &Signature,
    point: &BoundaryPoint,
    kind: EventKind,
    offset: f64,
) -> Event
where
    F: Fn(f64) -> Result<(Unit, Stops), UnitError>,
{
    let (unit, stops) = unit_at(point.param_value).unwrap();
    let guess = guess_of(point.alpha, &point.impact_phases);
    let start = solve_signature(&unit, &stops, point.omega + offset, signature, &guess)
        .or_else(|_| solve_signature(&unit, &stops, point.omega - offset, signature, &guess))
        .unwrap();
    event_of(
        &unit,
        &stops,
        &start,
        kind,
        point.omega - 0.05,
        point.omega + 0.05,
    )
    .unwrap_or_else(|| panic!("no {kind:?} near ω = {}", point.omega))
}

#[test]
fn the_grazing_curve_over_the_restitution_turns_at_its_located_turning_point() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let event = event_of(&unit, &stops, &start, EventKind::Grazing, 2.5, 3.0).unwrap();
    let follow = |at: &[f64]| {
        follow_boundary(
            &BoundaryStart {
                unit_at: paper_at_restitution,
                signature: &start.signature,
                event: &event,
                param: stops.restitution,
                at,
            },
            &BoundarySettings::new(0.5, 0.9),
        )
        .unwrap()
    };
    let boundary = follow(&[]);
    // The turn that `rattle boundary` finds near e = 0.559, ω = 2.452.
    let turns = special(&boundary, "turning-point");
    assert_eq!(turns.len(), 1, "{:?}", boundary.special_points);
    let turn = turns[0];
    assert!((turn.param_value - 0.559).abs() < 1e-3, "{turn:?}");
    // dp/ds of the curve's own unit tangent vanishes there.
    assert!(turn.value.abs() < 1e-9, "dp/ds = {:e}", turn.value);
    // It is the curve's lowest restitution: every point lies at or above it.
    let lowest = boundary
        .points
        .iter()
        .map(|p| p.param_value)
        .fold(f64::INFINITY, f64::min);
    assert_eq!(lowest, turn.param_value);
    // The curve is a point of it too, and crosses e = e* + 1e-4 twice, e* − 1e-4 never.
    assert!(boundary.points.contains(&turn.point));
    let delta = 1e-4;
    let again = follow(&[turn.param_value - delta, turn.param_value + delta]);
    let below = again.at.iter().filter(|a| a.param_value < turn.param_value);
    assert_eq!(below.count(), 0, "{:?}", again.at);
    assert_eq!(again.at.len(), 2, "{:?}", again.at);
    // Either side of the turn, `√δ`-close to it in ω (a quadratic turn).
    let (w0, w1) = (again.at[0].omega, again.at[1].omega);
    assert!(
        (w0 - turn.omega) * (w1 - turn.omega) < 0.0,
        "{w0} {w1} {turn:?}"
    );
}

#[test]
fn a_neimark_sacker_curve_over_the_gap_meets_its_one_to_four_resonance() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    // The asymmetric branch's Neimark–Sacker points near ω = 1.75 and 1.66 lie on one
    // curve over the gap, turning at gap 0.4089 (measured: from 1.75 it passes the turn and
    // meets the 1:4 resonance at gap 0.5574, ω = 1.6339).
    let event = event_of(&unit, &stops, &start, EventKind::NeimarkSacker, 1.5, 3.0).unwrap();
    let boundary = curve(
        paper_at_gap,
        &start.signature,
        &event,
        stops.gap,
        &[],
        (0.35, 0.65),
    );
    assert_eq!(special(&boundary, "turning-point").len(), 1);
    let resonances = special(&boundary, "resonance-1:4");
    assert_eq!(resonances.len(), 1, "{:?}", boundary.special_points);
    let r = resonances[0];
    // The cycle solver's own multipliers there: the pair at e^{±iπ/2}.
    let (unit, stops) = paper_at_gap(r.param_value).unwrap();
    let guess = guess_of(r.point.alpha, &r.point.impact_phases);
    let orbit = solve_signature(&unit, &stops, r.omega, &boundary.signature, &guess).unwrap();
    let mu = orbit
        .floquet_multipliers
        .iter()
        .find(|m| m.im > 1e-3)
        .unwrap();
    assert!(
        (mu.arg() - std::f64::consts::FRAC_PI_2).abs() < 1e-9,
        "arg μ = {}",
        mu.arg()
    );
    assert!((mu.norm() - 1.0).abs() < 1e-8, "|μ| = {}", mu.norm());
}

#[test]
fn a_grazing_curve_crosses_the_period_doubling_curve_where_each_locates_the_other() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let follow = |kind, omega_min, omega_max| {
        let event = event_of(&unit, &stops, &start, kind, omega_min, omega_max).unwrap();
        curve(
            paper_at_gap,
            &start.signature,
            &event,
            stops.gap,
            &[],
            (0.35, 0.55),
        )
    };
    let grazing = follow(EventKind::Grazing, 2.5, 3.0);
    let doubling = follow(EventKind::PeriodDoubling, 2.8, 3.0);
    // Measured: the two cross near gap 0.3839, ω = 2.8701.
    let crossing: Vec<_> = special(&grazing, "crossing")
        .into_iter()
        .filter(|s| {
            s.kind
                == SpecialKind::Crossing {
                    other: EventKind::PeriodDoubling,
                }
        })
        .collect();
    assert_eq!(crossing.len(), 1, "{:?}", grazing.special_points);
    let crossing = crossing[0];
    let graze = special(&doubling, "grazing");
    assert_eq!(graze.len(), 1, "{:?}", doubling.special_points);
    // The same point, located from either curve.
    assert!(
        (crossing.param_value - graze[0].param_value).abs() < 1e-9
            && (crossing.omega - graze[0].omega).abs() < 1e-9,
        "{crossing:?} vs {:?}",
        graze[0]
    );
    // The one-parameter continuation at that gap finds its period doubling at that ω.
    let event = event_at(
        paper_at_gap,
        &grazing.signature,
        &crossing.point,
        EventKind::PeriodDoubling,
        0.01,
    );
    assert!(
        (event.omega - crossing.omega).abs() < 1e-8,
        "continuation {} vs crossing {}",
        event.omega,
        crossing.omega
    );
}

/// As the special points' own search finds it: a Neimark–Sacker curve of the
/// paper unit's `++--` orbits, from its event near ω = 1.94817 at e = 0.8, followed down
/// the restitution, ends where its complex pair meets at +1 (e ≈ 0.368, ω ≈ 1.312): a 1:1
/// resonance, where the fold curve meets it.
#[test]
fn a_neimark_sacker_curve_ends_at_its_one_to_one_resonance() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let signature = Signature::parse("++--", 1).unwrap();
    let (start, event) = signature_orbits(&unit, &stops, 2.0, &signature)
        .into_iter()
        .find_map(|o| {
            let e = event_of(&unit, &stops, &o, EventKind::NeimarkSacker, 1.9, 2.0)?;
            ((e.omega - 1.94817).abs() < 1e-3).then_some((o, e))
        })
        .expect("the Neimark–Sacker point near 1.94817");
    let boundary = curve(
        paper_at_restitution,
        &start.signature,
        &event,
        stops.restitution,
        &[],
        (0.3, 0.8),
    );
    let resonance = special(&boundary, "resonance-1:1");
    assert_eq!(resonance.len(), 1, "{:?}", boundary.special_points);
    let r = resonance[0];
    assert!(
        (r.param_value - 0.368).abs() < 1e-3 && (r.omega - 1.312).abs() < 1e-3,
        "{r:?}"
    );
    // A crossing with the fold curve (measured near e = 0.623, ω = 1.786): the orbit there
    // has a multiplier at +1 and its complex pair on the unit circle, by the cycle solver.
    // (The fold test vanishes at the 1:1 resonance too, where the curve ends: whether a sign
    // change shows there is rounding's choice, so it is not asked for.)
    let fold = SpecialKind::Crossing {
        other: EventKind::Fold,
    };
    let folds: Vec<&BoundarySpecialPoint> = boundary
        .special_points
        .iter()
        .filter(|s| s.kind == fold)
        .collect();
    let other = folds
        .iter()
        .find(|c| (c.param_value - 0.623).abs() < 1e-3)
        .expect("the fold crossing near e = 0.623");
    let mu = solve_signature(
        &paper_at_restitution(other.param_value).unwrap().0,
        &paper_at_restitution(other.param_value).unwrap().1,
        other.omega,
        &boundary.signature,
        &guess_of(other.point.alpha, &other.point.impact_phases),
    )
    .unwrap()
    .floquet_multipliers;
    let at_one = mu
        .iter()
        .map(|m| (m - 1.0).norm())
        .fold(f64::INFINITY, f64::min);
    let on_circle = mu
        .iter()
        .filter(|m| m.im.abs() > 1e-3)
        .map(|m| (m.norm() - 1.0).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(at_one < 1e-8 && on_circle < 1e-8, "{mu:?}");
    // The curve's end on that side is the resonance itself.
    let end = boundary
        .ends
        .iter()
        .find(|e| e.reason == BoundaryEndReason::NeutralSaddle)
        .expect("a neutral-saddle end");
    assert_eq!((end.param_value, end.omega), (r.param_value, r.omega));
    // The cycle solver's multipliers there: a pair at +1 (a double multiplier, each located
    // only to about √ε, their sum to rounding).
    let (unit, stops) = paper_at_restitution(r.param_value).unwrap();
    let guess = guess_of(r.point.alpha, &r.point.impact_phases);
    let orbit = solve_signature(&unit, &stops, r.omega, &boundary.signature, &guess).unwrap();
    let mut near_one: Vec<Complex<f64>> = orbit
        .floquet_multipliers
        .iter()
        .copied()
        .filter(|m| (m - 1.0).norm() < 1e-6)
        .collect();
    assert_eq!(near_one.len(), 2, "{:?}", orbit.floquet_multipliers);
    let sum = near_one.pop().unwrap() + near_one.pop().unwrap();
    assert!((sum - 2.0).norm() < 1e-9, "μ₁ + μ₂ = {sum}");
}

/// The length of `boundary` in `(α, φ₂ … φₙ, ω, p)` (`α` modulo 2π): the sum of its chords.
fn boundary_length(boundary: &Boundary) -> f64 {
    let xs: Vec<Vec<f64>> = boundary
        .points
        .iter()
        .map(|p| {
            [
                &[p.alpha][..],
                &p.impact_phases[1..],
                &[p.omega, p.param_value],
            ]
            .concat()
        })
        .collect();
    common::chord_length(&xs)
}

#[test]
fn a_closed_curve_longer_than_one_direction_is_followed_once_from_both_ways() {
    // The branch-point curve of the `+-+-` orbits over the gap (a boundary of `cargo xtask
    // figures`) is closed and longer than one direction's `max_points` (300 there): the
    // backward way ends where the forward way stopped, rather than each going round it (607
    // points for a curve of about 356).
    let signature = Signature::parse("+-+-", 2).unwrap();
    let (unit, stops) = (paper_unit(), paper_stops());
    let omega = 2.4586286349587962;
    let event = signature_orbits(&unit, &stops, 2.45, &signature)
        .iter()
        .filter_map(|o| event_of(&unit, &stops, o, EventKind::BranchPoint, 2.3, 2.6))
        .find(|e| (e.omega - omega).abs() < 1e-6)
        .expect("the study's branch point of `+-+-` near ω = 2.4586");
    let follow = |max_points: usize| {
        follow_boundary(
            &BoundaryStart {
                unit_at: paper_at_gap,
                signature: &signature,
                event: &event,
                param: stops.gap,
                at: &[],
            },
            &BoundarySettings {
                max_points,
                ..BoundarySettings::new(0.1, 1.0)
            },
        )
        .unwrap()
    };
    let reasons = |b: &Boundary| b.ends.map(|e| e.reason);
    // Room for the whole curve one way: it closes through its start.
    let whole = follow(5_000);
    assert_eq!(reasons(&whole), [BoundaryEndReason::ClosedLoop; 2]);
    let points = whole.points.len();
    assert!(points > 100, "{points} points");
    // Three quarters of it each way: the second way ends where the first stopped.
    let halves = follow(points * 3 / 4);
    assert_eq!(reasons(&halves), [BoundaryEndReason::ClosedLoop; 2]);
    let (once, followed) = (boundary_length(&whole), boundary_length(&halves));
    assert!(
        (followed - once).abs() < 0.02 * once,
        "{followed} followed for a curve of {once} ({} points, {points} one way)",
        halves.points.len()
    );
}
