//! A flight of a [`LinearFlow`]: the flow from one state at one forcing phase, evaluated as
//! a state, as modal coordinates, or as a sum of exponential terms of a linear functional
//! (and the summaries of such sums that the event search bounds them by).

#[cfg(target_arch = "x86_64")]
use super::packed::{modal_state_avx, steady_state_avx, AVX_COLUMN, PACKED_MODES};
use super::{cexp, resonant, Functional, JointWeights, LinearFlow, SteadyResponse, C64};
use crate::expsum::{summarize_block, ExpSum, Summary, Term, LANES};
use nalgebra::DVector;

/// A flight: the flow from a given state at a given forcing phase.
#[derive(Debug, Clone)]
pub struct Flight<'a> {
    pub(super) flow: &'a LinearFlow,
    pub(super) form: Form<'a>,
}

/// How a flight forms its modal coordinates.
#[derive(Debug, Clone)]
pub(super) enum Form<'a> {
    /// `z(s) = e^{λs} ∘ h + z_p(t₀ + s)`: the deviation `h = z(0) − z_p(t₀)` from the steady
    /// response decays (or persists) mode by mode; `phase = e^{iωt₀}`, `harmonic_phases`
    /// each higher harmonic's `e^{ikωt₀}` (empty without harmonics). `deviation` holds the
    /// kept modes' only, in the order of [`LinearFlow::kept`] (contiguous: the loops over
    /// them read it in order).
    Steady {
        response: &'a SteadyResponse,
        deviation: Vec<C64>,
        phase: C64,
        harmonic_phases: Vec<C64>,
    },
    /// `z(s) = e^{λs} ∘ z(0) + Σ G φ(λ, μ, s)`, finite at resonance ([`GeneralStart`]),
    /// boxed: a flight is moved by value through the event loop, and the steady-response
    /// form's is the smaller.
    General(Box<GeneralStart>),
}

/// A flight in the general form: `z(s) = e^{λs} ∘ z(0) + Σ G φ(λ, μ, s)`. The forcing
/// coefficients carry the start phase: `G⁺ = g⁺ e^{iωt₀}`, `G⁻ = g⁻ e^{−iωt₀}`, and likewise
/// each higher harmonic's at `μ = ±ikω`. `start` holds the modes' `z(0)`, then, with rigid
/// modes, each one's start packed in `2 +` harmonics entries
/// ([`RigidModes::start`](super::rigid::RigidModes::start)).
#[derive(Debug, Clone)]
pub(super) struct GeneralStart {
    pub(super) start: DVector<C64>,
    pub(super) plus: DVector<C64>,
    pub(super) minus: DVector<C64>,
    pub(super) harmonics: Vec<HarmonicStart>,
}

/// One higher harmonic of a flight in the general form: its rate `ikω` and its modal forcing
/// at the flight's start, `G⁺_k = g⁺_k e^{ikωt₀}`, `G⁻_k = g⁻_k e^{−ikωt₀}`.
#[derive(Debug, Clone)]
pub(super) struct HarmonicStart {
    pub(super) rate: C64,
    pub(super) plus: DVector<C64>,
    pub(super) minus: DVector<C64>,
}

/// `φ(λ, μ, s) = ∫₀ˢ e^{λ(s−σ)} e^{μσ} dσ` as terms in `s`, resonance-safe.
fn phi_terms(lambda: C64, mu: C64, period: f64, scale: C64, out: &mut Vec<Term>) {
    let delta = mu - lambda;
    let zero = C64::new(0.0, 0.0);
    if resonant(delta, period) {
        out.push(Term {
            poly: [
                zero,
                scale,
                scale * delta / 2.0,
                scale * delta * delta / 6.0,
            ],
            rate: lambda,
        });
    } else {
        let c = scale / delta;
        out.push(Term {
            poly: [c, zero, zero, zero],
            rate: mu,
        });
        out.push(Term {
            poly: [-c, zero, zero, zero],
            rate: lambda,
        });
    }
}

/// Value of `φ(λ, μ, s)` given `e^{λs}` and `e^{μs}`.
fn phi_shared(lambda: C64, el: C64, mu: C64, em: C64, s: f64, period: f64) -> C64 {
    let delta = mu - lambda;
    if resonant(delta, period) {
        el * (s + delta * (s * s / 2.0) + delta * delta * (s * s * s / 6.0))
    } else {
        (em - el) / delta
    }
}

impl Flight<'_> {
    /// The flight's storage for its modal deviation (empty for the resonance-safe form), for
    /// the next [`LinearFlow::flight_at_phase`].
    #[inline]
    pub(crate) fn into_storage(self) -> Vec<C64> {
        match self.form {
            Form::Steady { deviation, .. } => deviation,
            Form::General(_) => Vec::new(),
        }
    }

    /// In the steady-response form, each higher harmonic's term of `functional`: its rate
    /// `ikω` and coefficient `A_k e^{ikωt₀}`, in the flow's order of its harmonics (a harmonic
    /// the functional has no part of, e.g. one prepared by another flow, with coefficient 0:
    /// a steady-form expansion always holds one term per harmonic); none in the general form.
    fn harmonic_terms<'s>(
        &'s self,
        functional: &'s Functional,
    ) -> impl Iterator<Item = (C64, C64)> + 's {
        let (harmonics, phases): (&[_], &[C64]) = match &self.form {
            Form::Steady {
                response,
                harmonic_phases,
                ..
            } => (&response.harmonics, harmonic_phases),
            Form::General(_) => (&[], &[]),
        };
        harmonics
            .iter()
            .zip(phases)
            .enumerate()
            .map(move |(i, (h, &phase))| {
                let a = functional.harmonic.get(i).copied().unwrap_or_default();
                (C64::new(0.0, h.rate), a * phase)
            })
    }

    /// Each higher harmonic's phase `e^{ikω(t₀ + s)}` at `s` into the flight, from its start
    /// phase and `e^{ikωs}`: the exponential `known` lists (after the kept modes' and the
    /// forcing's, as [`Self::expand`] orders the terms), or evaluated.
    fn harmonic_forced(&self, s: f64, known: Option<&[C64]>, harmonic_phases: &[C64]) -> Vec<C64> {
        let f = self.flow;
        let first = f.kept.len() + 1;
        let rates = f
            .steady
            .iter()
            .flat_map(|p| p.harmonics.iter().map(|h| h.rate));
        rates
            .zip(harmonic_phases)
            .enumerate()
            .map(|(i, (rate, &phase))| {
                let e = match known {
                    Some(e) => e[first + i],
                    None => cexp(C64::new(0.0, rate), s),
                };
                e * phase
            })
            .collect()
    }

    /// The state `y(s)` at time `s` into the flight.
    pub fn state(&self, s: f64) -> DVector<f64> {
        let mut y = DVector::zeros(2 * self.flow.dofs);
        self.state_into(s, &mut y);
        y
    }

    /// [`Self::state`] written into `y` (length `2n`), without allocating.
    pub fn state_into(&self, s: f64, y: &mut DVector<f64>) {
        self.state_with(s, None, y);
    }

    /// [`Self::state_into`], given `exponentials`: `e^{μ_j s}` of the terms of any functional
    /// [`Self::expand`]ed from this flight, in their order (as a search over that functional
    /// leaves them at the contact it found). They replace the exponentials of the modes, the
    /// forcing and its harmonics when the flight follows the steady response; otherwise they
    /// are ignored.
    pub fn state_at(&self, s: f64, exponentials: &[C64], y: &mut DVector<f64>) {
        self.state_with(s, Some(exponentials), y);
    }

    fn state_with(&self, s: f64, exponentials: Option<&[C64]>, y: &mut DVector<f64>) {
        let f = self.flow;
        // Zeroed as a slice: nalgebra's element iterator takes some 360 instructions for a
        // chain's 32 entries.
        y.as_mut_slice().fill(0.0);
        // `expand` lists the kept modes, then the forcing, then each harmonic.
        let known = exponentials.filter(|e| e.len() > f.kept.len() + f.steady_harmonics());
        // Shared exponentials: e^{±iωs} once for all modes.
        let ep = match known {
            Some(e) if matches!(self.form, Form::Steady { .. }) => e[f.kept.len()],
            _ => cexp(C64::new(0.0, f.omega), s),
        };
        match &self.form {
            Form::Steady {
                response: p,
                deviation,
                phase,
                harmonic_phases,
            } => {
                let forced = ep * phase;
                if !harmonic_phases.is_empty() {
                    let harmonic = self.harmonic_forced(s, known, harmonic_phases);
                    for (j, &(k, weight)) in f.kept.iter().enumerate() {
                        let el = known.map_or_else(|| cexp(f.rates[k], s), |e| e[j]);
                        let forcing = (deviation[j] * el, forced, &harmonic[..]);
                        let zk = p.coordinate_with_harmonics(j, forcing, weight);
                        f.add_mode(k, zk, y.as_mut_slice());
                    }
                    return;
                }
                // A chain's state with AVX when the CPU has it (the same bits).
                #[cfg(target_arch = "x86_64")]
                if 2 * f.dofs >= AVX_COLUMN && std::arch::is_x86_feature_detected!("avx") {
                    let at = (s, known);
                    // SAFETY: the CPU has AVX (checked just above).
                    unsafe { steady_state_avx(f, (p, deviation, forced), at, y.as_mut_slice()) };
                    return;
                }
                for (j, &(k, weight)) in f.kept.iter().enumerate() {
                    let el = known.map_or_else(|| cexp(f.rates[k], s), |e| e[j]);
                    let zk = p.coordinate(j, deviation[j] * el, forced, weight);
                    f.add_mode(k, zk, y.as_mut_slice());
                }
            }
            Form::General(general) => {
                let GeneralStart {
                    start,
                    plus,
                    minus,
                    harmonics,
                } = &**general;
                let w = C64::new(0.0, f.omega);
                let em = ep.conj();
                let zero = C64::new(0.0, 0.0);
                // Each harmonic's `e^{ikωs}`, once for all modes.
                let harmonic_exps: Vec<C64> = harmonics.iter().map(|h| cexp(h.rate, s)).collect();
                for &(k, weight) in &f.kept {
                    let l = f.rates[k];
                    let el = cexp(l, s);
                    let mut zk = el * start[k]
                        + plus[k] * phi_shared(l, el, w, ep, s, f.period)
                        + minus[k] * phi_shared(l, el, -w, em, s, f.period);
                    if f.constant[k] != zero {
                        zk += f.constant[k]
                            * phi_shared(l, el, zero, C64::new(1.0, 0.0), s, f.period);
                    }
                    for (h, &e) in harmonics.iter().zip(&harmonic_exps) {
                        zk += h.plus[k] * phi_shared(l, el, h.rate, e, s, f.period)
                            + h.minus[k] * phi_shared(l, el, -h.rate, e.conj(), s, f.period);
                    }
                    let zk = zk * weight;
                    f.add_mode(k, zk, y.as_mut_slice());
                }
                if let Some(modes) = &f.rigid {
                    let starts = &start.as_slice()[f.rates.len()..];
                    let exps = (ep, &harmonic_exps[..]);
                    modes.add_state(starts, s, exps, f.omega, y.as_mut_slice());
                }
            }
        }
    }

    /// The kept modes' coordinates `z_k` (their weights included, `y = Σ_k Re(v_k z_k)`) of
    /// the state at `s` into the flight, into `z` (the kept modes', in their order), given
    /// `exponentials` as for [`Self::state_at`], which forms the state from the same
    /// coordinates, the same bits: `(h_k e^{λ_k s} + P⁺_k F + P⁻_k F̄ + P⁰_k)·weight`, `F`
    /// the forcing's phase at `s` (each harmonic's terms added before the weight). Without
    /// harmonics, with AVX and the exponentials there given, `h_k e^{λ_k s}` too, into
    /// `carried`, bit for bit [`Self::deviation_at`]'s (else `carried` is left empty).
    /// `false` (nothing written) for the general form.
    pub(crate) fn modal_state(
        &self,
        s: f64,
        exponentials: &[C64],
        (z, carried): (&mut Vec<C64>, &mut Vec<C64>),
    ) -> bool {
        let f = self.flow;
        let Form::Steady {
            response: p,
            deviation,
            phase,
            harmonic_phases,
        } = &self.form
        else {
            return false;
        };
        let known =
            (exponentials.len() > f.kept.len() + f.steady_harmonics()).then_some(exponentials);
        let ep = match known {
            Some(e) => e[f.kept.len()],
            None => cexp(C64::new(0.0, f.omega), s),
        };
        let forced = ep * phase;
        z.clear();
        carried.clear();
        if !harmonic_phases.is_empty() {
            let harmonic = self.harmonic_forced(s, known, harmonic_phases);
            z.extend(f.kept.iter().enumerate().map(|(j, &(k, weight))| {
                let el = known.map_or_else(|| cexp(f.rates[k], s), |e| e[j]);
                p.coordinate_with_harmonics(j, (deviation[j] * el, forced, &harmonic), weight)
            }));
            return true;
        }
        #[cfg(target_arch = "x86_64")]
        if let Some(e) = known {
            if f.kept.len() >= PACKED_MODES && std::arch::is_x86_feature_detected!("avx") {
                z.resize(f.kept.len(), C64::default());
                carried.resize(f.kept.len(), C64::default());
                // SAFETY: the CPU has AVX (checked just above).
                unsafe { modal_state_avx(f, (p, deviation, forced), e, (z, carried)) };
                return true;
            }
        }
        z.extend(f.kept.iter().enumerate().map(|(j, &(k, weight))| {
            let el = match known {
                Some(e) => e[j],
                None => cexp(f.rates[k], s),
            };
            p.coordinate(j, deviation[j] * el, forced, weight)
        }));
        true
    }

    /// The deviation from the steady response at `s` into the flight, `h e^{λs}` per kept
    /// mode, written into `out` (the kept modes', in their order), given `exponentials` as for
    /// [`Self::state_at`]: the start of the next flight without recomputing it from the
    /// state. `false` (nothing written) for the general form or without those exponentials.
    pub(crate) fn deviation_at(&self, exponentials: &[C64], out: &mut Vec<C64>) -> bool {
        let f = self.flow;
        let Form::Steady { deviation, .. } = &self.form else {
            return false;
        };
        if exponentials.len() <= f.kept.len() {
            return false;
        }
        out.clear();
        #[cfg(target_arch = "x86_64")]
        if deviation.len() >= PACKED_MODES && std::arch::is_x86_feature_detected!("avx") {
            out.resize(deviation.len(), C64::default());
            // SAFETY: the CPU has AVX (checked just above).
            unsafe { crate::expsum::products_avx(deviation, exponentials, out) };
            return true;
        }
        out.extend(deviation.iter().zip(exponentials).map(|(&h, &e)| h * e));
        true
    }

    /// The [`Summary`] of the functional's terms, as [`Self::expand`] would write them (the
    /// same coefficients — `w (d·weight)` there `(w d)·weight`, equal since a weight of 1 or 2
    /// scales exactly — in the same order), without writing them, term by term as
    /// [`Summary::add_mode`] adds them: for the steady-response form when no rate grows (then
    /// the summary holds for any cutoff); `None` otherwise.
    pub(crate) fn summarize(&self, functional: &Functional, horizon: f64) -> Option<Summary> {
        let f = self.flow;
        let Form::Steady {
            deviation, phase, ..
        } = &self.form
        else {
            return None;
        };
        if !horizon.is_finite() || f.rates.iter().any(|r| r.re > 0.0) {
            return None;
        }
        let weights = functional.weights.as_slice();
        let mut sum = Summary::default();
        let modes = f.kept.iter().zip(&f.kept_sizes).zip(deviation);
        for ((&(k, weight), &(rate, cube)), &h) in modes {
            let (c, mu) = (weights[k] * (h * weight), f.rates[k]);
            if rate == 0.0 {
                sum.add_decaying::<true>(c, mu);
            } else {
                sum.add_mode(c, mu, rate, cube);
            }
        }
        let forcing = C64::new(0.0, f.omega);
        let rate = forcing.re.abs() + forcing.im.abs();
        sum.add_mode(functional.forced * phase, forcing, rate, rate * rate * rate);
        if !f.harmonics.is_empty() {
            for (mu, c) in self.harmonic_terms(functional) {
                let rate = mu.re.abs() + mu.im.abs();
                sum.add_mode(c, mu, rate, rate * rate * rate);
            }
        }
        if functional.constant != 0.0 {
            sum.add_decaying::<true>(C64::new(functional.constant, 0.0), C64::default());
        }
        Some(sum)
    }

    /// [`Self::summarize`] of every functional of `joint`, in its order, into `out`, in one
    /// pass over the modes (each mode's deviation and rate read once for all functionals);
    /// each summary is bit for bit the one [`Self::summarize`] gives. `false` (nothing
    /// written) where [`Self::summarize`] gives `None`, or a kept mode has rate zero.
    /// The terms' coefficients are left in `coefficients`, laid out as `joint`'s weights, for
    /// [`Self::expand_joint`].
    pub(crate) fn summarize_all(
        &self,
        joint: &JointWeights,
        horizon: f64,
        (deviations, coefficients): (&mut Vec<C64>, &mut Vec<[f64; 2 * LANES]>),
        out: &mut Vec<Summary>,
    ) -> bool {
        let f = self.flow;
        let Form::Steady {
            deviation,
            phase,
            harmonic_phases,
            ..
        } = &self.form
        else {
            return false;
        };
        let Some(template) = &f.joint_modes else {
            return false;
        };
        let rows = f.kept.len() + 1 + harmonic_phases.len();
        if !horizon.is_finite()
            || template.len() != rows
            || joint.blocks.len() != joint.count.div_ceil(LANES) * rows
        {
            return false;
        }
        let count = joint.count;
        let modes = &template[..];
        // Each kept mode's deviation times its weight, then the forced part `forced · phase`
        // at `iω` (weight 1: exact).
        deviations.clear();
        deviations.extend(modes.iter().zip(deviation).map(|(m, &h)| m.weighted(h)));
        deviations.push(modes[f.kept.len()].weighted(*phase));
        if !harmonic_phases.is_empty() {
            let harmonic_modes = &modes[f.kept.len() + 1..];
            deviations.extend(
                harmonic_modes
                    .iter()
                    .zip(harmonic_phases)
                    .map(|(m, &phase)| m.weighted(phase)),
            );
        }
        coefficients.resize(joint.blocks.len(), [0.0; 2 * LANES]);
        let per_block = modes.len();
        // Every summary is written below: storage of the right length is only kept.
        out.resize(joint.blocks.len() / per_block * LANES, Summary::default());
        for ((block, written), sums) in joint
            .blocks
            .chunks_exact(per_block)
            .zip(coefficients.chunks_exact_mut(per_block))
            .zip(out.chunks_exact_mut(LANES))
        {
            summarize_block(block, (modes, deviations), written, sums);
        }
        out.truncate(count);
        for (sum, &constant) in out.iter_mut().zip(&joint.constant) {
            if constant != 0.0 {
                sum.add_decaying::<true>(C64::new(constant, 0.0), C64::default());
            }
        }
        true
    }

    /// The linear functional `c · y(s)` as a sum of exponential terms in `s`.
    pub fn value_of(&self, c: &DVector<f64>) -> ExpSum {
        let mut out = ExpSum::default();
        self.expand(&self.flow.functional(c), &mut out);
        out
    }

    /// [`Self::expand`] of the functional in slot `slot` of the joint summaries that
    /// [`Self::summarize_all`] has just formed for this flight, into `out` that holds the
    /// expansion of that functional by an earlier flight of the same flow in the
    /// steady-response form (its rates, its zero coefficients beyond the constant ones, its
    /// constant term): only the constant coefficients that depend on the flight are written,
    /// copied from the summaries' `coefficients` (`w (d·weight)` there, `(w d)·weight` in
    /// [`Self::expand`]: equal, since a weight of 1 or 2 scales exactly), so `out` ends as
    /// [`Self::expand`] would leave it, bit for bit. Otherwise (another form, or `out` not of
    /// that length) it is [`Self::expand`]. Writing the terms out is some 5 % of a chain's
    /// time, and forming their coefficients again would be 5 % of its instructions (see the
    /// performance page, `docs/performance.md`).
    pub(crate) fn expand_joint(
        &self,
        functional: &Functional,
        (coefficients, slot): (&[[f64; 2 * LANES]], usize),
        out: &mut ExpSum,
    ) {
        let f = self.flow;
        // The kept modes, the forcing and each harmonic: a block's rows per functional.
        let per_block = f.kept.len() + 1 + f.steady_harmonics();
        let count = per_block + usize::from(functional.constant != 0.0);
        let (block, lane) = (slot / LANES, slot % LANES);
        let rows = coefficients.get(block * per_block..(block + 1) * per_block);
        match (&self.form, rows) {
            (Form::Steady { .. }, Some(rows)) if out.terms.len() == count => {
                for (t, row) in out.terms.iter_mut().zip(rows) {
                    t.poly[0] = C64::new(row[lane], row[LANES + lane]);
                }
            }
            _ => self.expand(functional, out),
        }
    }

    /// The functional prepared by [`LinearFlow::functional`] as a sum of exponential terms in
    /// `s`, written into `out` (its previous terms are dropped, its storage reused).
    pub fn expand(&self, functional: &Functional, out: &mut ExpSum) {
        let f = self.flow;
        let zero = C64::new(0.0, 0.0);
        let w = C64::new(0.0, f.omega);
        let weights = &functional.weights;
        out.terms.clear();
        match &self.form {
            Form::Steady {
                deviation, phase, ..
            } => {
                let weights = weights.as_slice();
                out.terms
                    .extend(f.kept.iter().zip(deviation).map(|(&(k, weight), &h)| Term {
                        poly: [weights[k] * h * weight, zero, zero, zero],
                        rate: f.rates[k],
                    }));
                out.terms.push(Term {
                    poly: [functional.forced * phase, zero, zero, zero],
                    rate: w,
                });
                if !f.harmonics.is_empty() {
                    out.terms
                        .extend(self.harmonic_terms(functional).map(|(rate, c)| Term {
                            poly: [c, zero, zero, zero],
                            rate,
                        }));
                }
                if functional.constant != 0.0 {
                    out.terms.push(Term {
                        poly: [C64::new(functional.constant, 0.0), zero, zero, zero],
                        rate: zero,
                    });
                }
            }
            Form::General(general) => {
                let GeneralStart {
                    start,
                    plus,
                    minus,
                    harmonics,
                } = &**general;
                let per_mode = 4 + 4 * harmonics.len();
                let per_rigid = 2 + harmonics.len();
                let mut terms =
                    Vec::with_capacity(per_mode * f.rates.len() + per_rigid * f.rigid_modes());
                for (k, &l) in f.rates.iter().enumerate() {
                    let wk = weights[k];
                    terms.push(Term {
                        poly: [wk * start[k], zero, zero, zero],
                        rate: l,
                    });
                    phi_terms(l, w, f.period, wk * plus[k], &mut terms);
                    phi_terms(l, -w, f.period, wk * minus[k], &mut terms);
                    if f.constant[k] != zero {
                        phi_terms(l, zero, f.period, wk * f.constant[k], &mut terms);
                    }
                    // Each harmonic's particular terms, resonance-safe at its own rate `±ikω`.
                    for h in harmonics {
                        phi_terms(l, h.rate, f.period, wk * h.plus[k], &mut terms);
                        phi_terms(l, -h.rate, f.period, wk * h.minus[k], &mut terms);
                    }
                }
                if let Some(modes) = &f.rigid {
                    let elastic = f.rates.len();
                    let starts = &start.as_slice()[elastic..];
                    let weights = &functional.weights.as_slice()[elastic..];
                    modes.terms(weights, starts, f.omega, &mut terms);
                }
                out.terms = merge(terms);
            }
        }
    }
}

/// Merges terms with equal rates, and folds each term with rate `μ̄` into the one with rate `μ`
/// (`Re(B e^{μ̄s}) = Re(B̄ e^{μs})`): half the exponentials to evaluate for a real system.
fn merge(terms: Vec<Term>) -> Vec<Term> {
    let mut out: Vec<Term> = Vec::with_capacity(terms.len());
    for t in terms {
        if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate) {
            for i in 0..4 {
                o.poly[i] += t.poly[i];
            }
        } else if let Some(o) = out.iter_mut().find(|o| o.rate == t.rate.conj()) {
            for i in 0..4 {
                o.poly[i] += t.poly[i].conj();
            }
        } else {
            out.push(t);
        }
    }
    out
}
