//! The loop: `init`, `next_iter` (a free flight or a stuck phase) and, at each section,
//! `terminate`, then the report.

use super::*;

/// Periods a fixed run lasts at least for its searches to recall their exits as starts of
/// later polishes ([`SearchStack::recall`](crate::expsum::SearchStack)): a long fixed run
/// repeats its flights once its transient has decayed, and a polish started at the exit a
/// period earlier takes one evaluation (`unit_long`, 10⁶ periods: 0.67 → 0.51 s of CPU). A run
/// until periodic stops soon after its flights start repeating, and the engine's own fixed
/// stretches (a run's final stretch, a Newton evaluation of one cycle) last a few periods:
/// there the bookkeeping costs more than it saves (a sweep and a map 1 to 2 % slower with
/// recall in every run), and the contact times' last bits would move.
pub(crate) const RECALL_PERIODS: u64 = 1000;

impl Engine<'_> {
    /// The run: `init`, then `next_iter` until `terminate` says why it ends, then the report.
    pub(crate) fn run(
        &mut self,
        start: &Start,
        options: &SimulationOptions,
        watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
    ) -> Result<SteadyState, SimulationError> {
        self.run_resumed(start, options, Resume::default(), watch)
    }

    /// As [`Engine::run`], resumed after `resume.periods` periods and `resume.impacts`
    /// impacts of an earlier run (which the caps count, and the watch's section numbers
    /// continue), the periodicity rule held for `resume.hold` periods. The report counts this
    /// run's periods and impacts only.
    pub(crate) fn run_resumed(
        &mut self,
        start: &Start,
        options: &SimulationOptions,
        resume: Resume,
        watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
    ) -> Result<SteadyState, SimulationError> {
        let mut plan = self.plan(options);
        plan.limit = plan.limit.saturating_sub(resume.periods);
        plan.window_len = plan.window_len.min(plan.limit);
        plan.max_events = plan
            .max_events
            .map(|cap| cap.saturating_sub(resume.impacts));
        plan.hold = resume.hold;
        self.work.stack.recall = plan.fixed && plan.limit >= RECALL_PERIODS;
        let mut state = self.init(start, &plan)?;
        let mut watch = |k: u64, y: &DVector<f64>| watch(k + resume.periods, y);
        let stop = loop {
            if self.next_iter(&mut state, &plan)? {
                if let Some(stop) = self.terminate(&mut state, &plan, &mut watch) {
                    break stop;
                }
            }
        };
        Ok(self.report(state, stop, &plan))
    }

    /// The caps of this run.
    pub(super) fn plan(&self, options: &SimulationOptions) -> Plan {
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
            hold: 0,
        }
    }

    /// The state at the start: free (or pressed on the compliant pairs beyond a stop:
    /// [`Engine::initial_mode`]), at `start`, its time carried modulo the period. A run
    /// starts afresh: a flight left pending by an earlier run of this engine is dropped.
    ///
    /// # Errors
    /// [`SimulationError::Flow`] when a pressed start's flow does not exist.
    pub(super) fn init(&mut self, start: &Start, plan: &Plan) -> Result<RunState, SimulationError> {
        self.drop_pending();
        let mode = self.initial_mode(&start.state)?;
        let open_contacts = self.initial_contacts(mode, &start.state, start.time);
        let mut state = RunState {
            k: 0,
            tau: start.time.rem_euclid(self.period),
            y: start.state.clone(),
            section_unformed: false,
            mode,
            open_contacts,
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
        Ok(state)
    }

    /// One step: a free flight or a stuck phase, up to its first event or to the next section
    /// `t = (k + 1)T`; at the section, the section check. Returns whether a section was reached.
    ///
    /// # Errors
    /// [`SimulationError::EventStorm`], and [`SimulationError::Flow`] when a stuck flow does not
    /// exist.
    pub(super) fn next_iter(
        &mut self,
        state: &mut RunState,
        plan: &Plan,
    ) -> Result<bool, SimulationError> {
        if self.open_window(state, plan) {
            // The final stretch starts afresh at its section, as a run started there does
            // (a trace of the final cycle): the same steps, to the bit.
            self.drop_pending();
        }
        match state.mode {
            Mode::Free => self.free_flight(state, plan)?,
            Mode::Stuck(index) => self.stuck_phase(state, index, plan)?,
            Mode::Pressed(index) => self.pressed_phase(state, index, plan)?,
        }
        if state.tau < self.period {
            return Ok(false);
        }
        self.section(state);
        Ok(true)
    }

    /// Starts recording the final stretch when its first period begins; `true` when it does.
    pub(super) fn open_window(&self, state: &mut RunState, plan: &Plan) -> bool {
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
            return true;
        }
        false
    }

    /// The section check at `t = (k + 1)T`: the period is counted, the stroboscopic state
    /// recorded.
    pub(super) fn section(&self, state: &mut RunState) {
        state.k += 1;
        if let Some(trace) = state.trace.as_mut() {
            trace.next = 0;
        }
        state.tau = 0.0;
        state.events_total += state.events_this_period;
        state.events_this_period = 0;
        // `grace` is a time within the period just ended.
        state.grace.fill(f64::NEG_INFINITY);
        if std::mem::take(&mut state.section_unformed) {
            // A section nothing observes (`Engine::unobserved_section`): its state is neither
            // formed nor recorded.
            return;
        }
        if let Some(w) = state.window.as_mut() {
            w.stroboscopic.push(state.y.clone());
        }
        state.ring.push(&state.y);
    }

    /// Whether the section that ends the current period is one nothing observes: in a run of
    /// a fixed number of periods (no stopping rule reads the sections, no watch is called)
    /// that records nothing (no trace, tangent or final-stretch window yet), more than the
    /// ring's length (`p_max + 2` sections) before the final stretch opens. Its state would go
    /// only to the stroboscopic ring, whose states are all replaced by later ones before the
    /// run reads the ring (in its report), so a flight carried past it need not form it: the
    /// run's results are bit for bit those of one that does.
    pub(super) fn unobserved_section(&self, state: &RunState, plan: &Plan) -> bool {
        #[cfg(test)]
        if self.form_every_section {
            return false;
        }
        let window_start = match state.observing {
            Some(_) => return false,
            None => plan.limit.saturating_sub(plan.window_len),
        };
        plan.fixed
            && state.window.is_none()
            && state.trace.is_none()
            && state.tangent.is_none()
            && (state.k + 1).saturating_add(state.ring.capacity as u64) < window_start
    }

    /// At a section: applies the stopping rules' decision; `Some` when the run is over.
    pub(super) fn terminate(
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
    ///    stop ([`Stop::Decided`]). Not before the plan's `hold` (a run resumed off an
    ///    unstable cycle).
    ///
    /// Rules 1, 2 and 4 only apply while running until steady and nothing is decided yet.
    pub(super) fn stopping_rule(&self, state: &RunState, plan: &Plan) -> Decision {
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
        if deciding && state.k >= plan.hold {
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
    pub(super) fn report(&self, state: RunState, stopped: Stop, plan: &Plan) -> SteadyState {
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
        // A contact belongs to the cycle its exit is in: one through the cycle's start is
        // counted once, as the same contact through its end is not over yet.
        let cycle_contacts: Vec<ContactRecord> = window
            .contacts
            .iter()
            .filter(|c| c.exit_time >= cycle_start - slack)
            .cloned()
            .collect();
        let contact_time = cycle_contacts
            .iter()
            .fold(0.0, |sum, c| sum + (c.exit_time - c.entry_time));
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
        let family = status == Status::Periodic
            && cycle_impacts.is_empty()
            && cycle_contacts.is_empty()
            && !window.sticking
            && self.free.rigid_modes() > 0;
        SteadyState {
            status,
            family,
            period: period_found,
            impacts_per_period: cycle_impacts.len() as f64 / cycle as f64,
            contacts_per_period: cycle_contacts.len() as f64 / cycle as f64,
            amplitudes: window.amplitudes,
            sticking: window.sticking,
            stopped,
            periods_run: k,
            impacts: state.impacts,
            cycle_impacts,
            cycle_contacts,
            contact_time_per_period: contact_time / cycle as f64,
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{paper_unit, LIGHT_DAMPING};

    /// A fixed run that leaves its unobserved sections unformed against the same run forming
    /// every one: the same report, bit for bit, over runs that leave most sections unformed.
    #[test]
    fn unformed_sections_change_no_result() {
        for (omega, periods) in [(2.0, 400), (1.3, 300), (2.6, 500)] {
            let model = paper_unit(omega, Some(LIGHT_DAMPING), Some((0.5, 0.8)));
            let options = SimulationOptions {
                fixed_periods: Some(periods),
                ..SimulationOptions::default()
            };
            let run = |form_every_section: bool| {
                let mut engine = Engine::new(&model, omega, &options).unwrap();
                engine.form_every_section = form_every_section;
                let report = engine
                    .run(&Start::rest(2), &options, &mut |_, _| false)
                    .unwrap();
                (report, engine.unformed_sections.get())
            };
            let (lazy, unformed) = run(false);
            let (formed, none) = run(true);
            assert_eq!(none, 0);
            assert!(
                unformed > periods / 4,
                "omega {omega}: {unformed} sections unformed"
            );
            let bits = |y: &DVector<f64>| y.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&lazy.final_state.state),
                bits(&formed.final_state.state)
            );
            assert_eq!(lazy.stroboscopic.len(), formed.stroboscopic.len());
            for (a, b) in lazy.stroboscopic.iter().zip(&formed.stroboscopic) {
                assert_eq!(bits(a), bits(b));
            }
            assert_eq!(lazy, formed, "omega {omega}");
        }
    }

    /// A chain's run that forms at its contacts only the entries an impact that cannot stick
    /// reads ([`Engine::before_contact`]) against the same run forming the whole state at
    /// every contact: the same report, bit for bit (the same impacts, stroboscopic states and
    /// final state). Over runs that bounce, in which most contacts are not formed whole, and
    /// one that sticks (restitution 0.3 at 1 rad/s), in which the contacts that may stick are
    /// formed whole and the others not.
    #[test]
    fn unformed_contact_states_change_no_result() {
        use crate::test_models::paper_chain;
        use crate::CellStops;
        for (cells, omega, restitution, sticks) in [
            (3, 2.0, 0.8, false),
            (4, 1.3, 0.8, false),
            (2, 1.0, 0.3, true),
        ] {
            let stops = CellStops::symmetric(0.5, restitution);
            let model = paper_chain(cells, omega, Some(LIGHT_DAMPING), Some(stops));
            let options = SimulationOptions {
                fixed_periods: Some(200),
                ..SimulationOptions::default()
            };
            let run = |form_every_contact: bool| {
                let mut engine = Engine::new(&model, omega, &options).unwrap();
                engine.form_every_contact = form_every_contact;
                let report = engine
                    .run(&Start::rest(2 * cells), &options, &mut |_, _| false)
                    .unwrap();
                (report, engine.unformed_contacts.get())
            };
            let (lazy, unformed) = run(false);
            let (formed, none) = run(true);
            assert_eq!(none, 0);
            let impacts = lazy.impacts;
            let case =
                format!("{cells} cells at {omega}: {unformed} of {impacts} impacts unformed");
            assert!(unformed > impacts / 4, "{case}");
            assert_eq!(lazy.sticking, sticks, "{case}");
            if sticks {
                assert!(unformed < impacts, "{case}");
            }
            let bits = |y: &DVector<f64>| y.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&lazy.final_state.state),
                bits(&formed.final_state.state)
            );
            for (a, b) in lazy.stroboscopic.iter().zip(&formed.stroboscopic) {
                assert_eq!(bits(a), bits(b));
            }
            assert_eq!(lazy, formed, "{case}");
        }
    }
}
