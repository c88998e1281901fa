//! `rattle.transmission`'s native half: the Welch estimate of the transmissibility under
//! random base motion, as `rattle transmission --json`, whole or as the parts of
//! `--shard K/N` and their merge (the parts a Dask task computes).

use crate::common::{compute_api, json, python_names, shard};
use crate::scene::NativeScene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, TransmissionOptions, TransmissionPart, TransmissionRequest};
use rattle_compare::runs::parallel::Progress;

/// The command's options named as this function's parameters (`--levels[1]` is
/// `levels[1]`).
fn transmission_names(message: &str) -> String {
    python_names(message)
        .replace("--signal", "signal")
        .replace("--duration", "duration")
        .replace("--levels", "levels")
        .replace("--seeds", "seeds")
        .replace("--segment", "segment")
        .replace("--overlap", "overlap")
        .replace("--confidence", "confidence")
        .replace("--transient", "transient")
}

/// The request from the parameters, as the command's flags give it.
#[allow(clippy::too_many_arguments)]
fn request(
    signal: String,
    duration: f64,
    levels: Option<Vec<f64>>,
    seeds: i64,
    segment: Option<f64>,
    overlap: f64,
    confidence: f64,
    transient: Option<f64>,
) -> PyResult<TransmissionRequest> {
    let seeds = u64::try_from(seeds).map_err(|_| {
        PyValueError::new_err(format!(
            "seeds = {seeds} is out of range: must be in [1, 100000], the last seed S + N − 1 \
             below 2^64"
        ))
    })?;
    Ok(TransmissionRequest {
        signal,
        duration,
        options: TransmissionOptions {
            levels: levels.unwrap_or_default(),
            seeds,
            segment,
            overlap,
            confidence,
            transient,
        },
    })
}

/// `rattle transmission --json`: the document as JSON text, by the facade's call
/// ([`api::transmission`]); runs in parallel on rayon's pool. `levels = None`: the signal's
/// `rms`; `segment`, `transient` `None`: the command's defaults.
#[pyfunction]
#[pyo3(signature = (scene, signal, duration, levels=None, seeds=1, segment=None, overlap=0.5, confidence=0.95, transient=None))]
#[allow(clippy::too_many_arguments)]
fn transmission(
    py: Python<'_>,
    scene: &NativeScene,
    signal: String,
    duration: f64,
    levels: Option<Vec<f64>>,
    seeds: i64,
    segment: Option<f64>,
    overlap: f64,
    confidence: f64,
    transient: Option<f64>,
) -> PyResult<String> {
    let request = request(
        signal, duration, levels, seeds, segment, overlap, confidence, transient,
    )?;
    let scene = &scene.scene;
    let record = compute_api(py, transmission_names, || {
        api::transmission(scene, &request)
    })?;
    json(&record)
}

/// `rattle transmission --shard K/N --out F.json`: part `part = (K, N)` of the `(level,
/// seed)` runs, the part's JSON text (`{"kind": "transmission-part", …}`, each run's raw
/// segment sums), by [`api::PreparedTransmission::run_part`]; every check of the whole
/// estimate is made first, so a part with no runs (`K/N` past the runs) checks the request
/// and computes nothing.
#[pyfunction]
#[pyo3(signature = (scene, signal, duration, levels=None, seeds=1, segment=None, overlap=0.5, confidence=0.95, transient=None, part=(1, 1)))]
#[allow(clippy::too_many_arguments)]
fn transmission_part(
    py: Python<'_>,
    scene: &NativeScene,
    signal: String,
    duration: f64,
    levels: Option<Vec<f64>>,
    seeds: i64,
    segment: Option<f64>,
    overlap: f64,
    confidence: f64,
    transient: Option<f64>,
    part: (i64, i64),
) -> PyResult<String> {
    let request = request(
        signal, duration, levels, seeds, segment, overlap, confidence, transient,
    )?;
    let part = shard(Some(part))?.expect("a part was given");
    let scene = &scene.scene;
    let record = compute_api(py, transmission_names, || {
        api::prepare_transmission(scene, &request)?.run_part(part, &Progress::hidden())
    })?;
    json(&record)
}

/// `rattle merge` of the parts of a sharded transmission estimate (their JSON texts, any
/// order): the whole document as JSON text, the same bits as the unsharded run
/// ([`api::merge_transmission`]). A part missing, repeated or from another estimate is a
/// `ValueError`, with the command's message.
#[pyfunction]
fn merge_transmission_parts(py: Python<'_>, parts: Vec<String>) -> PyResult<String> {
    let parts = parts
        .iter()
        .enumerate()
        .map(|(i, text)| {
            serde_json::from_str::<TransmissionPart>(text).map_err(|e| {
                PyValueError::new_err(format!("parts[{i}] is not a transmission part: {e}"))
            })
        })
        .collect::<PyResult<Vec<_>>>()?;
    let record = compute_api(py, transmission_names, || api::merge_transmission(&parts))?;
    json(&record)
}

/// Registers `transmission`, `transmission_part` and `merge_transmission_parts`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(transmission, m)?)?;
    m.add_function(wrap_pyfunction!(transmission_part, m)?)?;
    m.add_function(wrap_pyfunction!(merge_transmission_parts, m)?)?;
    Ok(())
}
