//! Contact events: impacts (restitution along the contact direction), and the accelerations
//! that tell a hold from a bounce.

use super::*;

impl Engine<'_> {
    /// Relative acceleration `r̈` of pair `pair` at state `y`, phase time `tau`, in `mode`:
    /// the free one, or with the held pairs' contact forces (`a = a_free − R D a_free`).
    pub(super) fn relative_acceleration(
        &self,
        pair: usize,
        y: &DVector<f64>,
        tau: f64,
        mode: Mode,
    ) -> f64 {
        let p = &self.pairs[pair];
        match mode {
            Mode::Free => self.free_relative_acceleration(p, y, tau),
            Mode::Stuck(i) => {
                let st = &self.stuck[i];
                let free = self.free_acceleration(y, tau);
                let correction = &st.reaction * (&st.constraint * &free);
                p.direction.dot(&(free - correction))
            }
            Mode::Pressed(i) => {
                let a = self.free_acceleration(y, tau) + self.pressed_acceleration(i, y);
                p.direction.dot(&a)
            }
        }
    }

    /// The free acceleration `M⁻¹(f(τ) − K u − C u̇)` at state `y`.
    pub(super) fn free_acceleration(&self, y: &DVector<f64>, tau: f64) -> DVector<f64> {
        let n = self.n;
        let m = self.model;
        let (sin, cos) = self.forcing_at(tau);
        let mut f = &m.forcing_cos * cos + &m.forcing_sin * sin - &m.stiffness * y.rows(0, n);
        if let Some(c) = &m.damping {
            f -= c * y.rows(n, n);
        }
        for h in m.active_harmonics() {
            let (sin, cos) = crate::trig::sin_cos(h.order as f64 * self.omega * tau);
            f += &h.cos * cos + &h.sin * sin;
        }
        &self.inverse_mass * f
    }

    /// Newton restitution of pair `pair` (restitution `e`, the pair's own if `None`) in
    /// `mode`: free, or with the held pairs' constraints kept (`D u̇ = 0`), along the
    /// constrained mobility `m_c = M⁻¹d − R D M⁻¹d`. When the impact does not reach the held
    /// pairs (`D M⁻¹ d = 0`, e.g. pairs of different cells of a chain) both are the free
    /// impact, applied as such.
    pub(super) fn restitute(&self, pair: usize, y: &mut DVector<f64>, e: Option<f64>, mode: Mode) {
        let st = match mode {
            Mode::Free | Mode::Pressed(_) => None,
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
            _ => Self::free_impact(p, y, e),
        }
    }

    /// The free impact of pair `p` (restitution `e`, the pair's own if `None`): the arithmetic
    /// of [`Model::apply_impact`] on the nonzero entries of `d` and `M⁻¹d` only (the terms it
    /// adds beyond them are exact zeros; `ṙ ≠ 0` at an impact, so no sign of zero differs).
    #[inline]
    fn free_impact(p: &Pair, y: &mut DVector<f64>, e: Option<f64>) {
        let n = y.len() / 2;
        let e = e.unwrap_or(p.spec.restitution);
        let rdot = p.relative_velocity(y);
        let scale = (1.0 + e) * rdot / p.impact_compliance;
        let velocities = &mut y.as_mut_slice()[n..];
        for &(i, m) in &p.impact_mobility {
            velocities[i] -= m * scale;
        }
    }

    /// Relative acceleration `r̈` of pair `p` in free flight at state `y`, phase time `tau`:
    /// `(M⁻¹d) · (f(τ) − K u − C u̇)`, summed row by row over the nonzero entries only
    /// ([`Pair::acceleration_rows`]): the terms left out are exact zeros, so the value is the
    /// dense sum's. The higher harmonics' part ([`Pair::harmonic_forcing`]) is added after.
    /// Inlined, as it is without harmonics: a contact's decision reads it once.
    #[inline(always)]
    pub(super) fn free_relative_acceleration(&self, p: &Pair, y: &DVector<f64>, tau: f64) -> f64 {
        let (sin, cos) = self.forcing_at(tau);
        let y = y.as_slice();
        let mut acceleration = p
            .acceleration_rows
            .iter()
            .map(|r| {
                let mut f = r.forcing.0 * cos + r.forcing.1 * sin;
                for &(j, v) in &r.coefficients {
                    f -= v * y[j];
                }
                r.mobility * f
            })
            .sum();
        if !p.harmonic_forcing.is_empty() {
            acceleration += Self::harmonic_relative_acceleration(p, tau);
        }
        acceleration
    }

    /// The higher harmonics' part of pair `p`'s `r̈` at phase time `tau`,
    /// `Σ_k (M⁻¹d)·(f_c,k cos kωτ + f_s,k sin kωτ)` (out of line: a forcing at `ω` alone
    /// never comes here).
    #[cold]
    #[inline(never)]
    fn harmonic_relative_acceleration(p: &Pair, tau: f64) -> f64 {
        p.harmonic_forcing
            .iter()
            .map(|&(rate, on_cos, on_sin)| {
                let (sin, cos) = crate::trig::sin_cos(rate * tau);
                on_cos * cos + on_sin * sin
            })
            .sum()
    }

    /// A contact found by the search, with the state just before it: an impact if the pair
    /// approaches the stop, then a stick if the stop holds it (or the chatter would accumulate
    /// within [`CHATTER`] of a period); otherwise a graze, stepped past. In a stuck phase the
    /// impact keeps the held pairs' constraints and the stop's push is the constrained
    /// acceleration's; a stick adds the pair to the held set.
    ///
    /// `before` says what [`Self::before_contact`] found: the velocities' size where the
    /// state was not formed from itself, and whether the contact can stick at all (if not,
    /// the state need hold only [`Pair::contact_entries`]).
    pub(super) fn contact(
        &mut self,
        state: &mut RunState,
        c: Contact,
        before: BeforeContact,
    ) -> Result<(), SimulationError> {
        state.count_event(self.period)?;
        if let Some(t) = state.tangent.as_mut() {
            t.before_impact = false;
        }
        if self.law(c.pair).is_some() {
            return self.enter(state, c);
        }
        let p = &self.pairs[c.pair];
        let side = c.side as f64;
        let rdot = p.relative_velocity(&state.y);
        // Only an approach counts as an impact; a start on the stop moving out of it (rounding)
        // is handled as sticking below. Velocities are known to rounding relative to their size:
        // a slower approach is a graze, not an impact.
        let velocity_size = before
            .velocity_size
            .unwrap_or_else(|| largest_velocity(&state.y));
        let velocity_round = VELOCITY_ROUNDING * velocity_size;
        let approaching = rdot * side > velocity_round;
        if approaching {
            self.impact(state, c, rdot);
        }
        if before.cannot_stick {
            // An impact that bounces off (`Self::cannot_stick`): nothing more to decide. Where
            // the whole state is formed, the decision below agrees.
            debug_assert!(approaching);
            debug_assert!(
                !before.formed || !self.sticks(state, c, (approaching, velocity_round)),
                "a contact found unable to stick sticks at t = {}",
                state.tau
            );
            return Ok(());
        }
        let stick = self.sticks(state, c, (approaching, velocity_round));
        if stick {
            self.stick(state, c)?;
        } else if !approaching {
            // A touch that is neither an impact nor a hold (rounding at a graze): step past it
            // rather than find it again.
            state.grace[c.pair] = state.tau + self.release_grace;
        }
        Ok(())
    }

    /// Whether the stop holds pair `c.pair` after the contact (the state `state.y` after
    /// the impact, if any): the relative acceleration pushes into the stop, and the relative
    /// speed after it is below the resting velocity, or the chatter would accumulate within
    /// [`CHATTER`] of a period, or the pair was not approaching.
    fn sticks(
        &self,
        state: &RunState,
        c: Contact,
        (approaching, velocity_round): (bool, f64),
    ) -> bool {
        let p = &self.pairs[c.pair];
        let e = p.spec.restitution;
        let rdot_after = p.relative_velocity(&state.y);
        let push =
            self.relative_acceleration(c.pair, &state.y, state.tau, state.mode) * c.side as f64;
        let accumulation = if push > 0.0 && e < 1.0 {
            2.0 * rdot_after.abs() / (push * (1.0 - e))
        } else {
            f64::INFINITY
        };
        push > 0.0
            && (rdot_after.abs() <= self.resting_velocity + velocity_round
                || accumulation < CHATTER * self.period
                || !approaching)
    }

    /// Event: impact of pair `c.pair` on side `c.side`, approaching at `rdot`. Newton
    /// restitution along the contact direction, momentum kept.
    pub(super) fn impact(&self, state: &mut RunState, c: Contact, rdot: f64) {
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
}

/// What [`Engine::before_contact`] found before a contact, for [`Engine::contact`].
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct BeforeContact {
    /// Whether the flight's modal deviation is carried across the contact
    /// ([`Engine::carry_across`]).
    pub(super) carry: bool,
    /// The velocities' size for their rounding, where it comes from the modal coordinates
    /// ([`ContactMode`]) rather than from the state's largest velocity.
    pub(super) velocity_size: Option<f64>,
    /// Whether the contact is an impact that cannot stick ([`Engine::cannot_stick`]).
    pub(super) cannot_stick: bool,
    /// Whether the whole state was formed (else [`Pair::contact_entries`] only): read by
    /// the tests' count.
    #[cfg_attr(not(test), allow(dead_code))]
    pub(super) formed: bool,
}

impl BeforeContact {
    /// The whole state formed, nothing carried, the contact decided from the state alone
    /// (one pair).
    pub(super) fn formed() -> Self {
        Self {
            formed: true,
            ..Self::default()
        }
    }
}

/// The margin by which [`Engine::cannot_stick`] asks a bounce to clear the chatter test: far
/// above the rounding of that test's products and of the bound on `|r̈|`.
const BOUNCE_MARGIN: f64 = 1.0 + 1e-6;

/// What [`Engine::cannot_stick`] reads of the engine besides the pair: its resting velocity
/// and period.
pub(super) struct BounceTest {
    pub(super) resting_velocity: f64,
    pub(super) period: f64,
}

impl Engine<'_> {
    /// Whether a contact of `p` on `side` at the state `y` (of which only
    /// [`Pair::contact_entries`] are read) is an impact that [`Self::contact`] would not
    /// stick: an approach faster than the velocities' rounding (`velocity_size`), a rebound
    /// faster than the resting velocity, and (`e < 1`) too fast for the chatter to
    /// accumulate within [`CHATTER`] of a period under any push up to `push`, a bound on
    /// `|r̈|` before the impact ([`Pair::contact_modes`], [`Pair::forcing_size`]), plus the
    /// impact's velocity jumps times their weights in it ([`Pair::impact_weights`]). The same decisions as
    /// [`Self::contact`]'s, which then need not form the rest of the state. `y` is left as
    /// it was.
    pub(super) fn cannot_stick(
        test: BounceTest,
        (p, side): (&Pair, i8),
        y: &mut DVector<f64>,
        (velocity_size, push): (f64, f64),
    ) -> bool {
        let rdot = p.relative_velocity(y);
        let velocity_round = VELOCITY_ROUNDING * velocity_size;
        if rdot * side as f64 <= velocity_round || p.impact_mobility.len() > 4 {
            return false;
        }
        // The impact on the entries it changes, undone after; the push grows by at most its
        // part in the velocities' jumps.
        let n = y.len() / 2;
        let mut kept = [0.0; 4];
        for (k, &(i, _)) in kept.iter_mut().zip(&p.impact_mobility) {
            *k = y[n + i];
        }
        Self::free_impact(p, y, None);
        let rdot_after = p.relative_velocity(y);
        let mut push = push;
        for ((k, &(i, _)), &weight) in kept.iter().zip(&p.impact_mobility).zip(&p.impact_weights) {
            push += weight * (y[n + i] - *k).abs();
            y[n + i] = *k;
        }
        if rdot_after.abs() <= test.resting_velocity + velocity_round {
            return false;
        }
        let e = p.spec.restitution;
        if e >= 1.0 {
            return true;
        }
        2.0 * rdot_after.abs() > BOUNCE_MARGIN * push * (1.0 - e) * CHATTER * test.period
    }
}

impl Pair {
    /// `ṙ = d · u̇` at the state `y` (length `2n`), over the nonzero entries of `d`: the dense
    /// dot product's value (its other terms are exact zeros, and `d` has two nonzero entries,
    /// whose sum is the same in any order).
    #[inline]
    fn relative_velocity(&self, y: &DVector<f64>) -> f64 {
        let n = y.len() / 2;
        let velocities = &y.as_slice()[n..];
        self.direction_entries
            .iter()
            .map(|&(i, d)| d * velocities[i])
            .sum()
    }
}

/// `max |u̇_i|` at the state `y` (length `2n`), as `amax` of the velocities gives it.
#[inline]
fn largest_velocity(y: &DVector<f64>) -> f64 {
    let n = y.len() / 2;
    largest_magnitude(&y.as_slice()[n..])
}

/// `max |x_i|` (`0` for none), as nalgebra's `amax` gives it for finite entries (the largest
/// magnitude is exact in any order), without its generic iteration.
#[inline]
pub(super) fn largest_magnitude(x: &[f64]) -> f64 {
    x.iter().fold(0.0, |largest: f64, v| {
        crate::expsum::larger(largest, v.abs())
    })
}
