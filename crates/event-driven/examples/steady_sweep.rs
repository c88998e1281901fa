//! Steady-state runs from rest over a sweep of frequencies, as `rattle sweep` and the figures
//! make them (half the CPU of `cargo xtask figures` is in the event core, mostly in such runs):
//! the paper's unit (`m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`), stops at `±0.5` with
//! `e = 0.8`, lightly damped (`c_o = 0.1, c_i = 0.05`) and undamped, each run from rest with
//! the default options (until steady, or the caps). Prints the impacts and periods run over
//! the sweep and the time the simulations took.
//!
//! ```text
//! cargo run --release -p rattle-event-driven --example steady_sweep -- [frequencies]
//! ```
//!
//! (default 12 frequencies, ω from 0.5 to 5). The measured times, and where the time goes,
//! are on the performance page, `docs/performance.md`.

use rattle_event_driven::test_models::{paper_unit, LIGHT_DAMPING};
use rattle_event_driven::{simulate, SimulationOptions, Start};
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let frequencies: usize = match std::env::args().nth(1) {
        Some(a) => a.parse()?,
        None => 12,
    };
    let clock = Instant::now();
    let (mut impacts, mut periods) = (0, 0);
    for damping in [Some(LIGHT_DAMPING), None] {
        for i in 0..frequencies {
            let omega = 0.5 + 4.5 * i as f64 / (frequencies.max(2) - 1) as f64;
            let model = paper_unit(omega, damping, Some((0.5, 0.8)));
            let run = simulate(
                &model,
                omega,
                &Start::rest(2),
                &SimulationOptions::default(),
            )?;
            impacts += run.impacts;
            periods += run.periods_run;
        }
    }
    let seconds = clock.elapsed().as_secs_f64();
    println!("{frequencies} frequencies, 2 dampings: {impacts} impacts, {periods} periods run");
    println!("{seconds:.3} s");
    Ok(())
}
