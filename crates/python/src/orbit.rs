//! `rattle.orbit` and `rattle.orbit_trajectory`: the analytic solver, as `rattle orbit --json`,
//! and one orbit's cycle sampled from the closed form (`--orbit K --trajectory F --impacts I`).

use crate::common::{check_frequency, compute, json, python_names, unit_only};
use crate::scene::NativeScene;
use crate::table::{columns, PyColumns};
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use rattle_analytic::Signature;
use rattle_compare::output::records::{
    At, LinearRecord, OrbitRecord, OrbitsRecord, SignatureOrbitRecord, SignatureOrbitsRecord,
};
use rattle_compare::output::trajectory::{analytic_rows, MAX_SAMPLES_PER_PERIOD};
use rattle_compare::scene::analytic::{
    analyse, chain_linear_model, orbits_of_signature, sample_sequence_orbit,
    sample_signature_orbit, OrbitSearch,
};
use rattle_compare::scene::Scene;
use rattle_compare::verdict::chain::{chain_orbits, ChainOrbitsError};

/// `rattle orbit --json`: the linear steady state and every two-impact orbit, or, with a
/// signature, every orbit of that signature; on a chain (with a signature only, as the
/// command), every orbit of that impact sequence of its pairs.
#[pyfunction]
#[pyo3(signature = (scene, omega, signature=None, period=1, symmetric_only=false))]
fn orbit(
    py: Python<'_>,
    scene: &NativeScene,
    omega: f64,
    signature: Option<&str>,
    period: i64,
    symmetric_only: bool,
) -> PyResult<String> {
    let omega = check_frequency(&scene.scene, "omega", omega)?;
    let scene = &scene.scene;
    if scene.is_chain() {
        return chain_orbit(py, scene, omega, signature, period, symmetric_only);
    }
    let Some(text) = signature else {
        if period != 1 {
            return Err(PyValueError::new_err(
                "period applies to an orbit of a given signature: pass signature too",
            ));
        }
        let search = if symmetric_only {
            OrbitSearch::Symmetric
        } else {
            OrbitSearch::All
        };
        let record = compute(py, || {
            let point = analyse(scene, omega, search).map_err(|e| e.to_string())?;
            Ok(OrbitsRecord {
                at: At::new(scene, omega),
                linear: LinearRecord::new(&point.linear, scene.gap()),
                orbits: point
                    .orbits
                    .iter()
                    .map(|(b, o)| OrbitRecord::new(o, *b))
                    .collect(),
            })
        })?;
        return json(&record);
    };
    if symmetric_only {
        return Err(PyValueError::new_err(
            "symmetric_only and signature exclude each other",
        ));
    }
    let period = u32::try_from(period).unwrap_or(0);
    let signature = Signature::parse(text, period)
        .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))?;
    if scene.stops.is_none() {
        return Err(PyValueError::new_err(
            "signature: the scene has no `stops`, so no impact signature",
        ));
    }
    let record = compute(py, || {
        Ok(SignatureOrbitsRecord {
            at: At::new(scene, omega),
            signature: signature.to_string(),
            period: signature.period(),
            orbits: orbits_of_signature(scene, omega, &signature)
                .iter()
                .map(SignatureOrbitRecord::new)
                .collect(),
        })
    })?;
    json(&record)
}

/// [`orbit`] on a chain: `rattle orbit --signature SEQUENCE --period P --json`; without a
/// signature, the command's refusal of a chain.
fn chain_orbit(
    py: Python<'_>,
    scene: &Scene,
    omega: f64,
    signature: Option<&str>,
    period: i64,
    symmetric_only: bool,
) -> PyResult<String> {
    let Some(text) = signature else {
        unit_only(scene, "rattle.orbit(signature=None)")?;
        return Err(PyValueError::new_err(
            "signature: a chain's orbits are those of an impact sequence of its pairs",
        ));
    };
    if symmetric_only {
        return Err(PyValueError::new_err(
            "symmetric_only and signature exclude each other",
        ));
    }
    let period = u32::try_from(period).unwrap_or(0);
    let record = compute(py, || Ok(chain_orbits(scene, omega, text, period)))?
        .map_err(|e| chain_orbits_error(&e))?;
    json(&record)
}

/// A chain's orbits' error as the matching Python exception, worded as the command words it:
/// bad input a `ValueError` (options named as the Python parameters), a numerical failure a
/// `RuntimeError`.
fn chain_orbits_error(error: &ChainOrbitsError) -> PyErr {
    match error {
        ChainOrbitsError::Numerical(_) => {
            PyRuntimeError::new_err(format!("numerical failure: {error}"))
        }
        _ => PyValueError::new_err(python_names(&error.to_string())),
    }
}

/// `samples_per_period` if in the command's range `[1, MAX_SAMPLES_PER_PERIOD]`; else the
/// command's message for `--samples-per-period`, named as the Python parameter.
pub(crate) fn check_samples(samples_per_period: i64) -> PyResult<u64> {
    u64::try_from(samples_per_period)
        .ok()
        .filter(|n| (1..=MAX_SAMPLES_PER_PERIOD).contains(n))
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "samples_per_period = {samples_per_period} is out of range: must be in [1, {MAX_SAMPLES_PER_PERIOD}]"
            ))
        })
}

/// `rattle orbit --signature SIG --period P --orbit K --trajectory F --impacts I --json`: the
/// orbits of the signature (the command's JSON) and the `orbit`-th of them sampled from the
/// closed form, as the two tables the command writes.
#[pyfunction]
#[pyo3(signature = (scene, omega, signature, period, orbit, samples_per_period))]
fn orbit_trajectory<'py>(
    py: Python<'py>,
    scene: &NativeScene,
    omega: f64,
    signature: &str,
    period: i64,
    orbit: i64,
    samples_per_period: i64,
) -> PyResult<(String, PyColumns<'py>, PyColumns<'py>)> {
    let omega = check_frequency(&scene.scene, "omega", omega)?;
    let samples = check_samples(samples_per_period)?;
    let period = u32::try_from(period).unwrap_or(0);
    if scene.scene.is_chain() {
        return chain_orbit_trajectory(py, &scene.scene, omega, signature, period, orbit, samples);
    }
    let signature = Signature::parse(signature, period)
        .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))?;
    let scene = &scene.scene;
    if scene.stops.is_none() {
        return Err(PyValueError::new_err(
            "signature: the scene has no `stops`, so no impact signature",
        ));
    }
    let (record, tables) = compute(py, || {
        let orbits = orbits_of_signature(scene, omega, &signature);
        let tables = usize::try_from(orbit)
            .ok()
            .and_then(|k| orbits.get(k))
            .map(|o| {
                let (samples, impacts) = sample_signature_orbit(scene, o, samples);
                analytic_rows(
                    &samples,
                    &impacts,
                    omega,
                    scene.base.amplitude,
                    &scene.cell_pairs(),
                )
            });
        let record = SignatureOrbitsRecord {
            at: At::new(scene, omega),
            signature: signature.to_string(),
            period: signature.period(),
            orbits: orbits.iter().map(SignatureOrbitRecord::new).collect(),
        };
        Ok((record, tables))
    })?;
    let Some((rows, impacts)) = tables else {
        return Err(PyValueError::new_err(format!(
            "orbit = {orbit} is out of range: {} orbit(s) of {signature} at ω = {omega}, numbered from 0",
            record.orbits.len()
        )));
    };
    Ok((json(&record)?, columns(py, &rows)?, columns(py, &impacts)?))
}

/// [`orbit_trajectory`] on a chain: the orbits of the impact sequence `sequence`, as
/// `rattle orbit CHAIN --signature SEQUENCE --orbit K --trajectory F --impacts I --json`.
fn chain_orbit_trajectory<'py>(
    py: Python<'py>,
    scene: &Scene,
    omega: f64,
    sequence: &str,
    period: u32,
    orbit: i64,
    samples_per_period: u64,
) -> PyResult<(String, PyColumns<'py>, PyColumns<'py>)> {
    let (record, tables) = compute(py, || {
        Ok(
            chain_orbits(scene, omega, sequence, period).and_then(|record| {
                let model = chain_linear_model(scene)?;
                let tables = usize::try_from(orbit)
                    .ok()
                    .and_then(|k| record.orbits.get(k))
                    .map(|o| {
                        let (samples, impacts) =
                            sample_sequence_orbit(&model, o, samples_per_period);
                        analytic_rows(
                            &samples,
                            &impacts,
                            omega,
                            scene.base.amplitude,
                            &scene.cell_pairs(),
                        )
                    });
                Ok((record, tables))
            }),
        )
    })?
    .map_err(|e| chain_orbits_error(&e))?;
    let Some((rows, impacts)) = tables else {
        return Err(PyValueError::new_err(format!(
            "orbit = {orbit} is out of range: {} orbit(s) of {} at ω = {omega}, numbered from 0",
            record.orbits.len(),
            record.sequence
        )));
    };
    Ok((json(&record)?, columns(py, &rows)?, columns(py, &impacts)?))
}

/// Registers `orbit` and `orbit_trajectory`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(orbit, m)?)?;
    m.add_function(wrap_pyfunction!(orbit_trajectory, m)?)?;
    Ok(())
}
