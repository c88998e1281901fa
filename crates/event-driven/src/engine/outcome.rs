//! What a run reports: its status, why it stopped, the impacts it observed, the steady state
//! (with the periodic orbit the Newton polished it to).

use super::*;
use nalgebra::Complex;

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
    /// The caller's section watch ended the run ([`simulate_watched`](crate::simulate_watched)) before anything was
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
    /// A periodic final cycle without impact (and not held on a stop) of a model with rigid
    /// modes ([`LinearFlow::rigid_modes`](crate::flow::LinearFlow::rigid_modes): a free body):
    /// the motion is one member of a family of steady states, a rigid mode keeping whatever
    /// constant position the run left it at (the linear steady state is unique only up to
    /// rigid translations). Its cycle is not polished ([`Self::orbit`] is `None`,
    /// [`Self::orbit_error`] gives [`NewtonError::Family`](crate::newton::NewtonError::Family)'s
    /// reason): no isolated orbit exists.
    pub family: bool,
    /// Least `p` with `x(t + pT) = x(t)`, when periodic.
    pub period: Option<u32>,
    /// Impacts in the final cycle divided by its length in periods: rigid stops' impacts
    /// only (a compliant stop's contacts are [`Self::cycle_contacts`]).
    pub impacts_per_period: f64,
    /// `max |u_k|` over the final cycle, per degree of freedom, from closed-form extrema: of
    /// one cycle run from the polished orbit when the run polishes one ([`Self::orbit`]),
    /// else of the last simulated cycle.
    pub amplitudes: Vec<f64>,
    /// Whether the final cycle contains sticking.
    pub sticking: bool,
    /// Why the run ended.
    pub stopped: Stop,
    /// Forcing periods simulated.
    pub periods_run: u64,
    /// Impacts over the whole run.
    pub impacts: u64,
    /// Impacts of the final cycle (rigid stops only).
    pub cycle_impacts: Vec<ImpactRecord>,
    /// The contact phases of compliant stops ([`crate::Compliance`]) that end in the final
    /// cycle, in the order they end (a contact through the cycle's start is one of them, with
    /// its entry before the start); empty for a model of rigid stops.
    pub cycle_contacts: Vec<ContactRecord>,
    /// Time spent in contact with compliant stops over the final cycle (summed over pairs),
    /// divided by its length in periods; `0` for a model of rigid stops.
    pub contact_time_per_period: f64,
    /// Contact phases of compliant stops ending in the final cycle ([`Self::cycle_contacts`])
    /// divided by its length in periods; `0` for a model of rigid stops.
    pub contacts_per_period: f64,
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

/// A periodic orbit found by Newton on the simulator's stroboscopic map.
#[derive(Debug, Clone, PartialEq)]
pub struct PeriodicOrbit {
    /// The state `(u, u̇)` at the section, the fixed point of the `periods`-period map.
    pub state: DVector<f64>,
    /// The time of the section (the guess's time): the orbit passes through [`Self::state`]
    /// at `time + k·periods·T`.
    pub time: f64,
    /// The section's time within the forcing period, in `[0, T)`.
    pub phase: f64,
    /// Forcing periods per cycle `p`.
    pub periods: u32,
    /// The impacts over one cycle in time order from the section: `+1` side 1, `−1` side 2.
    pub impact_sides: Vec<i8>,
    /// The impacts' times after the section as fractions of the cycle `pT`, in `[0, 1)`.
    pub impact_phases: Vec<f64>,
    /// The compliant stops' contact phases over one cycle, in time order of their entries
    /// from the section, entry and exit as fractions of the cycle (a contact through the
    /// section has its exit below its entry); empty for a model of rigid stops.
    pub contact_phases: Vec<ContactPhase>,
    /// The eigenvalues of `DP` at the fixed point: the simulator's own Floquet multipliers.
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Newton steps taken.
    pub iterations: u32,
    /// The final `|P(y) − y|`, relative to `max(|y|, gap)`: at most
    /// [`NEWTON_TOLERANCE_FACTOR`](crate::newton::NEWTON_TOLERANCE_FACTOR) × [`SimulationOptions::root_tolerance`], or at most
    /// [`NEWTON_FLOOR_FACTOR`](crate::newton::NEWTON_FLOOR_FACTOR) times that when the map's rounding floor was reached.
    pub residual: f64,
}

/// One contact phase of a compliant stop in the final cycle ([`SteadyState::cycle_contacts`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactRecord {
    /// Contact pair index.
    pub pair: usize,
    /// `+1` for side 1 (`r = +gap_plus`), `−1` for side 2.
    pub side: i8,
    /// Absolute time of the entry (the run's start for a pair pressed there).
    pub entry_time: f64,
    /// Absolute time of the exit.
    pub exit_time: f64,
    /// The entry's time within the forcing period, in `[0, T)`.
    pub entry_phase: f64,
    /// The exit's time within the forcing period, in `[0, T)` (below the entry's for a
    /// contact through a section).
    pub exit_phase: f64,
    /// `ṙ` at the entry (into the stop).
    pub entry_velocity: f64,
    /// `ṙ` at the exit (out of the stop, or `0` to rounding when the contact ends at rest).
    pub exit_velocity: f64,
    /// The largest penetration `δ = side·r − gap_side` during the contact.
    pub max_penetration: f64,
}

/// One contact phase of a compliant stop over a cycle of the stroboscopic map or of a
/// periodic orbit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactPhase {
    /// Contact pair index.
    pub pair: usize,
    /// `+1` for side 1 (`r = +gap_plus`), `−1` for side 2.
    pub side: i8,
    /// In a [`crate::StroboscopicMap`], the entry's time after the section (`0` for a pair
    /// pressed at the section); in a [`PeriodicOrbit`], as a fraction of the cycle `pT`, in
    /// `[0, 1)`.
    pub entry: f64,
    /// In a [`crate::StroboscopicMap`], the exit's time after the section (the cycle's
    /// length `pT` for a pair still pressed at its end); in a [`PeriodicOrbit`], as a
    /// fraction of the cycle in `[0, 1)`, below [`Self::entry`] for a contact through the
    /// section.
    pub exit: f64,
}
