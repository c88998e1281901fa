//! Pseudo-arclength continuation in `ω` of orbits of any impact signature, with bifurcation
//! events and branch switching.
//!
//! The unknowns are those of [`crate::cycle`], `x = (α, φ₂ … φₙ)`, with the forcing frequency
//! `ω` appended: `X = (x, ω)`. The `n` contact residuals `R(X)` define a curve in `X`; it is
//! followed by a tangent predictor `X₀ + h t₀` and a corrector on the bordered system
//! `[R(X); t₀ · (X − X_pred)] = 0`, so the branch is followed through folds. The corrector is
//! a chord Newton iteration with the exact Jacobian of the previous point (each iteration one
//! residual evaluation), falling back to full Newton; step control uses its iteration count.
//! Where the periodicity solve is ill-conditioned (near a natural frequency) points are
//! accepted at its rounding floor, `ε · cond(I − Ψ_xx)`, and carry their residual.
//!
//! All derivatives are exact. In the forcing angle `σ = ωt` the flight over the phase fraction
//! `Δφ` of a cycle of `p` periods is `Φ = exp(B(ω) σ)`, `σ = 2πp Δφ`, `B = Â/ω`, so `ω`
//! enters only through `B`: `∂Φ/∂ω` is the Fréchet derivative of the exponential in the
//! direction `B'(ω) σ`, read off the top-right block of the 12×12 exponential
//! `exp([[Bσ, B'σ], [0, Bσ]])` (whose diagonal blocks are `Φ` itself).
//!
//! Along the branch each point carries its Floquet multipliers, amplitude and viability, and
//! test functions whose sign changes between consecutive points are events: every test that
//! changed sign over a step is located on its own, by the Illinois variant of regula falsi on
//! the chord between the two points (each trial point corrected onto the branch) until the
//! chord fraction is bracketed to [`LOCATION_FRACTION`], and the events of a step are listed
//! in their order along it (events closer than the step are all found):
//!
//! | event | test function |
//! |---|---|
//! | fold | `dω/ds`, the tangent's `ω` component |
//! | branch point | `det(M − I) / (dω/ds)` (both factors change sign at a fold, the ratio only at a branch point) |
//! | period doubling | `det(M + I)` |
//! | Neimark–Sacker | `Π_{i<j} (μ_i μ_j − 1)`, kept when a complex pair sits on the unit circle |
//! | grazing | per flight, `Δ − max |r|` over the interior critical points of `r` |
//! | vanishing impact | per impact, `s_j ṙ⁻_j` |
//!
//! `M` is the monodromy matrix with saltation at each impact, `μ_i` its eigenvalues.
//!
//! Each branch is followed once. The unit is symmetric (stops at `±Δ`, forcing odd over half
//! a period): with `u(t)` a motion, `−u(t + T/2)` is one too, with the sides mirrored; and a
//! motion timed from another impact is the same motion. A branch whose seed, or whose next
//! point, lies on a branch already followed in any of these representations (a branch and
//! its mirror image, the asymmetric pair leaving a symmetric orbit, a period-doubled orbit
//! one period later) ends there with [`EndReason::Joins`], and an event listed already in
//! another representation is not listed again. Switching is bounded by
//! [`ContinuationSettings::max_depth`].

use crate::branch_point::locate_branch_point;
use crate::cycle::{SignatureOrbit, MIN_FLIGHT, NEWTON_TOLERANCE, STEP_ROUNDING};
use crate::flow::{join, Augmented, ForcedFlow};
use crate::linear::transmittance_db;
use crate::orbit::{
    eigenvalues, impact, relative_displacement, saltation, wrap, STABILITY_MARGIN,
    VIABILITY_TOLERANCE,
};
use crate::signature::Signature;
use crate::unit::{Stops, Unit, UnitError};
use nalgebra::{Complex, DMatrix, DVector, Matrix2, Matrix4, Matrix6, SMatrix, Vector2, Vector4};
use std::collections::{HashMap, VecDeque};
use thiserror::Error;

type Matrix12 = SMatrix<f64, 12, 12>;

/// Cap on the corrector's Newton iterations for one continuation step. From the tangent
/// predictor at an accepted step length the corrector converges quadratically in two to four
/// iterations; a step that needs more than this is halved instead.
pub const CORRECTOR_ITERATIONS: usize = 8;

/// Fallback acceptance of the corrector, relative to the motion's size, once Newton has
/// stalled at the rounding floor of the residual evaluation (an iteration that no longer divides it by 4). Measured: on
/// the paper unit's symmetric branch near `ω = 2.465` (close to the second natural frequency
/// `√6`, where the periodicity solve is ill-conditioned) the evaluation of the residuals
/// scatters by up to `4e-11` of the motion's size from one rounding to the next, above
/// [`crate::cycle::NEWTON_ACCEPTANCE`]; this bound is a factor 2.5 above that scatter.
pub const CORRECTOR_ACCEPTANCE: f64 = 1e-10;

/// Rounding of the contact residuals in units of `ε · cond(K)` (times the motion's size),
/// `K = I − Ψ_xx` the periodicity matrix. Measured on the paper unit's symmetric branch at
/// `ω = 2.4554` (near `√6`): `cond(K) = 4.2e5` and the residual scattered between `8e-12` and
/// `1.1e-10` of the size from one rounding to the next, i.e. up to 1.2 `ε cond(K)`.
pub const ROUNDING_ULPS: f64 = 4.0;

/// The fallback acceptance of the corrector at one evaluation, relative to the motion's
/// size: [`CORRECTOR_ACCEPTANCE`], or the rounding floor `ROUNDING_ULPS · ε · cond(K)` where
/// the periodicity solve is ill-conditioned (near a natural frequency), whichever is larger.
/// Points accepted above [`CORRECTOR_ACCEPTANCE`] carry their residual in
/// [`ContinuationPoint::residual`]; the floor is capped at [`MAX_ROUNDING_FLOOR`].
fn rounding_floor(eval: &Eval) -> f64 {
    CORRECTOR_ACCEPTANCE
        .max(ROUNDING_ULPS * f64::EPSILON * eval.conditioning)
        .min(MAX_ROUNDING_FLOOR)
}

/// Cap on the corrector's rounding floor (`ROUNDING_ULPS · ε · cond(K)`): closer to an undamped resonance (`cond(K)` above about `10⁷`)
/// the residuals cannot be met to `1e-8` of the motion's size in double precision, and the
/// branch ends there ([`EndReason::StepBelowMinimum`]) rather than carry such points.
pub const MAX_ROUNDING_FLOOR: f64 = 1e-8;

/// Newton's residual has stalled (rounding) when an iteration reduces it by less than this
/// factor: quadratic convergence reduces it by orders of magnitude per iteration.
const STALL_RATIO: f64 = 0.25;

/// Central-difference step (relative to the largest unknown) for the second derivatives of
/// the branching equation at a branch point: truncation `O(ε²) ≈ 1e-12`, rounding of the
/// exact Jacobians `O(ε_mach/ε) ≈ 1e-10`; ample for a direction that the corrector then
/// follows onto the branch.
pub const BRANCHING_DIFFERENCE: f64 = 1e-6;

/// Cap on the extra Newton iterations of [`System::polish`]: linear convergence at rate
/// about ½ along a singular direction gains the 26 binary orders between `√ε` and `ε` in
/// about 26 iterations.
const POLISH_ITERATIONS: usize = 60;

/// [`System::polish`] stops when a step is not below this fraction of the previous one.
const POLISH_SHRINK: f64 = 0.9;

/// Cap on the chord iterations of one step (Jacobian of the previous point). From the tangent
/// predictor the chord iteration contracts by a factor of order `h ‖R_XX‖ / ‖R_X‖` per
/// iteration, so a step it cannot finish in this many is better redone with full Newton.
pub const CHORD_ITERATIONS: usize = 10;

/// The chord iteration is abandoned when an iteration does not reduce the residual by at
/// least this factor: it is then too far from the previous point for its Jacobian.
const CHORD_CONTRACTION: f64 = 0.5;

/// A full-Newton fallback of at most this many iterations (quadratic convergence from the
/// predictor) counts as [`HARD_ITERATIONS`] for the step control: the step is kept.
const FALLBACK_QUICK: usize = 3;

/// Step growth when the corrector converged in at most [`EASY_ITERATIONS`] iterations.
const STEP_GROWTH: f64 = 1.5;

/// Chord iterations at or below which the step is grown. The chord iteration contracts by
/// about `hκ` per iteration from a predictor error of about `κh²`, so its count grows with
/// the step: measured on the paper unit (`+-` over `ω ∈ [2.5, 3.5]`, `++--` over
/// `[1.8, 2.2]`), growing at ≤ 3 gave 957 and 383 points in 34 ms per branch, ≤ 4 gave 392
/// and 183 points in 17 and 22 ms, ≤ 5 gave 253 and 138 points in 13 and 19 ms: ≤ 4 keeps
/// the curves resolved for plotting at half the cost of ≤ 3.
const EASY_ITERATIONS: usize = 4;

/// Chord iterations above which the next step is shrunk by [`STEP_SHRINK`] (a slow full
/// Newton fallback counts as [`CHORD_ITERATIONS`]): twice [`EASY_ITERATIONS`].
const HARD_ITERATIONS: usize = 8;

/// Shrink factor after a hard step, and after a rejected one (halved then).
const STEP_SHRINK: f64 = 0.7;

/// Two consecutive tangents must make an angle whose cosine is at least this, or the step is
/// halved: about 26°. A larger turn within one step means the corrector may have jumped to
/// another branch, or the step skipped over a sharp feature (a fold of short extent).
pub const MIN_TANGENT_COSINE: f64 = 0.9;

/// An event is located when the chord fraction `θ ∈ [0, 1]` between two points is bracketed
/// to this width: steps are at most `max_step` long in `(x, ω)`, so the event's `ω` is pinned
/// to well under `1e-12` for any `max_step ≤ 1`, four orders inside the required `1e-8`.
pub const LOCATION_FRACTION: f64 = 1e-13;

/// Cap on the Illinois iterations of one event location: Illinois converges superlinearly,
/// so a location that needs more is stalling on a discontinuity.
const LOCATION_ITERATIONS: usize = 100;

/// A sign change of a test function is an event only if its value at the located point is
/// below this fraction of the larger of its values at the two points around it. A continuous
/// test function is zero there to rounding; one that jumped (a critical point of `r` born
/// away from the stops, a multiplier test through a pole as `ṙ⁻ → 0`) is not.
pub const EVENT_ACCEPTANCE: f64 = 1e-3;

/// A located zero of the branch-point test is a branch point when the smallest singular value
/// of `R_X` there is below this fraction of its largest (it vanishes at a branch point, where
/// `R_X` loses rank; at a regular point it is of the order of the largest). Measured on the
/// paper unit: 1.7e-10 at the pitchfork at 2.1925686 rad/s located on the asymmetric pair,
/// 0.026 at a sign change of the test through its pole at a vanishing impact (2.19307 rad/s).
pub const BRANCH_RANK_DEFICIENCY: f64 = 1e-5;

/// `σ_min / σ_max` of `R_X` (`n × (n + 1)`); 1 when it cannot be formed.
fn rank_deficiency(jacobian: &DMatrix<f64>) -> f64 {
    let sv = jacobian.singular_values();
    let max = sv.iter().copied().fold(0.0, f64::max);
    let min = sv.iter().copied().fold(f64::INFINITY, f64::min);
    if max > 0.0 && min.is_finite() {
        min / max
    } else {
        1.0
    }
}

/// A complex pair of multipliers is on the unit circle at a Neimark–Sacker event when its
/// modulus is within this of 1; a located zero of the pair-product test without such a pair
/// is a neutral saddle (real `μ, 1/μ`), not an event. The multipliers come from a 4×4 Schur
/// form carrying about `1e-13` of rounding; located to `1e-13` in the chord fraction, the
/// modulus is pinned far tighter than this.
pub const TORUS_TOLERANCE: f64 = 1e-6;

/// Imaginary part below which a multiplier counts as real.
const REAL_MULTIPLIER: f64 = 1e-9;

/// Two switch points are the same (a branch point seen from both branches, a doubling seen
/// from the doubled branch) when `ω` and every unknown agree to this: the located events sit
/// at about `1e-12` of each other, and distinct bifurcations of the unit lie far apart.
pub const SWITCH_DEDUP: f64 = 1e-6;

/// A probe from a branch point that lands back on the known branch has a secant within
/// `1 − cos ≈ (κ step)²/8` of its tangent, about `1e-8` for the switch step and curvatures of
/// order one; the two branches' tangents, though both dominated by `α` in these coordinates,
/// were measured at cosines up to 0.94 on the paper unit. This threshold separates the two.
pub const PROBE_COSINE: f64 = 0.9999;

/// Size of the first step onto a switched branch, relative to `initial_step`: small, so the
/// corrector stays on the new branch near the bifurcation.
const SWITCH_STEP: f64 = 0.1;

/// A branch whose last step passes within this fraction of the step of its seed, after at
/// least [`LOOP_MIN_POINTS`] points, has closed on itself (an isola). The chord of a step `h`
/// departs from the curve by about `κh²/8`, far below `0.1 h` for the steps the tangent-turn
/// test ([`MIN_TANGENT_COSINE`]) allows; a distinct branch passing that close to the seed is
/// not told apart from a loop.
const LOOP_CLOSURE: f64 = 0.1;

/// A loop closes only where the branch comes back through its seed travelling the same way:
/// the tangents agree to this cosine (a branch crossing the seed at a branch point, or
/// passing near it, does not).
const LOOP_TANGENT_COSINE: f64 = 0.99;

/// Fewest points before closure of a loop is tested.
const LOOP_MIN_POINTS: usize = 8;

/// A graze is interior when its critical point lies at least this far (as a fraction of the
/// cycle) from both ends of its flight. As an impact's velocity `ṙ⁻` passes through zero, a
/// critical point of `r` leaves the flight through that end with `r` at the stop: the
/// clearance crosses zero at the vanishing impact too, within the location tolerance of it.
/// Those crossings are the vanishing impact, not a graze. Far above the location error of an
/// event's time, far below the flights of the orbits followed.
pub const GRAZE_INTERIOR: f64 = 1e-6;

/// Shortest flight (fraction of the cycle) below which a failed step is reported as two
/// impacts merging rather than as a step below the minimum.
const MERGE_WARNING: f64 = 1e-6;

/// Default switching depth ([`ContinuationSettings::max_depth`]). Measured on the issue #22
/// run (`+-` from ω = 2.1725686 over 1.8925686–2.4925686 rad/s, paper scene, one thread):
/// depth 2 follows 15 branches, 7 183 points, 85 events in 1.4 s of CPU; depth 3 (the depth
/// the former cap of 16 branches per start reached there) 27 branches, 27 524 points, 323
/// events in 24 s, the third level being period-8 orbits of the doubling cascade (20 341 of
/// the points, 16 impacts per cycle each).
pub const DEFAULT_MAX_DEPTH: usize = 2;

/// Settings of a continuation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContinuationSettings {
    /// Lowest forcing frequency followed (rad/s), `> 0`.
    pub omega_min: f64,
    /// Highest forcing frequency followed (rad/s), `> omega_min`.
    pub omega_max: f64,
    /// First step length in `(α, φ₂ … φₙ, ω)` (radians, cycle fractions, rad/s).
    pub initial_step: f64,
    /// Smallest step: a branch whose step would fall below it ends.
    pub min_step: f64,
    /// Largest step.
    pub max_step: f64,
    /// Cap on the points of one branch (both directions together, seed included).
    pub max_points_per_branch: usize,
    /// Cap on the branches followed, the start's own included.
    pub max_branches: usize,
    /// Whether to follow the branches that leave at branch points, period doublings and
    /// grazings.
    pub follow_switches: bool,
    /// Switching depth: the start's branch has depth 0, a branch switched onto from one of
    /// depth `d` has depth `d + 1`; branches deeper than this are not followed (the cut is
    /// recorded as a branch without points ending [`EndReason::MaxDepth`]).
    pub max_depth: usize,
}

impl Default for ContinuationSettings {
    /// `ω ∈ [0.1, 4]` (the band the workbench studies on the paper unit), steps from `10⁻⁹`
    /// to `0.05` starting at `0.01` (a few hundred points over a branch spanning the band),
    /// 20 000 points per branch, 16 branches, switching on to depth [`DEFAULT_MAX_DEPTH`].
    fn default() -> Self {
        Self {
            omega_min: 0.1,
            omega_max: 4.0,
            initial_step: 0.01,
            min_step: 1e-9,
            max_step: 0.05,
            max_points_per_branch: 20_000,
            max_branches: 16,
            follow_switches: true,
            max_depth: DEFAULT_MAX_DEPTH,
        }
    }
}

impl ContinuationSettings {
    /// The defaults within `[omega_min, omega_max]`.
    pub fn new(omega_min: f64, omega_max: f64) -> Self {
        Self {
            omega_min,
            omega_max,
            ..Self::default()
        }
    }

    /// Checks every setting.
    ///
    /// # Errors
    /// [`ContinuationError::Setting`] naming the first field that fails: `--omega-min`
    /// (finite, `> 0`), `--omega-max` (finite, `> omega_min`), `continuation.min_step`
    /// (finite, `> 0`), `continuation.max_step` (finite, `≥ min_step`),
    /// `continuation.initial_step` (in `[min_step, max_step]`),
    /// `continuation.max_points_per_branch` (`≥ 2`), `continuation.max_branches` (`≥ 1`).
    pub fn validate(&self) -> Result<(), ContinuationError> {
        let check = |field: &'static str, value: f64, ok: bool, allowed: String| {
            if value.is_finite() && ok {
                Ok(())
            } else {
                Err(ContinuationError::Setting {
                    field,
                    value,
                    allowed,
                })
            }
        };
        check(
            "--omega-min",
            self.omega_min,
            self.omega_min > 0.0,
            "finite and > 0".into(),
        )?;
        check(
            "--omega-max",
            self.omega_max,
            self.omega_max > self.omega_min,
            format!("finite and > --omega-min = {}", self.omega_min),
        )?;
        check(
            "continuation.min_step",
            self.min_step,
            self.min_step > 0.0,
            "finite and > 0".into(),
        )?;
        check(
            "continuation.max_step",
            self.max_step,
            self.max_step >= self.min_step,
            format!("finite and >= continuation.min_step = {}", self.min_step),
        )?;
        check(
            "continuation.initial_step",
            self.initial_step,
            self.initial_step >= self.min_step && self.initial_step <= self.max_step,
            format!(
                "in [{}, {}] (min_step, max_step)",
                self.min_step, self.max_step
            ),
        )?;
        check(
            "continuation.max_points_per_branch",
            self.max_points_per_branch as f64,
            self.max_points_per_branch >= 2,
            ">= 2".into(),
        )?;
        check(
            "continuation.max_branches",
            self.max_branches as f64,
            self.max_branches >= 1,
            ">= 1".into(),
        )
    }
}

/// Why a continuation cannot start.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum ContinuationError {
    /// A setting outside its allowed range.
    #[error("{field} = {value} is out of range: must be {allowed}")]
    Setting {
        /// The setting, e.g. `--omega-min` or `continuation.max_step`.
        field: &'static str,
        /// The rejected value.
        value: f64,
        /// The allowed range, in words.
        allowed: String,
    },
    /// The unit or the stops are not physical.
    #[error(transparent)]
    Unit(#[from] UnitError),
    /// The start orbit's frequency lies outside `[omega_min, omega_max]`.
    #[error("the start orbit's omega = {omega} lies outside [--omega-min, --omega-max] = [{min}, {max}]")]
    StartOutside {
        /// The start's frequency.
        omega: f64,
        /// `omega_min`.
        min: f64,
        /// `omega_max`.
        max: f64,
    },
    /// The start does not converge to an orbit of its signature at its own frequency.
    #[error("the start orbit ({signature}, period {period}) does not converge at omega = {omega}")]
    StartNotConverged {
        /// The start's signature.
        signature: String,
        /// Its period.
        period: u32,
        /// Its frequency.
        omega: f64,
    },
}

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
    /// `X_o = max |u_o(t)|` over the cycle (rigorous extrema).
    pub outer_amplitude: f64,
    /// `20 log10(X_o / u_g)`.
    pub transmittance_db: f64,
    /// Every Floquet multiplier has modulus `< 1 −` [`STABILITY_MARGIN`].
    pub stable: bool,
    /// No interior excursion of `r` beyond a stop (beyond [`VIABILITY_TOLERANCE`]`·Δ`) and
    /// every impact approached from inside.
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

/// A branch followed by continuation.
#[derive(Debug, Clone, PartialEq)]
pub struct Branch {
    /// Its index in [`Continuation::branches`].
    pub index: usize,
    /// The canonical signature of its orbits.
    pub signature: Signature,
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
    /// An interior extremum of `r` reaches a stop.
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
pub struct Event {
    /// The branch on which it was found.
    pub branch: usize,
    /// What happens.
    pub kind: EventKind,
    /// Its frequency.
    pub omega: f64,
    /// The signature of the branch that leaves here (branch point: the same; period
    /// doubling: the doubled one; grazing: the one with the extra impact), if any.
    pub signature_after: Option<Signature>,
    /// The period (forcing periods per cycle) of `signature_after`.
    pub period_after: Option<u32>,
    /// For grazing and vanishing impact: the impact involved, as its time from the first
    /// canonical impact in fractions of the cycle (grazing: the graze time).
    pub phase: Option<f64>,
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
    /// The branch came back to its seed: a closed loop (isola), followed once.
    ClosedLoop,
    /// The branch runs onto one already followed, or onto its image under the unit's
    /// symmetry (half a forcing period later with the stops mirrored), or onto another
    /// representation of the same orbits: [`BranchEnd::joins`] names that branch. A branch
    /// whose seed lies on one already followed ends so in both directions at its seed.
    Joins,
    /// A branch that leaves an event of a branch at [`ContinuationSettings::max_depth`]:
    /// recorded without points, not followed.
    MaxDepth,
}

impl EndReason {
    /// `omega-min`, `omega-max`, `step-below-minimum`, `point-cap`, `flight-merged`,
    /// `vanishing-impact`, `newton-failed`, `closed-loop`, `joins` or `max-depth`.
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
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Continuation {
    /// The branches, the start's first.
    pub branches: Vec<Branch>,
    /// The events, in the order found.
    pub events: Vec<Event>,
    /// The ends of the branches, two per branch.
    pub ends: Vec<BranchEnd>,
}

/// The cycle equations of one signature as functions of `X = (α, φ₂ … φₙ, ω)`.
struct System<'a> {
    unit: &'a Unit,
    signature: Signature,
    sides: Vec<i8>,
    g: Matrix2<f64>,
    g_hat: Matrix6<f64>,
    gap: f64,
    /// `2πp`: the cycle in forcing angle.
    angle: f64,
    /// `dÂ/dω`.
    a_rate: Matrix6<f64>,
}

/// The cycle evaluated at one `X`.
struct Eval {
    flights: Vec<Matrix6<f64>>,
    pre: Vec<Matrix6<f64>>,
    y1: Vector4<f64>,
    p0: Vector2<f64>,
    residual: DVector<f64>,
    /// `‖K‖∞ ‖K⁻¹‖∞` of the periodicity matrix `K = I − Ψ_xx`: the residuals carry rounding
    /// of about this many units of the motion's size.
    conditioning: f64,
    /// `∂R/∂X`, `n × (n + 1)`.
    jacobian: DMatrix<f64>,
}

/// Test functions at one point.
#[derive(Debug, Clone)]
struct Tests {
    fold: f64,
    branch: f64,
    doubling: f64,
    torus: f64,
    /// Per flight: `Δ − max|r|` over its interior critical points (`Δ` if none).
    clearance: Vec<f64>,
    /// Per flight: time (from the flight's start, in cycle fractions) and side of that
    /// critical point.
    graze: Vec<(f64, i8)>,
    /// Per impact: `s_j ṙ⁻_j`.
    approach: Vec<f64>,
}

/// A point on a branch with everything derived from it.
#[derive(Debug, Clone)]
struct Node {
    x: Vec<f64>,
    tangent: Vec<f64>,
    /// `R_X` at `x`.
    jacobian: DMatrix<f64>,
    point: ContinuationPoint,
    tests: Tests,
}

/// The hyperplane that closes the corrector's system.
enum Constraint<'a> {
    /// `normal · (X − through) = 0`.
    Plane {
        normal: &'a [f64],
        through: &'a [f64],
    },
    /// `ω = value`.
    Omega(f64),
}

impl<'a> System<'a> {
    fn new(unit: &'a Unit, stops: &Stops, signature: Signature) -> Self {
        let g = stops.impact_map(unit);
        let mut g_hat = Matrix6::identity();
        g_hat.fixed_view_mut::<2, 2>(2, 2).copy_from(&g);
        let co = unit.damping.map_or(0.0, |d| d.outer);
        let mut a_rate = Matrix6::zeros();
        a_rate[(2, 5)] = -co * unit.base_amplitude / unit.outer_mass;
        a_rate[(4, 5)] = -1.0;
        a_rate[(5, 4)] = 1.0;
        Self {
            unit,
            sides: signature.sides().to_vec(),
            angle: std::f64::consts::TAU * signature.period() as f64,
            signature,
            g,
            g_hat,
            gap: stops.gap,
            a_rate,
        }
    }

    fn n(&self) -> usize {
        self.sides.len()
    }

    /// Start and end of flight `f` as cycle fractions.
    fn flight_span(&self, x: &[f64], f: usize) -> (f64, f64) {
        let n = self.n();
        let start = if f == 0 { 0.0 } else { x[f] };
        let end = if f + 1 < n { x[f + 1] } else { 1.0 };
        (start, end)
    }

    /// Shortest flight of `X`, as a fraction of the cycle.
    fn shortest_flight(&self, x: &[f64]) -> f64 {
        (0..self.n())
            .map(|f| {
                let (a, b) = self.flight_span(x, f);
                b - a
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether `X` is finite, ordered with flights above [`MIN_FLIGHT`] and `ω > 0`.
    fn admissible(&self, x: &[f64]) -> bool {
        x.iter().all(|v| v.is_finite()) && x[self.n()] > 0.0 && self.shortest_flight(x) > MIN_FLIGHT
    }

    /// Residuals and the exact Jacobian in `X`. `None` when the periodicity solve is singular.
    fn evaluate(&self, x: &[f64]) -> Option<Eval> {
        self.evaluate_with(x, true)
    }

    /// Residuals only (an empty Jacobian): one 6×6 exponential per flight, no derivatives.
    fn evaluate_residual(&self, x: &[f64]) -> Option<Eval> {
        self.evaluate_with(x, false)
    }

    fn evaluate_with(&self, x: &[f64], with_jacobian: bool) -> Option<Eval> {
        let n = self.n();
        let omega = x[n];
        let alpha = x[0];
        let a = self.unit.augmented_matrix(omega);
        let b = a / omega;
        let b_rate = self.a_rate / omega - a / (omega * omega);
        let mut flights = Vec::with_capacity(n);
        let mut flights_rate = Vec::with_capacity(n);
        for f in 0..n {
            let (s, e) = self.flight_span(x, f);
            let sigma = (e - s) * self.angle;
            let bs = b * sigma;
            if !with_jacobian {
                flights.push(bs.exp());
                continue;
            }
            let mut big = Matrix12::zeros();
            big.fixed_view_mut::<6, 6>(0, 0).copy_from(&bs);
            big.fixed_view_mut::<6, 6>(6, 6).copy_from(&bs);
            big.fixed_view_mut::<6, 6>(0, 6)
                .copy_from(&(b_rate * sigma));
            let ex = big.exp();
            // The flight itself from its own 6×6 exponential: the 12×12 one needs more
            // squarings (its norm is larger), which costs the contact residuals an order or
            // two of accuracy; its diagonal block is not used.
            flights.push(bs.exp());
            flights_rate.push(ex.fixed_view::<6, 6>(0, 6).into_owned());
        }
        let mut pre: Vec<Matrix6<f64>> = Vec::with_capacity(n);
        pre.push(flights[0]);
        for f in 1..n {
            pre.push(flights[f] * self.g_hat * pre[f - 1]);
        }
        let psi = self.g_hat * pre[n - 1];
        let k = Matrix4::identity() - psi.fixed_view::<4, 4>(0, 0);
        let lu = k.lu();
        if !lu.is_invertible() {
            return None;
        }
        let inf_norm = |m: &Matrix4<f64>| {
            (0..4)
                .map(|i| (0..4).map(|j| m[(i, j)].abs()).sum::<f64>())
                .fold(0.0, f64::max)
        };
        let conditioning = inf_norm(&k) * lu.try_inverse().map_or(f64::INFINITY, |i| inf_norm(&i));
        let psi_xp = psi.fixed_view::<4, 2>(0, 4).into_owned();
        let p0 = Vector2::new(alpha.cos(), alpha.sin());
        let y1 = lu.solve(&(psi_xp * p0))?;
        let z1 = join(&y1, &p0);
        let h = join(&relative_displacement(), &Vector2::zeros());
        let mut residual = DVector::zeros(n);
        residual[0] = h.dot(&z1) - self.sides[0] as f64 * self.gap;
        for j in 1..n {
            residual[j] = h.dot(&(pre[j - 1] * z1)) - self.sides[j] as f64 * self.gap;
        }

        if !with_jacobian {
            return Some(Eval {
                flights,
                pre,
                y1,
                p0,
                residual,
                conditioning,
                jacobian: DMatrix::zeros(0, 0),
            });
        }
        let mut jacobian = DMatrix::zeros(n, n + 1);
        let zero = Matrix6::zeros();
        // The derivative of the residuals along one direction, given each flight's
        // derivative (`None`: unchanged) and that of p₀.
        let column = |dphi: &dyn Fn(usize) -> Option<Matrix6<f64>>,
                      dp0: Vector2<f64>|
         -> Option<DVector<f64>> {
            let mut dpre: Vec<Matrix6<f64>> = Vec::with_capacity(n);
            dpre.push(dphi(0).unwrap_or(zero));
            for f in 1..n {
                let mut d = flights[f] * (self.g_hat * dpre[f - 1]);
                if let Some(df) = dphi(f) {
                    d += df * (self.g_hat * pre[f - 1]);
                }
                dpre.push(d);
            }
            let dpsi = self.g_hat * dpre[n - 1];
            let dy1 = lu.solve(
                &(dpsi.fixed_view::<4, 4>(0, 0) * y1
                    + dpsi.fixed_view::<4, 2>(0, 4) * p0
                    + psi_xp * dp0),
            )?;
            let dz1 = join(&dy1, &dp0);
            let mut col = DVector::zeros(n);
            col[0] = h.dot(&dz1);
            for j in 1..n {
                col[j] = h.dot(&(dpre[j - 1] * z1 + pre[j - 1] * dz1));
            }
            Some(col)
        };
        let dp0 = Vector2::new(-alpha.sin(), alpha.cos());
        jacobian.set_column(0, &column(&|_| None, dp0)?);
        let rate = b * self.angle;
        for i in 1..n {
            let c = column(
                &|f| {
                    if f + 1 == i {
                        Some(rate * flights[f])
                    } else if f == i {
                        Some(-(rate * flights[f]))
                    } else {
                        None
                    }
                },
                Vector2::zeros(),
            )?;
            jacobian.set_column(i, &c);
        }
        let c = column(&|f| Some(flights_rate[f]), Vector2::zeros())?;
        jacobian.set_column(n, &c);
        Some(Eval {
            flights,
            pre,
            y1,
            p0,
            residual,
            conditioning,
            jacobian,
        })
    }

    /// Size of the motion against which residuals are measured (as in [`crate::cycle`]).
    fn scale(&self, y1: &Vector4<f64>) -> f64 {
        self.gap.max(y1[0].abs()).max(y1[1].abs())
    }

    /// Newton on `[R(X); constraint] = 0` from `guess`: the converged `X`, its evaluation
    /// and the Newton steps taken.
    fn correct(&self, guess: &[f64], constraint: &Constraint) -> Option<(Vec<f64>, Eval, usize)> {
        let n = self.n();
        let mut x = guess.to_vec();
        let mut last = f64::INFINITY;
        for iteration in 0..=CORRECTOR_ITERATIONS {
            if !self.admissible(&x) {
                return None;
            }
            let eval = self.evaluate(&x)?;
            let norm = eval.residual.amax();
            let scale = self.scale(&eval.y1);
            if !norm.is_finite() {
                return None;
            }
            // Converged; or stalled at the rounding floor of an ill-conditioned cycle, below
            // the fallback acceptance of `cycle`'s Newton.
            let floor = rounding_floor(&eval) * scale;
            if norm <= NEWTON_TOLERANCE * scale || (norm > STALL_RATIO * last && norm <= floor) {
                return Some((x, eval, iteration));
            }
            last = norm;
            if iteration == CORRECTOR_ITERATIONS {
                return None;
            }
            let step = self.newton_step(&x, &eval, constraint)?;
            if step.amax() <= STEP_ROUNDING * (1.0 + x[n].abs()) {
                return (norm <= floor).then_some((x, eval, iteration));
            }
            for k in 0..=n {
                x[k] += step[k];
            }
        }
        None
    }

    /// Chord Newton on `[R(X); constraint] = 0` from `guess`, with the bordered matrix built
    /// once from `jacobian` (the exact Jacobian at a nearby point, e.g. the previous point of
    /// the branch): each iteration costs one residual evaluation (no derivatives). Converges
    /// linearly at a rate of the order of the distance to that point; `None` when it does not
    /// reach the tolerance within [`CHORD_ITERATIONS`] or stops contracting. The returned
    /// evaluation has no Jacobian.
    fn correct_chord(
        &self,
        guess: &[f64],
        constraint: &Constraint,
        jacobian: &DMatrix<f64>,
    ) -> Option<(Vec<f64>, Eval, usize)> {
        let n = self.n();
        if jacobian.nrows() != n {
            return None;
        }
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n + 1)).copy_from(jacobian);
        match constraint {
            Constraint::Plane { normal, .. } => {
                for k in 0..=n {
                    m[(n, k)] = normal[k];
                }
            }
            Constraint::Omega(_) => m[(n, n)] = 1.0,
        }
        let lu = m.lu();
        let mut x = guess.to_vec();
        let mut last = f64::INFINITY;
        for iteration in 0..=CHORD_ITERATIONS {
            if !self.admissible(&x) {
                return None;
            }
            let eval = self.evaluate_residual(&x)?;
            let norm = eval.residual.amax();
            let scale = self.scale(&eval.y1);
            if !norm.is_finite() {
                return None;
            }
            if norm <= NEWTON_TOLERANCE * scale {
                return Some((x, eval, iteration));
            }
            if norm > CHORD_CONTRACTION * last {
                // Not contracting: too far from the Jacobian's point, or at the rounding
                // floor of the evaluation; full Newton tells the two apart.
                return None;
            }
            last = norm;
            let mut rhs = DVector::zeros(n + 1);
            rhs.rows_mut(0, n).copy_from(&(-&eval.residual));
            rhs[n] = match constraint {
                Constraint::Plane { normal, through } => -(0..=n)
                    .map(|k| normal[k] * (x[k] - through[k]))
                    .sum::<f64>(),
                Constraint::Omega(w) => w - x[n],
            };
            let step = lu.solve(&rhs)?;
            for k in 0..=n {
                x[k] += step[k];
            }
        }
        None
    }

    /// A point of the branch near `guess`: chord Newton with `jacobian` first, full Newton
    /// if that fails; with the full evaluation (Jacobian included) at the converged point.
    fn converge(
        &self,
        guess: &[f64],
        constraint: &Constraint,
        jacobian: &DMatrix<f64>,
    ) -> Option<(Vec<f64>, Eval, usize)> {
        if let Some((x, _, iterations)) = self.correct_chord(guess, constraint, jacobian) {
            if let Some(eval) = self.evaluate(&x) {
                return Some((x, eval, iterations));
            }
        }
        // A quick full Newton (at a rounding floor the chord iteration cannot finish) keeps
        // the step; a slow one shrinks it.
        self.correct(guess, constraint).map(|(x, e, it)| {
            let count = if it <= FALLBACK_QUICK {
                HARD_ITERATIONS
            } else {
                CHORD_ITERATIONS
            };
            (x, e, count)
        })
    }

    /// The unit tangent at a point with Jacobian `jacobian`, oriented along `previous`:
    /// the solution of `[R_X; previousᵀ] t = e_{n+1}`, normalised.
    fn tangent(&self, jacobian: &DMatrix<f64>, previous: &[f64]) -> Option<Vec<f64>> {
        let n = self.n();
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n + 1)).copy_from(jacobian);
        for k in 0..=n {
            m[(n, k)] = previous[k];
        }
        let mut rhs = DVector::zeros(n + 1);
        rhs[n] = 1.0;
        let t = m.lu().solve(&rhs)?;
        let norm = t.norm();
        (norm.is_finite() && norm > 0.0).then(|| t.iter().map(|v| v / norm).collect())
    }

    /// The mechanical state just before each impact and the forcing phase there.
    fn impact_states(&self, eval: &Eval) -> (Vec<Vector4<f64>>, Vec<Vector2<f64>>) {
        let n = self.n();
        let z1 = join(&eval.y1, &eval.p0);
        let before: Vec<Augmented> = (0..n)
            .map(|j| eval.pre[if j == 0 { n - 1 } else { j - 1 }] * z1)
            .collect();
        let x_before = before.iter().map(|z| z.fixed_rows::<4>(0).into()).collect();
        let p_at = (0..n)
            .map(|j| {
                if j == 0 {
                    eval.p0
                } else {
                    before[j].fixed_rows::<2>(4).into()
                }
            })
            .collect();
        (x_before, p_at)
    }

    /// The monodromy matrix from just after the first impact: flights and saltations.
    fn monodromy(
        &self,
        flow: &ForcedFlow,
        eval: &Eval,
        x_before: &[Vector4<f64>],
        p_at: &[Vector2<f64>],
    ) -> Matrix4<f64> {
        let n = self.n();
        let mut monodromy = Matrix4::identity();
        for f in 0..n {
            let next = (f + 1) % n;
            let hom = eval.flights[f].fixed_view::<4, 4>(0, 0).into_owned();
            let s = saltation(flow, &self.g, &x_before[next], &p_at[next]);
            monodromy = s * hom * monodromy;
        }
        monodromy
    }

    /// One test function at a converged `X` (`eval` with or without Jacobian), computing
    /// only what it needs. `None` when the fold test's tangent cannot be formed.
    fn test_value(&self, test: Test, x: &[f64], eval: &Eval, previous: &[f64]) -> Option<f64> {
        let n = self.n();
        let omega = x[n];
        match test {
            Test::Fold => {
                let full = self.evaluate(x)?;
                Some(self.tangent(&full.jacobian, previous)?[n])
            }
            Test::Branch | Test::Doubling | Test::Torus => {
                let flow = ForcedFlow::new(self.unit, omega);
                let (x_before, p_at) = self.impact_states(eval);
                let m = self.monodromy(&flow, eval, &x_before, &p_at);
                Some(match test {
                    Test::Branch => (m - Matrix4::identity()).determinant(),
                    Test::Doubling => (m + Matrix4::identity()).determinant(),
                    _ => torus_test(&eigenvalues(&m)?),
                })
            }
            Test::Clearance(f) => {
                let flow = ForcedFlow::new(self.unit, omega);
                let (x_before, p_at) = self.impact_states(eval);
                let (s, e) = self.flight_span(x, f);
                let start = join(&impact(&self.g, &x_before[f]), &p_at[f]);
                let r_fn = join(&relative_displacement(), &Vector2::zeros());
                let ext = flow.critical_extrema(&start, (e - s) * self.angle / omega, &[r_fn])[0];
                let value = ext.max.max(-ext.min);
                Some(if value.is_finite() {
                    self.gap - value
                } else {
                    self.gap
                })
            }
            Test::Approach(j) => {
                let (x_before, _) = self.impact_states(eval);
                Some(self.sides[j] as f64 * (x_before[j][3] - x_before[j][2]))
            }
        }
    }

    /// Orbit data and test functions at a converged `X`.
    fn describe(&self, x: &[f64], eval: &Eval, tangent: &[f64], branch: usize) -> Node {
        let n = self.n();
        let omega = x[n];
        let flow = ForcedFlow::new(self.unit, omega);
        let (x_before, p_at) = self.impact_states(eval);
        let approach: Vec<f64> = (0..n)
            .map(|j| self.sides[j] as f64 * (x_before[j][3] - x_before[j][2]))
            .collect();
        let r_fn = join(&relative_displacement(), &Vector2::zeros());
        let uo_fn = Augmented::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
        let cycle = self.angle / omega;
        let mut outer_amplitude: f64 = 0.0;
        let mut clearance = Vec::with_capacity(n);
        let mut graze = Vec::with_capacity(n);
        for f in 0..n {
            let (s, e) = self.flight_span(x, f);
            let after = impact(&self.g, &x_before[f]);
            let start = join(&after, &p_at[f]);
            let ext = flow.mixed_extrema(&start, (e - s) * cycle, &[r_fn, uo_fn], &[true, false]);
            outer_amplitude = outer_amplitude.max(ext[1].max.abs()).max(ext[1].min.abs());
            let (high, low) = (ext[0].max, -ext[0].min);
            if high.is_finite() || low.is_finite() {
                let (value, time, side) = if high >= low {
                    (high, ext[0].argmax, 1)
                } else {
                    (low, ext[0].argmin, -1)
                };
                clearance.push(self.gap - value);
                graze.push((time / cycle, side));
            } else {
                clearance.push(self.gap);
                graze.push((f64::NAN, 0));
            }
        }
        let tol = VIABILITY_TOLERANCE * self.gap;
        let viable = approach.iter().all(|&v| v > 0.0) && clearance.iter().all(|&c| c >= -tol);

        let monodromy = self.monodromy(&flow, eval, &x_before, &p_at);
        let floquet_multipliers: Vec<Complex<f64>> = eigenvalues(&monodromy)
            .map(|e| e.to_vec())
            .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); 4]);
        let stable = floquet_multipliers
            .iter()
            .all(|m| m.norm() < 1.0 - STABILITY_MARGIN);
        let torus = torus_test(&floquet_multipliers);
        let tests = Tests {
            fold: tangent[n],
            branch: (monodromy - Matrix4::identity()).determinant(),
            doubling: (monodromy + Matrix4::identity()).determinant(),
            torus,
            clearance,
            graze,
            approach,
        };
        let mut impact_phases = vec![0.0; n];
        impact_phases[1..n].copy_from_slice(&x[1..n]);
        let point = ContinuationPoint {
            branch,
            omega,
            alpha: wrap(x[0]),
            impact_phases,
            outer_amplitude,
            transmittance_db: transmittance_db(outer_amplitude, self.unit.base_amplitude),
            stable,
            viable,
            floquet_multipliers,
            domega_ds: tangent[n],
            residual: eval.residual.amax(),
        };
        Node {
            x: x.to_vec(),
            tangent: tangent.to_vec(),
            jacobian: eval.jacobian.clone(),
            point,
            tests,
        }
    }

    /// The direction of the branch that leaves `x` roughly along `guess`: a corrector step
    /// of length `step` along `guess` (in the hyperplane normal to it), and the unit secant
    /// to the converged point. `None` when the corrector fails or lands back on the branch
    /// of tangent `known` (secant within [`PROBE_COSINE`] of it).
    fn probe(&self, x: &[f64], guess: &[f64], known: &[f64], step: f64) -> Option<Vec<f64>> {
        let n = self.n();
        let pred: Vec<f64> = (0..=n).map(|k| x[k] + step * guess[k]).collect();
        let (x1, _, _) = self.correct(
            &pred,
            &Constraint::Plane {
                normal: guess,
                through: &pred,
            },
        )?;
        let d: Vec<f64> = (0..=n).map(|k| x1[k] - x[k]).collect();
        let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        let known_norm = known.iter().map(|v| v * v).sum::<f64>().sqrt();
        let cosine = d.iter().zip(known).map(|(a, b)| a * b).sum::<f64>() / (norm * known_norm);
        (norm > 0.0 && cosine.abs() < PROBE_COSINE).then(|| d.iter().map(|v| v / norm).collect())
    }

    /// The tangent of the other branch through a branch point `x` (Jacobian `jacobian`),
    /// the branch of tangent `known` being one of the two.
    ///
    /// At a simple branch point `R_X` has a two-dimensional null space `{v₁, v₂}` and a left
    /// null vector `ψ`; the tangents `c v₁ + d v₂` of the branches through it are the roots of
    /// the algebraic branching equation `ψᵀ R_XX[c v₁ + d v₂, c v₁ + d v₂] = 0`. The second
    /// derivatives are central differences ([`BRANCHING_DIFFERENCE`]) of the exact Jacobian:
    /// only a direction comes from them, and every point of the new branch is put on the
    /// equations by the corrector. Of the two roots, the one least parallel to `known`.
    fn other_direction(
        &self,
        x: &[f64],
        jacobian: &DMatrix<f64>,
        known: &[f64],
    ) -> Option<Vec<f64>> {
        let n = self.n();
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n + 1)).copy_from(jacobian);
        let svd = m.svd(true, true);
        let (u, v_t) = (svd.u?, svd.v_t?);
        let mut order: Vec<usize> = (0..=n).collect();
        order.sort_by(|&a, &b| svd.singular_values[a].total_cmp(&svd.singular_values[b]));
        let v1 = v_t.row(order[0]).transpose();
        let v2 = v_t.row(order[1]).transpose();
        // The left null space of the padded matrix holds e_{n+1} (its zero row) and (ψ, 0):
        // eliminate the last component.
        let (ua, ub) = (u.column(order[0]), u.column(order[1]));
        let w = ua * ub[n] - ub * ua[n];
        let psi = w.rows(0, n).into_owned();
        let psi_norm = psi.norm();
        if psi_norm.is_nan() || psi_norm <= 0.0 {
            return None;
        }
        let psi = psi / psi_norm;
        let scale = x.iter().fold(1.0f64, |m, v| m.max(v.abs()));
        let eps = BRANCHING_DIFFERENCE * scale;
        let directional = |d: &DVector<f64>| -> Option<DMatrix<f64>> {
            let plus: Vec<f64> = (0..=n).map(|k| x[k] + eps * d[k]).collect();
            let minus: Vec<f64> = (0..=n).map(|k| x[k] - eps * d[k]).collect();
            let jp = self.evaluate(&plus)?.jacobian;
            let jm = self.evaluate(&minus)?.jacobian;
            Some((jp - jm) / (2.0 * eps))
        };
        let d1 = directional(&v1)?;
        let d2 = directional(&v2)?;
        let a11 = psi.dot(&(&d1 * &v1));
        let a12 = 0.5 * (psi.dot(&(&d1 * &v2)) + psi.dot(&(&d2 * &v1)));
        let a22 = psi.dot(&(&d2 * &v2));
        let disc = (a12 * a12 - a11 * a22).max(0.0).sqrt();
        let roots: Vec<(f64, f64)> = if a11.abs() >= a22.abs() {
            if a11 == 0.0 {
                return None;
            }
            vec![((-a12 + disc) / a11, 1.0), ((-a12 - disc) / a11, 1.0)]
        } else {
            vec![(1.0, (-a12 + disc) / a22), (1.0, (-a12 - disc) / a22)]
        };
        let k = DVector::from_column_slice(known);
        let k = &k / k.norm();
        roots
            .into_iter()
            .map(|(c, d)| {
                let t = &v1 * c + &v2 * d;
                let t = &t / t.norm();
                (k.dot(&t).abs(), t)
            })
            .filter(|(c, t)| c.is_finite() && t.iter().all(|v| v.is_finite()))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, t)| t.iter().copied().collect())
    }

    /// Continues Newton after [`Self::correct`] while its steps keep shrinking, down to
    /// rounding: near a branch point the corrector's system is nearly singular and Newton
    /// converges only linearly along the singular direction, so the residual test stops it
    /// about `√(tolerance)` away from the branch; this brings it onto the branch.
    /// The branch point of these equations near `x` (within about `1e-4`), solved by the
    /// regular defining system of [`crate::branch_point`]; `None` if that does not converge
    /// there, or if its solution has an unfolding `β` or residual above the corrector's
    /// acceptance (no branch point of this system, only a near one).
    fn branch_point_near(&self, x: &[f64]) -> Option<Vec<f64>> {
        let h = |u: &[f64]| {
            if !self.admissible(u) {
                return None;
            }
            let eval = self.evaluate(u)?;
            Some((eval.residual, eval.jacobian))
        };
        let found = locate_branch_point(h, x)?;
        let eval = self.evaluate(&found.u)?;
        let floor = rounding_floor(&eval) * self.scale(&eval.y1);
        (found.unfolding.abs() <= floor && eval.residual.amax() <= floor).then_some(found.u)
    }

    fn polish(&self, x: Vec<f64>, eval: Eval, constraint: &Constraint) -> (Vec<f64>, Eval) {
        let n = self.n();
        let (mut x, mut eval) = (x, eval);
        let mut last = f64::INFINITY;
        for _ in 0..POLISH_ITERATIONS {
            let Some(step) = self.newton_step(&x, &eval, constraint) else {
                break;
            };
            let size = step.amax();
            if size.is_nan()
                || size >= POLISH_SHRINK * last
                || size <= STEP_ROUNDING * (1.0 + x[n].abs())
            {
                break;
            }
            last = size;
            let trial: Vec<f64> = (0..=n).map(|k| x[k] + step[k]).collect();
            if !self.admissible(&trial) {
                break;
            }
            let Some(e) = self.evaluate(&trial) else {
                break;
            };
            x = trial;
            eval = e;
        }
        (x, eval)
    }

    /// The point of the branch at chord fraction `theta` between its points `a` and `b`
    /// (corrected within the hyperplane normal to the chord), described as a point of the
    /// branch of `a` with its tangent oriented as `a`'s.
    fn node_at(&self, a: &Node, b: &Node, theta: f64) -> Option<Node> {
        let n = self.n();
        let chord: Vec<f64> = (0..=n).map(|k| b.x[k] - a.x[k]).collect();
        let through: Vec<f64> = (0..=n).map(|k| a.x[k] + theta * chord[k]).collect();
        let plane = Constraint::Plane {
            normal: &chord,
            through: &through,
        };
        let (x, eval, _) = self.converge(&through, &plane, &a.jacobian)?;
        let tangent = self.tangent(&eval.jacobian, &a.tangent)?;
        Some(self.describe(&x, &eval, &tangent, a.point.branch))
    }

    /// The Newton step of the bordered system at `x`.
    fn newton_step(&self, x: &[f64], eval: &Eval, constraint: &Constraint) -> Option<DVector<f64>> {
        let n = self.n();
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n + 1)).copy_from(&eval.jacobian);
        let mut rhs = DVector::zeros(n + 1);
        rhs.rows_mut(0, n).copy_from(&(-&eval.residual));
        match constraint {
            Constraint::Plane { normal, through } => {
                for k in 0..=n {
                    m[(n, k)] = normal[k];
                }
                rhs[n] = -(0..=n)
                    .map(|k| normal[k] * (x[k] - through[k]))
                    .sum::<f64>();
            }
            Constraint::Omega(w) => {
                m[(n, n)] = 1.0;
                rhs[n] = w - x[n];
            }
        }
        m.lu().solve(&rhs)
    }
}

/// A branch still to be followed.
struct Seed {
    signature: Signature,
    x: Vec<f64>,
    /// Direction to follow (both ways); `None`: the null vector of `R_X`.
    tangent: Option<Vec<f64>>,
    from_event: Option<usize>,
    /// Born at a grazing: impact `j` of the new signature is the graze; a direction on which
    /// it is approached from outside is dropped.
    grazing_impact: Option<usize>,
    /// Switching depth: 0 for the start, one more than its parent's for a switch.
    depth: usize,
}

/// A switch already taken: signature, `X`.
type SwitchKey = (Signature, Vec<f64>);

/// Follows the branch through `start` in both directions of `ω` within
/// `[omega_min, omega_max]`, locating events on it, and (with `follow_switches`) the
/// branches that leave it at branch points, period doublings and grazings, up to
/// `max_branches` in all and `max_depth` switches deep. Each branch ends in each direction
/// with an [`EndReason`]; each branch is followed once: one that runs onto a branch already
/// followed, or onto its mirror image, ends there ([`EndReason::Joins`]), and each event is
/// listed once, in its order along its branch.
///
/// Continuation goes on through non-viable stretches: each point carries its `viable` flag,
/// and grazing and vanishing-impact events say where viability is lost.
///
/// # Errors
/// [`ContinuationError::Setting`] for a bad setting (see [`ContinuationSettings::validate`]);
/// [`ContinuationError::Unit`] for a non-physical unit or stops;
/// [`ContinuationError::StartOutside`] when `start.omega` is outside the range;
/// [`ContinuationError::StartNotConverged`] when Newton at `start.omega` from the start's
/// unknowns does not converge.
pub fn continue_orbit(
    unit: &Unit,
    stops: &Stops,
    start: &SignatureOrbit,
    settings: &ContinuationSettings,
) -> Result<Continuation, ContinuationError> {
    let mut out = Continuation::default();
    continue_orbit_after(unit, stops, start, settings, &mut out)?;
    Ok(out)
}

/// [`continue_orbit`] after the branches already in `out` (of the same unit and stops):
/// unless `start` lies on one of them or on its mirror image (then `Ok(false)` and `out` is
/// unchanged), the branches from `start` are appended to `out`, numbered after those there,
/// each ending [`EndReason::Joins`] where it runs onto any branch of `out`, and events
/// already in `out` are not listed again. `max_branches` counts the branches from `start`.
///
/// # Errors
/// As [`continue_orbit`].
pub fn continue_orbit_after(
    unit: &Unit,
    stops: &Stops,
    start: &SignatureOrbit,
    settings: &ContinuationSettings,
    out: &mut Continuation,
) -> Result<bool, ContinuationError> {
    settings.validate()?;
    unit.validate()?;
    stops.validate()?;
    if !(start.omega >= settings.omega_min && start.omega <= settings.omega_max) {
        return Err(ContinuationError::StartOutside {
            omega: start.omega,
            min: settings.omega_min,
            max: settings.omega_max,
        });
    }
    let not_converged = || ContinuationError::StartNotConverged {
        signature: start.signature.to_string(),
        period: start.signature.period(),
        omega: start.omega,
    };
    let n = start.signature.impacts();
    let mut x = Vec::with_capacity(n + 1);
    x.push(start.alpha);
    x.extend_from_slice(&start.impact_phases[1..n.min(start.impact_phases.len())]);
    x.push(start.omega);
    if x.len() != n + 1 {
        return Err(not_converged());
    }
    let system = System::new(unit, stops, start.signature.clone());
    let (x, eval, _) = system
        .correct(&x, &Constraint::Omega(start.omega))
        .ok_or_else(not_converged)?;
    let seed = Seed {
        signature: start.signature.clone(),
        x,
        tangent: None,
        from_event: None,
        grazing_impact: None,
        depth: 0,
    };
    let atlas = Atlas::of(&out.branches);
    if let Some(t) = seed_tangent(&system, &seed, &eval) {
        if atlas.joins(&seed.signature, &seed.x, &t, None).is_some() {
            return Ok(false);
        }
    }
    let mut run = Run {
        unit,
        stops,
        settings,
        out,
        atlas,
        switched: Vec::new(),
        queue: VecDeque::from([seed]),
        followed: 0,
    };
    while let Some(seed) = run.queue.pop_front() {
        if run.followed >= settings.max_branches {
            break;
        }
        run.follow(seed);
    }
    Ok(true)
}

/// The state of a continuation from one start: the result so far, the branches followed
/// (an [`Atlas`]), the switch points taken and the seeds still to follow.
struct Run<'a> {
    unit: &'a Unit,
    stops: &'a Stops,
    settings: &'a ContinuationSettings,
    out: &'a mut Continuation,
    atlas: Atlas,
    switched: Vec<SwitchKey>,
    queue: VecDeque<Seed>,
    /// Branches followed from this start.
    followed: usize,
}

impl Run<'_> {
    /// Follows the branch of `seed`, records it, its ends and events, and queues its switches.
    fn follow(&mut self, seed: Seed) {
        self.followed += 1;
        let index = self.out.branches.len();
        let system = System::new(self.unit, self.stops, seed.signature.clone());
        let follow = Follow {
            system: &system,
            settings: self.settings,
            origin: &seed,
            branch: index,
            atlas: &self.atlas,
        };
        let Some(followed) = follow.branch() else {
            // The seed itself could not be evaluated: record the attempt as a branch without
            // points ending where it started.
            let omega = seed.x[seed.x.len() - 1];
            self.unfollowed(
                &seed.signature,
                seed.from_event,
                omega,
                EndReason::NewtonFailed,
            );
            return;
        };
        self.out.branches.push(Branch {
            index,
            signature: seed.signature.clone(),
            period: seed.signature.period(),
            points: followed.nodes.iter().map(|n| n.point.clone()).collect(),
            from_event: seed.from_event,
        });
        self.out.ends.extend(followed.ends);
        self.atlas.curves.push(followed.curve);
        for found in followed.events {
            self.event(&system, &seed, index, found);
        }
        // The seed of this branch is a switch point too (so the way back is not taken).
        self.switched.push((seed.signature.clone(), seed.x.clone()));
    }

    /// Records a branch that is not followed: no points, both ends `reason` at `omega`.
    fn unfollowed(
        &mut self,
        signature: &Signature,
        from_event: Option<usize>,
        omega: f64,
        reason: EndReason,
    ) {
        let index = self.out.branches.len();
        self.out.branches.push(Branch {
            index,
            signature: signature.clone(),
            period: signature.period(),
            points: Vec::new(),
            from_event,
        });
        for _ in 0..2 {
            self.out.ends.push(BranchEnd {
                branch: index,
                omega,
                reason,
                joins: None,
            });
        }
    }

    /// Lists an event found on branch `index` (unless it is listed already: a branch point
    /// seen from both branches through it, or the image of one listed) and queues the branch
    /// that leaves there, or records the depth cut.
    fn event(&mut self, system: &System, seed: &Seed, index: usize, found: Found) {
        let mut event = found.event;
        event.branch = index;
        event.point.branch = index;
        if listed(self.out, &system.signature, event.kind, &found.node.x) {
            return;
        }
        let event_index = self.out.events.len();
        let switches = matches!(
            event.kind,
            EventKind::BranchPoint | EventKind::PeriodDoubling | EventKind::Grazing
        ) && event.signature_after.is_some();
        if self.settings.follow_switches && switches {
            if seed.depth >= self.settings.max_depth {
                if let Some(signature) = event.signature_after.clone() {
                    let omega = event.omega;
                    self.out.events.push(event);
                    self.unfollowed(&signature, Some(event_index), omega, EndReason::MaxDepth);
                    return;
                }
            }
            let step = (SWITCH_STEP * self.settings.initial_step).max(self.settings.min_step);
            if let Some(mut next) = switch_seed(system, &found.node, &event, event_index, step) {
                let key = (next.signature.clone(), next.x.clone());
                if !self.switched.iter().any(|k| same_switch(k, &key)) {
                    next.depth = seed.depth + 1;
                    self.switched.push(key);
                    self.queue.push_back(next);
                }
            }
        }
        self.out.events.push(event);
    }
}

/// Whether an event of `kind` at `x` on a branch of `signature` is in `out` already, as
/// itself or as one of its other representations ([`representations`]).
fn listed(out: &Continuation, signature: &Signature, kind: EventKind, x: &[f64]) -> bool {
    let tangent = vec![0.0; x.len()];
    let reps = representations(signature, x, &tangent);
    out.events.iter().filter(|e| e.kind == kind).any(|e| {
        let Some(branch) = out.branches.get(e.branch) else {
            return false;
        };
        let y = point_unknowns(&e.point);
        reps.iter()
            .any(|r| r.signature == branch.signature && same_point(&r.x, &y))
    })
}

/// `X = (α, φ₂ … φₙ, ω)` of a point.
fn point_unknowns(p: &ContinuationPoint) -> Vec<f64> {
    let mut x = vec![p.alpha];
    x.extend_from_slice(p.impact_phases.get(1..).unwrap_or(&[]));
    x.push(p.omega);
    x
}

/// Whether two `X` agree to [`SWITCH_DEDUP`] (`α` modulo 2π).
fn same_point(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && wrap(a[0] - b[0]).abs() < SWITCH_DEDUP
        && a[1..]
            .iter()
            .zip(&b[1..])
            .all(|(p, q)| (p - q).abs() < SWITCH_DEDUP)
}

/// Whether two switch keys are the same point of the same signature ([`SWITCH_DEDUP`]).
fn same_switch(a: &SwitchKey, b: &SwitchKey) -> bool {
    a.0 == b.0 && same_point(&a.1, &b.1)
}

/// One representation of an orbit: its signature, `X` and tangent.
struct Representation {
    signature: Signature,
    x: Vec<f64>,
    tangent: Vec<f64>,
    /// The orbit as given (no rotation, no mirror).
    identity: bool,
}

/// Every representation of the orbit `x` of `signature` (tangent `tangent`) in canonical
/// form. The same motion timed from another impact whose rotation of the sides is canonical
/// (`k`: `α + 2πp φ_k`, phases `φ_{j+k} − φ_k`), and its image under the unit's symmetry:
/// with symmetric stops and the base's forcing odd over half a period, `−u(t + T/2)` is a
/// motion too, with the sides mirrored (`s → −s`) and, timed from impact `k`,
/// `α + 2πp φ_k − π`.
fn representations(signature: &Signature, x: &[f64], tangent: &[f64]) -> Vec<Representation> {
    let sides = signature.sides();
    let n = sides.len();
    let period = signature.period();
    let angle = std::f64::consts::TAU * period as f64;
    let phase = |v: &[f64], k: usize| if k == 0 { 0.0 } else { v[k] };
    let mut out = Vec::new();
    for mirror in [false, true] {
        let sign = if mirror { -1 } else { 1 };
        for k in 0..n {
            let rotated: Vec<i8> = (0..n).map(|j| sign * sides[(j + k) % n]).collect();
            let Ok(canonical) = Signature::from_sides(&rotated, period) else {
                continue;
            };
            if canonical.sides() != rotated.as_slice() {
                continue;
            }
            let shift = if mirror { std::f64::consts::PI } else { 0.0 };
            let mut xr = vec![wrap(x[0] + angle * phase(x, k) - shift)];
            let mut tr = vec![tangent[0] + angle * phase(tangent, k)];
            for j in 1..n {
                let i = (j + k) % n;
                xr.push((phase(x, i) - phase(x, k)).rem_euclid(1.0));
                tr.push(phase(tangent, i) - phase(tangent, k));
            }
            xr.push(x[n]);
            tr.push(tangent[n]);
            out.push(Representation {
                signature: canonical,
                x: xr,
                tangent: tr,
                identity: !mirror && k == 0,
            });
        }
    }
    out
}

/// Width in `ω` (rad/s) of the buckets in which a [`Curve`] files its segments.
const CURVE_BUCKET: f64 = 0.01;

/// A branch as a polyline in `X`, with the unit tangent at each vertex, its segments filed
/// by `ω` for the test of whether a point lies on it.
struct Curve {
    branch: usize,
    signature: Signature,
    x: Vec<Vec<f64>>,
    tangent: Vec<Vec<f64>>,
    segments: Vec<(usize, usize)>,
    buckets: HashMap<i64, Vec<usize>>,
}

impl Curve {
    fn new(branch: usize, signature: Signature) -> Self {
        Self {
            branch,
            signature,
            x: Vec::new(),
            tangent: Vec::new(),
            segments: Vec::new(),
            buckets: HashMap::new(),
        }
    }

    /// A branch recorded in a [`Continuation`]: its points in order, the tangent at each
    /// from the chord between its neighbours.
    fn of(branch: &Branch) -> Self {
        let mut curve = Self::new(branch.index, branch.signature.clone());
        let xs: Vec<Vec<f64>> = branch.points.iter().map(point_unknowns).collect();
        for i in 0..xs.len() {
            let (a, b) = (&xs[i.saturating_sub(1)], &xs[(i + 1).min(xs.len() - 1)]);
            let mut t: Vec<f64> = (0..a.len())
                .map(|k| {
                    if k == 0 {
                        wrap(b[0] - a[0])
                    } else {
                        b[k] - a[k]
                    }
                })
                .collect();
            let norm = t.iter().map(|v| v * v).sum::<f64>().sqrt();
            t.iter_mut().for_each(|v| *v /= norm);
            let k = curve.push(&xs[i], &t);
            if k > 0 {
                curve.link(k - 1, k);
            }
        }
        curve
    }

    /// Adds a vertex; its index.
    fn push(&mut self, x: &[f64], tangent: &[f64]) -> usize {
        self.x.push(x.to_vec());
        self.tangent.push(tangent.to_vec());
        self.x.len() - 1
    }

    /// Adds the segment between vertices `i` and `j`, filed in every bucket that a point
    /// projecting onto it within [`LOOP_CLOSURE`] of its length can fall in.
    fn link(&mut self, i: usize, j: usize) {
        let (a, b) = (&self.x[i], &self.x[j]);
        let n = a.len() - 1;
        let length = distance(a, b);
        let margin = 2.0 * LOOP_CLOSURE * length;
        let lo = ((a[n].min(b[n]) - margin) / CURVE_BUCKET).floor();
        let hi = ((a[n].max(b[n]) + margin) / CURVE_BUCKET).floor();
        if !(lo.is_finite() && hi.is_finite()) {
            return;
        }
        let s = self.segments.len();
        self.segments.push((i, j));
        for bucket in lo as i64..=hi as i64 {
            self.buckets.entry(bucket).or_default().push(s);
        }
    }

    /// Whether the point `x` with unit tangent `tangent` lies on the curve: a segment passes
    /// within [`LOOP_CLOSURE`] of its length of `x` (the chord of a step departs from the
    /// branch by far less) and the tangent interpolated there is parallel to `tangent` to
    /// [`LOOP_TANGENT_COSINE`] (a branch crossing this one at a branch point is not on it).
    fn holds(&self, x: &[f64], tangent: &[f64]) -> bool {
        let n = x.len() - 1;
        let bucket = (x[n] / CURVE_BUCKET).floor();
        if !bucket.is_finite() {
            return false;
        }
        let Some(segments) = self.buckets.get(&(bucket as i64)) else {
            return false;
        };
        segments.iter().any(|&s| {
            let (i, j) = self.segments[s];
            let (a, b) = (&self.x[i], &self.x[j]);
            let Some((theta, gap)) = projection(a, b, x) else {
                return false;
            };
            if gap >= LOOP_CLOSURE * distance(a, b) {
                return false;
            }
            let w = theta.clamp(0.0, 1.0);
            let t: Vec<f64> = (0..=n)
                .map(|k| (1.0 - w) * self.tangent[i][k] + w * self.tangent[j][k])
                .collect();
            cosine(&t, tangent).abs() > LOOP_TANGENT_COSINE
        })
    }
}

/// The branches followed, as curves.
struct Atlas {
    curves: Vec<Curve>,
}

impl Atlas {
    /// The branches of a [`Continuation`].
    fn of(branches: &[Branch]) -> Self {
        Self {
            curves: branches.iter().map(Curve::of).collect(),
        }
    }

    /// The branch that the orbit `x` of `signature` (tangent `tangent`), or another of its
    /// representations, lies on; with `live` (the branch being followed, its last step
    /// `step` long) also that one, against the representations other than `x` itself that
    /// lie more than a step from `x` (near a point that is its own image, such as a branch
    /// point of the asymmetric pair on a symmetric orbit, the image of a point is the point
    /// a little further on: the branch ends only once it has passed there).
    fn joins(
        &self,
        signature: &Signature,
        x: &[f64],
        tangent: &[f64],
        live: Option<(&Curve, f64)>,
    ) -> Option<usize> {
        let reps = representations(signature, x, tangent);
        for rep in &reps {
            if let Some(c) = self
                .curves
                .iter()
                .find(|c| c.signature == rep.signature && c.holds(&rep.x, &rep.tangent))
            {
                return Some(c.branch);
            }
            if let Some((live, step)) = live {
                if !rep.identity
                    && live.signature == rep.signature
                    && distance(&rep.x, x) > step
                    && live.holds(&rep.x, &rep.tangent)
                {
                    return Some(live.branch);
                }
            }
        }
        None
    }
}

/// Euclidean distance between two `X` (`α` modulo 2π).
fn distance(a: &[f64], b: &[f64]) -> f64 {
    (0..a.len())
        .map(|k| {
            let d = if k == 0 {
                wrap(b[0] - a[0])
            } else {
                b[k] - a[k]
            };
            d * d
        })
        .sum::<f64>()
        .sqrt()
}

/// Cosine of the angle between two vectors.
fn cosine(a: &[f64], b: &[f64]) -> f64 {
    let dot: f64 = a.iter().zip(b).map(|(u, v)| u * v).sum();
    let na = a.iter().map(|v| v * v).sum::<f64>().sqrt();
    let nb = b.iter().map(|v| v * v).sum::<f64>().sqrt();
    dot / (na * nb)
}

/// The tangent at the seed of a branch: the seed's own, or the null vector of `R_X` oriented
/// towards increasing `ω`.
fn seed_tangent(system: &System, seed: &Seed, eval: &Eval) -> Option<Vec<f64>> {
    if let Some(t) = &seed.tangent {
        return Some(t.clone());
    }
    let n = system.n();
    let mut m = DMatrix::zeros(n + 1, n + 1);
    m.view_mut((0, 0), (n, n + 1)).copy_from(&eval.jacobian);
    let svd = m.svd(false, true);
    let v_t = svd.v_t?;
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)?;
    let mut t: Vec<f64> = v_t.row(k).iter().copied().collect();
    if t[n] < 0.0 {
        t.iter_mut().for_each(|v| *v = -*v);
    }
    Some(t)
}

/// A located event with the branch point it sits at.
struct Found {
    event: Event,
    node: Node,
}

/// The result of following one branch both ways.
struct Followed {
    nodes: Vec<Node>,
    /// In their order along the branch.
    events: Vec<Found>,
    ends: Vec<BranchEnd>,
    /// The branch as followed.
    curve: Curve,
}

/// Following one branch: the problem (its equations, the settings, its seed, the branches
/// already followed).
struct Follow<'a, 's> {
    system: &'a System<'s>,
    settings: &'a ContinuationSettings,
    origin: &'a Seed,
    branch: usize,
    atlas: &'a Atlas,
}

impl Follow<'_, '_> {
    fn end(&self, reason: EndReason, omega: f64) -> BranchEnd {
        BranchEnd {
            branch: self.branch,
            omega,
            reason,
            joins: None,
        }
    }

    /// Follows the branch of the seed both ways; a switched seed that lies on a branch
    /// already followed is not followed (both ends [`EndReason::Joins`]).
    fn branch(&self) -> Option<Followed> {
        let (system, seed, branch) = (self.system, self.origin, self.branch);
        let eval = system.evaluate(&seed.x)?;
        let tangent = seed_tangent(system, seed, &eval)?;
        let mut seed_node = system.describe(&seed.x, &eval, &tangent, branch);
        let mut curve = Curve::new(branch, system.signature.clone());
        curve.push(&seed.x, &tangent);
        if seed.from_event.is_some() {
            if let Some(other) = self.atlas.joins(&system.signature, &seed.x, &tangent, None) {
                let end = BranchEnd {
                    joins: Some(other),
                    ..self.end(EndReason::Joins, seed.x[system.n()])
                };
                return Some(Followed {
                    nodes: vec![seed_node],
                    events: Vec::new(),
                    ends: vec![end, end],
                    curve,
                });
            }
            // At a switch point the test functions sit at zero by construction (a
            // multiplier at ±1, a zero-velocity impact): no sign change is read from the
            // seed.
            seed_node.tests = Tests {
                fold: f64::NAN,
                branch: f64::NAN,
                doubling: f64::NAN,
                torus: f64::NAN,
                clearance: vec![f64::NAN; system.n()],
                graze: seed_node.tests.graze.clone(),
                approach: vec![f64::NAN; system.n()],
            };
        }
        let cap = self.settings.max_points_per_branch;
        let (forward, events_forward, end_forward) =
            self.direction(&seed_node, 1.0, cap / 2, &mut curve);
        let second_cap = cap.saturating_sub(1 + forward.len());
        let (backward, mut events, end_backward) = if end_forward.reason == EndReason::ClosedLoop {
            // The whole loop is followed already.
            (Vec::new(), Vec::new(), end_forward)
        } else {
            self.direction(&seed_node, -1.0, second_cap, &mut curve)
        };
        // In the branch's order: backward reversed, seed, forward.
        events.reverse();
        events.extend(events_forward);
        // The backward points were found along −t: orient their tangents along that order.
        let mut nodes: Vec<Node> = backward
            .into_iter()
            .rev()
            .map(|mut node| {
                node.tangent.iter_mut().for_each(|v| *v = -*v);
                node.point.domega_ds = -node.point.domega_ds;
                node
            })
            .collect();
        nodes.push(seed_node);
        nodes.extend(forward);
        Some(Followed {
            nodes,
            events,
            ends: vec![end_forward, end_backward],
            curve,
        })
    }

    /// The point on the band's edge `edge` between `prev` and `x` (just beyond it).
    fn edge_node(&self, prev: &Node, x: &[f64], edge: f64) -> Option<Node> {
        let system = self.system;
        let n = system.n();
        let w = (edge - prev.x[n]) / (x[n] - prev.x[n]);
        let guess: Vec<f64> = (0..=n)
            .map(|k| prev.x[k] + w * (x[k] - prev.x[k]))
            .collect();
        let (xe, ee, _) = system.correct(&guess, &Constraint::Omega(edge))?;
        let te = system.tangent(&ee.jacobian, &prev.tangent)?;
        Some(system.describe(&xe, &ee, &te, self.branch))
    }

    /// Follows one direction from `seed` (its tangent times `direction`), adding the points
    /// to `curve` (whose vertex 0 is the seed).
    fn direction(
        &self,
        seed: &Node,
        direction: f64,
        cap: usize,
        curve: &mut Curve,
    ) -> (Vec<Node>, Vec<Found>, BranchEnd) {
        let (system, settings) = (self.system, self.settings);
        let n = system.n();
        let mut prev = seed.clone();
        prev.tangent.iter_mut().for_each(|v| *v *= direction);
        prev.point.domega_ds = prev.tangent[n];
        if prev.tests.fold.is_finite() {
            prev.tests.fold = prev.tangent[n];
        }
        let switched = self.origin.from_event.is_some();
        let mut h = if switched {
            (SWITCH_STEP * settings.initial_step).max(settings.min_step)
        } else {
            settings.initial_step
        };
        let mut nodes: Vec<Node> = Vec::new();
        let mut events = Vec::new();
        let mut vertex = 0;
        let mut before: Option<Node> = None;
        loop {
            if nodes.len() >= cap {
                return (nodes, events, self.end(EndReason::PointCap, prev.x[n]));
            }
            if h < settings.min_step {
                let reason = if system.shortest_flight(&prev.x) < MERGE_WARNING {
                    EndReason::FlightMerged
                } else {
                    EndReason::StepBelowMinimum
                };
                return (nodes, events, self.end(reason, prev.x[n]));
            }
            let pred: Vec<f64> = (0..=n).map(|k| prev.x[k] + h * prev.tangent[k]).collect();
            let plane = Constraint::Plane {
                normal: &prev.tangent,
                through: &pred,
            };
            let Some((x, eval, iterations)) = system.converge(&pred, &plane, &prev.jacobian) else {
                if switched && nodes.is_empty() && h <= settings.min_step * 2.0 {
                    return (nodes, events, self.end(EndReason::NewtonFailed, prev.x[n]));
                }
                h *= 0.5;
                continue;
            };
            let Some(tangent) = system.tangent(&eval.jacobian, &prev.tangent) else {
                h *= 0.5;
                continue;
            };
            let turn: f64 = tangent.iter().zip(&prev.tangent).map(|(a, b)| a * b).sum();
            if turn < MIN_TANGENT_COSINE {
                h *= 0.5;
                continue;
            }
            let mut node = system.describe(&x, &eval, &tangent, self.branch);
            // Leaving the band: the last point lies on its edge.
            let bound = if x[n] > settings.omega_max {
                Some((settings.omega_max, EndReason::OmegaMax))
            } else if x[n] < settings.omega_min {
                Some((settings.omega_min, EndReason::OmegaMin))
            } else {
                None
            };
            if let Some((edge, reason)) = bound {
                let Some(edge_node) = self.edge_node(&prev, &x, edge) else {
                    h *= 0.5;
                    continue;
                };
                events.extend(detect(system, &prev, &edge_node, before.as_ref()));
                let k = curve.push(&edge_node.x, &edge_node.tangent);
                curve.link(vertex, k);
                nodes.push(edge_node);
                return (nodes, events, self.end(reason, edge));
            }
            // A branch born at a grazing that leaves on the side where the new impact is
            // approached from outside is not a motion.
            if let Some(j) = self.origin.grazing_impact {
                if nodes.is_empty() && node.tests.approach[j] <= 0.0 {
                    return (
                        nodes,
                        events,
                        self.end(EndReason::VanishingImpact, prev.x[n]),
                    );
                }
            }
            events.extend(detect(system, &prev, &node, before.as_ref()));
            node.point.domega_ds = node.tangent[n];
            let k = curve.push(&node.x, &node.tangent);
            curve.link(vertex, k);
            vertex = k;
            if let Some(other) = self.atlas.joins(
                &system.signature,
                &node.x,
                &node.tangent,
                Some((curve, distance(&prev.x, &node.x))),
            ) {
                nodes.push(node);
                let end = BranchEnd {
                    joins: Some(other),
                    ..self.end(EndReason::Joins, x[n])
                };
                return (nodes, events, end);
            }
            // Closed loop: the step from `prev` to `node` passes the seed.
            let along = cosine(&node.tangent, &seed.tangent) * direction;
            if nodes.len() >= LOOP_MIN_POINTS
                && along > LOOP_TANGENT_COSINE
                && passes(&prev.x, &node.x, &seed.x, h)
            {
                nodes.push(node);
                return (nodes, events, self.end(EndReason::ClosedLoop, x[n]));
            }
            nodes.push(node.clone());
            before = Some(std::mem::replace(&mut prev, node));
            h = if iterations <= EASY_ITERATIONS {
                h * STEP_GROWTH
            } else if iterations > HARD_ITERATIONS {
                h * STEP_SHRINK
            } else {
                h
            }
            .min(settings.max_step);
        }
    }
}

/// The parameter `θ` of the projection of `p` on the line through `a` and `b` (`a + θ (b −
/// a)`) and the distance of `p` from that projection (`α` modulo 2π); `None` for `a = b`.
fn projection(a: &[f64], b: &[f64], p: &[f64]) -> Option<(f64, f64)> {
    let d = |u: &[f64], v: &[f64], k: usize| {
        if k == 0 {
            wrap(u[0] - v[0])
        } else {
            u[k] - v[k]
        }
    };
    let m = a.len();
    let ab: Vec<f64> = (0..m).map(|k| d(b, a, k)).collect();
    let ap: Vec<f64> = (0..m).map(|k| d(p, a, k)).collect();
    let len2: f64 = ab.iter().map(|v| v * v).sum();
    if len2 == 0.0 {
        return None;
    }
    let t = ab.iter().zip(&ap).map(|(u, v)| u * v).sum::<f64>() / len2;
    if !(-LOOP_CLOSURE..=1.0 + LOOP_CLOSURE).contains(&t) {
        return None;
    }
    let dist2: f64 = (0..m).map(|k| (ap[k] - t * ab[k]).powi(2)).sum();
    Some((t, dist2.sqrt()))
}

/// Whether the segment from `a` to `b` passes within [`LOOP_CLOSURE`]` · h` of `p` (angles
/// `α` compared modulo 2π), `p` projecting inside the segment.
fn passes(a: &[f64], b: &[f64], p: &[f64], h: f64) -> bool {
    projection(a, b, p).is_some_and(|(_, gap)| gap < LOOP_CLOSURE * h)
}

/// The Neimark–Sacker test `Π_{i<j} (μ_i μ_j − 1)`: real (conjugates pair up); a conjugate
/// pair contributes `|μ|² − 1`, which vanishes when the pair crosses the unit circle.
fn torus_test(multipliers: &[Complex<f64>]) -> f64 {
    let mut product = Complex::new(1.0, 0.0);
    for i in 0..multipliers.len() {
        for j in i + 1..multipliers.len() {
            product *= multipliers[i] * multipliers[j] - 1.0;
        }
    }
    product.re
}

/// Which test function.
#[derive(Debug, Clone, Copy)]
enum Test {
    Fold,
    Branch,
    Doubling,
    Torus,
    Clearance(usize),
    Approach(usize),
}

impl Test {
    /// The test function's value at a point. The branch-point test is `det(M − I)` over
    /// `dω/ds`: both change sign at a fold (a multiplier through 1 where the branch turns),
    /// their ratio does not (it is `det([R_X; tᵀ])` up to a factor that does not vanish), so
    /// a fold and a branch point within one step are both seen.
    fn value(self, t: &Tests) -> f64 {
        match self {
            Test::Fold => t.fold,
            Test::Branch => t.branch / t.fold,
            Test::Doubling => t.doubling,
            Test::Torus => t.torus,
            Test::Clearance(f) => t.clearance[f],
            Test::Approach(j) => t.approach[j],
        }
    }

    fn kind(self) -> EventKind {
        match self {
            Test::Fold => EventKind::Fold,
            Test::Branch => EventKind::BranchPoint,
            Test::Doubling => EventKind::PeriodDoubling,
            Test::Torus => EventKind::NeimarkSacker,
            Test::Clearance(_) => EventKind::Grazing,
            Test::Approach(_) => EventKind::VanishingImpact,
        }
    }
}

/// Every test function of a branch of `n` impacts.
fn all_tests(n: usize) -> Vec<Test> {
    let mut tests = vec![Test::Fold, Test::Branch, Test::Doubling, Test::Torus];
    for f in 0..n {
        tests.push(Test::Clearance(f));
        tests.push(Test::Approach(f));
    }
    tests
}

/// Every test whose function changes sign between `a` and `b`.
fn sign_changes(a: &Tests, b: &Tests, n: usize) -> Vec<Test> {
    let mut tests = all_tests(n);
    tests.retain(|t| t.value(a) * t.value(b) < 0.0);
    tests
}

/// A pair of zeros of one test function within the step from `a` to `b`, which the signs at
/// `a` and `b` do not show: the quadratic in arclength through the function's values at
/// `before`, `a` and `b` has its extremum inside the step, of the other sign. Returns the
/// chord fraction of that extremum (for the first test where it happens).
fn hidden_pair(before: &Node, a: &Node, b: &Node, n: usize) -> Option<f64> {
    let s0 = -distance(&before.x, &a.x);
    let s2 = distance(&a.x, &b.x);
    if !(s0 < 0.0 && s2 > 0.0) {
        return None;
    }
    all_tests(n).into_iter().find_map(|test| {
        let v0 = test.value(&before.tests);
        let v1 = test.value(&a.tests);
        let v2 = test.value(&b.tests);
        if !(v0.is_finite() && v1.is_finite() && v2.is_finite()) || v1 * v2 <= 0.0 {
            return None;
        }
        // Newton's form: q(s) = v0 + d01 (s − s0) + c2 (s − s0) s.
        let d01 = (v1 - v0) / -s0;
        let d12 = (v2 - v1) / s2;
        let c2 = (d12 - d01) / (s2 - s0);
        if c2 == 0.0 || !c2.is_finite() {
            return None;
        }
        let vertex = 0.5 * (s0 - d01 / c2);
        let q = v0 + d01 * (vertex - s0) + c2 * (vertex - s0) * vertex;
        (vertex > 0.0 && vertex < s2 && q * v1 < 0.0).then_some(vertex / s2)
    })
}

/// The events between two consecutive points `a`, `b` (`before`: the point before `a`): the
/// zero of every test function that changed sign over the step, each located on its own, in
/// their order along the step. Where a test function may have two zeros within the step
/// ([`hidden_pair`]), the step is split at the point between them and each half searched.
fn detect(system: &System, a: &Node, b: &Node, before: Option<&Node>) -> Vec<Found> {
    let split = before
        .and_then(|p| hidden_pair(p, a, b, system.n()))
        .and_then(|theta| system.node_at(a, b, theta));
    match split {
        Some(middle) => {
            let mut found = detect_step(system, a, &middle);
            found.extend(detect_step(system, &middle, b));
            found
        }
        None => detect_step(system, a, b),
    }
}

/// [`detect`] over one step, without splitting it.
fn detect_step(system: &System, a: &Node, b: &Node) -> Vec<Found> {
    let mut found: Vec<(f64, Found)> = sign_changes(&a.tests, &b.tests, system.n())
        .into_iter()
        .filter_map(|test| {
            let (theta, node) = locate(system, a, b, test)?;
            Some((theta, event_at(system, a, b, test, node)?))
        })
        .collect();
    found.sort_by(|p, q| p.0.total_cmp(&q.0));
    found.into_iter().map(|(_, f)| f).collect()
}

/// The event of `test` at its located zero `node` between `a` and `b`, unless the zero is
/// not an event (a jump of the test function, a neutral saddle, a graze at a flight's end).
fn event_at(system: &System, a: &Node, b: &Node, test: Test, mut node: Node) -> Option<Found> {
    let n = system.n();
    if let Test::Branch = test {
        // At a branch point R_X has a two-dimensional null space and the bordered tangent
        // solve picks an arbitrary member of it: the branch's own direction there is the
        // chord between the two regular points around it.
        let chord: Vec<f64> = (0..=n).map(|k| b.x[k] - a.x[k]).collect();
        let norm = chord.iter().map(|v| v * v).sum::<f64>().sqrt();
        node.tangent = chord.iter().map(|v| v / norm).collect();
        node.point.domega_ds = node.tangent[n];
    }
    // The branch test is accepted on its determinant `det(M − I)`, zero at a branch point
    // (the tangent there, hence `dω/ds`, is arbitrary: on the asymmetric pair through a
    // pitchfork `dω/ds` vanishes too).
    let value = |t: &Tests| match test {
        Test::Branch => t.branch.abs(),
        _ => test.value(t).abs(),
    };
    let (va, vb, located) = (value(&a.tests), value(&b.tests), value(&node.tests));
    let accepted = match test {
        // A branch point is accepted where `R_X` has lost rank (located by the regular
        // defining system, or, where that does not converge, pinned by the bracket to about
        // `√ε`), which a jump of the test (a pole as an impact's velocity vanishes) does not
        // show.
        Test::Branch => rank_deficiency(&node.jacobian) < BRANCH_RANK_DEFICIENCY,
        _ => located <= EVENT_ACCEPTANCE * va.max(vb),
    };
    if located.is_nan() || !accepted {
        return None;
    }
    let mut phase = None;
    let mut signature_after = None;
    match test {
        Test::Torus => {
            let on_circle =
                node.point.floquet_multipliers.iter().any(|m| {
                    m.im.abs() > REAL_MULTIPLIER && (m.norm() - 1.0).abs() < TORUS_TOLERANCE
                });
            if !on_circle {
                return None;
            }
        }
        Test::Branch => signature_after = Some(system.signature.clone()),
        Test::Doubling => signature_after = doubled(&system.signature),
        Test::Clearance(f) => {
            let (time, side) = node.tests.graze[f];
            let (s, e) = system.flight_span(&node.x, f);
            // A critical point of r at a flight's end is the shadow of a vanishing impact
            // there (r̈ turns r back at the stop), not a graze between impacts.
            if !(time > GRAZE_INTERIOR && e - s - time > GRAZE_INTERIOR) {
                return None;
            }
            phase = Some(s + time);
            signature_after = grazed(&system.signature, f, side).map(|(sig, _)| sig);
        }
        Test::Approach(j) => {
            phase = Some(if j == 0 { 0.0 } else { node.x[j] });
        }
        Test::Fold => {}
    }
    let period_after = signature_after.as_ref().map(|s| s.period());
    Some(Found {
        event: Event {
            branch: node.point.branch,
            kind: test.kind(),
            omega: node.x[n],
            signature_after,
            period_after,
            phase,
            point: node.point.clone(),
        },
        node,
    })
}

/// The zero of `test` between `a` and `b`, by Illinois on the chord fraction `θ`: each trial
/// point `a + θ (b − a)` is corrected onto the branch within the hyperplane normal to the
/// chord. Returns `θ` at the zero and the point there.
fn locate(system: &System, a: &Node, b: &Node, test: Test) -> Option<(f64, Node)> {
    let n = system.n();
    let chord: Vec<f64> = (0..=n).map(|k| b.x[k] - a.x[k]).collect();
    // A trial point on the branch at chord fraction θ, and the test function there: only
    // what the test needs is computed (the full point is built once, at the end).
    let at = |theta: f64| -> Option<(Vec<f64>, f64)> {
        let through: Vec<f64> = (0..=n).map(|k| a.x[k] + theta * chord[k]).collect();
        let plane = Constraint::Plane {
            normal: &chord,
            through: &through,
        };
        let (x, eval) = match test {
            // Near a branch point Newton converges only linearly along the singular
            // direction: full Newton, then polish.
            Test::Branch => {
                let (x, eval, _) = system.correct(&through, &plane)?;
                system.polish(x, eval, &plane)
            }
            _ => {
                let (x, eval, _) = system
                    .correct_chord(&through, &plane, &a.jacobian)
                    .or_else(|| system.correct(&through, &plane))?;
                (x, eval)
            }
        };
        let mut value = system.test_value(test, &x, &eval, &a.tangent)?;
        if let Test::Branch = test {
            value /= system.tangent(&eval.jacobian, &a.tangent)?[n];
        }
        Some((x, value))
    };
    let finish = |x: &[f64]| -> Option<Node> {
        let eval = system.evaluate(x)?;
        let tangent = system.tangent(&eval.jacobian, &a.tangent)?;
        Some(system.describe(x, &eval, &tangent, a.point.branch))
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut f_lo = test.value(&a.tests);
    let mut f_hi = test.value(&b.tests);
    if f_lo.is_nan() || f_hi.is_nan() || f_lo * f_hi >= 0.0 {
        return None;
    }
    let mut best: Option<(f64, Vec<f64>)> = None;
    let mut side = 0i8;
    for _ in 0..LOCATION_ITERATIONS {
        if hi - lo <= LOCATION_FRACTION {
            break;
        }
        let mut theta = (lo * f_hi - hi * f_lo) / (f_hi - f_lo);
        if !(theta > lo && theta < hi) {
            theta = 0.5 * (lo + hi);
        }
        let (x, f) = at(theta)?;
        if !f.is_finite() {
            return None;
        }
        let done = f == 0.0;
        if f.signum() == f_hi.signum() {
            hi = theta;
            f_hi = f;
            if side == -1 {
                f_lo *= 0.5;
            }
            side = -1;
        } else {
            lo = theta;
            f_lo = f;
            if side == 1 {
                f_hi *= 0.5;
            }
            side = 1;
        }
        best = Some((theta, x));
        if done {
            break;
        }
    }
    let (theta, mut x) = best?;
    if let Test::Branch = test {
        // The bracket pins a branch point only to about √ε (see above): the regular defining
        // system takes it from there to rounding.
        if let Some(u) = system.branch_point_near(&x) {
            x = u;
        }
    }
    Some((theta, finish(&x)?))
}

/// The signature repeated over twice the periods, if within the limits of [`Signature`].
fn doubled(signature: &Signature) -> Option<Signature> {
    let mut sides = signature.sides().to_vec();
    sides.extend_from_slice(signature.sides());
    Signature::from_sides(&sides, 2 * signature.period()).ok()
}

/// The signature with an impact on `side` inserted after impact `flight` (during that
/// flight), and the rotation `k` of the new side list (with the new impact at position
/// `flight + 1`) that is canonical.
fn grazed(signature: &Signature, flight: usize, side: i8) -> Option<(Signature, usize)> {
    let mut sides = signature.sides().to_vec();
    sides.insert(flight + 1, side);
    let canonical = Signature::from_sides(&sides, signature.period()).ok()?;
    let m = sides.len();
    let k = (0..m).find(|&k| (0..m).all(|j| sides[(j + k) % m] == canonical.sides()[j]))?;
    Some((canonical, k))
}

/// The seed of the branch that leaves at `event` (found at `node` on `system`'s branch).
///
/// At a branch point (and at a period doubling, a branch point of the doubled cycle) the
/// null space of `R_X` holds both branches' tangents, not in general orthogonal in these
/// coordinates: the direction orthogonal to the known tangent is only a start. A corrector
/// step of length `step` along it lands on the new branch, and the secant from the
/// bifurcation to that point is the new branch's direction ([`System::probe`]).
fn switch_seed(
    system: &System,
    node: &Node,
    event: &Event,
    event_index: usize,
    step: f64,
) -> Option<Seed> {
    let n = system.n();
    match event.kind {
        EventKind::BranchPoint => {
            let eval = system.evaluate(&node.x)?;
            let t = system.other_direction(&node.x, &eval.jacobian, &node.tangent)?;
            let t = system.probe(&node.x, &t, &node.tangent, step)?;
            Some(Seed {
                signature: system.signature.clone(),
                x: node.x.clone(),
                tangent: Some(t),
                from_event: Some(event_index),
                grazing_impact: None,
                depth: 0,
            })
        }
        EventKind::PeriodDoubling => {
            let signature = doubled(&system.signature)?;
            // The orbit traversed twice, in the doubled cycle's fractions.
            let mut x2 = vec![node.x[0]];
            x2.extend((1..n).map(|i| 0.5 * node.x[i]));
            x2.push(0.5);
            x2.extend((1..n).map(|i| 0.5 + 0.5 * node.x[i]));
            x2.push(node.x[n]);
            let mut t2 = vec![node.tangent[0]];
            t2.extend((1..n).map(|i| 0.5 * node.tangent[i]));
            t2.push(0.0);
            t2.extend((1..n).map(|i| 0.5 * node.tangent[i]));
            t2.push(node.tangent[n]);
            let doubled_system = System {
                signature: signature.clone(),
                sides: signature.sides().to_vec(),
                angle: 2.0 * system.angle,
                ..*system
            };
            let eval = doubled_system.evaluate(&x2)?;
            let t = doubled_system.other_direction(&x2, &eval.jacobian, &t2)?;
            let t = doubled_system.probe(&x2, &t, &t2, step)?;
            Some(Seed {
                signature,
                x: x2,
                tangent: Some(t),
                from_event: Some(event_index),
                grazing_impact: None,
                depth: 0,
            })
        }
        EventKind::Grazing => {
            let phase = event.phase?;
            let f = (0..n).rev().find(|&f| f == 0 || node.x[f] <= phase)?;
            let side = node.tests.graze[f].1;
            let (signature, k) = grazed(&system.signature, f, side)?;
            // Times of the new impacts (old impacts and the graze), in the inserted order.
            let mut times = vec![0.0];
            times.extend_from_slice(&node.x[1..n]);
            times.insert(f + 1, phase);
            let m = n + 1;
            let shift = times[k];
            let mut x = vec![node.x[0] + system.angle * shift];
            for j in 1..m {
                x.push((times[(j + k) % m] - shift).rem_euclid(1.0));
            }
            x.push(node.x[n]);
            Some(Seed {
                signature,
                x,
                tangent: None,
                from_event: Some(event_index),
                grazing_impact: Some((m - k + f + 1) % m),
                depth: 0,
            })
        }
        _ => None,
    }
}
