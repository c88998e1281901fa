//! Basins of attraction through the front door: the unit's default plane and any two
//! coordinates of any scene form (`rattle basins`).

use super::{argument, check_cells_frequency, check_frequency, ApiError, Table};
use crate::output::Format;
use crate::runs::basins::{write_basins, write_plane_basins, BasinGrid, BasinPlane, Basins};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::scene::{AnyScene, Scene};
use rattle_event_driven::SimulationOptions;
use std::io::Write;

/// Basins of attraction of a single unit at `omega`: every start at rest of `grid` (outer
/// and inner displacement) run to its steady state with `options` and numbered by the
/// attractor it reaches, in parallel, the table written to `out` in its format (only part
/// `shard` of the starts with a shard): `rattle basins`.
///
/// # Errors
/// [`ApiError::Argument`] for a chain or a structure; [`ApiError::Frequency`] naming `--omega`;
/// [`ApiError::Write`] when the table cannot be written.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::output::Format;
/// use rattle_compare::runs::basins::{basin_options, BasinGrid};
/// use rattle_compare::runs::parallel::Progress;
/// use rattle_compare::scene::Scene;
///
/// let grid = BasinGrid::new((-0.5, 0.5), (-0.5, 0.5), 2).unwrap();
/// let mut table = Vec::new();
/// let basins = api::basins(
///     &Scene::paper(), 2.0, grid, &basin_options(), None,
///     (Format::Csv, &mut table), &Progress::hidden(),
/// )?;
/// assert_eq!(basins.cells.len(), 4);
/// assert_eq!(basins.counts.iter().sum::<usize>(), 4);
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn basins<W: Write>(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    out: (Format, W),
    progress: &Progress,
) -> Result<Basins, ApiError> {
    scene
        .refuse_chain("rattle_compare::api::basins")
        .map_err(argument)?;
    let omega = check_cells_frequency(scene, "--omega", omega)?;
    write_basins(scene, omega, grid, options, shard, out, progress).map_err(|source| {
        ApiError::Write {
            table: Table::Points,
            source,
        }
    })
}

/// Basins of attraction of a scene of any form (unit, chain or structure) at `omega`: every
/// start of `plane` (the scene at rest with the plane's two coordinates set, at time 0) run to
/// its steady state with `options` and numbered by the attractor it reaches, in parallel, the
/// table written to `out` in its format (only part `shard` of the starts with a shard):
/// `rattle basins --x … --y …`. A structure's start outside a stop's clearance is not run
/// (attractor "start outside a stop's clearance").
///
/// # Errors
/// [`ApiError::Frequency`] naming `--omega`; [`ApiError::Argument`] when `plane` names a
/// coordinate `scene` does not have (a plane built for another scene); [`ApiError::Write`]
/// when the table cannot be written.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::output::Format;
/// use rattle_compare::runs::basins::{basin_options, BasinPlane};
/// use rattle_compare::runs::parallel::Progress;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/impact-oscillator.json");
/// let scene = api::load(path)?;
/// let plane = BasinPlane::new(&scene, ("u:x", (-0.5, 0.4)), ("v:x", (-0.5, 0.5)), 2).unwrap();
/// let mut table = Vec::new();
/// let basins = api::plane_basins(
///     &scene, 1.8, &plane, &basin_options(), None,
///     (Format::Csv, &mut table), &Progress::hidden(),
/// )?;
/// assert_eq!(basins.cells.len(), 4);
/// let text = String::from_utf8(table).unwrap();
/// assert!(text.starts_with("x_start,x_velocity_start,attractor,"));
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub fn plane_basins<W: Write>(
    scene: &AnyScene,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    out: (Format, W),
    progress: &Progress,
) -> Result<Basins, ApiError> {
    let bodies = crate::runs::basins::body_names(scene);
    for (flag, c) in [("--x", &plane.x), ("--y", &plane.y)] {
        if bodies.get(c.index) != Some(&c.body) {
            return Err(argument(crate::runs::basins::BasinsError::Coordinate {
                flag,
                given: c.to_string(),
                names: crate::runs::basins::coordinate_names(&bodies).join(", "),
            }));
        }
    }
    let omega = check_frequency(scene, "--omega", omega)?;
    write_plane_basins(scene, omega, plane, options, shard, out, progress).map_err(|source| {
        ApiError::Write {
            table: Table::Points,
            source,
        }
    })
}
