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
//! The analytic prediction at a point: the stable, viable symmetric two-impact orbits and, with
//! damping, the linear motion when it stays clear of the stops (the candidates of
//! [`crate::classify`]). The predicted transmittance is the **largest** over the candidates,
//! so a predicted attenuation holds whichever candidate the unit settles on; with no candidate
//! there is no prediction.

use crate::bands::bands;
use crate::classify::difference;
use crate::frequency::analyse;
use crate::json::{csv_row, number};
use crate::scene::{Scene, StopsSpec};
use crate::simulation::{run, stop_name, Regime};
use crate::sweep::{frequencies, parallel_map};
use rattle_event_driven::{SimulationOptions, Start};
use serde_json::{json, Value};
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

/// Periods run per point when nothing can dissipate (no damping, `e = 1`): the simulator calls
/// such a motion `no-dissipation` whatever the cap (unless it repeats), so a short run suffices.
pub const MAP_CONSERVATIVE_PERIODS: u64 = 40;

/// A simulated two-impact (or impact-free) motion matches an analytic candidate when they
/// differ by less than this, relatively: 100 × [`MAP_PERIODICITY_TOLERANCE`], because a motion
/// that repeats to `ε` can still be `ε / (1 − |μ|)` from its orbit (Floquet multiplier `μ`).
pub const MAP_MATCH_TOLERANCE: f64 = 1e-3;

/// A range of values sampled at `count` evenly spaced points, ends included (`count = 1`:
/// `min` alone).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Axis {
    /// First value.
    pub min: f64,
    /// Last value (≥ `min`).
    pub max: f64,
    /// Number of values (≥ 1).
    pub count: usize,
}

impl Axis {
    /// The values, ascending; the last is exactly `max`.
    pub fn values(&self) -> Vec<f64> {
        let mut v = frequencies(self.min, self.max, self.count);
        if let Some(last) = v.last_mut().filter(|_| self.count > 1) {
            *last = self.max;
        }
        v
    }

    /// The spacing between neighbouring values (0 for one value).
    pub fn step(&self) -> f64 {
        if self.count > 1 {
            (self.max - self.min) / (self.count - 1) as f64
        } else {
            0.0
        }
    }
}

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
                ..SimulationOptions::default()
            },
            match_tolerance: MAP_MATCH_TOLERANCE,
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
    /// Impacts per forcing period over the final cycle.
    pub impacts_per_period: f64,
    /// Simulated `X_o = max|u_o|` over the final cycle (or final stretch).
    pub outer_amplitude: f64,
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
    /// Bands `[from, to]` (rad/s) from the samples, as [`crate::bands::bands`] finds them: from
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
/// `restitution`.
pub fn scene_at(scene: &Scene, restitution: f64, gap_over_base_amplitude: f64) -> Scene {
    let mut s = scene.clone();
    s.stops = Some(StopsSpec {
        gap: gap_over_base_amplitude * scene.base.amplitude,
        restitution,
    });
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
    let gap = gap_over_base_amplitude * scene.base.amplitude;
    let damped = scene.unit_model().damping.is_some();
    let mut options = settings.simulation.clone();
    if !damped && restitution == 1.0 {
        options.max_periods = options.max_periods.min(MAP_CONSERVATIVE_PERIODS);
    }
    let mut start = Start::rest(2);
    let mut points = Vec::with_capacity(omegas.len());
    for &omega in omegas {
        let mut point = MapPoint {
            omega,
            regime: None,
            period: None,
            impacts_per_period: f64::NAN,
            outer_amplitude: f64::NAN,
            transmittance_db: None,
            stopped_by: "",
            periods_run: 0,
            analytic_candidates: 0,
            analytic_transmittance_db: None,
            analytic_match: false,
            error: None,
        };
        let sim = match run(&scene, omega, &start, &options) {
            Ok(sim) => {
                start = sim.steady.final_state.clone();
                point.regime = Some(sim.regime);
                point.period = sim.steady.period;
                point.impacts_per_period = sim.steady.impacts_per_period;
                point.outer_amplitude = sim.outer_amplitude;
                point.transmittance_db = sim.transmittance_db;
                point.stopped_by = stop_name(sim.steady.stopped);
                point.periods_run = sim.steady.periods_run;
                Some(sim)
            }
            Err(e) => {
                start = Start::rest(2);
                point.error = Some(format!("simulation: {e}"));
                None
            }
        };
        match analyse(&scene, omega, false) {
            Ok(analytic) => {
                let stable: Vec<_> = analytic
                    .orbits
                    .iter()
                    .map(|(_, o)| o)
                    .filter(|o| o.viable && o.stable)
                    .collect();
                let lin = &analytic.linear;
                let linear_candidate = damped && !lin.unbounded && lin.relative_amplitude <= gap;
                let mut predicted: Vec<f64> = stable.iter().map(|o| o.transmittance_db).collect();
                if linear_candidate {
                    predicted.push(lin.transmittance_db);
                }
                point.analytic_candidates = predicted.len();
                point.analytic_transmittance_db = predicted.into_iter().reduce(f64::max);
                if let Some(sim) = &sim {
                    let orbit_match = stable.iter().any(|o| {
                        difference(sim, o).is_some_and(|d| d.largest() < settings.match_tolerance)
                    });
                    let linear_match = linear_candidate
                        && sim.regime == Regime::NoImpact
                        && (sim.outer_amplitude - lin.outer_amplitude).abs()
                            < settings.match_tolerance * lin.outer_amplitude;
                    point.analytic_match = orbit_match || linear_match;
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

impl Map {
    /// Computes the map of `scene` over `grid`: lines in parallel (rayon), each line up in
    /// frequency with continuation; a progress line on stderr when `progress` and stderr is a
    /// terminal. The result does not depend on the number of threads.
    pub fn run(
        scene: &Scene,
        grid: MapGrid,
        settings: &MapSettings,
        progress: bool,
    ) -> Result<Map, MapError> {
        grid.validate()?;
        if scene.stops.is_none() {
            return Err(MapError::NoStops);
        }
        let omegas = grid.omega.values();
        let pairs: Vec<(f64, f64)> = grid
            .restitution
            .values()
            .into_iter()
            .flat_map(|e| {
                grid.gap_over_base_amplitude
                    .values()
                    .into_iter()
                    .map(move |g| (e, g))
            })
            .collect();
        let lines = parallel_map(&pairs, progress.then_some("map lines"), |&(e, g)| {
            line(scene, e, g, &omegas, settings)
        });
        Ok(Map {
            scene: scene.clone(),
            grid,
            settings: settings.clone(),
            lines,
        })
    }
}

/// Columns of the per-point table, in order; the same names in JSON and CSV.
pub const POINT_COLUMNS: [&str; 15] = [
    "restitution",
    "gap_over_base_amplitude",
    "omega",
    "simulated_regime",
    "simulated_period",
    "simulated_impacts_per_period",
    "simulated_outer_amplitude",
    "simulated_transmittance_db",
    "stopped_by",
    "periods_run",
    "analytic_candidates",
    "analytic_transmittance_db",
    "analytic_match",
    "continued_from",
    "error",
];

/// Columns of the per-line bandwidth table, in order; the same names in JSON and CSV.
pub const BANDWIDTH_COLUMNS: [&str; 14] = [
    "restitution",
    "gap_over_base_amplitude",
    "simulated_bandwidth",
    "simulated_first_band_start",
    "simulated_bands",
    "simulated_attenuating_points",
    "simulated_valued_points",
    "analytic_bandwidth",
    "analytic_first_band_start",
    "analytic_bands",
    "analytic_attenuating_points",
    "analytic_valued_points",
    "unsettled_points",
    "points",
];

fn point_row(line: &MapLine, index: usize) -> Vec<Value> {
    let p = &line.points[index];
    vec![
        number(line.restitution),
        number(line.gap_over_base_amplitude),
        number(p.omega),
        p.regime.map_or(Value::Null, |r| json!(r.name())),
        p.period.map_or(Value::Null, |k| json!(k)),
        number(p.impacts_per_period),
        number(p.outer_amplitude),
        p.transmittance_db.map_or(Value::Null, number),
        if p.stopped_by.is_empty() {
            Value::Null
        } else {
            json!(p.stopped_by)
        },
        json!(p.periods_run),
        json!(p.analytic_candidates),
        p.analytic_transmittance_db.map_or(Value::Null, number),
        json!(p.analytic_match),
        // Where the simulation started: the previous frequency's final state, or rest.
        json!(if index == 0 || line.points[index - 1].regime.is_none() {
            "rest"
        } else {
            "previous-frequency"
        }),
        p.error.as_ref().map_or(Value::Null, |e| json!(e)),
    ]
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

fn bandwidth_row(line: &MapLine, step: f64) -> Vec<Value> {
    let s = line.simulated_bandwidth(step);
    let a = line.analytic_bandwidth(step);
    let unsettled = line
        .points
        .iter()
        .filter(|p| matches!(p.regime, None | Some(Regime::Irregular | Regime::Undecided)))
        .count();
    vec![
        number(line.restitution),
        number(line.gap_over_base_amplitude),
        number(s.bandwidth),
        s.first_band_start.map_or(Value::Null, number),
        json!(bands_text(&s.bands)),
        json!(s.attenuating_points),
        json!(s.valued_points),
        number(a.bandwidth),
        a.first_band_start.map_or(Value::Null, number),
        json!(bands_text(&a.bands)),
        json!(a.attenuating_points),
        json!(a.valued_points),
        json!(unsettled),
        json!(line.points.len()),
    ]
}

fn csv(columns: &[&str], rows: Vec<Vec<Value>>) -> String {
    let mut out = columns.join(",");
    out.push('\n');
    for row in rows {
        out.push_str(&csv_row(row));
        out.push('\n');
    }
    out
}

fn objects(columns: &[&str], rows: Vec<Vec<Value>>) -> Vec<Value> {
    rows.into_iter()
        .map(|row| {
            let mut obj = serde_json::Map::new();
            for (k, v) in columns.iter().zip(row) {
                obj.insert((*k).to_owned(), v);
            }
            Value::Object(obj)
        })
        .collect()
}

impl Map {
    fn point_rows(&self) -> Vec<Vec<Value>> {
        self.lines
            .iter()
            .flat_map(|l| (0..l.points.len()).map(move |i| point_row(l, i)))
            .collect()
    }

    fn bandwidth_rows(&self) -> Vec<Vec<Value>> {
        let step = self.grid.omega.step();
        self.lines.iter().map(|l| bandwidth_row(l, step)).collect()
    }

    /// Every point as CSV: a header of [`POINT_COLUMNS`], one row per `(e, Δ/u_g, ω)`, lines in
    /// the order of [`Map::lines`]; empty cells where a value does not apply or is not finite.
    /// Loads with `pandas.read_csv` or MATLAB `readtable`.
    pub fn points_csv(&self) -> String {
        csv(&POINT_COLUMNS, self.point_rows())
    }

    /// The bandwidth of every line as CSV: a header of [`BANDWIDTH_COLUMNS`], one row per
    /// `(e, Δ/u_g)`.
    pub fn bandwidth_csv(&self) -> String {
        csv(&BANDWIDTH_COLUMNS, self.bandwidth_rows())
    }

    /// What the map was computed with: scene, effects, grid, settings.
    fn header(&self) -> serde_json::Map<String, Value> {
        let axis = |a: &Axis| json!({"min": number(a.min), "max": number(a.max), "count": a.count});
        let mut doc = serde_json::Map::new();
        doc.insert("scene".into(), json!(self.scene));
        doc.insert(
            "effects".into(),
            json!(self
                .scene
                .effects()
                .iter()
                .map(|e| e.name())
                .collect::<Vec<_>>()),
        );
        doc.insert(
            "grid".into(),
            json!({
                "restitution": axis(&self.grid.restitution),
                "gap_over_base_amplitude": axis(&self.grid.gap_over_base_amplitude),
                "omega": axis(&self.grid.omega),
            }),
        );
        doc.insert(
            "settings".into(),
            json!({
                "frequency_order": "ascending, each frequency started from the previous one's final state",
                "periodicity_tolerance": self.settings.simulation.periodicity_tolerance,
                "max_periods": self.settings.simulation.max_periods,
                "max_period_multiplicity": self.settings.simulation.max_period_multiplicity,
                "root_tolerance": self.settings.simulation.root_tolerance,
                "match_tolerance": self.settings.match_tolerance,
            }),
        );
        doc
    }

    /// Every point as one JSON document: the header (scene, effects, grid, settings) and
    /// `results`, one object per point with the keys of [`POINT_COLUMNS`].
    pub fn points_json(&self) -> Value {
        let mut doc = self.header();
        doc.insert("points".into(), json!(self.grid.points()));
        doc.insert(
            "results".into(),
            Value::Array(objects(&POINT_COLUMNS, self.point_rows())),
        );
        Value::Object(doc)
    }

    /// The bandwidth of every line as one JSON document: the header and `results`, one object
    /// per line with the keys of [`BANDWIDTH_COLUMNS`].
    pub fn bandwidth_json(&self) -> Value {
        let mut doc = self.header();
        doc.insert("lines".into(), json!(self.lines.len()));
        doc.insert(
            "results".into(),
            Value::Array(objects(&BANDWIDTH_COLUMNS, self.bandwidth_rows())),
        );
        Value::Object(doc)
    }
}
