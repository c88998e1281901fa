//! The event loop of a response: flights between segment boundaries and contacts, the
//! contacts' restitution, and what the run records of each flight.

use super::modal::Flight;
use super::phase::Phase;
use super::signal::{check, Signal};
use super::*;
// The contact, graze, rest and chatter thresholds are the periodic engine's, each a fraction of
// this run's gap, position, velocity and time scales.
use crate::engine::{
    CHATTER, CONTACT_DEPTH, POSITION_ROUNDING, RELEASE_GRACE as GRACE, RESTING_VELOCITY,
    VELOCITY_ROUNDING,
};
use crate::expsum::{ExpSum, SearchStack};

/// Iterations of the Illinois search for a zero of `u̇_j` (a peak of `u_j`): each at least
/// halves the bracket every other step, so 120 reach any double's resolution.
const PEAK_ITERATIONS: usize = 120;

/// Smallest scale divided by.
const SCALE_FLOOR: f64 = 1e-300;

/// Gauss–Legendre nodes on `[−1, 1]`, rising, and weights, eight points: exact for
/// polynomials of degree 15.
const GAUSS: [(f64, f64); 8] = [
    (-0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
    (-0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (-0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (-0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.183_434_642_495_649_8, 0.362_683_783_378_362),
    (0.525_532_409_916_329, 0.313_706_645_877_887_3),
    (0.796_666_477_413_626_7, 0.222_381_034_453_374_5),
    (0.960_289_856_497_536_3, 0.101_228_536_290_376_3),
];

/// Where uniform samples go.
pub(super) type Sink<'s> = &'s mut dyn FnMut(SampledState<'_>);

/// What ends a flight besides its horizon.
enum Event {
    /// Pair `.0` reaches its stop on side `.1`.
    Contact(usize, i8),
    /// The `.0`-th held pair's stop lets go.
    Release(usize),
}

/// One contact pair's geometry.
struct Geometry {
    /// `d`.
    direction: DVector<f64>,
    /// `−gap_minus`, `gap_plus`.
    lo: f64,
    hi: f64,
}

/// Everything fixed for the run.
struct Runner<'a> {
    model: &'a Model,
    excitation: &'a Excitation,
    signal: &'a Signal,
    pairs: Vec<Geometry>,
    /// The fastest rate of the free flow and the signal (`≥ 2π/T`).
    fastest: f64,
    duration: f64,
    time_scale: f64,
    time_tolerance: f64,
    gap_scale: f64,
    resting_velocity: f64,
    grace: f64,
    chatter: f64,
    max_flight: f64,
    max_events: u64,
}

/// What the run accumulates.
struct Record {
    impacts: Vec<ResponseImpact>,
    holds: Vec<ResponseHold>,
    grazes: u64,
    flights: u64,
    squares: Vec<f64>,
    peak: Vec<f64>,
    dashpots: f64,
    work: f64,
    /// `(time, index into at)`, by time; the next one to serve.
    at: Vec<(f64, usize)>,
    next_at: usize,
    states: Vec<Option<ResponseState>>,
    /// Uniform samples: their count `N`, the next `j`.
    samples: Option<u64>,
    next_sample: u64,
}

/// `1` for side 1 (`+gap_plus`, `+1`), `2` for side 2.
fn side_number(side: i8) -> u8 {
    if side > 0 {
        1
    } else {
        2
    }
}

fn state_of(t: f64, y: &DVector<f64>) -> ResponseState {
    let n = y.len() / 2;
    ResponseState {
        t,
        displacements: y.as_slice()[..n].to_vec(),
        velocities: y.as_slice()[n..].to_vec(),
    }
}

/// Checks the inputs: the excitation's vectors, the duration, the requested times and the
/// tolerances.
fn check_inputs(
    model: &Model,
    excitation: &Excitation,
    options: &ResponseOptions,
) -> Result<(), SignalError> {
    let n = model.dofs();
    for (name, v) in [
        ("on_signal", &excitation.on_signal),
        ("on_rate", &excitation.on_rate),
    ] {
        check(
            || format!("excitation.{name}"),
            v.len() as f64,
            v.len() == n,
            "one entry per degree of freedom",
        )?;
        for (i, &x) in v.iter().enumerate() {
            check(|| format!("excitation.{name}[{i}]"), x, true, "finite")?;
        }
    }
    let duration = options.duration;
    check(|| "duration".into(), duration, duration > 0.0, "> 0")?;
    for (i, &t) in options.at.iter().enumerate() {
        check(
            || format!("at[{i}]"),
            t,
            (0.0..=duration).contains(&t),
            "in [0, duration]",
        )?;
    }
    let tol = options.root_tolerance;
    check(
        || "root_tolerance".into(),
        tol,
        tol > 0.0 && tol < 1e-3,
        "in (0, 1e-3)",
    )?;
    if let Some(scale) = options.time_scale {
        check(|| "time_scale".into(), scale, scale > 0.0, "> 0")?;
    }
    Ok(())
}

/// The run of [`respond`] and [`respond_sampled`].
pub(super) fn run(
    model: &Model,
    excitation: &Excitation,
    signal: &Signal,
    options: &ResponseOptions,
    sampling: Option<(u64, Sink<'_>)>,
) -> Result<Response, ResponseError> {
    let (samples, mut sink) = match sampling {
        Some((count, sink)) => (Some(count), Some(sink)),
        None => (None, None),
    };
    check_inputs(model, excitation, options)?;
    if let Some(pair) = (0..model.contacts().len()).find(|&p| model.compliance(p).is_some()) {
        return Err(ResponseError::Compliant { pair });
    }
    let free = Phase::free(model, excitation)?;
    let runner = Runner::new(model, (excitation, signal), &free, options)?;
    let n = model.dofs();
    let mut order: Vec<(f64, usize)> = options.at.iter().copied().zip(0..).collect();
    order.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut record = Record {
        impacts: Vec::new(),
        holds: Vec::new(),
        grazes: 0,
        flights: 0,
        squares: vec![0.0; n],
        peak: vec![0.0; n],
        dashpots: 0.0,
        work: 0.0,
        at: order,
        next_at: 0,
        states: vec![None; options.at.len()],
        samples,
        next_sample: 0,
    };
    let mut phases = vec![free];
    let mut current = 0;
    let mut y = DVector::zeros(2 * n);
    let mut t = 0.0;
    let mut grace = vec![f64::NEG_INFINITY; runner.pairs.len()];
    let mut stack = SearchStack::default();
    let mut sum = ExpSum::default();
    while t < runner.duration {
        let phase = &phases[current];
        let segment = signal.segment_at(t);
        let segment_end = segment.map_or(f64::INFINITY, |i| signal.segments()[i].end);
        let end = runner.duration.min(segment_end).min(t + runner.max_flight);
        let horizon = end - t;
        let flight = phase.flight(&y, (signal, segment), t, horizon);
        record.flights += 1;
        let (span, event) = runner.first_event(
            (phase, &flight),
            (segment, t, horizon),
            &y,
            &grace,
            (&mut stack, &mut sum),
        );
        let t_end = if span == horizon { end } else { t + span };
        runner.record_flight(
            &mut record,
            (phase, &flight),
            (segment, t, t_end, span),
            sink.as_deref_mut(),
        );
        phase.state_into(&flight, span, &mut y);
        t = t_end;
        if let Some(Event::Contact(pair, side)) = event {
            current = runner.contact(
                (&mut phases, current),
                &mut record,
                &mut y,
                (t, pair, side),
                &mut grace,
            )?;
        } else if let Some(Event::Release(k)) = event {
            runner.count_event(&record, t)?;
            let (pair, side) = phases[current].held[k];
            let mut held = phases[current].held.clone();
            held.remove(k);
            record.holds.push(ResponseHold {
                t,
                pair,
                side: side_number(side),
                stick: false,
                energy_lost: 0.0,
            });
            grace[pair] = t + runner.grace;
            current = runner.settle((&mut phases, &held), &mut record, &y, t, &mut grace)?;
        }
    }
    // The requested times at `T`, and the last sample: the state reached.
    while record.next_at < record.at.len() {
        let (_, index) = record.at[record.next_at];
        record.states[index] = Some(state_of(runner.duration, &y));
        record.next_at += 1;
    }
    if let (Some(count), Some(sink)) = (record.samples, sink.as_mut()) {
        while record.next_sample <= count {
            let ts = runner.sample_time(record.next_sample, count);
            sink(SampledState {
                t: ts,
                displacements: &y.as_slice()[..n],
                velocities: &y.as_slice()[n..],
            });
            record.next_sample += 1;
        }
    }
    Ok(runner.report(record, &y))
}

impl<'a> Runner<'a> {
    fn new(
        model: &'a Model,
        (excitation, signal): (&'a Excitation, &'a Signal),
        free: &Phase,
        options: &ResponseOptions,
    ) -> Result<Self, ResponseError> {
        let n = model.dofs();
        let duration = options.duration;
        let fastest = free
            .fastest_rate()
            .max(signal.fastest_frequency())
            .max(std::f64::consts::TAU / duration);
        let time_scale = std::f64::consts::TAU / fastest;
        check(
            || "duration".into(),
            duration,
            duration / time_scale <= MAX_DURATION_SCALES,
            "at most 1e7 time scales 2π/max(|λ|, ν) (the fastest oscillation's period)",
        )?;
        let time_scale = options.time_scale.unwrap_or(time_scale);
        let scale_rate = std::f64::consts::TAU / time_scale;
        let pairs = model
            .contacts
            .iter()
            .map(|c| Geometry {
                direction: c.direction(n),
                lo: -c.gap_minus,
                hi: c.gap_plus,
            })
            .collect();
        let gap_scale = model
            .contacts
            .iter()
            .flat_map(|c| [c.gap_plus, c.gap_minus])
            .filter(|g| g.is_finite())
            .fold(0.0, f64::max)
            .max(SCALE_FLOOR);
        Ok(Runner {
            model,
            excitation,
            signal,
            pairs,
            fastest,
            duration,
            time_scale,
            time_tolerance: options.root_tolerance * time_scale,
            gap_scale,
            resting_velocity: RESTING_VELOCITY * scale_rate * gap_scale,
            grace: GRACE * time_scale,
            chatter: CHATTER * time_scale,
            max_flight: MAX_FLIGHT_SCALES * time_scale,
            max_events: options.max_events,
        })
    }

    /// The first event of `flight` (from `t` in segment `segment`, over `horizon`) in
    /// `phase`, and the time to it: a held pair's release (its push first reaching zero), a
    /// contact of another pair (every pair searched up to the earliest found so far), or,
    /// for a pair in its grace time that reaches its edge first, the end of its grace
    /// without an event (`None`, as at the horizon). A contact at a release's instant is
    /// resolved first; the release is found again at once by the next flight.
    fn first_event(
        &self,
        (phase, flight): (&Phase, &Flight),
        (segment, t, horizon): (Option<usize>, f64, f64),
        y: &DVector<f64>,
        grace: &[f64],
        (stack, sum): (&mut SearchStack, &mut ExpSum),
    ) -> (f64, Option<Event>) {
        let n = self.model.dofs();
        let signal = self.signal;
        let mut release: Option<(f64, usize)> = None;
        for k in 0..phase.held.len() {
            let within = release.map_or(horizon, |r| r.0);
            if within <= 0.0 {
                break;
            }
            phase.push(flight, k, (signal, segment), t, sum);
            let found = sum.first_exit(0.0, f64::INFINITY, within, self.time_tolerance, 0.0, stack);
            if let Some((s, _)) = found {
                if release.is_none_or(|r| s < r.0) {
                    release = Some((s, k));
                }
            }
        }
        let position_size = y.as_slice()[..n]
            .iter()
            .fold(0.0, |m: f64, v| m.max(v.abs()));
        let depth = CONTACT_DEPTH * self.gap_scale + POSITION_ROUNDING * position_size;
        let mut contact: Option<(f64, usize, i8)> = None;
        let mut step = release.map_or(horizon, |r| r.0);
        for (pair, geometry) in self.pairs.iter().enumerate() {
            if phase.holds(pair) {
                continue;
            }
            let within = contact.map_or(step, |c| c.0).min(step);
            if within <= 0.0 {
                // An event at the flight's start: no other pair can come earlier.
                break;
            }
            phase.gap(flight, pair, sum);
            let found = sum.first_exit(
                geometry.lo,
                geometry.hi,
                within,
                self.time_tolerance,
                depth,
                stack,
            );
            if let Some((s, side)) = found {
                if t + s < grace[pair] {
                    step = step.min(grace[pair] - t);
                } else if contact.is_none_or(|c| s < c.0) {
                    contact = Some((s, pair, side));
                }
            }
        }
        match (contact.filter(|c| c.0 <= step), release) {
            (Some((s, pair, side)), _) => (s, Some(Event::Contact(pair, side))),
            (None, Some((s, k))) if s <= step => (s, Some(Event::Release(k))),
            _ => (step, None),
        }
    }

    /// The uniform sample time `jT/N`.
    fn sample_time(&self, j: u64, count: u64) -> f64 {
        if j == count {
            self.duration
        } else {
            j as f64 * self.duration / count as f64
        }
    }

    /// The force `f(t) = d s(t) + v ṡ(t)` by segment `segment`'s form.
    fn force_at(&self, segment: Option<usize>, t: f64) -> DVector<f64> {
        let (s, rate) = self.signal.value_and_rate_in(segment, t);
        &self.excitation.on_signal * s + &self.excitation.on_rate * rate
    }

    /// `½u̇ᵀMu̇`.
    fn kinetic(&self, y: &DVector<f64>) -> f64 {
        let n = self.model.dofs();
        let v = y.rows(n, n);
        0.5 * v.dot(&(&self.model.mass * v))
    }

    /// What the run records of a flight from `t0` over `span` (to `t1`): its integrals, its
    /// peaks, and the requested and sampled states in `[t0, t1)`.
    fn record_flight<'o>(
        &self,
        record: &mut Record,
        (phase, flight): (&Phase, &Flight),
        (segment, t0, t1, span): (Option<usize>, f64, f64, f64),
        mut sink: Option<&mut (dyn FnMut(SampledState<'_>) + 'o)>,
    ) {
        let n = self.model.dofs();
        let mut y = DVector::zeros(2 * n);
        while record.next_at < record.at.len() && record.at[record.next_at].0 < t1 {
            let (ta, index) = record.at[record.next_at];
            phase.state_into(flight, (ta - t0).max(0.0), &mut y);
            record.states[index] = Some(state_of(ta, &y));
            record.next_at += 1;
        }
        if let (Some(count), Some(sink)) = (record.samples, sink.as_mut()) {
            while record.next_sample <= count {
                let ts = self.sample_time(record.next_sample, count);
                if ts >= t1 {
                    break;
                }
                phase.state_into(flight, (ts - t0).max(0.0), &mut y);
                sink(SampledState {
                    t: ts,
                    displacements: &y.as_slice()[..n],
                    velocities: &y.as_slice()[n..],
                });
                record.next_sample += 1;
            }
        }
        if span <= 0.0 {
            return;
        }
        // Gauss–Legendre on pieces at most `1/(2 max(|λ|, ν))` long; the points visited in
        // time order (the flight's ends and the nodes), each coordinate's peak taken there
        // and at the zeros of its velocity bracketed between consecutive points.
        let piece = 0.5 / self.fastest.max(phase.fastest_rate());
        let pieces = (span / piece).ceil().max(1.0);
        let h = span / pieces;
        let damping = self.model.damping.as_ref();
        phase.state_into(flight, 0.0, &mut y);
        let mut previous = (0.0, y.clone());
        let nodes = (0..pieces as u64).flat_map(|p| {
            let mid = (p as f64 + 0.5) * h;
            GAUSS
                .iter()
                .map(move |&(x, w)| (mid + 0.5 * h * x, 0.5 * h * w))
        });
        for (s, weight) in nodes.chain(std::iter::once((span, 0.0))) {
            phase.state_into(flight, s, &mut y);
            if weight != 0.0 {
                let (u, v) = (y.rows(0, n), y.rows(n, n));
                let f = self.force_at(segment, t0 + s);
                record.work += weight * f.dot(&v);
                if let Some(c) = damping {
                    record.dashpots += weight * v.dot(&(c * v));
                }
                for (sq, &uj) in record.squares.iter_mut().zip(u.iter()) {
                    *sq += weight * uj * uj;
                }
            }
            for j in 0..n {
                let mut peak = record.peak[j].max(previous.1[j].abs()).max(y[j].abs());
                let (va, vb) = (previous.1[n + j], y[n + j]);
                if va * vb < 0.0 {
                    peak =
                        peak.max(self.turning_point((phase, flight), j, (previous.0, va), (s, vb)));
                }
                record.peak[j] = peak;
            }
            previous = (s, y.clone());
        }
    }

    /// `|u_j|` where `u̇_j` vanishes between `a` and `b` (its values there of opposite
    /// signs), by the Illinois variant of regula falsi on the flight's exact `u̇_j`.
    fn turning_point(
        &self,
        (phase, flight): (&Phase, &Flight),
        j: usize,
        (mut a, mut fa): (f64, f64),
        (mut b, mut fb): (f64, f64),
    ) -> f64 {
        let n = self.model.dofs();
        let mut y = DVector::zeros(2 * n);
        let mut side = 0;
        for _ in 0..PEAK_ITERATIONS {
            let mut x = (a * fb - b * fa) / (fb - fa);
            if !(x > a && x < b) {
                x = 0.5 * (a + b);
            }
            if x <= a || x >= b {
                break;
            }
            phase.state_into(flight, x, &mut y);
            let fx = y[n + j];
            if fx == 0.0 {
                a = x;
                b = x;
                break;
            }
            if (fx < 0.0) == (fa < 0.0) {
                (a, fa) = (x, fx);
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                (b, fb) = (x, fx);
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
        }
        phase.state_into(flight, 0.5 * (a + b), &mut y);
        y[j].abs()
    }

    /// Counts one more event (impact, graze, stick or release) at `t` against the cap.
    fn count_event(&self, record: &Record, t: f64) -> Result<(), ResponseError> {
        let events = record.impacts.len() as u64 + record.grazes + record.holds.len() as u64;
        if events >= self.max_events {
            return Err(ResponseError::EventCap {
                cap: self.max_events,
                time: t,
            });
        }
        Ok(())
    }

    /// The phase of the pairs `held` (built on first use), after releasing at once, one at a
    /// time, any held pair whose push at the state `y` (time `t`) is already negative (the
    /// contact forces shift when a set changes); its index in `phases`.
    fn settle(
        &self,
        (phases, held): (&mut Vec<Phase>, &[(usize, i8)]),
        record: &mut Record,
        y: &DVector<f64>,
        t: f64,
        grace: &mut [f64],
    ) -> Result<usize, ResponseError> {
        let mut held = held.to_vec();
        loop {
            let index = match phases.iter().position(|p| p.held == held) {
                Some(i) => i,
                None => {
                    phases.push(Phase::held(self.model, self.excitation, &held, t)?);
                    phases.len() - 1
                }
            };
            let f = self.force_at(self.signal.segment_at(t), t);
            let pushes = phases[index].pushes_at(self.model, y, &f);
            let pulling = pushes
                .iter()
                .enumerate()
                .filter(|(_, &p)| p < 0.0)
                .min_by(|a, b| a.1.total_cmp(b.1))
                .map(|(k, _)| k);
            let Some(k) = pulling else {
                return Ok(index);
            };
            let (pair, side) = held.remove(k);
            self.count_event(record, t)?;
            record.holds.push(ResponseHold {
                t,
                pair,
                side: side_number(side),
                stick: false,
                energy_lost: 0.0,
            });
            grace[pair] = t + self.grace;
        }
    }

    /// A contact of pair `pair` on `side` at `t`, the state `y` just before, in phase
    /// `current`: an impact if the pair approaches (restitution with the held pairs kept,
    /// recorded), then a stick if the stop holds it (the rebound slower than the resting
    /// velocity, or chatter that would end within [`CHATTER`] of the time scale, with the
    /// stop pushing), else a graze (its grace set). The phase index after it.
    fn contact(
        &self,
        (phases, current): (&mut Vec<Phase>, usize),
        record: &mut Record,
        y: &mut DVector<f64>,
        (t, pair, side): (f64, usize, i8),
        grace: &mut [f64],
    ) -> Result<usize, ResponseError> {
        self.count_event(record, t)?;
        let n = self.model.dofs();
        let phase = &phases[current];
        let direction = &self.pairs[pair].direction;
        let rdot = direction.dot(&y.rows(n, n));
        // A flight's velocities are sums of terms as large as the positions times the fastest
        // rate: they are known to rounding relative to that as well as to their own size (a
        // body just released on its stop has velocities at rounding level, which set no scale).
        let position_size = y.as_slice()[..n]
            .iter()
            .fold(0.0, |m: f64, v| m.max(v.abs()));
        let velocity_size = y.as_slice()[n..]
            .iter()
            .fold(self.fastest * position_size, |m: f64, v| m.max(v.abs()));
        let velocity_round = VELOCITY_ROUNDING * velocity_size;
        let approaching = rdot * side as f64 > velocity_round;
        let e = self.model.contacts[pair].restitution;
        if approaching {
            let before = self.kinetic(y);
            phase.restitute(self.model, pair, y, e);
            let after = self.kinetic(y);
            record.impacts.push(ResponseImpact {
                t,
                pair,
                side: side_number(side),
                relative_velocity_before: rdot,
                energy_lost: before - after,
            });
        }
        // The stop pushes when the relative acceleration (the held pairs' forces included)
        // points into it.
        let f = self.force_at(self.signal.segment_at(t), t);
        let push = direction.dot(&phase.acceleration(self.model, y, &f)) * side as f64;
        let rdot_after = direction.dot(&y.rows(n, n));
        let accumulation = if push > 0.0 && e < 1.0 {
            2.0 * rdot_after.abs() / (push * (1.0 - e))
        } else {
            f64::INFINITY
        };
        let sticks = push > 0.0
            && (rdot_after.abs() <= self.resting_velocity + velocity_round
                || accumulation < self.chatter
                || !approaching);
        if sticks {
            // Plastic: the relative velocity to zero, momentum kept.
            let before = self.kinetic(y);
            phase.restitute(self.model, pair, y, 0.0);
            let after = self.kinetic(y);
            self.count_event(record, t)?;
            record.holds.push(ResponseHold {
                t,
                pair,
                side: side_number(side),
                stick: true,
                energy_lost: before - after,
            });
            let mut held = phase.held.clone();
            held.retain(|h| h.0 != pair);
            held.push((pair, side));
            held.sort_unstable();
            return self.settle((phases, &held), record, y, t, grace);
        }
        if !approaching {
            record.grazes += 1;
            grace[pair] = t + self.grace;
        }
        Ok(current)
    }

    /// The response from what the run recorded, and the state `y` at `T`.
    fn report(&self, record: Record, y: &DVector<f64>) -> Response {
        let n = self.model.dofs();
        let u = y.rows(0, n);
        let potential = 0.5 * u.dot(&(&self.model.stiffness * u));
        let summary = ResponseSummary {
            impacts: record.impacts.len() as u64,
            grazes: record.grazes,
            flights: record.flights,
            rms: record
                .squares
                .iter()
                .map(|s| (s / self.duration).sqrt())
                .collect(),
            peak: record.peak,
            dissipated_by_dashpots: record.dashpots,
            sticks: record.holds.iter().filter(|h| h.stick).count() as u64,
            releases: record.holds.iter().filter(|h| !h.stick).count() as u64,
            dissipated_by_impacts: record
                .impacts
                .iter()
                .map(|i| i.energy_lost)
                .chain(record.holds.iter().map(|h| h.energy_lost))
                .sum(),
            work: record.work,
            final_energy: self.kinetic(y) + potential,
        };
        Response {
            duration: self.duration,
            time_scale: self.time_scale,
            impacts: record.impacts,
            holds: record.holds,
            states: record
                .states
                .into_iter()
                .map(|s| s.expect("every requested time is served"))
                .collect(),
            final_state: state_of(self.duration, y),
            summary,
        }
    }
}
