//! Pseudo-arclength continuation in `ω` of orbits of any impact signature of the unit
//! ([`continue_orbit`]) and of any impact sequence of a [`crate::LinearModel`] such as a chain
//! ([`continue_sequence`]), with bifurcation events and branch switching.
//!
//! The unknowns are those of [`crate::cycle_equations`], `x = (α, φ₂ … φₙ)`, with the forcing
//! frequency `ω` appended: `X = (x, ω)`; the residuals and their exact Jacobian in `X` are
//! [`crate::CycleEquations::evaluate_in_omega`] (the unit on stack matrices, a model on heap ones). The `n` contact residuals `R(X)` define a curve in `X`; it is
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
//! direction `B'(ω) σ`, read off the top-right block of the doubled exponential
//! `exp([[Bσ, B'σ], [0, Bσ]])` (whose diagonal blocks are `Φ` itself).
//!
//! Along the branch each point carries its Floquet multipliers, amplitude and viability, and
//! test functions whose sign changes between consecutive points are events: every test that
//! changed sign over a step is located on its own, by the Illinois variant of regula falsi on
//! the chord between the two points (each trial point corrected onto the branch) until the
//! chord fraction is bracketed to `1e-13`, and the events of a step are listed
//! in their order along it (events closer than the step are all found):
//!
//! | event | test function |
//! |---|---|
//! | fold | `dω/ds`, the tangent's `ω` component |
//! | branch point | `det(M − I) / (dω/ds)` (both factors change sign at a fold, the ratio only at a branch point) |
//! | period doubling | `det(M + I)` |
//! | Neimark–Sacker | `Π_{i<j} (μ_i μ_j − 1)`, kept when a complex pair sits on the unit circle |
//! | grazing | per flight and contact pair, the distance of the pair's `r` to its nearer stop over the interior critical points of `r` |
//! | vanishing impact | per impact, `s_j ṙ⁻_j` of its pair |
//!
//! `M` is the monodromy matrix with saltation at each impact, `μ_i` its eigenvalues.
//!
//! By job: `system` (the equations in `X` on any model, with the unit's and a model's
//! sides in `unit` and `model`), the predictor, the corrector, the test functions, event
//! location, branch switching, branch bookkeeping and the driver that follows the branches.
//!
//! Each branch is followed once. The unit is symmetric (stops at `±Δ`, forcing odd over half
//! a period): with `u(t)` a motion, `−u(t + T/2)` is one too, with the sides mirrored (so is a
//! model whose every pair has equal gaps on both sides); and a motion timed from another
//! impact is the same motion. A branch whose seed, or whose next
//! point, lies on a branch already followed in any of these representations (a branch and
//! its mirror image, the asymmetric pair leaving a symmetric orbit, a period-doubled orbit
//! one period later) ends there with [`EndReason::Joins`], and an event listed already in
//! another representation is not listed again. Switching is bounded by
//! [`ContinuationSettings::max_depth`].

mod boundary;
mod branch_point;
mod branches;
mod corrector;
mod driver;
mod events;
mod model;
mod predictor;
mod result;
mod settings;
mod switching;
mod system;
mod test_functions;
mod unit;

pub use boundary::{
    follow_boundary, follow_sequence_boundary, Boundary, BoundaryAt, BoundaryEnd,
    BoundaryEndReason, BoundaryError, BoundaryPoint, BoundarySettings, BoundarySpecialPoint,
    BoundaryStart, SequenceBoundaryStart, SpecialKind,
};
pub use corrector::CORRECTOR_ACCEPTANCE;
pub use result::{Branch, BranchEnd, Continuation, ContinuationPoint, EndReason, Event, EventKind};
pub use settings::{ContinuationError, ContinuationSettings, DEFAULT_MAX_DEPTH};

use crate::cycle::SignatureOrbit;
use crate::model::LinearModel;
use crate::sequence::ImpactSequence;
use crate::sequence_verdicts::SequenceOrbit;
use crate::unit::{Stops, Unit};
use branches::Atlas;
use corrector::Constraint;
use driver::Run;
use model::ModelBranch;
use predictor::seed_tangent;
use std::collections::VecDeque;
use switching::Seed;
use system::{BranchModel, System};
use unit::UnitBranch;

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
    let model = UnitBranch::new(unit, stops, start.signature.clone());
    start_run(model, x, settings, out).ok_or_else(not_converged)
}

/// Corrects the start `x` (`X` of the model's label at its frequency) onto its orbit and,
/// unless it lies on a branch of `out` already (`Some(false)`), follows its branches into
/// `out` (`Some(true)`); `None` when the start does not converge.
fn start_run<M: BranchModel>(
    model: M,
    x: Vec<f64>,
    settings: &ContinuationSettings,
    out: &mut Continuation<M::Label>,
) -> Option<bool> {
    let omega = x[x.len() - 1];
    let system = System::new(model);
    let (x, eval, _) = system.correct(&x, &Constraint::Omega(omega))?;
    let seed = Seed {
        signature: system.label().clone(),
        x,
        tangent: None,
        from_event: None,
        grazing_impact: None,
        depth: 0,
    };
    let atlas = Atlas::of(&out.branches, system.model.mirrored());
    if let Some(t) = seed_tangent(&system, None, &eval) {
        if atlas.joins(&seed.signature, &seed.x, &t, None).is_some() {
            return Some(false);
        }
    }
    let mut run = Run {
        model: &system.model,
        settings,
        out,
        atlas,
        switched: Vec::new(),
        queue: VecDeque::from([seed]),
        followed: 0,
    };
    run.run();
    Some(true)
}

/// [`continue_orbit`] on any [`LinearModel`] with contact pairs (a chain of cells): follows the
/// branch through `start`, an orbit of an impact sequence (e.g. from
/// [`crate::solve_sequence`] or [`crate::sequence_orbits`]), both ways within
/// `[omega_min, omega_max]`, with the same events (grazing and vanishing impact for every
/// contact pair) and switching. Each point carries the amplitude of every cell's outer mass
/// ([`ContinuationPoint::cell_outer_amplitudes`]) and the verdicts of
/// [`crate::solve_sequence`] (one assembly for every model). Mirror images count as the same branch when every
/// pair's stops are symmetric.
///
/// # Errors
/// [`ContinuationError::Setting`] for a bad setting; [`ContinuationError::Sequence`] when the
/// start's sequence names a pair the model lacks or has contact phases (compliant pairs are
/// not continued); [`ContinuationError::StartOutside`] and
/// [`ContinuationError::StartNotConverged`] as [`continue_orbit`].
pub fn continue_sequence(
    model: &LinearModel,
    start: &SequenceOrbit,
    settings: &ContinuationSettings,
) -> Result<Continuation<ImpactSequence>, ContinuationError> {
    let mut out = Continuation::default();
    continue_sequence_after(model, start, settings, &mut out)?;
    Ok(out)
}

/// [`continue_sequence`] after the branches already in `out` (of the same model), as
/// [`continue_orbit_after`]: `Ok(false)` when `start` lies on one of them.
///
/// # Errors
/// As [`continue_sequence`].
pub fn continue_sequence_after(
    model: &LinearModel,
    start: &SequenceOrbit,
    settings: &ContinuationSettings,
    out: &mut Continuation<ImpactSequence>,
) -> Result<bool, ContinuationError> {
    settings.validate()?;
    if !(start.omega >= settings.omega_min && start.omega <= settings.omega_max) {
        return Err(ContinuationError::StartOutside {
            omega: start.omega,
            min: settings.omega_min,
            max: settings.omega_max,
        });
    }
    let branch = ModelBranch::new(model, start.sequence.clone())?;
    let not_converged = || ContinuationError::StartNotConverged {
        signature: start.sequence.to_string(),
        period: start.sequence.period(),
        omega: start.omega,
    };
    let n = start.sequence.impacts().len();
    if start.impact_phases.len() != n {
        return Err(not_converged());
    }
    let mut x = Vec::with_capacity(n + 1);
    x.push(start.alpha);
    x.extend_from_slice(&start.impact_phases[1..]);
    x.push(start.omega);
    start_run(branch, x, settings, out).ok_or_else(not_converged)
}
