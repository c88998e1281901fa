//! `rattle map`: the map over restitution, gap and frequency, streamed to a file.

use super::{check_frequency, load, Accuracy, RattleError};
use crate::api::{self, ApiError, Table};
use crate::output::{Format, OutputError};
use crate::runs::axis::Axis;
use crate::runs::map::{MapError, MapGrid, MapSettings};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
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
    /// Compute only part K of N (a contiguous block of whole (restitution, gap) lines, in
    /// the order of the output), e.g. `--shard 3/8`; join the parts of each table with
    /// `rattle merge` (CSV or JSON parts).
    #[arg(long)]
    pub shard: Option<String>,
}

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
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()
        .map_err(RattleError::Argument)?;
    if shard.is_some() && [Some(points_format), bandwidth_format].contains(&Some(Format::JsonLines))
    {
        return Err(RattleError::Argument(
            "--shard: parts must be .csv or .json (a .jsonl file has no header to say which part it is)".into(),
        ));
    }
    let settings = MapSettings::with_simulation(
        Accuracy {
            tol: args.tol,
            steady_tol: args.steady_tol,
            max_periods: args.max_periods,
            max_oscillations: super::default_max_oscillations(),
        }
        .options()?,
    );
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
    let lines = shard.map_or(grid.lines(), |s| s.range(grid.lines()).len());
    let points = create(&args.out)?;
    let bandwidth = match (&args.bandwidth_out, bandwidth_format) {
        (Some(path), Some(format)) => Some((format, create(path)?)),
        _ => None,
    };
    let progress = Progress::new("map lines", lines, true);
    api::map(
        &scene,
        &grid,
        &settings,
        shard,
        (points_format, points),
        bandwidth,
        &progress,
    )
    .map_err(|e| match e {
        ApiError::Write {
            table: Table::Points,
            source,
        } => io(&args.out)(source),
        ApiError::Write {
            table: Table::Bandwidth,
            source,
        } => io(args.bandwidth_out.as_deref().unwrap_or(Path::new("")))(source),
        e => e.into(),
    })?;
    let part = shard.map_or(String::new(), |s| {
        format!(", part {}/{}: {lines} lines", s.index, s.count)
    });
    let mut out = format!(
        "wrote {} ({} points: {} restitutions × {} gaps × {} frequencies{part})\n",
        args.out.display(),
        grid.points(),
        args.restitutions,
        args.gaps,
        args.points
    );
    if let Some(path) = &args.bandwidth_out {
        out.push_str(&format!("wrote {} ({lines} lines)\n", path.display()));
    }
    Ok(out)
}
