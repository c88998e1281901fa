//! The defining system of one event's curve in `Y = (X, p)`: its residual `[R; T]` and
//! Jacobian, the Newton corrector onto the curve closed by a hyperplane, and the orbit at a
//! point of it.

use super::family::Family;
use super::{BoundaryPoint, DIFFERENCE_STEP};
use crate::continuation::corrector::rounding_floor;
use crate::continuation::events::TORUS_TOLERANCE;
use crate::continuation::result::EventKind;
use crate::continuation::system::{BranchModel, Label};
use crate::continuation::test_functions::Test;
use crate::cycle_equations::MIN_FLIGHT;
use crate::orbit::wrap;
use nalgebra::{Complex, DMatrix, DVector, Matrix4};

/// Cap on the Newton iterations of one correction: from the tangent predictor Newton converges
/// quadratically in three to five iterations; a step needing more is halved.
const NEWTON_ITERATIONS: usize = 10;

/// Newton has converged when its step is below this, relative to `1 + |Y|`: `ω` is then
/// pinned far below the `1e-9` asked of a boundary.
const STEP_TOLERANCE: f64 = 1e-12;

/// Newton has stalled at the rounding floor when its step is below this, relative to
/// `1 + |Y|`, and no longer shrinks by [`STALL_RATIO`]: quadratic convergence shrinks it by
/// orders of magnitude per iteration.
const STALL_TOLERANCE: f64 = 1e-10;

/// See [`STALL_TOLERANCE`].
const STALL_RATIO: f64 = 0.25;

/// Imaginary part below which a multiplier counts as real (as in event location).
const REAL_MULTIPLIER: f64 = 1e-9;

/// The hyperplane that closes the corrector's system.
pub(super) enum Border<'a> {
    /// `normal · (Y − through) = 0`.
    Plane {
        normal: &'a [f64],
        through: &'a [f64],
    },
    /// `Y[index] = value`.
    Fixed { index: usize, value: f64 },
}

impl Border<'_> {
    /// The constraint's row and its residual at `y`.
    fn row(&self, y: &[f64]) -> (Vec<f64>, f64) {
        match self {
            Border::Plane { normal, through } => {
                let value = (0..y.len()).map(|k| normal[k] * (y[k] - through[k])).sum();
                (normal.to_vec(), value)
            }
            Border::Fixed { index, value } => {
                let mut row = vec![0.0; y.len()];
                row[*index] = 1.0;
                (row, y[*index] - value)
            }
        }
    }
}

/// The defining system of one event's curve.
pub(super) struct EventCurve<Fam: Family> {
    pub(super) family: Fam,
    pub(super) label: Fam::Label,
    /// Contact pairs of the model (1 on the unit).
    pub(super) pairs: usize,
    pub(super) test: Test,
    pub(super) kind: EventKind,
}

/// `R` and `T` at one `Y`.
struct Values {
    residual: DVector<f64>,
    test: f64,
}

impl<Fam: Family> EventCurve<Fam> {
    /// Number of impacts.
    pub(super) fn n(&self) -> usize {
        self.label.impact_list().len()
    }

    /// `f` of the branch model at parameter value `p`; `None` where `p` gives no model.
    pub(super) fn with_model<R>(
        &self,
        p: f64,
        f: impl FnOnce(&Fam::Model<'_>) -> Option<R>,
    ) -> Option<R> {
        let owned = self.family.build(p).ok()?;
        let model = Fam::model(&owned, &self.label)?;
        f(&model)
    }

    /// Whether `Y` is finite, ordered with flights above [`MIN_FLIGHT`] and `ω > 0`.
    fn admissible(&self, y: &[f64]) -> bool {
        let n = self.n();
        let mut last = 0.0;
        for &phase in &y[1..n] {
            if phase - last <= MIN_FLIGHT {
                return false;
            }
            last = phase;
        }
        y.iter().all(|v| v.is_finite()) && 1.0 - last > MIN_FLIGHT && y[n] > 0.0
    }

    /// `R` and `T` at `X` on `model` (the fold's test from the Jacobian in the state
    /// unknowns alone).
    fn values<M: BranchModel>(&self, model: &M, x: &[f64]) -> Option<Values> {
        let eval = if matches!(self.test, Test::Fold) {
            model.evaluate_state(x)?
        } else {
            model.evaluate(x, false)?
        };
        self.values_of(model, x, &eval)
    }

    /// `R` and `T` at `X` on `model` from its evaluation `eval` there (with the Jacobian
    /// when the test is the fold's).
    fn values_of<M: BranchModel>(
        &self,
        model: &M,
        x: &[f64],
        eval: &M::Evaluation,
    ) -> Option<Values> {
        let test = match self.test {
            Test::Fold => fold_test(M::jacobian(eval)),
            Test::Torus => torus_test(&model.monodromy(x, eval)?),
            test => model.test_value(test, x, eval)?,
        };
        Some(Values {
            residual: M::residual(eval).clone(),
            test,
        })
    }

    /// The defining system's residual at `Y` and its Jacobian in `Y` (one row fewer than
    /// columns): `[R; T]` for an event with a test function, Moore's extended system with `p`
    /// free for a branch point.
    fn linearise(&self, y: &[f64]) -> Option<(DVector<f64>, DMatrix<f64>)> {
        if matches!(self.test, Test::Branch) {
            self.linearise_branch(y)
        } else {
            self.linearise_event(y)
        }
    }

    /// The residual `[R; T]` at `Y` and its Jacobian in `Y` (`n + 1` rows, `n + 2` columns):
    /// `R_X` exact, the rest by central differences.
    fn linearise_event(&self, y: &[f64]) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let n = self.n();
        let x = &y[..=n];
        let mut jacobian = DMatrix::zeros(n + 1, n + 2);
        let values = self.with_model(y[n + 1], |model| {
            let eval = model.evaluate(x, true)?;
            jacobian
                .view_mut((0, 0), (n, n + 1))
                .copy_from(jacobian_of(model, &eval));
            let values = self.values_of(model, x, &eval)?;
            for k in 0..=n {
                let h = DIFFERENCE_STEP * x[k].abs().max(1.0);
                let (mut up, mut down) = (x.to_vec(), x.to_vec());
                up[k] += h;
                down[k] -= h;
                let difference = self.values(model, &up)?.test - self.values(model, &down)?.test;
                jacobian[(n, k)] = difference / (2.0 * h);
            }
            Some(values)
        })?;
        let p = y[n + 1];
        let h = DIFFERENCE_STEP * p.abs().max(1.0);
        // Central where both sides give a unit; one-sided at the edge of the parameter's
        // physical range (restitution 1, say), where Newton then converges linearly at a
        // rate of order `h`, still onto the exact residual's zero.
        let up = self.with_model(p + h, |model| self.values(model, x));
        let down = self.with_model(p - h, |model| self.values(model, x));
        let (high, low, width) = match (&up, &down) {
            (Some(u), Some(d)) => (u, d, 2.0 * h),
            (Some(u), None) => (u, &values, h),
            (None, Some(d)) => (&values, d, h),
            (None, None) => return None,
        };
        for i in 0..n {
            jacobian[(i, n + 1)] = (high.residual[i] - low.residual[i]) / width;
        }
        jacobian[(n, n + 1)] = (high.test - low.test) / width;
        let mut residual = DVector::zeros(n + 1);
        residual.rows_mut(0, n).copy_from(&values.residual);
        residual[n] = values.test;
        Some((residual, jacobian))
    }

    /// Newton on `[defining system; border] = 0` from `guess`: the converged `Y`, the
    /// Jacobian of the defining system at the last iterate, and the iterations taken. `None`
    /// when it leaves the admissible set, does not converge within [`NEWTON_ITERATIONS`], or
    /// stops with contact residuals above [`CORRECTOR_ACCEPTANCE`] of the motion's size.
    pub(super) fn correct(
        &self,
        guess: &[f64],
        border: &Border,
    ) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
        let k = guess.len();
        let mut y = guess.to_vec();
        let mut last = f64::INFINITY;
        for iteration in 1..=NEWTON_ITERATIONS {
            if !self.admissible(&y) {
                return None;
            }
            let (residual, jacobian) = self.linearise(&y)?;
            let (row, constraint) = border.row(&y);
            let mut m = DMatrix::zeros(k, k);
            m.view_mut((0, 0), (k - 1, k)).copy_from(&jacobian);
            for (j, v) in row.iter().enumerate() {
                m[(k - 1, j)] = *v;
            }
            let mut rhs = DVector::zeros(k);
            rhs.rows_mut(0, k - 1).copy_from(&(-&residual));
            rhs[k - 1] = -constraint;
            let step = m.lu().solve(&rhs)?;
            for (v, s) in y.iter_mut().zip(step.iter()) {
                *v += s;
            }
            let size = y.iter().fold(1.0_f64, |a, v| a.max(v.abs()));
            let length = step.amax();
            // Converged; or stalled at the rounding floor of an ill-conditioned cycle (near a
            // natural frequency the test function's rounding keeps Newton's step from
            // shrinking further), well inside the 1e-9 asked of ω.
            let stalled = length <= STALL_TOLERANCE * size && length > STALL_RATIO * last;
            if length <= STEP_TOLERANCE * size || stalled {
                return self.accepted(&y).then_some((y, jacobian, iteration));
            }
            last = length;
        }
        None
    }

    /// Whether the contact residuals at a converged `Y` are within the continuation
    /// corrector's acceptance ([`CORRECTOR_ACCEPTANCE`], or its rounding floor where the
    /// periodicity solve is ill-conditioned).
    fn accepted(&self, y: &[f64]) -> bool {
        let n = self.n();
        self.admissible(y)
            && self
                .with_model(y[n + 1], |model| {
                    let eval = model.evaluate(&y[..=n], false)?;
                    let floor = rounding_floor(model.conditioning(&y[..=n], &eval));
                    Some(residual_of(model, &eval).amax() <= floor * model.scale(&eval))
                })
                .unwrap_or(false)
    }

    /// Whether the orbit at `Y` has a complex pair of multipliers on the unit circle.
    pub(super) fn on_circle(&self, y: &[f64]) -> bool {
        let n = self.n();
        self.with_model(y[n + 1], |model| {
            let eval = model.evaluate(&y[..=n], false)?;
            let m = model.monodromy(&y[..=n], &eval)?;
            Some(complex_pair_on_circle(&multipliers(&m)?))
        })
        .unwrap_or(false)
    }

    /// The orbit at a point of the curve.
    pub(super) fn describe(&self, y: &[f64]) -> Option<BoundaryPoint> {
        let n = self.n();
        self.with_model(y[n + 1], |model| {
            let x = &y[..=n];
            let eval = model.evaluate(x, false)?;
            let verdicts = model.verdicts(x, &eval);
            let mut impact_phases = vec![0.0; n];
            impact_phases[1..n].copy_from_slice(&x[1..n]);
            Some(BoundaryPoint {
                param_value: y[n + 1],
                omega: y[n],
                alpha: wrap(y[0]),
                impact_phases,
                outer_amplitude: verdicts.outer_amplitude,
                amplitudes: verdicts.amplitudes,
                critical_multiplier: critical(self.kind, &verdicts.floquet_multipliers),
                floquet_multipliers: verdicts.floquet_multipliers,
                residual: residual_of(model, &eval).amax() / model.scale(&eval),
            })
        })
    }
}

/// `det R_x`: the determinant of the Jacobian `R_X` in the state unknowns (all columns but
/// `ω`'s; `jacobian` may have the `ω` column or not).
pub(super) fn fold_test(jacobian: &DMatrix<f64>) -> f64 {
    let n = jacobian.nrows();
    jacobian.columns(0, n).into_owned().determinant()
}

/// `R` of an evaluation on `model`.
pub(super) fn residual_of<'e, M: BranchModel>(
    _model: &M,
    eval: &'e M::Evaluation,
) -> &'e DVector<f64> {
    M::residual(eval)
}

/// `R_X` of an evaluation on `model`.
pub(super) fn jacobian_of<'e, M: BranchModel>(
    _model: &M,
    eval: &'e M::Evaluation,
) -> &'e DMatrix<f64> {
    M::jacobian(eval)
}

/// The eigenvalues of a monodromy matrix: the unit's (4 × 4) by the closed-form orbit's
/// routine, a model's by the model flight's.
pub(super) fn multipliers(m: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
    if m.shape() == (4, 4) {
        let fixed: Matrix4<f64> = m.fixed_view::<4, 4>(0, 0).into_owned();
        crate::orbit::eigenvalues(&fixed).map(|e| e.to_vec())
    } else {
        crate::model_flight::eigenvalues(m)
    }
}

/// The Neimark–Sacker test `det(M ⊙ M − I) = Π_{i<j} (μ_i μ_j − 1)`, `M ⊙ M` the second
/// compound of `M` (its 2×2 minors, whose eigenvalues are the products `μ_i μ_j`, `i < j`):
/// the continuation's pair product, but a polynomial in `M`'s entries, so that its
/// differences stay accurate where two multipliers nearly coincide (as the complex pair
/// nears −1), which those of a product over computed eigenvalues do not.
pub(super) fn torus_test(m: &DMatrix<f64>) -> f64 {
    let size = m.nrows();
    let pairs: Vec<(usize, usize)> = (0..size)
        .flat_map(|i| (i + 1..size).map(move |j| (i, j)))
        .collect();
    let k = pairs.len();
    let mut compound = DMatrix::zeros(k, k);
    for (a, &(p, q)) in pairs.iter().enumerate() {
        for (b, &(r, s)) in pairs.iter().enumerate() {
            compound[(a, b)] = m[(p, r)] * m[(q, s)] - m[(p, s)] * m[(q, r)];
        }
    }
    (compound - DMatrix::identity(k, k)).determinant()
}

/// Whether `multipliers` hold a complex pair on the unit circle (as the continuation's
/// Neimark–Sacker events do, to [`TORUS_TOLERANCE`]): where the curve of zeros of the
/// Neimark–Sacker test goes on with real multipliers `μ, 1/μ`, it is a neutral saddle.
fn complex_pair_on_circle(multipliers: &[Complex<f64>]) -> bool {
    multipliers
        .iter()
        .any(|m| m.im.abs() > REAL_MULTIPLIER && (m.norm() - 1.0).abs() < TORUS_TOLERANCE)
}

/// The multiplier an event of `kind` concerns (see [`BoundaryPoint::critical_multiplier`]).
fn critical(kind: EventKind, multipliers: &[Complex<f64>]) -> Complex<f64> {
    let by = |key: &dyn Fn(&Complex<f64>) -> f64| {
        multipliers
            .iter()
            .copied()
            .min_by(|a, b| key(a).total_cmp(&key(b)))
            .unwrap_or(Complex::new(f64::NAN, f64::NAN))
    };
    match kind {
        EventKind::Fold | EventKind::BranchPoint => by(&|m| (m - 1.0).norm()),
        EventKind::PeriodDoubling => by(&|m| (m + 1.0).norm()),
        EventKind::NeimarkSacker => by(&|m| {
            if m.im >= 0.0 && m.im.abs() > 0.0 {
                (m.norm() - 1.0).abs()
            } else {
                f64::INFINITY
            }
        }),
        EventKind::Grazing | EventKind::VanishingImpact => by(&|m| -m.norm()),
    }
}

/// A point of the curve and its unit tangent.
#[derive(Debug, Clone)]
pub(super) struct Node {
    pub(super) y: Vec<f64>,
    pub(super) tangent: Vec<f64>,
}
