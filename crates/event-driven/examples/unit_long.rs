//! The whole process on one unit, for timing from outside (`/usr/bin/time`): the paper's unit
//! (`m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`), lightly damped (`c_o = 0.1, c_i = 0.05`, the
//! scene `data/scenes/paper-damped.json`), stops at `±gap` with `e = 0.8`, forced at `ω = 2`
//! (a two-impact orbit), run from rest for a fixed number of periods: model, flows and the
//! event loop, as `rattle simulate data/scenes/paper-damped.json --omega 2 --periods N` does
//! them. Prints the impacts, the time the simulation itself took and impacts per second
//! (issue 24's target: twice main's, about 2.5 M/s on a quiet machine).
//!
//! `cargo run --release -p rattle-event-driven --example unit_long -- [periods] [omega]`
//! (defaults: 1 000 000 periods, ω = 2).
//!
//! Measured (branch h24-speed against main b5cf96f, the two builds alternated, five runs each,
//! medians, `/usr/bin/time -f "%U %e"`; the 2-core machine was shared by six builds and runs,
//! wall times two to ten times the CPU times, so CPU time is quoted): 2 000 009 impacts in
//! 1.59 s of one core before (1.26 M impacts/s) and 1.55 s after (1.29 M/s); callgrind over
//! 20 000 periods (40 009 impacts): 436.3e6 instructions before, 432.8e6 after (−0.8 %: one
//! `sincos` fewer per impact, the forcing phase kept from the contact to the next flight).
//! Issue 24's ×2 is not reached: what the branch did is the crate's restructuring, at the same
//! bits (48 `rattle simulate --json` outputs identical, 4 scenes × 6 frequencies × 2 option
//! sets). Where the time goes (callgrind, main): the one-pair search 65 % (its polish 16 %),
//! `sincos` 12.6 % (per flight: 3 for the grid's steps or the first chunk's end, 3 for the
//! polish's start, 1 each for the flight's and the contact's forcing phase), the contact
//! state 7.5 %, the flight's start 6.4 %. Measured and not taken: searching one pair as the
//! summarised searches do (fixed grid, cached chunk exponentials, seeded polish) costs 9.8 %
//! fewer instructions (436.3e6 → 393.6e6) but moves the unit's last bits.
//!
//! Measured again (branch h24-core against main 2f00f23, whose event-driven crate is b5cf96f's
//! restructured and with one `sincos` fewer per impact, at the same bits by those commits'
//! messages; the two builds alternated, five runs each, medians of
//! `/usr/bin/time -f "%U %e"`; five agents shared the 2-core machine, load average 9 to 11, wall
//! times 2.5 times the CPU times, so CPU time is quoted): 2 000 009 impacts in 1.55 s of one core
//! before (1.29 M impacts/s) and 1.35 s after (1.48 M/s), ×1.15; callgrind over 20 000 periods
//! (40 009 impacts): 432.8e6 instructions before (10 820 per impact), 368.7e6 after (9 220).
//! What changed: the one-pair search of a steady-response flight is the summarised searches'
//! (fixed grid, cached chunk exponentials, polish from a cached seed point: no `sin`/`cos` in
//! the search; it moves the last bits), the fixed grid's last chunk is searched as the whole
//! cached chunk (no fresh exponentials at the section), a one-pair watch makes no quadratic
//! estimate, and a flight reuses the last one's storage (no allocation per flight). Issue 24's
//! ×2 is not reached: where the time goes now (callgrind), the search 64 % (its exit-in-chunk
//! tests and polish 27 %, the polish's exponential steps 10 %), the state at the contact and at
//! the section 9 %, the contact 8 %, the flight's start 5 %; `sin`/`cos` 4 % (the flight's state,
//! the contact's accelerations, the amplitudes of the final stretch).
//!
//! Measured again (branch h24-core2 against main f6e240e and against b5cf96f, each pair of
//! builds alternated, five runs each, medians of `/usr/bin/time -f "%U %e"`; five agents shared
//! the 2-core machine, load average 7 to 11, wall times 1.5 to 2.5 times the CPU times, so CPU
//! time is quoted): 2 000 009 impacts in 1.58 s of one core at b5cf96f, 1.34 s at f6e240e and
//! 1.15 s after (×1.37 over b5cf96f, ×1.17 over f6e240e); `rattle simulate
//! data/scenes/paper-damped.json --omega 2 --periods 1000000`: 1.54 s at f6e240e, 1.08 s after
//! (×1.43), the same impacts and amplitude. Callgrind over 20 000 periods (40 009 impacts):
//! 436.3e6 instructions at b5cf96f (10 900 per impact), 368.7e6 at f6e240e (9 220), 285.0e6
//! after (7 120), −35 % and −23 %. What changed: an impact's flight clears its first chunk by a
//! bound at its start (the chunk test it replaces cost one bisection level and the
//! fourth-derivative bound per impact); the polish's iterates are evaluated on `f`'s degree-7
//! Taylor polynomial at its seed point, and the exponentials advanced once, to the root; a
//! flight that reaches the section is searched on past it and goes on after it (one flight,
//! summary and search per impact instead of 1.5); the polish's series and the
//! fourth-derivative bound cost fewer instructions. Contact times move in their last bits
//! (within the root tolerance); see the branch's commits. Issue 24's ×2 is not reached: where
//! the time goes now (callgrind), the search 57 % (the chunk tests of some five chunks a
//! flight, about 250 instructions each, 26 %; the polish 15 %, of which the exponentials
//! advanced to the root 7 %), the state at the contact and at the section 11 %, the contact
//! 11 % (its forcing phase's `sin`/`cos` included), the flight's start 4 %, `sin`/`cos` 5 %.
//!
//! Measured again (branch h24-core3 against b5cf96f's and main's binaries, the three builds
//! alternated, five runs each, medians of `/usr/bin/time -f "%U %e"`; other agents on the
//! 2-core machine, load average 2.5 to 3.5, wall times within 3 % of the CPU times): 2 000 009
//! impacts in 1.33 s of one core at b5cf96f (1.50 M impacts/s), 0.94 s at main (2.13 M/s) and
//! 0.77 s after (2.60 M/s): ×1.73 over b5cf96f, ×1.22 over main (two earlier alternations, at
//! the branch's commits c6664ef and 6bef556, whose unit runs the same instructions: 1.28, 0.91
//! and 0.75 s, ×1.71; 1.33, 0.93 and 0.77 s, ×1.73). Callgrind over 20 000 periods
//! (40 009 impacts): 436.3e6 instructions at b5cf96f (10 900 per impact), 285.0e6 at main
//! (7 120), 238.8e6 after (5 970), −45 % and −16 %. Every result is bit for bit main's (a
//! comparison program printing, in full precision, the impacts of the final cycle, the
//! stroboscopic states, the final state and the amplitudes of 24 runs of the unit, ω from 0.8
//! to 5, two dampings, fixed and steady-state runs, and of two 300-period chain runs: all
//! identical). What changed: a flight carried past a section of a fixed run that nothing
//! observes (more than the ring's `p_max + 2` sections before the final stretch, nothing
//! recorded) does not form the state there (−7 %: the state's `sin`/`cos`/`exp` and the ring's
//! copy, once a period); the fixed grid's chunk rows are looked up inline (−4 %); a contact's
//! relative velocities and a free impact use the nonzero entries of `d` and `M⁻¹d` only; the
//! most recent fixed grid is taken without a rotation, and a search that departs from a stop
//! forms no quadratic estimate; a flight's deviation is written over its storage; a cached
//! chunk's midpoint values are summed without index checks. Issue 24's ×2 is not reached
//! (×1.73 in CPU time, ×1.83 in instructions). Where the time goes now (callgrind): the search
//! 60 % (the chunk tests and their set-up, some four chunks a flight, 23 %; the polish 23 %, of
//! which the exponentials advanced to the root 8.6 %), the contact 10 % (its forcing phase's
//! `sin`/`cos` 2 %), the glue of the step (watch, pending flight, scratch) 11 %, the state at
//! the contact 6.5 %, the flight's start 4.5 % and its terms 3.4 %; in time (`perf`) the polish
//! weighs more (28 %: its Halley steps' divisions and square roots, the exponentials' series).
//! Measured and not taken: a fat-LTO, one-codegen-unit release profile (at c6664ef: 233.1e6
//! instructions, the same CPU time; on the chain 715.8e6, +2.4 %); the modal deviation carried
//! across the contact as the chain's flights do (+3.5 % instructions for a two-degree-of-freedom
//! unit, and other last bits); the ends of excluded chunks left unevaluated until the next
//! chunk is searched (+2 % here, −1 % on the chain); each term's exponential series stepped on
//! its own rather than four side by side (no change here, +5.5 % on the chain); inline
//! `ceil`/`round` (fewer calls, no measurable time); the fourth-derivative bound of a steady
//! search without the tests that choose its path (no change); a functional's kept weights and
//! the kept rates read in order when a flight writes its terms (+4 % on the chain, the
//! compiler inlining otherwise).
//!
//! Measured again (branch h24-core4, the commits after 2dc52fa on h24-core3, against b5cf96f's
//! binary and 2dc52fa, alternated, five runs each, medians of CPU time, load average 1.8 to
//! 2.7): 1.19 s of one core at b5cf96f, 0.69 s at 2dc52fa and 0.70 s after, the same 2 000 009
//! impacts (three more alternations, the last two at 7ce2255: 1.21, 0.70 and 0.71 s; 1.20,
//! 0.70 and 0.72 s; 1.19, 0.70 and 0.70 s): the unit did not move, or lost 1 to 3 % (×1.70
//! over b5cf96f). Callgrind over 20 000 periods:
//! 238.8e6 instructions at 2dc52fa, 241.0e6 after (+0.9 %, the code around the chain's packed
//! paths; every result bit for bit 2dc52fa's). The round's AVX routines (see `chain8`) are a
//! chain's: with the unit's three terms the packed chunk sums, polish series and local sums
//! cost fewer instructions (231.5e6) but more time (0.72 s → 0.74 s), so they start at eight
//! terms (`PACKED_TERMS`), and a unit's four-entry mode columns stay on the inlined loop
//! (`AVX_COLUMN`; out of line they cost 238.8e6 → 241.7e6).
//!
//! Measured again (branch h24-core5, from d26cb51, against b5cf96f's binary and the branch's
//! start, alternated, five runs each, medians of CPU time, load average 1.1 to 2.1): 1.29 s of
//! one core at b5cf96f, 0.76 s at the start and 0.72 s after, the same 2 000 009 impacts
//! (a second alternation: 1.32, 0.79 and 0.73 s): ×1.79 and ×1.81 over b5cf96f, 5 to 8 %
//! over the start. Issue 24's ×2 (about 0.65 s at these loads) is not reached. Callgrind over
//! 20 000 periods: 241.0e6 instructions at the start, 232.0e6 after (−3.7 %), every result bit
//! for bit the start's (the throwaway comparison program of h24-core4: identical output at
//! every commit). What moved it is work done per search that a run does once: a fixed-grid
//! search formed its derivative coefficients after testing that every polynomial is a
//! constant, which the search is made only for (→ 237.4e6); it found the fastest rate and
//! the half-width from the terms, which the most recent grid of the same rates already holds
//! (→ 233.9e6); a state was zeroed through nalgebra's element iterator (→ 232.0e6). Tried and
//! not taken: the polish's stopping test without its division and square root (`step² ×
//! contraction f'²` against the bounds times `f'²`: the same bits on the comparison program,
//! the same instructions, no measurable time, 0.71 s both, nine runs each: out-of-order
//! execution hides them).
//!
//! Measured again (branch h25-core, from ac8b2d7, against b5cf96f's binary, alternated, five
//! runs each, medians of CPU time, load average 2.2): 1.27 s of one core at b5cf96f and 0.70 s
//! after, the same 2 000 009 impacts (×1.81; an alternation at the branch's fourth commit,
//! b8c3c48, whose unit runs the start's instructions to 0.03 %: 1.31 s and 0.73 s, ×1.79). Issue 24's ×2
//! is not reached. Callgrind over 20 000 periods: 231.9e6 instructions at the start, 229.6e6
//! after (−1.0 %), every result bit for bit the start's (a throwaway program printing in full
//! precision the final cycle's impacts, stroboscopic states and amplitudes of 139 runs: the
//! four unit scenes of `data/scenes` at nine frequencies from 0.3 to 5, fixed and until
//! steady, the two chain scenes at four, the previous rounds' 32 unit and 9 chain runs, a
//! sticking unit (gap 0.25) at four frequencies and a chain with plastic pairs: identical
//! output at every commit). What moved it: the polish's last step, the exponentials' series
//! to the root, stepped a fourth, empty lane for the unit's three terms through every degree
//! (blocks of as many lanes as terms now). The branch's other commits are for the chain's
//! final stretch and for steady-state runs (`steady_sweep`). Where the time goes now (`perf`,
//! 300 000 periods): the polish 17 % (its Halley steps' divisions and square root, its local
//! polynomial's sums), the fixed grid's chunk tests 15 %, the exponentials advanced to the
//! root 11 % (dependent complex products: latency, not instructions), the contact 7.6 %, the
//! search's summary 7.3 %, the run loop 6.4 %, the bisection within the contact's chunk 5 %,
//! the state at the contact 4.9 %, `round`/`ceil` calls 2.2 %, `sin`/`cos` 2.2 %. The search
//! is one chunk test and one polish per impact already; what remains is arithmetic whose
//! bits a faster form would move (Estrin's scheme for the series, the forcing phase at the
//! contact from the search's exponentials, a cheaper polish start).
//!
//! Measured again (stop 28, main 46c371b against b5cf96f's binary and 9a6d237, the three
//! builds alternated, five runs each, medians of CPU time, load average 1.4 to 1.5): 1.16 s of
//! one core at b5cf96f, 0.67 s at 9a6d237 and 0.51 s after, the same 2 000 009 impacts:
//! **×2.27 over b5cf96f** (issue 24's ×2 for the unit; a second alternation 1.20, 0.68 and
//! 0.52 s, ×2.31). Callgrind over 20 000 periods: 229.2e6 instructions at 9a6d237, 207.8e6
//! after (b5cf96f 436.3e6: ×2.10). What moved it: a fixed run of 1000 periods or more recalls
//! each pair's last two polished exits with the exponentials there (`Seeds::recalled`); a
//! flight whose Newton step from one is within 4e-6 of the chunk's half-width (it repeats the
//! flight a period earlier) starts its polish there, and the polish stops after one
//! evaluation, from the exponentials, without forming the degree-7 Taylor polynomial, the
//! exponentials then advanced to the root by a first-degree step. Before, every polish
//! started at the seed point nearest the quadratic model's guess, which misses a steady
//! flight's exit by about w/80, and took two evaluations. Contact times move in their last
//! bits: `rattle simulate --periods 3000` on the damped and the undamped paper unit at seven
//! frequencies from 0.8 to 4.5 rad/s, 14 runs: 7 bit for bit (the non-periodic ones, where no
//! flight repeats), the periodic ones within 3e-13 in amplitude, 1.6e-12 in a Floquet
//! multiplier and 1e-11 relative in a transmittance of 0.01 dB. Runs until periodic, the
//! engine's final stretches and the Newton's one-cycle runs do not recall (with recall in
//! every run a sweep and a map cost 1 to 2 % more and moved their last bits): `cargo xtask
//! figures` writes the same bits as before. Where the time goes now (callgrind, inclusive):
//! the search 50 % (the exit's chunk, its test and polish, 14 %), the state at the contact
//! 7 %, the contact 5.5 %, the flight's start 2.3 %.

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
