//! The response of a structure to a non-periodic signal from rest: the method is documented
//! on [`respond`].

mod modal;
mod phase;
mod run;
mod signal;

use crate::flow::FlowError;
use crate::model::Model;
use nalgebra::DVector;
use serde::Serialize;
use thiserror::Error;

pub use signal::{Segment, Shape, Signal, SignalError, Sinusoid, MAX_SINUSOIDS};

/// A flight lasts at most this many time scales (`2π/max(|λ|, ν)`): the polynomial terms of
/// rigid modes and secular responses stay small over it.
pub const MAX_FLIGHT_SCALES: f64 = 16.0;

/// At most this many time scales (`2π/max(|λ|, ν)`, the fastest oscillation's period) in a
/// response: `T × max(|λ|, ν) / 2π ≤ 10⁷` oscillations.
pub const MAX_DURATION_SCALES: f64 = 1e7;

/// Default [`ResponseOptions::max_events`].
pub const DEFAULT_RESPONSE_MAX_EVENTS: u64 = 1_000_000;

/// At most this many uniform samples in [`respond_sampled`].
pub const MAX_RESPONSE_SAMPLES: u64 = 10_000_000;

/// How the signal forces the structure: `f(t) = d s(t) + v ṡ(t)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Excitation {
    /// `d`, one entry per degree of freedom: the force per unit `s`.
    pub on_signal: DVector<f64>,
    /// `v`, one entry per degree of freedom: the force per unit `ṡ`.
    pub on_rate: DVector<f64>,
}

impl Excitation {
    /// `f = d s + v ṡ`: for a base motion `s = u_g`, `d` the stiffness and `v` the damping
    /// tying each degree of freedom to the base.
    pub fn new(on_signal: DVector<f64>, on_rate: DVector<f64>) -> Excitation {
        Excitation { on_signal, on_rate }
    }

    /// A force `s(t)` on degree of freedom `dof` of `n`: `d = e_dof`, `v = 0`.
    ///
    /// # Panics
    /// If `dof ≥ n`.
    pub fn force(n: usize, dof: usize) -> Excitation {
        let mut d = DVector::zeros(n);
        d[dof] = 1.0;
        Excitation::new(d, DVector::zeros(n))
    }
}

/// What to compute.
#[derive(Debug, Clone, PartialEq)]
pub struct ResponseOptions {
    /// `T > 0`, s, at most [`MAX_DURATION_SCALES`] time scales.
    pub duration: f64,
    /// Times at which to report the state, each in `[0, T]`, in any order (reported in the
    /// order given).
    pub at: Vec<f64>,
    /// Contact times are resolved to this fraction of the time scale.
    pub root_tolerance: f64,
    /// The time scale the contact thresholds are relative to (the time tolerance, the chatter
    /// cut, the resting velocity `10⁻¹⁰ × 2π/scale × gap`, the grace after a graze or a
    /// release), s; `None`: `2π/max(|λ|, ν)`, the fastest oscillation's period. The periodic
    /// simulator's are relative to the forcing period `2π/ω`: the same scale gives the same
    /// decisions.
    pub time_scale: Option<f64>,
    /// At most this many impacts, grazes, sticks and releases: a run that needs more ends
    /// with [`ResponseError::EventCap`].
    pub max_events: u64,
}

impl ResponseOptions {
    /// Over `duration`, no states asked, the default tolerance and cap.
    pub fn over(duration: f64) -> ResponseOptions {
        ResponseOptions {
            duration,
            at: Vec::new(),
            root_tolerance: crate::DEFAULT_ROOT_TOLERANCE,
            time_scale: None,
            max_events: DEFAULT_RESPONSE_MAX_EVENTS,
        }
    }
}

/// Why there is no response.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ResponseError {
    /// An input out of range, named ([`SignalError::OutOfRange`]).
    #[error(transparent)]
    Input(#[from] SignalError),
    /// The modal flow of the model's matrices does not exist.
    #[error("flow: {0}")]
    Flow(#[from] FlowError),
    /// Pairs held on their stops at once whose directions are dependent (or more than the
    /// degrees of freedom): their contact forces are not determined.
    #[error("the held contact pairs {pairs:?} are dependent at t = {time}")]
    DependentHolds {
        /// The held pairs.
        pairs: Vec<usize>,
        /// When the set formed.
        time: f64,
    },
    /// The model has a compliant stop ([`Model::with_compliance`]): the signal response
    /// simulates rigid stops only, and refuses such a model before it runs.
    #[error("contact pair {pair} is compliant: the signal response simulates rigid stops only")]
    Compliant {
        /// The first compliant pair.
        pair: usize,
    },
    /// More impacts, grazes, sticks and releases than [`ResponseOptions::max_events`].
    #[error("more than {cap} impacts, grazes, sticks and releases by t = {time}")]
    EventCap {
        /// The cap.
        cap: u64,
        /// The time of the event past the cap.
        time: f64,
    },
}

/// One impact.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponseImpact {
    /// Its time, s.
    pub t: f64,
    /// The contact pair (index into the model's).
    pub pair: usize,
    /// `1`: the `+gap_plus` side, `2`: the `−gap_minus` side.
    pub side: u8,
    /// `ṙ⁻`, the relative velocity just before.
    pub relative_velocity_before: f64,
    /// The kinetic energy it took, `½u̇⁻ᵀMu̇⁻ − ½u̇⁺ᵀMu̇⁺` from the velocities before and
    /// after (`½μ(1 − e²)ṙ⁻²` up to rounding, never negative beyond it).
    pub energy_lost: f64,
}

/// A pair coming to rest on a stop (a stick) or leaving it (a release).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponseHold {
    /// Its time, s.
    pub t: f64,
    /// The contact pair.
    pub pair: usize,
    /// `1`: the `+gap_plus` side, `2`: the `−gap_minus` side.
    pub side: u8,
    /// `true`: a stick, `false`: a release.
    pub stick: bool,
    /// The kinetic energy the stick's plastic step took (after the impact, if any, at the
    /// same time): `0` for a release.
    pub energy_lost: f64,
}

/// The state at one time.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponseState {
    /// The time, s.
    pub t: f64,
    /// `u`.
    pub displacements: Vec<f64>,
    /// `u̇` (just after an impact at exactly `t`).
    pub velocities: Vec<f64>,
}

/// What the run amounts to over `[0, T]`.
///
/// The integrals (RMS, dashpot dissipation, work) are Gauss–Legendre quadratures of the
/// exact flights, eight nodes on pieces of each flight at most `1/(2 max(|λ|, ν))` long:
/// the integrands' fastest rate is at most `2 max(|λ|, ν)`, so each piece's rule errs by
/// about `10⁻²³` of its length times the integrand's size, rounding-level.
///
/// The peaks are the largest `|u_j|` among the flights' ends, the quadrature nodes and the
/// zeros of `u̇_j` bracketed between consecutive ones (a sign change of the exact `u̇_j`,
/// solved by the Illinois method to rounding): the exact maximum, unless `u̇_j` has two zeros
/// between consecutive points (at most `0.092/max(|λ|, ν)` apart), where the maximum missed
/// exceeds the points' by at most `sup|ü_j| δ²/4` (`δ` the two zeros' distance). A
/// branch-and-bound on derivative bounds would be certified, but costs a bisection down to
/// the tolerance wherever the response is at rounding level (from rest).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ResponseSummary {
    /// Impacts.
    pub impacts: u64,
    /// Grazes (touches without an approach, stepped past).
    pub grazes: u64,
    /// Sticks (a pair coming to rest on its stop).
    pub sticks: u64,
    /// Releases (a held pair leaving its stop).
    pub releases: u64,
    /// Flights (between segment boundaries, events and the flight cap).
    pub flights: u64,
    /// Per coordinate, `√(∫₀ᵀ u_j² dt / T)`.
    pub rms: Vec<f64>,
    /// Per coordinate, `max |u_j|` over `[0, T]`.
    pub peak: Vec<f64>,
    /// `∫₀ᵀ u̇ᵀ C u̇ dt`.
    pub dissipated_by_dashpots: f64,
    /// `Σ` of the impacts' and the sticks' `energy_lost`.
    pub dissipated_by_impacts: f64,
    /// `∫₀ᵀ f(t)ᵀ u̇ dt`.
    pub work: f64,
    /// `E(T) = ½u̇ᵀMu̇ + ½uᵀKu` at `T` (`E(0) = 0`: the run starts at rest).
    pub final_energy: f64,
}

impl ResponseSummary {
    /// `work − E(T) − dissipated`: zero up to the quadratures' and the contact times'
    /// accuracy.
    pub fn energy_imbalance(&self) -> f64 {
        self.work - self.final_energy - self.dissipated_by_dashpots - self.dissipated_by_impacts
    }
}

/// The response.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Response {
    /// `T`, s.
    pub duration: f64,
    /// The time scale the contact thresholds are relative to
    /// ([`ResponseOptions::time_scale`]; by default `2π/max(|λ|, ν)`, or `T` when that is
    /// longer), s.
    pub time_scale: f64,
    /// Every impact, in time order.
    pub impacts: Vec<ResponseImpact>,
    /// Every stick and release, in time order.
    pub holds: Vec<ResponseHold>,
    /// The states at [`ResponseOptions::at`], in its order.
    pub states: Vec<ResponseState>,
    /// The state at `T`.
    pub final_state: ResponseState,
    /// The summary.
    pub summary: ResponseSummary,
}

/// A uniform sample of [`respond_sampled`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledState<'a> {
    /// The time `jT/N`, s.
    pub t: f64,
    /// `u`.
    pub displacements: &'a [f64],
    /// `u̇` (just after an impact at exactly `t`).
    pub velocities: &'a [f64],
}

/// The response of `model`'s structure to `excitation` by `signal`, from rest at `t = 0`.
///
/// The response of a model to a non-periodic signal, from rest at `t = 0` over a duration
/// `T`: exact between events, every impact found with the event search's guarantee.
///
/// The structure is the model's (its mass, damping and stiffness matrices and its contact
/// pairs with their gaps, sides and restitution; free bodies held by stops fly as the
/// periodic flow flies them, as rigid modes); its own periodic forcing is not applied.
/// The forcing is `f(t) = d s(t) + v ṡ(t)` ([`Excitation`]): a base motion `s = u_g(t)`
/// acting through springs (`d`, the stiffness to the base) and dashpots (`v`, the damping to
/// the base), or a force signal on one body (`d = e_body`, `v = 0`). The scalar `s(t)`
/// ([`Signal`]) is made of segments on which it is affine or a finite sum of sinusoids
/// (sampled records interpolated piecewise linearly, tone bursts, stepped sweeps), zero
/// after the last.
///
/// **The flow.** On each segment the forcing is a polynomial of degree one or a sum of
/// exponentials, so each modal coordinate is a finite sum of (polynomial × exponential) terms
/// in closed form, resonance-safe: a sinusoid at (or near) a natural frequency, or at `ν = 0`,
/// gives the secular or limit particular solution, and a rigid mode under an affine force the
/// cubic of a free body (see `modal`). Segment boundaries are events: a flight ends there and
/// the next starts from the state reached, under the next segment's forcing. A flight also
/// ends after [`MAX_FLIGHT_SCALES`] time scales, which bounds the growth of its polynomial
/// terms (the state is carried exactly across).
///
/// **Contacts.** Each pair's relative displacement over a flight is such a sum
/// ([`crate::expsum::ExpSum`]), and its first exit from `[−gap_minus, gap_plus]` is found by
/// [`ExpSum::first_exit`](crate::expsum::ExpSum::first_exit): intervals are discarded only
/// on rigorous derivative bounds, so no impact between steps is missed, however close two
/// crossings are; the crossing is polished to the time tolerance
/// ([`ResponseOptions::root_tolerance`] of the time scale). The earliest contact of all
/// pairs ends the flight (ties to the lower pair index). An approach faster than the
/// velocities' rounding (relative to the larger of their size and the positions' times the
/// fastest rate, so that a body at rest on a stop sets no scale) is an impact: Newton's
/// restitution `ṙ⁺ = −e ṙ⁻` along the contact direction, momentum kept
/// ([`Model::apply_impact`], the periodic engine's contact law). A slower touch is a graze,
/// stepped past. The thresholds are the periodic engine's, with the time scale
/// `2π/max(|λ|, ν)` for its period ([`ResponseOptions::time_scale`]).
///
/// **Sticking.** A pair that comes to rest on its stop (restitution 0, or a rebound slower
/// than the resting velocity while the stop pushes), or whose chatter would end within
/// `10⁻⁵` of the time scale, sticks, as in the periodic engine: a plastic step sets its
/// relative velocity to zero, and the structure then moves on the constrained flow with the
/// held pairs' relative displacements fixed (`phase`), exact in closed form as the free flow
/// is, the signal projected onto it. Each held pair's contact force is a sum of terms over a
/// flight too, searched for its first zero (the release); the other pairs are watched for
/// contact in the constrained flow with the same guarantee, and their impacts keep the held
/// pairs on their stops. Held directions that are dependent end the run
/// ([`ResponseError::DependentHolds`]).
///
/// **Output.** Every impact (time, pair, side, `ṙ⁻`, the kinetic energy it took), every stick
/// and release, the state at requested times, and a summary: per-coordinate RMS and peak of
/// the displacement over `[0, T]`, the energy dissipated by the dashpots and by the impacts
/// and sticks, the work done by the forcing and the final energy, so that
/// `work = E(T) + dissipated` can be checked (the held stops do no work: `D u̇ = 0`;
/// [`ResponseSummary`] says how each is computed). Uniform samples are streamed to a
/// callback ([`respond_sampled`]).
///
/// # Errors
/// [`ResponseError::Input`] naming the field (`excitation.on_signal`, `excitation.on_rate`
/// and their entries, `duration`, `at[i]`, `root_tolerance`, `time_scale`),
/// [`ResponseError::Flow`], [`ResponseError::DependentHolds`],
/// [`ResponseError::EventCap`], and [`ResponseError::Compliant`] for a model with a compliant
/// stop.
pub fn respond(
    model: &Model,
    excitation: &Excitation,
    signal: &Signal,
    options: &ResponseOptions,
) -> Result<Response, ResponseError> {
    run::run(model, excitation, signal, options, None)
}

/// [`respond`], streaming the states at the `samples + 1` uniform times `t_j = jT/N`
/// (`N = samples`, `j = 0..=N`) to `sink` in time order, as the run reaches them.
///
/// # Errors
/// As [`respond`], and [`ResponseError::Input`] naming `samples` (in `1..=`[`MAX_RESPONSE_SAMPLES`]).
pub fn respond_sampled(
    model: &Model,
    excitation: &Excitation,
    signal: &Signal,
    options: &ResponseOptions,
    samples: u64,
    sink: &mut dyn FnMut(SampledState<'_>),
) -> Result<Response, ResponseError> {
    signal::check(
        || "samples".into(),
        samples as f64,
        (1..=MAX_RESPONSE_SAMPLES).contains(&samples),
        "in 1..=10000000",
    )?;
    run::run(model, excitation, signal, options, Some((samples, sink)))
}
