//! `rattle.compare`: both solvers on the motion the unit settles on, as
//! `rattle compare --json`.

use crate::common::{check_frequency, compute, json, options};
use crate::scene::NativeScene;
use pyo3::prelude::*;
use rattle_compare::verdict::chain::chain_cross_check;
use rattle_compare::verdict::cross_check;

/// `rattle compare --json`: both solvers on the motion the unit settles on; on a chain, the
/// simulated cycle beside the analytic orbit of its impact sequence (the command's chain
/// record).
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
    let scene = &scene.scene;
    if scene.is_chain() {
        let record = compute(py, || {
            chain_cross_check(scene, omega, &options)
                .map(|c| c.record(scene))
                .map_err(|e| e.to_string())
        })?;
        return json(&record);
    }
    let record = compute(py, || {
        cross_check(scene, omega, &options)
            .map(|c| c.record(scene))
            .map_err(|e| e.to_string())
    })?;
    json(&record)
}

/// Registers `compare`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(compare, m)?)
}
