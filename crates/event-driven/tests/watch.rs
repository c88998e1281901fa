//! The section watch of [`simulate_watched`]: what it is asked, that it can end a run, and that
//! a watch that never fires leaves the run exactly as [`simulate`] makes it.

use nalgebra::DVector;
use rattle_event_driven::test_models::paper_unit;
use rattle_event_driven::*;

/// The paper's unit at ω = 2 with stops (Δ = 0.5, e = 0.8), undamped: it repeats after some
/// hundred periods from rest.
fn unit() -> Model {
    paper_unit(2.0, None, Some((0.5, 0.8)))
}

#[test]
fn a_watch_that_never_fires_changes_nothing() {
    let model = unit();
    let options = SimulationOptions::default();
    let start = Start::rest(2);
    let plain = simulate(&model, 2.0, &start, &options).expect("simulates");
    let mut asked = Vec::new();
    let watched = simulate_watched(&model, 2.0, &start, &options, &mut |k, _| {
        asked.push(k);
        false
    })
    .expect("simulates");
    assert_eq!(plain, watched);
    assert_eq!(plain.status, Status::Periodic);
    // Asked at every undecided section, in order, from the first period on; not once the
    // period is found and the final cycle is being observed.
    let decided_at = plain.periods_run - u64::from(plain.period.expect("periodic"));
    assert_eq!(asked, (1..decided_at).collect::<Vec<u64>>());
}

#[test]
fn a_watch_ends_the_run_at_its_section_with_nothing_observed() {
    let model = unit();
    let options = SimulationOptions::default();
    let start = Start::rest(2);
    let reference = simulate(
        &model,
        2.0,
        &start,
        &SimulationOptions {
            fixed_periods: Some(7),
            ..options.clone()
        },
    )
    .expect("simulates");
    let mut seen: Option<DVector<f64>> = None;
    let watched = simulate_watched(&model, 2.0, &start, &options, &mut |k, x| {
        seen = Some(x.clone());
        k == 7
    })
    .expect("simulates");
    assert_eq!(watched.stopped, Stop::Watched);
    assert_eq!(watched.periods_run, 7);
    assert_ne!(watched.status, Status::Periodic);
    assert!(watched.amplitudes.is_empty() && watched.cycle_impacts.is_empty());
    assert!(watched.stroboscopic.is_empty() && watched.orbit.is_none());
    // The state the watch saw at t = 7T is where the run ended, and where a fixed run of 7
    // periods ends.
    let seen = seen.expect("asked");
    assert_eq!(seen, watched.final_state.state);
    assert_eq!(seen, reference.final_state.state);
}

#[test]
fn a_fixed_run_never_asks() {
    let model = unit();
    let options = SimulationOptions {
        fixed_periods: Some(20),
        ..SimulationOptions::default()
    };
    let mut asked = 0;
    let run = simulate_watched(&model, 2.0, &Start::rest(2), &options, &mut |_, _| {
        asked += 1;
        true
    })
    .expect("simulates");
    assert_eq!(asked, 0);
    assert_eq!(run.stopped, Stop::FixedPeriods);
    assert_eq!(run.periods_run, 20);
}
