//! A 400-point analytic sweep of the paper scene, on the machine's threads.

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rattle_compare::scene::Scene;
use rattle_compare::sweep::{frequencies, sweep, Solver};
use rattle_event_driven::SimulationOptions;

fn analytic_sweep(c: &mut Criterion) {
    let scene = Scene::paper();
    let omegas = frequencies(0.1, 4.0, 400);
    let options = SimulationOptions::default();
    let mut group = c.benchmark_group("compare");
    group.throughput(Throughput::Elements(400));
    group.bench_function("analytic sweep, 400 frequencies (points/s)", |b| {
        b.iter(|| sweep(&scene, &omegas, Solver::Analytic, &options, false))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = analytic_sweep
}
criterion_main!(benches);
