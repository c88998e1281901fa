//! The sums behind a search's evaluation-free tests ([`Summary`]), formed from a function's
//! terms or, for several functionals of one flight, from its modes in one pass.

use super::*;

/// The sums behind the first, evaluation-free tests of [`ExpSum::first_exit_until`] (see
/// [`Summary::excludes`]): `f(0)`, `f'(0)`, `f''(0)`, the constant part, and bounds on the
/// varying part's size and on `|f'|`, `|f''|`, `|f'''|` over `[0, cutoff]` (and `|f'''|`
/// over the horizon, for the grid), from the terms' absolute coefficients and rates.
///
/// Terms with constant polynomials are added one by one ([`Summary::add`]); a flight can so
/// summarise a functional without writing its terms out ([`Summary::add_mode`]: the same
/// bounds, `f''(0)` and `sup|f''|` formed with fewer products), and the summarised search
/// ([`ExpSum::first_exit_summarized`]) starts from that summary rather than forming its own.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub(crate) struct Summary {
    /// `f(0)`.
    pub(super) start: f64,
    /// `f'(0)`.
    pub(super) slope0: f64,
    /// `f''(0)`.
    pub(super) curve0: f64,
    /// `Σ |c|` over every term: the rounding scale of `f(0)`.
    pub(super) size0: f64,
    /// The constant terms' sum.
    pub(super) centre: f64,
    /// A bound on the varying terms' size on `[0, cutoff]`.
    pub(super) spread: f64,
    /// A bound on `|f'|` on `[0, cutoff]`.
    pub(super) speed: f64,
    /// A bound on `|f''|` on `[0, cutoff]`.
    pub(super) bend: f64,
    /// A bound on `|f'''|` on `[0, cutoff]`.
    pub(super) jerk_cut: f64,
    /// A bound on `|f'''|` on `[0, horizon]`.
    pub(super) jerk_horizon: f64,
}

/// One mode of a flow as [`Flight::summarize_all`](crate::flow::Flight) adds it to every
/// functional's [`Summary`]: the term `(w d)·weight e^{μs}` of a functional of modal weight
/// `w`, with `rate = |Re μ| + |Im μ| > 0` and `cube = (rate · rate) · rate`; the flight's
/// deviation `d` comes apart, times the weight ([`Self::weighted`]). Formed once per flow
/// ([`ModeTerm::new`]).
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ModeTerm {
    pub(crate) weight: f64,
    pub(crate) rate_complex: C64,
    /// `μ²` as [`Complex`]'s product forms it (a flow's constant, formed once).
    pub(crate) rate_square: C64,
    pub(crate) rate: f64,
    /// `rate · rate`.
    pub(crate) square: f64,
    pub(crate) cube: f64,
    /// `Re μ`, `Im μ`, `Re μ²`, `Im μ²`, `rate`, `square` and `cube`, each in all four lanes
    /// of a register ([`summarize_block_avx`] loads them rather than broadcasting seven
    /// scalars per mode and block: fewer instructions).
    pub(crate) lanes: [[f64; LANES]; 7],
}

impl ModeTerm {
    /// The mode of rate `μ` and weight `weight` (`rate = |Re μ| + |Im μ| > 0`, `cube =
    /// (rate · rate) · rate`).
    pub(crate) fn new(rate_complex: C64, weight: f64, (rate, cube): (f64, f64)) -> Self {
        let mu = rate_complex;
        let rate_square = C64::new(mu.re * mu.re - mu.im * mu.im, mu.re * mu.im + mu.im * mu.re);
        let square = rate * rate;
        let lanes = [
            mu.re,
            mu.im,
            rate_square.re,
            rate_square.im,
            rate,
            square,
            cube,
        ]
        .map(|x| [x; LANES]);
        Self {
            weight,
            rate_complex,
            rate_square,
            rate,
            square,
            cube,
            lanes,
        }
    }

    /// A flight's deviation `d` of the mode times its weight, `(d.re·weight, d.im·weight)`,
    /// as the summaries take it.
    #[inline]
    pub(crate) fn weighted(&self, d: C64) -> C64 {
        C64::new(d.re * self.weight, d.im * self.weight)
    }
}

/// Functionals summarised side by side by [`summarize_block`]: the lanes of one block.
pub(crate) const LANES: usize = 4;

/// The sums of [`LANES`] functionals' [`Summary`]s over the `modes`, side by side (the lanes
/// independent, so the compiler may pack them): `weights[j] = [Re w₀, …, Re w₃, Im w₀, …,
/// Im w₃]` for mode `j`. Each lane's sums are bit for bit those of [`Summary::add_mode`] over
/// the modes in order, `c = w (d·weight)` formed as [`Complex`]'s products. With AVX at run
/// time the same operations are packed four wide ([`summarize_block_avx`]): the same bits.
///
/// Each mode's coefficients `c` are left in `coefficients[j]` (`[Re c₀, …, Re c₃, Im c₀, …,
/// Im c₃]`; as long as `modes`): a pair that is then searched has its terms' coefficients
/// copied from there ([`Flight::expand_joint`](crate::flow::Flight)) rather than formed
/// again.
///
/// The summaries are written to `out`, lane by lane (in place: returned, they would be
/// copied by a call of `memcpy` per block, 0.8 % of a chain's instructions).
///
/// # Panics
///
/// If `coefficients` is shorter than `weights`, `modes` and `deviations` (the flight's
/// deviation of each mode times its weight, [`ModeTerm::weighted`]), or `out` is not
/// [`LANES`] long.
pub(crate) fn summarize_block(
    weights: &[[f64; 2 * LANES]],
    (modes, deviations): (&[ModeTerm], &[C64]),
    coefficients: &mut [[f64; 2 * LANES]],
    out: &mut [Summary],
) {
    let count = weights.len().min(modes.len()).min(deviations.len());
    let coefficients = &mut coefficients[..count];
    let out: &mut [Summary; LANES] = out.try_into().expect("a block's summaries");
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX (checked just above), the only requirement of the
        // `target_feature` function.
        return unsafe { summarize_block_avx(weights, (modes, deviations), coefficients, out) };
    }
    *out = summarize_lanes(weights, (modes, deviations), coefficients);
}

/// [`summarize_lanes`] with AVX intrinsics: each lane's operations, in the same order, on
/// four lanes at once (no FMA: every product and sum rounds as the scalar one does; `abs`
/// clears the sign bit as [`f64::abs`] does).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn summarize_block_avx(
    weights: &[[f64; 2 * LANES]],
    (modes, deviations): (&[ModeTerm], &[C64]),
    coefficients: &mut [[f64; 2 * LANES]],
    out: &mut [Summary; LANES],
) {
    use std::arch::x86_64::*;
    let zero = _mm256_setzero_pd();
    let (mut start, mut slope0, mut curve0, mut size0) = (zero, zero, zero, zero);
    let (mut speed, mut bend, mut jerk) = (zero, zero, zero);
    let magnitude = _mm256_castsi256_pd(_mm256_set1_epi64x(i64::MAX));
    let modes = modes.iter().zip(deviations);
    for ((w, (m, d)), out) in weights.iter().zip(modes).zip(coefficients) {
        // SAFETY: each of `m.lanes` holds four `f64`: one unaligned load.
        let [mu_re, mu_im, mu2_re, mu2_im, rate, square, cube] = m
            .lanes
            .each_ref()
            .map(|x| unsafe { _mm256_loadu_pd(x.as_ptr()) });
        let (d_re, d_im) = (d.re, d.im);
        let (wa, wb) = w.split_at(LANES);
        let a = _mm256_set_pd(wa[3], wa[2], wa[1], wa[0]);
        let b = _mm256_set_pd(wb[3], wb[2], wb[1], wb[0]);
        let (d_re, d_im) = (_mm256_set1_pd(d_re), _mm256_set1_pd(d_im));
        let c_re = _mm256_sub_pd(_mm256_mul_pd(a, d_re), _mm256_mul_pd(b, d_im));
        let c_im = _mm256_add_pd(_mm256_mul_pd(a, d_im), _mm256_mul_pd(b, d_re));
        // SAFETY: `out` holds eight `f64`: two unaligned stores of four.
        unsafe {
            _mm256_storeu_pd(out.as_mut_ptr(), c_re);
            _mm256_storeu_pd(out.as_mut_ptr().add(LANES), c_im);
        }
        start = _mm256_add_pd(start, c_re);
        let slope = _mm256_sub_pd(_mm256_mul_pd(c_re, mu_re), _mm256_mul_pd(c_im, mu_im));
        slope0 = _mm256_add_pd(slope0, slope);
        let curve = _mm256_sub_pd(_mm256_mul_pd(c_re, mu2_re), _mm256_mul_pd(c_im, mu2_im));
        curve0 = _mm256_add_pd(curve0, curve);
        let size = _mm256_add_pd(
            _mm256_and_pd(c_re, magnitude),
            _mm256_and_pd(c_im, magnitude),
        );
        size0 = _mm256_add_pd(size0, size);
        speed = _mm256_add_pd(speed, _mm256_mul_pd(rate, size));
        bend = _mm256_add_pd(bend, _mm256_mul_pd(square, size));
        jerk = _mm256_add_pd(jerk, _mm256_mul_pd(cube, size));
    }
    let lanes = |v: __m256d| {
        let mut out = [0.0; LANES];
        // SAFETY: `out` holds four `f64`, the unaligned store's 32 bytes.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr(), v) };
        out
    };
    LaneSums {
        start: lanes(start),
        slope0: lanes(slope0),
        curve0: lanes(curve0),
        size0: lanes(size0),
        speed: lanes(speed),
        bend: lanes(bend),
        jerk: lanes(jerk),
    }
    .write(out);
}

/// The body of [`summarize_block`].
#[inline(always)]
fn summarize_lanes(
    weights: &[[f64; 2 * LANES]],
    (modes, deviations): (&[ModeTerm], &[C64]),
    coefficients: &mut [[f64; 2 * LANES]],
) -> [Summary; LANES] {
    let mut start = [0.0; LANES];
    let mut slope0 = [0.0; LANES];
    let mut curve0 = [0.0; LANES];
    let mut size0 = [0.0; LANES];
    let mut speed = [0.0; LANES];
    let mut bend = [0.0; LANES];
    let mut jerk = [0.0; LANES];
    let modes = modes.iter().zip(deviations);
    for ((w, (m, d)), out) in weights.iter().zip(modes).zip(coefficients) {
        let (mu, rate, cube) = (m.rate_complex, m.rate, m.cube);
        let (d_re, d_im) = (d.re, d.im);
        let (mu2_re, mu2_im) = (m.rate_square.re, m.rate_square.im);
        let square = m.square;
        // Quantity by quantity over the lanes (each a packed operation), the same
        // operations per lane as one lane at a time.
        let (a, b) = w.split_at(LANES);
        let c_re: [f64; LANES] = std::array::from_fn(|l| a[l] * d_re - b[l] * d_im);
        let c_im: [f64; LANES] = std::array::from_fn(|l| a[l] * d_im + b[l] * d_re);
        let size: [f64; LANES] = std::array::from_fn(|l| c_re[l].abs() + c_im[l].abs());
        let (out_re, out_im) = out.split_at_mut(LANES);
        out_re.copy_from_slice(&c_re);
        out_im.copy_from_slice(&c_im);
        for l in 0..LANES {
            start[l] += c_re[l];
        }
        for l in 0..LANES {
            slope0[l] += c_re[l] * mu.re - c_im[l] * mu.im;
        }
        for l in 0..LANES {
            curve0[l] += c_re[l] * mu2_re - c_im[l] * mu2_im;
        }
        for l in 0..LANES {
            size0[l] += size[l];
        }
        for l in 0..LANES {
            speed[l] += rate * size[l];
        }
        for l in 0..LANES {
            bend[l] += square * size[l];
        }
        for l in 0..LANES {
            jerk[l] += cube * size[l];
        }
    }
    LaneSums {
        start,
        slope0,
        curve0,
        size0,
        speed,
        bend,
        jerk,
    }
    .summaries()
}

/// The sums of [`summarize_lanes`] (and of its AVX form), lane by lane.
struct LaneSums {
    start: [f64; LANES],
    slope0: [f64; LANES],
    curve0: [f64; LANES],
    size0: [f64; LANES],
    speed: [f64; LANES],
    bend: [f64; LANES],
    jerk: [f64; LANES],
}

impl LaneSums {
    /// Each lane's [`Summary`] (a summary of constant-polynomial decaying terms: no centre,
    /// the spread its size, the same third-derivative bound cut or not).
    #[inline(always)]
    fn write(&self, out: &mut [Summary; LANES]) {
        for (l, sum) in out.iter_mut().enumerate() {
            *sum = Summary {
                start: self.start[l],
                slope0: self.slope0[l],
                curve0: self.curve0[l],
                size0: self.size0[l],
                centre: 0.0,
                spread: self.size0[l],
                speed: self.speed[l],
                bend: self.bend[l],
                jerk_cut: self.jerk[l],
                jerk_horizon: self.jerk[l],
            };
        }
    }

    /// [`Self::write`] as an array.
    #[inline(always)]
    fn summaries(&self) -> [Summary; LANES] {
        let mut out = [Summary::default(); LANES];
        self.write(&mut out);
        out
    }
}

impl Summary {
    /// Adds the term `c e^{μs}` (a constant polynomial), for a search cut at `cutoff` on the
    /// grid of `horizon` (both finite; they matter only for a growing rate, `Re μ > 0`).
    #[inline]
    pub(crate) fn add(&mut self, c: C64, mu: C64, cutoff: f64, horizon: f64) {
        let slope = c * mu;
        self.start += c.re;
        self.slope0 += slope.re;
        let size = l1(c);
        self.size0 += size;
        let rate = l1(mu);
        let growth_horizon = if mu.re > 0.0 {
            (mu.re * horizon).exp()
        } else {
            1.0
        };
        self.jerk_horizon += rate * rate * rate * size * growth_horizon;
        if mu == C64::default() {
            self.centre += c.re;
        } else {
            let growth = if mu.re > 0.0 {
                (mu.re * cutoff).exp()
            } else {
                1.0
            };
            self.spread += size * growth;
            self.speed += (rate * size) * growth;
            self.bend += (rate * (rate * size)) * growth;
            self.curve0 += slope.re * mu.re - slope.im * mu.im;
            self.jerk_cut += (rate * rate * rate * size) * growth;
        }
    }

    /// [`Self::add`] for a rate that does not grow (`Re μ ≤ 0`): the same sums, without the
    /// growth factors, which are then exactly 1.
    #[inline]
    /// `CUT`: whether to form `f''(0)` and `sup|f'''|` on `[0, cutoff]` (only the tests of a
    /// search cut short use them).
    pub(crate) fn add_decaying<const CUT: bool>(&mut self, c: C64, mu: C64) {
        if mu.re == 0.0 && mu.im == 0.0 {
            self.start += c.re;
            self.slope0 += (c * mu).re;
            let size = l1(c);
            self.size0 += size;
            self.jerk_horizon += 0.0 * size;
            self.centre += c.re;
        } else {
            let rate = l1(mu);
            self.add_moving::<CUT>(c, mu, rate, rate * rate * rate);
        }
    }

    /// [`Self::add_decaying`] for a rate `μ ≠ 0`, given `rate = |Re μ| + |Im μ|` and
    /// `cube = (rate · rate) · rate`.
    #[inline]
    pub(crate) fn add_moving<const CUT: bool>(&mut self, c: C64, mu: C64, rate: f64, cube: f64) {
        let slope = c * mu;
        self.start += c.re;
        self.slope0 += slope.re;
        let size = l1(c);
        self.size0 += size;
        let jerk = cube * size;
        self.jerk_horizon += jerk;
        self.spread += size;
        self.speed += rate * size;
        self.bend += rate * (rate * size);
        if CUT {
            self.curve0 += slope.re * mu.re - slope.im * mu.im;
            self.jerk_cut += jerk;
        }
    }

    /// Adds a flight's term `c e^{μs}` for a rate `μ ≠ 0` that does not grow, given
    /// `rate = |Re μ| + |Im μ|` and `cube = (rate · rate) · rate`: the sums of
    /// [`Self::add_moving`] with `CUT` (the same bounds), with `f''(0)` formed as
    /// `Re(c · μ²)` and `sup|f''|` as `(rate · rate)·|c|`, so that [`summarize_block`] forms
    /// them with fewer products.
    #[inline]
    pub(crate) fn add_mode(&mut self, c: C64, mu: C64, rate: f64, cube: f64) {
        let mu2 = mu * mu;
        self.start += c.re;
        self.slope0 += c.re * mu.re - c.im * mu.im;
        self.curve0 += c.re * mu2.re - c.im * mu2.im;
        let size = c.re.abs() + c.im.abs();
        self.size0 += size;
        self.spread += size;
        self.speed += rate * size;
        self.bend += (rate * rate) * size;
        self.jerk_cut += cube * size;
        self.jerk_horizon += cube * size;
    }

    /// Where the quadratic Taylor model at `0` first leaves `(lo, hi)`, as
    /// [`ExpSum::estimated_exit`].
    pub(crate) fn estimated_exit(&self, lo: f64, hi: f64) -> f64 {
        quadratic_exit(self.start, self.slope0, self.curve0, lo, hi)
    }

    /// Whether that quadratic model stays inside `(lo, hi)` up to `until` (so that
    /// [`Self::estimated_exit`] is later), without its square root and divisions: a watch
    /// that wants only the earliest estimate skips the pairs that cannot have it.
    pub(crate) fn estimate_later_than(&self, lo: f64, hi: f64, until: f64) -> bool {
        let model = (self.start, self.slope0, self.curve0);
        quadratic_stays_inside(model, (lo, hi), until)
    }

    /// Whether `f` provably stays inside `(lo, hi)` on `[0, cutoff]` (a start on an edge
    /// moving back inside counts as inside), by bounds alone:
    ///
    /// - envelope: the constant part ± the largest the varying terms can be;
    /// - drift: `|f(s) − f(0)| ≤ s sup|f'|` (a short horizon, cut to an earlier contact of
    ///   another pair, is mostly decided here);
    /// - second order: `f(s) ∈ f(0) + [min(0, f'(0)s), max(0, f'(0)s)] ± ½ s² sup|f''|`;
    /// - for a search cut short of its horizon (`cutoff < horizon`: the watch of several
    ///   pairs, at an earlier contact of another pair), third order:
    ///   `f(s) ∈ f(0) + f'(0)s + ½f''(0)s² ± ⅙ s³ sup|f'''|`, the quadratic's extremes on
    ///   `[0, cutoff]` at its ends or its vertex; and for a start on an edge moving back
    ///   inside (the pair that has just impacted), `f(s) − f(0) = s (f'(0) + ½f''(0)s ±
    ///   ⅙ sup|f'''| s²)`, whose bracket is convex (concave) in `s` for the upper (lower)
    ///   bound, so its extreme on `[0, cutoff]` is at an end.
    ///
    /// Each test carries the rounding of the sums (`DRIFT_ROUNDING` of the terms' sizes).
    pub(crate) fn excludes(&self, lo: f64, hi: f64, cutoff: f64, horizon: f64) -> bool {
        let (start, slope0, curve0) = (self.start, self.slope0, self.curve0);
        let (size0, speed, bend) = (self.size0, self.speed, self.bend);
        if self.centre + self.spread < hi && self.centre - self.spread > lo {
            return true;
        }
        let drift = cutoff * speed + DRIFT_ROUNDING * size0;
        if start + drift < hi && start - drift > lo {
            return true;
        }
        let reach = 0.5 * cutoff * cutoff * bend + DRIFT_ROUNDING * (size0 + cutoff * speed);
        let moved = slope0 * cutoff;
        if start + moved.max(0.0) + reach < hi && start + moved.min(0.0) - reach > lo {
            return true;
        }
        if cutoff >= horizon {
            return false;
        }
        let quadratic = |s: f64| s * (slope0 + 0.5 * curve0 * s);
        let end = quadratic(cutoff);
        let (mut upper, mut lower) = (end.max(0.0), end.min(0.0));
        if curve0 != 0.0 {
            let vertex = -slope0 / curve0;
            if vertex > 0.0 && vertex < cutoff {
                upper = upper.max(quadratic(vertex));
                lower = lower.min(quadratic(vertex));
            }
        }
        let reach = cutoff * cutoff * cutoff * self.jerk_cut / 6.0
            + DRIFT_ROUNDING * (size0 + cutoff * speed + 0.5 * cutoff * cutoff * bend);
        let slope_slack = DRIFT_ROUNDING * (speed + 0.5 * cutoff * bend);
        let slope_end = slope0 + 0.5 * curve0 * cutoff;
        let third = self.jerk_cut * cutoff * cutoff / 6.0;
        let below = start + upper + reach < hi
            || (start <= hi && slope0.max(slope_end + third) + slope_slack < 0.0);
        let above = start + lower - reach > lo
            || (start >= lo && slope0.min(slope_end - third) - slope_slack > 0.0);
        below && above
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Numbers of both signs and several magnitudes, the same on every run.
    fn numbers(seed: u64) -> impl FnMut() -> f64 {
        let mut x = seed;
        move || {
            x = x
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            let unit = (x >> 11) as f64 / (1u64 << 53) as f64;
            (unit - 0.5) * 10f64.powi((x % 7) as i32 - 3)
        }
    }

    /// A pair whose quadratic model stays inside its band past `until` has its estimate later
    /// than `until`, so the watch may skip it; and the test says so for most models whose
    /// estimate is well past `until` (it is not vacuous). Over many models of every kind:
    /// exits on either side, starts on an edge moving in or out, turns short of a stop.
    #[test]
    fn an_estimate_skipped_is_later_than_the_earliest() {
        let mut next = numbers(11);
        let (mut skipped, mut later) = (0, 0);
        for _ in 0..20_000 {
            let (lo, hi) = (-0.5, 0.5);
            let mut start = 0.4 * next().signum() * next().abs().min(1.0);
            if next() > 0.3 {
                start = if next() > 0.0 { hi } else { lo };
            }
            let summary = Summary {
                start,
                slope0: next(),
                curve0: next(),
                ..Summary::default()
            };
            let until = next().abs();
            let estimate = summary.estimated_exit(lo, hi);
            if summary.estimate_later_than(lo, hi, until) {
                skipped += 1;
                assert!(estimate > until, "{summary:?}: {estimate} within {until}");
            }
            if estimate > 2.0 * until {
                later += 1;
            }
        }
        // Most models whose estimate is well past `until` are skipped.
        assert!(skipped > later / 2, "{skipped} skipped of {later}");
        assert!(!Summary::default().estimate_later_than(-1.0, 1.0, f64::INFINITY));
    }

    /// Each lane of a block's summaries, with and without AVX, is bit for bit the fold of
    /// `Summary::add_mode` over the modes, and the coefficients left are those it was given.
    #[test]
    fn a_blocks_lanes_are_each_functionals_summary_bit_for_bit() {
        let mut next = numbers(7);
        for count in [0, 1, 5, 17] {
            let (modes, deviations): (Vec<ModeTerm>, Vec<C64>) = (0..count)
                .map(|_| {
                    let rate_complex = C64::new(-next().abs(), next());
                    let rate = rate_complex.re.abs() + rate_complex.im.abs();
                    let weight = if next() > 0.0 { 2.0 } else { 1.0 };
                    let mode = ModeTerm::new(rate_complex, weight, (rate, rate * rate * rate));
                    (mode, mode.weighted(C64::new(next(), next())))
                })
                .unzip();
            let weights: Vec<[f64; 2 * LANES]> = (0..count)
                .map(|_| std::array::from_fn(|_| next()))
                .collect();
            let expected: [Summary; LANES] = std::array::from_fn(|l| {
                let mut sum = Summary::default();
                for ((w, m), &d) in weights.iter().zip(&modes).zip(&deviations) {
                    let c = C64::new(w[l], w[LANES + l]) * d;
                    sum.add_mode(c, m.rate_complex, m.rate, m.cube);
                }
                sum
            });
            // Each lane's coefficients, as `Summary::add_mode` was given them.
            let expected_coefficients: Vec<[f64; 2 * LANES]> = weights
                .iter()
                .zip(&deviations)
                .map(|(w, &d)| {
                    let c: [C64; LANES] = std::array::from_fn(|l| C64::new(w[l], w[LANES + l]) * d);
                    std::array::from_fn(|i| if i < LANES { c[i].re } else { c[i - LANES].im })
                })
                .collect();
            let bits = |c: &[[f64; 2 * LANES]]| {
                c.iter()
                    .flat_map(|row| row.map(f64::to_bits))
                    .collect::<Vec<_>>()
            };
            let mut coefficients = vec![[f64::NAN; 2 * LANES]; count];
            assert_eq!(
                summarize_lanes(&weights, (&modes, &deviations), &mut coefficients),
                expected
            );
            assert_eq!(bits(&coefficients), bits(&expected_coefficients));
            let mut coefficients = vec![[f64::NAN; 2 * LANES]; count];
            let mut sums = [Summary::default(); LANES];
            summarize_block(
                &weights,
                (&modes, &deviations),
                &mut coefficients,
                &mut sums,
            );
            assert_eq!(sums, expected);
            assert_eq!(bits(&coefficients), bits(&expected_coefficients));
            #[cfg(target_arch = "x86_64")]
            if std::arch::is_x86_feature_detected!("avx") {
                let mut coefficients = vec![[f64::NAN; 2 * LANES]; count];
                let mut sums = [Summary::default(); LANES];
                // SAFETY: the CPU has AVX.
                unsafe {
                    summarize_block_avx(
                        &weights,
                        (&modes, &deviations),
                        &mut coefficients,
                        &mut sums,
                    )
                };
                assert_eq!(sums, expected);
                assert_eq!(bits(&coefficients), bits(&expected_coefficients));
            }
        }
    }
}
