//! One long run of the metamaterial, whole process, for timing from outside (`/usr/bin/time`,
//! `perf stat`, callgrind): an 8-cell chain of the paper's cell (`m_i = 1, m_o = 2, k_i = 3,
//! k_o = 6, u_g = 1`), lightly damped (`c_o = 0.1, c_i = 0.05`), with stops at `±gap` and
//! `e = 0.8`, forced at `ω = 2` and run from rest for a fixed number of periods: the model, its
//! flows and the event loop, as `simulate` runs them.
//!
//! ```text
//! cargo run --release -p rattle-event-driven --example chain8 -- [periods] [gap]
//! ```
//!
//! (defaults: 20 000 periods, gap 0.5). It prints the run (cells, gap, periods, impacts,
//! whether the final stretch sticks), then the time the simulation took and the impacts per
//! second. The measured times, and where the time goes, are on the performance page,
//! `docs/performance.md`.

use rattle_event_driven::test_models::{paper_chain, LIGHT_DAMPING};
use rattle_event_driven::{simulate, CellStops, SimulationOptions, Start};
use std::time::Instant;

/// Cells of the chain.
const CELLS: usize = 8;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let periods: u64 = match args.next() {
        Some(a) => a.parse()?,
        None => 20_000,
    };
    let gap: f64 = match args.next() {
        Some(a) => a.parse()?,
        None => 0.5,
    };
    let omega = 2.0;
    let clock = Instant::now();
    let model = paper_chain(
        CELLS,
        omega,
        Some(LIGHT_DAMPING),
        Some(CellStops::symmetric(gap, 0.8)),
    );
    let options = SimulationOptions {
        fixed_periods: Some(periods),
        ..SimulationOptions::default()
    };
    let run = simulate(&model, omega, &Start::rest(2 * CELLS), &options)?;
    let seconds = clock.elapsed().as_secs_f64();
    println!(
        "{CELLS} cells, gap {gap}, e 0.8, omega {omega}: {periods} periods from rest, {} impacts, \
         sticking in the final stretch: {}",
        run.impacts, run.sticking
    );
    println!(
        "{seconds:.3} s, {:.0} impacts/s",
        run.impacts as f64 / seconds
    );
    Ok(())
}
