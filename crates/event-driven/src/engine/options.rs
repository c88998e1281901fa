//! What a run is asked: the options, the start, the errors, and the checks on them.

use super::*;

/// How the simulator runs and when it calls a motion steady.
#[derive(Debug, Clone, PartialEq)]
pub struct SimulationOptions {
    /// Contact times are resolved to `root_tolerance × T` (the accuracy knob).
    pub root_tolerance: f64,
    /// The motion is periodic when the stroboscopic state repeats to this relative tolerance.
    pub periodicity_tolerance: f64,
    /// Cap on forcing periods when running until steady (undamped elastic units, which cannot
    /// settle, at most [`CONSERVATIVE_MAX_PERIODS`]).
    pub max_periods: u64,
    /// Cap on events (impacts, stick and release) when running until steady: bounds the time
    /// of motions with very many events per period. `None`: no cap.
    pub max_events: Option<u64>,
    /// Cap on the free oscillations of the fastest mode when running until steady, counted as
    /// periods × `ω_fastest/ω`: transients decay on the natural time scale, and a forcing far
    /// below the natural frequencies (thousands of oscillations per period) would otherwise
    /// make [`Self::max_periods`] periods cost minutes. `None`: no cap.
    pub max_oscillations: Option<f64>,
    /// Largest period multiplicity `p` looked for (also the length, in periods, of the final
    /// stretch observed when no period is found).
    pub max_period_multiplicity: u32,
    /// Run exactly this many periods and judge the steady state from the tail.
    pub fixed_periods: Option<u64>,
    /// Keep dense samples of the final cycle (or the final
    /// [`Self::max_period_multiplicity`] periods), [`SAMPLES_PER_PERIOD`] per period.
    pub record_trajectory: bool,
    /// Polish a periodic final cycle (not sticking) with Newton on the stroboscopic map
    /// ([`crate::newton::periodic_orbit`]), once at the end of the run, into
    /// [`SteadyState::orbit`], and read [`SteadyState::amplitudes`] from one cycle run from
    /// the polished orbit. Every other output is unchanged by it.
    pub polish: bool,
}

/// Default [`SimulationOptions::root_tolerance`]: contact times to `1e-12 T`, a few thousand
/// rounding units of a time within the period, so the contact states are accurate to about the
/// rounding of the state itself.
pub const DEFAULT_ROOT_TOLERANCE: f64 = 1e-12;

/// Default [`SimulationOptions::periodicity_tolerance`]: three orders above the root tolerance,
/// so the state error left by the contact times cannot fake or hide a repetition. The damped
/// paper unit at ω = 2 repeats to it after 138 periods (README, performance table).
pub const DEFAULT_PERIODICITY_TOLERANCE: f64 = 1e-9;

/// Default [`SimulationOptions::max_periods`]: two orders above the 138 periods the damped paper
/// unit needs at ω = 2, for slower transients near resonance, while a run that never settles
/// stops within about a second (README, extreme-scene table: 0.7–1.4 s at the period cap).
pub const DEFAULT_MAX_PERIODS: u64 = 20_000;

/// Default [`SimulationOptions::max_events`]: about two seconds of events at the measured
/// ~1M impacts/s, the bound for motions with very many events per period (chatter on tiny gaps:
/// README, extreme-scene table, 1.3–2.5 s at the event cap).
pub const DEFAULT_MAX_EVENTS: u64 = 2_000_000;

/// Default [`SimulationOptions::max_oscillations`]: 20 000 periods near the natural frequencies
/// hold some 1e4 free oscillations, so transients get as many natural oscillations as there
/// at any forcing frequency, while a forcing far below them stays bounded (e = 0 undamped at
/// ω = 0.001, ~2400 oscillations per period: 816 periods, 1.4 s).
pub const DEFAULT_MAX_OSCILLATIONS: f64 = 2e6;

/// Default [`SimulationOptions::max_period_multiplicity`]: `rattle simulate` reports least
/// periods up to 16. The stroboscopic history is `p + 2` sections long and the periodicity test
/// tries every multiplicity up to it at each section, so it also bounds that cost.
pub const DEFAULT_MAX_PERIOD_MULTIPLICITY: u32 = 16;

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            root_tolerance: DEFAULT_ROOT_TOLERANCE,
            periodicity_tolerance: DEFAULT_PERIODICITY_TOLERANCE,
            max_periods: DEFAULT_MAX_PERIODS,
            max_events: Some(DEFAULT_MAX_EVENTS),
            max_oscillations: Some(DEFAULT_MAX_OSCILLATIONS),
            max_period_multiplicity: DEFAULT_MAX_PERIOD_MULTIPLICITY,
            fixed_periods: None,
            record_trajectory: false,
            polish: true,
        }
    }
}

/// Where a simulation starts: the state `(u, u̇)` at time `time` (forcing phase `ω·time`).
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// `(u, u̇)`, length `2n`.
    pub state: DVector<f64>,
    /// Start time; only `ω·time` modulo `2π` matters.
    pub time: f64,
}

impl Start {
    /// At rest at `t = 0`, for `n` degrees of freedom.
    pub fn rest(n: usize) -> Start {
        Start {
            state: DVector::zeros(2 * n),
            time: 0.0,
        }
    }

    /// On the linear steady state of `model` at `omega` (its motion without contacts, every
    /// free transient decayed) at `t = 0`: [`LinearFlow::linear_steady_state`]. With free
    /// bodies (rigid modes) that steady state is a family, each rigid mode free to sit at any
    /// constant position: this start is its zero-mean member, each rigid mode on the harmonic
    /// particular solution `q = −Re(F e^{iωt})/ω²` alone (a body in a clearance starts
    /// centred on its mean position zero).
    ///
    /// # Errors
    /// [`SimulationError::Omega`] for an `omega` that is not finite and positive, and
    /// [`SimulationError::Flow`] when the modal flow does not exist, a mode is resonant with
    /// the forcing ([`FlowError::Resonant`]) or a constant force drives a rigid mode
    /// ([`FlowError::RigidDrift`]).
    pub fn linear_steady_state(model: &Model, omega: f64) -> Result<Start, SimulationError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(SimulationError::Omega(omega));
        }
        let flow = LinearFlow::of_model(model, omega)?;
        Ok(Start {
            state: flow.linear_steady_state(0.0)?,
            time: 0.0,
        })
    }
}

/// A failure of the simulation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SimulationError {
    /// The frequency is not finite and positive.
    #[error("omega = {0} is out of range: must be finite and > 0")]
    Omega(f64),
    /// The start state has the wrong length or is not finite.
    #[error("start state: {0}")]
    Start(String),
    /// An option is out of range.
    #[error("option {0}")]
    Option(String),
    /// The modal flow does not exist.
    #[error("flow: {0}")]
    Flow(#[from] FlowError),
    /// Impacts accumulated without a resolution (more than [`EVENT_STORM`] in one period).
    #[error("more than {0} events in one forcing period at t = {1}: an unresolved accumulation")]
    EventStorm(u64, f64),
    /// The pairs to be held at once constrain dependent directions (or all of them): no
    /// constrained flow exists for them.
    #[error("cannot hold contact pairs {0:?} at once: their directions are dependent")]
    DependentHolds(Vec<usize>),
    /// A model value out of range for this run: a compliant stop too stiff for the forcing
    /// frequency ([`Model::check_compliance`]).
    #[error("model: {0}")]
    Model(#[from] crate::model::ModelError),
    /// A rigid pair would stick on its stop while a compliant pair is in contact, or a
    /// compliant pair would enter contact while a rigid pair is held on its stop, at this
    /// time: a hold and a compliant contact at once are not simulated.
    #[error("a rigid hold and a compliant contact at once at t = {0}: not simulated")]
    HoldWithCompliantContact(f64),
}

/// Undamped elastic units (nothing dissipates) are run at most this many periods: no steady
/// state can be reached, and 1000 periods are enough to report the motion's last stretch.
pub const CONSERVATIVE_MAX_PERIODS: u64 = 1000;

/// The oscillation cap never cuts a run below this many periods: enough sections to judge a
/// repetition of multiplicity up to [`DEFAULT_MAX_PERIOD_MULTIPLICITY`] several times over.
pub const MIN_OSCILLATION_PERIODS: u64 = 64;

/// More events than this in one forcing period is an unresolved accumulation
/// ([`SimulationError::EventStorm`]): a chatter sticks once its remaining bounces fit in `1e-5`
/// of a period, after about `ln(1e5)/ln(1/e)` bounces from a flight of a period (~50 at
/// `e = 0.8`, ~1100 at `e = 0.99`), so a million means the accumulation was not detected.
pub const EVENT_STORM: u64 = 1_000_000;

/// Dense samples per forcing period in [`SteadyState::trajectory`] (ends of each segment
/// included): enough to draw a period's motion smoothly.
pub const SAMPLES_PER_PERIOD: f64 = 200.0;

/// The checks of [`crate::simulate()`] on its inputs.
///
/// # Errors
/// As [`crate::simulate()`]: [`SimulationError::Omega`], [`SimulationError::Start`],
/// [`SimulationError::Option`], and [`SimulationError::Model`] for a compliant stop too stiff
/// for `omega` ([`Model::check_compliance`]).
pub(crate) fn check_inputs(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> Result<(), SimulationError> {
    if !(omega.is_finite() && omega > 0.0) {
        return Err(SimulationError::Omega(omega));
    }
    let n = model.dofs();
    if start.state.len() != 2 * n
        || start.state.iter().any(|v| !v.is_finite())
        || !start.time.is_finite()
    {
        return Err(SimulationError::Start(format!(
            "must be {} finite numbers and a finite time",
            2 * n
        )));
    }
    let in_unit = |x: f64| x > 0.0 && x < 1.0;
    if !in_unit(options.root_tolerance)
        || !in_unit(options.periodicity_tolerance)
        || options.max_period_multiplicity == 0
    {
        return Err(SimulationError::Option(
            "tolerances must be in (0, 1), multiplicity ≥ 1".into(),
        ));
    }
    model.check_compliance(omega)?;
    Ok(())
}
