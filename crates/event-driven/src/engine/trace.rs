//! Traced runs: each segment's closed form sampled, and each event's states.

use super::*;

/// What a row of a sampled trajectory is ([`crate::trajectory::TrajectoryRow::kind`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// A uniform sample in time.
    Sample,
    /// The state just before an impact (or a stick without impact).
    BeforeImpact,
    /// The state just after an impact's restitution.
    AfterImpact,
    /// The state just after a stick (the plastic hold on a stop).
    AfterStick,
}

/// An impact seen by a traced run.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct TracedImpact {
    /// Time since the run's start (a section).
    pub(crate) time: f64,
    pub(crate) pair: usize,
    pub(crate) side: i8,
    /// `ṙ⁻`.
    pub(crate) relative_velocity: f64,
    /// The state just before.
    pub(crate) state_before: DVector<f64>,
}

/// The exact samples of a traced run: uniform samples, and each event's states.
#[derive(Debug, Clone, Default)]
pub(crate) struct Trace {
    /// Uniform samples per period.
    pub(crate) per_period: u64,
    /// The next uniform sample's index within the current period.
    pub(super) next: u64,
    /// `(time since the start, kind, state)`, in time order.
    pub(crate) rows: Vec<(f64, RowKind, DVector<f64>)>,
    pub(crate) impacts: Vec<TracedImpact>,
}

impl Trace {
    /// The uniform samples `t_j = jT/N` of period `k` inside the segment `[tau, tau + span)`,
    /// from the segment's closed form `at(s)`, `s = t_j − tau`.
    pub(super) fn segment<F: Fn(f64) -> DVector<f64>>(
        &mut self,
        k: u64,
        period: f64,
        tau: f64,
        span: f64,
        at: F,
    ) {
        let step = period / self.per_period as f64;
        while self.next < self.per_period {
            let tj = self.next as f64 * step;
            if tj >= tau + span {
                break;
            }
            if tj >= tau {
                self.rows
                    .push((k as f64 * period + tj, RowKind::Sample, at(tj - tau)));
            }
            self.next += 1;
        }
    }
}

/// Dense samples of a segment: [`SAMPLES_PER_PERIOD`] per forcing period, ends included.
pub(super) fn sample<F: Fn(f64) -> (f64, DVector<f64>)>(
    out: &mut Vec<(f64, DVector<f64>)>,
    span: f64,
    period: f64,
    at: F,
) {
    let count = ((span / period) * SAMPLES_PER_PERIOD).ceil().max(1.0) as usize;
    for i in 0..=count {
        out.push(at(span * i as f64 / count as f64));
    }
}

impl Engine<'_> {
    /// Runs `periods` periods from state `y` at the section `t = 0`, tracing it: `per_period`
    /// uniform samples per period from each segment's closed form (the last at
    /// `t = periods·T`), each impact's states before and after, each stick's, and the impacts.
    ///
    /// # Errors
    /// As [`Engine::next_iter`].
    pub(crate) fn trace_run(
        &mut self,
        y: &DVector<f64>,
        periods: u64,
        per_period: u64,
    ) -> Result<Trace, SimulationError> {
        let plan = Plan::fixed(periods);
        let mut state = self.init(
            &Start {
                state: y.clone(),
                time: 0.0,
            },
            &plan,
        )?;
        state.trace = Some(Trace {
            per_period: per_period.max(1),
            ..Trace::default()
        });
        while state.k < periods {
            self.next_iter(&mut state, &plan)?;
        }
        let mut trace = state.trace.take().unwrap_or_default();
        trace
            .rows
            .push((periods as f64 * self.period, RowKind::Sample, state.y));
        Ok(trace)
    }
}
