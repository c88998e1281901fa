//! `rattle.continue_branch`: the orbits of a signature followed in frequency, as
//! `rattle continue --json`, with the command's settings, checks and messages.

use crate::common::{check_any_frequency, check_omega, compute_api, json, python_names};
use crate::scene::NativeScene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rattle_analytic::ContinuationSettings;
use rattle_analytic::Signature;
use rattle_compare::api;
use rattle_compare::scene::AnyScene;

/// The continuation's default `max_step`, `max_branches` and `max_depth`, as the command's.
#[pyfunction]
fn continuation_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = ContinuationSettings::default();
    let out = PyDict::new(py);
    out.set_item("max_step", d.max_step)?;
    out.set_item("max_branches", d.max_branches)?;
    out.set_item("max_depth", d.max_depth)?;
    Ok(out)
}

/// `rattle continue --json`: every orbit of `signature` (on a chain: an impact sequence of its
/// pairs; on a structure: of its stops) at `omega` (or only the `orbit`-th) followed in ω over
/// `[omega_min, omega_max]`, with the command's settings, checks and messages (options named
/// as the Python parameters).
#[pyfunction]
#[pyo3(signature = (scene, signature, omega, omega_min, omega_max, period, orbit, switch, max_step, max_branches, max_depth))]
#[allow(clippy::too_many_arguments)]
fn continue_branch(
    py: Python<'_>,
    scene: &NativeScene,
    signature: &str,
    omega: f64,
    omega_min: f64,
    omega_max: f64,
    period: i64,
    orbit: Option<i64>,
    switch: bool,
    max_step: f64,
    max_branches: i64,
    max_depth: i64,
) -> PyResult<String> {
    // The command's checks in the command's order, so that the first bad argument gets the
    // command's message: the settings and the range of `omega`, then the scene and its bounds.
    let scene = &scene.scene;
    let omega = check_omega("omega", omega)?;
    let period = u32::try_from(period).unwrap_or(0);
    let text = signature;
    if matches!(scene, AnyScene::Cells(s) if !s.is_chain()) {
        // A unit's signature is checked first, so that its message comes before the
        // settings'; a chain's impact sequence is parsed against the chain, as the command
        // does ([`api::continuation`]).
        Signature::parse(text, period)
            .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))?;
    }
    let max_branches = usize::try_from(max_branches).unwrap_or(0);
    let max_depth = usize::try_from(max_depth).map_err(|_| {
        PyValueError::new_err(format!(
            "max_depth = {max_depth} is out of range: must be ≥ 0"
        ))
    })?;
    let mut settings = ContinuationSettings {
        max_step,
        max_branches,
        max_depth,
        follow_switches: switch,
        ..ContinuationSettings::new(omega_min, omega_max)
    };
    if !(max_step.is_finite() && max_step >= settings.min_step) {
        return Err(PyValueError::new_err(format!(
            "max_step = {max_step} is out of range: must be finite and ≥ {:e}",
            settings.min_step
        )));
    }
    if max_branches == 0 {
        return Err(PyValueError::new_err(
            "max_branches = 0 is out of range: must be ≥ 1",
        ));
    }
    if settings.initial_step > settings.max_step {
        settings.initial_step = settings.max_step;
    }
    settings
        .validate()
        .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))?;
    if !(omega_min..=omega_max).contains(&omega) {
        return Err(PyValueError::new_err(format!(
            "omega = {omega} is out of range: must be in [omega_min, omega_max] = [{omega_min}, {omega_max}]"
        )));
    }
    check_any_frequency(scene, "omega_min", omega_min)?;
    check_any_frequency(scene, "omega_max", omega_max)?;
    let orbit = orbit
        .map(|k| {
            usize::try_from(k).map_err(|_| {
                PyValueError::new_err(format!("orbit = {k} is out of range: must be ≥ 0"))
            })
        })
        .transpose()?;
    // Which errors are the caller's is the command's split (its exit code 2 against 1); a
    // numerical failure keeps the command's words (its hint names a command).
    let continued = compute_api(py, python_names, || {
        api::continuation(scene, text, period, omega, orbit, &settings)
    })?;
    json(&continued)
}

/// Registers `continuation_defaults` and `continue_branch`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(continuation_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(continue_branch, m)?)?;
    Ok(())
}
