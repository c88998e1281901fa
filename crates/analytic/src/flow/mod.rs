//! The exact forced flow between impacts, and rigorous extrema of the motion along a flight.
//!
//! The state `x = (u_o, u_i, u̇_o, u̇_i)` is augmented with the forcing's phase states
//! `p = (cos θ, sin θ)`, `θ = ωt + α`. The augmented system `ż = Â z` is linear and autonomous,
//! so the flow over a time `t` is the matrix exponential `exp(Â t)`: exact, and finite at every
//! frequency, including undamped exact resonance where the modal particular solution blows up.

pub mod model_flight;

use crate::unit::Unit;
use nalgebra::{Matrix2, Matrix4, Matrix4x2, Vector2, Vector4, Vector6};

/// Augmented state `z = (x, p)`: mechanical state and forcing phase.
pub type Augmented = Vector6<f64>;
type Matrix6 = nalgebra::Matrix6<f64>;

/// The forced flow of a [`Unit`] at one angular frequency.
#[derive(Debug, Clone)]
pub struct ForcedFlow {
    augmented: Matrix6,
    omega: f64,
    /// Bound on the fastest rate of the flow, `max(ω, |λ(A)|)`: sets the piece length `1/rate`
    /// of the extremum search.
    rate: f64,
    /// The last [`CACHED_TABLES`] Taylor tables of [`Self::extrema`].
    tables: std::cell::RefCell<Vec<Table>>,
}

/// Taylor rows `c (Âh)^k / k!` of some functionals for pieces of length `h`, and the flow over
/// one piece.
#[derive(Debug, Clone)]
struct Table {
    duration: f64,
    functionals: Vec<Augmented>,
    pieces: usize,
    h: f64,
    rows: Vec<[Augmented; TAYLOR_DEGREE + 1]>,
    step: Matrix6,
}

/// The flow over a time `t`, split into its blocks:
/// `x(t) = homogeneous · x(0) + forced · p(0)`, `p(t) = rotation · p(0)`.
#[derive(Debug, Clone, Copy)]
pub struct Transition {
    /// `E(t)`, the top-left 4×4 block: the free (unforced) flow, also the variational flow.
    pub homogeneous: Matrix4<f64>,
    /// `F(t)`, the top-right 4×2 block: the response to the initial forcing phase.
    pub forced: Matrix4x2<f64>,
    /// `R(ωt)`, the rotation of the forcing phase.
    pub rotation: Matrix2<f64>,
}

impl Transition {
    /// Applies the flow: `(x, p) ↦ (E x + F p, R p)`.
    pub fn apply(&self, x: &Vector4<f64>, p: &Vector2<f64>) -> (Vector4<f64>, Vector2<f64>) {
        (self.homogeneous * x + self.forced * p, self.rotation * p)
    }
}

/// Maximum and minimum of a scalar function of the state along a flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Extrema {
    /// Largest value over the closed interval.
    pub max: f64,
    /// Time (from the flight's start) at which `max` is attained.
    pub argmax: f64,
    /// Smallest value over the closed interval.
    pub min: f64,
    /// Time (from the flight's start) at which `min` is attained.
    pub argmin: f64,
}

impl Extrema {
    /// The extrema of a single value `v` at the flight's start: where a search over the
    /// flight begins.
    pub(crate) fn at_start(v: f64) -> Self {
        Self {
            max: v,
            argmax: 0.0,
            min: v,
            argmin: 0.0,
        }
    }
}

/// Degree of the Taylor polynomial of the flow on one piece. Pieces start no longer than
/// `1/rate`, so `‖Âh‖` is of order one and the last term is of order `1/24! ≈ 1.6e-24`: the
/// tail test (`TAIL_TOLERANCE = 1e-18`) has six orders of margin for matrices whose norm exceeds
/// their spectral radius before a piece must be halved.
pub(crate) const TAYLOR_DEGREE: usize = 24;

/// A piece is accepted when its last two Taylor rows are below this fraction of `|c|₁`: two
/// orders below the double-precision unit roundoff `ε/2 ≈ 1.1e-16`, so the truncated
/// polynomial *is* the flow to machine precision.
pub(crate) const TAIL_TOLERANCE: f64 = 1e-18;

/// Cap on the number of pieces of one flight: pieces are doubled until the tail passes, and a
/// non-finite augmented matrix (NaN tail) never passes. `2²⁴ ≈ 1.7e7` pieces bound the work
/// of a pathological flight; a finite flight needs about `duration × rate` pieces (a few
/// hundred at the lowest frequencies swept).
pub(crate) const MAX_PIECES: usize = 1 << 24;

/// How many Taylor tables a [`ForcedFlow`] keeps: the branches of a symmetric orbit share
/// one flight duration, the two flights of an asymmetric orbit need two.
const CACHED_TABLES: usize = 2;

/// A polynomial coefficient below this fraction of `Σ|q_k|` is dropped: it changes no value
/// on `[0, 1]` by more than `1e-18` of the polynomial's size, the same truncation level as
/// `TAIL_TOLERANCE = 1e-18` and below rounding.
const NEGLIGIBLE_COEFFICIENT: f64 = 1e-18;

/// Value resolution of the extremum search, relative to `Σ|q_k|`: an interval whose value
/// bound cannot beat the extrema found so far by more than this is dropped. About five unit
/// roundoffs of the largest term: below it, Horner's evaluation cannot tell values apart.
const VALUE_RESOLUTION: f64 = 1e-15;

/// Smallest half-width (in the piece's unit time `s ∈ [0, 1]`) of an exclusion interval,
/// reached after about 43 halvings. An interval this narrow is settled by its midpoint: near a
/// critical point the value differs from the extremum by `½ max|q''| w² = 5e-27 max|q''|`.
const MIN_HALF_WIDTH: f64 = 1e-13;

/// Depth of the stack of pending exclusion intervals. The search is depth-first and halves
/// the interval at each level, so at most one interval per level is pending; [`MIN_HALF_WIDTH`]
/// stops it by level ~43, well inside 128 (the guard on the stack's length never binds).
const EXCLUSION_STACK: usize = 128;

/// Cap on the safeguarded Newton iterations for a critical point: bisection alone reduces
/// `[0, 1]` to one ulp in 53 steps, so 100 is never reached by a converging iteration.
const CRITICAL_POINT_ITERATIONS: usize = 100;

/// Newton on `q'` stops when a step is below this fraction of `1 + |s|`: under one ulp of
/// `s ∈ [0, 1]` (`ε ≈ 2.2e-16`), where further steps no longer move `s`.
const CRITICAL_POINT_STEP: f64 = 1e-16;

impl ForcedFlow {
    /// The flow of `unit` under base motion at angular frequency `omega` (> 0).
    pub fn new(unit: &Unit, omega: f64) -> Self {
        let augmented = unit.augmented_matrix(omega);
        // |λ|² ≤ ‖M⁻¹K‖ + |λ| ‖M⁻¹C‖ for every eigenvalue of the quadratic pencil.
        let row_norm = |col: usize| {
            (2..4)
                .map(|i| augmented[(i, col)].abs() + augmented[(i, col + 1)].abs())
                .fold(0.0, f64::max)
        };
        let (k, c) = (row_norm(0), row_norm(2));
        let natural = 0.5 * (c + (c * c + 4.0 * k).sqrt());
        Self {
            augmented,
            omega,
            rate: natural.max(omega),
            tables: std::cell::RefCell::new(Vec::with_capacity(CACHED_TABLES)),
        }
    }

    /// Angular frequency of the forcing.
    pub(crate) fn omega(&self) -> f64 {
        self.omega
    }

    /// Forcing period `T = 2π/ω`.
    pub fn period(&self) -> f64 {
        std::f64::consts::TAU / self.omega
    }

    /// The augmented matrix `Â`.
    pub(crate) fn augmented_matrix(&self) -> &Matrix6 {
        &self.augmented
    }

    /// The flow over time `t`: `exp(Â t)`, split into blocks.
    pub fn transition(&self, t: f64) -> Transition {
        split(&(self.augmented * t).exp())
    }

    /// The time derivative of the flow over time `t`: `Â exp(Â t)`, split into blocks.
    pub(crate) fn transition_rate(&self, t: f64) -> Transition {
        split(&(self.augmented * (self.augmented * t).exp()))
    }

    /// The vector field `ẋ = A x + b(p)` of the mechanical state.
    pub fn vector_field(&self, x: &Vector4<f64>, p: &Vector2<f64>) -> Vector4<f64> {
        let z = self.augmented * join(x, p);
        Vector4::new(z[0], z[1], z[2], z[3])
    }

    /// Extrema of the linear functionals `c · z(t)` over `t ∈ [0, duration]`, starting from the
    /// augmented state `start`.
    ///
    /// The flight is cut into equal pieces no longer than `1/max(ω, |λ|)`, halved until the
    /// last two rows `c (Âh)^k / k!` of the degree-24 Taylor expansion are below `1e-18` of
    /// `|c|₁`: on each piece the functional *is* a polynomial to machine precision, its
    /// coefficients one dot product each with the piece's starting state. Its extrema are
    /// found among the piece's ends and the roots of its derivative, isolated by exclusion tests with bounds on the second and third derivatives
    /// and polished by safeguarded Newton. No extremum can fall between samples.
    pub(crate) fn extrema(
        &self,
        start: &Augmented,
        duration: f64,
        functionals: &[Augmented],
    ) -> Vec<Extrema> {
        self.mixed_extrema(
            start,
            duration,
            functionals,
            &vec![false; functionals.len()],
        )
    }

    /// Extrema of the linear functionals `c · z(t)` over the *interior critical points* of the
    /// flight only: the times `0 < t < duration` where `d(c · z)/dt = 0`, found with the same
    /// guarantee as the extrema of a whole flight (exact Taylor pieces and exclusion tests: no
    /// critical point can fall between samples). The flight's ends are not candidates, so a
    /// functional that is monotone along the whole flight has `max = −∞`, `min = +∞` (and
    /// `NaN` times).
    ///
    /// This is what decides grazing: between two impacts `r(t)` touches a stop from inside at
    /// an interior critical point, while at the flight's ends it sits on the stops anyway.
    pub fn critical_extrema(
        &self,
        start: &Augmented,
        duration: f64,
        functionals: &[Augmented],
    ) -> Vec<Extrema> {
        self.mixed_extrema(start, duration, functionals, &vec![true; functionals.len()])
    }

    /// [`Self::extrema`] for the functionals whose `critical` flag is false and
    /// [`Self::critical_extrema`] for the others, in one pass over the flight (one Taylor
    /// table). `critical` has one flag per functional (missing flags count as false).
    pub(crate) fn mixed_extrema(
        &self,
        start: &Augmented,
        duration: f64,
        functionals: &[Augmented],
        critical: &[bool],
    ) -> Vec<Extrema> {
        let mut found: Vec<Extrema> = functionals
            .iter()
            .enumerate()
            .map(|(i, c)| {
                if critical.get(i).copied().unwrap_or(false) {
                    Extrema {
                        max: f64::NEG_INFINITY,
                        argmax: f64::NAN,
                        min: f64::INFINITY,
                        argmin: f64::NAN,
                    }
                } else {
                    Extrema::at_start(c.dot(start))
                }
            })
            .collect();
        if duration <= 0.0 || functionals.is_empty() {
            return found;
        }
        let mut cache = self.tables.borrow_mut();
        let hit = cache
            .iter()
            .position(|t| t.duration == duration && t.functionals.as_slice() == functionals);
        let index = match hit {
            Some(i) => i,
            None => {
                if cache.len() == CACHED_TABLES {
                    cache.remove(0);
                }
                cache.push(self.table(duration, functionals));
                cache.len() - 1
            }
        };
        let table = &cache[index];
        let (h, rows, step) = (table.h, &table.rows, &table.step);
        let pieces = table.pieces;
        let mut z = *start;
        let mut poly = [0.0; TAYLOR_DEGREE + 1];
        for piece in 0..pieces {
            let t0 = piece as f64 * h;
            for (i, (row, ext)) in rows.iter().zip(found.iter_mut()).enumerate() {
                for (pk, rk) in poly.iter_mut().zip(row.iter()) {
                    *pk = rk.dot(&z);
                }
                let critical_only = critical.get(i).copied().unwrap_or(false);
                polynomial_extrema(&poly, ext, t0, h, critical_only);
            }
            z = step * z;
        }
        found
    }
}

impl ForcedFlow {
    /// Equal pieces no longer than `1/rate`; the rows `c (Âh)^k / k!` of each functional are
    /// computed once, and the pieces halved until their tail is below `TAIL_TOLERANCE = 1e-18`.
    fn table(&self, duration: f64, functionals: &[Augmented]) -> Table {
        let mut pieces = (duration * self.rate).ceil().max(1.0) as usize;
        let mut rows = vec![[Augmented::zeros(); TAYLOR_DEGREE + 1]; functionals.len()];
        let h = loop {
            let h = duration / pieces as f64;
            let step_t = (self.augmented * h).transpose();
            let mut tail: f64 = 0.0;
            for (c, row) in functionals.iter().zip(rows.iter_mut()) {
                row[0] = *c;
                for k in 1..=TAYLOR_DEGREE {
                    row[k] = step_t * row[k - 1] / k as f64;
                }
                let size = c.lp_norm(1).max(f64::MIN_POSITIVE);
                tail = tail.max(
                    (row[TAYLOR_DEGREE].lp_norm(1) + row[TAYLOR_DEGREE - 1].lp_norm(1)) / size,
                );
            }
            if tail <= TAIL_TOLERANCE || pieces >= MAX_PIECES {
                break h;
            }
            pieces *= 2;
        };
        Table {
            duration,
            functionals: functionals.to_vec(),
            pieces,
            h,
            rows,
            step: (self.augmented * h).exp(),
        }
    }
}

/// Joins a mechanical state and a forcing phase into the augmented state.
pub fn join(x: &Vector4<f64>, p: &Vector2<f64>) -> Augmented {
    Augmented::new(x[0], x[1], x[2], x[3], p[0], p[1])
}

fn split(m: &Matrix6) -> Transition {
    Transition {
        homogeneous: m.fixed_view::<4, 4>(0, 0).into_owned(),
        forced: m.fixed_view::<4, 2>(0, 4).into_owned(),
        rotation: m.fixed_view::<2, 2>(4, 4).into_owned(),
    }
}

/// Value, first and second derivative of `Σ q_k s^k` (Horner).
fn horner(q: &[f64], s: f64) -> (f64, f64, f64) {
    let (mut v, mut d1, mut d2) = (0.0, 0.0, 0.0);
    for &c in q.iter().rev() {
        d2 = d2 * s + 2.0 * d1;
        d1 = d1 * s + v;
        v = v * s + c;
    }
    (v, d1, d2)
}

/// Updates `ext` with the extrema of `q(s) = Σ q_k s^k` on `s ∈ [0, 1]`, which is the
/// functional on `t ∈ [t0, t0 + h]`.
///
/// Candidates are `s = 0, 1` and the roots of `q'`. An interval `[m − w, m + w]` holds no root
/// of `q'` when `|q'(m)| > w · max|q''|`, and at most one when `|q''(m)| > w · max|q'''|`
/// (then a sign change brackets it and safeguarded Newton polishes it); intervals whose value
/// bound cannot beat the extrema found so far are dropped.
///
/// With `critical_only`, the piece's ends are not candidates: only roots of `q'`.
pub(crate) fn polynomial_extrema(
    q: &[f64],
    ext: &mut Extrema,
    t0: f64,
    h: f64,
    critical_only: bool,
) {
    let update = |ext: &mut Extrema, s: f64, v: f64| {
        if v > ext.max {
            ext.max = v;
            ext.argmax = t0 + s * h;
        }
        if v < ext.min {
            ext.min = v;
            ext.argmin = t0 + s * h;
        }
    };
    let size: f64 = q.iter().map(|c| c.abs()).sum();
    // Coefficients below rounding of the largest term do not change any value: drop them.
    let degree = q
        .iter()
        .rposition(|c| c.abs() > NEGLIGIBLE_COEFFICIENT * size)
        .unwrap_or(0);
    let q = &q[..=degree];
    let tol = VALUE_RESOLUTION * size;
    // The whole piece lies within q(0) ± Σ_{k≥1} |q_k|: skip it if that cannot beat the
    // extrema found so far.
    let spread = size - q[0].abs();
    if q[0] + spread <= ext.max + tol && q[0] - spread >= ext.min - tol {
        return;
    }
    if !critical_only {
        update(ext, 0.0, q[0]);
        update(ext, 1.0, horner(q, 1.0).0);
    }
    let (mut m2, mut m3) = (0.0, 0.0);
    for (k, c) in q.iter().enumerate() {
        let k = k as f64;
        m2 += k * (k - 1.0) * c.abs();
        m3 += k * (k - 1.0) * (k - 2.0) * c.abs();
    }
    let mut stack = [(0.0f64, 1.0f64); EXCLUSION_STACK];
    let mut top = 1;
    while top > 0 {
        top -= 1;
        let (a, b) = stack[top];
        let (m, w) = (0.5 * (a + b), 0.5 * (b - a));
        let (v, d1, d2) = horner(q, m);
        let reach = d1.abs() * w + 0.5 * m2 * w * w;
        let cannot_improve = v + reach <= ext.max + tol && v - reach >= ext.min - tol;
        if cannot_improve || d1.abs() > m2 * w {
            continue;
        }
        if d2.abs() > m3 * w || w < MIN_HALF_WIDTH || top + 2 > stack.len() {
            // At most one critical point (or the interval is as small as it gets): polish it
            // if q' changes sign.
            let (da, db) = (horner(q, a).1, horner(q, b).1);
            if da.signum() != db.signum() {
                let s = critical_point(q, a, b, da);
                update(ext, s, horner(q, s).0);
            } else if w < MIN_HALF_WIDTH {
                update(ext, m, v);
            }
            continue;
        }
        stack[top] = (a, m);
        stack[top + 1] = (m, b);
        top += 2;
    }
}

/// The root of `q'` in `[a, b]`, where `q'(a) = da` and `q'(b)` have opposite signs:
/// Newton on `q'`, falling back to bisection whenever a step leaves the bracket.
fn critical_point(q: &[f64], mut a: f64, mut b: f64, da: f64) -> f64 {
    let mut s = 0.5 * (a + b);
    for _ in 0..CRITICAL_POINT_ITERATIONS {
        let (_, d1, d2) = horner(q, s);
        if d1 == 0.0 {
            return s;
        }
        if d1.signum() == da.signum() {
            a = s;
        } else {
            b = s;
        }
        let newton = s - d1 / d2;
        let next = if newton > a && newton < b {
            newton
        } else {
            0.5 * (a + b)
        };
        if (next - s).abs() <= CRITICAL_POINT_STEP * (1.0 + s.abs()) {
            return next;
        }
        s = next;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomial_extrema_find_interior_peaks() {
        // q(s) = −(s − 0.3)² + 1e-3 (s − 0.3)^4 on [0, 1]: peak 0 at 0.3; minimum at s = 1.
        let q = [
            -0.09 + 1e-3 * 0.0081,
            0.6 - 4e-3 * 0.027,
            -1.0 + 6e-3 * 0.09,
            -4e-3 * 0.3,
            1e-3,
        ];
        let mut e = Extrema {
            max: f64::NEG_INFINITY,
            argmax: 0.0,
            min: f64::INFINITY,
            argmin: 0.0,
        };
        polynomial_extrema(&q, &mut e, 10.0, 2.0, false);
        assert!(e.max.abs() < 1e-15, "max {}", e.max);
        assert!((e.argmax - 10.6).abs() < 1e-9, "at {}", e.argmax);
        assert!((e.min - (-0.49 + 1e-3 * 0.7f64.powi(4))).abs() < 1e-15);
        assert_eq!(e.argmin, 12.0);
    }

    #[test]
    fn extrema_of_a_pure_oscillation_are_exact() {
        // c·z = cos θ(t) has max 1 and min −1 over a full period.
        let unit = crate::test_models::paper_unit();
        let flow = ForcedFlow::new(&unit, 0.7);
        let start = join(&Vector4::zeros(), &Vector2::new(0.3f64.cos(), 0.3f64.sin()));
        let c = Augmented::new(0.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        let e = flow.extrema(&start, flow.period(), &[c])[0];
        assert!(
            (e.max - 1.0).abs() < 1e-14 && (e.min + 1.0).abs() < 1e-14,
            "{e:?}"
        );
        // cos(0.3 + 0.7 t) = 1 at t = (2π − 0.3)/0.7.
        assert!((e.argmax - (std::f64::consts::TAU - 0.3) / 0.7).abs() < 1e-6);
    }

    #[test]
    fn extrema_match_a_dense_scan_of_the_exact_flow() {
        // Damped and undamped flights from an arbitrary state: the rigorous maximum is never
        // below any sampled value, and a fine scan comes within its resolution of it.
        for unit in [
            crate::test_models::paper_unit(),
            crate::test_models::damped_paper_unit(),
        ] {
            let flow = ForcedFlow::new(&unit, 1.3);
            let start = join(&Vector4::new(0.2, -0.4, 1.1, -0.7), &Vector2::new(0.6, 0.8));
            let c = Augmented::new(-1.0, 1.0, 0.0, 0.0, 0.0, 0.0);
            let duration = 7.0;
            let e = flow.extrema(&start, duration, &[c])[0];
            let n = 20000;
            let (mut smax, mut smin) = (f64::NEG_INFINITY, f64::INFINITY);
            for k in 0..=n {
                let t = duration * k as f64 / n as f64;
                let (x, _) = flow.transition(t).apply(
                    &start.fixed_rows::<4>(0).into(),
                    &start.fixed_rows::<2>(4).into(),
                );
                let v = x[1] - x[0];
                smax = smax.max(v);
                smin = smin.min(v);
            }
            assert!(
                e.max >= smax - 1e-13 && e.max - smax < 1e-6,
                "{e:?} vs {smax}"
            );
            assert!(
                e.min <= smin + 1e-13 && smin - e.min < 1e-6,
                "{e:?} vs {smin}"
            );
        }
    }
}
