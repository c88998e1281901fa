//! `rattle.respond`: the exact response to a non-periodic signal from rest, as
//! `rattle respond --json`, with the sampled response of `--out` as columns.

use crate::common::{compute_api, json, python_names};
use crate::scene::NativeScene;
use crate::table::PyColumns;
use numpy::PyArray1;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, ResponseRequest};
use rattle_compare::runs::parallel::Progress;

/// The command's options named as this function's parameters.
fn respond_names(message: &str) -> String {
    python_names(message)
        .replace("--signal", "signal")
        .replace("--duration", "duration")
        .replace("--samples", "samples")
        .replace("--at", "at")
        .replace("--on", "on")
}

/// `rattle respond --json --out F --samples N`: the document and the sampled columns (`t`,
/// `u_g` or `F`, `u:NAME…`, `v:NAME…`), by the facade's calls, as the command's
/// ([`api::prepare_response`], [`api::PreparedResponse::run`]). `samples = None`: the
/// command's default count.
#[pyfunction]
#[pyo3(signature = (scene, signal, duration, at=None, on=None, samples=None))]
fn respond<'py>(
    py: Python<'py>,
    scene: &NativeScene,
    signal: String,
    duration: f64,
    at: Option<Vec<f64>>,
    on: Option<String>,
    samples: Option<i64>,
) -> PyResult<(String, PyColumns<'py>)> {
    let samples = samples
        .map(|n| {
            u64::try_from(n).map_err(|_| {
                PyValueError::new_err(format!(
                    "samples = {n} is out of range: must be in [1, 10000000]"
                ))
            })
        })
        .transpose()?;
    let request = ResponseRequest {
        signal,
        duration,
        at: at.unwrap_or_default(),
        on,
    };
    let scene = &scene.scene;
    let (record, columns, rows) = compute_api(py, respond_names, || {
        let prepared = api::prepare_response(scene, &request)?;
        let count = samples.unwrap_or_else(|| prepared.default_samples());
        let columns = prepared.columns();
        let mut rows: Vec<Vec<f64>> = vec![Vec::new(); columns.len()];
        let record = prepared.run(Some(count), &Progress::hidden(), &mut |row| {
            for (column, &x) in rows.iter_mut().zip(row) {
                column.push(x);
            }
            Ok(())
        })?;
        Ok((record, columns, rows))
    })?;
    let table = columns
        .into_iter()
        .zip(rows)
        .map(|(name, values)| (name, PyArray1::from_vec(py, values).into_any()))
        .collect();
    Ok((json(&record)?, table))
}

/// Registers `respond`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(respond, m)?)
}
