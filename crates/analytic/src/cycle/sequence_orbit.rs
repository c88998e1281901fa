//! Periodic orbits of any [`ImpactSequence`] on any [`LinearModel`], by the Nigm–Shabana
//! method generalised: the problem, the Newton solver and its state.
//!
//! A cycle of `p` forcing periods (`pT`) has `m` impacts at `0 = t₁ < t₂ < … < t_m < pT`, impact
//! `j` of pair `k_j` on side `s_j`. The forcing phase at the first impact is `α`. For fixed
//! `x = (α, t₂ … t_m)` everything else is linear: with the augmented flow `Φ_j = exp(Â τ_j)` of
//! flight `j` (from impact `j` to `j + 1`, the last back to the first of the next cycle) and the
//! augmented impact map `Ĝ_j = diag(I_n, G_{k_j}, I_P)` (`P` phase states), the maps `Pre_j = Φ_j Ĝ_j Pre_{j−1}`
//! (`Pre_0 = Φ_0`) carry `(y₁, p₀)`, the state just after the first impact and
//! `p₀ = (cos α, sin α)` (with harmonics, `(cos kα, sin kα)` of every order,
//! [`crate::problem::forcing`]), to the state just before impact `j + 1`. Periodicity
//! `(I − Ψ_xx) y₁ = Ψ_xp p₀`, `Ψ = Ĝ_0 Pre_{m−1}`, fixes `y₁` (the paper's equation 19,
//! generalised), and the `m` contact conditions `w_{k_j}ᵀ u(t_j⁻) = s_j gap` are the residuals:
//! `m` equations in the `m` unknowns `x`.
//!
//! Newton uses exact derivatives of the same closed form: `∂Φ_j/∂τ_j = Â Φ_j` (the vector field
//! at the flight's end), `∂p₀/∂α = (−sin α, cos α)` (`k (−sin kα, cos kα)` per order), and the
//! periodicity solve differentiated implicitly, `dy₁ = (I − Ψ_xx)⁻¹ (dΨ_xx y₁ + dΨ_xp p₀ + Ψ_xp dp₀)`. No finite differences.
//!
//! A model with rigid modes (free bodies, [`crate::problem::rigid`]) has a singular
//! `I − Ψ_xx`: its periodicity solve is bordered by the contact conditions of the first impacts
//! that see the rigid modes, and the free bodies' drift over the cycle becomes a residual in
//! their place (the formulation is in [`crate::cycle_equations`]); the unknowns and the number of
//! equations are those of a model without.
//!
//! Layout: [`crate::cycle_equations::CycleEquations`] evaluates residuals and Jacobian for any
//! model, on stack matrices for the unit and heap matrices for a chain; [`SequenceProblem`] is
//! a model's instance; [`SequenceNewton`] (the one solver of both) goes
//! [`SequenceNewton::init`], [`SequenceNewton::next_iter`] until [`SequenceNewton::terminate`]
//! says why it stops; [`NewtonState`] is what one iteration hands to the next. The verdicts on a
//! converged cycle are in [`crate::sequence_verdicts`].

use crate::cycle_equations::{CycleEquations, CycleEvaluation, ImpactCondition};
use crate::model::LinearModel;
use crate::sequence::{EventKind, ImpactKind, ImpactSequence, PairImpact, SequenceError};
use nalgebra::allocator::Allocator;
use nalgebra::{DMatrix, DVector, DefaultAllocator, Dim, DimMin, Dyn};
use thiserror::Error;

/// Cap on Newton iterations. From a start inside the basin Newton converges quadratically in
/// well under ten steps; the cap bounds starts that wander (most multi-start points do not
/// lie near an orbit) and is the only bound on the work of one solve.
pub const NEWTON_ITERATIONS: usize = 40;

/// Newton has converged when the largest contact residual is below this fraction of the
/// motion's size (the largest stop and displacement just after the first impact): about 450
/// `ε`, the rounding left by a chain of a few exponentials and a periodicity solve.
pub(crate) const NEWTON_TOLERANCE: f64 = 1e-13;

/// Fallback acceptance: when the Newton step has shrunk to rounding (`STEP_ROUNDING = 1e-15`) the
/// residual cannot be reduced further; it is then accepted if below this fraction of the
/// motion's size (two orders looser than `NEWTON_TOLERANCE = 1e-13`, for ill-conditioned cycles).
pub const NEWTON_ACCEPTANCE: f64 = 1e-11;

/// A Newton step below this (in radians of `α` and in fractions of the cycle) no longer moves
/// the unknowns beyond a few ulps of numbers of order one.
pub(crate) const STEP_ROUNDING: f64 = 1e-15;

/// Halvings of the Newton step when it would reorder the impacts or raise the residual's
/// 2-norm: `2⁻¹⁰ ≈ 1e-3` of a step; beyond that the direction is useless and the start is
/// abandoned. (30 halvings cost the multi-start 2–3 times more and found the same viable
/// orbits on the paper unit; see [`crate::signature_orbits`].)
pub(crate) const LINE_SEARCH_HALVINGS: usize = 10;

/// Whether `guess = (α, φ₂, …, φ_n)` is a usable start for `n` impacts: `n` finite entries
/// with the impact phases ordered in `(0, 1)` (`α` is free).
pub(crate) fn is_ordered_guess(guess: &[f64], n: usize) -> bool {
    guess.len() == n
        && guess.iter().all(|v| v.is_finite())
        && (1..n).all(|i| guess[i] > if i == 1 { 0.0 } else { guess[i - 1] })
        && (n == 1 || guess[n - 1] < 1.0)
}

/// Why an orbit of an impact sequence could not be computed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SequenceOrbitError {
    /// The sequence does not fit the model (it names a pair the model lacks).
    #[error(transparent)]
    Sequence(#[from] SequenceError),
    /// The forcing frequency is not finite and positive.
    #[error("omega = {omega} is out of range: must be finite and > 0")]
    InvalidFrequency {
        /// The rejected frequency.
        omega: f64,
    },
    /// A guess is not `(α, φ₂, …, φ_m)` with finite entries and `0 < φ₂ < … < φ_m < 1`.
    #[error(
        "guess has {len} entries: must be alpha and {impacts} - 1 finite impact phases, \
         ordered in (0, 1)"
    )]
    InvalidGuess {
        /// Number of impacts of the sequence.
        impacts: usize,
        /// Number of entries given.
        len: usize,
    },
    /// The model has rigid modes (free bodies) that no impact of the sequence restrains: the
    /// offset along them is not fixed by any contact condition.
    #[error(
        "the impacts of the sequence restrain {restrained} of the model's {modes} rigid modes: \
         every rigid mode must be seen (w'phi != 0) by the pair of some impact"
    )]
    UnrestrainedRigidMode {
        /// Number of independent rigid directions the sequence's impacts see.
        restrained: usize,
        /// Number of rigid modes of the model.
        modes: usize,
    },
    /// The periodicity solve or the Newton Jacobian is singular.
    #[error("the impact-sequence cycle equations are singular at omega = {omega}")]
    SingularCycle {
        /// The frequency.
        omega: f64,
    },
    /// Newton did not converge.
    #[error(
        "Newton on the impact-sequence equations did not converge at omega = {omega} \
         (residual {residual:e} after {iterations} iterations)"
    )]
    NoConvergence {
        /// The frequency.
        omega: f64,
        /// The largest contact residual reached.
        residual: f64,
        /// Iterations done.
        iterations: usize,
    },
}

/// The cycle equations of one sequence on one model at one frequency: the model's instance of
/// [`CycleEquations`] (heap matrices of the model's augmented dimension).
#[derive(Debug, Clone)]
pub struct SequenceProblem<'a> {
    model: &'a LinearModel,
    sequence: &'a ImpactSequence,
    /// The events of the cycle equations: one per rigid impact, entry and exit per contact
    /// phase ([`ImpactSequence::events`]).
    events: Vec<(PairImpact, EventKind)>,
    equations: CycleEquations<Dyn>,
}

impl<'a> SequenceProblem<'a> {
    /// The cycle equations of `sequence` on `model` at `omega`.
    ///
    /// For a model with rigid modes the equations are bordered: the anchors are the first
    /// impacts (in sequence order) whose pairs' projections `Φᵀw` are independent (Gram–Schmidt,
    /// a projection counting when it keeps more than [`crate::model::RIGID_COUPLING`] of `|w|`),
    /// the shifts `(Φ, 0, 0)`.
    ///
    /// A sequence with contact phases (compliant pairs, `0+c`) has two events per contact
    /// phase, its entry and its exit, each an unknown time with the pair's contact condition;
    /// the flight between them is the contact system's (see `contact_flights`), and the
    /// augmented state carries the constant phase pair of order 0 that holds the contact's
    /// constant force. A sticking phase (`0+s`, a rigid pair of restitution 0) has two events,
    /// its landing impact (the pair's condition) and its release (the release functional of
    /// [`LinearModel`], the pair's free relative acceleration over `ω²`, zero); the flight
    /// between them is the flow held on the stop, `wᵀü = 0`.
    ///
    /// # Errors
    /// [`SequenceOrbitError::InvalidFrequency`] unless `omega` is finite and positive;
    /// [`SequenceOrbitError::Sequence`] when the sequence names a pair the model lacks or an
    /// impact whose kind (contact phase, sticking phase or rigid impact) is not its pair's;
    /// [`SequenceOrbitError::UnrestrainedRigidMode`] when the model has rigid modes that the
    /// sequence's impacts do not all see.
    pub fn new(
        model: &'a LinearModel,
        omega: f64,
        sequence: &'a ImpactSequence,
    ) -> Result<Self, SequenceOrbitError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(SequenceOrbitError::InvalidFrequency { omega });
        }
        sequence.check(model)?;
        let n = model.dofs();
        let events = sequence.events();
        let contact = sequence.has_contact_phases();
        let size = model.augmented_size() + if contact { 2 } else { 0 };
        let impacts = events
            .iter()
            .map(|(impact, kind)| {
                let mut g_hat = DMatrix::identity(size, size);
                if *kind == EventKind::Impact {
                    g_hat
                        .view_mut((n, n), (n, n))
                        .copy_from(&model.impact_map(impact.pair));
                }
                let pair = &model.pairs()[impact.pair];
                if *kind == EventKind::Release {
                    return ImpactCondition {
                        impact_map: g_hat,
                        contact: model.release_functional(omega, impact.pair),
                        stop: 0.0,
                    };
                }
                let mut h = DVector::zeros(size);
                h.rows_mut(0, n).copy_from(&pair.direction);
                let stop = if impact.side == 1 {
                    pair.gap_side1
                } else {
                    -pair.gap_side2
                };
                ImpactCondition {
                    impact_map: g_hat,
                    contact: h,
                    stop,
                }
            })
            .collect();
        let augmented = if contact {
            model.compliant_augmented(omega)
        } else {
            model.augmented_matrix(omega)
        };
        let mut equations = CycleEquations::new(
            omega,
            augmented,
            impacts,
            sequence_symmetries(&events),
            f64::from(sequence.period()) * std::f64::consts::TAU / omega,
        );
        if contact {
            let mut orders = model.forcing().orders();
            orders.push(0);
            equations = equations.with_forcing_orders(&orders);
            let increments = events
                .iter()
                .map(|(impact, kind)| match (kind, impact.kind) {
                    (EventKind::Entry, _) => {
                        Some(model.contact_increment(impact.pair, impact.side))
                    }
                    (EventKind::Impact, ImpactKind::Stick) => {
                        Some(model.stick_increment(omega, impact.pair))
                    }
                    _ => None,
                })
                .collect();
            equations = equations.with_contact_flights(increments);
        } else if !model.forcing().harmonics.is_empty() {
            equations = equations.with_forcing_orders(&model.forcing().orders());
        }
        if model.has_rigid_modes() {
            let rigid = model.rigid_modes();
            let anchors = anchors(model, &events)?;
            let mut shifts = DMatrix::zeros(size, rigid.ncols());
            shifts.view_mut((0, 0), (n, rigid.ncols())).copy_from(rigid);
            equations = equations.with_rigid_border(shifts, anchors);
        }
        Ok(Self {
            model,
            sequence,
            events,
            equations,
        })
    }

    /// The events of the cycle equations, in time order: `(impact, kind)` of each (one per
    /// rigid impact, entry and exit per contact phase).
    pub(crate) fn events(&self) -> &[(PairImpact, EventKind)] {
        &self.events
    }

    /// The model.
    pub fn model(&self) -> &LinearModel {
        self.model
    }

    /// The sequence.
    pub fn sequence(&self) -> &ImpactSequence {
        self.sequence
    }

    /// The forcing frequency.
    pub fn omega(&self) -> f64 {
        self.equations.omega()
    }

    /// Length of the cycle, `pT`.
    pub fn cycle(&self) -> f64 {
        self.equations.cycle()
    }

    /// The cycle equations.
    pub fn equations(&self) -> &CycleEquations<Dyn> {
        &self.equations
    }
}

/// The anchors of a model with rigid modes `Φ`: the first events whose pairs' `Φᵀw` are
/// independent, one per rigid mode.
fn anchors(
    model: &LinearModel,
    events: &[(PairImpact, EventKind)],
) -> Result<Vec<usize>, SequenceOrbitError> {
    let rigid = model.rigid_modes();
    let modes = rigid.ncols();
    let mut basis: Vec<DVector<f64>> = Vec::with_capacity(modes);
    let mut anchors = Vec::with_capacity(modes);
    for (j, (impact, _)) in events.iter().enumerate() {
        if anchors.len() == modes {
            break;
        }
        let w = &model.pairs()[impact.pair].direction;
        let mut b = rigid.transpose() * w;
        for q in &basis {
            let along = q.dot(&b);
            b -= q * along;
        }
        if crate::model::couples(&b, w) {
            basis.push(b.normalize());
            anchors.push(j);
        }
    }
    if anchors.len() < modes {
        return Err(SequenceOrbitError::UnrestrainedRigidMode {
            restrained: anchors.len(),
            modes,
        });
    }
    Ok(anchors)
}

/// The rotations `k` of the cycle's events that map them onto themselves (starting the cycle
/// at event `k` gives the same sequence). Always contains 0.
fn sequence_symmetries(impacts: &[(PairImpact, EventKind)]) -> Vec<usize> {
    let m = impacts.len();
    (0..m)
        .filter(|&k| (0..m).all(|j| impacts[(j + k) % m] == impacts[j]))
        .collect()
}

/// What one Newton iteration hands to the next.
#[derive(Debug, Clone)]
pub struct NewtonState<D: Dim>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    /// The unknowns `x = (α, φ₂ … φ_m)`.
    pub unknowns: Vec<f64>,
    /// The cycle at `unknowns`.
    pub evaluation: CycleEvaluation<D>,
    /// Largest contact residual.
    pub residual: f64,
    /// 2-norm of the residuals (the line search's merit).
    pub merit: f64,
    /// Iterations done.
    pub iteration: usize,
    /// True when the last step could not lower the merit (or was below rounding).
    pub stalled: bool,
}

/// Why Newton stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Termination {
    /// The residual is below the tolerance (or, stalled, below the acceptance).
    Converged,
    /// Stalled above the acceptance, too many iterations, or a non-finite residual.
    Failed,
}

/// Newton with a backtracking line search on the contact residuals of [`CycleEquations`] (the
/// unit's and every model's): the settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SequenceNewton {
    /// Cap on iterations.
    pub max_iterations: usize,
    /// Converged when the largest residual is below this fraction of the motion's size.
    pub tolerance: f64,
    /// When stalled, accepted when below this fraction of the motion's size.
    pub acceptance: f64,
}

impl Default for SequenceNewton {
    /// [`NEWTON_ITERATIONS`], `NEWTON_TOLERANCE = 1e-13`, [`NEWTON_ACCEPTANCE`].
    fn default() -> Self {
        Self {
            max_iterations: NEWTON_ITERATIONS,
            tolerance: NEWTON_TOLERANCE,
            acceptance: NEWTON_ACCEPTANCE,
        }
    }
}

fn singular(equations_omega: f64) -> SequenceOrbitError {
    SequenceOrbitError::SingularCycle {
        omega: equations_omega,
    }
}

/// The cycle at `x` with its Jacobian, or [`SequenceOrbitError::SingularCycle`].
fn evaluate<D: DimMin<D, Output = D>>(
    equations: &CycleEquations<D>,
    x: &[f64],
) -> Result<CycleEvaluation<D>, SequenceOrbitError>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    equations
        .evaluate_with(x, true)
        .ok_or_else(|| singular(equations.omega()))
}

impl SequenceNewton {
    /// The state at the guess `x = (α, φ₂ … φ_m)`.
    ///
    /// # Errors
    /// [`SequenceOrbitError::InvalidGuess`] unless the guess has one finite entry per impact
    /// with ordered phases in `(0, 1)`; [`SequenceOrbitError::SingularCycle`] from the
    /// evaluation.
    pub fn init<D: DimMin<D, Output = D>>(
        &self,
        equations: &CycleEquations<D>,
        guess: &[f64],
    ) -> Result<NewtonState<D>, SequenceOrbitError>
    where
        DefaultAllocator: Allocator<D, D> + Allocator<D>,
    {
        let m = equations.impacts();
        if !is_ordered_guess(guess, m) {
            return Err(SequenceOrbitError::InvalidGuess {
                impacts: m,
                len: guess.len(),
            });
        }
        let evaluation = evaluate(equations, guess)?;
        Ok(state(guess.to_vec(), evaluation, 0, false))
    }

    /// One damped Newton step: the full step, halved up to `LINE_SEARCH_HALVINGS = 10` times
    /// until it keeps the impacts ordered and lowers the merit; `stalled` when none does or
    /// the step is below `STEP_ROUNDING = 1e-15`.
    ///
    /// # Errors
    /// [`SequenceOrbitError::SingularCycle`] when the Jacobian is singular.
    pub fn next_iter<D: DimMin<D, Output = D>>(
        &self,
        equations: &CycleEquations<D>,
        current: NewtonState<D>,
    ) -> Result<NewtonState<D>, SequenceOrbitError>
    where
        DefaultAllocator: Allocator<D, D> + Allocator<D>,
    {
        let step = newton_step(equations, &current)?;
        let iteration = current.iteration + 1;
        if step.amax() <= STEP_ROUNDING {
            return Ok(NewtonState {
                stalled: true,
                iteration,
                ..current
            });
        }
        let mut lambda = 1.0;
        for _ in 0..LINE_SEARCH_HALVINGS {
            let trial: Vec<f64> = current
                .unknowns
                .iter()
                .zip(step.iter())
                .map(|(a, d)| a + lambda * d)
                .collect();
            if equations.ordered(&trial) {
                if let Ok(e) = evaluate(equations, &trial) {
                    if e.residual.norm() < current.merit {
                        return Ok(state(trial, e, iteration, false));
                    }
                }
            }
            lambda *= 0.5;
        }
        Ok(NewtonState {
            stalled: true,
            iteration,
            ..current
        })
    }

    /// Whether to stop, and why; `None` to go on.
    pub fn terminate<D: DimMin<D, Output = D>>(
        &self,
        equations: &CycleEquations<D>,
        s: &NewtonState<D>,
    ) -> Option<Termination>
    where
        DefaultAllocator: Allocator<D, D> + Allocator<D>,
    {
        let scale = equations.scale(&s.evaluation.z1);
        if !s.residual.is_finite() {
            Some(Termination::Failed)
        } else if s.residual <= self.tolerance * scale {
            Some(Termination::Converged)
        } else if s.stalled {
            Some(if s.residual <= self.acceptance * scale {
                Termination::Converged
            } else {
                Termination::Failed
            })
        } else if s.iteration >= self.max_iterations {
            Some(Termination::Failed)
        } else {
            None
        }
    }

    /// Runs Newton from `guess` to convergence; a converged state is polished by one more
    /// full step, kept only if it lowers the merit (quadratic convergence down to rounding).
    ///
    /// # Errors
    /// As [`SequenceNewton::init`] and [`SequenceNewton::next_iter`];
    /// [`SequenceOrbitError::NoConvergence`] when it stops without converging.
    pub fn solve<D: DimMin<D, Output = D>>(
        &self,
        equations: &CycleEquations<D>,
        guess: &[f64],
    ) -> Result<NewtonState<D>, SequenceOrbitError>
    where
        DefaultAllocator: Allocator<D, D> + Allocator<D>,
    {
        let mut s = self.init(equations, guess)?;
        loop {
            match self.terminate(equations, &s) {
                Some(Termination::Converged) => return Ok(polish(equations, s)),
                Some(Termination::Failed) => {
                    return Err(SequenceOrbitError::NoConvergence {
                        omega: equations.omega(),
                        residual: s.residual,
                        iterations: s.iteration,
                    })
                }
                None => s = self.next_iter(equations, s)?,
            }
        }
    }
}

fn state<D: Dim>(
    unknowns: Vec<f64>,
    evaluation: CycleEvaluation<D>,
    iteration: usize,
    stalled: bool,
) -> NewtonState<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    NewtonState {
        unknowns,
        residual: evaluation.residual.amax(),
        merit: evaluation.residual.norm(),
        evaluation,
        iteration,
        stalled,
    }
}

fn newton_step<D: DimMin<D, Output = D>>(
    equations: &CycleEquations<D>,
    s: &NewtonState<D>,
) -> Result<DVector<f64>, SequenceOrbitError>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    s.evaluation
        .jacobian
        .clone()
        .lu()
        .solve(&(-&s.evaluation.residual))
        .ok_or_else(|| singular(equations.omega()))
}

/// One more full Newton step from a converged state, kept if it lowers the merit.
fn polish<D: DimMin<D, Output = D>>(
    equations: &CycleEquations<D>,
    s: NewtonState<D>,
) -> NewtonState<D>
where
    DefaultAllocator: Allocator<D, D> + Allocator<D>,
{
    let Ok(step) = newton_step(equations, &s) else {
        return s;
    };
    let trial: Vec<f64> = s
        .unknowns
        .iter()
        .zip(step.iter())
        .map(|(a, d)| a + d)
        .collect();
    if equations.ordered(&trial) {
        if let Ok(e) = evaluate(equations, &trial) {
            if e.residual.norm() < s.merit {
                return state(trial, e, s.iteration + 1, false);
            }
        }
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{damped_paper_unit, paper_stops};

    /// `model` with harmonics of orders 2 and 3 added to its forcing, each with every part
    /// (cosine, sine, sine per `ω` on different coordinates) and a phase, so that every column
    /// of the harmonics' forcing and its `ω`-rate is exercised.
    fn with_harmonics(model: &LinearModel) -> LinearModel {
        let n = model.dofs();
        let on = |k: usize, v: f64| DVector::from_fn(n, |i, _| if i == k % n { v } else { 0.0 });
        let mut forcing = model.forcing().clone();
        forcing.harmonics = vec![
            crate::model::Harmonic {
                order: 3,
                cosine: on(0, 0.7),
                sine: on(1, 0.2),
                sine_per_omega: on(0, -0.05),
                phase: 0.4,
            },
            crate::model::Harmonic {
                order: 2,
                cosine: on(2, 0.3),
                sine: on(0, -0.4),
                sine_per_omega: on(1, 0.08),
                phase: -1.1,
            },
        ];
        LinearModel::new(
            model.mass().clone(),
            model.damping().clone(),
            model.stiffness().clone(),
            forcing,
            model.pairs().to_vec(),
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }

    /// The exact Jacobian against central differences of the residuals (a check of the
    /// derivation only; the solver never differences), on the two-cell chain and on the same
    /// chain with harmonics (the `α` column then carries `k (−sin kα, cos kα)` per order):
    /// with step `1e-6` the difference quotient's truncation is `O(1e-12)` and its rounding
    /// `O(1e-10)` of the residuals' size.
    #[test]
    fn jacobian_is_the_derivative_of_the_residuals() {
        let chain = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2)
            .unwrap_or_else(|e| panic!("{e}"));
        for model in [with_harmonics(&chain), chain] {
            let sequence =
                ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap_or_else(|e| panic!("{e}"));
            let problem =
                SequenceProblem::new(&model, 2.3, &sequence).unwrap_or_else(|e| panic!("{e}"));
            let x = [0.7, 0.21, 0.48, 0.83];
            let equations = problem.equations();
            let exact = evaluate(equations, &x)
                .unwrap_or_else(|e| panic!("{e}"))
                .jacobian;
            let step = 1e-6;
            let scale = exact.amax();
            for i in 0..4 {
                let shifted = |d: f64| {
                    let mut y = x;
                    y[i] += d;
                    evaluate(equations, &y)
                        .unwrap_or_else(|e| panic!("{e}"))
                        .residual
                };
                let quotient = (shifted(step) - shifted(-step)) / (2.0 * step);
                for j in 0..4 {
                    assert!(
                        (quotient[j] - exact[(j, i)]).abs() <= 1e-7 * scale,
                        "{} phase states: ∂r{j}/∂x{i}: {} vs {}",
                        model.phase_states(),
                        quotient[j],
                        exact[(j, i)]
                    );
                }
            }
        }
    }

    /// A primary mass on a spring and dashpot with `free` free masses, each in a clearance of
    /// the primary (pair `k`: direction `e_{k+1} − e_0`, gaps 1 and 0.8).
    fn free_masses(free: usize) -> LinearModel {
        let n = free + 1;
        let diagonal = |first: f64, rest: f64| {
            DMatrix::from_diagonal(&DVector::from_fn(
                n,
                |i, _| if i == 0 { first } else { rest },
            ))
        };
        let pairs = (1..n)
            .map(|k| {
                let mut w = DVector::zeros(n);
                w[0] = -1.0;
                w[k] = 1.0;
                crate::model::ContactPair {
                    direction: w,
                    gap_side1: 1.0,
                    gap_side2: 0.8,
                    restitution: 0.7,
                }
            })
            .collect();
        let mut cosine = DVector::zeros(n);
        cosine[0] = 1.0;
        let mut sine = DVector::zeros(n);
        sine[0] = 0.3;
        LinearModel::new(
            diagonal(1.0, 0.15),
            diagonal(0.05, 0.0),
            diagonal(1.0, 0.0),
            crate::model::HarmonicForcing {
                cosine,
                sine,
                sine_per_omega: DVector::zeros(n),
                harmonics: Vec::new(),
            },
            pairs,
        )
        .unwrap_or_else(|e| panic!("{e}"))
    }

    /// The bordered residuals of models with rigid modes (one free mass, anchor the first
    /// impact; two free masses, anchors the first two impacts, the second's border row moving
    /// with the impact times; one free mass with harmonics): the exact Jacobian in `x` and its
    /// `ω` column against central differences, step `1e-6`, truncation `O(1e-12)` and rounding
    /// `O(1e-10)` of the residuals' size, as for the chain.
    #[test]
    fn bordered_jacobian_is_the_derivative_of_the_residuals() {
        let cases = [
            (free_masses(1), "0+ 0-", vec![0.7, 0.43]),
            (free_masses(2), "0+ 1+ 0- 1-", vec![-0.4, 0.2, 0.55, 0.8]),
            (with_harmonics(&free_masses(1)), "0+ 0-", vec![0.7, 0.43]),
        ];
        for (model, text, x) in cases {
            let sequence = ImpactSequence::parse(text, 1).unwrap_or_else(|e| panic!("{e}"));
            let omega = 1.3;
            let problem =
                SequenceProblem::new(&model, omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
            assert!(problem.equations().is_bordered());
            let m = x.len();
            let exact = problem
                .equations()
                .evaluate_in_omega(&x, &model.augmented_rate())
                .unwrap_or_else(|| panic!("singular"))
                .jacobian;
            let in_x = evaluate(problem.equations(), &x)
                .unwrap_or_else(|e| panic!("{e}"))
                .jacobian;
            assert!((exact.columns(0, m) - &in_x).amax() <= 1e-12 * in_x.amax());
            let scale = exact.amax();
            let step = 1e-6;
            for i in 0..=m {
                let at = |d: f64| {
                    let mut y = x.clone();
                    let w = if i < m {
                        y[i] += d;
                        omega
                    } else {
                        omega + d
                    };
                    let p = SequenceProblem::new(&model, w, &sequence)
                        .unwrap_or_else(|e| panic!("{e}"));
                    evaluate(p.equations(), &y)
                        .unwrap_or_else(|e| panic!("{e}"))
                        .residual
                };
                let quotient = (at(step) - at(-step)) / (2.0 * step);
                for j in 0..m {
                    assert!(
                        (quotient[j] - exact[(j, i)]).abs() <= 1e-7 * scale,
                        "{text}: ∂r{j}/∂x{i}: {} vs {}",
                        quotient[j],
                        exact[(j, i)]
                    );
                }
            }
        }
    }

    /// The exact `ω` column of the Jacobian against a central difference of the residuals in
    /// `ω` (phases fixed as fractions of the cycle), on the two-cell chain and on the same
    /// chain with harmonics (whose `dÂ/dω` carries `k M⁻¹f_ω,k (sin φ_k, cos φ_k)` and the
    /// rotations' `kJ`): step `1e-6`, truncation `O(1e-12)` and rounding `O(1e-10)` of the
    /// residuals' size, as above.
    #[test]
    fn omega_column_is_the_derivative_of_the_residuals() {
        let chain = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2)
            .unwrap_or_else(|e| panic!("{e}"));
        for model in [with_harmonics(&chain), chain] {
            omega_column_of(&model);
        }
    }

    fn omega_column_of(model: &LinearModel) {
        let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap_or_else(|e| panic!("{e}"));
        let omega = 2.3;
        let x = [0.7, 0.21, 0.48, 0.83];
        let problem =
            SequenceProblem::new(model, omega, &sequence).unwrap_or_else(|e| panic!("{e}"));
        let exact = problem
            .equations()
            .evaluate_in_omega(&x, &model.augmented_rate())
            .unwrap_or_else(|| panic!("singular"))
            .jacobian;
        assert_eq!(exact.shape(), (4, 5));
        let in_x = evaluate(problem.equations(), &x)
            .unwrap_or_else(|e| panic!("{e}"))
            .jacobian;
        assert!((exact.columns(0, 4) - &in_x).amax() <= 1e-12 * in_x.amax());
        let step = 1e-6;
        let at = |w: f64| {
            let p = SequenceProblem::new(model, w, &sequence).unwrap_or_else(|e| panic!("{e}"));
            evaluate(p.equations(), &x)
                .unwrap_or_else(|e| panic!("{e}"))
                .residual
        };
        let quotient = (at(omega + step) - at(omega - step)) / (2.0 * step);
        let scale = exact.amax();
        for j in 0..4 {
            assert!(
                (quotient[j] - exact[(j, 4)]).abs() <= 1e-7 * scale,
                "∂r{j}/∂ω: {} vs {}",
                quotient[j],
                exact[(j, 4)]
            );
        }
    }
}
