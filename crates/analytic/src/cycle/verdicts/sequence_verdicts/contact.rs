//! The verdicts on a converged cycle with contact phases (compliant pairs).
//!
//! As [`crate::verdicts::assemble`], flight by flight, with what a contact phase changes:
//! - entry and exit keep the state (no jump, no impact loss); the entry is an approach
//!   (`s ṙ > 0`, else [`SequenceViolation::WrongApproach`]), the exit a departure (`s ṙ < 0`,
//!   else [`ContactViolation::WrongExit`]);
//! - the contact flight runs under the contact system (spring, dashpot, constant force), its
//!   extrema from the balanced matrix `S⁻¹Â_cS` (`S = diag(I, σI, I)`, see
//!   `contact_flights`): `z = S y`, and a functional `c` of the positions reads the same on
//!   `y`; its second moment `∫zzᵀ` by Gauss–Legendre quadrature of the exact flow (see
//!   [`ContactFlow::second_moment`]);
//! - the contacting pair's penetration stays positive through the contact (else
//!   [`ContactViolation::EarlyExit`]); its largest value is reported;
//! - the contact dashpot dissipates `∫ c_c ṙ² dt` ([`EnergyBalance::contact_dissipation`]);
//!   the contact spring's work over a contact is zero (its energy `½k_c δ²` vanishes at entry
//!   and exit), so `forcing_work = dashpot_dissipation + contact_dissipation + impact_losses`;
//! - the monodromy has at entry and exit the saltation `S = I + (f⁺ − f⁻) ∇hᵀ / (∇h · f⁻)`,
//!   `h` the penetration, `f∓` the vector fields of the flights before and after (the dashpot's
//!   force jumps there).

use super::{ContactPhase, ContactViolation, ModelVerdicts};
use crate::cycle_equations::{balanced_exp, velocity_balance};
use crate::flow::Extrema;
use crate::model_flight::ModelFlight;
use crate::orbit::{STABILITY_MARGIN, VIABILITY_TOLERANCE};
use crate::sequence::{EventKind, ImpactKind};
use crate::verdicts::{energy_reference, side_number, CycleModel, CycleVerdicts};
use crate::verdicts::{EnergyBalance, SequenceViolation};
use nalgebra::{Complex, DMatrix, DVector};

/// A contact phase's flight: its balanced flow for the extrema and second moment, and the
/// velocity scale `σ` of the balance.
pub(super) struct ContactFlow {
    balanced: ModelFlight,
    balance: f64,
    /// `Â_c`, unbalanced.
    matrix: DMatrix<f64>,
    /// `c_c (0, w, 0)(0, w, 0)ᵀ`: the contact dashpot's dissipation rate as a quadratic form.
    dissipation: DMatrix<f64>,
}

/// The contact flows of the flights of `verdicts`' problem: `Some` for a contact phase.
pub(super) fn contact_flows(verdicts: &ModelVerdicts<'_, '_>) -> Vec<Option<ContactFlow>> {
    let problem = verdicts.problem;
    let (model, equations) = (problem.model(), problem.equations());
    let n = model.dofs();
    let size = equations.augmented_matrix().nrows();
    let forcing_rate = f64::from(model.forcing().highest_order()) * problem.omega();
    problem
        .events()
        .iter()
        .enumerate()
        .map(|(f, (impact, _))| {
            let a = equations.contact_matrix(f)?;
            let balance = velocity_balance(a, n);
            let scale = |i: usize| {
                if (n..2 * n).contains(&i) {
                    balance
                } else {
                    1.0
                }
            };
            let b = DMatrix::from_fn(size, size, |i, j| a[(i, j)] * (scale(j) / scale(i)));
            let system = DMatrix::from_fn(2 * n, 2 * n, |i, j| a[(i, j)]);
            let rate = crate::model::fastest_rate(&system, n).max(forcing_rate);
            let damping = model.compliance(impact.pair).map_or(0.0, |c| c.damping);
            let w = &model.pairs()[impact.pair].direction;
            let mut v = DVector::zeros(size);
            v.rows_mut(n, n).copy_from(w);
            Some(ContactFlow {
                balanced: ModelFlight::from_matrix(b, rate),
                balance,
                matrix: a.clone(),
                dissipation: &v * v.transpose() * damping,
            })
        })
        .collect()
}

impl ContactFlow {
    /// `y = S⁻¹ z`.
    fn balanced_state(&self, z: &DVector<f64>, n: usize) -> DVector<f64> {
        let mut y = z.clone();
        y.rows_mut(n, n).unscale_mut(self.balance);
        y
    }

    /// `∫₀^τ z zᵀ dt` along the exact contact flow from `z`, by Gauss–Legendre quadrature
    /// ([`GAUSS_NODES`] nodes) on pieces no longer than `2/rate` (`rate` the flow's fastest,
    /// [`ModelFlight::rate`]), the state at each node from the balanced exponential.
    ///
    /// Van Loan's block exponential (the free flights' [`ModelFlight::second_moment`]) is
    /// accurate to rounding of its largest entry, the constant phase state's `∫1 dt`; a stiff
    /// contact's velocities are of order `σ` times its penetration, so their block would carry
    /// that rounding times `σ²`. The quadrature of the flow's own states keeps each entry's
    /// accuracy: the integrand `z zᵀ` is an entire function whose fastest term turns at
    /// `2 · rate`, `≤ 4` radians per piece, where the rule of degree `2 · 16 − 1` leaves
    /// `(4/2)^32/32! ≈ 2e-26` of it.
    fn second_moment(&self, z: &DVector<f64>, n: usize, tau: f64) -> DMatrix<f64> {
        let size = z.len();
        let mut moment = DMatrix::zeros(size, size);
        if tau <= 0.0 {
            return moment;
        }
        let pieces = (tau * self.balanced.rate() / 2.0).ceil().max(1.0);
        let h = tau / pieces;
        let step = balanced_exp(&self.matrix, n, self.balance, h);
        let nodes = gauss_legendre(GAUSS_NODES);
        let at_nodes: Vec<(DMatrix<f64>, f64)> = nodes
            .iter()
            .map(|&(x, w)| {
                let s = 0.5 * h * (x + 1.0);
                (balanced_exp(&self.matrix, n, self.balance, s), 0.5 * h * w)
            })
            .collect();
        let mut start = z.clone();
        for _ in 0..pieces as usize {
            for (flow, weight) in &at_nodes {
                let state = flow * &start;
                moment += &state * state.transpose() * *weight;
            }
            start = &step * start;
        }
        moment
    }
}

/// The held pair's release functional `h` (see [`crate::LinearModel`]'s release
/// functional) along the sticking flight `f` of `duration` from `start`: the stop holds the
/// pair only while `s h ≥ 0`; where it falls below `−`[`VIABILITY_TOLERANCE`]` · gap` the pair
/// is released before the sequence's release ([`ContactViolation::EarlyRelease`]). The flight
/// begins at `t0` after the first event.
fn early_release(
    verdicts: &ModelVerdicts<'_, '_>,
    held: &ContactFlow,
    f: usize,
    start: &DVector<f64>,
    (t0, duration): (f64, f64),
) -> Option<ContactViolation> {
    let problem = verdicts.problem;
    let (equations, events) = (problem.equations(), problem.events());
    let n = problem.model().dofs();
    let (impact, _) = events[f];
    let next = (f + 1) % events.len();
    // `h · z = (S h) · y`: the velocity entries scaled by the balance.
    let mut h = equations.contact_functional(next).clone();
    h.rows_mut(n, n).scale_mut(held.balance);
    let ext = held
        .balanced
        .extrema(&held.balanced_state(start, n), duration, &[h])[0];
    let (least, at) = if impact.side == 1 {
        (ext.min, ext.argmin)
    } else {
        (-ext.max, ext.argmax)
    };
    let gap = verdicts.pairs()[impact.pair].1[usize::from(impact.side != 1)];
    (least < -VIABILITY_TOLERANCE * gap).then(|| ContactViolation::EarlyRelease {
        pair: impact.pair,
        side: side_number(impact.side),
        time: t0 + at,
        excess: -least,
    })
}

/// Nodes of the Gauss–Legendre rule of the contact flights' second moments: degree 31 on
/// pieces of at most 4 radians of the integrand's fastest term (see
/// [`ContactFlow::second_moment`]).
const GAUSS_NODES: usize = 16;

/// The `count`-point Gauss–Legendre rule on `[−1, 1]`: `(node, weight)` pairs, the nodes by
/// Newton on the Legendre polynomial from Chebyshev's estimates (to rounding in a few steps).
fn gauss_legendre(count: usize) -> Vec<(f64, f64)> {
    let n = count as f64;
    (0..count)
        .map(|i| {
            let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n + 0.5)).cos();
            let mut slope = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=count {
                    let k = k as f64;
                    let p2 = ((2.0 * k - 1.0) * x * p1 - (k - 1.0) * p0) / k;
                    p0 = p1;
                    p1 = p2;
                }
                slope = n * (x * p1 - p0) / (x * x - 1.0);
                let dx = p1 / slope;
                x -= dx;
                if dx.abs() <= 1e-16 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * slope * slope))
        })
        .collect()
}

/// What the flights give: amplitudes, violations, the energy integrals and the contact
/// phases' reports.
struct Flights {
    amplitudes: Vec<f64>,
    violations: Vec<SequenceViolation>,
    contact_violations: Vec<ContactViolation>,
    energy: EnergyBalance,
    penetrations: Vec<f64>,
}

/// The orbit's verdicts at the converged `(alpha, phases)` (phases with first 0) of a cycle
/// with contact phases, its contact violations and its contact phases; `None` when the
/// periodicity solve is singular.
pub(super) fn assemble(
    verdicts: &ModelVerdicts<'_, '_>,
    alpha: f64,
    phases: &[f64],
) -> Option<(
    CycleVerdicts<nalgebra::Dyn>,
    Vec<ContactViolation>,
    Vec<ContactPhase>,
)> {
    let problem = verdicts.problem;
    let (model, equations, events) = (problem.model(), problem.equations(), problem.events());
    let (n, m) = (model.dofs(), events.len());
    let states = equations.states();
    let mut x = phases.to_vec();
    x[0] = alpha;
    let e = equations.evaluate_with(&x, false)?;
    let before = e.before_impacts();
    let states_before: Vec<DVector<f64>> = before
        .iter()
        .map(|z| z.rows(0, states).into_owned())
        .collect();
    let states_after: Vec<DVector<f64>> = (0..m)
        .map(|j| match events[j].1 {
            EventKind::Impact => model.impact_state(events[j].0.pair, &states_before[j]),
            _ => states_before[j].clone(),
        })
        .collect();
    let rdot: Vec<f64> = (0..m)
        .map(|j| verdicts.relative_velocity(events[j].0.pair, &states_before[j]))
        .collect();
    let (wrong, mut violations, mut contact_violations) = event_checks(verdicts, &before, &rdot);
    let starts: Vec<DVector<f64>> = (0..m)
        .map(|f| {
            let mut z = if f == 0 {
                e.z1.clone()
            } else {
                before[f].clone()
            };
            z.rows_mut(0, states).copy_from(&states_after[f]);
            z
        })
        .collect();
    let mut totals = flights(verdicts, equations.cycle(), phases, &starts, &wrong);
    violations.append(&mut totals.violations);
    contact_violations.append(&mut totals.contact_violations);
    let mut energy = totals.energy;
    energy.impact_losses = (0..m)
        .filter(|&j| events[j].1 == EventKind::Impact)
        .map(|j| verdicts.impact_loss(events[j].0.pair, rdot[j]))
        .sum();
    let losses =
        energy.dashpot_dissipation.abs() + energy.contact_dissipation + energy.impact_losses;
    let reference = energy_reference(
        energy.forcing_work,
        losses,
        energy.exchange_bound,
        verdicts.static_energy(),
    );
    let energy_residual = (energy.forcing_work
        - energy.dashpot_dissipation
        - energy.contact_dissipation
        - energy.impact_losses)
        .abs()
        / reference;
    let monodromy = monodromy(verdicts, &e.flights, &before, n);
    let floquet_multipliers = verdicts
        .eigenvalues(&monodromy)
        .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); 2 * n]);
    let stable = floquet_multipliers
        .iter()
        .all(|mu| mu.norm() < 1.0 - STABILITY_MARGIN);
    // A contact phase from its entry, a sticking phase from its landing impact.
    let contacts = (0..m)
        .filter(|&j| {
            events[j].1 == EventKind::Entry
                || (events[j].1 == EventKind::Impact && events[j].0.kind == ImpactKind::Stick)
        })
        .map(|j| ContactPhase {
            pair: events[j].0.pair,
            side: events[j].0.side,
            kind: events[j].0.kind,
            entry_phase: phases[j],
            duration: (phases[j + 1] - phases[j]) * equations.cycle(),
            entry_velocity: rdot[j],
            exit_velocity: rdot[j + 1],
            max_penetration: totals.penetrations[j],
        })
        .collect();
    let cycle = CycleVerdicts {
        states_before,
        states_after,
        amplitudes: totals.amplitudes,
        violations,
        energy,
        energy_residual,
        monodromy,
        floquet_multipliers,
        stable,
    };
    Some((cycle, contact_violations, contacts))
}

/// Whether each event meets its stop the right way, and the violations where not: an impact
/// or an entry approaches its stop (`s ṙ > 0`, else [`SequenceViolation::WrongApproach`]), an
/// exit leaves it (`s ṙ < 0`, else [`ContactViolation::WrongExit`]), and at a release the held
/// pair's free acceleration turns away from the stop (`s ḣ < 0` for the release functional
/// `h`, else [`ContactViolation::WrongRelease`]). `before[j]` is the augmented state just
/// before event `j`, `rdot[j]` its `ṙ`.
fn event_checks(
    verdicts: &ModelVerdicts<'_, '_>,
    before: &[DVector<f64>],
    rdot: &[f64],
) -> (Vec<bool>, Vec<SequenceViolation>, Vec<ContactViolation>) {
    let problem = verdicts.problem;
    let (equations, events) = (problem.equations(), problem.events());
    let m = events.len();
    let mut wrong = vec![false; m];
    let mut violations = Vec::new();
    let mut contact_violations = Vec::new();
    for j in 0..m {
        let (impact, kind) = events[j];
        let (pair, side, s) = (
            impact.pair,
            side_number(impact.side),
            f64::from(impact.side),
        );
        let approach = s * rdot[j];
        match kind {
            EventKind::Impact | EventKind::Entry => {
                wrong[j] = approach <= 0.0;
                if wrong[j] {
                    violations.push(SequenceViolation::WrongApproach {
                        pair,
                        side,
                        relative_velocity: rdot[j],
                    });
                }
            }
            EventKind::Exit => {
                wrong[j] = approach >= 0.0;
                if wrong[j] {
                    contact_violations.push(ContactViolation::WrongExit {
                        pair,
                        side,
                        relative_velocity: rdot[j],
                    });
                }
            }
            EventKind::Release => {
                let held = equations.flight_matrix((j + m - 1) % m);
                let rate = s * equations.contact_functional(j).dot(&(held * &before[j]));
                wrong[j] = rate >= 0.0;
                if wrong[j] {
                    contact_violations.push(ContactViolation::WrongRelease { pair, side, rate });
                }
            }
        }
    }
    (wrong, violations, contact_violations)
}

/// The saltation `S = Ĝ + (f⁺ − Ĝf⁻) ∇hᵀ / ḣ⁻` of an event with the state map `g`
/// (`2n × 2n`), the gradient `grad` of its condition on the state, the vector fields `f∓`
/// (state rows) before and after it, and `rate`, the condition's rate of change before it
/// along the augmented flow (`∇h · f⁻` plus the part through the forcing's phase, which a
/// release condition has: a mass held at rest is released by the force alone).
fn event_saltation(
    g: DMatrix<f64>,
    grad: &DVector<f64>,
    f_minus: &DVector<f64>,
    f_plus: &DVector<f64>,
    rate: f64,
) -> DMatrix<f64> {
    let jump = f_plus - &g * f_minus;
    g + jump * grad.transpose() / rate
}

/// The monodromy from just after event 0: the flights' homogeneous blocks and, at each event,
/// the impact's saltation ([`crate::LinearModel::saltation`]) or the contact's
/// `I + (f⁺ − f⁻) ∇hᵀ / (∇h · f⁻)` from the augmented vector fields of the flights on either
/// side (`before[j]`: the augmented state just before event `j`).
fn monodromy(
    verdicts: &ModelVerdicts<'_, '_>,
    flights: &[DMatrix<f64>],
    before: &[DVector<f64>],
    n: usize,
) -> DMatrix<f64> {
    let problem = verdicts.problem;
    let (model, equations, events) = (problem.model(), problem.equations(), problem.events());
    let m = events.len();
    let s = 2 * n;
    let mut monodromy = DMatrix::identity(s, s);
    for (f, flight) in flights.iter().enumerate() {
        let next = (f + 1) % m;
        let (impact, kind) = events[next];
        let z = &before[next];
        let h = equations.contact_functional(next);
        let grad = h.rows(0, s).into_owned();
        let field = equations.flight_matrix(f) * z;
        let rate = h.dot(&field);
        let f_minus = field.rows(0, s).into_owned();
        let salt = match kind {
            EventKind::Impact if equations.contact_matrix(next).is_none() => {
                let p = z.rows(s, z.len() - s).into_owned();
                model.saltation(problem.omega(), impact.pair, &z.rows(0, s).into_owned(), &p)
            }
            EventKind::Impact => {
                // A landing: the impact map, then the flow held on the stop.
                let mut g = DMatrix::identity(s, s);
                g.view_mut((n, n), (n, n))
                    .copy_from(&model.impact_map(impact.pair));
                let mut after = z.clone();
                let velocities = model.impact_map(impact.pair) * z.rows(n, n);
                after.rows_mut(n, n).copy_from(&velocities);
                let f_plus = (equations.flight_matrix(next) * after)
                    .rows(0, s)
                    .into_owned();
                event_saltation(g, &grad, &f_minus, &f_plus, rate)
            }
            EventKind::Entry | EventKind::Exit | EventKind::Release => {
                let f_plus = (equations.flight_matrix(next) * z).rows(0, s).into_owned();
                event_saltation(DMatrix::identity(s, s), &grad, &f_minus, &f_plus, rate)
            }
        };
        let hom = flight.view((0, 0), (s, s));
        monodromy = salt * hom * monodromy;
    }
    monodromy
}

/// Along every flight (from `starts[f]`, the augmented state after event `f`): amplitudes,
/// excursions beyond stops (and, in a contact, the contacting pair's penetration), the energy
/// integrals. `wrong[j]`: event `j` approaches (or, an exit, leaves) its stop the wrong way.
fn flights(
    verdicts: &ModelVerdicts<'_, '_>,
    cycle: f64,
    phases: &[f64],
    starts: &[DVector<f64>],
    wrong: &[bool],
) -> Flights {
    let problem = verdicts.problem;
    let events = problem.events();
    let n = problem.model().dofs();
    let m = events.len();
    let pairs = verdicts.pairs();
    let amplitude_of = verdicts.amplitude_functionals();
    let k = amplitude_of.len();
    let mut functionals = amplitude_of.to_vec();
    functionals.extend(pairs.iter().map(|(c, _)| c.clone()));
    let forms = verdicts.energy_forms();
    let mut totals = Flights {
        amplitudes: vec![0.0; k],
        violations: Vec::new(),
        contact_violations: Vec::new(),
        energy: EnergyBalance {
            forcing_work: 0.0,
            dashpot_dissipation: 0.0,
            impact_losses: 0.0,
            exchange_bound: 0.0,
            contact_dissipation: 0.0,
        },
        penetrations: vec![f64::NAN; m],
    };
    for f in 0..m {
        let end = if f + 1 < m { phases[f + 1] } else { 1.0 };
        let duration = (end - phases[f]) * cycle;
        let contact = verdicts.contact_flows[f].as_ref();
        let ext: Vec<Extrema> = match contact {
            Some(c) => c
                .balanced
                .extrema(&c.balanced_state(&starts[f], n), duration, &functionals),
            None => verdicts.extrema(&starts[f], duration, &functionals),
        };
        for (a, e) in totals.amplitudes.iter_mut().zip(&ext) {
            *a = a.max(e.max.abs()).max(e.min.abs());
        }
        let next = (f + 1) % m;
        let t0 = phases[f] * cycle;
        // The contacting pair and side of a contact flight.
        let inside = contact.map(|_| (events[f].0.pair, events[f].0.side));
        for (p, (_, gaps)) in pairs.iter().enumerate() {
            let r = ext[k + p];
            let attached = |s: i8| {
                [f, next]
                    .iter()
                    .any(|&j| events[j].0.pair == p && events[j].0.side == s && wrong[j])
            };
            for (s, gap, excess, time) in [
                (1i8, gaps[0], r.max - gaps[0], r.argmax),
                (-1i8, gaps[1], -gaps[1] - r.min, r.argmin),
            ] {
                if inside == Some((p, s)) {
                    // In contact: the penetration must stay positive; its depth is reported.
                    totals.penetrations[f] = excess;
                    let (shallow, at) = if s == 1 {
                        (gaps[0] - r.min, r.argmin)
                    } else {
                        (r.max + gaps[1], r.argmax)
                    };
                    if shallow > VIABILITY_TOLERANCE * gap {
                        totals.contact_violations.push(ContactViolation::EarlyExit {
                            pair: p,
                            side: side_number(s),
                            time: t0 + at,
                            excess: shallow,
                        });
                    }
                    continue;
                }
                if excess > VIABILITY_TOLERANCE * gap {
                    let (pair, side, time) = (p, side_number(s), t0 + time);
                    totals.violations.push(if attached(s) {
                        SequenceViolation::Penetration {
                            pair,
                            side,
                            time,
                            excess,
                        }
                    } else {
                        SequenceViolation::ExtraImpact {
                            pair,
                            side,
                            time,
                            excess,
                        }
                    });
                }
            }
        }
        if let Some(c) = contact.filter(|_| events[f].0.kind == ImpactKind::Stick) {
            if let Some(early) = early_release(verdicts, c, f, &starts[f], (t0, duration)) {
                totals.contact_violations.push(early);
            }
        }
        let moment = match contact {
            Some(c) => c.second_moment(&starts[f], n, duration),
            None => verdicts.second_moment(&starts[f], duration),
        };
        let integral = |q: &DMatrix<f64>| q.component_mul(&moment).sum();
        totals.energy.forcing_work += integral(&forms.work);
        totals.energy.dashpot_dissipation += integral(&forms.dissipation);
        totals.energy.exchange_bound += integral(&forms.exchange);
        if let Some(c) = contact {
            totals.energy.contact_dissipation += integral(&c.dissipation);
        }
    }
    totals
}
