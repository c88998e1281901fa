//! The event-driven simulator on a scene: building its model with only the scene's effects,
//! starting it from rest or on an analytic orbit, and naming the regime it settles in.

use crate::scene::analytic::orbit_state;
use crate::scene::structure::Structure;
use crate::scene::{phase, Scene};
use nalgebra::{DVector, Vector4};
use rattle_analytic::transmittance_db;
use rattle_analytic::{Orbit, Signature};
use rattle_event_driven::{
    simulate, simulate_watched, CellParameters, CellStops, ContactRecord, ImpactRecord, Model,
    ModelError, PeriodicOrbit, SimulationError, SimulationOptions, Start, Status, SteadyState,
    Stop,
};
use thiserror::Error;

/// A failure of the simulator on a scene.
#[derive(Debug, Error)]
pub enum SimulateError {
    /// The scene does not make a valid model.
    #[error("model: {0}")]
    Model(#[from] ModelError),
    /// The simulation itself failed.
    #[error("simulation: {0}")]
    Simulation(#[from] SimulationError),
}

/// The simulator's accuracy knobs as a user gives them, before their range checks: the
/// command's `--tol`, `--steady-tol`, `--max-periods` and `--max-oscillations`, the Python
/// package's `tol`, `steady_tol`, `max_periods` and `max_oscillations`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Accuracy {
    /// Relative tolerance of contact times, in [1e-15, 1e-2]
    /// ([`SimulationOptions::root_tolerance`]).
    pub tol: f64,
    /// Relative tolerance of the periodicity test of the steady state, in [1e-14, 1e-2]
    /// ([`SimulationOptions::periodicity_tolerance`]).
    pub steady_tol: f64,
    /// Cap on forcing periods when running until steady, > 0
    /// ([`SimulationOptions::max_periods`]).
    pub max_periods: u64,
    /// Cap on free oscillations of the fastest mode when running until steady, finite and > 0
    /// ([`SimulationOptions::max_oscillations`]).
    pub max_oscillations: f64,
}

/// Allowed range of [`Accuracy::tol`].
const ROOT_TOLERANCE_RANGE: (f64, f64) = (1e-15, 1e-2);
/// Allowed range of [`Accuracy::steady_tol`]: below 1e-14 rounding in the stroboscopic state
/// can prevent a periodic motion from ever repeating.
const PERIODICITY_TOLERANCE_RANGE: (f64, f64) = (1e-14, 1e-2);

/// An accuracy knob out of its range; the message names it as the command's option
/// (`--tol`, …).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum AccuracyError {
    /// `--tol` or `--steady-tol` outside its allowed range.
    #[error("{option} = {value} is out of range: must be in [{low:e}, {high:e}]")]
    OutOfRange {
        /// The option: `--tol` or `--steady-tol`.
        option: &'static str,
        /// The value given.
        value: f64,
        /// Smallest allowed value.
        low: f64,
        /// Largest allowed value.
        high: f64,
    },
    /// `--max-periods` is 0.
    #[error("--max-periods must be > 0")]
    MaxPeriods,
    /// `--max-oscillations` is not finite and positive.
    #[error("--max-oscillations = {0} is out of range: must be finite and > 0")]
    MaxOscillations(f64),
}

impl Accuracy {
    /// The simulator's options, after range checks (every other option its default).
    ///
    /// # Errors
    /// [`AccuracyError`] naming the first knob out of its range, and the range.
    pub fn options(&self) -> Result<SimulationOptions, AccuracyError> {
        in_range("--tol", self.tol, ROOT_TOLERANCE_RANGE)?;
        in_range("--steady-tol", self.steady_tol, PERIODICITY_TOLERANCE_RANGE)?;
        if self.max_periods == 0 {
            return Err(AccuracyError::MaxPeriods);
        }
        if !(self.max_oscillations.is_finite() && self.max_oscillations > 0.0) {
            return Err(AccuracyError::MaxOscillations(self.max_oscillations));
        }
        Ok(SimulationOptions {
            root_tolerance: self.tol,
            periodicity_tolerance: self.steady_tol,
            max_periods: self.max_periods,
            max_oscillations: Some(self.max_oscillations),
            ..SimulationOptions::default()
        })
    }
}

/// `value` if finite and in `[low, high]`; else the error naming `option`.
fn in_range(
    option: &'static str,
    value: f64,
    (low, high): (f64, f64),
) -> Result<(), AccuracyError> {
    if value.is_finite() && (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(AccuracyError::OutOfRange {
            option,
            value,
            low,
            high,
        })
    }
}

/// The motion the simulator settled in, in a researcher's words.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Regime {
    /// Periodic, no impacts in the final cycle.
    NoImpact,
    /// Period 1 with one impact on each stop: the motion of the two-impact model.
    TwoImpact,
    /// Period 1 with another number or pattern of impacts.
    MoreImpacts,
    /// Periodic with period `p > 1`.
    Subharmonic,
    /// Not periodic within the cap.
    Irregular,
    /// The final cycle contains sticking on a stop.
    Sticking,
    /// Undamped and elastic: transients never decay, no steady state to report.
    NoDissipation,
}

impl Regime {
    /// The word used in JSON and CSV.
    pub fn name(self) -> &'static str {
        match self {
            Regime::NoImpact => "no-impact",
            Regime::TwoImpact => "two-impact",
            Regime::MoreImpacts => "more-impacts",
            Regime::Subharmonic => "subharmonic",
            Regime::Irregular => "irregular",
            Regime::Sticking => "sticking",
            Regime::NoDissipation => "no-dissipation",
        }
    }

    /// Words for legends.
    pub fn words(self) -> &'static str {
        match self {
            Regime::NoImpact => "no impact",
            Regime::TwoImpact => "two impacts per period (period 1)",
            Regime::MoreImpacts => "other impacts, period 1",
            Regime::Subharmonic => "period p > 1",
            Regime::Irregular => "not periodic",
            Regime::Sticking => "sticking",
            Regime::NoDissipation => "no dissipation (transients persist)",
        }
    }
}

/// What the simulator found at one frequency.
#[derive(Debug, Clone)]
pub struct SimulatedPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The regime.
    pub regime: Regime,
    /// The simulator's own report.
    pub steady: SteadyState,
    /// `X_o = max|u_o|` over the final cycle.
    pub outer_amplitude: f64,
    /// `20 log10(X_o/u_g)`, `None` when no steady state was reached.
    pub transmittance_db: Option<f64>,
    /// Cells of the scene (1 for a single unit and for a structure).
    pub cells: usize,
    /// Contact pairs of the scene's model.
    pub pairs: usize,
    /// For a two-impact motion: the state just before the side-1 impact and the base phase
    /// `α ∈ (−π, π]` there, to compare with an analytic orbit.
    pub side1_impact: Option<(Vector4<f64>, f64)>,
}

/// The simulator's model of `scene` at `omega`: contact pair only with stops, damping terms
/// only with damping; a chain of cells as [`Model::chain`], one cell as the unit.
pub fn model(scene: &Scene, omega: f64) -> Result<Model, ModelError> {
    if scene.is_chain() {
        let cells: Vec<CellParameters> = scene
            .cell_scenes()
            .iter()
            .map(|cell| {
                let unit = cell.unit_model();
                CellParameters {
                    outer_mass: unit.outer_mass,
                    inner_mass: unit.inner_mass,
                    outer_stiffness: unit.outer_stiffness,
                    inner_stiffness: unit.inner_stiffness,
                    outer_damping: unit.damping.map(|d| d.outer),
                    inner_damping: unit.damping.map(|d| d.inner),
                    stops: cell
                        .stops
                        .map(|s| CellStops::symmetric(s.gap, s.rigid_restitution())),
                }
            })
            .collect();
        return Model::chain(&cells, scene.base.amplitude, omega);
    }
    let unit = scene.unit_model();
    let damping = unit.damping;
    let cell = CellParameters {
        outer_mass: unit.outer_mass,
        inner_mass: unit.inner_mass,
        outer_stiffness: unit.outer_stiffness,
        inner_stiffness: unit.inner_stiffness,
        outer_damping: damping.map(|d| d.outer),
        inner_damping: damping.map(|d| d.inner),
        stops: scene
            .stops
            .map(|s| CellStops::symmetric(s.gap, s.rigid_restitution())),
    };
    Model::unit(&cell, unit.base_amplitude, omega)
}

/// The start at rest at `t = 0` for `scene`'s model (every cell).
pub fn rest(scene: &Scene) -> Start {
    Start::rest(2 * scene.cell_count())
}

/// Relative size of the nudge [`start_on_orbit`] applies: large enough that an unstable orbit
/// is seen to be left rather than held by exact arithmetic, small enough (far below the match
/// tolerances of [`crate::verdict`]) that a stable orbit is still the one the run ends on.
pub const START_PERTURBATION: f64 = 1e-7;

/// The fixed direction of the nudge (any direction off the orbit's tangent will do).
const NUDGE_DIRECTION: [f64; 4] = [1.0, -0.7, 0.4, 0.9];

/// Where to start on an analytic orbit: mid-way through its first flight (away from any
/// impact), at the right forcing phase, nudged by a relative `perturbation` of the state
/// (0 for none).
pub fn start_on_orbit(scene: &Scene, orbit: &Orbit, perturbation: f64) -> Start {
    let period = std::f64::consts::TAU / orbit.omega;
    let t_mid = 0.5 * orbit.beta * period;
    let x = orbit_state(scene, orbit, t_mid);
    let scale = x.norm().max(orbit.gap);
    let x = x + Vector4::from(NUDGE_DIRECTION) * (perturbation * scale);
    // Base phase ω t_sim = ω t + α.
    let time = (t_mid + orbit.alpha / orbit.omega).rem_euclid(period);
    Start {
        state: DVector::from_column_slice(x.as_slice()),
        time,
    }
}

/// Runs the simulator on `scene` at `omega` from `start` and names the regime.
///
/// # Errors
/// [`SimulateError::Model`] when the scene makes no valid model at `omega`,
/// [`SimulateError::Simulation`] when the simulator refuses the start or the options, or
/// meets an unresolved accumulation of events.
pub fn run(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> Result<SimulatedPoint, SimulateError> {
    run_watched(scene, omega, start, options, &mut |_, _| false)
}

/// As [`run`], with the simulator's section `watch` ([`simulate_watched`]): `watch(k, state)`
/// at each undecided section `t = kT` may end the run (then nothing is observed and the
/// amplitudes are NaN).
///
/// # Errors
/// As [`run`].
pub fn run_watched(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
    watch: &mut dyn FnMut(u64, &DVector<f64>) -> bool,
) -> Result<SimulatedPoint, SimulateError> {
    let model = model(scene, omega)?;
    let steady = simulate_watched(&model, omega, start, options, watch)?;
    let regime = if scene.is_chain() {
        chain_regime(&steady)
    } else {
        regime(&steady)
    };
    // The last cell's outer mass: coordinate 2(N − 1) (0 for the unit).
    let last_outer = 2 * (scene.cell_count() - 1);
    let outer_amplitude = steady
        .amplitudes
        .get(last_outer)
        .copied()
        .unwrap_or(f64::NAN);
    let settled = !matches!(steady.status, Status::NoDissipation);
    let transmittance = (settled && outer_amplitude.is_finite())
        .then(|| transmittance_db(outer_amplitude, scene.base.amplitude));
    // A two-impact motion, or one still converging to it (two alternating impacts per period
    // without repeating to the tolerance yet).
    let alternating = steady.impacts_per_period == 2.0
        && steady
            .cycle_impacts
            .windows(2)
            .all(|w| w[0].side != w[1].side);
    let side1_impact = (!scene.is_chain()
        && (regime == Regime::TwoImpact || (regime == Regime::Irregular && alternating)))
        .then(|| {
            steady.cycle_impacts.iter().find(|i| i.side > 0).map(|i| {
                let s = &i.state_before;
                let alpha = phase::wrap(omega * i.phase);
                (Vector4::new(s[0], s[1], s[2], s[3]), alpha)
            })
        })
        .flatten();
    Ok(SimulatedPoint {
        omega,
        regime,
        steady,
        outer_amplitude,
        transmittance_db: transmittance,
        cells: scene.cell_count(),
        pairs: scene.pair_count(),
        side1_impact,
    })
}

/// Runs the simulator on `structure` at `omega` from `start` and names the regime as a
/// chain's ([`chain_regime`]: the two-impact motion is the unit's); the outer amplitude is
/// the observed body's, the transmittance against `u_g` when the base moves. A periodic
/// motion that the simulator's Newton polishes (with `options.polish`) is reported from its
/// polished cycle (the simulator reads the amplitudes there; [`polished_cycle`] gives its
/// impacts).
///
/// # Errors
/// As [`run`].
pub fn run_structure(
    structure: &Structure,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> Result<SimulatedPoint, SimulateError> {
    let model = structure.event_model(omega)?;
    let steady = simulate_watched(&model, omega, start, options, &mut |_, _| false)?;
    let outer_amplitude = steady
        .amplitudes
        .get(structure.observe)
        .copied()
        .unwrap_or(f64::NAN);
    let settled = !matches!(steady.status, Status::NoDissipation);
    let transmittance_db = structure
        .base_amplitude
        .filter(|_| settled && outer_amplitude.is_finite())
        .map(|ug| transmittance_db(outer_amplitude, ug));
    Ok(SimulatedPoint {
        omega,
        regime: chain_regime(&steady),
        steady,
        outer_amplitude,
        transmittance_db,
        cells: 1,
        pairs: structure.stops.len(),
        side1_impact: None,
    })
}

/// One stop's canonical signature over a cycle: of its impacts, or of a compliant stop's
/// contact phases, each side then marked `c` (`+c-c`), as impact sequences write them.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PairSignature {
    /// The sides in canonical order.
    pub signature: Signature,
    /// Whether the sides are contact phases of a compliant stop.
    pub contact: bool,
}

impl PairSignature {
    /// The signature of stop `pair` over the final cycle of `steady`, of `period` forcing
    /// periods: of its impacts, or of its contact phases (a stop is rigid or compliant, never
    /// both); `None` for a stop the cycle does not touch.
    ///
    /// # Errors
    /// A cycle beyond what a signature holds.
    pub fn of(
        steady: &SteadyState,
        pair: usize,
        period: u32,
    ) -> Result<Option<PairSignature>, rattle_analytic::SignatureError> {
        let impacts: Vec<i8> = steady
            .cycle_impacts
            .iter()
            .filter(|i| i.pair == pair)
            .map(|i| i.side)
            .collect();
        let (sides, contact) = if impacts.is_empty() {
            let contacts = steady
                .cycle_contacts
                .iter()
                .filter(|c| c.pair == pair)
                .map(|c| c.side)
                .collect();
            (contacts, true)
        } else {
            (impacts, false)
        };
        if sides.is_empty() {
            return Ok(None);
        }
        Signature::from_cycle(&sides, period)
            .map(|signature| Some(PairSignature { signature, contact }))
    }
}

impl std::fmt::Display for PairSignature {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mark = if self.contact { "c" } else { "" };
        for &side in self.signature.sides() {
            write!(f, "{}{mark}", if side > 0 { '+' } else { '-' })?;
        }
        Ok(())
    }
}

/// The simulator's polished cycle, read from the simulator alone.
#[derive(Debug, Clone)]
pub struct PolishedCycle {
    /// The simulator's Newton-polished orbit (state at its section, multipliers).
    pub orbit: PeriodicOrbit,
    /// The impacts of one cycle run from the polished state at the section, in time order,
    /// each with its pair, side, absolute time and state just before.
    pub impacts: Vec<ImpactRecord>,
    /// The contact phases of compliant stops that end in that cycle, in the order they end
    /// (one through the section enters before it).
    pub contacts: Vec<ContactRecord>,
    /// `max_t |u_k(t)|` of every coordinate over that cycle, from the simulator's closed-form
    /// extrema.
    pub amplitudes: Vec<f64>,
}

/// One cycle of the simulator on `model` run from the polished `orbit`'s section (`p` periods
/// exactly, no polish): its impacts and amplitudes are those of the polished cycle.
///
/// # Errors
/// A failure of the simulator.
pub fn polished_cycle(
    model: &Model,
    omega: f64,
    orbit: &PeriodicOrbit,
    options: &SimulationOptions,
) -> Result<PolishedCycle, SimulateError> {
    let start = Start {
        state: orbit.state.clone(),
        time: orbit.time,
    };
    let once = SimulationOptions {
        fixed_periods: Some(u64::from(orbit.periods)),
        max_period_multiplicity: options.max_period_multiplicity.max(orbit.periods),
        polish: false,
        record_trajectory: false,
        ..*options
    };
    let steady = simulate(model, omega, &start, &once)?;
    Ok(PolishedCycle {
        orbit: orbit.clone(),
        impacts: steady.cycle_impacts,
        contacts: steady.cycle_contacts,
        amplitudes: steady.amplitudes,
    })
}

/// Names the regime of a steady state.
pub fn regime(steady: &SteadyState) -> Regime {
    match steady.status {
        Status::NoDissipation => Regime::NoDissipation,
        Status::NonPeriodic => Regime::Irregular,
        Status::Periodic => {
            if steady.sticking {
                Regime::Sticking
            } else if steady.cycle_impacts.is_empty() && steady.cycle_contacts.is_empty() {
                Regime::NoImpact
            } else if steady.period != Some(1) {
                Regime::Subharmonic
            } else {
                // A compliant stop's contact phase counts as its impact.
                let sides: Vec<i8> = steady
                    .cycle_impacts
                    .iter()
                    .map(|i| i.side)
                    .chain(steady.cycle_contacts.iter().map(|c| c.side))
                    .collect();
                if sides.len() == 2 && sides[0] != sides[1] {
                    Regime::TwoImpact
                } else {
                    Regime::MoreImpacts
                }
            }
        }
    }
}

/// Names the regime of a chain's steady state: as [`regime`], except that a period-1 motion
/// with impacts is [`Regime::MoreImpacts`] (the two-impact motion is the unit's).
pub fn chain_regime(steady: &SteadyState) -> Regime {
    match regime(steady) {
        Regime::TwoImpact => Regime::MoreImpacts,
        other => other,
    }
}

impl SimulatedPoint {
    /// `max|u_o,j|` of every cell's outer mass over the final cycle, from the base out.
    pub fn cell_outer_amplitudes(&self) -> Vec<f64> {
        self.steady.amplitudes.iter().step_by(2).copied().collect()
    }

    /// Impacts per forcing period of each of the scene's `pairs` contact pairs (one per cell
    /// with stops, from the base out) over the final cycle; they sum to the steady state's
    /// `impacts_per_period`.
    pub fn pair_impacts_per_period(&self, pairs: usize) -> Vec<f64> {
        let mut counts = vec![0.0; pairs];
        for impact in &self.steady.cycle_impacts {
            if let Some(c) = counts.get_mut(impact.pair) {
                *c += 1.0;
            }
        }
        let total: f64 = counts.iter().sum();
        let scale = if total > 0.0 {
            self.steady.impacts_per_period / total
        } else {
            0.0
        };
        // A pair with every impact (a single unit's) carries the total itself, not a rounding
        // of it.
        counts
            .iter()
            .map(|&c| {
                if c == total && total > 0.0 {
                    self.steady.impacts_per_period
                } else {
                    c * scale
                }
            })
            .collect()
    }

    /// The simulator's status as a word: `periodic`, `non-periodic` or `no-dissipation`, with
    /// `, sticking` appended when the final cycle sticks.
    pub fn status_name(&self) -> String {
        let base = match self.steady.status {
            Status::Periodic => "periodic",
            Status::NonPeriodic => "non-periodic",
            Status::NoDissipation => "no-dissipation",
        };
        if self.steady.sticking {
            format!("{base}, sticking")
        } else {
            base.to_owned()
        }
    }

    /// Why the run ended, in words: `decided` (periodic, or no dissipation possible),
    /// `fixed-periods`, `period-cap`, `event-cap`, `oscillation-cap` or `watched` (the
    /// caller recognised the motion before it was decided, as `rattle basins` does).
    pub fn stopped_by(&self) -> &'static str {
        match self.steady.stopped {
            Stop::Decided => "decided",
            Stop::FixedPeriods => "fixed-periods",
            Stop::PeriodCap => "period-cap",
            Stop::EventCap => "event-cap",
            Stop::OscillationCap => "oscillation-cap",
            Stop::Watched => "watched",
        }
    }

    /// The canonical impact signature of the periodic cycle, from the simulator's own Newton
    /// polish of it (`None` when there is none, and for a chain or a structure of several
    /// pairs, whose pairs each have their own: [`Self::pair_signatures`]).
    pub fn signature(&self) -> Option<Signature> {
        if self.cells > 1 || self.pairs > 1 {
            return None;
        }
        let orbit = self.steady.orbit.as_ref()?;
        Signature::from_cycle(&orbit.impact_sides, orbit.periods).ok()
    }

    /// Each of the `pairs` contact pairs' canonical signature over the final cycle, from the
    /// simulated impacts: `Ok(None)` for a pair without impacts, `Err` when its impacts are
    /// beyond what a signature holds; `None` when the motion is not periodic or sticks.
    pub fn pair_signatures(
        &self,
        pairs: usize,
    ) -> Option<Vec<Result<Option<PairSignature>, rattle_analytic::SignatureError>>> {
        let s = &self.steady;
        let period = s
            .period
            .filter(|_| s.status == Status::Periodic && !s.sticking)?;
        Some(
            (0..pairs)
                .map(|pair| PairSignature::of(s, pair, period))
                .collect(),
        )
    }

    /// Contact phases of compliant stops per forcing period over the final cycle (the
    /// simulator's own count: the final cycle of a run that is not periodic spans the run's
    /// last stretch, not one period).
    pub fn contacts_per_period(&self) -> f64 {
        self.steady.contacts_per_period
    }

    /// For a motion with one impact on each side per period: the fraction `β` of the period
    /// from the side-1 to the side-2 impact (½ for a symmetric motion).
    pub fn impact_spacing(&self) -> Option<f64> {
        let impacts = &self.steady.cycle_impacts;
        let one = impacts.iter().find(|i| i.side > 0)?;
        let two = impacts.iter().find(|i| i.side < 0)?;
        let period = std::f64::consts::TAU / self.omega;
        Some((two.phase - one.phase).rem_euclid(period) / period)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The command's defaults (`rattle simulate --help`).
    fn defaults() -> Accuracy {
        let d = SimulationOptions::default();
        Accuracy {
            tol: d.root_tolerance,
            steady_tol: d.periodicity_tolerance,
            max_periods: d.max_periods,
            max_oscillations: d.max_oscillations.unwrap_or(f64::INFINITY),
        }
    }

    #[test]
    fn the_defaults_give_the_simulators_defaults() {
        let options = defaults().options().unwrap();
        let d = SimulationOptions::default();
        assert_eq!(options.root_tolerance, d.root_tolerance);
        assert_eq!(options.periodicity_tolerance, d.periodicity_tolerance);
        assert_eq!(options.max_periods, d.max_periods);
        assert_eq!(options.max_oscillations, d.max_oscillations);
        assert_eq!(options.fixed_periods, d.fixed_periods);
    }

    #[test]
    fn the_range_ends_are_allowed() {
        for (tol, steady_tol) in [(1e-15, 1e-14), (1e-2, 1e-2)] {
            let a = Accuracy {
                tol,
                steady_tol,
                ..defaults()
            };
            assert!(a.options().is_ok(), "{a:?}");
        }
    }

    /// The messages `rattle simulate` prints (and the Python package renames), word for word.
    #[test]
    fn each_knob_out_of_range_is_named_with_its_range() {
        let cases = [
            (
                Accuracy {
                    tol: 1.0,
                    ..defaults()
                },
                "--tol = 1 is out of range: must be in [1e-15, 1e-2]",
            ),
            (
                Accuracy {
                    tol: f64::NAN,
                    ..defaults()
                },
                "--tol = NaN is out of range: must be in [1e-15, 1e-2]",
            ),
            (
                Accuracy {
                    steady_tol: 1e-15,
                    ..defaults()
                },
                "--steady-tol = 0.000000000000001 is out of range: must be in [1e-14, 1e-2]",
            ),
            (
                Accuracy {
                    max_periods: 0,
                    ..defaults()
                },
                "--max-periods must be > 0",
            ),
            (
                Accuracy {
                    max_oscillations: -1.0,
                    ..defaults()
                },
                "--max-oscillations = -1 is out of range: must be finite and > 0",
            ),
            (
                Accuracy {
                    max_oscillations: f64::INFINITY,
                    ..defaults()
                },
                "--max-oscillations = inf is out of range: must be finite and > 0",
            ),
        ];
        for (accuracy, message) in cases {
            assert_eq!(accuracy.options().unwrap_err().to_string(), message);
        }
    }
}
