//! The front door: one call per job of the `rattle` command, each taking a loaded scene and
//! plain options and returning the record the command prints with `--json`.
//!
//! The `rattle` command and the Python package call these functions; they add argument
//! parsing, text tables and files around them. Every record is [`serde::Serialize`], and its
//! JSON is the command's, key for key. The records' fields are documented on their types in
//! [`crate::output::records`] and [`crate::output::structure`].
//!
//! | call | the command | returns |
//! | --- | --- | --- |
//! | [`load`], [`parse`] | `rattle … SCENE` | [`AnyScene`] |
//! | [`simulate`] | `rattle simulate` | [`Simulation`] |
//! | [`orbits`] | `rattle orbit` | [`Orbits`] |
//! | [`signature_orbits`] | `rattle orbit --signature` | [`SignatureOrbits`] |
//! | [`compare`] | `rattle compare` | [`Comparison`] |
//! | [`sweep`], [`sweep_each`] | `rattle sweep` | [`Sweep`], rows one by one |
//! | [`continuation`] | `rattle continue` | [`Continuation`] |
//! | [`boundary`] | `rattle boundary` | [`BoundaryRecord`](crate::runs::boundary::BoundaryRecord) |
//! | [`map`], [`map_document`] | `rattle map` | the map's tables |
//! | [`basins`], [`plane_basins`] | `rattle basins` | [`Basins`](crate::runs::basins::Basins) and its table |
//! | [`respond`], [`prepare_response`] | `rattle respond` | [`RespondRecord`](crate::output::respond::RespondRecord), samples one by one |
//! | [`transmission`], [`prepare_transmission`], [`merge_transmission`] | `rattle transmission` | [`TransmissionRecord`](crate::output::transmission::TransmissionRecord), or a shard's [`TransmissionPart`] |
//!
//! Errors are values ([`ApiError`]): bad input names the parameter (or the scene's field) and
//! its allowed range; a solver that fails says why.
//!
//! # Examples
//!
//! ```
//! use rattle_compare::api;
//! use rattle_event_driven::SimulationOptions;
//!
//! let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/paper.json");
//! let scene = api::load(path)?;
//! let sim = api::simulate(&scene, 2.0, &SimulationOptions::default())?;
//! assert!(sim.point().outer_amplitude > 0.0);
//! let json = serde_json::to_string(&sim)?;
//! assert!(json.contains("\"status\""));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use crate::output::records::{
    ChainCompareRecord, CrossCheckRecord, LyapunovRecord, SimulationRecord,
};
use crate::output::structure::{
    structure_trajectory, NamedTable, StructureCompareRecord, StructureSimulationRecord,
};
use crate::output::trajectory::{simulated_rows, ImpactRow, TrajectoryRow};
use crate::runs::parallel::Progress;
use crate::runs::structure_sweep::{structure_sweep_rows, StructureSweepRow};
use crate::runs::sweep::{sweep_rows, Solver, SweepRow};
use crate::scene::frequency::{FrequencyBounds, FrequencyError};
use crate::scene::lyapunov::{check_periods, spectrum, structure_spectrum};
use crate::scene::simulator::{model, rest, run, run_structure, SimulatedPoint};
use crate::scene::structure::StructureForm;
use crate::scene::{AnyScene, Scene, SceneError};
use crate::verdict::chain::chain_cross_check;
use crate::verdict::structure::{record as structure_compare_record, structure_cross_check};
use crate::verdict::{chain::ChainCheck, cross_check};
use rattle_event_driven::SimulationOptions;
use rattle_event_driven::{final_cycle_trajectory, sample_trajectory, TrajectoryOptions};
use serde::{Serialize, Serializer};
use std::path::Path;
use thiserror::Error;

mod basins;
mod branches;
mod maps;
mod orbits;
mod respond;
mod transmission;

pub use basins::{basins, plane_basins};
pub use branches::{boundary, continuation, Continuation, ContinuedBranches};
pub use maps::{map, map_document};
pub use orbits::{orbit_trajectory, orbits, signature_orbits, Orbits, SignatureOrbits};
pub use respond::{
    prepare_response, respond, PreparedResponse, ResponseRequest, DEFAULT_MAX_SAMPLES,
    DEFAULT_SAMPLES_PER_PERIOD,
};
pub use transmission::{
    merge_transmission, prepare_transmission, transmission, PreparedTransmission,
    TransmissionOptions, TransmissionPart, TransmissionRequest,
};

/// A facade call that did not give its result.
///
/// [`ApiError::Scene`], [`ApiError::Frequency`] and [`ApiError::Argument`] are the caller's
/// (bad input, each message naming the scene's field, or the parameter as the `rattle`
/// command's option spells it (`--omega`, `--signature`), and its allowed range);
/// [`ApiError::Numerical`] is a solver's failure; [`ApiError::Write`] an output that could
/// not be written.
#[derive(Debug, Error)]
pub enum ApiError {
    /// The scene is unreadable or invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// A frequency the scene cannot be run at in bounded time.
    #[error(transparent)]
    Frequency(#[from] FrequencyError),
    /// A parameter out of its range, or a request the scene does not admit; the message names
    /// the parameter and what it must be.
    #[error("{0}")]
    Argument(String),
    /// A solver failed; the message says why.
    #[error("numerical failure: {0}")]
    Numerical(String),
    /// A table could not be written to its writer.
    #[error("cannot write the {table} table: {source}")]
    Write {
        /// Which table.
        table: Table,
        /// The writer's error.
        #[source]
        source: std::io::Error,
    },
}

/// The tables [`map`] and [`basins`] write, to say which one failed in [`ApiError::Write`].
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Table {
    /// Every point of a map, or every start of a basins grid.
    Points,
    /// The attenuation bandwidth of every line of a map.
    Bandwidth,
}

impl std::fmt::Display for Table {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Table::Points => "points",
            Table::Bandwidth => "bandwidth",
        })
    }
}

/// A numerical failure carrying `e`'s message.
fn numerical(e: impl std::fmt::Display) -> ApiError {
    ApiError::Numerical(e.to_string())
}

/// Bad input carrying `e`'s message.
fn argument(e: impl std::fmt::Display) -> ApiError {
    ApiError::Argument(e.to_string())
}

/// Reads and validates the scene file at `path`, in either form (cells or structure).
///
/// # Errors
/// [`ApiError::Scene`]: the file cannot be read, is not JSON of the scene format (line and
/// column), or a value is out of range (its JSON path and allowed range).
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::scene::AnyScene;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/impact-oscillator.json");
/// let scene = api::load(path)?;
/// assert!(matches!(scene, AnyScene::Structure(_)));
///
/// let missing = api::load("no-such-scene.json").unwrap_err();
/// assert!(missing.to_string().contains("no-such-scene.json"));
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn load(path: impl AsRef<Path>) -> Result<AnyScene, ApiError> {
    Ok(AnyScene::load(path.as_ref())?)
}

/// Parses and validates a scene given as JSON text, in either form; error messages name it
/// `text`.
///
/// # Errors
/// [`ApiError::Scene`], as [`load`].
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
///
/// let scene = api::parse(r#"{
///     "name": "inline",
///     "unit": {"outer_mass": 1.0, "inner_mass": 0.5,
///              "outer_stiffness": 1.0, "inner_stiffness": 2.0},
///     "base": {"amplitude": 1.0},
///     "stops": {"gap": 0.5, "restitution": 0.8}
/// }"#)?;
/// assert_eq!(scene.name(), "inline");
///
/// // A value out of range is refused with its field and its range.
/// let bad = api::parse(r#"{
///     "name": "bad",
///     "unit": {"outer_mass": -1.0, "inner_mass": 0.5,
///              "outer_stiffness": 1.0, "inner_stiffness": 2.0},
///     "base": {"amplitude": 1.0}
/// }"#).unwrap_err();
/// assert!(bad.to_string().contains("unit.outer_mass"));
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn parse(text: &str) -> Result<AnyScene, ApiError> {
    Ok(AnyScene::parse(text, "text")?)
}

/// `omega` if it is finite and positive and `scene` can be run at it in bounded time
/// ([`FrequencyBounds`]); errors name the frequency `name` (the command passes `--omega`).
///
/// # Errors
/// [`ApiError::Frequency`] naming `name`, with the allowed range.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::scene::{AnyScene, Scene};
///
/// let scene = AnyScene::Cells(Scene::paper());
/// assert_eq!(api::check_frequency(&scene, "omega", 2.0)?, 2.0);
/// let refused = api::check_frequency(&scene, "omega", -1.0).unwrap_err();
/// assert!(refused.to_string().starts_with("omega = -1"));
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn check_frequency(scene: &AnyScene, name: &str, omega: f64) -> Result<f64, ApiError> {
    match scene {
        AnyScene::Cells(scene) => check_cells_frequency(scene, name, omega),
        AnyScene::Structure(form) => {
            Ok(FrequencyBounds::of_structure(&form.structure).check(name, omega)?)
        }
    }
}

/// [`check_frequency`] on a scene of the cells form.
fn check_cells_frequency(scene: &Scene, name: &str, omega: f64) -> Result<f64, ApiError> {
    Ok(FrequencyBounds::of(scene).check(name, omega)?)
}

/// The cells form of `scene`, or bad input naming `call` for a structure.
fn cells<'a>(scene: &'a AnyScene, call: &str) -> Result<&'a Scene, ApiError> {
    match scene {
        AnyScene::Cells(scene) => Ok(scene),
        AnyScene::Structure(_) => Err(ApiError::Argument(format!(
            "{call} is not taken on a scene in the structure form yet: it is taken on the unit \
             and chain forms"
        ))),
    }
}

/// What [`simulate`] found: the simulator's own report and the record `rattle simulate
/// --json` prints (serializing a `Simulation` gives that record).
#[derive(Debug, Clone)]
pub enum Simulation {
    /// A unit or a chain of cells.
    Cells {
        /// The simulator's report.
        point: SimulatedPoint,
        /// The command's record.
        record: SimulationRecord,
    },
    /// A structure.
    Structure {
        /// The simulator's report.
        point: SimulatedPoint,
        /// The command's record.
        record: StructureSimulationRecord,
    },
}

impl Simulation {
    /// The simulator's report: the regime, the steady state, amplitudes and transmittance.
    pub fn point(&self) -> &SimulatedPoint {
        match self {
            Simulation::Cells { point, .. } | Simulation::Structure { point, .. } => point,
        }
    }
}

impl Serialize for Simulation {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        match self {
            Simulation::Cells { record, .. } => record.serialize(s),
            Simulation::Structure { record, .. } => record.serialize(s),
        }
    }
}

/// The event-driven simulator on `scene` at `omega` from rest (a structure from its rest
/// state), run until the motion is periodic or a cap (or for `options.fixed_periods`
/// periods): `rattle simulate`. A structure's periodic motion is reported from the cycle the
/// simulator's Newton polishes, when it polishes it.
///
/// # Errors
/// [`ApiError::Frequency`] for a frequency the scene cannot be run at (named `--omega`);
/// [`ApiError::Numerical`] when the simulator refuses the model, the start or the options,
/// or meets an unresolved accumulation of impacts.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::scene::{AnyScene, Scene};
/// use rattle_event_driven::SimulationOptions;
///
/// let scene = AnyScene::Cells(Scene::paper());
/// // Eight forcing periods exactly, the steady state judged from their tail.
/// let options = SimulationOptions { fixed_periods: Some(8), ..SimulationOptions::default() };
/// let sim = api::simulate(&scene, 2.0, &options)?;
/// let api::Simulation::Cells { record, .. } = &sim else { unreachable!() };
/// assert_eq!(record.periods_run, 8);
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn simulate(
    scene: &AnyScene,
    omega: f64,
    options: &SimulationOptions,
) -> Result<Simulation, ApiError> {
    let omega = check_frequency(scene, "--omega", omega)?;
    match scene {
        AnyScene::Cells(scene) => {
            let point = run(scene, omega, &rest(scene), options).map_err(numerical)?;
            let record = SimulationRecord::new(scene, &point);
            Ok(Simulation::Cells { point, record })
        }
        AnyScene::Structure(form) => {
            let structure = &form.structure;
            let point =
                run_structure(structure, omega, &structure.rest(), options).map_err(numerical)?;
            let polished = point.steady.orbit.is_some();
            let record = StructureSimulationRecord::new(&form.scene, structure, &point, polished);
            Ok(Simulation::Structure { point, record })
        }
    }
}

/// A cycle sampled in time: the two tables `--trajectory` and `--impacts` write.
#[derive(Debug, Clone)]
pub enum TrajectoryTables {
    /// A unit or a chain: one row per cell at each time, every impact as two rows.
    Cells {
        /// The states, columns `t, kind, cell, base, u_o, u_i, v_o, v_i, r`.
        rows: Vec<TrajectoryRow>,
        /// The impacts.
        impacts: Vec<ImpactRow>,
    },
    /// A structure: a column per body and per stop.
    Structure {
        /// The states.
        states: NamedTable,
        /// The impacts.
        impacts: NamedTable,
    },
}

/// Which stretch of a simulated motion [`simulation_trajectory`] samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stretch {
    /// The final cycle of the run (its last period with `options.fixed_periods`).
    FinalCycle,
    /// This many forcing periods continued from where the run ended: with one sample per
    /// period, the samples are the stroboscopic (Poincaré) section at `t = kT` and the
    /// impacts the impact map of the settled motion, periodic or not.
    Continued(u64),
}

/// Most rows of uniform samples [`simulation_trajectory`] writes for a continued stretch
/// (periods × samples per period): ten million rows of a two-body CSV are about a gigabyte.
pub const MAX_CONTINUED_SAMPLES: u64 = 10_000_000;

/// A stretch of `simulation` sampled from the closed form between events, `samples_per_period`
/// uniform samples per forcing period plus every impact: the final cycle, or a stretch
/// continued from where the run ended (`rattle simulate --trajectory`, with
/// `--sampled-periods`). `options` are those of the run.
///
/// # Errors
/// [`ApiError::Argument`] naming `--samples-per-period` outside
/// `[1, MAX_SAMPLES_PER_PERIOD]`, or `--sampled-periods` of zero or with more than
/// [`MAX_CONTINUED_SAMPLES`] samples; [`ApiError::Numerical`] when the stretch cannot be run.
pub fn simulation_trajectory(
    scene: &AnyScene,
    simulation: &Simulation,
    samples_per_period: u64,
    stretch: Stretch,
    options: &SimulationOptions,
) -> Result<TrajectoryTables, ApiError> {
    crate::output::trajectory::check_samples_per_period(samples_per_period.into())
        .map_err(ApiError::Argument)?;
    if let Stretch::Continued(periods) = stretch {
        if periods == 0 || periods.saturating_mul(samples_per_period) > MAX_CONTINUED_SAMPLES {
            return Err(ApiError::Argument(format!(
                "--sampled-periods = {periods} is out of range: must be ≥ 1, with at most \
                 {MAX_CONTINUED_SAMPLES} samples (periods × --samples-per-period = {samples_per_period})"
            )));
        }
    }
    let sim = simulation.point();
    let sample = |m: &rattle_event_driven::Model, base_amplitude| {
        let sampling = TrajectoryOptions {
            periods: 1,
            samples_per_period,
            base_amplitude,
            simulation: options.clone(),
        };
        match stretch {
            Stretch::FinalCycle => final_cycle_trajectory(m, sim.omega, &sim.steady, &sampling),
            Stretch::Continued(periods) => sample_trajectory(
                m,
                sim.omega,
                &sim.steady.final_state,
                &TrajectoryOptions {
                    periods,
                    ..sampling
                },
            ),
        }
        .map_err(numerical)
    };
    match scene {
        AnyScene::Cells(scene) => {
            let m = model(scene, sim.omega).map_err(numerical)?;
            let trajectory = sample(&m, scene.base.amplitude)?;
            let (rows, impacts) = simulated_rows(&trajectory, &scene.cell_pairs());
            Ok(TrajectoryTables::Cells { rows, impacts })
        }
        AnyScene::Structure(form) => {
            let structure = &form.structure;
            let m = structure.event_model(sim.omega).map_err(numerical)?;
            let trajectory = sample(&m, structure.base_amplitude.unwrap_or(0.0))?;
            let (states, impacts) = structure_trajectory(structure, &trajectory);
            Ok(TrajectoryTables::Structure { states, impacts })
        }
    }
}

/// The Lyapunov exponents of `simulation` over `periods` more forcing periods from its end
/// state: `rattle simulate --lyapunov`. `options` are those of the run. A structure has two
/// exponents per body. A free body that no impact touches has a pair of exponents of exactly
/// zero (its translation grows as `v t`, not exponentially), which a run of time `t`
/// approaches only as `log t / t`, more slowly than the batches' uncertainty says: on the
/// gallery's impact damper at ω = 1.25 rad/s, 200 periods give `±0.0011 ± 0.0002` 1/s.
///
/// # Errors
/// [`ApiError::Argument`] for fewer periods than the exponents need (named
/// `--lyapunov-periods`, with the range); [`ApiError::Numerical`] when the exponents' run
/// fails.
pub fn lyapunov(
    scene: &AnyScene,
    simulation: &Simulation,
    periods: u64,
    options: &SimulationOptions,
) -> Result<LyapunovRecord, ApiError> {
    check_periods(periods).map_err(argument)?;
    let sim = simulation.point();
    let spectrum = match scene {
        AnyScene::Cells(scene) => spectrum(scene, sim, periods, options),
        AnyScene::Structure(form) => structure_spectrum(&form.structure, sim, periods, options),
    }
    .map_err(numerical)?;
    Ok(LyapunovRecord::new(sim, &spectrum))
}

/// Both solvers on the motion `scene` settles on at `omega` and the verdict between them
/// ([`compare`]); serializing it gives the record `rattle compare --json` prints.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Comparison {
    /// A single unit: the simulated cycle, the analytic orbit of its signature, the class.
    Unit(CrossCheckRecord),
    /// A chain: the simulated cycle beside the analytic orbit of its impact sequence.
    Chain(ChainCompareRecord),
    /// A structure: as a chain's, every body named.
    Structure(StructureCompareRecord),
}

impl Comparison {
    /// The verdict's class: `agreement`, `disagreement`, … (the record's `class`).
    pub fn class(&self) -> &'static str {
        match self {
            Comparison::Unit(r) => r.class,
            Comparison::Chain(r) => r.class,
            Comparison::Structure(r) => r.class,
        }
    }
}

/// Both solvers on the motion `scene` settles on at `omega`, whatever its impact signature:
/// the simulator from rest with its own Newton-polished cycle, the analytic orbit of that
/// signature (a chain's or structure's: of its impact sequence) solved from the simulated
/// impact phases, and the verdict: `rattle compare`.
///
/// # Errors
/// [`ApiError::Frequency`] naming `--omega`; [`ApiError::Numerical`] when the simulator fails
/// (the analytic solver's failure is part of the record, not an error).
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::scene::{AnyScene, Scene};
/// use rattle_event_driven::SimulationOptions;
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let check = api::compare(&scene, 2.0, &SimulationOptions::default())?;
/// assert_eq!(check.class(), "agreement");
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn compare(
    scene: &AnyScene,
    omega: f64,
    options: &SimulationOptions,
) -> Result<Comparison, ApiError> {
    let omega = check_frequency(scene, "--omega", omega)?;
    match scene {
        AnyScene::Structure(form) => {
            let check =
                structure_cross_check(&form.structure, omega, options).map_err(numerical)?;
            Ok(Comparison::Structure(structure_compare_record(
                &form.scene,
                &form.structure,
                &check,
            )))
        }
        AnyScene::Cells(scene) if scene.is_chain() => {
            let check: ChainCheck = chain_cross_check(scene, omega, options).map_err(numerical)?;
            Ok(Comparison::Chain(check.record(scene)))
        }
        AnyScene::Cells(scene) => {
            let check = cross_check(scene, omega, options).map_err(numerical)?;
            Ok(Comparison::Unit(check.record(scene)))
        }
    }
}

/// The rows of a frequency sweep ([`sweep`]), in frequency order; serializing it gives the
/// rows as a JSON array.
#[derive(Debug, Clone, Serialize)]
#[serde(untagged)]
pub enum Sweep {
    /// A unit's or a chain's rows.
    Cells(Vec<SweepRow>),
    /// A structure's rows.
    Structure(Vec<StructureSweepRow>),
}

impl Sweep {
    /// How many rows.
    pub fn len(&self) -> usize {
        match self {
            Sweep::Cells(rows) => rows.len(),
            Sweep::Structure(rows) => rows.len(),
        }
    }

    /// No rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Every frequency of `omegas` checked against `bounds`, each named `omegas[i]`.
fn check_frequencies(bounds: &FrequencyBounds, omegas: &[f64]) -> Result<(), ApiError> {
    for (i, &omega) in omegas.iter().enumerate() {
        bounds.check(&format!("omegas[{i}]"), omega)?;
    }
    Ok(())
}

/// `solver` at every frequency of `omegas`, in parallel on rayon's pool, the rows in order:
/// `rattle sweep` (`both`: the verdict of [`compare`] at every frequency).
///
/// # Errors
/// [`ApiError::Frequency`] naming `omegas[i]`, the first frequency the scene cannot be run
/// at. A point whose solver fails is a row that says so, not an error.
///
/// # Examples
///
/// ```
/// use rattle_compare::api;
/// use rattle_compare::runs::sweep::Solver;
/// use rattle_compare::scene::{AnyScene, Scene};
/// use rattle_event_driven::SimulationOptions;
///
/// let scene = AnyScene::Cells(Scene::paper());
/// let rows = api::sweep(&scene, &[1.5, 2.0, 2.5], Solver::Analytic, &SimulationOptions::default())?;
/// assert_eq!(rows.len(), 3);
/// let api::Sweep::Cells(rows) = rows else { unreachable!() };
/// assert_eq!(rows[1].omega, Some(2.0));
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
pub fn sweep(
    scene: &AnyScene,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
) -> Result<Sweep, ApiError> {
    match scene {
        AnyScene::Cells(s) => {
            let mut rows = Vec::with_capacity(omegas.len());
            sweep_each(s, omegas, solver, options, &Progress::hidden(), |row| {
                rows.push(row);
                Ok::<_, ApiError>(())
            })?;
            Ok(Sweep::Cells(rows))
        }
        AnyScene::Structure(form) => {
            let mut rows = Vec::with_capacity(omegas.len());
            structure_sweep_each(form, omegas, solver, options, &Progress::hidden(), |row| {
                rows.push(row);
                Ok::<_, ApiError>(())
            })?;
            Ok(Sweep::Structure(rows))
        }
    }
}

/// [`sweep`] on a unit or a chain with every row handed to `each` as soon as it and those
/// before it are done (to stream them to a file), `progress` told of every point.
///
/// # Errors
/// [`ApiError::Frequency`] as [`sweep`], converted to `E`; the first error of `each`, which
/// stops the sweep.
pub fn sweep_each<E: From<ApiError>>(
    scene: &Scene,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
    progress: &Progress,
    each: impl FnMut(SweepRow) -> Result<(), E>,
) -> Result<(), E> {
    check_frequencies(&FrequencyBounds::of(scene), omegas)?;
    sweep_rows(scene, omegas, solver, options, progress, each)
}

/// [`sweep_each`] on a structure.
///
/// # Errors
/// As [`sweep_each`].
pub fn structure_sweep_each<E: From<ApiError>>(
    form: &StructureForm,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
    progress: &Progress,
    each: impl FnMut(StructureSweepRow) -> Result<(), E>,
) -> Result<(), E> {
    check_frequencies(&FrequencyBounds::of_structure(&form.structure), omegas)?;
    structure_sweep_rows(&form.structure, omegas, solver, options, progress, each)
}
