//! What a continuation is asked to do ([`ContinuationSettings`]) and why it may refuse
//! ([`ContinuationError`]).

use crate::sequence::SequenceError;
use crate::unit::UnitError;
use thiserror::Error;

/// Default switching depth ([`ContinuationSettings::max_depth`]). Measured on the run of `+-`
/// from ω = 2.1725686 over 1.8925686–2.4925686 rad/s (paper scene, one thread): depth 2
/// follows 15 branches, 7 183 points, 85 events in 1.4 s of CPU; depth 3 27 branches,
/// 27 524 points, 323 events in 24 s, the third level being period-8 orbits of the doubling
/// cascade (20 341 of the points, 16 impacts per cycle each).
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
    /// recorded as a branch without points ending [`EndReason::MaxDepth`](crate::EndReason::MaxDepth)(crate::EndReason::MaxDepth)).
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
        check_range_and_steps(
            (self.omega_min, self.omega_max),
            [
                ("continuation.min_step", self.min_step),
                ("continuation.max_step", self.max_step),
                ("continuation.initial_step", self.initial_step),
            ],
            check,
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
    /// The start's impact sequence names a contact pair the model lacks.
    #[error(transparent)]
    Sequence(#[from] SequenceError),
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
    /// The start does not converge to an orbit of its signature (or impact sequence) at its own
    /// frequency.
    #[error("the start orbit ({signature}, period {period}) does not converge at omega = {omega}")]
    StartNotConverged {
        /// The start's signature (or impact sequence, as text).
        signature: String,
        /// Its period.
        period: u32,
        /// Its frequency.
        omega: f64,
    },
}

/// The checks a continuation's and a boundary's settings share: the frequency range
/// (`--omega-min` finite and > 0, `--omega-max` > it) and the steps (`min_step` > 0,
/// `max_step` ≥ it, `initial_step` between them; each named by its field in `names`), each
/// through `check` (field, value, whether it is allowed besides finite, what is allowed),
/// which makes the caller's error.
///
/// # Errors
/// The first of `check`'s errors.
pub(crate) fn check_range_and_steps<E>(
    (omega_min, omega_max): (f64, f64),
    steps: [(&'static str, f64); 3],
    check: impl Fn(&'static str, f64, bool, String) -> Result<(), E>,
) -> Result<(), E> {
    let [(min_name, min_step), (max_name, max_step), (initial_name, initial_step)] = steps;
    check(
        "--omega-min",
        omega_min,
        omega_min > 0.0,
        "finite and > 0".into(),
    )?;
    check(
        "--omega-max",
        omega_max,
        omega_max > omega_min,
        format!("finite and > --omega-min = {omega_min}"),
    )?;
    check(min_name, min_step, min_step > 0.0, "finite and > 0".into())?;
    check(
        max_name,
        max_step,
        max_step >= min_step,
        format!("finite and >= {min_name} = {min_step}"),
    )?;
    check(
        initial_name,
        initial_step,
        initial_step >= min_step && initial_step <= max_step,
        format!("in [{min_step}, {max_step}] (min_step, max_step)"),
    )
}
