//! `rattle.boundary`: one regime boundary, as `rattle boundary --json`, over the facade's
//! [`api::boundary`] with the command's own checks ([`BoundaryOptions`]) and messages, the
//! options named as the Python parameters.

use crate::common::{compute_api, json, python_names};
use crate::scene::NativeScene;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rattle_analytic::BoundarySettings;
use rattle_compare::api;
use rattle_compare::runs::boundary::BoundaryOptions;

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

/// The boundary's default `omega_min`, `omega_max` and `max_step`, as the command's.
#[pyfunction]
fn boundary_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = BoundarySettings::new(0.0, 1.0);
    let out = PyDict::new(py);
    out.set_item("omega_min", d.omega_min)?;
    out.set_item("omega_max", d.omega_max)?;
    out.set_item("max_step", d.max_step)?;
    Ok(out)
}

/// `rattle boundary --json`: the event of one kind nearest `omega` on the branches of the
/// signature's orbits there (on a chain: of an impact sequence of its pairs), followed in
/// (ω, the scene parameter) within `[min, max]`; the command's record as JSON text. The
/// options are checked by the command's own check ([`BoundaryOptions`]), in its order. On a
/// structure the signature is an impact sequence of its stops and the parameter a path of
/// the structure form (`structure.stops[0].gap_plus`).
#[pyfunction]
fn boundary(py: Python<'_>, scene: &NativeScene, input: BoundaryInput) -> PyResult<String> {
    let scene = &scene.scene;
    let options = BoundaryOptions {
        signature: input.signature,
        period: u32::try_from(input.period).unwrap_or(0),
        event: input.event,
        omega: input.omega,
        param: input.param,
        min: input.min,
        max: input.max,
        at: input.at,
        omega_min: input.omega_min,
        omega_max: input.omega_max,
        max_step: input.max_step,
    };
    let record = compute_api(py, boundary_names, || api::boundary(scene, &options))?;
    json(&record)
}

/// Registers `boundary_defaults` and `boundary`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(boundary_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(boundary, m)?)?;
    Ok(())
}
