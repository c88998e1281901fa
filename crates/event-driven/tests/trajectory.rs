//! Exact trajectories: the samples stay within the stops, impact rows obey the restitution
//! law, the sections of the sampled final cycle are the steady state's own, and bad options
//! are errors.

use rattle_event_driven::test_models::{paper_unit, BASE_AMPLITUDE, LIGHT_DAMPING};
use rattle_event_driven::*;

/// The chaotic point of the paper unit (`tests/lyapunov.rs`): many impacts of all speeds.
const CHAOTIC_OMEGA: f64 = 1.25;
const STOPS: (f64, f64) = (0.25, 0.8);

fn settled(omega: f64) -> (Model, SteadyState) {
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some(STOPS));
    let steady = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .unwrap();
    (model, steady)
}

fn options(periods: u64) -> TrajectoryOptions {
    TrajectoryOptions {
        periods,
        samples_per_period: 200,
        base_amplitude: BASE_AMPLITUDE,
        ..TrajectoryOptions::default()
    }
}

/// `|r| ≤ Δ + tol` with the tolerance the simulator guarantees: a contact is resolved in time
/// to `root_tolerance × T`, so the state before an impact may lie beyond the stop by up to
/// `|ṙ| × root_tolerance × T`; an excursion shallower than `1e-12 Δ` plus `1e-14 max|u|`
/// (the simulator's contact depth and position rounding) is no contact at all.
fn check_within_stops(trajectory: &Trajectory, gap: f64) {
    let max_u = trajectory
        .rows
        .iter()
        .flat_map(|r| r.displacements.iter())
        .fold(0.0f64, |m, u| m.max(u.abs()));
    let max_rdot = trajectory
        .rows
        .iter()
        .map(|r| (r.velocities[1] - r.velocities[0]).abs())
        .fold(0.0, f64::max);
    let root = SimulationOptions::default().root_tolerance;
    let tol = max_rdot * root * trajectory.period + 1e-12 * gap + 1e-14 * max_u;
    for row in &trajectory.rows {
        assert!(
            row.relative[0].abs() <= gap + tol,
            "t = {}: r = {} beyond {gap} + {tol:e}",
            row.time,
            row.relative[0]
        );
    }
}

#[test]
fn samples_stay_within_the_stops_and_impacts_obey_restitution() {
    let (model, steady) = settled(CHAOTIC_OMEGA);
    let start = steady.final_state.clone();
    let trajectory = sample_trajectory(&model, CHAOTIC_OMEGA, &start, &options(20)).unwrap();
    let (gap, e) = STOPS;
    check_within_stops(&trajectory, gap);
    // Uniform samples: 200 a period and the end.
    let samples = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::Sample)
        .count();
    assert_eq!(samples, 20 * 200 + 1);
    assert!(trajectory.rows.windows(2).all(|w| w[0].time <= w[1].time));
    // Each impact: its two rows at its time, ṙ⁺ = −e ṙ⁻ to rounding of the restitution
    // formula (a few ε of the velocities; measured ≤ 2.3 ε).
    assert!(
        trajectory.impacts.len() > 20,
        "{}",
        trajectory.impacts.len()
    );
    let mut seen = 0;
    for w in trajectory.rows.windows(2) {
        if w[0].kind == RowKind::BeforeImpact && w[1].kind == RowKind::AfterImpact {
            assert_eq!(w[0].time, w[1].time);
            assert_eq!(w[0].displacements, w[1].displacements);
            let before = w[0].velocities[1] - w[0].velocities[0];
            let after = w[1].velocities[1] - w[1].velocities[0];
            let scale = w[0].velocities.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(
                (after + e * before).abs() <= 4.0 * f64::EPSILON * scale,
                "t = {}: ṙ⁺ = {after}, −e ṙ⁻ = {}",
                w[0].time,
                -e * before
            );
            let impact = &trajectory.impacts[seen];
            assert_eq!(impact.time, w[0].time);
            assert_eq!(impact.relative_velocity_before, before);
            assert_eq!(impact.velocities_before, w[0].velocities);
            // The approach is towards the stop it hits, at the stop.
            assert!(impact.relative_velocity_before * impact.side as f64 > 0.0);
            assert!((w[0].relative[0] - impact.side as f64 * gap).abs() <= 1e-9 * gap);
            seen += 1;
        }
    }
    assert_eq!(seen, trajectory.impacts.len());
    // The base column is u_g cos ωt from the start's phase (here a section, phase 0).
    let first = &trajectory.rows[0];
    assert_eq!(first.base, BASE_AMPLITUDE);
}

#[test]
fn the_final_cycle_passes_through_the_steady_states_sections() {
    for omega in [1.1, CHAOTIC_OMEGA] {
        let (model, steady) = settled(omega);
        let trajectory = final_cycle_trajectory(&model, omega, &steady, &options(1)).unwrap();
        let period = trajectory.period;
        let sections: Vec<&TrajectoryRow> = trajectory
            .rows
            .iter()
            .filter(|r| r.kind == RowKind::Sample && (r.time / period).fract() == 0.0)
            .collect();
        assert_eq!(sections.len(), steady.stroboscopic.len());
        // The same engine from the same state: the same numbers, to rounding.
        for (row, x) in sections.iter().zip(&steady.stroboscopic) {
            let scale = x.amax();
            for j in 0..2 {
                assert!(
                    (row.displacements[j] - x[j]).abs() <= 1e-12 * scale,
                    "{omega}"
                );
                assert!(
                    (row.velocities[j] - x[2 + j]).abs() <= 1e-12 * scale,
                    "{omega}"
                );
            }
        }
        let last = trajectory.rows.last().unwrap();
        let end = &steady.final_state.state;
        let scale = end.amax();
        for j in 0..2 {
            assert!((last.displacements[j] - end[j]).abs() <= 1e-12 * scale);
            assert!((last.velocities[j] - end[2 + j]).abs() <= 1e-12 * scale);
        }
        check_within_stops(&trajectory, STOPS.0);
    }
}

#[test]
fn a_sticking_cycle_rides_on_the_stop() {
    // ω = 1.4: the periodic motion that sticks once a period (tests/lyapunov.rs).
    let omega = 1.4;
    let (model, steady) = settled(omega);
    assert!(steady.sticking);
    let trajectory = final_cycle_trajectory(&model, omega, &steady, &options(1)).unwrap();
    let sticks: Vec<&TrajectoryRow> = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::AfterStick)
        .collect();
    assert!(!sticks.is_empty());
    for row in sticks {
        assert_eq!(row.velocities[1] - row.velocities[0], 0.0);
    }
    check_within_stops(&trajectory, STOPS.0);
}

#[test]
fn bad_options_are_errors() {
    let model = paper_unit(1.3, Some(LIGHT_DAMPING), Some(STOPS));
    let start = Start::rest(2);
    let e = sample_trajectory(&model, 1.3, &start, &options(0)).unwrap_err();
    assert!(e.to_string().contains("periods"), "{e}");
    let e = sample_trajectory(
        &model,
        1.3,
        &start,
        &TrajectoryOptions {
            samples_per_period: 0,
            ..options(1)
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("samples_per_period"), "{e}");
    let e = sample_trajectory(
        &model,
        1.3,
        &start,
        &TrajectoryOptions {
            base_amplitude: f64::NAN,
            ..options(1)
        },
    )
    .unwrap_err();
    assert!(e.to_string().contains("base_amplitude"), "{e}");
    assert!(sample_trajectory(&model, -1.0, &start, &options(1)).is_err());
    // No stops: a linear stretch, no impacts.
    let free = paper_unit(1.3, Some(LIGHT_DAMPING), None);
    let t = sample_trajectory(&free, 1.3, &start, &options(2)).unwrap();
    assert!(t.impacts.is_empty());
    assert!(t.rows.iter().all(|r| r.relative.is_empty()));
}
