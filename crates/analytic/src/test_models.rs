//! Reference problems with known answers, shared by the tests, benches and examples of this
//! crate: fixtures, not API (compiled for the crate's tests, and with the `fixtures` feature,
//! which its benches and examples enable through the crate's dev-dependency on itself).
//!
//! Each model returns the problem *together with* its answer, worked out by hand (Cramer's
//! rule, the characteristic polynomial, the trace of the system matrix) and written here with
//! the unit's numbers as literals, so that no answer is computed by the code under test.
//! The bare problems ([`paper_unit`], [`damped_paper_unit`], [`paper_stops`]) stay for callers
//! that need only the problem.

use crate::unit::{Damping, Stops, Unit};
use nalgebra::Complex;

/// The paper's §2.2 unit: `m_i = 1, m_o = 2, k_i = 3, k_o = 6, u_g = 1`, undamped.
/// `ω² = 1.5, 6`; anti-resonance `√(k_i/m_i)`. With its answers: [`paper_modes`].
pub fn paper_unit() -> Unit {
    Unit {
        outer_mass: 2.0,
        inner_mass: 1.0,
        outer_stiffness: 6.0,
        inner_stiffness: 3.0,
        base_amplitude: 1.0,
        damping: None,
    }
}

/// The paper's unit with light dashpots `c_o = 0.1`, `c_i = 0.05`. With its answers:
/// [`damped_steady_state`].
pub fn damped_paper_unit() -> Unit {
    Unit {
        damping: Some(Damping {
            outer: 0.1,
            inner: 0.05,
        }),
        ..paper_unit()
    }
}

/// The paper's stops under the reading "0.5 m to each side": `Δ = 0.5`, and restitution
/// `e = 0.8` (the paper does not state `e`).
pub fn paper_stops() -> Stops {
    Stops {
        gap: 0.5,
        restitution: 0.8,
    }
}

/// The modal facts of the paper's unit, by hand.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModalAnswer {
    /// `ω_n²` ascending: the roots of `det(K − ω²M) = 2ω⁴ − 15ω² + 18 = 2(ω² − 3/2)(ω² − 6)`.
    pub natural_frequencies_squared: [f64; 2],
    /// The anti-resonance `√(k_i/m_i) = √3`, where `U_o = 0`.
    pub anti_resonance: f64,
    /// `|P_n| = |φ_n,o| k_o u_g` with mass-normalised shapes `φ₁ = (1, 2)/√6`,
    /// `φ₂ = (1, −1)/√3`: `(6/√6, 6/√3) = (√6, √12)` (paper §2.2: 2.4495, 3.4641). The sign of
    /// each depends on the sign convention of its mode shape.
    pub modal_force_magnitudes: [f64; 2],
    /// The mass-normalised shapes as `(u_o, u_i)` columns, each with a positive inner-mass
    /// component: `(1, 2)/√6` and `(−1, 1)/√3`.
    pub shapes: [[f64; 2]; 2],
}

/// The paper's unit ([`paper_unit`]) with its modal answer.
pub fn paper_modes() -> (Unit, ModalAnswer) {
    let answer = ModalAnswer {
        natural_frequencies_squared: [1.5, 6.0],
        anti_resonance: 3f64.sqrt(),
        modal_force_magnitudes: [6f64.sqrt(), 12f64.sqrt()],
        shapes: [
            [1.0 / 6f64.sqrt(), 2.0 / 6f64.sqrt()],
            [-1.0 / 3f64.sqrt(), 1.0 / 3f64.sqrt()],
        ],
    };
    (paper_unit(), answer)
}

/// A linear steady state `u(t) = Re{U e^{iωt}}` known in closed form.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SteadyStateAnswer {
    /// The angular frequency.
    pub omega: f64,
    /// `U_o`.
    pub outer: Complex<f64>,
    /// `U_i`.
    pub inner: Complex<f64>,
    /// `(k_o + k_i + ω² m_o)(k_i + ω² m_i)`, the size of the terms of the determinant: the
    /// scale against which its rounding is measured (see `RESONANCE_ULPS = 64.0`).
    pub determinant_scale: f64,
    /// `|det(K − ω²M + iωC)|`: the relative error of any solve grows like
    /// `determinant_scale / |det|` near a resonance.
    pub determinant_norm: f64,
}

/// The undamped paper unit's steady state at `omega`, by Cramer's rule on the 2×2 system
/// `[[9 − 2ω², −3], [−3, 3 − ω²]] U = (6, 0)`:
/// `D = 2ω⁴ − 15ω² + 18`, `U_o = 6(3 − ω²)/D`, `U_i = 18/D`.
///
/// # Panics
/// At the undamped resonances `ω² = 3/2, 6` (`D = 0`, no bounded steady state).
pub fn paper_steady_state(omega: f64) -> (Unit, SteadyStateAnswer) {
    let w2 = omega * omega;
    let d = 2.0 * w2 * w2 - 15.0 * w2 + 18.0;
    assert!(d != 0.0, "ω = {omega} is an undamped resonance");
    let answer = SteadyStateAnswer {
        omega,
        outer: Complex::new(6.0 * (3.0 - w2) / d, 0.0),
        inner: Complex::new(18.0 / d, 0.0),
        determinant_scale: (9.0 + 2.0 * w2) * (3.0 + w2),
        determinant_norm: d.abs(),
    };
    (paper_unit(), answer)
}

/// Steady states of the undamped paper unit at frequencies where the answer is a small
/// rational, from [`paper_steady_state`]'s formulas evaluated by hand:
///
/// | `ω²` | `D`  | `U_o`  | `U_i`  |
/// |------|------|--------|--------|
/// | 1    | 5    | 12/5   | 18/5   |
/// | 2    | −4   | −3/2   | −9/2   |
/// | 3    | −9   | 0      | −2     |
/// | 4    | −10  | 3/5    | −9/5   |
/// | 9    | 45   | −4/5   | 2/5    |
///
/// `ω² = 3` is the anti-resonance (the outer mass stands still); `ω² = 2` lies in the
/// attenuation band of neither (`|U_o| = 1.5 > u_g`), `ω² = 9` in the band `ω > 2.9`.
pub fn paper_steady_states_exact() -> (Unit, Vec<SteadyStateAnswer>) {
    let rows: [(f64, f64, f64, f64); 5] = [
        (1.0, 5.0, 12.0 / 5.0, 18.0 / 5.0),
        (2.0, -4.0, -3.0 / 2.0, -9.0 / 2.0),
        (3.0, -9.0, 0.0, -2.0),
        (4.0, -10.0, 3.0 / 5.0, -9.0 / 5.0),
        (9.0, 45.0, -4.0 / 5.0, 2.0 / 5.0),
    ];
    let answers = rows
        .iter()
        .map(|&(w2, d, uo, ui)| SteadyStateAnswer {
            omega: f64::sqrt(w2),
            outer: Complex::new(uo, 0.0),
            inner: Complex::new(ui, 0.0),
            determinant_scale: (9.0 + 2.0 * w2) * (3.0 + w2),
            determinant_norm: f64::abs(d),
        })
        .collect();
    (paper_unit(), answers)
}

/// The damped paper unit's ([`damped_paper_unit`]) complex steady state at `omega`, by
/// Cramer's rule on `(K − ω²M + iωC) U = ((k_o + iω c_o) u_g, 0)` with the numbers written out:
/// `a = 9 − 2ω² + 0.15 iω`, `b = −3 − 0.05 iω`, `c = 3 − ω² + 0.05 iω`, `f = 6 + 0.1 iω`,
/// `D = a c − b²`, `U_o = c f / D`, `U_i = −b f / D`.
pub fn damped_steady_state(omega: f64) -> (Unit, SteadyStateAnswer) {
    let w2 = omega * omega;
    let a = Complex::new(9.0 - 2.0 * w2, 0.15 * omega);
    let b = Complex::new(-3.0, -0.05 * omega);
    let c = Complex::new(3.0 - w2, 0.05 * omega);
    let f = Complex::new(6.0, 0.1 * omega);
    let d = a * c - b * b;
    let answer = SteadyStateAnswer {
        omega,
        outer: c * f / d,
        inner: -b * f / d,
        determinant_scale: (9.0 + 2.0 * w2) * (3.0 + w2),
        determinant_norm: d.norm(),
    };
    (damped_paper_unit(), answer)
}

/// The damped paper unit with stops so far away (`Δ = 1000`, `e = 0.8`) that no motion
/// reaches them: its linear relative amplitude `|U_i − U_o|` stays below 33 at every `ω` (the
/// damped peak at `ω₁`, 32.66, from [`damped_steady_state`] scanned in steps of `10⁻⁵`), so the answer at every `ω` is *no* two-impact orbit, symmetric or not,
/// viable or not: in the symmetric equations the phase line lies at a distance proportional to
/// `Δ` from the origin and misses the unit circle. (The *undamped* unit does have such orbits
/// near its resonances, where its linear amplitude is unbounded.)
pub fn unreachable_stops() -> (Unit, Stops) {
    (
        damped_paper_unit(),
        Stops {
            gap: 1000.0,
            restitution: 0.8,
        },
    )
}

/// Identities every symmetric two-impact orbit obeys, whatever its branch.
///
/// - Half-period symmetry: `u(t + T/2) = −u(t)` for all `t`.
/// - Restitution at each impact: `ṙ⁺ = −e ṙ⁻`, momentum `m_o u̇_o + m_i u̇_i` kept.
/// - Liouville: `det E(t) = exp(tr A · t)`, and `det S = e²` for each saltation matrix: `S` is
///   a rank-one update of `Ĝ = diag(I, G)`, so `det S = det G · ṙ⁺/ṙ⁻`, with
///   `det G = −e` (expand `G`: `(m_o m_i (1 + e²) − e(m_o² + m_i²) − m_o m_i (1 + e)²)/(m_o +
///   m_i)²`) and `ṙ⁺/ṙ⁻ = −e`. So `det(monodromy) = e^{2n} exp(tr A · T)`, `n = 2` impacts.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SymmetricIdentities {
    /// Impacts per period: 2.
    pub impacts_per_period: i32,
    /// `tr A = −tr(M⁻¹C) = −((c_o + c_i)/m_o + c_i/m_i)`, by hand: `0` undamped,
    /// `−(0.15/2 + 0.05) = −0.125` for [`damped_paper_unit`].
    pub system_trace: f64,
}

impl SymmetricIdentities {
    /// `det(monodromy) = e^{2n} exp(tr A · 2π/ω)`.
    pub fn monodromy_determinant(&self, restitution: f64, omega: f64) -> f64 {
        restitution.powi(2 * self.impacts_per_period)
            * (self.system_trace * std::f64::consts::TAU / omega).exp()
    }
}

/// The undamped and the damped paper unit, each with its symmetric-orbit identities.
pub fn symmetric_identities() -> [(Unit, SymmetricIdentities); 2] {
    [
        (
            paper_unit(),
            SymmetricIdentities {
                impacts_per_period: 2,
                system_trace: 0.0,
            },
        ),
        (
            damped_paper_unit(),
            SymmetricIdentities {
                impacts_per_period: 2,
                system_trace: -0.125,
            },
        ),
    ]
}

/// One harmonic of a base motion `u_g(t) = Σ a cos(kθ + φ)`, `θ = ωt + α`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaseHarmonic {
    /// The order `k` (1: the fundamental).
    pub order: u32,
    /// The amplitude `a`.
    pub amplitude: f64,
    /// The phase `φ` (the fundamental's must be 0: `α` is its phase).
    pub phase: f64,
}

/// The base motion `a cos θ`, the fundamental alone.
pub fn fundamental(amplitude: f64) -> BaseHarmonic {
    BaseHarmonic {
        order: 1,
        amplitude,
        phase: 0.0,
    }
}

/// The forcing of a base motion acting on coordinate `at` of an `n`-DOF model through a spring
/// `k` and a dashpot `c`: `f = k u_g + c u̇_g` on that coordinate, by hand for each harmonic
/// `a cos(kθ + φ)`: cosine `k a`, sine `0`, sine per unit of its frequency `−c a`, phase `φ`
/// (the fundamental's entries when the order is 1; a missing fundamental is zero).
///
/// # Panics
/// If an order-1 entry has a phase other than 0.
pub fn base_forcing(
    n: usize,
    at: usize,
    spring: f64,
    dashpot: f64,
    base: &[BaseHarmonic],
) -> crate::HarmonicForcing {
    let on = |v: f64| {
        let mut f = nalgebra::DVector::zeros(n);
        f[at] = v;
        f
    };
    let mut forcing = crate::HarmonicForcing::fundamental(on(0.0), on(0.0), on(0.0));
    for h in base {
        if h.order == 1 {
            assert!(h.phase == 0.0, "the fundamental's phase is α");
            forcing.cosine = on(spring * h.amplitude);
            forcing.sine_per_omega = on(-dashpot * h.amplitude);
        } else {
            forcing.harmonics.push(crate::Harmonic {
                order: h.order,
                cosine: on(spring * h.amplitude),
                sine: on(0.0),
                sine_per_omega: on(-dashpot * h.amplitude),
                phase: h.phase,
            });
        }
    }
    forcing
}

/// The impact oscillator: a mass `m = 1` on a spring `k = 1` and a dashpot `c = 0.05` to a
/// moving base `base`, against one stop at `u = +0.5` (side 1; no stop on side 2) with
/// restitution `e = 0.8`. Its exact linear response: [`oscillator_response`].
pub fn impact_oscillator(base: &[BaseHarmonic]) -> crate::LinearModel {
    let one = |v: f64| nalgebra::DMatrix::from_element(1, 1, v);
    crate::LinearModel::new(
        one(1.0),
        one(0.05),
        one(1.0),
        base_forcing(1, 0, 1.0, 0.05, base),
        vec![crate::ContactPair {
            direction: nalgebra::DVector::from_element(1, 1.0),
            gap_side1: 0.5,
            gap_side2: f64::INFINITY,
            restitution: 0.8,
        }],
    )
    .unwrap_or_else(|e| panic!("the impact oscillator is a model: {e}"))
}

/// The impact oscillator's ([`impact_oscillator`]) linear displacement at time `t`, frequency
/// `omega` and base phase `α = 0`, by hand: each harmonic `a cos(kθ + φ)` moves the mass by
/// `Re{a H(kω) e^{i(kωt + φ)}}` with `H(Ω) = (1 + 0.05 iΩ)/(1 − Ω² + 0.05 iΩ)`, summed.
pub fn oscillator_response(base: &[BaseHarmonic], omega: f64, t: f64) -> f64 {
    base.iter()
        .map(|h| {
            let w = f64::from(h.order) * omega;
            let transfer = Complex::new(1.0, 0.05 * w) / Complex::new(1.0 - w * w, 0.05 * w);
            (transfer * h.amplitude * Complex::from_polar(1.0, w * t + h.phase)).re
        })
        .sum()
}

/// Two masses with two contact pairs: `m₁ = 1` on a spring `1` and a dashpot `0.05` to the
/// moving base `base`, `m₂ = 0.5` on a spring `0.6` and a dashpot `0.02` to `m₁`
/// (`K = [[1.6, −0.6], [−0.6, 0.6]]`, `C = [[0.07, −0.02], [−0.02, 0.02]]`). Pair 0: `m₂`
/// rattling against `m₁` (`r = u₂ − u₁`, stops at `±0.4`, `e = 0.7`); pair 1: `m₁` against the
/// frame (`r = u₁`, one stop at `+1.5`, `e = 0.8`).
pub fn two_masses_two_pairs(base: &[BaseHarmonic]) -> crate::LinearModel {
    let m = |a: [f64; 4]| nalgebra::DMatrix::from_row_slice(2, 2, &a);
    let pair = |w: [f64; 2], gap_side1: f64, gap_side2: f64, restitution: f64| crate::ContactPair {
        direction: nalgebra::DVector::from_row_slice(&w),
        gap_side1,
        gap_side2,
        restitution,
    };
    crate::LinearModel::new(
        m([1.0, 0.0, 0.0, 0.5]),
        m([0.07, -0.02, -0.02, 0.02]),
        m([1.6, -0.6, -0.6, 0.6]),
        base_forcing(2, 0, 1.0, 0.05, base),
        vec![
            pair([-1.0, 1.0], 0.4, 0.4, 0.7),
            pair([1.0, 0.0], 1.5, f64::INFINITY, 0.8),
        ],
    )
    .unwrap_or_else(|e| panic!("the two masses are a model: {e}"))
}
