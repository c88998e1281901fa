//! One long run of the paper's unit, whole process, for timing from outside (`/usr/bin/time`,
//! `perf stat`, callgrind): the unit (`m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`), lightly
//! damped (`c_o = 0.1, c_i = 0.05`, the scene `data/scenes/paper-damped.json`), with stops at
//! `±0.5` and `e = 0.8`, forced at `ω` (2 by default: a two-impact orbit) and run from rest for
//! a fixed number of periods: the model, its flows and the event loop, as
//! `rattle simulate data/scenes/paper-damped.json --omega 2 --periods N` runs them.
//!
//! ```text
//! cargo run --release -p rattle-event-driven --example unit_long -- [periods] [omega]
//! ```
//!
//! (defaults: 1 000 000 periods, ω = 2). It prints the run (gap, restitution, ω, periods,
//! impacts, whether the final stretch sticks), then the time the simulation took and the
//! impacts per second. The measured times, and where the time goes, are on the performance
//! page, `docs/performance.md`.

use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
use rattle_event_driven::{simulate, SimulationOptions, Start};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let periods: u64 = match args.next() {
        Some(a) => a.parse()?,
        None => 1_000_000,
    };
    let omega: f64 = match args.next() {
        Some(a) => a.parse()?,
        None => 2.0,
    };
    let clock = Instant::now();
    let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
    let options = SimulationOptions {
        fixed_periods: Some(periods),
        ..SimulationOptions::default()
    };
    let run = simulate(&model, omega, &Start::rest(2), &options)?;
    let seconds = clock.elapsed().as_secs_f64();
    println!(
        "unit, gap 0.5, e 0.8, omega {omega}: {periods} periods from rest, {} impacts, \
         sticking in the final stretch: {}",
        run.impacts, run.sticking
    );
    println!(
        "{seconds:.3} s, {:.0} impacts/s",
        run.impacts as f64 / seconds
    );
    Ok(())
}
