//! `rattle.sweep`'s native half: a frequency sweep with one solver or both, as
//! `rattle sweep --out F.json [--shard K/N]`, on a scene of either form, its rows kept in Rust
//! and handed to numpy column by column ([`crate::table`]), and the command's frequency axis.

use crate::common::{
    check_any_frequency, check_omega, compute_api, json, options, python_names, shard,
};
use crate::scene::NativeScene;
use crate::table::{columns, PyColumns};
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, ApiError};
use rattle_compare::output::{table_text, Format, Header};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::structure_sweep::{structure_header, StructureSweepRow};
use rattle_compare::runs::sweep::{header, Solver, SweepRow};
use rattle_compare::scene::AnyScene;

/// A sweep's rows, in frequency order: a unit's or a chain's, or a structure's.
enum Rows {
    /// One [`SweepRow`] per frequency.
    Cells(Vec<SweepRow>),
    /// One [`StructureSweepRow`] per frequency.
    Structure(Vec<StructureSweepRow>),
}

/// A sweep's result: the command's header and one row per frequency.
#[pyclass(frozen, module = "rattle._rattle")]
struct NativeSweep {
    /// The command's JSON header.
    header: Header,
    /// The rows, in frequency order.
    rows: Rows,
}

#[pymethods]
impl NativeSweep {
    /// The command's JSON header (`scene`, `solver`, `effects`, `points`) as a JSON object.
    fn header_json(&self) -> String {
        let fields: Vec<String> = self
            .header
            .fields()
            .iter()
            .map(|(key, value)| {
                let key = serde_json::to_string(key).unwrap_or_else(|_| "\"?\"".to_owned());
                format!("{key}:{value}")
            })
            .collect();
        format!("{{{}}}", fields.join(","))
    }

    /// The command's `--out F.json` file as text (for a part, with its `shard`).
    fn document(&self) -> PyResult<String> {
        Ok(match &self.rows {
            Rows::Cells(rows) => table_text(Format::Json, &self.header, rows),
            Rows::Structure(rows) => table_text(Format::Json, &self.header, rows),
        })
    }

    /// The rows as one JSON array, each row as the command writes it.
    fn rows_json(&self) -> PyResult<String> {
        match &self.rows {
            Rows::Cells(rows) => json(rows),
            Rows::Structure(rows) => json(rows),
        }
    }

    /// The columns, in the command's order (the row type's `COLUMNS`: [`SweepRow`]'s, or
    /// [`StructureSweepRow`]'s for a structure), as `(name, numpy array)` pairs, each typed
    /// by its field's type ([`crate::table`]).
    ///
    /// # Errors
    /// A `RuntimeError` if a row's fields are not the command's columns (a bug).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<PyColumns<'py>> {
        match &self.rows {
            Rows::Cells(rows) => columns(py, rows),
            Rows::Structure(rows) => columns(py, rows),
        }
    }

    /// The name of the rows' table for `table_kinds`: `sweep`, or `structure-sweep`.
    #[getter]
    fn table(&self) -> &'static str {
        match &self.rows {
            Rows::Cells(_) => "sweep",
            Rows::Structure(_) => "structure-sweep",
        }
    }

    fn __len__(&self) -> usize {
        match &self.rows {
            Rows::Cells(rows) => rows.len(),
            Rows::Structure(rows) => rows.len(),
        }
    }
}

/// The solver called `name` on the command line.
fn solver(name: &str) -> PyResult<Solver> {
    [Solver::Analytic, Solver::Event, Solver::Both]
        .into_iter()
        .find(|s| s.name() == name)
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "solver = {name:?} is not a solver: must be one of \"analytic\", \"event\", \"both\""
            ))
        })
}

/// `rattle sweep --out FILE.json [--shard K/N]`: `solver` at every frequency of `omegas` (with
/// `part`, of its block of them), in parallel on rayon's pool, in order; on a structure, its
/// rows and header, as the command's.
#[pyfunction]
#[pyo3(signature = (scene, omegas, solver_name, tol, steady_tol, max_periods, max_oscillations, part=None))]
#[allow(clippy::too_many_arguments)]
fn sweep(
    py: Python<'_>,
    scene: &NativeScene,
    omegas: PyReadonlyArray1<'_, f64>,
    solver_name: &str,
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
    part: Option<(i64, i64)>,
) -> PyResult<NativeSweep> {
    let all = omegas.as_array().to_vec();
    for (i, &omega) in all.iter().enumerate() {
        check_any_frequency(&scene.scene, &format!("omegas[{i}]"), omega)?;
    }
    let part = shard(part)?;
    let omegas = match part {
        Some(s) => all[s.range(all.len())].to_vec(),
        None => all.clone(),
    };
    let solver = solver(solver_name)?;
    let options = options(tol, steady_tol, max_periods, max_oscillations)?;
    let scene = match &scene.scene {
        AnyScene::Cells(scene) => scene,
        AnyScene::Structure(form) => {
            let rows = compute_api(py, python_names, || {
                let mut rows = Vec::with_capacity(omegas.len());
                api::structure_sweep_each(
                    form,
                    &omegas,
                    solver,
                    &options,
                    &Progress::hidden(),
                    |row| {
                        rows.push(row);
                        Ok::<_, ApiError>(())
                    },
                )?;
                Ok(rows)
            })?;
            return Ok(NativeSweep {
                header: structure_header(form, solver, all.len(), part),
                rows: Rows::Structure(rows),
            });
        }
    };
    let rows = compute_api(py, python_names, || {
        // The command's own row builder (with the Lyapunov columns), rows kept in order.
        let mut rows = Vec::with_capacity(omegas.len());
        api::sweep_each(
            scene,
            &omegas,
            solver,
            &options,
            &Progress::hidden(),
            |row| {
                rows.push(row);
                Ok::<_, ApiError>(())
            },
        )?;
        Ok(rows)
    })?;
    Ok(NativeSweep {
        header: header(scene, solver, all.len(), part),
        rows: Rows::Cells(rows),
    })
}

/// `count` evenly spaced frequencies from `omega_min` to `omega_max`, ends included: the axis
/// of `rattle sweep --omega-min … --omega-max … --points …`, value for value.
#[pyfunction]
fn frequencies<'py>(
    py: Python<'py>,
    omega_min: f64,
    omega_max: f64,
    points: i64,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let lo = check_omega("omega_min", omega_min)?;
    let hi = check_omega("omega_max", omega_max)?;
    if hi < lo {
        return Err(PyValueError::new_err(format!(
            "omega_max = {hi} is out of range: must be ≥ omega_min = {lo}"
        )));
    }
    let points = usize::try_from(points)
        .ok()
        .filter(|&n| n >= 1)
        .ok_or_else(|| PyValueError::new_err("points must be ≥ 1"))?;
    Ok(PyArray1::from_vec(py, Axis::new(lo, hi, points).values()))
}

/// Registers the sweep class, `sweep` and `frequencies`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<NativeSweep>()?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(frequencies, m)?)?;
    Ok(())
}
