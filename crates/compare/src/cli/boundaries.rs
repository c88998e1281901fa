//! `rattle boundaries`: every regime boundary of a unit or a structure at once: each event of
//! the one-parameter continuation of the motions a sweep settles on, followed in (ω, a scene
//! parameter).

use super::{load_any, write_record, RattleError};
use crate::output::{Format, Row};
use crate::runs::boundaries::{
    follow_events, follow_structure_events, rows, BoundariesError, BoundariesRecord, BoundariesRow,
    EventFilter,
};
use crate::runs::continuation::Branches;
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::scene::parameter::{AnyParameter, AnyParameterError, ParameterError, SceneParameter};
use crate::scene::structure::StructureForm;
use crate::scene::structure_parameter::{StructureParameter, StructureParameterError};
use crate::scene::{AnyScene, Scene};
use crate::study::{compared_seeds, study_continuation, two_impact_seeds, StudySize};
use crate::verdict::structure::structure_cross_check;
use crate::verdict::{compare, Starts};
use clap::Args;
use rattle_analytic::BoundarySettings;
use rattle_analytic::ImpactSequence;
use rattle_analytic::{continue_sequence_after, Continuation};
use rattle_event_driven::SimulationOptions;
use std::fmt::Write as _;
use std::io::IsTerminal;
use std::path::PathBuf;

/// Cap on the forcing periods of each simulation of the seeding sweep, as in the study of
/// `cargo xtask figures`: points that need longer to settle give no seed.
pub const SWEEP_MAX_PERIODS: u64 = 4000;

/// Arguments of `rattle boundaries`.
#[derive(Debug, Args)]
pub struct BoundariesArgs {
    /// Scene file (JSON), a single unit or a structure. Omit for the built-in paper scene
    /// (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The scene parameter varied, by its JSON path: stops.gap, stops.restitution,
    /// unit.inner_stiffness, damping.outer, … (on a structure: `structure.stops[0].gap_plus`,
    /// `structure.bodies[1].mass`, `forcing.forces[0].amplitude`, …)
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
    /// Follow only the events of orbits with at most this many impacts per cycle (≥ 2); the
    /// others are listed as skipped. By default every event.
    #[arg(long)]
    pub max_impacts: Option<usize>,
    /// Follow only the events that bound a stable motion (no Floquet multiplier outside the
    /// unit circle at the event but the critical ones); the others are listed as skipped.
    #[arg(long)]
    pub stable_only: bool,
    /// Print one JSON document (every curve, the events skipped) instead of a summary.
    #[arg(long, conflicts_with = "out")]
    pub json: bool,
    /// Write the points of every curve to a `.csv` file (one row per point, with the curve's
    /// index) or the whole document to a `.json` file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The branches of the one-parameter continuation in ω of `scene` over `[omega_min,
/// omega_max]`, seeded as the study of `cargo xtask figures` seeds its own (with the same
/// settings, [`study_continuation`]): the viable `+-` orbits at the study's four seed
/// frequencies in the range, then the analytic orbit of every periodic motion the simulator
/// settles on from rest at `points` frequencies (both solvers, [`compare`], each run capped
/// at [`SWEEP_MAX_PERIODS`] periods), in the order of the frequencies; each seed skipped when
/// a branch already followed passes through it. The sweep runs in parallel, the
/// continuation serially: the branches do not depend on the thread count. `progress` ticks
/// once per frequency of the sweep.
fn sweep_branches(
    scene: &Scene,
    omega_min: f64,
    omega_max: f64,
    points: usize,
    progress: &Progress,
) -> Branches {
    let mut out = Branches::default();
    let Some(stops) = scene.stops_model() else {
        return out;
    };
    let size = StudySize {
        omega_min,
        omega_max,
        ..StudySize::full()
    };
    let options = SimulationOptions {
        max_periods: SWEEP_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let grid = crate::runs::axis::Axis::new(omega_min, omega_max, points).values();
    let compared: Vec<_> = parallel_map(&grid, Grain::Uneven, progress, |&w| {
        compare(scene, w, &options, Starts::Rest).ok()
    })
    .into_iter()
    .flatten()
    .collect();
    let mut seeds = two_impact_seeds(scene, &size);
    seeds.extend(compared_seeds(&compared));
    let settings = study_continuation(omega_min, omega_max);
    // A seed the continuation refuses leaves the others' branches.
    let _ = out.extend_all(&scene.unit_model(), &stops, &seeds, &settings);
    out
}

/// [`sweep_branches`] on a structure: the seeds are the viable analytic orbits of the
/// motions the structure settles on from rest (its cross-check, each run capped at
/// [`SWEEP_MAX_PERIODS`] periods), followed on its analytic model.
fn structure_branches(
    form: &StructureForm,
    omega_min: f64,
    omega_max: f64,
    points: usize,
    progress: &Progress,
) -> Continuation<ImpactSequence> {
    let mut out = Continuation::default();
    let Ok(model) = form.structure.analytic_model() else {
        return out;
    };
    let options = SimulationOptions {
        max_periods: SWEEP_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let grid = crate::runs::axis::Axis::new(omega_min, omega_max, points).values();
    let seeds: Vec<_> = parallel_map(&grid, Grain::Uneven, progress, |&w| {
        structure_cross_check(&form.structure, w, &options)
            .ok()
            .and_then(|check| check.analytic)
            .filter(|o| o.viable)
    })
    .into_iter()
    .flatten()
    .collect();
    let settings = study_continuation(omega_min, omega_max);
    for seed in &seeds {
        // A seed the continuation refuses leaves the others' branches.
        let _ = continue_sequence_after(&model, seed, &settings, &mut out);
    }
    out
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
    if let Some(cap) = args.max_impacts.filter(|&cap| cap < 2) {
        return Err(RattleError::Argument(format!(
            "--max-impacts = {cap} is out of range: must be ≥ 2"
        )));
    }
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
    let param: AnyParameter = args
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
    let any = load_any(&args.scene)?;
    crate::api::check_frequency(&any, "--omega-min", args.omega_min)?;
    crate::api::check_frequency(&any, "--omega-max", args.omega_max)?;
    let filter = EventFilter {
        max_impacts: args.max_impacts,
        stable_only: args.stable_only,
    };
    let show = std::io::stderr().is_terminal();
    let bad_param = |e: AnyParameterError| RattleError::Argument(format!("--param: {e}"));
    let path = param.to_string();
    let record = match &any {
        AnyScene::Structure(form) => {
            let param: StructureParameter = path
                .parse()
                .map_err(|e: StructureParameterError| bad_param(e.into()))?;
            // The arguments are checked against the scene before the sweep runs.
            let check = |c: &Continuation<ImpactSequence>, progress: &Progress| {
                follow_structure_events(form, c, &param, &settings, filter, progress)
            };
            check(&Continuation::default(), &Progress::hidden()).map_err(run_error)?;
            let branches = structure_branches(
                form,
                args.omega_min,
                args.omega_max,
                args.points,
                &Progress::new("sweep", args.points, show),
            );
            tell(show, branches.branches.len(), branches.events.len(), &param);
            check(
                &branches,
                &Progress::new("curves", branches.events.len(), show),
            )
            .map_err(run_error)?
        }
        AnyScene::Cells(scene) => {
            scene
                .refuse_chain("boundaries")
                .map_err(|e| RattleError::Argument(e.to_string()))?;
            let param: SceneParameter = path
                .parse()
                .map_err(|e: ParameterError| bad_param(e.into()))?;
            unit_record(scene, &param, &args, &settings, filter, show)?
        }
    };
    write_record(
        args.json,
        args.out.as_ref(),
        format,
        &record,
        BoundariesRow::COLUMNS,
        || rows(&record),
        || summary(&record),
    )
}

/// Tells the user, on a terminal, what the continuation found and what follows.
fn tell(show: bool, branches: usize, events: usize, param: &impl std::fmt::Display) {
    if show {
        eprintln!(
            "continuation: {branches} branches, {events} events; following each in (ω, {param})"
        );
    }
}

/// [`run`] on a unit: the branches seeded by [`sweep_branches`], each event followed.
fn unit_record(
    scene: &Scene,
    param: &SceneParameter,
    args: &BoundariesArgs,
    settings: &BoundarySettings,
    filter: EventFilter,
    show: bool,
) -> Result<BoundariesRecord, RattleError> {
    let check = |b: &Branches, progress: &Progress| {
        follow_events(scene, b, param, settings, filter, progress)
    };
    // The arguments are checked against the scene before the sweep runs.
    check(&Branches::default(), &Progress::hidden()).map_err(run_error)?;
    let branches = sweep_branches(
        scene,
        args.omega_min,
        args.omega_max,
        args.points,
        &Progress::new("sweep", args.points, show),
    );
    tell(show, branches.branches.len(), branches.events.len(), param);
    check(
        &branches,
        &Progress::new("curves", branches.events.len(), show),
    )
    .map_err(run_error)
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
