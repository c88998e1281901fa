//! `rattle.compare`: both solvers on the motion the unit settles on, as
//! `rattle compare --json`.

use crate::common::{any, check_frequency, compute_api, json, options, python_names};
use crate::scene::NativeScene;
use pyo3::prelude::*;
use rattle_compare::api;

/// `rattle compare --json`: both solvers on the motion the unit settles on; on a chain, the
/// simulated cycle beside the analytic orbit of its impact sequence (the command's chain
/// record); the facade's [`api::compare`], as the command's.
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
    let omega = check_frequency(&scene.scene, "omega", omega)?;
    let options = options(tol, steady_tol, max_periods, max_oscillations)?;
    let scene = any(&scene.scene);
    json(&compute_api(py, python_names, || {
        api::compare(&scene, omega, &options)
    })?)
}

/// Registers `compare`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(compare, m)?)
}
