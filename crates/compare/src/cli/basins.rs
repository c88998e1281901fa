//! `rattle basins`: a grid of starts at rest, each coloured by the attractor it reaches.

use super::{check_frequency, check_omega, load_unit, RattleError};
use crate::api::{self, ApiError};
use crate::output::{Format, OutputError};
use crate::runs::basins::{basin_options, BasinGrid};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
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
    /// Smallest outer displacement at the start, m.
    #[arg(long, default_value_t = -2.0, allow_hyphen_values = true)]
    pub outer_min: f64,
    /// Largest outer displacement at the start, m.
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    pub outer_max: f64,
    /// Smallest inner displacement at the start, m.
    #[arg(long, default_value_t = -2.0, allow_hyphen_values = true)]
    pub inner_min: f64,
    /// Largest inner displacement at the start, m.
    #[arg(long, default_value_t = 2.0, allow_hyphen_values = true)]
    pub inner_max: f64,
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
    let grid = BasinGrid::new(
        (args.outer_min, args.outer_max),
        (args.inner_min, args.inner_max),
        args.points,
    )
    .map_err(|e| RattleError::Argument(e.to_string()))?;
    let scene = load_unit(&args.scene, "rattle basins")?;
    check_frequency(&scene, "--omega", omega)?;
    let starts = shard.map_or(grid.starts(), |s| s.range(grid.starts()).len());
    let progress = Progress::new("basins", starts, true);
    let io = |source| {
        RattleError::Output(OutputError::Io {
            path: args.out.clone(),
            source,
        })
    };
    let file = std::fs::File::create(&args.out).map_err(io)?;
    let b = api::basins(
        &scene,
        omega,
        grid,
        &basin_options(),
        shard,
        (format, std::io::BufWriter::new(file)),
        &progress,
    )
    .map_err(|e| match e {
        ApiError::Write { source, .. } => io(source),
        e => e.into(),
    })?;
    let part = shard.map_or(String::new(), |s| {
        format!(" (part {}/{})", s.index, s.count)
    });
    let mut out = format!(
        "scene {} at ω = {omega} rad/s{part}: {} starts, {} attractors\n",
        scene.name,
        b.cells.len(),
        b.attractors.len()
    );
    for (k, (a, n)) in b.attractors.iter().zip(&b.counts).enumerate() {
        let _ = writeln!(out, "{k}: {} — {n} starts", a.words());
    }
    Ok(out)
}
