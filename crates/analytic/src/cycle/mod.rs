//! Periodic orbits of any impact signature, by the Nigm–Shabana method with Newton.
//!
//! A cycle of `p` forcing periods (`pT`) has `n` impacts at `0 = t₁ < t₂ < … < tₙ < pT` on
//! sides `s_j` (`+1` at `r = +Δ`, `−1` at `r = −Δ`), in the canonical order of its
//! [`Signature`]. The base moves as `u_g cos(ωt + α)`. For fixed `x = (α, t₂ … tₙ)`
//! everything else is linear: with the augmented flow `Φ_j = exp(Â τ_j)` of flight `j`
//! (`τ_j = t_{j+1} − t_j`, `t_{n+1} = pT`) and the augmented impact map `Ĝ = diag(I₂, G, I₂)`,
//! the cycle map `Ψ = Ĝ Φₙ Ĝ Φₙ₋₁ ⋯ Ĝ Φ₁` carries `(y₁, p₀)`, the state just after the first
//! impact and the forcing phase `p₀ = (cos α, sin α)`, round the cycle. Periodicity
//! `(I − Ψ_xx) y₁ = Ψ_xp p₀` fixes `y₁`, and the `n` contact conditions
//! `r(t_j⁻) = s_j Δ` are the residuals: `n` equations in `n` unknowns.
//!
//! These are the unit's fixed-size instance (6×6 stack matrices) of the cycle equations every
//! model shares, [`crate::cycle_equations::CycleEquations`]: residuals and exact derivatives
//! (`∂Φ_j/∂τ_j = Â Φ_j`, `∂p₀/∂α = (−sin α, cos α)`, the periodicity solve differentiated
//! implicitly), solved by the one Newton ([`crate::SequenceNewton`]) and found by the one
//! multi-start of [`crate::sequence_search`]; its verdicts are the ones every model shares
//! (`verdicts::assemble`), run on the unit's own flow.

#[cfg(test)]
mod contact_tests;
pub mod cycle_equations;
pub mod motion;
pub mod sequence_orbit;
pub mod sequence_search;
pub(crate) mod unit_flights;
pub(crate) mod unit_modes;
pub(crate) mod verdicts;

/// Matrix entries for the bit-for-bit tests of this module's products, from a xorshift
/// generator seeded with `seed`: exact zeros of both signs (a seventh each), the rest of
/// every sign and of sizes from `1e-6` to `1e6`.
#[cfg(test)]
pub(crate) fn awkward_entries(seed: u64) -> impl FnMut() -> f64 {
    let mut state = seed;
    move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        let mantissa = (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
        match state % 7 {
            0 => 0.0,
            1 => -0.0,
            _ => mantissa * 10f64.powi((state % 13) as i32 - 6),
        }
    }
}

use crate::cycle_equations::{CycleEquations, ImpactCondition};
use crate::flow::{join, Augmented, Extrema, ForcedFlow};
use crate::linear::{modes, transmittance_db};
use crate::orbit::{eigenvalues, impact, relative_displacement, saltation, Side, Violation};
use crate::sequence::{ImpactSequence, PairImpact};
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError};
use crate::sequence_search::{grid_intervals, multi_start, ALPHA_SCAN};
use crate::signature::Signature;
use crate::symmetric::OrbitError;
use crate::unit::{Stops, Unit};
use crate::verdicts::EnergyBalance;
use crate::verdicts::{energy_forms, CycleModel, EnergyForms, SequenceViolation};
use nalgebra::{Complex, Matrix2, Matrix4, Matrix6, SMatrix, Vector2, Vector4, U4, U6};

pub(crate) use crate::sequence_orbit::{NEWTON_TOLERANCE, STEP_ROUNDING};

type Matrix12 = SMatrix<f64, 12, 12>;

/// A periodic orbit of an impact signature and its verdicts.
///
/// Times and phases are measured from the first impact of the canonical signature.
#[derive(Debug, Clone, PartialEq)]
pub struct SignatureOrbit {
    /// The signature, canonical.
    pub signature: Signature,
    /// Number of forcing periods in the cycle.
    pub period: u32,
    /// Angular frequency `ω` of the forcing.
    pub omega: f64,
    /// Impact times as fractions of the cycle `pT`, in canonical order, first = 0.
    pub impact_phases: Vec<f64>,
    /// Base-motion phase at the first canonical impact, radians in `(−π, π]`.
    pub alpha: f64,
    /// State `(u_o, u_i, u̇_o, u̇_i)` just after the first canonical impact.
    pub state_after_impact: Vector4<f64>,
    /// State just before each impact, in canonical order.
    pub states_before_impacts: Vec<Vector4<f64>>,
    /// State just after each impact, in canonical order (the first is
    /// `state_after_impact`); the motion between impacts is [`crate::UnitMotion`]'s.
    pub states_after_impacts: Vec<Vector4<f64>>,
    /// `X_o = max |u_o(t)|` over the cycle, from the rigorous extrema of every flight.
    pub outer_amplitude: f64,
    /// `20 log10(X_o / u_g)`.
    pub transmittance_db: f64,
    /// True when no [`Violation`] was found.
    pub viable: bool,
    /// Every condition that fails; times from the first canonical impact.
    pub violations: Vec<Violation>,
    /// Eigenvalues of the monodromy matrix (flight propagators and saltation matrices).
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Every multiplier has modulus `< 1 −` [`crate::orbit::STABILITY_MARGIN`].
    pub stable: bool,
    /// The monodromy matrix over the cycle, from just after the first canonical impact.
    pub monodromy: Matrix4<f64>,
    /// The energy balance over the cycle, the same terms as every model's
    /// ([`crate::SequenceOrbit::energy`]).
    pub energy: EnergyBalance,
    /// `|work − dissipation − impact losses|` relative to the reference of every path
    /// ([`crate::SequenceOrbit::energy_residual`]): the largest of `|work|`,
    /// `dissipation + losses`, [`crate::ENERGY_EXCHANGE_FRACTION`]` · exchange_bound` and
    /// `ENERGY_FLOOR = 1e-6`` k_o u_g²`.
    pub energy_residual: f64,
    /// Newton iterations taken to converge.
    pub newton_iterations: usize,
}

/// The cycle's problem: the unit's fixed-size instance of the cycle equations, and what the
/// verdicts need of the unit (its flow, impact map, contact pair and energy forms).
struct Problem {
    flow: ForcedFlow,
    g: Matrix2<f64>,
    equations: CycleEquations<U6>,
    sequence: ImpactSequence,
    /// The pair's coordinate `r = u_i − u_o` and its two gaps.
    pair: [(Augmented, [f64; 2]); 1],
    /// `u_o`, whose amplitude is reported.
    outer: [Augmented; 1],
    forms: EnergyForms<U6>,
    /// `k_o u_g²`: both masses follow the base statically.
    static_energy: f64,
    reduced_mass: f64,
    restitution_squared: f64,
    base_amplitude: f64,
}

impl Problem {
    fn new(unit: &Unit, stops: &Stops, omega: f64, signature: &Signature) -> Self {
        let flow = ForcedFlow::new(unit, omega);
        let g = stops.impact_map(unit);
        let mut g_hat = Matrix6::identity();
        g_hat.fixed_view_mut::<2, 2>(2, 2).copy_from(&g);
        let h = join(&relative_displacement(), &Vector2::zeros());
        let impacts = signature
            .sides()
            .iter()
            .map(|&s| ImpactCondition {
                impact_map: g_hat,
                contact: h,
                stop: f64::from(s) * stops.gap,
            })
            .collect();
        let cycle = flow.period() * f64::from(signature.period());
        let equations = CycleEquations::new(
            omega,
            *flow.augmented_matrix(),
            impacts,
            signature.symmetries(),
            cycle,
        );
        let (ko, ug) = (unit.outer_stiffness, unit.base_amplitude);
        let co = unit.damping.map_or(0.0, |d| d.outer);
        let forms = energy_forms(
            U6,
            &unit.mass(),
            &unit.damping_matrix(),
            &Vector2::new(ko * ug, 0.0),
            &Vector2::new(-co * ug * omega, 0.0),
            omega,
        );
        Self {
            flow,
            g,
            equations,
            sequence: ImpactSequence::from_signature(signature),
            pair: [(h, [stops.gap, stops.gap])],
            outer: [Augmented::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0)],
            forms,
            static_energy: ko * ug.powi(2),
            reduced_mass: unit.reduced_mass(),
            restitution_squared: stops.restitution * stops.restitution,
            base_amplitude: ug,
        }
    }
}

/// The unit's own numerics for the verdicts: 6×6 flights, 4×4 monodromy.
impl CycleModel<U6> for Problem {
    type State = U4;

    fn state_dim(&self) -> U4 {
        U4
    }

    fn impacts(&self) -> &[PairImpact] {
        self.sequence.impacts()
    }

    fn pairs(&self) -> &[(Augmented, [f64; 2])] {
        &self.pair
    }

    fn amplitude_functionals(&self) -> &[Augmented] {
        &self.outer
    }

    fn energy_forms(&self) -> &EnergyForms<U6> {
        &self.forms
    }

    fn static_energy(&self) -> f64 {
        self.static_energy
    }

    fn extrema(&self, start: &Augmented, duration: f64, functionals: &[Augmented]) -> Vec<Extrema> {
        self.flow.extrema(start, duration, functionals)
    }

    fn second_moment(&self, start: &Augmented, tau: f64) -> Matrix6<f64> {
        second_moment(&self.flow, start, tau)
    }

    fn impact_state(&self, _pair: usize, before: &Vector4<f64>) -> Vector4<f64> {
        impact(&self.g, before)
    }

    fn relative_velocity(&self, _pair: usize, x: &Vector4<f64>) -> f64 {
        x[3] - x[2]
    }

    fn impact_loss(&self, _pair: usize, rdot: f64) -> f64 {
        0.5 * self.reduced_mass * (1.0 - self.restitution_squared) * rdot * rdot
    }

    fn saltation(&self, _pair: usize, before: &Vector4<f64>, phase: &[f64]) -> Matrix4<f64> {
        saltation(
            &self.flow,
            &self.g,
            before,
            &Vector2::new(phase[0], phase[1]),
        )
    }

    fn eigenvalues(&self, monodromy: &Matrix4<f64>) -> Option<Vec<Complex<f64>>> {
        eigenvalues(monodromy).map(|e| e.to_vec())
    }
}

/// The unit's error for an error of the shared Newton.
fn orbit_error(e: SequenceOrbitError) -> OrbitError {
    match e {
        SequenceOrbitError::InvalidFrequency { omega } => OrbitError::InvalidFrequency { omega },
        SequenceOrbitError::InvalidGuess { impacts, len } => {
            OrbitError::InvalidGuess { impacts, len }
        }
        SequenceOrbitError::NoConvergence {
            omega, residual, ..
        } => OrbitError::NoConvergence { omega, residual },
        SequenceOrbitError::SingularCycle { omega } => OrbitError::SingularCycle { omega },
        // A signature has one pair: the unit's.
        SequenceOrbitError::Sequence(_) => unreachable!("a signature names no other pair"),
        // The unit's outer spring is positive: its stiffness matrix is regular.
        SequenceOrbitError::UnrestrainedRigidMode { .. } => {
            unreachable!("the unit has no rigid modes")
        }
    }
}

/// The orbit of `signature` nearest (in Newton's sense) to `guess = (α, φ₂, …, φₙ)`: the base
/// phase at the first canonical impact and the impact times of the others as fractions of the
/// cycle (`0 < φ₂ < … < φₙ < 1`). The unit and stops are not validated here.
///
/// # Errors
/// [`OrbitError::InvalidFrequency`] unless `omega` is finite and positive;
/// [`OrbitError::InvalidGuess`] when `guess` does not have `n` finite entries with ordered
/// phases in `(0, 1)`; [`OrbitError::SingularCycle`] when the periodicity solve or the Newton
/// Jacobian is singular; [`OrbitError::NoConvergence`] when Newton does not reach
/// `NEWTON_TOLERANCE = 1e-13` within [`crate::NEWTON_ITERATIONS`].
pub fn solve_signature(
    unit: &Unit,
    stops: &Stops,
    omega: f64,
    signature: &Signature,
    guess: &[f64],
) -> Result<SignatureOrbit, OrbitError> {
    if !(omega.is_finite() && omega > 0.0) {
        return Err(OrbitError::InvalidFrequency { omega });
    }
    let problem = Problem::new(unit, stops, omega, signature);
    let converged = SequenceNewton::default()
        .solve(&problem.equations, guess)
        .map_err(orbit_error)?;
    let (alpha, phases) = problem.equations.canonical(&converged.unknowns);
    assemble(&problem, signature, alpha, &phases, converged.iteration)
}

/// Builds the orbit at converged unknowns by the verdicts every model shares
/// ([`crate::verdicts::assemble`]) on the unit's own flow.
fn assemble(
    problem: &Problem,
    signature: &Signature,
    alpha: f64,
    phases: &[f64],
    newton_iterations: usize,
) -> Result<SignatureOrbit, OrbitError> {
    let omega = problem.flow.omega();
    let verdicts = crate::verdicts::assemble(problem, &problem.equations, alpha, phases)
        .ok_or(OrbitError::SingularCycle { omega })?;
    let outer_amplitude = verdicts.amplitudes[0];
    let side = |side: u8| if side == 1 { Side::One } else { Side::Two };
    let violations: Vec<Violation> = verdicts
        .violations
        .iter()
        .map(|v| match *v {
            SequenceViolation::Penetration {
                side: s,
                time,
                excess,
                ..
            } => Violation::Penetration {
                side: side(s),
                time,
                excess,
            },
            SequenceViolation::WrongApproach {
                side: s,
                relative_velocity,
                ..
            } => Violation::WrongApproach {
                side: side(s),
                relative_velocity,
            },
            SequenceViolation::ExtraImpact {
                side: s,
                time,
                excess,
                ..
            } => Violation::ExtraImpact {
                side: side(s),
                time,
                excess,
            },
        })
        .collect();
    Ok(SignatureOrbit {
        signature: signature.clone(),
        period: signature.period(),
        omega,
        impact_phases: phases.to_vec(),
        alpha,
        state_after_impact: verdicts.states_after[0],
        states_before_impacts: verdicts.states_before,
        states_after_impacts: verdicts.states_after,
        outer_amplitude,
        transmittance_db: transmittance_db(outer_amplitude, problem.base_amplitude),
        viable: violations.is_empty(),
        violations,
        floquet_multipliers: verdicts.floquet_multipliers,
        stable: verdicts.stable,
        monodromy: verdicts.monodromy,
        energy: verdicts.energy,
        energy_residual: verdicts.energy_residual,
        newton_iterations,
    })
}

/// `W = ∫₀^τ z(t) z(t)ᵀ dt` along the exact flow from `start`, in closed form by Van Loan's
/// block exponential: `exp([[−Â, z₀z₀ᵀ], [0, Âᵀ]] τ) = [[·, G], [0, e^{Âᵀτ}]]` and
/// `∫₀^τ e^{Âs} z₀z₀ᵀ e^{Âᵀs} ds = e^{Âτ} G`. Any quadratic rate `zᵀQz` (`Q` symmetric)
/// integrates to `Σ Q_ij W_ij`: one exponential serves every energy term of the flight.
fn second_moment(flow: &ForcedFlow, start: &Augmented, tau: f64) -> Matrix6<f64> {
    let a = flow.augmented_matrix();
    let mut c = Matrix12::zeros();
    c.fixed_view_mut::<6, 6>(0, 0).copy_from(&(-a));
    c.fixed_view_mut::<6, 6>(0, 6)
        .copy_from(&(start * start.transpose()));
    c.fixed_view_mut::<6, 6>(6, 6).copy_from(&a.transpose());
    let ex = (c * tau).exp();
    ex.fixed_view::<6, 6>(6, 6).transpose() * ex.fixed_view::<6, 6>(0, 6)
}

/// Every orbit of `signature` found by a systematic multi-start over impact phases,
/// deduplicated, viable or not, sorted by `α`.
///
/// The cycle `pT` is cut into `N = max(`[`crate::MIN_GRID`]`, ⌈`[`crate::GRID_PER_OSCILLATION`]` · p ·
/// max(ω, ω_n)/ω⌉)` intervals: [`crate::GRID_PER_OSCILLATION`] points per period of the fastest
/// oscillation of the motion (the forcing or the highest natural frequency `ω_n`). Every
/// ordered tuple `0 < φ₂ < … < φₙ < 1` of grid points is scanned. The phase `α` is not a
/// Newton guess from a coarse grid: for fixed impact times the contact residuals are
/// *linear* in `(cos α, sin α)`, so each tuple's squared residual is scanned on
/// `ALPHA_SCAN = 64` values of `α` for the cost of one cycle. Newton starts from every minimum
/// in `α` of every tuple when there are at most `FULL_START_TUPLES = 5000` tuples, and otherwise
/// from the nodes that are minima over the joint grid of impact phases and `α`.
///
/// Why this grid: each impact time of any orbit lies within `1/32` of the fastest period of
/// the motion from a grid tuple, where `r(t)` near an impact is close to its linearisation,
/// and `α` is then the best one for those times. For `n ≤ 4` impacts and `p ≤ 2` on the
/// paper unit (undamped and damped, `ω` from 0.8 to 3) no refinement of the grid (up to
/// 4 times finer for two impacts, 2 to 3 times for four) found a viable orbit this grid
/// missed; refinement does find a few more *non-viable* solutions, whose basins are smaller
/// than a grid cell (near folds). This is a measured and reasoned claim, not a proof.
///
/// Orbits of a repeated signature (e.g. `+-+-` over 2 periods) include those of its root
/// (`+-` over 1 period) traversed twice: they are solutions too. A start whose Newton
/// iteration fails is dropped silently: most starts lie far from any orbit. The unit and
/// stops are not validated here.
pub fn signature_orbits(
    unit: &Unit,
    stops: &Stops,
    omega: f64,
    signature: &Signature,
) -> Vec<SignatureOrbit> {
    if !(omega.is_finite() && omega > 0.0) {
        return Vec::new();
    }
    let nat = modes(unit)
        .natural_frequencies_squared
        .iter()
        .fold(omega, |m, w2| m.max(w2.sqrt()));
    let grid = grid_intervals(nat, omega, signature.period(), signature.impacts());
    signature_orbits_on_grid(unit, stops, omega, signature, grid)
}

/// [`signature_orbits`] with an explicit number of grid intervals over the cycle. The work
/// and memory grow like the number of tuples, `C(grid − 1, n − 1)`: the caller bounds it.
/// An empty list when `grid` is below the number of impacts or `omega` is not finite and
/// positive.
pub fn signature_orbits_on_grid(
    unit: &Unit,
    stops: &Stops,
    omega: f64,
    signature: &Signature,
    grid: usize,
) -> Vec<SignatureOrbit> {
    let n = signature.impacts();
    if grid < n || !(omega.is_finite() && omega > 0.0) {
        return Vec::new();
    }
    let problem = Problem::new(unit, stops, omega, signature);
    multi_start(
        &problem.equations,
        grid,
        ALPHA_SCAN,
        |alpha, phases, iterations| assemble(&problem, signature, alpha, phases, iterations).ok(),
    )
}
