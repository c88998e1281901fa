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

/// [`INVERSE_FACTORIALS`] as the real parts of two complex numbers, `[c, −0, c, −0]`, for
/// [`series_pairs_avx`] (adding `−0` leaves an imaginary part as it is, its sign too).
const PACKED_FACTORIALS: [[f64; 4]; 9] = {
    let mut packed = [[0.0; 4]; 9];
    let mut i = 0;
    while i < 9 {
        let c = INVERSE_FACTORIALS[i];
        packed[i] = [c, -0.0, c, -0.0];
        i += 1;
    }
    packed
};

/// `1` as [`PACKED_FACTORIALS`] lays its coefficients out.
const PACKED_ONE: [f64; 4] = [1.0, -0.0, 1.0, -0.0];

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
    let degree = 1 + SERIES_BOUNDS.iter().filter(|&&b| size > b).count();
    INVERSE_FACTORIALS.len() - degree
}

/// The bounds of [`series_start_fine`]'s degrees.
const SERIES_BOUNDS: [f64; 7] = [4e-9, 3e-6, 1e-4, 1e-3, 4e-3, 1e-2, 2.5e-2];

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
    /// The largest `|Re μ| + |Im μ|` of `f`'s terms, as the search's grid formed it
    /// ([`GridSteps::fastest`](super::cache::GridSteps)).
    pub(super) fastest: f64,
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
/// When every polynomial is a constant, the iterates within [`LOCAL_REACH`] of the start are
/// evaluated on `f`'s Taylor polynomial there ([`Local`]); other iterates carry the
/// exponentials from one to the next, `e^{μ(s+δ)} = e^{μs} e^{μδ}`, with `e^{μδ}` from its
/// Taylor series once the steps are small (converging steps are tiny), so the polish costs
/// about one transcendental evaluation per term. The exponentials end at the root.
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
    polish_from(g, bracket, (start, PolishStart::Near), tol, exps)
}

/// Where a polish starts: what [`iterate`] expects of its first evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum PolishStart {
    /// Near the root (a guess, a seed point): `f`'s Taylor polynomial at the start
    /// ([`Local`]) is formed at once, the first evaluation on it.
    Near,
    /// At the root to within a few roundings (a recalled exit whose Newton step is short,
    /// [`Seeds::recalled`]), with `(f, f', f'')` there, evaluated from the exponentials when
    /// the start was chosen: the first iterate from them ([`first_at_root`]), the polynomial
    /// formed only if a second one is needed (a polish mostly stops after one).
    AtRoot((f64, f64, f64)),
}

/// [`polish()`] with `exps` already at `start`. Always inlined: the compiler's heuristics
/// keep it out of line, and a unit then runs about 1 % more instructions (callgrind,
/// `unit_long 20000`).
#[inline(always)]
pub(super) fn polish_from(
    g: &Crossing<'_>,
    bracket: (f64, f64),
    (start, kind): (f64, PolishStart),
    tol: f64,
    exps: &mut Exponentials,
) -> f64 {
    let at_root = match kind {
        PolishStart::AtRoot(at_start) => first_at_root(g, bracket, (start, at_start), tol),
        PolishStart::Near => None,
    };
    let root = match at_root {
        Some(root) => root,
        None => {
            let local = Local::at(g, start, &exps.values);
            iterate(g, bracket, start, tol, exps, local.as_ref())
        }
    };
    exps.advance(&g.f.terms, root);
    root
}

/// `|μ δ|` (as `|re| + |im|`, for the fastest term) up to which [`Local`]'s degree-7 Taylor
/// polynomial stands in for `f`: its remainder is below `|μδ|⁸/8! ≤ 4e-18` of the terms'
/// sizes there (the exponentials' own series, [`series_start_fine`], take degree 7 up to the
/// same `2.5e-2`).
pub(super) const LOCAL_REACH: f64 = 2.5e-2;

/// `f` near the polish's start `at` as its Taylor polynomial of degree 7 in `δ = s − at`,
/// valid for `|δ| ≤ radius` ([`LOCAL_REACH`] over the fastest rate): the iterates of a polish
/// (which starts near its guess) are evaluated on it without advancing the exponentials,
/// which are advanced once, to the root.
pub(super) struct Local {
    at: f64,
    radius: f64,
    /// `f⁽ᵏ⁾(at)/k!`, `k = 0..=7`.
    coefficients: [f64; 8],
}

/// `1/k!`, `k = 0..=7`.
const LOCAL_FACTORIALS: [f64; 8] = [
    1.0,
    1.0,
    0.5,
    1.0 / 6.0,
    1.0 / 24.0,
    1.0 / 120.0,
    1.0 / 720.0,
    1.0 / 5040.0,
];

/// [`Local::at`]'s sums: `Σ Re(c_k e)` over the terms for `k = 0..=3` (`c_k = cμᵏ`, the
/// [`Derivatives`]), then `Σ Re(c₃ μ^{k−3} e)` for `k = 4..=7`; and the fastest rate (as
/// `|re| + |im|`).
#[inline(always)]
fn local_sums(derivatives: &[[C64; 4]], exps: &[C64], terms: &[Term]) -> [f64; 8] {
    let mut sums = [0.0; 8];
    for ((c, &e), t) in derivatives.iter().zip(exps).zip(terms) {
        let re = |a: C64| a.re * e.re - a.im * e.im;
        sums[0] += re(c[0]);
        sums[1] += re(c[1]);
        sums[2] += re(c[2]);
        sums[3] += re(c[3]);
        // `c μ^k e^{μ s}` for k = 4..=7.
        let mut x = c[3] * e;
        for sum in &mut sums[4..] {
            x *= t.rate;
            *sum += x.re;
        }
    }
    sums
}

/// [`local_sums`] with its first four sums side by side in an AVX register (each
/// `c.re·e.re − c.im·e.im` as there, summed over the terms in order from `+0`), the rest as
/// there: the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn local_sums_avx(derivatives: &[[C64; 4]], exps: &[C64], terms: &[Term]) -> [f64; 8] {
    use super::complex_pair_product;
    use std::arch::x86_64::*;
    let mut sums = [0.0; 8];
    // Lanes `[Σ Re(c₀e), Σ Re(c₂e), Σ Re(c₁e), Σ Re(c₃e)]`, as `_mm256_hsub_pd` leaves them.
    let mut low = _mm256_setzero_pd();
    for (c, &e) in derivatives.iter().zip(exps) {
        let e4 = _mm256_set_pd(e.im, e.re, e.im, e.re);
        let first = _mm256_set_pd(c[1].im, c[1].re, c[0].im, c[0].re);
        let second = _mm256_set_pd(c[3].im, c[3].re, c[2].im, c[2].re);
        low = _mm256_add_pd(
            low,
            _mm256_hsub_pd(_mm256_mul_pd(first, e4), _mm256_mul_pd(second, e4)),
        );
    }
    // `c μ^k e^{μ s}` for k = 4..=7, two terms to a register ([`complex_pair_product`]: `C64`'s
    // products), each term's real part added in the terms' order.
    let pack = |a: C64, b: C64| _mm256_set_pd(b.im, b.re, a.im, a.re);
    let n = derivatives.len().min(exps.len()).min(terms.len());
    let mut j = 0;
    while j + 2 <= n {
        let c3 = pack(derivatives[j][3], derivatives[j + 1][3]);
        let rate = pack(terms[j].rate, terms[j + 1].rate);
        let mut x = complex_pair_product(c3, pack(exps[j], exps[j + 1]));
        for sum in &mut sums[4..] {
            x = complex_pair_product(x, rate);
            let first = _mm256_cvtsd_f64(x);
            let second = _mm_cvtsd_f64(_mm256_extractf128_pd::<1>(x));
            *sum += first;
            *sum += second;
        }
        j += 2;
    }
    if j < n {
        let mut x = derivatives[j][3] * exps[j];
        for sum in &mut sums[4..] {
            x *= terms[j].rate;
            *sum += x.re;
        }
    }
    let mut out = [0.0; 4];
    // SAFETY: `out` holds four `f64`, the unaligned store's 32 bytes.
    unsafe { _mm256_storeu_pd(out.as_mut_ptr(), low) };
    sums[..4].copy_from_slice(&[out[0], out[2], out[1], out[3]]);
    sums
}

impl Local {
    /// The polynomial at `start`, given `exps[j] = e^{μ_j start}`; `None` unless every
    /// polynomial of `f` is a constant ([`Derivatives`] formed) and the exponentials are
    /// there.
    #[inline]
    pub(super) fn at(g: &Crossing<'_>, start: f64, exps: &[C64]) -> Option<Self> {
        let derivatives = &g.derivatives.0;
        if derivatives.is_empty() || exps.len() != derivatives.len() {
            return None;
        }
        #[cfg(target_arch = "x86_64")]
        let sums =
            if derivatives.len() >= PACKED_TERMS && std::arch::is_x86_feature_detected!("avx") {
                // SAFETY: the CPU has AVX (checked just above).
                unsafe { local_sums_avx(derivatives, exps, &g.f.terms) }
            } else {
                local_sums(derivatives, exps, &g.f.terms)
            };
        #[cfg(not(target_arch = "x86_64"))]
        let sums = local_sums(derivatives, exps, &g.f.terms);
        let fastest = g.fastest;
        debug_assert_eq!(
            fastest.to_bits(),
            g.f.terms
                .iter()
                .fold(0.0, |m, t| larger(m, l1(t.rate)))
                .to_bits()
        );
        let mut coefficients = [0.0; 8];
        for ((a, s), k) in coefficients.iter_mut().zip(sums).zip(LOCAL_FACTORIALS) {
            *a = s * k;
        }
        Some(Self {
            at: start,
            radius: LOCAL_REACH / fastest,
            coefficients,
        })
    }

    /// `(f, f', f'')` at `s`, or `None` beyond the polynomial's radius.
    #[inline]
    fn eval(&self, s: f64) -> Option<(f64, f64, f64)> {
        let d = s - self.at;
        if d.abs() > self.radius {
            return None;
        }
        let a = &self.coefficients;
        let (mut v, mut d1, mut d2) = (a[7], 7.0 * a[7], 42.0 * a[7]);
        for k in (2..7).rev() {
            v = v * d + a[k];
            d1 = d1 * d + k as f64 * a[k];
            d2 = d2 * d + (k * (k - 1)) as f64 * a[k];
        }
        v = (v * d + a[1]) * d + a[0];
        d1 = d1 * d + a[1];
        Some((v, d1, d2))
    }
}

/// Halley's step from `s`, where `g = v`, `g' = d`, `g'' = dd`, and whether its result is
/// the root: inside the bracket `[a, b]`, and no longer than `tol` or in the asymptotic
/// regime with a predicted next error below [`HALLEY_MARGIN`] of `tol` (`jerk` bounding
/// `|f'''|`).
#[inline(always)]
fn halley_step(
    (v, d, dd): (f64, f64, f64),
    s: f64,
    jerk: f64,
    tol: f64,
    (a, b): (f64, f64),
) -> (f64, bool) {
    let denominator = 2.0 * d * d - v * dd;
    let halley = if denominator != 0.0 {
        s - 2.0 * v * d / denominator
    } else {
        s - v / d
    };
    let step = (halley - s).abs();
    let converged = halley >= a && halley <= b && {
        // Halley's error: e⁺ ≈ (f''²/(4f'²) − f'''/(6f')) e³, with e ≈ the step.
        let contraction = 0.25 * (dd / d).powi(2) + jerk / (6.0 * d.abs());
        step <= tol
            || (step * contraction.sqrt() <= HALLEY_ASYMPTOTIC
                && contraction * step * step * step <= HALLEY_MARGIN * tol)
    };
    (halley, converged)
}

/// The first iterate of a polish [`PolishStart::AtRoot`] from `f`, `f'`, `f''` at `start`
/// (`at_start`, from the exponentials there): the root when Halley's step from `start` is
/// taken ([`halley_step`]), else `None` (the polish then iterates from `start` as from any
/// other start, its first evaluation on [`Local`] the same bits as these).
#[inline]
fn first_at_root(
    crossing: &Crossing<'_>,
    (a, b): (f64, f64),
    (start, (v, d, dd)): (f64, (f64, f64, f64)),
    tol: f64,
) -> Option<f64> {
    let sign = crossing.sign;
    let (v, d, dd) = (sign * (v - crossing.level), sign * d, sign * dd);
    if v == 0.0 {
        return Some(start);
    }
    let bracket = if v > 0.0 { (start, b) } else { (a, start) };
    let (halley, converged) = halley_step((v, d, dd), start, crossing.jerk, tol, bracket);
    converged.then_some(halley)
}

/// The iteration of [`polish()`]: `g` evaluated on `local` within its radius, else from the
/// exponentials advanced to each iterate.
pub(super) fn iterate(
    crossing: &Crossing<'_>,
    (mut a, mut b): (f64, f64),
    start: f64,
    tol: f64,
    exps: &mut Exponentials,
    local: Option<&Local>,
) -> f64 {
    let Crossing {
        f,
        derivatives,
        sign,
        level,
        jerk,
        ..
    } = *crossing;
    let mut g = |s: f64| {
        let (v, d, dd) = match local.and_then(|local| local.eval(s)) {
            Some(near) => near,
            None => {
                exps.advance(&f.terms, s);
                derivatives.at(f, s, &exps.values)
            }
        };
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
        let (halley, converged) = halley_step((v, d, dd), s, jerk, tol, (a, b));
        if converged {
            return halley;
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

/// Terms whose series [`Exponentials::advance_together`] steps side by side.
const TOGETHER: usize = 4;

/// `e^{μ_j s}` of every term at one time `s`.
#[derive(Debug, Clone)]
pub(super) struct Exponentials {
    pub(super) at: f64,
    pub(super) values: Vec<C64>,
    /// Whether a small step takes every term's series to one degree, the least that the
    /// largest `|μ_j δ|` needs, all terms side by side (the summarised searches); otherwise
    /// each term's series has its own least degree.
    pub(super) together: bool,
    /// The terms' largest `|Re μ| + |Im μ|` as their grid formed it
    /// ([`GridSteps::fastest`](super::cache::GridSteps)), or `NaN`: then the largest `|μ_j
    /// δ|` of a step is that times `|δ|` to within a few roundings ([`largest_step`]).
    pub(super) fastest: f64,
}

/// Relative distance from a bound of [`series_start_fine`] (or [`SMALL_STEP`]) beyond which
/// the largest `|μ_j δ|` (as `|Re μ_j δ| + |Im μ_j δ|`) and `|δ|` times the largest `|Re μ_j|
/// + |Im μ_j|` fall on the same side of it: each is within two roundings (`4.4e-16`) of the
/// exact `|δ| max_j (|Re μ_j| + |Im μ_j|)`.
const STEP_SIDE: f64 = 1e-14;

/// The degree [`Exponentials::advance_together`] takes for a step `δ` of `terms` whose largest
/// `|Re μ| + |Im μ|` is `fastest` (`NaN` if not known): as a place in [`INVERSE_FACTORIALS`]
/// ([`series_start_fine`]), or `None` beyond [`SMALL_STEP`]. From `|δ|·fastest` alone when
/// no bound lies within [`STEP_SIDE`] of it (the decisions of the largest `|μ_j δ|`, which
/// then need not be formed: a pass over the terms per step), else from the largest itself.
#[inline]
fn largest_step(terms: &[Term], delta: f64, fastest: f64) -> Option<usize> {
    let exact = || {
        terms
            .iter()
            .fold(0.0, |m: f64, t| larger(m, l1(t.rate * delta)))
    };
    let estimate = delta.abs() * fastest;
    let clear = |b: f64| (estimate - b).abs() > STEP_SIDE * b;
    // A unit's three terms cost fewer instructions than the bounds' tests.
    let shortcut = terms.len() >= PACKED_TERMS
        && estimate.is_finite()
        && clear(SMALL_STEP)
        && SERIES_BOUNDS.iter().all(|&b| clear(b));
    let degree = |largest: f64| (largest <= SMALL_STEP).then(|| series_start_fine(largest));
    if !shortcut {
        return degree(exact());
    }
    debug_assert_eq!(degree(estimate), degree(exact()), "δ = {delta}");
    degree(estimate)
}

impl Default for Exponentials {
    fn default() -> Self {
        Self {
            at: 0.0,
            values: Vec::new(),
            together: false,
            fastest: f64::NAN,
        }
    }
}

impl Exponentials {
    /// For a new search: at no time yet, stepping its terms `together` or not, their largest
    /// `|Re μ| + |Im μ|` `fastest` as their grid formed it (`NaN` until known).
    #[inline]
    pub(super) fn restart(&mut self, together: bool, fastest: f64) {
        self.at = f64::NAN;
        self.together = together;
        self.fastest = fastest;
    }

    /// Moves to `s`, from the current time by Taylor series for small steps (always inlined,
    /// as [`polish_from`] is).
    #[inline(always)]
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
    /// [`series_start_fine`]), by Horner's rule one coefficient at a time across a block of up
    /// to [`TOGETHER`] terms held on the stack (independent products, where each term's own
    /// chain of products would wait on the previous one); by term when a step is too large
    /// for the series.
    #[inline(never)]
    pub(super) fn advance_together(&mut self, terms: &[Term], s: f64, delta: f64) {
        let step = largest_step(terms, delta, self.fastest);
        if let Some(from) = step {
            self.series_together(terms, delta, from);
        } else {
            for (e, t) in self.values.iter_mut().zip(terms) {
                let z = t.rate * delta;
                *e = if l1(z) <= SMALL_STEP {
                    *e * exp_small(z)
                } else {
                    cexp(t.rate, s)
                };
            }
        }
        self.at = s;
    }

    /// [`Self::advance_together`]'s series, every term to the degree `from` gives.
    #[inline]
    fn series_together(&mut self, terms: &[Term], delta: f64, from: usize) {
        let n = self.values.len().min(terms.len());
        let (values, terms) = (&mut self.values[..n], &terms[..n]);
        // Two terms at a time with AVX, the rest (and all without it) below.
        #[cfg(target_arch = "x86_64")]
        let done = if n >= PACKED_TERMS && std::arch::is_x86_feature_detected!("avx") {
            // SAFETY: the CPU has AVX (checked just above).
            unsafe { series_pairs_avx(values, terms, delta, from) }
        } else {
            0
        };
        #[cfg(not(target_arch = "x86_64"))]
        let done = 0;
        let (values, terms) = (&mut values[done..], &terms[done..]);
        for (values, terms) in values.chunks_mut(TOGETHER).zip(terms.chunks(TOGETHER)) {
            // As many lanes as terms: a block of four would step a unit's three terms and a
            // fourth, empty lane through every degree.
            match terms.len() {
                TOGETHER => series_block::<TOGETHER>(values, terms, delta, from),
                3 => series_block::<3>(values, terms, delta, from),
                2 => series_block::<2>(values, terms, delta, from),
                _ => series_block::<1>(values, terms, delta, from),
            }
        }
    }
}

/// [`Exponentials::advance_together`]'s series for a block of `N` terms (`values` and
/// `terms` of `N` entries): `e_j ← e_j·(p_j z_j + 1)`, `p_j` by Horner's rule from
/// `INVERSE_FACTORIALS[from]`, `z_j = μ_j δ`, one coefficient at a time across the block.
#[inline(always)]
fn series_block<const N: usize>(values: &mut [C64], terms: &[Term], delta: f64, from: usize) {
    let mut z = [C64::default(); N];
    let mut p = [C64::new(INVERSE_FACTORIALS[from], 0.0); N];
    for (z, t) in z.iter_mut().zip(terms) {
        *z = t.rate * delta;
    }
    for c in &INVERSE_FACTORIALS[from + 1..] {
        for (p, z) in p.iter_mut().zip(&z) {
            *p = *p * *z + *c;
        }
    }
    for (e, (z, p)) in values.iter_mut().zip(z.iter().zip(&p)) {
        *e *= *p * *z + 1.0;
    }
}

/// [`Exponentials::advance_together`]'s series for the terms in pairs, two complex numbers to
/// an AVX register: `e_j ← e_j·(p_j z_j + 1)`, `p_j` by Horner's rule from
/// `INVERSE_FACTORIALS[from]`, `z_j = μ_j δ`. Each complex product is [`Complex`]'s (`re =
/// a.re b.re − a.im b.im`, `im = a.re b.im + a.im b.re`, the sum's operands swapped, which
/// rounds the same) and a real coefficient is added to the real part only (`−0` to the
/// imaginary part, which leaves it as it is, its sign too): the same bits as term by term.
/// Returns how many terms it advanced (all but a last odd one).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn series_pairs_avx(values: &mut [C64], terms: &[Term], delta: f64, from: usize) -> usize {
    use super::complex_pair_product as product;
    use std::arch::x86_64::*;
    // The series' coefficients as real parts of two complex numbers (`−0` imaginary parts),
    // loaded rather than formed per step.
    let real = |c: &[f64; 4]| {
        // SAFETY: `c` holds four `f64`: one unaligned load.
        unsafe { _mm256_loadu_pd(c.as_ptr()) }
    };
    let step = _mm256_set1_pd(delta);
    let start = _mm256_set_pd(0.0, INVERSE_FACTORIALS[from], 0.0, INVERSE_FACTORIALS[from]);
    let pairs = values.len().min(terms.len()) / 2;
    for (e, t) in values
        .chunks_exact_mut(2)
        .zip(terms.chunks_exact(2))
        .take(pairs)
    {
        let (r0, r1) = (t[0].rate, t[1].rate);
        let z = _mm256_mul_pd(_mm256_set_pd(r1.im, r1.re, r0.im, r0.re), step);
        let mut p = start;
        for c in &PACKED_FACTORIALS[from + 1..] {
            p = _mm256_add_pd(product(p, z), real(c));
        }
        let factor = _mm256_add_pd(product(p, z), real(&PACKED_ONE));
        // SAFETY: `e` holds two `C64` (`repr(C)`: four `f64`, `[re₀, im₀, re₁, im₁]`): one
        // unaligned load and one store.
        unsafe {
            let old = _mm256_loadu_pd(e.as_ptr().cast());
            _mm256_storeu_pd(e.as_mut_ptr().cast(), product(old, factor));
        }
    }
    2 * pairs
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Deterministic test values of mixed sign over five decades.
    fn value(i: usize, a: f64) -> f64 {
        (a * i as f64 + 0.3).sin() * 10f64.powi(i as i32 % 5 - 2)
    }

    /// `n` terms with constant polynomials (zero) and decaying or oscillating rates.
    fn decaying_terms(n: usize) -> Vec<Term> {
        (0..n)
            .map(|j| Term {
                poly: [C64::default(); 4],
                rate: C64::new(-value(j, 0.7).abs(), value(j, 3.1)),
            })
            .collect()
    }

    /// A local polynomial's sums with AVX are bit for bit those without.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn a_local_polynomials_sums_with_avx_are_those_without() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("skipped: this CPU has no AVX");
            return;
        }
        for n in [0, 1, 3, 17] {
            let terms = decaying_terms(n);
            let derivatives: Vec<[C64; 4]> = (0..n)
                .map(|j| {
                    std::array::from_fn(|k| C64::new(value(4 * j + k, 1.1), value(j + k, 2.3)))
                })
                .collect();
            let exps: Vec<C64> = (0..n)
                .map(|j| C64::new(value(j, 1.3), value(j, 2.9)))
                .collect();
            let sums = local_sums(&derivatives, &exps, &terms);
            // SAFETY: the CPU has AVX.
            let packed = unsafe { local_sums_avx(&derivatives, &exps, &terms) };
            assert_eq!(
                packed.map(f64::to_bits),
                sums.map(f64::to_bits),
                "{n} terms"
            );
        }
    }

    /// The series advanced two terms at a time with AVX is bit for bit the series term by
    /// term, at every degree.
    #[cfg(target_arch = "x86_64")]
    #[test]
    fn a_series_advanced_in_pairs_is_the_series_term_by_term() {
        if !std::arch::is_x86_feature_detected!("avx") {
            eprintln!("skipped: this CPU has no AVX");
            return;
        }
        for n in [0, 1, 2, 3, 17] {
            let terms = decaying_terms(n);
            let start: Vec<C64> = (0..n)
                .map(|j| C64::new(value(j, 1.3), value(j, 2.9)))
                .collect();
            for (from, delta) in [(0, 2e-3), (4, -1e-3), (7, 1e-7), (8, 1e-9)] {
                let expected: Vec<C64> = start
                    .iter()
                    .zip(&terms)
                    .map(|(e, t)| {
                        let z = t.rate * delta;
                        let mut p = C64::new(INVERSE_FACTORIALS[from], 0.0);
                        for c in &INVERSE_FACTORIALS[from + 1..] {
                            p = p * z + *c;
                        }
                        *e * (p * z + 1.0)
                    })
                    .collect();
                let mut values = start.clone();
                // SAFETY: the CPU has AVX.
                let done = unsafe { series_pairs_avx(&mut values, &terms, delta, from) };
                assert_eq!(done, n - n % 2);
                let bits = |v: &[C64]| {
                    v.iter()
                        .map(|c| (c.re.to_bits(), c.im.to_bits()))
                        .collect::<Vec<_>>()
                };
                assert_eq!(bits(&values[..done]), bits(&expected[..done]), "{n} terms");
            }
        }
    }
}
