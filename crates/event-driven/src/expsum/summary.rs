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

/// One mode of a flight as [`Flight::summarize_all`](crate::flow::Flight) adds it to every
/// functional's [`Summary`]: the term `(w d)·weight e^{μs}` of a functional of modal weight
/// `w`, with `rate = |Re μ| + |Im μ| > 0` and `cube = (rate · rate) · rate`.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct ModeTerm {
    pub(crate) deviation: C64,
    pub(crate) weight: f64,
    pub(crate) rate_complex: C64,
    pub(crate) rate: f64,
    pub(crate) cube: f64,
}

/// The sums of two functionals' [`Summary`]s over the `modes`, side by side (the two lanes
/// independent, so the compiler may pack them): `weights[j] = [Re w₀, Re w₁, Im w₀, Im w₁]`
/// for mode `j`. Each lane's sums are bit for bit those of [`Summary::add_mode`] over the
/// modes in order, `c = w (d·weight)` formed as [`Complex`]'s products.
pub(crate) fn summarize_two(weights: &[[f64; 4]], modes: &[ModeTerm]) -> [Summary; 2] {
    let mut start = [0.0; 2];
    let mut slope0 = [0.0; 2];
    let mut curve0 = [0.0; 2];
    let mut size0 = [0.0; 2];
    let mut speed = [0.0; 2];
    let mut bend = [0.0; 2];
    let mut jerk = [0.0; 2];
    for (w, m) in weights.iter().zip(modes) {
        let (mu, rate, cube) = (m.rate_complex, m.rate, m.cube);
        // `d·weight` and `μ²` written out as [`Complex`]'s products form them (the same
        // operations in the same order), so that the loop calls nothing generic and compiles
        // the same whatever else the crate holds.
        let (d_re, d_im) = (m.deviation.re * m.weight, m.deviation.im * m.weight);
        let (mu2_re, mu2_im) = (mu.re * mu.re - mu.im * mu.im, mu.re * mu.im + mu.im * mu.re);
        let square = rate * rate;
        for l in 0..2 {
            let (a, b) = (w[l], w[2 + l]);
            let c_re = a * d_re - b * d_im;
            let c_im = a * d_im + b * d_re;
            start[l] += c_re;
            slope0[l] += c_re * mu.re - c_im * mu.im;
            curve0[l] += c_re * mu2_re - c_im * mu2_im;
            let size = c_re.abs() + c_im.abs();
            size0[l] += size;
            speed[l] += rate * size;
            bend[l] += square * size;
            jerk[l] += cube * size;
        }
    }
    [0, 1].map(|l| Summary {
        start: start[l],
        slope0: slope0[l],
        curve0: curve0[l],
        size0: size0[l],
        centre: 0.0,
        spread: size0[l],
        speed: speed[l],
        bend: bend[l],
        jerk_cut: jerk[l],
        jerk_horizon: jerk[l],
    })
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
    /// `Re(c · μ²)` and `sup|f''|` as `(rate · rate)·|c|`, so that [`summarize_two`] forms
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
