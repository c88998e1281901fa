//! Cost of continuation in ω on the paper unit: the symmetric `+-` branch over
//! `ω ∈ [2.5, 3.5]` (from the viable symmetric orbit at 2.9) and a `++--` branch over
//! `[1.8, 2.2]` (from the viable orbit at 2.0), switching off, events located. Throughput
//! is reported in branch points per second (`elements/s`).

use criterion::{criterion_group, criterion_main, Criterion, Throughput};
use rattle_analytic::test_models::{paper_stops, paper_unit};
use rattle_analytic::{continue_orbit, signature_orbits, ContinuationSettings, Signature};

fn continuation(c: &mut Criterion) {
    let (unit, stops) = (paper_unit(), paper_stops());
    let cases = [("+-", 2.9, 2.5, 3.5, true), ("++--", 2.0, 1.8, 2.2, false)];
    let mut group = c.benchmark_group("continuation");
    for (text, omega, lo, hi, symmetric) in cases {
        let signature = Signature::parse(text, 1).expect("a valid signature");
        let start = signature_orbits(&unit, &stops, omega, &signature)
            .into_iter()
            .find(|o| o.viable && (!symmetric || (o.impact_phases[1] - 0.5).abs() < 1e-9))
            .expect("a viable start orbit");
        let settings = ContinuationSettings {
            follow_switches: false,
            ..ContinuationSettings::new(lo, hi)
        };
        let points = continue_orbit(&unit, &stops, &start, &settings)
            .expect("continuation runs")
            .branches[0]
            .points
            .len();
        group.throughput(Throughput::Elements(points as u64));
        group.bench_function(format!("{text} branch, {points} points"), |b| {
            b.iter(|| continue_orbit(&unit, &stops, &start, &settings))
        });
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = continuation
}
criterion_main!(benches);
