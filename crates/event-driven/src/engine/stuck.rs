//! The stuck phase: pairs held on their stops, the constrained flow, stick and release.

use super::*;

/// A set of contact pairs held on their stops at once: the constrained (reduced) flow, each
/// held pair's contact force and each other pair's relative displacement in it.
///
/// With `D` the held pairs' directions (rows), the constraint `D u = g` (`g_p = +gap_plus` or
/// `−gap_minus`) leaves `u = T ũ + u*`, `T` an orthonormal basis of `null D`,
/// `u* = Dᵀ(DDᵀ)⁻¹g`; the reduced flow is `TᵀMT ũ̈ + TᵀCT ũ̇ + TᵀKT ũ = Tᵀ(f − K u*)`. The
/// contact forces `λ` (`M ü = f − C u̇ − K u + Dᵀλ`) follow from `D ü = 0`:
/// `λ = −W⁻¹ D M⁻¹ (f − C u̇ − K u)`, `W = D M⁻¹ Dᵀ`.
pub(super) struct Stuck {
    /// `(pair, side)` of the held pairs, in pair order.
    pub(super) held: Vec<(usize, i8)>,
    pub(super) flow: LinearFlow,
    /// `u = basis ũ + offset`.
    pub(super) basis: DMatrix<f64>,
    pub(super) offset: DVector<f64>,
    /// Per held pair, its contact force along `d`.
    pub(super) forces: Vec<HeldForce>,
    /// The pairs not held, watched for contact: `(pair, r as a functional of the reduced
    /// state, d·u*)`, `r = functional + d·u*`.
    pub(super) watched: Vec<(usize, Functional, f64)>,
    /// `D` (held directions as rows).
    pub(super) constraint: DMatrix<f64>,
    /// `M⁻¹ Dᵀ W⁻¹`: the constraint's correction of accelerations and impulses,
    /// `a = a_free − reaction · D a_free`.
    pub(super) reaction: DMatrix<f64>,
}

/// The contact force of one held pair:
/// `λ = state · (ũ, ũ̇) + constant + Re{harmonic e^{iωt}} + Σ_k Re{H_k e^{ikωt}}`; held while
/// `side · λ < 0`.
pub(super) struct HeldForce {
    pub(super) state: DVector<f64>,
    pub(super) constant: f64,
    pub(super) harmonic: nalgebra::Complex<f64>,
    /// Per higher harmonic of the forcing, its rate `kω` and `H_k`.
    pub(super) harmonics: Vec<(f64, nalgebra::Complex<f64>)>,
}

impl Engine<'_> {
    /// The constrained flow of the pairs `held` (`(pair, side)`, in pair order) on their
    /// stops, built on first use (see [`Stuck`]). One held pair gives the same numbers as the
    /// one-pair construction it generalises (same Gram–Schmidt, offset and force weights).
    /// Held directions that span every coordinate (a body held on a stop against the frame)
    /// leave a reduced flow of no coordinates: the structure rests on its stops, and only the
    /// contact forces move, with the forcing.
    ///
    /// # Errors
    /// [`SimulationError::DependentHolds`] when the held directions are dependent, and
    /// [`SimulationError::Flow`] when the reduced flow does not exist.
    pub(super) fn stuck_index(&mut self, held: &[(usize, i8)]) -> Result<usize, SimulationError> {
        if let Some(i) = self.stuck.iter().position(|s| s.held == held) {
            return Ok(i);
        }
        let n = self.n;
        let h = held.len();
        let dependent = || SimulationError::DependentHolds(held.iter().map(|h| h.0).collect());
        if h == 0 || h > n {
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
        let t = if basis.is_empty() {
            DMatrix::zeros(n, 0)
        } else {
            DMatrix::from_columns(&basis)
        };
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
        let k = &self.model.stiffness;
        let tt = t.transpose();
        let flow = self.reduced_flow(&t, &offset)?;
        // λ = −W⁻¹DM⁻¹(f − C u̇ − K u), u = Tũ + u*, u̇ = Tũ̇.
        let mob = mobilities.transpose();
        let a = solve(&mob * k * &t);
        let b = self.model.damping.as_ref().map(|c| solve(&mob * c * &t));
        let constants = solve(&mob * k * DMatrix::from_column_slice(n, 1, offset.as_slice()));
        let fcos =
            solve(&mob * DMatrix::from_column_slice(n, 1, self.model.forcing_cos.as_slice()));
        let fsin =
            solve(&mob * DMatrix::from_column_slice(n, 1, self.model.forcing_sin.as_slice()));
        // Per harmonic, `(kω, W⁻¹DM⁻¹f_c,k, W⁻¹DM⁻¹f_s,k)`, as the fundamental's.
        let column =
            |f: &DVector<f64>| solve(&mob * DMatrix::from_column_slice(n, 1, f.as_slice()));
        let harmonic_parts: Vec<(f64, DMatrix<f64>, DMatrix<f64>)> = self
            .model
            .active_harmonics()
            .map(|h| (h.order as f64 * self.omega, column(&h.cos), column(&h.sin)))
            .collect();
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
                    harmonics: harmonic_parts
                        .iter()
                        .map(|(rate, c, s)| {
                            (*rate, nalgebra::Complex::new(-c[(row, 0)], s[(row, 0)]))
                        })
                        .collect(),
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

    /// The reduced flow on `u = T ũ + u*` (`basis` `T`, `offset` `u*`):
    /// `TᵀMT ũ̈ + TᵀCT ũ̇ + TᵀKT ũ = Tᵀ(f − K u*)`, every harmonic of the forcing projected
    /// as the fundamental is (a harmonic along the held directions only forces the contact
    /// forces, and leaves the reduced flow).
    ///
    /// # Errors
    /// [`FlowError`] when the reduced flow does not exist.
    fn reduced_flow(
        &self,
        basis: &DMatrix<f64>,
        offset: &DVector<f64>,
    ) -> Result<LinearFlow, FlowError> {
        let (t, m, k) = (basis, &self.model.mass, &self.model.stiffness);
        let tt = t.transpose();
        let mr = &tt * m * t;
        let kr = &tt * k * t;
        let cr = self.model.damping.as_ref().map(|c| &tt * c * t);
        let fc = &tt * &self.model.forcing_cos;
        let fs = &tt * &self.model.forcing_sin;
        let f0 = -(&tt * (k * offset));
        let harmonics: Vec<crate::Harmonic> = self
            .model
            .active_harmonics()
            .map(|h| crate::Harmonic {
                order: h.order,
                cos: &tt * &h.cos,
                sin: &tt * &h.sin,
            })
            .collect();
        let flow = LinearFlow::with_harmonics(
            (&mr, cr.as_ref(), &kr),
            (&fc, &fs, &f0),
            &harmonics,
            self.omega,
        )?;
        Ok(if self.model.general_form {
            flow.without_steady_response()
        } else {
            flow
        })
    }

    /// The held set after pair `pair` sticks on `side` in `mode`.
    pub(super) fn held_with(&self, mode: Mode, pair: usize, side: i8) -> Vec<(usize, i8)> {
        let mut held = match mode {
            Mode::Free | Mode::Pressed(_) => Vec::new(),
            Mode::Stuck(i) => self.stuck[i].held.clone(),
        };
        held.retain(|h| h.0 != pair);
        held.push((pair, side));
        held.sort_unstable();
        held
    }

    /// Event: pair `c.pair` sticks on side `c.side`. Plastic: relative velocity to zero,
    /// momentum kept; the run continues on the reduced flow.
    pub(super) fn stick(
        &mut self,
        state: &mut RunState,
        c: Contact,
    ) -> Result<(), SimulationError> {
        let time = state.k as f64 * self.period + state.tau;
        if matches!(state.mode, Mode::Pressed(_)) {
            return Err(SimulationError::HoldWithCompliantContact(time));
        }
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

    /// Event: the held pair at position `released` of the held set is let go `s` into the
    /// stuck phase (its contact force would pull); the others stay held, and the run
    /// continues on their constrained flow (free flight when none is left).
    pub(super) fn release(
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
    pub(super) fn stuck_phase(
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
        let (sin, cos) = crate::trig::sin_cos(self.omega * tau);
        let rotation = nalgebra::Complex::new(cos, sin);
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
            for &(rate, harmonic) in &force.harmonics {
                let (sin, cos) = crate::trig::sin_cos(rate * tau);
                lambda.terms.push(crate::expsum::Term {
                    poly: [
                        harmonic * nalgebra::Complex::new(cos, sin),
                        Default::default(),
                        Default::default(),
                        Default::default(),
                    ],
                    rate: nalgebra::Complex::new(0.0, rate),
                });
            }
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
            let watched = WatchedPairs {
                pairs: &self.pairs,
                functionals: st.watched.iter().map(|(q, f, shift)| (*q, f, *shift)),
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
                self.contact(state, c, contact::BeforeContact::formed())?;
            }
            (Watch::Step(_), _) => state.tau += span,
            (Watch::Clear, Some((s, position))) => self.release(state, index, position, s)?,
            (Watch::Clear, None) => state.tau = period,
        }
        Ok(())
    }
}
