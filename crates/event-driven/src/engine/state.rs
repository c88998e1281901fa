//! The state of a run (everything that changes from one step to the next) and the run's caps.

use super::*;

/// Free flight, a set of pairs held on their stops (an index into `Engine::stuck`), or a set
/// of compliant pairs pressed into theirs (an index into `Engine::pressed`).
#[derive(Clone, Copy)]
pub(super) enum Mode {
    Free,
    Stuck(usize),
    Pressed(usize),
}

/// The first contact of a flight: `s` after its start, pair `pair`, on `side`.
#[derive(Clone, Copy)]
pub(super) struct Contact {
    pub(super) s: f64,
    pub(super) pair: usize,
    pub(super) side: i8,
}

/// The run's caps, fixed by the options before the first step.
pub(super) struct Plan {
    /// Largest period multiplicity looked for.
    pub(super) p_max: usize,
    /// The run ends after this many periods unless a rule ends it earlier.
    pub(super) limit: u64,
    /// Why the run ended, if it reaches `limit`.
    pub(super) at_limit: Stop,
    /// Periods observed at the end of a run that found no period (amplitudes, impacts).
    pub(super) window_len: u64,
    /// A fixed number of periods: no rule ends the run early.
    pub(super) fixed: bool,
    pub(super) max_events: Option<u64>,
    pub(super) periodicity_tolerance: f64,
    pub(super) record_trajectory: bool,
    /// The periodicity rule is not applied before this section: a run resumed off a cycle
    /// that proved unstable ([`Resume`]) first runs until a departure from it would show.
    pub(super) hold: u64,
}

impl Plan {
    /// Exactly `periods` periods, nothing observed and no event cap: the runs of the tangent
    /// flow and of the trace.
    pub(super) fn fixed(periods: u64) -> Self {
        Self {
            p_max: 1,
            limit: periods,
            at_limit: Stop::FixedPeriods,
            window_len: 0,
            fixed: true,
            max_events: None,
            periodicity_tolerance: DEFAULT_PERIODICITY_TOLERANCE,
            record_trajectory: false,
            hold: 0,
        }
    }
}

/// A run resumed where an earlier one stopped on a cycle that the simulator's Newton found
/// unstable: the periods and impacts spent so far (the caps count them), and the periods to
/// run before the periodicity rule applies again.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Resume {
    /// Periods already run.
    pub(crate) periods: u64,
    /// Impacts already made (counted against the event cap).
    pub(crate) impacts: u64,
    /// Periods of this run before periodicity is tested.
    pub(crate) hold: u64,
}

/// A decision taken at a section: run `until` period `until`, observing the final `cycle`
/// periods, then stop for `then`.
#[derive(Clone, Copy)]
pub(super) struct Observation {
    pub(super) until: u64,
    pub(super) cycle: u32,
    pub(super) then: Stop,
}

/// What the stopping rules decide at a section.
pub(super) enum Decision {
    /// Keep going.
    Continue,
    /// Observe a final stretch (amplitudes, impacts), then stop.
    Observe(Observation),
    /// The run is over.
    Stop(Stop),
}

/// Records kept while the final cycle is being observed.
#[derive(Default)]
pub(super) struct Window {
    pub(super) impacts: Vec<ImpactRecord>,
    /// The compliant contacts ended in the window.
    pub(super) contacts: Vec<ContactRecord>,
    pub(super) amplitudes: Vec<f64>,
    pub(super) sticking: bool,
    pub(super) stroboscopic: Vec<DVector<f64>>,
    pub(super) trajectory: Vec<(f64, DVector<f64>)>,
}

/// The state of a run: everything that changes from one step to the next.
pub(super) struct RunState {
    /// Forcing periods completed: the last section crossed is `t = kT`.
    pub(super) k: u64,
    /// Time within the current period, in `[0, T]` (time is carried modulo the period so the
    /// forcing phase stays exact).
    pub(super) tau: f64,
    /// `(u, u̇)` at `kT + tau` (but see `section_unformed`).
    pub(super) y: DVector<f64>,
    /// Whether `y` is not the state at the section just reached: a section of a fixed run
    /// that nothing observes ([`Engine::unobserved_section`]), reached by a flight carried
    /// past it ([`Pending`](super::flight::Pending)), which goes on from its own start, not
    /// from `y`; `y` then holds the state that flight started from until the flight forms the
    /// state again (at its contact or at the next section). Cleared by the section's check,
    /// which then records no state.
    pub(super) section_unformed: bool,
    /// Free, held on a stop, or pressed into compliant stops.
    pub(super) mode: Mode,
    /// The compliant contacts under way.
    pub(super) open_contacts: Vec<OpenContact>,
    /// Impacts over the whole run.
    pub(super) impacts: u64,
    /// Events (impacts, grazes, sticks, releases) in the current period.
    pub(super) events_this_period: u64,
    /// Events in the completed periods.
    pub(super) events_total: u64,
    /// The period of the last impact.
    pub(super) last_impact_period: Option<u64>,
    /// Per pair: its contacts are ignored before this time within the period (just after its
    /// release or graze); `−∞` when none is pending.
    pub(super) grace: Vec<f64>,
    /// Stroboscopic history: the states at the last `p_max + 2` sections.
    pub(super) ring: Sections,
    /// Records of the final stretch, once it has begun.
    pub(super) window: Option<Window>,
    /// The stopping rules' decision to end the run after an observed final stretch.
    pub(super) observing: Option<Observation>,
    /// The tangent flow, when asked for ([`Engine::tangent_run`]); `None` in ordinary runs.
    pub(super) tangent: Option<Tangent>,
    /// Exact samples of the run, when asked for ([`Engine::trace_run`]); `None` otherwise.
    pub(super) trace: Option<Trace>,
}

impl RunState {
    /// Absolute time of the time `tau` within the current period of length `period`.
    pub(super) fn absolute(&self, period: f64, tau: f64) -> f64 {
        self.k as f64 * period + tau
    }

    /// Counts one event of the current period.
    ///
    /// # Errors
    /// [`SimulationError::EventStorm`] past [`EVENT_STORM`] events in one period.
    pub(super) fn count_event(&mut self, period: f64) -> Result<(), SimulationError> {
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
