//! Maps over restitution, gap and frequency: the regime of the motion and the attenuation
//! bandwidth, simulated and predicted.
//!
//! A map is a grid of lines, one per `(e, Δ/u_g)`; along each line the frequency goes **up**,
//! and the simulator at each frequency starts from the final state of the previous one
//! (continuation; the first frequency starts from rest). Transients are then short, which is
//! what makes 640 000 steady states affordable, but the map follows an up-sweep: where
//! attractors coexist (hysteresis), a unit started from rest may settle elsewhere (see the
//! `bifurcation` figure and `rattle sweep`). Lines are independent and run in parallel; each
//! line is sequential, so the output does not depend on the number of threads.
//!
//! The simulator runs with map-specific settings ([`MapSettings::default`]): the stroboscopic
//! state must repeat to [`MAP_PERIODICITY_TOLERANCE`], at most [`MAP_MAX_PERIODS`] periods per
//! frequency. A point that does not repeat within the cap is reported as `irregular`, with the
//! transmittance of its final stretch (an honest amplitude, though not of a periodic motion);
//! an undamped point whose transients cannot decay is reported as `no-dissipation`, with no
//! transmittance. Neither is hidden.
//!
//! The analytic prediction at a point: the [`candidates`] of [`crate::verdict`] (stable,
//! viable symmetric two-impact orbits and, with damping, the linear motion clear of the stops),
//! chosen by [`Choice::LargestAttracting`]: the **largest** transmittance over the attracting
//! candidates, so a predicted attenuation holds whichever the unit settles on; with no
//! candidate there is no prediction.

use crate::output::{finite, number_list, table_row, writer, Format, Header, TableWriter};
use crate::runs::axis::Axis;
use crate::runs::bands::bands;
use crate::runs::parallel::{for_each_ordered, Grain, Progress};
use crate::runs::shard::Shard;
use crate::scene::analytic::{analyse, OrbitSearch};
use crate::scene::frequency::{FrequencyBounds, FrequencyError};
use crate::scene::lyapunov::chaos;
use crate::scene::simulator::{run, Regime};
use crate::scene::{Scene, StopsSpec};
use crate::verdict::{candidates, difference, predicted_transmittance, Choice, Motion};
use rattle_event_driven::lyapunov::Regime as LyapunovRegime;
use rattle_event_driven::SimulationOptions;
use serde::Serialize;
use std::io::Write;
use thiserror::Error;

/// The stroboscopic state of a map point must repeat to this tolerance, relative to the gap
/// (the sweeps use 1e-9; a map needs the regime and the amplitude to about 1e-4, not the
/// last digits, and lightly damped transients decay by only ~10 % per period).
pub const MAP_PERIODICITY_TOLERANCE: f64 = 1e-5;

/// At most this many forcing periods per map point; a point that has not repeated by then is
/// `irregular` (or `no-dissipation` when undamped and free of impacts), and its transmittance
/// is that of its last periods. Measured on the lightly damped paper unit at e = 0.8 (10 gaps
/// × 100 frequencies): caps of 100, 400 and 1500 periods leave 69 %, 42 % and 38 % of the
/// points irregular, so 400 settles nearly all that settle at all, at a quarter of the cost
/// of 1500 (irregular points run to the cap and dominate the cost).
pub const MAP_MAX_PERIODS: u64 = 400;

/// Forcing periods of the exponents' run at a map point that did not repeat within
/// [`MAP_MAX_PERIODS`]: 200 (20 per batch), fewer than a sweep's 2000 to keep the map's cost
/// in check (irregular points already dominate it; 200 periods plus the 100 of alignment cost
/// about 1.4 × 300 plain periods, about as much as the point's own run to the cap). The
/// uncertainty is larger by `√10` than at 2000 periods, so weakly chaotic points may read
/// `quasi-periodic`: the regime is a cheap first reading, `rattle simulate --lyapunov` the
/// careful one.
pub const MAP_LYAPUNOV_PERIODS: u64 = 200;

/// Periods run per point when nothing can dissipate (no damping, `e = 1`): the simulator calls
/// such a motion `no-dissipation` whatever the cap (unless it repeats), so a short run suffices.
pub const MAP_CONSERVATIVE_PERIODS: u64 = 40;

/// A simulated two-impact (or impact-free) motion matches an analytic candidate when they
/// differ by less than this, relatively: 100 × [`MAP_PERIODICITY_TOLERANCE`], because a motion
/// that repeats to `ε` can still be `ε / (1 − |μ|)` from its orbit (Floquet multiplier `μ`).
pub const MAP_MATCH_TOLERANCE: f64 = 1e-3;

/// The grid of a map: restitution `e`, gap relative to the base amplitude `Δ/u_g`, and
/// angular frequency `ω` (rad/s).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapGrid {
    /// Restitution values, in `[0, 1]`.
    pub restitution: Axis,
    /// `Δ/u_g` values, finite and > 0.
    pub gap_over_base_amplitude: Axis,
    /// Frequencies, rad/s, finite and > 0.
    pub omega: Axis,
}

/// A map grid or setting out of range; the message names the field and its allowed range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MapError {
    /// A field is out of range.
    #[error("{field} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// The field, as on the command line (e.g. `--gap-min`).
        field: &'static str,
        /// The value given.
        value: String,
        /// The allowed range.
        allowed: &'static str,
    },
    /// The scene has no stops: there is no gap or restitution to vary.
    #[error("the scene has no `stops`: a map varies their gap and restitution")]
    NoStops,
    /// A frequency of the grid that the scene cannot be run at in bounded time.
    #[error(transparent)]
    Frequency(#[from] FrequencyError),
}

fn check_axis(
    axis: &Axis,
    names: [&'static str; 3],
    valid: impl Fn(f64) -> bool,
    allowed: &'static str,
) -> Result<(), MapError> {
    let [min, max, count] = names;
    if !valid(axis.min) {
        return Err(MapError::OutOfRange {
            field: min,
            value: axis.min.to_string(),
            allowed,
        });
    }
    if !valid(axis.max) || axis.max < axis.min {
        return Err(MapError::OutOfRange {
            field: max,
            value: axis.max.to_string(),
            allowed: "must be in the same range and ≥ the minimum",
        });
    }
    if axis.count == 0 {
        return Err(MapError::OutOfRange {
            field: count,
            value: "0".into(),
            allowed: "must be ≥ 1",
        });
    }
    Ok(())
}

impl MapGrid {
    /// Checks every axis; errors name the command-line field.
    pub fn validate(&self) -> Result<(), MapError> {
        check_axis(
            &self.restitution,
            ["--restitution-min", "--restitution-max", "--restitutions"],
            |e| (0.0..=1.0).contains(&e),
            "must be in [0, 1]",
        )?;
        check_axis(
            &self.gap_over_base_amplitude,
            ["--gap-min", "--gap-max", "--gaps"],
            |g| g.is_finite() && g > 0.0,
            "must be finite and > 0 (gap Δ over base amplitude u_g)",
        )?;
        check_axis(
            &self.omega,
            ["--omega-min", "--omega-max", "--points"],
            |w| w.is_finite() && w > 0.0,
            "must be finite and > 0 (rad/s)",
        )
    }

    /// Number of `(e, Δ/u_g)` lines.
    pub fn lines(&self) -> usize {
        self.restitution.count * self.gap_over_base_amplitude.count
    }

    /// Number of steady states the map computes.
    pub fn points(&self) -> usize {
        self.restitution.count * self.gap_over_base_amplitude.count * self.omega.count
    }
}

/// The simulator's settings for a map.
#[derive(Debug, Clone, PartialEq)]
pub struct MapSettings {
    /// The simulator's options (periodicity tolerance and period cap included).
    pub simulation: SimulationOptions,
    /// Relative tolerance for "the simulated motion is the analytic candidate".
    pub match_tolerance: f64,
    /// Forcing periods of the exponents' run at a point that did not repeat; `None` computes
    /// no exponents (the largest exponent of periodic points, from their multipliers, needs
    /// the polish, which the map does not run).
    pub lyapunov_periods: Option<u64>,
}

impl Default for MapSettings {
    /// [`MAP_PERIODICITY_TOLERANCE`], [`MAP_MAX_PERIODS`] ([`MAP_CONSERVATIVE_PERIODS`] on
    /// undamped lines with `e = 1`), [`MAP_MATCH_TOLERANCE`]; the other
    /// simulator options at their defaults.
    fn default() -> Self {
        Self {
            simulation: SimulationOptions {
                periodicity_tolerance: MAP_PERIODICITY_TOLERANCE,
                max_periods: MAP_MAX_PERIODS,
                // A map point reports no signature: the Newton polish of each periodic point
                // (a third of the map's time on its short, continued runs) is not run.
                polish: false,
                ..SimulationOptions::default()
            },
            match_tolerance: MAP_MATCH_TOLERANCE,
            lyapunov_periods: Some(MAP_LYAPUNOV_PERIODS),
        }
    }
}

impl MapSettings {
    /// The map's settings with the simulator's `options` (from the command's accuracy
    /// options: contact tolerance, periodicity tolerance, period cap), without the Newton
    /// polish a map does not run; the others as [`MapSettings::default`].
    pub fn with_simulation(options: SimulationOptions) -> MapSettings {
        let defaults = MapSettings::default();
        MapSettings {
            simulation: SimulationOptions {
                polish: defaults.simulation.polish,
                ..options
            },
            ..defaults
        }
    }
}

/// One point of a map.
#[derive(Debug, Clone, PartialEq)]
pub struct MapPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The simulated regime (`None` if the simulation failed).
    pub regime: Option<Regime>,
    /// Least period `p` of a periodic motion, in forcing periods.
    pub period: Option<u32>,
    /// Impacts per forcing period over the final cycle (of a chain: all pairs').
    pub impacts_per_period: f64,
    /// Impacts per forcing period of each contact pair, from the base out (empty if the
    /// simulation failed).
    pub pair_impacts_per_period: Vec<f64>,
    /// Simulated `X_o = max|u_o|` over the final cycle (or final stretch); of a chain, the
    /// last cell's.
    pub outer_amplitude: f64,
    /// Simulated `max|u_o,j|` of every cell, from the base out (empty if the simulation
    /// failed).
    pub cell_outer_amplitudes: Vec<f64>,
    /// Simulated `20 log10(X_o/u_g)`; `None` without dissipation or on failure.
    pub transmittance_db: Option<f64>,
    /// Why the simulation ended (`decided`, `period-cap`, `event-cap`).
    pub stopped_by: &'static str,
    /// Forcing periods simulated at this frequency.
    pub periods_run: u64,
    /// Stable viable analytic candidates (symmetric two-impact orbits, and the linear motion
    /// clear of the stops when damped).
    pub analytic_candidates: usize,
    /// The predicted transmittance: the largest over the candidates; `None` without one.
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

/// One line of a map: fixed restitution and gap, frequencies ascending.
#[derive(Debug, Clone, PartialEq)]
pub struct MapLine {
    /// Restitution `e`.
    pub restitution: f64,
    /// `Δ/u_g`.
    pub gap_over_base_amplitude: f64,
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

/// A whole map.
#[derive(Debug, Clone, PartialEq)]
pub struct Map {
    /// The scene whose gap and restitution the map replaces.
    pub scene: Scene,
    /// The grid.
    pub grid: MapGrid,
    /// The settings.
    pub settings: MapSettings,
    /// Lines, restitution-major (all gaps of the first restitution, then the next).
    pub lines: Vec<MapLine>,
}

/// The scene with its stops replaced by gap `gap_over_base_amplitude · u_g` and restitution
/// `restitution`: of every cell, for a chain.
pub fn scene_at(scene: &Scene, restitution: f64, gap_over_base_amplitude: f64) -> Scene {
    let mut s = scene.clone();
    s.stops = Some(StopsSpec {
        gap: gap_over_base_amplitude * scene.base.amplitude,
        restitution,
    });
    // Every cell of a graded chain takes the map's stops.
    if let Some(chain) = &mut s.chain {
        for cell in chain {
            cell.stops = None;
        }
    }
    s
}

/// One line: up the frequencies at fixed `e` and `Δ/u_g`, each simulation started from the
/// previous one's final state (the first from rest, and again from rest after a failure).
pub fn line(
    scene: &Scene,
    restitution: f64,
    gap_over_base_amplitude: f64,
    omegas: &[f64],
    settings: &MapSettings,
) -> MapLine {
    let scene = scene_at(scene, restitution, gap_over_base_amplitude);
    let damped = scene.is_damped();
    let mut options = settings.simulation.clone();
    if !damped && restitution == 1.0 {
        options.max_periods = options.max_periods.min(MAP_CONSERVATIVE_PERIODS);
    }
    let mut start = crate::scene::simulator::rest(&scene);
    let mut points = Vec::with_capacity(omegas.len());
    for &omega in omegas {
        let mut point = MapPoint {
            omega,
            regime: None,
            period: None,
            impacts_per_period: f64::NAN,
            pair_impacts_per_period: Vec::new(),
            outer_amplitude: f64::NAN,
            cell_outer_amplitudes: Vec::new(),
            transmittance_db: None,
            stopped_by: "",
            periods_run: 0,
            analytic_candidates: 0,
            analytic_transmittance_db: None,
            analytic_match: false,
            error: None,
            largest_exponent: None,
            lyapunov_regime: None,
        };
        let sim = match run(&scene, omega, &start, &options) {
            Ok(sim) => {
                start = sim.steady.final_state.clone();
                point.regime = Some(sim.regime);
                point.period = sim.steady.period;
                point.impacts_per_period = sim.steady.impacts_per_period;
                point.pair_impacts_per_period = sim.pair_impacts_per_period(scene.pair_count());
                point.outer_amplitude = sim.outer_amplitude;
                point.cell_outer_amplitudes = sim.cell_outer_amplitudes();
                point.transmittance_db = sim.transmittance_db;
                point.stopped_by = sim.stopped_by();
                point.periods_run = sim.steady.periods_run;
                if let (Regime::Irregular, Some(periods)) = (sim.regime, settings.lyapunov_periods)
                {
                    match chaos(&scene, &sim, periods, &options) {
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
                start = crate::scene::simulator::rest(&scene);
                point.error = Some(format!("simulation: {e}"));
                None
            }
        };
        match analyse(&scene, omega, OrbitSearch::Symmetric) {
            Ok(analytic) => {
                let offered = candidates(&scene, &analytic);
                let attracting: Vec<_> = offered.iter().filter(|c| c.attracting).collect();
                point.analytic_candidates = attracting.len();
                point.analytic_transmittance_db =
                    predicted_transmittance(&offered, Choice::LargestAttracting);
                if let Some(sim) = &sim {
                    point.analytic_match = attracting.iter().any(|c| match c.motion {
                        Motion::Orbit { branch } => analytic
                            .orbits
                            .iter()
                            .find(|(b, _)| *b == branch)
                            .and_then(|(_, o)| difference(sim, o))
                            .is_some_and(|d| d.largest() < settings.match_tolerance),
                        Motion::Linear => {
                            sim.regime == Regime::NoImpact
                                && (sim.outer_amplitude - c.outer_amplitude).abs()
                                    < settings.match_tolerance * c.outer_amplitude
                        }
                    });
                }
            }
            Err(e) => {
                let message = format!("analytic: {e}");
                point.error = Some(match point.error.take() {
                    Some(first) => format!("{first}; {message}"),
                    None => message,
                });
            }
        }
        points.push(point);
    }
    MapLine {
        restitution,
        gap_over_base_amplitude,
        points,
    }
}

/// Checks `grid` and `scene` for a map.
fn check(scene: &Scene, grid: &MapGrid) -> Result<(), MapError> {
    grid.validate()?;
    if scene.stops.is_none() {
        return Err(MapError::NoStops);
    }
    let bounds = FrequencyBounds::of(scene);
    bounds.check("--omega-min", grid.omega.min)?;
    bounds.check("--omega-max", grid.omega.max)?;
    Ok(())
}

/// The `(e, Δ/u_g)` of every line of `grid`, restitution-major.
fn line_keys(grid: &MapGrid) -> Vec<(f64, f64)> {
    let gaps = grid.gap_over_base_amplitude.values();
    grid.restitution
        .values()
        .into_iter()
        .flat_map(|e| gaps.iter().map(move |&g| (e, g)))
        .collect()
}

/// Computes the map of `scene` over `grid` line by line — lines in parallel, each line up in
/// frequency with continuation — and hands each line to `sink` in the order of
/// [`Map::lines`] as soon as its block of lines is done. The result does not depend on the
/// number of threads.
///
/// # Errors
/// [`StreamError::Map`] for a grid out of range or a scene without stops (before anything is
/// computed); [`StreamError::Sink`] for the first error of `sink`.
pub fn stream<E>(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    progress: &Progress,
    sink: impl FnMut(MapLine) -> Result<(), E>,
) -> Result<(), StreamError<E>> {
    stream_lines(scene, grid, settings, None, progress, sink)
}

/// [`stream`] over the lines of one part of the map only (all of them for `None`): part `K`
/// of `N` is block `K` of `N` nearly equal contiguous blocks of whole lines ([`Shard::range`]
/// over [`MapGrid::lines`]), since each line continues every frequency from the previous one.
/// A part beyond the number of lines has none. The lines are those of the whole map, bit for
/// bit, whatever the number of parts.
///
/// # Errors
/// As [`stream`].
pub fn stream_lines<E>(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    progress: &Progress,
    mut sink: impl FnMut(MapLine) -> Result<(), E>,
) -> Result<(), StreamError<E>> {
    check(scene, grid).map_err(StreamError::Map)?;
    let omegas = grid.omega.values();
    let keys = line_keys(grid);
    let range = shard.map_or(0..keys.len(), |s| s.range(keys.len()));
    for_each_ordered(
        &keys[range],
        Grain::Uneven,
        progress,
        |&(e, g)| line(scene, e, g, &omegas, settings),
        |l| sink(l).map_err(StreamError::Sink),
    )
}

/// A failure of [`stream`].
#[derive(Debug, Error)]
pub enum StreamError<E> {
    /// The grid or the scene.
    #[error(transparent)]
    Map(MapError),
    /// The sink.
    #[error("{0}")]
    Sink(E),
}

impl Map {
    /// Computes the map of `scene` over `grid` (see [`stream`]) and keeps every line.
    ///
    /// # Errors
    /// A grid out of range, or a scene without stops.
    pub fn run(
        scene: &Scene,
        grid: MapGrid,
        settings: &MapSettings,
        progress: &Progress,
    ) -> Result<Map, MapError> {
        let mut lines = Vec::new();
        stream(scene, &grid, settings, progress, |l| {
            lines.push(l);
            Ok::<(), std::convert::Infallible>(())
        })
        .map_err(|e| match e {
            StreamError::Map(e) => e,
            StreamError::Sink(never) => match never {},
        })?;
        Ok(Map {
            scene: scene.clone(),
            grid,
            settings: settings.clone(),
            lines,
        })
    }

    /// Every point's row, lines in order.
    pub fn point_rows(&self) -> impl Iterator<Item = MapPointRow> + '_ {
        self.lines.iter().flat_map(MapPointRow::of_line)
    }

    /// Every line's bandwidth row.
    pub fn bandwidth_rows(&self) -> impl Iterator<Item = BandwidthRow> + '_ {
        let step = self.grid.omega.step();
        self.lines.iter().map(move |l| BandwidthRow::new(l, step))
    }
}

table_row! {
    /// One point of a map.
    pub struct MapPointRow {
        /// Restitution `e`.
        pub restitution: Option<f64>,
        /// `Δ/u_g`.
        pub gap_over_base_amplitude: Option<f64>,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// Simulated regime (empty when the simulation failed).
        pub simulated_regime: Option<&'static str>,
        /// Least period of a periodic motion, forcing periods.
        pub simulated_period: Option<u32>,
        /// Impacts per forcing period over the final cycle (of a chain: all pairs').
        pub simulated_impacts_per_period: Option<f64>,
        /// Impacts per forcing period of each contact pair, from the base out: a list,
        /// `;`-separated ([`number_list`]).
        pub simulated_pair_impacts_per_period: Option<String>,
        /// Simulated `X_o`, m (of a chain: the last cell's).
        pub simulated_outer_amplitude: Option<f64>,
        /// Simulated `max|u_o,j|` of every cell, from the base out, m: a list, `;`-separated
        /// ([`number_list`]).
        pub simulated_cell_outer_amplitudes: Option<String>,
        /// Simulated `T`, dB.
        pub simulated_transmittance_db: Option<f64>,
        /// Why the simulation ended.
        pub stopped_by: Option<&'static str>,
        /// Forcing periods simulated at this frequency.
        pub periods_run: u64,
        /// Attracting analytic candidates.
        pub analytic_candidates: usize,
        /// The predicted `T`, dB (largest over the attracting candidates).
        pub analytic_transmittance_db: Option<f64>,
        /// Whether the simulated motion is one of the candidates.
        pub analytic_match: bool,
        /// Where the simulation started: `rest` or `previous-frequency`.
        pub continued_from: &'static str,
        /// A failure of either solver.
        pub error: Option<String>,
        /// The largest Lyapunov exponent of a point that did not repeat, 1/s.
        pub largest_exponent: Option<f64>,
        /// Its regime: `chaotic`, `quasi-periodic` or `unsettled`.
        pub lyapunov_regime: Option<&'static str>,
    }
}

impl MapPointRow {
    /// The rows of one line, by ascending frequency.
    pub fn of_line(line: &MapLine) -> impl Iterator<Item = MapPointRow> + '_ {
        line.points
            .iter()
            .enumerate()
            .map(move |(i, p)| MapPointRow {
                restitution: finite(line.restitution),
                gap_over_base_amplitude: finite(line.gap_over_base_amplitude),
                omega: finite(p.omega),
                simulated_regime: p.regime.map(Regime::name),
                simulated_period: p.period,
                simulated_impacts_per_period: finite(p.impacts_per_period),
                simulated_pair_impacts_per_period: number_list(&p.pair_impacts_per_period),
                simulated_outer_amplitude: finite(p.outer_amplitude),
                simulated_cell_outer_amplitudes: number_list(&p.cell_outer_amplitudes),
                simulated_transmittance_db: p.transmittance_db.and_then(finite),
                stopped_by: (!p.stopped_by.is_empty()).then_some(p.stopped_by),
                periods_run: p.periods_run,
                analytic_candidates: p.analytic_candidates,
                analytic_transmittance_db: p.analytic_transmittance_db.and_then(finite),
                analytic_match: p.analytic_match,
                continued_from: if i == 0 || line.points[i - 1].regime.is_none() {
                    "rest"
                } else {
                    "previous-frequency"
                },
                error: p.error.clone(),
                largest_exponent: p.largest_exponent.and_then(finite),
                lyapunov_regime: p.lyapunov_regime.map(LyapunovRegime::name),
            })
    }
}

table_row! {
    /// The attenuation of one `(e, Δ/u_g)` line of a map.
    pub struct BandwidthRow {
        /// Restitution `e`.
        pub restitution: Option<f64>,
        /// `Δ/u_g`.
        pub gap_over_base_amplitude: Option<f64>,
        /// Simulated bandwidth, rad/s.
        pub simulated_bandwidth: Option<f64>,
        /// First simulated frequency with `T < 0 dB`.
        pub simulated_first_band_start: Option<f64>,
        /// Simulated bands, `from-to;…` (rad/s).
        pub simulated_bands: String,
        /// Simulated samples with `T < 0 dB`.
        pub simulated_attenuating_points: usize,
        /// Simulated samples with a value.
        pub simulated_valued_points: usize,
        /// Predicted bandwidth, rad/s.
        pub analytic_bandwidth: Option<f64>,
        /// First predicted frequency with `T < 0 dB`.
        pub analytic_first_band_start: Option<f64>,
        /// Predicted bands, `from-to;…` (rad/s).
        pub analytic_bands: String,
        /// Predicted samples with `T < 0 dB`.
        pub analytic_attenuating_points: usize,
        /// Samples with a prediction.
        pub analytic_valued_points: usize,
        /// Points not settled (irregular, no dissipation, failed).
        pub unsettled_points: usize,
        /// Points on the line.
        pub points: usize,
    }
}

impl BandwidthRow {
    /// The row of `line`, frequencies `step` apart.
    pub fn new(line: &MapLine, step: f64) -> BandwidthRow {
        let s = line.simulated_bandwidth(step);
        let a = line.analytic_bandwidth(step);
        let unsettled = line
            .points
            .iter()
            .filter(|p| {
                matches!(
                    p.regime,
                    None | Some(Regime::Irregular | Regime::NoDissipation)
                )
            })
            .count();
        BandwidthRow {
            restitution: finite(line.restitution),
            gap_over_base_amplitude: finite(line.gap_over_base_amplitude),
            simulated_bandwidth: finite(s.bandwidth),
            simulated_first_band_start: s.first_band_start.and_then(finite),
            simulated_bands: bands_text(&s.bands),
            simulated_attenuating_points: s.attenuating_points,
            simulated_valued_points: s.valued_points,
            analytic_bandwidth: finite(a.bandwidth),
            analytic_first_band_start: a.first_band_start.and_then(finite),
            analytic_bands: bands_text(&a.bands),
            analytic_attenuating_points: a.attenuating_points,
            analytic_valued_points: a.valued_points,
            unsettled_points: unsettled,
            points: line.points.len(),
        }
    }
}

/// Bands as text: `1.5-2.2;2.9-inf` (rad/s), empty when there is none.
pub fn bands_text(bands: &[(f64, f64)]) -> String {
    bands
        .iter()
        .map(|(a, b)| {
            if b.is_infinite() {
                format!("{a}-inf")
            } else {
                format!("{a}-{b}")
            }
        })
        .collect::<Vec<_>>()
        .join(";")
}

/// An axis as written in a map's header.
#[derive(Serialize)]
struct AxisRecord {
    min: Option<f64>,
    max: Option<f64>,
    count: usize,
}

impl From<&Axis> for AxisRecord {
    fn from(a: &Axis) -> Self {
        AxisRecord {
            min: finite(a.min),
            max: finite(a.max),
            count: a.count,
        }
    }
}

/// What a map was computed with, as written in its header.
#[derive(Serialize)]
struct SettingsRecord {
    frequency_order: &'static str,
    periodicity_tolerance: f64,
    max_periods: u64,
    max_period_multiplicity: u32,
    root_tolerance: f64,
    match_tolerance: f64,
}

/// The header of a map's JSON tables: scene, effects, grid, settings, `count` rows of the
/// whole map under the key `counted` (`points` or `lines`) and, for a part, which shard it is.
pub fn header(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    counted: &str,
    count: usize,
    shard: Option<Shard>,
) -> Header {
    #[derive(Serialize)]
    struct GridRecord {
        restitution: AxisRecord,
        gap_over_base_amplitude: AxisRecord,
        omega: AxisRecord,
    }
    let mut h = Header::default();
    h.push("scene", scene);
    h.push("effects", &scene.effect_names());
    h.push(
        "grid",
        &GridRecord {
            restitution: (&grid.restitution).into(),
            gap_over_base_amplitude: (&grid.gap_over_base_amplitude).into(),
            omega: (&grid.omega).into(),
        },
    );
    let sim = &settings.simulation;
    h.push(
        "settings",
        &SettingsRecord {
            frequency_order:
                "ascending, each frequency started from the previous one's final state",
            periodicity_tolerance: sim.periodicity_tolerance,
            max_periods: sim.max_periods,
            max_period_multiplicity: sim.max_period_multiplicity,
            root_tolerance: sim.root_tolerance,
            match_tolerance: settings.match_tolerance,
        },
    );
    h.push(counted, &count);
    if let Some(s) = shard {
        h.push("shard", &s);
    }
    h
}

/// A failure of [`write_map`]; each names the table it concerns.
#[derive(Debug, Error)]
pub enum WriteMapError {
    /// The grid or the scene (nothing was computed).
    #[error(transparent)]
    Map(MapError),
    /// The points table could not be written.
    #[error("{0}")]
    Points(std::io::Error),
    /// The bandwidth table could not be written.
    #[error("{0}")]
    Bandwidth(std::io::Error),
}

/// Computes the map (or one part of it, [`stream_lines`]) and writes its points to `points`,
/// one row per point as each block of lines is done, and, if given, each line's bandwidth to
/// `bandwidth` at the end: the tables `rattle map --out … --bandwidth-out …` writes, with
/// the part named in a JSON header's `shard` or a CSV part's first line, `# shard K/N of P
/// points` (`L lines` for the bandwidth), so that [`crate::runs::shard::merge`] joins the
/// parts into exactly the whole map's tables.
///
/// # Errors
/// [`WriteMapError`]: the grid or scene (before anything is computed or written), or the
/// first failure to write either table.
pub fn write_map<P: Write, B: Write>(
    scene: &Scene,
    grid: &MapGrid,
    settings: &MapSettings,
    shard: Option<Shard>,
    points: (Format, P),
    bandwidth: Option<(Format, B)>,
    progress: &Progress,
) -> Result<(), WriteMapError> {
    check(scene, grid).map_err(WriteMapError::Map)?;
    let preamble = |total: usize, unit: &str| shard.map(|s| s.csv_preamble_of(total, unit));
    let mut table: Box<dyn TableWriter<MapPointRow>> = writer(
        points.0,
        points.1,
        &header(scene, grid, settings, "points", grid.points(), shard),
        preamble(grid.points(), "points").as_deref(),
    )
    .map_err(WriteMapError::Points)?;
    let step = grid.omega.step();
    let mut bandwidth_rows = Vec::new();
    stream_lines(scene, grid, settings, shard, progress, |line| {
        for row in MapPointRow::of_line(&line) {
            table.row(&row)?;
        }
        if bandwidth.is_some() {
            bandwidth_rows.push(BandwidthRow::new(&line, step));
        }
        Ok(())
    })
    .map_err(|e| match e {
        StreamError::Map(e) => WriteMapError::Map(e),
        StreamError::Sink(e) => WriteMapError::Points(e),
    })?;
    table.finish().map_err(WriteMapError::Points)?;
    if let Some((format, out)) = bandwidth {
        let mut table: Box<dyn TableWriter<BandwidthRow>> = writer(
            format,
            out,
            &header(scene, grid, settings, "lines", grid.lines(), shard),
            preamble(grid.lines(), "lines").as_deref(),
        )
        .map_err(WriteMapError::Bandwidth)?;
        for row in &bandwidth_rows {
            table.row(row).map_err(WriteMapError::Bandwidth)?;
        }
        table.finish().map_err(WriteMapError::Bandwidth)?;
    }
    Ok(())
}
