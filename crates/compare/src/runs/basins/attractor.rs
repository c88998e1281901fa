//! What a start reaches: the kinds of motion ([`Attractor`]) and when two are one attractor,
//! where each start went ([`Reached`]), and the numbering of the attractors by first
//! appearance in grid order into the grid's cells ([`number`], [`Basins`]).

use super::plane::{BasinGrid, BasinPlane};
use super::BASIN_AMPLITUDE_TOLERANCE;
use crate::scene::simulator::{PairSignature, SimulatedPoint};
use rattle_analytic::Signature;
use rattle_event_driven::{Status, SteadyState};
use serde::{Deserialize, Serialize};

/// The kind of motion a start ends on (as JSON in a part's header, [`write_basins`]).
///
/// [`write_basins`]: super::write_basins
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
    /// A periodic motion of a chain or a structure: each stop's signature and every body's
    /// amplitude.
    Motion {
        /// Each stop's canonical impact signature over the cycle, in stop order: `""` for a
        /// stop without impacts, `None` for impacts beyond what a signature holds.
        signatures: Vec<Option<String>>,
        /// Least period, forcing periods.
        period: u32,
        /// Every body's amplitude `max|u|` over the cycle, m, in body order; `None` for a
        /// floating body that no impact of the cycle touches (it rests anywhere the stops
        /// leave room for).
        amplitudes: Vec<Option<f64>>,
    },
    /// Sticking in the final cycle.
    Sticking,
    /// Not periodic within the cap.
    NotPeriodic,
    /// No dissipation: the transient persists.
    NoDissipation,
    /// The simulation failed.
    Failed,
    /// The start lies outside a stop's clearance of a structure: not run.
    OutsideClearance,
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

    /// The attractor a chain's or a structure's `steady` state of `pairs` stops is: by status
    /// as [`Attractor::of`], a periodic motion by each stop's signature, its least period and
    /// every body's amplitude, `None` for each body `j` not `held(j)`.
    pub fn motion(steady: &SteadyState, pairs: usize, held: impl Fn(usize) -> bool) -> Attractor {
        match steady.status {
            Status::NoDissipation => Attractor::NoDissipation,
            Status::NonPeriodic => Attractor::NotPeriodic,
            Status::Periodic if steady.sticking => Attractor::Sticking,
            Status::Periodic => {
                let period = steady.period.unwrap_or(1);
                let signatures = (0..pairs)
                    .map(|pair| match PairSignature::of(steady, pair, period) {
                        Ok(signature) => Some(signature.map(|s| s.to_string()).unwrap_or_default()),
                        Err(_) => None,
                    })
                    .collect();
                let amplitudes = steady
                    .amplitudes
                    .iter()
                    .enumerate()
                    .map(|(j, &a)| held(j).then_some(a))
                    .collect();
                Attractor::Motion {
                    signatures,
                    period,
                    amplitudes,
                }
            }
        }
    }

    /// Every body's amplitude of a [`Attractor::Motion`] (empty for the other kinds).
    pub fn body_amplitudes(&self) -> &[Option<f64>] {
        match self {
            Attractor::Motion { amplitudes, .. } => amplitudes,
            _ => &[],
        }
    }

    /// Whether the attractor is a family: a motion with a floating body no impact touches.
    pub fn is_family(&self) -> bool {
        self.body_amplitudes().iter().any(Option::is_none)
    }

    /// Whether the attractor is a periodic motion ([`Attractor::Periodic`] or
    /// [`Attractor::Motion`]).
    pub fn is_periodic(&self) -> bool {
        matches!(self, Attractor::Periodic { .. } | Attractor::Motion { .. })
    }

    /// Whether `self` and `other` are one attractor (same kind; for periodic motions the same
    /// signatures and period, and amplitudes within [`BASIN_AMPLITUDE_TOLERANCE`]: relative
    /// to the larger `X_o` on the unit, to the largest of every body's on a chain or a
    /// structure, where a body without amplitude matches only one without).
    pub fn same(&self, other: &Attractor) -> bool {
        match (self, other) {
            (
                Attractor::Motion {
                    signatures: a,
                    period: p,
                    amplitudes: x,
                },
                Attractor::Motion {
                    signatures: b,
                    period: q,
                    amplitudes: y,
                },
            ) => {
                let scale = x
                    .iter()
                    .chain(y)
                    .flatten()
                    .fold(0.0_f64, |m, v| m.max(v.abs()));
                a == b
                    && p == q
                    && x.len() == y.len()
                    && x.iter().zip(y).all(|(u, v)| match (u, v) {
                        (Some(u), Some(v)) => (u - v).abs() <= BASIN_AMPLITUDE_TOLERANCE * scale,
                        (None, None) => true,
                        _ => false,
                    })
            }
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
            Attractor::Motion {
                signatures,
                period,
                amplitudes,
            } => {
                let impacts = if signatures.iter().all(|s| s.as_deref() == Some("")) {
                    "no impact".to_owned()
                } else if signatures.len() == 1 {
                    signatures[0].clone().unwrap_or_else(|| "?".into())
                } else {
                    signatures
                        .iter()
                        .enumerate()
                        .map(|(k, s)| match s.as_deref() {
                            Some("") => format!("{k}: none"),
                            Some(s) => format!("{k}: {s}"),
                            None => format!("{k}: ?"),
                        })
                        .collect::<Vec<_>>()
                        .join("; ")
                };
                let amplitudes = amplitudes
                    .iter()
                    .map(|a| a.map_or_else(|| "free".to_owned(), |a| format!("{a:.4}")))
                    .collect::<Vec<_>>()
                    .join(", ");
                format!("{impacts} (p = {period}), amplitudes [{amplitudes}]")
            }
            Attractor::Sticking => "sticking".into(),
            Attractor::NotPeriodic => "not periodic within the cap".into(),
            Attractor::NoDissipation => "no dissipation".into(),
            Attractor::Failed => "simulation failed".into(),
            Attractor::OutsideClearance => "start outside a stop's clearance (not run)".into(),
        }
    }
}

/// One start of the grid and where it went.
#[derive(Debug, Clone, PartialEq)]
pub struct BasinCell {
    /// The first coordinate at the start: the outer displacement on the default plane, m.
    pub outer: f64,
    /// The second coordinate at the start: the inner displacement on the default plane, m.
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
    /// The grid of starts: the values of the plane's two axes (`plane.grid`).
    pub grid: BasinGrid,
    /// The plane of starts: its two coordinates and their values.
    pub plane: BasinPlane,
    /// The attractors, numbered by first appearance in grid order.
    pub attractors: Vec<Attractor>,
    /// Starts reaching each attractor (same order).
    pub counts: Vec<usize>,
    /// The cells, the first coordinate slowest, the second fastest.
    pub cells: Vec<BasinCell>,
    /// Every body's amplitude of the motion each cell reached, m (same order as `cells`; as
    /// [`Attractor::body_amplitudes`]: empty on the unit and for motions that are not
    /// periodic).
    pub body_amplitudes: Vec<Vec<Option<f64>>>,
}

/// Where one start went, before the attractors are numbered.
#[derive(Debug, Clone, PartialEq)]
pub struct Reached {
    /// The first coordinate at the start (the outer displacement on the default plane).
    pub outer: f64,
    /// The second coordinate at the start (the inner displacement on the default plane).
    pub inner: f64,
    /// The attractor reached; a periodic one with this start's own amplitudes.
    pub attractor: Attractor,
    /// `X_o` of the motion reached (a structure's observed body's amplitude), m (NaN on
    /// failure).
    pub outer_amplitude: f64,
    /// Periods run.
    pub periods_run: u64,
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
