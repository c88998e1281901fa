//! Continuation in ω: points on their own equations (propagated independently), agreement
//! with the symmetric solver, and each kind of event checked against an answer computed
//! another way (the β family's gap for the branch point, the cycle solver's own multipliers
//! for the period doubling, rigorous extrema for the grazing).

use nalgebra::{Matrix4, Matrix6, Vector2, Vector4};
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::CORRECTOR_ACCEPTANCE;
use rattle_analytic::*;
use rattle_analytic::{join, Augmented, ForcedFlow};

mod common;

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The largest contact residual `|r(t_j⁻) − s_j Δ|` of an orbit given by `(α, phases, ω)`,
/// and the motion's size, by composing the exact flights (`ForcedFlow::transition` over each
/// flight's duration) and impact maps around the cycle and solving the periodicity, without
/// any code of the continuation.
fn contact_residual(
    unit: &Unit,
    stops: &Stops,
    signature: &Signature,
    omega: f64,
    alpha: f64,
    phases: &[f64],
) -> (f64, f64) {
    let flow = ForcedFlow::new(unit, omega);
    let cycle = flow.period() * signature.period() as f64;
    let g = stops.impact_map(unit);
    let mut g_hat = Matrix6::identity();
    g_hat.fixed_view_mut::<2, 2>(2, 2).copy_from(&g);
    let n = phases.len();
    let flight = |f: usize| {
        let end = if f + 1 < n { phases[f + 1] } else { 1.0 };
        let t = flow.transition((end - phases[f]) * cycle);
        let mut m = Matrix6::zeros();
        m.fixed_view_mut::<4, 4>(0, 0).copy_from(&t.homogeneous);
        m.fixed_view_mut::<4, 2>(0, 4).copy_from(&t.forced);
        m.fixed_view_mut::<2, 2>(4, 4).copy_from(&t.rotation);
        m
    };
    let mut pre = vec![flight(0)];
    for f in 1..n {
        let next = flight(f) * g_hat * pre[f - 1];
        pre.push(next);
    }
    let psi = g_hat * pre[n - 1];
    let k = Matrix4::identity() - psi.fixed_view::<4, 4>(0, 0);
    let p0 = Vector2::new(alpha.cos(), alpha.sin());
    let y1: Vector4<f64> = k.lu().solve(&(psi.fixed_view::<4, 2>(0, 4) * p0)).unwrap();
    let z1 = join(&y1, &p0);
    let r = Augmented::new(-1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
    let sides = signature.sides();
    let mut worst = (r.dot(&z1) - sides[0] as f64 * stops.gap).abs();
    for j in 1..n {
        worst = worst.max((r.dot(&(pre[j - 1] * z1)) - sides[j] as f64 * stops.gap).abs());
    }
    (worst, stops.gap.max(y1[0].abs()).max(y1[1].abs()))
}

/// A symmetric (`β = ½`) `+-` orbit of the paper unit at `omega` (the viable one if any), as
/// a signature orbit.
fn symmetric_start(omega: f64) -> SignatureOrbit {
    let signature = Signature::parse("+-", 1).unwrap();
    let mut symmetric: Vec<SignatureOrbit> =
        signature_orbits(&paper_unit(), &paper_stops(), omega, &signature)
            .into_iter()
            .filter(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9)
            .collect();
    symmetric.sort_by_key(|o| !o.viable);
    symmetric.into_iter().next().expect("a symmetric orbit")
}

/// The asymmetric `+-` orbit of the paper unit at ω = 2.9 with its side-2 impact at
/// `β ≈ 0.43` (found by the multi-start; viable).
fn asymmetric_start() -> SignatureOrbit {
    let signature = Signature::parse("+-", 1).unwrap();
    signature_orbits(&paper_unit(), &paper_stops(), 2.9, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.43).abs() < 0.01)
        .expect("the asymmetric orbit at β ≈ 0.43")
}

#[test]
fn symmetric_branch_points_solve_their_equations_and_match_the_symmetric_solver() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = symmetric_start(2.9);
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(2.5, 3.5)
    };
    let c = continue_orbit(&unit, &stops, &start, &settings).unwrap();
    let branch = &c.branches[0];
    assert!(branch.points.len() > 20, "{} points", branch.points.len());
    let bp: Vec<f64> = c
        .events
        .iter()
        .filter(|e| e.kind == EventKind::BranchPoint)
        .map(|e| e.omega)
        .collect();
    let mut compared = 0;
    for (i, p) in branch.points.iter().enumerate() {
        let (residual, scale) = contact_residual(
            &unit,
            &stops,
            &branch.signature,
            p.omega,
            p.alpha,
            &p.impact_phases,
        );
        assert!(
            residual <= CORRECTOR_ACCEPTANCE * scale,
            "ω = {}: residual {residual:e}",
            p.omega
        );
        assert!(p.residual <= CORRECTOR_ACCEPTANCE * scale);
        // Every fifth point away from the branch points (where the pitchfork's other branch
        // is within rounding of this one): the symmetric solver's orbit.
        if i % 5 != 0 || bp.iter().any(|w| (w - p.omega).abs() < 1e-3) {
            continue;
        }
        let symmetric = symmetric_orbits(&unit, &stops, p.omega).unwrap();
        let o = symmetric
            .iter()
            .min_by(|a, b| {
                wrap(a.alpha - p.alpha)
                    .abs()
                    .total_cmp(&wrap(b.alpha - p.alpha).abs())
            })
            .expect("a symmetric orbit at every ω of the branch");
        assert!(wrap(o.alpha - p.alpha).abs() < 1e-10, "ω = {}", p.omega);
        assert!((p.impact_phases[1] - 0.5).abs() < 1e-10, "ω = {}", p.omega);
        assert!(
            (o.outer_amplitude - p.outer_amplitude).abs() < 1e-10 * o.outer_amplitude,
            "ω = {}: {} vs {}",
            p.omega,
            o.outer_amplitude,
            p.outer_amplitude
        );
        assert_eq!(o.viable, p.viable, "ω = {}", p.omega);
        compared += 1;
    }
    assert!(compared > 5, "{compared} compared");
}

#[test]
fn branch_point_of_the_symmetric_orbit_is_where_the_half_period_gap_is_the_gap() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = symmetric_start(2.9);
    let c = continue_orbit(&unit, &stops, &start, &ContinuationSettings::new(2.8, 3.0)).unwrap();
    let event = c
        .events
        .iter()
        .find(|e| e.branch == 0 && e.kind == EventKind::BranchPoint)
        .expect("a branch point on the symmetric branch");
    // Independently: Δ*(½)(ω) = Δ by bisection on ω.
    let f = |w: f64| gap_for_beta(&unit, stops.restitution, w, 0.5).unwrap().gap - stops.gap;
    let (mut a, mut b) = (2.92, 2.925);
    assert!(f(a) * f(b) < 0.0, "bracket");
    while b - a > 1e-14 {
        let m = 0.5 * (a + b);
        if f(m) * f(a) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    let reference = 0.5 * (a + b);
    // Located by the regular defining system to rounding (see the bound of
    // `branch_point_among_crowded_events_is_found_from_either_side`).
    assert!(
        (event.omega - reference).abs() < 1e-13,
        "located {} vs Δ*(½) = Δ at {reference}",
        event.omega
    );
    // The asymmetric pair leaves there: a branch switched onto from this event, off β = ½,
    // on its own equations.
    let index = c.events.iter().position(|e| e == event).unwrap();
    let other = c
        .branches
        .iter()
        .find(|b| b.from_event == Some(index))
        .expect("the other branch followed");
    let asymmetric: Vec<&ContinuationPoint> = other
        .points
        .iter()
        .filter(|p| (p.impact_phases[1] - 0.5).abs() > 1e-3)
        .collect();
    assert!(!asymmetric.is_empty(), "the other branch leaves β = ½");
    for p in asymmetric {
        let (residual, scale) = contact_residual(
            &unit,
            &stops,
            &other.signature,
            p.omega,
            p.alpha,
            &p.impact_phases,
        );
        assert!(residual <= CORRECTOR_ACCEPTANCE * scale, "ω = {}", p.omega);
    }
}

#[test]
fn period_doubling_has_a_multiplier_at_minus_one_and_the_doubled_branch_is_followed() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let c = continue_orbit(&unit, &stops, &start, &ContinuationSettings::new(2.8, 3.0)).unwrap();
    let (index, event) = c
        .events
        .iter()
        .enumerate()
        .find(|(_, e)| e.branch == 0 && e.kind == EventKind::PeriodDoubling)
        .expect("a period doubling on the asymmetric branch");
    // The cycle solver's own multipliers at the located ω, from the event's orbit.
    let signature = &c.branches[0].signature;
    let mut guess = vec![event.point.alpha];
    guess.extend_from_slice(&event.point.impact_phases[1..]);
    let orbit = solve_signature(&unit, &stops, event.omega, signature, &guess).unwrap();
    let nearest = orbit
        .floquet_multipliers
        .iter()
        .map(|m| (m + 1.0).norm())
        .fold(f64::INFINITY, f64::min);
    assert!(
        nearest < 1e-8,
        "|μ + 1| = {nearest:e} at ω = {}",
        event.omega
    );
    let doubled = event.signature_after.as_ref().unwrap();
    assert_eq!((doubled.to_string(), doubled.period()), ("+-+-".into(), 2));
    let branch = c
        .branches
        .iter()
        .find(|b| b.from_event == Some(index))
        .expect("the doubled branch followed");
    assert_eq!(&branch.signature, doubled);
    // Off the doubling the two halves of the cycle differ: a genuine period-2 orbit.
    let split = branch.points.iter().any(|p| {
        let ph = &p.impact_phases;
        (ph[2] - 0.5).abs() > 1e-4 || (ph[3] - ph[2] - ph[1]).abs() > 1e-4
    });
    assert!(
        split,
        "the doubled branch is the period-1 orbit traversed twice"
    );
    for p in &branch.points {
        let (residual, scale) =
            contact_residual(&unit, &stops, doubled, p.omega, p.alpha, &p.impact_phases);
        assert!(residual <= CORRECTOR_ACCEPTANCE * scale, "ω = {}", p.omega);
    }
}

#[test]
fn grazing_touches_the_stop_and_the_new_signature_is_followed() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let c = continue_orbit(&unit, &stops, &start, &ContinuationSettings::new(2.5, 3.0)).unwrap();
    let (index, event) = c
        .events
        .iter()
        .enumerate()
        .find(|(_, e)| e.branch == 0 && e.kind == EventKind::Grazing)
        .expect("a grazing on the asymmetric branch");
    // The orbit at the located ω by the cycle solver, and the rigorous interior extrema of
    // r along the flight that holds the graze.
    let signature = &c.branches[0].signature;
    let mut guess = vec![event.point.alpha];
    guess.extend_from_slice(&event.point.impact_phases[1..]);
    let orbit = solve_signature(&unit, &stops, event.omega, signature, &guess).unwrap();
    let phase = event.phase.unwrap();
    let n = orbit.impact_phases.len();
    let f = (0..n)
        .rev()
        .find(|&f| orbit.impact_phases[f] <= phase)
        .unwrap();
    let end = if f + 1 < n {
        orbit.impact_phases[f + 1]
    } else {
        1.0
    };
    let flow = ForcedFlow::new(&unit, event.omega);
    let cycle = flow.period() * signature.period() as f64;
    let before = orbit.states_before_impacts[f];
    let v = stops.impact_map(&unit) * Vector2::new(before[2], before[3]);
    let after = Vector4::new(before[0], before[1], v[0], v[1]);
    let p = orbit.impact_phases[f] * cycle;
    let alpha = orbit.alpha + event.omega * p;
    let start_state = join(&after, &Vector2::new(alpha.cos(), alpha.sin()));
    let r = Augmented::new(-1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
    let ext = flow.critical_extrema(&start_state, (end - orbit.impact_phases[f]) * cycle, &[r])[0];
    let extremum = ext.max.max(-ext.min);
    assert!(
        (extremum - stops.gap).abs() < 1e-10 * stops.gap,
        "interior extremum {extremum} vs gap {} at ω = {}",
        stops.gap,
        event.omega
    );
    // The branch with the extra impact.
    let after_signature = event.signature_after.as_ref().unwrap();
    assert_eq!(after_signature.impacts(), signature.impacts() + 1);
    let branch = c
        .branches
        .iter()
        .find(|b| b.from_event == Some(index))
        .expect("the new signature followed");
    assert_eq!(&branch.signature, after_signature);
    assert!(branch.points.len() > 2, "{} points", branch.points.len());
    assert!(branch.points.iter().any(|p| p.viable));
    for p in &branch.points {
        let (residual, scale) = contact_residual(
            &unit,
            &stops,
            after_signature,
            p.omega,
            p.alpha,
            &p.impact_phases,
        );
        assert!(residual <= CORRECTOR_ACCEPTANCE * scale, "ω = {}", p.omega);
    }
}

#[test]
fn fold_turns_the_branch_with_a_multiplier_at_one() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = symmetric_start(0.75);
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(0.6, 0.8)
    };
    let c = continue_orbit(&unit, &stops, &start, &settings).unwrap();
    let event = c
        .events
        .iter()
        .find(|e| e.kind == EventKind::Fold)
        .expect("a fold on the symmetric branch");
    // Located to 1e-13 of a step in the chord fraction: dω/ds vanishes to that order times
    // the curvature, and the critical multiplier differs from 1 by the same order times its
    // rate along the branch; 1e-9 leaves three orders for both.
    assert!(
        event.point.domega_ds.abs() < 1e-9,
        "{}",
        event.point.domega_ds
    );
    let nearest = event
        .point
        .floquet_multipliers
        .iter()
        .map(|m| (m - 1.0).norm())
        .fold(f64::INFINITY, f64::min);
    assert!(nearest < 1e-9, "|μ − 1| = {nearest:e}");
    // The branch does turn: points on both sides of the fold lie above its ω.
    let branch = &c.branches[0];
    assert!(branch.points.iter().all(|p| p.omega >= event.omega - 1e-12));
}

#[test]
fn bad_settings_are_refused_with_the_field_named() {
    let message = |s: ContinuationSettings| s.validate().unwrap_err().to_string();
    let base = ContinuationSettings::default();
    assert!(base.validate().is_ok());
    let m = message(ContinuationSettings {
        omega_min: -1.0,
        ..base
    });
    assert!(m.contains("--omega-min") && m.contains("> 0"), "{m}");
    let m = message(ContinuationSettings {
        omega_max: 0.05,
        ..base
    });
    assert!(m.contains("--omega-max"), "{m}");
    let m = message(ContinuationSettings {
        min_step: f64::NAN,
        ..base
    });
    assert!(m.contains("continuation.min_step"), "{m}");
    let m = message(ContinuationSettings {
        max_step: 1e-12,
        ..base
    });
    assert!(m.contains("continuation.max_step"), "{m}");
    let m = message(ContinuationSettings {
        initial_step: 1.0,
        ..base
    });
    assert!(m.contains("continuation.initial_step"), "{m}");
    let m = message(ContinuationSettings {
        max_points_per_branch: 1,
        ..base
    });
    assert!(m.contains("continuation.max_points_per_branch"), "{m}");
    let m = message(ContinuationSettings {
        max_branches: 0,
        ..base
    });
    assert!(m.contains("continuation.max_branches"), "{m}");
    // And through continue_orbit, with the start outside the band.
    let start = symmetric_start(2.9);
    let err = continue_orbit(
        &paper_unit(),
        &paper_stops(),
        &start,
        &ContinuationSettings {
            omega_min: -1.0,
            ..base
        },
    )
    .unwrap_err();
    assert!(err.to_string().contains("--omega-min"));
    let err = continue_orbit(
        &paper_unit(),
        &paper_stops(),
        &start,
        &ContinuationSettings::new(0.5, 2.0),
    )
    .unwrap_err();
    assert!(
        matches!(err, ContinuationError::StartOutside { .. }),
        "{err}"
    );
}

#[test]
fn event_and_end_names() {
    let names: Vec<&str> = [
        EventKind::Fold,
        EventKind::BranchPoint,
        EventKind::PeriodDoubling,
        EventKind::NeimarkSacker,
        EventKind::Grazing,
        EventKind::VanishingImpact,
    ]
    .iter()
    .map(|k| k.name())
    .collect();
    assert_eq!(
        names,
        [
            "fold",
            "branch-point",
            "period-doubling",
            "neimark-sacker",
            "grazing",
            "vanishing-impact"
        ]
    );
    assert_eq!(EndReason::OmegaMax.name(), "omega-max");
    assert_eq!(EndReason::FlightMerged.name(), "flight-merged");
}

/// The branch cap lists the seeds still queued rather than dropping them without a word. With
/// one branch allowed, the symmetric branch through ω = 2.9 is followed and every branch it would
/// switch onto is listed, without points, both ends `branch-cap`: as many as leave it when
/// the cap allows them.
#[test]
fn branches_past_the_cap_are_listed_with_their_reason() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = symmetric_start(2.9);
    let capped = ContinuationSettings {
        max_branches: 1,
        max_depth: 1,
        ..ContinuationSettings::new(2.8, 3.0)
    };
    let c = continue_orbit(&unit, &stops, &start, &capped).unwrap();
    assert!(!c.branches[0].points.is_empty());
    let listed: Vec<&Branch> = c.branches.iter().skip(1).collect();
    assert!(!listed.is_empty(), "the branch point's branch is queued");
    for b in &listed {
        assert!(
            b.points.is_empty(),
            "branch {} followed past the cap",
            b.index
        );
        let reasons: Vec<EndReason> = c
            .ends
            .iter()
            .filter(|e| e.branch == b.index)
            .map(|e| e.reason)
            .collect();
        assert_eq!(reasons, [EndReason::BranchCap; 2], "branch {}", b.index);
    }
    assert_eq!(EndReason::BranchCap.name(), "branch-cap");
    let free = ContinuationSettings {
        max_depth: 1,
        ..ContinuationSettings::new(2.8, 3.0)
    };
    let all = continue_orbit(&unit, &stops, &start, &free).unwrap();
    let from_start = all
        .branches
        .iter()
        .filter(|b| b.from_event.is_some_and(|e| all.events[e].branch == 0))
        .count();
    assert_eq!(listed.len(), from_start);
}

#[test]
fn neimark_sacker_puts_a_complex_pair_on_the_unit_circle() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = symmetric_start(2.9);
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(2.9, 3.5)
    };
    let c = continue_orbit(&unit, &stops, &start, &settings).unwrap();
    let event = c
        .events
        .iter()
        .find(|e| e.kind == EventKind::NeimarkSacker)
        .expect("a Neimark–Sacker event on the symmetric branch");
    // The cycle solver's own multipliers at the located ω.
    let mut guess = vec![event.point.alpha];
    guess.extend_from_slice(&event.point.impact_phases[1..]);
    let orbit = solve_signature(&unit, &stops, event.omega, &start.signature, &guess).unwrap();
    let on_circle = orbit
        .floquet_multipliers
        .iter()
        .filter(|m| m.im.abs() > 1e-6)
        .map(|m| (m.norm() - 1.0).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(
        on_circle < 1e-8,
        "||μ| − 1| = {on_circle:e} at ω = {}",
        event.omega
    );
}

#[test]
fn vanishing_impact_has_zero_relative_velocity() {
    let (unit, stops) = (paper_unit(), paper_stops());
    // The other symmetric orbit at ω = 3.5 (the one that is not a motion).
    let signature = Signature::parse("+-", 1).unwrap();
    let start = signature_orbits(&unit, &stops, 3.5, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9 && !o.viable)
        .expect("a non-viable symmetric orbit at 3.5");
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(3.0, 3.7)
    };
    let c = continue_orbit(&unit, &stops, &start, &settings).unwrap();
    let event = c
        .events
        .iter()
        .find(|e| e.kind == EventKind::VanishingImpact)
        .expect("a vanishing impact on the symmetric branch");
    let mut guess = vec![event.point.alpha];
    guess.extend_from_slice(&event.point.impact_phases[1..]);
    let orbit = solve_signature(&unit, &stops, event.omega, &start.signature, &guess).unwrap();
    let phase = event.phase.unwrap();
    let j = orbit
        .impact_phases
        .iter()
        .position(|p| (p - phase).abs() < 1e-9)
        .expect("the impact of the event");
    let x = orbit.states_before_impacts[j];
    // Relative to the velocity scale ω Δ of the motion.
    let rdot = (x[3] - x[2]) / (event.omega * stops.gap);
    assert!(
        rdot.abs() < 1e-9,
        "ṙ⁻/(ωΔ) = {rdot:e} at ω = {}",
        event.omega
    );
    // On one side the impact is approached from outside, on the other from inside.
    let approach = |w: f64| {
        let p = c.branches[0]
            .points
            .iter()
            .min_by(|a, b| (a.omega - w).abs().total_cmp(&(b.omega - w).abs()))
            .unwrap();
        let mut guess = vec![p.alpha];
        guess.extend_from_slice(&p.impact_phases[1..]);
        let o = solve_signature(&unit, &stops, p.omega, &start.signature, &guess).unwrap();
        let x = o.states_before_impacts[j];
        signature.sides()[j] as f64 * (x[3] - x[2])
    };
    assert!(approach(event.omega - 0.05) * approach(event.omega + 0.05) < 0.0);
}

/// `ω` where the symmetric orbit's half-period gap is the gap (`Δ*(½)(ω) = Δ`), by bisection
/// within `[a, b]`: where the asymmetric pair leaves the symmetric orbit.
fn symmetric_branch_point(a: f64, b: f64) -> f64 {
    let (unit, stops) = (paper_unit(), paper_stops());
    let f = |w: f64| gap_for_beta(&unit, stops.restitution, w, 0.5).unwrap().gap - stops.gap;
    let (mut a, mut b) = (a, b);
    assert!(f(a) * f(b) < 0.0, "bracket");
    while b - a > 1e-14 {
        let m = 0.5 * (a + b);
        if f(m) * f(a) > 0.0 {
            a = m;
        } else {
            b = m;
        }
    }
    0.5 * (a + b)
}

/// Started 0.02 below the symmetric orbit's branch point at 2.1925686 rad/s (the paper
/// scene), the continuation meets grazings, a Neimark–Sacker, a vanishing impact, a period
/// doubling and a fold within 1e-3 of it, and a fold in the same step could mask the branch
/// point. From either side it is found, to 1e-13 of `Δ*(½) = Δ`.
#[test]
fn branch_point_among_crowded_events_is_found_from_either_side() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let reference = symmetric_branch_point(2.19, 2.195);
    let signature = Signature::parse("+-", 1).unwrap();
    // Below, the asymmetric orbit that reaches the symmetric one there (β ≈ 0.666); above,
    // the symmetric orbit it reaches (α ≈ 3.12).
    let below = signature_orbits(&unit, &stops, reference - 0.02, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.666).abs() < 0.01)
        .expect("the asymmetric orbit at β ≈ 0.666");
    let above = signature_orbits(&unit, &stops, reference + 0.02, &signature)
        .into_iter()
        .find(|o| (o.impact_phases[1] - 0.5).abs() < 1e-9 && o.alpha.abs() > 3.0)
        .expect("the symmetric orbit at α ≈ 3.12");
    // Both sides locate it by the regular defining system (crate::branch_point), solved to
    // rounding: Newton stops at a step of 1e-14 of the unknowns' size (about 3 here, α ≈ 3.12),
    // and the reference is bisected to 1e-14, so 1e-13 bounds the sum with room for the
    // rounding of the two different sets of equations. Measured: 2.2e-15 from below, under
    // 1e-15 from above. (By bisection of the test function alone, before: 1.13e-8 from below,
    // under 1e-8 from above: the corrected points near a branch point carry errors of √ε.)
    for start in [below, above] {
        let bound = 1e-13;
        let start_omega = start.omega;
        let settings = ContinuationSettings {
            follow_switches: false,
            ..ContinuationSettings::new(2.15, 2.24)
        };
        let c = continue_orbit(&unit, &stops, &start, &settings).unwrap();
        let nearest = c
            .events
            .iter()
            .filter(|e| e.kind == EventKind::BranchPoint)
            .map(|e| (e.omega - reference).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(
            nearest < bound,
            "from ω = {start_omega}: nearest branch point {nearest:e} from {reference}; events {:?}",
            c.events
                .iter()
                .map(|e| (e.kind, e.omega))
                .collect::<Vec<_>>()
        );
    }
}

/// The switching depth of each branch: 0 for the start's, one more than the branch its
/// event lies on for a switched one.
fn depths(c: &Continuation) -> Vec<usize> {
    let mut depth = vec![0; c.branches.len()];
    for b in &c.branches {
        if let Some(e) = b.from_event {
            depth[b.index] = depth[c.events[e].branch] + 1;
        }
    }
    depth
}

/// Each branch followed once (not a branch and its half-period mirror image as two, nor a
/// period-doubled branch round twice), each event listed once.
/// An event and its image have the same kind, frequency and amplitude: no two events may.
#[test]
fn each_event_is_listed_once_and_images_are_not_followed() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let c = continue_orbit(&unit, &stops, &start, &ContinuationSettings::new(2.8, 3.0)).unwrap();
    for (i, a) in c.events.iter().enumerate() {
        for b in &c.events[i + 1..] {
            // (A branch of another signature may meet the same orbit: the period-4 branch
            // born at a grazing of the doubled period-2 orbit grazes where that orbit does.)
            let (sa, sb) = (
                &c.branches[a.branch].signature,
                &c.branches[b.branch].signature,
            );
            let same = a.kind == b.kind
                && (sa.impacts(), sa.period()) == (sb.impacts(), sb.period())
                && (a.omega - b.omega).abs() < 1e-9
                && (a.point.outer_amplitude - b.point.outer_amplitude).abs() < 1e-9;
            assert!(
                !same,
                "{:?} at ω = {} on branches {} and {}; {:?}",
                a.kind,
                a.omega,
                a.branch,
                b.branch,
                c.branches
                    .iter()
                    .map(|b| (
                        b.index,
                        b.signature.to_string(),
                        b.from_event,
                        b.points.len()
                    ))
                    .collect::<Vec<_>>()
            );
        }
    }
    // The doubled branch is its own image one forcing period later: it ends where it starts
    // to retrace itself, not after going round twice.
    let doubled = c
        .branches
        .iter()
        .find(|b| {
            b.from_event
                .is_some_and(|e| c.events[e].kind == EventKind::PeriodDoubling)
        })
        .expect("a doubled branch");
    let joins = c
        .ends
        .iter()
        .filter(|e| e.branch == doubled.index && e.reason == EndReason::Joins)
        .count();
    assert!(joins >= 1, "{:?}", c.ends);
    // Every depth-cut or joined end names what it should.
    for e in &c.ends {
        assert_eq!(e.joins.is_some(), e.reason == EndReason::Joins, "{e:?}");
    }
}

#[test]
fn switching_stops_at_the_depth_and_says_where() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = asymmetric_start();
    let settings = ContinuationSettings {
        max_depth: 1,
        ..ContinuationSettings::new(2.8, 3.0)
    };
    let c = continue_orbit(&unit, &stops, &start, &settings).unwrap();
    let depth = depths(&c);
    let mut cut = 0;
    for b in &c.branches {
        let reasons: Vec<EndReason> = c
            .ends
            .iter()
            .filter(|e| e.branch == b.index)
            .map(|e| e.reason)
            .collect();
        assert_eq!(reasons.len(), 2, "branch {}", b.index);
        if reasons.contains(&EndReason::MaxDepth) {
            cut += 1;
            assert!(
                b.points.is_empty() && depth[b.index] == 2,
                "branch {}",
                b.index
            );
            let event = &c.events[b.from_event.unwrap()];
            assert_eq!(Some(&b.signature), event.signature_after.as_ref());
        } else {
            assert!(
                depth[b.index] <= 1,
                "branch {} at depth {}",
                b.index,
                depth[b.index]
            );
        }
    }
    assert!(cut > 0, "the depth cut something");
}

/// The isola of `+++---` orbits of the paper unit near ω = 1.46 (found by the study of
/// `cargo xtask figures`, whose continuation followed it from a simulated cycle), started at
/// one of its points.
fn isola_start() -> SignatureOrbit {
    let signature = Signature::parse("+++---", 1).unwrap();
    let guess = [
        2.724777494928146,
        0.10241138075153798,
        0.39196406770200254,
        0.49999999999999994,
        0.6024113807515379,
        0.8919640677020025,
    ];
    solve_signature(
        &paper_unit(),
        &paper_stops(),
        1.461986389643092,
        &signature,
        &guess,
    )
    .expect("the isola's point converges")
}

/// The length of `branch` in `X = (α, φ₂ … φₙ, ω)` (`α` modulo 2π): the sum of its chords.
fn arc_length(branch: &Branch) -> f64 {
    let xs: Vec<Vec<f64>> = branch
        .points
        .iter()
        .map(|p| [&[p.alpha][..], &p.impact_phases[1..], &[p.omega]].concat())
        .collect();
    common::chord_length(&xs)
}

#[test]
fn a_loop_longer_than_one_direction_is_followed_once_from_both_ways() {
    // A closed loop longer than the first direction's half of the points (the study's
    // continuation in `cargo xtask figures` has such loops; the example `branch_overlap`
    // checks the study) is followed once: the other direction stops where the first stopped
    // rather than going round the other way until its own cap.
    let (unit, stops) = (paper_unit(), paper_stops());
    let start = isola_start();
    let single = |points: usize| ContinuationSettings {
        max_branches: 1,
        max_points_per_branch: points,
        ..ContinuationSettings::new(0.1, 4.0)
    };
    // With room for the whole loop one way, it closes through its seed.
    let whole = continue_orbit(&unit, &stops, &start, &single(10_000)).unwrap();
    let loop_points = whole.branches[0].points.len();
    let reasons = |c: &Continuation| -> Vec<EndReason> {
        c.ends
            .iter()
            .filter(|e| e.branch == 0)
            .map(|e| e.reason)
            .collect()
    };
    assert_eq!(reasons(&whole), [EndReason::ClosedLoop; 2]);
    assert!(loop_points > 100, "{loop_points} points");
    // With a cap of 1.5 loops, each way follows more than half of it before its half of the
    // points runs out: the second way ends where the first stopped.
    let halves = continue_orbit(&unit, &stops, &start, &single(loop_points * 3 / 2)).unwrap();
    let branch = &halves.branches[0];
    assert_eq!(reasons(&halves), [EndReason::ClosedLoop; 2]);
    // Once round: the same length to within the step that closes it (not the cap's 1.5
    // loops).
    let (once, followed) = (arc_length(&whole.branches[0]), arc_length(branch));
    assert!(
        (followed - once).abs() < 0.02 * once,
        "{followed} followed for a loop of {once} ({} points, {loop_points} one way)",
        branch.points.len()
    );
}

#[test]
fn a_branch_of_more_impacts_than_the_search_takes_is_recognised_when_run_onto() {
    // The representations of a label of more than 16 impacts (a branch seeded from a
    // simulated cycle, as in the study's continuation of `cargo xtask figures`) are formed
    // under a simulated cycle's caps: under the search's they would not exist, no point or
    // event on such a branch would be recognised, and a branch switched back onto one would
    // be followed again in full.
    let (unit, stops) = (paper_unit(), paper_stops());
    // A period-2 orbit of 40 impacts on an isola near ω = 1.45, as the study found it.
    let tens = [[1i8; 10], [-1; 10]].concat();
    let long = Signature::from_cycle(&[&tens[..], &tens[..]].concat(), 2).unwrap();
    assert!(!long.is_searchable());
    let quarter = [
        0.0,
        0.03850093307865421,
        0.06581822146542309,
        0.08742717474634559,
        0.10537514718938334,
        0.12074280287672551,
        0.13422091420805016,
        0.146326293252703,
        0.15752626885193363,
        0.16839223534839093,
    ];
    let mut guess = vec![2.096678627599093];
    for k in 0..4 {
        guess.extend(quarter.iter().map(|p| p + 0.25 * k as f64));
    }
    guess.remove(1); // the first impact's phase is 0, not an unknown
    let omega = 1.450963320832921;
    let start = solve_signature(&unit, &stops, omega, &long, &guess)
        .expect("the 40-impact orbit converges");
    let settings = ContinuationSettings {
        max_branches: 1,
        max_points_per_branch: 200,
        ..ContinuationSettings::new(0.1, 4.0)
    };
    let mut out = Continuation::default();
    assert!(continue_orbit_after(&unit, &stops, &start, &settings, &mut out).unwrap());
    let branches = out.branches.len();
    // Another point of the branch just followed, started again, lies on it.
    let points = &out.branches[0].points;
    let again = &points[points.len() / 3];
    let x: Vec<f64> = [&[again.alpha][..], &again.impact_phases[1..]].concat();
    let restart = solve_signature(&unit, &stops, again.omega, &long, &x).unwrap();
    assert!(
        !continue_orbit_after(&unit, &stops, &restart, &settings, &mut out).unwrap(),
        "a start on the branch just followed is followed again"
    );
    assert_eq!(out.branches.len(), branches);
}
