//! The corrector: Newton on the bordered system `[R(X); constraint] = 0` that puts a predicted
//! point onto the branch: chord Newton with the Jacobian of a nearby point (one residual
//! evaluation per iteration), full Newton as the fallback, and polishing near a branch point.

use super::branch_point::solve_branch_point;
use super::system::{BranchModel, System};
use crate::cycle::{NEWTON_TOLERANCE, STEP_ROUNDING};
use nalgebra::{DMatrix, DVector};

/// Cap on the corrector's Newton iterations for one continuation step. From the tangent
/// predictor at an accepted step length the corrector converges quadratically in two to four
/// iterations; a step that needs more than this is halved instead.
pub(crate) const CORRECTOR_ITERATIONS: usize = 8;

/// Fallback acceptance of the corrector, relative to the motion's size, once Newton has
/// stalled at the rounding floor of the residual evaluation (an iteration that no longer
/// divides it by 4). Measured: on the paper unit's symmetric branch near `ω = 2.465` (close to the second natural frequency
/// `√6`, where the periodicity solve is ill-conditioned) the evaluation of the residuals
/// scatters by up to `4e-11` of the motion's size from one rounding to the next, above
/// [`crate::NEWTON_ACCEPTANCE`]; this bound is a factor 2.5 above that scatter.
pub const CORRECTOR_ACCEPTANCE: f64 = 1e-10;

/// Rounding of the contact residuals in units of `ε · cond(K)` (times the motion's size),
/// `K = I − Ψ_xx` the periodicity matrix. Measured on the paper unit's symmetric branch at
/// `ω = 2.4554` (near `√6`): `cond(K) = 4.2e5` and the residual scattered between `8e-12` and
/// `1.1e-10` of the size from one rounding to the next, i.e. up to 1.2 `ε cond(K)`.
pub(crate) const ROUNDING_ULPS: f64 = 4.0;

/// The fallback acceptance of the corrector at an evaluation of conditioning
/// `conditioning` ([`crate::CycleEquations::conditioning`]), relative to the motion's
/// size: [`CORRECTOR_ACCEPTANCE`], or the rounding floor `ROUNDING_ULPS · ε · cond(K)` where
/// the periodicity solve is ill-conditioned (near a natural frequency), whichever is larger.
/// Points accepted above [`CORRECTOR_ACCEPTANCE`] carry their residual in
/// [`ContinuationPoint::residual`]; the floor is capped at [`MAX_ROUNDING_FLOOR`].
pub(crate) fn rounding_floor(conditioning: f64) -> f64 {
    CORRECTOR_ACCEPTANCE
        .max(ROUNDING_ULPS * f64::EPSILON * conditioning)
        .min(MAX_ROUNDING_FLOOR)
}

/// Cap on the corrector's rounding floor (`ROUNDING_ULPS · ε · cond(K)`): closer to an undamped resonance (`cond(K)` above about `10⁷`)
/// the residuals cannot be met to `1e-8` of the motion's size in double precision, and the
/// branch ends there ([`EndReason::StepBelowMinimum`]) rather than carry such points.
pub(crate) const MAX_ROUNDING_FLOOR: f64 = 1e-8;

/// Newton's residual has stalled (rounding) when an iteration reduces it by less than this
/// factor: quadratic convergence reduces it by orders of magnitude per iteration.
const STALL_RATIO: f64 = 0.25;

/// Cap on the extra Newton iterations of [`System::polish`]: linear convergence at rate
/// about ½ along a singular direction gains the 26 binary orders between `√ε` and `ε` in
/// about 26 iterations.
const POLISH_ITERATIONS: usize = 60;

/// [`System::polish`] stops when a step is not below this fraction of the previous one.
const POLISH_SHRINK: f64 = 0.9;

/// Cap on the chord iterations of one step (Jacobian of the previous point). From the tangent
/// predictor the chord iteration contracts by a factor of order `h ‖R_XX‖ / ‖R_X‖` per
/// iteration, so a step it cannot finish in this many is better redone with full Newton.
pub(crate) const CHORD_ITERATIONS: usize = 10;

/// The chord iteration is abandoned when an iteration does not reduce the residual by at
/// least this factor: it is then too far from the previous point for its Jacobian.
const CHORD_CONTRACTION: f64 = 0.5;

/// A full-Newton fallback of at most this many iterations (quadratic convergence from the
/// predictor) counts as [`HARD_ITERATIONS`] for the step control: the step is kept.
const FALLBACK_QUICK: usize = 3;

/// Chord iterations above which the next step is shrunk (a slow full Newton fallback counts
/// as [`CHORD_ITERATIONS`]): twice the count at or below which it is grown.
pub(crate) const HARD_ITERATIONS: usize = 8;

/// The hyperplane that closes the corrector's system.
pub(crate) enum Constraint<'a> {
    /// `normal · (X − through) = 0`.
    Plane {
        normal: &'a [f64],
        through: &'a [f64],
    },
    /// `ω = value`.
    Omega(f64),
}

impl<M: BranchModel> System<M> {
    /// Newton on `[R(X); constraint] = 0` from `guess`: the converged `X`, its evaluation
    /// and the Newton steps taken.
    pub(crate) fn correct(
        &self,
        guess: &[f64],
        constraint: &Constraint,
    ) -> Option<(Vec<f64>, M::Evaluation, usize)> {
        let n = self.n();
        let mut x = guess.to_vec();
        let mut last = f64::INFINITY;
        for iteration in 0..=CORRECTOR_ITERATIONS {
            if !self.admissible(&x) {
                return None;
            }
            let eval = self.evaluate(&x)?;
            let norm = M::residual(&eval).amax();
            let scale = self.model.scale(&eval);
            if !norm.is_finite() {
                return None;
            }
            // Converged; or stalled at the rounding floor of an ill-conditioned cycle, below
            // the fallback acceptance of `cycle`'s Newton.
            let floor = rounding_floor(self.model.conditioning(&x, &eval)) * scale;
            if norm <= NEWTON_TOLERANCE * scale || (norm > STALL_RATIO * last && norm <= floor) {
                return Some((x, eval, iteration));
            }
            last = norm;
            if iteration == CORRECTOR_ITERATIONS {
                return None;
            }
            let step = self.newton_step(&x, &eval, constraint)?;
            if step.amax() <= STEP_ROUNDING * (1.0 + x[n].abs()) {
                return (norm <= floor).then_some((x, eval, iteration));
            }
            for k in 0..=n {
                x[k] += step[k];
            }
        }
        None
    }

    /// The branch point of these equations near `x` (within about `1e-4`), solved by the
    /// regular defining system of [`super::branch_point`]; `None` if that does not converge
    /// there, or if its solution has an unfolding `β` or residual above the corrector's
    /// acceptance (no branch point of this system, only a near one).
    pub(crate) fn branch_point_near(&self, x: &[f64]) -> Option<Vec<f64>> {
        let h = |u: &[f64]| {
            if !self.admissible(u) {
                return None;
            }
            let eval = self.evaluate(u)?;
            Some((M::residual(&eval).clone(), M::jacobian(&eval).clone()))
        };
        let found = solve_branch_point(h, x)?;
        let eval = self.evaluate(&found.u)?;
        let floor =
            rounding_floor(self.model.conditioning(&found.u, &eval)) * self.model.scale(&eval);
        (found.unfolding.abs() <= floor && M::residual(&eval).amax() <= floor).then_some(found.u)
    }

    /// Chord Newton on `[R(X); constraint] = 0` from `guess`, with the bordered matrix built
    /// once from `jacobian` (the exact Jacobian at a nearby point, e.g. the previous point of
    /// the branch): each iteration costs one residual evaluation (no derivatives). Converges
    /// linearly at a rate of the order of the distance to that point; `None` when it does not
    /// reach the tolerance within [`CHORD_ITERATIONS`] or stops contracting. The returned
    /// evaluation has no Jacobian.
    pub(crate) fn correct_chord(
        &self,
        guess: &[f64],
        constraint: &Constraint,
        jacobian: &DMatrix<f64>,
    ) -> Option<(Vec<f64>, M::Evaluation, usize)> {
        let n = self.n();
        if jacobian.nrows() != n {
            return None;
        }
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n + 1)).copy_from(jacobian);
        match constraint {
            Constraint::Plane { normal, .. } => {
                for k in 0..=n {
                    m[(n, k)] = normal[k];
                }
            }
            Constraint::Omega(_) => m[(n, n)] = 1.0,
        }
        let lu = m.lu();
        let mut x = guess.to_vec();
        let mut last = f64::INFINITY;
        for iteration in 0..=CHORD_ITERATIONS {
            if !self.admissible(&x) {
                return None;
            }
            let eval = self.evaluate_residual(&x)?;
            let norm = M::residual(&eval).amax();
            let scale = self.model.scale(&eval);
            if !norm.is_finite() {
                return None;
            }
            if norm <= NEWTON_TOLERANCE * scale {
                return Some((x, eval, iteration));
            }
            if norm > CHORD_CONTRACTION * last {
                // Not contracting: too far from the Jacobian's point, or at the rounding
                // floor of the evaluation; full Newton tells the two apart.
                return None;
            }
            last = norm;
            let mut rhs = DVector::zeros(n + 1);
            rhs.rows_mut(0, n).copy_from(&(-M::residual(&eval)));
            rhs[n] = match constraint {
                Constraint::Plane { normal, through } => -(0..=n)
                    .map(|k| normal[k] * (x[k] - through[k]))
                    .sum::<f64>(),
                Constraint::Omega(w) => w - x[n],
            };
            let step = lu.solve(&rhs)?;
            for k in 0..=n {
                x[k] += step[k];
            }
        }
        None
    }

    /// A point of the branch near `guess`: chord Newton with `jacobian` first, full Newton
    /// if that fails; with the full evaluation (Jacobian included) at the converged point.
    pub(crate) fn converge(
        &self,
        guess: &[f64],
        constraint: &Constraint,
        jacobian: &DMatrix<f64>,
    ) -> Option<(Vec<f64>, M::Evaluation, usize)> {
        if let Some((x, residual, iterations)) = self.correct_chord(guess, constraint, jacobian) {
            if let Some(eval) = self.complete(&x, residual) {
                return Some((x, eval, iterations));
            }
        }
        // A quick full Newton (at a rounding floor the chord iteration cannot finish) keeps
        // the step; a slow one shrinks it.
        self.correct(guess, constraint).map(|(x, e, it)| {
            let count = if it <= FALLBACK_QUICK {
                HARD_ITERATIONS
            } else {
                CHORD_ITERATIONS
            };
            (x, e, count)
        })
    }

    /// Continues Newton after [`Self::correct`] while its steps keep shrinking, down to
    /// rounding: near a branch point the corrector's system is nearly singular and Newton
    /// converges only linearly along the singular direction, so the residual test stops it
    /// about `√(tolerance)` away from the branch; this brings it onto the branch.
    pub(crate) fn polish(
        &self,
        x: Vec<f64>,
        eval: M::Evaluation,
        constraint: &Constraint,
    ) -> (Vec<f64>, M::Evaluation) {
        let n = self.n();
        let (mut x, mut eval) = (x, eval);
        let mut last = f64::INFINITY;
        for _ in 0..POLISH_ITERATIONS {
            let Some(step) = self.newton_step(&x, &eval, constraint) else {
                break;
            };
            let size = step.amax();
            if size.is_nan()
                || size >= POLISH_SHRINK * last
                || size <= STEP_ROUNDING * (1.0 + x[n].abs())
            {
                break;
            }
            last = size;
            let trial: Vec<f64> = (0..=n).map(|k| x[k] + step[k]).collect();
            if !self.admissible(&trial) {
                break;
            }
            let Some(e) = self.evaluate(&trial) else {
                break;
            };
            x = trial;
            eval = e;
        }
        (x, eval)
    }

    /// The Newton step of the bordered system at `x`.
    fn newton_step(
        &self,
        x: &[f64],
        eval: &M::Evaluation,
        constraint: &Constraint,
    ) -> Option<DVector<f64>> {
        let n = self.n();
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n + 1)).copy_from(M::jacobian(eval));
        let mut rhs = DVector::zeros(n + 1);
        rhs.rows_mut(0, n).copy_from(&(-M::residual(eval)));
        match constraint {
            Constraint::Plane { normal, through } => {
                for k in 0..=n {
                    m[(n, k)] = normal[k];
                }
                rhs[n] = -(0..=n)
                    .map(|k| normal[k] * (x[k] - through[k]))
                    .sum::<f64>();
            }
            Constraint::Omega(w) => {
                m[(n, n)] = 1.0;
                rhs[n] = w - x[n];
            }
        }
        m.lu().solve(&rhs)
    }
}
