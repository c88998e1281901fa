//! `rattle.boundary`: one regime boundary, as `rattle boundary --json`, over
//! [`rattle_compare::runs::boundary::follow`] with the command's checks in the command's order
//! and its messages, the options named as the Python parameters.

use super::{check_omega, compute, json, python_names, NativeScene};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rattle_analytic::continuation::{BoundaryError, BoundarySettings, EventKind};
use rattle_analytic::{ImpactSequence, Signature};
use rattle_compare::runs::boundary::{
    follow, follow_chain, BoundaryRecord, BoundaryRequest, BoundaryRunError, ChainBoundaryRequest,
};
use rattle_compare::scene::parameter::SceneParameter;
use rattle_compare::scene::Scene;

/// The event kinds, in the command's order.
const KINDS: [EventKind; 6] = [
    EventKind::Fold,
    EventKind::BranchPoint,
    EventKind::PeriodDoubling,
    EventKind::NeimarkSacker,
    EventKind::Grazing,
    EventKind::VanishingImpact,
];

/// The arguments of [`boundary`], as the Python half passes them (a dict, one item each).
#[derive(FromPyObject)]
#[pyo3(from_item_all)]
pub(crate) struct BoundaryInput {
    /// The impact signature of the orbits.
    signature: String,
    /// Forcing periods per cycle.
    period: i64,
    /// The event kind's name.
    event: String,
    /// The frequency near which the event is looked for.
    omega: f64,
    /// The scene parameter's path.
    param: String,
    /// Lowest parameter value.
    min: f64,
    /// Highest parameter value.
    max: f64,
    /// Parameter values at which the curve's ω is solved.
    at: Vec<f64>,
    /// Lowest frequency.
    omega_min: f64,
    /// Highest frequency.
    omega_max: f64,
    /// Largest step along the curve.
    max_step: f64,
}

/// The command's boundary options named as this module's parameters (`--min` is `min`,
/// `--at` is `at`, `boundary.max_step` is `max_step`).
fn boundary_names(message: &str) -> String {
    python_names(message)
        .replace("--event", "event")
        .replace("--param", "param")
        .replace("--min", "min")
        .replace("--max", "max")
        .replace("--at", "at")
        .replace("boundary.max_step", "max_step")
}

/// A `ValueError` with the command's message, named as the Python parameters.
fn bad(message: impl std::fmt::Display) -> PyErr {
    PyValueError::new_err(boundary_names(&message.to_string()))
}

/// The boundary's default `omega_min`, `omega_max` and `max_step`, as the command's.
#[pyfunction]
pub(crate) fn boundary_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = BoundarySettings::new(0.0, 1.0);
    let out = PyDict::new(py);
    out.set_item("omega_min", d.omega_min)?;
    out.set_item("omega_max", d.omega_max)?;
    out.set_item("max_step", d.max_step)?;
    Ok(out)
}

/// What to follow: on a unit a signature's orbits, on a chain an impact sequence's.
enum Request {
    /// A unit scene's request.
    Unit(BoundaryRequest),
    /// A chain scene's request.
    Chain(ChainBoundaryRequest),
}

/// The request and settings of `input` on `scene`, checked as the command checks its
/// arguments, in its order (the frequency, the event, the parameter, the settings, `omega`
/// within them, then the signature: a unit's, or on a chain an impact sequence of its pairs).
fn request(input: BoundaryInput, scene: &Scene) -> PyResult<(Request, BoundarySettings)> {
    let omega = check_omega("omega", input.omega)?;
    let kind = KINDS
        .into_iter()
        .find(|k| k.name() == input.event)
        .ok_or_else(|| {
            bad(format!(
                "--event = {} is not an event: give fold, branch-point, period-doubling, neimark-sacker, grazing or vanishing-impact",
                input.event
            ))
        })?;
    let param: SceneParameter = input
        .param
        .parse()
        .map_err(|e| bad(format!("--param: {e}")))?;
    let settings = BoundarySettings {
        omega_min: input.omega_min,
        omega_max: input.omega_max,
        max_step: input.max_step,
        ..BoundarySettings::new(input.min, input.max)
    };
    let settings = BoundarySettings {
        initial_step: settings.initial_step.min(settings.max_step),
        ..settings
    };
    settings.validate().map_err(bad)?;
    if !(input.omega_min..=input.omega_max).contains(&omega) {
        return Err(bad(format!(
            "--omega = {omega} is out of range: must be in [--omega-min, --omega-max] = [{}, {}]",
            input.omega_min, input.omega_max
        )));
    }
    let period = u32::try_from(input.period).unwrap_or(0);
    let request = if scene.is_chain() {
        let sequence = ImpactSequence::parse(&input.signature, period)
            .map_err(|e| bad(format!("--signature: {e}")))?;
        Request::Chain(ChainBoundaryRequest {
            sequence,
            kind,
            omega,
            param,
            at: input.at,
        })
    } else {
        let signature = Signature::parse(&input.signature, period).map_err(bad)?;
        Request::Unit(BoundaryRequest {
            signature,
            kind,
            omega,
            param,
            at: input.at,
        })
    };
    Ok((request, settings))
}

/// The Python exception for a refused boundary: the caller's (`ValueError`) or a numerical
/// failure (`RuntimeError`), the command's split between its exit codes 2 and 1.
fn run_error(e: BoundaryRunError) -> PyErr {
    match e {
        BoundaryRunError::NoStops
        | BoundaryRunError::CellWithoutStops { .. }
        | BoundaryRunError::Sequence(_)
        | BoundaryRunError::Parameter(_)
        | BoundaryRunError::Range { .. }
        | BoundaryRunError::Boundary(BoundaryError::Setting { .. })
        | BoundaryRunError::Boundary(BoundaryError::Unsupported { .. }) => bad(e),
        _ => PyRuntimeError::new_err(format!("numerical failure: {e}")),
    }
}

/// `rattle boundary --json`: the event of one kind nearest `omega` on the branches of the
/// signature's orbits there (on a chain: of an impact sequence of its pairs), followed in
/// (ω, the scene parameter) within `[min, max]`; the command's record as JSON text.
#[pyfunction]
pub(crate) fn boundary(
    py: Python<'_>,
    scene: &NativeScene,
    input: BoundaryInput,
) -> PyResult<String> {
    let scene = &scene.scene;
    let (request, settings) = request(input, scene)?;
    let record: Result<BoundaryRecord, BoundaryRunError> = compute(py, || {
        Ok(match &request {
            Request::Unit(r) => follow(scene, r, &settings),
            Request::Chain(r) => follow_chain(scene, r, &settings),
        })
    })?;
    json(&record.map_err(run_error)?)
}
