//! `rattle.compare`: both solvers on the motion the scene settles on, as
//! `rattle compare --json`, on a scene of either form.

use crate::common::{check_any_frequency, compute_api, json, options, python_names};
use crate::scene::NativeScene;
use pyo3::prelude::*;
use rattle_compare::api;

/// `rattle compare --json`: both solvers on the motion the unit settles on; on a chain, the
/// simulated cycle beside the analytic orbit of its impact sequence (the command's chain
/// record); on a structure, the analytic orbit of the simulated impact sequence, every body
/// compared (the command's structure record); the facade's [`api::compare`], as the
/// command's.
#[pyfunction]
#[pyo3(signature = (scene, omega, tol, steady_tol, max_periods, max_oscillations))]
fn compare(
    py: Python<'_>,
    scene: &NativeScene,
    omega: f64,
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
) -> PyResult<String> {
    let scene = &scene.scene;
    let omega = check_any_frequency(scene, "omega", omega)?;
    let options = options(tol, steady_tol, max_periods, max_oscillations)?;
    json(&compute_api(py, python_names, || {
        api::compare(scene, omega, &options)
    })?)
}

/// Registers `compare`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(compare, m)?)
}
