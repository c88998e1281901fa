//! `rattle boundaries`: every regime boundary of a unit at once: each event of the
//! one-parameter continuation of the motions a sweep settles on, followed in (ω, a scene
//! parameter).

use super::{check_frequency, load_unit, write_record, RattleError};
use crate::output::{finite, table_row, Format};
use crate::runs::boundaries::{follow_events, sweep_branches, BoundariesError, BoundariesRecord};
use crate::runs::parallel::Progress;
use crate::scene::parameter::SceneParameter;
use clap::Args;
use rattle_analytic::continuation::BoundarySettings;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;

/// Arguments of `rattle boundaries`.
#[derive(Debug, Args)]
pub struct BoundariesArgs {
    /// Scene file (JSON), a single unit. Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The scene parameter varied, by its JSON path: stops.gap, stops.restitution,
    /// unit.inner_stiffness, damping.outer, …
    #[arg(long)]
    pub param: String,
    /// Lowest parameter value followed (within the field's physical range, ≤ the scene's
    /// value).
    #[arg(long, allow_hyphen_values = true)]
    pub min: f64,
    /// Highest parameter value followed (> min, within the field's physical range, ≥ the
    /// scene's value).
    #[arg(long, allow_hyphen_values = true)]
    pub max: f64,
    /// Lowest frequency, rad/s (finite, > 0): of the sweep, the continuation and the curves.
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).omega_min)]
    pub omega_min: f64,
    /// Highest frequency, rad/s (finite, > omega-min): of the sweep, the continuation and the
    /// curves.
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).omega_max)]
    pub omega_max: f64,
    /// Frequencies of the sweep (both solvers, from rest) whose periodic motions seed the
    /// continuation beside the `+-` orbits, in [1, 100000].
    #[arg(long, default_value_t = 200)]
    pub points: usize,
    /// Largest step along each curve (in α, impact phases, ω and the parameter together).
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).max_step)]
    pub max_step: f64,
    /// Cap on the points of each curve in each direction, ≥ 1.
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).max_points)]
    pub max_points: usize,
    /// Print one JSON document (every curve, the events skipped) instead of a summary.
    #[arg(long, conflicts_with = "out")]
    pub json: bool,
    /// Write the points of every curve to a `.csv` file (one row per point, with the curve's
    /// index) or the whole document to a `.json` file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

table_row! {
    /// One point of one curve of `rattle boundaries`, as a CSV row.
    pub struct BoundariesRow {
        /// Index of the curve in the document's `curves`.
        pub curve: usize,
        /// Index of the event the curve was followed from.
        pub from_event: usize,
        /// The event kind followed.
        pub event: &'static str,
        /// The orbits' canonical signature.
        pub signature: String,
        /// Forcing periods per cycle.
        pub period: u32,
        /// The parameter's value.
        pub param_value: Option<f64>,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// `X_o`, m.
        pub outer_amplitude: Option<f64>,
        /// Real part of the event's multiplier.
        pub critical_multiplier_re: Option<f64>,
        /// Imaginary part of the event's multiplier.
        pub critical_multiplier_im: Option<f64>,
    }
}

/// The rows of every point of every curve of `record`.
pub fn rows(record: &BoundariesRecord) -> impl Iterator<Item = BoundariesRow> + '_ {
    record.curves.iter().enumerate().flat_map(|(k, c)| {
        c.boundary.points.iter().map(move |p| BoundariesRow {
            curve: k,
            from_event: c.from_event,
            event: c.boundary.event,
            signature: c.boundary.signature.clone(),
            period: c.boundary.period,
            param_value: finite(p.param_value),
            omega: finite(p.omega),
            outer_amplitude: finite(p.outer_amplitude),
            critical_multiplier_re: finite(p.critical_multiplier[0]),
            critical_multiplier_im: finite(p.critical_multiplier[1]),
        })
    })
}

/// The curves' settings of the arguments.
///
/// # Errors
/// [`RattleError::Argument`] naming the option out of range.
fn settings(args: &BoundariesArgs) -> Result<BoundarySettings, RattleError> {
    let settings = BoundarySettings {
        omega_min: args.omega_min,
        omega_max: args.omega_max,
        max_step: args.max_step,
        max_points: args.max_points,
        ..BoundarySettings::new(args.min, args.max)
    };
    let settings = BoundarySettings {
        initial_step: settings.initial_step.min(settings.max_step),
        ..settings
    };
    settings.validate().map_err(|e| {
        RattleError::Argument(
            e.to_string()
                .replace("boundary.max_step", "--max-step")
                .replace("boundary.max_points", "--max-points"),
        )
    })?;
    if !(1..=100_000).contains(&args.points) {
        return Err(RattleError::Argument(format!(
            "--points = {} is out of range: must be in [1, 100000]",
            args.points
        )));
    }
    Ok(settings)
}

/// Runs `rattle boundaries`.
///
/// # Errors
/// Bad arguments or scene (exit code 2).
pub fn run(args: BoundariesArgs) -> Result<String, RattleError> {
    let settings = settings(&args)?;
    let param: SceneParameter = args
        .param
        .parse()
        .map_err(|e| RattleError::Argument(format!("--param: {e}")))?;
    let format = args
        .out
        .as_ref()
        .map(|p| Format::of(p, "--out"))
        .transpose()?;
    if format == Some(Format::JsonLines) {
        return Err(RattleError::Argument(
            "--out: boundaries are written as .csv (points) or .json (the whole document)".into(),
        ));
    }
    let scene = load_unit(&args.scene, "boundaries")?;
    check_frequency(&scene, "--omega-min", args.omega_min)?;
    check_frequency(&scene, "--omega-max", args.omega_max)?;
    // The arguments are checked against the scene before the sweep runs.
    let checked = follow_events(
        &scene,
        &Default::default(),
        &param,
        &settings,
        &Progress::hidden(),
    );
    checked.map_err(run_error)?;
    let show = std::io::stderr().is_terminal();
    let tell = |line: String| {
        if show {
            eprintln!("{line}");
        }
    };
    let branches = sweep_branches(
        &scene,
        args.omega_min,
        args.omega_max,
        args.points,
        &Progress::new("sweep", args.points, show),
    );
    tell(format!(
        "continuation: {} branches, {} events; following each in (ω, {param})",
        branches.branches.len(),
        branches.events.len()
    ));
    let record = follow_events(
        &scene,
        &branches,
        &param,
        &settings,
        &Progress::new("curves", branches.events.len(), show),
    )
    .map_err(run_error)?;
    write_record(
        args.json,
        args.out.as_ref(),
        format,
        &record,
        || rows(&record),
        || summary(&record),
    )
}

/// The command's error: every refusal is of the input (exit code 2).
fn run_error(e: BoundariesError) -> RattleError {
    RattleError::Argument(
        e.to_string()
            .replace("boundary.max_step", "--max-step")
            .replace("boundary.max_points", "--max-points"),
    )
}

/// The summary printed without `--json`.
fn summary(record: &BoundariesRecord) -> String {
    let mut out = format!(
        "scene {}: {} events on {} branches over ω ∈ [{}, {}] at {} = {}; {} curves in [{}, {}], {} skipped\n",
        record.scene,
        record.events,
        record.branches,
        record.omega_min,
        record.omega_max,
        record.param,
        record.param_start,
        record.curves.len(),
        record.min,
        record.max,
        record.skipped.len()
    );
    for (k, c) in record.curves.iter().enumerate() {
        let b = &c.boundary;
        let ends: Vec<&str> = b.ends.iter().map(|e| e.reason).collect();
        let _ = writeln!(
            out,
            "curve {k}: {} of {} (period {}) from event {} at ω = {:.10}, {} points, ends {}{}",
            b.event,
            b.signature,
            b.period,
            c.from_event,
            b.omega_start,
            b.points.len(),
            ends.join(" / "),
            if c.same_as_events.is_empty() {
                String::new()
            } else {
                format!(", also events {:?}", c.same_as_events)
            }
        );
    }
    for s in &record.skipped {
        let _ = writeln!(
            out,
            "skipped event {}: {} of {} at ω = {:.10}: {}",
            s.event, s.kind, s.signature, s.omega, s.reason
        );
    }
    out
}
