//! `rattle.map`'s native half: the map's points table, as `rattle map --out F.json
//! [--shard K/N]` writes it, and the map's default accuracy options.

use crate::common::{check_frequency, compute_api, count_of, options, python_names, shard};
use crate::scene::NativeScene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rattle_compare::api;
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::map::{MapError, MapGrid, MapSettings};

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
/// text (computed on rayon's pool, lines in parallel). Each axis is `(min, max, count)`. A
/// structure is refused by name, as the command refuses one.
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
    let scene = scene.cells("rattle.map")?;
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
    if scene.stops.is_none() {
        return Err(PyValueError::new_err(MapError::NoStops.to_string()));
    }
    check_frequency(scene, "omega[0]", grid.omega.min)?;
    check_frequency(scene, "omega[1]", grid.omega.max)?;
    compute_api(py, map_names, || {
        api::map_document(scene, &grid, &settings, part)
    })
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

/// Registers `map_document` and `map_defaults`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(map_document, m)?)?;
    m.add_function(wrap_pyfunction!(map_defaults, m)?)?;
    Ok(())
}
