//! The simulator's own Newton: periodic orbits as fixed points of the stroboscopic map, with
//! its exact Jacobian and the Floquet multipliers.
//!
//! `P(y)`: the state after `p` forcing periods from state `y` at a section (a fixed forcing
//! phase). Its Jacobian `DP` is the tangent flow along the run, with the simulator's own
//! numerics: the product of each flight's homogeneous propagator `e^{Aτ}`
//! ([`LinearFlow::propagator`](crate::flow::LinearFlow::propagator)) and, at each impact, the
//! saltation matrix `S = Ĝ + (f⁺ − Ĝ f⁻) h_xᵀ / (h_x · f⁻)` (contact function
//! `h = r ∓ Δ`, `Ĝ` the identity on positions and the restitution map on velocities, `f` the
//! vector field with the forcing at the impact). `det S = e²`, so
//! `det DP = e^{2n} exp(tr A · pT)` over `n` impacts. A run that sticks has no such Jacobian
//! (the reduced flow is not a smooth map of the start state): [`NewtonError::Sticking`].
//!
//! Newton `y ← y − (DP − I)⁻¹ (P(y) − y)` converges quadratically from a good guess to the
//! orbit whatever its stability; the eigenvalues of `DP` there are the Floquet multipliers.
//!
//! With free bodies (rigid modes `R` of the flow) the propagator carries their rigid block and
//! the saltation matrices their share of each impact, so `DP` is exact for them too. A rigid
//! translation `(R a, 0)` that no impact of the cycle involves is mapped onto itself (the
//! flight moves positions by velocities only), so such orbits are not isolated: they form a
//! family with a multiplier exactly 1, and `DP − I` is singular by construction. Newton checks
//! `(DP − I) (R, 0)` first and reports that case as [`NewtonError::Family`] instead of an
//! ill-conditioned solve.

use crate::engine::{
    check_inputs, Engine, SimulationError, SimulationOptions, Start, TangentContact,
};
pub use crate::engine::{ContactPhase, PeriodicOrbit};
use crate::flow::{eigenvalues, FlowError};
use crate::model::Model;
use nalgebra::{DMatrix, DVector};
use thiserror::Error;

/// Newton's iterations are capped at this: from a guess within the basin of quadratic
/// convergence it takes a handful (measured: 2–4 from a periodic run's final state or an
/// analytic orbit); more means the guess was too far.
pub const MAX_NEWTON_ITERATIONS: u32 = 30;

/// The residual `|P(y) − y|`, relative to `max(|y|, gap)`, at which Newton stops, in units of
/// [`SimulationOptions::root_tolerance`]: contact times are resolved to `root_tolerance × T`,
/// so the map itself is known to about that relative accuracy.
pub const NEWTON_TOLERANCE_FACTOR: f64 = 1.0;

/// A residual that stops decreasing (a step that does not halve it) within this factor of the
/// tolerance is the rounding floor of the map (reached early on strongly unstable orbits, whose
/// map amplifies rounding by their largest multiplier): Newton has converged as far as the map
/// allows. Measured floors: `1e-16`–`1e-13` on the paper units (multipliers up to ~300).
pub const NEWTON_FLOOR_FACTOR: f64 = 1e3;

/// The stroboscopic map at one state, with its Jacobian.
#[derive(Debug, Clone, PartialEq)]
pub struct StroboscopicMap {
    /// `P(y)`: the state after the periods.
    pub state: DVector<f64>,
    /// `DP = ∂P/∂y`: flight propagators and impact saltation matrices along the run.
    pub jacobian: DMatrix<f64>,
    /// The impacts in time order: `+1` side 1, `−1` side 2.
    pub impact_sides: Vec<i8>,
    /// The contact pair of each impact.
    pub impact_pairs: Vec<usize>,
    /// The time of each impact after the section.
    pub impact_times: Vec<f64>,
    /// The compliant stops' contact phases over the run, in time order of their entries,
    /// entry and exit as times after the section ([`ContactPhase`]); empty for a model of
    /// rigid stops.
    pub contacts: Vec<ContactPhase>,
}

/// Why Newton on the stroboscopic map found no orbit.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NewtonError {
    /// The inputs, the flow or the run failed.
    #[error("simulation: {0}")]
    Simulation(#[from] SimulationError),
    /// Zero periods asked for.
    #[error("the cycle must span at least one period")]
    Periods,
    /// The run sticks (a plastic impact, or chatter ending on a stop), at this time after the
    /// section: the stroboscopic map has no saltation-matrix Jacobian there.
    #[error("the run sticks at t = {0} after the section: no smooth stroboscopic map")]
    Sticking(f64),
    /// An iterate's impact sequence (or its sequence of compliant contacts' pairs and sides)
    /// differs from the first iterate's: the guess was on the wrong side of a grazing. The
    /// sides listed are the impacts'.
    #[error("iteration {iteration}: the impact sequence changed from {first:?} to {now:?}")]
    SignatureChanged {
        /// The iteration where it changed.
        iteration: u32,
        /// Sides of the first iterate's impacts.
        first: Vec<i8>,
        /// Sides of this iterate's impacts.
        now: Vec<i8>,
    },
    /// `DP − I` is singular (a multiplier at 1: a fold, or a family of orbits).
    #[error("DP − I is singular at iteration {0}")]
    Singular(u32),
    /// No convergence within [`MAX_NEWTON_ITERATIONS`] (or a non-finite iterate).
    #[error("no convergence after {iterations} iterations: residual {residual:e}")]
    NoConvergence {
        /// Iterations taken.
        iterations: u32,
        /// The last residual.
        residual: f64,
    },
    /// The model has rigid modes (free bodies) that the cycle's impacts leave untouched
    /// (a cycle without impacts, or a free body no impact reaches): a rigid translation of
    /// such a body maps every periodic orbit onto another one, so the orbits form a family
    /// (a Floquet multiplier exactly 1 with no isolated fixed point) and `DP − I` is singular
    /// by construction rather than by a fold. This many independent rigid translations are
    /// neutral.
    #[error(
        "the cycle leaves {neutral} rigid mode(s) untouched by impacts: its periodic orbits \
         form a family (a Floquet multiplier exactly 1), no isolated orbit to polish"
    )]
    Family {
        /// Rigid translations `(δu, 0) = (R a, 0)` with `DP (R a, 0) = (R a, 0)`.
        neutral: usize,
    },
    /// The eigenvalues of `DP` did not converge.
    #[error("multipliers: {0}")]
    Eigenvalues(#[from] FlowError),
}

/// A rigid translation whose image under `DP − I` is at most this fraction of
/// `max(1, |DP|)` is neutral ([`NewtonError::Family`]): a translation untouched by any impact
/// is mapped onto itself to rounding (a few `ε`), while an impact that involves it changes it
/// by a saltation term of the order of the motion's own scales.
pub const NEUTRAL_TRANSLATION: f64 = 1e-9;

/// The number of rigid translations `(R a, 0)` that `jacobian` (`DP`) keeps fixed to
/// [`NEUTRAL_TRANSLATION`]: the singular values of `(DP − I) [R; 0]` that small.
fn neutral_translations(shapes: &DMatrix<f64>, jacobian: &DMatrix<f64>) -> usize {
    let (n, r) = (shapes.nrows(), shapes.ncols());
    let mut translations = DMatrix::zeros(2 * n, r);
    translations.view_mut((0, 0), (n, r)).copy_from(shapes);
    let image = jacobian * &translations - &translations;
    let scale = jacobian.amax().max(1.0);
    image
        .svd(false, false)
        .singular_values
        .iter()
        .filter(|&&s| s <= NEUTRAL_TRANSLATION * scale)
        .count()
}

/// `model` with its forcing advanced by `time` (`f(t) → f(t + time)`), so that a section at
/// the forcing phase `ω·time` becomes the section `t = 0`: the fundamental's amplitudes
/// rotated by `ω·time`, each higher harmonic's by `kω·time`. `time = 0` returns an exact copy.
pub(crate) fn shifted(model: &Model, omega: f64, time: f64) -> Model {
    let mut out = model.clone();
    if time != 0.0 {
        let (sin, cos) = crate::trig::sin_cos(omega * time);
        out.forcing_cos = &model.forcing_cos * cos + &model.forcing_sin * sin;
        out.forcing_sin = &model.forcing_sin * cos - &model.forcing_cos * sin;
        for (shifted, h) in out.harmonics.iter_mut().zip(&model.harmonics) {
            let (sin, cos) = crate::trig::sin_cos(h.order as f64 * omega * time);
            shifted.cos = &h.cos * cos + &h.sin * sin;
            shifted.sin = &h.sin * cos - &h.cos * sin;
        }
    }
    out
}

/// What every Newton iterate must keep of the first: its impacts' pairs and sides, and its
/// compliant contacts' pairs and sides, in time order.
type Signature = (Vec<usize>, Vec<i8>, Vec<(usize, i8)>);

/// A solver for the map at the section of `start`'s phase.
fn prepare(
    model: &Model,
    omega: f64,
    start: &Start,
    periods: u32,
    options: &SimulationOptions,
) -> Result<(Model, f64), NewtonError> {
    check_inputs(model, omega, start, options)?;
    if periods == 0 {
        return Err(NewtonError::Periods);
    }
    let phase = start.time.rem_euclid(std::f64::consts::TAU / omega);
    Ok((shifted(model, omega, phase), phase))
}

fn map_at(
    engine: &mut Engine<'_>,
    y: &DVector<f64>,
    periods: u32,
) -> Result<StroboscopicMap, NewtonError> {
    let (state, tangent) = engine.tangent_run(y, periods)?;
    if let Some(t) = tangent.sticking {
        return Err(NewtonError::Sticking(t));
    }
    let cycle = periods as f64 * engine.period();
    Ok(StroboscopicMap {
        state,
        jacobian: tangent.jacobian,
        impact_sides: tangent.impacts.iter().map(|i| i.1).collect(),
        impact_pairs: tangent.impacts.iter().map(|i| i.0).collect(),
        impact_times: tangent.impacts.iter().map(|i| i.2).collect(),
        contacts: map_contacts(&tangent.contacts, cycle),
    })
}

/// The tangent run's contacts as the map reports them: a contact pressed at the section
/// enters at `0`, one still pressed at the end exits at `cycle`; in time order of entries.
fn map_contacts(contacts: &[TangentContact], cycle: f64) -> Vec<ContactPhase> {
    let mut out: Vec<ContactPhase> = contacts
        .iter()
        .map(|c| ContactPhase {
            pair: c.pair,
            side: c.side,
            entry: c.entry.unwrap_or(0.0),
            exit: c.exit.unwrap_or(cycle),
        })
        .collect();
    out.sort_by(|a, b| a.entry.total_cmp(&b.entry).then(a.pair.cmp(&b.pair)));
    out
}

/// A cycle's contact phases as fractions of the cycle: a contact through the section (one
/// entering at `0` and the same pair and side leaving at the cycle's end) is one contact
/// whose exit is below its entry.
fn orbit_contacts(contacts: &[ContactPhase], cycle: f64) -> Vec<ContactPhase> {
    let mut through: Vec<ContactPhase> = Vec::new();
    let mut out: Vec<ContactPhase> = Vec::new();
    for c in contacts {
        if c.entry == 0.0 && c.exit < cycle {
            through.push(*c);
        }
    }
    for c in contacts {
        if c.entry == 0.0 && c.exit < cycle {
            continue;
        }
        let exit = if c.exit >= cycle {
            match through
                .iter()
                .position(|t| t.pair == c.pair && t.side == c.side)
            {
                Some(at) => through.remove(at).exit,
                None => cycle,
            }
        } else {
            c.exit
        };
        out.push(ContactPhase {
            entry: (c.entry / cycle).rem_euclid(1.0),
            exit: (exit / cycle).rem_euclid(1.0),
            ..*c
        });
    }
    // A contact pressed at the section whose end the cycle does not reach again.
    out.extend(through.into_iter().map(|c| ContactPhase {
        entry: 0.0,
        exit: (c.exit / cycle).rem_euclid(1.0),
        ..c
    }));
    out
}

/// The stroboscopic map `P` over `periods` forcing periods from `start` (its time fixes the
/// section's forcing phase), with its exact Jacobian.
///
/// # Errors
/// [`NewtonError::Simulation`] for inputs [`crate::simulate()`] refuses or a failed run,
/// [`NewtonError::Periods`] for zero periods, and [`NewtonError::Sticking`] when the run
/// sticks.
pub fn stroboscopic_map(
    model: &Model,
    omega: f64,
    start: &Start,
    periods: u32,
    options: &SimulationOptions,
) -> Result<StroboscopicMap, NewtonError> {
    let (model, _) = prepare(model, omega, start, periods, options)?;
    let mut engine = Engine::new(&model, omega, options)?;
    map_at(&mut engine, &start.state, periods)
}

/// The `periods`-period orbit through the section at `guess`'s forcing phase, by Newton
/// `y ← y − (DP − I)⁻¹ (P(y) − y)` from `guess`, until the residual `|P(y) − y|` is within
/// [`NEWTON_TOLERANCE_FACTOR`] × [`SimulationOptions::root_tolerance`] of `max(|y|, gap)` (or
/// stops decreasing within [`NEWTON_FLOOR_FACTOR`] of that: the map's rounding floor). Every
/// iterate must keep the first iterate's impact sequence.
///
/// # Errors
/// As [`stroboscopic_map`] at any iterate; [`NewtonError::SignatureChanged`] when an iterate's
/// impact sequence differs from the first, [`NewtonError::Singular`] when `DP − I` cannot be
/// solved, [`NewtonError::NoConvergence`] after [`MAX_NEWTON_ITERATIONS`] steps or at a
/// non-finite iterate, [`NewtonError::Eigenvalues`] when the multipliers do not converge,
/// and [`NewtonError::Family`] when the model has a rigid mode that the cycle's impacts leave
/// untouched (a free body on a cycle without impacts): its orbits form a family, none
/// isolated.
pub fn periodic_orbit(
    model: &Model,
    omega: f64,
    guess: &Start,
    periods: u32,
    options: &SimulationOptions,
) -> Result<PeriodicOrbit, NewtonError> {
    let (shifted_model, phase) = prepare(model, omega, guess, periods, options)?;
    let mut engine = Engine::new(&shifted_model, omega, options)?;
    let gap = engine.scale;
    let tolerance = NEWTON_TOLERANCE_FACTOR * options.root_tolerance;
    let m = guess.state.len();
    let cycle = periods as f64 * std::f64::consts::TAU / omega;
    let mut y = guess.state.clone();
    let mut first: Option<Signature> = None;
    let mut residual = f64::INFINITY;
    let mut previous = f64::INFINITY;
    for iteration in 0..=MAX_NEWTON_ITERATIONS {
        let map = map_at(&mut engine, &y, periods)?;
        if let Some(shapes) = engine.rigid_shapes() {
            let neutral = neutral_translations(shapes, &map.jacobian);
            if neutral > 0 {
                return Err(NewtonError::Family { neutral });
            }
        }
        let contact_signature: Vec<(usize, i8)> =
            map.contacts.iter().map(|c| (c.pair, c.side)).collect();
        match &first {
            None => {
                first = Some((
                    map.impact_pairs.clone(),
                    map.impact_sides.clone(),
                    contact_signature,
                ))
            }
            Some((pairs, sides, contacts)) => {
                if *pairs != map.impact_pairs
                    || *sides != map.impact_sides
                    || *contacts != contact_signature
                {
                    return Err(NewtonError::SignatureChanged {
                        iteration,
                        first: sides.clone(),
                        now: map.impact_sides,
                    });
                }
            }
        }
        let step = &map.state - &y;
        residual = step.norm() / y.norm().max(gap);
        if !residual.is_finite() {
            break;
        }
        let stalled = residual > 0.5 * previous && residual <= NEWTON_FLOOR_FACTOR * tolerance;
        if residual <= tolerance || stalled {
            let floquet_multipliers = eigenvalues(&map.jacobian)?;
            return Ok(PeriodicOrbit {
                state: y,
                time: guess.time,
                phase,
                periods,
                impact_sides: map.impact_sides,
                impact_phases: map.impact_times.iter().map(|t| t / cycle).collect(),
                contact_phases: orbit_contacts(&map.contacts, cycle),
                floquet_multipliers,
                iterations: iteration,
                residual,
            });
        }
        if iteration == MAX_NEWTON_ITERATIONS {
            break;
        }
        previous = residual;
        let a = map.jacobian - DMatrix::<f64>::identity(m, m);
        let delta = a
            .lu()
            .solve(&step)
            .ok_or(NewtonError::Singular(iteration))?;
        // y − (DP − I)⁻¹ (P(y) − y).
        y -= delta;
        if y.iter().any(|v| !v.is_finite()) {
            break;
        }
    }
    Err(NewtonError::NoConvergence {
        iterations: MAX_NEWTON_ITERATIONS,
        residual,
    })
}
