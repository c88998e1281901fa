//! `rattle basins`: a grid of starts over two coordinates of a scene (the rest at rest), each
//! coloured by the attractor it reaches.

use super::{check_omega, load_any, RattleError};
use crate::api::{self, ApiError};
use crate::output::{Format, OutputError};
use crate::runs::basins::{basin_options, BasinAxes, BasinStarts, Basins};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::scene::AnyScene;
use clap::Args;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `rattle basins`.
#[derive(Debug, Args)]
pub struct BasinsArgs {
    /// Scene file (JSON). Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// Angular frequency of the base motion, rad/s (finite, > 0).
    #[arg(long, allow_hyphen_values = true)]
    pub omega: f64,
    /// The first axis's coordinate: `u:NAME` (a body's displacement) or `v:NAME` (its
    /// velocity). Bodies are named `outer`, `inner` on the unit, `outer0`, `inner0`, `outer1`, …
    /// on a chain (cells from 0 at the base), by their own names on a structure. Default on the
    /// unit: `u:outer`; required on a chain or a structure.
    #[arg(long)]
    pub x: Option<String>,
    /// The second axis's coordinate, as `--x`. Default on the unit: `u:inner`; required on a
    /// chain or a structure.
    #[arg(long)]
    pub y: Option<String>,
    /// Smallest value of the `--x` coordinate at the start, m or m/s [default: -2].
    #[arg(long, allow_hyphen_values = true)]
    pub x_min: Option<f64>,
    /// Largest value of the `--x` coordinate at the start [default: 2].
    #[arg(long, allow_hyphen_values = true)]
    pub x_max: Option<f64>,
    /// Smallest value of the `--y` coordinate at the start [default: -2].
    #[arg(long, allow_hyphen_values = true)]
    pub y_min: Option<f64>,
    /// Largest value of the `--y` coordinate at the start [default: 2].
    #[arg(long, allow_hyphen_values = true)]
    pub y_max: Option<f64>,
    /// Smallest outer displacement at the start on the unit's default plane (`u:outer ×
    /// u:inner`, without `--x`/`--y`), m [default: -2].
    #[arg(long, allow_hyphen_values = true)]
    pub outer_min: Option<f64>,
    /// Largest outer displacement at the start on the unit's default plane, m [default: 2].
    #[arg(long, allow_hyphen_values = true)]
    pub outer_max: Option<f64>,
    /// Smallest inner displacement at the start on the unit's default plane, m [default: -2].
    #[arg(long, allow_hyphen_values = true)]
    pub inner_min: Option<f64>,
    /// Largest inner displacement at the start on the unit's default plane, m [default: 2].
    #[arg(long, allow_hyphen_values = true)]
    pub inner_max: Option<f64>,
    /// Starts per side of the grid (at least 1).
    #[arg(long, default_value_t = 200)]
    pub points: usize,
    /// Where to write the grid: `.csv`, `.json` or `.jsonl`.
    #[arg(long)]
    pub out: PathBuf,
    /// Compute only part K of N (a contiguous block of the starts in grid order), e.g.
    /// `--shard 3/8`; join the parts with `rattle merge` (CSV or JSON parts), which numbers
    /// the attractors over the whole grid.
    #[arg(long)]
    pub shard: Option<String>,
}

/// Runs `rattle basins`.
///
/// # Errors
/// Bad arguments, scene or output path.
pub fn run(args: BasinsArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.omega)?;
    let format = Format::of(&args.out, "--out")?;
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()
        .map_err(RattleError::Argument)?;
    if shard.is_some() && format == Format::JsonLines {
        return Err(RattleError::Argument(
            "--shard: parts must be .csv or .json (a .jsonl file has no header to say which part it is)".into(),
        ));
    }
    let scene = load_any(&args.scene)?;
    let axes = BasinAxes {
        x: args.x.clone(),
        y: args.y.clone(),
        x_range: (args.x_min, args.x_max),
        y_range: (args.y_min, args.y_max),
        outer: (args.outer_min, args.outer_max),
        inner: (args.inner_min, args.inner_max),
        points: args.points,
    };
    let starts = axes
        .starts(&scene)
        .map_err(|e| RattleError::Argument(e.to_string()))?;
    api::check_frequency(&scene, "--omega", omega)?;
    let progress = Progress::new(
        "basins",
        shard.map_or(starts.starts(), |s| s.range(starts.starts()).len()),
        true,
    );
    let io = |source| {
        RattleError::Output(OutputError::Io {
            path: args.out.clone(),
            source,
        })
    };
    let written = |e| match e {
        ApiError::Write { source, .. } => io(source),
        e => e.into(),
    };
    let file = std::fs::File::create(&args.out).map_err(io)?;
    let out = (format, std::io::BufWriter::new(file));
    let b: Basins = match (&scene, &starts) {
        (AnyScene::Cells(unit), BasinStarts::Unit(grid)) => {
            api::basins(unit, omega, *grid, &basin_options(), shard, out, &progress)
        }
        (_, BasinStarts::Plane(plane)) => api::plane_basins(
            &scene,
            omega,
            plane,
            &basin_options(),
            shard,
            out,
            &progress,
        ),
        (AnyScene::Structure(_), BasinStarts::Unit(_)) => {
            unreachable!("the default plane is the unit's")
        }
    }
    .map_err(written)?;
    let part = shard.map_or(String::new(), |s| {
        format!(" (part {}/{})", s.index, s.count)
    });
    let mut out = format!(
        "scene {} at ω = {omega} rad/s{part}: {} starts, {} attractors\n",
        scene.name(),
        b.cells.len(),
        b.attractors.len()
    );
    for (k, (a, n)) in b.attractors.iter().zip(&b.counts).enumerate() {
        let _ = writeln!(out, "{k}: {} — {n} starts", a.words());
    }
    Ok(out)
}
