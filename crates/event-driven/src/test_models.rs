//! Reference problems for tests and benchmarks, each with its known answer worked out here in
//! closed form, independently of the simulator (no [`crate::flow`], no event search): the paper's
//! unit (`m_o = 2, m_i = 1, k_o = 6, k_i = 3, u_g = 1`, `ω_n² = 1.5, 6`) in the variants the
//! tests need, a single undamped oscillator flying to a stop, and one impact.
//!
//! Fixtures, not API: compiled for the crate's own tests, and with the `fixtures` feature,
//! which its benches and examples enable through the crate's dev-dependency on itself.

use crate::engine::Start;
use crate::model::{CellParameters, CellStops, ContactPair, Model};
use nalgebra::{Complex, DMatrix, DVector, Matrix4};

/// Outer mass of the paper's unit.
pub const OUTER_MASS: f64 = 2.0;
/// Inner mass of the paper's unit.
pub const INNER_MASS: f64 = 1.0;
/// Outer (base) spring of the paper's unit.
pub const OUTER_STIFFNESS: f64 = 6.0;
/// Inner spring of the paper's unit.
pub const INNER_STIFFNESS: f64 = 3.0;
/// Base amplitude of the paper's unit.
pub const BASE_AMPLITUDE: f64 = 1.0;

/// Light dashpots `c_o = 0.1`, `c_i = 0.05`.
pub const LIGHT_DAMPING: (f64, f64) = (0.1, 0.05);

/// The paper's unit at `omega`, with optional dashpots `(c_o, c_i)` and stops `(gap, e)`.
///
/// # Panics
/// If `omega` is not finite and positive, or a damping, gap or restitution is out of range
/// (see [`Model::unit`]).
pub fn paper_unit(omega: f64, damping: Option<(f64, f64)>, stops: Option<(f64, f64)>) -> Model {
    let stops = stops.map(|(gap, restitution)| CellStops::symmetric(gap, restitution));
    Model::unit(&paper_cell(damping, stops), BASE_AMPLITUDE, omega)
        .expect("the paper's unit is valid")
}

/// The paper's unit as one cell of a chain, with optional dashpots `(c_o, c_i)` and stops.
pub fn paper_cell(damping: Option<(f64, f64)>, stops: Option<CellStops>) -> CellParameters {
    CellParameters {
        outer_mass: OUTER_MASS,
        inner_mass: INNER_MASS,
        outer_stiffness: OUTER_STIFFNESS,
        inner_stiffness: INNER_STIFFNESS,
        outer_damping: damping.map(|d| d.0),
        inner_damping: damping.map(|d| d.1),
        stops,
    }
}

/// A chain of `cells` copies of the paper's cell at `omega` (base amplitude
/// [`BASE_AMPLITUDE`]).
///
/// # Panics
/// If `cells` is outside `1..=`[`crate::model::MAX_CELLS`] or a value is out of range (see
/// [`Model::chain`]).
pub fn paper_chain(
    cells: usize,
    omega: f64,
    damping: Option<(f64, f64)>,
    stops: Option<CellStops>,
) -> Model {
    Model::chain(
        &vec![paper_cell(damping, stops); cells],
        BASE_AMPLITUDE,
        omega,
    )
    .expect("the paper's chain is valid")
}

/// A problem with its exact answer.
#[derive(Debug, Clone)]
pub struct Reference<A> {
    /// What is simulated.
    pub model: Model,
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// Where the run starts.
    pub start: Start,
    /// The exact answer.
    pub answer: A,
}

/// The steady state of the linear paper unit: complex amplitudes `U` with
/// `(K − ω²M + iωC) U = F`, `u(t) = Re{U e^{iωt}}`, solved by hand (Cramer's rule on 2×2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearSteadyState {
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// `U_o`.
    pub outer: Complex<f64>,
    /// `U_i`.
    pub inner: Complex<f64>,
}

impl LinearSteadyState {
    /// The paper unit's steady state at `omega` with dashpots `(c_o, c_i)`.
    pub fn of_paper_unit(omega: f64, damping: (f64, f64)) -> Self {
        let (co, ci) = damping;
        let (mo, mi, ko, ki) = (OUTER_MASS, INNER_MASS, OUTER_STIFFNESS, INNER_STIFFNESS);
        let w2 = omega * omega;
        let c = Complex::new;
        // Dynamic stiffness D = K − ω²M + iωC.
        let d00 = c(ko + ki - mo * w2, omega * (co + ci));
        let d01 = c(-ki, -omega * ci);
        let d11 = c(ki - mi * w2, omega * ci);
        let det = d00 * d11 - d01 * d01;
        // F = (k_o + iω c_o) u_g on the outer mass.
        let f = c(ko, omega * co) * BASE_AMPLITUDE;
        Self {
            omega,
            outer: d11 * f / det,
            inner: -d01 * f / det,
        }
    }

    /// `(u_o, u_i, u̇_o, u̇_i)` at time `t`.
    pub fn state_at(&self, t: f64) -> DVector<f64> {
        let e = Complex::new(0.0, self.omega * t).exp();
        let iw = Complex::new(0.0, self.omega);
        DVector::from_vec(vec![
            (self.outer * e).re,
            (self.inner * e).re,
            (self.outer * iw * e).re,
            (self.inner * iw * e).re,
        ])
    }

    /// `max_t |u_o|, max_t |u_i|`: the moduli `|U_o|, |U_i|`.
    pub fn amplitudes(&self) -> [f64; 2] {
        [self.outer.norm(), self.inner.norm()]
    }

    /// `max_t |r|`, `r = u_i − u_o`: `|U_i − U_o|`.
    pub fn relative_amplitude(&self) -> f64 {
        (self.inner - self.outer).norm()
    }
}

/// The damped linear paper unit at `omega`, started on its steady state: the answer is that
/// steady state (period 1, amplitudes `|U|`).
pub fn linear_damped_unit(omega: f64) -> Reference<LinearSteadyState> {
    let answer = LinearSteadyState::of_paper_unit(omega, LIGHT_DAMPING);
    Reference {
        model: paper_unit(omega, Some(LIGHT_DAMPING), None),
        omega,
        start: Start {
            state: answer.state_at(0.0),
            time: 0.0,
        },
        answer,
    }
}

/// The linear answer for a run from rest of a unit with stops it can never reach, and how far a
/// section can be from it once the stroboscopic map repeats.
#[derive(Debug, Clone, PartialEq)]
pub struct FarStops {
    /// The steady state the run must reach.
    pub steady: LinearSteadyState,
    /// The stops' half-clearance: twice a bound on `|r(t)|` over the whole run from rest.
    pub gap: f64,
    /// `‖Φ(Φ − I)⁻¹‖_F`, `Φ = e^{AT}` the linear unit's monodromy matrix: for a linear map with
    /// fixed point `x*`, `x_k − x* = Φ(Φ − I)⁻¹ (x_k − x_{k−1})`, so a section that repeats to
    /// `δ` is within this times `δ` of the steady state.
    pub settling_factor: f64,
}

/// The damped paper unit at `omega` with stops so far away that it never impacts, run from rest:
/// the answer is the linear steady state.
///
/// The gap is twice the bound `|r(t)| ≤ |U_i − U_o| + √(2 E₀ dᵀK⁻¹d)`: the transient
/// `z = x − x_ss` obeys the unforced damped equation, so its energy `½żᵀMż + ½zᵀKz` never
/// exceeds its initial value `E₀` (the steady state's energy at `t = 0`, as the run starts at
/// rest), and `|dᵀz| ≤ √(dᵀK⁻¹d · zᵀKz)` by Cauchy–Schwarz, `d = (−1, 1)`.
pub fn far_stops_unit(omega: f64, restitution: f64) -> Reference<FarStops> {
    let steady = LinearSteadyState::of_paper_unit(omega, LIGHT_DAMPING);
    let (mo, mi, ko, ki) = (OUTER_MASS, INNER_MASS, OUTER_STIFFNESS, INNER_STIFFNESS);
    let x0 = steady.state_at(0.0);
    let (uo, ui, vo, vi) = (x0[0], x0[1], x0[2], x0[3]);
    let energy =
        0.5 * (mo * vo * vo + mi * vi * vi) + 0.5 * (ko * uo * uo + ki * (ui - uo) * (ui - uo));
    // K⁻¹ of [[k_o + k_i, −k_i], [−k_i, k_i]] is [[1/k_o, 1/k_o], [1/k_o, 1/k_o + 1/k_i]], so
    // dᵀK⁻¹d = 1/k_i for d = (−1, 1).
    let compliance = 1.0 / ki;
    let bound = steady.relative_amplitude() + (2.0 * energy * compliance).sqrt();
    let gap = 2.0 * bound;
    // Monodromy of ẋ = Ax, A = [[0, I], [−M⁻¹K, −M⁻¹C]].
    let (co, ci) = LIGHT_DAMPING;
    #[rustfmt::skip]
    let a = Matrix4::new(
        0.0, 0.0, 1.0, 0.0,
        0.0, 0.0, 0.0, 1.0,
        -(ko + ki) / mo, ki / mo, -(co + ci) / mo, ci / mo,
        ki / mi, -ki / mi, ci / mi, -ci / mi,
    );
    let phi = (a * (std::f64::consts::TAU / omega)).exp();
    let settling = phi
        * (phi - Matrix4::identity())
            .try_inverse()
            .expect("a damped unit has no multiplier 1");
    Reference {
        model: paper_unit(omega, Some(LIGHT_DAMPING), Some((gap, restitution))),
        omega,
        start: Start::rest(2),
        answer: FarStops {
            steady,
            gap,
            settling_factor: settling.norm(),
        },
    }
}

/// The first contact of a free flight and the impact there, in closed form.
#[derive(Debug, Clone, PartialEq)]
pub struct FirstContact {
    /// Time of the first contact, `arcsin(Δ ω_n / v₀)/ω_n`.
    pub time: f64,
    /// Relative velocity `ṙ⁻ = v₀ cos(ω_n t*)` just before.
    pub relative_velocity: f64,
    /// Relative acceleration `r̈ = −ω_n² Δ` at the contact: the sensitivity of the velocity to
    /// the contact time.
    pub relative_acceleration: f64,
    /// Velocities `(u̇_o, u̇_i)` just after the impact, from the impact matrix `G` of the physics
    /// notes.
    pub velocities_after: [f64; 2],
}

/// A single undamped oscillator (the inner mass, `k_i = 3`, `m_i = 1`, `ω_n = √3`) leaving its
/// rest position at `v₀ = 1` toward a stop at `Δ = 0.3` on a free outer mass that stays at rest
/// (no coupling, no forcing): `r(t) = (v₀/ω_n) sin(ω_n t)` reaches `Δ` at
/// `t* = arcsin(Δ ω_n / v₀)/ω_n ≈ 0.3175`, and the impact there (restitution `e`) gives the
/// velocities `G (0, ṙ⁻)`. The forcing frequency `omega = 1` only sets the period
/// (`T = 2π > t*`).
pub fn free_flight_to_a_stop(restitution: f64) -> Reference<FirstContact> {
    let (mo, mi, ki) = (OUTER_MASS, INNER_MASS, INNER_STIFFNESS);
    let (gap, v0) = (0.3, 1.0);
    let wn = (ki / mi).sqrt();
    let time = (gap * wn / v0).asin() / wn;
    let rdot = v0 * (wn * time).cos();
    let velocities_after = impact_matrix(mo, mi, restitution, [0.0, rdot]);
    let model = Model::new(
        DMatrix::from_row_slice(2, 2, &[mo, 0.0, 0.0, mi]),
        // The outer mass on its own spring (ω² = 4, distinct from the inner ω_n² = 3: the
        // modal flow needs distinct eigenvalues, see `FlowError::Defective`).
        DMatrix::from_row_slice(2, 2, &[8.0, 0.0, 0.0, ki]),
        None,
        DVector::zeros(2),
        DVector::zeros(2),
        vec![ContactPair {
            plus_dof: Some(1),
            minus_dof: Some(0),
            gap_plus: gap,
            gap_minus: gap,
            restitution,
        }],
    )
    .expect("a valid model");
    Reference {
        model,
        omega: 1.0,
        start: Start {
            state: DVector::from_vec(vec![0.0, 0.0, 0.0, v0]),
            time: 0.0,
        },
        answer: FirstContact {
            time,
            relative_velocity: rdot,
            relative_acceleration: -wn * wn * gap,
            velocities_after,
        },
    }
}

/// The unit's impact map (`docs/methods.md`), written out:
/// `G = 1/(m_i+m_o) [[m_o − m_i e, m_i(1+e)], [m_o(1+e), m_i − m_o e]]` applied to
/// `(u̇_o, u̇_i)`.
pub fn impact_matrix(mo: f64, mi: f64, e: f64, v: [f64; 2]) -> [f64; 2] {
    let s = mo + mi;
    [
        ((mo - mi * e) * v[0] + mi * (1.0 + e) * v[1]) / s,
        (mo * (1.0 + e) * v[0] + (mi - mo * e) * v[1]) / s,
    ]
}

/// One impact of the paper's unit and its conserved and lost quantities.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactAnswer {
    /// Velocities `(u̇_o, u̇_i)` before.
    pub before: [f64; 2],
    /// Velocities after, from [`impact_matrix`].
    pub after: [f64; 2],
    /// Momentum `m_o u̇_o + m_i u̇_i`, the same before and after.
    pub momentum: f64,
    /// Relative velocity after: `ṙ⁺ = −e ṙ⁻`.
    pub relative_velocity_after: f64,
    /// Kinetic energy lost: `½ μ (1 − e²) ṙ⁻²`, `μ = m_o m_i/(m_o + m_i)`.
    pub energy_lost: f64,
}

/// The paper's unit with stops `(0.5, e)` and an impact at velocities `(0.4, −1.3)`.
pub fn paper_impact(restitution: f64) -> (Model, ImpactAnswer) {
    let (mo, mi) = (OUTER_MASS, INNER_MASS);
    let before = [0.4, -1.3];
    let rdot = before[1] - before[0];
    let mu = mo * mi / (mo + mi);
    let answer = ImpactAnswer {
        before,
        after: impact_matrix(mo, mi, restitution, before),
        momentum: mo * before[0] + mi * before[1],
        relative_velocity_after: -restitution * rdot,
        energy_lost: 0.5 * mu * (1.0 - restitution * restitution) * rdot * rdot,
    };
    (paper_unit(2.0, None, Some((0.5, restitution))), answer)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The hand-solved amplitudes satisfy `(K − ω²M + iωC) U = F` (a check on the algebra, not
    /// on the simulator).
    #[test]
    fn linear_amplitudes_solve_the_frequency_response() {
        for omega in [0.5, 1.3, 2.0, 3.9] {
            let s = LinearSteadyState::of_paper_unit(omega, LIGHT_DAMPING);
            let (co, ci) = LIGHT_DAMPING;
            let iw = Complex::new(0.0, omega);
            let w2 = omega * omega;
            let r0 = (OUTER_STIFFNESS + INNER_STIFFNESS - OUTER_MASS * w2 + iw * (co + ci))
                * s.outer
                - (INNER_STIFFNESS + iw * ci) * s.inner
                - (OUTER_STIFFNESS + iw * co) * BASE_AMPLITUDE;
            let r1 = -(INNER_STIFFNESS + iw * ci) * s.outer
                + (INNER_STIFFNESS - INNER_MASS * w2 + iw * ci) * s.inner;
            assert!(r0.norm() < 1e-14 && r1.norm() < 1e-14, "ω={omega}");
        }
    }

    /// `G` keeps momentum and maps `ṙ⁻` to `−e ṙ⁻`.
    #[test]
    fn impact_matrix_is_the_restitution_law() {
        for e in [0.0, 0.5, 1.0] {
            let v = [0.4, -1.3];
            let a = impact_matrix(2.0, 1.0, e, v);
            assert!((2.0 * a[0] + a[1] - (2.0 * v[0] + v[1])).abs() < 1e-15);
            assert!(((a[1] - a[0]) + e * (v[1] - v[0])).abs() < 1e-15);
        }
    }
}
