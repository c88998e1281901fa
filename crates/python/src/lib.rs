//! The native half of the `rattle` Python package, imported as `rattle._rattle`.
//!
//! Every function here does what the matching `rattle` command does, on the same library calls
//! of `rattle-compare`, and returns the same serializable record the command prints with
//! `--json`, as JSON text: the pure-Python half (`python/rattle/__init__.py`) turns it into
//! objects with attributes and `.to_dict()`. Going through the command's own JSON makes the
//! dictionaries equal to the command's output by construction (same keys, same order, lists
//! where it has lists, `None` where it has `null`), and costs microseconds (measured in the
//! crate's README note).
//!
//! Contracts at the boundary:
//! - the computation runs with the GIL released (`Python::detach`), sweeps on rayon's pool;
//! - bad input is a `ValueError` whose message is the command's (a scene's field path and
//!   allowed range word for word; options named as the Python parameters, e.g. `tol` for
//!   `--tol`); an unreadable scene file an `OSError`; a numerical failure a `RuntimeError`
//!   (`numerical failure: …`, as the command says it);
//! - a panic never crosses the boundary: it is caught and raised as a `RuntimeError` that says
//!   it is a bug.
#![deny(missing_docs)]

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::exceptions::{PyFileNotFoundError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use rattle_analytic::continuation::ContinuationSettings;
use rattle_analytic::Signature;
use rattle_compare::output::records::{
    At, LinearRecord, LyapunovRecord, OrbitRecord, OrbitsRecord, SignatureOrbitRecord,
    SignatureOrbitsRecord, SimulationRecord, WithLyapunov,
};
use rattle_compare::output::trajectory::{
    analytic_rows, simulated_rows, ImpactRow, TrajectoryRow, MAX_SAMPLES_PER_PERIOD,
};
use rattle_compare::output::Row;
use rattle_compare::output::{table_text, Format, Header};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::basins::{basin_options, write_basins, BasinGrid, BasinRow};
use rattle_compare::runs::continuation::{follow, follow_chain, FollowError};
use rattle_compare::runs::map::{write_map, MapError, MapGrid, MapPointRow, MapSettings};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::shard::{merge as merge_parts, Shard};
use rattle_compare::runs::sweep::{header, sweep_rows, Solver, SweepRow};
use rattle_compare::scene::analytic::{
    analyse, chain_linear_model, orbits_of_signature, sample_sequence_orbit,
    sample_signature_orbit, OrbitSearch,
};
use rattle_compare::scene::frequency::FrequencyBounds;
use rattle_compare::scene::lyapunov::{check_periods, spectrum};
use rattle_compare::scene::simulator::{model, run as simulate_scene, Accuracy};
use rattle_compare::scene::{Scene, SceneError};
use rattle_compare::verdict::chain::{chain_cross_check, chain_orbits, ChainOrbitsError};
use rattle_compare::verdict::cross_check;
use rattle_event_driven::lyapunov::BATCHES;
use rattle_event_driven::trajectory::{final_cycle_trajectory, TrajectoryOptions};
use rattle_event_driven::SimulationOptions;
use serde::Serialize;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::PathBuf;

mod boundary;

/// The origin a scene built from a Python dictionary is named by in error messages (the
/// command names the file, or `built-in`).
const DICT_ORIGIN: &str = "dict";

/// A validated scene, as the command loads it.
#[pyclass(frozen, module = "rattle._rattle")]
struct NativeScene {
    scene: Scene,
}

/// The Python exception for a scene that could not be used: the command's message. A scene
/// from a dictionary has no lines, so its format errors leave out the line and column.
fn scene_error(error: SceneError) -> PyErr {
    match error {
        SceneError::Read { ref source, .. } => {
            if source.kind() == std::io::ErrorKind::NotFound {
                PyFileNotFoundError::new_err(error.to_string())
            } else {
                PyOSError::new_err(error.to_string())
            }
        }
        SceneError::Format {
            ref origin,
            ref path_in_scene,
            ref message,
            ..
        } if origin == DICT_ORIGIN => {
            PyValueError::new_err(format!("{origin}: {path_in_scene}: {message}"))
        }
        SceneError::Format { .. }
        | SceneError::Value { .. }
        | SceneError::CellValue { .. }
        | SceneError::Chain { .. }
        | SceneError::Structure { .. }
        | SceneError::StructureForm { .. } => PyValueError::new_err(error.to_string()),
    }
}

#[pymethods]
impl NativeScene {
    /// Reads and validates the scene file at `path`, as `rattle … PATH` does.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        Scene::load(&path)
            .map(|scene| NativeScene { scene })
            .map_err(scene_error)
    }

    /// Parses and validates a scene given as JSON text built from a dictionary.
    ///
    /// JSON has no NaN or infinity, so the dictionary's non-finite numbers come apart, as
    /// `(field path, value)` pairs, with finite placeholders at their places in `text`: once
    /// the text has the scene's shape they are put back and the scene is validated, so that a
    /// NaN is refused as the command refuses any value out of range (field path and range).
    #[staticmethod]
    fn from_dict_json(text: &str, non_finite: Vec<(String, f64)>) -> PyResult<Self> {
        let checked = Scene::parse(text, DICT_ORIGIN);
        if non_finite.is_empty() {
            return checked
                .map(|scene| NativeScene { scene })
                .map_err(scene_error);
        }
        if let Err(e @ (SceneError::Format { .. } | SceneError::Read { .. })) = checked {
            return Err(scene_error(e));
        }
        let mut scene: Scene =
            serde_json::from_str(text).map_err(|e| PyValueError::new_err(e.to_string()))?;
        for (path, value) in &non_finite {
            set_number(&mut scene, path, *value)?;
        }
        scene
            .validated(DICT_ORIGIN)
            .map(|scene| NativeScene { scene })
            .map_err(scene_error)
    }

    /// The command's built-in paper scene.
    #[staticmethod]
    fn paper() -> Self {
        NativeScene {
            scene: Scene::paper(),
        }
    }

    /// The scene as JSON text (the format of a scene file).
    fn to_json(&self) -> PyResult<String> {
        json(&self.scene)
    }

    /// The scene's name.
    #[getter]
    fn name(&self) -> &str {
        &self.scene.name
    }

    /// The scene's active effects, as outputs list them.
    #[getter]
    fn effects(&self) -> Vec<&'static str> {
        self.scene.effect_names()
    }
}

/// Sets the number at `path` (e.g. `stops.gap`) of `scene` to `value`.
fn set_number(scene: &mut Scene, path: &str, value: f64) -> PyResult<()> {
    let field = match path {
        "unit.outer_mass" => Some(&mut scene.unit.outer_mass),
        "unit.inner_mass" => Some(&mut scene.unit.inner_mass),
        "unit.outer_stiffness" => Some(&mut scene.unit.outer_stiffness),
        "unit.inner_stiffness" => Some(&mut scene.unit.inner_stiffness),
        "base.amplitude" => Some(&mut scene.base.amplitude),
        "stops.gap" => scene.stops.as_mut().map(|s| &mut s.gap),
        "stops.restitution" => scene.stops.as_mut().map(|s| &mut s.restitution),
        "damping.outer" => scene.damping.as_mut().map(|d| &mut d.outer),
        "damping.inner" => scene.damping.as_mut().map(|d| &mut d.inner),
        _ => None,
    };
    match field {
        Some(field) => {
            *field = value;
            Ok(())
        }
        None => Err(PyValueError::new_err(format!(
            "{DICT_ORIGIN}: {path}: {value} is not a value of the scene format"
        ))),
    }
}

/// Compact JSON text of a record.
/// Refuses a chain scene for a function that takes a single unit, with the command's message.
fn unit_only(scene: &Scene, function: &str) -> PyResult<()> {
    scene
        .refuse_chain(function)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

fn json(record: &impl Serialize) -> PyResult<String> {
    serde_json::to_string(record).map_err(|e| PyRuntimeError::new_err(e.to_string()))
}

/// The text of a panic's payload.
fn panic_text(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "unknown panic".to_owned()
    }
}

/// Runs `work` with the GIL released. Its error is a numerical failure (`RuntimeError`, worded
/// as the command words it); a panic is caught and raised as a `RuntimeError`, never unwound
/// into Python.
fn compute<T: Send>(
    py: Python<'_>,
    work: impl FnOnce() -> Result<T, String> + Send,
) -> PyResult<T> {
    py.detach(|| catch_unwind(AssertUnwindSafe(work)))
        .map_err(|payload| {
            PyRuntimeError::new_err(format!(
                "internal error (a bug in rattle, please report it): {}",
                panic_text(payload.as_ref())
            ))
        })?
        .map_err(|message| PyRuntimeError::new_err(format!("numerical failure: {message}")))
}

/// The command's options named as this module's parameters (`--steady-tol` is `steady_tol`).
fn python_names(message: &str) -> String {
    message
        .replace("--lyapunov-periods", "lyapunov_periods")
        .replace("--max-oscillations", "max_oscillations")
        .replace("--max-periods", "max_periods")
        .replace("--steady-tol", "steady_tol")
        .replace("--tol", "tol")
        .replace("--signature", "signature")
        .replace("--samples-per-period", "samples_per_period")
        .replace("--period", "period")
        .replace("--orbit", "orbit")
        .replace("--max-step", "max_step")
        .replace("--max-branches", "max_branches")
        .replace("--omega-min", "omega_min")
        .replace("--omega-max", "omega_max")
        .replace("--omega", "omega")
        .replace("continuation.max_step", "max_step")
}

/// `omega` if finite and positive; else the command's message, naming `name`.
fn check_omega(name: &str, omega: f64) -> PyResult<f64> {
    if omega.is_finite() && omega > 0.0 {
        Ok(omega)
    } else {
        Err(PyValueError::new_err(format!(
            "{name} = {omega} is out of range: must be finite and > 0 (rad/s)"
        )))
    }
}

/// `omega` if `scene` can be run at it in bounded time; else the command's message, naming
/// `name` ([`FrequencyBounds`]).
fn check_frequency(scene: &Scene, name: &str, omega: f64) -> PyResult<f64> {
    FrequencyBounds::of(scene)
        .check(name, omega)
        .map_err(|e| PyValueError::new_err(e.to_string()))
}

/// A count that must be at least 1.
fn positive(name: &str, value: i64) -> PyResult<u64> {
    u64::try_from(value)
        .ok()
        .filter(|&n| n > 0)
        .ok_or_else(|| PyValueError::new_err(format!("{name} must be > 0")))
}

/// The simulator's options from the accuracy knobs, checked by the library's ranges, the
/// command's too ([`Accuracy::options`]; messages named as the Python parameters).
fn options(
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
) -> PyResult<SimulationOptions> {
    let max_periods = positive("max_periods", max_periods)?;
    Accuracy {
        tol,
        steady_tol,
        max_periods,
        max_oscillations,
    }
    .options()
    .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))
}

/// The default accuracy knobs, as the command's: `tol`, `steady_tol`, `max_periods`,
/// `max_oscillations`.
#[pyfunction]
fn defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = SimulationOptions::default();
    let out = PyDict::new(py);
    out.set_item("tol", d.root_tolerance)?;
    out.set_item("steady_tol", d.periodicity_tolerance)?;
    out.set_item("max_periods", d.max_periods)?;
    out.set_item(
        "max_oscillations",
        d.max_oscillations.unwrap_or(f64::INFINITY),
    )?;
    Ok(out)
}

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
fn check_samples(samples_per_period: i64) -> PyResult<u64> {
    u64::try_from(samples_per_period)
        .ok()
        .filter(|n| (1..=MAX_SAMPLES_PER_PERIOD).contains(n))
        .ok_or_else(|| {
            PyValueError::new_err(format!(
                "samples_per_period = {samples_per_period} is out of range: must be in [1, {MAX_SAMPLES_PER_PERIOD}]"
            ))
        })
}

/// A trajectory's two tables, as the command writes them with `--trajectory` and `--impacts`.
type Tables = (Vec<TrajectoryRow>, Vec<ImpactRow>);

/// A table handed to Python: `(column name, numpy array)` pairs in the command's order.
type PyColumns<'py> = Vec<(&'static str, Bound<'py, PyAny>)>;

/// A `float64` array of one column, NaN where the command writes nothing (not finite).
fn float_column<'py, R>(
    py: Python<'py>,
    rows: &[R],
    cell: impl Fn(&R) -> Option<f64>,
) -> Bound<'py, PyAny> {
    PyArray1::from_vec(
        py,
        rows.iter().map(|r| cell(r).unwrap_or(f64::NAN)).collect(),
    )
    .into_any()
}

/// The columns `t, kind, cell, base, u_o, u_i, v_o, v_i, r` of the command's `--trajectory`
/// file; `cell` as `int64` (0 at the base; one row per cell at each time).
fn trajectory_columns<'py>(py: Python<'py>, rows: &[TrajectoryRow]) -> PyColumns<'py> {
    let kinds: Vec<Py<PyAny>> = rows
        .iter()
        .map(|r| PyString::new(py, r.kind).into_any().unbind())
        .collect();
    let cells: Vec<i64> = rows.iter().map(|r| r.cell as i64).collect();
    vec![
        ("t", float_column(py, rows, |r| r.t)),
        ("kind", PyArray1::from_vec(py, kinds).into_any()),
        ("cell", PyArray1::from_vec(py, cells).into_any()),
        ("base", float_column(py, rows, |r| r.base)),
        ("u_o", float_column(py, rows, |r| r.u_o)),
        ("u_i", float_column(py, rows, |r| r.u_i)),
        ("v_o", float_column(py, rows, |r| r.v_o)),
        ("v_i", float_column(py, rows, |r| r.v_i)),
        ("r", float_column(py, rows, |r| r.r)),
    ]
}

/// The columns `t, pair, side, relative_velocity_before, u_o, u_i, v_o_before, v_i_before`
/// of the command's `--impacts` file; `pair` and `side` as `int64` (`side` 1 or 2).
fn impact_columns<'py>(py: Python<'py>, rows: &[ImpactRow]) -> PyColumns<'py> {
    let sides: Vec<i64> = rows.iter().map(|r| i64::from(r.side)).collect();
    let pairs: Vec<i64> = rows.iter().map(|r| r.pair as i64).collect();
    vec![
        ("t", float_column(py, rows, |r| r.t)),
        ("pair", PyArray1::from_vec(py, pairs).into_any()),
        ("side", PyArray1::from_vec(py, sides).into_any()),
        (
            "relative_velocity_before",
            float_column(py, rows, |r| r.relative_velocity_before),
        ),
        ("u_o", float_column(py, rows, |r| r.u_o)),
        ("u_i", float_column(py, rows, |r| r.u_i)),
        ("v_o_before", float_column(py, rows, |r| r.v_o_before)),
        ("v_i_before", float_column(py, rows, |r| r.v_i_before)),
    ]
}

/// `rattle simulate --json`: the event-driven simulator from rest; with `samples_per_period`,
/// also the tables `--trajectory` and `--impacts` write (the final cycle, or with `periods`
/// the last period, sampled from the closed form); with `lyapunov_periods`, the exponents of
/// `--lyapunov --lyapunov-periods N` in the document (the library's [`spectrum`] and
/// [`LyapunovRecord::new`], as the command's).
#[pyfunction]
#[pyo3(signature = (scene, omega, periods, tol, steady_tol, max_periods, max_oscillations, samples_per_period=None, lyapunov_periods=None))]
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
) -> PyResult<(String, Option<(PyColumns<'py>, PyColumns<'py>)>)> {
    let omega = check_frequency(&scene.scene, "omega", omega)?;
    let mut options = options(tol, steady_tol, max_periods, max_oscillations)?;
    if let Some(n) = periods {
        options.fixed_periods = Some(positive("periods", n)?);
    }
    let samples = samples_per_period.map(check_samples).transpose()?;
    let lyapunov = lyapunov_periods.map(checked_lyapunov_periods).transpose()?;
    let scene = &scene.scene;
    let (record, tables, exponents) = compute(py, || {
        let sim = simulate_scene(
            scene,
            omega,
            &rattle_compare::scene::simulator::rest(scene),
            &options,
        )
        .map_err(|e| e.to_string())?;
        let tables: Option<Tables> = match samples {
            None => None,
            Some(samples_per_period) => {
                let m = model(scene, sim.omega).map_err(|e| e.to_string())?;
                let trajectory = final_cycle_trajectory(
                    &m,
                    sim.omega,
                    &sim.steady,
                    &TrajectoryOptions {
                        periods: 1,
                        samples_per_period,
                        base_amplitude: scene.base.amplitude,
                        simulation: options.clone(),
                    },
                )
                .map_err(|e| e.to_string())?;
                Some(simulated_rows(&trajectory, &scene.cell_pairs()))
            }
        };
        let exponents = match &lyapunov {
            None => None,
            Some(periods) => Some(
                spectrum(scene, &sim, *periods, &options)
                    .map(|s| LyapunovRecord::new(&sim, &s))
                    .map_err(|e| e.to_string())?,
            ),
        };
        Ok((SimulationRecord::new(scene, &sim), tables, exponents))
    })?;
    let tables =
        tables.map(|(rows, impacts)| (trajectory_columns(py, &rows), impact_columns(py, &impacts)));
    let document = WithLyapunov {
        record: &record,
        lyapunov: exponents.as_ref(),
    };
    Ok((json(&document)?, tables))
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
    Ok((
        json(&record)?,
        trajectory_columns(py, &rows),
        impact_columns(py, &impacts),
    ))
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
    Ok((
        json(&record)?,
        trajectory_columns(py, &rows),
        impact_columns(py, &impacts),
    ))
}

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
/// pairs) at `omega` (or only the `orbit`-th) followed in ω over `[omega_min, omega_max]`,
/// with the command's settings, checks and messages (options named as the Python parameters).
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
    let omega = check_omega("omega", omega)?;
    let period = u32::try_from(period).unwrap_or(0);
    let text = signature;
    let signature = if scene.scene.is_chain() {
        // A chain's impact sequence is parsed against the chain, as the command does.
        None
    } else {
        Some(
            Signature::parse(text, period)
                .map_err(|e| PyValueError::new_err(python_names(&e.to_string())))?,
        )
    };
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
    check_frequency(&scene.scene, "omega_min", omega_min)?;
    check_frequency(&scene.scene, "omega_max", omega_max)?;
    let orbit = orbit
        .map(|k| {
            usize::try_from(k).map_err(|_| {
                PyValueError::new_err(format!("orbit = {k} is out of range: must be ≥ 0"))
            })
        })
        .transpose()?;
    let scene = &scene.scene;
    let followed = compute(py, || {
        Ok(match &signature {
            Some(signature) => {
                follow(scene, signature, omega, orbit, &settings).map(|f| f.record(&scene.name))
            }
            None => follow_chain(scene, text, period, omega, orbit, &settings)
                .map(|f| f.record(&scene.name)),
        })
    })?;
    // Which errors are the caller's is the command's split (its exit code 2 against 1); a
    // numerical failure keeps the command's words (its hint names a command).
    let record = followed.map_err(|e| match e {
        FollowError::OrbitIndex { .. }
        | FollowError::NoStops
        | FollowError::Chain(ChainOrbitsError::Sequence(_) | ChainOrbitsError::MissingStops(_)) => {
            PyValueError::new_err(python_names(&e.to_string()))
        }
        FollowError::Continuation(ref c) if c.to_string().contains("out of range") => {
            PyValueError::new_err(python_names(&e.to_string()))
        }
        _ => PyRuntimeError::new_err(format!("numerical failure: {e}")),
    })?;
    json(&record)
}

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

/// A sweep's result: the command's header and one [`SweepRow`] per frequency.
#[pyclass(frozen, module = "rattle._rattle")]
struct NativeSweep {
    /// The command's JSON header.
    header: Header,
    /// The rows, in frequency order.
    rows: Vec<SweepRow>,
}

/// How a sweep column is handed to numpy.
enum Column {
    /// `float64`, NaN where the row has none.
    Number(Vec<f64>),
    /// `bool`, `False` where the row has none.
    Flag(Vec<bool>),
    /// `object`: `str`, or `None` where the row has none.
    Text(Vec<Option<String>>),
}

fn number(rows: &[SweepRow], cell: impl Fn(&SweepRow) -> Option<f64>) -> Column {
    Column::Number(rows.iter().map(|r| cell(r).unwrap_or(f64::NAN)).collect())
}

fn count<N: Into<f64>>(rows: &[SweepRow], cell: impl Fn(&SweepRow) -> Option<N>) -> Column {
    Column::Number(
        rows.iter()
            .map(|r| cell(r).map_or(f64::NAN, Into::into))
            .collect(),
    )
}

fn flag(rows: &[SweepRow], cell: impl Fn(&SweepRow) -> Option<bool>) -> Column {
    Column::Flag(rows.iter().map(|r| cell(r).unwrap_or(false)).collect())
}

fn text(rows: &[SweepRow], cell: impl Fn(&SweepRow) -> Option<String>) -> Column {
    Column::Text(rows.iter().map(cell).collect())
}

/// Every column of `rows`, in [`SweepRow::COLUMNS`] order. A count is exact in `float64`
/// (sweeps have fewer than 2^53 orbits).
fn columns(rows: &[SweepRow]) -> Vec<(&'static str, Column)> {
    let small = |n: usize| u32::try_from(n).unwrap_or(u32::MAX);
    vec![
        ("omega", number(rows, |r| r.omega)),
        (
            "linear_outer_amplitude",
            number(rows, |r| r.linear_outer_amplitude),
        ),
        (
            "linear_transmittance_db",
            number(rows, |r| r.linear_transmittance_db),
        ),
        (
            "linear_touches_stops",
            flag(rows, |r| r.linear_touches_stops),
        ),
        (
            "linear_cell_outer_amplitudes",
            text(rows, |r| r.linear_cell_outer_amplitudes.clone()),
        ),
        ("orbits", count(rows, |r| r.orbits.map(small))),
        (
            "stable_viable_orbits",
            count(rows, |r| r.stable_viable_orbits.map(small)),
        ),
        ("branch0_alpha", number(rows, |r| r.branch0_alpha)),
        (
            "branch0_outer_amplitude",
            number(rows, |r| r.branch0_outer_amplitude),
        ),
        (
            "branch0_transmittance_db",
            number(rows, |r| r.branch0_transmittance_db),
        ),
        ("branch0_viable", flag(rows, |r| r.branch0_viable)),
        ("branch0_stable", flag(rows, |r| r.branch0_stable)),
        ("branch1_alpha", number(rows, |r| r.branch1_alpha)),
        (
            "branch1_outer_amplitude",
            number(rows, |r| r.branch1_outer_amplitude),
        ),
        (
            "branch1_transmittance_db",
            number(rows, |r| r.branch1_transmittance_db),
        ),
        ("branch1_viable", flag(rows, |r| r.branch1_viable)),
        ("branch1_stable", flag(rows, |r| r.branch1_stable)),
        (
            "simulated_regime",
            text(rows, |r| r.simulated_regime.map(str::to_owned)),
        ),
        (
            "simulated_status",
            text(rows, |r| r.simulated_status.clone()),
        ),
        ("simulated_period", count(rows, |r| r.simulated_period)),
        (
            "simulated_impacts_per_period",
            number(rows, |r| r.simulated_impacts_per_period),
        ),
        (
            "simulated_pair_impacts_per_period",
            text(rows, |r| r.simulated_pair_impacts_per_period.clone()),
        ),
        (
            "simulated_outer_amplitude",
            number(rows, |r| r.simulated_outer_amplitude),
        ),
        (
            "simulated_cell_outer_amplitudes",
            text(rows, |r| r.simulated_cell_outer_amplitudes.clone()),
        ),
        (
            "simulated_transmittance_db",
            number(rows, |r| r.simulated_transmittance_db),
        ),
        ("simulated_sticking", flag(rows, |r| r.simulated_sticking)),
        (
            "simulated_signature",
            text(rows, |r| r.simulated_signature.clone()),
        ),
        ("largest_exponent", number(rows, |r| r.largest_exponent)),
        (
            "largest_exponent_uncertainty",
            number(rows, |r| r.largest_exponent_uncertainty),
        ),
        (
            "lyapunov_regime",
            text(rows, |r| r.lyapunov_regime.map(str::to_owned)),
        ),
        (
            "analytic_outer_amplitude",
            number(rows, |r| r.analytic_outer_amplitude),
        ),
        (
            "analytic_cell_outer_amplitudes",
            text(rows, |r| r.analytic_cell_outer_amplitudes.clone()),
        ),
        ("analytic_viable", flag(rows, |r| r.analytic_viable)),
        ("analytic_stable", flag(rows, |r| r.analytic_stable)),
        (
            "analytic_energy_residual",
            number(rows, |r| r.analytic_energy_residual),
        ),
        ("class", text(rows, |r| r.class.map(str::to_owned))),
        (
            "relative_difference",
            number(rows, |r| r.relative_difference),
        ),
        (
            "multiplier_difference",
            number(rows, |r| r.multiplier_difference),
        ),
        ("class_detail", text(rows, |r| r.class_detail.clone())),
        ("matched", text(rows, |r| r.matched.clone())),
        ("error", text(rows, |r| r.error.clone())),
    ]
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
        Ok(table_text(Format::Json, &self.header, &self.rows))
    }

    /// The rows as one JSON array, each row as the command writes it.
    fn rows_json(&self) -> PyResult<String> {
        json(&self.rows)
    }

    /// The columns, in the command's order, as `(name, numpy array)` pairs.
    ///
    /// # Errors
    /// A `RuntimeError` if the columns here no longer match the command's (a bug).
    fn columns<'py>(&self, py: Python<'py>) -> PyResult<Vec<(&'static str, Bound<'py, PyAny>)>> {
        let columns = columns(&self.rows);
        let names: Vec<&str> = columns.iter().map(|(n, _)| *n).collect();
        if names != SweepRow::COLUMNS {
            return Err(PyRuntimeError::new_err(format!(
                "internal error (a bug in rattle, please report it): sweep columns {names:?} differ from the command's {:?}",
                SweepRow::COLUMNS
            )));
        }
        columns
            .into_iter()
            .map(|(name, column)| {
                let array = match column {
                    Column::Number(v) => PyArray1::from_vec(py, v).into_any(),
                    Column::Flag(v) => PyArray1::from_vec(py, v).into_any(),
                    Column::Text(v) => {
                        let objects: Vec<Py<PyAny>> = v
                            .into_iter()
                            .map(|s| match s {
                                Some(s) => PyString::new(py, &s).into_any().unbind(),
                                None => py.None(),
                            })
                            .collect();
                        PyArray1::from_vec(py, objects).into_any()
                    }
                };
                Ok((name, array))
            })
            .collect()
    }

    fn __len__(&self) -> usize {
        self.rows.len()
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

/// `rattle sweep --out FILE.json`: `solver` at every frequency of `omegas`, in parallel on
/// rayon's pool, in order.
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
        check_frequency(&scene.scene, &format!("omegas[{i}]"), omega)?;
    }
    let part = shard(part)?;
    let omegas = match part {
        Some(s) => all[s.range(all.len())].to_vec(),
        None => all.clone(),
    };
    let solver = solver(solver_name)?;
    let options = options(tol, steady_tol, max_periods, max_oscillations)?;
    let scene = &scene.scene;
    let rows = compute(py, || {
        // The command's own row builder (with the Lyapunov columns), rows kept in order.
        let mut rows = Vec::with_capacity(omegas.len());
        let done: Result<(), std::convert::Infallible> = sweep_rows(
            scene,
            &omegas,
            solver,
            &options,
            &Progress::hidden(),
            |row| {
                rows.push(row);
                Ok(())
            },
        );
        match done {
            Ok(()) => Ok(rows),
            Err(never) => match never {},
        }
    })?;
    Ok(NativeSweep {
        header: header(scene, solver, all.len(), part),
        rows,
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

/// `(K, N)` from Python as the command's `--shard K/N`; `None` for the whole run.
fn shard(value: Option<(i64, i64)>) -> PyResult<Option<Shard>> {
    value
        .map(|(k, n)| {
            Shard::parse(&format!("{k}/{n}")).map_err(|_| {
                PyValueError::new_err(format!(
                    "shard = ({k}, {n}): must be (K, N) with 1 ≤ K ≤ N, e.g. (3, 8)"
                ))
            })
        })
        .transpose()
}

/// A count from Python, refused with `message` when negative (the command takes `usize`;
/// zero is refused by the grid's own checks, with the command's message).
fn count_of(name: &str, n: i64) -> PyResult<usize> {
    usize::try_from(n)
        .map_err(|_| PyValueError::new_err(format!("{name} = {n} is out of range: must be ≥ 1")))
}

/// The command's map options named as this module's parameters: `--gap-min` is `gap[0]`,
/// `--points` is `omega[2]`.
fn map_names(message: &str) -> String {
    let mut m = message.to_owned();
    for (axis, [min, max, count]) in [
        (
            "restitution",
            ["--restitution-min", "--restitution-max", "--restitutions"],
        ),
        ("gap", ["--gap-min", "--gap-max", "--gaps"]),
        ("omega", ["--omega-min", "--omega-max", "--points"]),
    ] {
        m = m
            .replace(min, &format!("{axis}[0]"))
            .replace(max, &format!("{axis}[1]"))
            .replace(count, &format!("{axis}[2]"));
    }
    python_names(&m)
}

/// `rattle map --out F.json [--shard K/N]`: the map's points table, the command's file as
/// text (computed on rayon's pool, lines in parallel). Each axis is `(min, max, count)`.
#[pyfunction]
#[pyo3(signature = (scene, restitution, gap, omega, tol, steady_tol, max_periods, max_oscillations, part=None))]
#[allow(clippy::too_many_arguments)]
fn map_document(
    py: Python<'_>,
    scene: &NativeScene,
    restitution: (f64, f64, i64),
    gap: (f64, f64, i64),
    omega: (f64, f64, i64),
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
    part: Option<(i64, i64)>,
) -> PyResult<String> {
    let axis = |name: &str, (min, max, n): (f64, f64, i64)| {
        Ok::<_, PyErr>(Axis::new(min, max, count_of(&format!("{name}[2]"), n)?))
    };
    let grid = MapGrid {
        restitution: axis("restitution", restitution)?,
        gap_over_base_amplitude: axis("gap", gap)?,
        omega: axis("omega", omega)?,
    };
    grid.validate()
        .map_err(|e| PyValueError::new_err(map_names(&e.to_string())))?;
    let settings =
        MapSettings::with_simulation(options(tol, steady_tol, max_periods, max_oscillations)?);
    let part = shard(part)?;
    let scene = &scene.scene;
    if scene.stops.is_none() {
        return Err(PyValueError::new_err(MapError::NoStops.to_string()));
    }
    check_frequency(scene, "omega[0]", grid.omega.min)?;
    check_frequency(scene, "omega[1]", grid.omega.max)?;
    let text = compute(py, || {
        let mut out = Vec::new();
        let none: Option<(Format, Vec<u8>)> = None;
        write_map(
            scene,
            &grid,
            &settings,
            part,
            (Format::Json, &mut out),
            none,
            &Progress::hidden(),
        )
        .map_err(|e| e.to_string())?;
        String::from_utf8(out).map_err(|e| e.to_string())
    })?;
    Ok(text)
}

/// `rattle basins --out F.json [--shard K/N]`: the basins table, the command's file as text.
/// `outer` and `inner` are `(min, max)`, m.
#[pyfunction]
#[pyo3(signature = (scene, omega, outer, inner, points, part=None))]
fn basins_document(
    py: Python<'_>,
    scene: &NativeScene,
    omega: f64,
    outer: (f64, f64),
    inner: (f64, f64),
    points: i64,
    part: Option<(i64, i64)>,
) -> PyResult<String> {
    let omega = check_omega("omega", omega)?;
    let points = count_of("points", points)?;
    let grid = BasinGrid::new(outer, inner, points).map_err(|e| {
        PyValueError::new_err(
            e.to_string()
                .replace("--outer-min", "outer[0]")
                .replace("--outer-max", "outer[1]")
                .replace("--inner-min", "inner[0]")
                .replace("--inner-max", "inner[1]")
                .replace("--points", "points"),
        )
    })?;
    let part = shard(part)?;
    unit_only(&scene.scene, "rattle basins")?;
    check_frequency(&scene.scene, "omega", omega)?;
    let scene = &scene.scene;
    compute(py, || {
        let mut out = Vec::new();
        write_basins(
            scene,
            omega,
            grid,
            &basin_options(),
            part,
            (Format::Json, &mut out),
            &Progress::hidden(),
        )
        .map_err(|e| e.to_string())?;
        String::from_utf8(out).map_err(|e| e.to_string())
    })
}

/// `rattle merge`: the parts of a sharded sweep, map or basins (documents as text, all JSON
/// or all CSV, any order) joined into exactly the document of the whole run.
#[pyfunction]
fn merge(py: Python<'_>, parts: Vec<String>) -> PyResult<String> {
    py.detach(|| merge_parts(&parts))
        .map_err(PyValueError::new_err)
}

/// The defaults of `rattle map`'s accuracy options: `tol`, `steady_tol` (the map's looser
/// periodicity tolerance), `max_periods` (the map's cap), `max_oscillations`.
#[pyfunction]
fn map_defaults(py: Python<'_>) -> PyResult<Bound<'_, PyDict>> {
    let d = MapSettings::default().simulation;
    let out = PyDict::new(py);
    out.set_item("tol", d.root_tolerance)?;
    out.set_item("steady_tol", d.periodicity_tolerance)?;
    out.set_item("max_periods", d.max_periods)?;
    out.set_item(
        "max_oscillations",
        d.max_oscillations.unwrap_or(f64::INFINITY),
    )?;
    Ok(out)
}

/// The columns of the command's tables, in order: `"map"` (the points), `"basins"`, `"sweep"`.
#[pyfunction]
fn table_columns(table: &str) -> PyResult<Vec<&'static str>> {
    match table {
        "map" => Ok(MapPointRow::COLUMNS.to_vec()),
        "basins" => Ok(BasinRow::COLUMNS.to_vec()),
        "sweep" => Ok(SweepRow::COLUMNS.to_vec()),
        _ => Err(PyValueError::new_err(format!("no table {table:?}"))),
    }
}

/// Exercises the boundary's failure paths, for the tests (no input is known to make either
/// solver fail): `"error"` fails as a numerical failure, `"panic"` panics inside the released
/// computation; both must come out as `RuntimeError`.
#[pyfunction]
fn _boundary_check(py: Python<'_>, kind: &str) -> PyResult<()> {
    let kind = kind.to_owned();
    compute(py, move || match kind.as_str() {
        "error" => Err("a failure from the boundary check".to_owned()),
        "panic" => panic!("a panic from the boundary check"),
        _ => Ok(()),
    })
}

/// The native module.
#[pymodule]
fn _rattle(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The command's `--lyapunov-periods` default.
    m.add(
        "LYAPUNOV_PERIODS",
        rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS,
    )?;
    m.add_class::<NativeScene>()?;
    m.add_class::<NativeSweep>()?;
    m.add_function(wrap_pyfunction!(defaults, m)?)?;
    m.add_function(wrap_pyfunction!(orbit, m)?)?;
    m.add_function(wrap_pyfunction!(simulate, m)?)?;
    m.add_function(wrap_pyfunction!(orbit_trajectory, m)?)?;
    m.add_function(wrap_pyfunction!(continuation_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(continue_branch, m)?)?;
    m.add_function(wrap_pyfunction!(compare, m)?)?;
    m.add_function(wrap_pyfunction!(sweep, m)?)?;
    m.add_function(wrap_pyfunction!(frequencies, m)?)?;
    m.add_function(wrap_pyfunction!(map_document, m)?)?;
    m.add_function(wrap_pyfunction!(basins_document, m)?)?;
    m.add_function(wrap_pyfunction!(merge, m)?)?;
    m.add_function(wrap_pyfunction!(map_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(table_columns, m)?)?;
    m.add_function(wrap_pyfunction!(_boundary_check, m)?)?;
    m.add_function(wrap_pyfunction!(boundary::boundary_defaults, m)?)?;
    m.add_function(wrap_pyfunction!(boundary::boundary, m)?)?;
    Ok(())
}
