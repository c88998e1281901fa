//! `rattle basins`: a grid of starts at rest, each coloured by the attractor it reaches.

use super::{check_frequency, check_omega, load_unit, RattleError};
use crate::output::{finite, table_row, write_table, Format, Header};
use crate::runs::axis::Axis;
use crate::runs::basins::{basin_options, basins, BasinGrid, Basins};
use crate::runs::parallel::Progress;
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
}

table_row! {
    /// One start of a basins grid.
    pub struct BasinRow {
        /// Outer displacement at the start, m.
        pub outer_start: Option<f64>,
        /// Inner displacement at the start, m.
        pub inner_start: Option<f64>,
        /// The attractor's number (first appearance in grid order).
        pub attractor: usize,
        /// The attractor in words.
        pub attractor_words: String,
        /// `X_o` of the motion reached, m.
        pub outer_amplitude: Option<f64>,
        /// Forcing periods run.
        pub periods_run: u64,
    }
}

/// The rows of `basins`, in grid order.
pub fn rows(basins: &Basins) -> impl Iterator<Item = BasinRow> + '_ {
    basins.cells.iter().map(|c| BasinRow {
        outer_start: finite(c.outer),
        inner_start: finite(c.inner),
        attractor: c.attractor,
        attractor_words: basins.attractors[c.attractor].words(),
        outer_amplitude: finite(c.outer_amplitude),
        periods_run: c.periods_run,
    })
}

fn axis(name: &str, min: f64, max: f64, count: usize) -> Result<Axis, RattleError> {
    if !(min.is_finite() && max.is_finite() && min <= max) {
        return Err(RattleError::Argument(format!(
            "--{name}-min = {min}, --{name}-max = {max}: must be finite with min ≤ max"
        )));
    }
    Ok(Axis::new(min, max, count))
}

/// Runs `rattle basins`.
///
/// # Errors
/// Bad arguments, scene or output path.
pub fn run(args: BasinsArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.omega)?;
    if args.points == 0 {
        return Err(RattleError::Argument("--points must be ≥ 1".into()));
    }
    let format = Format::of(&args.out, "--out")?;
    let grid = BasinGrid {
        outer: axis("outer", args.outer_min, args.outer_max, args.points)?,
        inner: axis("inner", args.inner_min, args.inner_max, args.points)?,
    };
    let scene = load_unit(&args.scene, "rattle basins")?;
    check_frequency(&scene, "--omega", omega)?;
    let progress = Progress::new("basins", args.points * args.points, true);
    let b = basins(&scene, omega, grid, &basin_options(), &progress);
    let mut header = Header::default();
    header.push("scene", &scene);
    header.push("omega", &omega);
    write_table(&args.out, format, &header, rows(&b))?;
    let mut out = format!(
        "scene {} at ω = {omega} rad/s: {} starts, {} attractors\n",
        scene.name,
        b.cells.len(),
        b.attractors.len()
    );
    for (k, (a, n)) in b.attractors.iter().zip(&b.counts).enumerate() {
        let _ = writeln!(out, "{k}: {} — {n} starts", a.words());
    }
    Ok(out)
}
