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

use crate::runs::axis::Axis;
use crate::runs::map::MAP_PERIODICITY_TOLERANCE;
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::scene::simulator::{run, SimulatedPoint};
use crate::scene::Scene;
use nalgebra::DVector;
use rattle_analytic::Signature;
use rattle_event_driven::{SimulationOptions, Start, Status};

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

/// The kind of motion a start ends on.
#[derive(Debug, Clone, PartialEq)]
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
                    signature: Signature::from_sides(&sides, period)
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

/// Where `start` goes on `scene` at `omega`: the attractor, `X_o` and periods run.
pub fn destination(
    scene: &Scene,
    omega: f64,
    start: &Start,
    options: &SimulationOptions,
) -> (Attractor, f64, u64) {
    match run(scene, omega, start, options) {
        Ok(sim) => (
            Attractor::of(&sim),
            sim.outer_amplitude,
            sim.steady.periods_run,
        ),
        Err(_) => (Attractor::Failed, f64::NAN, 0),
    }
}

/// The basins of `scene` at `omega` over `grid`, in parallel, deterministic.
pub fn basins(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    progress: &Progress,
) -> Basins {
    let starts: Vec<(f64, f64)> = grid
        .outer
        .values()
        .into_iter()
        .flat_map(|o| grid.inner.values().into_iter().map(move |i| (o, i)))
        .collect();
    let reached = parallel_map(&starts, Grain::Uneven, progress, |&(o, i)| {
        destination(scene, omega, &start_at_rest(o, i), options)
    });
    let mut attractors: Vec<Attractor> = Vec::new();
    let mut counts: Vec<usize> = Vec::new();
    let cells = starts
        .iter()
        .zip(reached)
        .map(
            |(&(outer, inner), (attractor, outer_amplitude, periods_run))| {
                let index = match attractors.iter().position(|a| a.same(&attractor)) {
                    Some(k) => k,
                    None => {
                        attractors.push(attractor);
                        counts.push(0);
                        attractors.len() - 1
                    }
                };
                counts[index] += 1;
                BasinCell {
                    outer,
                    inner,
                    attractor: index,
                    outer_amplitude,
                    periods_run,
                }
            },
        )
        .collect();
    Basins {
        omega,
        grid,
        attractors,
        counts,
        cells,
    }
}
