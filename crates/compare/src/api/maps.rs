//! `rattle map` through the front door: the map of a scene of any form over two of its
//! parameters (by default a unit's restitution and gap) and frequency, its tables written to
//! any writers.

use super::{argument, numerical, ApiError, Table};
use crate::output::Format;
use crate::runs::map::{write_any_map, AnyMapGrid, MapError, MapSettings, WriteMapError};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::scene::AnyScene;
use std::io::Write;

/// The map of `scene` over `grid` (its two axes, each frequency continued from the previous
/// one): every point written to `points` and, when given, the attenuation bandwidth of every
/// line to `bandwidth`, each in its format, line by line as the lines are done (only part
/// `shard` of the lines with a shard): `rattle map`. The grid is checked whole on the scene
/// before anything is written ([`AnyMapGrid::line_scenes`]).
///
/// # Errors
/// [`ApiError::Argument`] for a grid out of range (naming the axis's flag and the parameter's
/// range), a path the scene does not have, or a scene the axes do not take (no stops; a
/// structure on the default axes); [`ApiError::Frequency`] naming `--omega-min` or
/// `--omega-max` on the default axes (on two parameters, a line's frequency bounds are an
/// [`ApiError::Argument`] naming the line); [`ApiError::Write`] naming the table that could not
/// be written.
pub fn map<P: Write, B: Write>(
    scene: &AnyScene,
    grid: &AnyMapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    points: (Format, P),
    bandwidth: Option<(Format, B)>,
    progress: &Progress,
) -> Result<(), ApiError> {
    write_any_map(scene, grid, settings, shard, points, bandwidth, progress).map_err(|e| match e {
        WriteMapError::Map(MapError::Frequency(e)) => ApiError::Frequency(e),
        WriteMapError::Map(e) => argument(e),
        WriteMapError::Points(source) => ApiError::Write {
            table: Table::Points,
            source,
        },
        WriteMapError::Bandwidth(source) => ApiError::Write {
            table: Table::Bandwidth,
            source,
        },
    })
}

/// [`map`]'s points table as the JSON document `rattle map --out F.json` writes.
///
/// # Errors
/// As [`map`].
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::runs::axis::Axis;
/// use rattle_compare::runs::map::{AnyMapGrid, MapAxes, MapGrid, MapSettings};
/// use rattle_compare::scene::parameter::AnyParameter;
/// use rattle_compare::scene::{AnyScene, Scene};
///
/// // The map over restitution and gap.
/// let unit = AnyScene::Cells(Scene::paper());
/// let grid = MapGrid {
///     restitution: Axis::new(0.8, 0.8, 1),
///     gap_over_base_amplitude: Axis::new(0.5, 0.5, 1),
///     omega: Axis::new(1.8, 2.2, 3),
/// };
/// let text = api::map_document(&unit, &grid.into(), &MapSettings::default(), None)?;
/// let document: serde_json::Value = serde_json::from_str(&text).unwrap();
/// assert_eq!(document["points"], 3);
/// assert_eq!(document["results"].as_array().unwrap().len(), 3);
///
/// // Over two parameters by their paths: columns `x` and `y`, the paths in the header.
/// let grid = AnyMapGrid {
///     axes: MapAxes::Parameters {
///         x: AnyParameter::parse(&unit, "unit.inner_mass")?,
///         y: AnyParameter::parse(&unit, "damping.inner")?,
///     },
///     x: Axis::new(0.8, 1.2, 2),
///     y: Axis::new(0.1, 0.1, 1),
///     omega: Axis::new(1.8, 2.2, 3),
/// };
/// let text = api::map_document(&unit, &grid, &MapSettings::default(), None)?;
/// let document: serde_json::Value = serde_json::from_str(&text).unwrap();
/// assert_eq!(document["grid"]["x"]["path"], "unit.inner_mass");
/// assert_eq!(document["results"][5]["x"], 1.2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn map_document(
    scene: &AnyScene,
    grid: &AnyMapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
) -> Result<String, ApiError> {
    let mut out = Vec::new();
    map(
        scene,
        grid,
        settings,
        shard,
        (Format::Json, &mut out),
        None::<(Format, Vec<u8>)>,
        &Progress::hidden(),
    )?;
    String::from_utf8(out).map_err(numerical)
}
