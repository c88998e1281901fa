//! Real functions of time that are finite sums of (polynomial × complex exponential) terms:
//! the form every coordinate of a linear flow takes between events. Evaluation, a rigorous
//! bound on the second derivative, the *first* root after zero with a guarantee, and extrema.

use nalgebra::Complex;

type C64 = Complex<f64>;

mod amplitude;
mod cache;
mod chunk;
mod derivatives;
#[cfg(target_arch = "x86_64")]
mod packed;
mod polish;
mod scan;
mod search;
mod summary;

pub use amplitude::SharedPoints;
pub use cache::SearchStack;
use cache::{
    chunk_rows, fixed_grid, real_dot, set_exponentials, GridSteps, Seed, Seeds, CACHED_CHUNKS,
    CHUNK_ROWS, PACKED_ROWS, SEED_DIVISIONS,
};
use chunk::{departs, inside, quadratic_exit, quadratic_stays_inside, taylor_clearance, ChunkTest};
use derivatives::Derivatives;
#[cfg(target_arch = "x86_64")]
pub(crate) use packed::{complex_pair, complex_pair_product, products_avx};
use polish::{polish, polish_from, Crossing, Exponentials, PolishStart};
use scan::{CachedChunks, ChunkSource, Chunks, SteppedChunks};
pub use search::Tolerances;
pub(crate) use summary::{summarize_block, ModeTerm, Summary, LANES};

/// The fewest terms whose sums and series the searches form with AVX
/// ([`CachedChunks::packed`], a polish's local sums and series): a unit's three take more
/// time so, though fewer instructions (the packed sums' shuffles and calls outweigh three
/// terms' products); a chain's seventeen gain in both (see the performance page,
/// `docs/performance.md`).
const PACKED_TERMS: usize = 8;

/// Whether the CPU has AVX, for [`CachedChunks::packed`].
#[inline]
fn packed_chunks() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// How far the fixed grid of a search whose fastest rate is at most `fastest` (`|re| + |im|`)
/// keeps its chunks' exponentials ([`CACHED_CHUNKS`] chunks of `2w`, `w = π/(8 fastest)`): a
/// search of constant terms with no growing rate up to this horizon evaluates no exponential
/// afresh after the run's first flights.
pub(crate) fn fixed_grid_reach(fastest: f64) -> f64 {
    CACHED_CHUNKS as f64 * std::f64::consts::PI / (search::CHUNKS_PER_OSCILLATION * fastest) * 2.0
}

/// `e^{μ s}`, skipping the real exponential for purely oscillatory and constant terms, and
/// where it is exactly 1 ([`exp_real`]).
#[inline]
fn cexp(mu: C64, s: f64) -> C64 {
    if mu.im == 0.0 {
        C64::new(exp_real(mu.re * s), 0.0)
    } else {
        let (sin, cos) = crate::trig::sin_cos(mu.im * s);
        let r = if mu.re == 0.0 {
            1.0
        } else {
            exp_real(mu.re * s)
        };
        C64::new(r * cos, r * sin)
    }
}

/// `2⁻⁵⁴`: for `|x|` below it `e^x` lies within `2⁻⁵⁴` of 1, less than half the spacing of
/// the doubles next to 1 (`2⁻⁵³` below, `2⁻⁵²` above), so it rounds to exactly 1 (glibc's
/// `exp` returns `1.0 + x` there, which is 1; so does any correctly rounded `exp`).
const EXP_IS_ONE: f64 = 5.551_115_123_125_783e-17;

/// `e^x`, without the library call where it is exactly 1 (`|x| <` [`EXP_IS_ONE`]): the
/// same value. An undamped flow's rates have real parts of a few `1e-17` (rounding of the
/// eigenvalues), whose exponentials over a flight are mostly that; measured on the
/// `steady_sweep` example (half its runs undamped), half the searches' real exponentials.
#[inline]
fn exp_real(x: f64) -> f64 {
    if x.abs() < EXP_IS_ONE {
        1.0
    } else {
        x.exp()
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

/// The larger of `a` (never NaN) and `b`, `a` for a NaN `b`: [`f64::max`]'s value for such
/// an `a`, as one `maxsd` (`f64::max` adds a NaN fix-up of three dependent instructions,
/// which a running maximum repeats per element): the running maxima of the polish's sums and
/// steps and of a contact's largest position and velocity, the same bits in fewer
/// instructions.
#[inline(always)]
pub(crate) fn larger(a: f64, b: f64) -> f64 {
    if b > a {
        b
    } else {
        a
    }
}

/// `|re| + |im|`: an upper bound on the modulus, without a square root.
#[inline]
fn l1(c: C64) -> f64 {
    c.re.abs() + c.im.abs()
}

/// Interval halvings in [`ExpSum::max_abs`] stop at this fraction of the horizon: a few
/// rounding units of the time, below which the function cannot be resolved.
const MAX_ABS_RESOLUTION: f64 = 1e-15;

/// One term `(c₀ + c₁ s + c₂ s² + c₃ s³) e^{μ s}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    /// Polynomial coefficients, lowest degree first.
    pub poly: [C64; 4],
    /// Complex rate `μ`.
    pub rate: C64,
}

impl Term {
    /// The term's contribution to `f(s)` and `f'(s)` given `e = e^{μ s}` (the sums of
    /// [`ExpSum::eval`] and of the shared bisection of `max_abs_shared`).
    #[inline(always)]
    fn value_at(&self, s: f64, e: C64) -> (f64, f64) {
        let p = self.poly;
        let poly = p[0] + (p[1] + (p[2] + p[3] * s) * s) * s;
        let dpoly = p[1] + (p[2] * 2.0 + p[3] * (3.0 * s)) * s;
        ((poly * e).re, ((dpoly + poly * self.rate) * e).re)
    }
}

/// `f(s) = Re Σ_j term_j(s)`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ExpSum {
    /// The terms.
    pub terms: Vec<Term>,
}

impl ExpSum {
    /// Value and first derivative at `s`.
    #[inline]
    pub fn eval(&self, s: f64) -> (f64, f64) {
        let (mut v, mut d) = (0.0, 0.0);
        for t in &self.terms {
            let (tv, td) = t.value_at(s, cexp(t.rate, s));
            v += tv;
            d += td;
        }
        (v, d)
    }

    /// The same function of `s + by` as a function of `s`: each term's coefficients times
    /// `e^{μ by}` and its polynomial re-expanded about `by`.
    pub fn move_origin(&mut self, by: f64) {
        for t in &mut self.terms {
            let e = cexp(t.rate, by);
            let [c0, c1, c2, c3] = t.poly;
            // p(s + a) = Σ c_k (s + a)^k, by the binomial expansion.
            let shifted = [
                c0 + (c1 + (c2 + c3 * by) * by) * by,
                c1 + (c2 * 2.0 + c3 * (3.0 * by)) * by,
                c2 + c3 * (3.0 * by),
                c3,
            ];
            t.poly = shifted.map(|c| c * e);
        }
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
    ///
    /// A term with a constant polynomial (`+0` higher coefficients) and a rate that does not
    /// grow takes a short path to the same value, `|μ|⁴ |c|` (the general sum's other
    /// products are exact zeros, its growth factor 1).
    pub fn fourth_derivative_bound(&self, horizon: f64) -> f64 {
        self.terms
            .iter()
            .map(|t| {
                let zero_bits = t.poly[1..]
                    .iter()
                    .fold(0, |bits, c| bits | c.re.to_bits() | c.im.to_bits());
                let m = l1(t.rate);
                if zero_bits == 0 && t.rate.re <= 0.0 && horizon.is_finite() && m.is_finite() {
                    let m2 = m * m;
                    return m2 * m2 * l1(t.poly[0]);
                }
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

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

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

    /// A search on a fixed grid recalls its polished exit; a later search of the same key
    /// whose function repeats it (coefficients within `1e-13`) starts its polish there and
    /// finds the exit a fresh search finds, to twice the time tolerance (each search is
    /// within it of the exit); one whose function moved
    /// (`1e-3`) does not start there (its key's polishes without a recalled start count up)
    /// and finds the fresh search's exit too.
    #[test]
    fn a_repeated_flight_starts_its_polish_at_the_recalled_exit() {
        let tolerances = Tolerances {
            time: 1e-12,
            depth: 0.0,
        };
        let scaled = |f: &ExpSum, by: f64| ExpSum {
            terms: f
                .terms
                .iter()
                .map(|t| Term {
                    poly: [t.poly[0] * by, t.poly[1], t.poly[2], t.poly[3]],
                    rate: t.rate,
                })
                .collect(),
        };
        let (mut recalled, mut moved) = (0, 0);
        for k in 0..40 {
            let f = flight_like(k);
            let f0 = f.eval(0.0).0;
            let (lo, hi) = (f0 - 0.6, f0 + 0.3 + 0.005 * k as f64);
            let mut stack = SearchStack {
                recall_key: 3,
                recall: true,
                ..SearchStack::default()
            };
            let first = f.first_exit_until(lo, hi, 10.0, 10.0, tolerances, &mut stack);
            let Some((s1, _)) = first else { continue };
            if stack.exponentials_at(s1).is_none() {
                continue; // not polished: nothing recalled
            }
            for (by, repeats) in [(1.0 + 1e-13, true), (1.0 + 1e-3, false)] {
                let g = scaled(&f, by);
                let fresh =
                    g.first_exit_until(lo, hi, 10.0, 10.0, tolerances, &mut SearchStack::default());
                let mut again = stack.clone();
                let found = g.first_exit_until(lo, hi, 10.0, 10.0, tolerances, &mut again);
                let ((s, side), (e, fresh_side)) =
                    (found.expect("an exit"), fresh.expect("an exit"));
                assert_eq!(side, fresh_side, "k {k}");
                assert!((s - e).abs() <= 2e-12, "k {k} by {by}: {s} vs {e}");
                let misses = again.fixed[0].seeds.misses[3];
                if repeats {
                    assert_eq!(
                        misses, 0,
                        "k {k}: the recalled exit did not start the polish"
                    );
                    recalled += 1;
                } else {
                    assert!(
                        misses > 0,
                        "k {k}: a moved flight started at the recalled exit"
                    );
                    moved += 1;
                }
            }
        }
        assert!(
            recalled >= 10 && moved >= 10,
            "{recalled} recalled, {moved} moved"
        );
    }

    /// Beats: two undamped oscillations at `2` and `2.05` rad/s (amplitude `1` each, the
    /// first of phase `φ = 5 + 0.05k`) and a damped one: the envelope `|1 + e^{i(0.05s − φ)}|`
    /// is `1.6` at `s = 0` and first peaks (`2`) at `s = φ/0.05 = 100 + k`.
    fn beats(k: usize) -> ExpSum {
        let term = |c: C64, rate: C64| Term {
            poly: [c, C64::default(), C64::default(), C64::default()],
            rate,
        };
        ExpSum {
            terms: vec![
                term(
                    C64::from_polar(1.0, 5.0 + 0.05 * k as f64),
                    C64::new(0.0, 2.0),
                ),
                term(C64::new(1.0, 0.0), C64::new(0.0, 2.05)),
                term(C64::new(0.1, -0.05), C64::new(-0.3, 1.3)),
            ],
        }
    }

    #[test]
    fn searches_of_more_chunks_than_cached_find_the_horizon_grids_exits() {
        // A horizon of some 520 chunks of the fixed grid (more than CACHED_CHUNKS = 256, which
        // cover s < 98): the fixed grid's search steps its exponentials (SteppedChunks) and
        // searches its last chunk alone. Against the search on the horizon's grid: the same
        // first exit, to the time tolerance, on the same side, or none in both; cut horizons
        // too. Bands just inside the beats' peak make the exits late.
        let tolerances = Tolerances {
            time: 1e-12,
            depth: 1e-12,
        };
        let horizon = 200.0;
        let cached_end = 256.0 * PI / (4.0 * 2.05);
        let (mut fixed, mut plain) = (SearchStack::default(), SearchStack::default());
        let (mut exits, mut late) = (0, 0);
        for k in 0..20 {
            let f = beats(k);
            for edge in [1.7, 1.9, 1.95, 1.999, 2.2] {
                let (lo, hi) = (-edge - 0.01, edge);
                for cutoff in [horizon, 120.0, 7.0] {
                    let found = f.first_exit_until(lo, hi, horizon, cutoff, tolerances, &mut fixed);
                    let expected = f.first_exit_on_horizon_grid(
                        (lo, hi),
                        horizon,
                        cutoff,
                        tolerances,
                        &mut plain,
                    );
                    let keep = |e: Option<(f64, i8)>| e.filter(|&(s, _)| s <= cutoff);
                    match (keep(expected), keep(found)) {
                        (None, None) => {}
                        (Some((a, sa)), Some((b, sb))) => {
                            assert_eq!(sa, sb, "k {k} edge {edge}: side");
                            assert!((a - b).abs() <= 4e-12, "k {k} edge {edge}: {a} vs {b}");
                            exits += 1;
                            late += usize::from(a > cached_end);
                        }
                        (a, b) => panic!("k {k} edge {edge}: {a:?} vs {b:?}"),
                    }
                }
            }
        }
        assert!(
            exits >= 40 && late >= 20,
            "{exits} exits, {late} past the cached chunks"
        );
    }

    #[test]
    fn the_real_exponential_is_the_librarys_near_zero_too() {
        // Either side of `EXP_IS_ONE`, and the smallest magnitudes, of both signs.
        let mut x = EXP_IS_ONE * 4.0;
        while x > 1e-300 {
            for v in [x, -x, x * 0.999_999, -x * 1.000_001] {
                assert_eq!(exp_real(v).to_bits(), v.exp().to_bits(), "{v:e}");
            }
            x *= 0.7;
        }
        for v in [
            0.0,
            -0.0,
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            1e-3,
            -2.0,
        ] {
            assert_eq!(exp_real(v).to_bits(), v.exp().to_bits(), "{v:e}");
        }
    }

    #[test]
    fn max_abs_is_exact_for_a_sinusoid() {
        let f = cosine(2.0, 3.0, 0.4, 0.0);
        assert!((f.max_abs(5.0, 0.0, 1e-14) - 2.0).abs() < 1e-13);
        // A floor above the maximum is the answer; one below it changes nothing.
        assert_eq!(f.max_abs(5.0, 3.0, 1e-14), 3.0);
        assert!((f.max_abs(5.0, 1.5, 1e-14) - 2.0).abs() < 1e-13);
    }

    #[test]
    fn moving_the_origin_is_the_same_function() {
        // f(s + a) against the moved sum at s, for steady-flight-like sums and one with a full
        // cubic polynomial: the same values to rounding of the terms' sizes.
        for k in 0..10 {
            let mut f = flight_like(k);
            f.terms.push(Term {
                poly: [
                    C64::new(0.2, -0.1),
                    C64::new(0.05 * k as f64, 0.3),
                    C64::new(-0.02, 0.01),
                    C64::new(0.003, -0.004),
                ],
                rate: C64::new(-0.1, 0.7),
            });
            for a in [0.0, 0.37, 2.9] {
                let mut g = f.clone();
                g.move_origin(a);
                for s in [0.0, 0.5, 1.7] {
                    let (expected, slope) = f.eval(s + a);
                    let (value, moved_slope) = g.eval(s);
                    assert!((value - expected).abs() <= 1e-14, "k {k} a {a} s {s}");
                    assert!((moved_slope - slope).abs() <= 1e-14, "k {k} a {a} s {s}");
                }
            }
        }
    }

    #[test]
    fn the_departure_test_clears_only_starts_without_an_exit() {
        // A start on one edge moving away from it, the other edge from near to far: whenever
        // `departs` clears `(0, length]`, the search on the horizon's grid finds no exit
        // there. It must clear most starts whose far edge is out of reach (else the engine's
        // first-chunk shortcut never fires) and none whose far edge is reached.
        let tolerances = Tolerances {
            time: 1e-12,
            depth: 1e-12,
        };
        let mut stack = SearchStack::default();
        let (mut cleared, mut tried) = (0, 0);
        for k in 0..60 {
            let f = flight_like(k);
            let (f0, d0, dd0) = f.eval2(0.0);
            for length in [0.05, 0.16, 0.4] {
                let jerk = f.jerk_bound(length);
                for reach in [0.01, 0.1, 0.5, 2.0] {
                    let band = if d0 > 0.0 {
                        (f0, f0 + reach)
                    } else {
                        (f0 - reach, f0)
                    };
                    tried += 1;
                    if !departs((f0, d0, dd0), jerk, band, tolerances.depth, length) {
                        continue;
                    }
                    cleared += 1;
                    let exit = f
                        .first_exit_on_horizon_grid(band, length, length, tolerances, &mut stack)
                        .filter(|&(s, _)| s <= length);
                    assert_eq!(exit, None, "k {k} length {length} reach {reach}");
                }
            }
        }
        assert!(
            cleared >= tried / 3 && cleared < tried,
            "{cleared} of {tried}"
        );
    }
}
