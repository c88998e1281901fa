//! One regime boundary of a scene: the event of one kind nearest a frequency on the
//! branches of a signature's orbits there, followed in (ω, a scene parameter) by
//! [`rattle_analytic::follow_boundary`] on a unit ([`follow`]), by
//! [`rattle_analytic::follow_sequence_boundary`] on a chain ([`follow_chain`]) and on a
//! structure ([`follow_structure`]).

use crate::scene::analytic::{chain_model, orbits_of_signature};
use crate::scene::parameter::{AnyParameter, AnyParameterError, ParameterError, SceneParameter};
use crate::scene::structure::StructureForm;
use crate::scene::structure_parameter::{StructureParameter, StructureParameterError};
use crate::scene::{AnyScene, Scene};
use rattle_analytic::{
    continue_orbit, continue_sequence, follow_boundary, follow_sequence_boundary, Boundary,
    BoundaryError, BoundaryPoint, BoundarySettings, BoundarySpecialPoint, BoundaryStart,
    ContinuationError, ContinuationSettings, Event, EventKind, SequenceBoundaryStart, SpecialKind,
};
use rattle_analytic::{sequence_orbits, ImpactSequence, LinearModel, Signature, Stops, Unit};
use serde::Serialize;
use std::fmt::Display;
use thiserror::Error;

/// What to follow.
#[derive(Debug, Clone)]
pub struct BoundaryRequest {
    /// The signature of the orbits.
    pub signature: Signature,
    /// The event kind.
    pub kind: EventKind,
    /// The frequency near which the event is looked for, rad/s.
    pub omega: f64,
    /// The scene parameter varied.
    pub param: SceneParameter,
    /// Parameter values at which the curve's ω is solved.
    pub at: Vec<f64>,
}

/// What to follow on a chain scene.
#[derive(Debug, Clone)]
pub struct ChainBoundaryRequest {
    /// The impact sequence of the orbits (pairs numbered from the base).
    pub sequence: ImpactSequence,
    /// The event kind.
    pub kind: EventKind,
    /// The frequency near which the event is looked for, rad/s.
    pub omega: f64,
    /// The scene parameter varied (the chain's own field, or a cell's: `chain[K].…`).
    pub param: SceneParameter,
    /// Parameter values at which the curve's ω is solved.
    pub at: Vec<f64>,
}

/// What to follow on a structure scene.
#[derive(Debug, Clone)]
pub struct StructureBoundaryRequest {
    /// The impact sequence of the orbits (stops numbered from 0 in file order).
    pub sequence: ImpactSequence,
    /// The event kind.
    pub kind: EventKind,
    /// The frequency near which the event is looked for, rad/s.
    pub omega: f64,
    /// The structure parameter varied.
    pub param: StructureParameter,
    /// Parameter values at which the curve's ω is solved.
    pub at: Vec<f64>,
}

/// Why no boundary could be followed.
#[derive(Debug, Error)]
pub enum BoundaryRunError {
    /// The scene has no stops.
    #[error("the scene has no stops: there is no impacting orbit and no boundary")]
    NoStops,
    /// A cell of a chain scene has no stops.
    #[error("cell {cell} of the chain has no `stops`: a chain's orbits need stops in every cell")]
    CellWithoutStops {
        /// The cell, numbered from 0 at the base.
        cell: usize,
    },
    /// The impact sequence names a pair the chain lacks.
    #[error("--signature: {0}")]
    Sequence(String),
    /// The parameter cannot be read from the scene or set.
    #[error("--param: {0}")]
    Parameter(#[from] AnyParameterError),
    /// `--min` or `--max` outside the parameter's physical range.
    #[error("{option}: {source}")]
    Range {
        /// `--min` or `--max`.
        option: &'static str,
        /// The scene's refusal, naming the path and its range.
        source: AnyParameterError,
    },
    /// The request was made for a scene of another form than the one given.
    #[error("the boundary's request was made for a scene of another form (unit, chain or structure) than the one given")]
    OtherForm,
    /// The structure's analytic model refuses it.
    #[error("{0}")]
    Model(#[from] rattle_analytic::ModelError),
    /// No orbit of the signature at `--omega`.
    #[error("no {signature} orbit over {period} period(s) at --omega = {omega}: nothing to follow (try `rattle orbit --signature`)")]
    NoOrbit {
        /// The signature.
        signature: String,
        /// Its period.
        period: u32,
        /// The frequency.
        omega: f64,
    },
    /// No event of the kind on the branches through `--omega` within the frequency range.
    #[error("no {kind} on the branches of the {signature} orbits at --omega = {omega} within [--omega-min, --omega-max] = [{min}, {max}]")]
    NoEvent {
        /// The event kind.
        kind: &'static str,
        /// The signature.
        signature: String,
        /// The frequency.
        omega: f64,
        /// Lowest frequency searched.
        min: f64,
        /// Highest frequency searched.
        max: f64,
    },
    /// The one-parameter continuation refused its settings.
    #[error("{0}")]
    Continuation(#[from] ContinuationError),
    /// The boundary refused its settings or start.
    #[error("{0}")]
    Boundary(#[from] BoundaryError),
}

impl From<ParameterError> for BoundaryRunError {
    fn from(e: ParameterError) -> Self {
        BoundaryRunError::Parameter(e.into())
    }
}

impl From<StructureParameterError> for BoundaryRunError {
    fn from(e: StructureParameterError) -> Self {
        BoundaryRunError::Parameter(e.into())
    }
}

/// One point of a boundary, as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundaryPointRecord {
    /// The parameter's value.
    pub param_value: f64,
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// `X_o` (on a structure: the observed body's amplitude).
    pub outer_amplitude: f64,
    /// The event's multiplier, `[re, im]`.
    pub critical_multiplier: [f64; 2],
    /// The kind of the special point this point is (see [`BoundarySpecialRecord::kind`]),
    /// if it is one.
    pub special: Option<&'static str>,
}

/// One special point of the curve, as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundarySpecialRecord {
    /// `turning-point`, `grazing`, `vanishing-impact`, `resonance-1:1`, `resonance-1:2`,
    /// `resonance-1:3`, `resonance-1:4` or `crossing`.
    pub kind: &'static str,
    /// The parameter value.
    pub param_value: f64,
    /// The curve's frequency there.
    pub omega: f64,
    /// At a crossing, the other event (`fold`, `period-doubling`, `neimark-sacker`).
    pub other: Option<&'static str>,
    /// At a grazing, the flight that grazes (from impact `flight` of the signature).
    pub flight: Option<usize>,
    /// At a vanishing impact, the impact's index in the signature.
    pub impact: Option<usize>,
}

impl BoundarySpecialRecord {
    /// The written form of `special`.
    fn of(special: &BoundarySpecialPoint) -> Self {
        let (mut other, mut flight, mut impact) = (None, None, None);
        match special.kind {
            SpecialKind::Crossing { other: o } => other = Some(o.name()),
            SpecialKind::Grazing { flight: f, .. } => flight = Some(f),
            SpecialKind::VanishingImpact { impact: j } => impact = Some(j),
            _ => {}
        }
        Self {
            kind: special.kind.name(),
            param_value: special.param_value,
            omega: special.omega,
            other,
            flight,
            impact,
        }
    }
}

/// The curve's ω at one parameter value, as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundaryAtRecord {
    /// The parameter value.
    pub param_value: f64,
    /// The curve's frequency there.
    pub omega: f64,
}

/// One end of the curve, as written.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundaryEndRecord {
    /// The parameter value of the last point.
    pub param_value: f64,
    /// Its frequency.
    pub omega: f64,
    /// Why the curve stops (`param-min`, `param-max`, `omega-min`, `omega-max`,
    /// `step-below-minimum`, `flight-merged`, `point-cap`, `closed-loop`, `neutral-saddle`).
    pub reason: &'static str,
}

/// A boundary curve, as `rattle boundary --json` prints it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundaryRecord {
    /// The scene's name.
    pub scene: String,
    /// The signature of the orbits, canonical.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// The event kind followed.
    pub event: &'static str,
    /// The parameter's path.
    pub param: String,
    /// The parameter's value in the scene, where the curve starts.
    pub param_start: f64,
    /// The event's frequency at `param_start`.
    pub omega_start: f64,
    /// The points along the curve.
    pub points: Vec<BoundaryPointRecord>,
    /// The curve's ω at each `--at` value (one entry per crossing).
    pub at: Vec<BoundaryAtRecord>,
    /// Special points in order along the curve, each located to rounding (and also one of
    /// the points): turning points in the parameter, grazings and vanishing impacts of the
    /// orbit, strong resonances of a Neimark–Sacker curve, crossings with the curves of the
    /// orbit's other events.
    pub special_points: Vec<BoundarySpecialRecord>,
    /// The two ends, the first point's then the last point's.
    pub ends: Vec<BoundaryEndRecord>,
}

/// The unit and stops of `scene` with `param` set to `value`.
pub(crate) fn unit_at(
    scene: &Scene,
    param: &SceneParameter,
    value: f64,
) -> Result<(Unit, Stops), BoundaryRunError> {
    let scene = param.with_value(scene, value)?;
    let stops = scene.stops_model().ok_or(BoundaryRunError::NoStops)?;
    Ok((scene.unit_model(), stops))
}

/// The event of `request.kind` nearest `request.omega` on the branches through every orbit of
/// the signature at `request.omega` (each followed within the settings' frequency range,
/// without switching).
fn nearest_event(
    scene: &Scene,
    request: &BoundaryRequest,
    settings: &BoundarySettings,
) -> Result<Event, BoundaryRunError> {
    let (unit, stops) = (
        scene.unit_model(),
        scene.stops_model().ok_or(BoundaryRunError::NoStops)?,
    );
    let starts = orbits_of_signature(scene, request.omega, &request.signature);
    if starts.is_empty() {
        return Err(BoundaryRunError::NoOrbit {
            signature: request.signature.to_string(),
            period: request.signature.period(),
            omega: request.omega,
        });
    }
    let continuation = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(settings.omega_min, settings.omega_max)
    };
    let mut best: Option<Event> = None;
    for start in &starts {
        let c = continue_orbit(&unit, &stops, start, &continuation)?;
        for e in c.events.into_iter().filter(|e| e.kind == request.kind) {
            let d = |e: &Event| (e.omega - request.omega).abs();
            if best.as_ref().is_none_or(|b| d(&e) < d(b)) {
                best = Some(e);
            }
        }
    }
    best.ok_or_else(|| BoundaryRunError::NoEvent {
        kind: request.kind.name(),
        signature: request.signature.to_string(),
        omega: request.omega,
        min: settings.omega_min,
        max: settings.omega_max,
    })
}

/// The options of one boundary as a user gives them (the command's flags, Python's
/// arguments), before they are checked. Error messages name the command's flags (`--event`,
/// `--min`, …); Python renames them to its parameters.
#[derive(Debug, Clone)]
pub struct BoundaryOptions {
    /// The signature (on a chain: an impact sequence of its pairs), as typed.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// The event kind's name.
    pub event: String,
    /// The frequency near which the event is looked for, rad/s.
    pub omega: f64,
    /// The scene parameter's JSON path.
    pub param: String,
    /// Lowest parameter value.
    pub min: f64,
    /// Highest parameter value.
    pub max: f64,
    /// Parameter values at which the curve's ω is solved.
    pub at: Vec<f64>,
    /// Lowest frequency, rad/s.
    pub omega_min: f64,
    /// Highest frequency, rad/s.
    pub omega_max: f64,
    /// Largest step along the curve.
    pub max_step: f64,
}

/// The options of a boundary that do not depend on the scene, checked.
#[derive(Debug, Clone)]
pub struct CheckedOptions {
    /// The event kind.
    pub kind: EventKind,
    /// The frequency near which the event is looked for, rad/s.
    pub omega: f64,
    /// The scene parameter (of the unit and chain forms, or of the structure form).
    pub param: AnyParameter,
    /// The curve's settings.
    pub settings: BoundarySettings,
}

/// What to follow on a scene: a unit's signature or a chain's impact sequence.
#[derive(Debug, Clone)]
pub enum AnyBoundaryRequest {
    /// On a unit scene.
    Unit(BoundaryRequest),
    /// On a chain scene.
    Chain(ChainBoundaryRequest),
    /// On a structure scene.
    Structure(StructureBoundaryRequest),
}

/// The event kinds, in the order the command lists them.
const KINDS: [EventKind; 6] = [
    EventKind::Fold,
    EventKind::BranchPoint,
    EventKind::PeriodDoubling,
    EventKind::NeimarkSacker,
    EventKind::Grazing,
    EventKind::VanishingImpact,
];

impl BoundaryOptions {
    /// The options that do not depend on the scene, checked in the command's order: the
    /// frequency, the event, the parameter's path, the settings, then the frequency within
    /// `[omega_min, omega_max]`.
    ///
    /// # Errors
    /// A message naming the flag and what it allows.
    pub fn checked(&self) -> Result<CheckedOptions, String> {
        let omega = self.omega;
        if !(omega.is_finite() && omega > 0.0) {
            return Err(format!(
                "--omega = {omega} is out of range: must be finite and > 0 (rad/s)"
            ));
        }
        let kind = KINDS
            .into_iter()
            .find(|k| k.name() == self.event)
            .ok_or_else(|| {
                format!(
                    "--event = {} is not an event: give fold, branch-point, period-doubling, neimark-sacker, grazing or vanishing-impact",
                    self.event
                )
            })?;
        let param: AnyParameter = self.param.parse().map_err(|e| format!("--param: {e}"))?;
        let settings = BoundarySettings {
            omega_min: self.omega_min,
            omega_max: self.omega_max,
            max_step: self.max_step,
            ..BoundarySettings::new(self.min, self.max)
        };
        let settings = BoundarySettings {
            initial_step: settings.initial_step.min(settings.max_step),
            ..settings
        };
        settings.validate().map_err(|e| e.to_string())?;
        if !(self.omega_min..=self.omega_max).contains(&omega) {
            return Err(format!(
                "--omega = {omega} is out of range: must be in [--omega-min, --omega-max] = [{}, {}]",
                self.omega_min, self.omega_max
            ));
        }
        Ok(CheckedOptions {
            kind,
            omega,
            param,
            settings,
        })
    }

    /// The request on `scene`: on a chain the signature is an impact sequence of its pairs,
    /// on a structure of its stops.
    ///
    /// # Errors
    /// A message naming `--signature` or `--period` when the signature does not parse, and
    /// `--param` for a path of the other form than the scene's.
    pub fn request(
        &self,
        checked: &CheckedOptions,
        scene: &AnyScene,
    ) -> Result<AnyBoundaryRequest, String> {
        let (kind, omega, at) = (checked.kind, checked.omega, self.at.clone());
        let path = checked.param.to_string();
        let bad_param = |e: AnyParameterError| format!("--param: {e}");
        let (scene, param) = match scene {
            AnyScene::Structure(form) => {
                let param: StructureParameter = path
                    .parse()
                    .map_err(|e: StructureParameterError| bad_param(e.into()))?;
                let sequence = form
                    .structure
                    .sequence(&self.signature, self.period)
                    .map_err(|e| format!("--signature: {e}"))?;
                return Ok(AnyBoundaryRequest::Structure(StructureBoundaryRequest {
                    sequence,
                    kind,
                    omega,
                    param,
                    at,
                }));
            }
            AnyScene::Cells(scene) => {
                let param: SceneParameter = path
                    .parse()
                    .map_err(|e: ParameterError| bad_param(e.into()))?;
                (scene, param)
            }
        };
        Ok(if scene.is_chain() {
            let sequence = ImpactSequence::parse(&self.signature, self.period)
                .map_err(|e| format!("--signature: {e}"))?;
            AnyBoundaryRequest::Chain(ChainBoundaryRequest {
                sequence,
                kind,
                omega,
                param,
                at,
            })
        } else {
            let signature =
                Signature::parse(&self.signature, self.period).map_err(|e| e.to_string())?;
            AnyBoundaryRequest::Unit(BoundaryRequest {
                signature,
                kind,
                omega,
                param,
                at,
            })
        })
    }
}

impl BoundaryRunError {
    /// Whether the caller is at fault (bad input: the command's exit code 2, Python's
    /// `ValueError`) rather than the numerics (no orbit, no event, no convergence).
    pub fn is_bad_input(&self) -> bool {
        matches!(
            self,
            BoundaryRunError::NoStops
                | BoundaryRunError::CellWithoutStops { .. }
                | BoundaryRunError::Sequence(_)
                | BoundaryRunError::Parameter(_)
                | BoundaryRunError::Range { .. }
                | BoundaryRunError::OtherForm
                | BoundaryRunError::Boundary(BoundaryError::Setting { .. })
                | BoundaryRunError::Boundary(BoundaryError::Unsupported { .. })
        )
    }
}

/// Follows the boundary of `request` on `scene` ([`follow`] on a unit, [`follow_chain`] on
/// a chain) within `settings`.
///
/// # Errors
/// See [`BoundaryRunError`].
pub fn follow_any(
    scene: &AnyScene,
    request: &AnyBoundaryRequest,
    settings: &BoundarySettings,
) -> Result<BoundaryRecord, BoundaryRunError> {
    match (scene, request) {
        (AnyScene::Cells(scene), AnyBoundaryRequest::Unit(r)) => follow(scene, r, settings),
        (AnyScene::Cells(scene), AnyBoundaryRequest::Chain(r)) => follow_chain(scene, r, settings),
        (AnyScene::Structure(form), AnyBoundaryRequest::Structure(r)) => {
            follow_structure(form, r, settings)
        }
        _ => Err(BoundaryRunError::OtherForm),
    }
}

/// Follows the boundary of `request` on the unit scene `scene` within `settings`.
///
/// # Errors
/// See [`BoundaryRunError`].
pub fn follow(
    scene: &Scene,
    request: &BoundaryRequest,
    settings: &BoundarySettings,
) -> Result<BoundaryRecord, BoundaryRunError> {
    let param_start = param_start(scene, &request.param, settings)?;
    let event = nearest_event(scene, request, settings)?;
    let start = BoundaryStart {
        unit_at: |v: f64| unit_at(scene, &request.param, v),
        signature: &request.signature,
        event: &event,
        param: param_start,
        at: &request.at,
    };
    let boundary = follow_boundary(&start, settings)?;
    Ok(record(
        &scene.name,
        &request.param,
        (param_start, event.omega),
        boundary.signature.period(),
        &boundary,
        |p| p.outer_amplitude,
    ))
}

/// The parameter's value in `scene`, after checking that `--min` and `--max` are within its
/// physical range.
fn param_start(
    scene: &Scene,
    param: &SceneParameter,
    settings: &BoundarySettings,
) -> Result<f64, BoundaryRunError> {
    settings.validate()?;
    let start = param.value(scene)?;
    for (option, value) in [("--min", settings.param_min), ("--max", settings.param_max)] {
        param
            .with_value(scene, value)
            .map_err(|e| BoundaryRunError::Range {
                option,
                source: e.into(),
            })?;
    }
    Ok(start)
}

/// The chain model of `scene` with `param` set to `value`.
fn model_at(
    scene: &Scene,
    param: &SceneParameter,
    value: f64,
) -> Result<LinearModel, BoundaryRunError> {
    let scene = param.with_value(scene, value)?;
    chain_model(&scene).map_err(|cell| BoundaryRunError::CellWithoutStops { cell })
}

/// The event of `kind` nearest `omega` on the branches through every orbit of `sequence`
/// at `omega` on `model` (a chain's, a structure's).
fn nearest_sequence_event(
    model: &LinearModel,
    (sequence, kind, omega): (&ImpactSequence, EventKind, f64),
    settings: &BoundarySettings,
) -> Result<Event<ImpactSequence>, BoundaryRunError> {
    let starts = sequence_orbits(model, omega, sequence)
        .map_err(|e| BoundaryRunError::Sequence(e.to_string()))?;
    if starts.is_empty() {
        return Err(BoundaryRunError::NoOrbit {
            signature: sequence.to_string(),
            period: sequence.period(),
            omega,
        });
    }
    let continuation = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(settings.omega_min, settings.omega_max)
    };
    let mut best: Option<Event<ImpactSequence>> = None;
    for start in &starts {
        let c = continue_sequence(model, start, &continuation)?;
        for e in c.events.into_iter().filter(|e| e.kind == kind) {
            let d = |e: &Event<ImpactSequence>| (e.omega - omega).abs();
            if best.as_ref().is_none_or(|b| d(&e) < d(b)) {
                best = Some(e);
            }
        }
    }
    best.ok_or_else(|| BoundaryRunError::NoEvent {
        kind: kind.name(),
        signature: sequence.to_string(),
        omega,
        min: settings.omega_min,
        max: settings.omega_max,
    })
}

/// Follows the boundary of `request` on the chain scene `scene` within `settings`: as
/// [`follow`], on the chain's orbits of an impact sequence (grazing and vanishing impact of
/// any contact pair), the parameter a field of the whole chain or of one cell.
///
/// # Errors
/// See [`BoundaryRunError`]; [`BoundaryRunError::CellWithoutStops`] for a cell without
/// stops, [`BoundaryRunError::Sequence`] for a sequence naming a pair the chain lacks.
pub fn follow_chain(
    scene: &Scene,
    request: &ChainBoundaryRequest,
    settings: &BoundarySettings,
) -> Result<BoundaryRecord, BoundaryRunError> {
    let param_start = param_start(scene, &request.param, settings)?;
    let model = model_at(scene, &request.param, param_start)?;
    let event = nearest_sequence_event(
        &model,
        (&request.sequence, request.kind, request.omega),
        settings,
    )?;
    let start = SequenceBoundaryStart {
        model_at: |v: f64| model_at(scene, &request.param, v),
        sequence: &request.sequence,
        event: &event,
        param: param_start,
        at: &request.at,
    };
    let boundary = follow_sequence_boundary(&start, settings)?;
    Ok(record(
        &scene.name,
        &request.param,
        (param_start, event.omega),
        request.sequence.period(),
        &boundary,
        |p| p.outer_amplitude,
    ))
}

/// Follows the boundary of `request` on the structure `form` within `settings`: as
/// [`follow_chain`], on the structure's orbits of an impact sequence of its stops, the
/// parameter a field of the structure scene; each point's amplitude is the observed body's.
///
/// # Errors
/// See [`BoundaryRunError`]; [`BoundaryRunError::Sequence`] for a sequence naming a stop the
/// structure lacks.
pub fn follow_structure(
    form: &StructureForm,
    request: &StructureBoundaryRequest,
    settings: &BoundarySettings,
) -> Result<BoundaryRecord, BoundaryRunError> {
    settings.validate()?;
    let param = &request.param;
    let param_start = param.value(&form.scene)?;
    for (option, value) in [("--min", settings.param_min), ("--max", settings.param_max)] {
        param
            .with_value(&form.scene, value)
            .map_err(|e| BoundaryRunError::Range {
                option,
                source: e.into(),
            })?;
    }
    let model_at = |v: f64| -> Result<LinearModel, BoundaryRunError> {
        Ok(param
            .with_value(&form.scene, v)?
            .structure
            .analytic_model()?)
    };
    let model = model_at(param_start)?;
    request
        .sequence
        .check(&model)
        .map_err(|e| BoundaryRunError::Sequence(e.to_string()))?;
    let event = nearest_sequence_event(
        &model,
        (&request.sequence, request.kind, request.omega),
        settings,
    )?;
    let start = SequenceBoundaryStart {
        model_at,
        sequence: &request.sequence,
        event: &event,
        param: param_start,
        at: &request.at,
    };
    let boundary = follow_sequence_boundary(&start, settings)?;
    let structure = &form.structure;
    Ok(record(
        &form.scene.name,
        param,
        (param_start, event.omega),
        request.sequence.period(),
        &boundary,
        |p| {
            p.amplitudes
                .get(structure.observe)
                .copied()
                .unwrap_or(f64::NAN)
        },
    ))
}

/// The written form of `boundary` (of orbits over `period` forcing periods) on the scene
/// named `scene`, started at `param_start` from the event at `omega_start`, each point's
/// amplitude by `amplitude`.
pub(crate) fn record<L: Display>(
    scene: &str,
    param: &impl Display,
    (param_start, omega_start): (f64, f64),
    period: u32,
    boundary: &Boundary<L>,
    amplitude: impl Fn(&BoundaryPoint) -> f64,
) -> BoundaryRecord {
    BoundaryRecord {
        scene: scene.to_owned(),
        signature: boundary.signature.to_string(),
        period,
        event: boundary.kind.name(),
        param: param.to_string(),
        param_start,
        omega_start,
        points: boundary
            .points
            .iter()
            .map(|p| BoundaryPointRecord {
                param_value: p.param_value,
                omega: p.omega,
                outer_amplitude: amplitude(p),
                critical_multiplier: [p.critical_multiplier.re, p.critical_multiplier.im],
                special: boundary
                    .special_points
                    .iter()
                    .find(|s| s.point == *p)
                    .map(|s| s.kind.name()),
            })
            .collect(),
        at: boundary
            .at
            .iter()
            .map(|a| BoundaryAtRecord {
                param_value: a.param_value,
                omega: a.omega,
            })
            .collect(),
        special_points: boundary
            .special_points
            .iter()
            .map(BoundarySpecialRecord::of)
            .collect(),
        ends: boundary
            .ends
            .iter()
            .map(|e| BoundaryEndRecord {
                param_value: e.param_value,
                omega: e.omega,
                reason: e.reason.name(),
            })
            .collect(),
    }
}
