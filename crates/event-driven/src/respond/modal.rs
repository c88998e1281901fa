//! The exact flight of `M ü + C u̇ + K u = d s(t) + v ṡ(t)` over one piece of one segment,
//! in modal coordinates, each a finite sum of (polynomial × exponential) terms.
//!
//! The elastic modes `z_k = (V⁻¹ y)_k` obey `ż_k = λ_k z_k + g_k(σ)` in the flight's own time
//! `σ` (from its start `t₀`), with the modal forcing `g = V⁻¹ (0, M⁻¹ f)`:
//!
//! - affine: `f(t₀ + σ) = f₀ + f₁ σ` adds `g₀ φ(λ, 0, σ) + g₁ φ₁(λ, σ)`;
//! - a sinusoid of frequency `ν`: `f = Re(F e^{iνσ})` adds `G⁺ φ(λ, iν, σ) + G⁻ φ(λ, −iν, σ)`,
//!   `G^± = ½ V⁻¹ (0, M⁻¹ F)` and its conjugate forcing's,
//!
//! with `φ(λ, μ, σ) = ∫₀^σ e^{λ(σ−x)} e^{μx} dx` and `φ₁(λ, σ) = ∫₀^σ e^{λ(σ−x)} x dx =
//! (e^{λσ} − 1 − λσ)/λ²`. Both are written resonance-safe, as the periodic flow writes `φ`
//! ([`crate::flow`]): where `|μ − λ| h` (`h` the flight's horizon) is at most
//! [`RESONANCE`], `φ` is `e^{λσ}(σ + δσ²/2 + δ²σ³/6)` (`δ = μ − λ`, relative error at most
//! `(δh)³/24 ≤ 4·10⁻¹⁴`), the secular response at exact resonance; where `|λ| h` is at most
//! [`LINEAR_RESONANCE`], `φ₁` is `e^{λσ}(σ²/2 − λσ³/3)` (relative error at most
//! `(λh)²/4 ≤ 10⁻⁸` of `φ₁`, exact at `λ = 0`; the closed form there would lose
//! `ε/(λh)²` of `φ₁` to cancellation, as much at that bound, far more below it).
//!
//! The rigid modes (free bodies: `K R = C R = 0`) move as `q̈ = a(σ)`, `a = X_p (0, M⁻¹ f)`:
//! affine forcing gives the cubic `q = q₀ + p₀σ + a₀σ²/2 + a₁σ³/6`, exact; a sinusoid
//! `Re(B e^{iνσ})` adds `Re(B φ₁(iν, σ))` (`φ₁(μ, σ)` is the double integral of `e^{μx}`:
//! at `ν = 0` the constant's `σ²/2`, resonance-safe as above), and `p = q̇` term by term.
//!
//! Every coordinate, and so every linear functional of the state, is then a sum of terms
//! `(c₀ + c₁σ + c₂σ² + c₃σ³) e^{μσ}` ([`ExpSum`]), which the event search brackets with its
//! guarantee; states are evaluated from the same terms, so the search and the states agree.

use super::signal::{Shape, Signal};
use crate::expsum::{ExpSum, Term};
use crate::flow::{FlowError, LinearFlow};
use crate::model::Model;
use nalgebra::{Complex, DMatrix, DVector};

type C64 = Complex<f64>;

/// Below this `|μ − λ| h` the particular solution `φ(λ, μ, σ)` is written in its secular
/// (series) form: the periodic flow's threshold, with the flight's horizon for its period.
pub(crate) const RESONANCE: f64 = 1e-4;

/// Below this `|λ| h` the linear forcing's `φ₁(λ, σ)` is written as a series: where the
/// series' truncation `(λh)²/4` meets the closed form's cancellation `ε/(λh)²`
/// (`(4ε)^{1/4} ≈ 1.2·10⁻⁴`), rounded up.
pub(crate) const LINEAR_RESONANCE: f64 = 2e-4;

/// `e^{μσ}` with the crate's own sine and cosine.
#[inline]
pub(crate) fn cexp(mu: C64, s: f64) -> C64 {
    let r = if mu.re == 0.0 { 1.0 } else { (mu.re * s).exp() };
    if mu.im == 0.0 {
        return C64::new(r, 0.0);
    }
    let (sin, cos) = crate::trig::sin_cos(mu.im * s);
    C64::new(r * cos, r * sin)
}

/// A term `scale · poly · e^{rate σ}`.
fn term(rate: C64, poly: [C64; 4]) -> Term {
    Term { poly, rate }
}

const ZERO: C64 = C64::new(0.0, 0.0);

/// `scale · φ(λ, μ, σ)` as terms, resonance-safe over a horizon `h`.
fn phi(lambda: C64, mu: C64, h: f64, scale: C64, out: &mut Vec<Term>) {
    if scale == ZERO {
        return;
    }
    let delta = mu - lambda;
    if (delta.re.abs() + delta.im.abs()) * h <= RESONANCE {
        out.push(term(
            lambda,
            [
                ZERO,
                scale,
                scale * delta / 2.0,
                scale * delta * delta / 6.0,
            ],
        ));
    } else {
        let c = scale / delta;
        out.push(term(mu, [c, ZERO, ZERO, ZERO]));
        out.push(term(lambda, [-c, ZERO, ZERO, ZERO]));
    }
}

/// `scale · φ₁(λ, σ) = scale ∫₀^σ e^{λ(σ−x)} x dx` as terms, resonance-safe over `h`.
fn phi1(lambda: C64, h: f64, scale: C64, out: &mut Vec<Term>) {
    if scale == ZERO {
        return;
    }
    if lambda == ZERO {
        out.push(term(ZERO, [ZERO, ZERO, scale * 0.5, ZERO]));
    } else if (lambda.re.abs() + lambda.im.abs()) * h <= LINEAR_RESONANCE {
        out.push(term(
            lambda,
            [ZERO, ZERO, scale * 0.5, -scale * lambda / 3.0],
        ));
    } else {
        let l2 = lambda * lambda;
        out.push(term(lambda, [scale / l2, ZERO, ZERO, ZERO]));
        out.push(term(ZERO, [-scale / l2, -scale / lambda, ZERO, ZERO]));
    }
}

/// The derivative in `σ` of a sum of terms, as terms.
fn derivative(terms: &[Term]) -> Vec<Term> {
    terms
        .iter()
        .map(|t| {
            let p = t.poly;
            let mu = t.rate;
            term(
                mu,
                [
                    p[1] + p[0] * mu,
                    p[2] * 2.0 + p[1] * mu,
                    p[3] * 3.0 + p[2] * mu,
                    p[3] * mu,
                ],
            )
        })
        .collect()
}

/// `Σ poly(σ) e^{μσ}` (complex).
fn evaluate(terms: &[Term], s: f64) -> C64 {
    terms
        .iter()
        .map(|t| {
            let p = t.poly;
            (p[0] + (p[1] + (p[2] + p[3] * s) * s) * s) * cexp(t.rate, s)
        })
        .sum()
}

/// The modal forcing of one force vector: on the elastic coordinates (`V⁻¹ (0, M⁻¹ f)`) and
/// the rigid accelerations (`X_p (0, M⁻¹ f)`).
#[derive(Debug, Clone)]
pub(crate) struct ModalForce {
    elastic: Vec<C64>,
    rigid: Vec<f64>,
}

/// The rigid modes' part of the basis.
#[derive(Debug, Clone)]
struct Rigid {
    /// `R` (`n × r`).
    shapes: DMatrix<f64>,
    /// `X_q` (`r × 2n`).
    position_rows: DMatrix<f64>,
    /// `X_p` (`r × 2n`).
    velocity_rows: DMatrix<f64>,
}

/// The modal basis of a model's matrices (its own forcing aside).
#[derive(Debug, Clone)]
pub(crate) struct Basis {
    n: usize,
    rates: Vec<C64>,
    modes: DMatrix<C64>,
    inverse: DMatrix<C64>,
    rigid: Option<Rigid>,
    minv: DMatrix<f64>,
}

/// A linear functional `c · y` in modal form: `Re Σ_k w_k z_k + Σ_j (a_j q_j + b_j p_j)`.
#[derive(Debug, Clone)]
pub(crate) struct Functional {
    elastic: Vec<C64>,
    positions: Vec<f64>,
    velocities: Vec<f64>,
}

/// The forcing of one flight in its own time `σ`, modally: a constant, a linear part and
/// sinusoids (`rate ν > 0`, elastic `G^±` with the `½`, rigid `B`).
#[derive(Debug, Clone, Default)]
pub(crate) struct FlightForcing {
    constant: Option<ModalForce>,
    linear: Option<ModalForce>,
    waves: Vec<Wave>,
}

#[derive(Debug, Clone)]
struct Wave {
    rate: f64,
    plus: Vec<C64>,
    minus: Vec<C64>,
    rigid: Vec<C64>,
}

/// One flight: per elastic mode `z_k(σ)`, per rigid mode `q_j(σ)` and `p_j(σ)`, as terms.
#[derive(Debug, Clone)]
pub(crate) struct Flight {
    elastic: Vec<Vec<Term>>,
    positions: Vec<Vec<Term>>,
    velocities: Vec<Vec<Term>>,
}

impl FlightForcing {
    /// The forcing with the constant modal force `extra` added (the held stops' share in a
    /// constrained flow).
    pub(crate) fn with_constant(mut self, extra: &ModalForce) -> FlightForcing {
        self.constant = Some(match self.constant.take() {
            None => extra.clone(),
            Some(c) => ModalForce {
                elastic: c
                    .elastic
                    .iter()
                    .zip(&extra.elastic)
                    .map(|(a, b)| a + b)
                    .collect(),
                rigid: c
                    .rigid
                    .iter()
                    .zip(&extra.rigid)
                    .map(|(a, b)| a + b)
                    .collect(),
            },
        });
        self
    }
}

impl Basis {
    /// The basis of the matrices `(M, C, K)` (`C` `None`: no damping terms), of any size
    /// (none: a structure held on its stops in every direction has no coordinates left).
    ///
    /// # Errors
    /// As [`LinearFlow::new`] when the modal flow does not exist.
    pub(crate) fn new(
        mass: &DMatrix<f64>,
        damping: Option<&DMatrix<f64>>,
        stiffness: &DMatrix<f64>,
    ) -> Result<Basis, FlowError> {
        let n = mass.nrows();
        let zero = DVector::zeros(n);
        let flow = LinearFlow::new(mass, damping, stiffness, &zero, &zero, &zero, 1.0)?;
        let b = flow.basis();
        let minv = mass.clone().try_inverse().ok_or(FlowError::SingularMass)?;
        Ok(Basis {
            n,
            rates: b.rates.to_vec(),
            modes: b.modes.clone(),
            inverse: b.inverse.clone(),
            rigid: b.rigid.map(|(shapes, position_rows, velocity_rows)| Rigid {
                shapes: shapes.clone(),
                position_rows: position_rows.clone(),
                velocity_rows: velocity_rows.clone(),
            }),
            minv,
        })
    }

    /// The basis of `model`'s mass, damping and stiffness.
    ///
    /// # Errors
    /// As [`Self::new`].
    pub(crate) fn of_model(model: &Model) -> Result<Basis, FlowError> {
        Basis::new(&model.mass, model.damping.as_ref(), &model.stiffness)
    }

    /// The fastest elastic rate `max |λ_k|` (`0` for none).
    pub(crate) fn fastest_rate(&self) -> f64 {
        self.rates.iter().map(|l| l.norm()).fold(0.0, f64::max)
    }

    /// Rigid modes `r`.
    fn rigid_count(&self) -> usize {
        self.rigid.as_ref().map_or(0, |r| r.shapes.ncols())
    }

    /// The modal forcing of the force vector `f` (length `n`).
    pub(crate) fn force(&self, f: &DVector<f64>) -> ModalForce {
        let n = self.n;
        let a = &self.minv * f;
        let elastic = (0..self.rates.len())
            .map(|k| (0..n).map(|i| self.inverse[(k, n + i)] * a[i]).sum())
            .collect();
        let rigid = match &self.rigid {
            Some(r) => (0..r.shapes.ncols())
                .map(|j| (0..n).map(|i| r.velocity_rows[(j, n + i)] * a[i]).sum())
                .collect(),
            None => Vec::new(),
        };
        ModalForce { elastic, rigid }
    }

    /// The functional `c · y` (`c` of length `2n`) in modal form.
    pub(crate) fn functional(&self, c: &DVector<f64>) -> Functional {
        let n = self.n;
        let elastic = (0..self.rates.len())
            .map(|k| (0..2 * n).map(|i| self.modes[(i, k)] * c[i]).sum())
            .collect();
        let (positions, velocities) = match &self.rigid {
            Some(r) => (
                (0..r.shapes.ncols())
                    .map(|j| (0..n).map(|i| r.shapes[(i, j)] * c[i]).sum())
                    .collect(),
                (0..r.shapes.ncols())
                    .map(|j| (0..n).map(|i| r.shapes[(i, j)] * c[n + i]).sum())
                    .collect(),
            ),
            None => (Vec::new(), Vec::new()),
        };
        Functional {
            elastic,
            positions,
            velocities,
        }
    }

    /// The flight from state `y` under `forcing`, its particular solutions resonance-safe
    /// over the horizon `h`.
    pub(crate) fn flight(&self, y: &DVector<f64>, forcing: &FlightForcing, h: f64) -> Flight {
        let n = self.n;
        let elastic = self
            .rates
            .iter()
            .enumerate()
            .map(|(k, &lambda)| {
                let z0: C64 = (0..2 * n).map(|i| self.inverse[(k, i)] * y[i]).sum();
                let mut terms = vec![term(lambda, [z0, ZERO, ZERO, ZERO])];
                if let Some(c) = &forcing.constant {
                    phi(lambda, ZERO, h, c.elastic[k], &mut terms);
                }
                if let Some(l) = &forcing.linear {
                    phi1(lambda, h, l.elastic[k], &mut terms);
                }
                for w in &forcing.waves {
                    let mu = C64::new(0.0, w.rate);
                    phi(lambda, mu, h, w.plus[k], &mut terms);
                    phi(lambda, -mu, h, w.minus[k], &mut terms);
                }
                merge(terms)
            })
            .collect();
        let (mut positions, mut velocities) = (Vec::new(), Vec::new());
        if let Some(r) = &self.rigid {
            for j in 0..r.shapes.ncols() {
                let q0 = r.position_rows.row(j).dot(&y.transpose());
                let p0 = r.velocity_rows.row(j).dot(&y.transpose());
                let a0 = forcing.constant.as_ref().map_or(0.0, |c| c.rigid[j]);
                let a1 = forcing.linear.as_ref().map_or(0.0, |l| l.rigid[j]);
                let re = |v: f64| C64::new(v, 0.0);
                let mut terms = vec![term(ZERO, [re(q0), re(p0), re(0.5 * a0), re(a1 / 6.0)])];
                for w in &forcing.waves {
                    phi1(C64::new(0.0, w.rate), h, w.rigid[j], &mut terms);
                }
                let terms = merge(terms);
                velocities.push(derivative(&terms));
                positions.push(terms);
            }
        }
        Flight {
            elastic,
            positions,
            velocities,
        }
    }

    /// The state `y(σ)` of `flight` into `y` (length `2n`).
    pub(crate) fn state_into(&self, flight: &Flight, s: f64, y: &mut DVector<f64>) {
        let m = 2 * self.n;
        y.fill(0.0);
        for (k, terms) in flight.elastic.iter().enumerate() {
            let z = evaluate(terms, s);
            for i in 0..m {
                y[i] += (self.modes[(i, k)] * z).re;
            }
        }
        if let Some(r) = &self.rigid {
            let n = self.n;
            for j in 0..r.shapes.ncols() {
                let q = evaluate(&flight.positions[j], s).re;
                let p = evaluate(&flight.velocities[j], s).re;
                for i in 0..n {
                    y[i] += r.shapes[(i, j)] * q;
                    y[n + i] += r.shapes[(i, j)] * p;
                }
            }
        }
    }

    /// The functional `c` of `flight` as a sum of terms in `σ`, written into `out`.
    pub(crate) fn expand(&self, flight: &Flight, c: &Functional, out: &mut ExpSum) {
        let mut terms = Vec::new();
        for (terms_k, &w) in flight.elastic.iter().zip(&c.elastic) {
            if w == ZERO {
                continue;
            }
            terms.extend(terms_k.iter().map(|t| term(t.rate, t.poly.map(|p| p * w))));
        }
        for j in 0..self.rigid_count() {
            for (list, w) in [
                (&flight.positions[j], c.positions[j]),
                (&flight.velocities[j], c.velocities[j]),
            ] {
                if w != 0.0 {
                    terms.extend(list.iter().map(|t| term(t.rate, t.poly.map(|p| p * w))));
                }
            }
        }
        out.terms = merge_with(terms, true);
    }

    /// The forcing of a flight from `t0` in segment `segment` of `signal` (`None`: past its
    /// end, no forcing), given the modal forcings of `d` and `v`.
    pub(crate) fn flight_forcing(
        (on_signal, on_rate): (&ModalForce, &ModalForce),
        signal: &Signal,
        segment: Option<usize>,
        t0: f64,
    ) -> FlightForcing {
        let Some(i) = segment else {
            return FlightForcing::default();
        };
        let seg = &signal.segments()[i];
        let combine = |a: f64, b: f64| ModalForce {
            elastic: on_signal
                .elastic
                .iter()
                .zip(&on_rate.elastic)
                .map(|(&x, &y)| x * a + y * b)
                .collect(),
            rigid: on_signal
                .rigid
                .iter()
                .zip(&on_rate.rigid)
                .map(|(&x, &y)| x * a + y * b)
                .collect(),
        };
        match &seg.shape {
            Shape::Affine { value, slope } => {
                let s0 = value + slope * (t0 - seg.start);
                FlightForcing {
                    constant: Some(combine(s0, *slope)),
                    linear: (*slope != 0.0).then(|| combine(*slope, 0.0)),
                    waves: Vec::new(),
                }
            }
            Shape::Sinusoids(list) => {
                let mut constant = 0.0;
                let mut waves = Vec::new();
                for s in list {
                    if s.frequency == 0.0 {
                        constant += s.cos;
                        continue;
                    }
                    let nu = s.frequency;
                    let (sin, cos) = crate::trig::sin_cos(nu * t0);
                    // c cos νt + s sin νt = Re(A e^{iνσ}), A = (c − i s) e^{iνt₀}.
                    let a = C64::new(s.cos, -s.sin) * C64::new(cos, sin);
                    let inu = C64::new(0.0, nu);
                    // f = Re((d + iν v) A e^{iνσ}) = ½ (F e^{iνσ} + F̄ e^{−iνσ}).
                    let plus = on_signal
                        .elastic
                        .iter()
                        .zip(&on_rate.elastic)
                        .map(|(&gd, &gv)| (gd + inu * gv) * a * 0.5)
                        .collect();
                    let minus = on_signal
                        .elastic
                        .iter()
                        .zip(&on_rate.elastic)
                        .map(|(&gd, &gv)| (gd - inu * gv) * a.conj() * 0.5)
                        .collect();
                    let rigid = on_signal
                        .rigid
                        .iter()
                        .zip(&on_rate.rigid)
                        .map(|(&ad, &av)| (inu * av + ad) * a)
                        .collect();
                    waves.push(Wave {
                        rate: nu,
                        plus,
                        minus,
                        rigid,
                    });
                }
                FlightForcing {
                    constant: (constant != 0.0).then(|| combine(constant, 0.0)),
                    linear: None,
                    waves,
                }
            }
        }
    }
}

/// Merges terms of equal rates, and folds a term of rate `μ̄` into one of rate `μ`
/// (`Re(B e^{μ̄σ}) = Re(B̄ e^{μσ})` for real `σ`); for the elastic coordinates, which are
/// complex, only equal rates are merged (`conjugates` false).
fn merge_with(terms: Vec<Term>, conjugates: bool) -> Vec<Term> {
    let mut out: Vec<Term> = Vec::with_capacity(terms.len());
    for t in terms {
        if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate) {
            for i in 0..4 {
                o.poly[i] += t.poly[i];
            }
        } else if let Some(o) = out
            .iter_mut()
            .find(|o| conjugates && o.rate == t.rate.conj())
        {
            for i in 0..4 {
                o.poly[i] += t.poly[i].conj();
            }
        } else {
            out.push(t);
        }
    }
    out
}

/// [`merge_with`] of a complex coordinate's terms (equal rates only).
fn merge(terms: Vec<Term>) -> Vec<Term> {
    merge_with(terms, false)
}
