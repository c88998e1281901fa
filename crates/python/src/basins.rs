//! `rattle.basins`' native half: the basins table, as `rattle basins --out F.json
//! [--shard K/N]` writes it, on the unit's default plane or over any two coordinates of a
//! scene of any form (`--x`, `--y`).

use crate::common::{check_any_frequency, check_omega, compute_api, count_of, python_names, shard};
use crate::scene::NativeScene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, ApiError};
use rattle_compare::output::Format;
use rattle_compare::runs::basins::{basin_options, BasinAxes, BasinStarts};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::scene::AnyScene;

/// The command's basins options in `message` named as this function's parameters: the unit's
/// default plane's sides as the tuples `outer` and `inner`, the named axes' as `x_min`…
fn basins_names(message: &str) -> String {
    message
        .replace(
            "--outer-min/--outer-max/--inner-min/--inner-max",
            "outer/inner",
        )
        .replace("--x-min/--x-max/--y-min/--y-max", "x_min/x_max/y_min/y_max")
        .replace("--outer-min", "outer[0]")
        .replace("--outer-max", "outer[1]")
        .replace("--inner-min", "inner[0]")
        .replace("--inner-max", "inner[1]")
        .replace("--x-min", "x_min")
        .replace("--x-max", "x_max")
        .replace("--y-min", "y_min")
        .replace("--y-max", "y_max")
        .replace("--x/--y", "x/y")
        .replace("--x and --y", "x and y")
        .replace("--x", "x")
        .replace("--y", "y")
        .replace("--points", "points")
}

/// `rattle basins [--x X --y Y --x-min … --y-max …] --out F.json [--shard K/N]`: the basins
/// table, the command's file as text. `outer` and `inner` are the unit's default plane's
/// sides, `(min, max)`, m; `x` and `y` name two coordinates of any scene (`u:NAME`,
/// `v:NAME`), over `[x_min, x_max]` and `[y_min, y_max]`. A side left out (`None`) is the
/// command's default, and the options are read as the command reads its flags
/// ([`BasinAxes::starts`]), their errors named as these parameters.
#[pyfunction]
#[pyo3(signature = (scene, omega, outer, inner, points, part=None, x=None, y=None, x_min=None, x_max=None, y_min=None, y_max=None))]
#[allow(clippy::too_many_arguments)]
fn basins_document(
    py: Python<'_>,
    scene: &NativeScene,
    omega: f64,
    outer: Option<(f64, f64)>,
    inner: Option<(f64, f64)>,
    points: i64,
    part: Option<(i64, i64)>,
    x: Option<String>,
    y: Option<String>,
    x_min: Option<f64>,
    x_max: Option<f64>,
    y_min: Option<f64>,
    y_max: Option<f64>,
) -> PyResult<String> {
    let scene = &scene.scene;
    let omega = check_omega("omega", omega)?;
    let points = count_of("points", points)?;
    let part = shard(part)?;
    let side = |s: Option<(f64, f64)>| (s.map(|s| s.0), s.map(|s| s.1));
    let axes = BasinAxes {
        x,
        y,
        x_range: (x_min, x_max),
        y_range: (y_min, y_max),
        outer: side(outer),
        inner: side(inner),
        points,
    };
    let starts = axes
        .starts(scene)
        .map_err(|e| PyValueError::new_err(basins_names(&e.to_string())))?;
    check_any_frequency(scene, "omega", omega)?;
    compute_api(py, python_names, || {
        let mut out = Vec::new();
        let table = (Format::Json, &mut out);
        let progress = Progress::hidden();
        match (scene, &starts) {
            (AnyScene::Cells(unit), BasinStarts::Unit(grid)) => {
                api::basins(unit, omega, *grid, &basin_options(), part, table, &progress)?;
            }
            (_, BasinStarts::Plane(plane)) => {
                api::plane_basins(
                    scene,
                    omega,
                    plane,
                    &basin_options(),
                    part,
                    table,
                    &progress,
                )?;
            }
            (AnyScene::Structure(_), BasinStarts::Unit(_)) => {
                unreachable!("the default plane is the unit's")
            }
        }
        String::from_utf8(out).map_err(|e| ApiError::Numerical(e.to_string()))
    })
}

/// Registers `basins_document`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(basins_document, m)?)
}
