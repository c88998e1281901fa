//! The cost of one impact and of one steady-state solve of the event-driven simulator, on the
//! damped paper unit at ω = 2 rad/s (a stable two-impact orbit, `max|μ| = 0.855`).
//!
//! - "one impact": a single flight from a fixed state just after a side-1 impact of the settled
//!   orbit through the first-contact search to the next impact and its restitution, measured as
//!   a run of exactly one forcing period from there (two impacts) divided by two; and the same
//!   over 1000 periods divided by the impacts, which amortises the per-run setup.
//! - "a steady-state solve": from rest until the stroboscopic map repeats to 1e-9 (138 periods,
//!   285 impacts), as `rattle simulate` does, model construction included.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
use rattle_event_driven::{simulate, SimulationOptions, Start};

fn one_impact(c: &mut Criterion) {
    let omega = 2.0;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let settled = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .expect("settles")
    .final_state;
    let mut group = c.benchmark_group("event-driven steady state");
    for periods in [1_u64, 1000] {
        let options = SimulationOptions {
            fixed_periods: Some(periods),
            ..SimulationOptions::default()
        };
        let impacts = simulate(&model, omega, &settled, &options)
            .expect("runs")
            .impacts;
        group.throughput(Throughput::Elements(impacts));
        group.bench_function(
            format!("one impact: {periods} period(s) on the orbit, per impact"),
            |b| b.iter(|| simulate(&model, black_box(omega), &settled, &options)),
        );
    }
    group.finish();
}

fn steady_state_solve(c: &mut Criterion) {
    let omega = 2.0;
    let options = SimulationOptions::default();
    let mut group = c.benchmark_group("event-driven steady state");
    group.bench_function("steady-state solve from rest (periodicity 1e-9)", |b| {
        b.iter(|| {
            let model = paper_unit(black_box(omega), Some(LIGHT_DAMPING), Some((0.5, 0.8)));
            simulate(&model, omega, &Start::rest(2), &options)
        })
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = one_impact, steady_state_solve
}
criterion_main!(benches);
