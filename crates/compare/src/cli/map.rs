//! `rattle map`: the map over restitution, gap and frequency, streamed to a file.

use super::{check_frequency, load, Accuracy, RattleError};
use crate::output::{writer, Format, OutputError, TableWriter};
use crate::runs::axis::Axis;
use crate::runs::map::{
    header, stream, BandwidthRow, MapError, MapGrid, MapPointRow, MapSettings, StreamError,
};
use crate::runs::parallel::Progress;
use clap::Args;
use rattle_event_driven::SimulationOptions;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Arguments of `rattle map`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// Scene file (JSON). Omit for the built-in paper scene; its gap and restitution are replaced
    /// by the map's.
    pub scene: Option<PathBuf>,
    /// Lowest restitution, in [0, 1].
    #[arg(long, default_value_t = 0.0)]
    pub restitution_min: f64,
    /// Highest restitution, in [restitution-min, 1].
    #[arg(long, default_value_t = 1.0)]
    pub restitution_max: f64,
    /// Number of restitutions, evenly spaced, ends included (≥ 1; 1: restitution-min alone).
    #[arg(long, default_value_t = 40)]
    pub restitutions: usize,
    /// Smallest gap over base amplitude Δ/u_g (finite, > 0).
    #[arg(long, default_value_t = 0.05)]
    pub gap_min: f64,
    /// Largest Δ/u_g (finite, ≥ gap-min).
    #[arg(long, default_value_t = 1.0)]
    pub gap_max: f64,
    /// Number of gaps, evenly spaced, ends included (≥ 1).
    #[arg(long, default_value_t = 40)]
    pub gaps: usize,
    /// Lowest angular frequency, rad/s (finite, > 0).
    #[arg(long, default_value_t = 0.1)]
    pub omega_min: f64,
    /// Highest angular frequency, rad/s (finite, ≥ omega-min).
    #[arg(long, default_value_t = 4.0)]
    pub omega_max: f64,
    /// Number of frequencies per line, evenly spaced, ends included (≥ 1).
    #[arg(long, default_value_t = 400)]
    pub points: usize,
    /// Every point: `.csv`, `.json` or `.jsonl`, by extension; written line by line as it runs.
    #[arg(long)]
    pub out: PathBuf,
    /// The bandwidth of every (e, Δ/u_g) line: `.csv`, `.json` or `.jsonl`, by extension.
    #[arg(long)]
    pub bandwidth_out: Option<PathBuf>,
    /// Relative tolerance of contact times, in [1e-15, 1e-2].
    #[arg(long, default_value_t = SimulationOptions::default().root_tolerance)]
    pub tol: f64,
    /// Relative tolerance of the periodicity test, in [1e-14, 1e-2] (looser than a sweep's:
    /// a map needs the regime and the amplitude, not the last digits).
    #[arg(long, default_value_t = crate::runs::map::MAP_PERIODICITY_TOLERANCE)]
    pub steady_tol: f64,
    /// Cap on forcing periods per point (a point not periodic by then is `irregular`).
    #[arg(long, default_value_t = crate::runs::map::MAP_MAX_PERIODS)]
    pub max_periods: u64,
}

/// A table file being written.
type Table = Box<dyn TableWriter<MapPointRow>>;

fn create(path: &Path) -> Result<BufWriter<std::fs::File>, RattleError> {
    let file = std::fs::File::create(path).map_err(|source| OutputError::Io {
        path: path.to_owned(),
        source,
    })?;
    Ok(BufWriter::new(file))
}

/// Runs `rattle map`.
///
/// # Errors
/// Bad arguments or scene (a grid out of range, no stops); an output that cannot be written.
pub fn run(args: MapArgs) -> Result<String, RattleError> {
    let grid = MapGrid {
        restitution: Axis::new(
            args.restitution_min,
            args.restitution_max,
            args.restitutions,
        ),
        gap_over_base_amplitude: Axis::new(args.gap_min, args.gap_max, args.gaps),
        omega: Axis::new(args.omega_min, args.omega_max, args.points),
    };
    grid.validate()
        .map_err(|e| RattleError::Argument(e.to_string()))?;
    let points_format = Format::of(&args.out, "--out")?;
    let bandwidth_format = args
        .bandwidth_out
        .as_deref()
        .map(|p| Format::of(p, "--bandwidth-out"))
        .transpose()?;
    let defaults = MapSettings::default();
    let simulation = SimulationOptions {
        polish: defaults.simulation.polish,
        ..Accuracy {
            tol: args.tol,
            steady_tol: args.steady_tol,
            max_periods: args.max_periods,
            max_oscillations: super::default_max_oscillations(),
        }
        .options()?
    };
    let settings = MapSettings {
        simulation,
        ..defaults
    };
    let scene = load(&args.scene)?;
    if scene.stops.is_none() {
        return Err(RattleError::Argument(MapError::NoStops.to_string()));
    }
    check_frequency(&scene, "--omega-min", args.omega_min)?;
    check_frequency(&scene, "--omega-max", args.omega_max)?;
    let io = |path: &Path| {
        let path = path.to_owned();
        move |source| RattleError::Output(OutputError::Io { path, source })
    };
    let lines = grid.restitution.count * grid.gap_over_base_amplitude.count;
    let mut points: Table = writer(
        points_format,
        create(&args.out)?,
        &header(&scene, &grid, &settings, "points", grid.points()),
        None,
    )
    .map_err(io(&args.out))?;
    let step = grid.omega.step();
    let mut bandwidth_rows = Vec::new();
    let progress = Progress::new("map lines", lines, true);
    stream(&scene, &grid, &settings, &progress, |line| {
        for row in MapPointRow::of_line(&line) {
            points.row(&row)?;
        }
        if bandwidth_format.is_some() {
            bandwidth_rows.push(BandwidthRow::new(&line, step));
        }
        Ok(())
    })
    .map_err(|e| match e {
        StreamError::Map(e) => RattleError::Argument(e.to_string()),
        StreamError::Sink(source) => io(&args.out)(source),
    })?;
    points.finish().map_err(io(&args.out))?;
    let mut out = format!(
        "wrote {} ({} points: {} restitutions × {} gaps × {} frequencies)\n",
        args.out.display(),
        grid.points(),
        args.restitutions,
        args.gaps,
        args.points
    );
    if let (Some(path), Some(format)) = (&args.bandwidth_out, bandwidth_format) {
        let mut table: Box<dyn TableWriter<BandwidthRow>> = writer(
            format,
            create(path)?,
            &header(&scene, &grid, &settings, "lines", lines),
            None,
        )
        .map_err(io(path))?;
        for row in &bandwidth_rows {
            table.row(row).map_err(io(path))?;
        }
        table.finish().map_err(io(path))?;
        out.push_str(&format!("wrote {} ({lines} lines)\n", path.display()));
    }
    Ok(out)
}
