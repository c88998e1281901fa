//! Throughput of the event-driven simulator on the metamaterial: impacts per second of an
//! 8-cell chain of the paper's cell (`m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`), lightly
//! damped (`c_o = 0.1, c_i = 0.05`), `e = 0.8`, for the two readings of the paper's gap
//! (`Δ = 0.5` and `Δ = 0.25`), whole process (`simulate` with a fixed number of periods from a
//! settled state, model and flows built in each iteration). The target is 300 000 impacts/s.
//!
//! The measured throughput is on the performance page (`docs/performance.md`), with the
//! command that reproduces it.

use criterion::{black_box, criterion_group, criterion_main, Criterion, Throughput};
use rattle_event_driven::test_models::{paper_chain, LIGHT_DAMPING};
use rattle_event_driven::{simulate, CellStops, SimulationOptions, Start};

/// Cells of the benchmarked chain (the target chain of the throughput figure).
const CELLS: usize = 8;

/// Periods per iteration: enough impacts (tens of thousands) that the set-up and the final
/// observed stretch (16 periods, amplitudes from closed-form extrema) are a small part.
const PERIODS: u64 = 1000;

fn chain_impacts(c: &mut Criterion) {
    let omega = 2.0;
    let mut group = c.benchmark_group("event-driven chain");
    for gap in [0.5, 0.25] {
        let stops = Some(CellStops::symmetric(gap, 0.8));
        let model = paper_chain(CELLS, omega, Some(LIGHT_DAMPING), stops);
        // Settle first (the transient from rest), then time a fixed stretch.
        let settle = SimulationOptions {
            fixed_periods: Some(500),
            ..SimulationOptions::default()
        };
        let settled = simulate(&model, omega, &Start::rest(2 * CELLS), &settle)
            .expect("runs")
            .final_state;
        let options = SimulationOptions {
            fixed_periods: Some(PERIODS),
            ..SimulationOptions::default()
        };
        let probe = simulate(&model, omega, &settled, &options).expect("runs");
        group.throughput(Throughput::Elements(probe.impacts));
        group.bench_function(
            format!(
                "8 cells, gap {gap}, e 0.8, ω 2, {PERIODS} periods: {} impacts, {} sticking (impacts/s)",
                probe.impacts, probe.sticking
            ),
            |b| {
                b.iter(|| {
                    let model = paper_chain(CELLS, black_box(omega), Some(LIGHT_DAMPING), stops);
                    simulate(&model, omega, &settled, &options)
                })
            },
        );
    }
    group.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = chain_impacts
}
criterion_main!(benches);
