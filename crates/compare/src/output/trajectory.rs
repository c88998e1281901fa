//! Trajectories as tables: one row per sampled state (uniform samples, and each impact as two
//! rows, before and after), one row per impact; the same columns for both solvers.

use super::{finite, table_row};
use crate::scene::analytic::{OrbitImpact, OrbitSample, SampleKind};
use rattle_event_driven::trajectory::{RowKind, Trajectory};

table_row! {
    /// One state of a trajectory.
    pub struct TrajectoryRow {
        /// Time, s, with the base at `u_g cos ωt`.
        pub t: Option<f64>,
        /// `sample`, `before_impact`, `after_impact` or `after_stick`.
        pub kind: &'static str,
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
        /// `r = u_i − u_o`, m.
        pub r: Option<f64>,
    }
}

table_row! {
    /// One impact of a trajectory.
    pub struct ImpactRow {
        /// Time, s, with the base at `u_g cos ωt`.
        pub t: Option<f64>,
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

/// The rows of a simulated trajectory of the two-degree-of-freedom unit; times brought to the
/// forcing's own (the start's phase within the period added).
pub fn simulated_rows(trajectory: &Trajectory) -> (Vec<TrajectoryRow>, Vec<ImpactRow>) {
    let t0 = trajectory.phase;
    let rows = trajectory
        .rows
        .iter()
        .map(|row| {
            let u = |i: usize| row.displacements.get(i).copied().and_then(finite);
            let v = |i: usize| row.velocities.get(i).copied().and_then(finite);
            TrajectoryRow {
                t: finite(t0 + row.time),
                kind: kind_name(row.kind),
                base: finite(row.base),
                u_o: u(0),
                u_i: u(1),
                v_o: v(0),
                v_i: v(1),
                r: row.relative.first().copied().and_then(finite),
            }
        })
        .collect();
    let impacts = trajectory
        .impacts
        .iter()
        .map(|i| ImpactRow {
            t: finite(t0 + i.time),
            side: side_number(i.side),
            relative_velocity_before: finite(i.relative_velocity_before),
            u_o: i.displacements.first().copied().and_then(finite),
            u_i: i.displacements.get(1).copied().and_then(finite),
            v_o_before: i.velocities_before.first().copied().and_then(finite),
            v_i_before: i.velocities_before.get(1).copied().and_then(finite),
        })
        .collect();
    (rows, impacts)
}

/// The rows of an analytic orbit sampled by
/// [`crate::scene::analytic::sample_signature_orbit`]; `omega` and `base_amplitude` give the
/// base column.
pub fn analytic_rows(
    samples: &[OrbitSample],
    impacts: &[OrbitImpact],
    omega: f64,
    base_amplitude: f64,
) -> (Vec<TrajectoryRow>, Vec<ImpactRow>) {
    let rows = samples
        .iter()
        .map(|s| TrajectoryRow {
            t: finite(s.time),
            kind: match s.kind {
                SampleKind::Sample => "sample",
                SampleKind::BeforeImpact => "before_impact",
                SampleKind::AfterImpact => "after_impact",
            },
            base: finite(base_amplitude * (omega * s.time).cos()),
            u_o: finite(s.state[0]),
            u_i: finite(s.state[1]),
            v_o: finite(s.state[2]),
            v_i: finite(s.state[3]),
            r: finite(s.state[1] - s.state[0]),
        })
        .collect();
    let impacts = impacts
        .iter()
        .map(|i| ImpactRow {
            t: finite(i.time),
            side: side_number(i.side),
            relative_velocity_before: finite(i.before[3] - i.before[2]),
            u_o: finite(i.before[0]),
            u_i: finite(i.before[1]),
            v_o_before: finite(i.before[2]),
            v_i_before: finite(i.before[3]),
        })
        .collect();
    (rows, impacts)
}
