//! The scan of a grid of chunks, one loop over a [`ChunkSource`]: the exponentials of each
//! chunk's midpoint and end either cached with a fixed grid ([`CachedChunks`]) or stepped
//! from chunk to chunk ([`SteppedChunks`]).

use super::*;

/// Grid steps between fresh exponentials in [`ExpSum::first_exit`]: the recurrence
/// `e^{μ(s + w)} = e^{μs} e^{μw}` gains at most about this many roundings.
pub(super) const REANCHOR: usize = 32;

/// How a grid's last chunk `[a, horizon]` is searched.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum LastChunk {
    /// The grid ends at the horizon (the grid of the horizon): the last chunk is `[a, horizon]`.
    AtHorizon,
    /// By [`ExpSum::last_chunk`]: excluded by the test on the whole chunk `[a, a + 2w]` that
    /// contains it, or else searched on its own from fresh exponentials.
    Alone,
    /// As the whole chunk `[a, a + 2w]`, an exit after the horizon meaning none before it.
    Whole,
}

/// Where a scan of chunks takes `f` and its derivatives at each chunk's midpoint and end.
/// A scan asks, for chunk `i` in order, [`Self::mid`], then (if the chunk is not excluded at
/// once) [`Self::third`] and [`Self::keep_mid`], then [`Self::end`]; and, for a chunk that is
/// searched, [`Self::prepare`] and [`Self::seed`].
pub(super) trait ChunkSource {
    /// How the last chunk is searched.
    fn last_chunk(&self) -> LastChunk;
    /// `(f, f', f'')` at chunk `i`'s midpoint `m`.
    fn mid(&mut self, f: &ExpSum, derivatives: &Derivatives, i: usize, m: f64) -> (f64, f64, f64);
    /// `f'''` at the midpoint last given by [`Self::mid`].
    fn third(&mut self, f: &ExpSum, derivatives: &Derivatives) -> f64;
    /// Keeps the midpoint's exponentials for [`Self::seed`] (chunk not excluded at once).
    fn keep_mid(&mut self);
    /// `f` at chunk `i`'s end `b`, after [`Self::mid`] of the same chunk.
    fn end(&mut self, f: &ExpSum, derivatives: &Derivatives, i: usize, b: f64) -> f64;
    /// Makes `derivatives` those of `f` before a chunk is searched.
    fn prepare(&mut self, f: &ExpSum, derivatives: &mut Derivatives);
    /// The polish's seed points around the midpoint `m` of the chunk last given, if any.
    fn seed(&mut self, m: f64, w: f64) -> Option<Seed<'_>>;
}

/// A fixed grid's cached chunk rows ([`GridSteps::chunk_exps`], filled on first use) and its
/// seed points; [`Derivatives::of_constants`] formed once, when first needed.
pub(super) struct CachedChunks<'g> {
    pub(super) terms: &'g [Term],
    pub(super) w: f64,
    pub(super) chunk_exps: &'g mut Vec<C64>,
    pub(super) chunk_filled: &'g mut Vec<bool>,
    pub(super) seeds: &'g mut Seeds,
    /// Whether [`Derivatives::of_constants`] has been formed for this search.
    pub(super) derived: bool,
    /// The chunk last given by [`ChunkSource::mid`].
    pub(super) current: usize,
    /// Whether the CPU has AVX: a chunk's values are then summed four at once from its
    /// packed rows ([`chunk_values_avx`]), `f` at its end with those at its midpoint.
    pub(super) packed: bool,
    /// `f` at the end of the chunk last given by [`ChunkSource::mid`], when `packed`.
    pub(super) end_value: f64,
}

impl<'g> CachedChunks<'g> {
    /// Chunk `i`'s rows (see [`GridSteps::chunk_exps`]), computed on first use.
    #[inline]
    pub(super) fn rows(&mut self, i: usize) -> &[C64] {
        chunk_rows(self.chunk_exps, self.chunk_filled, i, self.w, self.terms)
    }

    /// Chunk `i`'s exponentials at its midpoint and the grid's seed points.
    #[inline]
    pub(super) fn mid_and_seeds(&mut self, i: usize) -> (&[C64], &mut Seeds) {
        let n = self.terms.len();
        let rows = chunk_rows(self.chunk_exps, self.chunk_filled, i, self.w, self.terms);
        (&rows[..n], &mut *self.seeds)
    }

    /// The current chunk's rows (filled by [`ChunkSource::mid`]).
    #[inline]
    fn current_rows(&self) -> &[C64] {
        let rows = CHUNK_ROWS * self.terms.len();
        &self.chunk_exps[self.current * rows..(self.current + 1) * rows]
    }
}

impl ChunkSource for CachedChunks<'_> {
    #[inline]
    fn last_chunk(&self) -> LastChunk {
        LastChunk::Whole
    }

    #[inline]
    fn mid(&mut self, _: &ExpSum, _: &Derivatives, i: usize, _: f64) -> (f64, f64, f64) {
        self.current = i;
        let terms = self.terms;
        #[cfg(target_arch = "x86_64")]
        if self.packed {
            let n = terms.len();
            let rows = &self.rows(i)[5 * n..];
            // SAFETY: `packed` is set only when the CPU has AVX (`packed_chunks`).
            let [fm, dm, ddm, fb] = unsafe { chunk_values_avx(terms, rows) };
            self.end_value = fb;
            return (fm, dm, ddm);
        }
        mid_values(terms, self.rows(i))
    }

    #[inline]
    fn third(&mut self, _: &ExpSum, _: &Derivatives) -> f64 {
        let n = self.terms.len();
        real_dot(self.terms, &self.current_rows()[3 * n..4 * n])
    }

    #[inline]
    fn keep_mid(&mut self) {}

    #[inline]
    fn end(&mut self, _: &ExpSum, _: &Derivatives, _: usize, _: f64) -> f64 {
        if self.packed {
            return self.end_value;
        }
        let n = self.terms.len();
        real_dot(self.terms, &self.current_rows()[4 * n..5 * n])
    }

    #[inline]
    fn prepare(&mut self, f: &ExpSum, derivatives: &mut Derivatives) {
        if !self.derived {
            derivatives.of_constants(f);
            self.derived = true;
        }
    }

    #[inline]
    fn seed(&mut self, m: f64, w: f64) -> Option<Seed<'_>> {
        let n = self.terms.len();
        let at = self.current * CHUNK_ROWS * n;
        Some(Seed {
            m,
            w,
            mid: &self.chunk_exps[at..at + n],
            seeds: &mut *self.seeds,
        })
    }
}

/// Exponentials stepped from chunk to chunk (`e^{μ(s + w)} = e^{μs} e^{μw}`, evaluated afresh
/// every [`REANCHOR`] steps), `exps` at the current point; on a fixed grid, the midpoint's
/// kept in `mid` for the seed points `seeds`. [`Derivatives::of`] is formed before the scan.
pub(super) struct SteppedChunks<'g> {
    pub(super) terms: &'g [Term],
    pub(super) exps: &'g mut [C64],
    pub(super) steps: &'g [C64],
    /// The fixed grid's midpoint exponentials and seed points (`None` on the horizon's grid).
    pub(super) fixed: Option<(&'g mut Vec<C64>, &'g mut Seeds)>,
}

impl ChunkSource for SteppedChunks<'_> {
    #[inline]
    fn last_chunk(&self) -> LastChunk {
        if self.fixed.is_some() {
            LastChunk::Alone
        } else {
            LastChunk::AtHorizon
        }
    }

    #[inline]
    fn mid(&mut self, f: &ExpSum, derivatives: &Derivatives, _: usize, m: f64) -> (f64, f64, f64) {
        for (e, step) in self.exps.iter_mut().zip(self.steps) {
            *e *= step;
        }
        derivatives.at(f, m, self.exps)
    }

    #[inline]
    fn third(&mut self, _: &ExpSum, derivatives: &Derivatives) -> f64 {
        derivatives.third(self.exps)
    }

    #[inline]
    fn keep_mid(&mut self) {
        if let Some((mid, _)) = self.fixed.as_mut() {
            mid.clear();
            mid.extend_from_slice(self.exps);
        }
    }

    #[inline]
    fn end(&mut self, f: &ExpSum, derivatives: &Derivatives, i: usize, b: f64) -> f64 {
        if (2 * i + 2) % REANCHOR == 0 {
            for (e, t) in self.exps.iter_mut().zip(self.terms) {
                *e = cexp(t.rate, b);
            }
        } else {
            for (e, step) in self.exps.iter_mut().zip(self.steps) {
                *e *= step;
            }
        }
        derivatives.value(f, b, self.exps)
    }

    #[inline]
    fn prepare(&mut self, _: &ExpSum, _: &mut Derivatives) {}

    #[inline]
    fn seed(&mut self, m: f64, w: f64) -> Option<Seed<'_>> {
        self.fixed.as_mut().map(|(mid, seeds)| Seed {
            m,
            w,
            mid: &mid[..],
            seeds,
        })
    }
}

/// `(f, f', f'')` at a cached chunk's midpoint: the terms' constant coefficients against its
/// rows `e^{μm}`, `μe^{μm}`, `μ²e^{μm}` ([`GridSteps::chunk_exps`]).
#[inline]
pub(super) fn mid_values(terms: &[Term], rows: &[C64]) -> (f64, f64, f64) {
    let n = terms.len();
    let (mut fm, mut dm, mut ddm) = (0.0, 0.0, 0.0);
    // The three rows as slices of the terms' length: no index checks in the loop.
    let (value, rows) = rows.split_at(n);
    let (slope, rows) = rows.split_at(n);
    let curve = &rows[..n];
    for (((t, &e0), &e1), &e2) in terms.iter().zip(value).zip(slope).zip(curve) {
        let c = t.poly[0];
        let re = |x: C64| c.re * x.re - c.im * x.im;
        fm += re(e0);
        dm += re(e1);
        ddm += re(e2);
    }
    (fm, dm, ddm)
}

/// A cached chunk's `(f, f', f'')` at its midpoint and `f` at its end from its packed rows
/// (`[e^{μm}, μe^{μm}, μ²e^{μm}, e^{μb}]` per term, [`GridSteps::chunk_exps`]), the four sums
/// side by side with AVX: each is [`mid_values`]' (and, at the end, [`real_dot`]'s) sum of
/// `c.re·x.re − c.im·x.im` over the terms in order, from the same starting zero (`+0` for
/// the midpoint's, `−0` for the end's, as `f64`'s `Sum` starts), so the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
pub(super) fn chunk_values_avx(terms: &[Term], packed: &[C64]) -> [f64; 4] {
    use std::arch::x86_64::*;
    // Lanes `[f(m), f''(m), f'(m), f(b)]`, as `_mm256_hsub_pd` leaves them.
    let mut sums = _mm256_set_pd(-0.0, 0.0, 0.0, 0.0);
    for (t, x) in terms.iter().zip(packed.chunks_exact(PACKED_ROWS)) {
        let c = t.poly[0];
        let c = _mm256_set_pd(c.im, c.re, c.im, c.re);
        let (x, y) = x.split_at(2);
        let first = _mm256_set_pd(x[1].im, x[1].re, x[0].im, x[0].re);
        let second = _mm256_set_pd(y[1].im, y[1].re, y[0].im, y[0].re);
        let terms = _mm256_hsub_pd(_mm256_mul_pd(first, c), _mm256_mul_pd(second, c));
        sums = _mm256_add_pd(sums, terms);
    }
    let mut out = [0.0; 4];
    // SAFETY: `out` holds four `f64`, the unaligned store's 32 bytes.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), sums) };
    [out[0], out[2], out[1], out[3]]
}

/// The chunks a scan covers: `first..chunks` of half-width `w`, up to `cutoff`; `fa` is `f`
/// at the first one's start.
#[derive(Debug, Clone, Copy)]
pub(super) struct Chunks {
    pub(super) first: usize,
    pub(super) chunks: usize,
    pub(super) w: f64,
    pub(super) cutoff: f64,
    pub(super) fa: f64,
}

impl ExpSum {
    /// The first exit in the chunks `range` of a grid, left to right, each chunk's values from
    /// `source`: a chunk whose Taylor enclosure at its midpoint (`± ⅙ M₃ w³`) lies inside the
    /// band is excluded at once, any other is searched by [`Self::exit_in_chunk`]; the last
    /// chunk as [`ChunkSource::last_chunk`] says. Chunks from `cutoff` on are not searched.
    #[inline(always)]
    pub(super) fn scan<S: ChunkSource>(
        &self,
        test: &mut ChunkTest<'_>,
        source: &mut S,
        range: Chunks,
    ) -> Option<(f64, i8)> {
        let Chunks {
            first,
            chunks,
            w,
            cutoff,
            mut fa,
        } = range;
        let (band, horizon) = (test.band, test.horizon);
        let jerk_reach = test.jerk * w * w * w / 6.0;
        let last = source.last_chunk();
        for i in first..chunks {
            let a = 2.0 * w * i as f64;
            if a >= cutoff {
                break;
            }
            let b = if i + 1 == chunks && last == LastChunk::AtHorizon {
                horizon
            } else {
                2.0 * w * (i + 1) as f64
            };
            let m = a + w;
            let (fm, dm, ddm) = source.mid(self, test.derivatives, i, m);
            if i + 1 == chunks && last == LastChunk::Alone {
                return self.last_chunk(test, (a, w), (fm, dm, ddm), fa);
            }
            let excluded = inside((fm, dm, ddm), w, jerk_reach, band);
            let d3m = if excluded {
                f64::NAN
            } else {
                let d3m = source.third(self, test.derivatives);
                source.keep_mid();
                d3m
            };
            let fb = source.end(self, test.derivatives, i, b);
            if excluded {
                fa = fb;
                continue;
            }
            source.prepare(self, test.derivatives);
            let seed = source.seed(m, w);
            let found = self.exit_in_chunk(test, (a, b, fa, fb), (fm, dm, ddm, d3m), seed);
            if found.is_some() {
                // Past the horizon only in a last chunk searched whole: then none before it.
                return found.filter(|&(s, _)| s <= horizon);
            }
            fa = fb;
        }
        None
    }

    /// The last chunk of a fixed grid, `[a, horizon]` within `[a, a + 2w]` (`(f, f', f'')` at
    /// `a + w` given, `fa = f(a)`): excluded by the test on `[a, a + 2w]` when that contains
    /// it, or else searched on its own from fresh exponentials.
    pub(super) fn last_chunk(
        &self,
        test: &mut ChunkTest<'_>,
        (a, w): (f64, f64),
        at_m: (f64, f64, f64),
        fa: f64,
    ) -> Option<(f64, i8)> {
        let horizon = test.horizon;
        let jerk_reach = test.jerk * w * w * w / 6.0;
        if a + 2.0 * w >= horizon && inside(at_m, w, jerk_reach, test.band) {
            return None;
        }
        let at_m = self.eval3(0.5 * (a + horizon), test.derivatives, test.point);
        let fb = self.eval(horizon).0;
        self.exit_in_chunk(test, (a, horizon, fa, fb), at_m, None)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A chunk's packed sums with AVX are bit for bit [`mid_values`] and [`real_dot`] of its
    /// rows by kind.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn a_chunks_packed_sums_are_its_sums_by_kind_bit_for_bit() {
        if !packed_chunks() {
            return;
        }
        let value = |i: usize, a: f64| (a * i as f64 + 0.3).sin() * 10f64.powi(i as i32 % 7 - 3);
        for n in [0, 1, 2, 17] {
            let terms: Vec<Term> = (0..n)
                .map(|j| Term {
                    poly: [
                        C64::new(value(j, 1.1), value(j, 2.3)),
                        C64::default(),
                        C64::default(),
                        C64::default(),
                    ],
                    rate: C64::new(-value(j, 0.7).abs(), value(j, 3.1)),
                })
                .collect();
            let rows: Vec<C64> = (0..5 * n)
                .map(|i| C64::new(value(i, 0.9), value(i, 1.7)))
                .collect();
            let mut packed = Vec::new();
            for j in 0..n {
                packed.extend([rows[j], rows[n + j], rows[2 * n + j], rows[4 * n + j]]);
            }
            let (fm, dm, ddm) = mid_values(&terms, &rows);
            let fb = real_dot(&terms, &rows[4 * n..]);
            // SAFETY: the CPU has AVX (`packed_chunks`).
            let sums = unsafe { chunk_values_avx(&terms, &packed) };
            assert_eq!(
                sums.map(f64::to_bits),
                [fm, dm, ddm, fb].map(f64::to_bits),
                "{n} terms"
            );
        }
    }
}
