//! What every binding shares: the boundary's contracts (the GIL released, a panic or a
//! numerical failure raised as a `RuntimeError`, records handed over as JSON text) and the
//! checks of the options several commands take, worded as the command words them.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rattle_compare::api::{self, ApiError};
use rattle_compare::runs::shard::Shard;
use rattle_compare::scene::simulator::Accuracy;
use rattle_compare::scene::{AnyScene, Scene};
use rattle_event_driven::SimulationOptions;
use serde::Serialize;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Refuses a chain scene for a function that takes a single unit, with the command's message.
pub(crate) fn unit_only(scene: &Scene, function: &str) -> PyResult<()> {
    scene
        .refuse_chain(function)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// Compact JSON text of a record.
pub(crate) fn json(record: &impl Serialize) -> PyResult<String> {
    serde_json::to_string(record).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The text of a panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_owned()
    }
}

/// Runs `work` with the GIL released. Its error is a numerical failure (`RuntimeError`, worded
/// as the command words it); a panic is caught and raised as a `RuntimeError`, never unwound
/// into Python.
pub(crate) fn compute<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> Result<T, String> + Send,
) -> PyResult<T> {
    py.detach(|| catch_unwind(AssertUnwindSafe(work)))
        .map_err(|payload| {
            PyRuntimeError::new_err(format!(
                "internal error (a bug in rattle, please report it): {}",
                panic_text(payload.as_ref())
            ))
        })?
        .map_err(|message| PyRuntimeError::new_err(format!("numerical failure: {message}")))
}

/// Runs the facade call `work` with the GIL released ([`compute`]), its [`ApiError`] raised as
/// the command words it: a numerical failure a `RuntimeError`, a table that cannot be written
/// an `OSError`, bad input a `ValueError` whose message `names` renames (the command's options
/// named as the Python parameters).
pub(crate) fn compute_api<T: Send>(
    py: Python<'_>,
    names: fn(&str) -> String,
    work: impl FnOnce() -> Result<T, ApiError> + Send,
) -> PyResult<T> {
    compute(py, || Ok(work()))?.map_err(|e| match e {
        ApiError::Numerical(message) => {
            PyRuntimeError::new_err(format!("numerical failure: {message}"))
        }
        ApiError::Write { .. } => PyOSError::new_err(e.to_string()),
        ApiError::Scene(_) | ApiError::Frequency(_) | ApiError::Argument(_) => {
            PyValueError::new_err(names(&e.to_string()))
        }
    })
}

/// The command's options named as this module's parameters (`--steady-tol` is `steady_tol`).
pub(crate) fn python_names(message: &str) -> String {
    message
        .replace("--lyapunov-periods", "lyapunov_periods")
        .replace("--max-oscillations", "max_oscillations")
        .replace("--max-periods", "max_periods")
        .replace("--steady-tol", "steady_tol")
        .replace("--tol", "tol")
        .replace("--signature", "signature")
        .replace("--samples-per-period", "samples_per_period")
        .replace("--sampled-periods", "sampled_periods")
        .replace("--period", "period")
        .replace("--orbit", "orbit")
        .replace("--max-step", "max_step")
        .replace("--max-branches", "max_branches")
        .replace("--omega-min", "omega_min")
        .replace("--omega-max", "omega_max")
        .replace("--omega", "omega")
        .replace("continuation.max_step", "max_step")
}

/// `omega` if finite and positive; else the command's message, naming `name`.
pub(crate) fn check_omega(name: &str, omega: f64) -> PyResult<f64> {
    if omega.is_finite() && omega > 0.0 {
        Ok(omega)
    } else {
        Err(PyValueError::new_err(format!(
            "{name} = {omega} is out of range: must be finite and > 0 (rad/s)"
        )))
    }
}

/// `omega` if `scene`, of either form, can be run at it in bounded time; else the command's
/// message, naming `name` ([`api::check_frequency`]).
pub(crate) fn check_any_frequency(scene: &AnyScene, name: &str, omega: f64) -> PyResult<f64> {
    api::check_frequency(scene, name, omega).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// A count that must be at least 1.
pub(crate) fn positive(name: &str, value: i64) -> PyResult<u64> {
    u64::try_from(value)
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| PyValueError::new_err(format!("{name} must be > 0")))
}

/// The simulator's options from the accuracy knobs, checked by the library's ranges, the
/// command's too ([`Accuracy::options`]; messages named as the Python parameters).
pub(crate) fn options(
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
) -> PyResult<SimulationOptions> {
    let max_periods = positive("max_periods", max_periods)?;
    Accuracy {
        tol,
        steady_tol,
        max_periods,
        max_oscillations,
    }
    .options()
    .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))
}

/// `(K, N)` from Python as the command's `--shard K/N`; `None` for the whole run.
pub(crate) fn shard(value: Option<(i64, i64)>) -> PyResult<Option<Shard>> {
    value
        .map(|(k, n)| {
            Shard::parse(&format!("{k}/{n}")).map_err(|_| {
                PyValueError::new_err(format!(
                    "shard = ({k}, {n}): must be (K, N) with 1 ≤ K ≤ N, e.g. (3, 8)"
                ))
            })
        })
        .transpose()
}

/// A count from Python, refused with `message` when negative (the command takes `usize`;
/// zero is refused by the grid's own checks, with the command's message).
pub(crate) fn count_of(name: &str, n: i64) -> PyResult<usize> {
    usize::try_from(n)
        .map_err(|_| PyValueError::new_err(format!("{name} = {n} is out of range: must be ≥ 1")))
}

/// The default accuracy knobs, as the command's: `tol`, `steady_tol`, `max_periods`,
/// `max_oscillations`.
#[pyfunction]
fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = SimulationOptions::default();
    let out = PyDict::new(py);
    out.set_item("tol", d.root_tolerance)?;
    out.set_item("steady_tol", d.periodicity_tolerance)?;
    out.set_item("max_periods", d.max_periods)?;
    out.set_item(
        "max_oscillations",
        d.max_oscillations.unwrap_or(f64::INFINITY),
    )?;
    Ok(out)
}

/// Exercises the boundary's failure paths, for the tests (no input is known to make either
/// solver fail): `"error"` fails as a numerical failure, `"panic"` panics inside the released
/// computation; both must come out as `RuntimeError`.
#[pyfunction]
fn _boundary_check(py: Python<'_>, kind: &str) -> PyResult<()> {
    let kind = kind.to_owned();
    compute(py, move || match kind.as_str() {
        "error" => Err("a failure from the boundary check".to_owned()),
        "panic" => panic!("a panic from the boundary check"),
        _ => Ok(()),
    })
}

/// Registers the simulator's defaults and the boundary's self-check.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add_function(wrap_pyfunction!(_boundary_check, m)?)?;
    Ok(())
}
