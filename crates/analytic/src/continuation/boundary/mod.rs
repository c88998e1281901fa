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

//!
//! By job: this module holds the curve's types and the entry points; `curve` the defining
//! system (residual, Jacobian, corrector, the orbit at a point), `follow` the follower
//! (predictor–corrector steps, step control, ends, the curve's `ω` at given parameter
//! values), `special` the special points, `branch` Moore's system, `family` the unit or model
//! as a function of the parameter. The tangent and the start's null vector are the
//! continuation's predictor's (`crate::continuation::predictor`).

mod branch;
mod curve;
mod family;
mod follow;
mod special;

pub use special::{BoundarySpecialPoint, SpecialKind};

use super::predictor::null_vector;
use super::result::{Event, EventKind};
use super::settings::check_range_and_steps;
use super::system::{BranchModel, Label};
use super::test_functions::Test;
use crate::model::LinearModel;
use crate::sequence::ImpactSequence;
use crate::signature::Signature;
use crate::unit::{Stops, Unit};
use curve::{Border, EventCurve};
use family::{Family, ModelFamily, UnitFamily};
use nalgebra::Complex;
use thiserror::Error;

/// Relative step of the central differences: `ε^{1/3}`, balancing truncation (`h²`) against
/// rounding (`ε / h`).
const DIFFERENCE_STEP: f64 = 6.055_454_452_393_343e-6;

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
    /// On a model's curve: every coordinate's amplitude over the cycle, in model order
    /// (rigorous extrema); empty on the unit's.
    pub amplitudes: Vec<f64>,
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
