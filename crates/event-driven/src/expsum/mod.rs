//! Real functions of time that are finite sums of (polynomial × complex exponential) terms:
//! the form every coordinate of a linear flow takes between events. Evaluation, a rigorous
//! bound on the second derivative, the *first* root after zero with a guarantee, and extrema.

use nalgebra::Complex;

type C64 = Complex<f64>;

/// `e^{μ s}`, skipping the real exponential for purely oscillatory and constant terms.
#[inline]
fn cexp(mu: C64, s: f64) -> C64 {
    if mu.im == 0.0 {
        C64::new((mu.re * s).exp(), 0.0)
    } else {
        let (sin, cos) = (mu.im * s).sin_cos();
        let r = if mu.re == 0.0 { 1.0 } else { (mu.re * s).exp() };
        C64::new(r * cos, r * sin)
    }
}

/// The drift test of [`ExpSum::first_exit`] widens its band by this many rounding units of the
/// terms' sizes at `s = 0`: `f(0)` is their sum, known to a few rounding units of them, so a
/// start that close to an edge is left to the full search.
const DRIFT_ROUNDING: f64 = 64.0 * f64::EPSILON;

/// For one term on `[0, h]`: bounds on its polynomial and the polynomial's first three
/// derivatives (absolute coefficients at `s = h`), `|μ|` (as `|re| + |im|`), and the growth
/// factor `max(1, e^{Re μ h})`.
///
/// A constant polynomial (every steady-response flight's terms) takes a short path with the
/// same values: the higher coefficients are exact zeros, and so are their contributions.
#[inline]
fn term_bounds(t: &Term, h: f64) -> ([f64; 4], f64, f64) {
    let zero = C64::default();
    let constant = t.poly[1] == zero && t.poly[2] == zero && t.poly[3] == zero;
    let p = if constant && h.is_finite() {
        [l1(t.poly[0]), 0.0, 0.0, 0.0]
    } else {
        let a = [l1(t.poly[0]), l1(t.poly[1]), l1(t.poly[2]), l1(t.poly[3])];
        [
            a[0] + h * (a[1] + h * (a[2] + h * a[3])),
            a[1] + h * (2.0 * a[2] + 3.0 * h * a[3]),
            2.0 * a[2] + 6.0 * h * a[3],
            6.0 * a[3],
        ]
    };
    let growth = if t.rate.re > 0.0 {
        (t.rate.re * h).exp()
    } else {
        1.0
    };
    (p, l1(t.rate), growth)
}

/// `|re| + |im|`: an upper bound on the modulus, without a square root.
#[inline]
fn l1(c: C64) -> f64 {
    c.re.abs() + c.im.abs()
}

/// Reusable storage for the interval stack of [`ExpSum::first_exit`]: passing the same one to
/// every search of a run avoids an allocation per search.
#[derive(Debug, Clone, Default)]
pub struct SearchStack {
    intervals: Vec<(f64, f64, f64, f64)>,
    /// `e^{μ_j s}` of every term at the current grid point.
    exps: Vec<C64>,
    /// The steps of the last grid of a horizon (the one-pair searches).
    grid: GridSteps,
    /// The steps of the fixed grids of the summarised searches, most recently used first (at
    /// most [`FIXED_GRIDS`]: the free flow's, and those of the sets of pairs held on their
    /// stops that the run goes through).
    fixed: Vec<GridSteps>,
    /// See [`Derivatives`].
    derivatives: Derivatives,
    /// The exponentials of the polishing iterate; after a search, at the exit it found (when
    /// polished).
    polish: Exponentials,
    /// The exponentials at one bisection point.
    point: Vec<C64>,
    /// The exponentials at the midpoint of the chunk being searched, on the fixed grid of a
    /// summarised search (see [`Seeds`]).
    mid: Vec<C64>,
}

/// Fixed grids kept by a [`SearchStack`] (see [`SearchStack::fixed`]).
const FIXED_GRIDS: usize = 4;

/// A grid's exponential steps for one set of rates and one half-width `w`.
#[derive(Debug, Clone, Default)]
struct GridSteps {
    /// The rates the steps were computed for.
    rates: Vec<C64>,
    /// The half-width `w` (`0` before the first search: no grid has it).
    w: f64,
    /// `e^{μ_j w}`: one grid step.
    steps: Vec<C64>,
    /// `e^{2μ_j w}`: the first chunk's end.
    doubled: Vec<C64>,
    /// The polish starts' exponential steps (fixed grids only).
    seeds: Seeds,
    /// Per chunk `i < CACHED_CHUNKS` of a fixed grid, `CHUNK_ROWS` rows of one entry per term:
    /// at the chunk's midpoint `m_i = 2wi + w`, `e^{μm}`, `μe^{μm}`, `μ²e^{μm}`, `μ³e^{μm}`, and
    /// at its end `e^{2μw(i+1)}`, each exponential evaluated afresh; valid where
    /// `chunk_filled`.
    chunk_exps: Vec<C64>,
    /// Per chunk, whether its rows in `chunk_exps` are computed.
    chunk_filled: Vec<bool>,
}

/// Chunks of a fixed grid whose exponentials a [`GridSteps`] keeps (see
/// [`ExpSum::fixed_search`]); a search over more uses the grid's recurrence.
const CACHED_CHUNKS: usize = 256;

/// Rows per chunk in [`GridSteps::chunk_exps`].
const CHUNK_ROWS: usize = 5;

/// The fixed grid of `terms`' rates and half-width `w` among `grids` (most recently used first,
/// at most [`FIXED_GRIDS`]), moved to the front, or made there in place of the least recently
/// used.
fn fixed_grid<'g>(grids: &'g mut Vec<GridSteps>, terms: &[Term], w: f64) -> &'g mut GridSteps {
    match grids.iter().position(|g| g.matches(terms, w)) {
        Some(i) => grids[..=i].rotate_right(1),
        None => {
            if grids.len() < FIXED_GRIDS {
                grids.push(GridSteps::default());
            }
            grids.rotate_right(1);
            grids[0].refresh(terms, w);
        }
    }
    &mut grids[0]
}

/// Chunk `i`'s rows of a fixed grid (see [`GridSteps::chunk_exps`]), computed on first use.
fn chunk_rows<'c>(
    exps: &'c mut Vec<C64>,
    filled: &mut Vec<bool>,
    i: usize,
    w: f64,
    terms: &[Term],
) -> &'c [C64] {
    let n = terms.len();
    let rows = CHUNK_ROWS * n;
    if filled.len() <= i {
        filled.resize(i + 1, false);
        exps.resize((i + 1) * rows, C64::default());
    }
    let slot = &mut exps[i * rows..(i + 1) * rows];
    if !filled[i] {
        let m = 2.0 * w * i as f64 + w;
        let end = 2.0 * w * (i + 1) as f64;
        for (j, t) in terms.iter().enumerate() {
            let e = cexp(t.rate, m);
            let e1 = e * t.rate;
            let e2 = e1 * t.rate;
            slot[j] = e;
            slot[n + j] = e1;
            slot[2 * n + j] = e2;
            slot[3 * n + j] = e2 * t.rate;
            slot[4 * n + j] = cexp(t.rate, end);
        }
        filled[i] = true;
    }
    slot
}

/// `Σ_j Re(c_j x_j)`, the terms' constant coefficients `c_j` against `x`.
#[inline]
fn real_dot(terms: &[Term], x: &[C64]) -> f64 {
    terms
        .iter()
        .zip(x)
        .map(|(t, x)| t.poly[0].re * x.re - t.poly[0].im * x.im)
        .sum()
}

impl GridSteps {
    /// Whether these are the steps of `terms`' rates and half-width `w`.
    fn matches(&self, terms: &[Term], w: f64) -> bool {
        self.w == w
            && self.rates.len() == terms.len()
            && self.rates.iter().zip(terms).all(|(r, t)| *r == t.rate)
    }

    /// The steps of `terms`' rates and half-width `w`, computed afresh.
    fn refresh(&mut self, terms: &[Term], w: f64) {
        self.steps.clear();
        self.steps.extend(terms.iter().map(|t| cexp(t.rate, w)));
        self.doubled.clear();
        self.seeds.reset();
        self.rates.clear();
        self.rates.extend(terms.iter().map(|t| t.rate));
        self.w = w;
        self.chunk_exps.clear();
        self.chunk_filled.clear();
    }
}

/// Points within a chunk of the fixed grid where a summarised search's polish may start,
/// `m + k w/SEED_DIVISIONS` (`m` the chunk's midpoint, `|k| ≤ SEED_DIVISIONS`): their
/// exponentials follow from those at `m` by one complex product each,
/// `e^{μ(m + kh)} = e^{μm} e^{μkh}`, with `e^{μkh}` computed once per `k` and kept with the
/// grid's steps (the grid's half-width `w` is then the same from one flight to the next). The
/// polish so starts within `h/2` of the quadratic model's guess without evaluating an
/// exponential afresh.
#[derive(Debug, Clone, Default)]
struct Seeds {
    /// `e^{μ_j k h}` at `(k + SEED_DIVISIONS)·terms + j`, valid where `filled`.
    values: Vec<C64>,
    /// Per `k + SEED_DIVISIONS`, whether its exponentials are computed.
    filled: Vec<bool>,
}

impl Seeds {
    /// Forgets every step (the grid's rates or half-width changed).
    fn reset(&mut self) {
        self.values.clear();
        self.filled.clear();
        self.filled.resize(2 * SEED_DIVISIONS + 1, false);
    }
}

/// Seed points per half-chunk on either side of a chunk's midpoint (see [`Seeds`]): a start
/// within `w/128` of the guess, `|μ|w/128 ≤ π/1024` for the fastest term, so the polish's
/// first step needs a Taylor series of low degree.
const SEED_DIVISIONS: usize = 64;

/// A chunk's midpoint and its exponentials, for [`Seeds`].
struct Seed<'s> {
    m: f64,
    w: f64,
    mid: &'s [C64],
    seeds: &'s mut Seeds,
}

impl Seed<'_> {
    /// The seed point nearest `guess` within `[a, b]`, with its exponentials written into
    /// `exps`; `None` when no seed point lies in `[a, b]` (a bracket narrower than `h`).
    fn start_near(
        &mut self,
        guess: f64,
        (a, b): (f64, f64),
        terms: &[Term],
        exps: &mut Exponentials,
    ) -> Option<f64> {
        let divisions = SEED_DIVISIONS as f64;
        let h = self.w / divisions;
        let mut k = ((guess - self.m) / h).round();
        if self.m + k * h < a {
            k += 1.0;
        } else if self.m + k * h > b {
            k -= 1.0;
        }
        let start = self.m + k * h;
        if !(start >= a && start <= b && k.abs() <= divisions) {
            return None;
        }
        self.exponentials_at(k as i64, terms, &mut exps.values);
        exps.at = start;
        Some(start)
    }

    /// The seed point `m + kh` (`|k| ≤ SEED_DIVISIONS`).
    fn point(&self, k: i64) -> f64 {
        self.m + k as f64 * (self.w / SEED_DIVISIONS as f64)
    }

    /// The exponentials at the seed point `m + kh` (`|k| ≤ SEED_DIVISIONS`) into `out`.
    fn exponentials_at(&mut self, k: i64, terms: &[Term], out: &mut Vec<C64>) {
        let divisions = SEED_DIVISIONS as i64;
        debug_assert!(k.abs() <= divisions);
        let index = (k + divisions) as usize;
        let n = terms.len();
        if self.seeds.values.len() != (2 * SEED_DIVISIONS + 1) * n {
            self.seeds.values.clear();
            self.seeds
                .values
                .resize((2 * SEED_DIVISIONS + 1) * n, C64::default());
        }
        let steps = &mut self.seeds.values[index * n..(index + 1) * n];
        if !self.seeds.filled[index] {
            let h = self.w / SEED_DIVISIONS as f64;
            for (e, t) in steps.iter_mut().zip(terms) {
                *e = cexp(t.rate, k as f64 * h);
            }
            self.seeds.filled[index] = true;
        }
        out.clear();
        out.extend(self.mid.iter().zip(steps.iter()).map(|(x, y)| x * y));
    }
}

/// The exponentials at the end of the first chunk, `first_end`: when it is a whole chunk
/// (`chunks > 1`: `first_end = 2w`), from the cache kept with the grid's steps, filled on
/// first use.
fn set_exponentials(
    exps: &mut [C64],
    terms: &[Term],
    first_end: f64,
    chunks: usize,
    doubled: &mut Vec<C64>,
) {
    if chunks > 1 && doubled.len() == terms.len() {
        exps.copy_from_slice(doubled);
        return;
    }
    for (e, t) in exps.iter_mut().zip(terms) {
        *e = cexp(t.rate, first_end);
    }
    if chunks > 1 {
        doubled.clear();
        doubled.extend_from_slice(exps);
    }
}

impl SearchStack {
    /// `e^{μ_j s}` of every term of the function last searched, when `s` is the exit that
    /// search returned and was polished (`None` otherwise): what the flow needs for the state
    /// at the exit, without evaluating the exponentials again.
    pub fn exponentials_at(&self, s: f64) -> Option<&[C64]> {
        (self.polish.at == s).then_some(&self.polish.values[..])
    }
}

/// `e^{μ_j s}` of every term at one time `s`.
#[derive(Debug, Clone, Default)]
struct Exponentials {
    at: f64,
    values: Vec<C64>,
    /// Whether a small step takes every term's series to one degree, the least that the
    /// largest `|μ_j δ|` needs, all terms side by side (the summarised searches); otherwise
    /// each term's series has its own least degree.
    together: bool,
    /// Per term, `(μ_j δ, partial sum)` of a step taken together.
    work: Vec<(C64, C64)>,
}

impl Exponentials {
    /// Moves to `s`, from the current time by Taylor series for small steps.
    #[inline]
    fn advance(&mut self, terms: &[Term], s: f64) {
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
    fn advance_together(&mut self, terms: &[Term], s: f64, delta: f64) {
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

/// `(c, cμ, cμ²)` of every term when every polynomial is a constant `c` (the steady-response
/// flights), so that `f, f', f''` at a point where the exponentials are known cost three
/// real parts of products per term; empty otherwise.
#[derive(Debug, Clone, Default)]
struct Derivatives(Vec<[C64; 4]>);

impl Derivatives {
    fn of(&mut self, f: &ExpSum) {
        self.0.clear();
        if f.terms
            .iter()
            .all(|t| t.poly[1..].iter().all(|c| *c == C64::default()))
        {
            self.0.extend(f.terms.iter().map(|t| {
                let c = t.poly[0];
                let c2 = c * t.rate * t.rate;
                [c, c * t.rate, c2, c2 * t.rate]
            }));
        }
    }

    /// `f` at `s`, given `exps[j] = e^{μ_j s}`.
    #[inline]
    fn value(&self, f: &ExpSum, s: f64, exps: &[C64]) -> f64 {
        if self.0.is_empty() {
            return f
                .terms
                .iter()
                .zip(exps)
                .map(|(t, &e)| {
                    let p = t.poly;
                    ((p[0] + (p[1] + (p[2] + p[3] * s) * s) * s) * e).re
                })
                .sum();
        }
        self.0
            .iter()
            .zip(exps)
            .map(|(c, e)| c[0].re * e.re - c[0].im * e.im)
            .sum()
    }

    /// `(f, f', f'', f''')` at `s`, given `exps[j] = e^{μ_j s}`, for steady-response flights
    /// (every polynomial a constant); `f''' = NaN` otherwise.
    #[inline]
    fn at3(&self, f: &ExpSum, s: f64, exps: &[C64]) -> (f64, f64, f64, f64) {
        if self.0.is_empty() {
            let (v, d, dd) = f.eval2_with(s, exps);
            return (v, d, dd, f64::NAN);
        }
        let re = |a: C64, b: C64| a.re * b.re - a.im * b.im;
        let (mut v, mut d, mut dd, mut d3) = (0.0, 0.0, 0.0, 0.0);
        for (c, &e) in self.0.iter().zip(exps) {
            v += re(c[0], e);
            d += re(c[1], e);
            dd += re(c[2], e);
            d3 += re(c[3], e);
        }
        (v, d, dd, d3)
    }

    /// `f'''` at the point where `exps[j] = e^{μ_j s}`, for steady-response flights; `NaN`
    /// otherwise.
    #[inline]
    fn third(&self, exps: &[C64]) -> f64 {
        if self.0.is_empty() {
            return f64::NAN;
        }
        self.0
            .iter()
            .zip(exps)
            .map(|(c, e)| c[3].re * e.re - c[3].im * e.im)
            .sum()
    }

    /// `(f, f', f'')` at `s`, given `exps[j] = e^{μ_j s}`.
    #[inline]
    fn at(&self, f: &ExpSum, s: f64, exps: &[C64]) -> (f64, f64, f64) {
        if self.0.is_empty() {
            return f.eval2_with(s, exps);
        }
        let re = |a: C64, b: C64| a.re * b.re - a.im * b.im;
        let (mut v, mut d, mut dd) = (0.0, 0.0, 0.0);
        for (c, &e) in self.0.iter().zip(exps) {
            v += re(c[0], e);
            d += re(c[1], e);
            dd += re(c[2], e);
        }
        (v, d, dd)
    }
}

/// Grid steps between fresh exponentials in [`ExpSum::first_exit`]: the recurrence
/// `e^{μ(s + w)} = e^{μs} e^{μw}` gains at most about this many roundings.
const REANCHOR: usize = 32;

/// Growth factor of the head chunks of [`ExpSum::first_exit`]: a short flight is covered by
/// chunks that double from the start's clearance, so it is found in about `log₂` of the first
/// chunk's length over the flight's steps.
const HEAD: f64 = 2.0;

/// Search chunks per oscillation of the fastest term in [`ExpSum::first_exit`]: an eighth of an
/// oscillation is short enough for the derivative bounds to exclude most chunks at once.
const CHUNKS_PER_OSCILLATION: f64 = 8.0;

/// The head of doubling chunks is used when the quadratic model's exit lies within this
/// fraction of the first chunk (a short bounce), as it is for a slow start (see [`HEAD`]).
const HEAD_ESTIMATE: f64 = 8.0;

/// A start within this fraction of the band `[lo, hi]` of an edge is "on the edge" (a release,
/// a graze), and worth a Taylor clearance: far above rounding and the event loop's contact
/// depth (`1e-12` of the gap), far below the height of a bounce that the grid finds anyway.
const ON_EDGE: f64 = 1e-6;

/// ... provided its slope would move it by less than this fraction of the band over the first
/// chunk: a slow departure. A fast one (an impact) is found by the quadratic model or the grid.
const SLOW_DEPARTURE: f64 = 1e-3;

/// Halvings of the Taylor clearance from its first trial length before giving up (clearance
/// `0` below `limit / 2¹⁶`): past that, the grid search costs less than more halvings.
const CLEARANCE_HALVINGS: usize = 16;

/// Interval halvings in [`ExpSum::max_abs`] stop at this fraction of the horizon: a few
/// rounding units of the time, below which the function cannot be resolved.
const MAX_ABS_RESOLUTION: f64 = 1e-15;

/// Cap on polishing iterations (Halley, or bisection where Halley leaves the bracket): a
/// bisection alone halves a bracket to rounding in ~60 steps, so 100 is never reached by a
/// converging polish.
const POLISH_ITERATIONS: usize = 100;

/// Halley's a-posteriori stop: the iterate is taken once the step is in the asymptotic regime
/// (`step × √contraction ≤` this) ...
const HALLEY_ASYMPTOTIC: f64 = 1e-2;

/// ... and the predicted next error `contraction × step³` is below this fraction of the time
/// tolerance: the next step could not change the contact time by a visible amount.
const HALLEY_MARGIN: f64 = 1e-3;

/// `|z|` up to which a degree-3 Taylor series of `e^z` is exact to `1e-17` (see [`exp_small`]).
const TAYLOR_DEGREE_3: f64 = 1e-4;

/// `|z|` up to which a degree-5 Taylor series of `e^z` is exact to `1e-17` (see [`exp_small`]).
const TAYLOR_DEGREE_5: f64 = 2e-3;

/// One term `(c₀ + c₁ s + c₂ s² + c₃ s³) e^{μ s}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    /// Polynomial coefficients, lowest degree first.
    pub poly: [C64; 4],
    /// Complex rate `μ`.
    pub rate: C64,
}

/// `f(s) = Re Σ_j term_j(s)`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExpSum {
    /// The terms.
    pub terms: Vec<Term>,
}

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
    start: f64,
    /// `f'(0)`.
    slope0: f64,
    /// `f''(0)`.
    curve0: f64,
    /// `Σ |c|` over every term: the rounding scale of `f(0)`.
    size0: f64,
    /// The constant terms' sum.
    centre: f64,
    /// A bound on the varying terms' size on `[0, cutoff]`.
    spread: f64,
    /// A bound on `|f'|` on `[0, cutoff]`.
    speed: f64,
    /// A bound on `|f''|` on `[0, cutoff]`.
    bend: f64,
    /// A bound on `|f'''|` on `[0, cutoff]`.
    jerk_cut: f64,
    /// A bound on `|f'''|` on `[0, horizon]`.
    jerk_horizon: f64,
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
        let d = m.deviation * m.weight;
        let mu2 = mu * mu;
        let square = rate * rate;
        for l in 0..2 {
            let (a, b) = (w[l], w[2 + l]);
            let c_re = a * d.re - b * d.im;
            let c_im = a * d.im + b * d.re;
            start[l] += c_re;
            slope0[l] += c_re * mu.re - c_im * mu.im;
            curve0[l] += c_re * mu2.re - c_im * mu2.im;
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

impl ExpSum {
    /// Value and first derivative at `s`.
    #[inline]
    pub fn eval(&self, s: f64) -> (f64, f64) {
        let (mut v, mut d) = (0.0, 0.0);
        for t in &self.terms {
            let e = cexp(t.rate, s);
            let p = t.poly;
            let poly = p[0] + (p[1] + (p[2] + p[3] * s) * s) * s;
            let dpoly = p[1] + (p[2] * 2.0 + p[3] * (3.0 * s)) * s;
            v += (poly * e).re;
            d += ((dpoly + poly * t.rate) * e).re;
        }
        (v, d)
    }

    /// Value and first two derivatives at `s`.
    #[inline]
    pub fn eval2(&self, s: f64) -> (f64, f64, f64) {
        let (mut v, mut d, mut dd) = (0.0, 0.0, 0.0);
        for t in &self.terms {
            let e = cexp(t.rate, s);
            let p = t.poly;
            let mu = t.rate;
            let poly = p[0] + (p[1] + (p[2] + p[3] * s) * s) * s;
            let d1 = p[1] + (p[2] * 2.0 + p[3] * (3.0 * s)) * s;
            let d2 = p[2] * 2.0 + p[3] * (6.0 * s);
            v += (poly * e).re;
            d += ((d1 + poly * mu) * e).re;
            dd += ((d2 + (d1 * 2.0 + poly * mu) * mu) * e).re;
        }
        (v, d, dd)
    }

    /// A bound on `|f'''(s)|` for `s ∈ [0, horizon]`, like [`Self::curvature_bound`].
    pub fn jerk_bound(&self, horizon: f64) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                let ([p0, p1, p2, p3], m, growth) = term_bounds(t, horizon);
                (p3 + 3.0 * m * p2 + 3.0 * m * m * p1 + m * m * m * p0) * growth
            })
            .sum()
    }

    /// A bound on `|f''''(s)|` for `s ∈ [0, horizon]`, like [`Self::curvature_bound`].
    pub fn fourth_derivative_bound(&self, horizon: f64) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                let ([p0, p1, p2, p3], m, growth) = term_bounds(t, horizon);
                let m2 = m * m;
                (m2 * m2 * p0 + 4.0 * m2 * m * p1 + 6.0 * m2 * p2 + 4.0 * m * p3) * growth
            })
            .sum()
    }

    /// The fastest rate `max |μ|` among the terms (at least `1/horizon`).
    fn fastest(&self, horizon: f64) -> f64 {
        self.terms
            .iter()
            .map(|t| l1(t.rate))
            .fold(1.0 / horizon, f64::max)
    }

    /// A bound on `|f''(s)|` for `s ∈ [0, horizon]`: each term's polynomial and its
    /// derivatives bounded at `s = horizon` with absolute coefficients, times
    /// `max(1, e^{Re μ · horizon})`.
    pub fn curvature_bound(&self, horizon: f64) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                let ([p0, p1, p2, _], m, growth) = term_bounds(t, horizon);
                (p2 + 2.0 * m * p1 + m * m * p0) * growth
            })
            .sum()
    }

    /// Value and first two derivatives at `s`, given `exps[j] = e^{μ_j s}` for every term.
    #[inline]
    fn eval2_with(&self, s: f64, exps: &[C64]) -> (f64, f64, f64) {
        let (mut v, mut d, mut dd) = (0.0, 0.0, 0.0);
        for (t, &e) in self.terms.iter().zip(exps) {
            let p = t.poly;
            let mu = t.rate;
            let poly = p[0] + (p[1] + (p[2] + p[3] * s) * s) * s;
            let d1 = p[1] + (p[2] * 2.0 + p[3] * (3.0 * s)) * s;
            let d2 = p[2] * 2.0 + p[3] * (6.0 * s);
            v += (poly * e).re;
            d += ((d1 + poly * mu) * e).re;
            dd += ((d2 + (d1 * 2.0 + poly * mu) * mu) * e).re;
        }
        (v, d, dd)
    }

    /// Where the quadratic Taylor model of `f` at `s = 0` first leaves `(lo, hi)` (`∞` if it
    /// does not): an estimate only, with no transcendental evaluation, to order searches.
    pub fn estimated_exit(&self, lo: f64, hi: f64) -> f64 {
        let (mut f0, mut d0, mut dd0) = (0.0, 0.0, 0.0);
        for t in &self.terms {
            let (p, mu) = (t.poly, t.rate);
            f0 += p[0].re;
            d0 += (p[1] + p[0] * mu).re;
            dd0 += (p[2] * 2.0 + (p[1] * 2.0 + p[0] * mu) * mu).re;
        }
        quadratic_exit(f0, d0, dd0, lo, hi)
    }

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
    /// The horizon is first cut into chunks about an eighth of the fastest oscillation long;
    /// their midpoints and ends lie on a uniform grid where every exponential follows from
    /// the previous one by one complex product (`e^{μ(s+w)} = e^{μs} e^{μw}`, recomputed
    /// afresh every `REANCHOR` = 32 steps), so a whole flight costs a handful of transcendental
    /// evaluations. When the quadratic model at `0` leaves the band early, or the start is
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
        self.first_exit_until(
            lo,
            hi,
            horizon,
            horizon,
            time_tolerance,
            depth_tolerance,
            stack,
        )
    }

    /// [`Self::first_exit`] on the grid of `horizon`, but searched only until `cutoff ≤
    /// horizon`: every exit before `cutoff` is found as there (an exit after it may or may not
    /// be reported). Searches of several functionals of one flight with one `horizon` share
    /// the grid, and `stack` keeps the grid's exponential steps from one to the next when the
    /// rates are the same (a flight's pairs all have the flow's rates).
    #[allow(clippy::too_many_arguments)]
    pub fn first_exit_until(
        &self,
        lo: f64,
        hi: f64,
        horizon: f64,
        cutoff: f64,
        time_tolerance: f64,
        depth_tolerance: f64,
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
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
                for t in &self.terms {
                    sum.add_decaying::<false>(t.poly[0], t.rate);
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

    /// [`Self::first_exit_until`] of a function whose [`Summary`] is known (as
    /// [`Flight::summarize`](crate::flow::Flight) forms it from the terms the flight writes:
    /// every polynomial a constant, no growing rate, `horizon` finite), whose evaluation-free
    /// tests ([`Summary::excludes`] up to `cutoff`) the caller has already made and found
    /// undecided: the same search, without forming the sums or making the tests again.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn first_exit_summarized(
        &self,
        summary: &Summary,
        lo: f64,
        hi: f64,
        horizon: f64,
        cutoff: f64,
        time_tolerance: f64,
        depth_tolerance: f64,
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
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

    /// The search of [`Self::first_exit_summarized`]: [`Self::grid_search`] on its fixed grid
    /// (half-width `w = π/(8 max|μ|)`), with each chunk's exponentials taken from the grid's
    /// cache ([`GridSteps::chunk_exps`], evaluated afresh once per run) rather than carried
    /// from chunk to chunk: a chunk's `f`, `f'`, `f''` at its midpoint and `f` at its end are
    /// four sums of the terms' coefficients against cached rows, and the products `cμᵏ` of
    /// [`Derivatives`] are formed only for a search that needs them (a head of short chunks,
    /// a chunk not excluded at once). `f(0)`, `f'(0)`, `f''(0)` are the summary's. The tests,
    /// the head, the last chunk and the seeded polish are those of [`Self::grid_search`];
    /// a horizon of more than [`CACHED_CHUNKS`] chunks is left to it.
    fn fixed_search(
        &self,
        summary: &Summary,
        (lo, hi): (f64, f64),
        horizon: f64,
        cutoff: f64,
        (time_tolerance, depth_tolerance): (f64, f64),
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
        let jerk = summary.jerk_horizon;
        let fastest = self.terms.iter().map(|t| l1(t.rate)).fold(0.0, f64::max);
        let w = std::f64::consts::PI / (CHUNKS_PER_OSCILLATION * fastest);
        let chunks = if fastest > 0.0 && fastest.is_finite() {
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
            ..
        } = stack;
        let GridSteps {
            seeds,
            chunk_exps,
            chunk_filled,
            ..
        } = fixed_grid(fixed_grids, &self.terms, w);
        let n = self.terms.len();
        let mut fourth = f64::NAN;
        // `Derivatives::of`, once, when first needed.
        let mut derived = false;
        let mut derive = |derivatives: &mut Derivatives| {
            if !derived {
                derivatives.of(self);
                derived = true;
            }
        };
        scratch.at = f64::NAN;
        scratch.together = true;
        let (f0, d0, dd0) = (summary.start, summary.slope0, summary.curve0);
        let mut fa = f0;
        // The head, as in `grid_search`.
        let first_end = if chunks == 1 { horizon } else { 2.0 * w };
        let estimate = quadratic_exit(f0, d0, dd0, lo, hi);
        let on_edge = (f0 - lo).min(hi - f0) <= ON_EDGE * (hi - lo)
            && d0.abs() * first_end < SLOW_DEPARTURE * (hi - lo);
        let cleared = if !on_edge {
            0.0
        } else {
            derive(derivatives);
            let d3: f64 = derivatives
                .0
                .iter()
                .zip(&self.terms)
                .map(|(c, t)| (c[2] * t.rate).re)
                .sum();
            taylor_clearance(
                [f0, d0, dd0, d3],
                self.fourth_derivative_bound(horizon),
                (lo, hi),
                depth_tolerance,
                first_end,
            )
        };
        let mut first = 0;
        if cleared >= first_end {
            first = 1;
            if chunks > 1 {
                let rows = chunk_rows(chunk_exps, chunk_filled, 0, w, &self.terms);
                fa = real_dot(&self.terms, &rows[4 * n..]);
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
            derive(derivatives);
            let rows = chunk_rows(chunk_exps, chunk_filled, 0, w, &self.terms);
            let mut seed = Seed {
                m: w,
                w,
                mid: &rows[..n],
                seeds: &mut *seeds,
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
                seed.exponentials_at(km, &self.terms, point);
                let at_m = derivatives.at3(self, seed.point(km), point);
                seed.exponentials_at(kb, &self.terms, point);
                let fb = derivatives.value(self, b, point);
                let found = self.exit_in_chunk(
                    (a, b, fa, fb),
                    at_m,
                    (lo, hi),
                    (jerk, &mut fourth, horizon),
                    (time_tolerance, depth_tolerance),
                    intervals,
                    derivatives,
                    scratch,
                    point,
                    Some(Seed {
                        m: w,
                        w,
                        mid: &rows[..n],
                        seeds: &mut *seed.seeds,
                    }),
                );
                if found.is_some() {
                    return found;
                }
                fa = fb;
                ka = kb;
                length *= 2.0;
            }
            first = 1;
        } else if (cleared > 0.0 && HEAD * cleared < first_end)
            || HEAD_ESTIMATE * estimate < first_end
        {
            derive(derivatives);
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
                let at_m = self.eval3(m, derivatives, point);
                let fb = self.eval(b).0;
                let found = self.exit_in_chunk(
                    (a, b, fa, fb),
                    at_m,
                    (lo, hi),
                    (jerk, &mut fourth, horizon),
                    (time_tolerance, depth_tolerance),
                    intervals,
                    derivatives,
                    scratch,
                    point,
                    None,
                );
                if found.is_some() {
                    return found;
                }
                fa = fb;
                a = b;
                length *= 2.0;
            }
            first = 1;
        }
        let jerk_reach = jerk * w * w * w / 6.0;
        for i in first..chunks {
            let a = 2.0 * w * i as f64;
            if a >= cutoff {
                break;
            }
            let m = a + w;
            let rows = chunk_rows(chunk_exps, chunk_filled, i, w, &self.terms);
            let (mut fm, mut dm, mut ddm) = (0.0, 0.0, 0.0);
            for (j, t) in self.terms.iter().enumerate() {
                let c = t.poly[0];
                let re = |x: C64| c.re * x.re - c.im * x.im;
                fm += re(rows[j]);
                dm += re(rows[n + j]);
                ddm += re(rows[2 * n + j]);
            }
            if i + 1 == chunks {
                // The last chunk, `[a, horizon]` within `[a, a + 2w]`.
                if a + 2.0 * w >= horizon && inside((fm, dm, ddm), w, jerk_reach, (lo, hi)) {
                    return None;
                }
                derive(derivatives);
                let at_m = self.eval3(0.5 * (a + horizon), derivatives, point);
                let fb = self.eval(horizon).0;
                return self.exit_in_chunk(
                    (a, horizon, fa, fb),
                    at_m,
                    (lo, hi),
                    (jerk, &mut fourth, horizon),
                    (time_tolerance, depth_tolerance),
                    intervals,
                    derivatives,
                    scratch,
                    point,
                    None,
                );
            }
            let b = 2.0 * w * (i + 1) as f64;
            let fb = real_dot(&self.terms, &rows[4 * n..]);
            if inside((fm, dm, ddm), w, jerk_reach, (lo, hi)) {
                fa = fb;
                continue;
            }
            let d3m = real_dot(&self.terms, &rows[3 * n..4 * n]);
            derive(derivatives);
            let seed = Seed {
                m,
                w,
                mid: &rows[..n],
                seeds: &mut *seeds,
            };
            let found = self.exit_in_chunk(
                (a, b, fa, fb),
                (fm, dm, ddm, d3m),
                (lo, hi),
                (jerk, &mut fourth, horizon),
                (time_tolerance, depth_tolerance),
                intervals,
                derivatives,
                scratch,
                point,
                Some(seed),
            );
            if found.is_some() {
                return found;
            }
            fa = fb;
        }
        None
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
    /// polish starts from them ([`Seed`]). The one-pair searches keep the grid of the horizon.
    #[inline(always)]
    fn grid_search<const FIXED: bool>(
        &self,
        (lo, hi): (f64, f64),
        horizon: f64,
        cutoff: f64,
        jerk: f64,
        (time_tolerance, depth_tolerance): (f64, f64),
        stack: &mut SearchStack,
    ) -> Option<(f64, i8)> {
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
        let SearchStack {
            intervals,
            exps,
            grid,
            fixed: fixed_grids,
            derivatives,
            polish: scratch,
            point,
            mid,
        } = stack;
        // A bound on |f''''| over the horizon, computed when a chunk first needs it.
        let mut fourth = f64::NAN;
        derivatives.of(self);
        scratch.at = f64::NAN;
        scratch.together = FIXED;
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
            ..
        } = grid;
        let (f0, d0, dd0) = derivatives.at(self, 0.0, exps);
        let mut fa = f0;
        // Head: when the flight may leave the band long before the first chunk ends (a bounce
        // within chatter, a departure from a stop after a release), the first chunk is
        // covered by chunks that double from the start's Taylor clearance and the quadratic
        // model's exit, so that a short flight is not found by bisecting down from a whole
        // chunk.
        let first_end = if chunks == 1 { horizon } else { 2.0 * w };
        let estimate = quadratic_exit(f0, d0, dd0, lo, hi);
        // Only a slow start on an edge (a release, a graze) is worth clearing: a fast one
        // (an impact) is found by the quadratic model or the grid.
        let on_edge = (f0 - lo).min(hi - f0) <= ON_EDGE * (hi - lo)
            && d0.abs() * first_end < SLOW_DEPARTURE * (hi - lo);
        let cleared = if derivatives.0.is_empty() || !on_edge {
            0.0
        } else {
            let d3: f64 = derivatives
                .0
                .iter()
                .zip(&self.terms)
                .map(|(c, t)| (c[2] * t.rate).re)
                .sum();
            taylor_clearance(
                [f0, d0, dd0, d3],
                self.fourth_derivative_bound(horizon),
                (lo, hi),
                depth_tolerance,
                first_end,
            )
        };
        let mut first = 0;
        if cleared >= first_end {
            first = 1;
            set_exponentials(exps, &self.terms, first_end, chunks, doubled);
            fa = derivatives.value(self, first_end, exps);
        } else if (cleared > 0.0 && HEAD * cleared < first_end)
            || HEAD_ESTIMATE * estimate < first_end
        {
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
                let at_m = self.eval3(m, derivatives, point);
                let fb = self.eval(b).0;
                let found = self.exit_in_chunk(
                    (a, b, fa, fb),
                    at_m,
                    (lo, hi),
                    (jerk, &mut fourth, horizon),
                    (time_tolerance, depth_tolerance),
                    intervals,
                    derivatives,
                    scratch,
                    point,
                    None,
                );
                if found.is_some() {
                    return found;
                }
                fa = fb;
                a = b;
                length *= 2.0;
            }
            first = 1;
            set_exponentials(exps, &self.terms, first_end, chunks, doubled);
        }
        let jerk_reach = jerk * w * w * w / 6.0;
        for i in first..chunks {
            let a = 2.0 * w * i as f64;
            if a >= cutoff {
                break;
            }
            let b = if i + 1 == chunks {
                horizon
            } else {
                2.0 * w * (i + 1) as f64
            };
            let m = a + w;
            for (e, step) in exps.iter_mut().zip(steps.iter()) {
                *e *= step;
            }
            let (fm, dm, ddm) = derivatives.at(self, m, exps);
            if fixed && i + 1 == chunks {
                // The last chunk, `[a, horizon]` within `[a, a + 2w]`.
                if a + 2.0 * w >= horizon && inside((fm, dm, ddm), w, jerk_reach, (lo, hi)) {
                    return None;
                }
                let at_m = self.eval3(0.5 * (a + horizon), derivatives, point);
                let fb = self.eval(horizon).0;
                return self.exit_in_chunk(
                    (a, horizon, fa, fb),
                    at_m,
                    (lo, hi),
                    (jerk, &mut fourth, horizon),
                    (time_tolerance, depth_tolerance),
                    intervals,
                    derivatives,
                    scratch,
                    point,
                    None,
                );
            }
            // The test of `exit_in_chunk`, inline: most chunks are excluded at once.
            let excluded = inside((fm, dm, ddm), w, jerk_reach, (lo, hi));
            let d3m = if excluded {
                f64::NAN
            } else {
                derivatives.third(exps)
            };
            if fixed && !excluded {
                mid.clear();
                mid.extend_from_slice(exps);
            }
            if (2 * i + 2) % REANCHOR == 0 {
                for (e, t) in exps.iter_mut().zip(&self.terms) {
                    *e = cexp(t.rate, b);
                }
            } else {
                for (e, step) in exps.iter_mut().zip(steps.iter()) {
                    *e *= step;
                }
            }
            let fb = derivatives.value(self, b, exps);
            if excluded {
                fa = fb;
                continue;
            }
            let at_m = (fm, dm, ddm, d3m);
            let seed = fixed.then_some(Seed {
                m,
                w,
                mid,
                seeds: &mut *seeds,
            });
            let found = self.exit_in_chunk(
                (a, b, fa, fb),
                at_m,
                (lo, hi),
                (jerk, &mut fourth, horizon),
                (time_tolerance, depth_tolerance),
                intervals,
                derivatives,
                scratch,
                point,
                seed,
            );
            if found.is_some() {
                return found;
            }
            fa = fb;
        }
        None
    }

    /// The first exit from `(lo, hi)` within one chunk `[a, b]` (values `fa`, `fb` at its
    /// ends, value and derivatives `at_m` at its midpoint), by the bounds of
    /// [`Self::first_exit`]; bisects left first. With a `seed` (the chunk's midpoint
    /// exponentials), the polish starts at the seed point nearest its guess.
    #[allow(clippy::too_many_arguments)]
    fn exit_in_chunk(
        &self,
        chunk: (f64, f64, f64, f64),
        at_m: (f64, f64, f64, f64),
        (lo, hi): (f64, f64),
        (jerk, fourth, horizon): (f64, &mut f64, f64),
        (time_tolerance, depth_tolerance): (f64, f64),
        intervals: &mut Vec<(f64, f64, f64, f64)>,
        derivatives: &Derivatives,
        scratch: &mut Exponentials,
        point: &mut Vec<C64>,
        mut seed: Option<Seed<'_>>,
    ) -> Option<(f64, i8)> {
        intervals.clear();
        intervals.push(chunk);
        let mut known_m = Some(at_m);
        while let Some((a, b, fa, fb)) = intervals.pop() {
            let m = 0.5 * (a + b);
            let w = 0.5 * (b - a);
            let (fm, dm, ddm, d3m) = known_m
                .take()
                .unwrap_or_else(|| self.eval3(m, derivatives, point));
            // f(m + τ) = f(m) + f'(m)τ + ½f''(m)τ² + R, |R| ≤ ⅙ M₃ w³ on [a, b].
            if inside((fm, dm, ddm), w, jerk * w * w * w / 6.0, (lo, hi)) {
                continue;
            }
            // Monotone when f' cannot reach zero: |f'(t) − f'(m)| ≤ |f''(m)| w + ½ M₃ w².
            let mut monotone = dm.abs() > ddm.abs() * w + 0.5 * jerk * w * w;
            if !monotone && d3m.is_finite() {
                // One order more, with f'''(m) known and M₄ bounding |f''''|: the cubic model
                // ± M₄ w⁴/24, and f' = f'(m) + f''(m)τ + ½f'''(m)τ² ± M₄ w³/6. A near graze
                // is settled in fewer halvings.
                if fourth.is_nan() {
                    *fourth = self.fourth_derivative_bound(horizon);
                }
                let w3 = w * w * w;
                if inside_cubic((fm, dm, ddm, d3m), w, *fourth * w3 * w / 24.0, (lo, hi)) {
                    continue;
                }
                monotone = slope_keeps_sign((dm, ddm, d3m), w, *fourth * w3 / 6.0);
            }
            if monotone {
                // Monotone on [a, b]: it can only reach `hi` if increasing, `lo` if decreasing.
                // Quadratic model at m: a first guess for Newton.
                let guess = |target: f64| {
                    let disc = dm * dm - 2.0 * ddm * (fm - target);
                    let step = if ddm != 0.0 && disc >= 0.0 {
                        (-dm + dm.signum() * disc.sqrt()) / ddm
                    } else {
                        (target - fm) / dm
                    };
                    (m + step).clamp(a, b)
                };
                // The polish of `sign·(f − level)` from the guess: from the seed point
                // nearest it when there is one in the bracket, else from fresh exponentials.
                let mut polish_to = |sign: f64, level: f64| {
                    let guess = guess(level);
                    let seeded = seed
                        .as_mut()
                        .and_then(|seed| seed.start_near(guess, (a, b), &self.terms, scratch));
                    match seeded {
                        Some(start) => polish_from(
                            self,
                            derivatives,
                            sign,
                            level,
                            (a, b),
                            start,
                            time_tolerance,
                            jerk,
                            scratch,
                        ),
                        None => polish(
                            self,
                            derivatives,
                            sign,
                            level,
                            (a, b),
                            guess,
                            time_tolerance,
                            jerk,
                            scratch,
                        ),
                    }
                };
                if dm > 0.0 {
                    if fa >= hi {
                        return Some((a, 1)); // on the upper edge at the start, moving out
                    }
                    if fb >= hi {
                        // hi − f: positive, then ≤ 0.
                        return Some((polish_to(-1.0, hi), 1));
                    }
                } else {
                    if fa <= lo {
                        return Some((a, -1));
                    }
                    if fb <= lo {
                        // f − lo: positive, then ≤ 0.
                        return Some((polish_to(1.0, lo), -1));
                    }
                }
                continue;
            }
            if w < time_tolerance {
                if fm >= hi + depth_tolerance {
                    return Some((m, 1));
                }
                if fm <= lo - depth_tolerance {
                    return Some((m, -1));
                }
                continue;
            }
            intervals.push((m, b, fm, fb));
            intervals.push((a, m, fa, fm));
        }
        None
    }

    /// `(f, f', f'', f''')` at `s` (`f''' = NaN` unless every polynomial is a constant), with
    /// the exponentials evaluated afresh into `point`.
    fn eval3(
        &self,
        s: f64,
        derivatives: &Derivatives,
        point: &mut Vec<C64>,
    ) -> (f64, f64, f64, f64) {
        point.clear();
        point.extend(self.terms.iter().map(|t| cexp(t.rate, s)));
        derivatives.at3(self, s, point)
    }

    /// Whether `|f| < floor` on `[0, horizon]` with room for the rounding of any evaluation
    /// there (see [`Self::max_abs`]; `false` when that cannot be told from the Taylor bound at
    /// `0`, or for terms with a polynomial or a growing rate).
    fn bounded_by(&self, floor: f64, horizon: f64) -> bool {
        let zero = C64::default();
        let (mut value, mut slope, mut curve) = (0.0, 0.0, 0.0);
        let (mut size, mut speed, mut bend, mut jerk) = (0.0, 0.0, 0.0, 0.0);
        for t in &self.terms {
            if t.rate.re > 0.0 || t.poly[1..].iter().any(|c| *c != zero) {
                return false;
            }
            let (c, mu) = (t.poly[0], t.rate);
            let cm = c * mu;
            value += c.re;
            slope += cm.re;
            curve += (cm * mu).re;
            let (a, m) = (l1(c), l1(mu));
            size += a;
            speed += a * m;
            bend += a * m * m;
            jerk += a * m * m * m;
        }
        let h = horizon;
        let quadratic = |s: f64| value + s * (slope + 0.5 * curve * s);
        let mut largest = quadratic(0.0).abs().max(quadratic(h).abs());
        if curve != 0.0 {
            let vertex = -slope / curve;
            if vertex > 0.0 && vertex < h {
                largest = largest.max(quadratic(vertex).abs());
            }
        }
        let rounding = DRIFT_ROUNDING * (size + h * speed + 0.5 * h * h * bend);
        largest + jerk * h * h * h / 6.0 + 2.0 * rounding < floor
    }

    /// `f + c`.
    pub fn shifted(&self, c: f64) -> ExpSum {
        let mut out = self.clone();
        out.terms.push(Term {
            poly: [
                C64::new(c, 0.0),
                C64::default(),
                C64::default(),
                C64::default(),
            ],
            rate: C64::default(),
        });
        out
    }

    /// `−f`.
    pub fn negated(&self) -> ExpSum {
        let mut out = self.clone();
        for t in &mut out.terms {
            for c in &mut t.poly {
                *c = -*c;
            }
        }
        out
    }

    /// `max(floor, max |f|)` on `[0, horizon]` to an absolute tolerance `tolerance`, by branch
    /// and bound with the curvature bound. Intervals where `|f|` cannot exceed the larger of
    /// `floor` and the best value so far by more than `tolerance` are not refined, so a running
    /// maximum passed as `floor` makes most calls cost one evaluation.
    ///
    /// A call whose floor already bounds `|f|` on the whole horizon returns it at once: for
    /// terms with constant polynomials and no growing rate, `|f(s)| ≤ |f(0)| + |f'(0)| s +
    /// ½f''(0) s² ± ⅙ s³ sup|f'''|` plus the rounding of every evaluation (`DRIFT_ROUNDING` of
    /// the terms' sizes), and when that is below the floor no evaluation could exceed it
    /// either.
    pub fn max_abs(&self, horizon: f64, floor: f64, tolerance: f64) -> f64 {
        if self.bounded_by(floor, horizon) {
            return floor;
        }
        let curvature = self.curvature_bound(horizon);
        let mut best = floor
            .max(self.eval(0.0).0.abs())
            .max(self.eval(horizon).0.abs());
        let mut stack = vec![(0.0, horizon)];
        while let Some((a, b)) = stack.pop() {
            let m = 0.5 * (a + b);
            let w = 0.5 * (b - a);
            let (fm, dm) = self.eval(m);
            best = best.max(fm.abs());
            if fm.abs() + dm.abs() * w + 0.5 * curvature * w * w <= best + tolerance
                || w < MAX_ABS_RESOLUTION * horizon
            {
                continue;
            }
            stack.push((a, m));
            stack.push((m, b));
        }
        best
    }
}

/// The largest `h ≤ limit` (halving from `limit`, `0` below `limit / 2¹⁶`) such that `f`
/// cannot leave `(lo − depth, hi + depth)` on `[0, h]`, from the Taylor expansion at `0`
/// (`taylor = [f, f', f'', f''']`) and a bound `fourth` on `|f''''|`: on each side
/// `g = ±(f − edge) + depth`, `g(t) ≥ g₀ + g₁t + ½g₂t² + ⅙g₃t³ − fourth·t⁴/24`, and the
/// minimum over `[0, h]` of the cubic that bounds this from below (`t⁴ ≤ h t³` absorbed into
/// the cubic coefficient) is found in closed form. A flight that departs from a stop with
/// zero velocity (a plastic impact, a release) is cleared this way for a good part of its
/// departure, where bisection would need a level per halving.
fn taylor_clearance(
    taylor: [f64; 4],
    fourth: f64,
    (lo, hi): (f64, f64),
    depth: f64,
    limit: f64,
) -> f64 {
    // Lower bound of g on [0, h] for g with Taylor coefficients (g0, g1, g2, g3):
    // q(t) = g0 + g1 t + ½g2 t² + (⅙g3 − fourth·h/24) t³ ≤ g(t), minimised over the ends
    // and the roots of q' in (0, h).
    let min_on = |g: [f64; 4], h: f64| -> f64 {
        let (c1, c2, c3) = (g[1], 0.5 * g[2], g[3] / 6.0 - fourth * h / 24.0);
        let q = |t: f64| g[0] + t * (c1 + t * (c2 + t * c3));
        let mut least = g[0].min(q(h));
        // q'(t) = c1 + 2c2 t + 3c3 t².
        let (a, b, c) = (3.0 * c3, 2.0 * c2, c1);
        let roots = if a == 0.0 {
            [-c / b, f64::NAN]
        } else {
            let disc = b * b - 4.0 * a * c;
            if disc < 0.0 {
                [f64::NAN, f64::NAN]
            } else {
                let q = -0.5 * (b + b.signum() * disc.sqrt());
                [q / a, c / q]
            }
        };
        for t in roots {
            if t > 0.0 && t < h {
                least = least.min(q(t));
            }
        }
        least
    };
    let [f0, f1, f2, f3] = taylor;
    let below = [f0 - lo + depth, f1, f2, f3];
    let above = [hi + depth - f0, -f1, -f2, -f3];
    if !(below[0] > 0.0 && above[0] > 0.0 && fourth.is_finite()) {
        return 0.0;
    }
    let mut h = limit;
    for _ in 0..CLEARANCE_HALVINGS {
        if min_on(below, h) > 0.0 && min_on(above, h) > 0.0 {
            return h;
        }
        h *= 0.5;
    }
    0.0
}

/// Whether `f` stays inside `(lo, hi)` on `[m − w, m + w]`, given `(f, f', f'')` at `m` and
/// `cubic = M₃ w³/6` (`M₃` a bound on `|f'''|`): `f(m + τ) = f + f'τ + ½f''τ² + R`,
/// `|R| ≤ cubic`, and the quadratic's extremes over `|τ| ≤ w` are at the ends or at its
/// vertex. Keeping the sign of `f''` makes a motion that turns back short of a stop (a near
/// graze) excluded at once, where `|f'|w + ½|f''|w²` would need many bisections.
#[inline]
fn inside((f, d, dd): (f64, f64, f64), w: f64, cubic: f64, (lo, hi): (f64, f64)) -> bool {
    let ends = 0.5 * dd * w * w;
    let (mut upper, mut lower) = ((d * w).abs() + ends, ends - (d * w).abs());
    if dd != 0.0 && d.abs() <= dd.abs() * w {
        let vertex = -0.5 * d * d / dd;
        if dd < 0.0 {
            upper = upper.max(vertex);
        } else {
            lower = lower.min(vertex);
        }
    }
    f + upper + cubic < hi && f + lower - cubic > lo
}

/// Whether `f` stays inside `(lo, hi)` on `[m − w, m + w]`, given `(f, f', f'', f''')` at `m`
/// and `quartic = M₄ w⁴/24` (`M₄` a bound on `|f''''|`): the cubic Taylor polynomial's
/// extremes over `|τ| ≤ w` (at the ends or where its slope vanishes) ± `quartic`.
#[inline]
fn inside_cubic(
    (f, d, dd, d3): (f64, f64, f64, f64),
    w: f64,
    quartic: f64,
    (lo, hi): (f64, f64),
) -> bool {
    let p = |t: f64| t * (d + t * (0.5 * dd + t * d3 / 6.0));
    let (mut upper, mut lower) = (p(w).max(p(-w)), p(w).min(p(-w)));
    // p'(τ) = d + dd τ + ½ d3 τ².
    for t in quadratic_roots(0.5 * d3, dd, d) {
        if t.abs() < w {
            upper = upper.max(p(t));
            lower = lower.min(p(t));
        }
    }
    f + upper + quartic < hi && f + lower - quartic > lo
}

/// Whether `f'` keeps its sign on `[m − w, m + w]`, given `(f', f'', f''')` at `m` and
/// `cubic = M₄ w³/6`: the extremes of `f' + f''τ + ½f'''τ²` over `|τ| ≤ w`, ± `cubic`.
#[inline]
fn slope_keeps_sign((d, dd, d3): (f64, f64, f64), w: f64, cubic: f64) -> bool {
    let q = |t: f64| d + t * (dd + 0.5 * t * d3);
    let (mut upper, mut lower) = (q(w).max(q(-w)), q(w).min(q(-w)));
    if d3 != 0.0 {
        let t = -dd / d3;
        if t.abs() < w {
            upper = upper.max(q(t));
            lower = lower.min(q(t));
        }
    }
    lower > cubic || upper < -cubic
}

/// The real roots of `a t² + b t + c` (NaN where there is none), without cancellation.
#[inline]
fn quadratic_roots(a: f64, b: f64, c: f64) -> [f64; 2] {
    if a == 0.0 {
        return [-c / b, f64::NAN];
    }
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return [f64::NAN, f64::NAN];
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    [q / a, c / q]
}

/// The first `t > 0` at which `f0 + d0 t + ½ dd0 t²` reaches `lo` or `hi` (`∞` if never):
/// an estimate of a flight's length, not a bound.
fn quadratic_exit(f0: f64, d0: f64, dd0: f64, lo: f64, hi: f64) -> f64 {
    // Smallest positive root of ½ dd0 t² + d0 t + c where the model moves out of the band
    // (`outward` · slope > 0): a start on an edge moving inside is no exit.
    let root = |c: f64, outward: f64| -> f64 {
        let a = 0.5 * dd0;
        let candidates = if a == 0.0 {
            [-c / d0, f64::NAN]
        } else {
            let disc = d0 * d0 - 4.0 * a * c;
            if disc < 0.0 {
                return f64::INFINITY;
            }
            // Roots without cancellation.
            let q = -0.5 * (d0 + d0.signum() * disc.sqrt());
            [q / a, c / q]
        };
        candidates
            .into_iter()
            .filter(|&t| t > 0.0 && outward * (d0 + dd0 * t) > 0.0)
            .fold(f64::INFINITY, f64::min)
    };
    // A side the model moves away from throughout (`f'` and `f''` both of the other sign, so
    // `d0 + dd0·t` keeps that sign for every `t > 0`) has no candidate: `∞` without the root's
    // division and square root.
    let upper = if d0 <= 0.0 && dd0 <= 0.0 {
        f64::INFINITY
    } else {
        root(f0 - hi, 1.0)
    };
    let lower = if d0 >= 0.0 && dd0 >= 0.0 {
        f64::INFINITY
    } else {
        root(f0 - lo, -1.0)
    };
    upper.min(lower)
}

/// Largest `|μ δ|` (as `|re| + |im|`) for which `e^{μδ}` is taken from its Taylor series.
const SMALL_STEP: f64 = 0.03;

/// `1/k!` from `k = 9` down to `1`: the Taylor coefficients of [`exp_small`], highest first
/// (the constant term `1` is added last).
const INVERSE_FACTORIALS: [f64; 9] = [
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
fn series_start_fine(size: f64) -> usize {
    const BOUNDS: [f64; 7] = [4e-9, 3e-6, 1e-4, 1e-3, 4e-3, 1e-2, 2.5e-2];
    let degree = 1 + BOUNDS.iter().filter(|&&b| size > b).count();
    INVERSE_FACTORIALS.len() - degree
}

/// Where in [`INVERSE_FACTORIALS`] the series of [`exp_small`] starts for `|z| ≤ size`: degree
/// 3, 5 or 9.
#[inline]
fn series_start(size: f64) -> usize {
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
fn exp_small(z: C64) -> C64 {
    let from = series_start(l1(z));
    let mut p = C64::new(INVERSE_FACTORIALS[from], 0.0);
    for c in &INVERSE_FACTORIALS[from + 1..] {
        p = p * z + *c;
    }
    p * z + 1.0
}

/// The root of `g = sign·(f − level)` in `[a, b]` where `g(a) > 0 ≥ g(b)` and `g` is monotone:
/// Halley's iteration from `start` (cubic convergence, from the value and the two derivatives
/// that one evaluation gives), falling back to bisection when a step leaves the bracket.
/// Stops after a Halley step no longer than `tol`, or once the step's error estimate
/// `(f''²/(4f'²) + M₃/(6|f'|)) δ³` (`M₃ = jerk`, a bound on `|f'''|`) is below `10⁻³ tol`
/// while `δ` is well inside the asymptotic regime. `exps` is scratch storage.
///
/// The exponentials are carried from one iterate to the next, `e^{μ(s+δ)} = e^{μs} e^{μδ}`,
/// with `e^{μδ}` from its Taylor series once the steps are small (converging steps are tiny),
/// so the polish costs about one transcendental evaluation per term.
#[allow(clippy::too_many_arguments)]
fn polish(
    f: &ExpSum,
    derivatives: &Derivatives,
    sign: f64,
    level: f64,
    (a, b): (f64, f64),
    start: f64,
    tol: f64,
    jerk: f64,
    exps: &mut Exponentials,
) -> f64 {
    exps.values.clear();
    exps.values
        .extend(f.terms.iter().map(|t| cexp(t.rate, start)));
    exps.at = start;
    polish_from(f, derivatives, sign, level, (a, b), start, tol, jerk, exps)
}

/// [`polish`] with `exps` already at `start`.
#[allow(clippy::too_many_arguments)]
#[inline]
fn polish_from(
    f: &ExpSum,
    derivatives: &Derivatives,
    sign: f64,
    level: f64,
    (a, b): (f64, f64),
    start: f64,
    tol: f64,
    jerk: f64,
    exps: &mut Exponentials,
) -> f64 {
    let root = iterate(f, derivatives, sign, level, (a, b), start, tol, jerk, exps);
    exps.advance(&f.terms, root);
    root
}

/// The iteration of [`polish`].
#[allow(clippy::too_many_arguments)]
fn iterate(
    f: &ExpSum,
    derivatives: &Derivatives,
    sign: f64,
    level: f64,
    (mut a, mut b): (f64, f64),
    start: f64,
    tol: f64,
    jerk: f64,
    exps: &mut Exponentials,
) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn cosine(amplitude: f64, omega: f64, phase: f64, offset: f64) -> ExpSum {
        // offset + A cos(ωs + φ) = Re[offset + A e^{iφ} e^{iωs}]
        ExpSum {
            terms: vec![
                Term {
                    poly: [
                        C64::new(offset, 0.0),
                        C64::default(),
                        C64::default(),
                        C64::default(),
                    ],
                    rate: C64::default(),
                },
                Term {
                    poly: [
                        C64::from_polar(amplitude, phase),
                        C64::default(),
                        C64::default(),
                        C64::default(),
                    ],
                    rate: C64::new(0.0, omega),
                },
            ],
        }
    }

    /// The first time `f` reaches zero from above.
    fn first_root(f: &ExpSum, horizon: f64) -> Option<f64> {
        f.first_exit(
            0.0,
            f64::INFINITY,
            horizon,
            1e-14,
            0.0,
            &mut SearchStack::default(),
        )
        .map(|(s, side)| {
            assert_eq!(side, -1);
            s
        })
    }

    #[test]
    fn finds_the_first_of_two_crossings() {
        // 0.5 + cos(s): first zero at 2π/3.
        let f = cosine(1.0, 1.0, 0.0, 0.5);
        let r = first_root(&f, 10.0).unwrap();
        assert!((r - 2.0 * std::f64::consts::PI / 3.0).abs() < 1e-12, "{r}");
    }

    #[test]
    fn catches_a_dip_narrower_than_any_coarse_sampling() {
        // 1 − (1 + 1e-6) cos(s − 3): below zero only for |s − 3| < 1.4e-3.
        let f = cosine(1.0 + 1e-6, 1.0, std::f64::consts::PI - 3.0, 1.0);
        let r = first_root(&f, 6.0).expect("dip found");
        let exact = 3.0 - (1.0 / (1.0 + 1e-6f64)).acos();
        assert!((r - exact).abs() < 1e-10, "{r} vs {exact}");
        // A function that only comes within 1e-9 of zero is not a crossing.
        let g = cosine(1.0, 1.0, std::f64::consts::PI, 1.0 + 1e-9);
        assert_eq!(first_root(&g, 6.0), None);
    }

    #[test]
    fn leaving_a_contact_is_not_a_contact() {
        // sin(s) starts at 0 and increases: first root at π.
        let f = cosine(1.0, 1.0, -std::f64::consts::FRAC_PI_2, 0.0);
        let r = first_root(&f, 5.0).unwrap();
        assert!((r - std::f64::consts::PI).abs() < 1e-12, "{r}");
    }

    /// A damped two-mode motion under forcing, as the steady-response flights give it.
    fn flight_like(k: usize) -> ExpSum {
        let x = k as f64;
        let term = |c: C64, rate: C64| Term {
            poly: [c, C64::default(), C64::default(), C64::default()],
            rate,
        };
        ExpSum {
            terms: vec![
                term(C64::new(0.3 + 0.01 * x, -0.2), C64::new(-0.05, 1.2247)),
                term(C64::new(-0.1, 0.15 + 0.02 * x), C64::new(-0.2, 2.4495)),
                term(C64::new(0.35, 0.1 * x.sin()), C64::new(0.0, 2.0)),
                term(C64::new(0.02 * x.cos(), 0.0), C64::default()),
            ],
        }
    }

    #[test]
    fn exit_times_are_within_the_time_tolerance() {
        let mut checked = 0;
        for k in 0..40 {
            let f = flight_like(k);
            let f0 = f.eval(0.0).0;
            let (lo, hi) = (f0 - 0.6, f0 + 0.3 + 0.005 * k as f64);
            // Reference: the first sample outside the band on a fine grid, bisected.
            let n = 200_000;
            let h = 10.0 / n as f64;
            let Some(j) = (1..=n).find(|&j| {
                let v = f.eval(j as f64 * h).0;
                v >= hi || v <= lo
            }) else {
                continue;
            };
            let (mut a, mut b) = ((j - 1) as f64 * h, j as f64 * h);
            let outside = |s: f64| {
                let v = f.eval(s).0;
                v >= hi || v <= lo
            };
            while b - a > 1e-15 {
                let m = 0.5 * (a + b);
                if outside(m) {
                    b = m;
                } else {
                    a = m;
                }
            }
            for tol in [1e-6, 1e-9, 1e-12] {
                let mut stack = SearchStack::default();
                let (s, _) = f
                    .first_exit(lo, hi, 10.0, tol, 0.0, &mut stack)
                    .expect("an exit");
                assert!(
                    (s - b).abs() <= tol.max(4e-15),
                    "k {k} tol {tol}: {s} vs {b}"
                );
                checked += 1;
                // The exponentials left at the exit are those of the exit time.
                if let Some(e) = stack.exponentials_at(s) {
                    for (t, e) in f.terms.iter().zip(e) {
                        assert!((cexp(t.rate, s) - e).norm() < 1e-13);
                    }
                }
            }
        }
        assert!(checked >= 100, "only {checked} exits checked");
    }

    #[test]
    fn max_abs_is_exact_for_a_sinusoid() {
        let f = cosine(2.0, 3.0, 0.4, 0.0);
        assert!((f.max_abs(5.0, 0.0, 1e-14) - 2.0).abs() < 1e-13);
        // A floor above the maximum is the answer; one below it changes nothing.
        assert_eq!(f.max_abs(5.0, 3.0, 1e-14), 3.0);
        assert!((f.max_abs(5.0, 1.5, 1e-14) - 2.0).abs() < 1e-13);
    }
}
