//! `rattle map`: the map over two scene parameters (by default a unit's restitution and gap)
//! and frequency, streamed to a file.

use super::{load_any, Accuracy, RattleError};
use crate::api::{self, ApiError, Table};
use crate::output::{Format, OutputError};
use crate::runs::axis::Axis;
use crate::runs::map::{AnyMapGrid, MapAxes, MapError, MapSettings};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::scene::parameter::AnyParameter;
use crate::scene::AnyScene;
use clap::Args;
use rattle_event_driven::SimulationOptions;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

/// Values per axis when a count is not given (`--restitutions`, `--gaps`, `--x-count`,
/// `--y-count`).
pub const DEFAULT_COUNT: usize = 40;

/// Arguments of `rattle map`.
#[derive(Debug, Args)]
pub struct MapArgs {
    /// Scene file (JSON), of any form. Omit for the built-in paper scene. Without --x/--y its
    /// stops' gap and restitution are replaced by the map's.
    pub scene: Option<PathBuf>,
    /// Lowest restitution, in [0, 1] (default 0). Not with --x/--y.
    #[arg(long)]
    pub restitution_min: Option<f64>,
    /// Highest restitution, in [restitution-min, 1] (default 1). Not with --x/--y.
    #[arg(long)]
    pub restitution_max: Option<f64>,
    /// Number of restitutions, evenly spaced, ends included (≥ 1, default 40; 1:
    /// restitution-min alone). Not with --x/--y.
    #[arg(long)]
    pub restitutions: Option<usize>,
    /// Smallest gap over base amplitude Δ/u_g (finite, > 0; default 0.05). Not with --x/--y.
    #[arg(long)]
    pub gap_min: Option<f64>,
    /// Largest Δ/u_g (finite, ≥ gap-min; default 1). Not with --x/--y.
    #[arg(long)]
    pub gap_max: Option<f64>,
    /// Number of gaps, evenly spaced, ends included (≥ 1, default 40). Not with --x/--y.
    #[arg(long)]
    pub gaps: Option<usize>,
    /// The x axis's parameter, by its JSON path in the scene: `unit.inner_mass`,
    /// `chain[2].stops.gap`, `damping.outer`, … on a unit or chain,
    /// `structure.stops[0].gap_plus`, `structure.bodies[1].mass`, `forcing.forces[0].amplitude`,
    /// `forcing.base.harmonics[0].amplitude`, … on a structure. With --y; the map's columns are then `x` and `y` (the paths are in a
    /// JSON table's `grid`).
    #[arg(long, value_name = "PATH")]
    pub x: Option<String>,
    /// Lowest value of --x (within the parameter's range).
    #[arg(long, allow_hyphen_values = true)]
    pub x_min: Option<f64>,
    /// Highest value of --x (≥ x-min, within the parameter's range).
    #[arg(long, allow_hyphen_values = true)]
    pub x_max: Option<f64>,
    /// Number of values of --x, evenly spaced, ends included (≥ 1, default 40).
    #[arg(long)]
    pub x_count: Option<usize>,
    /// The y axis's parameter, by its JSON path (as --x; a different parameter). With --x.
    #[arg(long, value_name = "PATH")]
    pub y: Option<String>,
    /// Lowest value of --y (within the parameter's range).
    #[arg(long, allow_hyphen_values = true)]
    pub y_min: Option<f64>,
    /// Highest value of --y (≥ y-min, within the parameter's range).
    #[arg(long, allow_hyphen_values = true)]
    pub y_max: Option<f64>,
    /// Number of values of --y, evenly spaced, ends included (≥ 1, default 40).
    #[arg(long)]
    pub y_count: Option<usize>,
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
    /// Columns `restitution, gap_over_base_amplitude, omega, …`; with --x/--y, `x, y, omega, …`
    /// (on a structure `simulated_body_amplitudes` lists every body's amplitude).
    #[arg(long)]
    pub out: PathBuf,
    /// The bandwidth of every line (every (e, Δ/u_g), or every (x, y)): `.csv`, `.json` or
    /// `.jsonl`, by extension.
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
    /// Compute only part K of N (a contiguous block of whole lines, in the order of the
    /// output), e.g. `--shard 3/8`; join the parts of each table with `rattle merge` (CSV or
    /// JSON parts).
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

/// The two parameter axes asked for by --x and --y, before their paths are read on the scene.
struct ParameterArgs<'a> {
    x: &'a str,
    y: &'a str,
    x_axis: Axis,
    y_axis: Axis,
}

impl MapArgs {
    /// The x and y axes when --x and --y are given, after the checks of the flags alone: each
    /// path with its range, and none of the restitution and gap flags beside them.
    fn parameters(&self) -> Result<Option<ParameterArgs<'_>>, RattleError> {
        let argument = |message: String| Err(RattleError::Argument(message));
        let ranges = [
            ("--x-min", self.x_min.is_some()),
            ("--x-max", self.x_max.is_some()),
            ("--x-count", self.x_count.is_some()),
            ("--y-min", self.y_min.is_some()),
            ("--y-max", self.y_max.is_some()),
            ("--y-count", self.y_count.is_some()),
        ];
        let (x, y) = match (self.x.as_deref(), self.y.as_deref()) {
            (Some(x), Some(y)) => (x, y),
            (None, None) => {
                return match ranges.iter().find(|(_, given)| *given) {
                    Some((flag, _)) => argument(format!(
                        "{flag} is taken with --x and --y only: give both parameters' paths"
                    )),
                    None => Ok(None),
                }
            }
            (Some(_), None) | (None, Some(_)) => {
                let (given, missing) = if self.x.is_some() {
                    ("--x", "--y")
                } else {
                    ("--y", "--x")
                };
                return argument(format!(
                    "{given} is given without {missing}: a map over two parameters takes both \
                     (--x PATH --y PATH)"
                ));
            }
        };
        let stops = [
            ("--restitution-min", self.restitution_min.is_some()),
            ("--restitution-max", self.restitution_max.is_some()),
            ("--restitutions", self.restitutions.is_some()),
            ("--gap-min", self.gap_min.is_some()),
            ("--gap-max", self.gap_max.is_some()),
            ("--gaps", self.gaps.is_some()),
        ];
        if let Some((flag, _)) = stops.iter().find(|(_, given)| *given) {
            return argument(format!(
                "{flag} is not taken with --x and --y: the map's axes are then the two \
                 parameters"
            ));
        }
        let bound = |value: Option<f64>, flag: &str, axis: &str, path: &str| {
            value.ok_or_else(|| {
                RattleError::Argument(format!("{flag} is required with {axis} {path}"))
            })
        };
        Ok(Some(ParameterArgs {
            x,
            y,
            x_axis: Axis::new(
                bound(self.x_min, "--x-min", "--x", x)?,
                bound(self.x_max, "--x-max", "--x", x)?,
                self.x_count.unwrap_or(DEFAULT_COUNT),
            ),
            y_axis: Axis::new(
                bound(self.y_min, "--y-min", "--y", y)?,
                bound(self.y_max, "--y-max", "--y", y)?,
                self.y_count.unwrap_or(DEFAULT_COUNT),
            ),
        }))
    }

    fn omega(&self) -> Axis {
        Axis::new(self.omega_min, self.omega_max, self.points)
    }

    /// The grid over restitution and gap, from their flags (each at its default when not
    /// given).
    fn stops_grid(&self) -> AnyMapGrid {
        AnyMapGrid {
            axes: MapAxes::Stops,
            x: Axis::new(
                self.restitution_min.unwrap_or(0.0),
                self.restitution_max.unwrap_or(1.0),
                self.restitutions.unwrap_or(DEFAULT_COUNT),
            ),
            y: Axis::new(
                self.gap_min.unwrap_or(0.05),
                self.gap_max.unwrap_or(1.0),
                self.gaps.unwrap_or(DEFAULT_COUNT),
            ),
            omega: self.omega(),
        }
    }

    /// The grid over the two parameters of `p`, their paths read on `scene`'s form.
    fn parameters_grid(
        &self,
        scene: &AnyScene,
        p: &ParameterArgs,
    ) -> Result<AnyMapGrid, RattleError> {
        let parse = |flag: &str, path: &str| {
            AnyParameter::parse(scene, path)
                .map_err(|e| RattleError::Argument(format!("{flag}: {e}")))
        };
        Ok(AnyMapGrid {
            axes: MapAxes::Parameters {
                x: parse("--x", p.x)?,
                y: parse("--y", p.y)?,
            },
            x: p.x_axis,
            y: p.y_axis,
            omega: self.omega(),
        })
    }
}

/// The error of a grid the scene does not take, as the command reports it.
fn refused(e: MapError) -> RattleError {
    match e {
        MapError::Frequency(e) => RattleError::Frequency(e),
        e => RattleError::Argument(e.to_string()),
    }
}

/// Runs `rattle map`.
///
/// # Errors
/// Bad arguments or scene (a grid out of range, no stops, a path the scene does not have, a
/// parameter's value out of its range); an output that cannot be written.
pub fn run(args: MapArgs) -> Result<String, RattleError> {
    let parameters = args.parameters()?;
    if parameters.is_none() {
        // The default axes' ranges are known before the scene is read.
        args.stops_grid().validate().map_err(refused)?;
    }
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
    let scene = load_any(&args.scene)?;
    let grid = match &parameters {
        Some(p) => args.parameters_grid(&scene, p)?,
        None => args.stops_grid(),
    };
    grid.check(&scene).map_err(refused)?;
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
    let axes = match grid.axes {
        MapAxes::Stops => format!("{} restitutions × {} gaps", grid.x.count, grid.y.count),
        MapAxes::Parameters { x, y } => format!(
            "{} values of {x} (x) × {} of {y} (y)",
            grid.x.count, grid.y.count
        ),
    };
    let mut out = format!(
        "wrote {} ({} points: {axes} × {} frequencies{part})\n",
        args.out.display(),
        grid.points(),
        args.points
    );
    if let Some(path) = &args.bandwidth_out {
        out.push_str(&format!("wrote {} ({lines} lines)\n", path.display()));
    }
    Ok(out)
}
