//! Cost of the Lyapunov spectrum against the plain simulation of as many periods: the paper's
//! unit at its chaotic point (ω = 1.25, Δ = 0.25, e = 0.8, light damping; `tests/lyapunov.rs`),
//! 1000 periods from the settled state, both ways. Target: the exponents within 2× the plain run.

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
use rattle_event_driven::{
    lyapunov_exponents, simulate, LyapunovOptions, SimulationOptions, Start,
};

/// Periods of both runs.
const PERIODS: u64 = 1000;

fn exponents_against_plain_run(c: &mut Criterion) {
    let omega = 1.25;
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.25, 0.8)));
    let settled: Start = simulate(
        &model,
        omega,
        &Start::rest(2),
        &SimulationOptions::default(),
    )
    .expect("runs")
    .final_state;
    let plain = SimulationOptions {
        fixed_periods: Some(PERIODS),
        polish: false,
        ..SimulationOptions::default()
    };
    // The same 1000 periods, all counted (no alignment periods), for a like-for-like ratio;
    // the default adds `DEFAULT_ALIGNMENT_PERIODS` more.
    let exponents = LyapunovOptions {
        periods: PERIODS,
        alignment_periods: 0,
        ..LyapunovOptions::default()
    };
    let mut group = c.benchmark_group("lyapunov");
    group.bench_function("plain simulation, 1000 periods (chaotic)", |b| {
        b.iter(|| simulate(&model, black_box(omega), &settled, &plain))
    });
    group.bench_function("Lyapunov spectrum, 1000 periods (chaotic)", |b| {
        b.iter(|| lyapunov_exponents(&model, black_box(omega), &settled, &exponents))
    });
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = exponents_against_plain_run
}
criterion_main!(benches);
