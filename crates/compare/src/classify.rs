//! One frequency, both solvers: the analytic candidates, the simulator from rest and from each
//! candidate, and the verdict on how the two relate.

use crate::frequency::{analyse, AnalyticPoint};
use crate::scene::Scene;
use crate::simulation::{run, start_on_orbit, Regime, SimulateError, SimulatedPoint};
use rattle_analytic::{asymmetric_orbits, Orbit, OrbitError};
use rattle_event_driven::{SimulationOptions, Start};
use thiserror::Error;

/// Two results agree when they differ by less than this, relatively.
pub const MATCH_TOLERANCE: f64 = 1e-6;

/// Relative nudge applied when starting the simulator on an analytic orbit, so that an
/// unstable orbit is seen to be left rather than held by exact arithmetic.
pub const START_PERTURBATION: f64 = 1e-7;

/// How the two solvers relate at one frequency.
#[derive(Debug, Clone, PartialEq)]
pub enum Class {
    /// The simulator from rest settles on the analytic stable, viable motion (a two-impact orbit
    /// or the linear motion clear of the stops).
    Agreement,
    /// A stable viable analytic motion exists and holds when started on it, but from rest the
    /// simulator goes elsewhere.
    Coexistence,
    /// No stable viable analytic motion; the simulator shows another regime, named.
    Beyond(String),
    /// Anything else, e.g. a "stable" orbit the simulator leaves: explained.
    Contradiction(String),
}

impl Class {
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

/// Differences between a simulated two-impact motion and an analytic orbit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Difference {
    /// `|X_o,sim − X_o| / X_o`.
    pub outer_amplitude: f64,
    /// `|x_sim(0⁻) − x(0⁻)| / |x(0⁻)|`, the state just before the side-1 impact.
    pub impact_state: f64,
    /// `|α_sim − α|` wrapped to `[0, π]`, radians.
    pub phase: f64,
}

impl Difference {
    /// The largest of the relative differences (phase counted relative to π).
    pub fn largest(&self) -> f64 {
        self.outer_amplitude
            .max(self.impact_state)
            .max(self.phase / std::f64::consts::PI)
    }
}

/// Compares a simulated motion with an analytic orbit; `None` unless the simulation is a
/// two-impact motion.
pub fn difference(sim: &SimulatedPoint, orbit: &Orbit) -> Option<Difference> {
    let (state, alpha) = sim.side1_impact?;
    let d = (alpha - orbit.alpha).rem_euclid(std::f64::consts::TAU);
    Some(Difference {
        outer_amplitude: (sim.outer_amplitude - orbit.outer_amplitude).abs()
            / orbit.outer_amplitude,
        impact_state: (state - orbit.state_before_impact).norm() / orbit.state_before_impact.norm(),
        phase: d.min(std::f64::consts::TAU - d),
    })
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
    /// The simulator from rest.
    pub from_rest: SimulatedPoint,
    /// The simulator from each viable orbit.
    pub trials: Vec<Trial>,
    /// Agreement of the from-rest motion with the analytic motion it matches, if any.
    pub difference: Option<Difference>,
    /// The verdict.
    pub class: Class,
    /// What the from-rest motion matched, in words (e.g. `symmetric branch 1`), if anything.
    pub matched: Option<String>,
    /// Whether the analytic prediction "a stable viable orbit exists" matches "the simulator
    /// holds an orbit started on it".
    pub prediction_confirmed: bool,
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

/// Both solvers at `omega`, and the verdict.
pub fn compare(
    scene: &Scene,
    omega: f64,
    options: &SimulationOptions,
) -> Result<ComparedPoint, CompareError> {
    compare_with(scene, omega, options, true)
}

/// [`compare`], optionally without starting the simulator on each viable orbit (then `trials`
/// is empty, and the verdict takes every stable viable orbit as held).
pub fn compare_with(
    scene: &Scene,
    omega: f64,
    options: &SimulationOptions,
    start_on_orbits: bool,
) -> Result<ComparedPoint, CompareError> {
    let analytic = analyse(scene, omega, false)?;
    let from_rest = run(scene, omega, &Start::rest(2), options)?;
    let mut trials = Vec::new();
    for (branch, orbit) in analytic
        .orbits
        .iter()
        .filter(|(_, o)| o.viable && start_on_orbits)
    {
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
    let stable: Vec<&Orbit> = analytic
        .orbits
        .iter()
        .filter(|(_, o)| o.viable && o.stable)
        .map(|(_, o)| o)
        .collect();
    let gap = scene.stops.map(|s| s.gap);
    let linear_clear =
        !analytic.linear.unbounded && gap.is_none_or(|g| analytic.linear.relative_amplitude <= g);
    let damped = scene.unit_model().damping.is_some();
    // The linear motion clear of the stops is a stable candidate only with damping (undamped,
    // its free transients never decay).
    let linear_candidate = linear_clear && damped;

    let mut matched = None;
    let mut difference_from_rest = None;
    for (branch, o) in analytic.orbits.iter().filter(|(_, o)| o.viable && o.stable) {
        if let Some(d) = difference(&from_rest, o) {
            if difference_from_rest.is_none_or(|best: Difference| d.largest() < best.largest()) {
                difference_from_rest = Some(d);
                matched = Some(format!("symmetric branch {branch}"));
            }
        }
    }
    // A two-impact motion off the symmetric orbits: look for it in the β family.
    let asymmetric = from_rest.regime == Regime::TwoImpact
        && symmetric_spacing(&from_rest).is_some_and(|b| (b - 0.5).abs() > 1e-6)
        && !difference_from_rest.is_some_and(|d| d.largest() < MATCH_TOLERANCE);
    if asymmetric {
        if let Some(stops) = scene.stops_model() {
            for o in asymmetric_orbits(
                &scene.unit_model(),
                &stops,
                omega,
                crate::frequency::BETA_SAMPLES,
            ) {
                if let Some(d) = difference(&from_rest, &o) {
                    if d.largest() < MATCH_TOLERANCE {
                        difference_from_rest = Some(d);
                        matched = Some(format!(
                            "asymmetric orbit β = {:.6} (stable: {})",
                            o.beta, o.stable
                        ));
                    }
                }
            }
        }
    }
    let linear_match = linear_candidate
        && from_rest.regime == Regime::NoImpact
        && (from_rest.outer_amplitude - analytic.linear.outer_amplitude).abs()
            < MATCH_TOLERANCE * analytic.linear.outer_amplitude.max(f64::MIN_POSITIVE);
    if linear_match {
        let d = (from_rest.outer_amplitude - analytic.linear.outer_amplitude).abs()
            / analytic.linear.outer_amplitude;
        difference_from_rest = Some(Difference {
            outer_amplitude: d,
            impact_state: 0.0,
            phase: 0.0,
        });
        matched = Some("linear motion clear of the stops".into());
    }
    let rest_match =
        linear_match || difference_from_rest.is_some_and(|d| d.largest() < MATCH_TOLERANCE);

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
    let prediction_confirmed = !start_on_orbits || stable.is_empty() != held_any;

    let class = if !left.is_empty() {
        Class::Contradiction(format!(
            "stable viable orbit (branch {left:?}) left by the simulator started on it"
        ))
    } else if rest_match {
        Class::Agreement
    } else if !stable.is_empty() || linear_candidate {
        Class::Coexistence
    } else if from_rest.regime == Regime::TwoImpact {
        match symmetric_spacing(&from_rest) {
            Some(beta) if (beta - 0.5).abs() > 1e-6 => {
                Class::Beyond(format!("asymmetric two-impact orbit, β = {beta:.4}"))
            }
            _ => Class::Contradiction(
                "the simulator settles on a symmetric two-impact orbit that no stable viable analytic orbit matches".into(),
            ),
        }
    } else {
        Class::Beyond(from_rest.regime.words().to_owned())
    };
    Ok(ComparedPoint {
        analytic,
        from_rest,
        trials,
        difference: difference_from_rest,
        class,
        matched,
        prediction_confirmed,
    })
}

/// For a two-impact motion, the fraction of the period from the side-1 to the side-2 impact.
pub fn symmetric_spacing(sim: &SimulatedPoint) -> Option<f64> {
    let impacts = &sim.steady.cycle_impacts;
    let one = impacts.iter().find(|i| i.side > 0)?;
    let two = impacts.iter().find(|i| i.side < 0)?;
    let period = std::f64::consts::TAU / sim.omega;
    Some((two.phase - one.phase).rem_euclid(period) / period)
}
