//! `rattle.simulate`: the event-driven simulator from rest, as `rattle simulate --json`, with
//! the `--trajectory`/`--impacts` tables and the `--lyapunov` exponents on request, on a scene
//! of either form.

use crate::common::{check_any_frequency, compute_api, json, options, positive, python_names};
use crate::orbit::check_samples;
use crate::scene::NativeScene;
use crate::table::{columns, structure_columns, PyColumns};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, Simulation, Stretch, TrajectoryTables};
use rattle_compare::output::records::WithLyapunov;
use rattle_compare::scene::lyapunov::check_periods;
use rattle_compare::scene::AnyScene;
use rattle_event_driven::BATCHES;

/// `rattle simulate --json`: the event-driven simulator from rest; with `samples_per_period`,
/// also the tables `--trajectory` and `--impacts` write (the final cycle, or with `periods`
/// the last period, sampled from the closed form; with `sampled_periods`, that many periods
/// continued from where the run ended, as `--sampled-periods`); with `lyapunov_periods`, the
/// exponents of
/// `--lyapunov --lyapunov-periods N` in the document. A scene of either form: a structure's
/// record names every body, its tables have a column per body and per stop. The facade's
/// calls, as the command's ([`api::simulate`], [`api::simulation_trajectory`],
/// [`api::lyapunov`]).
#[pyfunction]
#[pyo3(signature = (scene, omega, periods, tol, steady_tol, max_periods, max_oscillations, samples_per_period=None, lyapunov_periods=None, sampled_periods=None))]
#[allow(clippy::too_many_arguments, clippy::type_complexity)]
fn simulate<'py>(
    py: Python<'py>,
    scene: &NativeScene,
    omega: f64,
    periods: Option<i64>,
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
    samples_per_period: Option<i64>,
    lyapunov_periods: Option<i64>,
    sampled_periods: Option<i64>,
) -> PyResult<(String, Option<(PyColumns<'py>, PyColumns<'py>)>)> {
    let omega = check_any_frequency(&scene.scene, "omega", omega)?;
    let mut options = options(tol, steady_tol, max_periods, max_oscillations)?;
    if let Some(n) = periods {
        options.fixed_periods = Some(positive("periods", n)?);
    }
    let samples = samples_per_period.map(check_samples).transpose()?;
    let stretch = match sampled_periods {
        None => Stretch::FinalCycle,
        // A negative count is out of the range the facade names (`≥ 1`).
        Some(n) => Stretch::Continued(u64::try_from(n).unwrap_or(0)),
    };
    let lyapunov = lyapunov_periods.map(checked_lyapunov_periods).transpose()?;
    let scene = &scene.scene;
    let (simulation, tables, exponents) = compute_api(py, python_names, || {
        let simulation = api::simulate(scene, omega, &options)?;
        let tables = samples
            .map(|samples_per_period| {
                api::simulation_trajectory(
                    scene,
                    &simulation,
                    samples_per_period,
                    stretch,
                    &options,
                )
            })
            .transpose()?;
        let exponents = lyapunov
            .map(|periods| api::lyapunov(scene, &simulation, periods, &options))
            .transpose()?;
        Ok((simulation, tables, exponents))
    })?;
    let tables = match (tables, scene) {
        (None, _) => None,
        (Some(TrajectoryTables::Cells { rows, impacts }), _) => {
            Some((columns(py, &rows)?, columns(py, &impacts)?))
        }
        (Some(TrajectoryTables::Structure { states, impacts }), AnyScene::Structure(form)) => {
            Some(structure_columns(py, &form.structure, &states, &impacts)?)
        }
        (Some(TrajectoryTables::Structure { .. }), AnyScene::Cells(_)) => {
            unreachable!("a trajectory has the form of its scene")
        }
    };
    let lyapunov = exponents.as_ref();
    let document = match &simulation {
        Simulation::Cells { record, .. } => json(&WithLyapunov { record, lyapunov })?,
        Simulation::Structure { record, .. } => json(&WithLyapunov { record, lyapunov })?,
    };
    Ok((document, tables))
}

/// `lyapunov_periods = N` checked by the library's range, the command's too ([`check_periods`],
/// named as the Python parameter).
fn checked_lyapunov_periods(periods: i64) -> PyResult<u64> {
    let out_of_range = || {
        PyValueError::new_err(format!(
            "lyapunov_periods = {periods} is out of range: must be at least {BATCHES}"
        ))
    };
    let periods = u64::try_from(periods).map_err(|_| out_of_range())?;
    check_periods(periods).map_err(|e| PyValueError::new_err(python_names(&e.to_string())))
}

/// Registers `simulate`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(simulate, m)?)
}
