//! How the two solvers relate at one frequency: the analytic **candidates** (the motions the
//! analytic solver says the unit can settle on), what the simulator does from rest and from
//! each viable orbit, and the **class** of the frequency.
//!
//! [`candidates`] is the one definition of "the analytic prediction": sweeps, maps and the
//! report all call it, and each names the [`Choice`] it makes among the candidates.
//! [`chain`] relates the two on a chain of cells, [`structure`] on a structure scene (through
//! the same seeded check on each solver's own model).

use crate::output::finite;
use crate::output::records::{
    multipliers, AnalyticCycleRecord, ConfirmationRecord, CrossCheckRecord, SimulatedCycleRecord,
};
use crate::scene::analytic::{
    analyse, orbits_of_signature, signature_orbit_state, AnalyticPoint, OrbitSearch,
};
use crate::scene::simulator::{
    model, run, start_on_orbit, Regime, SimulateError, SimulatedPoint, START_PERTURBATION,
};
use crate::scene::{phase, Scene};
use nalgebra::{DVector, Vector4};
use rattle_analytic::{solve_signature, Orbit, OrbitError, Signature, SignatureOrbit};
use rattle_event_driven::{periodic_orbit, PeriodicOrbit, SimulationOptions, Start, Status};
use thiserror::Error;

pub mod chain;
mod contact;
pub mod structure;

/// Two results agree when they differ by less than this, relatively: 1000 × the simulator's
/// default periodicity tolerance (1e-9), because a motion that repeats to `ε` can still be
/// `ε / (1 − |μ|)` from its orbit (largest Floquet multiplier `μ`); on the paper's scenes the
/// agreeing points differ by at most 1.8e-7.
pub const MATCH_TOLERANCE: f64 = 1e-6;

/// A steady motion the analytic solver offers at one frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Candidate {
    /// Which motion.
    pub motion: Motion,
    /// Its transmittance, dB.
    pub transmittance_db: f64,
    /// Its outer amplitude `X_o`, m.
    pub outer_amplitude: f64,
    /// Whether nearby motions converge to it: a stable viable orbit always; the linear motion
    /// only with damping (undamped, its free transients never decay).
    pub attracting: bool,
}

/// What a candidate is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Motion {
    /// The linear steady state, clear of the stops.
    Linear,
    /// A stable, viable two-impact orbit, by its branch number.
    Orbit {
        /// Branch number in [`AnalyticPoint::orbits`].
        branch: usize,
    },
}

/// The candidates at `point` of `scene`: every stable viable orbit of `point` (in branch
/// order), then the linear motion when it is bounded and stays clear of the stops (always,
/// without stops).
pub fn candidates(scene: &Scene, point: &AnalyticPoint) -> Vec<Candidate> {
    let mut out: Vec<Candidate> = point
        .stable_viable_orbits()
        .map(|(branch, o)| Candidate {
            motion: Motion::Orbit { branch },
            transmittance_db: o.transmittance_db,
            outer_amplitude: o.outer_amplitude,
            attracting: true,
        })
        .collect();
    let linear = &point.linear;
    // Of a chain: clear of every pair's stops.
    let clear = !point.touches_stops.unwrap_or(false);
    if clear && !linear.unbounded {
        out.push(Candidate {
            motion: Motion::Linear,
            transmittance_db: linear.transmittance_db,
            outer_amplitude: linear.outer_amplitude,
            attracting: scene.is_damped(),
        });
    }
    out
}

/// Which candidate a prediction takes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Choice {
    /// The paper's method (its §3): a stable viable orbit where there is one (the first),
    /// else the linear motion where it stays clear of the stops, damped or not.
    PaperMethod,
    /// The largest transmittance among the attracting candidates, so that a predicted
    /// attenuation holds whichever of them the unit settles on (the maps).
    LargestAttracting,
}

/// The transmittance predicted by `choice` among `candidates`; `None` when there is nothing
/// to choose.
pub fn predicted_transmittance(candidates: &[Candidate], choice: Choice) -> Option<f64> {
    match choice {
        Choice::PaperMethod => candidates
            .iter()
            .find(|c| matches!(c.motion, Motion::Orbit { .. }))
            .or_else(|| candidates.iter().find(|c| c.motion == Motion::Linear))
            .map(|c| c.transmittance_db),
        Choice::LargestAttracting => candidates
            .iter()
            .filter(|c| c.attracting)
            .map(|c| c.transmittance_db)
            .reduce(f64::max),
    }
}

/// How the two solvers relate at one frequency.
#[derive(Debug, Clone, PartialEq)]
pub enum Class {
    /// The simulator from rest settles on an attracting candidate (a two-impact orbit or the
    /// linear motion clear of the stops).
    Agreement,
    /// An attracting candidate exists and holds when started on it, but from rest the
    /// simulator goes elsewhere.
    Coexistence,
    /// No attracting candidate; the simulator shows another regime, named.
    Beyond(String),
    /// Anything else, e.g. a "stable" orbit the simulator leaves: explained.
    Contradiction(String),
}

impl Class {
    /// Every class's name, in the order of the summaries.
    pub const NAMES: [&'static str; 4] = ["agreement", "coexistence", "beyond", "contradiction"];

    /// The class's name in JSON and CSV.
    pub fn name(&self) -> &'static str {
        match self {
            Class::Agreement => "agreement",
            Class::Coexistence => "coexistence",
            Class::Beyond(_) => "beyond",
            Class::Contradiction(_) => "contradiction",
        }
    }

    /// Detail for `beyond` and `contradiction`, empty otherwise.
    pub fn detail(&self) -> &str {
        match self {
            Class::Beyond(d) | Class::Contradiction(d) => d,
            _ => "",
        }
    }
}

/// Differences between a simulated motion and an analytic orbit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Difference {
    /// `|X_o,sim − X_o| / X_o`.
    pub outer_amplitude: f64,
    /// `|x_sim(0⁻) − x(0⁻)| / |x(0⁻)|`, the state just before the side-1 impact.
    pub impact_state: f64,
    /// Distance of the base phases at the side-1 impact, radians in `[0, π]`.
    pub phase: f64,
}

impl Difference {
    /// The difference of a motion with outer amplitude `outer_amplitude`, state
    /// `state_before_side1` just before a side-1 impact and base phase `alpha` there, from
    /// `orbit`.
    pub fn between(
        state_before_side1: &Vector4<f64>,
        alpha: f64,
        outer_amplitude: f64,
        orbit: &Orbit,
    ) -> Difference {
        Difference {
            outer_amplitude: (outer_amplitude - orbit.outer_amplitude).abs()
                / orbit.outer_amplitude,
            impact_state: (state_before_side1 - orbit.state_before_impact).norm()
                / orbit.state_before_impact.norm(),
            phase: phase::distance(alpha, orbit.alpha),
        }
    }

    /// The largest of the relative differences (phase counted relative to π).
    pub fn largest(&self) -> f64 {
        self.outer_amplitude
            .max(self.impact_state)
            .max(self.phase / std::f64::consts::PI)
    }
}

/// Compares a simulated motion with an analytic orbit; `None` unless the simulation is a
/// two-impact motion (or converging to one).
pub fn difference(sim: &SimulatedPoint, orbit: &Orbit) -> Option<Difference> {
    let (state, alpha) = sim.side1_impact?;
    Some(Difference::between(
        &state,
        alpha,
        sim.outer_amplitude,
        orbit,
    ))
}

/// A viable analytic orbit and what the simulator did when started on it.
#[derive(Debug, Clone)]
pub struct Trial {
    /// Branch number of the orbit.
    pub branch: usize,
    /// The simulator's result.
    pub simulated: SimulatedPoint,
    /// Whether it stayed on the orbit (difference below [`MATCH_TOLERANCE`]).
    pub held: bool,
    /// The difference, if the simulation was a two-impact motion.
    pub difference: Option<Difference>,
}

/// Everything both solvers say at one frequency.
#[derive(Debug, Clone)]
pub struct ComparedPoint {
    /// The analytic picture (linear and symmetric orbits).
    pub analytic: AnalyticPoint,
    /// The candidates of [`candidates`].
    pub candidates: Vec<Candidate>,
    /// The simulator from rest.
    pub from_rest: SimulatedPoint,
    /// The simulator from each viable orbit.
    pub trials: Vec<Trial>,
    /// The largest relative difference of the from-rest motion from the analytic motion of its
    /// signature ([`CrossCheck::relative_difference`]).
    pub difference: Option<f64>,
    /// The verdict: the [`CrossCheck`]'s class, except that a stable viable two-impact orbit
    /// the simulator leaves is a contradiction, and a from-rest motion beyond exact comparison
    /// beside an attracting analytic candidate ([`ComparedPoint::coexisting`]) is a
    /// coexistence.
    pub class: Class,
    /// What the from-rest motion agrees with, in words (e.g. `++-- orbit over 1 period(s)`).
    pub matched: Option<String>,
    /// Whether the analytic prediction "a stable viable orbit exists" matches "the simulator
    /// holds an orbit started on it".
    pub prediction_confirmed: bool,
    /// Whether an attracting analytic candidate (a stable viable symmetric orbit that holds
    /// when started on it, or the damped linear motion clear of the stops) exists that the
    /// from-rest motion is not on: the unit has more than one attractor here.
    pub coexisting: bool,
    /// The from-rest motion beside the analytic orbit of its signature, whatever the signature.
    pub cross: CrossCheck,
}

/// A failure of either solver at one frequency.
#[derive(Debug, Error)]
pub enum CompareError {
    /// The analytic solver failed.
    #[error("analytic: {0}")]
    Analytic(#[from] OrbitError),
    /// The simulator failed.
    #[error("{0}")]
    Simulation(#[from] SimulateError),
}

/// Where the simulator is started at each frequency.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Starts {
    /// From rest only; the verdict then takes every stable viable orbit as held.
    Rest,
    /// From rest, and on every viable orbit (nudged by [`START_PERTURBATION`]).
    RestAndOrbits,
}

/// Both solvers at `omega`, the simulator started as `starts` says, and the verdict.
///
/// # Errors
/// The first failure of either solver.
pub fn compare(
    scene: &Scene,
    omega: f64,
    options: &SimulationOptions,
    starts: Starts,
) -> Result<ComparedPoint, CompareError> {
    let analytic = analyse(scene, omega, OrbitSearch::Symmetric)?;
    let candidates = candidates(scene, &analytic);
    let from_rest = run(scene, omega, &crate::scene::simulator::rest(scene), options)?;
    let mut trials = Vec::new();
    if starts == Starts::RestAndOrbits {
        for (branch, orbit) in analytic.orbits.iter().filter(|(_, o)| o.viable) {
            let start = start_on_orbit(scene, orbit, START_PERTURBATION);
            let simulated = run(scene, omega, &start, options)?;
            let difference = difference(&simulated, orbit);
            let held = difference.is_some_and(|d| d.largest() < MATCH_TOLERANCE);
            trials.push(Trial {
                branch: *branch,
                simulated,
                held,
                difference,
            });
        }
    }
    let cross = cross_check_simulated(scene, omega, from_rest.clone(), options, Confirm::Seeded)?;
    let left: Vec<usize> = trials
        .iter()
        .filter(|t| !t.held)
        .filter(|t| {
            analytic
                .orbits
                .iter()
                .any(|(b, o)| *b == t.branch && o.stable)
        })
        .map(|t| t.branch)
        .collect();
    let held_any = trials.iter().any(|t| t.held);
    let attracting_orbits = candidates
        .iter()
        .filter(|c| matches!(c.motion, Motion::Orbit { .. }))
        .count();
    let prediction_confirmed = starts == Starts::Rest || (attracting_orbits == 0) != held_any;
    // An attracting candidate the from-rest motion is not on (an orbit only if it holds when
    // started on it, where that was tried).
    let coexisting = candidates
        .iter()
        .filter(|c| c.attracting)
        .any(|c| match c.motion {
            Motion::Orbit { branch } => {
                let held =
                    starts == Starts::Rest || trials.iter().any(|t| t.branch == branch && t.held);
                let on_it = analytic
                    .orbits
                    .iter()
                    .find(|(b, _)| *b == branch)
                    .and_then(|(_, o)| difference(&from_rest, o))
                    .is_some_and(|d| d.largest() < MATCH_TOLERANCE);
                held && !on_it
            }
            Motion::Linear => {
                from_rest.regime != Regime::NoImpact
                    || (from_rest.outer_amplitude - c.outer_amplitude).abs()
                        >= MATCH_TOLERANCE * c.outer_amplitude.max(f64::MIN_POSITIVE)
            }
        });
    let class = if !left.is_empty() {
        Class::Contradiction(format!(
            "stable viable orbit (branch {left:?}) left by the simulator started on it"
        ))
    } else {
        match &cross.class {
            Class::Beyond(_) if coexisting => Class::Coexistence,
            other => other.clone(),
        }
    };
    let matched = (cross.class == Class::Agreement).then(|| match &cross.signature {
        Some(sig) => format!("{sig} orbit over {} period(s)", sig.period()),
        None => "linear motion clear of the stops".to_owned(),
    });
    Ok(ComparedPoint {
        analytic,
        candidates,
        from_rest,
        trials,
        difference: cross.relative_difference,
        class,
        matched,
        prediction_confirmed,
        coexisting,
        cross,
    })
}

/// A simulated periodic motion of any signature beside the analytic orbit of that signature.
#[derive(Debug, Clone)]
pub struct CrossCheck {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The simulator from rest (with its own Newton-polished cycle when periodic).
    pub simulated: SimulatedPoint,
    /// The canonical signature of the simulated cycle, when it is periodic and polished.
    pub signature: Option<Signature>,
    /// The analytic orbit of that signature, seeded from the simulated impact phases and solved
    /// by the analytic crate's own equations.
    pub analytic: Option<SignatureOrbit>,
    /// Why there is no analytic orbit, when the simulated cycle has one to look for.
    pub analytic_error: Option<String>,
    /// The verdict.
    pub class: Class,
    /// The largest of: the difference of the states at the simulator's section relative to
    /// the state's size, of the impact phases (fractions of the cycle), and of the base phase
    /// at the first impact over π.
    pub relative_difference: Option<f64>,
    /// The two solvers' Floquet multipliers matched one to one, closest pairs first
    /// ([`chain::matched_distance`]): the largest distance of a matched pair (a nearest match
    /// could pair two simulated multipliers with one analytic one and hide a missing one).
    pub multiplier_difference: Option<f64>,
    /// Every viable analytic orbit of the simulated signature (within the multi-start's scope,
    /// [`MULTI_START_IMPACTS`] and [`MULTI_START_PERIODS`]; beyond it the seeded orbit alone),
    /// and whether the simulator's own Newton confirms it when started on it (stable or not).
    pub confirmed_orbits: Vec<Confirmation>,
}

/// The analytic multi-start looks for every orbit of a signature with at most this many
/// impacts…
pub const MULTI_START_IMPACTS: usize = 4;
/// …over at most this many forcing periods (the scope in which it is measured to find every
/// viable orbit). Beyond it the search grows combinatorially (14 impacts: 85 s; 16 over two
/// periods: over 300 s), so [`cross_check`] confirms only the orbit seeded from the simulation.
pub const MULTI_START_PERIODS: u32 = 2;

/// A viable analytic orbit and the simulator's Newton started on it.
#[derive(Debug, Clone)]
pub struct Confirmation {
    /// The analytic orbit.
    pub orbit: SignatureOrbit,
    /// Whether Newton converged to a cycle with the same signature and a state within
    /// [`MATCH_TOLERANCE`] of the analytic one.
    pub confirmed: bool,
    /// The state difference at the start time, relative to the state's size.
    pub state_difference: Option<f64>,
    /// The two solvers' multipliers matched one to one ([`chain::matched_distance`]).
    pub multiplier_difference: Option<f64>,
    /// Why Newton failed, if it did.
    pub error: Option<String>,
}

/// The simulator's Newton started on `orbit` mid-way through its first flight.
fn confirm_orbit(
    scene: &Scene,
    omega: f64,
    orbit: &SignatureOrbit,
    options: &SimulationOptions,
) -> Confirmation {
    let cycle = orbit.period as f64 * std::f64::consts::TAU / omega;
    let first_flight = orbit.impact_phases.get(1).copied().unwrap_or(1.0);
    let t = 0.5 * first_flight * cycle;
    let x = signature_orbit_state(scene, orbit, t);
    let start = Start {
        state: DVector::from_column_slice(x.as_slice()),
        // Base phase ω t_sim = α + ω t.
        time: t + orbit.alpha / omega,
    };
    let mut out = Confirmation {
        orbit: orbit.clone(),
        confirmed: false,
        state_difference: None,
        multiplier_difference: None,
        error: None,
    };
    let newton = model(scene, omega)
        .map_err(|e| e.to_string())
        .and_then(|m| {
            periodic_orbit(&m, omega, &start, orbit.period, options).map_err(|e| e.to_string())
        });
    match newton {
        Ok(found) => {
            let same = Signature::from_cycle(&found.impact_sides, found.periods)
                .is_ok_and(|s| s == orbit.signature);
            let d = (0..4)
                .map(|i| (found.state[i] - x[i]).abs())
                .fold(0.0, f64::max)
                / x.norm().max(f64::MIN_POSITIVE);
            out.state_difference = Some(d);
            out.multiplier_difference = Some(chain::matched_distance(
                &found.floquet_multipliers,
                &orbit.floquet_multipliers,
            ));
            out.confirmed = same && d < MATCH_TOLERANCE;
        }
        Err(e) => out.error = Some(e),
    }
    out
}

/// Both solvers on any periodic motion at `omega`: the simulator from rest settles, polishes
/// its cycle by Newton on its own stroboscopic map and names its signature; the analytic crate
/// solves that signature from the simulated impact phases; the two are compared.
///
/// Classes: `agreement` (the analytic orbit is viable and stable and within
/// [`MATCH_TOLERANCE`]; or, without impacts, the linear motion); `beyond` (not periodic, no
/// dissipation, or sticking: outside exact comparison, with the reason); `contradiction`
/// (the analytic solver finds no orbit, or calls it non-viable or unstable, or it differs).
///
/// # Errors
/// A failure of the simulator.
pub fn cross_check(
    scene: &Scene,
    omega: f64,
    options: &SimulationOptions,
) -> Result<CrossCheck, CompareError> {
    let simulated = run(scene, omega, &crate::scene::simulator::rest(scene), options)?;
    cross_check_simulated(scene, omega, simulated, options, Confirm::Every)
}

/// Which viable analytic orbits of the simulated signature a cross-check confirms with the
/// simulator's own Newton.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Confirm {
    /// Every one the analytic multi-start finds (within [`MULTI_START_IMPACTS`] and
    /// [`MULTI_START_PERIODS`]; beyond, the seeded one): `rattle compare`.
    Every,
    /// Only the orbit seeded from the simulated phases: sweeps, where the multi-start at every
    /// frequency would cost up to two seconds a point.
    Seeded,
}

/// [`cross_check`] of a motion `simulated` from rest at `omega`, confirming `confirm` orbits.
///
/// # Errors
/// A failure of the analytic solver on the linear motion.
pub fn cross_check_simulated(
    scene: &Scene,
    omega: f64,
    simulated: SimulatedPoint,
    options: &SimulationOptions,
    confirm: Confirm,
) -> Result<CrossCheck, CompareError> {
    let mut check = CrossCheck {
        omega,
        signature: simulated.signature(),
        simulated,
        analytic: None,
        analytic_error: None,
        class: Class::Beyond(String::new()),
        relative_difference: None,
        multiplier_difference: None,
        confirmed_orbits: Vec::new(),
    };
    let steady = &check.simulated.steady;
    check.class = match (steady.status, steady.sticking, steady.orbit.as_deref()) {
        (_, true, _) => Class::Beyond("sticking: outside exact comparison".into()),
        (Status::NonPeriodic, _, _) => Class::Beyond("not periodic within the cap".into()),
        (Status::NoDissipation, _, _) => {
            Class::Beyond("no dissipation: transients never decay".into())
        }
        (Status::Periodic, _, _) if steady.cycle_impacts.is_empty() => {
            let point = analyse(scene, omega, OrbitSearch::Symmetric)?;
            let linear = candidates(scene, &point)
                .into_iter()
                .find(|c| c.motion == Motion::Linear);
            match linear {
                Some(c) => {
                    let d = (check.simulated.outer_amplitude - c.outer_amplitude).abs()
                        / c.outer_amplitude;
                    check.relative_difference = Some(d);
                    if d < MATCH_TOLERANCE {
                        Class::Agreement
                    } else {
                        Class::Contradiction(format!(
                            "periodic without impacts, {d:.1e} from the linear motion"
                        ))
                    }
                }
                None => Class::Contradiction(
                    "periodic without impacts, but the linear motion reaches the stops".into(),
                ),
            }
        }
        (Status::Periodic, _, None) => Class::Beyond(format!(
            "the simulator could not polish its cycle: {}",
            steady.orbit_error.as_deref().unwrap_or("unknown")
        )),
        (Status::Periodic, _, Some(orbit)) => {
            let orbit = orbit.clone();
            seeded_check(scene, omega, &orbit, options, confirm, &mut check)
        }
    };
    Ok(check)
}

/// The analytic orbit of the simulated cycle's signature and its differences; the class.
fn seeded_check(
    scene: &Scene,
    omega: f64,
    cycle: &PeriodicOrbit,
    options: &SimulationOptions,
    confirm: Confirm,
    check: &mut CrossCheck,
) -> Class {
    let Some(stops) = scene.stops_model() else {
        return Class::Beyond("no stops".into());
    };
    let signature = match Signature::from_cycle(&cycle.impact_sides, cycle.periods) {
        Ok(signature) => signature,
        // e.g. more impacts per cycle than a signature holds
        Err(e) => return Class::Beyond(format!("the simulated cycle has no signature: {e}")),
    };
    let n = cycle.impact_sides.len();
    let length = cycle.periods as f64 * std::f64::consts::TAU / omega;
    // The rotations of the simulated impacts that read as the canonical signature.
    let rotations: Vec<usize> = (0..n)
        .filter(|&k| (0..n).all(|j| cycle.impact_sides[(k + j) % n] == signature.sides()[j]))
        .collect();
    let Some(&k) = rotations.first() else {
        return Class::Contradiction("the simulated sides do not read as their signature".into());
    };
    let phases_from = |k: usize| -> Vec<f64> {
        (0..n)
            .map(|j| (cycle.impact_phases[(k + j) % n] - cycle.impact_phases[k]).rem_euclid(1.0))
            .collect()
    };
    let impact_time = |k: usize| cycle.time + cycle.impact_phases[k] * length;
    let mut guess = vec![phase::wrap(omega * impact_time(k))];
    guess.extend_from_slice(&phases_from(k)[1..]);
    let analytic = match solve_signature(&scene.unit_model(), &stops, omega, &signature, &guess) {
        Ok(o) => o,
        Err(e) => {
            check.analytic_error = Some(e.to_string());
            return Class::Contradiction(format!(
                "the analytic solver finds no {signature} orbit from the simulated phases: {e}"
            ));
        }
    };
    // The analytic orbit starts at one of the equivalent rotations: compare with the closest.
    let difference = rotations
        .iter()
        .map(|&k| {
            let alpha = phase::wrap(omega * impact_time(k));
            let since = (cycle.time - impact_time(k)).rem_euclid(length);
            let x = signature_orbit_state(scene, &analytic, since);
            let y = &cycle.state;
            let state = (0..4).map(|i| (y[i] - x[i]).abs()).fold(0.0, f64::max)
                / x.norm().max(f64::MIN_POSITIVE);
            let phases = phases_from(k)
                .iter()
                .zip(&analytic.impact_phases)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            state
                .max(phases)
                .max(phase::distance(alpha, analytic.alpha) / std::f64::consts::PI)
        })
        .fold(f64::INFINITY, f64::min);
    let multipliers =
        chain::matched_distance(&cycle.floquet_multipliers, &analytic.floquet_multipliers);
    let within_search = confirm == Confirm::Every
        && signature.impacts() <= MULTI_START_IMPACTS
        && signature.period() <= MULTI_START_PERIODS;
    let viable: Vec<SignatureOrbit> = if within_search {
        orbits_of_signature(scene, omega, &signature)
            .into_iter()
            .filter(|o| o.viable)
            .collect()
    } else {
        vec![analytic.clone()]
            .into_iter()
            .filter(|o| o.viable)
            .collect()
    };
    check.confirmed_orbits = viable
        .iter()
        .map(|o| confirm_orbit(scene, omega, o, options))
        .collect();
    check.relative_difference = Some(difference);
    check.multiplier_difference = Some(multipliers);
    let class = if !analytic.viable {
        Class::Contradiction(format!(
            "the simulator settles on a {signature} cycle the analytic solver calls not viable"
        ))
    } else if !analytic.stable {
        Class::Contradiction(format!(
            "the simulator settles on a {signature} cycle the analytic solver calls unstable"
        ))
    } else if difference < MATCH_TOLERANCE {
        Class::Agreement
    } else {
        Class::Contradiction(format!("the {signature} orbits differ by {difference:.1e}"))
    };
    check.analytic = Some(analytic);
    class
}

impl CrossCheck {
    /// The record of this check on `scene`: what `rattle compare --json` prints, and the Python
    /// package's `compare` returns.
    pub fn record(&self, scene: &Scene) -> CrossCheckRecord {
        let s = &self.simulated;
        CrossCheckRecord {
            scene: scene.name.clone(),
            omega: finite(self.omega),
            simulated: SimulatedCycleRecord {
                status: s.status_name(),
                period: s.steady.period,
                signature: self.signature.as_ref().map(|sig| sig.to_string()),
                impacts_per_period: finite(s.steady.impacts_per_period),
                outer_amplitude: finite(s.outer_amplitude),
                floquet_multipliers: s
                    .steady
                    .orbit
                    .as_ref()
                    .map(|o| multipliers(&o.floquet_multipliers)),
            },
            analytic: self.analytic.as_ref().map(|o| AnalyticCycleRecord {
                signature: o.signature.to_string(),
                period: o.period,
                outer_amplitude: finite(o.outer_amplitude),
                viable: o.viable,
                stable: o.stable,
                floquet_multipliers: multipliers(&o.floquet_multipliers),
                energy_residual: finite(o.energy_residual),
            }),
            analytic_error: self.analytic_error.clone(),
            class: self.class.name(),
            class_detail: self.class.detail().to_owned(),
            relative_difference: self.relative_difference.and_then(finite),
            multiplier_difference: self.multiplier_difference.and_then(finite),
            confirmed_orbits: self
                .confirmed_orbits
                .iter()
                .map(|k| ConfirmationRecord {
                    alpha: finite(k.orbit.alpha),
                    impact_phases: k.orbit.impact_phases.iter().map(|&p| finite(p)).collect(),
                    stable: k.orbit.stable,
                    outer_amplitude: finite(k.orbit.outer_amplitude),
                    confirmed: k.confirmed,
                    state_difference: k.state_difference.and_then(finite),
                    multiplier_difference: k.multiplier_difference.and_then(finite),
                    error: k.error.clone(),
                })
                .collect(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Candidates with hand-set transmittances, to check each choice.
    fn offered() -> Vec<Candidate> {
        let orbit = |branch, t| Candidate {
            motion: Motion::Orbit { branch },
            transmittance_db: t,
            outer_amplitude: 1.0,
            attracting: true,
        };
        vec![
            orbit(1, -3.0),
            orbit(0, 2.0),
            Candidate {
                motion: Motion::Linear,
                transmittance_db: 5.0,
                outer_amplitude: 1.0,
                attracting: false,
            },
        ]
    }

    #[test]
    fn each_choice_takes_its_candidate() {
        let c = offered();
        assert_eq!(predicted_transmittance(&c, Choice::PaperMethod), Some(-3.0));
        assert_eq!(
            predicted_transmittance(&c, Choice::LargestAttracting),
            Some(2.0)
        );
        let linear_only = &c[2..];
        assert_eq!(
            predicted_transmittance(linear_only, Choice::PaperMethod),
            Some(5.0)
        );
        assert_eq!(
            predicted_transmittance(linear_only, Choice::LargestAttracting),
            None
        );
        assert_eq!(predicted_transmittance(&[], Choice::PaperMethod), None);
    }

    #[test]
    fn the_linear_motion_attracts_only_with_damping() {
        // Far stops: the linear motion is clear of them at ω = 0.5 (paper unit, X_r ≈ 0.3).
        let mut scene = Scene::paper();
        scene.stops = scene.stops.map(|mut s| {
            s.gap = 10.0;
            s
        });
        let point = analyse(&scene, 0.5, OrbitSearch::Symmetric).unwrap();
        let undamped = candidates(&scene, &point);
        assert_eq!(undamped.len(), 1);
        assert_eq!(undamped[0].motion, Motion::Linear);
        assert!(!undamped[0].attracting);
        scene.damping = Some(crate::scene::DampingSpec {
            outer: 0.1,
            inner: 0.05,
        });
        let point = analyse(&scene, 0.5, OrbitSearch::Symmetric).unwrap();
        assert!(candidates(&scene, &point)[0].attracting);
    }
}
