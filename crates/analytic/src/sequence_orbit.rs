//! Periodic orbits of any [`ImpactSequence`] on any [`LinearModel`], by the Nigm–Shabana
//! method generalised: the problem, the Newton solver and its state.
//!
//! A cycle of `p` forcing periods (`pT`) has `m` impacts at `0 = t₁ < t₂ < … < t_m < pT`, impact
//! `j` of pair `k_j` on side `s_j`. The forcing phase at the first impact is `α`. For fixed
//! `x = (α, t₂ … t_m)` everything else is linear: with the augmented flow `Φ_j = exp(Â τ_j)` of
//! flight `j` (from impact `j` to `j + 1`, the last back to the first of the next cycle) and the
//! augmented impact map `Ĝ_j = diag(I_n, G_{k_j}, I₂)`, the maps `Pre_j = Φ_j Ĝ_j Pre_{j−1}`
//! (`Pre_0 = Φ_0`) carry `(y₁, p₀)`, the state just after the first impact and
//! `p₀ = (cos α, sin α)`, to the state just before impact `j + 1`. Periodicity
//! `(I − Ψ_xx) y₁ = Ψ_xp p₀`, `Ψ = Ĝ_0 Pre_{m−1}`, fixes `y₁` (the paper's equation 19,
//! generalised), and the `m` contact conditions `w_{k_j}ᵀ u(t_j⁻) = s_j gap` are the residuals:
//! `m` equations in the `m` unknowns `x`.
//!
//! Newton uses exact derivatives of the same closed form: `∂Φ_j/∂τ_j = Â Φ_j` (the vector field
//! at the flight's end), `∂p₀/∂α = (−sin α, cos α)`, and the periodicity solve differentiated
//! implicitly, `dy₁ = (I − Ψ_xx)⁻¹ (dΨ_xx y₁ + dΨ_xp p₀ + Ψ_xp dp₀)`. No finite differences.
//!
//! Layout: [`SequenceProblem`] evaluates residuals and Jacobian; [`SequenceNewton`] (the
//! solver) goes [`SequenceNewton::init`], [`SequenceNewton::next_iter`] until
//! [`SequenceNewton::terminate`] says why it stops; [`NewtonState`] is what one iteration
//! hands to the next. The verdicts on a converged cycle are in [`crate::sequence_verdicts`].

use crate::cycle::{
    is_ordered_guess, LINE_SEARCH_HALVINGS, MIN_FLIGHT, NEWTON_ACCEPTANCE, NEWTON_ITERATIONS,
    NEWTON_TOLERANCE, STEP_ROUNDING,
};
use crate::model::LinearModel;
use crate::sequence::{ImpactSequence, SequenceError};
use nalgebra::{DMatrix, DVector};
use thiserror::Error;

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

/// The cycle equations of one sequence on one model at one frequency.
#[derive(Debug, Clone)]
pub struct SequenceProblem<'a> {
    model: &'a LinearModel,
    sequence: &'a ImpactSequence,
    omega: f64,
    augmented: DMatrix<f64>,
    /// `Ĝ_j` of each impact, in sequence order.
    g_hats: Vec<DMatrix<f64>>,
    /// `h_j = (w_{k_j}, 0, 0)`: the augmented gradient of impact `j`'s pair coordinate.
    contacts: Vec<DVector<f64>>,
    /// `s_j gap` of each impact: where its pair coordinate must be.
    stops: Vec<f64>,
    cycle: f64,
}

/// The cycle evaluated at one `x = (α, φ₂ … φ_m)`.
#[derive(Debug, Clone)]
pub struct SequenceEvaluation {
    /// `Φ_j` of each flight.
    pub flights: Vec<DMatrix<f64>>,
    /// `Pre_j`: from `(y₁, p₀)` to the augmented state just before impact `j + 1` (impact `m`
    /// being the first impact of the next cycle).
    pub pre: Vec<DMatrix<f64>>,
    /// State `(u, u̇)` just after the first impact.
    pub y1: DVector<f64>,
    /// `p₀ = (cos α, sin α)`.
    pub p0: DVector<f64>,
    /// Contact residuals `w_{k_j}ᵀ u(t_j⁻) − s_j gap`, in sequence order.
    pub residual: DVector<f64>,
    /// `∂ residual / ∂ (α, φ₂ … φ_m)`, `φ` the impact times as fractions of the cycle.
    pub jacobian: DMatrix<f64>,
}

impl<'a> SequenceProblem<'a> {
    /// The cycle equations of `sequence` on `model` at `omega`.
    ///
    /// # Errors
    /// [`SequenceOrbitError::InvalidFrequency`] unless `omega` is finite and positive;
    /// [`SequenceOrbitError::Sequence`] when the sequence names a pair the model lacks.
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
        let size = 2 * n + 2;
        let mut g_hats = Vec::new();
        let mut contacts = Vec::new();
        let mut stops = Vec::new();
        for impact in sequence.impacts() {
            let mut g_hat = DMatrix::identity(size, size);
            g_hat
                .view_mut((n, n), (n, n))
                .copy_from(&model.impact_map(impact.pair));
            g_hats.push(g_hat);
            let pair = &model.pairs()[impact.pair];
            let mut h = DVector::zeros(size);
            h.rows_mut(0, n).copy_from(&pair.direction);
            contacts.push(h);
            stops.push(if impact.side == 1 {
                pair.gap_side1
            } else {
                -pair.gap_side2
            });
        }
        Ok(Self {
            model,
            sequence,
            omega,
            augmented: model.augmented_matrix(omega),
            g_hats,
            contacts,
            stops,
            cycle: f64::from(sequence.period()) * std::f64::consts::TAU / omega,
        })
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
        self.omega
    }

    /// Length of the cycle, `pT`.
    pub fn cycle(&self) -> f64 {
        self.cycle
    }

    /// `Ĝ_j = diag(I_n, G_{k_j}, I₂)` of each impact, in sequence order.
    pub fn impact_matrices(&self) -> &[DMatrix<f64>] {
        &self.g_hats
    }

    /// `h_j = (w_{k_j}, 0, 0)` of each impact: its pair coordinate as a functional of the
    /// augmented state.
    pub fn contact_functionals(&self) -> &[DVector<f64>] {
        &self.contacts
    }

    /// `s_j gap` of each impact: where its pair coordinate must be.
    pub fn contact_positions(&self) -> &[f64] {
        &self.stops
    }

    /// Number of impacts `m`, also the number of unknowns.
    pub fn impacts(&self) -> usize {
        self.stops.len()
    }

    /// The impact phases `(0, φ₂ … φ_m)` of the unknowns `x = (α, φ₂ … φ_m)`.
    pub fn phases(x: &[f64]) -> Vec<f64> {
        let mut p = x.to_vec();
        if let Some(first) = p.first_mut() {
            *first = 0.0;
        }
        p
    }

    /// Whether the unknowns keep every flight longer than [`MIN_FLIGHT`] of the cycle.
    pub fn ordered(&self, x: &[f64]) -> bool {
        let m = self.impacts();
        (1..m).all(|i| {
            let prev = if i == 1 { 0.0 } else { x[i - 1] };
            x[i] - prev > MIN_FLIGHT
        }) && (m == 1 || 1.0 - x[m - 1] > MIN_FLIGHT)
    }

    /// Size of the motion against which residuals are measured: the largest gap the sequence
    /// hits and the largest displacement just after the first impact.
    pub fn scale(&self, y1: &DVector<f64>) -> f64 {
        let n = self.model.dofs();
        let gaps = self.stops.iter().fold(0.0, |a: f64, s| a.max(s.abs()));
        y1.rows(0, n).iter().fold(gaps, |a, v| a.max(v.abs()))
    }

    /// Residuals and their exact Jacobian at `x = (α, φ₂ … φ_m)`.
    ///
    /// # Errors
    /// [`SequenceOrbitError::SingularCycle`] when `I − Ψ_xx` is singular.
    ///
    /// # Panics
    /// If `x` does not have one entry per impact.
    pub fn evaluate(&self, x: &[f64]) -> Result<SequenceEvaluation, SequenceOrbitError> {
        let m = self.impacts();
        assert_eq!(x.len(), m, "one unknown per impact");
        let n2 = 2 * self.model.dofs();
        let a = &self.augmented;
        let phases = Self::phases(x);
        let alpha = x[0];
        let singular = SequenceOrbitError::SingularCycle { omega: self.omega };
        let flights: Vec<DMatrix<f64>> = (0..m)
            .map(|f| {
                let end = if f + 1 < m { phases[f + 1] } else { 1.0 };
                (a * ((end - phases[f]) * self.cycle)).exp()
            })
            .collect();
        let mut pre: Vec<DMatrix<f64>> = Vec::with_capacity(m);
        pre.push(flights[0].clone());
        for f in 1..m {
            let next = &flights[f] * (&self.g_hats[f] * &pre[f - 1]);
            pre.push(next);
        }
        let psi = &self.g_hats[0] * &pre[m - 1];
        let k = DMatrix::<f64>::identity(n2, n2) - psi.view((0, 0), (n2, n2));
        let lu = k.lu();
        if !lu.is_invertible() {
            return Err(singular);
        }
        let solve = |b: DVector<f64>| lu.solve(&b).ok_or(singular.clone());
        let psi_xp = psi.view((0, n2), (n2, 2)).into_owned();
        let p0 = DVector::from_vec(vec![alpha.cos(), alpha.sin()]);
        let y1 = solve(&psi_xp * &p0)?;
        let join = |x: &DVector<f64>, p: &DVector<f64>| {
            let mut z = DVector::zeros(n2 + 2);
            z.rows_mut(0, n2).copy_from(x);
            z.rows_mut(n2, 2).copy_from(p);
            z
        };
        let z1 = join(&y1, &p0);
        let h = &self.contacts;
        let mut residual = DVector::zeros(m);
        residual[0] = h[0].dot(&z1) - self.stops[0];
        for f in 0..m - 1 {
            residual[f + 1] = h[f + 1].dot(&(&pre[f] * &z1)) - self.stops[f + 1];
        }

        let mut jacobian = DMatrix::zeros(m, m);
        // α: only p₀ moves.
        let dp0 = DVector::from_vec(vec![-alpha.sin(), alpha.cos()]);
        let dz1 = join(&solve(&psi_xp * &dp0)?, &dp0);
        jacobian[(0, 0)] = h[0].dot(&dz1);
        for f in 0..m - 1 {
            jacobian[(f + 1, 0)] = h[f + 1].dot(&(&pre[f] * &dz1));
        }
        // t_i (impact i ≥ 1): flight i − 1 grows, flight i shrinks, so
        // ∂Pre_f = Φ_f Ĝ_f ∂Pre_{f−1} + c_f Â Pre_f with c_{i−1} = 1, c_i = −1, and
        // ∂Pre_f = 0 for f < i − 1.
        for i in 1..m {
            let c = |f: usize| (f + 1 == i) as i32 as f64 - (f == i) as i32 as f64;
            let mut dpre: Vec<Option<DMatrix<f64>>> = Vec::with_capacity(m);
            for f in 0..m {
                let carried = f
                    .checked_sub(1)
                    .and_then(|g| dpre[g].as_ref())
                    .map(|previous| &flights[f] * (&self.g_hats[f] * previous));
                let cf = c(f);
                let own = (cf != 0.0).then(|| a * &pre[f] * cf);
                dpre.push(match (carried, own) {
                    (Some(d), Some(o)) => Some(d + o),
                    (d, o) => d.or(o),
                });
            }
            let Some(last) = dpre[m - 1].as_ref() else {
                return Err(singular);
            };
            let dpsi = &self.g_hats[0] * last;
            let rhs = dpsi.view((0, 0), (n2, n2)) * &y1 + dpsi.view((0, n2), (n2, 2)) * &p0;
            let dy1 = solve(rhs)?;
            let dz1 = join(&dy1, &DVector::zeros(2));
            jacobian[(0, i)] = h[0].dot(&dz1) * self.cycle;
            for f in 0..m - 1 {
                let moved = &pre[f] * &dz1;
                let total = match dpre[f].as_ref() {
                    Some(d) => d * &z1 + moved,
                    None => moved,
                };
                jacobian[(f + 1, i)] = h[f + 1].dot(&total) * self.cycle;
            }
        }
        Ok(SequenceEvaluation {
            flights,
            pre,
            y1,
            p0,
            residual,
            jacobian,
        })
    }

    /// The rotations `k` of the cycle that map the sequence onto itself (starting the cycle at
    /// impact `k` gives the same sequence). Always contains 0.
    pub fn symmetries(&self) -> Vec<usize> {
        let impacts = self.sequence.impacts();
        let m = impacts.len();
        (0..m)
            .filter(|&k| (0..m).all(|j| impacts[(j + k) % m] == impacts[j]))
            .collect()
    }

    /// Among the rotations of the cycle that keep the canonical sequence, the representation
    /// of the unknowns `x` with the smallest wrapped `α`: returns `(α, phases)`.
    pub fn canonical(&self, x: &[f64]) -> (f64, Vec<f64>) {
        crate::sequence_search::smallest_rotation(
            x[0],
            Self::phases(x),
            self.symmetries(),
            self.omega * self.cycle,
        )
    }
}

/// What one Newton iteration hands to the next.
#[derive(Debug, Clone)]
pub struct NewtonState {
    /// The unknowns `x = (α, φ₂ … φ_m)`.
    pub unknowns: Vec<f64>,
    /// The cycle at `unknowns`.
    pub evaluation: SequenceEvaluation,
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

/// Newton with a backtracking line search on the contact residuals: the settings.
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
    /// The settings of the unit's signature solver: [`NEWTON_ITERATIONS`],
    /// [`NEWTON_TOLERANCE`], [`NEWTON_ACCEPTANCE`].
    fn default() -> Self {
        Self {
            max_iterations: NEWTON_ITERATIONS,
            tolerance: NEWTON_TOLERANCE,
            acceptance: NEWTON_ACCEPTANCE,
        }
    }
}

impl SequenceNewton {
    /// The state at the guess `x = (α, φ₂ … φ_m)`.
    ///
    /// # Errors
    /// [`SequenceOrbitError::InvalidGuess`] unless the guess has one finite entry per impact
    /// with ordered phases in `(0, 1)`; [`SequenceOrbitError::SingularCycle`] from the
    /// evaluation.
    pub fn init(
        &self,
        problem: &SequenceProblem,
        guess: &[f64],
    ) -> Result<NewtonState, SequenceOrbitError> {
        let m = problem.impacts();
        if !is_ordered_guess(guess, m) {
            return Err(SequenceOrbitError::InvalidGuess {
                impacts: m,
                len: guess.len(),
            });
        }
        let evaluation = problem.evaluate(guess)?;
        Ok(state(guess.to_vec(), evaluation, 0, false))
    }

    /// One damped Newton step: the full step, halved up to `LINE_SEARCH_HALVINGS` times
    /// until it keeps the impacts ordered and lowers the merit; `stalled` when none does or
    /// the step is below [`STEP_ROUNDING`].
    ///
    /// # Errors
    /// [`SequenceOrbitError::SingularCycle`] when the Jacobian is singular.
    pub fn next_iter(
        &self,
        problem: &SequenceProblem,
        current: NewtonState,
    ) -> Result<NewtonState, SequenceOrbitError> {
        let step = newton_step(problem, &current)?;
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
            if problem.ordered(&trial) {
                if let Ok(e) = problem.evaluate(&trial) {
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
    pub fn terminate(&self, problem: &SequenceProblem, s: &NewtonState) -> Option<Termination> {
        let scale = problem.scale(&s.evaluation.y1);
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
    pub fn solve(
        &self,
        problem: &SequenceProblem,
        guess: &[f64],
    ) -> Result<NewtonState, SequenceOrbitError> {
        let mut s = self.init(problem, guess)?;
        loop {
            match self.terminate(problem, &s) {
                Some(Termination::Converged) => return Ok(polish(problem, s)),
                Some(Termination::Failed) => {
                    return Err(SequenceOrbitError::NoConvergence {
                        omega: problem.omega(),
                        residual: s.residual,
                        iterations: s.iteration,
                    })
                }
                None => s = self.next_iter(problem, s)?,
            }
        }
    }
}

fn state(
    unknowns: Vec<f64>,
    evaluation: SequenceEvaluation,
    iteration: usize,
    stalled: bool,
) -> NewtonState {
    NewtonState {
        unknowns,
        residual: evaluation.residual.amax(),
        merit: evaluation.residual.norm(),
        evaluation,
        iteration,
        stalled,
    }
}

fn newton_step(
    problem: &SequenceProblem,
    s: &NewtonState,
) -> Result<DVector<f64>, SequenceOrbitError> {
    s.evaluation
        .jacobian
        .clone()
        .lu()
        .solve(&(-&s.evaluation.residual))
        .ok_or(SequenceOrbitError::SingularCycle {
            omega: problem.omega(),
        })
}

/// One more full Newton step from a converged state, kept if it lowers the merit.
fn polish(problem: &SequenceProblem, s: NewtonState) -> NewtonState {
    let Ok(step) = newton_step(problem, &s) else {
        return s;
    };
    let trial: Vec<f64> = s
        .unknowns
        .iter()
        .zip(step.iter())
        .map(|(a, d)| a + d)
        .collect();
    if problem.ordered(&trial) {
        if let Ok(e) = problem.evaluate(&trial) {
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

    /// The exact Jacobian against central differences of the residuals (a check of the
    /// derivation only; the solver never differences): with step `1e-6` the difference
    /// quotient's truncation is `O(1e-12)` and its rounding `O(1e-10)` of the residuals' size.
    #[test]
    fn jacobian_is_the_derivative_of_the_residuals() {
        let model = LinearModel::chain(&damped_paper_unit(), &paper_stops(), 2)
            .unwrap_or_else(|e| panic!("{e}"));
        let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).unwrap_or_else(|e| panic!("{e}"));
        let problem =
            SequenceProblem::new(&model, 2.3, &sequence).unwrap_or_else(|e| panic!("{e}"));
        let x = [0.7, 0.21, 0.48, 0.83];
        let exact = problem
            .evaluate(&x)
            .unwrap_or_else(|e| panic!("{e}"))
            .jacobian;
        let step = 1e-6;
        let scale = exact.amax();
        for i in 0..4 {
            let shifted = |d: f64| {
                let mut y = x;
                y[i] += d;
                problem
                    .evaluate(&y)
                    .unwrap_or_else(|e| panic!("{e}"))
                    .residual
            };
            let quotient = (shifted(step) - shifted(-step)) / (2.0 * step);
            for j in 0..4 {
                assert!(
                    (quotient[j] - exact[(j, i)]).abs() <= 1e-7 * scale,
                    "∂r{j}/∂x{i}: {} vs {}",
                    quotient[j],
                    exact[(j, i)]
                );
            }
        }
    }
}
