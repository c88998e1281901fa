//! Lyapunov exponents from the simulator's tangent flow against exact answers: the Floquet
//! multipliers of a periodic motion (the simulator's own Newton), the sum rule
//! `Σ λ = tr A + 2 log(e) × impacts per second`, the eigenvalues of a linear unit, and the
//! stability of a chaotic motion's largest exponent; and finite output (or an error) on the
//! degenerate scenes.

use nalgebra::{Complex, Matrix4};
use rattle_event_driven::test_models::{far_stops_unit, linear_damped_unit, paper_unit};
use rattle_event_driven::test_models::{INNER_MASS, LIGHT_DAMPING, OUTER_MASS};
use rattle_event_driven::BATCHES;
use rattle_event_driven::*;

/// The chaotic point of the paper's unit (light damping, `Δ = 0.25`, `e = 0.8`) found by a
/// scan of ω = 1.0–1.9 in steps of 0.05 from rest (2000 periods after the steady-state run):
/// `λ₁ ≈ 0.38`/s there, well beyond its uncertainty (≈ 0.012/s).
const CHAOTIC_OMEGA: f64 = 1.25;
const CHAOTIC_STOPS: (f64, f64) = (0.25, 0.8);

/// `A = [[0, I], [−M⁻¹K, −M⁻¹C]]` of the paper unit (`m_o = 2`, `m_i = 1`, `k_o = 6`,
/// `k_i = 3`), by hand.
fn system_matrix(damping: (f64, f64)) -> Matrix4<f64> {
    let (co, ci) = damping;
    let (mo, mi) = (OUTER_MASS, INNER_MASS);
    #[rustfmt::skip]
    let a = Matrix4::new(
        0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        -9.0 / mo, 3.0 / mo, -(co + ci) / mo, ci / mo,
        3.0 / mi, -3.0 / mi, ci / mi, -ci / mi,
    );
    a
}

fn settled(model: &Model, omega: f64) -> SteadyState {
    simulate(model, omega, &Start::rest(2), &SimulationOptions::default()).unwrap()
}

/// Compares `exponents` (descending) with exact `rates` `(Re, Im)` (descending by `Re`): a real
/// rate individually to `tol` relative, a complex-conjugate pair by its sum (the two members of
/// a pair share one growth rate and split it by a bounded oscillation, an `O(1/t)` error that
/// only their sum is free of) to `tol`, and each member within its stated uncertainty.
fn check_against(spectrum: &LyapunovSpectrum, rates: &[(f64, f64)], tol: f64) {
    let x = &spectrum.exponents;
    assert_eq!(x.len(), rates.len());
    let mut i = 0;
    while i < rates.len() {
        let (re, im) = rates[i];
        if im != 0.0 && i + 1 < rates.len() {
            let sum = x[i] + x[i + 1];
            let exact = re + rates[i + 1].0;
            assert!(
                (sum - exact).abs() <= tol * exact.abs(),
                "pair {i}: {sum} vs {exact} ({:?})",
                x
            );
            for j in [i, i + 1] {
                assert!(
                    (x[j] - rates[j].0).abs() <= spectrum.uncertainties[j],
                    "member {j}: {} vs {} ± {}",
                    x[j],
                    rates[j].0,
                    spectrum.uncertainties[j]
                );
            }
            i += 2;
        } else {
            assert!(
                (x[i] - re).abs() <= tol * re.abs(),
                "exponent {i}: {} vs {re} ({:?})",
                x[i],
                x
            );
            i += 1;
        }
    }
}

/// Floquet rates `(log|μ|/(pT), arg μ)` sorted descending by the first.
fn floquet_rates(orbit: &PeriodicOrbit, omega: f64) -> Vec<(f64, f64)> {
    let cycle = orbit.periods as f64 * std::f64::consts::TAU / omega;
    let mut rates: Vec<(f64, f64)> = orbit
        .floquet_multipliers
        .iter()
        .map(|m| (m.norm().ln() / cycle, m.im))
        .collect();
    rates.sort_by(|a, b| b.0.total_cmp(&a.0));
    rates
}

#[test]
fn periodic_motion_exponents_are_the_floquet_rates() {
    // Stable periodic motions of the paper unit (light damping, Δ = 0.25, e = 0.8) from the
    // same scan: one period at ω = 1.1, two at ω = 1.0.
    for omega in [1.1, 1.0] {
        let model = paper_unit(omega, Some(LIGHT_DAMPING), Some(CHAOTIC_STOPS));
        let steady = settled(&model, omega);
        assert_eq!(steady.status, Status::Periodic, "ω = {omega}");
        let orbit = steady.orbit.as_ref().expect("polished");
        let start = Start {
            state: orbit.state.clone(),
            time: orbit.time,
        };
        let spectrum =
            lyapunov_exponents(&model, omega, &start, &LyapunovOptions::default()).unwrap();
        assert_eq!(spectrum.collapsed, 0);
        check_against(&spectrum, &floquet_rates(orbit, omega), 1e-6);
    }
}

#[test]
fn sum_of_exponents_is_volume_contraction_on_a_chaotic_run() {
    let (omega, (gap, e)) = (CHAOTIC_OMEGA, CHAOTIC_STOPS);
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((gap, e)));
    let steady = settled(&model, omega);
    assert_eq!(steady.status, Status::NonPeriodic);
    let spectrum =
        lyapunov_after_steady_state(&model, omega, &steady, &LyapunovOptions::default()).unwrap();
    assert_eq!(
        spectrum.sticks, 0,
        "the sum rule holds while no pair sticks"
    );
    assert_eq!(spectrum.exponents.len(), 4);
    let trace = system_matrix(LIGHT_DAMPING).trace();
    let exact = trace + 2.0 * e.ln() * spectrum.impacts as f64 / spectrum.time;
    let sum = spectrum.sum();
    assert!(
        (sum - exact).abs() <= 1e-8 * exact.abs(),
        "Σλ = {sum}, tr A + 2 log e × rate = {exact}"
    );
    assert!(spectrum.impacts > 0);
}

#[test]
fn linear_unit_exponents_are_the_real_parts_of_the_eigenvalues() {
    let mut eigen: Vec<Complex<f64>> = system_matrix(LIGHT_DAMPING)
        .complex_eigenvalues()
        .iter()
        .copied()
        .collect();
    eigen.sort_by(|a, b| b.re.total_cmp(&a.re));
    let rates: Vec<(f64, f64)> = eigen.iter().map(|z| (z.re, z.im)).collect();
    let unit = linear_damped_unit(1.3);
    let spectrum = lyapunov_exponents(
        &unit.model,
        unit.omega,
        &unit.start,
        &LyapunovOptions::default(),
    )
    .unwrap();
    assert_eq!(spectrum.impacts, 0);
    check_against(&spectrum, &rates, 1e-8);
    // Stops it never reaches change nothing.
    let far = far_stops_unit(1.3, 0.8);
    let with_stops = lyapunov_exponents(
        &far.model,
        far.omega,
        &far.start,
        &LyapunovOptions::default(),
    )
    .unwrap();
    assert_eq!(with_stops.impacts, 0);
    check_against(&with_stops, &rates, 1e-8);
}

#[test]
fn chaotic_largest_exponent_is_positive_and_stable_when_the_run_is_doubled() {
    let (omega, stops) = (CHAOTIC_OMEGA, CHAOTIC_STOPS);
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some(stops));
    let steady = settled(&model, omega);
    let options = LyapunovOptions::default();
    let single = lyapunov_after_steady_state(&model, omega, &steady, &options).unwrap();
    let doubled = lyapunov_after_steady_state(
        &model,
        omega,
        &steady,
        &LyapunovOptions {
            periods: 2 * options.periods,
            ..options
        },
    )
    .unwrap();
    let (l1, l2) = (single.exponents[0], doubled.exponents[0]);
    assert!(
        l1 > single.uncertainty,
        "λ₁ = {l1} ± {}",
        single.uncertainty
    );
    assert_eq!(single.regime(), Regime::Chaotic);
    assert_eq!(single.regime().name(), "chaotic");
    assert!(
        (l1 - l2).abs() <= single.uncertainty,
        "λ₁ = {l1} ± {} over N, {l2} over 2N",
        single.uncertainty
    );
}

#[test]
fn regime_names_and_thresholds() {
    assert_eq!(Regime::of(0.5, 0.1), Regime::Chaotic);
    assert_eq!(Regime::of(0.05, 0.1), Regime::QuasiPeriodic);
    assert_eq!(Regime::of(-0.05, 0.1), Regime::QuasiPeriodic);
    assert_eq!(Regime::of(-0.5, 0.1), Regime::Unsettled);
    assert_eq!(Regime::Chaotic.name(), "chaotic");
    assert_eq!(Regime::QuasiPeriodic.name(), "quasi-periodic");
    assert_eq!(Regime::Unsettled.name(), "unsettled");
}

fn assert_finite(spectrum: &LyapunovSpectrum) {
    assert!(spectrum.exponents.iter().all(|x| x.is_finite()));
    assert!(spectrum.uncertainties.iter().all(|x| x.is_finite()));
    assert_eq!(spectrum.exponents.len() + spectrum.collapsed, 4);
}

#[test]
fn degenerate_scenes_give_finite_output_or_an_error() {
    let options = LyapunovOptions {
        periods: 200,
        ..LyapunovOptions::default()
    };
    let omega = 1.3;
    // No stops, no damping: a conservative linear unit, every exponent zero. The modes' planes
    // rotate, so each exponent is zero to within its stated uncertainty (O(1/t)).
    let free = paper_unit(omega, None, None);
    let start = Start {
        state: nalgebra::DVector::from_vec(vec![0.1, 0.2, 0.0, 0.0]),
        time: 0.0,
    };
    let s = lyapunov_exponents(&free, omega, &start, &options).unwrap();
    assert_finite(&s);
    for (x, u) in s.exponents.iter().zip(&s.uncertainties) {
        assert!(x.abs() <= *u, "{x} ± {u}");
    }
    assert!(
        s.sum().abs() <= 1e-10,
        "volume is conserved: Σλ = {}",
        s.sum()
    );
    assert_eq!(s.regime(), Regime::QuasiPeriodic);
    // No damping, elastic impacts: volume conserved (det S = 1), Σλ = 0.
    let elastic = paper_unit(omega, None, Some((0.25, 1.0)));
    let s = lyapunov_exponents(&elastic, omega, &start, &options).unwrap();
    assert_finite(&s);
    assert!(s.impacts > 0);
    assert!(
        s.sum().abs() <= 1e-9 * s.exponents[0].abs().max(1.0),
        "Σλ = {}",
        s.sum()
    );
    // e = 0: every impact sticks; two directions collapse, the rest stay finite.
    for damping in [None, Some(LIGHT_DAMPING)] {
        let plastic = paper_unit(omega, damping, Some((0.25, 0.0)));
        let s = lyapunov_exponents(&plastic, omega, &start, &options).unwrap();
        assert_finite(&s);
        assert!(s.sticks > 0);
        assert_eq!(s.collapsed, 2);
    }
    // Too few periods: an error naming the field.
    let e = lyapunov_exponents(
        &free,
        omega,
        &start,
        &LyapunovOptions {
            periods: BATCHES - 1,
            ..LyapunovOptions::default()
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("periods"), "{e}");
    // Bad inputs: errors, not panics.
    assert!(lyapunov_exponents(&free, f64::NAN, &start, &options).is_err());
    assert!(lyapunov_exponents(&free, omega, &Start::rest(3), &options).is_err());
}

#[test]
fn sticking_periodic_motion_keeps_two_finite_exponents() {
    // ω = 1.4, Δ = 0.25, e = 0.8: a periodic motion that sticks once a period (the scan). The
    // two directions across the stop collapse; the other two are the decaying free mode's
    // pair, below zero.
    let omega = 1.4;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some(CHAOTIC_STOPS));
    let steady = settled(&model, omega);
    assert!(steady.sticking);
    let s =
        lyapunov_after_steady_state(&model, omega, &steady, &LyapunovOptions::default()).unwrap();
    assert_finite(&s);
    assert_eq!(s.collapsed, 2);
    assert!(s.time_stuck > 0.0);
    assert!(s.exponents[0] < -s.uncertainty);
}

/// The simulator's stroboscopic map over one period, `P(y)`.
fn one_period(model: &Model, omega: f64, y: &nalgebra::DVector<f64>) -> nalgebra::DVector<f64> {
    let options = SimulationOptions {
        fixed_periods: Some(1),
        polish: false,
        ..SimulationOptions::default()
    };
    let start = Start {
        state: y.clone(),
        time: 0.0,
    };
    simulate(model, omega, &start, &options)
        .unwrap()
        .final_state
        .state
}

#[test]
fn sticking_tangent_matches_finite_differences_of_the_map() {
    // The stick's plastic saltation, the held pair's reduced propagator and the release (no
    // saltation) against the simulator's own map: at the sticking periodic motion (ω = 1.4,
    // Δ = 0.25, e = 0.8) the finite exponents must be `log|μ|/T` of the nonzero multipliers of
    // the central-difference Jacobian of `P`. Central differences with step `h` are accurate
    // to `O(h²)` plus rounding `ε|P|/h`: `h = 1e-6` of the state gives ~1e-10 relative, far
    // below the 1e-6 asked (the contact times, resolved to 1e-12 T, add ~1e-12/h = 1e-6 at
    // worst, which is why no tighter tolerance is asked).
    let omega = 1.4;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some(CHAOTIC_STOPS));
    let steady = settled(&model, omega);
    assert!(steady.sticking && steady.period == Some(1));
    let y = steady.final_state.state.clone();
    let h = 1e-6 * y.norm();
    let mut jacobian = nalgebra::DMatrix::zeros(4, 4);
    for j in 0..4 {
        let mut plus = y.clone();
        plus[j] += h;
        let mut minus = y.clone();
        minus[j] -= h;
        let column =
            (one_period(&model, omega, &plus) - one_period(&model, omega, &minus)) / (2.0 * h);
        jacobian.set_column(j, &column);
    }
    let period = std::f64::consts::TAU / omega;
    let mut moduli: Vec<f64> = jacobian
        .complex_eigenvalues()
        .iter()
        .map(|m| m.norm())
        .collect();
    moduli.sort_by(|a, b| b.total_cmp(a));
    // Two directions collapse: their multipliers vanish (to the differences' accuracy).
    assert!(moduli[2] < 1e-4 * moduli[1], "{moduli:?}");
    let spectrum =
        lyapunov_after_steady_state(&model, omega, &steady, &LyapunovOptions::default()).unwrap();
    assert_eq!(spectrum.collapsed, 2);
    let sum_fd = (moduli[0] * moduli[1]).ln() / period;
    assert!(
        (spectrum.sum() - sum_fd).abs() <= 1e-6 * sum_fd.abs(),
        "{:?} vs {:?}",
        spectrum.exponents,
        moduli.iter().map(|m| m.ln() / period).collect::<Vec<_>>()
    );
    for (x, m) in spectrum.exponents.iter().zip(&moduli) {
        let exact = m.ln() / period;
        assert!(
            (x - exact).abs() <= spectrum.uncertainty.max(1e-6 * exact.abs()),
            "{x} vs {exact}"
        );
    }
}

#[test]
fn exponents_do_not_depend_on_the_section_phase() {
    // The exponents are properties of the motion, not of the section: started a third of a
    // period after the orbit's section (the state there sampled exactly from the closed form),
    // the spectrum is again the Floquet rates.
    let omega = 1.1;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some(CHAOTIC_STOPS));
    let steady = settled(&model, omega);
    let orbit = steady.orbit.as_ref().expect("polished");
    let trajectory = sample_trajectory(
        &model,
        omega,
        &Start {
            state: orbit.state.clone(),
            time: orbit.time,
        },
        &TrajectoryOptions {
            periods: 1,
            samples_per_period: 3,
            ..TrajectoryOptions::default()
        },
    )
    .unwrap();
    let third = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::Sample)
        .nth(1)
        .unwrap();
    let mut state = nalgebra::DVector::zeros(4);
    for j in 0..2 {
        state[j] = third.displacements[j];
        state[2 + j] = third.velocities[j];
    }
    let start = Start {
        state,
        time: orbit.time + third.time,
    };
    let spectrum = lyapunov_exponents(&model, omega, &start, &LyapunovOptions::default()).unwrap();
    check_against(&spectrum, &floquet_rates(orbit, omega), 1e-6);
    // The run stayed on the orbit at that phase: a whole number of periods later it is back at
    // the start (to the periodicity the orbit was polished to).
    assert_eq!(spectrum.final_state.time, start.time);
    let back = (&spectrum.final_state.state - &start.state).norm() / start.state.norm();
    assert!(back <= 1e-9, "{back:e}");
}
