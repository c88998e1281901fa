//! `rattle.basins`' native half: the basins table, as `rattle basins --out F.json
//! [--shard K/N]` writes it.

use crate::common::{
    check_frequency, check_omega, compute_api, count_of, python_names, shard, unit_only,
};
use crate::scene::NativeScene;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rattle_compare::api::{self, ApiError};
use rattle_compare::output::Format;
use rattle_compare::runs::basins::{basin_options, BasinGrid};
use rattle_compare::runs::parallel::Progress;

/// `rattle basins --out F.json [--shard K/N]`: the basins table, the command's file as text.
/// `outer` and `inner` are `(min, max)`, m. A structure is refused by name, as the command
/// refuses one.
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
    let scene = scene.cells("rattle.basins")?;
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
    unit_only(scene, "rattle basins")?;
    check_frequency(scene, "omega", omega)?;
    compute_api(py, python_names, || {
        let mut out = Vec::new();
        api::basins(
            scene,
            omega,
            grid,
            &basin_options(),
            part,
            (Format::Json, &mut out),
            &Progress::hidden(),
        )?;
        String::from_utf8(out).map_err(|e| ApiError::Numerical(e.to_string()))
    })
}

/// Registers `basins_document`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(basins_document, m)?)
}
