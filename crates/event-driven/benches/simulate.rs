//! Throughput of the event-driven simulator: impacts per second on a damped 2-DOF scene with
//! contact times to 1e-12 relative, and the cost of the pieces of one event.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use nalgebra::DVector;
use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
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

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = impacts
}
criterion_main!(benches);
