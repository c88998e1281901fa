//! The simulator's own Newton: the tangent flow against closed forms, the saltation
//! determinant, Newton on the stroboscopic map, and the errors it must give.

use nalgebra::{Complex, DMatrix, DVector, Matrix4};
use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
use rattle_event_driven::*;

/// `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` of the paper unit (`m_o = 2`, `m_i = 1`, `k_o = 6`,
/// `k_i = 3`), by hand.
fn system_matrix(damping: (f64, f64)) -> Matrix4<f64> {
    let (co, ci) = damping;
    let (mo, mi) = (2.0, 1.0);
    Matrix4::new(
        0.0,
        0.0,
        1.0,
        0.0,
        0.0,
        0.0,
        0.0,
        1.0,
        -9.0 / mo,
        3.0 / mo,
        -(co + ci) / mo,
        ci / mo,
        3.0 / mi,
        -3.0 / mi,
        ci / mi,
        -ci / mi,
    )
}

fn max_entry(a: &DMatrix<f64>) -> f64 {
    a.amax()
}

#[test]
fn the_propagator_is_the_matrix_exponential() {
    let omega = 2.0;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), None);
    let flow = rattle_event_driven::LinearFlow::new(
        model.mass(),
        Some(&DMatrix::from_row_slice(2, 2, &[0.15, -0.05, -0.05, 0.05])),
        &DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]),
        &DVector::from_vec(vec![6.0, 0.0]),
        &DVector::zeros(2),
        &DVector::zeros(2),
        omega,
    )
    .unwrap();
    let a = system_matrix(LIGHT_DAMPING);
    for s in [0.0, 0.3, 1.7, 9.0] {
        let exact = (a * s).exp();
        let phi = flow.propagator(s);
        let diff = (phi - DMatrix::from_column_slice(4, 4, exact.as_slice())).amax();
        assert!(diff < 1e-13 * exact.amax().max(1.0), "s = {s}: {diff:e}");
    }
}

#[test]
fn without_stops_the_map_jacobian_is_the_exact_propagator() {
    let omega = 2.0;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), None);
    let a = system_matrix(LIGHT_DAMPING);
    let period = std::f64::consts::TAU / omega;
    for p in [1, 3] {
        // Any phase of the section: the homogeneous propagator does not depend on it.
        let start = Start {
            state: DVector::from_vec(vec![0.3, -0.2, 0.1, 0.5]),
            time: 0.37 * period,
        };
        let map =
            stroboscopic_map(&model, omega, &start, p, &SimulationOptions::default()).unwrap();
        let exact = (a * (p as f64 * period)).exp();
        let exact = DMatrix::from_column_slice(4, 4, exact.as_slice());
        let diff = max_entry(&(&map.jacobian - &exact));
        eprintln!("no stops, {p} periods: |DP − e^{{A pT}}| = {diff:.1e}");
        assert!(diff < 1e-12, "p = {p}: {diff:e}");
        assert!(map.impact_sides.is_empty());
    }
}

#[test]
fn the_determinant_over_a_cycle_counts_the_impacts() {
    // det S = e² per impact and det e^{Aτ} = exp(tr A τ): det DP = e^{2n} exp(tr A pT).
    let omega = 2.0;
    let e = 0.8;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, e)));
    let s = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .unwrap();
    assert_eq!(s.status, Status::Periodic);
    let p = s.period.unwrap();
    let period = std::f64::consts::TAU / omega;
    let trace = system_matrix(LIGHT_DAMPING).trace();
    for periods in [p, 2 * p, 5 * p] {
        let map = stroboscopic_map(
            &model,
            omega,
            &s.final_state,
            periods,
            &SimulationOptions::default(),
        )
        .unwrap();
        let n = map.impact_sides.len() as i32;
        assert_eq!(n as u32, 2 * periods);
        let expected = e.powi(2 * n) * (trace * periods as f64 * period).exp();
        let det = map.jacobian.determinant();
        eprintln!(
            "{periods} periods, {n} impacts: det DP relative error {:.1e}",
            (det - expected).abs() / expected
        );
        assert!(
            (det - expected).abs() < 1e-10 * expected,
            "{periods} periods: det {det:e}, expected {expected:e}"
        );
    }
}

#[test]
fn a_periodic_run_is_polished_and_only_its_amplitudes_change() {
    let omega = 2.0;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let on = SimulationOptions::default();
    let off = SimulationOptions {
        polish: false,
        ..SimulationOptions::default()
    };
    let a = simulate(&model, omega, &Start::rest(2), &on).unwrap();
    let mut b = simulate(&model, omega, &Start::rest(2), &off).unwrap();
    let orbit = a.orbit.clone().expect("polished");
    eprintln!(
        "polished: {} iterations, residual {:.1e}",
        orbit.iterations, orbit.residual
    );
    assert!(b.orbit.is_none() && a.orbit_error.is_none() && b.orbit_error.is_none());
    // The amplitudes are read from one cycle run from the polished orbit: within the run's
    // periodicity tolerance of the last simulated cycle's, and exactly a fixed run's from the
    // orbit's section.
    for (p, q) in a.amplitudes.iter().zip(&b.amplitudes) {
        assert!((p - q).abs() <= 1e-7 * q.abs(), "{p} {q}");
    }
    let once = SimulationOptions {
        fixed_periods: Some(u64::from(orbit.periods)),
        polish: false,
        ..SimulationOptions::default()
    };
    let section = Start {
        state: orbit.state.clone(),
        time: orbit.time,
    };
    let cycle = simulate(&model, omega, &section, &once).unwrap();
    assert_eq!(a.amplitudes, cycle.amplitudes);
    b.orbit = a.orbit.clone();
    b.amplitudes = a.amplitudes.clone();
    assert_eq!(
        a, b,
        "polishing changed an output other than the orbit and the amplitudes"
    );
    assert_eq!(orbit.periods, 1);
    assert!(orbit.residual <= NEWTON_TOLERANCE_FACTOR * on.root_tolerance);
    // The run repeated to 1e-9: Newton moves the state by about that.
    let moved = (&orbit.state - &a.final_state.state).norm() / orbit.state.norm();
    assert!(moved < 1e-7, "{moved:e}");
    assert_eq!(orbit.impact_sides.len(), 2);
    assert!(orbit.impact_sides[0] != orbit.impact_sides[1]);
    // The run's own impacts within the period, as fractions of the cycle.
    let period = std::f64::consts::TAU / omega;
    let mut run_phases: Vec<(i8, f64)> = a
        .cycle_impacts
        .iter()
        .map(|i| (i.side, i.phase / period))
        .collect();
    run_phases.sort_by(|x, y| x.1.total_cmp(&y.1));
    for ((side, phase), (run_side, run_phase)) in orbit
        .impact_sides
        .iter()
        .zip(&orbit.impact_phases)
        .zip(&run_phases)
    {
        assert_eq!(side, run_side);
        assert!((phase - run_phase).abs() < 1e-7, "{phase} vs {run_phase}");
    }
    // A stable orbit: every multiplier inside the unit circle.
    assert_eq!(orbit.floquet_multipliers.len(), 4);
    assert!(orbit.floquet_multipliers.iter().all(|m| m.norm() < 1.0));
    let product: Complex<f64> = orbit.floquet_multipliers.iter().product();
    let trace = system_matrix(LIGHT_DAMPING).trace();
    let expected = 0.8f64.powi(4) * (trace * period).exp();
    assert!((product.re - expected).abs() < 1e-10 * expected && product.im.abs() < 1e-12);
}

#[test]
fn the_section_phase_is_the_guess_phase() {
    // The same orbit through a section at another forcing phase: the guess is the orbit's own
    // state there (a dense sample of one period from the fixed point at t = 0), Newton stays on
    // it, and the multipliers (eigenvalues of conjugate monodromies) are the same.
    let omega = 2.0;
    let period = std::f64::consts::TAU / omega;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let options = SimulationOptions::default();
    let s = simulate(&model, omega, &Start::rest(2), &options).unwrap();
    let at_zero = s.orbit.unwrap();
    let sampled = SimulationOptions {
        fixed_periods: Some(1),
        record_trajectory: true,
        polish: false,
        ..SimulationOptions::default()
    };
    let one = simulate(
        &model,
        omega,
        &Start {
            state: at_zero.state.clone(),
            time: 0.0,
        },
        &sampled,
    )
    .unwrap();
    let trajectory = one.trajectory.unwrap();
    let (t, y) = trajectory
        .iter()
        .min_by(|a, b| {
            (a.0 - 0.37 * period)
                .abs()
                .total_cmp(&(b.0 - 0.37 * period).abs())
        })
        .unwrap();
    let guess = Start {
        state: y.clone(),
        time: *t,
    };
    let mid = periodic_orbit(&model, omega, &guess, 1, &options).unwrap();
    assert!((mid.phase - t).abs() < 1e-15 && mid.time == *t);
    assert!(mid.iterations <= 1, "{}", mid.iterations);
    assert!((&mid.state - y).norm() < 1e-9 * y.norm());
    let sorted = |o: &PeriodicOrbit| {
        let mut m = o.floquet_multipliers.clone();
        m.sort_by(|a, b| a.norm().total_cmp(&b.norm()).then(a.im.total_cmp(&b.im)));
        m
    };
    for (x, y) in sorted(&at_zero).iter().zip(&sorted(&mid)) {
        assert!((x - y).norm() < 1e-8, "{x} vs {y}");
    }
    // The impacts are the same, seen from the later section.
    let shift = t / period;
    let mut expected: Vec<f64> = at_zero
        .impact_phases
        .iter()
        .map(|p| (p - shift).rem_euclid(1.0))
        .collect();
    expected.sort_by(f64::total_cmp);
    for (a, b) in mid.impact_phases.iter().zip(&expected) {
        assert!((a - b).abs() < 1e-9, "{a} vs {b}");
    }
}

#[test]
fn a_sticking_run_is_an_error_not_a_jacobian() {
    // Plastic impacts (e = 0) stick at once.
    let model = paper_unit(0.8, Some(LIGHT_DAMPING), Some((0.2, 0.0)));
    let options = SimulationOptions {
        fixed_periods: Some(60),
        ..SimulationOptions::default()
    };
    let s = simulate(&model, 0.8, &Start::rest(2), &options).unwrap();
    assert!(s.sticking);
    assert!(s.orbit.is_none());
    if s.status == Status::Periodic {
        assert_eq!(s.orbit_error.as_deref(), Some("the final cycle sticks"));
    }
    let result = periodic_orbit(&model, 0.8, &s.final_state, 1, &options);
    assert!(
        matches!(result, Err(NewtonError::Sticking(_))),
        "{result:?}"
    );
    assert!(matches!(
        stroboscopic_map(&model, 0.8, &s.final_state, 1, &options),
        Err(NewtonError::Sticking(_))
    ));
    // Chatter ending on a stop.
    let model = paper_unit(0.6, Some(LIGHT_DAMPING), Some((0.05, 0.6)));
    let s = simulate(&model, 0.6, &Start::rest(2), &options).unwrap();
    assert!(s.sticking);
    let result = periodic_orbit(&model, 0.6, &s.final_state, 1, &options);
    assert!(
        matches!(result, Err(NewtonError::Sticking(_))),
        "{result:?}"
    );
}

#[test]
fn bad_inputs_are_errors() {
    let model = paper_unit(2.0, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let options = SimulationOptions::default();
    let rest = Start::rest(2);
    assert_eq!(
        periodic_orbit(&model, 2.0, &rest, 0, &options),
        Err(NewtonError::Periods)
    );
    assert!(matches!(
        periodic_orbit(&model, -1.0, &rest, 1, &options),
        Err(NewtonError::Simulation(SimulationError::Omega(_)))
    ));
    assert!(matches!(
        periodic_orbit(&model, 2.0, &Start::rest(3), 1, &options),
        Err(NewtonError::Simulation(SimulationError::Start(_)))
    ));
}

#[test]
fn a_guess_with_another_impact_sequence_is_refused() {
    // From rest the first period is a transient with four impacts; the orbit Newton's first
    // step aims for has two (one on each side): between them two impacts went through a
    // grazing, and the Jacobian of the first iterate says nothing about the second.
    let model = paper_unit(2.0, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let options = SimulationOptions::default();
    let first = stroboscopic_map(&model, 2.0, &Start::rest(2), 1, &options).unwrap();
    assert_eq!(first.impact_sides, vec![1, -1, -1, -1]);
    let result = periodic_orbit(&model, 2.0, &Start::rest(2), 1, &options);
    assert_eq!(
        result,
        Err(NewtonError::SignatureChanged {
            iteration: 1,
            first: vec![1, -1, -1, -1],
            now: vec![1, -1],
        })
    );
}

/// A hard point of the study's 400-frequency sweep of the paper's unit: at
/// ω = 1.4586466165413536 the sections from rest repeat to 1e-9 after 1 172 periods on a
/// 28-impact cycle whose multipliers (from this simulator's Newton and from the analytic
/// solver alike) include 1.0039: a transient passing near an unstable cycle along its stable
/// manifold, not the steady state. The run goes on past a cycle its Newton finds unstable,
/// and settles on the stable 28-impact cycle beside it.
#[test]
fn a_cycle_newton_finds_unstable_is_not_the_steady_state() {
    let omega = 1.4586466165413536;
    let model = paper_unit(omega, None, Some((0.5, 0.8)));
    let radius = |o: &PeriodicOrbit| {
        o.floquet_multipliers
            .iter()
            .map(|m| m.norm())
            .fold(0.0, f64::max)
    };
    // Without polishing there are no multipliers to judge by: the run stops where its
    // sections first repeat, on the unstable cycle (polished here to show it).
    let raw = SimulationOptions {
        polish: false,
        ..SimulationOptions::default()
    };
    let first = simulate(&model, omega, &Start::rest(2), &raw).unwrap();
    assert_eq!((first.status, first.period), (Status::Periodic, Some(1)));
    let unstable = periodic_orbit(&model, omega, &first.final_state, 1, &raw).unwrap();
    assert!(radius(&unstable) > 1.0 + UNSTABLE_MARGIN, "{unstable:?}");
    // With it, the run goes on.
    let steady = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .unwrap();
    let orbit = steady.orbit.as_ref().expect("polished");
    assert_eq!((steady.status, steady.period), (Status::Periodic, Some(1)));
    assert_eq!(steady.stopped, Stop::Decided);
    assert_eq!(steady.impacts_per_period, 28.0);
    assert!(radius(orbit) < 1.0, "{:?}", orbit.floquet_multipliers);
    assert!(steady.periods_run > first.periods_run);
    // Another cycle: its state differs from the unstable one's by far more than the
    // periodicity tolerance.
    let apart = (&orbit.state - &unstable.state).norm() / orbit.state.norm();
    assert!(apart > 1e-6, "{apart:e}");
}
