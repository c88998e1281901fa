//! The front end: [`simulate()`] and [`simulate_watched()`] run the event loop on a model from
//! a start, then, for a periodic motion, polish its final cycle with the simulator's own Newton
//! ([`crate::newton`]); a cycle that Newton finds unstable is not a steady state, and the run
//! goes on past it ([`UNSTABLE_MARGIN`]). The loop itself (flights, contacts, sticking, the stopping rules) is the
//! crate's engine; its options and results are re-exported here.

use crate::engine::{check_inputs, Engine, Resume};
pub use crate::engine::{
    ContactRecord, ImpactRecord, SimulationError, SimulationOptions, Start, Status, SteadyState,
    Stop, CONSERVATIVE_MAX_PERIODS, DEFAULT_MAX_EVENTS, DEFAULT_MAX_OSCILLATIONS,
    DEFAULT_MAX_PERIODS, DEFAULT_MAX_PERIOD_MULTIPLICITY, DEFAULT_PERIODICITY_TOLERANCE,
    DEFAULT_ROOT_TOLERANCE, EVENT_STORM, MIN_OSCILLATION_PERIODS, SAMPLES_PER_PERIOD,
};
use crate::model::Model;
use crate::newton::{periodic_orbit, PeriodicOrbit};
use nalgebra::DVector;

/// Simulates `model` at `omega` from `start` until steady (or for a fixed number of periods).
///
/// # Errors
/// [`SimulationError::Omega`] for an `omega` that is not finite and positive,
/// [`SimulationError::Start`] for a start state of the wrong length or not finite,
/// [`SimulationError::Option`] for tolerances outside `(0, 1)` or a zero multiplicity,
/// [`SimulationError::Flow`] when a modal flow does not exist (e.g. a defective system), and
/// [`SimulationError::EventStorm`] when more than [`EVENT_STORM`] events fall in one period.
pub fn simulate(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> Result<SteadyState, SimulationError> {
    simulate_watched(model, omega, start, options, &mut |_, _| false)
}

/// As [`simulate`], with a watch on the stroboscopic sections: at each section `t = kT` at
/// which the run is still undecided (running until steady, not periodic yet, no cap reached),
/// `watch(k, state)` is asked, after the stopping rules; `true` ends the run at once with
/// [`Stop::Watched`] (nothing observed: no amplitudes, no final cycle). For callers that
/// recognise a motion before it repeats to the tolerance, e.g. a start entering a known
/// attractor's neighbourhood. A fixed run ([`SimulationOptions::fixed_periods`]) never asks.
///
/// # Errors
/// As [`simulate`].
pub fn simulate_watched(
    model: &Model,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
    watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
) -> Result<SteadyState, SimulationError> {
    check_inputs(model, omega, start, options)?;
    let mut engine = Engine::new(model, omega, options)?;
    let mut steady = engine.run(start, options, watch)?;
    polish(model, omega, options, &mut steady);
    let mut spent = Resume::default();
    while let Some(hold) = unstable_hold(&steady, options) {
        spent.periods += steady.periods_run;
        spent.impacts += steady.impacts;
        spent.hold = hold;
        let next = engine.run_resumed(&steady.final_state, options, spent, watch)?;
        if next.periods_run == 0 {
            break;
        }
        steady = next;
        polish(model, omega, options, &mut steady);
    }
    steady.periods_run += spent.periods;
    steady.impacts += spent.impacts;
    Ok(steady)
}

/// A periodic final cycle whose simulator's own Floquet multipliers reach beyond
/// `1 + UNSTABLE_MARGIN` in modulus is unstable: the run repeated to the tolerance only while
/// passing near it (along its stable manifold), and is not steady there. Measured: the paper's
/// unit (`data/scenes/paper.json`) at ω = 1.4586466165413536 repeats to 1e-9 after 1 172
/// periods on a 28-impact cycle with a multiplier 1.0039 (from both solvers), then leaves it
/// for a stable 28-impact cycle (spectral radius 0.992, outer amplitude 13.227144 against
/// 13.227125) by 6 000 periods. The margin is far above the rounding of the multipliers
/// (Newton's residual, 1e-12) and keeps neutral cycles (a multiplier at 1 up to rounding)
/// steady.
pub const UNSTABLE_MARGIN: f64 = 1e-6;

/// The periods to run on, without testing periodicity, off a final cycle that is unstable:
/// the time for a departure of the periodicity tolerance to grow to the motion's size at the
/// cycle's spectral radius `ρ`, `ln(1/tol)/ln ρ`. `None` for a stable or neutral cycle, one
/// that was not polished, and a fixed run.
fn unstable_hold(steady: &SteadyState, options: &SimulationOptions) -> Option<u64> {
    if options.fixed_periods.is_some() || steady.stopped != Stop::Decided {
        return None;
    }
    let orbit = steady.orbit.as_ref()?;
    let radius = orbit
        .floquet_multipliers
        .iter()
        .map(|m| m.norm())
        .fold(0.0, f64::max);
    (radius > 1.0 + UNSTABLE_MARGIN)
        .then(|| (options.periodicity_tolerance.recip().ln() / radius.ln()).ceil() as u64)
}

/// For a periodic motion, when asked: the final cycle polished by the simulator's Newton (or
/// why not), and the amplitudes read from one cycle run from the polished orbit, so that they
/// are the periodic orbit's to rounding rather than the last simulated cycle's (which is
/// within the periodicity tolerance of it). The cycle runs on an engine of its own, so the
/// run's engine (its caches) is left as the run left it.
fn polish(model: &Model, omega: f64, options: &SimulationOptions, steady: &mut SteadyState) {
    if let (true, Status::Periodic, Some(p)) = (options.polish, steady.status, steady.period) {
        if steady.sticking {
            steady.orbit_error = Some("the final cycle sticks".into());
        } else {
            match periodic_orbit(model, omega, &steady.final_state, p, options) {
                Ok(orbit) => {
                    if let Some(amplitudes) = polished_amplitudes(model, omega, options, &orbit) {
                        steady.amplitudes = amplitudes;
                    }
                    steady.orbit = Some(Box::new(orbit));
                }
                Err(e) => steady.orbit_error = Some(e.to_string()),
            }
        }
    }
}

/// `max_t |u_k(t)|` of every coordinate over one cycle run from the polished `orbit` (its
/// `p` periods exactly, from its section); `None` when that run fails.
fn polished_amplitudes(
    model: &Model,
    omega: f64,
    options: &SimulationOptions,
    orbit: &PeriodicOrbit,
) -> Option<Vec<f64>> {
    let once = SimulationOptions {
        fixed_periods: Some(u64::from(orbit.periods)),
        max_period_multiplicity: options.max_period_multiplicity.max(orbit.periods),
        polish: false,
        record_trajectory: false,
        ..*options
    };
    let start = Start {
        state: orbit.state.clone(),
        time: orbit.time,
    };
    let mut engine = Engine::new(model, omega, &once).ok()?;
    let cycle = engine.run(&start, &once, &mut |_, _| false).ok()?;
    Some(cycle.amplitudes)
}
