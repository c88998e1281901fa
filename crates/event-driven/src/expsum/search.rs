//! The first-exit search: the evaluation-free tests, the head of short chunks, and the scan
//! of the grid of chunks.

use super::*;
use std::ops::ControlFlow;

/// Growth factor of the head chunks of [`ExpSum::first_exit`]: a short flight is covered by
/// chunks that double from the start's clearance, so it is found in about `log₂` of the first
/// chunk's length over the flight's steps.
pub(super) const HEAD: f64 = 2.0;

/// Search chunks per oscillation of the fastest term in [`ExpSum::first_exit`]: an eighth of an
/// oscillation is short enough for the derivative bounds to exclude most chunks at once.
pub(super) const CHUNKS_PER_OSCILLATION: f64 = 8.0;

/// The head of doubling chunks is used when the quadratic model's exit lies within this
/// fraction of the first chunk (a short bounce), as it is for a slow start (see [`HEAD`]).
pub(super) const HEAD_ESTIMATE: f64 = 8.0;

/// A start within this fraction of the band `[lo, hi]` of an edge is "on the edge" (a release,
/// a graze), and worth a Taylor clearance: far above rounding and the event loop's contact
/// depth (`1e-12` of the gap), far below the height of a bounce that the grid finds anyway.
pub(super) const ON_EDGE: f64 = 1e-6;

/// ... provided its slope would move it by less than this fraction of the band over the first
/// chunk: a slow departure. A fast one (an impact) is found by the quadratic model or the grid.
pub(super) const SLOW_DEPARTURE: f64 = 1e-3;

/// The tolerances of a first-exit search ([`ExpSum::first_exit`]): exits are resolved to `time`,
/// and a dip beyond an edge narrower than that counts when it is deeper than `depth`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tolerances {
    /// The time tolerance of the exit.
    pub time: f64,
    /// The depth beyond an edge from which a dip narrower than `time` counts.
    pub depth: f64,
}

impl ExpSum {
    /// The first `s ∈ [0, horizon]` where `f` leaves the open band `(lo, hi)`: `(s, +1)` on
    /// reaching `hi`, `(s, −1)` on reaching `lo`. `f(0)` is inside the band or on an edge; a
    /// start on an edge moving back inside is not an exit. `stack` is scratch storage.
    ///
    /// Guarantee: an interval `[m − w, m + w]` is discarded only when a rigorous enclosure of
    /// `f` on it lies inside the band: the quadratic Taylor model at `m` (its extremes, so the
    /// sign of `f''` counts) `± ⅙ M₃ w³` (`M₃` = [`Self::jerk_bound`]), or, for steady-response
    /// flights, the cubic model `± M₄ w⁴/24` (`M₄` = [`Self::fourth_derivative_bound`]). No
    /// exit can be skipped, however close two crossings are; intervals are searched left to
    /// right, and a bracket on which `f'` provably keeps its sign is polished by safeguarded
    /// Halley iteration to `time_tolerance`. A dip beyond an edge narrower than
    /// `time_tolerance` counts when it is deeper than `depth_tolerance`, and a slow start on an
    /// edge (a release) is cleared by a Taylor bound that tolerates excursions up to
    /// `depth_tolerance` beyond the edge. Either edge may be infinite (a one-sided band:
    /// `(0, ∞)` finds where a positive function first reaches zero).
    ///
    /// The horizon is first cut into chunks about an eighth of the fastest oscillation long.
    /// When every polynomial is a constant and no rate grows (every steady-response flight),
    /// the grid is fixed by the rates alone (half-width `π/(8 max|μ|)`) and each chunk's
    /// exponentials are cached with it, evaluated once per run, and a polish starts from
    /// them; otherwise the chunks' midpoints and ends lie on a
    /// uniform grid of the horizon where every exponential follows from the previous one by
    /// one complex product (`e^{μ(s+w)} = e^{μs} e^{μw}`, recomputed afresh every `REANCHOR` =
    /// 32 steps), so a whole flight costs a handful of transcendental evaluations. When the quadratic model at `0` leaves the band early, or the start is
    /// cleared only briefly, the first chunk is covered by chunks that double from there (a
    /// short flight in chatter is not found by halving a whole chunk). Only chunks that can be
    /// neither excluded nor bracketed are bisected.
    pub fn first_exit(
        &self,
        lo: f64,
        hi: f64,
        horizon: f64,
        time_tolerance: f64,
        depth_tolerance: f64,
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let tolerances = Tolerances {
            time: time_tolerance,
            depth: depth_tolerance,
        };
        self.first_exit_until(lo, hi, horizon, horizon, tolerances, stack)
    }

    /// [`Self::first_exit`] on the grid of `horizon`, but searched only until `cutoff ≤
    /// horizon`: every exit before `cutoff` is found as there (an exit after it may or may not
    /// be reported). Searches of several functionals of one flight with one `horizon` share
    /// the grid, and `stack` keeps the grid's exponential steps from one to the next when the
    /// rates are the same (a flight's pairs all have the flow's rates). `tolerances` are
    /// [`Self::first_exit`]'s `time_tolerance` and `depth_tolerance`.
    pub fn first_exit_until(
        &self,
        lo: f64,
        hi: f64,
        horizon: f64,
        cutoff: f64,
        tolerances: Tolerances,
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let Tolerances {
            time: time_tolerance,
            depth: depth_tolerance,
        } = tolerances;
        let cutoff = cutoff.min(horizon);
        // The evaluation-free tests first (envelope, drift, second and, for a search cut
        // short, third order: `Summary::excludes`): most searches end here, at no evaluation
        // cost. The general path bounds each term's polynomial and its derivatives
        // (`sup|f'| ≤ Σ (|p'| + |μ||p|) growth`, ...).
        let cut = cutoff < horizon;
        // Every polynomial a constant (the steady-response flights; `+0` coefficients, which
        // is how flights write them; anything else takes the general path): the same sums
        // without the higher coefficients, which are exact zeros and add nothing, and the
        // grid's `sup|f'''|` ([`Self::jerk_bound`]) in the same pass.
        let constant = cutoff.is_finite()
            && horizon.is_finite()
            && self.terms.iter().all(|t| {
                t.poly[1..]
                    .iter()
                    .fold(0, |bits, c| bits | c.re.to_bits() | c.im.to_bits())
                    == 0
            });
        let decaying = constant && self.terms.iter().all(|t| t.rate.re <= 0.0);
        let mut sum = Summary::default();
        match (constant, decaying, cut) {
            (true, true, true) => {
                for t in &self.terms {
                    sum.add_decaying::<true>(t.poly[0], t.rate);
                }
            }
            (true, true, false) => {
                // `f''(0)` too (`CUT`): the fixed grid's search below starts from it.
                for t in &self.terms {
                    sum.add_decaying::<true>(t.poly[0], t.rate);
                }
            }
            (true, false, _) => {
                for t in &self.terms {
                    sum.add(t.poly[0], t.rate, cutoff, horizon);
                }
            }
            _ => {}
        }
        for t in self.terms.iter().filter(|_| !constant) {
            sum.start += t.poly[0].re;
            sum.slope0 += (t.poly[1] + t.poly[0] * t.rate).re;
            sum.size0 += l1(t.poly[0]);
            if t.rate == C64::default() && t.poly[1..].iter().all(|c| *c == C64::default()) {
                sum.centre += t.poly[0].re;
            } else {
                let ([size, slope, curve, third], rate, growth) = term_bounds(t, cutoff);
                sum.spread += size * growth;
                sum.speed += (slope + rate * size) * growth;
                sum.bend += (curve + rate * (2.0 * slope + rate * size)) * growth;
                if cut {
                    let (p, mu) = (t.poly, t.rate);
                    sum.curve0 += (p[2] * 2.0 + (p[1] * 2.0 + p[0] * mu) * mu).re;
                    sum.jerk_cut += (third
                        + 3.0 * rate * curve
                        + 3.0 * rate * rate * slope
                        + rate * rate * rate * size)
                        * growth;
                }
            }
        }
        if sum.excludes(lo, hi, cutoff, horizon) {
            return None;
        }
        if decaying {
            return self.fixed_search(
                &sum,
                (lo, hi),
                horizon,
                cutoff,
                (time_tolerance, depth_tolerance),
                stack,
            );
        }
        let jerk = if constant {
            sum.jerk_horizon
        } else {
            self.jerk_bound(horizon)
        };
        self.grid_search::<false>(
            (lo, hi),
            horizon,
            cutoff,
            jerk,
            (time_tolerance, depth_tolerance),
            stack,
        )
    }

    /// The search of [`Self::first_exit_until`] on the grid of the horizon (chunks an eighth
    /// of the fastest oscillation long, exponentials stepped from chunk to chunk), without the
    /// evaluation-free tests: the reference that the fixed grid's search is tested against.
    #[cfg(test)]
    pub(crate) fn first_exit_on_horizon_grid(
        &self,
        (lo, hi): (f64, f64),
        horizon: f64,
        cutoff: f64,
        tolerances: Tolerances,
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let jerk = self.jerk_bound(horizon);
        self.grid_search::<false>(
            (lo, hi),
            horizon,
            cutoff.min(horizon),
            jerk,
            (tolerances.time, tolerances.depth),
            stack,
        )
    }

    /// [`Self::first_exit_until`] of a function whose [`Summary`] is known (as
    /// [`Flight::summarize`](crate::flow::Flight) forms it from the terms the flight writes:
    /// every polynomial a constant, no growing rate, `horizon` finite), whose evaluation-free
    /// tests ([`Summary::excludes`] up to `cutoff`) the caller has already made and found
    /// undecided: the same search, without forming the sums or making the tests again.
    pub(crate) fn first_exit_summarized(
        &self,
        summary: &Summary,
        (lo, hi): (f64, f64),
        horizon: f64,
        cutoff: f64,
        tolerances: Tolerances,
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let Tolerances {
            time: time_tolerance,
            depth: depth_tolerance,
        } = tolerances;
        let cutoff = cutoff.min(horizon);
        debug_assert!(!summary.excludes(lo, hi, cutoff, horizon));
        self.fixed_search(
            summary,
            (lo, hi),
            horizon,
            cutoff,
            (time_tolerance, depth_tolerance),
            stack,
        )
    }

    /// The half-width `w = π/(8 max|μ|)` of the fixed grid of these terms' rates, and whether
    /// it is finite (a nonzero, finite fastest rate). The most recent fixed grid is of these
    /// rates in most searches (a run's free flights all have the flow's): its half-width,
    /// formed from them in the same way, is taken as it is, without the fastest rate's pass
    /// over the terms and its division; the first value says whether it was.
    #[inline(always)]
    fn fixed_half_width(&self, stack: &SearchStack) -> (bool, f64, bool) {
        let front = stack
            .fixed
            .first()
            .is_some_and(|g| g.matches_rates(&self.terms));
        if front {
            return (true, stack.fixed[0].w, true);
        }
        let fastest = self.terms.iter().map(|t| l1(t.rate)).fold(0.0, f64::max);
        let w = std::f64::consts::PI / (CHUNKS_PER_OSCILLATION * fastest);
        (false, w, fastest > 0.0 && fastest.is_finite())
    }

    /// The search of [`Self::first_exit_summarized`]: [`Self::grid_search`] on its fixed grid
    /// (half-width `w = π/(8 max|μ|)`), with each chunk's exponentials taken from the grid's
    /// cache ([`GridSteps::chunk_exps`], evaluated afresh once per run) rather than carried
    /// from chunk to chunk: a chunk's `f`, `f'`, `f''` at its midpoint and `f` at its end are
    /// four sums of the terms' coefficients against cached rows, and the products `cμᵏ` of
    /// [`Derivatives`] are formed only for a search that needs them (a head of short chunks,
    /// a chunk not excluded at once). `f(0)`, `f'(0)`, `f''(0)` are the summary's. The tests,
    /// the head and the seeded polish are those of [`Self::grid_search`]; the last chunk
    /// `[a, horizon]` is searched as the whole cached chunk `[a, a + 2w]` that contains it, an
    /// exit found after `horizon` meaning none before it. A horizon of more than
    /// [`CACHED_CHUNKS`] chunks is left to [`Self::grid_search`]. The chunks after the head
    /// are scanned by [`Self::scan`] over [`CachedChunks`]. It is the search of every
    /// [`Self::first_exit_until`] whose polynomials are constants and rates do not grow (the
    /// one-pair searches of steady-response flights), as of the summarised searches.
    pub(super) fn fixed_search(
        &self,
        summary: &Summary,
        (lo, hi): (f64, f64),
        horizon: f64,
        cutoff: f64,
        (time_tolerance, depth_tolerance): (f64, f64),
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let jerk = summary.jerk_horizon;
        let (front, w, finite) = self.fixed_half_width(stack);
        let chunks = if finite {
            ((0.5 * horizon / w).ceil() as usize).clamp(1, 1 << 30)
        } else {
            usize::MAX
        };
        if chunks > CACHED_CHUNKS {
            return self.grid_search::<true>(
                (lo, hi),
                horizon,
                cutoff,
                jerk,
                (time_tolerance, depth_tolerance),
                stack,
            );
        }
        let SearchStack {
            intervals,
            fixed: fixed_grids,
            derivatives,
            polish: scratch,
            point,
            recall_key,
            recall,
            ..
        } = stack;
        let grid = if front {
            &mut fixed_grids[0]
        } else {
            fixed_grid(fixed_grids, &self.terms, w)
        };
        let GridSteps {
            seeds,
            chunk_exps,
            chunk_filled,
            fastest,
            ..
        } = grid;
        (seeds.key, seeds.enabled) = (*recall_key, *recall);
        let n = self.terms.len();
        let mut test = ChunkTest {
            band: (lo, hi),
            fastest: *fastest,
            jerk,
            fourth: f64::NAN,
            horizon,
            tolerances: (time_tolerance, depth_tolerance),
            intervals,
            derivatives,
            polish: scratch,
            point,
        };
        // `Derivatives::of_constants`, once, when first needed (`ChunkSource::prepare`).
        let mut source = CachedChunks {
            terms: &self.terms,
            w,
            chunk_exps,
            chunk_filled,
            seeds,
            derived: false,
            current: 0,
            packed: n >= PACKED_TERMS && packed_chunks(),
            end_value: f64::NAN,
        };
        test.polish.restart(true, *fastest);
        let (f0, d0, dd0) = (summary.start, summary.slope0, summary.curve0);
        let mut fa = f0;
        // The head, as in `grid_search`.
        let first_end = if chunks == 1 { horizon } else { 2.0 * w };
        // A flight that departs from a stop (an impact's) clears its first chunk at once (and
        // needs no estimate: only the heads below use it).
        let departing = departs((f0, d0, dd0), jerk, (lo, hi), depth_tolerance, first_end);
        let estimate = if departing {
            f64::INFINITY
        } else {
            quadratic_exit(f0, d0, dd0, lo, hi)
        };
        let cleared = if departing {
            first_end
        } else {
            if slow_on_edge((f0, d0), (lo, hi), first_end) {
                source.prepare(self, test.derivatives);
            }
            self.start_clearance(&test, (f0, d0, dd0), first_end)
        };
        let head = Head {
            cleared,
            estimate,
            first_end,
            cutoff,
        };
        let mut first = 0;
        if cleared >= first_end {
            first = 1;
            if chunks > 1 {
                fa = real_dot(&self.terms, &source.rows(0)[4 * n..5 * n]);
            }
        } else if cleared == 0.0
            && chunks > 1
            && HEAD_ESTIMATE * estimate < first_end
            && estimate * SEED_DIVISIONS as f64 >= w
        {
            // The head's chunks on the seed points of the first chunk, `kh` from its midpoint
            // `w` (`0` is `k = −SEED_DIVISIONS`, `2w` is `k = SEED_DIVISIONS`), each a whole
            // even number of steps long so that its midpoint is one too: their exponentials
            // follow from the cached ones at `w` by one product per term, and the polish
            // starts from them. (A flight estimated shorter than a step, as in chatter, keeps
            // the head of `grid_search`, whose chunks start that short.)
            source.prepare(self, test.derivatives);
            let cached = source.mid_and_seeds(0);
            match self.seeded_head(&mut test, cached, w, head, fa) {
                ControlFlow::Break(found) => return found,
                ControlFlow::Continue(end) => fa = end,
            }
            first = 1;
        } else if (cleared > 0.0 && HEAD * cleared < first_end)
            || HEAD_ESTIMATE * estimate < first_end
        {
            source.prepare(self, test.derivatives);
            match self.doubling_head(&mut test, head, fa) {
                ControlFlow::Break(found) => return found,
                ControlFlow::Continue(end) => fa = end,
            }
            first = 1;
        }
        let range = Chunks {
            first,
            chunks,
            w,
            cutoff,
            fa,
        };
        let found = self.scan(&mut test, &mut source, range);
        // A polished exit, recalled as a start for the polish of a later flight of this key.
        if let Some((s, _)) = found.filter(|&(s, _)| test.polish.at == s) {
            source.seeds.recall(s, &test.polish.values);
        }
        found
    }

    /// The search of [`Self::first_exit_until`] past its evaluation-free tests, with `jerk`
    /// bounding `|f'''|` on `[0, horizon]`: head chunks, then the grid of chunks. Inlined
    /// into both callers: a search costs what it cost as one function.
    ///
    /// `FIXED` (the summarised searches: every polynomial a constant and no growing rate, so
    /// that `jerk` and the fourth-derivative bound hold for every `s ≥ 0`): the grid's
    /// half-width is `w = π/(8 max|μ|)`, the largest the horizon's chunk count allows, fixed
    /// by the rates alone, so that its exponential steps and [`Seeds`] are kept from one
    /// flight to the next; the last chunk `[a, horizon]`, shorter than `2w`, is excluded by
    /// the test on `[a, a + 2w]` that contains it, or else searched on its own from fresh
    /// exponentials. A chunk that is not excluded keeps its midpoint's exponentials, and its
    /// polish starts from them ([`Seed`]). The chunks after the head are scanned by
    /// [`Self::scan`] over [`SteppedChunks`]. The searches of other functions (a polynomial that
    /// is not a constant, a growing rate) use the grid of the horizon.
    #[inline(always)]
    pub(super) fn grid_search<const FIXED: bool>(
        &self,
        (lo, hi): (f64, f64),
        horizon: f64,
        cutoff: f64,
        jerk: f64,
        (time_tolerance, depth_tolerance): (f64, f64),
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let (fixed, chunks, w) = self.grid::<FIXED>(horizon);
        let SearchStack {
            intervals,
            exps,
            grid,
            fixed: fixed_grids,
            derivatives,
            polish: scratch,
            point,
            mid,
            ..
        } = stack;
        // A bound on |f''''| over the horizon, computed when a chunk first needs it; the
        // fastest rate the grid's, set below once the grid is found.
        let mut test = ChunkTest {
            band: (lo, hi),
            fastest: f64::NAN,
            jerk,
            fourth: f64::NAN,
            horizon,
            tolerances: (time_tolerance, depth_tolerance),
            intervals,
            derivatives,
            polish: scratch,
            point,
        };
        test.derivatives.of(self);
        test.polish.restart(FIXED, f64::NAN);
        exps.clear();
        exps.resize(self.terms.len(), C64::new(1.0, 0.0));
        let grid = if fixed {
            fixed_grid(fixed_grids, &self.terms, w)
        } else {
            if !grid.matches(&self.terms, w) {
                grid.refresh(&self.terms, w);
            }
            grid
        };
        let GridSteps {
            steps,
            doubled,
            seeds,
            fastest,
            ..
        } = grid;
        test.fastest = *fastest;
        test.polish.fastest = *fastest;
        let (f0, d0, dd0) = test.derivatives.at(self, 0.0, exps);
        let mut fa = f0;
        // Head: when the flight may leave the band long before the first chunk ends (a bounce
        // within chatter, a departure from a stop after a release), the first chunk is
        // covered by chunks that double from the start's Taylor clearance and the quadratic
        // model's exit, so that a short flight is not found by bisecting down from a whole
        // chunk.
        let first_end = if chunks == 1 { horizon } else { 2.0 * w };
        let estimate = quadratic_exit(f0, d0, dd0, lo, hi);
        let cleared = self.start_clearance(&test, (f0, d0, dd0), first_end);
        let head = Head {
            cleared,
            estimate,
            first_end,
            cutoff,
        };
        let mut first = 0;
        if cleared >= first_end {
            first = 1;
            set_exponentials(exps, &self.terms, first_end, chunks, doubled);
            fa = test.derivatives.value(self, first_end, exps);
        } else if (cleared > 0.0 && HEAD * cleared < first_end)
            || HEAD_ESTIMATE * estimate < first_end
        {
            match self.doubling_head(&mut test, head, fa) {
                ControlFlow::Break(found) => return found,
                ControlFlow::Continue(end) => fa = end,
            }
            first = 1;
            set_exponentials(exps, &self.terms, first_end, chunks, doubled);
        }
        let mut source = SteppedChunks {
            terms: &self.terms,
            exps,
            steps,
            fixed: fixed.then_some((mid, seeds)),
        };
        let range = Chunks {
            first,
            chunks,
            w,
            cutoff,
            fa,
        };
        self.scan(&mut test, &mut source, range)
    }
}

/// The start of a search's head of short chunks: how far the start is cleared (`0` when it is
/// not), the quadratic model's exit `estimate`, the end of the first chunk, and the search's
/// cutoff.
#[derive(Debug, Clone, Copy)]
pub(super) struct Head {
    pub(super) cleared: f64,
    pub(super) estimate: f64,
    pub(super) first_end: f64,
    pub(super) cutoff: f64,
}

/// Whether a start `f0` moving at `d0` is a slow start on an edge of `(lo, hi)` (a release, a
/// graze), worth a Taylor clearance: a fast one (an impact) is found by the quadratic model or
/// the grid.
fn slow_on_edge((f0, d0): (f64, f64), (lo, hi): (f64, f64), first_end: f64) -> bool {
    (f0 - lo).min(hi - f0) <= ON_EDGE * (hi - lo)
        && d0.abs() * first_end < SLOW_DEPARTURE * (hi - lo)
}

impl ExpSum {
    /// How far a slow start on an edge is cleared by [`taylor_clearance`] from `f(0)`, `f'(0)`,
    /// `f''(0)` and the derivative coefficients' `f'''(0)`, up to `first_end`: `0` for a start
    /// that is not [`slow_on_edge`], or without derivative coefficients.
    fn start_clearance(
        &self,
        test: &ChunkTest<'_>,
        (f0, d0, dd0): (f64, f64, f64),
        first_end: f64,
    ) -> f64 {
        let (lo, hi) = test.band;
        if test.derivatives.0.is_empty() || !slow_on_edge((f0, d0), (lo, hi), first_end) {
            return 0.0;
        }
        let d3: f64 = test
            .derivatives
            .0
            .iter()
            .zip(&self.terms)
            .map(|(c, t)| (c[2] * t.rate).re)
            .sum();
        taylor_clearance(
            [f0, d0, dd0, d3],
            self.fourth_derivative_bound(test.horizon),
            (lo, hi),
            test.tolerances.1,
            first_end,
        )
    }

    /// The head of chunks that double from `head.cleared` (their first length from the
    /// quadratic model's exit) to the first chunk's end or the cutoff, each chunk's points
    /// evaluated afresh; `fa` is `f(0)`. `Break` with the exit found, or `Continue` with `f` at
    /// the head's end.
    fn doubling_head(
        &self,
        test: &mut ChunkTest<'_>,
        head: Head,
        mut fa: f64,
    ) -> ControlFlow<Option<(f64, i8)>, f64> {
        let Head {
            cleared,
            estimate,
            first_end,
            cutoff,
        } = head;
        let mut a = cleared;
        if cleared > 0.0 {
            fa = self.eval(cleared).0;
        }
        let mut length = if estimate.is_finite() && estimate > cleared {
            2.0 * (estimate - cleared)
        } else {
            cleared
        };
        while a < first_end && a < cutoff {
            let b = if a + 2.0 * length >= first_end {
                first_end
            } else {
                a + length
            };
            let m = 0.5 * (a + b);
            let at_m = self.eval3(m, test.derivatives, test.point);
            let fb = self.eval(b).0;
            let found = self.exit_in_chunk(test, (a, b, fa, fb), at_m, None);
            if found.is_some() {
                return ControlFlow::Break(found);
            }
            fa = fb;
            a = b;
            length *= 2.0;
        }
        ControlFlow::Continue(fa)
    }

    /// The head of a summarised search on the seed points of the first chunk (midpoint `w`,
    /// exponentials `mid` there, the grid's `seeds`), `kh` from `w` (`0` is
    /// `k = −SEED_DIVISIONS`, `2w` is `k = SEED_DIVISIONS`), each chunk a whole even number of
    /// steps long so that its midpoint is one too: their exponentials follow from the cached
    /// ones at `w` by one product per term, and the polish starts from them. `fa` is `f(0)`;
    /// `Break` with the exit found, or `Continue` with `f` at the head's end.
    fn seeded_head(
        &self,
        test: &mut ChunkTest<'_>,
        (mid, seeds): (&[C64], &mut Seeds),
        w: f64,
        head: Head,
        mut fa: f64,
    ) -> ControlFlow<Option<(f64, i8)>, f64> {
        let Head {
            estimate,
            first_end,
            cutoff,
            ..
        } = head;
        let mut seed = Seed {
            m: w,
            w,
            mid,
            seeds,
        };
        let divisions = SEED_DIVISIONS as i64;
        let h = w / SEED_DIVISIONS as f64;
        let mut ka = -divisions;
        let mut length = 2.0 * estimate;
        while ka < divisions && seed.point(ka) < cutoff {
            let a = seed.point(ka);
            let target = if a + 2.0 * length >= first_end {
                first_end
            } else {
                a + length
            };
            let mut kb = ((target - w) / h).ceil() as i64;
            kb += (kb - ka).rem_euclid(2);
            let kb = kb.clamp(ka + 2, divisions);
            let (b, km) = (seed.point(kb), (ka + kb) / 2);
            seed.exponentials_at(km, &self.terms, test.point);
            let at_m = test.derivatives.at3(self, seed.point(km), test.point);
            seed.exponentials_at(kb, &self.terms, test.point);
            let fb = test.derivatives.value(self, b, test.point);
            let found = self.exit_in_chunk(
                test,
                (a, b, fa, fb),
                at_m,
                Some(Seed {
                    m: w,
                    w,
                    mid,
                    seeds: &mut *seed.seeds,
                }),
            );
            if found.is_some() {
                return ControlFlow::Break(found);
            }
            fa = fb;
            ka = kb;
            length *= 2.0;
        }
        ControlFlow::Continue(fa)
    }
}

impl ExpSum {
    /// The grid of a search over `horizon`: `(fixed, chunks, w)`, on the fixed grid of the
    /// rates (`w = π/(8 max|μ|)`, `FIXED` and a finite positive fastest rate) or else the
    /// grid of the horizon (`chunks` an eighth of the fastest oscillation long, `w` half of
    /// one).
    #[inline(always)]
    fn grid<const FIXED: bool>(&self, horizon: f64) -> (bool, usize, f64) {
        let fastest = if FIXED {
            self.terms.iter().map(|t| l1(t.rate)).fold(0.0, f64::max)
        } else {
            0.0
        };
        let fixed = FIXED && fastest > 0.0 && fastest.is_finite();
        let (chunks, w) = if fixed {
            let w = std::f64::consts::PI / (CHUNKS_PER_OSCILLATION * fastest);
            (((0.5 * horizon / w).ceil() as usize).clamp(1, 1 << 30), w)
        } else {
            let chunks = ((horizon * self.fastest(horizon) * CHUNKS_PER_OSCILLATION
                / std::f64::consts::TAU)
                .ceil() as usize)
                .clamp(1, 1 << 30);
            (chunks, 0.5 * horizon / chunks as f64)
        };
        (fixed, chunks, w)
    }
}
