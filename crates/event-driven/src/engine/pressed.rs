//! Compliant contact phases: one or more compliant pairs pressed into their stops
//! ([`crate::Compliance`], a Kelvin–Voigt spring and dashpot along each pressed pair's
//! direction), the run on their augmented flow until a pressed pair's penetration returns
//! to zero (its exit) or another pair reaches a stop, and the entries and exits.
//!
//! While the set `P` of pairs is pressed the motion is the linear flow of
//! `M ü + (C + Σ_P c_c d dᵀ) u̇ + (K + Σ_P k_c d dᵀ) u = f(t) + Σ_P k_c side gap_side d`,
//! built on first use and cached per set, as the stuck flows are: an exact modal flow, no
//! time step, however stiff the contact. Each pressed pair's penetration
//! `δ = side·r − gap_side` is a sum of exponential terms over the phase, searched for its
//! first exit from `[0, ∞)` with the same guarantee as an impact's; the other pairs are
//! watched for their stops as in free flight. Entry and exit keep the state (no velocity
//! jump); the vector field jumps there by the dashpot's force `c_c ṙ M⁻¹d`, and the tangent
//! flow crosses with the saltation matrix `S = I ∓ (0, c_c M⁻¹d)(d, 0)ᵀ` (`−` at entry, `+`
//! at exit: `(f⁺ − f⁻) ∇hᵀ/(∇h·f⁻)` with `h = δ`, in which `ṙ` cancels, so `S` holds down to
//! a slow entry).

use super::*;
use crate::model::Compliance;

/// The flow of one set of pressed pairs, built on first use.
pub(super) struct Pressed {
    /// The pressed pairs and their sides, by pair index.
    pub(super) set: Vec<(usize, i8)>,
    /// The augmented flow.
    pub(super) flow: LinearFlow,
    /// Per pressed pair (in the order of `set`), `r` as a functional of the flow's state.
    pub(super) relative: Vec<Functional>,
    /// The pairs not pressed: `(pair, r as a functional, 0)`, watched for their stops.
    pub(super) watched: Vec<(usize, Functional, f64)>,
}

/// A contact phase under way: its pair and side, its entry and the largest penetration so
/// far.
#[derive(Debug, Clone, Copy)]
pub(super) struct OpenContact {
    pub(super) pair: usize,
    pub(super) side: i8,
    /// Absolute time of the entry (of the run's start for a pair pressed there).
    pub(super) entry_time: f64,
    /// The entry's time within the period.
    pub(super) entry_phase: f64,
    /// `ṙ` at the entry.
    pub(super) entry_velocity: f64,
    pub(super) max_penetration: f64,
}

impl Engine<'_> {
    /// The contact law of pair `pair`, if compliant.
    pub(super) fn law(&self, pair: usize) -> Option<Compliance> {
        self.model.compliance(pair)
    }

    /// The gap of pair `pair` on `side` as a signed position: `+gap_plus` or `−gap_minus`.
    fn signed_gap(&self, pair: usize, side: i8) -> f64 {
        let spec = &self.pairs[pair].spec;
        if side > 0 {
            spec.gap_plus
        } else {
            -spec.gap_minus
        }
    }

    /// The index of the pressed flow of `set` (sorted by pair), built on first use.
    ///
    /// # Errors
    /// [`SimulationError::Flow`] when the augmented flow does not exist.
    pub(super) fn pressed_index(&mut self, set: &[(usize, i8)]) -> Result<usize, SimulationError> {
        if let Some(i) = self.pressed.iter().position(|p| p.set == set) {
            return Ok(i);
        }
        let n = self.n;
        let model = self.model;
        let mut k = model.stiffness.clone();
        let mut c = model.damping.clone();
        let mut constant = DVector::zeros(n);
        for &(pair, side) in set {
            let law = self
                .law(pair)
                .ok_or_else(|| SimulationError::Option(format!("pair {pair} is not compliant")))?;
            let d = &self.pairs[pair].direction;
            let ddt = d * d.transpose();
            k += &ddt * law.stiffness;
            if law.damping > 0.0 || c.is_some() {
                let extra = &ddt * law.damping;
                c = Some(c.map_or(extra.clone(), |c| c + extra));
            }
            constant += d * (law.stiffness * self.signed_gap(pair, side));
        }
        let harmonics: Vec<crate::Harmonic> = model.active_harmonics().cloned().collect();
        let flow = LinearFlow::with_harmonics(
            (&model.mass, c.as_ref(), &k),
            (&model.forcing_cos, &model.forcing_sin, &constant),
            &harmonics,
            self.omega,
        )?;
        let flow = if model.general_form {
            flow.without_steady_response()
        } else {
            flow
        };
        let position = |q: usize| {
            let mut c = DVector::zeros(2 * n);
            c.rows_mut(0, n).copy_from(&self.pairs[q].direction);
            flow.functional(&c)
        };
        let relative = set.iter().map(|&(pair, _)| position(pair)).collect();
        let watched = (0..self.pairs.len())
            .filter(|q| set.iter().all(|&(pair, _)| pair != *q))
            .map(|q| (q, position(q), 0.0))
            .collect();
        self.pressed.push(Pressed {
            set: set.to_vec(),
            flow,
            relative,
            watched,
        });
        Ok(self.pressed.len() - 1)
    }

    /// The mode a run starts in from state `y`: pressed on every compliant pair beyond one of
    /// its stops (`δ > 0`), else free. A pair exactly on its stop starts free: the free
    /// flight finds its entry at once if it moves in.
    ///
    /// # Errors
    /// As [`Self::pressed_index`].
    pub(super) fn initial_mode(&mut self, y: &DVector<f64>) -> Result<Mode, SimulationError> {
        if !self.model.has_compliance() {
            return Ok(Mode::Free);
        }
        let n = self.n;
        let mut set = Vec::new();
        for pair in 0..self.pairs.len() {
            if self.law(pair).is_none() {
                continue;
            }
            let r = self.pairs[pair].direction.dot(&y.rows(0, n));
            let spec = &self.pairs[pair].spec;
            if r > spec.gap_plus {
                set.push((pair, 1));
            } else if -r > spec.gap_minus {
                set.push((pair, -1));
            }
        }
        if set.is_empty() {
            Ok(Mode::Free)
        } else {
            Ok(Mode::Pressed(self.pressed_index(&set)?))
        }
    }

    /// The open contacts of a run starting in `mode`: each pressed pair from the start.
    pub(super) fn initial_contacts(
        &self,
        mode: Mode,
        y: &DVector<f64>,
        time: f64,
    ) -> Vec<OpenContact> {
        let Mode::Pressed(index) = mode else {
            return Vec::new();
        };
        let n = self.n;
        self.pressed[index]
            .set
            .iter()
            .map(|&(pair, side)| {
                let p = &self.pairs[pair];
                let r = p.direction.dot(&y.rows(0, n));
                OpenContact {
                    pair,
                    side,
                    entry_time: time,
                    entry_phase: time.rem_euclid(self.period),
                    entry_velocity: p.direction.dot(&y.rows(n, n)),
                    max_penetration: side as f64 * r - side as f64 * self.signed_gap(pair, side),
                }
            })
            .collect()
    }

    /// A compliant pair `c.pair` found on its stop `c.side` (the state `state.y` there):
    /// moving into it faster than the velocities' rounding and the resting velocity, it
    /// enters contact (the pressed set grows by it, the state unchanged); otherwise it grazes
    /// the stop, and its stop is not watched for [`RELEASE_GRACE`] of a period (no contact
    /// of zero length).
    ///
    /// # Errors
    /// [`SimulationError::HoldWithCompliantContact`] while a rigid pair is held, and as
    /// [`Self::pressed_index`].
    pub(super) fn enter(
        &mut self,
        state: &mut RunState,
        c: Contact,
    ) -> Result<(), SimulationError> {
        let n = self.n;
        let p = &self.pairs[c.pair];
        let rdot = p.direction.dot(&state.y.rows(n, n));
        let velocity_size = state.y.rows(n, n).amax();
        // The velocities' rounding is relative to their size, which is itself rounding at a
        // graze of a pair at rest: an approach no faster than the resting velocity
        // ([`RESTING_VELOCITY`] of `ω × gap`) is a graze as well.
        if rdot * c.side as f64 <= VELOCITY_ROUNDING * velocity_size + self.resting_velocity {
            state.grace[c.pair] = state.tau + self.release_grace;
            return Ok(());
        }
        let mut set = match state.mode {
            Mode::Free => Vec::new(),
            Mode::Pressed(i) => self.pressed[i].set.clone(),
            Mode::Stuck(_) => {
                let time = state.absolute(self.period, state.tau);
                return Err(SimulationError::HoldWithCompliantContact(time));
            }
        };
        set.retain(|&(q, _)| q != c.pair);
        set.push((c.pair, c.side));
        set.sort_unstable();
        let index = self.pressed_index(&set)?;
        let time = state.absolute(self.period, state.tau);
        if let Some(t) = state.tangent.as_mut() {
            self.contact_saltation(t, c.pair, -1.0);
            t.contacts.push(TangentContact {
                pair: c.pair,
                side: c.side,
                entry: Some(time),
                exit: None,
            });
        }
        state.open_contacts.push(OpenContact {
            pair: c.pair,
            side: c.side,
            entry_time: time,
            entry_phase: state.tau,
            entry_velocity: rdot,
            max_penetration: 0.0,
        });
        state.last_impact_period = Some(state.k);
        state.mode = Mode::Pressed(index);
        Ok(())
    }

    /// Event: the pressed pair at position `position` of set `index` leaves its stop (its
    /// penetration is back to zero) `s` into the phase; the others stay pressed.
    ///
    /// # Errors
    /// As [`Self::pressed_index`], and [`SimulationError::EventStorm`].
    fn exit(
        &mut self,
        state: &mut RunState,
        index: usize,
        position: usize,
        s: f64,
    ) -> Result<(), SimulationError> {
        state.tau += s;
        let mut set = self.pressed[index].set.clone();
        let (pair, side) = set.remove(position);
        let n = self.n;
        let time = state.absolute(self.period, state.tau);
        let rdot = self.pairs[pair].direction.dot(&state.y.rows(n, n));
        if let Some(t) = state.tangent.as_mut() {
            self.contact_saltation(t, pair, 1.0);
            match t
                .contacts
                .iter_mut()
                .rev()
                .find(|x| x.pair == pair && x.exit.is_none())
            {
                Some(open) => open.exit = Some(time),
                None => t.contacts.push(TangentContact {
                    pair,
                    side,
                    entry: None,
                    exit: Some(time),
                }),
            }
        }
        if let Some(at) = state.open_contacts.iter().position(|o| o.pair == pair) {
            let open = state.open_contacts.remove(at);
            if let Some(w) = state.window.as_mut() {
                w.contacts.push(ContactRecord {
                    pair,
                    side: open.side,
                    entry_time: open.entry_time,
                    exit_time: time,
                    entry_phase: open.entry_phase,
                    exit_phase: state.tau.rem_euclid(self.period),
                    entry_velocity: open.entry_velocity,
                    exit_velocity: rdot,
                    max_penetration: open.max_penetration,
                });
            }
        }
        state.grace[pair] = state.tau + self.release_grace;
        state.mode = if set.is_empty() {
            Mode::Free
        } else {
            Mode::Pressed(self.pressed_index(&set)?)
        };
        state.count_event(self.period)
    }

    /// The saltation of a compliant pair's entry (`sign = −1`) or exit (`+1`) applied to the
    /// tangent: `J_v += sign c_c M⁻¹d (dᵀ J_u)`.
    fn contact_saltation(&self, t: &mut Tangent, pair: usize, sign: f64) {
        let Some(law) = self.law(pair) else { return };
        if law.damping == 0.0 {
            return;
        }
        let n = self.n;
        let p = &self.pairs[pair];
        let j = &mut t.jacobian;
        for col in 0..j.ncols() {
            let a: f64 = (0..n).map(|i| p.direction[i] * j[(i, col)]).sum();
            for i in 0..n {
                j[(n + i, col)] += sign * law.damping * p.mobility[i] * a;
            }
        }
    }

    /// The pressed pairs' contact forces' share of the acceleration at state `y`:
    /// `−M⁻¹ Σ_P d (k_c (r − side·gap) + c_c ṙ)`.
    pub(super) fn pressed_acceleration(&self, index: usize, y: &DVector<f64>) -> DVector<f64> {
        let n = self.n;
        let mut out = DVector::zeros(n);
        for &(pair, side) in &self.pressed[index].set {
            if let Some(law) = self.law(pair) {
                let p = &self.pairs[pair];
                let r = p.direction.dot(&y.rows(0, n));
                let rdot = p.direction.dot(&y.rows(n, n));
                let force = law.stiffness * (r - self.signed_gap(pair, side)) + law.damping * rdot;
                out -= &p.mobility * force;
            }
        }
        out
    }

    /// Contact phase: the pressed pairs on the augmented flow until one's penetration
    /// returns to zero (its exit), another pair reaches a stop (a rigid pair's impact, or a
    /// compliant pair's entry), or the next section. Every pair is watched as in free flight;
    /// a stop reached at the exit's instant is resolved first, and the exit found again at
    /// once by the next phase.
    pub(super) fn pressed_phase(
        &mut self,
        state: &mut RunState,
        index: usize,
        plan: &Plan,
    ) -> Result<(), SimulationError> {
        let n = self.n;
        let period = self.period;
        let horizon = period - state.tau;
        let tau = state.tau;
        let pr = &self.pressed[index];
        let flight = pr.flow.flight(&state.y, tau);
        let mut exit: Option<(f64, usize)> = None;
        let mut penetrations = Vec::with_capacity(pr.set.len());
        for (position, (&(pair, side), r)) in pr.set.iter().zip(&pr.relative).enumerate() {
            let mut delta = ExpSum::default();
            flight.expand(r, &mut delta);
            let gap = self.signed_gap(pair, side);
            let delta = if side > 0 {
                delta.shifted(-gap)
            } else {
                delta.negated().shifted(gap)
            };
            // The entry is on the stop to rounding: a start a rounding below it moving in is
            // on the band's edge, not an exit.
            let lo = delta.eval(0.0).0.min(0.0);
            self.work.stack.recall_key = self.pairs.len() + pair;
            if let Some((s, _)) = delta.first_exit(
                lo,
                f64::INFINITY,
                exit.map_or(horizon, |e| e.0),
                self.time_tolerance,
                0.0,
                &mut self.work.stack,
            ) {
                if exit.is_none_or(|e| s < e.0) {
                    exit = Some((s, position));
                }
            }
            penetrations.push((pair, delta));
        }
        let watch_horizon = exit.map_or(horizon, |e| e.0);
        let depth = self.contact_depth + POSITION_ROUNDING * state.y.rows(0, n).amax();
        let watch = if pr.watched.is_empty() || watch_horizon <= 0.0 {
            Watch::Clear
        } else {
            let watched = WatchedPairs {
                pairs: &self.pairs,
                functionals: pr.watched.iter().map(|(q, f, shift)| (*q, f, *shift)),
                joint: None,
                grace: &state.grace,
                tau,
            };
            let tolerances = Tolerances {
                time: self.time_tolerance,
                depth,
            };
            Self::watch(watched, &mut self.work, &flight, watch_horizon, tolerances)
        };
        let span = match watch {
            Watch::Contact(c) => c.s,
            Watch::Step(s) => s,
            Watch::Clear => watch_horizon,
        };
        for (pair, delta) in &penetrations {
            if let Some(open) = state.open_contacts.iter_mut().find(|o| o.pair == *pair) {
                let tolerance = self.time_tolerance;
                self.work.stack.recall_key = 2 * self.pairs.len() + pair;
                open.max_penetration = largest(
                    delta,
                    (span, open.max_penetration),
                    tolerance,
                    &mut self.work.stack,
                );
            }
        }
        let k = state.k;
        if let Some(w) = state.window.as_mut() {
            for (j, amp) in w.amplitudes.iter_mut().enumerate() {
                let mut c = DVector::zeros(2 * n);
                c[j] = 1.0;
                *amp = flight
                    .value_of(&c)
                    .max_abs(span, *amp, AMPLITUDE_TOLERANCE * (1.0 + *amp));
            }
            if plan.record_trajectory {
                sample(&mut w.trajectory, span, period, |s| {
                    (k as f64 * period + (tau + s), flight.state(s))
                });
            }
        }
        if let Some(trace) = state.trace.as_mut() {
            trace.segment(k, period, tau, span, |s| flight.state(s));
        }
        state.y = flight.state(span);
        if let Some(t) = state.tangent.as_mut() {
            Self::propagate_flow_tangent(&self.pressed[index].flow, t, span);
        }
        match (watch, exit) {
            (Watch::Contact(c), _) => {
                state.tau += span;
                self.contact(state, c, contact::BeforeContact::formed())?;
            }
            (Watch::Step(_), _) => state.tau += span,
            (Watch::Clear, Some((s, position))) => self.exit(state, index, position, s)?,
            (Watch::Clear, None) => state.tau = period,
        }
        Ok(())
    }
}

/// Local maxima [`largest`] looks for one by one in a phase before it bounds the rest of the
/// phase at once: a contact's penetration has one (or a few, under a fast forcing or another
/// pair's motion), so the searches end long before this.
const MAX_EXTREMA: usize = 16;

/// `f'` as a sum of the same rates: `(p' + μ p) e^{μs}` term by term.
fn derivative(f: &ExpSum) -> ExpSum {
    let terms = f
        .terms
        .iter()
        .map(|t| {
            let p = t.poly;
            let mut poly = [nalgebra::Complex::default(); 4];
            for (k, c) in poly.iter_mut().enumerate() {
                *c = t.rate * p[k];
                if k < 3 {
                    *c += p[k + 1] * (k + 1) as f64;
                }
            }
            crate::expsum::Term { poly, rate: t.rate }
        })
        .collect();
    ExpSum { terms }
}

/// The largest value of `f` (a penetration) over `[0, span]`, at least `floor`: `f` at both
/// ends and at each local maximum, the zeros of `f'` taken in time order from the certified
/// first-exit search (a maximum where `f'` leaves `(0, ∞)`, a minimum where it leaves
/// `(−∞, 0)`, each polished to `tolerance` in time, so the value to second order in it). A
/// start a rounding outside the band is on its edge. Past [`MAX_EXTREMA`] extrema the rest of
/// the phase is bounded by [`ExpSum::max_abs`] (the penetration is positive in contact).
fn largest(f: &ExpSum, (span, floor): (f64, f64), tolerance: f64, stack: &mut SearchStack) -> f64 {
    let mut best = floor.max(f.eval(0.0).0).max(f.eval(span).0);
    let mut rate = derivative(f);
    let mut s = 0.0;
    let mut rising = rate.eval(0.0).0 >= 0.0;
    for _ in 0..MAX_EXTREMA {
        let start = rate.eval(0.0).0;
        let (lo, hi) = if rising {
            (start.min(0.0), f64::INFINITY)
        } else {
            (f64::NEG_INFINITY, start.max(0.0))
        };
        match rate.first_exit(lo, hi, span - s, tolerance, 0.0, stack) {
            Some((t, _)) => {
                s += t;
                if rising {
                    best = best.max(f.eval(s).0);
                }
                rising = !rising;
                rate.move_origin(t);
            }
            None => return best,
        }
    }
    let mut rest = f.clone();
    rest.move_origin(s);
    rest.max_abs(span - s, best, AMPLITUDE_TOLERANCE * (1.0 + best))
}

/// A contact of the tangent run: entry and exit times since its start, `None` outside it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct TangentContact {
    pub(crate) pair: usize,
    pub(crate) side: i8,
    pub(crate) entry: Option<f64>,
    pub(crate) exit: Option<f64>,
}
