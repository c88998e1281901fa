//! Trajectories as tables: one row per sampled state (uniform samples, and each impact as two
//! rows, before and after), one row per impact; the same columns for both solvers.

use super::{finite, table_row};
use crate::scene::analytic::{OrbitImpact, OrbitSample, SampleKind};
use rattle_event_driven::{RowKind, Trajectory};

/// Largest number of uniform samples per forcing period of a trajectory (`--samples-per-period`,
/// the Python package's `samples_per_period`): a period drawn with 10⁵ points is smooth at any
/// zoom, and a 16-period cycle then still fits in a few hundred megabytes of CSV.
pub const MAX_SAMPLES_PER_PERIOD: u64 = 100_000;

/// `samples_per_period` when it is in `[1, MAX_SAMPLES_PER_PERIOD]`; else the message that
/// names `--samples-per-period` and its range (the one check of the command, the library and
/// the Python package).
///
/// # Errors
/// The message, when `samples_per_period` is out of range.
pub fn check_samples_per_period(samples_per_period: i128) -> Result<u64, String> {
    u64::try_from(samples_per_period)
        .ok()
        .filter(|n| (1..=MAX_SAMPLES_PER_PERIOD).contains(n))
        .ok_or_else(|| {
            format!(
                "--samples-per-period = {samples_per_period} is out of range: must be in [1, \
                 {MAX_SAMPLES_PER_PERIOD}]"
            )
        })
}

table_row! {
    /// One state of a trajectory.
    pub struct TrajectoryRow {
        /// Time, s, with the base at `u_g cos ωt`.
        pub t: Option<f64>,
        /// `sample`, `before_impact`, `after_impact` or `after_stick`.
        pub kind: &'static str,
        /// The cell this row's displacements are of, from the base out (0 for the unit): a
        /// chain's trajectory has one row per cell at each time.
        pub cell: usize,
        /// The base displacement `u_g cos ωt`, m.
        pub base: Option<f64>,
        /// Outer displacement, m.
        pub u_o: Option<f64>,
        /// Inner displacement, m.
        pub u_i: Option<f64>,
        /// Outer velocity, m/s.
        pub v_o: Option<f64>,
        /// Inner velocity, m/s.
        pub v_i: Option<f64>,
        /// `r = u_i − u_o` of the cell, m (empty for a simulated cell without stops).
        pub r: Option<f64>,
    }
}

table_row! {
    /// One impact of a trajectory.
    pub struct ImpactRow {
        /// Time, s, with the base at `u_g cos ωt`.
        pub t: Option<f64>,
        /// The contact pair (0 for the unit; a chain's pairs numbered from the base over the
        /// cells with stops); the displacements and velocities are its cell's.
        pub pair: usize,
        /// 1 (`r = +Δ`) or 2 (`r = −Δ`).
        pub side: u8,
        /// `ṙ⁻`, m/s.
        pub relative_velocity_before: Option<f64>,
        /// Outer displacement, m.
        pub u_o: Option<f64>,
        /// Inner displacement, m.
        pub u_i: Option<f64>,
        /// Outer velocity just before, m/s.
        pub v_o_before: Option<f64>,
        /// Inner velocity just before, m/s.
        pub v_i_before: Option<f64>,
    }
}

/// The side number of `side` (`+1` → 1, else 2).
fn side_number(side: i8) -> u8 {
    if side > 0 {
        1
    } else {
        2
    }
}

/// The name of a row kind in the table.
fn kind_name(kind: RowKind) -> &'static str {
    match kind {
        RowKind::Sample => "sample",
        RowKind::BeforeImpact => "before_impact",
        RowKind::AfterImpact => "after_impact",
        RowKind::AfterStick => "after_stick",
    }
}

/// The cell of contact pair `pair` given each cell's pair (see
/// [`crate::scene::Scene::cell_pairs`]); 0 when no cell has it.
fn cell_of(cell_pairs: &[Option<usize>], pair: usize) -> usize {
    cell_pairs
        .iter()
        .position(|p| *p == Some(pair))
        .unwrap_or(0)
}

/// The rows of a simulated trajectory, one per cell at each time (`cell_pairs`: each cell's
/// contact pair, [`crate::scene::Scene::cell_pairs`]); times brought to the forcing's own (the
/// start's phase within the period added).
pub fn simulated_rows(
    trajectory: &Trajectory,
    cell_pairs: &[Option<usize>],
) -> (Vec<TrajectoryRow>, Vec<ImpactRow>) {
    let t0 = trajectory.phase;
    let rows = trajectory
        .rows
        .iter()
        .flat_map(|row| {
            cell_pairs.iter().enumerate().map(move |(cell, pair)| {
                let u = |i: usize| {
                    row.displacements
                        .get(2 * cell + i)
                        .copied()
                        .and_then(finite)
                };
                let v = |i: usize| row.velocities.get(2 * cell + i).copied().and_then(finite);
                TrajectoryRow {
                    t: finite(t0 + row.time),
                    kind: kind_name(row.kind),
                    cell,
                    base: finite(row.base),
                    u_o: u(0),
                    u_i: u(1),
                    v_o: v(0),
                    v_i: v(1),
                    r: pair
                        .and_then(|p| row.relative.get(p).copied())
                        .and_then(finite),
                }
            })
        })
        .collect();
    let impacts = trajectory
        .impacts
        .iter()
        .map(|i| {
            let c = 2 * cell_of(cell_pairs, i.pair);
            let at = |values: &[f64], k: usize| values.get(c + k).copied().and_then(finite);
            ImpactRow {
                t: finite(t0 + i.time),
                pair: i.pair,
                side: side_number(i.side),
                relative_velocity_before: finite(i.relative_velocity_before),
                u_o: at(&i.displacements, 0),
                u_i: at(&i.displacements, 1),
                v_o_before: at(&i.velocities_before, 0),
                v_i_before: at(&i.velocities_before, 1),
            }
        })
        .collect();
    (rows, impacts)
}

/// The rows of an analytic orbit sampled by
/// [`crate::scene::analytic::sample_signature_orbit`] or
/// [`crate::scene::analytic::sample_sequence_orbit`], one per cell at each time (`cell_pairs`
/// as for [`simulated_rows`]); `omega` and `base_amplitude` give the base column.
///
/// # Panics
/// If a state has fewer than four entries per cell of `cell_pairs`.
pub fn analytic_rows(
    samples: &[OrbitSample],
    impacts: &[OrbitImpact],
    omega: f64,
    base_amplitude: f64,
    cell_pairs: &[Option<usize>],
) -> (Vec<TrajectoryRow>, Vec<ImpactRow>) {
    let cells = cell_pairs.len();
    let rows = samples
        .iter()
        .flat_map(|s| {
            (0..cells).map(move |cell| {
                let (o, i) = (2 * cell, 2 * cell + 1);
                let v = 2 * cells;
                TrajectoryRow {
                    t: finite(s.time),
                    kind: match s.kind {
                        SampleKind::Sample => "sample",
                        SampleKind::BeforeImpact => "before_impact",
                        SampleKind::AfterImpact => "after_impact",
                    },
                    cell,
                    base: finite(base_amplitude * (omega * s.time).cos()),
                    u_o: finite(s.state[o]),
                    u_i: finite(s.state[i]),
                    v_o: finite(s.state[v + o]),
                    v_i: finite(s.state[v + i]),
                    r: finite(s.state[i] - s.state[o]),
                }
            })
        })
        .collect();
    let impacts = impacts
        .iter()
        .map(|i| {
            let c = 2 * cell_of(cell_pairs, i.pair);
            let v = 2 * cells;
            ImpactRow {
                t: finite(i.time),
                pair: i.pair,
                side: side_number(i.side),
                relative_velocity_before: finite(i.before[v + c + 1] - i.before[v + c]),
                u_o: finite(i.before[c]),
                u_i: finite(i.before[c + 1]),
                v_o_before: finite(i.before[v + c]),
                v_i_before: finite(i.before[v + c + 1]),
            }
        })
        .collect();
    (rows, impacts)
}
