//! The bare Rust call behind `rattle.simulate(Scene.paper(), 2.0, periods=100)`: the simulator
//! from rest for 100 forcing periods, then the command's record of it and that record as JSON
//! text (what the Python module adds on the Rust side). `benches/overhead.py` times the same
//! call from Python; the difference is the module's overhead.

use criterion::{criterion_group, criterion_main, Criterion};
use rattle_compare::output::records::SimulationRecord;
use rattle_compare::scene::simulator::run;
use rattle_compare::scene::Scene;
use rattle_event_driven::{SimulationOptions, Start};
use std::hint::black_box;

/// Forcing frequency of the benchmark, rad/s: the paper scene's two-impact regime.
const OMEGA: f64 = 2.0;
/// Forcing periods simulated: as many as the Python call it is compared with.
const PERIODS: u64 = 100;

fn simulate_100_periods(c: &mut Criterion) {
    let scene = Scene::paper();
    let options = SimulationOptions {
        fixed_periods: Some(PERIODS),
        ..SimulationOptions::default()
    };
    let mut group = c.benchmark_group("python");
    group.bench_function("simulate 100 periods (bare Rust)", |b| {
        b.iter(|| run(black_box(&scene), OMEGA, &Start::rest(2), &options).unwrap())
    });
    let sim = run(&scene, OMEGA, &Start::rest(2), &options).unwrap();
    group.bench_function("record and JSON text of a simulation", |b| {
        b.iter(|| serde_json::to_string(&SimulationRecord::new(&scene, black_box(&sim))).unwrap())
    });
    group.finish();
}

criterion_group!(benches, simulate_100_periods);
criterion_main!(benches);
