//! The event loop: exact flights, first contacts, restitution, chatter and sticking, and the
//! steady state seen through the stroboscopic map at `t = kT`.

use crate::expsum::{ExpSum, SearchStack};
use crate::flow::{FlowError, Functional, LinearFlow};
use crate::model::{ContactPair, Model};
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
    /// Cap on forcing periods when running until steady.
    pub max_periods: u64,
    /// Cap on events (impacts, stick and release) when running until steady: bounds the time
    /// of motions with very many events per period. `None`: no cap.
    pub max_events: Option<u64>,
    /// Cap on the free oscillations of the fastest mode when running until steady, counted as
    /// periods × `ω_fastest/ω`: transients decay on the natural time scale, and a forcing far
    /// below the natural frequencies (thousands of oscillations per period) would otherwise
    /// make [`Self::max_periods`] periods cost minutes. `None`: no cap.
    pub max_oscillations: Option<f64>,
    /// Largest period multiplicity `p` looked for.
    pub max_period_multiplicity: u32,
    /// Run exactly this many periods and judge the steady state from the tail.
    pub fixed_periods: Option<u64>,
    /// Keep dense samples of the final cycle (or final 16 periods).
    pub record_trajectory: bool,
}

impl Default for SimulationOptions {
    fn default() -> Self {
        Self {
            root_tolerance: 1e-12,
            periodicity_tolerance: 1e-9,
            max_periods: 20_000,
            max_events: Some(2_000_000),
            max_oscillations: Some(2e6),
            max_period_multiplicity: 16,
            fixed_periods: None,
            record_trajectory: false,
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
    /// The motion repeated (or nothing could dissipate its transients).
    Decided,
    /// The requested number of periods was run.
    FixedPeriods,
    /// The period cap was reached.
    PeriodCap,
    /// The event cap was reached.
    EventCap,
    /// The oscillation cap ([`SimulationOptions::max_oscillations`]) was reached first.
    OscillationCap,
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
    /// Impacts accumulated without a resolution (more than a million in one period).
    #[error("more than {0} events in one forcing period at t = {1}: an unresolved accumulation")]
    EventStorm(u64, f64),
}

/// Geometry of one contact pair.
struct Pair {
    spec: ContactPair,
    /// `d` with `r = d·u`.
    direction: DVector<f64>,
    /// `M⁻¹ d`.
    mobility: DVector<f64>,
    /// `dᵀ M⁻¹ d`.
    compliance: f64,
    /// `r` as a functional of the free flow's state.
    relative_displacement: Functional,
}

/// A contact pair held on one stop: the reduced flow and the contact force.
struct Stuck {
    pair: usize,
    side: i8,
    flow: LinearFlow,
    /// `u = basis ũ + offset`.
    basis: DMatrix<f64>,
    offset: DVector<f64>,
    /// Contact force along `d`: `λ = force_state · (ũ, ũ̇) + force_constant + Re{force_harmonic e^{iωt}}`.
    force_state: DVector<f64>,
    force_constant: f64,
    force_harmonic: nalgebra::Complex<f64>,
}

enum Mode {
    Free,
    Stuck(usize),
}

struct Engine<'m> {
    model: &'m Model,
    omega: f64,
    period: f64,
    n: usize,
    free: LinearFlow,
    /// `u_j` as functionals of the free flow's state, for the amplitudes.
    displacements: Vec<Functional>,
    pairs: Vec<Pair>,
    stuck: Vec<Stuck>,
    time_tolerance: f64,
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

/// Simulates `model` at `omega` from `start` until steady (or for a fixed number of periods).
pub fn simulate(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> Result<SteadyState, SimulationError> {
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
    let mut engine = Engine::new(model, omega, options)?;
    engine.run(start, options)
}

impl<'m> Engine<'m> {
    fn new(
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
        let pairs = model
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
                Pair {
                    spec: *c,
                    direction: d,
                    mobility,
                    compliance,
                    relative_displacement,
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
        Ok(Self {
            model,
            omega,
            period,
            n,
            free,
            displacements,
            pairs,
            stuck: Vec::new(),
            time_tolerance: options.root_tolerance * period,
        })
    }

    /// The reduced flow of pair `pair` held on `side`, built on first use.
    fn stuck_index(&mut self, pair: usize, side: i8) -> Result<usize, SimulationError> {
        if let Some(i) = self
            .stuck
            .iter()
            .position(|s| s.pair == pair && s.side == side)
        {
            return Ok(i);
        }
        let n = self.n;
        let p = &self.pairs[pair];
        let d = &p.direction;
        // Orthonormal basis of d⊥ by Gram–Schmidt on the unit vectors.
        let dn = d.normalize();
        let mut basis: Vec<DVector<f64>> = Vec::new();
        for i in 0..n {
            let mut v = DVector::zeros(n);
            v[i] = 1.0;
            v -= &dn * dn.dot(&v);
            for b in &basis {
                v -= b * b.dot(&v);
            }
            if v.norm() > 1e-8 && basis.len() < n - 1 {
                basis.push(v.normalize());
            }
        }
        let t = DMatrix::from_columns(&basis);
        let gap = if side > 0 {
            p.spec.gap_plus
        } else {
            -p.spec.gap_minus
        };
        let offset = d * (gap / d.norm_squared());
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
        // λ = −dᵀM⁻¹(f − C u̇ − K u)/(dᵀM⁻¹d), u = Tũ + u*, u̇ = Tũ̇.
        let w = p.compliance;
        let mob = p.mobility.transpose();
        let a = (&mob * k * &t) / w;
        let mut force_state = DVector::zeros(2 * (n - 1));
        force_state.rows_mut(0, n - 1).copy_from(&a.transpose());
        if let Some(c) = &self.model.damping {
            let b = (&mob * c * &t) / w;
            force_state.rows_mut(n - 1, n - 1).copy_from(&b.transpose());
        }
        let force_constant = (&mob * k * &offset)[(0, 0)] / w;
        let lc = -(&mob * &self.model.forcing_cos)[(0, 0)] / w;
        let ls = -(&mob * &self.model.forcing_sin)[(0, 0)] / w;
        self.stuck.push(Stuck {
            pair,
            side,
            flow,
            basis: t,
            offset,
            force_state,
            force_constant,
            force_harmonic: nalgebra::Complex::new(lc, -ls),
        });
        Ok(self.stuck.len() - 1)
    }

    fn gap_scale(&self) -> f64 {
        self.pairs
            .iter()
            .map(|p| p.spec.gap_plus.max(p.spec.gap_minus))
            .fold(0.0, f64::max)
    }

    /// Relative acceleration `r̈` of pair `p` in free flight at state `y`, phase time `tau`:
    /// `(M⁻¹d) · (f(τ) − K u − C u̇)`.
    fn free_relative_acceleration(&self, p: &Pair, y: &DVector<f64>, tau: f64) -> f64 {
        let n = self.n;
        let m = self.model;
        let (sin, cos) = (self.omega * tau).sin_cos();
        (0..n)
            .map(|i| {
                let mut f = m.forcing_cos[i] * cos + m.forcing_sin[i] * sin;
                for j in 0..n {
                    f -= m.stiffness[(i, j)] * y[j];
                    if let Some(c) = &m.damping {
                        f -= c[(i, j)] * y[n + j];
                    }
                }
                p.mobility[i] * f
            })
            .sum()
    }

    fn run(
        &mut self,
        start: &Start,
        options: &SimulationOptions,
    ) -> Result<SteadyState, SimulationError> {
        let n = self.n;
        let period = self.period;
        let mut k: u64 = 0;
        let mut tau = start.time.rem_euclid(period);
        let mut y = start.state.clone();
        let mut mode = Mode::Free;
        let mut impacts: u64 = 0;
        let p_max = options.max_period_multiplicity as usize;
        let mut ring: VecDeque<DVector<f64>> = VecDeque::with_capacity(p_max + 2);
        let conservative = self.model.conservative();
        // Periods allowed by the oscillation cap (at least 64, enough to judge a period).
        let oscillation_periods = options.max_oscillations.map_or(u64::MAX, |cap| {
            let per_period = self.free.fastest_rate() / self.omega;
            ((cap / per_period.max(1e-300)).floor() as u64).max(64)
        });
        let limit = match options.fixed_periods {
            Some(n) => n,
            None if conservative => options.max_periods.min(1000).min(oscillation_periods),
            None => options.max_periods.min(oscillation_periods),
        };
        let window_len = (p_max as u64).min(limit);
        // Early stop when periodic: detect, then observe `p` more periods.
        let mut observe_until: Option<(u64, u32)> = None;
        let mut window: Option<Window> = None;
        let mut last_impact_period: Option<u64> = None;
        // Chatter bookkeeping.
        let mut events_this_period: u64 = 0;
        let mut events_total: u64 = 0;
        let mut stopped = if options.fixed_periods.is_some() {
            Stop::FixedPeriods
        } else if oscillation_periods
            < options
                .max_periods
                .min(if conservative { 1000 } else { u64::MAX })
        {
            Stop::OscillationCap
        } else {
            Stop::PeriodCap
        };
        let tol_scale = self.gap_scale().max(1e-300);
        let depth = 1e-12 * tol_scale;
        let v_tiny = 1e-10 * self.omega * tol_scale;
        // After a release the pair leaves the stop with zero relative velocity and acceleration;
        // rounding must not read that as a new contact. Contacts are ignored until `grace`.
        let settle = 1e-10 * period;
        let mut grace = f64::NEG_INFINITY;
        // Storage reused by every flight.
        let mut gap = ExpSum::default();
        let mut stack = SearchStack::default();
        let mut coordinate = ExpSum::default();
        let mut event_exponentials = Vec::new();

        if tau == 0.0 {
            ring.push_back(y.clone()); // the start is itself a section
        }
        loop {
            // Start the observation window.
            let window_start = match (options.fixed_periods, observe_until) {
                (_, Some((until, p))) => until - p as u64,
                _ => limit.saturating_sub(window_len),
            };
            if window.is_none() && k >= window_start {
                let mut w = Window {
                    amplitudes: vec![0.0; n],
                    ..Window::default()
                };
                if tau == 0.0 {
                    w.stroboscopic.push(y.clone());
                }
                window = Some(w);
            }
            let horizon = period - tau;
            let absolute = |tau: f64| k as f64 * period + tau;
            match mode {
                Mode::Free => {
                    let flight = self.free.flight(&y, tau);
                    // Positions are known to rounding relative to their size, not to the gap:
                    // an excursion beyond a stop smaller than that is no contact.
                    let position_scale = y.rows(0, n).amax();
                    let depth = depth + 1e-14 * position_scale;
                    let mut event: Option<(f64, usize, i8)> = None;
                    for (i, p) in self.pairs.iter().enumerate() {
                        flight.expand(&p.relative_displacement, &mut gap);
                        if let Some((s, side)) = gap.first_exit(
                            -p.spec.gap_minus,
                            p.spec.gap_plus,
                            horizon,
                            self.time_tolerance,
                            depth,
                            &mut stack,
                        ) {
                            if event.is_none_or(|e| s < e.0) {
                                event = Some((s, i, side));
                                event_exponentials.clear();
                                if let Some(e) = stack.exponentials_at(s) {
                                    event_exponentials.extend_from_slice(e);
                                }
                            }
                        }
                    }
                    if let Some((s, _, _)) = event {
                        if tau + s < grace {
                            // Just released: step past the stop's edge without an event.
                            let step = (grace - tau).min(horizon);
                            y = flight.state(step);
                            tau += step;
                            if tau >= period {
                                tau = period;
                            } else {
                                continue;
                            }
                        }
                    }
                    let event = event.filter(|_| tau < period);
                    let span = if tau >= period {
                        0.0
                    } else {
                        event.map_or(horizon, |e| e.0)
                    };
                    if let Some(w) = window.as_mut() {
                        for (amp, u) in w.amplitudes.iter_mut().zip(&self.displacements) {
                            flight.expand(u, &mut coordinate);
                            *amp = coordinate.max_abs(span, *amp, 1e-13 * (1.0 + *amp));
                        }
                        if options.record_trajectory {
                            sample(&mut w.trajectory, span, period, |s| {
                                (absolute(tau + s), flight.state(s))
                            });
                        }
                    }
                    match event {
                        None if tau >= period => {}
                        None => {
                            flight.state_into(horizon, &mut y);
                            tau = period;
                        }
                        Some((s, i, side)) => {
                            // Just before the event.
                            flight.state_at(s, &event_exponentials, &mut y);
                            tau += s;
                            events_this_period += 1;
                            if events_this_period > 1_000_000 {
                                return Err(SimulationError::EventStorm(1_000_000, absolute(tau)));
                            }
                            let p = &self.pairs[i];
                            let rdot = p.direction.dot(&y.rows(n, n));
                            // Only an approach counts as an impact; a start on the stop moving
                            // out of it (rounding) is handled as sticking below.
                            let e = p.spec.restitution;
                            // Velocities are known to rounding relative to their size: a slower
                            // approach is a graze, not an impact.
                            let velocity_round = 1e-13 * y.rows(n, n).amax();
                            let approaching = rdot * side as f64 > velocity_round;
                            if approaching {
                                if let Some(w) = window.as_mut() {
                                    w.impacts.push(ImpactRecord {
                                        time: absolute(tau),
                                        phase: tau,
                                        pair: i,
                                        side,
                                        state_before: y.clone(),
                                        relative_velocity: rdot,
                                    });
                                }
                                self.model.apply_impact(i, &mut y, None);
                                impacts += 1;
                                last_impact_period = Some(k);
                            }
                            // Stick? Post-impact relative speed, and the free relative
                            // acceleration pushing into the stop.
                            let rdot_after = p.direction.dot(&y.rows(n, n));
                            let push = self.free_relative_acceleration(p, &y, tau) * side as f64;
                            let accumulation = if push > 0.0 && e < 1.0 {
                                2.0 * rdot_after.abs() / (push * (1.0 - e))
                            } else {
                                f64::INFINITY
                            };
                            let stick = push > 0.0
                                && (rdot_after.abs() <= v_tiny + velocity_round
                                    || accumulation < CHATTER * period
                                    || !approaching);
                            if !approaching && !stick {
                                // A touch that is neither an impact nor a hold (rounding at a
                                // graze): step past it rather than find it again.
                                grace = tau + settle;
                            }
                            if stick {
                                // Plastic: relative velocity to zero, momentum kept.
                                self.model.apply_impact(i, &mut y, Some(0.0));
                                let idx = self.stuck_index(i, side)?;
                                mode = Mode::Stuck(idx);
                            }
                        }
                    }
                }
                Mode::Stuck(idx) => {
                    let st = &self.stuck[idx];
                    let nr = n - 1;
                    // Reduced state: ũ = Tᵀ(u − u*), ũ̇ = Tᵀ u̇.
                    let tt = st.basis.transpose();
                    let mut yr = DVector::zeros(2 * nr);
                    yr.rows_mut(0, nr)
                        .copy_from(&(&tt * (y.rows(0, n) - &st.offset)));
                    yr.rows_mut(nr, nr).copy_from(&(&tt * y.rows(n, n)));
                    let flight = st.flow.flight(&yr, tau);
                    let mut force = flight.value_of(&st.force_state).shifted(st.force_constant);
                    let e = nalgebra::Complex::new(0.0, self.omega * tau).exp();
                    force.terms.push(crate::expsum::Term {
                        poly: [
                            st.force_harmonic * e,
                            Default::default(),
                            Default::default(),
                            Default::default(),
                        ],
                        rate: nalgebra::Complex::new(0.0, self.omega),
                    });
                    // Held while side·λ < 0: release at the first root of −side·λ.
                    let hold = if st.side > 0 { force.negated() } else { force };
                    // `hold` ≥ 0 at the start: the release is its first exit from [0, ∞).
                    let release = hold
                        .first_exit(
                            0.0,
                            f64::INFINITY,
                            horizon,
                            self.time_tolerance,
                            0.0,
                            &mut stack,
                        )
                        .map(|(s, _)| s);
                    let span = release.unwrap_or(horizon);
                    let full = |s: f64| {
                        let r = flight.state(s);
                        let mut out = DVector::zeros(2 * n);
                        out.rows_mut(0, n)
                            .copy_from(&(&st.basis * r.rows(0, nr) + &st.offset));
                        out.rows_mut(n, n).copy_from(&(&st.basis * r.rows(nr, nr)));
                        out
                    };
                    if let Some(w) = window.as_mut() {
                        w.sticking = true;
                        for (j, amp) in w.amplitudes.iter_mut().enumerate() {
                            // u_j = T_j · ũ + offset_j.
                            let mut c = DVector::zeros(2 * nr);
                            c.rows_mut(0, nr).copy_from(&st.basis.row(j).transpose());
                            let f = flight.value_of(&c).shifted(st.offset[j]);
                            *amp = f.max_abs(span, *amp, 1e-13 * (1.0 + *amp));
                        }
                        if options.record_trajectory {
                            sample(&mut w.trajectory, span, period, |s| {
                                (absolute(tau + s), full(s))
                            });
                        }
                    }
                    y = full(span);
                    match release {
                        Some(s) => {
                            tau += s;
                            grace = tau + settle;
                            mode = Mode::Free;
                            events_this_period += 1;
                            if events_this_period > 1_000_000 {
                                return Err(SimulationError::EventStorm(1_000_000, absolute(tau)));
                            }
                        }
                        None => tau = period,
                    }
                }
            }
            if tau < period {
                continue;
            }
            // Section t = (k + 1)T.
            k += 1;
            tau = 0.0;
            events_total += events_this_period;
            events_this_period = 0;
            grace = f64::NEG_INFINITY; // `grace` is a time within the period just ended
            if let Some(w) = window.as_mut() {
                w.stroboscopic.push(y.clone());
            }
            ring.push_back(y.clone());
            if ring.len() > p_max + 2 {
                ring.pop_front();
            }
            let out_of_events = options.fixed_periods.is_none()
                && observe_until.is_none()
                && options.max_events.is_some_and(|cap| events_total > cap);
            if out_of_events {
                // Observe one more stretch for the amplitudes, then stop.
                stopped = Stop::EventCap;
                observe_until = Some((k + window_len, window_len as u32));
                window = None;
                continue;
            }
            let done = match observe_until {
                Some((until, _)) => k >= until,
                None => k >= limit,
            };
            // Undamped and no impact for QUIET periods: nothing will ever dissipate the
            // transients (unless a later beat reaches a stop; the status says so).
            let quiet = !self.model.has_damping()
                && options.fixed_periods.is_none()
                && observe_until.is_none()
                && k >= QUIET
                && last_impact_period.is_none_or(|last| k - last > QUIET);
            if quiet && window.is_none() {
                // Observe one more stretch for the amplitudes, then stop.
                observe_until = Some((k + window_len, window_len as u32));
                continue;
            }
            if done {
                break;
            }
            if options.fixed_periods.is_none() && observe_until.is_none() {
                if let Some(p) =
                    least_period(&ring, p_max, options.periodicity_tolerance, tol_scale)
                {
                    observe_until = Some((k + p as u64, p));
                    window = None;
                }
            }
        }
        let window = window.unwrap_or_default();
        // A period detected while running is confirmed at the end with ten times the
        // tolerance (a transient through complex multipliers does not decay monotonically);
        // a fixed run is judged from its tail alone.
        let period_found = match observe_until {
            Some((_, p)) if stopped != Stop::EventCap => {
                (repeat_error(&ring, p as usize, scale_floor(&ring, tol_scale))
                    <= 10.0 * options.periodicity_tolerance)
                    .then_some(p)
            }
            _ => least_period(&ring, p_max, options.periodicity_tolerance, tol_scale),
        };
        if matches!(stopped, Stop::PeriodCap | Stop::OscillationCap) && observe_until.is_some() {
            stopped = Stop::Decided;
        }
        let no_recent_impacts =
            last_impact_period.is_none_or(|last| k.saturating_sub(last) > window_len);
        let status = match period_found {
            Some(_) => Status::Periodic,
            None if conservative || (!self.model.has_damping() && no_recent_impacts) => {
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
        let cycle_impacts: Vec<ImpactRecord> = window
            .impacts
            .iter()
            .filter(|i| i.time >= cycle_start - 1e-9 * period)
            .cloned()
            .collect();
        let stroboscopic: Vec<DVector<f64>> = window
            .stroboscopic
            .iter()
            .skip(window.stroboscopic.len().saturating_sub(cycle as usize + 1))
            .cloned()
            .collect();
        let trajectory = options.record_trajectory.then(|| {
            window
                .trajectory
                .into_iter()
                .filter(|(t, _)| *t >= cycle_start - 1e-9 * period)
                .collect()
        });
        Ok(SteadyState {
            status,
            period: period_found,
            impacts_per_period: cycle_impacts.len() as f64 / cycle as f64,
            amplitudes: window.amplitudes,
            sticking: window.sticking,
            stopped,
            periods_run: k,
            impacts,
            cycle_impacts,
            stroboscopic,
            final_state: Start {
                state: y,
                time: 0.0,
            },
            trajectory,
        })
    }
}

/// Chatter is cut short when the remaining bounces would all fit in this fraction of a period:
/// the pair then sticks at once (the state error is of order the remaining relative velocity
/// times that time).
const CHATTER: f64 = 1e-5;

/// Undamped motion with no impact for this many periods is reported as `NoDissipation`.
const QUIET: u64 = 500;

/// Dense samples of a segment: about 200 per forcing period, ends included.
fn sample<F: Fn(f64) -> (f64, DVector<f64>)>(
    out: &mut Vec<(f64, DVector<f64>)>,
    span: f64,
    period: f64,
    at: F,
) {
    let count = ((span / period) * 200.0).ceil().max(1.0) as usize;
    for i in 0..=count {
        out.push(at(span * i as f64 / count as f64));
    }
}

/// The floor of the scale of [`repeat_error`]: the gap, or the motion's own size (the largest
/// state in `ring`) when that is smaller, so that a unit that never comes near its stops is
/// judged on its own scale.
fn scale_floor(ring: &VecDeque<DVector<f64>>, gap: f64) -> f64 {
    gap.min(ring.iter().map(|x| x.norm()).fold(0.0, f64::max))
}

/// Largest `|x_k − x_{k−p}|` over the last two sections (`∞` if too few), relative to
/// `max(|x_k|, floor)`.
fn repeat_error(ring: &VecDeque<DVector<f64>>, p: usize, floor: f64) -> f64 {
    let len = ring.len();
    if len <= p + 1 {
        return f64::INFINITY;
    }
    (0..2)
        .map(|back| {
            let a = &ring[len - 1 - back];
            let b = &ring[len - 1 - back - p];
            let diff = a
                .iter()
                .zip(b.iter())
                .map(|(x, y)| (x - y) * (x - y))
                .sum::<f64>()
                .sqrt();
            diff / a.norm().max(floor).max(1e-300)
        })
        .fold(0.0, f64::max)
}

/// Differences within this factor of the tolerance at a smaller multiplicity make a period
/// ambiguous: a transient decaying through a negative or complex Floquet multiplier can repeat
/// at `2T` long before it repeats at `T`.
const AMBIGUITY: f64 = 1e3;

/// The least `p` with `|x_k − x_{k−p}| ≤ tol·scale` at the last two sections, provided no
/// smaller multiplicity comes within [`AMBIGUITY`] of the tolerance (then it is too early to
/// tell, and `None` is returned).
fn least_period(ring: &VecDeque<DVector<f64>>, p_max: usize, tol: f64, gap: f64) -> Option<u32> {
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
