//! Orbits of any impact signature: agreement with the symmetric solver, the cycle's own
//! equations propagated independently, energy balance, Liouville, and refused inputs.

use nalgebra::{Complex, Vector2, Vector4};
use rattle_analytic::test_models::{
    damped_paper_unit, paper_stops, paper_unit, symmetric_identities,
};
use rattle_analytic::ForcedFlow;
use rattle_analytic::{
    signature_orbits, signature_orbits_on_grid, solve_signature, symmetric_orbits, OrbitError,
    Side, Signature, SignatureOrbit, Stops, Unit, Violation,
};

/// Agreement asked of two exact solvers of the same orbit.
const AGREEMENT: f64 = 1e-12;

fn wrap(a: f64) -> f64 {
    let w = a.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// Offset of the Newton guess from the symmetric orbit, in radians of `α` and in fractions
/// of the period: well outside rounding, well inside the basin.
const PERTURBATION: f64 = 1e-3;

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

#[test]
fn plus_minus_over_one_period_is_the_symmetric_orbit() {
    let signature = Signature::parse("-+", 1).unwrap();
    assert_eq!(signature.to_string(), "+-");
    let stops = paper_stops();
    let mut compared = 0;
    for unit in [paper_unit(), damped_paper_unit()] {
        for omega in [0.8, 1.2, 2.0, 2.6, 3.3] {
            let symmetric = symmetric_orbits(&unit, &stops, omega).unwrap();
            let found = signature_orbits(&unit, &stops, omega, &signature);
            for o in &symmetric {
                // Newton from a perturbed guess, so that it has work to do.
                let guess = [o.alpha + PERTURBATION, 0.5 - PERTURBATION];
                let g = solve_signature(&unit, &stops, omega, &signature, &guess)
                    .unwrap_or_else(|e| panic!("ω = {omega}: {e}"));
                let scale = o.state_after_impact.amax().max(1.0);
                let checks = [
                    ("alpha", wrap(g.alpha - o.alpha).abs()),
                    ("beta", (g.impact_phases[1] - 0.5).abs()),
                    (
                        "after",
                        (g.state_after_impact - o.state_after_impact).amax() / scale,
                    ),
                    (
                        "before 1",
                        (g.states_before_impacts[0] - o.state_before_impact).amax() / scale,
                    ),
                    (
                        "before 2",
                        (g.states_before_impacts[1] - o.state_before_side2).amax() / scale,
                    ),
                    (
                        "amplitude",
                        (g.outer_amplitude - o.outer_amplitude).abs() / o.outer_amplitude,
                    ),
                    (
                        "multipliers",
                        multiplier_distance(&g.floquet_multipliers, &o.floquet_multipliers)
                            / o.floquet_multipliers
                                .iter()
                                .map(|m| m.norm())
                                .fold(1.0, f64::max),
                    ),
                ];
                for (name, d) in checks {
                    assert!(
                        d <= AGREEMENT,
                        "ω = {omega}, α = {}: {name} differs by {d:e}",
                        o.alpha
                    );
                }
                assert_eq!((g.viable, g.stable), (o.viable, o.stable), "ω = {omega}");
                assert!(g.newton_iterations > 0);
                // The multi-start finds it too, if it is a motion (a non-viable solution may
                // have too small a basin for the grid: see `signature_orbits`).
                assert!(
                    !o.viable
                        || found.iter().any(|f| wrap(f.alpha - o.alpha).abs() < 1e-10
                            && (f.impact_phases[1] - 0.5).abs() < 1e-10),
                    "ω = {omega}: multi-start missed α = {}",
                    o.alpha
                );
                compared += 1;
            }
        }
    }
    assert!(compared >= 12, "only {compared} symmetric orbits compared");
}

/// Propagates the orbit flight by flight with the flow and the impact map, checking each
/// contact and periodicity; returns the largest defect relative to the motion's size.
fn own_equations_defect(unit: &Unit, stops: &Stops, o: &SignatureOrbit) -> f64 {
    let flow = ForcedFlow::new(unit, o.omega);
    let cycle = flow.period() * o.period as f64;
    let g = stops.impact_map(unit);
    let sides = o.signature.sides();
    let n = sides.len();
    let scale = o.state_after_impact.amax().max(stops.gap);
    let mut x = o.state_after_impact;
    let mut p = Vector2::new(o.alpha.cos(), o.alpha.sin());
    let mut defect: f64 = 0.0;
    for j in 0..n {
        let end = if j + 1 < n {
            o.impact_phases[j + 1]
        } else {
            1.0
        };
        let (x1, p1) = flow
            .transition((end - o.impact_phases[j]) * cycle)
            .apply(&x, &p);
        let next = (j + 1) % n;
        defect = defect.max((x1[1] - x1[0] - sides[next] as f64 * stops.gap).abs() / scale);
        defect = defect.max((x1 - o.states_before_impacts[next]).amax() / scale);
        let v = g * Vector2::new(x1[2], x1[3]);
        x = Vector4::new(x1[0], x1[1], v[0], v[1]);
        p = p1;
    }
    // Periodicity: back to the state after the first impact, and to the same forcing phase.
    defect = defect.max((x - o.state_after_impact).amax() / scale);
    defect.max((p - Vector2::new(o.alpha.cos(), o.alpha.sin())).amax())
}

/// `r(t)` of the orbit at time `t` after its first impact, restarting the exact flow from the
/// last impact before `t`.
fn relative_displacement_at(unit: &Unit, stops: &Stops, o: &SignatureOrbit, t: f64) -> f64 {
    let flow = ForcedFlow::new(unit, o.omega);
    let cycle = flow.period() * o.period as f64;
    let j = o
        .impact_phases
        .iter()
        .rposition(|&f| f * cycle <= t)
        .unwrap();
    let t0 = o.impact_phases[j] * cycle;
    let before = o.states_before_impacts[j];
    let v = stops.impact_map(unit) * Vector2::new(before[2], before[3]);
    let after = Vector4::new(before[0], before[1], v[0], v[1]);
    let p0 = Vector2::new(o.alpha.cos(), o.alpha.sin());
    let (_, pj) = flow.transition(t0).apply(&Vector4::zeros(), &p0);
    let (x, _) = flow.transition(t - t0).apply(&after, &pj);
    x[1] - x[0]
}

#[test]
fn reported_excursions_beyond_a_stop_are_real() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let mut extra = 0;
    for text in ["++--", "+-+-"] {
        let signature = Signature::parse(text, 1).unwrap();
        for o in signature_orbits(&unit, &stops, 1.5, &signature) {
            for v in &o.violations {
                let (side, time, excess) = match *v {
                    Violation::ExtraImpact { side, time, excess } => {
                        extra += 1;
                        (side, time, excess)
                    }
                    Violation::Penetration { side, time, excess } => (side, time, excess),
                    Violation::WrongApproach { .. } => continue,
                };
                let r = relative_displacement_at(&unit, &stops, &o, time);
                let beyond = if side == Side::One {
                    r - stops.gap
                } else {
                    -stops.gap - r
                };
                assert!(
                    (beyond - excess).abs() < 1e-9 && excess > 0.0,
                    "{v:?}: r = {r}"
                );
            }
        }
    }
    assert!(extra > 0, "no extra impact reported");
}

#[test]
fn four_impact_orbits_satisfy_their_own_equations() {
    let (unit, stops) = (paper_unit(), paper_stops());
    let signature = Signature::parse("+--+", 1).unwrap();
    assert_eq!(signature.to_string(), "++--");
    // At ω = 1.2 every ++-- orbit is non-viable; at ω = 2.0 two are viable (both unstable).
    let orbits = signature_orbits(&unit, &stops, 1.2, &signature);
    assert!(orbits.len() >= 10, "{} orbits", orbits.len());
    let at_two = signature_orbits(&unit, &stops, 2.0, &signature);
    let viable: Vec<&SignatureOrbit> = at_two.iter().filter(|o| o.viable).collect();
    assert_eq!(viable.len(), 2, "viable ++-- orbits at ω = 2.0");
    for o in orbits.iter().chain(&at_two) {
        let d = own_equations_defect(&unit, &stops, o);
        assert!(d <= AGREEMENT, "α = {}: defect {d:e}", o.alpha);
        assert_eq!(o.impact_phases[0], 0.0);
        assert!(o.impact_phases.windows(2).all(|w| w[0] < w[1]));
    }
    // A viable orbit stays between the stops on a dense scan of every flight, and each
    // impact is approached from inside.
    let flow = ForcedFlow::new(&unit, 2.0);
    for o in viable {
        for (j, x) in o.states_before_impacts.iter().enumerate() {
            assert!(o.signature.sides()[j] as f64 * (x[3] - x[2]) > 0.0);
        }
        let p0 = Vector2::new(o.alpha.cos(), o.alpha.sin());
        let samples = 4000;
        for k in 1..samples {
            let t = flow.period() * k as f64 / samples as f64;
            // Restart from the last impact before t.
            let j = o
                .impact_phases
                .iter()
                .rposition(|&f| f * flow.period() <= t)
                .unwrap();
            let t0 = o.impact_phases[j] * flow.period();
            let g = stops.impact_map(&unit);
            let before = o.states_before_impacts[j];
            let v = g * Vector2::new(before[2], before[3]);
            let after = Vector4::new(before[0], before[1], v[0], v[1]);
            let (_, pj) = flow.transition(t0).apply(&Vector4::zeros(), &p0);
            let (x, _) = flow.transition(t - t0).apply(&after, &pj);
            assert!((x[1] - x[0]).abs() <= stops.gap * (1.0 + 1e-9), "t = {t}");
        }
    }
}

#[test]
fn cycle_energy_balances_and_monodromy_obeys_liouville() {
    let stops = paper_stops();
    let mut checked = 0;
    for (unit, identities) in symmetric_identities() {
        for (text, period) in [("+-", 1), ("++--", 1), ("+-+-", 1), ("+-", 2)] {
            let signature = Signature::parse(text, period).unwrap();
            for omega in [2.0, 2.5] {
                for o in signature_orbits(&unit, &stops, omega, &signature) {
                    assert!(
                        o.energy_residual <= 1e-10,
                        "{text}/{period} ω = {omega}: energy residual {:e} ({:?})",
                        o.energy_residual,
                        o.energy
                    );
                    assert!(o.energy.impact_losses > 0.0);
                    let n = signature.impacts() as i32;
                    let cycle = std::f64::consts::TAU / omega * period as f64;
                    let want =
                        stops.restitution.powi(2 * n) * (identities.system_trace * cycle).exp();
                    let got = o.monodromy.determinant();
                    // The saltation matrices grow like 1/|ṙ⁻|; measure against their size.
                    let size = o.monodromy.amax().powi(4).max(1.0);
                    assert!(
                        (got - want).abs() <= 1e-11 * size,
                        "{text}/{period} ω = {omega}: det {got} vs {want}"
                    );
                    assert!(o.newton_iterations <= rattle_analytic::NEWTON_ITERATIONS + 1);
                    checked += 1;
                }
            }
        }
    }
    assert!(checked > 20, "{checked}");
}

#[test]
fn refining_the_grid_finds_no_other_viable_orbit() {
    let (unit, stops) = (paper_unit(), paper_stops());
    for (text, period, omega) in [("+-", 1, 2.0), ("+-", 2, 1.2), ("++--", 1, 2.0)] {
        let signature = Signature::parse(text, period).unwrap();
        {
            let coarse = signature_orbits(&unit, &stops, omega, &signature);
            let fine = signature_orbits_on_grid(&unit, &stops, omega, &signature, 48);
            assert!(fine.iter().any(|o| o.viable) || text != "++--");
            for f in fine.iter().filter(|o| o.viable) {
                assert!(
                    coarse.iter().any(|c| wrap(c.alpha - f.alpha).abs() < 1e-8),
                    "{text} ω = {omega}: the default grid missed viable α = {}",
                    f.alpha
                );
            }
        }
    }
}

#[test]
fn bad_inputs_are_refused() {
    assert!(Signature::parse("+ -", 1)
        .unwrap_err()
        .to_string()
        .contains("--signature"));
    assert!(Signature::parse("+-", 0)
        .unwrap_err()
        .to_string()
        .contains("--period"));
    let s = Signature::parse("++--", 1).unwrap();
    let (unit, stops) = (paper_unit(), paper_stops());
    for guess in [
        &[0.1, 0.2][..],
        &[0.1, 0.5, 0.3, 0.7],
        &[0.1, 0.2, 0.5, 1.2],
        &[f64::NAN, 0.1, 0.2, 0.3],
    ] {
        assert!(matches!(
            solve_signature(&unit, &stops, 1.2, &s, guess),
            Err(OrbitError::InvalidGuess { .. })
        ));
    }
    for omega in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            solve_signature(&unit, &stops, omega, &s, &[0.1, 0.2, 0.5, 0.7]),
            Err(OrbitError::InvalidFrequency { .. })
        ));
        assert!(signature_orbits(&unit, &stops, omega, &s).is_empty());
    }
    // A very low frequency coarsens the grid to MAX_TUPLES tuples instead of exploding.
    let start = std::time::Instant::now();
    let _ = signature_orbits(&unit, &stops, 0.05, &Signature::parse("+-+-", 2).unwrap());
    assert!(start.elapsed().as_secs_f64() < 60.0);
}
