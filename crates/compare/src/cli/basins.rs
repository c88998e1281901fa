//! `rattle basins`: a grid of starts over two coordinates of a scene (the rest at rest), each
//! coloured by the attractor it reaches.

use super::{check_frequency, check_omega, load_any, RattleError};
use crate::api::{self, ApiError};
use crate::output::{Format, OutputError};
use crate::runs::basins::{
    basin_options, body_names, coordinate_names, BasinGrid, BasinPlane, Basins,
};
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
    let default_plane = [
        args.outer_min,
        args.outer_max,
        args.inner_min,
        args.inner_max,
    ]
    .iter()
    .any(Option::is_some);
    let named = args.x.is_some()
        || args.y.is_some()
        || [args.x_min, args.x_max, args.y_min, args.y_max]
            .iter()
            .any(Option::is_some);
    if default_plane && named {
        return Err(RattleError::Argument(
            "--outer-min/--outer-max/--inner-min/--inner-max set the unit's default plane \
             (u:outer × u:inner); with --x/--y give the ranges as --x-min/--x-max/--y-min/--y-max"
                .into(),
        ));
    }
    let unit = matches!(&scene, AnyScene::Cells(s) if !s.is_chain());
    let coordinates = || coordinate_names(&body_names(&scene)).join(", ");
    if default_plane && !unit {
        return Err(RattleError::Argument(format!(
            "--outer-min/--outer-max/--inner-min/--inner-max set the unit's default plane; on \
             a chain or a structure name the axes with --x and --y (coordinates: {})",
            coordinates()
        )));
    }
    let or = |value: Option<f64>, default: f64| value.unwrap_or(default);
    let starts_of = |points: usize| shard.map_or(points, |s| s.range(points).len());
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
    let b: Basins = match &scene {
        AnyScene::Cells(unit) if !named && !unit.is_chain() => {
            let grid = BasinGrid::new(
                (or(args.outer_min, -2.0), or(args.outer_max, 2.0)),
                (or(args.inner_min, -2.0), or(args.inner_max, 2.0)),
                args.points,
            )
            .map_err(|e| RattleError::Argument(e.to_string()))?;
            check_frequency(unit, "--omega", omega)?;
            let progress = Progress::new("basins", starts_of(grid.starts()), true);
            let file = std::fs::File::create(&args.out).map_err(io)?;
            api::basins(
                unit,
                omega,
                grid,
                &basin_options(),
                shard,
                (format, std::io::BufWriter::new(file)),
                &progress,
            )
            .map_err(written)?
        }
        _ => {
            let axis =
                |flag: &str, given: &Option<String>, default: &'static str| match (given, unit) {
                    (Some(name), _) => Ok(name.clone()),
                    (None, true) => Ok(default.to_owned()),
                    (None, false) => Err(RattleError::Argument(format!(
                        "{flag} is required on a chain or a structure: one of {}",
                        coordinates()
                    ))),
                };
            let x = axis("--x", &args.x, "u:outer")?;
            let y = axis("--y", &args.y, "u:inner")?;
            let plane = BasinPlane::new(
                &scene,
                (&x, (or(args.x_min, -2.0), or(args.x_max, 2.0))),
                (&y, (or(args.y_min, -2.0), or(args.y_max, 2.0))),
                args.points,
            )
            .map_err(|e| RattleError::Argument(e.to_string()))?;
            api::check_frequency(&scene, "--omega", omega)?;
            let progress = Progress::new("basins", starts_of(plane.grid.starts()), true);
            let file = std::fs::File::create(&args.out).map_err(io)?;
            api::plane_basins(
                &scene,
                omega,
                &plane,
                &basin_options(),
                shard,
                (format, std::io::BufWriter::new(file)),
                &progress,
            )
            .map_err(written)?
        }
    };
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
