//! The front end: [`simulate()`] and [`simulate_watched()`] run the event loop on a model from
//! a start, then, for a periodic motion, polish its final cycle with the simulator's own Newton
//! ([`crate::newton`]). The loop itself (flights, contacts, sticking, the stopping rules) is the
//! crate's engine; its options and results are re-exported here.

use crate::engine::{check_inputs, Engine};
pub use crate::engine::{
    ImpactRecord, RowKind, SimulationError, SimulationOptions, Start, Status, SteadyState, Stop,
    CONSERVATIVE_MAX_PERIODS, DEFAULT_MAX_EVENTS, DEFAULT_MAX_OSCILLATIONS, DEFAULT_MAX_PERIODS,
    DEFAULT_MAX_PERIOD_MULTIPLICITY, DEFAULT_PERIODICITY_TOLERANCE, DEFAULT_ROOT_TOLERANCE,
    EVENT_STORM, MIN_OSCILLATION_PERIODS, SAMPLES_PER_PERIOD,
};
use crate::model::Model;
use crate::newton::periodic_orbit;
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
    if let (true, Status::Periodic, Some(p)) = (options.polish, steady.status, steady.period) {
        if steady.sticking {
            steady.orbit_error = Some("the final cycle sticks".into());
        } else {
            match periodic_orbit(model, omega, &steady.final_state, p, options) {
                Ok(orbit) => steady.orbit = Some(Box::new(orbit)),
                Err(e) => steady.orbit_error = Some(e.to_string()),
            }
        }
    }
    Ok(steady)
}
