//! The simulator against independent references: a generic integrator written here, the
//! conservation laws of an impact, and the hard cases of the validation page (`docs/validation.md`).

use nalgebra::{DMatrix, DVector};
use rattle_event_driven::test_models::{
    far_stops_unit, free_flight_to_a_stop, linear_damped_unit, paper_cell, paper_impact,
    paper_unit, LinearSteadyState, LIGHT_DAMPING,
};
use rattle_event_driven::LinearFlow;
use rattle_event_driven::*;

const M: [f64; 2] = [2.0, 1.0];

/// Classical RK4 on `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt` for the paper unit.
fn rk4(y0: &[f64; 4], t0: f64, t1: f64, steps: usize, omega: f64, damping: (f64, f64)) -> [f64; 4] {
    let (co, ci) = damping;
    let rhs = |t: f64, y: &[f64; 4]| {
        let (uo, ui, vo, vi) = (y[0], y[1], y[2], y[3]);
        let fo = 6.0 * (omega * t).cos() - co * omega * (omega * t).sin();
        let ao = (fo - 9.0 * uo + 3.0 * ui - (co + ci) * vo + ci * vi) / M[0];
        let ai = (3.0 * uo - 3.0 * ui + ci * vo - ci * vi) / M[1];
        [vo, vi, ao, ai]
    };
    let h = (t1 - t0) / steps as f64;
    let mut y = *y0;
    let mut t = t0;
    for _ in 0..steps {
        let k1 = rhs(t, &y);
        let add = |y: &[f64; 4], k: &[f64; 4], s: f64| {
            [
                y[0] + s * k[0],
                y[1] + s * k[1],
                y[2] + s * k[2],
                y[3] + s * k[3],
            ]
        };
        let k2 = rhs(t + h / 2.0, &add(&y, &k1, h / 2.0));
        let k3 = rhs(t + h / 2.0, &add(&y, &k2, h / 2.0));
        let k4 = rhs(t + h, &add(&y, &k3, h));
        for i in 0..4 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        t += h;
    }
    y
}

fn flow_of(omega: f64, damping: (f64, f64)) -> LinearFlow {
    let (co, ci) = damping;
    let mass = DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let k = DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]);
    let c = DMatrix::from_row_slice(2, 2, &[co + ci, -ci, -ci, ci]);
    let fc = DVector::from_vec(vec![6.0, 0.0]);
    let fs = DVector::from_vec(vec![-co * omega, 0.0]);
    let damping = (co != 0.0 || ci != 0.0).then_some(&c);
    LinearFlow::new(&mass, damping, &k, &fc, &fs, &DVector::zeros(2), omega).unwrap()
}

#[test]
fn closed_form_flow_matches_a_generic_integrator() {
    // Damped, undamped, and undamped at exact resonance ω = ω₁ = √1.5 and ω₂ = √6.
    let cases = [
        (1.3, LIGHT_DAMPING),
        (1.3, (0.0, 0.0)),
        (1.5f64.sqrt(), (0.0, 0.0)),
        (6f64.sqrt(), (0.0, 0.0)),
        (2.0, (0.8, 0.3)),
    ];
    for (omega, damping) in cases {
        let flow = flow_of(omega, damping);
        // Exact resonance needs the resonance-safe form; elsewhere the steady-response form.
        let at_resonance =
            damping == (0.0, 0.0) && (omega == 1.5f64.sqrt() || omega == 6f64.sqrt());
        assert_eq!(flow.has_steady_response(), !at_resonance, "ω={omega}");
        let y0 = [0.3, -0.2, 0.5, 1.1];
        let t0 = 0.7;
        let flight = flow.flight(&DVector::from_column_slice(&y0), t0);
        // r = u_i − u_o as a sum of exponentials, against the state.
        let r = flight.value_of(&DVector::from_vec(vec![-1.0, 1.0, 0.0, 0.0]));
        for s in [0.5, 3.0, 9.0] {
            let exact = flight.state(s);
            let (r_s, _) = r.eval(s);
            assert!(
                (r_s - (exact[1] - exact[0])).abs() < 1e-12 * (1.0 + r_s.abs()),
                "ω={omega}: r {r_s} vs state {}",
                exact[1] - exact[0]
            );
            let reference = rk4(&y0, t0, t0 + s, 20_000, omega, damping);
            for i in 0..4 {
                assert!(
                    (exact[i] - reference[i]).abs() < 1e-10 * (1.0 + reference[i].abs()),
                    "ω={omega} c={damping:?} s={s}: {} vs {}",
                    exact[i],
                    reference[i]
                );
            }
        }
    }
}

#[test]
fn impacts_conserve_momentum_and_lose_the_predicted_energy() {
    for e in [0.0, 0.3, 0.8, 1.0] {
        let (model, answer) = paper_impact(e);
        let before = DVector::from_column_slice(&answer.before);
        let after = model.impact_velocities(0, &before, None);
        let p = |v: &DVector<f64>| M[0] * v[0] + M[1] * v[1];
        let energy = |v: &DVector<f64>| 0.5 * (M[0] * v[0] * v[0] + M[1] * v[1] * v[1]);
        let mu = M[0] * M[1] / (M[0] + M[1]);
        let rdot = before[1] - before[0];
        assert!((p(&after) - p(&before)).abs() < 1e-14);
        assert!(((after[1] - after[0]) + e * rdot).abs() < 1e-14);
        let lost = energy(&before) - energy(&after);
        assert!(
            (lost - 0.5 * mu * (1.0 - e * e) * rdot * rdot).abs() < 1e-14,
            "e={e}"
        );
        // Against the impact matrix written out in the test model: equal to rounding (a few
        // ulps of velocities of size ~1).
        for i in 0..2 {
            assert!(
                (after[i] - answer.after[i]).abs() < 4.0 * f64::EPSILON,
                "e={e}: {} vs {}",
                after[i],
                answer.after[i]
            );
        }
        assert!((p(&after) - answer.momentum).abs() < 1e-14);
        assert!(((after[1] - after[0]) - answer.relative_velocity_after).abs() < 1e-14);
        assert!((lost - answer.energy_lost).abs() < 1e-14);
    }
}

fn relative(x: &DVector<f64>) -> f64 {
    x[1] - x[0]
}

#[test]
fn no_penetration_between_events_and_impacts_conserve_momentum_in_the_run() {
    let model = paper_unit(2.0, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let options = SimulationOptions {
        fixed_periods: Some(30),
        record_trajectory: true,
        ..SimulationOptions::default()
    };
    let s = simulate(&model, 2.0, &Start::rest(2), &options).unwrap();
    let traj = s.trajectory.unwrap();
    assert!(traj.len() > 1000);
    for (t, x) in &traj {
        assert!(
            relative(x).abs() <= 0.5 * (1.0 + 1e-12),
            "t={t}: r = {}",
            relative(x)
        );
    }
    assert!(!s.cycle_impacts.is_empty());
    for imp in &s.cycle_impacts {
        // At contact and approaching from inside.
        assert!((relative(&imp.state_before).abs() - 0.5).abs() < 1e-12);
        assert!(imp.relative_velocity * imp.side as f64 > 0.0);
    }
}

/// Steady state of the linear unit, from the test model's closed form.
fn linear_steady_state(omega: f64, damping: (f64, f64), t: f64) -> DVector<f64> {
    LinearSteadyState::of_paper_unit(omega, damping).state_at(t)
}

#[test]
fn a_million_periods_of_the_linear_unit_keep_their_phase() {
    let omega = 1.1;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), None);
    assert!(!model.has_contacts());
    let start = Start {
        state: linear_steady_state(omega, LIGHT_DAMPING, 0.0),
        time: 0.0,
    };
    let options = SimulationOptions {
        fixed_periods: Some(1_000_000),
        ..SimulationOptions::default()
    };
    let s = simulate(&model, omega, &start, &options).unwrap();
    assert_eq!(s.periods_run, 1_000_000);
    assert_eq!(s.impacts, 0);
    let drift = (&s.final_state.state - &start.state).norm() / start.state.norm();
    assert!(drift < 1e-9, "drift {drift:e}");
    assert_eq!(s.status, Status::Periodic);
    assert_eq!(s.period, Some(1));
}

#[test]
fn undamped_elastic_unit_reports_no_dissipation() {
    let model = paper_unit(2.0, None, Some((0.5, 1.0)));
    assert!(model.conservative());
    let s = simulate(&model, 2.0, &Start::rest(2), &SimulationOptions::default()).unwrap();
    assert_eq!(s.status, Status::NoDissipation);
    assert!(s.periods_run <= 1000);
}

#[test]
fn damped_impacting_unit_settles_on_a_two_impact_orbit() {
    let model = paper_unit(2.0, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let s = simulate(&model, 2.0, &Start::rest(2), &SimulationOptions::default()).unwrap();
    assert_eq!(s.status, Status::Periodic);
    assert_eq!(s.period, Some(1));
    assert_eq!(s.impacts_per_period, 2.0);
    let sides: Vec<i8> = s.cycle_impacts.iter().map(|i| i.side).collect();
    assert!(sides == vec![1, -1] || sides == vec![-1, 1], "{sides:?}");
    // The cycle closes: the stroboscopic states at both ends agree.
    let (a, b) = (&s.stroboscopic[0], s.stroboscopic.last().unwrap());
    assert!((a - b).norm() < 1e-8 * a.norm());
}

#[test]
fn a_graze_between_coarse_samples_is_caught() {
    // Start on the linear steady state with the stops set a hair inside its relative
    // amplitude: r(t) exceeds the gap by 1e-8 relative for a sliver of each period, far
    // narrower than any practical sampling step. The first contact must be found.
    let omega = 0.9;
    let damping = LIGHT_DAMPING;
    let y = linear_steady_state(omega, damping, 0.0);
    // Relative amplitude from the complex amplitudes.
    let quarter = linear_steady_state(omega, damping, std::f64::consts::FRAC_PI_2 / omega);
    let amplitude = (relative(&y).powi(2) + relative(&quarter).powi(2)).sqrt();
    let gap = amplitude * (1.0 - 1e-8);
    let model = paper_unit(omega, Some(damping), Some((gap, 0.8)));
    let options = SimulationOptions {
        fixed_periods: Some(1),
        ..SimulationOptions::default()
    };
    let s = simulate(
        &model,
        omega,
        &Start {
            state: y.clone(),
            time: 0.0,
        },
        &options,
    )
    .unwrap();
    assert!(s.impacts >= 1, "the graze was missed");
    // The width of the excursion beyond the stop, as a fraction of the period.
    let width = 2.0 * (2.0 * 1e-8f64).sqrt() / std::f64::consts::TAU;
    assert!(width < 1e-3);
    // And a coarse sampler with 1000 samples per period would have missed it.
    let stops_clear = linear_steady_state(omega, damping, 0.0);
    let _ = stops_clear;
    let model_far = paper_unit(omega, Some(damping), Some((amplitude * (1.0 + 1e-8), 0.8)));
    let s = simulate(
        &model_far,
        omega,
        &Start {
            state: y,
            time: 0.0,
        },
        &options,
    )
    .unwrap();
    assert_eq!(
        s.impacts, 0,
        "a motion clear of the stops by 1e-8 must not impact"
    );
}

#[test]
fn plastic_impacts_stick_at_once() {
    let model = paper_unit(0.8, Some(LIGHT_DAMPING), Some((0.2, 0.0)));
    let options = SimulationOptions {
        fixed_periods: Some(60),
        ..SimulationOptions::default()
    };
    let s = simulate(&model, 0.8, &Start::rest(2), &options).unwrap();
    assert!(s.sticking, "e = 0 must stick");
    // No chatter sequence: a plastic impact either sticks or separates at once, so only a few
    // impacts per period remain.
    assert!(s.impacts_per_period <= 4.0, "{}", s.impacts_per_period);
    assert!(s.impacts < 60 * 8, "{}", s.impacts);
}

#[test]
fn chatter_ends_in_sticking_and_release() {
    // A small gap at low frequency: the inner mass is thrown against a stop, chatters to rest on
    // it, rides it, and releases when the contact force would pull.
    let model = paper_unit(0.6, Some(LIGHT_DAMPING), Some((0.05, 0.6)));
    let options = SimulationOptions {
        fixed_periods: Some(80),
        record_trajectory: true,
        ..SimulationOptions::default()
    };
    let s = simulate(&model, 0.6, &Start::rest(2), &options).unwrap();
    assert!(s.sticking, "no sticking");
    let traj = s.trajectory.unwrap();
    // Both stops are visited within the final stretch: the mass released from one and crossed.
    let at_plus = traj.iter().any(|(_, x)| (relative(x) - 0.05).abs() < 1e-12);
    let at_minus = traj.iter().any(|(_, x)| (relative(x) + 0.05).abs() < 1e-12);
    assert!(
        at_plus && at_minus,
        "did not ride and release on both stops"
    );
    for (_, x) in &traj {
        assert!(relative(x).abs() <= 0.05 * (1.0 + 1e-10));
    }
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let negative_mass = CellParameters {
        outer_mass: -1.0,
        ..paper_cell(None, None)
    };
    assert!(Model::unit(&negative_mass, 1.0, 1.0).is_err());
    let restitution_above_one = paper_cell(None, Some(CellStops::symmetric(0.5, 1.5)));
    assert!(Model::unit(&restitution_above_one, 1.0, 1.0).is_err());
    let model = paper_unit(1.0, None, Some((0.5, 0.8)));
    assert!(simulate(
        &model,
        f64::NAN,
        &Start::rest(2),
        &SimulationOptions::default()
    )
    .is_err());
    assert!(simulate(&model, 1.0, &Start::rest(3), &SimulationOptions::default()).is_err());
}

#[test]
fn linear_unit_on_its_steady_state_has_the_closed_form_amplitudes() {
    for omega in [0.5, 1.1, 2.0, 3.9] {
        let case = linear_damped_unit(omega);
        let options = SimulationOptions::default();
        let s = simulate(&case.model, case.omega, &case.start, &options).unwrap();
        assert_eq!(s.status, Status::Periodic, "ω={omega}");
        assert_eq!(s.period, Some(1), "ω={omega}");
        assert_eq!(s.impacts, 0);
        // Started on the steady state the run repeats at once: the third section completes
        // the two comparisons the periodicity test needs, then one period is observed.
        assert_eq!(s.periods_run, 3, "ω={omega}");
        // The amplitudes are closed-form extrema of the exact motion: as accurate as the
        // simulator's accuracy knob (the root tolerance, relative).
        for (got, want) in s.amplitudes.iter().zip(case.answer.amplitudes()) {
            assert!(
                (got - want).abs() <= options.root_tolerance * want,
                "ω={omega}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn stops_out_of_reach_never_impact_and_the_run_settles_on_the_linear_answer() {
    for omega in [0.9, 2.0, 3.0] {
        let case = far_stops_unit(omega, 0.8);
        let options = SimulationOptions::default();
        let s = simulate(&case.model, case.omega, &case.start, &options).unwrap();
        assert_eq!(s.impacts, 0, "ω={omega}: the stops are out of reach");
        assert_eq!(s.status, Status::Periodic, "ω={omega}");
        assert_eq!(s.period, Some(1), "ω={omega}");
        assert_eq!(s.stopped, Stop::Decided);
        // The run stopped when the section repeated to the periodicity tolerance (confirmed at
        // the end to ten times it) relative to the motion's size (at most twice the steady
        // state's while the transient is that small); a section that repeats to δ is within
        // ‖Φ(Φ − I)⁻¹‖ δ of the fixed point.
        let exact = case.answer.steady.state_at(0.0);
        let repeat = 10.0 * options.periodicity_tolerance * 2.0 * exact.norm();
        let bound = case.answer.settling_factor * repeat;
        let error = (&s.final_state.state - &exact).norm();
        assert!(
            error <= bound,
            "ω={omega}: {error:e} from the linear steady state, bound {bound:e}"
        );
        // The run went on long enough for the bound to mean something: the transient from rest
        // is of the size of the steady state.
        assert!(s.periods_run > 10, "ω={omega}");
        assert!(case.answer.gap > 2.0 * case.answer.steady.relative_amplitude());
    }
}

#[test]
fn a_free_flight_reaches_the_stop_at_the_closed_form_time() {
    for e in [0.0, 0.5, 1.0] {
        let case = free_flight_to_a_stop(e);
        let options = SimulationOptions {
            fixed_periods: Some(1),
            ..SimulationOptions::default()
        };
        let s = simulate(&case.model, case.omega, &case.start, &options).unwrap();
        let first = s.cycle_impacts.first().expect("the stop is reached");
        let answer = &case.answer;
        assert_eq!(first.side, 1);
        // Contact times are resolved to root_tolerance × T.
        let period = std::f64::consts::TAU / case.omega;
        let dt = options.root_tolerance * period;
        assert!(
            (first.time - answer.time).abs() <= dt,
            "e={e}: contact at {} vs {}, tolerance {dt:e}",
            first.time,
            answer.time
        );
        // The velocity there is off by at most |r̈| times the time error (plus rounding of a
        // velocity of size 1).
        let dv = answer.relative_acceleration.abs() * dt + 8.0 * f64::EPSILON;
        assert!(
            (first.relative_velocity - answer.relative_velocity).abs() <= dv,
            "e={e}: ṙ⁻ {} vs {}",
            first.relative_velocity,
            answer.relative_velocity
        );
        // The impact there, applied to the state the simulator recorded, is the test model's
        // impact matrix to within the same velocity tolerance.
        let after =
            case.model
                .impact_velocities(0, &first.state_before.rows(2, 2).into_owned(), None);
        for i in 0..2 {
            assert!(
                (after[i] - answer.velocities_after[i]).abs() <= dv,
                "e={e}: velocity {i} after, {} vs {}",
                after[i],
                answer.velocities_after[i]
            );
        }
    }
}

#[test]
fn flights_carried_past_the_sections_agree_with_flights_restarted_there() {
    // A run whose one-pair flights go on past each section (searched up to the next) against
    // the same run restarted at every section (a run of one period from each section state,
    // which starts a fresh flight and search there): the same impacts, and states that agree
    // to what the contact times' tolerance (`1e-12 T`) allows over the transient of the
    // paper's damped unit at ω = 2 (two impacts a period) and at ω = 1.1.
    for omega in [2.0, 1.1] {
        let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
        let periods = 60;
        let fixed = |n: u64| SimulationOptions {
            fixed_periods: Some(n),
            ..SimulationOptions::default()
        };
        let carried = simulate(&model, omega, &Start::rest(2), &fixed(periods)).unwrap();
        let mut start = Start::rest(2);
        let mut impacts = 0;
        for _ in 0..periods {
            let step = simulate(&model, omega, &start, &fixed(1)).unwrap();
            impacts += step.impacts;
            start = step.final_state;
        }
        assert_eq!(carried.impacts, impacts, "ω = {omega}");
        assert!(impacts >= periods, "ω = {omega}: {impacts} impacts");
        // An impact's time known to `δ = 1e-12 T` moves the state by about `|Δu̇| δ`, some
        // `1e-11` of the motion's size; damped, such differences do not grow. (Measured
        // when written: 3e-15 at ω = 2, 5e-16 at ω = 1.1.)
        let (a, b) = (&carried.final_state.state, &start.state);
        let error = (a - b).amax() / b.amax();
        assert!(error <= 1e-10, "ω = {omega}: {error:e}");
    }
}
