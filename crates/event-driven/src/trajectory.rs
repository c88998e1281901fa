//! Exact trajectories: a stretch of the simulator's own run sampled from its closed form.
//!
//! The samples come from the simulator's event loop itself (a traced run of the same engine,
//! not a second integrator): each free flight or stuck phase is sampled from its closed form at
//! the uniform times `t = jT/N` that fall inside it, and each event adds its own rows at its
//! time: the state just before and just after an impact (so a plot shows the velocity jump),
//! and just after a stick. Rows carry the base displacement, the displacements, the velocities
//! and each contact pair's relative displacement `r = d·u`; the impacts are listed with their
//! pair, side, approach velocity `ṙ⁻` and the state before.

pub use crate::engine::RowKind;
use crate::engine::{check_inputs, Engine, SimulationError, SimulationOptions, Start, SteadyState};
use crate::model::Model;
use crate::newton::shifted;
use thiserror::Error;

/// Default [`TrajectoryOptions::samples_per_period`]: enough to draw a period's motion
/// smoothly (the simulator's own dense output uses as many, `SAMPLES_PER_PERIOD`).
pub const DEFAULT_SAMPLES_PER_PERIOD: u64 = 200;

/// At most this many uniform samples in one trajectory (periods × samples per period): 10⁷
/// rows of a few numbers each are already hundreds of megabytes of CSV.
pub const MAX_TRAJECTORY_SAMPLES: u64 = 10_000_000;

/// What to sample.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryOptions {
    /// Forcing periods sampled, at least 1.
    pub periods: u64,
    /// Uniform samples per period, at least 1 (events add their own rows).
    pub samples_per_period: u64,
    /// The base motion `u_g cos ωt` for the `base` column (the two-degree-of-freedom unit's
    /// `u_g`; the model itself only knows the force it causes). `0` for a model without one.
    pub base_amplitude: f64,
    /// The simulator's options (contact times to its `root_tolerance`).
    pub simulation: SimulationOptions,
}

impl Default for TrajectoryOptions {
    fn default() -> Self {
        Self {
            periods: 1,
            samples_per_period: DEFAULT_SAMPLES_PER_PERIOD,
            base_amplitude: 0.0,
            simulation: SimulationOptions::default(),
        }
    }
}

/// One row: the state at a time.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryRow {
    /// Time since the start (a section of the forcing phase of the start), in s.
    pub time: f64,
    /// A uniform sample, or an event's state before or after.
    pub kind: RowKind,
    /// The base displacement `u_g cos ω(t₀ + t)`.
    pub base: f64,
    /// `u`, one per degree of freedom.
    pub displacements: Vec<f64>,
    /// `u̇`, one per degree of freedom.
    pub velocities: Vec<f64>,
    /// Each contact pair's relative displacement `r = u[plus] − u[minus]`.
    pub relative: Vec<f64>,
}

/// One impact of the stretch.
#[derive(Debug, Clone, PartialEq)]
pub struct TrajectoryImpact {
    /// Time since the start, in s.
    pub time: f64,
    /// The contact pair.
    pub pair: usize,
    /// `+1` side 1 (`r = +gap_plus`), `−1` side 2.
    pub side: i8,
    /// `ṙ⁻`, the relative velocity just before.
    pub relative_velocity_before: f64,
    /// `u` at the impact.
    pub displacements: Vec<f64>,
    /// `u̇` just before.
    pub velocities_before: Vec<f64>,
}

/// A sampled stretch of motion.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// The rows in time order; rows of one event share its time.
    pub rows: Vec<TrajectoryRow>,
    /// The impacts in time order.
    pub impacts: Vec<TrajectoryImpact>,
    /// The forcing period `T`, in s.
    pub period: f64,
    /// The start's time within the forcing period (`t₀`), in s: row times are counted from it.
    pub phase: f64,
}

/// Why no trajectory was sampled.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum TrajectoryError {
    /// The inputs, the flow or the run failed.
    #[error("simulation: {0}")]
    Simulation(#[from] SimulationError),
    /// A count out of range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    OutOfRange {
        /// Which option.
        field: &'static str,
        /// Its value.
        value: u64,
        /// The allowed range.
        allowed: String,
    },
    /// The base amplitude is not finite.
    #[error("base_amplitude = {0} is out of range: must be finite")]
    BaseAmplitude(f64),
}

/// Samples `options.periods` periods of `model`'s motion at `omega` from `start` (its time
/// fixes the forcing phase; row times count from it).
///
/// # Errors
/// [`TrajectoryError::Simulation`] for inputs [`crate::simulate()`] refuses or a failed run,
/// [`TrajectoryError::OutOfRange`] for zero periods or samples per period, or more than
/// [`MAX_TRAJECTORY_SAMPLES`] samples, and [`TrajectoryError::BaseAmplitude`] for a non-finite base
/// amplitude.
pub fn sample_trajectory(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &TrajectoryOptions,
) -> Result<Trajectory, TrajectoryError> {
    check_inputs(model, omega, start, &options.simulation)?;
    let out_of_range = |field, value, allowed: String| TrajectoryError::OutOfRange {
        field,
        value,
        allowed,
    };
    if options.periods == 0 {
        return Err(out_of_range("periods", 0, ">= 1".into()));
    }
    if options.samples_per_period == 0 {
        return Err(out_of_range("samples_per_period", 0, ">= 1".into()));
    }
    let samples = options.periods.saturating_mul(options.samples_per_period);
    if samples > MAX_TRAJECTORY_SAMPLES {
        return Err(out_of_range(
            "periods × samples_per_period",
            samples,
            format!("<= {MAX_TRAJECTORY_SAMPLES}"),
        ));
    }
    if !options.base_amplitude.is_finite() {
        return Err(TrajectoryError::BaseAmplitude(options.base_amplitude));
    }
    let period = std::f64::consts::TAU / omega;
    let phase = start.time.rem_euclid(period);
    let shifted_model = shifted(model, omega, phase);
    let mut engine = Engine::new(&shifted_model, omega, &options.simulation)?;
    let trace = engine.trace_run(&start.state, options.periods, options.samples_per_period)?;
    let n = model.dofs();
    let pairs = model.contacts();
    let relative = |y: &nalgebra::DVector<f64>| -> Vec<f64> {
        pairs
            .iter()
            .map(|c| c.relative(&y.as_slice()[..n]))
            .collect()
    };
    let rows = trace
        .rows
        .iter()
        .map(|(t, kind, y)| TrajectoryRow {
            time: *t,
            kind: *kind,
            base: options.base_amplitude * crate::trig::sin_cos(omega * (phase + t)).1,
            displacements: y.rows(0, n).iter().copied().collect(),
            velocities: y.rows(n, n).iter().copied().collect(),
            relative: relative(y),
        })
        .collect();
    let impacts = trace
        .impacts
        .iter()
        .map(|i| TrajectoryImpact {
            time: i.time,
            pair: i.pair,
            side: i.side,
            relative_velocity_before: i.relative_velocity,
            displacements: i.state_before.rows(0, n).iter().copied().collect(),
            velocities_before: i.state_before.rows(n, n).iter().copied().collect(),
        })
        .collect();
    Ok(Trajectory {
        rows,
        impacts,
        period,
        phase,
    })
}

/// The final cycle of a run `steady` of `model` at `omega` (its last [`SteadyState::period`]
/// periods, or its observed final stretch), sampled from the cycle's first section
/// ([`SteadyState::stroboscopic`]); `options.periods` is replaced by the cycle's length.
///
/// # Errors
/// As [`sample_trajectory`].
pub fn final_cycle_trajectory(
    model: &Model,
    omega: f64,
    steady: &SteadyState,
    options: &TrajectoryOptions,
) -> Result<Trajectory, TrajectoryError> {
    let (state, periods) = match steady.stroboscopic.first() {
        Some(first) if steady.stroboscopic.len() > 1 => {
            (first.clone(), steady.stroboscopic.len() as u64 - 1)
        }
        _ => (steady.final_state.state.clone(), 1),
    };
    let start = Start {
        state,
        time: steady.final_state.time,
    };
    sample_trajectory(
        model,
        omega,
        &start,
        &TrajectoryOptions {
            periods,
            ..options.clone()
        },
    )
}
