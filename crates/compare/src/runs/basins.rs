//! Basins of attraction: a grid of starts at rest (outer and inner displacement), each run to
//! its steady state and coloured by the attractor it reaches.
//!
//! The plane of starts at rest is the one a unit meets when released from a displaced
//! position (the base at its phase 0): both displacements are free, both velocities zero. An
//! attractor is identified by its impact signature (from the sides of the final cycle's
//! impacts, no Newton polish) and its amplitude `X_o`, to [`BASIN_AMPLITUDE_TOLERANCE`]; the
//! motions that do not repeat within the cap form one class, as do those without dissipation
//! and those that stick (by status). Attractors are numbered by first appearance in grid order
//! (the inner displacement fastest), so the grid and its numbers do not depend on the number
//! of threads.
//!
//! A start converging slowly on a periodic attractor would run to the cap before it repeats
//! to the periodicity tolerance; so the periodic attractors of a coarse reference grid
//! ([`BASIN_REFERENCE_STRIDE`]) are found first, and a start is attributed to one of them as
//! soon as its stroboscopic state comes within [`BASIN_PROXIMITY`] of that attractor's, checked
//! at every section `t = kT` by the simulator's section watch, which ends the run there.

use crate::output::{
    finite, table_row, writer, CsvWriter, Format, Header, JsonWriter, Row, TableWriter,
};
use crate::runs::axis::Axis;
use crate::runs::map::MAP_PERIODICITY_TOLERANCE;
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::runs::shard::{check_cover, Shard};
use crate::scene::simulator::{run_watched, SimulatedPoint};
use crate::scene::Scene;
use nalgebra::DVector;
use rattle_analytic::Signature;
use rattle_event_driven::{SimulationOptions, Start, Status, Stop};
use serde::{Deserialize, Serialize};
use std::io::Write;
use thiserror::Error;

/// Periods each start runs at most: a start that has not repeated by then is `not periodic`.
/// From rest the paper's unit at the coexistence frequency ω = 1.86 settles within 150–212
/// periods (to 1e-5 and 1e-9); twice that leaves slower starts a margin while bounding the
/// cost of the motions that never repeat.
pub const BASIN_MAX_PERIODS: u64 = 400;

/// Two periodic motions of one signature are one attractor when their amplitudes `X_o`
/// differ by less than this, relative to the larger: far above the amplitude's error at the
/// periodicity tolerance ([`MAP_PERIODICITY_TOLERANCE`] relative to the gap), far below the
/// difference between coexisting orbits (tens of percent on the paper's unit).
pub const BASIN_AMPLITUDE_TOLERANCE: f64 = 1e-3;

/// The simulator's options for basins: the map's periodicity tolerance, the
/// [`BASIN_MAX_PERIODS`] cap, no Newton polish.
pub fn basin_options() -> SimulationOptions {
    SimulationOptions {
        periodicity_tolerance: MAP_PERIODICITY_TOLERANCE,
        max_periods: BASIN_MAX_PERIODS,
        polish: false,
        ..SimulationOptions::default()
    }
}

/// The plane of starts: outer and inner displacement at rest, at time 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BasinGrid {
    /// Outer displacement `u_o` at the start, m.
    pub outer: Axis,
    /// Inner displacement `u_i` at the start, m.
    pub inner: Axis,
}

/// A basins grid out of range; the message names the command-line field and its range.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum BasinsError {
    /// A side's ends are not finite or not in order.
    #[error("--{side}-min = {min}, --{side}-max = {max}: must be finite with min ≤ max")]
    Side {
        /// `outer` or `inner`.
        side: &'static str,
        /// The smallest displacement given.
        min: f64,
        /// The largest displacement given.
        max: f64,
    },
    /// No starts per side.
    #[error("--points must be ≥ 1")]
    NoPoints,
}

impl BasinGrid {
    /// The grid of `points × points` starts with outer displacements over `outer` and inner
    /// over `inner` (each `(min, max)`, m), as `rattle basins` takes them.
    ///
    /// # Errors
    /// [`BasinsError`] for no points, or a side not finite or with `min > max`.
    pub fn new(
        outer: (f64, f64),
        inner: (f64, f64),
        points: usize,
    ) -> Result<BasinGrid, BasinsError> {
        if points == 0 {
            return Err(BasinsError::NoPoints);
        }
        let axis = |side: &'static str, (min, max): (f64, f64)| {
            if min.is_finite() && max.is_finite() && min <= max {
                Ok(Axis::new(min, max, points))
            } else {
                Err(BasinsError::Side { side, min, max })
            }
        };
        Ok(BasinGrid {
            outer: axis("outer", outer)?,
            inner: axis("inner", inner)?,
        })
    }

    /// Number of starts.
    pub fn starts(&self) -> usize {
        self.outer.count * self.inner.count
    }
}

/// The kind of motion a start ends on (as JSON in a part's header, [`write_basins`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Attractor {
    /// A periodic motion: its canonical signature (`None` without impacts) and `X_o`, m.
    Periodic {
        /// The canonical impact signature, `None` without impacts.
        signature: Option<String>,
        /// Least period, forcing periods.
        period: u32,
        /// `X_o = max|u_o|` over the cycle, m.
        outer_amplitude: f64,
    },
    /// Sticking in the final cycle.
    Sticking,
    /// Not periodic within the cap.
    NotPeriodic,
    /// No dissipation: the transient persists.
    NoDissipation,
    /// The simulation failed.
    Failed,
}

impl Attractor {
    /// The attractor `sim` reached.
    pub fn of(sim: &SimulatedPoint) -> Attractor {
        match sim.steady.status {
            Status::NoDissipation => Attractor::NoDissipation,
            Status::NonPeriodic => Attractor::NotPeriodic,
            Status::Periodic if sim.steady.sticking => Attractor::Sticking,
            Status::Periodic => {
                let period = sim.steady.period.unwrap_or(1);
                let sides: Vec<i8> = sim.steady.cycle_impacts.iter().map(|i| i.side).collect();
                Attractor::Periodic {
                    signature: Signature::from_cycle(&sides, period)
                        .ok()
                        .map(|s| s.to_string()),
                    period,
                    outer_amplitude: sim.outer_amplitude,
                }
            }
        }
    }

    /// Whether `self` and `other` are one attractor (same kind; for periodic motions the same
    /// signature and amplitudes within [`BASIN_AMPLITUDE_TOLERANCE`]).
    pub fn same(&self, other: &Attractor) -> bool {
        match (self, other) {
            (
                Attractor::Periodic {
                    signature: a,
                    period: p,
                    outer_amplitude: x,
                },
                Attractor::Periodic {
                    signature: b,
                    period: q,
                    outer_amplitude: y,
                },
            ) => {
                a == b
                    && p == q
                    && (x - y).abs() <= BASIN_AMPLITUDE_TOLERANCE * x.abs().max(y.abs())
            }
            _ => self == other,
        }
    }

    /// Words for a legend or a table.
    pub fn words(&self) -> String {
        match self {
            Attractor::Periodic {
                signature,
                period,
                outer_amplitude,
            } => format!(
                "{} (p = {period}), X_o = {outer_amplitude:.4}",
                signature.as_deref().unwrap_or("no impact")
            ),
            Attractor::Sticking => "sticking".into(),
            Attractor::NotPeriodic => "not periodic within the cap".into(),
            Attractor::NoDissipation => "no dissipation".into(),
            Attractor::Failed => "simulation failed".into(),
        }
    }
}

/// One start of the grid and where it went.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinCell {
    /// Outer displacement at the start, m.
    pub outer: f64,
    /// Inner displacement at the start, m.
    pub inner: f64,
    /// Index into [`Basins::attractors`].
    pub attractor: usize,
    /// `X_o` of the motion reached, m (NaN on failure).
    pub outer_amplitude: f64,
    /// Periods run.
    pub periods_run: u64,
}

/// The basins of one frequency.
#[derive(Debug, Clone, PartialEq)]
pub struct Basins {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The grid of starts.
    pub grid: BasinGrid,
    /// The attractors, numbered by first appearance in grid order.
    pub attractors: Vec<Attractor>,
    /// Starts reaching each attractor (same order).
    pub counts: Vec<usize>,
    /// The cells, outer displacement slowest, inner fastest.
    pub cells: Vec<BasinCell>,
}

/// The start at rest with displacements `outer`, `inner` at time 0.
pub fn start_at_rest(outer: f64, inner: f64) -> Start {
    Start {
        state: DVector::from_column_slice(&[outer, inner, 0.0, 0.0]),
        time: 0.0,
    }
}

/// A start belongs to a reference periodic attractor once its stroboscopic state (at `t = kT`)
/// lies within this distance of one of the attractor's, relative to the larger of that state's
/// norm and the gap, unless the references lie closer together than that (then a third of their
/// smallest separation).
///
/// Measured on the undamped paper unit at ω = 1.9 rad/s (`rattle basins --omega 1.9`, ±1.5 m,
/// 100 × 100 starts), where the stable `++--` orbit attracts slowly (λ₁ = −0.008 /s, 2.6 % per
/// period) and a `+-` orbit coexists: at 1e-2, 31 starts stayed `not periodic` within the
/// 400-period cap (177 periods per start on average); at 3e-2, 17 of them were attributed to
/// `++--` (137 periods per start); at 1e-1, 26 (89 periods per start), and every one of the 26,
/// run on alone for up to 20 000 periods, repeats on `++--` after 677–757 periods. No start
/// changed between the two periodic attractors at any of the three values.
pub const BASIN_PROXIMITY: f64 = 1e-1;

/// The reference grid takes every this-many-th start on each axis (both ends included): 400
/// of a 200 × 200 grid, run to the cap without references.
pub const BASIN_REFERENCE_STRIDE: usize = 10;

/// The attribution distance for `references`: [`BASIN_PROXIMITY`], or a third of the smallest
/// relative distance between the stroboscopic states of two different references if that is
/// smaller, so that no state lies within it of two attractors.
fn proximity(references: &[Reference], gap: f64) -> f64 {
    let mut closest = f64::INFINITY;
    for (k, a) in references.iter().enumerate() {
        for b in &references[k + 1..] {
            for s in &a.states {
                for t in &b.states {
                    let scale = s.norm().max(t.norm()).max(gap);
                    closest = closest.min((s - t).norm() / scale);
                }
            }
        }
    }
    BASIN_PROXIMITY.min(closest / 3.0)
}

/// A periodic attractor reached from the reference grid, with its stroboscopic states.
#[derive(Debug, Clone)]
struct Reference {
    attractor: Attractor,
    outer_amplitude: f64,
    states: Vec<DVector<f64>>,
}

/// Where `start` goes on `scene` at `omega`: the attractor, `X_o`, periods run, and for a
/// periodic motion its stroboscopic states. One run up to the options' cap, watched at every
/// section `t = kT` before it is decided: a start whose state lies within `proximity` (relative,
/// see [`BASIN_PROXIMITY`]) of a reference's belongs to that attractor, and the run ends there.
fn reach(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
    references: &[Reference],
    proximity: f64,
) -> (Attractor, f64, u64, Vec<DVector<f64>>) {
    let gap = scene.gap().unwrap_or(1.0);
    let mut near: Option<&Reference> = None;
    let mut watch = |_: u64, x: &DVector<f64>| {
        near = references.iter().find(|r| {
            r.states
                .iter()
                .any(|s| x.metric_distance(s) <= proximity * s.norm().max(gap))
        });
        near.is_some()
    };
    let sim = match run_watched(scene, omega, start, options, &mut watch) {
        Ok(sim) => sim,
        Err(_) => return (Attractor::Failed, f64::NAN, 0, Vec::new()),
    };
    let periods = sim.steady.periods_run;
    match near {
        Some(r) if sim.steady.stopped == Stop::Watched => {
            (r.attractor.clone(), r.outer_amplitude, periods, Vec::new())
        }
        _ => (
            Attractor::of(&sim),
            sim.outer_amplitude,
            periods,
            sim.steady.stroboscopic,
        ),
    }
}

/// Where `start` goes on `scene` at `omega`, run to the options' cap (no references): the
/// attractor, `X_o` and periods run.
pub fn destination(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> (Attractor, f64, u64) {
    let (attractor, amplitude, periods, _) = reach(scene, omega, start, options, &[], 0.0);
    (attractor, amplitude, periods)
}

/// The starts of `grid`, outer displacement slowest, inner fastest.
fn starts(grid: &BasinGrid) -> Vec<(f64, f64)> {
    let inner = grid.inner.values();
    grid.outer
        .values()
        .into_iter()
        .flat_map(|o| inner.iter().map(move |&i| (o, i)))
        .collect()
}

/// The periodic attractors of the coarse reference subgrid of `grid` (every
/// [`BASIN_REFERENCE_STRIDE`]-th start on each axis, both ends included), run without
/// references, in grid order (so they do not depend on the number of threads), and the
/// attribution distance for them ([`proximity`]).
fn references(
    scene: &Scene,
    omega: f64,
    grid: &BasinGrid,
    options: &SimulationOptions,
) -> (Vec<Reference>, f64) {
    let (outer, inner) = (grid.outer.values(), grid.inner.values());
    let every = |n: usize| -> Vec<usize> {
        let mut k: Vec<usize> = (0..n).step_by(BASIN_REFERENCE_STRIDE).collect();
        if n > 0 && k.last() != Some(&(n - 1)) {
            k.push(n - 1);
        }
        k
    };
    let coarse: Vec<(f64, f64)> = every(outer.len())
        .into_iter()
        .flat_map(|a| every(inner.len()).into_iter().map(move |b| (a, b)))
        .map(|(a, b)| (outer[a], inner[b]))
        .collect();
    let mut references: Vec<Reference> = Vec::new();
    for (attractor, outer_amplitude, _, states) in
        parallel_map(&coarse, Grain::Uneven, &Progress::hidden(), |&(o, i)| {
            reach(scene, omega, &start_at_rest(o, i), options, &[], 0.0)
        })
    {
        let periodic = matches!(attractor, Attractor::Periodic { .. });
        if periodic && !references.iter().any(|r| r.attractor.same(&attractor)) {
            references.push(Reference {
                attractor,
                outer_amplitude,
                states,
            });
        }
    }
    let within = proximity(&references, scene.gap().unwrap_or(1.0));
    (references, within)
}

/// Where one start went, before the attractors are numbered.
#[derive(Debug, Clone, PartialEq)]
pub struct Reached {
    /// Outer displacement at the start, m.
    pub outer: f64,
    /// Inner displacement at the start, m.
    pub inner: f64,
    /// The attractor reached; a periodic one with this start's own `X_o`.
    pub attractor: Attractor,
    /// `X_o` of the motion reached, m (NaN on failure).
    pub outer_amplitude: f64,
    /// Periods run.
    pub periods_run: u64,
}

/// Where each of `starts` goes, in parallel, in order.
fn reach_all(
    scene: &Scene,
    omega: f64,
    starts: &[(f64, f64)],
    (references, within): &(Vec<Reference>, f64),
    options: &SimulationOptions,
    progress: &Progress,
) -> Vec<Reached> {
    parallel_map(starts, Grain::Uneven, progress, |&(outer, inner)| {
        let (attractor, outer_amplitude, periods_run, _) = reach(
            scene,
            omega,
            &start_at_rest(outer, inner),
            options,
            references,
            *within,
        );
        Reached {
            outer,
            inner,
            attractor,
            outer_amplitude,
            periods_run,
        }
    })
}

/// Numbers the attractors of `reached` (in order) by first appearance: each start takes the
/// first attractor so far that is [`Attractor::same`] as its own, or a new one. Returns the
/// attractors, the starts reaching each, and the cells.
pub fn number(reached: Vec<Reached>) -> (Vec<Attractor>, Vec<usize>, Vec<BasinCell>) {
    let mut attractors: Vec<Attractor> = Vec::new();
    let mut counts: Vec<usize> = Vec::new();
    let cells = reached
        .into_iter()
        .map(|r| {
            let index = match attractors.iter().position(|a| a.same(&r.attractor)) {
                Some(k) => k,
                None => {
                    attractors.push(r.attractor);
                    counts.push(0);
                    attractors.len() - 1
                }
            };
            counts[index] += 1;
            BasinCell {
                outer: r.outer,
                inner: r.inner,
                attractor: index,
                outer_amplitude: r.outer_amplitude,
                periods_run: r.periods_run,
            }
        })
        .collect();
    (attractors, counts, cells)
}

/// The basins of `scene` at `omega` over `grid`, in parallel, deterministic.
pub fn basins(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    progress: &Progress,
) -> Basins {
    basins_part(scene, omega, grid, options, None, progress)
}

/// The starts of one part of the basins (all of them for `None`): part `K` of `N` is block `K`
/// of `N` nearly equal contiguous blocks of the starts in grid order ([`Shard::range`]), each
/// start run as in the whole grid (every part finds the same references on the whole grid's
/// coarse subgrid), so that its cells are the whole grid's bit for bit. The attractors are
/// numbered within the part; [`merge_parts`] numbers them over the whole grid.
pub fn basins_part(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    progress: &Progress,
) -> Basins {
    let all = starts(&grid);
    let range = shard.map_or(0..all.len(), |s| s.range(all.len()));
    // A part without starts needs no references.
    let references = if range.is_empty() {
        (Vec::new(), BASIN_PROXIMITY)
    } else {
        references(scene, omega, &grid, options)
    };
    let reached = reach_all(scene, omega, &all[range], &references, options, progress);
    let (attractors, counts, cells) = number(reached);
    Basins {
        omega,
        grid,
        attractors,
        counts,
        cells,
    }
}

table_row! {
    /// One start of a basins grid.
    pub struct BasinRow {
        /// Outer displacement at the start, m.
        pub outer_start: Option<f64>,
        /// Inner displacement at the start, m.
        pub inner_start: Option<f64>,
        /// The attractor's number (first appearance in grid order).
        pub attractor: usize,
        /// The attractor in words.
        pub attractor_words: String,
        /// `X_o` of the motion reached, m.
        pub outer_amplitude: Option<f64>,
        /// Forcing periods run.
        pub periods_run: u64,
    }
}

/// The rows of `cells` numbered into `attractors`, in grid order.
pub fn rows<'a>(
    attractors: &'a [Attractor],
    cells: &'a [BasinCell],
) -> impl Iterator<Item = BasinRow> + 'a {
    cells.iter().map(|c| BasinRow {
        outer_start: finite(c.outer),
        inner_start: finite(c.inner),
        attractor: c.attractor,
        attractor_words: attractors[c.attractor].words(),
        outer_amplitude: finite(c.outer_amplitude),
        periods_run: c.periods_run,
    })
}

/// The header of a basins JSON table: the scene and the frequency.
pub fn header(scene: &Scene, omega: f64) -> Header {
    let mut h = Header::default();
    h.push("scene", scene);
    h.push("omega", &omega);
    h
}

/// Computes the basins (or one part of them, [`basins_part`]) and writes their table to `out`
/// in `format`: the table `rattle basins --out …` writes. A part's JSON header adds the
/// whole grid's `starts`, its `shard` and its `attractors` (numbered within the part, in
/// full); a CSV part starts with `# shard K/N of P starts, attractors: [...]` (the same list,
/// JSON). Its rows are numbered within the part; [`crate::runs::shard::merge`] numbers them
/// over the whole grid and writes exactly the whole grid's table. Returns the basins computed
/// (of the part: its cells and attractors).
///
/// # Errors
/// The writer's.
pub fn write_basins<W: Write>(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    (format, out): (Format, W),
    progress: &Progress,
) -> std::io::Result<Basins> {
    let b = basins_part(scene, omega, grid, options, shard, progress);
    let mut h = header(scene, omega);
    let total = grid.starts();
    let preamble = match shard {
        Some(s) => {
            h.push("starts", &total);
            h.push("shard", &s);
            h.push("attractors", &b.attractors);
            let list = serde_json::to_string(&b.attractors).map_err(std::io::Error::other)?;
            Some(format!(
                "{}, attractors: {list}",
                s.csv_preamble_of(total, "starts")
            ))
        }
        None => None,
    };
    let mut table: Box<dyn TableWriter<BasinRow>> = writer(format, out, &h, preamble.as_deref())?;
    for row in rows(&b.attractors, &b.cells) {
        table.row(&row)?;
    }
    table.finish()?;
    Ok(b)
}

/// Whether `text` is a part of sharded basins (its header or first line lists the part's
/// attractors).
pub fn is_basins_part(text: &str) -> bool {
    let first = text.lines().next().unwrap_or_default();
    (first.starts_with("# shard ") && first.contains(" starts, attractors: "))
        || (first.starts_with('{') && first.contains(",\"attractors\":"))
}

/// One part of sharded basins, read back: its shard, the whole grid's starts, the opening of
/// the whole grid's JSON document (for a JSON part) and its starts.
struct BasinsPart {
    shard: Shard,
    total: usize,
    opening: Option<String>,
    reached: Vec<Reached>,
}

/// A number cell of a part: empty or `null` is NaN (as [`finite`] wrote it).
fn number_cell(text: &str) -> Result<f64, String> {
    if text.is_empty() || text == "null" {
        return Ok(f64::NAN);
    }
    text.parse()
        .map_err(|_| format!("{text:?} is not a number"))
}

/// A start of a part from its cells: the attractor is the part's `attractors[attractor]`, a
/// periodic one with the start's own `X_o` (as [`reach`] found it).
fn reached_of(
    attractors: &[Attractor],
    [outer, inner, attractor, amplitude, periods]: [&str; 5],
) -> Result<Reached, String> {
    let outer_amplitude = number_cell(amplitude)?;
    let index: usize = attractor
        .parse()
        .map_err(|_| format!("attractor {attractor:?} is not a number"))?;
    let mut attractor = attractors
        .get(index)
        .cloned()
        .ok_or_else(|| format!("attractor {index} is not in the part's list"))?;
    if let Attractor::Periodic {
        outer_amplitude: x, ..
    } = &mut attractor
    {
        *x = outer_amplitude;
    }
    Ok(Reached {
        outer: number_cell(outer)?,
        inner: number_cell(inner)?,
        attractor,
        outer_amplitude,
        periods_run: periods
            .parse()
            .map_err(|_| format!("periods_run {periods:?} is not a count"))?,
    })
}

fn json_basins_part(text: &str) -> Result<BasinsPart, String> {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    let head: serde_json::Value = serde_json::from_str(&format!("{first}]}}"))
        .map_err(|e| format!("not a basins document ({e})"))?;
    let shard: Shard =
        serde_json::from_value(head["shard"].clone()).map_err(|e| format!("shard: {e}"))?;
    let attractors: Vec<Attractor> = serde_json::from_value(head["attractors"].clone())
        .map_err(|e| format!("attractors: {e}"))?;
    let total = head["starts"].as_u64().ok_or("no \"starts\"")? as usize;
    let cut = first.rfind(",\"starts\":").ok_or("no \"starts\"")?;
    let opening = format!("{},\"results\":[", &first[..cut]);
    let mut rows: Vec<&str> = lines.collect();
    if rows.pop() != Some("]}") {
        return Err("truncated (no closing \"]}\")".into());
    }
    let reached = rows
        .into_iter()
        .map(|line| {
            let row: serde_json::Value = serde_json::from_str(line.trim_end_matches(','))
                .map_err(|e| format!("a row: {e}"))?;
            let cell = |key: &str| match &row[key] {
                serde_json::Value::Null => String::new(),
                v => v.to_string(),
            };
            reached_of(
                &attractors,
                [
                    &cell("outer_start"),
                    &cell("inner_start"),
                    &cell("attractor"),
                    &cell("outer_amplitude"),
                    &cell("periods_run"),
                ],
            )
        })
        .collect::<Result<_, _>>()?;
    Ok(BasinsPart {
        shard,
        total,
        opening: Some(opening),
        reached,
    })
}

fn csv_basins_part(text: &str) -> Result<BasinsPart, String> {
    let (first, body) = text.split_once('\n').ok_or("empty")?;
    let bad = || "not a basins part (no '# shard K/N of P starts, attractors: [...]' line)";
    let spec = first.strip_prefix("# shard ").ok_or_else(bad)?;
    let (kn, rest) = spec.split_once(" of ").ok_or_else(bad)?;
    let (total, list) = rest.split_once(" starts, attractors: ").ok_or_else(bad)?;
    let shard = Shard::parse(kn)?;
    let total: usize = total.parse().map_err(|_| bad())?;
    let attractors: Vec<Attractor> =
        serde_json::from_str(list).map_err(|e| format!("attractors: {e}"))?;
    let mut reader = ::csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(body.as_bytes());
    let columns = reader.headers().map_err(|e| e.to_string())?.clone();
    if columns.iter().ne(BasinRow::COLUMNS.iter().copied()) {
        return Err("the columns are not those of a basins table".into());
    }
    let reached = reader
        .records()
        .map(|record| {
            let r = record.map_err(|e| e.to_string())?;
            let cell = |k: usize| r.get(k).unwrap_or_default();
            reached_of(&attractors, [cell(0), cell(1), cell(2), cell(4), cell(5)])
        })
        .collect::<Result<_, _>>()?;
    Ok(BasinsPart {
        shard,
        total,
        opening: None,
        reached,
    })
}

/// Joins the parts of sharded basins (all JSON or all CSV, in any order) into exactly the
/// table the unsharded run writes: the starts in grid order, the attractors numbered by first
/// appearance over the whole grid, each start's attractor decided as the whole grid decides
/// it ([`number`]).
///
/// # Errors
/// A message when a part is not a basins part, when parts are missing, repeated or from
/// different grids, or when the rows do not add up to the grid's starts.
pub fn merge_parts(parts: &[String]) -> Result<String, String> {
    let mut parsed: Vec<BasinsPart> = parts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let part = if p.trim_start().starts_with('{') {
                json_basins_part(p)
            } else {
                csv_basins_part(p)
            };
            part.map_err(|e| format!("part {}: {e}", i + 1))
        })
        .collect::<Result<_, _>>()?;
    check_cover(&parsed.iter().map(|p| p.shard).collect::<Vec<_>>())?;
    if parsed
        .iter()
        .any(|p| p.opening != parsed[0].opening || p.total != parsed[0].total)
    {
        return Err(
            "the parts come from different basins (scene, frequency or grid differ)".into(),
        );
    }
    parsed.sort_by_key(|p| p.shard.index);
    let total = parsed[0].total;
    let opening = parsed[0].opening.clone();
    let reached: Vec<Reached> = parsed.into_iter().flat_map(|p| p.reached).collect();
    if reached.len() != total {
        return Err(format!("{} starts for a grid of {total}", reached.len()));
    }
    let (attractors, _, cells) = number(reached);
    let mut out = Vec::new();
    let mut table: Box<dyn TableWriter<BasinRow>> = match &opening {
        Some(opening) => {
            Box::new(JsonWriter::with_opening(&mut out, opening).map_err(|e| e.to_string())?)
        }
        None => {
            Box::new(CsvWriter::new(&mut out, None, BasinRow::COLUMNS).map_err(|e| e.to_string())?)
        }
    };
    for row in rows(&attractors, &cells) {
        table.row(&row).map_err(|e| e.to_string())?;
    }
    table.finish().map_err(|e| e.to_string())?;
    String::from_utf8(out).map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn reference(states: &[[f64; 4]]) -> Reference {
        Reference {
            attractor: Attractor::NotPeriodic,
            outer_amplitude: 1.0,
            states: states
                .iter()
                .map(|s| DVector::from_column_slice(s))
                .collect(),
        }
    }

    #[test]
    fn the_proximity_keeps_the_attractors_neighbourhoods_apart() {
        let a = reference(&[[1.0, 0.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0]]);
        // One state of `b` 0.06 from one of `a`'s (relative to norms about 1): a third of it.
        let b = reference(&[[1.06, 0.0, 0.0, 0.0], [0.0, 3.0, 0.0, 0.0]]);
        let guarded = proximity(&[a.clone(), b], 0.5);
        assert!((guarded - 0.06 / 1.06 / 3.0).abs() < 1e-15, "{guarded}");
        // Far apart, or alone: the constant.
        let c = reference(&[[0.0, 0.0, 5.0, 0.0]]);
        assert_eq!(proximity(&[a.clone(), c], 0.5), BASIN_PROXIMITY);
        assert_eq!(proximity(&[a], 0.5), BASIN_PROXIMITY);
        assert_eq!(proximity(&[], 0.5), BASIN_PROXIMITY);
    }
}
