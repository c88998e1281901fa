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
//! multi-start of [`crate::sequence_search`]; the verdicts here use the unit's own flow.

use crate::cycle_equations::{CycleEquations, ImpactCondition};
use crate::flow::{join, Augmented, ForcedFlow};
use crate::linear::{modes, transmittance_db};
use crate::orbit::{
    eigenvalues, impact, relative_displacement, saltation, Side, Violation, STABILITY_MARGIN,
    VIABILITY_TOLERANCE,
};
use crate::sequence_orbit::{SequenceNewton, SequenceOrbitError};
use crate::sequence_search::{grid_intervals, multi_start};
use crate::sequence_verdicts::energy_reference;
pub use crate::sequence_verdicts::{ENERGY_EXCHANGE_FRACTION, ENERGY_FLOOR};
use crate::signature::Signature;
use crate::symmetric::OrbitError;
use crate::unit::{Stops, Unit};
use nalgebra::{Complex, Matrix2, Matrix4, Matrix6, SMatrix, Vector2, Vector4, U6};

pub use crate::cycle_equations::MIN_FLIGHT;
pub use crate::sequence_orbit::{
    NEWTON_ACCEPTANCE, NEWTON_ITERATIONS, NEWTON_TOLERANCE, STEP_ROUNDING,
};
pub use crate::sequence_search::{
    ALPHA_SCAN, DEDUP_TOLERANCE, FULL_START_TUPLES, GRID_PER_OSCILLATION, MAX_TUPLES, MIN_GRID,
};

type Matrix12 = SMatrix<f64, 12, 12>;

/// The energy balance of a cycle, each term computed on its own.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnergyBalance {
    /// Work done by the base over the cycle, `∫ −(k_o (u_o − u_g) + c_o (u̇_o − u̇_g)) u̇_g dt`.
    pub base_work: f64,
    /// Dissipation of both dashpots, `∫ c_o (u̇_o − u̇_g)² + c_i ṙ² dt`.
    pub dashpot_dissipation: f64,
    /// Impact losses `Σ ½ μ (1 − e²) ṙ⁻²`.
    pub impact_losses: f64,
    /// `½ ∮ (ω u̇ᵀMu̇ + fᵀM⁻¹f / ω) dt`, `f` the base's force on the outer mass: the bound on
    /// the gross energy exchanged of [`crate::ModelEnergy::exchange_bound`].
    pub exchange_bound: f64,
}

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
    /// Every multiplier has modulus `< 1 −` [`STABILITY_MARGIN`].
    pub stable: bool,
    /// The monodromy matrix over the cycle, from just after the first canonical impact.
    pub monodromy: Matrix4<f64>,
    /// The energy balance over the cycle.
    pub energy: EnergyBalance,
    /// `|work − dissipation − impact losses|` relative to the reference of every path
    /// ([`crate::SequenceOrbit::energy_residual`]): the largest of `|work|`,
    /// `dissipation + losses`, [`ENERGY_EXCHANGE_FRACTION`]` · exchange_bound` and
    /// [`ENERGY_FLOOR`]` k_o u_g²`.
    pub energy_residual: f64,
    /// Newton iterations taken to converge.
    pub newton_iterations: usize,
}

/// The cycle's problem: the flow and impact map of the verdicts, and the unit's fixed-size
/// instance of the cycle equations.
struct Problem {
    flow: ForcedFlow,
    g: Matrix2<f64>,
    gap: f64,
    equations: CycleEquations<U6>,
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
        Self {
            flow,
            g,
            gap: stops.gap,
            equations,
        }
    }

    fn cycle(&self) -> f64 {
        self.equations.cycle()
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
/// [`NEWTON_TOLERANCE`] within [`NEWTON_ITERATIONS`].
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
    assemble(
        unit,
        stops,
        &problem,
        signature,
        alpha,
        &phases,
        converged.iteration,
    )
}

/// Builds the orbit at converged unknowns and derives its verdicts.
fn assemble(
    unit: &Unit,
    stops: &Stops,
    problem: &Problem,
    signature: &Signature,
    alpha: f64,
    phases: &[f64],
    newton_iterations: usize,
) -> Result<SignatureOrbit, OrbitError> {
    let n = signature.impacts();
    let sides = signature.sides();
    let flow = &problem.flow;
    let mut x = phases.to_vec();
    x[0] = alpha;
    let e = problem
        .equations
        .evaluate_with(&x, false)
        .ok_or(OrbitError::SingularCycle {
            omega: flow.omega(),
        })?;
    let p0: Vector2<f64> = e.z1.fixed_rows::<2>(4).into();
    // Augmented state just before impact j (impact 0 closes the cycle).
    let before = e.before_impacts();
    let x_before: Vec<Vector4<f64>> = before.iter().map(|z| z.fixed_rows::<4>(0).into()).collect();
    let p_at: Vec<Vector2<f64>> = (0..n)
        .map(|j| {
            if j == 0 {
                p0
            } else {
                before[j].fixed_rows::<2>(4).into()
            }
        })
        .collect();
    let after: Vec<Vector4<f64>> = x_before.iter().map(|x| impact(&problem.g, x)).collect();

    let gap = problem.gap;
    let r_fn = join(&relative_displacement(), &Vector2::zeros());
    let uo_fn = Augmented::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let mut violations = Vec::new();
    let rdot: Vec<f64> = x_before.iter().map(|x| x[3] - x[2]).collect();
    let side_of = |s: i8| if s > 0 { Side::One } else { Side::Two };
    let wrong: Vec<bool> = (0..n).map(|j| sides[j] as f64 * rdot[j] <= 0.0).collect();
    for j in 0..n {
        if wrong[j] {
            violations.push(Violation::WrongApproach {
                side: side_of(sides[j]),
                relative_velocity: rdot[j],
            });
        }
    }
    let tol = VIABILITY_TOLERANCE * gap;
    let mut outer_amplitude: f64 = 0.0;
    let mut energy = EnergyBalance {
        base_work: 0.0,
        dashpot_dissipation: 0.0,
        impact_losses: 0.0,
        exchange_bound: 0.0,
    };
    let (work_q, dissipation_q, exchange_q) = energy_forms(unit, flow.omega());
    for f in 0..n {
        let end = if f + 1 < n { phases[f + 1] } else { 1.0 };
        let duration = (end - phases[f]) * problem.cycle();
        let start = join(&after[f], &p_at[f]);
        let ext = flow.extrema(&start, duration, &[r_fn, uo_fn]);
        outer_amplitude = outer_amplitude.max(ext[1].max.abs()).max(ext[1].min.abs());
        let t0 = phases[f] * problem.cycle();
        let next = (f + 1) % n;
        // An excursion beyond a stop that one of this flight's own impacts on that stop reaches
        // from outside is the flight passing through the stop; any other is a contact the
        // signature does not have.
        let attached = |s: i8| (sides[f] == s && wrong[f]) || (sides[next] == s && wrong[next]);
        for (s, excess, time) in [
            (1i8, ext[0].max - gap, ext[0].argmax),
            (-1i8, -gap - ext[0].min, ext[0].argmin),
        ] {
            if excess > tol {
                let (side, time) = (side_of(s), t0 + time);
                violations.push(if attached(s) {
                    Violation::Penetration { side, time, excess }
                } else {
                    Violation::ExtraImpact { side, time, excess }
                });
            }
        }
        let moment = second_moment(flow, &start, duration);
        let integral = |q: &Matrix6<f64>| q.component_mul(&moment).sum();
        energy.base_work += integral(&work_q);
        energy.dashpot_dissipation += integral(&dissipation_q);
        energy.exchange_bound += integral(&exchange_q);
    }
    let e2 = stops.restitution * stops.restitution;
    energy.impact_losses = rdot
        .iter()
        .map(|v| 0.5 * unit.reduced_mass() * (1.0 - e2) * v * v)
        .sum();
    // The static energy f_cᵀK⁻¹f_c of the base-driven unit: both masses follow the base.
    let static_energy = unit.outer_stiffness * unit.base_amplitude.powi(2);
    let reference = energy_reference(
        energy.base_work,
        energy.dashpot_dissipation.abs() + energy.impact_losses,
        energy.exchange_bound,
        static_energy,
    );
    let energy_residual =
        (energy.base_work - energy.dashpot_dissipation - energy.impact_losses).abs() / reference;

    // Monodromy from just after impact 0: E₀, then S₁, E₁, …, Eₙ₋₁, S₀.
    let mut monodromy = Matrix4::identity();
    for f in 0..n {
        let next = (f + 1) % n;
        let hom = e.flights[f].fixed_view::<4, 4>(0, 0).into_owned();
        let s = saltation(flow, &problem.g, &x_before[next], &p_at[next]);
        monodromy = s * hom * monodromy;
    }
    let floquet_multipliers: Vec<Complex<f64>> = eigenvalues(&monodromy)
        .map(|e| e.to_vec())
        .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); 4]);
    let stable = floquet_multipliers
        .iter()
        .all(|m| m.norm() < 1.0 - STABILITY_MARGIN);

    Ok(SignatureOrbit {
        signature: signature.clone(),
        period: signature.period(),
        omega: flow.omega(),
        impact_phases: phases.to_vec(),
        alpha,
        state_after_impact: after[0],
        states_before_impacts: x_before,
        outer_amplitude,
        transmittance_db: transmittance_db(outer_amplitude, unit.base_amplitude),
        viable: violations.is_empty(),
        violations,
        floquet_multipliers,
        stable,
        monodromy,
        energy,
        energy_residual,
        newton_iterations,
    })
}

/// The quadratic forms `Q` (`rate = zᵀ Q z` on the augmented state) of the base's power, of
/// the dashpots' dissipation and of the exchange bound. With `u_g(t) = u_g p₀`,
/// `u̇_g = −u_g ω p₁`: power `−(k_o (u_o − u_g) + c_o (u̇_o − u̇_g)) u̇_g`, dissipation
/// `c_o (u̇_o − u̇_g)² + c_i (u̇_i − u̇_o)²`, and the general path's bound on the gross
/// exchange ([`crate::ModelEnergy::exchange_bound`]) `½(ω u̇ᵀMu̇ + fᵀM⁻¹f/ω)` with the base's
/// force on the outer mass `f = k_o u_g + c_o u̇_g`.
fn energy_forms(unit: &Unit, omega: f64) -> (Matrix6<f64>, Matrix6<f64>, Matrix6<f64>) {
    let (co, ci) = unit.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
    let (ko, ug) = (unit.outer_stiffness, unit.base_amplitude);
    // Force on the base side of the spring-dashpot, k_o(u_o − u_g) + c_o(u̇_o − u̇_g), as w·z.
    let w = Augmented::new(ko, 0.0, co, 0.0, -ko * ug, co * ug * omega);
    // −u̇_g = u_g ω p₁.
    let v = Augmented::new(0.0, 0.0, 0.0, 0.0, 0.0, ug * omega);
    let work = 0.5 * (v * w.transpose() + w * v.transpose());
    let a = Augmented::new(0.0, 0.0, 1.0, 0.0, 0.0, ug * omega);
    let b = Augmented::new(0.0, 0.0, -1.0, 1.0, 0.0, 0.0);
    let dissipation = a * a.transpose() * co + b * b.transpose() * ci;
    let mut exchange = Matrix6::zeros();
    exchange[(2, 2)] = 0.5 * omega * unit.outer_mass;
    exchange[(3, 3)] = 0.5 * omega * unit.inner_mass;
    // f = k_o u_g p₀ − c_o u_g ω p₁ on the outer mass.
    let force = Vector2::new(ko * ug, -co * ug * omega);
    exchange
        .fixed_view_mut::<2, 2>(4, 4)
        .copy_from(&(force * force.transpose() * (0.5 / (omega * unit.outer_mass))));
    (work, dissipation, exchange)
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
/// The cycle `pT` is cut into `N = max(`[`MIN_GRID`]`, ⌈`[`GRID_PER_OSCILLATION`]` · p ·
/// max(ω, ω_n)/ω⌉)` intervals: [`GRID_PER_OSCILLATION`] points per period of the fastest
/// oscillation of the motion (the forcing or the highest natural frequency `ω_n`). Every
/// ordered tuple `0 < φ₂ < … < φₙ < 1` of grid points is scanned. The phase `α` is not a
/// Newton guess from a coarse grid: for fixed impact times the contact residuals are
/// *linear* in `(cos α, sin α)`, so each tuple's squared residual is scanned on
/// [`ALPHA_SCAN`] values of `α` for the cost of one cycle. Newton starts from every minimum
/// in `α` of every tuple when there are at most [`FULL_START_TUPLES`] tuples, and otherwise
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
    multi_start(&problem.equations, grid, |alpha, phases, iterations| {
        assemble(unit, stops, &problem, signature, alpha, phases, iterations).ok()
    })
}
