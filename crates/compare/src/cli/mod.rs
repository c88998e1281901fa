//! The `rattle` command: argument parsing, dispatch and exit codes; one module per subcommand.
//!
//! Exit codes: 0 success (including "no orbit exists"), 1 a numerical failure with an
//! explanation, 2 bad input (arguments or scene).

pub mod basins;
pub mod boundaries;
pub mod boundary;
pub mod compare;
pub mod continuation;
pub mod family;
pub mod map;
pub mod merge;
pub mod orbit;
pub mod respond;
pub mod simulate;
pub mod structure;
pub mod sweep;
pub mod transmission;

use crate::api::{ApiError, TrajectoryTables};
use crate::output::trajectory::{check_samples_per_period, ImpactRow, TrajectoryRow};
use crate::output::{write_table, Format, Header, OutputError};
use crate::scene::frequency::{FrequencyBounds, FrequencyError};
use crate::scene::{AnyScene, Scene, SceneError};
use clap::{Args, Parser, Subcommand};
use rattle_event_driven::SimulationOptions;
use std::path::PathBuf;
use thiserror::Error;

/// Steady states of vibro-impact structures, two independent ways.
#[derive(Debug, Parser)]
#[command(
    name = "rattle",
    version,
    about = "Steady states of vibro-impact structures (the impacting mass-in-mass unit, chains of it, any structure with stops), two independent ways: closed-form orbits (Nigm–Shabana) and exact event-driven simulation"
)]
pub struct Cli {
    /// What to compute.
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Analytic steady states at one frequency: the linear response and every two-impact
    /// orbit (symmetric branches and asymmetric β), with viability and Floquet stability; with
    /// --signature every orbit of an impact signature (of a chain's pairs or a structure's
    /// stops), and with --trajectory one of them sampled over its cycle.
    Orbit(orbit::OrbitArgs),
    /// The member of the two-impact family whose side-2 impact comes βT after the side-1
    /// impact: the gap Δ*(β) that admits it, its phase, viability and stability.
    Family(family::FamilyArgs),
    /// Event-driven simulation from rest until the motion is periodic (or a cap), or for
    /// exactly N periods: status, period, impacts per period, outer amplitude.
    Simulate(simulate::SimulateArgs),
    /// Both solvers on the motion the unit settles on at one frequency, whatever its impact
    /// signature: the simulator from rest with its own Newton-polished cycle, the analytic
    /// orbit of that signature solved from the simulated impact phases, and the verdict (on a
    /// chain: the analytic orbit of the cycle's impact sequence of the pairs).
    Compare(compare::CompareArgs),
    /// Pseudo-arclength continuation in ω of every orbit of an impact signature found at one
    /// frequency, through folds, with its bifurcations (fold, branch point, period doubling,
    /// Neimark–Sacker, grazing, vanishing impact) and the branches they lead onto.
    Continue(continuation::ContinueArgs),
    /// A regime boundary: the event of one kind (fold, period doubling, Neimark–Sacker,
    /// grazing, vanishing impact) nearest a frequency on the branches of a signature's orbits,
    /// followed in (ω, a scene parameter) through turning points, exact to rounding.
    Boundary(boundary::BoundaryArgs),
    /// Every regime boundary at once: each event of the continuation in ω of the motions a
    /// sweep settles on (and of the `+-` orbits), branch points included, followed in (ω, a
    /// scene parameter); the same curve reached from two events listed once.
    Boundaries(boundaries::BoundariesArgs),
    /// A frequency sweep with one solver or both, in parallel, written to a CSV, JSON or
    /// JSON Lines file as it runs; on a chain or a structure, every solver (`both`: the verdict
    /// of `compare` at every frequency); whole, or one part of it with --shard.
    Sweep(sweep::SweepArgs),
    /// Joins the parts of a sharded sweep, map or basins (`rattle sweep|map|basins …
    /// --shard K/N`) into the file the unsharded run would write, byte for byte; the parts
    /// of a sharded transmission estimate into its document (.json) or table (.csv).
    Merge(merge::MergeArgs),
    /// A map over two scene parameters and frequency (each frequency continued from the
    /// previous one, up the frequencies): by default a unit's or chain's restitution and gap,
    /// with --x and --y any two numbers of a scene of any form by their JSON paths; the
    /// simulated regime and transmittance at every point, the analytic prediction beside it,
    /// and the attenuation bandwidth of every line.
    Map(map::MapArgs),
    /// Basins of attraction at one frequency: a grid of starts over two coordinates (on the
    /// unit by default its outer and inner displacement; with --x and --y any body's
    /// displacement or velocity of a unit, a chain or a structure), the rest at rest, each run
    /// to its steady state and numbered by the attractor it reaches (signature and amplitude,
    /// or not periodic), in parallel, written to a file.
    Basins(basins::BasinsArgs),
    /// The exact response to a non-periodic signal from rest over a duration T: a record
    /// file (base displacement, or a force on one body), a tone burst, a sine sweep
    /// (continuous or stepped) or a random base motion, in place of the scene's harmonic base
    /// motion; every impact, the states at chosen times, every body's RMS and peak, the
    /// energy balance, and the uniformly sampled response written to a file.
    Respond(respond::RespondArgs),
    /// The transmissibility from the base to the observed body under random base motion,
    /// estimated by Welch's method (Hann segments, overlapped) from records from rest at one
    /// or more levels, averaged over seeds, in parallel: H1 = Sxy/Sxx with its confidence
    /// radius, the coherence and √(Syy/Sxx) at every frequency 2πj/segment at least two
    /// spacings inside the band, beside the exact
    /// linear response of the structure with its stops removed; whole, or one part of the
    /// runs with --shard.
    Transmission(transmission::TransmissionArgs),
}

/// A failure of a command, with its exit code.
#[derive(Debug, Error)]
pub enum RattleError {
    /// The scene is unreadable or invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A command-line value is out of range.
    #[error("{0}")]
    Argument(String),
    /// An output file cannot be written, or has no known format.
    #[error(transparent)]
    Output(#[from] OutputError),
    /// A forcing frequency the scene cannot be run at in bounded time.
    #[error(transparent)]
    Frequency(#[from] FrequencyError),
    /// The computation failed; the message says why.
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl From<ApiError> for RattleError {
    /// The facade's error as the command's, variant for variant (the same exit codes). A
    /// table that cannot be written is named by its table here; the commands that write
    /// tables name the file instead ([`RattleError::Output`]).
    fn from(e: ApiError) -> Self {
        match e {
            ApiError::Scene(e) => RattleError::Scene(e),
            ApiError::Frequency(e) => RattleError::Frequency(e),
            ApiError::Argument(message) => RattleError::Argument(message),
            ApiError::Numerical(message) => RattleError::Numerical(message),
            ApiError::Write { table, source } => RattleError::Output(OutputError::Io {
                path: PathBuf::from(format!("the {table} table")),
                source,
            }),
        }
    }
}

impl RattleError {
    /// 2 for bad input (and unwritable output), 1 for a numerical failure.
    pub fn exit_code(&self) -> i32 {
        match self {
            RattleError::Scene(_)
            | RattleError::Argument(_)
            | RattleError::Frequency(_)
            | RattleError::Output(_) => 2,
            RattleError::Numerical(_) => 1,
        }
    }
}

/// Runs a parsed command and returns what it prints on standard output.
///
/// # Errors
/// [`RattleError`], whose [`RattleError::exit_code`] the binary exits with.
pub fn run(cli: Cli) -> Result<String, RattleError> {
    match cli.command {
        Command::Orbit(args) => orbit::run(args),
        Command::Family(args) => family::run(args),
        Command::Simulate(args) => simulate::run(args),
        Command::Compare(args) => compare::run(args),
        Command::Continue(args) => continuation::run(args),
        Command::Boundary(args) => boundary::run(args),
        Command::Boundaries(args) => boundaries::run(args),
        Command::Sweep(args) => sweep::run(args),
        Command::Merge(args) => merge::run(args),
        Command::Map(args) => map::run(args),
        Command::Basins(args) => basins::run(args),
        Command::Respond(args) => respond::run(args),
        Command::Transmission(args) => transmission::run(args),
    }
}

/// Scene and frequency, common to the one-frequency commands.
#[derive(Debug, Args)]
pub struct Common {
    /// Scene file (JSON). Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// Angular frequency of the base motion, rad/s (finite, > 0).
    #[arg(long, allow_hyphen_values = true)]
    pub omega: f64,
    /// Print one JSON document instead of a table.
    #[arg(long)]
    pub json: bool,
}

/// Where to write a cycle's time history (`simulate`, `orbit`).
#[derive(Debug, Args)]
pub struct TrajectoryArgs {
    /// Write the cycle (`simulate`: the final cycle, or with --periods the last period;
    /// `orbit`: the orbit chosen by --signature and --orbit) sampled from the closed form to
    /// this `.csv`/`.json`/`.jsonl` file: columns `t, kind, cell, base, u_o, u_i, v_o, v_i, r`
    /// (SI units; `t` with the base at `u_g cos ωt`; a chain has one row per cell, numbered
    /// from 0 at the base, at each time), every impact as two rows (before and after). On a
    /// structure: columns `t, kind, base`, then `u_NAME` and `v_NAME` of every body and `r_K`
    /// of every stop, one row per time, the same for both commands.
    #[arg(long)]
    pub trajectory: Option<PathBuf>,
    /// Uniform samples per forcing period of --trajectory, in [1, 100000].
    #[arg(long, default_value_t = rattle_event_driven::DEFAULT_SAMPLES_PER_PERIOD, requires = "trajectory")]
    pub samples_per_period: u64,
    /// Write every impact of the sampled stretch to this file: columns `t, pair, side,
    /// relative_velocity_before, u_o, u_i, v_o_before, v_i_before` (the pair's cell's
    /// displacements and velocities). On a structure: `t, stop, side,
    /// relative_velocity_before`, then `u_NAME` and `v_NAME_before` of every body.
    #[arg(long, requires = "trajectory")]
    pub impacts: Option<PathBuf>,
}

impl TrajectoryArgs {
    /// Writes `rows` to --trajectory and `impacts` to --impacts, each if asked for.
    ///
    /// # Errors
    /// An unknown file extension, or a file that cannot be written.
    pub fn write(
        &self,
        rows: Vec<TrajectoryRow>,
        impacts: Vec<ImpactRow>,
    ) -> Result<(), RattleError> {
        if let Some(path) = &self.trajectory {
            write_table(
                path,
                Format::of(path, "--trajectory")?,
                &Header::default(),
                rows,
            )?;
        }
        if let Some(path) = &self.impacts {
            write_table(
                path,
                Format::of(path, "--impacts")?,
                &Header::default(),
                impacts,
            )?;
        }
        Ok(())
    }

    /// Writes `tables` (a unit's or a chain's rows, or a structure's named tables) to
    /// --trajectory and --impacts, each if asked for.
    ///
    /// # Errors
    /// An unknown file extension, or a file that cannot be written.
    pub fn write_tables(&self, tables: TrajectoryTables) -> Result<(), RattleError> {
        match tables {
            TrajectoryTables::Cells { rows, impacts } => self.write(rows, impacts),
            TrajectoryTables::Structure { states, impacts } => {
                if let Some(path) = &self.trajectory {
                    states.write(path, Format::of(path, "--trajectory")?)?;
                }
                if let Some(path) = &self.impacts {
                    impacts.write(path, Format::of(path, "--impacts")?)?;
                }
                Ok(())
            }
        }
    }

    /// Checks the options before anything runs.
    ///
    /// # Errors
    /// [`RattleError::Argument`] naming the option; an unknown file extension.
    pub fn check(&self) -> Result<(), RattleError> {
        check_samples_per_period(self.samples_per_period.into()).map_err(RattleError::Argument)?;
        if let Some(p) = &self.trajectory {
            crate::output::Format::of(p, "--trajectory")?;
        }
        if let Some(p) = &self.impacts {
            crate::output::Format::of(p, "--impacts")?;
        }
        Ok(())
    }
}

/// Accuracy knobs of the simulator; defaults are [`SimulationOptions::default`]'s.
#[derive(Debug, Args, Clone, Copy)]
pub struct Accuracy {
    /// Relative tolerance of contact times (the simulator's accuracy knob), in [1e-15, 1e-2].
    #[arg(long, default_value_t = SimulationOptions::default().root_tolerance)]
    pub tol: f64,
    /// Relative tolerance of the periodicity test of the steady state, in [1e-14, 1e-2].
    #[arg(long, default_value_t = SimulationOptions::default().periodicity_tolerance)]
    pub steady_tol: f64,
    /// Cap on forcing periods when running until steady.
    #[arg(long, default_value_t = SimulationOptions::default().max_periods)]
    pub max_periods: u64,
    /// Cap on free oscillations of the fastest mode when running until steady (periods ×
    /// ω_fastest/ω, at least 64 periods): bounds runs forced far below the natural
    /// frequencies; finite, > 0.
    #[arg(long, default_value_t = default_max_oscillations())]
    pub max_oscillations: f64,
}

fn default_max_oscillations() -> f64 {
    SimulationOptions::default()
        .max_oscillations
        .unwrap_or(f64::INFINITY)
}

impl Accuracy {
    /// The simulator's options, after the library's range checks
    /// ([`crate::scene::simulator::Accuracy::options`]).
    ///
    /// # Errors
    /// [`RattleError::Argument`] naming the option and its allowed range.
    pub fn options(&self) -> Result<SimulationOptions, RattleError> {
        crate::scene::simulator::Accuracy {
            tol: self.tol,
            steady_tol: self.steady_tol,
            max_periods: self.max_periods,
            max_oscillations: self.max_oscillations,
        }
        .options()
        .map_err(|e| RattleError::Argument(e.to_string()))
    }
}

/// `omega` if it is finite and positive.
fn check_omega(option: &str, omega: f64) -> Result<f64, RattleError> {
    if omega.is_finite() && omega > 0.0 {
        Ok(omega)
    } else {
        Err(RattleError::Argument(format!(
            "{option} = {omega} is out of range: must be finite and > 0 (rad/s)"
        )))
    }
}

/// `omega` if `scene` can be run at it in bounded time ([`FrequencyBounds`]).
fn check_frequency(scene: &Scene, option: &str, omega: f64) -> Result<f64, RattleError> {
    Ok(FrequencyBounds::of(scene).check(option, omega)?)
}

/// The scene at `path`, or the built-in paper scene.
fn load(path: &Option<PathBuf>) -> Result<Scene, RattleError> {
    Ok(match path {
        Some(path) => Scene::load(path)?,
        None => Scene::paper(),
    })
}

/// The scene at `path` in either form, or the built-in paper scene.
fn load_any(path: &Option<PathBuf>) -> Result<AnyScene, RattleError> {
    Ok(match path {
        Some(path) => AnyScene::load(path)?,
        None => AnyScene::Cells(Scene::paper()),
    })
}

/// The scene at `path` (or the built-in paper scene) for a command that works on a single
/// unit only.
///
/// # Errors
/// As [`load`]; [`RattleError::Argument`] naming `cells`/`chain` when the scene is a chain.
fn load_unit(path: &Option<PathBuf>, command: &str) -> Result<Scene, RattleError> {
    let scene = load(path)?;
    scene
        .refuse_chain(command)
        .map_err(|e| RattleError::Argument(e.to_string()))?;
    Ok(scene)
}

/// The first line of a one-frequency table: the scene, the frequency and the active effects.
fn heading(scene: &Scene, omega: f64) -> String {
    format!(
        "scene {} at ω = {omega} rad/s; effects: {}\n",
        scene.name,
        scene.effect_words()
    )
}

/// Pretty JSON of a one-document result, with a final newline.
fn pretty(record: &impl serde::Serialize) -> Result<String, RattleError> {
    serde_json::to_string_pretty(record)
        .map(|s| s + "\n")
        .map_err(|e| RattleError::Numerical(e.to_string()))
}

/// A one-document command's output: with `json`, the document itself (for stdout); else, with
/// `out` in `format`, the document (`.json`) or one row per item (`rows()`, as CSV or JSON
/// lines) written to that file, and `summary()` for stdout.
///
/// # Errors
/// [`RattleError::Output`] when the file cannot be written.
fn write_record<R: serde::Serialize, I: Iterator<Item = R>>(
    json: bool,
    out: Option<&std::path::PathBuf>,
    format: Option<crate::output::Format>,
    record: &impl serde::Serialize,
    columns: &[&str],
    rows: impl FnOnce() -> I,
    summary: impl FnOnce() -> String,
) -> Result<String, RattleError> {
    use crate::output::{writer_with_columns, Format, Header, OutputError};
    if json {
        return pretty(record);
    }
    if let (Some(path), Some(format)) = (out, format) {
        let io = |source| {
            RattleError::Output(OutputError::Io {
                path: path.clone(),
                source,
            })
        };
        if format == Format::Json {
            std::fs::write(path, pretty(record)?).map_err(io)?;
        } else {
            let file = std::fs::File::create(path).map_err(io)?;
            let mut table = writer_with_columns::<R, _>(
                format,
                std::io::BufWriter::new(file),
                &Header::default(),
                None,
                columns,
            )
            .map_err(io)?;
            for row in rows() {
                table.row(&row).map_err(io)?;
            }
            table.finish().map_err(io)?;
        }
    }
    Ok(summary())
}

/// ` (DETAIL)`, or nothing for an empty detail.
fn detail(words: &str) -> String {
    if words.is_empty() {
        String::new()
    } else {
        format!(" ({words})")
    }
}

/// The verdict's line of a table: the class, its `detail` (already in parentheses, or empty)
/// and the two differences.
fn class_line(class: &str, detail: &str, relative: Option<f64>, multiplier: Option<f64>) -> String {
    let number = |x: Option<f64>| x.map_or("-".to_owned(), |d| format!("{d:.1e}"));
    format!(
        "class: {class}{detail}; relative difference {}; multiplier difference {}\n",
        number(relative),
        number(multiplier)
    )
}

/// The `status:` and `period:` lines of a simulation's table.
fn status_lines(status: &str, regime: &str, period: Option<u32>) -> String {
    format!(
        "status: {status} ({regime})\nperiod: {}\n",
        period.map_or("none (not periodic)".to_owned(), |p| format!(
            "{p} forcing period(s)"
        ))
    )
}
