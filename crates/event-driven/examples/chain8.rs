//! The whole process on the metamaterial, for timing from outside (`/usr/bin/time`): an
//! 8-cell chain of the paper's cell (`m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`), lightly
//! damped (`c_o = 0.1, c_i = 0.05`), stops at `±gap` with `e = 0.8`, forced at `ω = 2`, run
//! from rest for a fixed number of periods: model, flows and the event loop, as `simulate`
//! does them. Prints the impacts, the time the simulation itself took and impacts per second
//! (issue 16's target: 300 000).
//!
//! `cargo run --release -p rattle-event-driven --example chain8 -- [periods] [gap]`
//! (defaults: 20 000 periods, gap 0.5).
//!
//! Measured (branch h-chainspeed, 2-core machine shared with other builds, so CPU time from
//! `/usr/bin/time -f %U`, three runs each): 368 750 impacts in 2.0 s of one core, about
//! 180 000 impacts/s, against 3.0 s (122 000 impacts/s) before that branch; the callgrind
//! instruction count of the first 1000 periods fell from 1.86e9 to 1.20e9.
//!
//! Measured again (branch h-speed2, the previous build and this one alternated, three runs each,
//! medians): 2.00 s of one core for 368 750 impacts (184 000 impacts/s) before, 1.62 s for 368 790
//! impacts (228 000 impacts/s) after, ×1.24; callgrind, first 1000 periods: 1.205e9 instructions
//! (18 388 impacts, 65 500 per impact) before, 0.979e9 (18 411 impacts, 53 100 per impact) after.
//! What changed: every pair's summary is formed in one pass over the modes, two pairs side by side,
//! and handed to the pair's search (bit-identical sums); a flight after a contact starts from the
//! modal deviation carried across it instead of `V⁻¹y` (a chain's last bits change; the impact
//! count of this long run moves from 368 750 to 368 790). Issue 16's 300 000 impacts/s is still not
//! reached. Where the time goes now (callgrind, first 1000 periods): the first-contact searches
//! that the bounds do not decide, 50 % (bisection evaluations 16 %, Halley polish 15 %, each
//! starting from 17 fresh complex exponentials), the summaries 12 %, the state at the contact 10 %,
//! the amplitudes of the observed final stretch 7 % (none in a longer run); `sin`, `cos` and `exp`
//! are some 18 % within these (the grid's steps, the polish start, the bisection points). What is
//! left: seeding the polish and the bisection points from exponentials already known (it needs a
//! complex exponential for steps up to about 0.4, likely no cheaper than the library's), and
//! per-pair bounds updated across an impact (it changes two velocities) rather than formed again.

use rattle_event_driven::test_models::{paper_chain, LIGHT_DAMPING};
use rattle_event_driven::{simulate, CellStops, SimulationOptions, Start};
use std::time::Instant;

/// Cells of the chain (the target chain).
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
