//! A map's tables: one row per point and one per line's bandwidth, their columns named after
//! the map's axes ([`MapColumns`]), the JSON header that records the axes, and the writer of
//! both tables, whole or one part of a sharded map.

use super::grid::{AnyMapGrid, MapAxes, MapGrid};
use super::line::MapLine;
use super::{run_lines, MapError, MapSettings, StreamError};
use crate::output::{
    finite, number_list, table_row, writer_with_columns, Format, Header, Renamed, TableWriter,
};
use crate::runs::axis::Axis;
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::scene::parameter::AnyParameter;
use crate::scene::simulator::Regime;
use crate::scene::{AnyScene, Scene};
use rattle_event_driven::Regime as LyapunovRegime;
use serde::Serialize;
use std::io::Write;
use thiserror::Error;

table_row! {
    /// One point of a map. The columns are named for the map over restitution and gap; a map
    /// over two parameters writes the first two as `x` and `y`, and a structure's map writes
    /// `simulated_cell_outer_amplitudes` as `simulated_body_amplitudes` ([`MapColumns`]).
    pub struct MapPointRow {
        /// Restitution `e` (column `x` on a map over two parameters: the x axis's value).
        pub restitution: Option<f64>,
        /// `Δ/u_g` (column `y` on a map over two parameters: the y axis's value).
        pub gap_over_base_amplitude: Option<f64>,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// Simulated regime (empty when the simulation failed).
        pub simulated_regime: Option<&'static str>,
        /// Least period of a periodic motion, forcing periods.
        pub simulated_period: Option<u32>,
        /// Impacts per forcing period over the final cycle (of a chain or a structure: all
        /// pairs').
        pub simulated_impacts_per_period: Option<f64>,
        /// Impacts per forcing period of each contact pair, from the base out (of a structure:
        /// each stop, in file order): a list, `;`-separated ([`number_list`]).
        pub simulated_pair_impacts_per_period: Option<String>,
        /// Simulated `X_o`, m (of a chain: the last cell's; of a structure: the observed
        /// body's).
        pub simulated_outer_amplitude: Option<f64>,
        /// Simulated `max|u_o,j|` of every cell, from the base out, m: a list, `;`-separated
        /// ([`number_list`]). On a structure, column `simulated_body_amplitudes`: `max|u|` of
        /// every body, in the scene's order.
        pub simulated_cell_outer_amplitudes: Option<String>,
        /// Simulated `T`, dB (empty without a moving base).
        pub simulated_transmittance_db: Option<f64>,
        /// Why the simulation ended.
        pub stopped_by: Option<&'static str>,
        /// Forcing periods simulated at this frequency.
        pub periods_run: u64,
        /// Attracting analytic candidates.
        pub analytic_candidates: usize,
        /// The predicted `T`, dB (largest over the attracting candidates).
        pub analytic_transmittance_db: Option<f64>,
        /// Whether the simulated motion is one of the candidates.
        pub analytic_match: bool,
        /// Where the simulation started: `rest` or `previous-frequency`.
        pub continued_from: &'static str,
        /// A failure of either solver.
        pub error: Option<String>,
        /// The largest Lyapunov exponent of a point that did not repeat, 1/s.
        pub largest_exponent: Option<f64>,
        /// Its regime: `chaotic`, `quasi-periodic` or `unsettled`.
        pub lyapunov_regime: Option<&'static str>,
    }
}

impl MapPointRow {
    /// The rows of one line, by ascending frequency.
    pub fn of_line(line: &MapLine) -> impl Iterator<Item = MapPointRow> + '_ {
        line.points
            .iter()
            .enumerate()
            .map(move |(i, p)| MapPointRow {
                restitution: finite(line.x),
                gap_over_base_amplitude: finite(line.y),
                omega: finite(p.omega),
                simulated_regime: p.regime.map(Regime::name),
                simulated_period: p.period,
                simulated_impacts_per_period: finite(p.impacts_per_period),
                simulated_pair_impacts_per_period: number_list(&p.pair_impacts_per_period),
                simulated_outer_amplitude: finite(p.outer_amplitude),
                simulated_cell_outer_amplitudes: number_list(&p.amplitudes),
                simulated_transmittance_db: p.transmittance_db.and_then(finite),
                stopped_by: (!p.stopped_by.is_empty()).then_some(p.stopped_by),
                periods_run: p.periods_run,
                analytic_candidates: p.analytic_candidates,
                analytic_transmittance_db: p.analytic_transmittance_db.and_then(finite),
                analytic_match: p.analytic_match,
                continued_from: if i == 0 || line.points[i - 1].regime.is_none() {
                    "rest"
                } else {
                    "previous-frequency"
                },
                error: p.error.clone(),
                largest_exponent: p.largest_exponent.and_then(finite),
                lyapunov_regime: p.lyapunov_regime.map(LyapunovRegime::name),
            })
    }
}

table_row! {
    /// The attenuation of one line of a map. The columns are named for the map over
    /// restitution and gap; a map over two parameters writes the first two as `x` and `y`
    /// ([`MapColumns`]).
    pub struct BandwidthRow {
        /// Restitution `e` (column `x` on a map over two parameters).
        pub restitution: Option<f64>,
        /// `Δ/u_g` (column `y` on a map over two parameters).
        pub gap_over_base_amplitude: Option<f64>,
        /// Simulated bandwidth, rad/s.
        pub simulated_bandwidth: Option<f64>,
        /// First simulated frequency with `T < 0 dB`.
        pub simulated_first_band_start: Option<f64>,
        /// Simulated bands, `from-to;…` (rad/s).
        pub simulated_bands: String,
        /// Simulated samples with `T < 0 dB`.
        pub simulated_attenuating_points: usize,
        /// Simulated samples with a value.
        pub simulated_valued_points: usize,
        /// Predicted bandwidth, rad/s.
        pub analytic_bandwidth: Option<f64>,
        /// First predicted frequency with `T < 0 dB`.
        pub analytic_first_band_start: Option<f64>,
        /// Predicted bands, `from-to;…` (rad/s).
        pub analytic_bands: String,
        /// Predicted samples with `T < 0 dB`.
        pub analytic_attenuating_points: usize,
        /// Samples with a prediction.
        pub analytic_valued_points: usize,
        /// Points not settled (irregular, no dissipation, failed).
        pub unsettled_points: usize,
        /// Points on the line.
        pub points: usize,
    }
}

impl BandwidthRow {
    /// The row of `line`, frequencies `step` apart.
    pub fn new(line: &MapLine, step: f64) -> BandwidthRow {
        let s = line.simulated_bandwidth(step);
        let a = line.analytic_bandwidth(step);
        let unsettled = line
            .points
            .iter()
            .filter(|p| {
                matches!(
                    p.regime,
                    None | Some(Regime::Irregular | Regime::NoDissipation)
                )
            })
            .count();
        BandwidthRow {
            restitution: finite(line.x),
            gap_over_base_amplitude: finite(line.y),
            simulated_bandwidth: finite(s.bandwidth),
            simulated_first_band_start: s.first_band_start.and_then(finite),
            simulated_bands: bands_text(&s.bands),
            simulated_attenuating_points: s.attenuating_points,
            simulated_valued_points: s.valued_points,
            analytic_bandwidth: finite(a.bandwidth),
            analytic_first_band_start: a.first_band_start.and_then(finite),
            analytic_bands: bands_text(&a.bands),
            analytic_attenuating_points: a.attenuating_points,
            analytic_valued_points: a.valued_points,
            unsettled_points: unsettled,
            points: line.points.len(),
        }
    }
}

/// Bands as text: `1.5-2.2;2.9-inf` (rad/s), empty when there is none.
pub fn bands_text(bands: &[(f64, f64)]) -> String {
    bands
        .iter()
        .map(|(a, b)| {
            if b.is_infinite() {
                format!("{a}-inf")
            } else {
                format!("{a}-{b}")
            }
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// The names of a map's columns that depend on what it maps, the same in CSV, JSON and JSON
/// Lines: the axes' values are `restitution` and `gap_over_base_amplitude` on the default
/// axes, `x` and `y` on two parameters (whose paths the JSON header's `grid` records, so that
/// every map loads under the same names whatever its parameters); a structure's list of
/// amplitudes is `simulated_body_amplitudes` (every body's, as a structure's sweep names it),
/// a unit's or chain's `simulated_cell_outer_amplitudes`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MapColumns {
    /// Each column of [`MapPointRow`] and [`BandwidthRow`] named otherwise, as `(from, to)`.
    pub renames: &'static [(&'static str, &'static str)],
}

impl MapColumns {
    /// The map over restitution and gap: the rows' own names.
    pub const STOPS: MapColumns = MapColumns { renames: &[] };
    /// A unit's or chain's map over two parameters.
    pub const PARAMETERS: MapColumns = MapColumns {
        renames: &[("restitution", "x"), ("gap_over_base_amplitude", "y")],
    };
    /// A structure's map over two parameters.
    pub const STRUCTURE: MapColumns = MapColumns {
        renames: &[
            ("restitution", "x"),
            ("gap_over_base_amplitude", "y"),
            (
                "simulated_cell_outer_amplitudes",
                "simulated_body_amplitudes",
            ),
        ],
    };

    /// The columns of a map over `axes` of `scene`.
    pub fn of(axes: &MapAxes, scene: &AnyScene) -> MapColumns {
        match (axes, scene) {
            (MapAxes::Stops, _) => MapColumns::STOPS,
            (MapAxes::Parameters { .. }, AnyScene::Cells(_)) => MapColumns::PARAMETERS,
            (MapAxes::Parameters { .. }, AnyScene::Structure(_)) => MapColumns::STRUCTURE,
        }
    }

    /// The points table's columns, in order.
    pub fn points(&self) -> Vec<&'static str> {
        Renamed::<MapPointRow>::columns(self.renames)
    }

    /// The bandwidth table's columns, in order.
    pub fn bandwidth(&self) -> Vec<&'static str> {
        Renamed::<BandwidthRow>::columns(self.renames)
    }
}

/// An axis as written in a map's header.
#[derive(Serialize)]
struct AxisRecord {
    min: Option<f64>,
    max: Option<f64>,
    count: usize,
}

impl From<&Axis> for AxisRecord {
    fn from(a: &Axis) -> Self {
        AxisRecord {
            min: finite(a.min),
            max: finite(a.max),
            count: a.count,
        }
    }
}

/// A parameter's axis as written in a map's header: its JSON path and its values.
#[derive(Serialize)]
struct ParameterAxisRecord {
    path: String,
    min: Option<f64>,
    max: Option<f64>,
    count: usize,
}

impl ParameterAxisRecord {
    fn new(parameter: &AnyParameter, a: &Axis) -> Self {
        ParameterAxisRecord {
            path: parameter.to_string(),
            min: finite(a.min),
            max: finite(a.max),
            count: a.count,
        }
    }
}

/// What a map was computed with, as written in its header.
#[derive(Serialize)]
struct SettingsRecord {
    frequency_order: &'static str,
    periodicity_tolerance: f64,
    max_periods: u64,
    max_period_multiplicity: u32,
    root_tolerance: f64,
    match_tolerance: f64,
}

/// The header of the JSON tables of the map over restitution and gap ([`any_header`] on its
/// axes).
pub fn header(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    counted: &str,
    count: usize,
    shard: Option<Shard>,
) -> Header {
    any_header(
        &AnyScene::Cells(scene.clone()),
        &AnyMapGrid::from(*grid),
        settings,
        counted,
        count,
        shard,
    )
}

/// The header of a map's JSON tables: the scene (of a structure, also `form`, its `bodies`
/// and the `observed` body), its `effects` (of a unit or chain), the `grid` (on the default
/// axes `restitution`, `gap_over_base_amplitude` and `omega`; on two parameters `x` and `y`,
/// each with its `path`, and `omega`), the settings, `count` rows of the whole map under the
/// key `counted` (`points` or `lines`) and, for a part, which shard it is.
pub fn any_header(
    scene: &AnyScene,
    grid: &AnyMapGrid,
    settings: &MapSettings,
    counted: &str,
    count: usize,
    shard: Option<Shard>,
) -> Header {
    #[derive(Serialize)]
    struct StopsGridRecord {
        restitution: AxisRecord,
        gap_over_base_amplitude: AxisRecord,
        omega: AxisRecord,
    }
    #[derive(Serialize)]
    struct ParametersGridRecord {
        x: ParameterAxisRecord,
        y: ParameterAxisRecord,
        omega: AxisRecord,
    }
    let mut h = Header::default();
    match scene {
        AnyScene::Cells(cells) => {
            h.push("scene", cells);
            h.push("effects", &cells.effect_names());
        }
        AnyScene::Structure(form) => {
            h.push("scene", &form.scene);
            h.push("form", &"structure");
            h.push("bodies", &form.structure.names);
            h.push("observed", &form.structure.names[form.structure.observe]);
        }
    }
    match grid.axes {
        MapAxes::Stops => h.push(
            "grid",
            &StopsGridRecord {
                restitution: (&grid.x).into(),
                gap_over_base_amplitude: (&grid.y).into(),
                omega: (&grid.omega).into(),
            },
        ),
        MapAxes::Parameters { x, y } => h.push(
            "grid",
            &ParametersGridRecord {
                x: ParameterAxisRecord::new(&x, &grid.x),
                y: ParameterAxisRecord::new(&y, &grid.y),
                omega: (&grid.omega).into(),
            },
        ),
    }
    let sim = &settings.simulation;
    h.push(
        "settings",
        &SettingsRecord {
            frequency_order:
                "ascending, each frequency started from the previous one's final state",
            periodicity_tolerance: sim.periodicity_tolerance,
            max_periods: sim.max_periods,
            max_period_multiplicity: sim.max_period_multiplicity,
            root_tolerance: sim.root_tolerance,
            match_tolerance: settings.match_tolerance,
        },
    );
    h.push(counted, &count);
    if let Some(s) = shard {
        h.push("shard", &s);
    }
    h
}

/// A failure of [`write_map`]; each names the table it concerns.
#[derive(Debug, Error)]
pub enum WriteMapError {
    /// The grid or the scene (nothing was computed).
    #[error(transparent)]
    Map(MapError),
    /// The points table could not be written.
    #[error("{0}")]
    Points(std::io::Error),
    /// The bandwidth table could not be written.
    #[error("{0}")]
    Bandwidth(std::io::Error),
}

/// [`write_any_map`] of the map over restitution and gap.
///
/// # Errors
/// As [`write_any_map`].
pub fn write_map<P: Write, B: Write>(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    points: (Format, P),
    bandwidth: Option<(Format, B)>,
    progress: &Progress,
) -> Result<(), WriteMapError> {
    write_any_map(
        &AnyScene::Cells(scene.clone()),
        &AnyMapGrid::from(*grid),
        settings,
        shard,
        points,
        bandwidth,
        progress,
    )
}

/// Computes the map (or one part of it, [`super::stream_any`]) and writes its points to `points`,
/// one row per point as each block of lines is done, and, if given, each line's bandwidth to
/// `bandwidth` at the end: the tables `rattle map --out … --bandwidth-out …` writes, their
/// columns named by [`MapColumns`], with the part named in a JSON header's `shard` or a CSV
/// part's first line, `# shard K/N of P points` (`L lines` for the bandwidth), so that
/// [`crate::runs::shard::merge`] joins the parts into exactly the whole map's tables.
///
/// # Errors
/// [`WriteMapError`]: the grid or scene (before anything is computed or written), or the
/// first failure to write either table.
pub fn write_any_map<P: Write, B: Write>(
    scene: &AnyScene,
    grid: &AnyMapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    points: (Format, P),
    bandwidth: Option<(Format, B)>,
    progress: &Progress,
) -> Result<(), WriteMapError> {
    let lines = grid.line_scenes(scene).map_err(WriteMapError::Map)?;
    let columns = MapColumns::of(&grid.axes, scene);
    let renames = columns.renames;
    let preamble = |total: usize, unit: &str| shard.map(|s| s.csv_preamble_of(total, unit));
    let mut table: Box<dyn TableWriter<Renamed<MapPointRow>>> = writer_with_columns(
        points.0,
        points.1,
        &any_header(scene, grid, settings, "points", grid.points(), shard),
        preamble(grid.points(), "points").as_deref(),
        &columns.points(),
    )
    .map_err(WriteMapError::Points)?;
    let step = grid.omega.step();
    let mut bandwidth_rows = Vec::new();
    run_lines(&lines, &grid.omega, settings, shard, progress, |line| {
        for row in MapPointRow::of_line(&line) {
            table.row(&Renamed { row, renames })?;
        }
        if bandwidth.is_some() {
            bandwidth_rows.push(BandwidthRow::new(&line, step));
        }
        Ok(())
    })
    .map_err(|e| match e {
        StreamError::Map(e) => WriteMapError::Map(e),
        StreamError::Sink(e) => WriteMapError::Points(e),
    })?;
    table.finish().map_err(WriteMapError::Points)?;
    if let Some((format, out)) = bandwidth {
        let mut table: Box<dyn TableWriter<Renamed<BandwidthRow>>> = writer_with_columns(
            format,
            out,
            &any_header(scene, grid, settings, "lines", grid.lines(), shard),
            preamble(grid.lines(), "lines").as_deref(),
            &columns.bandwidth(),
        )
        .map_err(WriteMapError::Bandwidth)?;
        for row in bandwidth_rows {
            table
                .row(&Renamed { row, renames })
                .map_err(WriteMapError::Bandwidth)?;
        }
        table.finish().map_err(WriteMapError::Bandwidth)?;
    }
    Ok(())
}
