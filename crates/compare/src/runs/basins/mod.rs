//! Basins of attraction: a grid of starts over two coordinates of a scene, each run to its
//! steady state and coloured by the attractor it reaches.
//!
//! The plane of starts is spanned by two coordinates of the scene ([`Coordinate`]: a body's
//! displacement `u:NAME` or velocity `v:NAME`); every other coordinate starts at rest, at time 0
//! (the base, or the forces, at phase 0). The unit's default plane is its outer and inner
//! displacements ([`BasinGrid`], `u:outer × u:inner`): the plane a unit meets when released from
//! a displaced position.
//!
//! On the unit an attractor is identified by its impact signature (from the sides of the final
//! cycle's impacts, no Newton polish), its least period and its amplitude `X_o`, to
//! [`BASIN_AMPLITUDE_TOLERANCE`] ([`Attractor::Periodic`]). On a chain or a structure it is
//! identified by each stop's signature, the least period and every body's amplitude, to the
//! same tolerance relative to the largest ([`Attractor::Motion`]); a floating body that no
//! impact of the cycle touches has no amplitude there (it rests anywhere the stops leave room
//! for, a family). The motions that do not repeat within the cap form one class, as do those
//! without dissipation and those that stick (by status). Attractors are numbered by first
//! appearance in grid order (the second coordinate fastest), so the grid and its numbers do not
//! depend on the number of threads.
//!
//! A start converging slowly on a periodic attractor would run to the cap before it repeats
//! to the periodicity tolerance; so the periodic attractors of a coarse reference grid
//! ([`BASIN_REFERENCE_STRIDE`]) are found first, and a start is attributed to one of them as
//! soon as its stroboscopic state comes within [`BASIN_PROXIMITY`] of that attractor's, checked
//! at every section `t = kT` by the simulator's section watch, which ends the run there. A
//! family (a motion with a floating body untouched by impacts) is no reference: being near one
//! of its members does not say which member, or whether an impact comes.
//!
//! The module is split by job: the plane of starts (its coordinates, its grid and the
//! command's axes, [`BasinAxes::starts`]), the attractors a start reaches and their numbering
//! ([`Attractor`], [`number`]), the runs over the grid ([`plane_basins_part`]), the tables
//! ([`write_plane_basins`]) and the merge of a sharded grid's parts ([`merge_parts`]).

mod attractor;
mod merge;
mod output;
mod plane;
mod run;

pub use attractor::{number, Attractor, BasinCell, Basins, Reached};
pub use merge::{is_basins_part, merge_parts};
pub use output::{
    header, rows, write_basins, write_plane_basins, BasinRow, PlaneRow, BODY_AMPLITUDES,
};
pub use plane::{
    body_names, coordinate_names, BasinAxes, BasinGrid, BasinPlane, BasinStarts, BasinsError,
    Coordinate, Quantity,
};
pub use run::{
    basins, basins_part, destination, destination_of, plane_basins_part, start_at_rest,
    BASIN_PROXIMITY, BASIN_REFERENCE_STRIDE,
};

use crate::runs::map::MAP_PERIODICITY_TOLERANCE;
use rattle_event_driven::SimulationOptions;

/// Periods each start runs at most: a start that has not repeated by then is `not periodic`.
/// From rest the paper's unit at the coexistence frequency ω = 1.86 settles within 150–212
/// periods (to 1e-5 and 1e-9); twice that leaves slower starts a margin while bounding the
/// cost of the motions that never repeat.
pub const BASIN_MAX_PERIODS: u64 = 400;

/// Two periodic motions of one signature are one attractor when their amplitudes `X_o`
/// differ by less than this, relative to the larger: far above the amplitude's error at the
/// periodicity tolerance ([`MAP_PERIODICITY_TOLERANCE`] relative to the gap), far below the
/// difference between coexisting orbits (tens of percent on the paper's unit).
pub const BASIN_AMPLITUDE_TOLERANCE: f64 = 1e-3;

/// The simulator's options for basins: the map's periodicity tolerance, the
/// [`BASIN_MAX_PERIODS`] cap, no Newton polish.
pub fn basin_options() -> SimulationOptions {
    SimulationOptions {
        periodicity_tolerance: MAP_PERIODICITY_TOLERANCE,
        max_periods: BASIN_MAX_PERIODS,
        polish: false,
        ..SimulationOptions::default()
    }
}
