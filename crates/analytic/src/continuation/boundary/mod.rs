//! Exact regime boundaries: one codimension-one event of the orbits of one signature
//! (fold, period doubling, Neimark–Sacker, grazing, vanishing impact) followed in the plane of
//! the forcing frequency `ω` and one parameter `p`: of the unit or its stops
//! ([`follow_boundary`]), or of any [`LinearModel`] such as a chain, its orbits of one
//! impact sequence ([`follow_sequence_boundary`]; grazing and vanishing impact per contact
//! pair).
//!
//! The unknowns are `Y = (X, p)`, `X = (α, φ₂ … φₙ, ω)` the branch's unknowns of
//! continuation in `ω`; the equations are `R(X; p) = 0`, the cycle equations of the unit (or
//! model) built at `p`, and `T(X; p) = 0`, the event's test function (`M` the monodromy
//! matrix with saltations, from the same model side as the continuation's):
//!
//! | event | `T` |
//! |---|---|
//! | fold | `det R_x`, `R_x` the Jacobian in the state unknowns `(α, φ₂ … φₙ)` (the numerator of the continuation's `dω/ds` by Cramer's rule: regular at a fold, where `dω/ds` changes sign) |
//! | period doubling | `det(M + I)` |
//! | Neimark–Sacker | `Π_{i<j} (μ_i μ_j − 1)`, as `det(M ⊙ M − I)` (second compound: smooth in `M`); the curve ends where the complex pair leaves the unit circle for the real axis |
//! | grazing | the clearance of the grazing flight (and pair): the gap less the largest `|r|` at the flight's interior critical points |
//! | vanishing impact | `s_j ṙ⁻_j` of the impact |
//!
//! `R_X` is the exact Jacobian of the cycle equations; `R_p`, `T_X` and `T_p` are central
//! differences with relative step `ε^{1/3}` (error of order `ε^{2/3}` relative; in `p`
//! one-sided at the edge of the parameter's physical range). The residual
//! itself is exact, so Newton on the defining system converges to rounding. The curve
//! `{R = 0, T = 0}` in `Y` is followed by pseudo-arclength continuation (tangent predictor,
//! Newton corrector on the bordered system, step control by the corrector's iterations),
//! through turning points in `p`, both ways from the start within `[param_min, param_max]`
//! and `[omega_min, omega_max]`; each end carries its reason, and the curve's `ω` at given
//! parameter values is solved on the same system with `p` fixed.
//!
//! Along the curve its special points ([`Boundary::special_points`], [`SpecialKind`]) are
//! located to rounding, each as the zero of a function that changes sign between two
//! consecutive points (regula falsi on the chord, each trial corrected onto the curve) and
//! inserted among the points: turning points in `p`, a grazing or vanishing impact of the
//! event's orbit (viability lost or gained), the strong resonances 1:3 and 1:4 of a
//! Neimark–Sacker curve (1:1 and 1:2 end it, where the pair reaches the real axis), and the
//! crossings with the curves of the orbit's other events (fold, period doubling,
//! Neimark–Sacker).
//!
//! A branch point has no regular test function (`R_X` loses rank there, and the set
//! `R = 0` crosses itself): its curve is followed on Moore's extended system with `p` free
//! (unknowns `(X, p, β, ψ)`, see the `branch` module), regular at a simple branch point.

mod branch;
mod family;
mod special;

pub use special::{BoundarySpecialPoint, SpecialKind};

use super::corrector::rounding_floor;
use super::events::TORUS_TOLERANCE;
use super::result::{Event, EventKind};
use super::settings::check_range_and_steps;
use super::system::BranchModel;
use super::system::Label;
use super::test_functions::Test;
use crate::cycle_equations::MIN_FLIGHT;
use crate::model::LinearModel;
use crate::orbit::wrap;
use crate::sequence::ImpactSequence;
use crate::signature::Signature;
use crate::unit::{Stops, Unit};
use family::{Family, ModelFamily, UnitFamily};
use nalgebra::{Complex, DMatrix, DVector, Matrix4};
use thiserror::Error;

/// Relative step of the central differences: `ε^{1/3}`, balancing truncation (`h²`) against
/// rounding (`ε / h`).
const DIFFERENCE_STEP: f64 = 6.055_454_452_393_343e-6;

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

/// Newton iterations at or below which the next step grows.
const EASY_ITERATIONS: usize = 4;

/// Step growth after an easy correction.
const STEP_GROWTH: f64 = 1.5;

/// Step shrink after a rejected one.
const STEP_SHRINK: f64 = 0.5;

/// Two consecutive tangents must make an angle of cosine at least this (about 26°), or the
/// step is halved: a larger turn within a step may have jumped to another curve.
const MIN_TANGENT_COSINE: f64 = 0.9;

/// Shortest flight (fraction of the cycle) below which a curve ending for want of a step is
/// reported as two impacts merging.
const MERGE_WARNING: f64 = 1e-6;

/// Settings of a boundary curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundarySettings {
    /// Lowest parameter value followed.
    pub param_min: f64,
    /// Highest parameter value followed, `> param_min`.
    pub param_max: f64,
    /// Lowest forcing frequency followed (rad/s), `> 0`.
    pub omega_min: f64,
    /// Highest forcing frequency followed (rad/s), `> omega_min`.
    pub omega_max: f64,
    /// First step length in `(α, φ₂ … φₙ, ω, p)`.
    pub initial_step: f64,
    /// Smallest step: a curve whose step would fall below it ends.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Cap on the points of the curve in each direction.
    pub max_points: usize,
}

impl BoundarySettings {
    /// The parameter range `[param_min, param_max]` with `ω ∈ [0.1, 4]` (the band the
    /// workbench studies on the paper unit), steps from `10⁻⁹` to `0.02` starting at `0.005`,
    /// 5 000 points each way.
    pub fn new(param_min: f64, param_max: f64) -> Self {
        Self {
            param_min,
            param_max,
            omega_min: 0.1,
            omega_max: 4.0,
            initial_step: 0.005,
            min_step: 1e-9,
            max_step: 0.02,
            max_points: 5000,
        }
    }

    /// Checks every setting.
    ///
    /// # Errors
    /// [`BoundaryError::Setting`] naming the first field that fails: `--min` (finite), `--max`
    /// (finite, `> --min`), `--omega-min` (finite, `> 0`), `--omega-max` (finite,
    /// `> --omega-min`), `boundary.min_step` (finite, `> 0`), `boundary.max_step` (finite,
    /// `≥ min_step`), `boundary.initial_step` (in `[min_step, max_step]`),
    /// `boundary.max_points` (`≥ 1`).
    pub fn validate(&self) -> Result<(), BoundaryError> {
        let check = |field: &'static str, value: f64, ok: bool, allowed: String| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(BoundaryError::Setting {
                    field,
                    value,
                    allowed,
                })
            }
        };
        check("--min", self.param_min, true, "finite".into())?;
        check(
            "--max",
            self.param_max,
            self.param_max > self.param_min,
            format!("finite and > --min = {}", self.param_min),
        )?;
        check_range_and_steps(
            (self.omega_min, self.omega_max),
            [
                ("boundary.min_step", self.min_step),
                ("boundary.max_step", self.max_step),
                ("boundary.initial_step", self.initial_step),
            ],
            check,
        )?;
        check(
            "boundary.max_points",
            self.max_points as f64,
            self.max_points >= 1,
            ">= 1".into(),
        )
    }
}

/// Why a boundary curve cannot be followed.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BoundaryError {
    /// A setting outside its allowed range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    Setting {
        /// The setting, e.g. `--min` or `boundary.max_step`.
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },
    /// An event kind whose curve is not followed (none at present: kept for callers that
    /// refuse a kind themselves).
    #[error("--event {kind} is not supported yet: supported are fold, period-doubling, neimark-sacker, grazing, vanishing-impact")]
    Unsupported {
        /// The event kind's name.
        kind: &'static str,
    },
    /// The event does not say which flight or impact it concerns, or names one the signature
    /// lacks.
    #[error(
        "the {kind} event at omega = {omega} names no flight or impact of the {signature} orbits"
    )]
    EventMismatch {
        /// The event kind's name.
        kind: &'static str,
        /// The event's frequency.
        omega: f64,
        /// The signature of the orbits.
        signature: String,
    },
    /// The parameter's own value gives no unit.
    #[error("the parameter value {value} gives no valid unit: {message}")]
    Parameter {
        /// The parameter value.
        value: f64,
        /// Why.
        message: String,
    },
    /// Newton on the defining system at the start's parameter value does not converge from
    /// the event's orbit.
    #[error("the {kind} event at omega = {omega} does not converge onto its curve at the parameter value {param}")]
    StartNotConverged {
        /// The event kind's name.
        kind: &'static str,
        /// The event's frequency.
        omega: f64,
        /// The start's parameter value.
        param: f64,
    },
}

/// One point of a boundary curve: the orbit at the event there.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundaryPoint {
    /// The parameter's value.
    pub param_value: f64,
    /// Forcing frequency (rad/s).
    pub omega: f64,
    /// Base phase at the first canonical impact, radians in `(−π, π]`.
    pub alpha: f64,
    /// Impact times as fractions of the cycle, first 0.
    pub impact_phases: Vec<f64>,
    /// `X_o = max |u_o(t)|` over the cycle (rigorous extrema).
    pub outer_amplitude: f64,
    /// Eigenvalues of the monodromy matrix.
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// The multiplier the event concerns: nearest `+1` at a fold, nearest `−1` at a period
    /// doubling, the one of the complex pair (non-negative imaginary part) nearest the unit
    /// circle at a Neimark–Sacker; the largest in modulus at a grazing or vanishing impact.
    pub critical_multiplier: Complex<f64>,
    /// Largest contact residual relative to the motion's size.
    pub residual: f64,
}

/// The curve's `ω` solved at one parameter value ([`follow_boundary`]'s `at`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryAt {
    /// The parameter value asked for.
    pub param_value: f64,
    /// The curve's frequency there (one entry per crossing of the curve).
    pub omega: f64,
}

/// Why a boundary curve stops in one direction.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BoundaryEndReason {
    /// It reached `param_min`; the last point lies exactly there.
    ParamMin,
    /// It reached `param_max`; the last point lies exactly there.
    ParamMax,
    /// It reached `omega_min`; the last point lies exactly there.
    OmegaMin,
    /// It reached `omega_max`; the last point lies exactly there.
    OmegaMax,
    /// The step fell below `min_step` without the corrector converging.
    StepBelowMinimum,
    /// Two impacts merge (a flight shrinks to nothing).
    FlightMerged,
    /// The direction reached `max_points`.
    PointCap,
    /// The curve closed on itself: it came back to its start, or its two directions met (a
    /// closed curve longer than one direction's `max_points`; both ends then say so). A
    /// closed curve, followed once.
    ClosedLoop,
    /// A Neimark–Sacker curve whose complex pair meets on the real axis (at a strong
    /// resonance, `μ = ±1` double): beyond, the zeros of its test are neutral saddles
    /// (real `μ, 1/μ`), not Neimark–Sacker points. The last point is that 1:1 or 1:2
    /// resonance, located (and listed among the special points); failing that, the last
    /// point with the pair on the unit circle.
    NeutralSaddle,
}

impl BoundaryEndReason {
    /// `param-min`, `param-max`, `omega-min`, `omega-max`, `step-below-minimum`,
    /// `flight-merged`, `point-cap`, `closed-loop` or `neutral-saddle`.
    pub fn name(self) -> &'static str {
        match self {
            BoundaryEndReason::ParamMin => "param-min",
            BoundaryEndReason::ParamMax => "param-max",
            BoundaryEndReason::OmegaMin => "omega-min",
            BoundaryEndReason::OmegaMax => "omega-max",
            BoundaryEndReason::StepBelowMinimum => "step-below-minimum",
            BoundaryEndReason::FlightMerged => "flight-merged",
            BoundaryEndReason::PointCap => "point-cap",
            BoundaryEndReason::ClosedLoop => "closed-loop",
            BoundaryEndReason::NeutralSaddle => "neutral-saddle",
        }
    }
}

/// One end of a boundary curve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BoundaryEnd {
    /// The parameter value of the last point.
    pub param_value: f64,
    /// Its frequency.
    pub omega: f64,
    /// Why the curve stops there.
    pub reason: BoundaryEndReason,
}

/// A followed boundary curve: of a unit's orbits (`L` a [`Signature`]) or of a model's
/// ([`ImpactSequence`], [`follow_sequence_boundary`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Boundary<L = Signature> {
    /// The signature (a model's: impact sequence) of the orbits.
    pub signature: L,
    /// The event followed.
    pub kind: EventKind,
    /// The points in order along the curve, the start somewhere inside.
    pub points: Vec<BoundaryPoint>,
    /// The curve's `ω` at each value asked for, in the order asked and along the curve.
    pub at: Vec<BoundaryAt>,
    /// The special points in order along the curve, each located to rounding and also one
    /// of [`Boundary::points`]: turning points in the parameter, grazings and vanishing
    /// impacts of the event's orbit (viability lost or gained), strong resonances of a
    /// Neimark–Sacker curve, crossings with the curves of the orbit's other events.
    pub special_points: Vec<BoundarySpecialPoint>,
    /// The two ends: the first point's, then the last point's.
    pub ends: [BoundaryEnd; 2],
}

/// What to follow: the unit as a function of the parameter, the orbits' signature, the event
/// on their branch (from [`crate::continue_orbit`] on the unit at `param`), the parameter's
/// own value there and the values at which to solve the curve's `ω`.
pub struct BoundaryStart<'a, F> {
    /// The unit and its stops at a parameter value; an `Err` (with its message) where the
    /// value gives no valid unit.
    pub unit_at: F,
    /// The signature of the branch the event lies on.
    pub signature: &'a Signature,
    /// The event to follow.
    pub event: &'a Event,
    /// The parameter's value at which the event was found.
    pub param: f64,
    /// Parameter values at which the curve's `ω` is solved.
    pub at: &'a [f64],
}

/// Follows the curve of `start.event` in `(ω, p)` both ways from `(event.omega, param)`
/// within the settings' ranges, through turning points in `p`, and solves its `ω` at each
/// value of `start.at` (every crossing of the curve there).
///
/// # Errors
/// [`BoundaryError::Setting`] for a bad setting, or (field `--at`) a value of `at` outside
/// `[param_min, param_max]`, or (field `param`) a start outside it;
/// [`BoundaryError::EventMismatch`] when
/// a grazing or vanishing impact names no flight or impact of the signature;
/// [`BoundaryError::Parameter`] when `unit_at(param)` fails;
/// [`BoundaryError::StartNotConverged`] when Newton on the defining system at `param` does
/// not converge from the event's orbit.
pub fn follow_boundary<F, E>(
    start: &BoundaryStart<'_, F>,
    settings: &BoundarySettings,
) -> Result<Boundary, BoundaryError>
where
    F: Fn(f64) -> Result<(Unit, Stops), E>,
    E: std::fmt::Display,
{
    let family = UnitFamily {
        unit_at: &start.unit_at,
    };
    follow_family(
        family,
        start.signature,
        start.event,
        start.param,
        start.at,
        settings,
    )
}

/// What to follow on a [`LinearModel`] (a chain): the model as a function of the parameter,
/// the orbits' impact sequence, the event on their branch (from
/// [`crate::continue_sequence`] on the model at `param`), the parameter's own value there
/// and the values at which to solve the curve's `ω`.
pub struct SequenceBoundaryStart<'a, F> {
    /// The model at a parameter value; an `Err` (with its message) where the value gives
    /// no valid model.
    pub model_at: F,
    /// The impact sequence of the branch the event lies on.
    pub sequence: &'a ImpactSequence,
    /// The event to follow.
    pub event: &'a Event<ImpactSequence>,
    /// The parameter's value at which the event was found.
    pub param: f64,
    /// Parameter values at which the curve's `ω` is solved.
    pub at: &'a [f64],
}

/// [`follow_boundary`] on a [`LinearModel`] such as a chain: the curve of `start.event` of
/// the orbits of `start.sequence` in `(ω, p)`, a grazing or vanishing impact of the event's
/// contact pair, special points per pair (a grazing of every pair over every flight).
///
/// # Errors
/// As [`follow_boundary`]; [`BoundaryError::EventMismatch`] also when the sequence names a
/// pair the model lacks.
pub fn follow_sequence_boundary<F, E>(
    start: &SequenceBoundaryStart<'_, F>,
    settings: &BoundarySettings,
) -> Result<Boundary<ImpactSequence>, BoundaryError>
where
    F: Fn(f64) -> Result<LinearModel, E>,
    E: std::fmt::Display,
{
    let family = ModelFamily {
        model_at: &start.model_at,
    };
    follow_family(
        family,
        start.sequence,
        start.event,
        start.param,
        start.at,
        settings,
    )
}

/// The curve of `event` of the orbits of `label` on `family`, from `param`.
fn follow_family<Fam: Family>(
    family: Fam,
    label: &Fam::Label,
    event: &Event<Fam::Label>,
    param: f64,
    at: &[f64],
    settings: &BoundarySettings,
) -> Result<Boundary<Fam::Label>, BoundaryError> {
    settings.validate()?;
    check_inside("param", param, settings)?;
    for &value in at {
        check_inside("--at", value, settings)?;
    }
    let owned = family
        .build(param)
        .map_err(|message| BoundaryError::Parameter {
            value: param,
            message,
        })?;
    let n = label.impact_list().len();
    let mismatch = || BoundaryError::EventMismatch {
        kind: event.kind.name(),
        omega: event.omega,
        signature: label.to_string(),
    };
    let pairs = Fam::model(&owned, label).ok_or_else(mismatch)?.pairs();
    let curve = EventCurve {
        test: test_of(event, n, pairs, label)?,
        family,
        label: label.clone(),
        pairs,
        kind: event.kind,
    };
    let not_converged = || BoundaryError::StartNotConverged {
        kind: event.kind.name(),
        omega: event.omega,
        param,
    };
    let mut guess = vec![event.point.alpha];
    guess.extend_from_slice(
        event
            .point
            .impact_phases
            .get(1..n)
            .ok_or_else(not_converged)?,
    );
    guess.extend([event.omega, param]);
    if event.kind == EventKind::BranchPoint {
        guess = curve.branch_guess(guess).ok_or_else(not_converged)?;
    }
    let fixed = Border::Fixed {
        index: n + 1,
        value: param,
    };
    let (y, jacobian, _) = curve.correct(&guess, &fixed).ok_or_else(not_converged)?;
    let tangent = null_vector(&jacobian).ok_or_else(not_converged)?;
    Ok(curve.trace(y, tangent, at, settings))
}

/// `Err` naming `field` when `value` is outside `[param_min, param_max]`.
fn check_inside(
    field: &'static str,
    value: f64,
    settings: &BoundarySettings,
) -> Result<(), BoundaryError> {
    if value.is_finite() && value >= settings.param_min && value <= settings.param_max {
        Ok(())
    } else {
        Err(BoundaryError::Setting {
            field,
            value,
            allowed: format!(
                "in [{}, {}] (--min, --max)",
                settings.param_min, settings.param_max
            ),
        })
    }
}

/// The test function of `event` on orbits of `n` impacts of a model with `pairs` contact
/// pairs (a grazing's clearance is indexed by flight and pair).
fn test_of<L: Label>(
    event: &Event<L>,
    n: usize,
    pairs: usize,
    signature: &L,
) -> Result<Test, BoundaryError> {
    let mismatch = || BoundaryError::EventMismatch {
        kind: event.kind.name(),
        omega: event.omega,
        signature: signature.to_string(),
    };
    let phases = &event.point.impact_phases;
    match event.kind {
        EventKind::Fold => Ok(Test::Fold),
        EventKind::PeriodDoubling => Ok(Test::Doubling),
        EventKind::NeimarkSacker => Ok(Test::Torus),
        EventKind::BranchPoint => Ok(Test::Branch),
        EventKind::Grazing => {
            let phase = event.phase.ok_or_else(mismatch)?;
            let f = (0..n)
                .rev()
                .find(|&f| phases.get(f).is_some_and(|&p| p <= phase))
                .ok_or_else(mismatch)?;
            let pair = event.pair.unwrap_or(0);
            if pair >= pairs {
                return Err(mismatch());
            }
            Ok(Test::Clearance(f * pairs + pair))
        }
        EventKind::VanishingImpact => {
            let phase = event.phase.ok_or_else(mismatch)?;
            let j = (0..n)
                .min_by(|&a, &b| {
                    let d = |j: usize| phases.get(j).map_or(f64::INFINITY, |p| (p - phase).abs());
                    d(a).total_cmp(&d(b))
                })
                .ok_or_else(mismatch)?;
            Ok(Test::Approach(j))
        }
    }
}

/// The hyperplane that closes the corrector's system.
enum Border<'a> {
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
struct EventCurve<Fam: Family> {
    family: Fam,
    label: Fam::Label,
    /// Contact pairs of the model (1 on the unit).
    pairs: usize,
    test: Test,
    kind: EventKind,
}

/// `R` and `T` at one `Y`.
struct Values {
    residual: DVector<f64>,
    test: f64,
}

impl<Fam: Family> EventCurve<Fam> {
    /// Number of impacts.
    fn n(&self) -> usize {
        self.label.impact_list().len()
    }

    /// `f` of the branch model at parameter value `p`; `None` where `p` gives no model.
    fn with_model<R>(&self, p: f64, f: impl FnOnce(&Fam::Model<'_>) -> Option<R>) -> Option<R> {
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
    fn correct(&self, guess: &[f64], border: &Border) -> Option<(Vec<f64>, DMatrix<f64>, usize)> {
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

    /// The curve both ways from `(y, tangent)`, its special points, the `ω` at the values
    /// `at`, and the ends.
    fn trace(
        &self,
        y: Vec<f64>,
        tangent: Vec<f64>,
        at: &[f64],
        settings: &BoundarySettings,
    ) -> Boundary<Fam::Label> {
        let start = Node { y, tangent };
        let mut forward = self.follow(&start, 1.0, settings, None);
        // Where the forward way stopped at its cap, a closed curve longer than that goes on
        // from there: the backward way, round it the other way, ends when it gets there.
        let meet = forward
            .nodes
            .last()
            .filter(|_| forward.reason == BoundaryEndReason::PointCap);
        let backward = if forward.reason == BoundaryEndReason::ClosedLoop {
            Leg {
                nodes: Vec::new(),
                reason: BoundaryEndReason::ClosedLoop,
                resonance: None,
            }
        } else {
            self.follow(&start, -1.0, settings, meet)
        };
        if forward.reason == BoundaryEndReason::PointCap
            && backward.reason == BoundaryEndReason::ClosedLoop
        {
            // The two ways met: the curve is followed whole, once.
            forward.reason = BoundaryEndReason::ClosedLoop;
        }
        let mut nodes = backward.nodes;
        nodes.reverse();
        nodes.push(start);
        nodes.extend(forward.nodes);
        let n = self.n();
        let end = |node: &Node, reason| BoundaryEnd {
            param_value: node.y[n + 1],
            omega: node.y[n],
            reason,
        };
        let ends = [
            end(&nodes[0], backward.reason),
            end(&nodes[nodes.len() - 1], forward.reason),
        ];
        let (nodes, specials) =
            self.with_special_points(nodes, backward.resonance, forward.resonance);
        let at = at.iter().flat_map(|&v| self.solve_at(&nodes, v)).collect();
        let special_points = specials
            .into_iter()
            .filter_map(|(node, kind, value)| {
                let point = self.describe(&node.y)?;
                Some(BoundarySpecialPoint {
                    kind,
                    param_value: point.param_value,
                    omega: point.omega,
                    value,
                    point,
                })
            })
            .collect();
        Boundary {
            signature: self.label.clone(),
            kind: self.kind,
            points: nodes
                .iter()
                .filter_map(|node| self.describe(&node.y))
                .collect(),
            at,
            special_points,
            ends,
        }
    }

    /// `nodes` with the special points between them inserted in order, and the special
    /// points (node, kind, value); `first` and `last` say that the first or last node is a
    /// resonance ending the curve.
    fn with_special_points(
        &self,
        nodes: Vec<Node>,
        first: Option<(SpecialKind, f64)>,
        last: Option<(SpecialKind, f64)>,
    ) -> (Vec<Node>, Vec<(Node, SpecialKind, f64)>) {
        let found = self.special_points(&nodes);
        let mut specials = Vec::with_capacity(found.len() + 2);
        if let Some((kind, value)) = first {
            specials.push((nodes[0].clone(), kind, value));
        }
        let mut out = Vec::with_capacity(nodes.len() + found.len());
        let mut found = found.into_iter().peekable();
        for (i, node) in nodes.into_iter().enumerate() {
            out.push(node);
            while let Some((_, special, kind, value)) = found.next_if(|f| f.0 == i) {
                out.push(special.clone());
                specials.push((special, kind, value));
            }
        }
        if let Some((kind, value)) = last {
            specials.push((out[out.len() - 1].clone(), kind, value));
        }
        (out, specials)
    }

    /// The curve's points at parameter value `value`: each crossing of `p = value` between
    /// consecutive nodes, solved with `p` fixed from the chord's point.
    fn solve_at(&self, nodes: &[Node], value: f64) -> Vec<BoundaryAt> {
        let n = self.n();
        let mut found: Vec<BoundaryAt> = Vec::new();
        for (i, pair) in nodes.windows(2).enumerate() {
            let (a, b) = (&pair[0].y, &pair[1].y);
            let (pa, pb) = (a[n + 1] - value, b[n + 1] - value);
            // A node exactly at the value is the previous pair's crossing.
            if pa * pb > 0.0 || pa == pb || (pa == 0.0 && i > 0) {
                continue;
            }
            let theta = pa / (pa - pb);
            let guess: Vec<f64> = a.iter().zip(b).map(|(u, v)| u + theta * (v - u)).collect();
            let border = Border::Fixed {
                index: n + 1,
                value,
            };
            if let Some((y, _, _)) = self.correct(&guess, &border) {
                found.push(BoundaryAt {
                    param_value: value,
                    omega: y[n],
                });
            }
        }
        found
    }

    /// The orbit at a point of the curve.
    fn describe(&self, y: &[f64]) -> Option<BoundaryPoint> {
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
                critical_multiplier: critical(self.kind, &verdicts.floquet_multipliers),
                floquet_multipliers: verdicts.floquet_multipliers,
                residual: residual_of(model, &eval).amax() / model.scale(&eval),
            })
        })
    }
}

/// `det R_x`: the determinant of the Jacobian `R_X` in the state unknowns (all columns but
/// `ω`'s; `jacobian` may have the `ω` column or not).
fn fold_test(jacobian: &DMatrix<f64>) -> f64 {
    let n = jacobian.nrows();
    jacobian.columns(0, n).into_owned().determinant()
}

/// `R` of an evaluation on `model`.
fn residual_of<'e, M: BranchModel>(_model: &M, eval: &'e M::Evaluation) -> &'e DVector<f64> {
    M::residual(eval)
}

/// `R_X` of an evaluation on `model`.
fn jacobian_of<'e, M: BranchModel>(_model: &M, eval: &'e M::Evaluation) -> &'e DMatrix<f64> {
    M::jacobian(eval)
}

/// The eigenvalues of a monodromy matrix: the unit's (4 × 4) by the closed-form orbit's
/// routine, a model's by the model flight's.
fn multipliers(m: &DMatrix<f64>) -> Option<Vec<Complex<f64>>> {
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
fn torus_test(m: &DMatrix<f64>) -> f64 {
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

/// The unit null vector of a `k × (k + 1)` Jacobian (its smallest right singular vector).
fn null_vector(jacobian: &DMatrix<f64>) -> Option<Vec<f64>> {
    let k = jacobian.ncols();
    let mut m = DMatrix::zeros(k, k);
    m.view_mut((0, 0), (k - 1, k)).copy_from(jacobian);
    let svd = m.svd(false, true);
    let v_t = svd.v_t?;
    let i = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)?;
    Some(v_t.row(i).iter().copied().collect())
}

/// The unit tangent at a point with Jacobian `jacobian`, oriented along `previous`.
fn tangent(jacobian: &DMatrix<f64>, previous: &[f64]) -> Option<Vec<f64>> {
    let k = jacobian.ncols();
    let mut m = DMatrix::zeros(k, k);
    m.view_mut((0, 0), (k - 1, k)).copy_from(jacobian);
    for (j, v) in previous.iter().enumerate() {
        m[(k - 1, j)] = *v;
    }
    let mut rhs = DVector::zeros(k);
    rhs[k - 1] = 1.0;
    let t = m.lu().solve(&rhs)?;
    let norm = t.norm();
    (norm.is_finite() && norm > 0.0).then(|| t.iter().map(|v| v / norm).collect())
}

/// A point of the curve and its unit tangent.
#[derive(Debug, Clone)]
struct Node {
    y: Vec<f64>,
    tangent: Vec<f64>,
}

/// The state of following the curve in one direction.
struct Walk {
    nodes: Vec<Node>,
    last: Node,
    step: f64,
    /// The last node is a strong resonance ending a Neimark–Sacker curve.
    resonance: Option<(SpecialKind, f64)>,
}

/// The curve followed in one direction: the points after the start, why it stops, and
/// whether its last point is a strong resonance (kind and value of its function).
struct Leg {
    nodes: Vec<Node>,
    reason: BoundaryEndReason,
    resonance: Option<(SpecialKind, f64)>,
}

/// What one step did.
enum Step {
    /// A new point, possibly past a range's bound, and the corrector's iterations.
    Accepted(Node, usize),
    /// The corrector failed or the curve turned too sharply: retry shorter.
    Rejected,
}

impl<Fam: Family> EventCurve<Fam> {
    /// Follows the curve from `start` in `direction` (`±1` along its tangent): the points
    /// after the start and why it stops.
    fn follow(
        &self,
        start: &Node,
        direction: f64,
        settings: &BoundarySettings,
        meet: Option<&Node>,
    ) -> Leg {
        let mut walk = Walk {
            nodes: Vec::new(),
            last: Node {
                y: start.y.clone(),
                tangent: start.tangent.iter().map(|v| direction * v).collect(),
            },
            step: settings.initial_step,
            resonance: None,
        };
        let reason = loop {
            match self.next_iter(&walk) {
                Step::Accepted(node, iterations) => {
                    let end = self.terminate(&mut walk, node, iterations, (start, meet), settings);
                    if let Some(reason) = end {
                        break reason;
                    }
                }
                Step::Rejected => {
                    if let Some((end, reason)) = self.beyond(&walk, settings) {
                        walk.nodes.push(end);
                        break reason;
                    }
                    walk.step *= STEP_SHRINK;
                    if walk.step < settings.min_step {
                        break self.stuck(&walk.last.y);
                    }
                }
            }
        };
        Leg {
            nodes: walk.nodes,
            reason,
            resonance: walk.resonance,
        }
    }

    /// One predictor–corrector step of `walk.step` from its last point.
    fn next_iter(&self, walk: &Walk) -> Step {
        let (y0, t0) = (&walk.last.y, &walk.last.tangent);
        let predicted: Vec<f64> = y0.iter().zip(t0).map(|(y, t)| y + walk.step * t).collect();
        let plane = Border::Plane {
            normal: t0,
            through: &predicted,
        };
        let Some((y, jacobian, iterations)) = self.correct(&predicted, &plane) else {
            return Step::Rejected;
        };
        let Some(t) = tangent(&jacobian, t0) else {
            return Step::Rejected;
        };
        let cosine: f64 = t.iter().zip(t0).map(|(a, b)| a * b).sum();
        if cosine < MIN_TANGENT_COSINE {
            return Step::Rejected;
        }
        Step::Accepted(Node { y, tangent: t }, iterations)
    }

    /// Takes the accepted `node` into `walk` and says whether the direction ends: past a
    /// range's bound (the end then solved exactly on it), back at the start, at `meet` (where
    /// the other direction stopped at its cap) travelling against it, at the point cap.
    /// Grows the step after an easy correction.
    fn terminate(
        &self,
        walk: &mut Walk,
        node: Node,
        iterations: usize,
        (start, meet): (&Node, Option<&Node>),
        settings: &BoundarySettings,
    ) -> Option<BoundaryEndReason> {
        let n = self.n();
        if let Some((index, value, reason)) = outside(&node.y, n, settings) {
            let end = self.end_at(&walk.last, &node, index, value);
            walk.nodes.extend(end);
            return Some(reason);
        }
        if self.kind == EventKind::NeimarkSacker && !self.on_circle(&node.y) {
            // The pair left the circle for the real axis at μ = 1 or −1: the last point is
            // that resonance, when located.
            if let Some((resonance, kind, value)) = self.resonance_end(&walk.last, &node) {
                walk.nodes.push(resonance);
                walk.resonance = Some((kind, value));
            }
            return Some(BoundaryEndReason::NeutralSaddle);
        }
        // Back at the start travelling the same way, or at `meet` travelling against it.
        let along = |other: &Node| -> f64 {
            node.tangent
                .iter()
                .zip(&other.tangent)
                .map(|(a, b)| a * b)
                .sum()
        };
        let near = |other: &Node| distance(&node.y, &other.y) < walk.step;
        let back = near(start) && walk.nodes.len() >= 3 && along(start) > 0.0;
        let met = meet.is_some_and(|end| near(end) && along(end) < 0.0);
        walk.last = node.clone();
        walk.nodes.push(node);
        if back || met {
            return Some(BoundaryEndReason::ClosedLoop);
        }
        if walk.nodes.len() >= settings.max_points {
            return Some(BoundaryEndReason::PointCap);
        }
        if iterations <= EASY_ITERATIONS {
            walk.step = (walk.step * STEP_GROWTH).min(settings.max_step);
        }
        None
    }

    /// After a failed step whose prediction lies beyond a range's bound (where the unit may
    /// not exist, e.g. restitution above 1): the curve's point on that bound, solved from the
    /// last point and the prediction, and the end's reason.
    fn beyond(
        &self,
        walk: &Walk,
        settings: &BoundarySettings,
    ) -> Option<(Node, BoundaryEndReason)> {
        let (y0, t0) = (&walk.last.y, &walk.last.tangent);
        let predicted: Vec<f64> = y0.iter().zip(t0).map(|(y, t)| y + walk.step * t).collect();
        let (index, value, reason) = outside(&predicted, self.n(), settings)?;
        let ahead = Node {
            y: predicted,
            tangent: t0.clone(),
        };
        Some((self.end_at(&walk.last, &ahead, index, value)?, reason))
    }

    /// The 1:1 or 1:2 resonance between the last point `a` with its complex pair on the
    /// unit circle and the next one `b`, where the pair is real: located as the zero of
    /// `c ∓ 1` ([`SpecialKind::Resonance`]), with its kind and the function's value.
    fn resonance_end(&self, a: &Node, b: &Node) -> Option<(Node, SpecialKind, f64)> {
        let n = self.n();
        let cosine = |y: &[f64]| {
            self.with_model(y[n + 1], |model| {
                let eval = model.evaluate(&y[..=n], false)?;
                special::pair_cosine(&model.monodromy(&y[..=n], &eval)?)
            })
        };
        let (ca, cb) = (cosine(&a.y)?, cosine(&b.y)?);
        let (q, target) = if cb > 1.0 { (1, 1.0) } else { (2, -1.0) };
        let kind = SpecialKind::Resonance { q };
        let (_, node, value) = self.locate(a, b, kind, ca - target, cb - target)?;
        Some((node, kind, value))
    }

    /// Whether the orbit at `Y` has a complex pair of multipliers on the unit circle.
    fn on_circle(&self, y: &[f64]) -> bool {
        let n = self.n();
        self.with_model(y[n + 1], |model| {
            let eval = model.evaluate(&y[..=n], false)?;
            let m = model.monodromy(&y[..=n], &eval)?;
            Some(complex_pair_on_circle(&multipliers(&m)?))
        })
        .unwrap_or(false)
    }

    /// The point where the curve crosses `Y[index] = value` between `a` and `b`.
    fn end_at(&self, a: &Node, b: &Node, index: usize, value: f64) -> Option<Node> {
        let theta = (value - a.y[index]) / (b.y[index] - a.y[index]);
        let guess: Vec<f64> =
            a.y.iter()
                .zip(&b.y)
                .map(|(u, v)| u + theta * (v - u))
                .collect();
        let (y, _, _) = self.correct(&guess, &Border::Fixed { index, value })?;
        Some(Node {
            y,
            tangent: b.tangent.clone(),
        })
    }

    /// Why the curve cannot go on from `y`: merging impacts or a step too small.
    fn stuck(&self, y: &[f64]) -> BoundaryEndReason {
        let n = self.n();
        let mut shortest = 1.0 - y[n - 1].max(0.0);
        let mut last = 0.0;
        for &phase in &y[1..n] {
            shortest = shortest.min(phase - last);
            last = phase;
        }
        if n > 1 && shortest < MERGE_WARNING {
            BoundaryEndReason::FlightMerged
        } else {
            BoundaryEndReason::StepBelowMinimum
        }
    }
}

/// The bound `Y` lies beyond, if any: its index in `Y`, value and end reason.
fn outside(
    y: &[f64],
    n: usize,
    settings: &BoundarySettings,
) -> Option<(usize, f64, BoundaryEndReason)> {
    let (omega, p) = (y[n], y[n + 1]);
    if p < settings.param_min {
        Some((n + 1, settings.param_min, BoundaryEndReason::ParamMin))
    } else if p > settings.param_max {
        Some((n + 1, settings.param_max, BoundaryEndReason::ParamMax))
    } else if omega < settings.omega_min {
        Some((n, settings.omega_min, BoundaryEndReason::OmegaMin))
    } else if omega > settings.omega_max {
        Some((n, settings.omega_max, BoundaryEndReason::OmegaMax))
    } else {
        None
    }
}

/// Euclidean distance.
fn distance(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(u, v)| (u - v).powi(2))
        .sum::<f64>()
        .sqrt()
}
