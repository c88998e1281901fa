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
//!
//! Measured again (branch h-speed3, the previous build and this one alternated, three runs each,
//! medians, `/usr/bin/time -f "%U %e"` around the whole process): 1.63 s of one core and 1.63 s
//! wall for 368 790 impacts before (the example's own count 225 000 impacts/s), 1.19 s of one
//! core and 1.19 s wall for 368 735 impacts after (310 000 impacts/s whole process; the example's
//! own count 309 000), ×1.37: issue 16's 300 000 impacts/s is reached, with little margin (a busy
//! machine moves these times by 10 % and more: a second alternation, the machine busier, gave
//! 1.67 s before and 1.22 s after, the same ×1.37, 302 000 impacts/s by the example's count). Callgrind, first 1000 periods: 0.979e9
//! instructions (18 411 impacts, 53 100 per impact) before, 0.774e9 (18 411 impacts, 42 000 per
//! impact) after. What changed, all in the several-pair (summarised) searches; the one-pair
//! searches are untouched and a single unit's results are bit for bit as before:
//! - the grid's half-width is fixed by the rates (`π/(8 max|μ|)`) rather than by the horizon, so
//!   its exponentials are kept from flight to flight: each chunk's `e^{μm}`, `μe^{μm}`, `μ²e^{μm}`,
//!   `μ³e^{μm}` at its midpoint and `e^{μb}` at its end are evaluated afresh once per run, and a
//!   chunk's test costs four sums of the terms' coefficients against them (no step recurrence,
//!   no derivative products unless a chunk is not excluded); the last, shorter chunk is excluded
//!   by the test on the whole chunk that contains it;
//! - the polish starts at the seed point nearest its guess, `m + kw/64`, whose exponentials are
//!   the cached ones at the chunk's midpoint times a kept step (no fresh exponentials), and its
//!   steps take every term's series together, to the least degree (1 to 8) the largest step needs;
//! - the head of short chunks (a short flight) lies on those seed points too;
//! - a summarised search does not repeat the exclusion tests the watch has just made, the watch
//!   reads the joint summaries in place, and the quadratic estimate skips the side the model moves
//!   away from;
//! - summaries form `f''(0)` as `Re(c·μ²)` and `sup|f''|` from `rate²` (no measurable gain).
//!
//! A chain's last bits change (the searches evaluate at other points, from other exponentials;
//! contact times agree with the one-pair search's to the time tolerance, see the test
//! `summarised_searches_find_the_one_pair_searches_exits`): the impact count of this long run
//! moves from 368 790 to 368 735, that of the first 1000 periods stays 18 411. Where the time goes
//! now (`perf`, the whole run): the grid searches some 16 %, the summaries 15 %, the polish 15 %
//! (a fifth of the polishes are of contacts that a later search of the same flight finds earlier),
//! the state at the contact 10 %, the quadratic estimates 5 %, the watch and run loop 5 %, the
//! exclusion tests 3.5 %, `sin`/`cos` 3 %. What is left: polishing only the flight's winning
//! contact (searches returning brackets), estimates only for pairs the summary does not exclude
//! over the whole horizon (it cost more instructions than it saved when tried), and wider
//! registers for the summaries and the contact state (both are packed two wide now).
//!
//! Measured again (branch h24-core against main 2f00f23, alternated, five runs each, medians,
//! CPU time on a 2-core machine shared by five agents): 1.01 s of one core before (368 735
//! impacts) and 1.01 s after (368 624 impacts): no change; callgrind, first 1000 periods: 779.8e6
//! instructions (18 411 impacts, 42 400 per impact) before, 759.4e6 (18 398 impacts, 41 300 per
//! impact) after. The chain's searches were already the summarised ones; what moved its last
//! bits is the fixed grid's last chunk, searched as the whole cached chunk.
//!
//! Measured again (branch h24-core2 against b5cf96f, alternated, five runs each, medians of CPU
//! time, five agents on the 2-core machine, load average 11): 1.00 s of one core before
//! (368 735 impacts) and 1.01 s after (368 712 impacts): no change; callgrind, first 1000
//! periods: 774.1e6 instructions at b5cf96f (18 411 impacts, 42 000 per impact), 759.4e6 at
//! f6e240e (18 398), 733.4e6 after (18 418 impacts, 39 800 per impact), −5 %. The chain gains
//! from the departure bound and the polish on the Taylor polynomial; its flights still restart
//! at each section (searching eight pairs' summaries past it cost more than it saved). In the
//! first 1000 periods the final stretch's amplitudes are 10 % (none in a longer run); the
//! summaries 16 %, the chunk tests and polish of the searches 35 %, the contact states 13 %.
//!
//! Measured again (branch h24-core3 against b5cf96f's and main's binaries, alternated, five runs
//! each, medians of CPU time, load average 2.5 to 3.5): 0.99 s of one core at b5cf96f (368 735
//! impacts, 372 000 impacts/s), 0.97 s at main (368 712) and 0.87 s after (368 712, 424 000
//! impacts/s): ×1.14 over b5cf96f, ×1.11 over main (two earlier alternations, at the branch's
//! commits c6664ef and 6bef556: 0.91, 0.88 and 0.84 s; 0.96, 0.92 and 0.88 s; ×1.08 and ×1.09 over
//! b5cf96f). Callgrind, first 1000 periods: 774.1e6 instructions at b5cf96f (18 411 impacts),
//! 733.4e6 at main (18 418), 690.5e6 after (18 418 impacts, 37 500 per impact), −10.8 % and −5.8 %,
//! every result bit for bit main's. What moved it: the fixed grid's chunk rows looked up inline, a
//! cached chunk's midpoint values summed without index checks, a contact's relative velocities and
//! free impact over the nonzero entries of `d` and `M⁻¹d`, a carried deviation's storage reused (a
//! carry allocated and freed a vector per impact) and its jump added over `V⁻¹`'s kept-mode columns
//! laid out contiguously, the contact depth's largest position taken on the slice. The unobserved
//! sections that gain the unit 7 % do not apply: the chain's flights still restart at each section.
//! Issue 24's ×2 is far from reached. Where the time goes now (first 1000 periods): the searches
//! 35 % (the chunk tests and their set-up 20 %, the polish 14 %, of which the exponentials advanced
//! to the root 6 %), the summaries 17 %, the contact states 13 % (the state from all kept modes, a
//! dense product already packed two wide), the final stretch's amplitudes 10 % (none in a longer
//! run), writing the searched pairs' terms 5.7 %, the carried deviation 3.6 %. What is left for ×2
//! is structural: a contact's state formed only where it is read (its pair's rows, the largest
//! position and velocity), summaries updated across an impact rather than formed again, polishing
//! only the flight's winning contact.
//!
//! Measured again (branch h24-core4, the commits after 2dc52fa on h24-core3, against b5cf96f's
//! binary and the branch's start 2dc52fa, alternated, five runs each, medians of CPU time, load
//! average 1.8 to 2.7): 0.85 s of one core at b5cf96f (368 735 impacts, 434 000 impacts/s), 0.78 s
//! at 2dc52fa (368 712) and 0.63 s after (368 712, 585 000 impacts/s): ×1.35 over b5cf96f, ×1.24
//! over 2dc52fa (a second alternation: 0.84, 0.78 and 0.63 s; two earlier, at 5dc1f0a and 5d83e00:
//! 0.85, 0.78 and 0.64 s). Issue 24's ×2 (about 0.43 s) is not reached. Callgrind, first 1000
//! periods: 774.1e6 instructions at b5cf96f (18 411 impacts), 690.5e6 at 2dc52fa (18 418), 536.1e6
//! after (18 418 impacts, 29 100 per impact), −30.7 % and −22.4 %; first 5000 periods (where the
//! final stretch's amplitudes weigh less): 3482.2e6 at b5cf96f (92 159 impacts), 3072.5e6 at
//! 2dc52fa (92 155), 2303.2e6 after (92 155), −33.9 % and −25.0 %. Every result is bit for bit
//! 2dc52fa's (a throwaway program printing the final cycle's impacts, stroboscopic states and
//! amplitudes of 32 unit runs and 9 chain runs in full precision: identical output at every
//! commit). What moved it is width, not structure: the hot sums run four lanes wide with AVX when
//! the CPU has it (a run-time check; each lane's operations in the scalar order, no FMA, so the
//! same bits, and each packed routine has a test against its scalar sums bit for bit; without AVX
//! the scalar code runs as before). By commit, `chain8 1000`: the joint summaries four pairs to a
//! block with AVX intrinsics and the state's mode columns added four entries at once, 690.5e6 →
//! 613.8e6; a cached chunk's `f, f', f''` at its midpoint and `f` at its end in one packed pass
//! over rows laid out term by term (beside the rows by kind), → 580.6e6; the polish's series two
//! terms to a register, → 567.0e6; its local polynomial's first four sums packed, → 555.0e6; the
//! contact state's mode coefficients two modes to a register and the columns added in line, →
//! 545.1e6; the packed sums and series only from eight terms on (`PACKED_TERMS`, for the unit), →
//! 545.5e6; a known exponential read by a `match` in the packed state (`Option::map_or_else` was
//! left out of line there), → 536.1e6. Tried and not taken: the summaries' four lanes left to the
//! compiler under `target_feature` (it packed across the sums rather than the lanes: 73.4e6 →
//! 84.6e6 instructions in `summarize`, 61.5e6 with the lanes written quantity by quantity, 30e6
//! with intrinsics); the packed routines for a unit's three terms (fewer instructions, more time);
//! a unit's chunks without the packed rows' room (243.2e6 instructions, no measurable time). Where
//! the time goes now (callgrind, first 5000 periods): the searches 39 % (the polish 12 %, its
//! series 6 %, the packed chunk sums 3.4 %), the summaries 12.9 %, the contact states 12.2 %,
//! writing the searched pairs' terms 7.9 %, the carried deviation 5.5 %, the final stretch's
//! amplitudes 3.8 %. The structural levers above are still open, and with them the ×2: none was
//! attempted in this round.
//!
//! Measured again (branch h24-core5, from d26cb51, against b5cf96f's binary and the branch's
//! start, alternated, five runs each, medians of CPU time, load average 1.1 to 2.1): 0.92 s of
//! one core at b5cf96f, 0.69 s at the start and 0.63 s after, the same 368 712 impacts (a
//! second alternation: 0.88, 0.66 and 0.60 s): ×1.46 and ×1.47 over b5cf96f, 9 % over the
//! start. Issue 24's ×2 is not reached. Callgrind, first 1000 periods: 536.1e6 instructions
//! at the start, 505.2e6 after (−5.8 %, 27 400 per impact), every result bit for bit the
//! start's. By commit: a fixed-grid search's derivative coefficients formed without testing
//! its seventeen polynomials for constants (six comparisons a term, some 2.7 % of the time by
//! `perf`), → 524.4e6; the half-width of the most recent fixed grid of the same rates taken
//! as it is (no pass over the terms for the fastest rate, no division), → 512.4e6; the state
//! zeroed as a slice rather than through nalgebra's element iterator (7.1e6 instructions), →
//! 505.2e6. Tried and not taken: the kept modes' columns added eight modes to a pass over the
//! state, each block of the state in a register (the same bits; 536.1e6 → 539.0e6, no
//! measurable time); pairs that their summary excludes on the whole horizon left out of the
//! order without an estimate (the same bits, but at this chain's full-period horizons no
//! summary excludes a pair: the test only added, 536.1e6 → 545.0e6); a search's quadratic
//! estimate passed from the order's instead of formed again (the same bits, 505.2e6 →
//! 503.4e6, no measurable time: 0.60 s both, seven runs each). The structural levers (a
//! contact's state formed only where it is read, summaries updated across an impact,
//! polishing only the flight's winning contact: 24 005 polishes for 18 418 impacts in the
//! first 1000 periods) are still open.
//!
//! Measured again (branch h25-core, from ac8b2d7, against b5cf96f's binary, alternated, five
//! runs each, medians of CPU time, load average 2.2): 0.91 s of one core at b5cf96f and 0.61 s
//! after, the same 368 712 impacts (×1.49, at d23b2d4; an alternation at the branch's
//! fourth commit b8c3c48: 0.92 s and 0.65 s, ×1.42; at 43dc924, the carry's commit, load
//! average 5 to 6: 0.92 s and 0.62 s, ×1.48). Issue 24's
//! ×2 (about 0.45 s) is not reached. Callgrind, first 1000 periods: 505.0e6 instructions at
//! the start, 481.7e6 after (−4.6 %), every result bit for bit the start's (the throwaway
//! program of `unit_long`'s last paragraph: 139 runs, 13 of them chains). What moved it is
//! the final stretch's amplitudes (14 % of these 1000 periods, none in a longer run): the
//! sixteen recorded coordinates share their rates, and `max_abs`'s bisection evaluates them
//! at the same points down to where the coordinates part, so the exponentials at its ends and
//! first eight levels are kept per rate and time and evaluated once (505.0e6 → 486.0e6; the
//! same evaluations, so the same bits); and the polish's series in blocks of as many lanes as
//! terms (the odd seventeenth term no longer stepped in a block of four, → 485.6e6). A long
//! run gains little from either. A contact's jump is added to the carried deviation over the
//! pair's free-impact velocities only, the entries it can change, rather than by comparing
//! the whole state (→ 481.7e6; the same additions in the same order). Tried and not taken: two blocks of pairs summarised in one
//! pass over the modes, each mode's scalars and broadcasts formed once (the same bits; 485.6e6
//! → 496.5e6 written with a per-block helper, 520.9e6 with a const-generic loop: fourteen
//! accumulators and nine broadcasts spill from AVX's sixteen registers); the state's column
//! loop by blocks rather than `step_by` (487.2e6 → 487.0e6, nothing); the watch's order
//! sorted as integer keys and slots rather than five-field entries by `total_cmp` (the same
//! order: 485.6e6 → 485.2e6, but the unit's one-pair watch 229.6e6 → 230.5e6, and 0.61 s →
//! 0.60 s, within the noise); the carried deviation's storage not zeroed before its kept
//! entries are written (481.7e6 → 481.8e6). Where the time goes now
//! (`perf`, 20 000 periods): the contact state 10.4 %, the chunk tests of the searches 10.2 %,
//! the summaries 10.2 %, the polish's local sums 6.6 %, the run loop 5.9 %, the quadratic
//! estimates that order the searches 5.5 % (a square root and divisions per pair and flight),
//! the summaries' exclusion tests 4.5 %, the polish 4.5 %, iterator folds (mostly writing the
//! searched pairs' terms, and their derivative coefficients) 4.2 %, the exponentials' series 5.5 %, `sin`/`cos` 2.6 %, the order's sort 1.4 %. The
//! structural levers of the last rounds (a contact's state formed only where it is read,
//! summaries updated across an impact, polishing only the flight's winning contact) are still
//! open, and with them the ×2.
//!
//! Measured again (branch h26-core, from 40c81f7, against b5cf96f's binary and the start,
//! alternated, five runs each, medians of CPU time, load average 3 to 4.5): 0.86 s of one core
//! at b5cf96f, 0.60 s at the start and 0.54 s after, the same 368 712 impacts (×1.59 over
//! b5cf96f, ×1.11 over the start). Issue 24's ×2 is not reached. Callgrind, first 1000
//! periods: 481.5e6 instructions at the start, 451.8e6 after (−6.2 %); first 5000 periods
//! 1962.2e6 after; every result bit for bit the start's (the 139-run program of `unit_long`'s
//! last paragraph: identical output at every commit). What moved it: the watch searches the
//! earliest estimate first and the other pairs in their slots' order rather than sorting all
//! eight by estimate (the order decides only how much is searched; → 465.9e6); the carried
//! and pending states compared bit for bit without a branch per entry (→ 463.6e6); a pair's
//! terms, which its slot holds from an earlier free flight, rewritten in their constant
//! coefficients only (`Flight::expand_again`, → 451.8e6). Tried and not taken: the watch's
//! quadratic estimates without branches (scalar, both sides' roots always formed: 0.53 s →
//! 0.55 s; four pairs at once with AVX: −0.7 % instructions, no measurable time); estimates
//! skipped for pairs whose quadratic provably leaves later than the earliest so far (in the
//! slots' order the earliest is found late: +0.4 %); every kept mode's column added to a block
//! of sixteen entries of the state held in registers (the same bits, +2.6 % instructions, no
//! measurable time); the forcing phase at a contact as the flight's start phase times the
//! search's `e^{iωs}` (at most four products from a `sin_cos`; it moves the last bits:
//! `unit_long 20000` 229.6e6 → 227.0e6, −1.1 %); the fixed grid's chunks at 6 or 12 per
//! oscillation instead of 8 (`unit_long 20000`: 324.9e6, 252.8e6; this chain: 491.6e6,
//! 480.1e6); a build for `x86-64-v3` (`-C target-cpu`, outside the crate: the same bits on
//! the 139 runs, 5 to 7 % less CPU time on both examples). Where the time goes now (`perf`,
//! 20 000 periods): the contact state 12.8 %, the chunk tests of the searches 11.3 %, the
//! summaries 10.6 %, the run loop 6.3 %, the watch's quadratic estimates 6.3 % (latency of
//! their square roots and divisions), the polish's local sums 6 %, the term rewrite 3.7 %,
//! the exclusion tests 3.6 %.
//!
//! Measured again (stop 29, from 80a8452, against b5cf96f's binary and the start, alternated,
//! nine runs each, medians of `perf stat`'s task clock, load average 1.2 to 1.4): 829 ms at
//! b5cf96f, 526 ms at the start and 450 ms after, the same 368 652 impacts (×1.84 over
//! b5cf96f, −14 % against the start; `/usr/bin/time`, seven runs each: 0.81, 0.52, 0.44 s).
//! Issue 24's ×2 is not reached in time; in instructions it is: callgrind, first 1000
//! periods 442.9e6 → 377.7e6 (774.1e6 at b5cf96f: ×2.05), first 5000 1955.5e6 → 1628.9e6
//! (3482.2e6 at b5cf96f: ×2.14). Every result bit for bit the start's (`rattle simulate` on
//! both chain scenes at six frequencies, until periodic and 1500 fixed periods with their
//! impacts, and the paper and damped unit: identical output after every commit). By commit
//! (first 5000 periods unless said): the joint summaries leave each term's coefficient
//! where they formed it and a searched pair's terms are copied from there
//! (`Flight::expand_joint`; first 1000 periods 442.9e6 → 431.5e6); the watch forms a pair's
//! quadratic estimate only when its model may leave the band before the earliest estimate so
//! far, tested without a square root or division (`Summary::estimate_later_than`: 8 → 2.9
//! estimates a flight, `quadratic_exit` 6.3 → 4.5 % of the time by `perf`; stop 26's version
//! of the same skip formed the test from the roots and cost more than it saved), running
//! maxima without `f64::max`'s NaN fix-up, a grid's rates compared without a branch per rate
//! (→ 423.0e6; 1853.3e6 for 5000); the joint summaries' modes formed once for the flow
//! (`LinearFlow::joint_modes`, → 1810.3e6), with `μ²` and `rate²` (→ 1776.4e6); a flight's
//! deviation kept for the kept modes only, in their order (→ 1741.1e6), and the steady
//! response too, so that the packed state loads each pair of modes in one load
//! (`SteadyResponse::of_kept`, → 1720.3e6); the carry's products and jump two modes to a
//! register (→ 1703.9e6); the summaries reading the flow's modes in place (→ 1691.3e6), their
//! seven per-mode factors in all four lanes (`ModeTerm::lanes`, → 1671.0e6); the polish's
//! series coefficients from a packed table (→ 1662.6e6), its radius from the grid's fastest
//! rate (`GridSteps::fastest`, → 1656.9e6); a pair of modes' columns added in one pass over
//! the state (`add_two_columns_avx`, → 1626.3e6, 460 → 444 ms); the polish's higher local
//! sums two terms to a register (→ 1637.2e6, more instructions but 453 → 447 ms: its chains
//! of dependent complex products halved); a polish start's exponentials two terms to a
//! register (→ 1628.9e6). Tried and not taken: a fourth-order exclusion test in the summaries
//! (`f'''(0)` and `Σ|c| rate⁴` formed with the others: it excluded 107 103 of the 416 826
//! pairs the third order leaves after the first contact, but first 1000 periods 442.9e6 →
//! 460.3e6); the two blocks of summaries side by side in AVX-512's eight lanes (the same bits;
//! 544 → 576 ms: slower on this Xeon); the contact state formed only at the entries the
//! contact reads (a throwaway build with the rounding scales left stale: 560 → 556 ms, within
//! the noise; scalar entries cost as much as the whole state four wide, and the next flight's
//! depth needs every position); every mode's column added to sixteen entries of the state
//! held in registers (1720.3e6 → 1735.9e6, 466 → 467 ms); four modes' columns to a pass
//! (1626.3e6 → 1646.9e6, no faster than two); the carry's product and jump fused in one pass
//! (1810.3e6 → 1817.2e6); the derivative coefficients two terms to a register (1810.3e6 →
//! 1814.4e6: packing cost more than it saved); `excludes` inlined (1691.3e6 → 1699.4e6); fat
//! LTO with one codegen unit (within the noise); the watch's estimate handed to the search
//! (−0.1 %); Halley's stopping test with its division and square root multiplied out, or
//! formed only past the step test (within the noise); the search's estimate formed only when
//! the first chunk is not cleared (no fewer); the column additions by `chunks_exact` instead
//! of `step_by` (+1.0 %); the largest velocity as four running maxima (within the noise). The
//! core runs at about 14e9 instructions a second on this 2.6 GHz machine (7.18e9 for the
//! 20 000 periods in 0.51 s at the first commits: four to five a cycle), so its time follows
//! its instruction count, except where chains of dependent products or divisions set the pace
//! (cachegrind: 2.5 % of data reads miss the first-level cache, all of them hits further
//! out). Where the time goes now (`perf`, 20 000 periods): the search's own loop 11.6 %, the
//! run loop 10.9 %, the contact state 10.1 %, the summaries 8.7 %, the polish's local sums
//! 5.8 %, the exclusion tests 4.8 %, Halley's iterations 4.6 %, the contact 4.3 %, the series
//! 4.2 %, the chunk sums 4.2 %. Per flight (a throwaway counter, at the start): 8 pairs, 5.6
//! excluded by their summaries, 2.4 searched (1.4 before the first contact is found, of which
//! 0.4 find none; 1.1 after it), 4.5 chunk midpoints and 1.0 chunk bisection, 1.1 polishes
//! (14 % of them of a contact a later search beats).
//!
//! Measured again (stop 30, from 04bc88c, against b5cf96f's binary and the start, alternated,
//! eleven runs each, medians of `perf stat`'s task clock, load average 0.9 to 1.9): 793 ms at
//! b5cf96f, 433 ms at the start and 381 ms after, the same 368 652 impacts (**×2.08** over
//! b5cf96f, −12 % against the start; `/usr/bin/time`, nine runs each: 0.80, 0.44, 0.39 s,
//! ×2.05). Issue 24's ×2 is reached. Callgrind, first 1000 periods 377.7e6 → 343.8e6 (774.1e6
//! at b5cf96f: ×2.25), first 5000 1628.2e6 → 1456.2e6 (3482.2e6: ×2.39). Every result bit for
//! bit the start's (the same runs as at stop 29, with `--trajectory` beside `--impacts` as the
//! command now asks: 54 outputs identical after every commit). By commit (first 5000 periods):
//! - a contact forms only the state's entries an impact that cannot stick reads and changes
//!   (its pair's two velocities), from the state's modal coordinates there
//!   (`Flight::modal_state`), which also give the positions' and velocities' rounding scales and
//!   a bound on the push (`ContactMode`), so that a contact that may stick, one at a section and
//!   one a run records form the whole state and decide alike (→ 1567.1e6, 453 → 421 ms; a
//!   first form with scalar coordinates and scale sums took more instructions than the state it
//!   saved: 377.6e6 → 383.4e6 for 1000 periods, though 16 ms faster);
//! - the contact's bounds and entries four lanes at once, the carried deviation's products
//!   taken from the coordinates', the constant terms' derivative coefficients two terms to a
//!   register with their storage kept rather than zeroed (stop 29's packed form zeroed it and
//!   cost more than it saved) (→ 1500.3e6, 415 → 407 ms);
//! - a flight's modal coordinates `V⁻¹y` two modes to a register, and the polish's series degree
//!   from the grid's fastest rate times the step where no bound is within 1e-14 of it
//!   (→ 1475.1e6); the summaries written in place rather than returned (a `memcpy` call per
//!   block, → 1461.9e6, 403 → 389 ms); the watch's earliest estimate moved to the front entry
//!   by entry (→ 1457.0e6).
//!
//! The unit's path is kept as it was (no call of the contact's modal path; `unit_long 20000`
//! 206.98e6 at the start, 208.0e6 after: the pairs carry the new bounds). Stop 29's reading of
//! the partial contact state ("as slow") was of scalar entries with stale scales: packed, with
//! scales from the coordinates, it is the largest gain of this stop. Where the time goes now
//! (`perf`, 20 000 periods): the search's own loop 13.5 %, the summaries 11.1 %, the run loop
//! 9.5 %, the polish's local sums 7.8 %, its series 5.9 %, the exclusion tests 5.2 %, the
//! quadratic estimates 5.1 %, Halley's iterations 4.8 %, the chunk sums 4.7 %, the derivative
//! coefficients 3.1 %, the contact's coordinates 2.8 %.

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
