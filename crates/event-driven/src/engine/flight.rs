//! Free flight: the watch of every pair for its first contact, and the flight to it.

use super::*;

/// What the watch of the pairs in flight found first.
pub(super) enum Watch {
    /// A contact to resolve.
    Contact(Contact),
    /// A pair in its grace time (just released or grazed) reaches its edge first: step this
    /// long without an event.
    Step(f64),
    /// No contact within the horizon.
    Clear,
}

/// Storage reused by every flight, so that no flight allocates.
#[derive(Default)]
pub(super) struct Scratch {
    /// Each watched pair's gap in the current flight.
    pub(super) gaps: Vec<ExpSum>,
    /// Per slot of `gaps`, the pair whose relative displacement it holds as a free flight
    /// of the joint watch wrote it ([`Flight::expand`] from the engine's free flow), if so:
    /// the next such flight rewrites only its constant coefficients
    /// ([`Flight::expand_joint`]).
    pub(super) expanded: Vec<Option<usize>>,
    /// Each watched pair's gap summarised ([`Flight::summarize`]) when several pairs are
    /// watched: its terms are then written out only for a search.
    pub(super) summaries: Vec<Option<Summary>>,
    /// The watched pairs' summaries formed in one pass ([`Flight::summarize_all`]).
    pub(super) joint: Vec<Summary>,
    /// The flight's deviation of each mode times its weight, as those summaries add them
    /// ([`ModeTerm::weighted`](crate::expsum::ModeTerm)).
    pub(super) deviations: Vec<nalgebra::Complex<f64>>,
    /// The watched pairs' terms' coefficients as those summaries formed them
    /// ([`Flight::summarize_all`]), copied into a searched pair's terms
    /// ([`Flight::expand_joint`]).
    pub(super) coefficients: Vec<[f64; 2 * LANES]>,
    /// The watch's search order: `(estimated exit, slot in gaps, pair, lo, hi)`, the estimate
    /// `∞` where the joint watch did not form it (it could not be the earliest).
    pub(super) order: Vec<(f64, usize, usize, f64, f64)>,
    pub(super) stack: SearchStack,
    pub(super) coordinate: ExpSum,
    /// The exponentials the recorded coordinates' amplitudes share ([`SharedPoints`]), in a
    /// cell: [`Engine::record_flight`] reads the engine and borrows them only in the final
    /// stretch (moving them out and back at every flight cost 1.6 % of a unit's run).
    pub(super) points: std::cell::RefCell<SharedPoints>,
    /// The exponentials of the search at the contact it found, for the contact state.
    pub(super) event_exponentials: Vec<nalgebra::Complex<f64>>,
    /// With several pairs, the next free flight's start carried across the last contact:
    /// its modal deviation ([`Flight::deviation_at`] plus the impact's jump), valid for the
    /// state [`Self::carried_state`] at [`Self::carried_tau`] only (`carried` empty when
    /// there is none).
    pub(super) carried: Vec<nalgebra::Complex<f64>>,
    /// The state the carried deviation belongs to.
    pub(super) carried_state: Vec<f64>,
    /// The time within the period it belongs to.
    pub(super) carried_tau: f64,
    /// The positions' size at the contact the deviation is carried across, from its modal
    /// coordinates ([`ContactMode`]: [`LinearFlow::kept_peaks`](crate::flow::LinearFlow)): the scale of the
    /// next flight's depth, where the state's own positions may not be formed.
    pub(super) carried_position_size: f64,
    /// The modal coordinates of the state at the last contact ([`Engine::before_contact`]).
    pub(super) modal: Vec<nalgebra::Complex<f64>>,
    /// The state just before the contact the deviation is carried across.
    pub(super) before_contact: Vec<f64>,
    /// The last free flight's storage for its modal deviation, handed to the next
    /// ([`LinearFlow::flight_at_phase`](crate::flow::LinearFlow)).
    pub(super) flight_storage: Vec<nalgebra::Complex<f64>>,
    /// A free flight searched past the section it reached, to go on after it.
    pub(super) pending: Pending,
}

/// A free flight that reached the section `t = (k + 1)T` with its search carried past it
/// (up to a second section): at the section the run checks its stopping rules, and the next
/// step goes on with this flight and the contact its search found, rather than starting a
/// flight and a search at the section ([`Engine::free_flight`]). Valid only for the state
/// `state` at the section, in free flight. What the run records does not decide it (a flight
/// that goes on records its part after the section then), so a run takes the same steps
/// whatever it records; but the final stretch starts afresh at its first section
/// ([`Engine::drop_pending`] where the window opens), as a run started there does.
///
/// A run so differs from one restarted at each section in the last bits of its contact times
/// (both within the root tolerance), and the state at a section is no longer all that decides
/// the next period's bits: a run started from a section state (other than the final stretch's
/// first) agrees with the run it came from to the root tolerance, not bit for bit.
#[derive(Default)]
pub(super) struct Pending {
    /// Whether a flight is pending.
    pub(super) live: bool,
    /// Its modal deviation at its start ([`Flight::into_storage`]).
    pub(super) deviation: Vec<nalgebra::Complex<f64>>,
    /// Its forcing phase at its start.
    pub(super) phase: nalgebra::Complex<f64>,
    /// The section's time after the flight's start.
    pub(super) section: f64,
    /// The contact found after the section (its exponentials in
    /// [`Scratch::event_exponentials`]), or `None` for none up to `end`.
    pub(super) contact: Option<Contact>,
    /// The end of the search: the next section, after the flight's start.
    pub(super) end: f64,
    /// The state at the section (or, at a section not formed, `RunState::section_unformed`,
    /// the state `y` left as it was), which the run must still hold for the flight to go on.
    pub(super) state: Vec<f64>,
}

/// What decides how much of the state a contact forms ([`Engine::state_before_contact`]):
/// whether the run records it ([`Engine::forms_contact_state`]), and whether the pair is
/// compliant (its entry forms the whole state).
#[derive(Clone, Copy)]
pub(super) struct FormsContact {
    pub(super) records: bool,
    pub(super) compliant: bool,
}

/// The relative margin past the earliest quadratic estimate so far within which a watch still
/// forms a pair's estimate ([`Summary::estimate_later_than`]): far above the estimate's
/// rounding (a root near a double root is known to about `√ε` of its size, 1.5e-8), so that
/// a pair skipped could not have had the earliest estimate. Skipping the others' square roots
/// and divisions (8 estimates a flight on `chain8`, 2.9 formed now: callgrind, `chain8
/// 1000`) took `quadratic_exit` from 6.3 % of `chain8`'s time to 4.5 % (`perf`, 20 000
/// periods, with the search's own estimates, 1.5 a flight).
const ESTIMATE_MARGIN: f64 = 1e-6;

/// The summary's quadratic estimate ([`Summary::estimated_exit`]) in `(lo, hi)` if it may be
/// earlier than `earliest` (within [`ESTIMATE_MARGIN`]), else `∞` without forming it.
fn estimate_if_earliest(summary: &Summary, (lo, hi): (f64, f64), earliest: f64) -> f64 {
    if summary.estimate_later_than(lo, hi, earliest * (1.0 + ESTIMATE_MARGIN)) {
        f64::INFINITY
    } else {
        summary.estimated_exit(lo, hi)
    }
}

/// Moves the watch order's entry of the earliest estimate (the lower slot of equal ones) to
/// the front, the others after it in their order.
fn earliest_first(order: &mut [(f64, usize, usize, f64, f64)]) {
    let earliest = order
        .iter()
        .enumerate()
        .min_by(|(_, a), (_, b)| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)))
        .map(|(at, _)| at);
    if let Some(at) = earliest {
        // Moved entry by entry (`rotate_right` called `memmove`: 0.26 % of `chain8`'s
        // instructions).
        let first = order[at];
        for i in (0..at).rev() {
            order[i + 1] = order[i];
        }
        order[0] = first;
    }
}

/// Whether `kept` is `y` bit for bit: every entry's bits compared, without stopping at the
/// first difference (a comparison of `f64`s entry by entry, branching on each, was some 1 %
/// of `chain8`'s time, `perf`). Where `==` would differ (`0.0` against `-0.0`, a NaN
/// against itself) a state is not bit for bit the one kept, and nothing is carried.
fn same_bits(kept: &[f64], y: &DVector<f64>) -> bool {
    let y = y.as_slice();
    kept.len() == y.len()
        && kept
            .iter()
            .zip(y)
            .fold(0, |differ, (a, b)| differ | (a.to_bits() ^ b.to_bits()))
            == 0
}

impl Scratch {
    /// The carried deviation, if it belongs to the state `y` at `tau` (bit for bit); the
    /// carry is used up either way.
    pub(super) fn take_carried(
        &mut self,
        y: &DVector<f64>,
        tau: f64,
    ) -> Option<Vec<nalgebra::Complex<f64>>> {
        if !self.carried.is_empty() && self.carried_tau == tau && same_bits(&self.carried_state, y)
        {
            Some(std::mem::take(&mut self.carried))
        } else {
            // Used up, its storage kept for the next carry.
            self.carried.clear();
            None
        }
    }
}

/// The pairs a flight watches for contact: `functionals` lists each watched pair's
/// `(pair, r − shift as a functional of the flight's state, shift)`, `joint` the same
/// functionals prepared for one summary pass (free flight with several pairs), `grace` each
/// pair's grace time and `tau` the flight's start within the period.
pub(super) struct WatchedPairs<'a, I> {
    pub(super) pairs: &'a [Pair],
    pub(super) functionals: I,
    pub(super) joint: Option<&'a JointWeights>,
    pub(super) grace: &'a [f64],
    pub(super) tau: f64,
}

impl Engine<'_> {
    /// The first contact of `flight` within `horizon` among the `watched` pairs
    /// (`(pair, r − shift as a functional of the flight's state, shift)`): each pair's relative
    /// displacement searched for its first exit from `[−gap_minus, gap_plus]`, every pair with
    /// the search's guarantee. A pair in its grace time (`tau + s < grace[pair]`) counts no
    /// contact; if it reaches its edge before any other pair's contact, the flight steps to the
    /// end of its grace without an event. Ties go to the lower pair index (see
    /// [`Engine::free_flight`]). Leaves the search's exponentials at the contact in
    /// `work.event_exponentials`.
    pub(super) fn watch<'f, I>(
        watched: WatchedPairs<'_, I>,
        work: &mut Scratch,
        flight: &Flight<'_>,
        horizon: f64,
        tolerances: Tolerances,
    ) -> Watch
    where
        I: Iterator<Item = (usize, &'f Functional, f64)> + Clone,
    {
        let WatchedPairs {
            pairs,
            functionals: watched,
            joint,
            grace,
            tau,
        } = watched;
        let mut contact: Option<Contact> = None;
        let mut step = f64::INFINITY;
        // Every pair's gap, then the searches, the earliest quadratic estimate first: the
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
                let scratch = (&mut work.deviations, &mut work.coefficients);
                flight.summarize_all(joint, horizon, scratch, &mut work.joint)
            });
        work.order.clear();
        // The earliest estimate so far: only the earliest is used (below), so a pair whose
        // quadratic model stays inside its band past it (with a margin for the estimate's
        // rounding) needs none.
        let mut earliest = f64::INFINITY;
        for (count, (i, functional, shift)) in watched.clone().enumerate() {
            if work.gaps.len() <= count {
                work.gaps.push(ExpSum::default());
                work.summaries.push(None);
                work.expanded.push(None);
            }
            let spec = &pairs[i].spec;
            let (lo, hi) = (-spec.gap_minus - shift, spec.gap_plus - shift);
            // The joint summaries are read where they were formed (not copied).
            let estimate = if joint {
                estimate_if_earliest(&work.joint[count], (lo, hi), earliest)
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
                        work.expanded[count] = None;
                        // One pair has no order to choose: no estimate.
                        if several {
                            gap.estimated_exit(lo, hi)
                        } else {
                            0.0
                        }
                    }
                }
            };
            earliest = earliest.min(estimate);
            work.order.push((estimate, count, i, lo, hi));
        }
        // The earliest estimate first, the others after it in their slots' order: the first
        // search mostly finds the contact, and cuts the others' horizons short, so that most
        // are decided by their summaries alone; their order decides little more (a full sort
        // by estimate cost 2 % of `chain8`'s time and saved no search worth it: callgrind,
        // `chain8 1000`, 481.5e6 → 465.9e6 instructions, the same contacts).
        if several {
            earliest_first(&mut work.order);
        }
        let Scratch {
            gaps,
            expanded,
            summaries,
            joint: joint_summaries,
            coefficients,
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
            stack.recall_key = i;
            let found = if let Some(summary) = summary {
                if summary.excludes(lo, hi, within, horizon) {
                    continue;
                }
                if let Some((_, functional, _)) = watched.clone().nth(slot) {
                    // A joint watch is the free flight's, over the pairs' relative
                    // displacements: a slot that holds pair `i`'s from an earlier free flight
                    // needs only its constant coefficients written, copied from the
                    // summaries that formed them.
                    let again = joint && expanded[slot] == Some(i);
                    if again {
                        flight.expand_joint(functional, (coefficients, slot), &mut gaps[slot]);
                    } else {
                        flight.expand(functional, &mut gaps[slot]);
                    }
                    expanded[slot] = joint.then_some(i);
                }
                // The search's own first tests are this summary's, just made: not made again.
                gaps[slot].first_exit_summarized(
                    summary,
                    (lo, hi),
                    horizon,
                    within,
                    tolerances,
                    stack,
                )
            } else {
                gaps[slot].first_exit_until(lo, hi, horizon, within, tolerances, stack)
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
    pub(super) fn free_flight(
        &mut self,
        state: &mut RunState,
        plan: &Plan,
    ) -> Result<(), SimulationError> {
        if self.work.pending.live {
            if self.pending_holds(state) {
                self.work.pending.live = false;
                return self.continue_pending(state, plan);
            }
            self.drop_pending();
        }
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
        let (sin, cos) = self.forcing_at(state.tau);
        let phase = nalgebra::Complex::new(cos, sin);
        let storage = std::mem::take(&mut self.work.flight_storage);
        let carried_flight = carried.is_some();
        let flight = match carried {
            Some(deviation) => match self.free.flight_with_deviation(deviation, phase) {
                Ok(flight) => {
                    // The last flight's storage holds the next carry (empty: none yet), so
                    // that a carry allocates nothing.
                    self.work.carried = storage;
                    self.work.carried.clear();
                    flight
                }
                Err(_) => self.free.flight_at_phase(&state.y, phase, storage),
            },
            None => self.free.flight_at_phase(&state.y, phase, storage),
        };
        // Positions are known to rounding relative to their size, not to the gap: an excursion
        // beyond a stop smaller than that is no contact. After a contact the flight starts from
        // the deviation carried across it, and the size is the one taken there from the modal
        // coordinates (the state's positions may not be formed).
        let position_size = if carried_flight {
            self.work.carried_position_size
        } else {
            contact::largest_magnitude(&state.y.as_slice()[..n])
        };
        let depth = self.contact_depth + POSITION_ROUNDING * position_size;
        let watched = WatchedPairs {
            pairs: &self.pairs,
            functionals: self
                .pairs
                .iter()
                .enumerate()
                .map(|(i, p)| (i, &p.relative_displacement, 0.0)),
            joint: self.free_joint.as_ref(),
            grace: &state.grace,
            tau: state.tau,
        };
        let tolerances = Tolerances {
            time: self.time_tolerance,
            depth,
        };
        // Searched on past the section, up to the next, when it may go on after it.
        let past_section = self.searches_past_section(state);
        let reach = if past_section {
            horizon + period
        } else {
            horizon
        };
        let watch = Self::watch(watched, &mut self.work, &flight, reach, tolerances);
        if let Watch::Step(step) = watch {
            // Just released (or grazed): step past the stop's edge without an event.
            if let Some(trace) = state.trace.as_mut() {
                trace.segment(state.k, period, state.tau, step, |s| flight.state(s));
            }
            state.y = flight.state(step);
            self.work.flight_storage = flight.into_storage();
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
        let beyond = past_section && contact.is_none_or(|c| c.s > horizon);
        let span = match contact {
            Some(c) if !beyond => c.s,
            _ => horizon,
        };
        let mut coordinate = std::mem::take(&mut self.work.coordinate);
        self.record_flight((state, plan), &flight, (0.0, span), &mut coordinate);
        self.work.coordinate = coordinate;
        if beyond {
            // To the section; the flight goes on after it (`continue_pending`). The state
            // there is formed only for a section something observes.
            if self.unobserved_section(state, plan) {
                state.section_unformed = true;
                #[cfg(test)]
                self.unformed_sections.set(self.unformed_sections.get() + 1);
            } else {
                flight.state_into(horizon, &mut state.y);
            }
            let pending = &mut self.work.pending;
            pending.live = true;
            pending.phase = phase;
            pending.section = horizon;
            pending.contact = contact;
            pending.end = reach;
            pending.state.clear();
            pending.state.extend_from_slice(state.y.as_slice());
            pending.deviation = flight.into_storage();
            state.tau = period;
            return Ok(());
        }
        match contact {
            None => {
                flight.state_into(horizon, &mut state.y);
                self.work.flight_storage = flight.into_storage();
                state.tau = period;
            }
            Some(c) => {
                let forms = FormsContact {
                    records: self.forms_contact_state(state),
                    compliant: self.law(c.pair).is_some(),
                };
                let parts = (&self.pairs[..], self.bounce_test(), forms);
                let before = Self::state_before_contact(parts, &mut self.work, state, (&flight, c));
                self.count_unformed(before);
                self.work.flight_storage = flight.into_storage();
                state.tau += c.s;
                self.contact(state, c, before)?;
                if before.carry {
                    self.carry_across(state, c.pair);
                }
            }
        }
        Ok(())
    }

    /// The state just before contact `c` at the end of the free flight `flight`: with
    /// several pairs [`Self::before_contact`]'s (`forms.records`:
    /// [`Self::forms_contact_state`]), with one (or at a compliant pair's stop, whose entry
    /// reads the whole state) the whole state, nothing carried (the one-pair path as it was).
    #[inline]
    fn state_before_contact(
        (pairs, test, forms): (&[Pair], contact::BounceTest, FormsContact),
        work: &mut Scratch,
        state: &mut RunState,
        (flight, c): (&Flight<'_>, Contact),
    ) -> contact::BeforeContact {
        if pairs.len() == 1 || forms.compliant {
            flight.state_at(c.s, &work.event_exponentials, &mut state.y);
            return contact::BeforeContact::formed();
        }
        let tau = state.tau + c.s;
        Self::before_contact((pairs, test), work, state, (flight, c, tau, forms.records))
    }

    /// What a run records of `flight` over `[offset, offset + span]` (its part in the current
    /// period, which starts at `state.tau`): the tangent flow, the trace, and in the window of
    /// the final stretch the amplitudes and the trajectory.
    /// `coordinate` is scratch storage.
    fn record_flight(
        &self,
        (state, plan): (&mut RunState, &Plan),
        flight: &Flight<'_>,
        (offset, span): (f64, f64),
        coordinate: &mut ExpSum,
    ) {
        let period = self.period;
        let (tau, k) = (state.tau, state.k);
        if let Some(t) = state.tangent.as_mut() {
            self.propagate_tangent(t, span);
        }
        if let Some(trace) = state.trace.as_mut() {
            trace.segment(k, period, tau, span, |s| flight.state(offset + s));
        }
        if let Some(w) = state.window.as_mut() {
            let mut points = self.work.points.borrow_mut();
            for (amp, u) in w.amplitudes.iter_mut().zip(&self.displacements) {
                flight.expand(u, coordinate);
                if offset != 0.0 {
                    coordinate.move_origin(offset);
                }
                let tolerance = AMPLITUDE_TOLERANCE * (1.0 + *amp);
                *amp = coordinate.max_abs_shared(span, (*amp, tolerance), &mut points);
            }
            if plan.record_trajectory {
                sample(&mut w.trajectory, span, period, |s| {
                    (k as f64 * period + (tau + s), flight.state(offset + s))
                });
            }
        }
    }

    /// Whether a free flight from `state` is searched on past the section, up to the next: no
    /// pair is in its grace time. (What the run records does not matter: a flight carried
    /// past the section records its part after it when it goes on, so a run takes the same
    /// steps whatever it records.)
    fn searches_past_section(&self, state: &RunState) -> bool {
        self.carries_sections && state.grace.iter().all(|&g| g <= state.tau)
    }

    /// Forgets the pending flight, if any ([`Pending`]): the next free flight starts afresh.
    pub(super) fn drop_pending(&mut self) {
        let pending = &mut self.work.pending;
        if std::mem::take(&mut pending.live) {
            self.work.flight_storage = std::mem::take(&mut pending.deviation);
        }
    }

    /// Whether the pending flight ([`Pending`]) goes on from `state`: at the section it
    /// reached, in free flight, from the state the flight left there (bit for bit).
    fn pending_holds(&self, state: &RunState) -> bool {
        state.tau == 0.0
            && matches!(state.mode, Mode::Free)
            && same_bits(&self.work.pending.state, &state.y)
    }

    /// The pending flight after its section: to the contact its search found (resolved as
    /// any flight's), or to the next section; recorded from the section on.
    fn continue_pending(
        &mut self,
        state: &mut RunState,
        plan: &Plan,
    ) -> Result<(), SimulationError> {
        let pending = &mut self.work.pending;
        let deviation = std::mem::take(&mut pending.deviation);
        let (section, contact, end) = (pending.section, pending.contact, pending.end);
        let flight = match self.free.flight_with_deviation(deviation, pending.phase) {
            Ok(flight) => flight,
            Err(deviation) => {
                // Not a steady-response flow: never kept (`carries_sections`).
                self.work.flight_storage = deviation;
                return Ok(());
            }
        };
        let span = contact.map_or(end, |c| c.s) - section;
        let mut coordinate = std::mem::take(&mut self.work.coordinate);
        self.record_flight((state, plan), &flight, (section, span), &mut coordinate);
        self.work.coordinate = coordinate;
        let Some(c) = contact else {
            flight.state_into(end, &mut state.y);
            self.work.flight_storage = flight.into_storage();
            state.tau = self.period;
            return Ok(());
        };
        // A pending flight has one pair ([`Engine::carries_sections`]): the state, nothing
        // carried.
        flight.state_at(c.s, &self.work.event_exponentials, &mut state.y);
        let before = contact::BeforeContact::formed();
        self.work.flight_storage = flight.into_storage();
        let c = Contact {
            s: c.s - section,
            ..c
        };
        state.tau = c.s;
        self.contact(state, c, before)?;
        if before.carry {
            self.carry_across(state, c.pair);
        }
        Ok(())
    }

    /// Whether the run records what a contact's state would go to (a trace, the final
    /// stretch's window, a tangent flow), so that [`Self::before_contact`] forms it whole.
    fn forms_contact_state(&self, state: &RunState) -> bool {
        #[cfg(test)]
        if self.form_every_contact {
            return true;
        }
        state.trace.is_some() || state.window.is_some() || state.tangent.is_some()
    }

    /// Tests only: counts a contact whose state was not formed whole.
    #[inline]
    fn count_unformed(&self, _before: contact::BeforeContact) {
        #[cfg(test)]
        if !_before.formed {
            self.unformed_contacts.set(self.unformed_contacts.get() + 1);
        }
    }

    /// With several pairs, the state just before contact `c` at the end of `flight`, as
    /// [`Self::contact`] needs it, and the deviation carried across it ([`Self::carry_from`]).
    ///
    /// On a steady-response flight, the state's modal coordinates there
    /// give the positions' and velocities' sizes ([`ContactMode`]), the scales of the
    /// contact's and the next flight's rounding whether or not the state is formed, so that
    /// a run decides the same whatever it records. An impact that cannot stick
    /// ([`Self::cannot_stick`]) reads and changes only [`Pair::contact_entries`] of the
    /// state. Those are formed alone (the same bits as in the whole state) unless `records`
    /// ([`Self::forms_contact_state`]), the contact is at a section (`tau`, its time in the
    /// period, is `0`: the final stretch's window may open there) or it may stick. The rest of
    /// `state.y` is then stale until a flight writes the state again: the next flight starts
    /// from the carried deviation, and every free flight ends by writing the state or by
    /// carrying a contact on.
    #[inline(never)]
    fn before_contact(
        (pairs, test): (&[Pair], contact::BounceTest),
        work: &mut Scratch,
        state: &mut RunState,
        (flight, c, tau, records): (&Flight<'_>, Contact, f64, bool),
    ) -> contact::BeforeContact {
        let p = &pairs[c.pair];
        let modal = p.contact_modes.is_some()
            && flight.modal_state(
                c.s,
                &work.event_exponentials,
                (&mut work.modal, &mut work.carried),
            );
        let Some(modes) = p.contact_modes.as_deref().filter(|_| modal) else {
            flight.state_at(c.s, &work.event_exponentials, &mut state.y);
            let carry = Self::carry_from(work, flight, &state.y);
            if carry {
                // The positions' size from the state itself, as for a flight not carried on.
                let n = state.y.len() / 2;
                work.carried_position_size = contact::largest_magnitude(&state.y.as_slice()[..n]);
            }
            return contact::BeforeContact {
                carry,
                formed: true,
                ..Default::default()
            };
        };
        let (sizes, entries) = contact_sums(modes, &work.modal);
        let [position_size, velocity_size, push, _] = sizes;
        for (&i, y) in p.contact_entries.iter().zip(entries) {
            state.y[i] = y;
        }
        let push = push + p.forcing_size;
        let cannot_stick =
            Self::cannot_stick(test, (p, c.side), &mut state.y, (velocity_size, push));
        // A contact at a section (`τ = 0`) forms the state: the final stretch's window may open
        // there and record it.
        let formed = records || !cannot_stick || tau <= 0.0;
        if formed {
            flight.state_at(c.s, &work.event_exponentials, &mut state.y);
            debug_assert!(p
                .contact_entries
                .iter()
                .zip(entries)
                .all(|(&i, y)| state.y[i].to_bits() == y.to_bits()));
        }
        // The deviation carried across, formed with the coordinates where it could be.
        let carry = if work.carried.is_empty() {
            Self::carry_from(work, flight, &state.y)
        } else {
            work.before_contact.clear();
            work.before_contact.extend_from_slice(state.y.as_slice());
            true
        };
        work.carried_position_size = position_size;
        contact::BeforeContact {
            carry,
            velocity_size: Some(velocity_size),
            cannot_stick,
            formed,
        }
    }

    /// With several pairs, before a contact at the end of `flight`: its modal deviation there
    /// and the state `y` just before the contact, kept for [`Self::carry_across`]; `false`
    /// when the flight cannot give it. Out of line: the one-pair path stays as it was.
    #[inline(never)]
    pub(super) fn carry_from(work: &mut Scratch, flight: &Flight<'_>, y: &DVector<f64>) -> bool {
        if !flight.deviation_at(&work.event_exponentials, &mut work.carried) {
            work.carried.clear();
            return false;
        }
        work.before_contact.clear();
        work.before_contact.extend_from_slice(y.as_slice());
        true
    }

    /// After the contact of pair `pair`: the deviation plus the contact's jump of the state,
    /// valid for the state after it while the pairs fly free (dropped otherwise). A contact
    /// in free flight that leaves the pairs free changes at most the velocities of the pair's
    /// free impact ([`Pair::impact_mobility`]'s entries), the only entries the jump reads.
    #[inline(never)]
    pub(super) fn carry_across(&mut self, state: &RunState, pair: usize) {
        let work = &mut self.work;
        if !matches!(state.mode, Mode::Free) {
            work.carried.clear();
            return;
        }
        let n = self.n;
        let changed = self.pairs[pair].impact_mobility.iter().map(|&(i, _)| n + i);
        self.free.add_jump(
            &mut work.carried,
            (&work.before_contact, state.y.as_slice()),
            changed,
        );
        work.carried_state.clear();
        work.carried_state.extend_from_slice(state.y.as_slice());
        work.carried_tau = state.tau;
    }
}

/// One pass of [`Engine::before_contact`] over the modes' coordinates `z`: the bounds
/// `Σ_k sizes_k (|Re z_k| + |Im z_k|)` ([`ContactMode`]: the positions', the velocities', `r̈`'s
/// part in the state, and a `0`) and the contact entries, each summed as
/// [`Flight::state_at`] sums it. With AVX when the CPU has it, each lane's operations the
/// same ([`contact_sums_avx`]).
fn contact_sums(
    modes: &[ContactMode],
    z: &[nalgebra::Complex<f64>],
) -> ([f64; 4], [f64; CONTACT_ENTRIES]) {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx") {
        // SAFETY: the CPU has AVX (checked just above).
        return unsafe { contact_sums_avx(modes, z) };
    }
    let mut sizes = [0.0; 4];
    let mut entries = [0.0; CONTACT_ENTRIES];
    for (mode, z) in modes.iter().zip(z) {
        let size = z.re.abs() + z.im.abs();
        for (sum, s) in sizes.iter_mut().zip(mode.sizes) {
            *sum += s * size;
        }
        for ((y, re), im) in entries.iter_mut().zip(mode.re).zip(mode.im) {
            *y += re * z.re - im * z.im;
        }
    }
    (sizes, entries)
}

/// [`contact_sums`] four lanes at once (no FMA: each lane's products and sums round as the
/// scalar ones do, in the same order).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx")]
fn contact_sums_avx(
    modes: &[ContactMode],
    z: &[nalgebra::Complex<f64>],
) -> ([f64; 4], [f64; CONTACT_ENTRIES]) {
    use std::arch::x86_64::*;
    // SAFETY (of each load): the arrays hold four `f64`, one unaligned load's 32 bytes.
    let load = |v: &[f64; 4]| unsafe { _mm256_loadu_pd(v.as_ptr()) };
    let (mut sizes, mut entries) = (_mm256_setzero_pd(), _mm256_setzero_pd());
    for (mode, z) in modes.iter().zip(z) {
        let size = _mm256_set1_pd(z.re.abs() + z.im.abs());
        sizes = _mm256_add_pd(sizes, _mm256_mul_pd(load(&mode.sizes), size));
        let (re, im) = (_mm256_set1_pd(z.re), _mm256_set1_pd(z.im));
        let step = _mm256_sub_pd(
            _mm256_mul_pd(load(&mode.re), re),
            _mm256_mul_pd(load(&mode.im), im),
        );
        entries = _mm256_add_pd(entries, step);
    }
    let (mut a, mut b) = ([0.0; 4], [0.0; CONTACT_ENTRIES]);
    // SAFETY: each array holds four `f64`, one unaligned store's 32 bytes.
    unsafe {
        _mm256_storeu_pd(a.as_mut_ptr(), sizes);
        _mm256_storeu_pd(b.as_mut_ptr(), entries);
    }
    (a, b)
}
