//! How the two solvers relate at one frequency on a chain of cells: the simulated motion from
//! rest, polished by the simulator's own Newton, beside the analytic orbit of its impact
//! sequence (every pair's impacts in time order), solved by the analytic crate's own equations
//! from the simulated impact times; the chain's counterpart of [`crate::verdict::cross_check`].
//!
//! The analytic orbit is the one of [`rattle_analytic::solve_sequence`] seeded from the
//! polished cycle: `α` the base phase `ω t` at the simulated impact that starts the canonical
//! sequence (both solvers move the base as `u_g cos ωt`; the analytic time counts from that
//! impact), and the other impacts' times after it as fractions of the cycle. Coordinates are
//! the same in both (`u = (u_o,1, u_i,1, u_o,2, …)`, pair `j` is cell `j`'s `r = u_i − u_o`).

use crate::output::finite;
use crate::output::records::{
    multipliers, At, ChainAnalyticRecord, ChainCompareRecord, ChainConfirmationRecord,
    ChainOrbitsRecord, ChainSimulatedRecord,
};
use crate::scene::analytic::{chain_linear_model, chain_model, MissingStops};
use crate::scene::simulator::{
    model, polished_cycle, rest, run, PolishedCycle, SimulateError, SimulatedPoint,
};
use crate::scene::{phase, Scene};
use crate::verdict::{Class, MATCH_TOLERANCE};
use nalgebra::{Complex, DVector};
use rattle_analytic::{
    chain_response, sequence_orbits, solve_sequence, Cell, ImpactSequence, PairImpact,
    SequenceError, SequenceOrbit, SequenceOrbitError,
};
use rattle_event_driven::{
    periodic_orbit, Model, PeriodicOrbit, SimulationOptions, Start, Status, SteadyState,
};
use thiserror::Error;

/// Why a chain's point is `beyond` exact comparison or a `contradiction`; `None` for an
/// agreement.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ChainReason {
    /// Beyond: the run from rest did not repeat within its caps.
    NonPeriodic,
    /// Beyond: nothing dissipates, transients never decay.
    NoDissipation,
    /// Beyond: the final cycle sticks on a stop (no smooth stroboscopic map, no sequence).
    Sticking,
    /// Beyond: the simulator's Newton could not polish the periodic cycle.
    NotPolished,
    /// Beyond: more impacts per cycle than an impact sequence holds
    /// ([`rattle_analytic::MAX_CYCLE_IMPACTS`]).
    TooManyImpacts,
    /// Beyond: a cycle longer than an impact sequence holds (`p` above
    /// [`rattle_analytic::MAX_CYCLE_PERIOD`]).
    PeriodTooLong,
    /// Beyond: a cell without stops (the analytic chain needs a contact pair in every cell).
    CellWithoutStops,
    /// Contradiction: the analytic solver finds no orbit of the sequence from the simulated
    /// impact times.
    NoAnalyticOrbit,
    /// Contradiction: the analytic orbit violates a contact condition.
    NotViable,
    /// Beyond: the orbits agree, but a Floquet multiplier lies on the unit circle (within
    /// [`NEUTRAL_MARGIN`]) in both solvers: an undamped mode the motion does not excite, whose
    /// stability is neutral.
    Neutral,
    /// Contradiction: the analytic orbit is unstable, yet the simulator settles on it.
    Unstable,
    /// Contradiction: the orbits differ by [`MATCH_TOLERANCE`] or more.
    Differ,
    /// Contradiction: periodic without impacts, but not the linear chain's motion (or the
    /// linear motion reaches the stops).
    NotLinear,
    /// Beyond: an impact or a contact during another contact (an event that comes before the
    /// contact before it ends): a sequence's events follow one another.
    OverlappingContacts,
}

impl ChainReason {
    /// The reason's name in JSON.
    pub fn name(self) -> &'static str {
        match self {
            ChainReason::NonPeriodic => "non-periodic",
            ChainReason::NoDissipation => "no-dissipation",
            ChainReason::Sticking => "sticking",
            ChainReason::NotPolished => "not-polished",
            ChainReason::TooManyImpacts => "too-many-impacts",
            ChainReason::PeriodTooLong => "period-too-long",
            ChainReason::CellWithoutStops => "cell-without-stops",
            ChainReason::NoAnalyticOrbit => "no-analytic-orbit",
            ChainReason::NotViable => "not-viable",
            ChainReason::Neutral => "neutral",
            ChainReason::Unstable => "unstable",
            ChainReason::Differ => "differ",
            ChainReason::NotLinear => "not-linear",
            ChainReason::OverlappingContacts => "overlapping-contacts",
        }
    }
}

/// A chain's simulated periodic motion beside the analytic orbit of its impact sequence.
#[derive(Debug, Clone)]
pub struct ChainCheck {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// Cells of the chain.
    pub cells: usize,
    /// The simulator from rest (with its own Newton-polished cycle when periodic).
    pub simulated: SimulatedPoint,
    /// The polished cycle run once more from its section, when there is one.
    pub polished: Option<PolishedCycle>,
    /// The polished cycle's impacts as a canonical impact sequence.
    pub sequence: Option<ImpactSequence>,
    /// The analytic orbit of that sequence, seeded from the simulated impact times.
    pub analytic: Option<SequenceOrbit>,
    /// Why there is no analytic orbit, when the simulated cycle has one to look for.
    pub analytic_error: Option<String>,
    /// The verdict (`agreement`, `contradiction` or `beyond`, as for the unit), with words.
    pub class: Class,
    /// The verdict's reason, `None` for an agreement.
    pub reason: Option<ChainReason>,
    /// The largest of: the state just before the first impact of the canonical sequence
    /// (Euclidean norm of the difference over the analytic state's), every cell's outer
    /// amplitude (relative, the last cell's included), the impact phases (fractions of the
    /// cycle) and the base phase at the first impact over π. Without impacts: every cell's
    /// outer amplitude against the linear chain's.
    pub relative_difference: Option<f64>,
    /// The Floquet multipliers of the two solvers matched as sets (each simulated multiplier
    /// paired with a distinct analytic one, closest pairs first): the largest distance of a
    /// pair.
    pub multiplier_difference: Option<f64>,
    /// The viable analytic orbit confirmed the other way: the simulator's Newton started on
    /// it (stable or not). `None` without a viable analytic orbit.
    pub confirmation: Option<ChainConfirmation>,
}

/// The simulator's Newton started on an analytic orbit of a chain, mid-way through its first
/// flight.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainConfirmation {
    /// Whether Newton converged to a cycle with the orbit's impacts (pairs and sides, in time
    /// order from the start) and a state within [`MATCH_TOLERANCE`] of the analytic one.
    pub confirmed: bool,
    /// `|x_Newton − x|` at the start over `|x|` (Euclidean norms): 0 when the analytic state
    /// is already within Newton's tolerance (no step taken).
    pub state_difference: Option<f64>,
    /// Newton's final `|P(y) − y|` relative to `max(|y|, gap)` ([`PeriodicOrbit::residual`]):
    /// at the analytic state itself when no step was taken.
    pub map_residual: Option<f64>,
    /// Newton steps taken from the analytic state.
    pub newton_iterations: Option<u32>,
    /// The two solvers' multipliers matched one to one ([`matched_distance`]).
    pub multiplier_difference: Option<f64>,
    /// Why Newton failed, if it did.
    pub error: Option<String>,
}

impl ChainConfirmation {
    /// The record of this confirmation, as `rattle compare --json` prints it.
    pub fn record(&self) -> ChainConfirmationRecord {
        ChainConfirmationRecord {
            confirmed: self.confirmed,
            state_difference: self.state_difference.and_then(finite),
            map_residual: self.map_residual.and_then(finite),
            newton_iterations: self.newton_iterations,
            multiplier_difference: self.multiplier_difference.and_then(finite),
            error: self.error.clone(),
        }
    }
}

impl ChainCheck {
    /// The record of this check on the chain `scene`: what `rattle compare --json` prints, and
    /// the Python package's `compare` returns.
    pub fn record(&self, scene: &Scene) -> ChainCompareRecord {
        let s = &self.simulated;
        let pairs = scene.pair_count();
        let pair_signatures = s.pair_signatures(pairs).map(|list| {
            list.into_iter()
                .map(|r| match r {
                    Ok(Some(sig)) => Some(sig.to_string()),
                    Ok(None) => Some(String::new()),
                    Err(_) => None,
                })
                .collect()
        });
        ChainCompareRecord {
            scene: scene.name.clone(),
            omega: finite(self.omega),
            cells: self.cells,
            simulated: ChainSimulatedRecord {
                status: s.status_name(),
                period: s.steady.period,
                pair_signatures,
                impacts_per_period: finite(s.steady.impacts_per_period),
                pair_impacts_per_period: s.pair_impacts_per_period(pairs),
                outer_amplitude: finite(s.outer_amplitude),
                cell_outer_amplitudes: s.cell_outer_amplitudes().into_iter().map(finite).collect(),
                floquet_multipliers: s
                    .steady
                    .orbit
                    .as_ref()
                    .map(|o| multipliers(&o.floquet_multipliers)),
            },
            analytic: self.analytic.as_ref().map(|o| ChainAnalyticRecord {
                sequence: o.sequence.to_string(),
                period: o.period,
                outer_amplitude: finite(o.outer_amplitude),
                cell_outer_amplitudes: o.cell_outer_amplitudes.iter().map(|&a| finite(a)).collect(),
                viable: o.viable,
                stable: o.stable,
                floquet_multipliers: multipliers(&o.floquet_multipliers),
                energy_residual: finite(o.energy_residual),
            }),
            analytic_error: self.analytic_error.clone(),
            class: self.class.name(),
            reason: self.reason.map(|r| r.name()),
            class_detail: self.class.detail().to_owned(),
            relative_difference: self.relative_difference.and_then(finite),
            multiplier_difference: self.multiplier_difference.and_then(finite),
            confirmation: self.confirmation.as_ref().map(ChainConfirmation::record),
        }
    }

    pub(crate) fn new(cells: usize, omega: f64, simulated: SimulatedPoint) -> Self {
        Self {
            omega,
            cells,
            simulated,
            polished: None,
            sequence: None,
            analytic: None,
            analytic_error: None,
            class: Class::Agreement,
            reason: None,
            relative_difference: None,
            multiplier_difference: None,
            confirmation: None,
        }
    }

    /// Records the verdict `class` for `reason`.
    pub(crate) fn decide(&mut self, reason: Option<ChainReason>, class: Class) {
        self.reason = reason;
        self.class = class;
    }

    pub(crate) fn beyond(&mut self, reason: ChainReason, words: String) {
        self.decide(Some(reason), Class::Beyond(words));
    }

    pub(crate) fn contradiction(&mut self, reason: ChainReason, words: String) {
        self.decide(Some(reason), Class::Contradiction(words));
    }
}

/// Both solvers on the motion a chain scene settles on from rest at `omega`: the simulator
/// runs from rest and polishes its cycle by Newton on its own stroboscopic map
/// (`options.polish` is switched on); the cycle's impacts, in time order, are the impact
/// sequence; the analytic crate solves that sequence seeded from the simulated impact times;
/// the two are compared ([`ChainCheck::relative_difference`],
/// [`ChainCheck::multiplier_difference`]).
///
/// Classes as for the unit ([`crate::verdict::cross_check`]): `agreement` (the analytic orbit
/// is viable, stable and within [`MATCH_TOLERANCE`]; without impacts, the linear chain's
/// motion clear of the stops), `beyond` exact comparison with a [`ChainReason`]
/// (non-periodic, sticking, too many impacts, …), `contradiction` otherwise.
///
/// # Errors
/// A failure of the simulator.
pub fn chain_cross_check(
    scene: &Scene,
    omega: f64,
    options: &SimulationOptions,
) -> Result<ChainCheck, SimulateError> {
    let options = SimulationOptions {
        polish: true,
        ..*options
    };
    let simulated = run(scene, omega, &rest(scene), &options)?;
    let check = ChainCheck::new(scene.cell_count(), omega, simulated);
    judge(
        check,
        |check| linear_check(scene, check),
        |check, orbit, steady| seeded_check(scene, omega, orbit, steady, &options, check),
    )
}

/// The verdict of a check whose simulated run is in: `beyond` for a sticking, non-periodic or
/// undecaying motion and for a cycle the simulator could not polish; `linear` for a periodic
/// motion without impacts; `seeded` (the analytic orbit of the polished cycle's sequence)
/// otherwise.
///
/// # Errors
/// A failure of the simulator in `seeded`.
pub(crate) fn judge(
    mut check: ChainCheck,
    linear: impl FnOnce(&mut ChainCheck),
    seeded: impl FnOnce(&mut ChainCheck, &PeriodicOrbit, &SteadyState) -> Result<(), SimulateError>,
) -> Result<ChainCheck, SimulateError> {
    let steady = check.simulated.steady.clone();
    match (steady.status, steady.sticking) {
        (_, true) => check.beyond(
            ChainReason::Sticking,
            "sticking: outside exact comparison".into(),
        ),
        (Status::NonPeriodic, _) => check.beyond(
            ChainReason::NonPeriodic,
            "not periodic within the cap".into(),
        ),
        (Status::NoDissipation, _) => check.beyond(
            ChainReason::NoDissipation,
            "no dissipation: transients never decay".into(),
        ),
        (Status::Periodic, _)
            if steady.cycle_impacts.is_empty() && steady.cycle_contacts.is_empty() =>
        {
            linear(&mut check)
        }
        (Status::Periodic, _) => match steady.orbit.as_deref() {
            None => check.beyond(
                ChainReason::NotPolished,
                format!(
                    "the simulator could not polish its cycle: {}",
                    steady.orbit_error.as_deref().unwrap_or("unknown")
                ),
            ),
            Some(orbit) => {
                let orbit = orbit.clone();
                seeded(&mut check, &orbit, &steady)?;
            }
        },
    }
    Ok(check)
}

/// A periodic motion without impacts beside the linear chain's steady state.
fn linear_check(scene: &Scene, check: &mut ChainCheck) {
    let cells: Vec<Cell> = scene
        .cell_scenes()
        .iter()
        .map(|c| Cell::of_unit(&c.unit_model()))
        .collect();
    let linear = match chain_response(&cells, scene.base.amplitude, check.omega) {
        Ok(r) if !r.unbounded => r,
        _ => {
            return check.contradiction(
                ChainReason::NotLinear,
                "periodic without impacts, but the linear chain has no bounded motion".into(),
            )
        }
    };
    let reaches = scene.cell_scenes().iter().enumerate().any(|(j, c)| {
        c.gap()
            .is_some_and(|gap| (linear.inner[j] - linear.outer[j]).norm() > gap)
    });
    let d = largest_relative(
        &check.simulated.cell_outer_amplitudes(),
        &linear.cell_outer_amplitudes,
    );
    check.decide_linear(d, reaches, "the linear chain's motion");
}

impl ChainCheck {
    /// The verdict on a periodic motion without impacts `difference` (relative) from the
    /// linear steady state (`linear`, in words), which `reaches` a stop or not: agreement
    /// within [`MATCH_TOLERANCE`] when it stays clear, a contradiction otherwise.
    pub(crate) fn decide_linear(&mut self, difference: f64, reaches: bool, linear: &str) {
        self.relative_difference = Some(difference);
        if reaches {
            self.contradiction(
                ChainReason::NotLinear,
                format!("periodic without impacts, but {linear} reaches the stops"),
            );
        } else if difference < MATCH_TOLERANCE {
            self.decide(None, Class::Agreement);
        } else {
            self.contradiction(
                ChainReason::NotLinear,
                format!("periodic without impacts, {difference:.1e} from {linear}"),
            );
        }
    }
}

/// `max_k |a_k − b_k| / max_k |b_k|` (infinite when the lengths differ).
pub(crate) fn relative_to_largest(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let scale = b.iter().fold(0.0, |m: f64, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale.max(f64::MIN_POSITIVE)
}

/// `max_k |a_k − b_k| / |b_k|` (infinite when the lengths differ).
pub(crate) fn largest_relative(a: &[f64], b: &[f64]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / y.abs().max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max)
}

/// The analytic orbit of the polished cycle's sequence, its differences and the class.
fn seeded_check(
    scene: &Scene,
    omega: f64,
    orbit: &PeriodicOrbit,
    steady: &SteadyState,
    options: &SimulationOptions,
    check: &mut ChainCheck,
) -> Result<(), SimulateError> {
    let Ok(analytic) = chain_model(scene) else {
        check.beyond(
            ChainReason::CellWithoutStops,
            "a cell without stops: the analytic chain needs a contact pair in every cell".into(),
        );
        return Ok(());
    };
    let models = CheckModels {
        event: model(scene, omega)?,
        analytic,
        compared: (0..scene.cell_count()).map(|j| 2 * j).collect(),
        relative_to_largest: false,
    };
    seeded_models(&models, omega, orbit, steady, options, check)
}

/// Each solver's own model of one scene at one frequency, and the coordinates whose
/// amplitudes a cross-check compares: what a seeded check needs of a scene, whatever its form.
#[derive(Debug, Clone)]
pub struct CheckModels {
    /// The simulator's model at the frequency.
    pub event: Model,
    /// The analytic solver's model.
    pub analytic: rattle_analytic::LinearModel,
    /// The coordinates whose amplitudes are compared (a chain's outer masses, a structure's
    /// bodies).
    pub compared: Vec<usize>,
    /// Whether each amplitude's difference is relative to the largest compared amplitude (a
    /// structure's, whose bodies may rest: an amplitude of 0 and one of 1e-30 are the same
    /// rest) rather than to its own (a chain's cells all move).
    pub relative_to_largest: bool,
}

impl CheckModels {
    /// The largest difference of the compared coordinates' amplitudes, `simulated` against
    /// `analytic` (every coordinate's, in the models' order): relative to the largest
    /// compared amplitude or to each its own ([`CheckModels::relative_to_largest`]).
    pub(crate) fn amplitude_difference(&self, simulated: &[f64], analytic: &[f64]) -> f64 {
        let pick = |amplitudes: &[f64]| -> Vec<f64> {
            self.compared.iter().map(|&k| amplitudes[k]).collect()
        };
        let (a, b) = (pick(simulated), pick(analytic));
        if self.relative_to_largest {
            relative_to_largest(&a, &b)
        } else {
            largest_relative(&a, &b)
        }
    }
}

/// The analytic orbit of the polished cycle's sequence on `models`, its differences from the
/// simulated cycle and the class.
///
/// # Errors
/// A failure of the simulator.
pub(crate) fn seeded_models(
    models: &CheckModels,
    omega: f64,
    orbit: &PeriodicOrbit,
    steady: &SteadyState,
    options: &SimulationOptions,
    check: &mut ChainCheck,
) -> Result<(), SimulateError> {
    let analytic_model = &models.analytic;
    let cycle = polished_cycle(&models.event, omega, orbit, options)?;
    let impacts: Vec<PairImpact> = cycle
        .impacts
        .iter()
        .map(|i| PairImpact::rigid(i.pair, i.side))
        .collect();
    // The polished cycle must be the cycle the run settled on: same impacts per cycle.
    if impacts.len() != orbit.impact_sides.len()
        || impacts.len() != steady.cycle_impacts.len()
        || impacts
            .iter()
            .zip(&orbit.impact_sides)
            .any(|(a, &s)| a.side != s)
    {
        check.polished = Some(cycle);
        check.beyond(
            ChainReason::NotPolished,
            "the cycle run from the polished state does not repeat the polished impacts".into(),
        );
        return Ok(());
    }
    let Some((sequence, rotations)) = read_sequence(&impacts, orbit.periods, check) else {
        check.polished = Some(cycle);
        return Ok(());
    };
    let first = rotations[0];
    let n = impacts.len();
    let length = f64::from(orbit.periods) * std::f64::consts::TAU / omega;
    let phases_from = |k: usize| -> Vec<f64> {
        (0..n)
            .map(|j| {
                ((cycle.impacts[(k + j) % n].time - cycle.impacts[k].time) / length).rem_euclid(1.0)
            })
            .collect()
    };
    let alpha_at = |k: usize| phase::wrap(omega * cycle.impacts[k].time);
    let mut guess = vec![alpha_at(first)];
    guess.extend_from_slice(&phases_from(first)[1..]);
    check.sequence = Some(sequence.clone());
    let analytic = match solve_sequence(analytic_model, omega, &sequence, &guess) {
        Ok(o) => o,
        Err(e) => {
            check.analytic_error = Some(e.to_string());
            check.polished = Some(cycle);
            check.contradiction(
                ChainReason::NoAnalyticOrbit,
                format!("the analytic solver finds no orbit of {sequence} from the simulated times: {e}"),
            );
            return Ok(());
        }
    };
    let amplitude = models.amplitude_difference(&cycle.amplitudes, &analytic.amplitudes);
    // The analytic orbit starts at one of the equivalent rotations: compare with the closest.
    let before = DVector::from_column_slice(&analytic.states_before_impacts[0]);
    let difference = rotations
        .iter()
        .map(|&k| {
            let state = (&cycle.impacts[k].state_before - &before).norm()
                / before.norm().max(f64::MIN_POSITIVE);
            let phases = phases_from(k)
                .iter()
                .zip(&analytic.impact_phases)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            state
                .max(phases)
                .max(phase::distance(alpha_at(k), analytic.alpha) / std::f64::consts::PI)
        })
        .fold(f64::INFINITY, f64::min)
        .max(amplitude);
    check.relative_difference = Some(difference);
    check.multiplier_difference = Some(matched_distance(
        &orbit.floquet_multipliers,
        &analytic.floquet_multipliers,
    ));
    classify(check, &sequence, &analytic, difference);
    if analytic.viable {
        check.confirmation = Some(confirm(
            &models.event,
            analytic_model,
            &analytic,
            &cycle.orbit,
            options,
        ));
    }
    check.polished = Some(cycle);
    check.analytic = Some(analytic);
    Ok(())
}

/// The canonical sequence of a polished cycle's `impacts` (rigid impacts and contact phases,
/// in time order) over `periods`, and the rotations of `impacts` that read as it, at least
/// one; `None` with the verdict recorded in `check` when the cycle has no sequence (`beyond`:
/// too many impacts, or too long) or, against the sequence's construction, no rotation reads
/// as it (`contradiction`).
pub(crate) fn read_sequence(
    impacts: &[PairImpact],
    periods: u32,
    check: &mut ChainCheck,
) -> Option<(ImpactSequence, Vec<usize>)> {
    let sequence = match ImpactSequence::from_cycle(impacts, periods) {
        Ok(s) => s,
        Err(e) => {
            let reason = match e {
                SequenceError::TooManyImpacts { .. } => ChainReason::TooManyImpacts,
                _ => ChainReason::PeriodTooLong,
            };
            check.beyond(
                reason,
                format!("the simulated cycle has no impact sequence: {e}"),
            );
            return None;
        }
    };
    let n = impacts.len();
    let rotations: Vec<usize> = (0..n)
        .filter(|&k| (0..n).all(|j| impacts[(k + j) % n] == sequence.impacts()[j]))
        .collect();
    if rotations.is_empty() {
        check.contradiction(
            ChainReason::NoAnalyticOrbit,
            "the simulated impacts do not read as their sequence".into(),
        );
        return None;
    }
    Some((sequence, rotations))
}

/// A largest Floquet multiplier within this of 1 in modulus, in both solvers, is neutral: the
/// simulator's own margin of a steady cycle ([`rattle_event_driven::UNSTABLE_MARGIN`]), far
/// above the multipliers' rounding (1e-14 between the solvers) and far below any decay a
/// dashpot or an impact gives.
pub const NEUTRAL_MARGIN: f64 = rattle_event_driven::UNSTABLE_MARGIN;

/// The class of a seeded check from the analytic orbit's verdicts and its `difference` from
/// the simulated cycle: a contradiction when the simulator settles on a cycle the analytic
/// solver calls not viable or unstable, or that differs from it; `beyond` (neutral) when the
/// orbits agree and both solvers put the largest multiplier on the unit circle; agreement
/// otherwise.
pub(crate) fn classify(
    check: &mut ChainCheck,
    sequence: &ImpactSequence,
    analytic: &rattle_analytic::SequenceOrbit,
    difference: f64,
) {
    let largest = |m: &[Complex<f64>]| m.iter().map(|m| m.norm()).fold(0.0, f64::max);
    let simulated = check
        .simulated
        .steady
        .orbit
        .as_ref()
        .map_or(f64::NAN, |o| largest(&o.floquet_multipliers));
    let neutral = [largest(&analytic.floquet_multipliers), simulated]
        .iter()
        .all(|m| (m - 1.0).abs() <= NEUTRAL_MARGIN);
    if analytic.viable && neutral && difference < MATCH_TOLERANCE {
        check.beyond(
            ChainReason::Neutral,
            format!(
                "the {sequence} orbits agree, but a Floquet multiplier lies on the unit circle \
                 (an undamped mode the motion does not excite): neutral stability"
            ),
        );
    } else if !analytic.viable {
        check.contradiction(
            ChainReason::NotViable,
            format!(
                "the simulator settles on a {sequence} cycle the analytic solver calls not viable"
            ),
        );
    } else if !analytic.stable {
        check.contradiction(
            ChainReason::Unstable,
            format!(
                "the simulator settles on a {sequence} cycle the analytic solver calls unstable"
            ),
        );
    } else if difference < MATCH_TOLERANCE {
        check.decide(None, Class::Agreement);
    } else {
        check.contradiction(
            ChainReason::Differ,
            format!("the {sequence} orbits differ by {difference:.1e}"),
        );
    }
}

/// The simulator's Newton on its own stroboscopic map, started on the analytic `orbit` of
/// `model` mid-way through the orbit's first flight (`orbit.impact_phases[1] / 2` of the
/// cycle after its first impact, base phase `α + ω t` there); its impacts compared with the
/// `polished` cycle's, its state with the analytic one.
fn confirm(
    event: &Model,
    model_of_chain: &rattle_analytic::LinearModel,
    orbit: &SequenceOrbit,
    polished: &PeriodicOrbit,
    options: &SimulationOptions,
) -> ChainConfirmation {
    let omega = orbit.omega;
    let length = f64::from(orbit.period) * std::f64::consts::TAU / omega;
    let t = 0.5 * orbit.impact_phases.get(1).copied().unwrap_or(1.0) * length;
    let phases = rattle_analytic::phase_state(&model_of_chain.forcing().orders(), orbit.alpha);
    let (x, _) = model_of_chain.transition(omega, t).apply(
        &DVector::from_column_slice(&orbit.state_after_impact),
        &DVector::from_vec(phases),
    );
    let start = Start {
        state: x.clone(),
        // Base phase ω t_sim = α + ω t.
        time: t + orbit.alpha / omega,
    };
    let mut out = ChainConfirmation {
        confirmed: false,
        state_difference: None,
        map_residual: None,
        newton_iterations: None,
        multiplier_difference: None,
        error: None,
    };
    match periodic_orbit(event, omega, &start, orbit.period, options) {
        Ok(found) => {
            let d = (&found.state - &x).norm() / x.norm().max(f64::MIN_POSITIVE);
            // The same impacts: a rotation of the polished cycle's sides (Newton's start lies
            // elsewhere in the cycle) of the same length.
            let n = found.impact_sides.len();
            let same = n == polished.impact_sides.len()
                && (0..n.max(1)).any(|k| {
                    (0..n).all(|j| found.impact_sides[(k + j) % n] == polished.impact_sides[j])
                });
            out.state_difference = Some(d);
            out.map_residual = Some(found.residual);
            out.newton_iterations = Some(found.iterations);
            out.multiplier_difference = Some(matched_distance(
                &found.floquet_multipliers,
                &orbit.floquet_multipliers,
            ));
            out.confirmed = same && d < MATCH_TOLERANCE;
        }
        Err(e) => out.error = Some(e.to_string()),
    }
    out
}

/// Two sets of multipliers matched one to one, closest pairs first: the largest distance of a
/// matched pair (infinite when the sets differ in size).
pub fn matched_distance(a: &[Complex<f64>], b: &[Complex<f64>]) -> f64 {
    if a.len() != b.len() {
        return f64::INFINITY;
    }
    let mut pairs: Vec<(f64, usize, usize)> = a
        .iter()
        .enumerate()
        .flat_map(|(i, x)| {
            b.iter()
                .enumerate()
                .map(move |(j, y)| ((x - y).norm(), i, j))
        })
        .collect();
    pairs.sort_by(|p, q| p.0.total_cmp(&q.0));
    let (mut used_a, mut used_b) = (vec![false; a.len()], vec![false; b.len()]);
    let mut largest: f64 = 0.0;
    for (d, i, j) in pairs {
        if !used_a[i] && !used_b[j] {
            used_a[i] = true;
            used_b[j] = true;
            largest = largest.max(d);
        }
    }
    largest
}

/// Why the orbits of an impact sequence of a chain's pairs were not found ([`chain_orbits`]).
#[derive(Debug, Error)]
pub enum ChainOrbitsError {
    /// The sequence does not parse (naming `--signature` or `--period`), or names a pair the
    /// chain does not have: bad input.
    #[error(transparent)]
    Sequence(#[from] SequenceError),
    /// A cell of the chain has no stops: bad input.
    #[error(transparent)]
    MissingStops(#[from] MissingStops),
    /// The analytic solver failed.
    #[error(transparent)]
    Numerical(#[from] SequenceOrbitError),
}

/// What `rattle orbit --signature SEQUENCE --period P --json` prints for the chain `scene` at
/// `omega` (and the Python package's `orbit` returns): every orbit of the impact sequence
/// `text` (`<pair><side>` tokens, e.g. `0+ 1- 0- 1+`) over `period` forcing periods.
///
/// # Errors
/// [`ChainOrbitsError::Sequence`] naming `--signature` or `--period` for a sequence that does
/// not parse or names a pair the chain does not have; [`ChainOrbitsError::MissingStops`] for a
/// cell without stops; [`ChainOrbitsError::Numerical`] when the analytic solver fails.
pub fn chain_orbits(
    scene: &Scene,
    omega: f64,
    text: &str,
    period: u32,
) -> Result<ChainOrbitsRecord, ChainOrbitsError> {
    let sequence = ImpactSequence::parse(text, period)?;
    let model = chain_linear_model(scene)?;
    sequence.check(&model)?;
    let orbits = sequence_orbits(&model, omega, &sequence)?;
    Ok(ChainOrbitsRecord {
        at: At::new(scene, omega),
        cells: scene.cell_count(),
        sequence: sequence.to_string(),
        period: sequence.period(),
        orbits,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn multipliers_are_matched_one_to_one() {
        let c = |re, im| Complex::new(re, im);
        // Nearest-neighbour distance would pair both of `a` with 0.5; one-to-one cannot.
        let a = [c(0.5, 0.0), c(0.51, 0.0)];
        let b = [c(0.5, 0.0), c(-0.5, 0.0)];
        assert!((matched_distance(&a, &b) - 1.01).abs() < 1e-15);
        let same = [c(0.1, 0.2), c(0.1, -0.2)];
        assert_eq!(matched_distance(&same, &[same[1], same[0]]), 0.0);
        assert_eq!(matched_distance(&a, &a[..1]), f64::INFINITY);
    }
}
