//! Throughput of the event-driven simulator: impacts per second on a damped 2-DOF scene with
//! contact times to 1e-12 relative, and the cost of the pieces of one event.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::DVector;
use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
use rattle_event_driven::LinearFlow;
use rattle_event_driven::SearchStack;
use rattle_event_driven::{simulate, SimulationOptions, Start};

fn impacts(c: &mut Criterion) {
    // ω = 2: a two-impact orbit; 2000 periods after settling give 4000 impacts.
    let omega = 2.0;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let options = SimulationOptions {
        fixed_periods: Some(2000),
        ..SimulationOptions::default()
    };
    let settled = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .expect("settles")
    .final_state;
    let probe = simulate(&model, omega, &settled, &options).expect("runs");
    let mut group = c.benchmark_group("event-driven");
    group.throughput(Throughput::Elements(probe.impacts));
    group.bench_function("damped two-impact orbit, 2000 periods (impacts/s)", |b| {
        b.iter(|| simulate(&model, black_box(omega), &settled, &options))
    });
    group.finish();

    let flow_model = paper_unit(1.3, Some(LIGHT_DAMPING), None);
    let linear = SimulationOptions {
        fixed_periods: Some(10_000),
        ..SimulationOptions::default()
    };
    let start = Start {
        state: DVector::from_vec(vec![0.1, 0.2, 0.0, 0.0]),
        time: 0.0,
    };
    let mut group = c.benchmark_group("event-driven");
    group.throughput(Throughput::Elements(10_000));
    group.bench_function("linear unit, 10000 periods (periods/s)", |b| {
        b.iter(|| simulate(&flow_model, black_box(1.3), &start, &linear))
    });
    group.finish();
}

fn pieces(c: &mut Criterion) {
    // The damped unit's free flow at ω = 2, one flight from a state 0.1 inside side 1.
    let mass = nalgebra::DMatrix::from_row_slice(2, 2, &[2.0, 0.0, 0.0, 1.0]);
    let stiffness = nalgebra::DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]);
    let damping = nalgebra::DMatrix::from_row_slice(2, 2, &[0.15, -0.05, -0.05, 0.05]);
    let fc = DVector::from_vec(vec![6.0, 0.0]);
    let fs = DVector::from_vec(vec![-0.2, 0.0]);
    let flow = LinearFlow::new(
        &mass,
        Some(&damping),
        &stiffness,
        &fc,
        &fs,
        &DVector::zeros(2),
        2.0,
    )
    .expect("flow");
    let y = DVector::from_vec(vec![0.3, 0.7, -0.4, 1.2]);
    let r = DVector::from_vec(vec![-1.0, 1.0, 0.0, 0.0]);
    let mut group = c.benchmark_group("event-driven pieces");
    group.bench_function("flow: state after 0.7 s", |b| {
        b.iter(|| flow.flight(black_box(&y), 0.3).state(black_box(0.7)))
    });
    group.bench_function("first-contact search over one period", |b| {
        b.iter(|| {
            let gap = flow.flight(black_box(&y), 0.3).value_of(&r);
            gap.first_exit(
                -0.5,
                0.5,
                std::f64::consts::PI,
                1e-12 * std::f64::consts::PI,
                1e-13,
                &mut SearchStack::default(),
            )
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = impacts, pieces
}
criterion_main!(benches);
