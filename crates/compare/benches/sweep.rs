//! Analytic sweeps of the paper scene on the machine's threads: 400 points in memory, and
//! 10 000 points streamed through each table writer (what `rattle sweep --out F` does, less
//! the file).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rattle_compare::output::{writer, Format};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::sweep::{header, sweep, sweep_rows, Solver};
use rattle_compare::scene::Scene;
use rattle_event_driven::SimulationOptions;

fn analytic_sweep(c: &mut Criterion) {
    let scene = Scene::paper();
    let omegas = Axis::new(0.1, 4.0, 400).values();
    let options = SimulationOptions::default();
    let mut group = c.benchmark_group("compare");
    group.throughput(Throughput::Elements(400));
    group.bench_function("analytic sweep, 400 frequencies (points/s)", |b| {
        b.iter(|| {
            sweep(
                &scene,
                &omegas,
                Solver::Analytic,
                &options,
                &Progress::hidden(),
            )
        })
    });
    let omegas = Axis::new(0.1, 4.0, 10_000).values();
    group.throughput(Throughput::Elements(10_000));
    group.sample_size(10);
    for (format, name) in [(Format::Csv, "csv"), (Format::Json, "json")] {
        group.bench_function(
            format!("analytic sweep streamed to {name}, 10 000 frequencies"),
            |b| {
                b.iter(|| {
                    let head = header(&scene, Solver::Analytic, omegas.len(), None);
                    let mut table = writer(format, std::io::sink(), &head, None).unwrap();
                    sweep_rows(
                        &scene,
                        &omegas,
                        Solver::Analytic,
                        &options,
                        &Progress::hidden(),
                        |row| table.row(&row),
                    )
                    .unwrap();
                    table.finish().unwrap();
                })
            },
        );
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = analytic_sweep
}
criterion_main!(benches);
