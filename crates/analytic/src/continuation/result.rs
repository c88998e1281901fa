//! What a continuation finds: branches of points, the events on them and how each branch
//! ends.

use crate::signature::Signature;
use nalgebra::Complex;

/// One point of a branch.
#[derive(Debug, Clone, PartialEq)]
pub struct ContinuationPoint {
    /// Index of the branch in [`Continuation::branches`].
    pub branch: usize,
    /// Forcing frequency (rad/s).
    pub omega: f64,
    /// Base phase at the first canonical impact, radians in `(−π, π]`.
    pub alpha: f64,
    /// Impact times as fractions of the cycle, first 0.
    pub impact_phases: Vec<f64>,
    /// `X_o = max |u_o(t)|` over the cycle (rigorous extrema), of the last cell on a chain.
    pub outer_amplitude: f64,
    /// For each contact pair (cell) in model order, the amplitude `max |u_o(t)|` of its outer
    /// coordinate (rigorous extrema): one entry on the unit, equal to `outer_amplitude`; on a
    /// chain `outer_amplitude` is the last cell's.
    pub cell_outer_amplitudes: Vec<f64>,
    /// On a model's branch: every coordinate's amplitude `max |u_k(t)|` over the cycle, in
    /// model order (rigorous extrema), the way any structure reads its bodies' motion; empty
    /// on the unit's (whose amplitude is `outer_amplitude`).
    pub amplitudes: Vec<f64>,
    /// `20 log10(X_o / X_s)`, `X_s` the static displacement of that coordinate (`u_g` on the
    /// unit and on a base-driven chain).
    pub transmittance_db: f64,
    /// Every Floquet multiplier has modulus `< 1 −` [`STABILITY_MARGIN`](crate::orbit::STABILITY_MARGIN).
    pub stable: bool,
    /// No interior excursion of any pair's coordinate beyond a stop (beyond
    /// [`VIABILITY_TOLERANCE`](crate::orbit::VIABILITY_TOLERANCE)` · gap`) and every impact approached from inside.
    pub viable: bool,
    /// Eigenvalues of the monodromy matrix.
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// `dω/ds` along the unit tangent in `(α, φ₂ … φₙ, ω)`, oriented along the order of
    /// [`Branch::points`] (for an [`Event`]'s point: along the direction in which the branch
    /// was being followed when the event was found): zero at a fold.
    pub domega_ds: f64,
    /// The largest contact residual `|r(t_j⁻) − s_j Δ|` of the point.
    pub residual: f64,
}

/// A branch followed by continuation: of a unit's orbits (`L` a [`Signature`]) or of a
/// model's ([`crate::ImpactSequence`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Branch<L = Signature> {
    /// Its index in [`Continuation::branches`].
    pub index: usize,
    /// The canonical signature (a model's: impact sequence) of its orbits.
    pub signature: L,
    /// Forcing periods per cycle.
    pub period: u32,
    /// The points in order along the branch (the seed somewhere inside).
    pub points: Vec<ContinuationPoint>,
    /// How the branch was reached: `None` for the start's branch, else the index of the
    /// event in [`Continuation::events`] it was switched onto from.
    pub from_event: Option<usize>,
}

/// The kind of a bifurcation event.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// Saddle-node: the branch turns back in `ω` (a multiplier through +1).
    Fold,
    /// A multiplier through +1 where the branch does not turn: another branch crosses.
    BranchPoint,
    /// A multiplier through −1.
    PeriodDoubling,
    /// A complex pair of multipliers through the unit circle.
    NeimarkSacker,
    /// An interior extremum of a pair's coordinate `r` reaches a stop.
    Grazing,
    /// An impact's relative velocity `ṙ⁻` passes through zero.
    VanishingImpact,
}

impl EventKind {
    /// `fold`, `branch-point`, `period-doubling`, `neimark-sacker`, `grazing` or
    /// `vanishing-impact`.
    pub fn name(self) -> &'static str {
        match self {
            EventKind::Fold => "fold",
            EventKind::BranchPoint => "branch-point",
            EventKind::PeriodDoubling => "period-doubling",
            EventKind::NeimarkSacker => "neimark-sacker",
            EventKind::Grazing => "grazing",
            EventKind::VanishingImpact => "vanishing-impact",
        }
    }
}

/// A located bifurcation event.
#[derive(Debug, Clone, PartialEq)]
pub struct Event<L = Signature> {
    /// The branch on which it was found.
    pub branch: usize,
    /// What happens.
    pub kind: EventKind,
    /// Its frequency.
    pub omega: f64,
    /// The signature of the branch that leaves here (branch point: the same; period
    /// doubling: the doubled one; grazing: the one with the extra impact), if any.
    pub signature_after: Option<L>,
    /// The period (forcing periods per cycle) of `signature_after`.
    pub period_after: Option<u32>,
    /// For grazing and vanishing impact: the impact involved, as its time from the first
    /// canonical impact in fractions of the cycle (grazing: the graze time).
    pub phase: Option<f64>,
    /// For grazing and vanishing impact: the contact pair involved (0 on the unit).
    pub pair: Option<usize>,
    /// The orbit at the event.
    pub point: ContinuationPoint,
}

/// Why a branch (in one direction) stops.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum EndReason {
    /// It reached `omega_min`; the last point lies exactly there.
    OmegaMin,
    /// It reached `omega_max`; the last point lies exactly there.
    OmegaMax,
    /// The step fell below `min_step` without the corrector converging.
    StepBelowMinimum,
    /// The branch reached `max_points_per_branch`.
    PointCap,
    /// Two impacts merge (a flight shrinks to nothing).
    FlightMerged,
    /// A branch born at a grazing leaves it on the side where the new impact would be
    /// approached from outside: not a motion, not followed.
    VanishingImpact,
    /// The corrector did not converge from a switch point onto the new branch.
    NewtonFailed,
    /// The branch closed on itself: it came back to its seed, or its two directions met (a
    /// loop longer than the first direction's half of `max_points_per_branch`; both ends
    /// then say so). A closed loop (isola), followed once.
    ClosedLoop,
    /// The branch runs onto one already followed, or onto its image under the unit's
    /// symmetry (half a forcing period later with the stops mirrored), or onto another
    /// representation of the same orbits: [`BranchEnd::joins`] names that branch. A branch
    /// whose seed lies on one already followed ends so in both directions at its seed.
    Joins,
    /// A branch that leaves an event of a branch at [`ContinuationSettings::max_depth`](crate::ContinuationSettings::max_depth):
    /// recorded without points, not followed.
    MaxDepth,
    /// A branch queued when [`ContinuationSettings::max_branches`](crate::ContinuationSettings::max_branches)
    /// had been followed: recorded without points, not followed.
    BranchCap,
}

impl EndReason {
    /// `omega-min`, `omega-max`, `step-below-minimum`, `point-cap`, `flight-merged`,
    /// `vanishing-impact`, `newton-failed`, `closed-loop`, `joins`, `max-depth` or `branch-cap`.
    pub fn name(self) -> &'static str {
        match self {
            EndReason::OmegaMin => "omega-min",
            EndReason::OmegaMax => "omega-max",
            EndReason::StepBelowMinimum => "step-below-minimum",
            EndReason::PointCap => "point-cap",
            EndReason::FlightMerged => "flight-merged",
            EndReason::VanishingImpact => "vanishing-impact",
            EndReason::NewtonFailed => "newton-failed",
            EndReason::ClosedLoop => "closed-loop",
            EndReason::Joins => "joins",
            EndReason::MaxDepth => "max-depth",
            EndReason::BranchCap => "branch-cap",
        }
    }
}

/// The end of a branch in one direction.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BranchEnd {
    /// The branch.
    pub branch: usize,
    /// Frequency of its last point in that direction.
    pub omega: f64,
    /// Why it stops.
    pub reason: EndReason,
    /// For [`EndReason::Joins`], the branch it runs onto (possibly itself: a branch that is
    /// its own mirror image, as the asymmetric pair leaving the symmetric orbit is, ends
    /// where it starts to retrace itself mirrored).
    pub joins: Option<usize>,
}

/// Everything a continuation found: every branch followed (the start's and those switched
/// onto), the events located on them and the ends of each branch (two per branch).
#[derive(Debug, Clone, PartialEq)]
pub struct Continuation<L = Signature> {
    /// The branches, the start's first.
    pub branches: Vec<Branch<L>>,
    /// The events, in the order found.
    pub events: Vec<Event<L>>,
    /// The ends of the branches, two per branch.
    pub ends: Vec<BranchEnd>,
}

impl<L> Default for Continuation<L> {
    fn default() -> Self {
        Self {
            branches: Vec::new(),
            events: Vec::new(),
            ends: Vec::new(),
        }
    }
}
