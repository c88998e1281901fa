//! Exact event-driven simulation of linear structures with impacting contact pairs.
//!
//! Between events the motion is the closed-form modal flow of `M ü + C u̇ + K u = f(t)`
//! ([`LinearFlow`]); each coordinate is a finite sum of exponential terms ([`ExpSum`]) whose first
//! crossing of a stop is found with a guarantee (derivative bounds exclude intervals; no
//! sampling can skip a grazing double crossing) and polished by Newton. Impacts apply Newton's
//! restitution along the contact direction, conserving momentum. Accumulating impacts (chatter)
//! end in sticking: the pair then moves as one body, again in closed form, until the contact
//! force would pull. The steady state is read off the stroboscopic map at `t = kT`, with time
//! carried modulo the period so the forcing phase stays exact over any number of periods.
//!
//! Periodic orbits are also found directly, by Newton on the stroboscopic map with its exact
//! Jacobian (flight propagators and impact saltation matrices), whatever their stability
//! ([`periodic_orbit`]); a periodic run is polished that way at its end ([`SteadyState::orbit`]).
//!
//! The same tangent flow, extended through sticking and re-orthonormalised once per period,
//! gives the Lyapunov spectrum ([`lyapunov_exponents`]); a traced run of the same engine
//! samples a stretch of motion exactly, events included ([`sample_trajectory`]).
//!
//! Chains of impacting cells ([`Model::chain`], the metamaterial) are models with one contact
//! pair per cell; any pairs may stick, chatter or fly at the same time, each watched with the
//! same guarantee ([`simulate()`]).
//!
//! Free bodies (a mass held by no spring or dashpot, such as an impact damper's ball in its
//! clearance) are rigid modes of the flow: they fly exactly as rigid bodies, their
//! polynomial drift searched with the same guarantee, and their tangent flow enters Newton
//! and the Lyapunov spectrum. A steady state in which no impact reaches them is a family
//! ([`SteadyState::family`], [`NewtonError::Family`]).
//!
//! The forcing may carry higher harmonics of the fundamental, `f(t) = Σ_k (f_c,k cos kωt +
//! f_s,k sin kωt)` with integer orders `k ≥ 2` ([`Model::with_harmonics`]): the period stays
//! `2π/ω`, each harmonic adds its exact particular solution at `kω` to the flow (secular
//! where `kω` meets an undamped natural frequency), and the events, the tangent flow and the
//! stuck phases see it. A model without them runs exactly as before, bit for bit.
//!
//! A stop may be compliant instead of rigid ([`Model::with_compliance`], [`Compliance`]): a
//! Kelvin–Voigt spring `k_c` and dashpot `c_c` act along the pair's direction while it
//! penetrates the stop, from the entry (no velocity jump) until the penetration returns to
//! zero. Each contact phase is again an exact modal flow, of the structure with the pressed
//! pairs' springs and dashpots added (built once per set of pressed pairs), so a contact
//! costs the same however stiff: no time step resolves it. Its exit is searched with the
//! same guarantee as an impact, several pairs may be pressed at once and rigid pairs impact
//! meanwhile; the tangent flow crosses entries and exits with their saltation matrices, so
//! Newton, the Floquet multipliers and the Lyapunov spectrum see the contact phases. The
//! steady state reports them apart from the impacts ([`SteadyState::cycle_contacts`],
//! [`PeriodicOrbit::contact_phases`]); as `k_c → ∞` with the isolated pair's restitution
//! held ([`Compliance::matching`]) the motion tends to the rigid stop's. A rigid hold and a
//! compliant contact at once are not simulated
//! ([`SimulationError::HoldWithCompliantContact`]), and [`respond()`] refuses compliant
//! stops ([`ResponseError::Compliant`]).
//!
//! Only the effects a model has are simulated: no contact pairs, no event search; no damping
//! matrix, no damping terms, and the oscillating rates purely imaginary, as a conservative
//! system's are (the Schur form's rounding-level real parts removed).
//!
//! Beside the periodic forcing, the same structure responds to a non-periodic signal from
//! rest, `f(t) = d s(t) + v ṡ(t)` with `s` piecewise affine or a sum of sinusoids (a sampled
//! record, a tone burst, a stepped sweep): exact between segment boundaries and events,
//! every impact found with the same guarantee, sticking as above ([`respond()`]).
//!
//! Its sines and cosines are musl's, not the platform's (`trig`): the event core derives
//! its numerics on its own, apart from the analytic solver's.
//!
//! Every public item has one path, at the crate's root (`rattle_event_driven::Model`,
//! `rattle_event_driven::simulate`, …); the source is in private modules by job.
#![deny(missing_docs)]

mod engine;
mod expsum;
mod flow;
mod lyapunov;
mod model;
mod newton;
mod respond;
mod simulate;
#[cfg(any(test, feature = "fixtures"))]
pub mod test_models;
mod trajectory;
mod trig;

pub use expsum::{ExpSum, SearchStack, SharedPoints, Term, Tolerances};
pub use flow::{Flight, FlowError, Functional, LinearFlow};

pub use lyapunov::{
    lyapunov_after_steady_state, lyapunov_exponents, system_matrix, LyapunovError, LyapunovOptions,
    LyapunovSpectrum, Regime, BATCHES, DEFAULT_ALIGNMENT_PERIODS, DEFAULT_LYAPUNOV_PERIODS,
    MAX_BRIDGE_POINTS, UNCERTAINTY_FACTOR,
};
pub use model::{
    CellParameters, CellStops, Compliance, ContactPair, Harmonic, Model, ModelError, MAX_CELLS,
    MAX_CONTACT_RATE_RATIO, MAX_HARMONIC_ORDER,
};
pub use newton::{
    periodic_orbit, stroboscopic_map, ContactPhase, NewtonError, PeriodicOrbit, StroboscopicMap,
    MAX_NEWTON_ITERATIONS, NEUTRAL_TRANSLATION, NEWTON_FLOOR_FACTOR, NEWTON_TOLERANCE_FACTOR,
};
pub use respond::{
    respond, respond_sampled, Excitation, Response, ResponseError, ResponseHold, ResponseImpact,
    ResponseOptions, ResponseState, ResponseSummary, SampledState, Segment, Shape, Signal,
    SignalError, Sinusoid, DEFAULT_RESPONSE_MAX_EVENTS, MAX_DURATION_SCALES, MAX_FLIGHT_SCALES,
    MAX_RESPONSE_SAMPLES, MAX_SINUSOIDS,
};
pub use simulate::{
    simulate, simulate_watched, ContactRecord, ImpactRecord, SimulationError, SimulationOptions,
    Start, Status, SteadyState, Stop, CONSERVATIVE_MAX_PERIODS, DEFAULT_MAX_EVENTS,
    DEFAULT_MAX_OSCILLATIONS, DEFAULT_MAX_PERIODS, DEFAULT_MAX_PERIOD_MULTIPLICITY,
    DEFAULT_PERIODICITY_TOLERANCE, DEFAULT_ROOT_TOLERANCE, EVENT_STORM, MIN_OSCILLATION_PERIODS,
    SAMPLES_PER_PERIOD, UNSTABLE_MARGIN,
};
pub use trajectory::{
    final_cycle_trajectory, sample_trajectory, RowKind, Trajectory, TrajectoryError,
    TrajectoryImpact, TrajectoryOptions, TrajectoryRow, DEFAULT_SAMPLES_PER_PERIOD,
    MAX_TRAJECTORY_SAMPLES,
};
