//! Every regime boundary of a unit scene or a structure: each event of a one-parameter
//! continuation in ω (a unit's branches of [`crate::runs::continuation::Branches`], a
//! structure's of its impact sequences) followed in (ω, a scene parameter) by
//! [`rattle_analytic::follow_boundary`] ([`follow_events`]) or
//! [`rattle_analytic::follow_sequence_boundary`] ([`follow_structure_events`]), the same curve
//! reached from two events listed once.
//!
//! **Same curve.** Each event is followed with its curve's ω solved exactly at the scene's own
//! value `p₀` of the parameter (every crossing of the curve there, the `at` of a boundary). A
//! later event of the same kind on orbits of the same signature and period whose frequency
//! equals one of those crossings within [`SAME_CURVE`] lies on that curve: it is listed under
//! the first curve's `same_as_events`, not as a curve of its own. (Mirror images of an
//! asymmetric orbit have the same events at the same ω, so they share their curves too.) A
//! curve that ends before it comes back to `p₀` does not absorb the events beyond its end.

use crate::output::{finite, table_row};
use crate::runs::boundary::{self, BoundaryRecord};
use crate::runs::continuation::Branches;
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::scene::parameter::{AnyParameterError, ParameterError, SceneParameter};
use crate::scene::structure::StructureForm;
use crate::scene::structure_parameter::{StructureParameter, StructureParameterError};
use crate::scene::Scene;
use rattle_analytic::{
    follow_boundary, follow_sequence_boundary, BoundaryError, BoundarySettings, BoundaryStart,
    Continuation, Event, SequenceBoundaryStart,
};
use rattle_analytic::{ImpactSequence, LinearModel, Signature};
use serde::Serialize;
use std::fmt::Display;
use thiserror::Error;

/// Two events of one kind and signature lie on one curve when the frequency of the second is
/// this close (relative to `1 + ω`) to a crossing of the first's curve at the scene's value:
/// both are located to about `1e-9` (the one-parameter continuation's event location and the
/// curve's Newton on its defining system), distinct events of a branch lie orders of
/// magnitude further apart.
pub const SAME_CURVE: f64 = 1e-7;

/// Why the boundaries cannot be followed.
#[derive(Debug, Error)]
pub enum BoundariesError {
    /// The scene has no stops.
    #[error("the scene has no stops: there is no impacting orbit and no boundary")]
    NoStops,
    /// The parameter cannot be read from the scene.
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
    /// The scene's own value of the parameter lies outside `[--min, --max]`: the events found
    /// there would start no curve inside.
    #[error("--min, --max: the scene's {param} = {value} must lie in [--min, --max] = [{min}, {max}], where the curves start")]
    StartOutside {
        /// The parameter's path.
        param: String,
        /// Its value in the scene.
        value: f64,
        /// `--min`.
        min: f64,
        /// `--max`.
        max: f64,
    },
    /// The curves' settings are refused.
    #[error("{0}")]
    Settings(#[from] BoundaryError),
}

impl From<ParameterError> for BoundariesError {
    fn from(e: ParameterError) -> Self {
        BoundariesError::Parameter(e.into())
    }
}

impl From<StructureParameterError> for BoundariesError {
    fn from(e: StructureParameterError) -> Self {
        BoundariesError::Parameter(e.into())
    }
}

/// One curve, as written: a `rattle boundary` document and the event it was followed from.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CurveRecord {
    /// Index of the event followed in the continuation's events.
    pub from_event: usize,
    /// The branch the event lies on.
    pub branch: usize,
    /// Later events found on this same curve (see the [module](self)), not followed again.
    pub same_as_events: Vec<usize>,
    /// The curve, as `rattle boundary --json` prints it; its `at` holds every crossing of the
    /// curve at the scene's own value `param_start`.
    #[serde(flatten)]
    pub boundary: BoundaryRecord,
}

/// An event whose curve is not followed, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SkippedRecord {
    /// Index of the event in the continuation's events.
    pub event: usize,
    /// The branch it lies on.
    pub branch: usize,
    /// Its kind.
    pub kind: &'static str,
    /// The branch's signature.
    pub signature: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// Its frequency, rad/s.
    pub omega: f64,
    /// Why it is not followed: the filter's reason, or the curve's failure.
    pub reason: String,
}

/// Every boundary of a scene, as `rattle boundaries --json` prints it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BoundariesRecord {
    /// The scene's name.
    pub scene: String,
    /// The parameter's path.
    pub param: String,
    /// Lowest parameter value followed.
    pub min: f64,
    /// Highest parameter value followed.
    pub max: f64,
    /// The parameter's value in the scene, where every curve starts.
    pub param_start: f64,
    /// Lowest frequency of the continuation and the curves, rad/s.
    pub omega_min: f64,
    /// Highest frequency, rad/s.
    pub omega_max: f64,
    /// Branches of the one-parameter continuation.
    pub branches: usize,
    /// Events on them (each a curve, a duplicate of one, or skipped).
    pub events: usize,
    /// The curves, in the order of the events they start from.
    pub curves: Vec<CurveRecord>,
    /// Events not followed.
    pub skipped: Vec<SkippedRecord>,
}

/// Whether `curve` passes through the start of `other` (see the [module](self)).
fn same_curve(curve: &BoundaryRecord, other: &BoundaryRecord) -> bool {
    curve.event == other.event
        && curve.signature == other.signature
        && curve.period == other.period
        && curve
            .at
            .iter()
            .any(|a| (a.omega - other.omega_start).abs() <= SAME_CURVE * (1.0 + a.omega.abs()))
}

/// Which events [`follow_events`] follows; the others are listed as skipped, with the reason.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct EventFilter {
    /// Only the events of orbits with at most this many impacts per cycle (the long orbits of
    /// a doubling cascade cost the most and lie in the thinnest slivers of a map).
    pub max_impacts: Option<usize>,
    /// Only the events that bound a stable motion: at the event no Floquet multiplier lies
    /// outside the unit circle by more than [`STABLE_MARGIN`] (the critical ones lie on it).
    /// Events between unstable orbits border nothing a simulation from rest can show.
    pub stable_only: bool,
}

/// A multiplier of an event's orbit counts as outside the unit circle beyond `1 +` this: far
/// above the event's location error on the critical multipliers, far below the distance of
/// an unstable orbit's multiplier from the circle away from an event.
pub const STABLE_MARGIN: f64 = 1e-6;

impl EventFilter {
    /// Why `event` (of orbits with `impacts` impacts per cycle) is not followed, if it is
    /// not.
    fn refuses<L>(&self, event: &Event<L>, impacts: usize) -> Option<String> {
        if let Some(cap) = self.max_impacts.filter(|&cap| impacts > cap) {
            return Some(format!(
                "{impacts} impacts per cycle: beyond the cap of {cap}, not followed"
            ));
        }
        let outside = event
            .point
            .floquet_multipliers
            .iter()
            .filter(|m| m.norm() > 1.0 + STABLE_MARGIN)
            .count();
        (self.stable_only && outside > 0).then(|| {
            format!("bounds no stable motion ({outside} multiplier(s) outside the unit circle there), not followed")
        })
    }
}

/// Follows every event of `branches` (found on `scene` at its own value of `param`) that
/// `filter` lets through in (ω, `param`) within `settings`, in parallel; the result is in the
/// events' order and does not depend on the thread count. `progress` ticks once per event.
///
/// # Errors
/// [`BoundariesError`] for a scene without stops, a parameter the scene lacks, `--min`/`--max`
/// outside its physical range or not around the scene's value, or refused settings. An event
/// whose curve cannot be followed is listed in `skipped`, not an error.
pub fn follow_events(
    scene: &Scene,
    branches: &Branches,
    param: &SceneParameter,
    settings: &BoundarySettings,
    filter: EventFilter,
    progress: &Progress,
) -> Result<BoundariesRecord, BoundariesError> {
    settings.validate()?;
    scene.stops_model().ok_or(BoundariesError::NoStops)?;
    let param_start = param_start(
        param,
        |v| param.with_value(scene, v).map(|_| ()),
        param.value(scene)?,
        settings,
    )?;
    let at = [param_start];
    let events = Events {
        events: &branches.events,
        signature_of: |e: &Event| branches.branches[e.branch].signature.clone(),
        branches: branches.branches.len(),
    };
    follow_each(
        (&scene.name, param, param_start),
        &events,
        settings,
        filter,
        progress,
        |event, signature| {
            let start = BoundaryStart {
                unit_at: |v: f64| boundary::unit_at(scene, param, v),
                signature,
                event,
                param: param_start,
                at: &at,
            };
            follow_boundary(&start, settings).map(|b| {
                let period = b.signature.period();
                boundary::record(
                    &scene.name,
                    param,
                    (param_start, event.omega),
                    period,
                    &b,
                    |p| p.outer_amplitude,
                )
            })
        },
    )
}

/// [`follow_events`] on a structure: every event of `continuation` (of the structure's
/// impact sequences, found at its own value of `param`) followed on its analytic model, each
/// point's amplitude the observed body's.
///
/// # Errors
/// As [`follow_events`].
pub fn follow_structure_events(
    form: &StructureForm,
    continuation: &Continuation<ImpactSequence>,
    param: &StructureParameter,
    settings: &BoundarySettings,
    filter: EventFilter,
    progress: &Progress,
) -> Result<BoundariesRecord, BoundariesError> {
    settings.validate()?;
    if form.structure.stops.is_empty() {
        return Err(BoundariesError::NoStops);
    }
    let param_start = param_start(
        param,
        |v| param.with_value(&form.scene, v).map(|_| ()),
        param.value(&form.scene)?,
        settings,
    )?;
    let at = [param_start];
    let model_at = |v: f64| -> Result<LinearModel, String> {
        let set = param
            .with_value(&form.scene, v)
            .map_err(|e| e.to_string())?;
        set.structure.analytic_model().map_err(|e| e.to_string())
    };
    let events = Events {
        events: &continuation.events,
        signature_of: |e: &Event<ImpactSequence>| continuation.branches[e.branch].signature.clone(),
        branches: continuation.branches.len(),
    };
    let observe = form.structure.observe;
    follow_each(
        (&form.scene.name, param, param_start),
        &events,
        settings,
        filter,
        progress,
        |event, sequence| {
            let start = SequenceBoundaryStart {
                model_at,
                sequence,
                event,
                param: param_start,
                at: &at,
            };
            follow_sequence_boundary(&start, settings).map(|b| {
                boundary::record(
                    &form.scene.name,
                    param,
                    (param_start, event.omega),
                    sequence.period(),
                    &b,
                    |p| p.amplitudes.get(observe).copied().unwrap_or(f64::NAN),
                )
            })
        },
    )
}

/// The parameter's value in the scene, `start`, after checking that `--min` and `--max` are
/// within its physical range (`set` refuses a value outside) and around `start`.
fn param_start<E: Into<AnyParameterError>>(
    param: &impl Display,
    set: impl Fn(f64) -> Result<(), E>,
    start: f64,
    settings: &BoundarySettings,
) -> Result<f64, BoundariesError> {
    for (option, value) in [("--min", settings.param_min), ("--max", settings.param_max)] {
        set(value).map_err(|e| BoundariesError::Range {
            option,
            source: e.into(),
        })?;
    }
    if !(settings.param_min..=settings.param_max).contains(&start) {
        return Err(BoundariesError::StartOutside {
            param: param.to_string(),
            value: start,
            min: settings.param_min,
            max: settings.param_max,
        });
    }
    Ok(start)
}

/// What a curve's record needs of a branch's signature: a unit's [`Signature`], a model's
/// [`ImpactSequence`].
trait CycleLabel: Display + Sync {
    /// Impacts per cycle.
    fn impacts_per_cycle(&self) -> usize;
    /// Forcing periods per cycle.
    fn periods(&self) -> u32;
}

impl CycleLabel for Signature {
    fn impacts_per_cycle(&self) -> usize {
        self.impacts()
    }
    fn periods(&self) -> u32 {
        self.period()
    }
}

impl CycleLabel for ImpactSequence {
    fn impacts_per_cycle(&self) -> usize {
        self.impacts().len()
    }
    fn periods(&self) -> u32 {
        self.period()
    }
}

/// The events of a continuation, with how to read the signature of the branch each lies on.
struct Events<'a, L, S> {
    /// The events, in the continuation's order.
    events: &'a [Event<L>],
    /// The signature of the branch an event lies on.
    signature_of: S,
    /// The continuation's number of branches.
    branches: usize,
}

/// Follows each of `events` that `filter` lets through by `follow_one` in parallel, and
/// lists the curves (the same curve reached twice listed once) and the events skipped, in
/// the events' order, on the scene named `name` with `param` starting at `param_start`.
fn follow_each<L, S, F>(
    (name, param, param_start): (&str, &impl Display, f64),
    events: &Events<'_, L, S>,
    settings: &BoundarySettings,
    filter: EventFilter,
    progress: &Progress,
    follow_one: F,
) -> Result<BoundariesRecord, BoundariesError>
where
    L: CycleLabel,
    S: Fn(&Event<L>) -> L + Sync,
    F: Fn(&Event<L>, &L) -> Result<BoundaryRecord, BoundaryError> + Sync,
{
    let outcomes = parallel_map(events.events, Grain::Uneven, progress, |event| {
        let signature = (events.signature_of)(event);
        if let Some(reason) = filter.refuses(event, signature.impacts_per_cycle()) {
            return Err(reason);
        }
        follow_one(event, &signature).map_err(|e| e.to_string())
    });
    let mut record = BoundariesRecord {
        scene: name.to_owned(),
        param: param.to_string(),
        min: settings.param_min,
        max: settings.param_max,
        param_start,
        omega_min: settings.omega_min,
        omega_max: settings.omega_max,
        branches: events.branches,
        events: events.events.len(),
        curves: Vec::new(),
        skipped: Vec::new(),
    };
    for (k, (event, outcome)) in events.events.iter().zip(outcomes).enumerate() {
        match outcome {
            Err(reason) => {
                let signature = (events.signature_of)(event);
                record.skipped.push(SkippedRecord {
                    event: k,
                    branch: event.branch,
                    kind: event.kind.name(),
                    signature: signature.to_string(),
                    period: signature.periods(),
                    omega: event.omega,
                    reason,
                })
            }
            Ok(boundary) => match record
                .curves
                .iter_mut()
                .find(|c| same_curve(&c.boundary, &boundary))
            {
                Some(curve) => curve.same_as_events.push(k),
                None => record.curves.push(CurveRecord {
                    from_event: k,
                    branch: event.branch,
                    same_as_events: Vec::new(),
                    boundary,
                }),
            },
        }
    }
    Ok(record)
}

table_row! {
    /// One point of one curve of `rattle boundaries`, as a CSV row.
    pub struct BoundariesRow {
        /// Index of the curve in the document's `curves`.
        pub curve: usize,
        /// Index of the event the curve was followed from.
        pub from_event: usize,
        /// The event kind followed.
        pub event: &'static str,
        /// The orbits' canonical signature.
        pub signature: String,
        /// Forcing periods per cycle.
        pub period: u32,
        /// The parameter's value.
        pub param_value: Option<f64>,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// `X_o`, m.
        pub outer_amplitude: Option<f64>,
        /// Real part of the event's multiplier.
        pub critical_multiplier_re: Option<f64>,
        /// Imaginary part of the event's multiplier.
        pub critical_multiplier_im: Option<f64>,
    }
}

/// The rows of every point of every curve of `record`.
pub fn rows(record: &BoundariesRecord) -> impl Iterator<Item = BoundariesRow> + '_ {
    record.curves.iter().enumerate().flat_map(|(k, c)| {
        c.boundary.points.iter().map(move |p| BoundariesRow {
            curve: k,
            from_event: c.from_event,
            event: c.boundary.event,
            signature: c.boundary.signature.clone(),
            period: c.boundary.period,
            param_value: finite(p.param_value),
            omega: finite(p.omega),
            outer_amplitude: finite(p.outer_amplitude),
            critical_multiplier_re: finite(p.critical_multiplier[0]),
            critical_multiplier_im: finite(p.critical_multiplier[1]),
        })
    })
}
