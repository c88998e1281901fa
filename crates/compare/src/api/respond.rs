//! `rattle respond`: the exact response of a scene's structure to a non-periodic signal from
//! rest ([`rattle_event_driven::respond`]), the signal in place of the scene's own harmonic
//! base motion.

use super::ApiError;
use crate::output::respond::{sample_columns, RespondRecord};
use crate::runs::parallel::Progress;
use crate::scene::frequency::FrequencyBounds;
use crate::scene::signal::{BuiltSignal, Input, SignalSpec};
use crate::scene::structure::Structure;
use crate::scene::AnyScene;
use rattle_event_driven::{respond as engine_respond, Model};
use rattle_event_driven::{
    respond_sampled, Excitation, ResponseError, ResponseOptions, SignalError, MAX_DURATION_SCALES,
    MAX_RESPONSE_SAMPLES,
};
use std::f64::consts::TAU;

/// The default sampling of the table: this many samples per period of the fastest of the
/// structure's natural frequencies and the signal's.
pub const DEFAULT_SAMPLES_PER_PERIOD: f64 = 64.0;

/// At most this many samples by default (more with an explicit count, up to
/// [`MAX_RESPONSE_SAMPLES`]).
pub const DEFAULT_MAX_SAMPLES: u64 = 1_000_000;

/// What to respond to: `rattle respond SCENE --signal SPEC --duration T --at … --on BODY`.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseRequest {
    /// `--signal`: a `.csv` record, `tone-burst:…`, `sweep:…` or `random:…`
    /// ([`crate::scene::signal`]).
    pub signal: String,
    /// `T`, s: finite, `> 0`, at most `10⁷` periods of the fastest oscillation.
    pub duration: f64,
    /// Times at which to report the state, each in `[0, T]`.
    pub at: Vec<f64>,
    /// The body a force record acts on, by its name in the scene.
    pub on: Option<String>,
}

/// A request checked and built, ready to run: every refusal happens here, before anything
/// is computed or written.
#[derive(Debug, Clone)]
pub struct PreparedResponse {
    scene: String,
    structure: Structure,
    model: Model,
    excitation: Excitation,
    built: BuiltSignal,
    options: ResponseOptions,
    on: Option<String>,
}

/// The scene's structure: the structure form's own, or the unit's or chain's written as one
/// (bodies `outer`, `inner`, or `outer0`, `inner0`, `outer1`, …).
fn structure_of(scene: &AnyScene) -> Result<Structure, ApiError> {
    match scene {
        AnyScene::Structure(form) => Ok(form.structure.clone()),
        AnyScene::Cells(cells) => cells
            .structure_scene(cells.base.clone())
            .structure()
            .map_err(|e| ApiError::Numerical(format!("the scene as a structure: {e}"))),
    }
}

/// Checks and builds `request` on `scene`.
///
/// # Errors
/// [`ApiError::Argument`] naming the option: `--duration` (not finite and `> 0`, or beyond
/// `10⁷` periods of the fastest of the structure's natural frequencies and the signal's),
/// `--at` (outside `[0, T]`), `--signal` and its field ([`SignalSpec::parse`],
/// [`SignalSpec::build`]; a base motion on a scene with nothing tied to the base), `--on`
/// (naming no body, given with a signal that is not a force record, or missing for one).
pub fn prepare_response(
    scene: &AnyScene,
    request: &ResponseRequest,
) -> Result<PreparedResponse, ApiError> {
    let duration = request.duration;
    if !(duration.is_finite() && duration > 0.0) {
        return Err(ApiError::Argument(format!(
            "--duration = {duration} is out of range: must be finite and > 0 (s)"
        )));
    }
    for (i, &t) in request.at.iter().enumerate() {
        if !(t.is_finite() && (0.0..=duration).contains(&t)) {
            return Err(ApiError::Argument(format!(
                "--at[{i}] = {t} is out of range: must be in [0, T = {duration}] (s)"
            )));
        }
    }
    let spec = SignalSpec::parse(&request.signal).map_err(|e| ApiError::Argument(e.to_string()))?;
    prepare_spec(scene, &spec, request)
}

/// [`prepare_response`] of a signal already read (`request.signal` is its text, for the
/// messages): `rattle transmission` builds each run's random signal from one spec.
///
/// # Errors
/// As [`prepare_response`], but for `--signal`'s syntax, already read.
pub(crate) fn prepare_spec(
    scene: &AnyScene,
    spec: &SignalSpec,
    request: &ResponseRequest,
) -> Result<PreparedResponse, ApiError> {
    let duration = request.duration;
    if request.on.is_some() && !spec.is_file() {
        return Err(ApiError::Argument(format!(
            "--on is for a force record (a .csv file with the columns t,F); --signal {} is a \
             base motion",
            request.signal
        )));
    }
    let structure = structure_of(scene)?;
    let fastest_mode = FrequencyBounds::of_structure(&structure).fastest;
    let amplitude = structure.base_amplitude.unwrap_or(1.0);
    let built = spec
        .build(duration, amplitude)
        .map_err(|e| ApiError::Argument(e.to_string()))?;
    let fastest = fastest_mode.max(built.description.fastest_frequency());
    if duration * fastest / TAU > MAX_DURATION_SCALES {
        return Err(ApiError::Argument(format!(
            "--duration = {duration} is out of range: must be at most 1e7 periods of the \
             fastest oscillation (2π/{fastest} s), {} s",
            MAX_DURATION_SCALES * TAU / fastest
        )));
    }
    let n = structure.dofs();
    let (excitation, on) = match (built.input, &request.on) {
        (Input::Force, Some(body)) => {
            let dof = structure
                .names
                .iter()
                .position(|b| b == body)
                .ok_or_else(|| {
                    ApiError::Argument(format!(
                        "--on = {body} names no body: the bodies are {}",
                        structure.names.join(", ")
                    ))
                })?;
            (Excitation::force(n, dof), Some(body.clone()))
        }
        (Input::Force, None) => {
            return Err(ApiError::Argument(format!(
                "--on is missing: the record {} is a force (column F); name the body it acts \
                 on with --on",
                request.signal
            )))
        }
        (Input::Base, Some(_)) => {
            return Err(ApiError::Argument(format!(
                "--on is for a force record (columns t,F); the record {} is a base motion \
                 (column u_g)",
                request.signal
            )))
        }
        (Input::Base, None) => {
            let tied = structure
                .base_stiffness
                .iter()
                .chain(structure.base_damping.iter())
                .any(|&x| x != 0.0);
            if !tied {
                return Err(ApiError::Argument(format!(
                    "--signal {}: the scene has no spring or dashpot tied to the base for a \
                     base motion to act through; give a force record (t,F) with --on",
                    request.signal
                )));
            }
            (
                Excitation::new(
                    structure.base_stiffness.clone(),
                    structure.base_damping.clone(),
                ),
                None,
            )
        }
    };
    // Any valid frequency: the response ignores the model's periodic forcing.
    let model = structure
        .event_model(1.0)
        .map_err(|e| ApiError::Numerical(e.to_string()))?;
    let mut options = ResponseOptions::over(duration);
    options.at = request.at.clone();
    Ok(PreparedResponse {
        scene: scene.name().to_owned(),
        structure,
        model,
        excitation,
        built,
        options,
        on,
    })
}

impl PreparedResponse {
    /// The columns of the sampled table: `t`, `u_g` or `F`, then `u:NAME` and `v:NAME` of
    /// every body.
    pub fn columns(&self) -> Vec<String> {
        sample_columns(&self.structure, self.built.input)
    }

    /// The structure the response is of.
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// The built signal.
    pub fn signal(&self) -> &BuiltSignal {
        &self.built
    }

    /// The default number of sample intervals: [`DEFAULT_SAMPLES_PER_PERIOD`] per period of
    /// the fastest of the structure's natural frequencies and the signal's, at most
    /// [`DEFAULT_MAX_SAMPLES`].
    pub fn default_samples(&self) -> u64 {
        let fastest = FrequencyBounds::of_structure(&self.structure)
            .fastest
            .max(self.built.description.fastest_frequency());
        let periods = self.options.duration * fastest / TAU;
        ((DEFAULT_SAMPLES_PER_PERIOD * periods).ceil() as u64).clamp(1, DEFAULT_MAX_SAMPLES)
    }

    /// Runs the response; with `samples = Some(N)`, the `N + 1` uniform samples `t_j = jT/N`
    /// go to `sink` in time order as rows `[t, s(t), u…, u̇…]` (the columns of
    /// [`PreparedResponse::columns`]), and `progress` steps once per sample. The sink's first
    /// error ends the run's writing and is returned.
    ///
    /// # Errors
    /// [`ApiError::Argument`] naming `--samples` (in `1..=10⁷`) or `--duration` (the engine's
    /// cap); [`ApiError::Numerical`] when the engine fails (dependent held stops, more than
    /// its cap of events); the sink's error.
    pub fn run(
        &self,
        samples: Option<u64>,
        progress: &Progress,
        sink: &mut dyn FnMut(&[f64]) -> Result<(), ApiError>,
    ) -> Result<RespondRecord, ApiError> {
        let signal = &self.built.signal;
        let response = match samples {
            None => engine_respond(&self.model, &self.excitation, signal, &self.options),
            Some(count) => {
                if !(1..=MAX_RESPONSE_SAMPLES).contains(&count) {
                    return Err(ApiError::Argument(format!(
                        "--samples = {count} is out of range: must be in [1, {MAX_RESPONSE_SAMPLES}]"
                    )));
                }
                let mut failed: Option<ApiError> = None;
                let mut row = Vec::with_capacity(2 + 2 * self.structure.dofs());
                let result = respond_sampled(
                    &self.model,
                    &self.excitation,
                    signal,
                    &self.options,
                    count,
                    &mut |s| {
                        progress.step();
                        if failed.is_some() {
                            return;
                        }
                        row.clear();
                        row.push(s.t);
                        row.push(signal.value_and_rate(s.t).0);
                        row.extend_from_slice(s.displacements);
                        row.extend_from_slice(s.velocities);
                        if let Err(e) = sink(&row) {
                            failed = Some(e);
                        }
                    },
                );
                progress.done();
                if let Some(e) = failed {
                    return Err(e);
                }
                result
            }
        }
        .map_err(engine_error)?;
        Ok(RespondRecord::new(
            &self.scene,
            &self.structure,
            (self.built.input, self.on.clone()),
            self.built.description.clone(),
            &response,
        ))
    }
}

/// The engine's refusal as the command's: its input errors name the option.
fn engine_error(e: ResponseError) -> ApiError {
    match e {
        ResponseError::Input(SignalError::OutOfRange {
            field,
            value,
            allowed,
        }) => {
            let option = match field.as_str() {
                "duration" => "--duration".to_owned(),
                "samples" => "--samples".to_owned(),
                f if f.starts_with("at[") => format!("--{f}"),
                f => format!("--signal {f}"),
            };
            ApiError::Argument(format!(
                "{option} = {value} is out of range: must be {allowed}"
            ))
        }
        other => ApiError::Numerical(other.to_string()),
    }
}

/// The response of `scene` to `request`, without samples ([`prepare_response`] then
/// [`PreparedResponse::run`]).
///
/// # Errors
/// As [`prepare_response`] and [`PreparedResponse::run`].
pub fn respond(scene: &AnyScene, request: &ResponseRequest) -> Result<RespondRecord, ApiError> {
    prepare_response(scene, request)?.run(None, &Progress::hidden(), &mut |_| Ok(()))
}
