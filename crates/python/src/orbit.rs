//! `rattle.orbit` and `rattle.orbit_trajectory`: the analytic solver, as `rattle orbit --json`,
//! and one orbit's cycle sampled from the closed form (`--orbit K --trajectory F --impacts I`).

use crate::common::{check_any_frequency, compute_api, json, python_names, unit_only};
use crate::scene::{structure_refused, NativeScene};
use crate::table::{columns, structure_columns, PyColumns};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, TrajectoryTables};
use rattle_compare::output::trajectory::check_samples_per_period;
use rattle_compare::scene::analytic::OrbitSearch;
use rattle_compare::scene::AnyScene;

/// `rattle orbit --json`: the linear steady state and every two-impact orbit, or, with a
/// signature, every orbit of that signature; on a chain or a structure (with a signature
/// only, as the command), every orbit of that impact sequence of its pairs or stops.
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
    let any = &scene.scene;
    let omega = check_any_frequency(any, "omega", omega)?;
    let Some(text) = signature else {
        return two_impact_orbits(py, any, omega, period, symmetric_only);
    };
    if symmetric_only {
        return Err(PyValueError::new_err(
            "symmetric_only and signature exclude each other",
        ));
    }
    let period = u32::try_from(period).unwrap_or(0);
    let found = compute_api(py, python_names, || {
        api::signature_orbits(any, omega, text, period)
    })?;
    json(&found)
}

/// [`orbit`] without a signature: `rattle orbit --json` on a unit (the linear steady state and
/// every two-impact orbit, the symmetric ones alone with `symmetric_only`); refused by name on
/// a structure and on a chain, whose orbits are those of an impact sequence.
fn two_impact_orbits(
    py: Python<'_>,
    any: &AnyScene,
    omega: f64,
    period: i64,
    symmetric_only: bool,
) -> PyResult<String> {
    match any {
        AnyScene::Structure(form) => {
            return Err(structure_refused(form, "rattle.orbit(signature=None)"));
        }
        AnyScene::Cells(scene) if scene.is_chain() => {
            unit_only(scene, "rattle.orbit(signature=None)")?;
            return Err(PyValueError::new_err(
                "signature: a chain's orbits are those of an impact sequence of its pairs",
            ));
        }
        AnyScene::Cells(_) => {}
    }
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
    let found = compute_api(py, python_names, || api::orbits(any, omega, search))?;
    json(&found)
}

/// `samples_per_period` if in the command's range `[1, 100000]`; else the
/// command's message ([`check_samples_per_period`]), named as the Python parameter.
pub(crate) fn check_samples(samples_per_period: i64) -> PyResult<u64> {
    check_samples_per_period(samples_per_period.into())
        .map_err(|message| PyValueError::new_err(python_names(&message)))
}

/// `rattle orbit --signature SIG --period P --orbit K --trajectory F --impacts I --json`: the
/// orbits of the signature (the command's JSON) and the `orbit`-th of them sampled from the
/// closed form, as the two tables the command writes, on a scene of any form (a structure's
/// with a column per body and per stop, as [`crate::simulate`]'s tables).
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
    let scene = &scene.scene;
    let omega = check_any_frequency(scene, "omega", omega)?;
    let samples = check_samples(samples_per_period)?;
    let period = u32::try_from(period).unwrap_or(0);
    let (found, tables) = compute_api(py, python_names, || {
        let found = api::signature_orbits(scene, omega, signature, period)?;
        let tables = usize::try_from(orbit)
            .ok()
            .map(|k| api::orbit_trajectory(scene, &found, k, samples))
            .transpose()?;
        Ok((found, tables))
    })?;
    let Some(tables) = tables else {
        return Err(PyValueError::new_err(format!(
            "orbit = {orbit} is out of range: {} orbit(s) of {} at ω = {omega}, numbered from 0",
            found.len(),
            found.signature()
        )));
    };
    let (rows, impacts) = match (tables, scene) {
        (TrajectoryTables::Cells { rows, impacts }, _) => {
            (columns(py, &rows)?, columns(py, &impacts)?)
        }
        (TrajectoryTables::Structure { states, impacts }, AnyScene::Structure(form)) => {
            structure_columns(py, &form.structure, &states, &impacts)?
        }
        (TrajectoryTables::Structure { .. }, AnyScene::Cells(_)) => {
            unreachable!("a trajectory has the form of its scene")
        }
    };
    Ok((json(&found)?, rows, impacts))
}

/// Registers `orbit` and `orbit_trajectory`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(orbit, m)?)?;
    m.add_function(wrap_pyfunction!(orbit_trajectory, m)?)?;
    Ok(())
}
