//! The closed-form flow of a linear system `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + f₀`
//! between events, by its complex modal decomposition.
//!
//! With the first-order state `y = (u, u̇)` and `A = [[0, I], [−M⁻¹K, −M⁻¹C]] = V Λ V⁻¹`,
//! the modal coordinates `z = V⁻¹ y` obey `ż_k = λ_k z_k + g⁺_k e^{iωt} + g⁻_k e^{−iωt} + g⁰_k`,
//! whose exact solution over a time `s` is
//! `z_k(s) = e^{λ_k s} z_k(0) + Σ G_k φ(λ_k, μ, s)`, `φ(λ, μ, s) = ∫₀ˢ e^{λ(s−σ)} e^{μσ} dσ`.
//! `φ` is evaluated in a form that stays finite when `μ = λ` (exact resonance of an undamped
//! mode): as `(e^{μs} − e^{λs})/(μ − λ)` when `|μ − λ| T` is large, and as
//! `e^{λs}(s + δs²/2 + δ²s³/6)`, `δ = μ − λ`, when it is below `10⁻⁴`.
//! The eigenvectors come from the quadratic pencil: `(λ²M + λC + K) φ = 0`, `v = (φ, λφ)`.

use crate::expsum::{ExpSum, Term};
use nalgebra::{Complex, DMatrix, DVector};
use thiserror::Error;

type C64 = Complex<f64>;

/// Why a flow could not be built.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FlowError {
    /// The mass matrix is singular.
    #[error("the mass matrix is singular")]
    SingularMass,
    /// The system matrix is defective (repeated eigenvalues without a full set of
    /// eigenvectors, e.g. exactly critical damping): the modal flow does not exist.
    #[error("the system is defective (e.g. exactly critically damped): condition number {0:e}")]
    Defective(f64),
}

/// Below this `|μ − λ|·T` a forcing rate counts as resonant with a mode.
const RESONANCE: f64 = 1e-4;

/// The modal flow of one linear system at one forcing frequency.
#[derive(Debug, Clone)]
pub struct LinearFlow {
    /// Degrees of freedom `n`; the state has `2n` entries.
    dofs: usize,
    omega: f64,
    period: f64,
    /// Eigenvalues `λ_k` of `A`.
    rates: Vec<C64>,
    /// Eigenvectors as columns.
    modes: DMatrix<C64>,
    /// `V⁻¹`.
    inverse: DMatrix<C64>,
    /// Modal forcing on `e^{+iωt}`, `e^{−iωt}` and the constant.
    plus: DVector<C64>,
    minus: DVector<C64>,
    constant: DVector<C64>,
}

/// A flight: the flow from a given state at a given forcing phase, as modal coefficients.
#[derive(Debug, Clone)]
pub struct Flight<'a> {
    flow: &'a LinearFlow,
    /// Modal state at the start.
    start: DVector<C64>,
    /// Forcing coefficients with the start phase folded in: `G⁺ = g⁺ e^{iωt₀}`, `G⁻`.
    plus: DVector<C64>,
    minus: DVector<C64>,
}

/// `φ(λ, μ, s) = ∫₀ˢ e^{λ(s−σ)} e^{μσ} dσ` as terms in `s`, resonance-safe.
fn phi_terms(lambda: C64, mu: C64, period: f64, scale: C64, out: &mut Vec<Term>) {
    let delta = mu - lambda;
    let zero = C64::new(0.0, 0.0);
    if (delta.re.abs() + delta.im.abs()) * period > RESONANCE {
        let c = scale / delta;
        out.push(Term {
            poly: [c, zero, zero, zero],
            rate: mu,
        });
        out.push(Term {
            poly: [-c, zero, zero, zero],
            rate: lambda,
        });
    } else {
        out.push(Term {
            poly: [
                zero,
                scale,
                scale * delta / 2.0,
                scale * delta * delta / 6.0,
            ],
            rate: lambda,
        });
    }
}

/// Value of `φ(λ, μ, s)` given `e^{λs}` and `e^{μs}`.
fn phi_shared(lambda: C64, el: C64, mu: C64, em: C64, s: f64, period: f64) -> C64 {
    let delta = mu - lambda;
    if (delta.re.abs() + delta.im.abs()) * period > RESONANCE {
        (em - el) / delta
    } else {
        el * (s + delta * (s * s / 2.0) + delta * delta * (s * s * s / 6.0))
    }
}

impl LinearFlow {
    /// The flow of `M ü + C u̇ + K u = f_c cos ωt + f_s sin ωt + f₀` (`damping` `None`: no
    /// damping terms at all).
    pub fn new(
        mass: &DMatrix<f64>,
        damping: Option<&DMatrix<f64>>,
        stiffness: &DMatrix<f64>,
        forcing_cos: &DVector<f64>,
        forcing_sin: &DVector<f64>,
        forcing_constant: &DVector<f64>,
        omega: f64,
    ) -> Result<Self, FlowError> {
        let n = mass.nrows();
        let minv = mass.clone().try_inverse().ok_or(FlowError::SingularMass)?;
        let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
        a.view_mut((0, n), (n, n)).fill_with_identity();
        a.view_mut((n, 0), (n, n))
            .copy_from(&(-(&minv * stiffness)));
        if let Some(c) = damping {
            a.view_mut((n, n), (n, n)).copy_from(&(-(&minv * c)));
        }
        let rates: Vec<C64> = a.clone().complex_eigenvalues().iter().copied().collect();
        let mut modes = DMatrix::<C64>::zeros(2 * n, 2 * n);
        let mc = mass.map(|v| C64::new(v, 0.0));
        let kc = stiffness.map(|v| C64::new(v, 0.0));
        let cc = damping.map(|c| c.map(|v| C64::new(v, 0.0)));
        for (k, &lambda) in rates.iter().enumerate() {
            let mut pencil = &mc * (lambda * lambda) + &kc;
            if let Some(c) = &cc {
                pencil += c * lambda;
            }
            let svd = pencil.svd(false, true);
            let v_t = svd.v_t.ok_or(FlowError::Defective(f64::INFINITY))?;
            let (imin, _) =
                svd.singular_values
                    .iter()
                    .enumerate()
                    .fold(
                        (0, f64::INFINITY),
                        |acc, (i, &s)| if s < acc.1 { (i, s) } else { acc },
                    );
            let shape: DVector<C64> = v_t.row(imin).adjoint();
            for i in 0..n {
                modes[(i, k)] = shape[i];
                modes[(n + i, k)] = shape[i] * lambda;
            }
        }
        let inverse = modes
            .clone()
            .try_inverse()
            .ok_or(FlowError::Defective(f64::INFINITY))?;
        let condition = modes.norm() * inverse.norm();
        if condition.is_nan() || condition >= 1e10 {
            return Err(FlowError::Defective(condition));
        }
        let lift = |f: DVector<C64>| {
            let mut b = DVector::<C64>::zeros(2 * n);
            let accel = minv.map(|v| C64::new(v, 0.0)) * f;
            b.rows_mut(n, n).copy_from(&accel);
            &inverse * b
        };
        // f_c cos ωt + f_s sin ωt = (F e^{iωt} + F̄ e^{−iωt})/2 with F = f_c − i f_s.
        let f = DVector::from_fn(n, |i, _| C64::new(forcing_cos[i], -forcing_sin[i]) * 0.5);
        let plus = lift(f.clone());
        let minus = lift(f.map(|c| c.conj()));
        let constant = lift(forcing_constant.map(|v| C64::new(v, 0.0)));
        Ok(Self {
            dofs: n,
            omega,
            period: std::f64::consts::TAU / omega,
            rates,
            modes,
            inverse,
            plus,
            minus,
            constant,
        })
    }

    /// Degrees of freedom.
    pub fn dofs(&self) -> usize {
        self.dofs
    }

    /// The flight from state `y` (length `2n`) at forcing phase time `t0` (the forcing is
    /// evaluated at `t0 + s`).
    pub fn flight(&self, y: &DVector<f64>, t0: f64) -> Flight<'_> {
        let start = &self.inverse * y.map(|v| C64::new(v, 0.0));
        let e = C64::new(0.0, self.omega * t0).exp();
        Flight {
            flow: self,
            start,
            plus: self.plus.map(|g| g * e),
            minus: self.minus.map(|g| g * e.conj()),
        }
    }
}

impl Flight<'_> {
    /// The state `y(s)` at time `s` into the flight.
    pub fn state(&self, s: f64) -> DVector<f64> {
        let f = self.flow;
        let w = C64::new(0.0, f.omega);
        // Shared exponentials: e^{±iωs} once for all modes.
        let (sin, cos) = (f.omega * s).sin_cos();
        let ep = C64::new(cos, sin);
        let em = ep.conj();
        let zero = C64::new(0.0, 0.0);
        let z = DVector::from_fn(f.rates.len(), |k, _| {
            let l = f.rates[k];
            let el = (l * s).exp();
            let mut zk = el * self.start[k]
                + self.plus[k] * phi_shared(l, el, w, ep, s, f.period)
                + self.minus[k] * phi_shared(l, el, -w, em, s, f.period);
            if f.constant[k] != zero {
                zk += f.constant[k] * phi_shared(l, el, zero, C64::new(1.0, 0.0), s, f.period);
            }
            zk
        });
        (&f.modes * z).map(|c| c.re)
    }

    /// The linear functional `c · y(s)` as a sum of exponential terms in `s`.
    pub fn functional(&self, c: &DVector<f64>) -> ExpSum {
        self.weighted(&self.flow.weights(c))
    }

    /// [`Self::functional`] for modal weights from [`LinearFlow::weights`] (computed once per
    /// functional, not per flight).
    pub fn weighted(&self, weights: &DVector<C64>) -> ExpSum {
        let f = self.flow;
        let w = C64::new(0.0, f.omega);
        let mut terms = Vec::with_capacity(4 * f.rates.len());
        let zero = C64::new(0.0, 0.0);
        for (k, &l) in f.rates.iter().enumerate() {
            let wk = weights[k];
            terms.push(Term {
                poly: [wk * self.start[k], zero, zero, zero],
                rate: l,
            });
            phi_terms(l, w, f.period, wk * self.plus[k], &mut terms);
            phi_terms(l, -w, f.period, wk * self.minus[k], &mut terms);
            if f.constant[k] != zero {
                phi_terms(l, zero, f.period, wk * f.constant[k], &mut terms);
            }
        }
        ExpSum {
            terms: merge(terms),
        }
    }
}

impl LinearFlow {
    /// Modal weights `Vᵀ c` of the functional `c · y`.
    pub fn weights(&self, c: &DVector<f64>) -> DVector<C64> {
        self.modes.transpose() * c.map(|v| C64::new(v, 0.0))
    }
}

/// Merges terms with equal rates, and folds each term with rate `μ̄` into the one with rate `μ`
/// (`Re(B e^{μ̄s}) = Re(B̄ e^{μs})`): half the exponentials to evaluate for a real system.
fn merge(terms: Vec<Term>) -> Vec<Term> {
    let mut out: Vec<Term> = Vec::with_capacity(terms.len());
    for t in terms {
        if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate) {
            for i in 0..4 {
                o.poly[i] += t.poly[i];
            }
        } else if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate.conj()) {
            for i in 0..4 {
                o.poly[i] += t.poly[i].conj();
            }
        } else {
            out.push(t);
        }
    }
    out
}
