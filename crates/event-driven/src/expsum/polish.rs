//! The polish of a bracketed exit: safeguarded Halley iteration with exponentials carried
//! by short Taylor series.

use super::*;

/// Cap on polishing iterations (Halley, or bisection where Halley leaves the bracket): a
/// bisection alone halves a bracket to rounding in ~60 steps, so 100 is never reached by a
/// converging polish.
pub(super) const POLISH_ITERATIONS: usize = 100;

/// Halley's a-posteriori stop: the iterate is taken once the step is in the asymptotic regime
/// (`step × √contraction ≤` this) ...
pub(super) const HALLEY_ASYMPTOTIC: f64 = 1e-2;

/// ... and the predicted next error `contraction × step³` is below this fraction of the time
/// tolerance: the next step could not change the contact time by a visible amount.
pub(super) const HALLEY_MARGIN: f64 = 1e-3;

/// `|z|` up to which a degree-3 Taylor series of `e^z` is exact to `1e-17` (see [`exp_small`]).
pub(super) const TAYLOR_DEGREE_3: f64 = 1e-4;

/// `|z|` up to which a degree-5 Taylor series of `e^z` is exact to `1e-17` (see [`exp_small`]).
pub(super) const TAYLOR_DEGREE_5: f64 = 2e-3;

/// Largest `|μ δ|` (as `|re| + |im|`) for which `e^{μδ}` is taken from its Taylor series.
pub(super) const SMALL_STEP: f64 = 0.03;

/// `1/k!` from `k = 9` down to `1`: the Taylor coefficients of [`exp_small`], highest first
/// (the constant term `1` is added last).
pub(super) const INVERSE_FACTORIALS: [f64; 9] = [
    1.0 / 362_880.0,
    1.0 / 40_320.0,
    1.0 / 5_040.0,
    1.0 / 720.0,
    1.0 / 120.0,
    1.0 / 24.0,
    1.0 / 6.0,
    0.5,
    1.0,
];

/// Where in [`INVERSE_FACTORIALS`] the series of `e^z` starts for `|z| ≤ size` with every
/// degree from 1 to 8, each the least whose relative remainder `|z|^{d+1}/(d+1)!` is below
/// `1e-17`: 1 up to `4e-9` (`8e-18`), 2 up to `3e-6` (`5e-18`), 3 up to `1e-4` (`4e-18`), 4
/// up to `1e-3` (`8e-18`), 5 up to `4e-3` (`6e-18`), 6 up to `1e-2` (`2e-18`), 7 up to
/// `2.5e-2` (`4e-18`), else 8 (up to [`SMALL_STEP`]: `5e-20`). A polish's last steps are far
/// below `1e-4`.
#[inline]
pub(super) fn series_start_fine(size: f64) -> usize {
    pub(super) const BOUNDS: [f64; 7] = [4e-9, 3e-6, 1e-4, 1e-3, 4e-3, 1e-2, 2.5e-2];
    let degree = 1 + BOUNDS.iter().filter(|&&b| size > b).count();
    INVERSE_FACTORIALS.len() - degree
}

/// Where in [`INVERSE_FACTORIALS`] the series of [`exp_small`] starts for `|z| ≤ size`: degree
/// 3, 5 or 9.
#[inline]
pub(super) fn series_start(size: f64) -> usize {
    if size <= TAYLOR_DEGREE_3 {
        6
    } else if size <= TAYLOR_DEGREE_5 {
        4
    } else {
        0
    }
}

/// `e^z` for `|z| ≤` [`SMALL_STEP`] by its Taylor series, evaluated by Horner's rule with
/// real coefficients, to the least degree whose relative remainder is below `1e-17`: degree 3
/// for `|z| ≤ 1e-4` (`|z|⁴/4! ≤ 5e-18`), 5 for `|z| ≤ 2e-3` (`|z|⁶/6! ≤ 1e-19`), else 9
/// (`|z|¹⁰/10! ≤ 2e-22`). `|z|` is taken as `|re| + |im|`, an upper bound.
#[inline]
pub(super) fn exp_small(z: C64) -> C64 {
    let from = series_start(l1(z));
    let mut p = C64::new(INVERSE_FACTORIALS[from], 0.0);
    for c in &INVERSE_FACTORIALS[from + 1..] {
        p = p * z + *c;
    }
    p * z + 1.0
}

/// The function whose root a polish finds, `g = sign·(f − level)`, with what its stopping rule
/// needs: `f`'s derivative coefficients and `jerk`, a bound on `|f'''|`.
pub(super) struct Crossing<'f> {
    pub(super) f: &'f ExpSum,
    pub(super) derivatives: &'f Derivatives,
    pub(super) sign: f64,
    pub(super) level: f64,
    pub(super) jerk: f64,
}

/// The root of `g = sign·(f − level)` ([`Crossing`]) in `[a, b]` where `g(a) > 0 ≥ g(b)` and
/// `g` is monotone: Halley's iteration from `start` (cubic convergence, from the value and the
/// two derivatives that one evaluation gives), falling back to bisection when a step leaves
/// the bracket. Stops after a Halley step no longer than `tol`, or once the step's error
/// estimate `(f''²/(4f'²) + M₃/(6|f'|)) δ³` (`M₃ = jerk`, a bound on `|f'''|`) is below
/// `10⁻³ tol` while `δ` is well inside the asymptotic regime. `exps` is scratch storage.
///
/// The exponentials are carried from one iterate to the next, `e^{μ(s+δ)} = e^{μs} e^{μδ}`,
/// with `e^{μδ}` from its Taylor series once the steps are small (converging steps are tiny),
/// so the polish costs about one transcendental evaluation per term.
pub(super) fn polish(
    g: &Crossing<'_>,
    bracket: (f64, f64),
    start: f64,
    tol: f64,
    exps: &mut Exponentials,
) -> f64 {
    exps.values.clear();
    exps.values
        .extend(g.f.terms.iter().map(|t| cexp(t.rate, start)));
    exps.at = start;
    polish_from(g, bracket, start, tol, exps)
}

/// [`polish`] with `exps` already at `start`.
#[inline]
pub(super) fn polish_from(
    g: &Crossing<'_>,
    bracket: (f64, f64),
    start: f64,
    tol: f64,
    exps: &mut Exponentials,
) -> f64 {
    let root = iterate(g, bracket, start, tol, exps);
    exps.advance(&g.f.terms, root);
    root
}

/// The iteration of [`polish`].
pub(super) fn iterate(
    crossing: &Crossing<'_>,
    (mut a, mut b): (f64, f64),
    start: f64,
    tol: f64,
    exps: &mut Exponentials,
) -> f64 {
    let Crossing {
        f,
        derivatives,
        sign,
        level,
        jerk,
    } = *crossing;
    let mut g = |s: f64| {
        exps.advance(&f.terms, s);
        let (v, d, dd) = derivatives.at(f, s, &exps.values);
        (sign * (v - level), sign * d, sign * dd)
    };
    let mut s = start;
    for _ in 0..POLISH_ITERATIONS {
        let (v, d, dd) = g(s);
        if v == 0.0 {
            return s;
        }
        if v > 0.0 {
            a = s;
        } else {
            b = s;
        }
        let denominator = 2.0 * d * d - v * dd;
        let halley = if denominator != 0.0 {
            s - 2.0 * v * d / denominator
        } else {
            s - v / d
        };
        let step = (halley - s).abs();
        if halley >= a && halley <= b {
            // Halley's error: e⁺ ≈ (f''²/(4f'²) − f'''/(6f')) e³, with e ≈ the step.
            let contraction = 0.25 * (dd / d).powi(2) + jerk / (6.0 * d.abs());
            let converged = step <= tol
                || (step * contraction.sqrt() <= HALLEY_ASYMPTOTIC
                    && contraction * step * step * step <= HALLEY_MARGIN * tol);
            if converged {
                return halley;
            }
        }
        if halley > a && halley < b {
            s = halley;
        } else {
            s = 0.5 * (a + b);
            if b - a <= tol {
                return s;
            }
        }
    }
    s
}

/// `e^{μ_j s}` of every term at one time `s`.
#[derive(Debug, Clone, Default)]
pub(super) struct Exponentials {
    pub(super) at: f64,
    pub(super) values: Vec<C64>,
    /// Whether a small step takes every term's series to one degree, the least that the
    /// largest `|μ_j δ|` needs, all terms side by side (the summarised searches); otherwise
    /// each term's series has its own least degree.
    pub(super) together: bool,
    /// Per term, `(μ_j δ, partial sum)` of a step taken together.
    pub(super) work: Vec<(C64, C64)>,
}

impl Exponentials {
    /// Moves to `s`, from the current time by Taylor series for small steps.
    #[inline]
    pub(super) fn advance(&mut self, terms: &[Term], s: f64) {
        let delta = s - self.at;
        if delta != 0.0 && self.together {
            self.advance_together(terms, s, delta);
        } else if delta != 0.0 {
            for (e, t) in self.values.iter_mut().zip(terms) {
                let z = t.rate * delta;
                *e = if l1(z) <= SMALL_STEP {
                    *e * exp_small(z)
                } else {
                    cexp(t.rate, s)
                };
            }
            self.at = s;
        }
    }

    /// [`Self::advance`] by `delta = s − at ≠ 0` with every term's series to the least degree
    /// whose relative remainder is below `1e-17` for the largest `|μ_j δ|` (see
    /// [`series_start_fine`]), by Horner's rule one coefficient
    /// at a time across all terms (independent products, where each term's own chain of
    /// products would wait on the previous one); by term when a step is too large for the
    /// series.
    #[inline(never)]
    pub(super) fn advance_together(&mut self, terms: &[Term], s: f64, delta: f64) {
        self.work.clear();
        self.work
            .extend(terms.iter().map(|t| (t.rate * delta, C64::default())));
        let largest = self.work.iter().fold(0.0, |m: f64, (z, _)| m.max(l1(*z)));
        if largest > SMALL_STEP {
            for (e, (t, &(z, _))) in self.values.iter_mut().zip(terms.iter().zip(&self.work)) {
                *e = if l1(z) <= SMALL_STEP {
                    *e * exp_small(z)
                } else {
                    cexp(t.rate, s)
                };
            }
        } else {
            let from = series_start_fine(largest);
            for (_, p) in self.work.iter_mut() {
                *p = C64::new(INVERSE_FACTORIALS[from], 0.0);
            }
            for c in &INVERSE_FACTORIALS[from + 1..] {
                for (z, p) in self.work.iter_mut() {
                    *p = *p * *z + *c;
                }
            }
            for (e, (z, p)) in self.values.iter_mut().zip(&self.work) {
                *e *= *p * *z + 1.0;
            }
        }
        self.at = s;
    }
}
