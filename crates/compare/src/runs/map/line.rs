//! One line of a map: up the frequencies on one line's scene, each simulation started from the
//! previous one's final state, the analytic prediction beside each point; and the line's
//! attenuation bandwidth.
//!
//! A line runs the solvers of its scene's form: on a unit or a chain the simulator of the
//! cells and the candidates of [`crate::verdict`] (stable viable symmetric two-impact orbits
//! and the linear motion clear of the stops); on a structure the simulator of the structure and
//! the one prediction its linear model gives cheaply, the linear steady state where it keeps
//! every stop clear and the structure's free motion decays ([`structure_prediction`]).

use super::{MapSettings, MAP_CONSERVATIVE_PERIODS};
use crate::runs::bands::bands;
use crate::scene::analytic::{analyse, OrbitSearch};
use crate::scene::lyapunov::{chaos, structure_chaos, Chaos, SpectrumError};
use crate::scene::simulator::{run, run_structure, Regime, SimulateError, SimulatedPoint};
use crate::scene::structure::Structure;
use crate::scene::{AnyScene, Scene};
use crate::verdict::{candidates, difference, predicted_transmittance, Choice, Motion};
use rattle_analytic::transmittance_db;
use rattle_analytic::{LinearModel, ModelError};
use rattle_event_driven::Regime as LyapunovRegime;
use rattle_event_driven::{SimulationOptions, Start};

/// A mode of a structure's free motion decays when the real part of its eigenvalue is below
/// this fraction of the largest eigenvalue's modulus, below zero: an undamped mode's real part
/// rounds to about 1e-15 of it, while a damping ratio `ζ` puts it at `ζ ω_n`, far beyond for
/// any dashpot a scene states.
pub const DECAY_RATE: f64 = 1e-10;

/// One point of a map.
#[derive(Debug, Clone, PartialEq)]
pub struct MapPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The simulated regime (`None` if the simulation failed).
    pub regime: Option<Regime>,
    /// Least period `p` of a periodic motion, in forcing periods.
    pub period: Option<u32>,
    /// Impacts per forcing period over the final cycle (of a chain or a structure: all
    /// pairs').
    pub impacts_per_period: f64,
    /// Impacts per forcing period of each contact pair, from the base out (of a structure: of
    /// each stop, in file order); empty if the simulation failed.
    pub pair_impacts_per_period: Vec<f64>,
    /// Simulated `X_o = max|u_o|` over the final cycle (or final stretch); of a chain, the
    /// last cell's; of a structure, the observed body's.
    pub outer_amplitude: f64,
    /// Simulated `max|u_o,j|` of every cell, from the base out; of a structure, `max|u|` of
    /// every body, in the scene's order (empty if the simulation failed).
    pub amplitudes: Vec<f64>,
    /// Simulated `20 log10(X_o/u_g)`; `None` without dissipation, without a moving base or on
    /// failure.
    pub transmittance_db: Option<f64>,
    /// Why the simulation ended (`decided`, `period-cap`, `event-cap`).
    pub stopped_by: &'static str,
    /// Forcing periods simulated at this frequency.
    pub periods_run: u64,
    /// Attracting analytic candidates (on a unit or chain: stable viable symmetric two-impact
    /// orbits, and the linear motion clear of the stops when damped; on a structure: the linear
    /// steady state clear of every stop when the structure's free motion decays).
    pub analytic_candidates: usize,
    /// The predicted transmittance: the largest over the candidates; `None` without one, or
    /// without a moving base.
    pub analytic_transmittance_db: Option<f64>,
    /// Whether the simulated motion is one of the candidates (to the match tolerance).
    pub analytic_match: bool,
    /// A failure of either solver at this point.
    pub error: Option<String>,
    /// The largest Lyapunov exponent of a point that did not repeat, 1/s.
    pub largest_exponent: Option<f64>,
    /// Its regime: chaotic, quasi-periodic or unsettled.
    pub lyapunov_regime: Option<LyapunovRegime>,
}

impl MapPoint {
    /// The point at `omega` before anything is computed.
    fn empty(omega: f64) -> MapPoint {
        MapPoint {
            omega,
            regime: None,
            period: None,
            impacts_per_period: f64::NAN,
            pair_impacts_per_period: Vec::new(),
            outer_amplitude: f64::NAN,
            amplitudes: Vec::new(),
            transmittance_db: None,
            stopped_by: "",
            periods_run: 0,
            analytic_candidates: 0,
            analytic_transmittance_db: None,
            analytic_match: false,
            error: None,
            largest_exponent: None,
            lyapunov_regime: None,
        }
    }

    /// Appends `message` to the point's error.
    fn add_error(&mut self, message: String) {
        self.error = Some(match self.error.take() {
            Some(first) => format!("{first}; {message}"),
            None => message,
        });
    }
}

/// One line of a map: fixed values of its two axes, frequencies ascending.
#[derive(Debug, Clone, PartialEq)]
pub struct MapLine {
    /// The x axis's value (the restitution `e` on the default axes).
    pub x: f64,
    /// The y axis's value (`Δ/u_g` on the default axes).
    pub y: f64,
    /// The points, by ascending frequency.
    pub points: Vec<MapPoint>,
}

/// The attenuation of one line: where `T < 0 dB`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bandwidth {
    /// Bands `[from, to]` (rad/s) from the samples, as [`crate::runs::bands::bands`] finds them: from
    /// the first to the last sample of each run below 0 dB; `to = ∞` when the run reaches the
    /// last frequency. A point without a value ends a band.
    pub bands: Vec<(f64, f64)>,
    /// The attenuation bandwidth, rad/s: the number of samples with `T < 0 dB` times the
    /// frequency step (each sample stands for one step of the swept range).
    pub bandwidth: f64,
    /// The first frequency with `T < 0 dB`, if any.
    pub first_band_start: Option<f64>,
    /// Samples with `T < 0 dB`.
    pub attenuating_points: usize,
    /// Samples with a value (simulated: a transmittance; analytic: a prediction).
    pub valued_points: usize,
}

impl Bandwidth {
    /// The attenuation of `values` (dB, `None` = no value) sampled at ascending `omegas`
    /// spaced `step` apart.
    pub fn of(omegas: &[f64], values: &[Option<f64>], step: f64) -> Bandwidth {
        let below: Vec<usize> = (0..omegas.len())
            .filter(|&i| values[i].is_some_and(|t| t < 0.0))
            .collect();
        Bandwidth {
            bands: bands(omegas, values, None),
            bandwidth: below.len() as f64 * step,
            first_band_start: below.first().map(|&i| omegas[i]),
            attenuating_points: below.len(),
            valued_points: values.iter().filter(|v| v.is_some()).count(),
        }
    }
}

impl MapLine {
    /// The simulated attenuation along this line (`step`: the frequency step).
    pub fn simulated_bandwidth(&self, step: f64) -> Bandwidth {
        let (w, t): (Vec<f64>, Vec<Option<f64>>) = self
            .points
            .iter()
            .map(|p| (p.omega, p.transmittance_db))
            .unzip();
        Bandwidth::of(&w, &t, step)
    }

    /// The predicted attenuation along this line.
    pub fn analytic_bandwidth(&self, step: f64) -> Bandwidth {
        let (w, t): (Vec<f64>, Vec<Option<f64>>) = self
            .points
            .iter()
            .map(|p| (p.omega, p.analytic_transmittance_db))
            .unzip();
        Bandwidth::of(&w, &t, step)
    }
}

/// The solvers a line runs: its scene's simulator and analytic prediction.
enum Solvers<'a> {
    /// A unit or a chain.
    Cells(&'a Scene),
    /// A structure, with its linear model (or why it has none) and whether its free motion
    /// decays.
    Structure {
        structure: &'a Structure,
        linear: Box<Result<LinearModel, String>>,
        decays: bool,
    },
}

impl Solvers<'_> {
    fn of(scene: &AnyScene) -> Solvers<'_> {
        match scene {
            AnyScene::Cells(cells) => Solvers::Cells(cells),
            AnyScene::Structure(form) => {
                let structure = &form.structure;
                let linear = structure.analytic_model().map_err(|e| e.to_string());
                let decays = linear
                    .as_ref()
                    .is_ok_and(|model| free_motion_decays(structure, model));
                Solvers::Structure {
                    structure,
                    linear: Box::new(linear),
                    decays,
                }
            }
        }
    }

    /// The start at rest.
    fn rest(&self) -> Start {
        match self {
            Solvers::Cells(scene) => crate::scene::simulator::rest(scene),
            Solvers::Structure { structure, .. } => structure.rest(),
        }
    }

    /// Whether nothing can dissipate: no dashpot, and every stop elastic (or none).
    fn conservative(&self) -> bool {
        match self {
            Solvers::Cells(scene) => {
                !scene.is_damped()
                    && scene
                        .cell_scenes()
                        .iter()
                        .all(|cell| cell.stops.is_none_or(|s| s.restitution == Some(1.0)))
            }
            Solvers::Structure { structure, .. } => {
                !structure.is_damped()
                    && structure
                        .stops
                        .iter()
                        .all(|s| s.law.restitution() == Some(1.0))
            }
        }
    }

    fn run(
        &self,
        omega: f64,
        start: &Start,
        options: &SimulationOptions,
    ) -> Result<SimulatedPoint, SimulateError> {
        match self {
            Solvers::Cells(scene) => run(scene, omega, start, options),
            Solvers::Structure { structure, .. } => run_structure(structure, omega, start, options),
        }
    }

    /// The point's simulated columns from `sim`.
    fn simulated(&self, sim: &SimulatedPoint, point: &mut MapPoint) {
        let (pairs, amplitudes) = match self {
            Solvers::Cells(scene) => (scene.pair_count(), sim.cell_outer_amplitudes()),
            Solvers::Structure { structure, .. } => {
                (structure.stops.len(), sim.steady.amplitudes.clone())
            }
        };
        point.regime = Some(sim.regime);
        point.period = sim.steady.period;
        point.impacts_per_period = sim.steady.impacts_per_period;
        point.pair_impacts_per_period = sim.pair_impacts_per_period(pairs);
        point.outer_amplitude = sim.outer_amplitude;
        point.amplitudes = amplitudes;
        point.transmittance_db = sim.transmittance_db;
        point.stopped_by = sim.stopped_by();
        point.periods_run = sim.steady.periods_run;
    }

    fn chaos(
        &self,
        sim: &SimulatedPoint,
        periods: u64,
        options: &SimulationOptions,
    ) -> Result<Chaos, SpectrumError> {
        match self {
            Solvers::Cells(scene) => chaos(scene, sim, periods, options),
            Solvers::Structure { structure, .. } => {
                structure_chaos(structure, sim, periods, options)
            }
        }
    }

    /// The point's analytic columns at `omega`, `sim` the simulated motion if any.
    ///
    /// # Errors
    /// The analytic solver's failure, in words.
    fn predict(
        &self,
        omega: f64,
        sim: Option<&SimulatedPoint>,
        match_tolerance: f64,
        point: &mut MapPoint,
    ) -> Result<(), String> {
        match self {
            Solvers::Cells(scene) => cells_prediction(scene, omega, sim, match_tolerance, point)
                .map_err(|e| e.to_string()),
            Solvers::Structure {
                structure,
                linear,
                decays,
            } => {
                let model = linear.as_ref().as_ref().map_err(Clone::clone)?;
                structure_prediction(
                    structure,
                    model,
                    *decays,
                    omega,
                    sim,
                    match_tolerance,
                    point,
                )
            }
        }
    }
}

/// On a unit or a chain: the attracting candidates, the largest transmittance over them, and
/// whether the simulated motion is one of them.
fn cells_prediction(
    scene: &Scene,
    omega: f64,
    sim: Option<&SimulatedPoint>,
    match_tolerance: f64,
    point: &mut MapPoint,
) -> Result<(), rattle_analytic::OrbitError> {
    let analytic = analyse(scene, omega, OrbitSearch::Symmetric)?;
    let offered = candidates(scene, &analytic);
    let attracting: Vec<_> = offered.iter().filter(|c| c.attracting).collect();
    point.analytic_candidates = attracting.len();
    point.analytic_transmittance_db = predicted_transmittance(&offered, Choice::LargestAttracting);
    if let Some(sim) = sim {
        point.analytic_match = attracting.iter().any(|c| match c.motion {
            Motion::Orbit { branch } => analytic
                .orbits
                .iter()
                .find(|(b, _)| *b == branch)
                .and_then(|(_, o)| difference(sim, o))
                .is_some_and(|d| d.largest() < match_tolerance),
            Motion::Linear => {
                sim.regime == Regime::NoImpact
                    && (sim.outer_amplitude - c.outer_amplitude).abs()
                        < match_tolerance * c.outer_amplitude
            }
        });
    }
    Ok(())
}

/// On a structure: the linear steady state is the one candidate, where some member of its
/// family keeps every stop clear ([`LinearModel::clear_family`]) and the structure's free
/// motion decays (`decays`), so that it attracts; its transmittance is the observed body's
/// against `u_g` (none without a moving base). No impacting motion is predicted: the analytic
/// solver finds an impacting orbit of a structure only from a guess of its impact sequence,
/// which here would be the simulator's own. At an undamped resonance there is no linear motion
/// and no candidate.
///
/// # Errors
/// The linear model's failure other than an undamped resonance, in words.
fn structure_prediction(
    structure: &Structure,
    model: &LinearModel,
    decays: bool,
    omega: f64,
    sim: Option<&SimulatedPoint>,
    match_tolerance: f64,
    point: &mut MapPoint,
) -> Result<(), String> {
    let family = match model.clear_family(omega) {
        Ok(family) => family,
        Err(ModelError::Unbounded { .. }) => return Ok(()),
        Err(e) => return Err(e.to_string()),
    };
    if !(family.exists && decays) {
        return Ok(());
    }
    let Some(&amplitude) = family.state.amplitudes().as_slice().get(structure.observe) else {
        return Ok(());
    };
    point.analytic_candidates = 1;
    point.analytic_transmittance_db = structure
        .base_amplitude
        .map(|ug| transmittance_db(amplitude, ug));
    point.analytic_match = sim.is_some_and(|sim| {
        sim.regime == Regime::NoImpact
            && (sim.outer_amplitude - amplitude).abs() < match_tolerance * amplitude
    });
    Ok(())
}

/// Whether every mode of the structure's free motion decays: a dashpot somewhere, no rigid
/// mode (a floating body drifts by any offset), and every eigenvalue of the first-order system
/// with a real part below zero by [`DECAY_RATE`] of the largest modulus (an undamped mode the
/// dashpots do not reach keeps any transient).
fn free_motion_decays(structure: &Structure, model: &LinearModel) -> bool {
    if !structure.is_damped() || structure.has_floating() {
        return false;
    }
    let eigenvalues = model.system_matrix().complex_eigenvalues();
    let scale = eigenvalues.iter().map(|l| l.norm()).fold(0.0, f64::max);
    eigenvalues.iter().all(|l| l.re < -DECAY_RATE * scale)
}

/// One line: up the frequencies `omegas` on the line's `scene` (its axes at `x` and `y`
/// already set), each simulation started from the previous one's final state (the first from
/// rest, and again from rest after a failure), the analytic prediction beside every point.
pub fn line(scene: &AnyScene, x: f64, y: f64, omegas: &[f64], settings: &MapSettings) -> MapLine {
    let solvers = Solvers::of(scene);
    let mut options = settings.simulation.clone();
    if solvers.conservative() {
        options.max_periods = options.max_periods.min(MAP_CONSERVATIVE_PERIODS);
    }
    let mut start = solvers.rest();
    let mut points = Vec::with_capacity(omegas.len());
    for &omega in omegas {
        let mut point = MapPoint::empty(omega);
        let sim = match solvers.run(omega, &start, &options) {
            Ok(sim) => {
                start = sim.steady.final_state.clone();
                solvers.simulated(&sim, &mut point);
                if let (Regime::Irregular, Some(periods)) = (sim.regime, settings.lyapunov_periods)
                {
                    match solvers.chaos(&sim, periods, &options) {
                        Ok(c) => {
                            point.largest_exponent = c.largest_exponent;
                            point.lyapunov_regime = c.regime;
                        }
                        Err(e) => point.error = Some(format!("lyapunov: {e}")),
                    }
                }
                Some(sim)
            }
            Err(e) => {
                start = solvers.rest();
                point.error = Some(format!("simulation: {e}"));
                None
            }
        };
        if let Err(e) = solvers.predict(omega, sim.as_ref(), settings.match_tolerance, &mut point) {
            point.add_error(format!("analytic: {e}"));
        }
        points.push(point);
    }
    MapLine { x, y, points }
}
