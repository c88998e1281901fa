//! Maps over two scene parameters and frequency: the regime of the motion and the attenuation
//! bandwidth, simulated and predicted.
//!
//! A map is a grid of lines, one per value of its two axes: by default the restitution `e` and
//! the gap over the base amplitude `Δ/u_g` of the stops of a unit or a chain ([`MapGrid`]), or
//! any two numbers of a scene of any form named by their JSON paths ([`AnyMapGrid`],
//! [`MapAxes`]). Along each line the frequency goes **up**, and the simulator at each
//! frequency starts from the final state of the previous one (continuation; the first
//! frequency starts from rest). Transients are then short, which is what makes 640 000 steady
//! states affordable, but the map follows an up-sweep: where attractors coexist (hysteresis),
//! a unit started from rest may settle elsewhere (see the `bifurcation` figure and `rattle
//! sweep`). Lines are independent and run in parallel; each line is sequential, so the output
//! does not depend on the number of threads.
//!
//! The simulator runs with map-specific settings ([`MapSettings::default`]): the stroboscopic
//! state must repeat to [`MAP_PERIODICITY_TOLERANCE`], at most [`MAP_MAX_PERIODS`] periods per
//! frequency. A point that does not repeat within the cap is reported as `irregular`, with the
//! transmittance of its final stretch (an honest amplitude, though not of a periodic motion);
//! an undamped point whose transients cannot decay is reported as `no-dissipation`, with no
//! transmittance. Neither is hidden.
//!
//! The analytic prediction at a point of a unit or a chain: the [`candidates`] of
//! [`crate::verdict`] (stable, viable symmetric two-impact orbits and, with damping, the linear
//! motion clear of the stops), chosen by [`Choice::LargestAttracting`]: the **largest**
//! transmittance over the attracting candidates, so a predicted attenuation holds whichever
//! the unit settles on; with no candidate there is no prediction. On a structure, the linear
//! steady state where it keeps every stop clear and the free motion decays, and nothing else
//! ([`line()`]).
//!
//! The module is split by job: the grid (its axes, each line's scene and the checks,
//! [`AnyMapGrid::line_scenes`]), one line (its points and bandwidth, [`line()`]) and the tables
//! ([`write_any_map`], [`MapColumns`]).
//!
//! [`candidates`]: crate::verdict::candidates
//! [`Choice::LargestAttracting`]: crate::verdict::Choice::LargestAttracting

mod grid;
mod line;
mod output;

pub use grid::{scene_at, AnyMapGrid, LineScene, MapAxes, MapGrid};
pub use line::{line, Bandwidth, MapLine, MapPoint, DECAY_RATE};
pub use output::{
    any_header, bands_text, header, write_any_map, write_map, BandwidthRow, MapColumns,
    MapPointRow, WriteMapError,
};

use crate::runs::axis::Axis;
use crate::runs::parallel::{for_each_ordered, Grain, Progress};
use crate::runs::shard::Shard;
use crate::scene::frequency::FrequencyError;
use crate::scene::{AnyScene, Scene};
use rattle_event_driven::SimulationOptions;
use thiserror::Error;

/// The stroboscopic state of a map point must repeat to this tolerance, relative to the gap
/// (the sweeps use 1e-9; a map needs the regime and the amplitude to about 1e-4, not the
/// last digits, and lightly damped transients decay by only ~10 % per period).
pub const MAP_PERIODICITY_TOLERANCE: f64 = 1e-5;

/// At most this many forcing periods per map point; a point that has not repeated by then is
/// `irregular` (or `no-dissipation` when undamped and free of impacts), and its transmittance
/// is that of its last periods. Measured on the lightly damped paper unit at e = 0.8 (10 gaps
/// × 100 frequencies): caps of 100, 400 and 1500 periods leave 69 %, 42 % and 38 % of the
/// points irregular, so 400 settles nearly all that settle at all, at a quarter of the cost
/// of 1500 (irregular points run to the cap and dominate the cost).
pub const MAP_MAX_PERIODS: u64 = 400;

/// Forcing periods of the exponents' run at a map point that did not repeat within
/// [`MAP_MAX_PERIODS`]: 200 (20 per batch), fewer than a sweep's 2000 to keep the map's cost
/// in check (irregular points already dominate it; 200 periods plus the 100 of alignment cost
/// about 1.4 × 300 plain periods, about as much as the point's own run to the cap). The
/// uncertainty is larger by `√10` than at 2000 periods, so weakly chaotic points may read
/// `quasi-periodic`: the regime is a cheap first reading, `rattle simulate --lyapunov` the
/// careful one.
pub const MAP_LYAPUNOV_PERIODS: u64 = 200;

/// Periods run per point when nothing can dissipate (no dashpot, every stop elastic): the
/// simulator calls such a motion `no-dissipation` whatever the cap (unless it repeats), so a
/// short run suffices.
pub const MAP_CONSERVATIVE_PERIODS: u64 = 40;

/// A simulated two-impact (or impact-free) motion matches an analytic candidate when they
/// differ by less than this, relatively: 100 × [`MAP_PERIODICITY_TOLERANCE`], because a motion
/// that repeats to `ε` can still be `ε / (1 − |μ|)` from its orbit (Floquet multiplier `μ`).
pub const MAP_MATCH_TOLERANCE: f64 = 1e-3;

/// A map grid or setting out of range; the message names the field and its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MapError {
    /// A field is out of range.
    #[error("{field} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// The field, as on the command line (e.g. `--gap-min`).
        field: &'static str,
        /// The value given.
        value: String,
        /// The allowed range.
        allowed: &'static str,
    },
    /// The scene has no stops: there is no gap or restitution to vary.
    #[error("the scene has no `stops`: a map varies their gap and restitution")]
    NoStops,
    /// A structure given to the map over restitution and gap, whose axes are a unit's stops.
    #[error(
        "scene '{scene}' is in the structure form: the map over restitution and gap takes the \
         unit and chain forms; give two of the structure's parameters as --x and --y (e.g. \
         structure.stops[0].gap_plus and structure.stops[0].restitution)"
    )]
    NoDefaultAxes {
        /// The scene's name.
        scene: String,
    },
    /// A parameter axis the scene does not take: a path it does not have, an end outside the
    /// parameter's range, the same parameter twice, or a line whose scene is refused or cannot
    /// be run at the grid's frequencies.
    #[error("{flag}: {message}")]
    Parameter {
        /// The flag, with its value (`--x-min = -1`), or the line (`at stops.gap = 0.1, …`).
        flag: String,
        /// Why, with the parameter's path and its allowed range.
        message: String,
    },
    /// A frequency of the grid that the scene cannot be run at in bounded time.
    #[error(transparent)]
    Frequency(#[from] FrequencyError),
}

/// The simulator's settings for a map.
#[derive(Debug, Clone, PartialEq)]
pub struct MapSettings {
    /// The simulator's options (periodicity tolerance and period cap included).
    pub simulation: SimulationOptions,
    /// Relative tolerance for "the simulated motion is the analytic candidate".
    pub match_tolerance: f64,
    /// Forcing periods of the exponents' run at a point that did not repeat; `None` computes
    /// no exponents (the largest exponent of periodic points, from their multipliers, needs
    /// the polish, which the map does not run).
    pub lyapunov_periods: Option<u64>,
}

impl Default for MapSettings {
    /// [`MAP_PERIODICITY_TOLERANCE`], [`MAP_MAX_PERIODS`] ([`MAP_CONSERVATIVE_PERIODS`] on
    /// lines where nothing dissipates: no dashpot, every stop elastic), [`MAP_MATCH_TOLERANCE`];
    /// the other simulator options at their defaults.
    fn default() -> Self {
        Self {
            simulation: SimulationOptions {
                periodicity_tolerance: MAP_PERIODICITY_TOLERANCE,
                max_periods: MAP_MAX_PERIODS,
                // A map point reports no signature: the Newton polish of each periodic point
                // (a third of the map's time on its short, continued runs) is not run.
                polish: false,
                ..SimulationOptions::default()
            },
            match_tolerance: MAP_MATCH_TOLERANCE,
            lyapunov_periods: Some(MAP_LYAPUNOV_PERIODS),
        }
    }
}

impl MapSettings {
    /// The map's settings with the simulator's `options` (from the command's accuracy
    /// options: contact tolerance, periodicity tolerance, period cap), without the Newton
    /// polish a map does not run; the others as [`MapSettings::default`].
    pub fn with_simulation(options: SimulationOptions) -> MapSettings {
        let defaults = MapSettings::default();
        MapSettings {
            simulation: SimulationOptions {
                polish: defaults.simulation.polish,
                ..options
            },
            ..defaults
        }
    }
}

/// A whole map over restitution and gap, every line kept.
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    /// The scene whose gap and restitution the map replaces.
    pub scene: Scene,
    /// The grid.
    pub grid: MapGrid,
    /// The settings.
    pub settings: MapSettings,
    /// Lines, restitution-major (all gaps of the first restitution, then the next): `x` the
    /// restitution, `y` the `Δ/u_g`.
    pub lines: Vec<MapLine>,
}

/// [`stream_any`] of the whole map over restitution and gap: every line, in the order of
/// [`Map::lines`].
///
/// # Errors
/// [`StreamError::Map`] for a grid out of range or a scene without stops (before anything is
/// computed); [`StreamError::Sink`] for the first error of `sink`.
pub fn stream<E>(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    progress: &Progress,
    sink: impl FnMut(MapLine) -> Result<(), E>,
) -> Result<(), StreamError<E>> {
    stream_lines(scene, grid, settings, None, progress, sink)
}

/// [`stream_any`] of the map over restitution and gap.
///
/// # Errors
/// As [`stream`].
pub fn stream_lines<E>(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    progress: &Progress,
    sink: impl FnMut(MapLine) -> Result<(), E>,
) -> Result<(), StreamError<E>> {
    stream_any(
        &AnyScene::Cells(scene.clone()),
        &AnyMapGrid::from(*grid),
        settings,
        shard,
        progress,
        sink,
    )
}

/// Computes the map of `scene` over `grid`, on any axes and any form, line by line (lines in
/// parallel, each line up in frequency with continuation), and hands each line to `sink` in
/// the order of the grid's lines (x-major) as soon as its block of lines is done; with a
/// shard, over the lines of that part only: part `K` of `N` is block `K` of `N` nearly equal
/// contiguous blocks of whole lines ([`Shard::range`] over [`AnyMapGrid::lines`]), since each
/// line continues every frequency from the previous one. A part beyond the number of lines has
/// none. The lines are those of the whole map, bit for bit, whatever the number of threads and
/// of parts.
///
/// # Errors
/// [`StreamError::Map`] for a grid the scene does not take ([`AnyMapGrid::line_scenes`],
/// before anything is computed); [`StreamError::Sink`] for the first error of `sink`.
pub fn stream_any<E>(
    scene: &AnyScene,
    grid: &AnyMapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    progress: &Progress,
    sink: impl FnMut(MapLine) -> Result<(), E>,
) -> Result<(), StreamError<E>> {
    let lines = grid.line_scenes(scene).map_err(StreamError::Map)?;
    run_lines(&lines, &grid.omega, settings, shard, progress, sink)
}

/// The lines of `shard` (all for `None`) among `lines`, each up the frequencies of `omega`, in
/// parallel, handed to `sink` in order.
fn run_lines<E>(
    lines: &[LineScene],
    omega: &Axis,
    settings: &MapSettings,
    shard: Option<Shard>,
    progress: &Progress,
    mut sink: impl FnMut(MapLine) -> Result<(), E>,
) -> Result<(), StreamError<E>> {
    let omegas = omega.values();
    let range = shard.map_or(0..lines.len(), |s| s.range(lines.len()));
    for_each_ordered(
        &lines[range],
        Grain::Uneven,
        progress,
        |l| line(&l.scene, l.x, l.y, &omegas, settings),
        |l| sink(l).map_err(StreamError::Sink),
    )
}

/// A failure of [`stream_any`].
#[derive(Debug, Error)]
pub enum StreamError<E> {
    /// The grid or the scene.
    #[error(transparent)]
    Map(MapError),
    /// The sink.
    #[error("{0}")]
    Sink(E),
}

impl Map {
    /// Computes the map of `scene` over `grid` (see [`stream`]) and keeps every line.
    ///
    /// # Errors
    /// A grid out of range, or a scene without stops.
    pub fn run(
        scene: &Scene,
        grid: MapGrid,
        settings: &MapSettings,
        progress: &Progress,
    ) -> Result<Map, MapError> {
        let mut lines = Vec::new();
        stream(scene, &grid, settings, progress, |l| {
            lines.push(l);
            Ok::<(), std::convert::Infallible>(())
        })
        .map_err(|e| match e {
            StreamError::Map(e) => e,
            StreamError::Sink(never) => match never {},
        })?;
        Ok(Map {
            scene: scene.clone(),
            grid,
            settings: settings.clone(),
            lines,
        })
    }

    /// Every point's row, lines in order.
    pub fn point_rows(&self) -> impl Iterator<Item = MapPointRow> + '_ {
        self.lines.iter().flat_map(MapPointRow::of_line)
    }

    /// Every line's bandwidth row.
    pub fn bandwidth_rows(&self) -> impl Iterator<Item = BandwidthRow> + '_ {
        let step = self.grid.omega.step();
        self.lines.iter().map(move |l| BandwidthRow::new(l, step))
    }
}
