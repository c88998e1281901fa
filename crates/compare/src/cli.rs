//! The `rattle` command: argument parsing, dispatch and exit codes.
//!
//! Exit codes: 0 success (including "no orbit exists"), 1 a numerical failure with an
//! explanation, 2 bad input (arguments or scene).

use crate::frequency::analyse;
use crate::json;
use crate::scene::{Scene, SceneError};
use crate::simulation::{run as simulate_scene, status_name};
use crate::sweep::{
    frequencies, merge, sweep, to_csv, to_csv_shard, to_json, to_json_shard, Shard, Solver,
};
use clap::{Args, Parser, Subcommand};
use rattle_analytic::{gap_for_beta, Orbit, Violation};
use rattle_event_driven::{SimulationOptions, Start};
use serde_json::{json, Value};
use std::fmt::Write as _;
use std::path::PathBuf;
use thiserror::Error;

/// Steady states of an impacting mass-in-mass unit, two independent ways.
#[derive(Debug, Parser)]
#[command(
    name = "rattle",
    version,
    about = "Steady states of an impacting mass-in-mass unit, two independent ways: closed-form orbits (Nigm–Shabana) and exact event-driven simulation"
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
    /// orbit (symmetric branches and asymmetric β), with viability and Floquet stability.
    Orbit(OrbitArgs),
    /// The member of the two-impact family whose side-2 impact comes βT after the side-1
    /// impact: the gap Δ*(β) that admits it, its phase, viability and stability.
    Family(FamilyArgs),
    /// Event-driven simulation from rest until the motion is periodic (or a cap), or for
    /// exactly N periods: status, period, impacts per period, outer amplitude.
    Simulate(SimulateArgs),
    /// A frequency sweep with one solver or both, in parallel, written to a JSON or CSV file.
    Sweep(SweepArgs),
    /// Joins the parts of a sharded sweep (`rattle sweep … --shard K/N`) into the file the
    /// unsharded sweep would write, byte for byte.
    Merge(MergeArgs),
    /// A map over restitution, gap and frequency (each frequency continued from the previous
    /// one, up the frequencies): the simulated regime and transmittance at every point, the
    /// analytic prediction beside it, and the attenuation bandwidth of every (e, Δ/u_g) line.
    Map(MapArgs),
}

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
    /// Every point: `.json` or `.csv`, by extension.
    #[arg(long)]
    pub out: PathBuf,
    /// The bandwidth of every (e, Δ/u_g) line: `.json` or `.csv`, by extension.
    #[arg(long)]
    pub bandwidth_out: Option<PathBuf>,
    /// Relative tolerance of contact times, in [1e-15, 1e-2].
    #[arg(long, default_value_t = 1e-12)]
    pub tol: f64,
    /// Relative tolerance of the periodicity test, in [1e-14, 1e-2] (looser than a sweep's:
    /// a map needs the regime and the amplitude, not the last digits).
    #[arg(long, default_value_t = crate::map::MAP_PERIODICITY_TOLERANCE)]
    pub steady_tol: f64,
    /// Cap on forcing periods per point (a point not periodic by then is `irregular`).
    #[arg(long, default_value_t = crate::map::MAP_MAX_PERIODS)]
    pub max_periods: u64,
}

/// Arguments of `rattle merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The parts (all `.json` or all `.csv`), in any order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged file.
    #[arg(long)]
    pub out: PathBuf,
}

/// Arguments of `rattle simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    /// Run exactly N forcing periods and judge the steady state from the tail (default: run
    /// until periodic, up to a cap).
    #[arg(long)]
    pub periods: Option<u64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub accuracy: Accuracy,
}

/// Accuracy knobs of the simulator.
#[derive(Debug, Args, Clone, Copy)]
pub struct Accuracy {
    /// Relative tolerance of contact times (the simulator's accuracy knob), in [1e-15, 1e-2].
    #[arg(long, default_value_t = 1e-12)]
    pub tol: f64,
    /// Relative tolerance of the periodicity test of the steady state, in [1e-14, 1e-2].
    #[arg(long, default_value_t = 1e-9)]
    pub steady_tol: f64,
    /// Cap on forcing periods when running until steady.
    #[arg(long, default_value_t = 20_000)]
    pub max_periods: u64,
    /// Cap on free oscillations of the fastest mode when running until steady (periods ×
    /// ω_fastest/ω, at least 64 periods): bounds runs forced far below the natural
    /// frequencies; finite, > 0.
    #[arg(long, default_value_t = 2e6)]
    pub max_oscillations: f64,
}

impl Accuracy {
    /// The simulator's options, after range checks.
    pub fn options(&self) -> Result<SimulationOptions, RattleError> {
        if !(self.tol.is_finite() && (1e-15..=1e-2).contains(&self.tol)) {
            return Err(RattleError::Argument(format!(
                "--tol = {} is out of range: must be in [1e-15, 1e-2]",
                self.tol
            )));
        }
        if !(self.steady_tol.is_finite() && (1e-14..=1e-2).contains(&self.steady_tol)) {
            return Err(RattleError::Argument(format!(
                "--steady-tol = {} is out of range: must be in [1e-14, 1e-2]",
                self.steady_tol
            )));
        }
        if self.max_periods == 0 {
            return Err(RattleError::Argument("--max-periods must be > 0".into()));
        }
        if !(self.max_oscillations.is_finite() && self.max_oscillations > 0.0) {
            return Err(RattleError::Argument(format!(
                "--max-oscillations = {} is out of range: must be finite and > 0",
                self.max_oscillations
            )));
        }
        Ok(SimulationOptions {
            root_tolerance: self.tol,
            periodicity_tolerance: self.steady_tol,
            max_periods: self.max_periods,
            max_oscillations: Some(self.max_oscillations),
            ..SimulationOptions::default()
        })
    }
}

/// Arguments of `rattle sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Scene file (JSON). Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// Lowest angular frequency, rad/s (finite, > 0).
    #[arg(long)]
    pub omega_min: f64,
    /// Highest angular frequency, rad/s (finite, ≥ omega-min).
    #[arg(long)]
    pub omega_max: f64,
    /// Number of frequencies, evenly spaced, ends included (≥ 1).
    #[arg(long)]
    pub points: usize,
    /// Which solver: analytic, event (simulator from rest) or both (with a verdict per point).
    #[arg(long, value_enum, default_value_t = Solver::Both)]
    pub solver: Solver,
    /// Output file: `.json` or `.csv`, by extension.
    #[arg(long)]
    pub out: PathBuf,
    /// Compute only part K of N (a contiguous block of the frequencies), e.g. `--shard 3/8`;
    /// join the parts with `rattle merge`.
    #[arg(long)]
    pub shard: Option<String>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub accuracy: Accuracy,
}

/// Scene and frequency, common to every command.
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

/// Arguments of `rattle orbit`.
#[derive(Debug, Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    /// Only the symmetric orbits (β = ½); skips the search over β.
    #[arg(long)]
    pub symmetric_only: bool,
}

/// Arguments of `rattle family`.
#[derive(Debug, Args)]
pub struct FamilyArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    /// Fraction of the period from the side-1 to the side-2 impact, in (0, 1).
    #[arg(long, allow_hyphen_values = true)]
    pub beta: f64,
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
    /// The computation failed; the message says why.
    #[error("numerical failure: {0}")]
    Numerical(String),
}

impl RattleError {
    /// 2 for bad input, 1 for a numerical failure.
    pub fn exit_code(&self) -> i32 {
        match self {
            RattleError::Scene(_) | RattleError::Argument(_) => 2,
            RattleError::Numerical(_) => 1,
        }
    }
}

fn check_omega(omega: f64) -> Result<f64, RattleError> {
    if omega.is_finite() && omega > 0.0 {
        Ok(omega)
    } else {
        Err(RattleError::Argument(format!(
            "--omega = {omega} is out of range: must be finite and > 0 (rad/s)"
        )))
    }
}

fn load(scene: &Option<PathBuf>) -> Result<Scene, RattleError> {
    Ok(match scene {
        Some(path) => Scene::load(path)?,
        None => Scene::paper(),
    })
}

fn effects(scene: &Scene) -> Value {
    json!(scene.effects().iter().map(|e| e.name()).collect::<Vec<_>>())
}

/// Runs a parsed command and returns what it prints on standard output.
pub fn run(cli: Cli) -> Result<String, RattleError> {
    match cli.command {
        Command::Orbit(args) => orbit(args),
        Command::Family(args) => family(args),
        Command::Simulate(args) => simulate_command(args),
        Command::Sweep(args) => sweep_command(args),
        Command::Merge(args) => merge_command(args),
        Command::Map(args) => map_command(args),
    }
}

fn orbit(args: OrbitArgs) -> Result<String, RattleError> {
    let omega = check_omega(args.common.omega)?;
    let scene = load(&args.common.scene)?;
    let point = analyse(&scene, omega, !args.symmetric_only)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let gap = scene.stops.map(|s| s.gap);
    if args.common.json {
        let doc = json!({
            "scene": scene.name,
            "omega": json::number(omega),
            "effects": effects(&scene),
            "linear": json::linear(&point.linear, gap),
            "orbits": point.orbits.iter().map(|(b, o)| json::orbit(o, *b)).collect::<Vec<_>>(),
        });
        return Ok(format!("{doc:#}\n"));
    }
    let mut out = String::new();
    let lin = &point.linear;
    let _ = writeln!(
        out,
        "scene {} at ω = {omega} rad/s; effects: {}",
        scene.name,
        effects_words(&scene)
    );
    if lin.unbounded {
        let _ = writeln!(out, "linear: unbounded (undamped exact resonance)");
    } else {
        let _ = writeln!(
            out,
            "linear: X_o = {:.6}, X_i = {:.6}, |u_i − u_o| = {:.6}, T = {:.3} dB{}",
            lin.outer_amplitude,
            lin.inner_amplitude,
            lin.relative_amplitude,
            lin.transmittance_db,
            match gap {
                Some(g) if lin.relative_amplitude > g => " (reaches the stops)",
                Some(_) => " (stays clear of the stops)",
                None => "",
            }
        );
    }
    if scene.stops.is_none() {
        let _ = writeln!(out, "no stops: no impacting orbits");
        return Ok(out);
    }
    if point.orbits.is_empty() {
        let _ = writeln!(out, "no two-impact orbit exists at this frequency");
        return Ok(out);
    }
    let _ = writeln!(
        out,
        "{:>6} {:>8} {:>9} {:>10} {:>9} {:>6} {:>6} {:>7}  violations",
        "branch", "beta", "alpha", "X_o", "T(dB)", "viable", "stable", "max|μ|"
    );
    for (b, o) in &point.orbits {
        let _ = writeln!(out, "{}", orbit_row(*b, o));
    }
    Ok(out)
}

fn effects_words(scene: &Scene) -> String {
    let e: Vec<&str> = scene.effects().iter().map(|e| e.name()).collect();
    if e.is_empty() {
        "none (linear, undamped)".to_owned()
    } else {
        e.join(", ")
    }
}

fn orbit_row(branch: usize, o: &Orbit) -> String {
    let mu = o
        .floquet_multipliers
        .iter()
        .map(|m| m.norm())
        .fold(0.0, f64::max);
    let violations: Vec<String> = o
        .violations
        .iter()
        .map(|v| match v {
            Violation::Penetration { side, excess, .. } => {
                format!("penetrates side {} by {excess:.3e}", side.number())
            }
            Violation::WrongApproach { side, .. } => {
                format!("approaches side {} from outside", side.number())
            }
        })
        .collect();
    format!(
        "{branch:>6} {:>8.5} {:>9.5} {:>10.6} {:>9.3} {:>6} {:>6} {:>7.4}  {}",
        o.beta,
        o.alpha,
        o.outer_amplitude,
        o.transmittance_db,
        o.viable,
        o.stable,
        mu,
        if violations.is_empty() {
            "-".to_owned()
        } else {
            violations.join("; ")
        }
    )
}

fn family(args: FamilyArgs) -> Result<String, RattleError> {
    let omega = check_omega(args.common.omega)?;
    let beta = args.beta;
    if !(beta.is_finite() && beta > 0.0 && beta < 1.0) {
        return Err(RattleError::Argument(format!(
            "--beta = {beta} is out of range: must be in (0, 1)"
        )));
    }
    let scene = load(&args.common.scene)?;
    let Some(stops) = scene.stops_model() else {
        return Err(RattleError::Argument(
            "the family needs stops: the scene has no `stops` (its restitution sets the impact law)".into(),
        ));
    };
    let unit = scene.unit_model();
    let point = gap_for_beta(&unit, stops.restitution, omega, beta)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let o = &point.orbit;
    if args.common.json {
        let doc = json!({
            "scene": scene.name,
            "omega": json::number(omega),
            "beta": json::number(beta),
            "effects": effects(&scene),
            "gap": json::number(point.gap),
            "gap_over_base_amplitude": json::number(point.gap / unit.base_amplitude),
            "alpha": json::number(o.alpha),
            "state_before_impact": json::state(&o.state_before_impact),
            "state_after_impact": json::state(&o.state_after_impact),
            "outer_amplitude": json::number(o.outer_amplitude),
            "transmittance_db": json::number(o.transmittance_db),
            "viable": o.viable,
            "violations": o.violations.iter().map(json::violation).collect::<Vec<_>>(),
            "floquet_multipliers": o.floquet_multipliers.iter().map(|m| json!([json::number(m.re), json::number(m.im)])).collect::<Vec<_>>(),
            "stable": o.stable,
        });
        return Ok(format!("{doc:#}\n"));
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "scene {} at ω = {omega} rad/s, β = {beta}: gap Δ*(β) = {:.9} (Δ*/u_g = {:.9})",
        scene.name,
        point.gap,
        point.gap / unit.base_amplitude
    );
    let _ = writeln!(
        out,
        "{:>6} {:>8} {:>9} {:>10} {:>9} {:>6} {:>6} {:>7}  violations",
        "branch", "beta", "alpha", "X_o", "T(dB)", "viable", "stable", "max|μ|"
    );
    let _ = writeln!(out, "{}", orbit_row(0, o));
    Ok(out)
}

fn simulate_command(args: SimulateArgs) -> Result<String, RattleError> {
    let omega = check_omega(args.common.omega)?;
    let mut options = args.accuracy.options()?;
    if let Some(n) = args.periods {
        if n == 0 {
            return Err(RattleError::Argument("--periods must be > 0".into()));
        }
        options.fixed_periods = Some(n);
    }
    let scene = load(&args.common.scene)?;
    let sim = simulate_scene(&scene, omega, &Start::rest(2), &options)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let s = &sim.steady;
    let status = status_name(s);
    if args.common.json {
        let doc = json!({
            "scene": scene.name,
            "omega": json::number(omega),
            "effects": effects(&scene),
            "status": status,
            "regime": sim.regime.name(),
            "period": s.period,
            "impacts_per_period": json::number(s.impacts_per_period),
            "outer_amplitude": json::number(sim.outer_amplitude),
            "transmittance_db": sim.transmittance_db.map_or(Value::Null, json::number),
            "sticking": s.sticking,
            "stopped_by": crate::simulation::stop_name(s.stopped),
            "periods_run": s.periods_run,
            "impacts": s.impacts,
        });
        return Ok(format!("{doc:#}\n"));
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "scene {} at ω = {omega} rad/s; effects: {}",
        scene.name,
        effects_words(&scene)
    );
    let _ = writeln!(out, "status: {status} ({})", sim.regime.words());
    let _ = writeln!(
        out,
        "period: {}",
        s.period
            .map_or("none (not periodic)".to_owned(), |p| format!(
                "{p} forcing period(s)"
            ))
    );
    let _ = writeln!(out, "impacts per period: {}", s.impacts_per_period);
    let _ = writeln!(
        out,
        "X_o = {:.9}, T = {}",
        sim.outer_amplitude,
        sim.transmittance_db
            .map_or("undefined (no steady state)".to_owned(), |t| format!(
                "{t:.4} dB"
            ))
    );
    let _ = writeln!(
        out,
        "periods run: {}, impacts: {}",
        s.periods_run, s.impacts
    );
    Ok(out)
}

fn sweep_command(args: SweepArgs) -> Result<String, RattleError> {
    let (lo, hi) = (check_omega(args.omega_min)?, check_omega(args.omega_max)?);
    if hi < lo {
        return Err(RattleError::Argument(format!(
            "--omega-max = {hi} is out of range: must be ≥ --omega-min = {lo}"
        )));
    }
    if args.points == 0 {
        return Err(RattleError::Argument("--points must be ≥ 1".into()));
    }
    let csv = match args.out.extension().and_then(|e| e.to_str()) {
        Some("csv") => true,
        Some("json") => false,
        _ => {
            return Err(RattleError::Argument(format!(
                "--out {}: the extension must be .json or .csv",
                args.out.display()
            )))
        }
    };
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()
        .map_err(RattleError::Argument)?;
    let options = args.accuracy.options()?;
    let scene = load(&args.scene)?;
    let all = frequencies(lo, hi, args.points);
    let omegas = match shard {
        Some(s) => all[s.range(all.len())].to_vec(),
        None => all.clone(),
    };
    let points = sweep(&scene, &omegas, args.solver, &options, true);
    let text = match (shard, csv) {
        (None, true) => to_csv(&scene, &points),
        (None, false) => format!("{:#}\n", to_json(&scene, args.solver, &points)),
        (Some(s), true) => to_csv_shard(&scene, &points, all.len(), s),
        (Some(s), false) => format!(
            "{:#}\n",
            to_json_shard(&scene, args.solver, &points, all.len(), s)
        ),
    };
    std::fs::write(&args.out, text)
        .map_err(|e| RattleError::Argument(format!("cannot write {}: {e}", args.out.display())))?;
    Ok(format!(
        "wrote {} ({} frequencies, solver {})\n",
        args.out.display(),
        omegas.len(),
        args.solver.name()
    ))
}

/// Whether `path` names a CSV (`true`) or JSON (`false`) file; `field` names the option.
fn table_kind(path: &std::path::Path, field: &str) -> Result<bool, RattleError> {
    match path.extension().and_then(|e| e.to_str()) {
        Some("csv") => Ok(true),
        Some("json") => Ok(false),
        _ => Err(RattleError::Argument(format!(
            "{field} {}: the extension must be .json or .csv",
            path.display()
        ))),
    }
}

fn map_command(args: MapArgs) -> Result<String, RattleError> {
    use crate::map::{Axis, Map, MapError, MapGrid, MapSettings};
    let grid = MapGrid {
        restitution: Axis {
            min: args.restitution_min,
            max: args.restitution_max,
            count: args.restitutions,
        },
        gap_over_base_amplitude: Axis {
            min: args.gap_min,
            max: args.gap_max,
            count: args.gaps,
        },
        omega: Axis {
            min: args.omega_min,
            max: args.omega_max,
            count: args.points,
        },
    };
    grid.validate()
        .map_err(|e| RattleError::Argument(e.to_string()))?;
    let points_csv = table_kind(&args.out, "--out")?;
    let bandwidth_csv = args
        .bandwidth_out
        .as_deref()
        .map(|p| table_kind(p, "--bandwidth-out"))
        .transpose()?;
    let simulation = Accuracy {
        tol: args.tol,
        steady_tol: args.steady_tol,
        max_periods: args.max_periods,
        max_oscillations: 2e6,
    }
    .options()?;
    let settings = MapSettings {
        simulation,
        ..MapSettings::default()
    };
    let scene = load(&args.scene)?;
    let map = Map::run(&scene, grid, &settings, true).map_err(|e| match e {
        MapError::NoStops | MapError::OutOfRange { .. } => RattleError::Argument(e.to_string()),
    })?;
    let write = |path: &std::path::Path, text: String| {
        std::fs::write(path, text)
            .map_err(|e| RattleError::Argument(format!("cannot write {}: {e}", path.display())))
    };
    write(
        &args.out,
        if points_csv {
            map.points_csv()
        } else {
            format!("{:#}\n", map.points_json())
        },
    )?;
    let mut out = format!(
        "wrote {} ({} points: {} restitutions × {} gaps × {} frequencies)\n",
        args.out.display(),
        grid.points(),
        args.restitutions,
        args.gaps,
        args.points
    );
    if let (Some(path), Some(csv)) = (&args.bandwidth_out, bandwidth_csv) {
        write(
            path,
            if csv {
                map.bandwidth_csv()
            } else {
                format!("{:#}\n", map.bandwidth_json())
            },
        )?;
        let _ = writeln!(out, "wrote {} ({} lines)", path.display(), map.lines.len());
    }
    Ok(out)
}

fn merge_command(args: MergeArgs) -> Result<String, RattleError> {
    let parts: Vec<String> = args
        .parts
        .iter()
        .map(|p| {
            std::fs::read_to_string(p)
                .map_err(|e| RattleError::Argument(format!("cannot read {}: {e}", p.display())))
        })
        .collect::<Result<_, _>>()?;
    let merged = merge(&parts).map_err(RattleError::Argument)?;
    std::fs::write(&args.out, merged)
        .map_err(|e| RattleError::Argument(format!("cannot write {}: {e}", args.out.display())))?;
    Ok(format!(
        "wrote {} from {} parts\n",
        args.out.display(),
        parts.len()
    ))
}
