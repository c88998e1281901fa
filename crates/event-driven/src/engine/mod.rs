//! The event loop: exact flights, first contacts, restitution, chatter and sticking, and the
//! steady state seen through the stroboscopic map at `t = kT`.
//!
//! The run is split the way iterative solvers are: the *problem* (a [`Model`], `ω` and the
//! [`SimulationOptions`]), the *solver* (`Engine`: the free flow, the contact geometry and the
//! stuck flows, prepared once) and the *state* (`RunState`: everything that changes during a
//! run). The loop is `init`, then `next_iter` (one free flight or one stuck phase, ending at an
//! event or at the section `t = kT`) and, at each section, `terminate` (the stopping rules, all
//! in `stopping_rule`). The events are named points: `impact`, `stick` and `release`, and each
//! flight is one closed-form segment. A run asked for its tangent flow (`Engine::tangent_run`,
//! used by [`crate::newton`]) multiplies the Jacobian by each flight's propagator and each
//! impact's saltation matrix, at a stick by the plastic saltation onto the held pair's
//! constrained tangent space and while held by the reduced propagator (a run that sticks has
//! no invertible Jacobian, which [`crate::newton`] refuses; [`crate::lyapunov`] counts the
//! collapsed directions); ordinary runs carry no tangent and only test for its absence. A
//! traced run (`Engine::trace_run`, used by [`crate::trajectory`]) samples each segment's
//! closed form and each event's states.
//!
//! **Many contact pairs** (chains of cells, [`Model::chain`]): every pair is watched at all
//! times with the same first-contact guarantee. In free flight all pairs' gaps are searched
//! (in the order of their quadratic estimates, each search cut at the earliest contact found
//! so far; a gap is first only summarised from the flight's modal coordinates, every pair's
//! in one pass over the modes, and a pair whose evaluation-free bounds keep it inside its
//! stops up to that contact is decided exactly as its search would decide it, without the
//! search; a pair that is searched hands its summary to the search). A free flight that
//! starts where a contact left the state starts from the modal deviation carried across the
//! contact (the previous flight's, advanced by the search's exponentials, plus `V⁻¹` of the
//! impact's jump) instead of recomputing it from the state: a chain's results differ from a
//! fresh start in their last bits; one pair keeps the fresh start, bit for bit as before.
//! Any set of pairs may be held on their stops at once: the motion is then the
//! constrained flow with the held pairs' relative coordinates fixed (`Stuck`), each held pair
//! is released when its own contact force would pull, and the other pairs are searched in
//! the constrained flow. Contacts are resolved one at a time in time order, ties by pair
//! index (see `Engine::free_flight` for what that assumes).
//!
//! The tangent flow through a stick or an impact made while other pairs are held uses the
//! free saltation matrices (exact when the event's pair shares no degree of freedom with the
//! held ones under a diagonal mass matrix, as in a chain; the constrained propagator is
//! exact in any case); [`crate::newton`] refuses sticking runs anyway.

use crate::expsum::{ExpSum, ModeTerm, SearchStack, Summary};
use crate::flow::{Flight, FlowError, Functional, JointWeights, LinearFlow};
use crate::model::{ContactPair, Model};
use crate::newton::{periodic_orbit, PeriodicOrbit};
use nalgebra::{DMatrix, DVector};
use std::collections::VecDeque;
use thiserror::Error;

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
    /// [`SteadyState::orbit`]. Every other output is unchanged by it.
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
/// ω = 0.001, ~2400 oscillations per period: 816 periods, 1.4 s; commit e44174c).
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
}

/// What the motion did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// The stroboscopic state repeats with some least period `p`.
    Periodic,
    /// No repetition within the cap (or the tail of a fixed run).
    NonPeriodic,
    /// Nothing dissipates the transients (no damping and elastic or no impacts): no steady
    /// state can be reached from this start.
    NoDissipation,
}

/// Why a run ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stop {
    /// The motion was decided: it repeated, or nothing can dissipate its transients (printed
    /// `decided`).
    Decided,
    /// The requested number of periods was run.
    FixedPeriods,
    /// The period cap was reached.
    PeriodCap,
    /// The event cap was reached.
    EventCap,
    /// The oscillation cap ([`SimulationOptions::max_oscillations`]) was reached first.
    OscillationCap,
    /// The caller's section watch ended the run ([`simulate_watched`]) before anything was
    /// decided: no final stretch was observed, so the amplitudes, the final cycle's impacts and
    /// its stroboscopic states are empty, and the status is not [`Status::Periodic`].
    Watched,
}

/// One impact.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactRecord {
    /// Absolute time.
    pub time: f64,
    /// Time within the forcing period, in `[0, T)`.
    pub phase: f64,
    /// Contact pair index.
    pub pair: usize,
    /// `+1` for side 1 (`r = +gap_plus`), `−1` for side 2.
    pub side: i8,
    /// State just before the impact.
    pub state_before: DVector<f64>,
    /// Relative velocity `ṙ⁻` just before.
    pub relative_velocity: f64,
}

/// The steady state (or the tail of the run) and what it took.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyState {
    /// Periodic, non-periodic or no dissipation.
    pub status: Status,
    /// Least `p` with `x(t + pT) = x(t)`, when periodic.
    pub period: Option<u32>,
    /// Impacts in the final cycle divided by its length in periods.
    pub impacts_per_period: f64,
    /// `max |u_k|` over the final cycle, per degree of freedom, from closed-form extrema.
    pub amplitudes: Vec<f64>,
    /// Whether the final cycle contains sticking.
    pub sticking: bool,
    /// Why the run ended.
    pub stopped: Stop,
    /// Forcing periods simulated.
    pub periods_run: u64,
    /// Impacts over the whole run.
    pub impacts: u64,
    /// Impacts of the final cycle.
    pub cycle_impacts: Vec<ImpactRecord>,
    /// States at `t = kT` over the final cycle.
    pub stroboscopic: Vec<DVector<f64>>,
    /// Where the run ended: continue from here.
    pub final_state: Start,
    /// Dense samples `(t, state)` of the final cycle, if asked for.
    pub trajectory: Option<Vec<(f64, DVector<f64>)>>,
    /// The final cycle polished by Newton on the stroboscopic map (from the final state, over
    /// [`Self::period`] periods), with its Floquet multipliers: `None` when the motion is not
    /// periodic, the cycle sticks, [`SimulationOptions::polish`] is off, or Newton failed.
    /// Boxed: it is rare in sweeps and keeps the steady state small.
    pub orbit: Option<Box<PeriodicOrbit>>,
    /// Why a periodic final cycle has no [`Self::orbit`] (sticking, or Newton's error).
    pub orbit_error: Option<String>,
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

/// A contact is an excursion beyond a stop deeper than this fraction of the gap scale (plus the
/// rounding of the positions, [`POSITION_ROUNDING`]): a motion that touches a stop to rounding
/// does not impact (no event storms at a graze).
const CONTACT_DEPTH: f64 = 1e-12;

/// Positions are known to this relative rounding of their size (`~100 ε`): an excursion beyond
/// a stop smaller than that, relative to the largest position, is no contact (introduced for
/// the base-amplitude-1e6 scene, whose positions dwarf the gap).
const POSITION_ROUNDING: f64 = 1e-14;

/// Velocities are known to this relative rounding of their size (`~1000 ε`, as they come out of
/// sums of exponentials of size comparable to the largest velocity): a slower approach is a
/// graze, not an impact.
const VELOCITY_ROUNDING: f64 = 1e-13;

/// A relative velocity below this fraction of `ω × gap` after an impact, with the stop pushing,
/// is a pair at rest on the stop: it sticks.
const RESTING_VELOCITY: f64 = 1e-10;

/// After a release the pair leaves the stop with zero relative velocity and acceleration;
/// rounding must not read that as a new contact, so contacts are ignored for this fraction of a
/// period (a hundred times the default root tolerance).
const RELEASE_GRACE: f64 = 1e-10;

/// Chatter is cut short when the remaining bounces would all fit in this fraction of a period:
/// the pair then sticks at once (the state error is of order the remaining relative velocity
/// times that time). Raised from `1e-6` in commit 0846a1f (the study's 200-frequency sweep),
/// having been `1e-9` before commit 87b7ae6.
const CHATTER: f64 = 1e-5;

/// Undamped motion with no impact for this many periods is reported as `NoDissipation`: nothing
/// will ever dissipate its transients (unless a later beat reaches a stop; the status says so).
const QUIET: u64 = 500;

/// A period found while running is confirmed at the end with this many times the periodicity
/// tolerance: a transient through complex multipliers does not decay monotonically, so the
/// last two sections may repeat slightly less well than the two that triggered detection.
const CONFIRMATION: f64 = 10.0;

/// Differences within this factor of the tolerance at a smaller multiplicity make a period
/// ambiguous: a transient decaying through a negative or complex Floquet multiplier can repeat
/// at `2T` long before it repeats at `T`.
const AMBIGUITY: f64 = 1e3;

/// Relative accuracy of the closed-form extrema in the amplitudes (`|u_j|` maxima), relative
/// to `1 + amplitude`: a few hundred rounding units, well below any reported digit.
const AMPLITUDE_TOLERANCE: f64 = 1e-13;

/// Records (impacts, trajectory samples) within this fraction of a period before the final
/// cycle's start are kept in it: an impact at the section itself carries an absolute time that
/// rounds to either side of `kT`.
const CYCLE_START_SLACK: f64 = 1e-9;

/// In the Gram–Schmidt of a stuck pair's basis of `d⊥`, a projected unit vector shorter than
/// this is dependent on the ones kept and is dropped: the vectors are of length 1 or 0 up to
/// rounding (`d` has entries ±1), so any threshold far from both works.
const BASIS_DROP: f64 = 1e-8;

/// Smallest scale divided by: keeps a relative measure finite when the scale is zero (a run at
/// rest, a unit with no stops).
const SCALE_FLOOR: f64 = 1e-300;

/// Geometry of one contact pair.
struct Pair {
    spec: ContactPair,
    /// `d` with `r = d·u`.
    direction: DVector<f64>,
    /// `M⁻¹ d`.
    mobility: DVector<f64>,
    /// `dᵀ M⁻¹ d`.
    compliance: f64,
    /// `M⁻¹ C M⁻¹ d` (zero without damping): how the impulse along `d` changes the damping
    /// force's acceleration, for the saltation matrices.
    drag: DVector<f64>,
    /// `r` as a functional of the free flow's state.
    relative_displacement: Functional,
    /// The nonzero rows of `r̈ = (M⁻¹d) · (f(τ) − K u − C u̇)`, for
    /// [`Engine::free_relative_acceleration`]: per row `i` with `(M⁻¹d)_i ≠ 0`, that entry and
    /// the nonzero `K_ij` (index `j` into the state) and `C_ij` (index `n + j`), in the order
    /// of the dense sum.
    acceleration_rows: Vec<AccelerationRow>,
}

/// One row `i` of [`Pair::acceleration_rows`]: `(M⁻¹d)_i (f_i(τ) − Σ_j (K_ij u_j + C_ij u̇_j))`
/// with only its nonzero coefficients.
struct AccelerationRow {
    row: usize,
    mobility: f64,
    /// `(index into the state, coefficient)`, `K_ij` at `j` then `C_ij` at `n + j`, `j` rising.
    coefficients: Vec<(usize, f64)>,
}

/// A set of contact pairs held on their stops at once: the constrained (reduced) flow, each
/// held pair's contact force and each other pair's relative displacement in it.
///
/// With `D` the held pairs' directions (rows), the constraint `D u = g` (`g_p = +gap_plus` or
/// `−gap_minus`) leaves `u = T ũ + u*`, `T` an orthonormal basis of `null D`,
/// `u* = Dᵀ(DDᵀ)⁻¹g`; the reduced flow is `TᵀMT ũ̈ + TᵀCT ũ̇ + TᵀKT ũ = Tᵀ(f − K u*)`. The
/// contact forces `λ` (`M ü = f − C u̇ − K u + Dᵀλ`) follow from `D ü = 0`:
/// `λ = −W⁻¹ D M⁻¹ (f − C u̇ − K u)`, `W = D M⁻¹ Dᵀ`.
struct Stuck {
    /// `(pair, side)` of the held pairs, in pair order.
    held: Vec<(usize, i8)>,
    flow: LinearFlow,
    /// `u = basis ũ + offset`.
    basis: DMatrix<f64>,
    offset: DVector<f64>,
    /// Per held pair, its contact force along `d`.
    forces: Vec<HeldForce>,
    /// The pairs not held, watched for contact: `(pair, r as a functional of the reduced
    /// state, d·u*)`, `r = functional + d·u*`.
    watched: Vec<(usize, Functional, f64)>,
    /// `D` (held directions as rows).
    constraint: DMatrix<f64>,
    /// `M⁻¹ Dᵀ W⁻¹`: the constraint's correction of accelerations and impulses,
    /// `a = a_free − reaction · D a_free`.
    reaction: DMatrix<f64>,
}

/// The contact force of one held pair:
/// `λ = state · (ũ, ũ̇) + constant + Re{harmonic e^{iωt}}`; held while `side · λ < 0`.
struct HeldForce {
    state: DVector<f64>,
    constant: f64,
    harmonic: nalgebra::Complex<f64>,
}

/// What the watch of the pairs in flight found first.
enum Watch {
    /// A contact to resolve.
    Contact(Contact),
    /// A pair in its grace time (just released or grazed) reaches its edge first: step this
    /// long without an event.
    Step(f64),
    /// No contact within the horizon.
    Clear,
}

/// Free flight, or a set of pairs held on their stops (an index into `Engine::stuck`).
#[derive(Clone, Copy)]
enum Mode {
    Free,
    Stuck(usize),
}

/// The solver: everything prepared once from the problem and fixed during the run.
pub(crate) struct Engine<'m> {
    model: &'m Model,
    omega: f64,
    period: f64,
    n: usize,
    free: LinearFlow,
    /// `u_j` as functionals of the free flow's state, for the amplitudes.
    displacements: Vec<Functional>,
    pairs: Vec<Pair>,
    /// With several pairs, their relative displacements prepared for the free flight's
    /// summaries in one pass ([`Flight::summarize_all`]); `None` for one pair.
    free_joint: Option<JointWeights>,
    /// `M⁻¹`.
    inverse_mass: DMatrix<f64>,
    /// Reduced flows of sets of pairs held on their stops, built on first use.
    stuck: Vec<Stuck>,
    /// Contact times are resolved to this (`root_tolerance × T`).
    time_tolerance: f64,
    /// The largest gap: the scale of the periodicity test and of the contact thresholds.
    pub(crate) scale: f64,
    /// [`CONTACT_DEPTH`] × scale.
    contact_depth: f64,
    /// [`RESTING_VELOCITY`] × ω × scale.
    resting_velocity: f64,
    /// [`RELEASE_GRACE`] × T.
    release_grace: f64,
    /// Storage reused by every flight.
    work: Scratch,
}

/// Storage reused by every flight, so that no flight allocates.
#[derive(Default)]
struct Scratch {
    /// Each watched pair's gap in the current flight.
    gaps: Vec<ExpSum>,
    /// Each watched pair's gap summarised ([`Flight::summarize`]) when several pairs are
    /// watched: its terms are then written out only for a search.
    summaries: Vec<Option<Summary>>,
    /// The watched pairs' summaries formed in one pass ([`Flight::summarize_all`]).
    joint: Vec<Summary>,
    /// The flight's modes, as those summaries add them.
    modes: Vec<ModeTerm>,
    /// The watch's search order: `(estimated exit, slot in gaps, pair, lo, hi)`.
    order: Vec<(f64, usize, usize, f64, f64)>,
    stack: SearchStack,
    coordinate: ExpSum,
    /// The exponentials of the search at the contact it found, for the contact state.
    event_exponentials: Vec<nalgebra::Complex<f64>>,
    /// With several pairs, the next free flight's start carried across the last contact:
    /// its modal deviation ([`Flight::deviation_at`] plus the impact's jump), valid for the
    /// state [`Self::carried_state`] at [`Self::carried_tau`] only (`carried` empty when
    /// there is none).
    carried: Vec<nalgebra::Complex<f64>>,
    /// The state the carried deviation belongs to.
    carried_state: Vec<f64>,
    /// The time within the period it belongs to.
    carried_tau: f64,
    /// The state just before the contact the deviation is carried across.
    before_contact: Vec<f64>,
}

impl Scratch {
    /// The carried deviation, if it belongs to the state `y` at `tau` (bit for bit); the
    /// carry is used up either way.
    fn take_carried(&mut self, y: &DVector<f64>, tau: f64) -> Option<Vec<nalgebra::Complex<f64>>> {
        let carried = std::mem::take(&mut self.carried);
        (!carried.is_empty() && self.carried_tau == tau && self.carried_state == y.as_slice())
            .then_some(carried)
    }
}

/// The first contact of a flight: `s` after its start, pair `pair`, on `side`.
#[derive(Clone, Copy)]
struct Contact {
    s: f64,
    pair: usize,
    side: i8,
}

/// The run's caps, fixed by the options before the first step.
struct Plan {
    /// Largest period multiplicity looked for.
    p_max: usize,
    /// The run ends after this many periods unless a rule ends it earlier.
    limit: u64,
    /// Why the run ended, if it reaches `limit`.
    at_limit: Stop,
    /// Periods observed at the end of a run that found no period (amplitudes, impacts).
    window_len: u64,
    /// A fixed number of periods: no rule ends the run early.
    fixed: bool,
    max_events: Option<u64>,
    periodicity_tolerance: f64,
    record_trajectory: bool,
}

/// A decision taken at a section: run `until` period `until`, observing the final `cycle`
/// periods, then stop for `then`.
#[derive(Clone, Copy)]
struct Observation {
    until: u64,
    cycle: u32,
    then: Stop,
}

/// What the stopping rules decide at a section.
enum Decision {
    /// Keep going.
    Continue,
    /// Observe a final stretch (amplitudes, impacts), then stop.
    Observe(Observation),
    /// The run is over.
    Stop(Stop),
}

/// Records kept while the final cycle is being observed.
#[derive(Default)]
struct Window {
    impacts: Vec<ImpactRecord>,
    amplitudes: Vec<f64>,
    sticking: bool,
    stroboscopic: Vec<DVector<f64>>,
    trajectory: Vec<(f64, DVector<f64>)>,
}

/// The state of a run: everything that changes from one step to the next.
struct RunState {
    /// Forcing periods completed: the last section crossed is `t = kT`.
    k: u64,
    /// Time within the current period, in `[0, T]` (time is carried modulo the period so the
    /// forcing phase stays exact).
    tau: f64,
    /// `(u, u̇)` at `kT + tau`.
    y: DVector<f64>,
    /// Free, or held on a stop.
    mode: Mode,
    /// Impacts over the whole run.
    impacts: u64,
    /// Events (impacts, grazes, sticks, releases) in the current period.
    events_this_period: u64,
    /// Events in the completed periods.
    events_total: u64,
    /// The period of the last impact.
    last_impact_period: Option<u64>,
    /// Per pair: its contacts are ignored before this time within the period (just after its
    /// release or graze); `−∞` when none is pending.
    grace: Vec<f64>,
    /// Stroboscopic history: the states at the last `p_max + 2` sections.
    ring: Sections,
    /// Records of the final stretch, once it has begun.
    window: Option<Window>,
    /// The stopping rules' decision to end the run after an observed final stretch.
    observing: Option<Observation>,
    /// The tangent flow, when asked for ([`Engine::tangent_run`]); `None` in ordinary runs.
    tangent: Option<Tangent>,
    /// Exact samples of the run, when asked for ([`Engine::trace_run`]); `None` otherwise.
    trace: Option<Trace>,
}

/// What a row of a sampled trajectory is ([`crate::trajectory::TrajectoryRow::kind`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// A uniform sample in time.
    Sample,
    /// The state just before an impact (or a stick without impact).
    BeforeImpact,
    /// The state just after an impact's restitution.
    AfterImpact,
    /// The state just after a stick (the plastic hold on a stop).
    AfterStick,
}

/// An impact seen by a traced run.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TracedImpact {
    /// Time since the run's start (a section).
    pub(crate) time: f64,
    pub(crate) pair: usize,
    pub(crate) side: i8,
    /// `ṙ⁻`.
    pub(crate) relative_velocity: f64,
    /// The state just before.
    pub(crate) state_before: DVector<f64>,
}

/// The exact samples of a traced run: uniform samples, and each event's states.
#[derive(Debug, Clone, Default)]
pub(crate) struct Trace {
    /// Uniform samples per period.
    pub(crate) per_period: u64,
    /// The next uniform sample's index within the current period.
    next: u64,
    /// `(time since the start, kind, state)`, in time order.
    pub(crate) rows: Vec<(f64, RowKind, DVector<f64>)>,
    pub(crate) impacts: Vec<TracedImpact>,
}

impl Trace {
    /// The uniform samples `t_j = jT/N` of period `k` inside the segment `[tau, tau + span)`,
    /// from the segment's closed form `at(s)`, `s = t_j − tau`.
    fn segment<F: Fn(f64) -> DVector<f64>>(
        &mut self,
        k: u64,
        period: f64,
        tau: f64,
        span: f64,
        at: F,
    ) {
        let step = period / self.per_period as f64;
        while self.next < self.per_period {
            let tj = self.next as f64 * step;
            if tj >= tau + span {
                break;
            }
            if tj >= tau {
                self.rows
                    .push((k as f64 * period + tj, RowKind::Sample, at(tj - tau)));
            }
            self.next += 1;
        }
    }
}

/// The tangent flow along a run: the Jacobian of the current state with respect to the start
/// state, as the product of the flights' propagators and the impacts' saltation matrices.
pub(crate) struct Tangent {
    /// `∂y/∂y(0)`.
    pub(crate) jacobian: DMatrix<f64>,
    /// The impacts in time order: pair, side and time since the start.
    pub(crate) impacts: Vec<(usize, i8, f64)>,
    /// The time since the start of the first sticking, if any: the Jacobian then maps onto the
    /// held pair's constrained tangent space (rank `2n − 2`), no longer a smooth map of the
    /// start state.
    pub(crate) sticking: Option<f64>,
    /// Whether [`Self::product`] holds the Jacobian just before the impact of the contact being
    /// resolved: a stick that follows it replaces both by one plastic saltation from the state
    /// before.
    before_impact: bool,
    /// Sticks (plastic holds on a stop) so far.
    pub(crate) sticks: u64,
    /// Which pairs have stuck so far (each collapses two tangent directions).
    pub(crate) stuck_pairs: Vec<bool>,
    /// Time spent held on a stop so far.
    pub(crate) stuck_time: f64,
    /// Storage for a flight's propagator and the product, reused by every flight (the product
    /// also keeps the Jacobian before an impact, see [`Self::before_impact`]).
    propagator: DMatrix<f64>,
    product: DMatrix<f64>,
}

impl Tangent {
    /// The identity tangent of a `2n`-dimensional state, for `pairs` contact pairs.
    fn new(n: usize, pairs: usize) -> Self {
        Tangent {
            jacobian: DMatrix::identity(2 * n, 2 * n),
            impacts: Vec::new(),
            sticking: None,
            before_impact: false,
            sticks: 0,
            stuck_pairs: vec![false; pairs],
            stuck_time: 0.0,
            propagator: DMatrix::zeros(0, 0),
            product: DMatrix::zeros(0, 0),
        }
    }
}

impl RunState {
    /// Absolute time of the time `tau` within the current period of length `period`.
    fn absolute(&self, period: f64, tau: f64) -> f64 {
        self.k as f64 * period + tau
    }

    /// Counts one event of the current period.
    ///
    /// # Errors
    /// [`SimulationError::EventStorm`] past [`EVENT_STORM`] events in one period.
    fn count_event(&mut self, period: f64) -> Result<(), SimulationError> {
        self.events_this_period += 1;
        if self.events_this_period > EVENT_STORM {
            return Err(SimulationError::EventStorm(
                EVENT_STORM,
                self.absolute(period, self.tau),
            ));
        }
        Ok(())
    }
}

/// Simulates `model` at `omega` from `start` until steady (or for a fixed number of periods).
///
/// # Errors
/// [`SimulationError::Omega`] for an `omega` that is not finite and positive,
/// [`SimulationError::Start`] for a start state of the wrong length or not finite,
/// [`SimulationError::Option`] for tolerances outside `(0, 1)` or a zero multiplicity,
/// [`SimulationError::Flow`] when a modal flow does not exist (e.g. a defective system), and
/// [`SimulationError::EventStorm`] when more than [`EVENT_STORM`] events fall in one period.
pub fn simulate(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> Result<SteadyState, SimulationError> {
    simulate_watched(model, omega, start, options, &mut |_, _| false)
}

/// As [`simulate`], with a watch on the stroboscopic sections: at each section `t = kT` at
/// which the run is still undecided (running until steady, not periodic yet, no cap reached),
/// `watch(k, state)` is asked, after the stopping rules; `true` ends the run at once with
/// [`Stop::Watched`] (nothing observed: no amplitudes, no final cycle). For callers that
/// recognise a motion before it repeats to the tolerance, e.g. a start entering a known
/// attractor's neighbourhood. A fixed run ([`SimulationOptions::fixed_periods`]) never asks.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_watched(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
    watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
) -> Result<SteadyState, SimulationError> {
    check_inputs(model, omega, start, options)?;
    let mut engine = Engine::new(model, omega, options)?;
    let mut steady = engine.run(start, options, watch)?;
    if let (true, Status::Periodic, Some(p)) = (options.polish, steady.status, steady.period) {
        if steady.sticking {
            steady.orbit_error = Some("the final cycle sticks".into());
        } else {
            match periodic_orbit(model, omega, &steady.final_state, p, options) {
                Ok(orbit) => steady.orbit = Some(Box::new(orbit)),
                Err(e) => steady.orbit_error = Some(e.to_string()),
            }
        }
    }
    Ok(steady)
}

/// The checks of [`simulate`] on its inputs.
///
/// # Errors
/// As [`simulate`]: [`SimulationError::Omega`], [`SimulationError::Start`] and
/// [`SimulationError::Option`].
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
    Ok(())
}

impl<'m> Engine<'m> {
    /// The solver for `model` at `omega`.
    ///
    /// # Errors
    /// [`SimulationError::Flow`] when the modal flow does not exist.
    pub(crate) fn new(
        model: &'m Model,
        omega: f64,
        options: &SimulationOptions,
    ) -> Result<Self, SimulationError> {
        let n = model.dofs();
        let period = std::f64::consts::TAU / omega;
        let free = LinearFlow::new(
            &model.mass,
            model.damping.as_ref(),
            &model.stiffness,
            &model.forcing_cos,
            &model.forcing_sin,
            &DVector::zeros(n),
            omega,
        )?;
        let minv = model
            .mass
            .clone()
            .try_inverse()
            .ok_or(FlowError::SingularMass)?;
        let pairs: Vec<Pair> = model
            .contacts
            .iter()
            .map(|c| {
                let mut d = DVector::zeros(n);
                d[c.plus_dof] = 1.0;
                d[c.minus_dof] = -1.0;
                let mut position = DVector::zeros(2 * n);
                position.rows_mut(0, n).copy_from(&d);
                let mobility = &minv * &d;
                let compliance = d.dot(&mobility);
                let relative_displacement = free.functional(&position);
                let drag = match &model.damping {
                    Some(damping) => &minv * (damping * &mobility),
                    None => DVector::zeros(n),
                };
                let acceleration_rows = (0..n)
                    .filter(|&i| mobility[i] != 0.0)
                    .map(|i| AccelerationRow {
                        row: i,
                        mobility: mobility[i],
                        coefficients: (0..n)
                            .flat_map(|j| {
                                let k = (j, model.stiffness[(i, j)]);
                                let c = (n + j, model.damping.as_ref().map_or(0.0, |c| c[(i, j)]));
                                [k, c]
                            })
                            .filter(|&(_, v)| v != 0.0)
                            .collect(),
                    })
                    .collect();
                Pair {
                    spec: *c,
                    direction: d,
                    mobility,
                    compliance,
                    drag,
                    relative_displacement,
                    acceleration_rows,
                }
            })
            .collect();
        let displacements = (0..n)
            .map(|j| {
                let mut c = DVector::zeros(2 * n);
                c[j] = 1.0;
                free.functional(&c)
            })
            .collect();
        let scale = pairs
            .iter()
            .map(|p| p.spec.gap_plus.max(p.spec.gap_minus))
            .fold(0.0, f64::max)
            .max(SCALE_FLOOR);
        let free_joint = (pairs.len() > 1).then(|| {
            let functionals: Vec<&Functional> =
                pairs.iter().map(|p| &p.relative_displacement).collect();
            free.joint_weights(&functionals)
        });
        Ok(Self {
            model,
            omega,
            period,
            n,
            free,
            displacements,
            pairs,
            free_joint,
            inverse_mass: minv,
            stuck: Vec::new(),
            time_tolerance: options.root_tolerance * period,
            scale,
            contact_depth: CONTACT_DEPTH * scale,
            resting_velocity: RESTING_VELOCITY * omega * scale,
            release_grace: RELEASE_GRACE * period,
            work: Scratch::default(),
        })
    }

    /// The constrained flow of the pairs `held` (`(pair, side)`, in pair order) on their
    /// stops, built on first use (see [`Stuck`]). One held pair gives the same numbers as the
    /// one-pair construction it generalises (same Gram–Schmidt, offset and force weights).
    ///
    /// # Errors
    /// [`SimulationError::DependentHolds`] when the held directions are dependent or leave no
    /// free direction, and [`SimulationError::Flow`] when the reduced flow does not exist.
    fn stuck_index(&mut self, held: &[(usize, i8)]) -> Result<usize, SimulationError> {
        if let Some(i) = self.stuck.iter().position(|s| s.held == held) {
            return Ok(i);
        }
        let n = self.n;
        let h = held.len();
        let dependent = || SimulationError::DependentHolds(held.iter().map(|h| h.0).collect());
        if h == 0 || h >= n {
            return Err(dependent());
        }
        // Orthonormal basis of span D, then of its complement by Gram–Schmidt on the unit
        // vectors.
        let mut spanned: Vec<DVector<f64>> = Vec::with_capacity(h);
        for &(pair, _) in held {
            let mut v = self.pairs[pair].direction.clone();
            for b in &spanned {
                v -= b * b.dot(&v);
            }
            if v.norm() <= BASIS_DROP {
                return Err(dependent());
            }
            spanned.push(v.normalize());
        }
        let mut basis: Vec<DVector<f64>> = Vec::new();
        for i in 0..n {
            let mut v = DVector::zeros(n);
            v[i] = 1.0;
            for b in &spanned {
                v -= b * b.dot(&v);
            }
            for b in &basis {
                v -= b * b.dot(&v);
            }
            if v.norm() > BASIS_DROP && basis.len() < n - h {
                basis.push(v.normalize());
            }
        }
        let nr = n - h;
        let t = DMatrix::from_columns(&basis);
        let gaps = DVector::from_iterator(
            h,
            held.iter().map(|&(pair, side)| {
                let spec = &self.pairs[pair].spec;
                if side > 0 {
                    spec.gap_plus
                } else {
                    -spec.gap_minus
                }
            }),
        );
        let directions: Vec<DVector<f64>> = held
            .iter()
            .map(|&(pair, _)| self.pairs[pair].direction.clone())
            .collect();
        let constraint =
            DMatrix::from_rows(&directions.iter().map(|d| d.transpose()).collect::<Vec<_>>());
        // W = D M⁻¹ Dᵀ; one pair divides by its compliance, as the one-pair flow did.
        let mobilities = DMatrix::from_columns(
            &held
                .iter()
                .map(|&(pair, _)| self.pairs[pair].mobility.clone())
                .collect::<Vec<_>>(),
        );
        let w = &constraint * &mobilities;
        let w_inverse = w.clone().try_inverse().ok_or_else(dependent)?;
        let solve = |x: DMatrix<f64>| -> DMatrix<f64> {
            if h == 1 {
                x / w[(0, 0)]
            } else {
                &w_inverse * x
            }
        };
        let offset = if h == 1 {
            &directions[0] * (gaps[0] / directions[0].norm_squared())
        } else {
            let ddt = &constraint * constraint.transpose();
            let x = ddt.try_inverse().ok_or_else(dependent)? * &gaps;
            constraint.transpose() * x
        };
        let m = &self.model.mass;
        let k = &self.model.stiffness;
        let tt = t.transpose();
        let mr = &tt * m * &t;
        let kr = &tt * k * &t;
        let cr = self.model.damping.as_ref().map(|c| &tt * c * &t);
        let fc = &tt * &self.model.forcing_cos;
        let fs = &tt * &self.model.forcing_sin;
        let f0 = -(&tt * (k * &offset));
        let flow = LinearFlow::new(&mr, cr.as_ref(), &kr, &fc, &fs, &f0, self.omega)?;
        // λ = −W⁻¹DM⁻¹(f − C u̇ − K u), u = Tũ + u*, u̇ = Tũ̇.
        let mob = mobilities.transpose();
        let a = solve(&mob * k * &t);
        let b = self.model.damping.as_ref().map(|c| solve(&mob * c * &t));
        let constants = solve(&mob * k * DMatrix::from_column_slice(n, 1, offset.as_slice()));
        let fcos =
            solve(&mob * DMatrix::from_column_slice(n, 1, self.model.forcing_cos.as_slice()));
        let fsin =
            solve(&mob * DMatrix::from_column_slice(n, 1, self.model.forcing_sin.as_slice()));
        let forces = (0..h)
            .map(|row| {
                let mut state = DVector::zeros(2 * nr);
                state.rows_mut(0, nr).copy_from(&a.row(row).transpose());
                if let Some(b) = &b {
                    state.rows_mut(nr, nr).copy_from(&b.row(row).transpose());
                }
                HeldForce {
                    state,
                    constant: constants[(row, 0)],
                    harmonic: nalgebra::Complex::new(-fcos[(row, 0)], fsin[(row, 0)]),
                }
            })
            .collect();
        let watched = (0..self.pairs.len())
            .filter(|q| held.iter().all(|&(pair, _)| pair != *q))
            .map(|q| {
                let d = &self.pairs[q].direction;
                let mut c = DVector::zeros(2 * nr);
                c.rows_mut(0, nr).copy_from(&(&tt * d));
                (q, flow.functional(&c), d.dot(&offset))
            })
            .collect();
        let reaction = &mobilities * &w_inverse;
        self.stuck.push(Stuck {
            held: held.to_vec(),
            flow,
            basis: t,
            offset,
            forces,
            watched,
            constraint,
            reaction,
        });
        Ok(self.stuck.len() - 1)
    }

    /// The held set after pair `pair` sticks on `side` in `mode`.
    fn held_with(&self, mode: Mode, pair: usize, side: i8) -> Vec<(usize, i8)> {
        let mut held = match mode {
            Mode::Free => Vec::new(),
            Mode::Stuck(i) => self.stuck[i].held.clone(),
        };
        held.retain(|h| h.0 != pair);
        held.push((pair, side));
        held.sort_unstable();
        held
    }

    /// Relative acceleration `r̈` of pair `pair` at state `y`, phase time `tau`, in `mode`:
    /// the free one, or with the held pairs' contact forces (`a = a_free − R D a_free`).
    fn relative_acceleration(&self, pair: usize, y: &DVector<f64>, tau: f64, mode: Mode) -> f64 {
        let p = &self.pairs[pair];
        match mode {
            Mode::Free => self.free_relative_acceleration(p, y, tau),
            Mode::Stuck(i) => {
                let st = &self.stuck[i];
                let free = self.free_acceleration(y, tau);
                let correction = &st.reaction * (&st.constraint * &free);
                p.direction.dot(&(free - correction))
            }
        }
    }

    /// The free acceleration `M⁻¹(f(τ) − K u − C u̇)` at state `y`.
    fn free_acceleration(&self, y: &DVector<f64>, tau: f64) -> DVector<f64> {
        let n = self.n;
        let m = self.model;
        let (sin, cos) = (self.omega * tau).sin_cos();
        let mut f = &m.forcing_cos * cos + &m.forcing_sin * sin - &m.stiffness * y.rows(0, n);
        if let Some(c) = &m.damping {
            f -= c * y.rows(n, n);
        }
        &self.inverse_mass * f
    }

    /// Newton restitution of pair `pair` (restitution `e`, the pair's own if `None`) in
    /// `mode`: free, or with the held pairs' constraints kept (`D u̇ = 0`), along the
    /// constrained mobility `m_c = M⁻¹d − R D M⁻¹d`. When the impact does not reach the held
    /// pairs (`D M⁻¹ d = 0`, e.g. pairs of different cells of a chain) both are the free
    /// impact, applied as such.
    fn restitute(&self, pair: usize, y: &mut DVector<f64>, e: Option<f64>, mode: Mode) {
        let st = match mode {
            Mode::Free => None,
            Mode::Stuck(i) => Some(&self.stuck[i]),
        };
        let p = &self.pairs[pair];
        let coupling = st.map(|st| &st.constraint * &p.mobility);
        match (st, coupling) {
            (Some(st), Some(coupling)) if coupling.iter().any(|&c| c != 0.0) => {
                let n = self.n;
                let e = e.unwrap_or(p.spec.restitution);
                let mc = &p.mobility - &st.reaction * coupling;
                let rdot = p.direction.dot(&y.rows(n, n));
                let scale = (1.0 + e) * rdot / p.direction.dot(&mc);
                for i in 0..n {
                    y[n + i] -= mc[i] * scale;
                }
            }
            _ => self.model.apply_impact(pair, y, e),
        }
    }

    /// Applies the saltation matrix of an impact of pair `p` to the tangent `t`, in place:
    /// `S = Ĝ + (f⁺ − Ĝ f⁻) h_xᵀ / (h_x · f⁻)`, with the contact function `h = d·u ∓ gap`
    /// (`h_x = (d, 0)`, `h_x · f⁻ = ṙ⁻`), `Ĝ` the identity on positions and the restitution
    /// map `G = I − (1 + e) M⁻¹d dᵀ/w` (`w = dᵀM⁻¹d`) on velocities, `f` the vector field.
    /// The jump of the field is closed form: with `v⁺ − v⁻ = −(1 + e) ṙ⁻ M⁻¹d / w`,
    /// `(f⁺ − Ĝ f⁻)/ṙ⁻ = ((1 + e)/w) (−M⁻¹d, M⁻¹CM⁻¹d + M⁻¹d r̈⁻/ṙ⁻)`, `r̈⁻` the free
    /// relative acceleration just before. So `S J` is `J` with its velocity rows corrected
    /// along `M⁻¹d` and a rank-one term in `dᵀ J_u`: no matrix is formed. `det S = e²`.
    fn apply_saltation(&self, t: &mut Tangent, p: &Pair, before: &DVector<f64>, tau: f64) {
        let n = self.n;
        let factor = (1.0 + p.spec.restitution) / p.compliance;
        let rdot = p.direction.dot(&before.rows(n, n));
        let rddot = self.free_relative_acceleration(p, before, tau);
        let ratio = rddot / rdot;
        let j = &mut t.jacobian;
        for col in 0..j.ncols() {
            let mut a = 0.0; // dᵀ δu
            let mut b = 0.0; // dᵀ δu̇
            for i in 0..n {
                a += p.direction[i] * j[(i, col)];
                b += p.direction[i] * j[(n + i, col)];
            }
            for i in 0..n {
                j[(i, col)] -= factor * p.mobility[i] * a;
                j[(n + i, col)] +=
                    factor * (-p.mobility[i] * b + (p.drag[i] + p.mobility[i] * ratio) * a);
            }
        }
    }

    /// Runs `periods` periods from state `y` at the section `t = 0` with the tangent flow: the
    /// state at `t = periods·T` and the tangent record (Jacobian, impacts, sticking).
    ///
    /// # Errors
    /// As [`Engine::next_iter`].
    pub(crate) fn tangent_run(
        &mut self,
        y: &DVector<f64>,
        periods: u32,
    ) -> Result<(DVector<f64>, Tangent), SimulationError> {
        let identity = DMatrix::identity(y.len(), y.len());
        self.tangent_periods(y, identity, periods as u64, |_| Ok(()))
    }

    /// [`Engine::tangent_run`] over `periods` periods with the tangent flow applied to `frame`
    /// (`2n` rows; the identity gives the Jacobian), calling `at_section` with the tangent at
    /// each section `t = kT`, `k ≥ 1` (it may replace the Jacobian, e.g. by an orthonormal
    /// frame, or stop the run with an error).
    ///
    /// # Errors
    /// As [`Engine::next_iter`], and those of `at_section`.
    pub(crate) fn tangent_periods<F>(
        &mut self,
        y: &DVector<f64>,
        frame: DMatrix<f64>,
        periods: u64,
        mut at_section: F,
    ) -> Result<(DVector<f64>, Tangent), SimulationError>
    where
        F: FnMut(&mut Tangent) -> Result<(), SimulationError>,
    {
        let n = self.n;
        let plan = Plan {
            p_max: 1,
            limit: periods,
            at_limit: Stop::FixedPeriods,
            window_len: 0,
            fixed: true,
            max_events: None,
            periodicity_tolerance: DEFAULT_PERIODICITY_TOLERANCE,
            record_trajectory: false,
        };
        let mut state = self.init(
            &Start {
                state: y.clone(),
                time: 0.0,
            },
            &plan,
        );
        let mut tangent = Tangent::new(n, self.pairs.len());
        tangent.jacobian = frame;
        while state.k < periods {
            state.tangent = Some(tangent);
            let at_section_reached = self.next_iter(&mut state, &plan);
            tangent = state
                .tangent
                .take()
                .ok_or_else(|| SimulationError::Option("tangent flow lost".into()))?;
            if at_section_reached? {
                at_section(&mut tangent)?;
            }
        }
        Ok((state.y, tangent))
    }

    /// Runs `periods` periods from state `y` at the section `t = 0`, tracing it: `per_period`
    /// uniform samples per period from each segment's closed form (the last at
    /// `t = periods·T`), each impact's states before and after, each stick's, and the impacts.
    ///
    /// # Errors
    /// As [`Engine::next_iter`].
    pub(crate) fn trace_run(
        &mut self,
        y: &DVector<f64>,
        periods: u64,
        per_period: u64,
    ) -> Result<Trace, SimulationError> {
        let plan = Plan {
            p_max: 1,
            limit: periods,
            at_limit: Stop::FixedPeriods,
            window_len: 0,
            fixed: true,
            max_events: None,
            periodicity_tolerance: DEFAULT_PERIODICITY_TOLERANCE,
            record_trajectory: false,
        };
        let mut state = self.init(
            &Start {
                state: y.clone(),
                time: 0.0,
            },
            &plan,
        );
        state.trace = Some(Trace {
            per_period: per_period.max(1),
            ..Trace::default()
        });
        while state.k < periods {
            self.next_iter(&mut state, &plan)?;
        }
        let mut trace = state.trace.take().unwrap_or_default();
        trace
            .rows
            .push((periods as f64 * self.period, RowKind::Sample, state.y));
        Ok(trace)
    }

    /// Relative acceleration `r̈` of pair `p` in free flight at state `y`, phase time `tau`:
    /// `(M⁻¹d) · (f(τ) − K u − C u̇)`, summed row by row over the nonzero entries only
    /// ([`Pair::acceleration_rows`]): the terms left out are exact zeros, so the value is the
    /// dense sum's.
    fn free_relative_acceleration(&self, p: &Pair, y: &DVector<f64>, tau: f64) -> f64 {
        let m = self.model;
        let (sin, cos) = (self.omega * tau).sin_cos();
        let y = y.as_slice();
        p.acceleration_rows
            .iter()
            .map(|r| {
                let i = r.row;
                let mut f = m.forcing_cos[i] * cos + m.forcing_sin[i] * sin;
                for &(j, v) in &r.coefficients {
                    f -= v * y[j];
                }
                r.mobility * f
            })
            .sum()
    }

    /// The run: `init`, then `next_iter` until `terminate` says why it ends, then the report.
    fn run(
        &mut self,
        start: &Start,
        options: &SimulationOptions,
        watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
    ) -> Result<SteadyState, SimulationError> {
        let plan = self.plan(options);
        let mut state = self.init(start, &plan);
        let stop = loop {
            if self.next_iter(&mut state, &plan)? {
                if let Some(stop) = self.terminate(&mut state, &plan, watch) {
                    break stop;
                }
            }
        };
        Ok(self.report(state, stop, &plan))
    }

    /// The caps of this run.
    fn plan(&self, options: &SimulationOptions) -> Plan {
        let p_max = options.max_period_multiplicity as usize;
        let conservative = self.model.conservative();
        // Periods allowed by the oscillation cap.
        let oscillation_periods = options.max_oscillations.map_or(u64::MAX, |cap| {
            let per_period = self.free.fastest_rate() / self.omega;
            ((cap / per_period.max(SCALE_FLOOR)).floor() as u64).max(MIN_OSCILLATION_PERIODS)
        });
        let period_cap = if conservative {
            options.max_periods.min(CONSERVATIVE_MAX_PERIODS)
        } else {
            options.max_periods
        };
        let (limit, at_limit) = match options.fixed_periods {
            Some(n) => (n, Stop::FixedPeriods),
            None if oscillation_periods < period_cap => (oscillation_periods, Stop::OscillationCap),
            None => (period_cap, Stop::PeriodCap),
        };
        Plan {
            p_max,
            limit,
            at_limit,
            window_len: (p_max as u64).min(limit),
            fixed: options.fixed_periods.is_some(),
            max_events: options.max_events,
            periodicity_tolerance: options.periodicity_tolerance,
            record_trajectory: options.record_trajectory,
        }
    }

    /// The state at the start: free, at `start`, its time carried modulo the period.
    fn init(&self, start: &Start, plan: &Plan) -> RunState {
        let mut state = RunState {
            k: 0,
            tau: start.time.rem_euclid(self.period),
            y: start.state.clone(),
            mode: Mode::Free,
            impacts: 0,
            events_this_period: 0,
            events_total: 0,
            last_impact_period: None,
            grace: vec![f64::NEG_INFINITY; self.pairs.len()],
            ring: Sections::new(plan.p_max + 2),
            window: None,
            observing: None,
            tangent: None,
            trace: None,
        };
        if state.tau == 0.0 {
            state.ring.push(&state.y); // the start is itself a section
        }
        state
    }

    /// One step: a free flight or a stuck phase, up to its first event or to the next section
    /// `t = (k + 1)T`; at the section, the section check. Returns whether a section was reached.
    ///
    /// # Errors
    /// [`SimulationError::EventStorm`], and [`SimulationError::Flow`] when a stuck flow does not
    /// exist.
    fn next_iter(&mut self, state: &mut RunState, plan: &Plan) -> Result<bool, SimulationError> {
        self.open_window(state, plan);
        match state.mode {
            Mode::Free => self.free_flight(state, plan)?,
            Mode::Stuck(index) => self.stuck_phase(state, index, plan)?,
        }
        if state.tau < self.period {
            return Ok(false);
        }
        self.section(state);
        Ok(true)
    }

    /// Starts recording the final stretch when its first period begins.
    fn open_window(&self, state: &mut RunState, plan: &Plan) {
        let window_start = match state.observing {
            Some(o) => o.until - o.cycle as u64,
            None => plan.limit.saturating_sub(plan.window_len),
        };
        if state.window.is_none() && state.k >= window_start {
            let mut w = Window {
                amplitudes: vec![0.0; self.n],
                ..Window::default()
            };
            if state.tau == 0.0 {
                w.stroboscopic.push(state.y.clone());
            }
            state.window = Some(w);
        }
    }

    /// The first contact of `flight` within `horizon` among the `watched` pairs
    /// (`(pair, r − shift as a functional of the flight's state, shift)`): each pair's relative
    /// displacement searched for its first exit from `[−gap_minus, gap_plus]`, every pair with
    /// the search's guarantee. A pair in its grace time (`tau + s < grace[pair]`) counts no
    /// contact; if it reaches its edge before any other pair's contact, the flight steps to the
    /// end of its grace without an event. Ties go to the lower pair index (see
    /// [`Engine::free_flight`]). Leaves the search's exponentials at the contact in
    /// `work.event_exponentials`.
    #[allow(clippy::too_many_arguments)]
    fn watch<'f, I>(
        pairs: &[Pair],
        watched: I,
        joint: Option<&JointWeights>,
        work: &mut Scratch,
        flight: &Flight<'_>,
        horizon: f64,
        time_tolerance: f64,
        depth: f64,
        grace: &[f64],
        tau: f64,
    ) -> Watch
    where
        I: Iterator<Item = (usize, &'f Functional, f64)> + Clone,
    {
        let mut contact: Option<Contact> = None;
        let mut step = f64::INFINITY;
        // Every pair's gap, then the searches in the order of their quadratic estimates: the
        // likely first contact is found first and cuts the others' horizons short. With
        // several pairs, each gap is first only summarised (the sums of the summarised
        // search's first tests): a pair those tests exclude up to the earliest contact found is
        // decided without writing its terms out, as its search would decide it. (The order
        // decides only how much is searched: each pair is searched up to the earliest contact
        // found before it, so the contact found is the same in any order, ties aside.)
        let several = watched.size_hint().0 > 1;
        // `joint` lists the watched pairs' functionals in their order: then every summary is
        // formed in one pass.
        let joint = several
            && joint.is_some_and(|joint| {
                flight.summarize_all(joint, horizon, &mut work.modes, &mut work.joint)
            });
        work.order.clear();
        for (count, (i, functional, shift)) in watched.clone().enumerate() {
            if work.gaps.len() <= count {
                work.gaps.push(ExpSum::default());
                work.summaries.push(None);
            }
            let spec = &pairs[i].spec;
            let (lo, hi) = (-spec.gap_minus - shift, spec.gap_plus - shift);
            // The joint summaries are read where they were formed (not copied).
            let estimate = if joint {
                work.joint[count].estimated_exit(lo, hi)
            } else {
                let summary = several
                    .then(|| flight.summarize(functional, horizon))
                    .flatten();
                work.summaries[count] = summary;
                match summary {
                    Some(summary) => summary.estimated_exit(lo, hi),
                    None => {
                        let gap = &mut work.gaps[count];
                        flight.expand(functional, gap);
                        gap.estimated_exit(lo, hi)
                    }
                }
            };
            work.order.push((estimate, count, i, lo, hi));
        }
        work.order
            .sort_unstable_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
        let Scratch {
            gaps,
            summaries,
            joint: joint_summaries,
            order,
            stack,
            event_exponentials,
            ..
        } = work;
        for &(_, slot, i, lo, hi) in order.iter() {
            // Only a contact before the earliest found so far matters: search up to it.
            let within = contact.map_or(horizon, |c| c.s).min(step).min(horizon);
            let summary = if joint {
                joint_summaries.get(slot)
            } else {
                summaries[slot].as_ref()
            };
            let found = if let Some(summary) = summary {
                if summary.excludes(lo, hi, within, horizon) {
                    continue;
                }
                if let Some((_, functional, _)) = watched.clone().nth(slot) {
                    flight.expand(functional, &mut gaps[slot]);
                }
                // The search's own first tests are this summary's, just made: not made again.
                gaps[slot].first_exit_summarized(
                    summary,
                    lo,
                    hi,
                    horizon,
                    within,
                    time_tolerance,
                    depth,
                    stack,
                )
            } else {
                gaps[slot].first_exit_until(lo, hi, horizon, within, time_tolerance, depth, stack)
            };
            if let Some((s, side)) = found {
                if tau + s < grace[i] {
                    step = step.min(grace[i] - tau);
                } else if contact.is_none_or(|c| s < c.s || (s == c.s && i < c.pair)) {
                    contact = Some(Contact { s, pair: i, side });
                    event_exponentials.clear();
                    if let Some(e) = stack.exponentials_at(s) {
                        event_exponentials.extend_from_slice(e);
                    }
                }
            }
        }
        match contact {
            Some(c) if c.s <= step => Watch::Contact(c),
            _ if step < horizon => Watch::Step(step),
            Some(c) => Watch::Contact(c),
            None => Watch::Clear,
        }
    }

    /// Free flight: the closed-form flow from the current state to its first contact (then the
    /// contact event) or to the next section.
    ///
    /// Contacts of different pairs are resolved one at a time, in time order: the flight ends
    /// at the earliest, which is resolved; the next flight starts there and finds the others
    /// (a pair whose contact is at the same instant, `s = 0`, at once). Ties go to the lower
    /// pair index. This is exact when the impacts commute: an impact of one pair changes the
    /// velocities along `M⁻¹d` only, so it leaves another pair's relative velocity unchanged
    /// when `dᵀM⁻¹d' = 0` (pairs sharing no degree of freedom under a diagonal mass matrix,
    /// such as the cells of a chain, coupled to one another only through springs and
    /// dashpots). Pairs that share a degree of freedom and impact at the same instant are
    /// resolved in index order (a sequential-impact model).
    fn free_flight(&mut self, state: &mut RunState, plan: &Plan) -> Result<(), SimulationError> {
        let n = self.n;
        let period = self.period;
        let horizon = period - state.tau;
        // With several pairs, a flight that starts where the last contact left the state
        // starts from the modal deviation carried across it (no product with `V⁻¹`).
        let several = self.pairs.len() > 1;
        let carried = if several {
            self.work.take_carried(&state.y, state.tau)
        } else {
            None
        };
        let flight = match carried {
            Some(deviation) => match self.free.flight_with_deviation(deviation, state.tau) {
                Ok(flight) => flight,
                Err(_) => self.free.flight(&state.y, state.tau),
            },
            None => self.free.flight(&state.y, state.tau),
        };
        // Positions are known to rounding relative to their size, not to the gap: an excursion
        // beyond a stop smaller than that is no contact.
        let depth = self.contact_depth + POSITION_ROUNDING * state.y.rows(0, n).amax();
        let watch = Self::watch(
            &self.pairs,
            self.pairs
                .iter()
                .enumerate()
                .map(|(i, p)| (i, &p.relative_displacement, 0.0)),
            self.free_joint.as_ref(),
            &mut self.work,
            &flight,
            horizon,
            self.time_tolerance,
            depth,
            &state.grace,
            state.tau,
        );
        if let Watch::Step(step) = watch {
            // Just released (or grazed): step past the stop's edge without an event.
            if let Some(trace) = state.trace.as_mut() {
                trace.segment(state.k, period, state.tau, step, |s| flight.state(s));
            }
            state.y = flight.state(step);
            if let Some(t) = state.tangent.as_mut() {
                self.propagate_tangent(t, step);
            }
            state.tau += step;
            return Ok(());
        }
        let contact = match watch {
            Watch::Contact(c) => Some(c),
            _ => None,
        };
        let span = contact.map_or(horizon, |c| c.s);
        let tau = state.tau;
        let k = state.k;
        if let Some(t) = state.tangent.as_mut() {
            self.propagate_tangent(t, span);
        }
        if let Some(trace) = state.trace.as_mut() {
            trace.segment(k, period, tau, span, |s| flight.state(s));
        }
        if let Some(w) = state.window.as_mut() {
            for (amp, u) in w.amplitudes.iter_mut().zip(&self.displacements) {
                flight.expand(u, &mut self.work.coordinate);
                *amp = self
                    .work
                    .coordinate
                    .max_abs(span, *amp, AMPLITUDE_TOLERANCE * (1.0 + *amp));
            }
            if plan.record_trajectory {
                sample(&mut w.trajectory, span, period, |s| {
                    (k as f64 * period + (tau + s), flight.state(s))
                });
            }
        }
        match contact {
            None => {
                flight.state_into(horizon, &mut state.y);
                state.tau = period;
            }
            Some(c) => {
                // Just before the contact.
                flight.state_at(c.s, &self.work.event_exponentials, &mut state.y);
                let carry = several && Self::carry_from(&mut self.work, &flight, &state.y);
                state.tau += c.s;
                self.contact(state, c)?;
                if carry {
                    self.carry_across(state);
                }
            }
        }
        Ok(())
    }

    /// With several pairs, before a contact at the end of `flight`: its modal deviation there
    /// and the state `y` just before the contact, kept for [`Self::carry_across`]; `false`
    /// when the flight cannot give it. Out of line: the one-pair path stays as it was.
    #[inline(never)]
    fn carry_from(work: &mut Scratch, flight: &Flight<'_>, y: &DVector<f64>) -> bool {
        if !flight.deviation_at(&work.event_exponentials, &mut work.carried) {
            work.carried.clear();
            return false;
        }
        work.before_contact.clear();
        work.before_contact.extend_from_slice(y.as_slice());
        true
    }

    /// After the contact: the deviation plus the contact's jump of the state, valid for the
    /// state after it while the pairs fly free (dropped otherwise).
    #[inline(never)]
    fn carry_across(&mut self, state: &RunState) {
        let work = &mut self.work;
        if !matches!(state.mode, Mode::Free) {
            work.carried.clear();
            return;
        }
        self.free
            .add_jump(&mut work.carried, &work.before_contact, state.y.as_slice());
        work.carried_state.clear();
        work.carried_state.extend_from_slice(state.y.as_slice());
        work.carried_tau = state.tau;
    }

    /// A contact found by the search, with the state just before it: an impact if the pair
    /// approaches the stop, then a stick if the stop holds it (or the chatter would accumulate
    /// within [`CHATTER`] of a period); otherwise a graze, stepped past. In a stuck phase the
    /// impact keeps the held pairs' constraints and the stop's push is the constrained
    /// acceleration's; a stick adds the pair to the held set.
    fn contact(&mut self, state: &mut RunState, c: Contact) -> Result<(), SimulationError> {
        let n = self.n;
        state.count_event(self.period)?;
        if let Some(t) = state.tangent.as_mut() {
            t.before_impact = false;
        }
        let p = &self.pairs[c.pair];
        let side = c.side as f64;
        let rdot = p.direction.dot(&state.y.rows(n, n));
        // Only an approach counts as an impact; a start on the stop moving out of it (rounding)
        // is handled as sticking below. Velocities are known to rounding relative to their size:
        // a slower approach is a graze, not an impact.
        let velocity_round = VELOCITY_ROUNDING * state.y.rows(n, n).amax();
        let approaching = rdot * side > velocity_round;
        if approaching {
            self.impact(state, c, rdot);
        }
        // Stick? Post-impact relative speed, and the relative acceleration pushing into the
        // stop.
        let p = &self.pairs[c.pair];
        let e = p.spec.restitution;
        let rdot_after = p.direction.dot(&state.y.rows(n, n));
        let push = self.relative_acceleration(c.pair, &state.y, state.tau, state.mode) * side;
        let accumulation = if push > 0.0 && e < 1.0 {
            2.0 * rdot_after.abs() / (push * (1.0 - e))
        } else {
            f64::INFINITY
        };
        let stick = push > 0.0
            && (rdot_after.abs() <= self.resting_velocity + velocity_round
                || accumulation < CHATTER * self.period
                || !approaching);
        if stick {
            self.stick(state, c)?;
        } else if !approaching {
            // A touch that is neither an impact nor a hold (rounding at a graze): step past it
            // rather than find it again.
            state.grace[c.pair] = state.tau + self.release_grace;
        }
        Ok(())
    }

    /// Event: impact of pair `c.pair` on side `c.side`, approaching at `rdot`. Newton
    /// restitution along the contact direction, momentum kept.
    fn impact(&self, state: &mut RunState, c: Contact, rdot: f64) {
        if let Some(w) = state.window.as_mut() {
            w.impacts.push(ImpactRecord {
                time: state.k as f64 * self.period + state.tau,
                phase: state.tau,
                pair: c.pair,
                side: c.side,
                state_before: state.y.clone(),
                relative_velocity: rdot,
            });
        }
        let time = state.k as f64 * self.period + state.tau;
        if let Some(trace) = state.trace.as_mut() {
            trace
                .rows
                .push((time, RowKind::BeforeImpact, state.y.clone()));
            trace.impacts.push(TracedImpact {
                time,
                pair: c.pair,
                side: c.side,
                relative_velocity: rdot,
                state_before: state.y.clone(),
            });
        }
        if state.tangent.is_some() {
            self.impact_with_tangent(state, c);
        } else {
            let mode = state.mode;
            self.restitute(c.pair, &mut state.y, None, mode);
        }
        if let Some(trace) = state.trace.as_mut() {
            trace
                .rows
                .push((time, RowKind::AfterImpact, state.y.clone()));
        }
        state.impacts += 1;
        state.last_impact_period = Some(state.k);
    }

    /// The restitution of [`Self::impact`] with the tangent flow's saltation matrix (kept out of
    /// line: ordinary runs never come here).
    #[cold]
    #[inline(never)]
    fn impact_with_tangent(&self, state: &mut RunState, c: Contact) {
        if let Some(t) = state.tangent.as_mut() {
            let time = state.k as f64 * self.period + state.tau;
            // `product` keeps the Jacobian before the impact.
            if t.product.shape() != t.jacobian.shape() {
                t.product = t.jacobian.clone();
            } else {
                t.product.copy_from(&t.jacobian);
            }
            t.before_impact = true;
            self.apply_saltation(t, &self.pairs[c.pair], &state.y, state.tau);
            t.impacts.push((c.pair, c.side, time));
        }
        let mode = state.mode;
        self.restitute(c.pair, &mut state.y, None, mode);
    }

    /// The tangent flow through a flight of duration `span` (out of line, as above).
    #[cold]
    #[inline(never)]
    fn propagate_tangent(&self, tangent: &mut Tangent, span: f64) {
        self.free.propagator_into(span, &mut tangent.propagator);
        if tangent.product.shape() != tangent.jacobian.shape() {
            tangent.product = tangent.jacobian.clone();
        }
        tangent
            .product
            .gemm(1.0, &tangent.propagator, &tangent.jacobian, 0.0);
        std::mem::swap(&mut tangent.product, &mut tangent.jacobian);
    }

    /// Event: pair `c.pair` sticks on side `c.side`. Plastic: relative velocity to zero,
    /// momentum kept; the run continues on the reduced flow.
    fn stick(&mut self, state: &mut RunState, c: Contact) -> Result<(), SimulationError> {
        let time = state.k as f64 * self.period + state.tau;
        if let Some(trace) = state.trace.as_mut() {
            let after_impact = trace
                .rows
                .last()
                .is_some_and(|r| r.0 == time && r.1 == RowKind::AfterImpact);
            if !after_impact {
                trace
                    .rows
                    .push((time, RowKind::BeforeImpact, state.y.clone()));
            }
        }
        let mode = state.mode;
        self.restitute(c.pair, &mut state.y, Some(0.0), mode);
        if let Some(trace) = state.trace.as_mut() {
            trace
                .rows
                .push((time, RowKind::AfterStick, state.y.clone()));
        }
        if let Some(t) = state.tangent.as_mut() {
            self.stick_tangent(t, c.pair, state.k as f64 * self.period + state.tau);
        }
        let held = self.held_with(state.mode, c.pair, c.side);
        let index = self.stuck_index(&held)?;
        state.mode = Mode::Stuck(index);
        Ok(())
    }

    /// The tangent flow through a stick of pair `pair` at time `time` since the start (out of
    /// line): the plastic saltation matrix from the state before the contact (an impact
    /// resolved just before at the same contact is replaced by it, since the plastic map
    /// absorbs any restitution: `G₀ G_e = G₀`).
    ///
    /// A plastic reset `v⁺ = G₀ v⁻` (`G₀ = I − M⁻¹d dᵀ/w`, `w = dᵀM⁻¹d`) on the surface
    /// `h = d·u ∓ gap = 0`, onto the constrained flow `f_s`, has the saltation matrix
    /// `S = Ĝ₀ + (f_s⁺ − Ĝ₀ f⁻) h_xᵀ / ṙ⁻`. The constrained acceleration is the free one
    /// projected, `a_s = G₀ a`, so `f_s⁺ − Ĝ₀ f⁻ = ṙ⁻ (−M⁻¹d/w, G₀ M⁻¹ C M⁻¹d/w)`: the
    /// division cancels, and `S = Ĝ₀ + c h_xᵀ` with `c = (−M⁻¹d, G₀ M⁻¹C M⁻¹d)/w`, a
    /// constant of the pair, valid down to a contact at zero relative velocity. `S` maps every
    /// perturbation onto the constrained tangent space `d·δu = d·δu̇ = 0` (rank `2n − 2`).
    #[cold]
    #[inline(never)]
    fn stick_tangent(&self, t: &mut Tangent, pair: usize, time: f64) {
        let n = self.n;
        let p = &self.pairs[pair];
        let w = p.compliance;
        let mut s = DMatrix::<f64>::identity(2 * n, 2 * n);
        let projection = &p.mobility * p.direction.transpose() / w;
        let mut block = s.view_mut((n, n), (n, n));
        block -= &projection;
        let mut c = DVector::zeros(2 * n);
        c.rows_mut(0, n).copy_from(&(-&p.mobility / w));
        if self.model.has_damping() {
            let drag = &p.drag / w;
            let projected = &drag - &projection * &drag;
            c.rows_mut(n, n).copy_from(&projected);
        }
        let mut h_x = DVector::zeros(2 * n);
        h_x.rows_mut(0, n).copy_from(&p.direction);
        s += c * h_x.transpose();
        t.jacobian = if std::mem::take(&mut t.before_impact) {
            s * &t.product
        } else {
            s * &t.jacobian
        };
        t.sticking.get_or_insert(time);
        t.sticks += 1;
        if let Some(stuck) = t.stuck_pairs.get_mut(pair) {
            *stuck = true;
        }
    }

    /// The tangent flow through a stuck phase of duration `span` (out of line): the reduced
    /// flow's propagator `P_r` in the reduced coordinates, `δy ← E P_r Eᵀ δy` with
    /// `E = diag(T, T)` (`T` the orthonormal basis of `d⊥`). The tangent is already in the
    /// constrained space (the stick's saltation put it there), where `Eᵀ` is exact.
    ///
    /// The release that ends the phase needs no saltation: it happens where the contact force
    /// is zero, so the free and constrained vector fields agree there (`S = I`).
    #[cold]
    #[inline(never)]
    fn propagate_stuck_tangent(st: &Stuck, t: &mut Tangent, span: f64) {
        let n = st.basis.nrows();
        let nr = st.basis.ncols();
        let mut e = DMatrix::zeros(2 * n, 2 * nr);
        e.view_mut((0, 0), (n, nr)).copy_from(&st.basis);
        e.view_mut((n, nr), (n, nr)).copy_from(&st.basis);
        let reduced = st.flow.propagator(span);
        t.jacobian = &e * (reduced * (e.transpose() * &t.jacobian));
        t.stuck_time += span;
    }

    /// Event: the held pair at position `released` of the held set is let go `s` into the
    /// stuck phase (its contact force would pull); the others stay held, and the run
    /// continues on their constrained flow (free flight when none is left).
    fn release(
        &mut self,
        state: &mut RunState,
        index: usize,
        released: usize,
        s: f64,
    ) -> Result<(), SimulationError> {
        state.tau += s;
        let mut held = self.stuck[index].held.clone();
        let (pair, _) = held.remove(released);
        state.grace[pair] = state.tau + self.release_grace;
        state.mode = if held.is_empty() {
            Mode::Free
        } else {
            Mode::Stuck(self.stuck_index(&held)?)
        };
        state.count_event(self.period)
    }

    /// Stuck phase: the held pairs ride their stops on the constrained flow until one's
    /// contact force would pull (its release), another pair reaches a stop (a contact: impact,
    /// or a stick that joins the held set), or the next section.
    ///
    /// Every pair is watched at all times: the pairs not held are searched for their first
    /// contact in the constrained flow with the same guarantee as in free flight, and each
    /// held pair's contact force for its first sign change (the watch runs up to the first
    /// release). The earliest event ends the phase; a contact found at the release's instant
    /// is resolved first, and the release is found again at once by the next phase.
    fn stuck_phase(
        &mut self,
        state: &mut RunState,
        index: usize,
        plan: &Plan,
    ) -> Result<(), SimulationError> {
        let n = self.n;
        let period = self.period;
        let horizon = period - state.tau;
        let tau = state.tau;
        let st = &self.stuck[index];
        let nr = st.basis.ncols();
        // Reduced state: ũ = Tᵀ(u − u*), ũ̇ = Tᵀ u̇.
        let tt = st.basis.transpose();
        let mut yr = DVector::zeros(2 * nr);
        yr.rows_mut(0, nr)
            .copy_from(&(&tt * (state.y.rows(0, n) - &st.offset)));
        yr.rows_mut(nr, nr).copy_from(&(&tt * state.y.rows(n, n)));
        let flight = st.flow.flight(&yr, tau);
        let rotation = nalgebra::Complex::new(0.0, self.omega * tau).exp();
        // The first release: held while side·λ < 0, released at the first root of −side·λ.
        let mut release: Option<(f64, usize)> = None;
        for (position, (force, &(_, side))) in st.forces.iter().zip(&st.held).enumerate() {
            let mut lambda = flight.value_of(&force.state).shifted(force.constant);
            lambda.terms.push(crate::expsum::Term {
                poly: [
                    force.harmonic * rotation,
                    Default::default(),
                    Default::default(),
                    Default::default(),
                ],
                rate: nalgebra::Complex::new(0.0, self.omega),
            });
            let hold = if side > 0 { lambda.negated() } else { lambda };
            // `hold` ≥ 0 at the start: the release is its first exit from [0, ∞).
            if let Some((s, _)) = hold.first_exit(
                0.0,
                f64::INFINITY,
                release.map_or(horizon, |r| r.0),
                self.time_tolerance,
                0.0,
                &mut self.work.stack,
            ) {
                if release.is_none_or(|r| s < r.0) {
                    release = Some((s, position));
                }
            }
        }
        let watch_horizon = release.map_or(horizon, |r| r.0);
        let depth = self.contact_depth + POSITION_ROUNDING * state.y.rows(0, n).amax();
        let watch = if st.watched.is_empty() || watch_horizon <= 0.0 {
            Watch::Clear
        } else {
            Self::watch(
                &self.pairs,
                st.watched.iter().map(|(q, f, shift)| (*q, f, *shift)),
                None,
                &mut self.work,
                &flight,
                watch_horizon,
                self.time_tolerance,
                depth,
                &state.grace,
                tau,
            )
        };
        let span = match watch {
            Watch::Contact(c) => c.s,
            Watch::Step(s) => s,
            Watch::Clear => watch_horizon,
        };
        let full = |s: f64| {
            let r = flight.state(s);
            let mut out = DVector::zeros(2 * n);
            out.rows_mut(0, n)
                .copy_from(&(&st.basis * r.rows(0, nr) + &st.offset));
            out.rows_mut(n, n).copy_from(&(&st.basis * r.rows(nr, nr)));
            out
        };
        let k = state.k;
        if let Some(w) = state.window.as_mut() {
            w.sticking = true;
            for (j, amp) in w.amplitudes.iter_mut().enumerate() {
                // u_j = T_j · ũ + offset_j.
                let mut c = DVector::zeros(2 * nr);
                c.rows_mut(0, nr).copy_from(&st.basis.row(j).transpose());
                let f = flight.value_of(&c).shifted(st.offset[j]);
                *amp = f.max_abs(span, *amp, AMPLITUDE_TOLERANCE * (1.0 + *amp));
            }
            if plan.record_trajectory {
                sample(&mut w.trajectory, span, period, |s| {
                    (k as f64 * period + (tau + s), full(s))
                });
            }
        }
        if let Some(trace) = state.trace.as_mut() {
            trace.segment(k, period, tau, span, full);
        }
        state.y = full(span);
        if let Some(t) = state.tangent.as_mut() {
            Self::propagate_stuck_tangent(st, t, span);
        }
        match (watch, release) {
            (Watch::Contact(c), _) => {
                state.tau += span;
                self.contact(state, c)?;
            }
            (Watch::Step(_), _) => state.tau += span,
            (Watch::Clear, Some((s, position))) => self.release(state, index, position, s)?,
            (Watch::Clear, None) => state.tau = period,
        }
        Ok(())
    }

    /// The section check at `t = (k + 1)T`: the period is counted, the stroboscopic state
    /// recorded.
    fn section(&self, state: &mut RunState) {
        state.k += 1;
        if let Some(trace) = state.trace.as_mut() {
            trace.next = 0;
        }
        state.tau = 0.0;
        state.events_total += state.events_this_period;
        state.events_this_period = 0;
        // `grace` is a time within the period just ended.
        state.grace.fill(f64::NEG_INFINITY);
        if let Some(w) = state.window.as_mut() {
            w.stroboscopic.push(state.y.clone());
        }
        state.ring.push(&state.y);
    }

    /// At a section: applies the stopping rules' decision; `Some` when the run is over.
    fn terminate(
        &self,
        state: &mut RunState,
        plan: &Plan,
        watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
    ) -> Option<Stop> {
        match self.stopping_rule(state, plan) {
            Decision::Continue if !plan.fixed && state.observing.is_none() => {
                watch(state.k, &state.y).then_some(Stop::Watched)
            }
            Decision::Continue => None,
            Decision::Observe(observation) => {
                state.observing = Some(observation);
                state.window = None;
                None
            }
            Decision::Stop(stop) => Some(stop),
        }
    }

    /// The stopping rules, all of them, checked at each section in this order:
    ///
    /// 1. **Event cap** ([`SimulationOptions::max_events`]): a motion with very many events per
    ///    period would take unbounded time; observe one more stretch for the amplitudes, then
    ///    stop ([`Stop::EventCap`]).
    /// 2. **Quiet**: undamped and no impact for [`QUIET`] periods, nothing will ever dissipate
    ///    the transients; observe one more stretch, then stop ([`Stop::Decided`]).
    /// 3. **End of the run**: after an observed stretch, for its reason; otherwise at the plan's
    ///    limit: the fixed number of periods ([`Stop::FixedPeriods`]), the period cap
    ///    ([`Stop::PeriodCap`], [`CONSERVATIVE_MAX_PERIODS`] for units that cannot settle) or
    ///    the oscillation cap ([`Stop::OscillationCap`]), whichever is smaller, so every run
    ///    ends.
    /// 4. **Periodic**: the stroboscopic state repeats with least multiplicity `p`
    ///    ([`least_period`]); observe the `p`-period cycle for its amplitudes and impacts, then
    ///    stop ([`Stop::Decided`]).
    ///
    /// Rules 1, 2 and 4 only apply while running until steady and nothing is decided yet.
    fn stopping_rule(&self, state: &RunState, plan: &Plan) -> Decision {
        let deciding = !plan.fixed && state.observing.is_none();
        let observe = |cycle: u64, then: Stop| {
            Decision::Observe(Observation {
                until: state.k + cycle,
                cycle: cycle as u32,
                then,
            })
        };
        if deciding && plan.max_events.is_some_and(|cap| state.events_total > cap) {
            return observe(plan.window_len, Stop::EventCap);
        }
        let quiet = deciding
            && !self.model.has_damping()
            && state.k >= QUIET
            && state
                .last_impact_period
                .is_none_or(|last| state.k - last > QUIET);
        if quiet && state.window.is_none() {
            return observe(plan.window_len, Stop::Decided);
        }
        match state.observing {
            Some(o) if state.k >= o.until => return Decision::Stop(o.then),
            None if state.k >= plan.limit => return Decision::Stop(plan.at_limit),
            _ => {}
        }
        if deciding {
            if let Some(p) = least_period(
                &state.ring,
                plan.p_max,
                plan.periodicity_tolerance,
                self.scale,
            ) {
                return observe(p as u64, Stop::Decided);
            }
        }
        Decision::Continue
    }

    /// The steady state (or the tail of the run) from the final state.
    fn report(&self, state: RunState, stopped: Stop, plan: &Plan) -> SteadyState {
        let period = self.period;
        let k = state.k;
        let ring = &state.ring;
        let window = match stopped {
            Stop::Watched => Window::default(),
            _ => state.window.unwrap_or_default(),
        };
        // A period decided while running is confirmed at the end with CONFIRMATION times the
        // tolerance; a run stopped by a cap or a fixed run is judged from its tail alone.
        let period_found = match state.observing {
            Some(o) if o.then == Stop::Decided => {
                (repeat_error(ring, o.cycle as usize, scale_floor(ring, self.scale))
                    <= CONFIRMATION * plan.periodicity_tolerance)
                    .then_some(o.cycle)
            }
            _ => least_period(ring, plan.p_max, plan.periodicity_tolerance, self.scale),
        };
        let no_recent_impacts = state
            .last_impact_period
            .is_none_or(|last| k.saturating_sub(last) > plan.window_len);
        let status = match period_found {
            Some(_) => Status::Periodic,
            None if self.model.conservative()
                || (!self.model.has_damping() && no_recent_impacts) =>
            {
                Status::NoDissipation
            }
            None => Status::NonPeriodic,
        };
        // The final cycle: the last p periods of the window (or the whole window).
        let cycle = match period_found {
            Some(p) => p as u64,
            None => (window.stroboscopic.len().saturating_sub(1) as u64).max(1),
        };
        let cycle_start = (k - cycle.min(k)) as f64 * period;
        let slack = CYCLE_START_SLACK * period;
        let cycle_impacts: Vec<ImpactRecord> = window
            .impacts
            .iter()
            .filter(|i| i.time >= cycle_start - slack)
            .cloned()
            .collect();
        let stroboscopic: Vec<DVector<f64>> = window
            .stroboscopic
            .iter()
            .skip(window.stroboscopic.len().saturating_sub(cycle as usize + 1))
            .cloned()
            .collect();
        let trajectory = plan.record_trajectory.then(|| {
            window
                .trajectory
                .into_iter()
                .filter(|(t, _)| *t >= cycle_start - slack)
                .collect()
        });
        SteadyState {
            status,
            period: period_found,
            impacts_per_period: cycle_impacts.len() as f64 / cycle as f64,
            amplitudes: window.amplitudes,
            sticking: window.sticking,
            stopped,
            periods_run: k,
            impacts: state.impacts,
            cycle_impacts,
            stroboscopic,
            final_state: Start {
                state: state.y,
                time: 0.0,
            },
            trajectory,
            orbit: None,
            orbit_error: None,
        }
    }
}

/// Dense samples of a segment: [`SAMPLES_PER_PERIOD`] per forcing period, ends included.
fn sample<F: Fn(f64) -> (f64, DVector<f64>)>(
    out: &mut Vec<(f64, DVector<f64>)>,
    span: f64,
    period: f64,
    at: F,
) {
    let count = ((span / period) * SAMPLES_PER_PERIOD).ceil().max(1.0) as usize;
    for i in 0..=count {
        out.push(at(span * i as f64 / count as f64));
    }
}

/// The floor of the scale of [`repeat_error`]: the gap, or the motion's own size (the largest
/// state in `ring`) when that is smaller, so that a unit that never comes near its stops is
/// judged on its own scale.
fn scale_floor(ring: &Sections, gap: f64) -> f64 {
    gap.min(ring.norms.iter().copied().fold(0.0, f64::max))
}

/// The stroboscopic history of a run: the states at its last sections, at most `capacity`,
/// each with its norm, computed once when it is recorded (the periodicity test reads every
/// norm at every section). A full history recycles its oldest state's storage.
struct Sections {
    states: VecDeque<DVector<f64>>,
    norms: VecDeque<f64>,
    capacity: usize,
}

impl Sections {
    /// An empty history of at most `capacity` sections.
    fn new(capacity: usize) -> Self {
        Self {
            states: VecDeque::with_capacity(capacity),
            norms: VecDeque::with_capacity(capacity),
            capacity,
        }
    }

    /// Records the state `y` at a section, dropping the oldest beyond the capacity.
    fn push(&mut self, y: &DVector<f64>) {
        let recycled = (self.states.len() >= self.capacity)
            .then(|| {
                self.norms.pop_front();
                self.states.pop_front()
            })
            .flatten();
        match recycled {
            Some(mut v) => {
                v.copy_from(y);
                self.states.push_back(v);
            }
            None => self.states.push_back(y.clone()),
        }
        self.norms.push_back(y.norm());
    }

    /// Sections recorded.
    fn len(&self) -> usize {
        self.states.len()
    }
}

/// Largest `|x_k − x_{k−p}|` over the last two sections (`∞` if too few), relative to
/// `max(|x_k|, floor)`.
fn repeat_error(ring: &Sections, p: usize, floor: f64) -> f64 {
    let len = ring.len();
    if len <= p + 1 {
        return f64::INFINITY;
    }
    (0..2)
        .map(|back| {
            let a = &ring.states[len - 1 - back];
            let b = &ring.states[len - 1 - back - p];
            let diff = a
                .iter()
                .zip(b.iter())
                .map(|(x, y)| (x - y) * (x - y))
                .sum::<f64>()
                .sqrt();
            diff / ring.norms[len - 1 - back].max(floor).max(SCALE_FLOOR)
        })
        .fold(0.0, f64::max)
}

/// Whether [`repeat_error`]`(ring, p, floor)` certainly exceeds `bound`, from the squared
/// difference at the last section alone, without a square root or a division: most
/// multiplicities at most sections are far from repeating, and the periodicity test is a
/// sizeable share of a run with few impacts per period. The margin of 1 % covers the rounding
/// of the squares and the square root, so that the test decides exactly as `repeat_error`
/// would; a `false` says nothing.
fn clearly_no_repeat(ring: &Sections, p: usize, floor: f64, bound: f64) -> bool {
    let last = ring.len() - 1;
    let (a, b) = (&ring.states[last], &ring.states[last - p]);
    let squared: f64 = a.iter().zip(b.iter()).map(|(x, y)| (x - y) * (x - y)).sum();
    let limit = NO_REPEAT_MARGIN * bound * ring.norms[last].max(floor).max(SCALE_FLOOR);
    squared > limit * limit
}

/// The margin of [`clearly_no_repeat`]: far above the few rounding units of a sum of squares
/// and its square root.
const NO_REPEAT_MARGIN: f64 = 1.01;

/// The least `p` with `|x_k − x_{k−p}| ≤ tol·scale` at the last two sections, provided no
/// smaller multiplicity comes within [`AMBIGUITY`] of the tolerance (then it is too early to
/// tell, and `None` is returned).
fn least_period(ring: &Sections, p_max: usize, tol: f64, gap: f64) -> Option<u32> {
    let floor = scale_floor(ring, gap);
    for p in 1..=p_max {
        if ring.len() <= p + 1 {
            return None;
        }
        if clearly_no_repeat(ring, p, floor, AMBIGUITY * tol) {
            continue;
        }
        let d = repeat_error(ring, p, floor);
        if d <= tol {
            return Some(p as u32);
        }
        if d <= AMBIGUITY * tol {
            return None;
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// [`least_period`] as it was before [`clearly_no_repeat`]: every multiplicity's exact
    /// [`repeat_error`].
    fn least_period_exact(ring: &Sections, p_max: usize, tol: f64, gap: f64) -> Option<u32> {
        let floor = scale_floor(ring, gap);
        for p in 1..=p_max {
            if ring.len() <= p + 1 {
                return None;
            }
            let d = repeat_error(ring, p, floor);
            if d <= tol {
                return Some(p as u32);
            }
            if d <= AMBIGUITY * tol {
                return None;
            }
        }
        None
    }

    /// Rings of states that repeat with period 1–4 up to a perturbation swept across the
    /// tolerance and the ambiguity band (random, or alternating as a transient through a
    /// multiplier −1), at scales from 1e-8 to 1e8: the shortcut decides
    /// exactly as every multiplicity's exact error does, and the sweep reaches all three
    /// outcomes (a period, too early to tell, none).
    #[test]
    fn the_shortcut_decides_as_the_exact_errors() {
        let mut seed: u64 = 0x9e37_79b9_7f4a_7c15;
        let mut uniform = move || {
            seed = seed
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let tol = 1e-9;
        let (mut periodic, mut ambiguous, mut none) = (0, 0, 0);
        for case in 0..4000 {
            let scale = 10f64.powi((case % 17) as i32 - 8);
            let period = 1 + (case / 2) % 4;
            let size = 10f64.powf(-12.0 + 10.0 * (uniform() + 0.5));
            let cycle: Vec<DVector<f64>> = (0..period)
                .map(|_| DVector::from_fn(4, |_, _| scale * uniform()))
                .collect();
            // Half the cases: a transient through a multiplier −1 (the state alternates by a
            // fixed `size` about a period-`period` cycle), ambiguous at `period` while it
            // repeats at `2 period`.
            let alternating = DVector::from_fn(4, |_, _| scale * size * uniform());
            let mut ring = Sections::new(18);
            for k in 0..18 {
                let noise = if case % 2 == 0 {
                    DVector::from_fn(4, |_, _| scale * size * uniform())
                } else if k % 2 == 0 {
                    alternating.clone()
                } else {
                    -&alternating
                };
                ring.push(&(&cycle[k % period] + noise));
            }
            let exact = least_period_exact(&ring, 16, tol, 0.5 * scale);
            assert_eq!(
                least_period(&ring, 16, tol, 0.5 * scale),
                exact,
                "case {case}"
            );
            let smallest = (1..=16)
                .map(|p| repeat_error(&ring, p, scale_floor(&ring, 0.5 * scale)))
                .fold(f64::INFINITY, f64::min);
            match exact {
                Some(_) => periodic += 1,
                None if smallest <= AMBIGUITY * tol => ambiguous += 1,
                None => none += 1,
            }
        }
        assert!(
            periodic > 100 && ambiguous > 100 && none > 100,
            "{periodic} {ambiguous} {none}"
        );
    }
}
