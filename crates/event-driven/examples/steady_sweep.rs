//! Steady-state runs from rest over a sweep of frequencies, as `rattle sweep` and the figures
//! make them (half the CPU of `cargo xtask figures` is in the event core, mostly in such runs):
//! the paper's unit (`m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`), stops at `±0.5` with
//! `e = 0.8`, lightly damped (`c_o = 0.1, c_i = 0.05`) and undamped, each run from rest with
//! the default options (until steady, or the caps). Prints the impacts and periods run over
//! the sweep and the time the simulations took.
//!
//! `cargo run --release -p rattle-event-driven --example steady_sweep -- [frequencies]`
//! (default 12 frequencies, ω from 0.5 to 5).
//!
//! Measured (branch h25-core, callgrind, 12 frequencies, 987 343 impacts, 249 216 periods):
//! 9339.2e6 instructions at its start ac8b2d7, 8766.7e6 after (−6.1 %), every result bit for
//! bit the start's. What moved it: the periodicity test at each section (8.5 % at the start)
//! summed over the states as slices rather than through nalgebra's element iterators
//! (→ 8932.9e6) and its first test's limit formed once per section (→ 8795.4e6 with the next);
//! a search's real exponential not called where it is exactly 1 (→ 8837.2e6: an undamped
//! flow's rates have real parts of a few `1e-17`, rounding of its eigenvalues). Where the time
//! goes now: the undamped half's searches take the horizon grid's path, not the fixed grid's
//! (those rates count as growing), whose bisection evaluates fresh exponentials (`eval3`,
//! 13 % with its `sin`/`cos`) and whose steps are formed per flight (3 %); `sin`/`cos` are 12 %
//! of the whole. Treating rates that small as zero would send them down the fixed grid's
//! path, but it moves every undamped run's bits (and a chaotic run's trajectory with them).
//!
//! Stop 26 took both, moving bits (interleaved medians of 5, wall): 0.55 s at 40c81f7; 0.52 s
//! with musl's `sincos` for glibc's (`trig`); 0.49 s with an undamped system's rates purely
//! imaginary (`flow::conservative_rates`). 986 586 impacts over 249 080 periods instead of
//! 987 343 over 249 216: the undamped chaotic runs take other paths.

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
