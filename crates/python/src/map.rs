//! `rattle.map`'s native half: the map's points table, as `rattle map --out F.json
//! [--shard K/N]` writes it, over restitution and gap or over two parameters of a scene of any
//! form, and the map's default accuracy options.

use crate::common::{compute_api, count_of, options, python_names, shard};
use crate::scene::NativeScene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use rattle_compare::api;
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::map::{AnyMapGrid, MapAxes, MapError, MapSettings};
use rattle_compare::scene::parameter::AnyParameter;

/// The command's map options named as this module's parameters: `--gap-min` is `gap[0]`,
/// `--points` is `omega[2]`, `--x` is `x[0]` and `--x-min` is `x[1]`.
fn map_names(message: &str) -> String {
    let mut m = message.replace("--x and --y", "x and y");
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
    for axis in ["x", "y"] {
        m = m
            .replace(&format!("--{axis}-min"), &format!("{axis}[1]"))
            .replace(&format!("--{axis}-max"), &format!("{axis}[2]"))
            .replace(&format!("--{axis}-count"), &format!("{axis}[3]"))
            .replace(&format!("--{axis}"), &format!("{axis}[0]"));
    }
    python_names(&m)
}

/// A parameter axis from Python: `(path, min, max, count)`.
type ParameterAxis = (String, f64, f64, i64);

/// `rattle map --out F.json [--shard K/N]`: the map's points table, the command's file as
/// text (computed on rayon's pool, lines in parallel). Each axis is `(min, max, count)`, and
/// `x`, `y` are `(path, min, max, count)`: with both, the map is over those two parameters of
/// a scene of any form (`restitution` and `gap` are then `None`); without, over the restitution
/// and gap of a unit or chain, as the command's default.
#[pyfunction]
#[pyo3(signature = (scene, restitution, gap, omega, tol, steady_tol, max_periods, max_oscillations, part=None, x=None, y=None))]
#[allow(clippy::too_many_arguments)]
fn map_document(
    py: Python<'_>,
    scene: &NativeScene,
    restitution: Option<(f64, f64, i64)>,
    gap: Option<(f64, f64, i64)>,
    omega: (f64, f64, i64),
    tol: f64,
    steady_tol: f64,
    max_periods: i64,
    max_oscillations: f64,
    part: Option<(i64, i64)>,
    x: Option<ParameterAxis>,
    y: Option<ParameterAxis>,
) -> PyResult<String> {
    let scene = &scene.scene;
    let axis = |name: &str, index: usize, (min, max, n): (f64, f64, i64)| {
        Ok::<_, PyErr>(Axis::new(
            min,
            max,
            count_of(&format!("{name}[{index}]"), n)?,
        ))
    };
    let value_error = |e: &dyn std::fmt::Display| PyValueError::new_err(map_names(&e.to_string()));
    let grid = match (x, y, restitution, gap) {
        (Some((x_path, x0, x1, xn)), Some((y_path, y0, y1, yn)), None, None) => {
            let parse = |flag: &str, path: &str| {
                AnyParameter::parse(scene, path).map_err(|e| {
                    value_error(&MapError::Parameter {
                        flag: flag.into(),
                        message: e.to_string(),
                    })
                })
            };
            AnyMapGrid {
                axes: MapAxes::Parameters {
                    x: parse("--x", &x_path)?,
                    y: parse("--y", &y_path)?,
                },
                x: axis("x", 3, (x0, x1, xn))?,
                y: axis("y", 3, (y0, y1, yn))?,
                omega: axis("omega", 2, omega)?,
            }
        }
        (None, None, Some(restitution), Some(gap)) => AnyMapGrid {
            axes: MapAxes::Stops,
            x: axis("restitution", 2, restitution)?,
            y: axis("gap", 2, gap)?,
            omega: axis("omega", 2, omega)?,
        },
        _ => {
            return Err(PyValueError::new_err(
                "map_document: give x and y, or restitution and gap (rattle.map chooses)",
            ))
        }
    };
    // In the command's order: the axes' shapes, the options, then the grid on the scene.
    grid.validate().map_err(|e| value_error(&e))?;
    let settings =
        MapSettings::with_simulation(options(tol, steady_tol, max_periods, max_oscillations)?);
    let part = shard(part)?;
    grid.check(scene).map_err(|e| value_error(&e))?;
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
