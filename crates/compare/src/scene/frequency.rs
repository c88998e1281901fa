//! The forcing frequencies a scene can be run at in bounded time.
//!
//! Both solvers do work in proportion to the free oscillations a forcing period holds: the
//! simulator scans every flight for contacts, the analytic solver finds the extrema of every
//! flight, and a run needs a number of forcing periods for its transients to decay. Forced far
//! below its fastest mode, one period of the unit holds `ω_fastest/ω` free oscillations; forced
//! far above its slowest mode, one free oscillation holds `ω/ω_slowest` forcing periods. Both
//! ratios are bounded here, so that every command ends in bounded time on any finite input,
//! and a frequency outside the bounds is refused with the reason and the range.
//!
//! The natural frequencies are those of the scene's linear model without stops and without
//! damping (the chain of cells in series for a chain, the structure's own `M` and `K` for a
//! structure), from the symmetric eigenproblem `M^{-1/2} K M^{-1/2}`.

use super::structure::{ContactLaw, Structure};
use super::Scene;
use nalgebra::{DMatrix, SymmetricEigen};
use thiserror::Error;

/// Most free oscillations of the scene's fastest mode that one forcing period may hold.
///
/// Measured on the paper's unit (fastest mode 2.449 rad/s) just inside the bound, ω = 2.4495e-3
/// rad/s, release build, CPU time (the machine was loaded, wall times meaningless): `rattle
/// orbit` 0.63 s, `rattle simulate` 0.86 s, `rattle compare` 0.90 s. Below it the work grows
/// in proportion: `rattle orbit --omega 2.5e-4` took 6.0 s and `rattle simulate --omega 2.5e-5`
/// 5.6 s of CPU, and at ω = 1e-6 the simulator did not end.
pub const MAX_OSCILLATIONS_PER_PERIOD: f64 = 1e3;

/// Most forcing periods that one free oscillation of the scene's slowest mode may hold.
///
/// Far above its modes the unit barely moves, and both solvers are quick up to about
/// `ω/ω_slowest = 1e140` on the paper's unit; beyond, the simulator's phase arithmetic loses
/// every digit and a run no longer ends (ω = 1e200 rad/s ran for more than 20 s). The bound is
/// far inside that and far above any frequency a study of the unit asks for.
pub const MAX_PERIODS_PER_OSCILLATION: f64 = 1e6;

/// Largest ratio of a compliant stop's contact rate `√(k_c/μ)` to the forcing frequency: the
/// simulator's own bound ([`rattle_event_driven::MAX_CONTACT_RATE_RATIO`]), below which a
/// contact lasts at least `T/(2·10⁶)` and its entry and exit, times within the period known to
/// `2.2e-16 T`, still resolve it.
pub const MAX_CONTACT_RATES_PER_FREQUENCY: f64 = rattle_event_driven::MAX_CONTACT_RATE_RATIO;

/// A natural frequency at most this fraction of the fastest is a rigid mode's zero: the
/// symmetric eigensolver leaves a zero eigenvalue of `ω²` at about `1e-16` of the largest, so
/// its square root at about `1e-8` of the fastest frequency; `1e-6` is above that rounding and
/// below any elastic mode a structure of at most a few dozen bodies with stiffness ratios
/// under `1e10` has.
pub const RIGID_RATE: f64 = 1e-6;

/// A forcing frequency that a scene cannot be run at.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FrequencyError {
    /// Not a finite number above zero.
    #[error("{field} = {omega} is out of range: must be finite and > 0 (rad/s)")]
    NotPositive {
        /// The option or argument that gave it, e.g. `--omega`.
        field: String,
        /// The value given.
        omega: f64,
    },
    /// Outside the scene's bounds ([`MAX_OSCILLATIONS_PER_PERIOD`],
    /// [`MAX_PERIODS_PER_OSCILLATION`]).
    #[error(
        "{field} = {omega:e} is out of range for this scene: must be in [{min:.6e}, {max:.6e}] \
         rad/s, so that one forcing period holds at most {MAX_OSCILLATIONS_PER_PERIOD:e} free \
         oscillations of the fastest mode ({fastest:.6} rad/s) and one free oscillation of the \
         slowest mode ({slowest:.6} rad/s) at most {MAX_PERIODS_PER_OSCILLATION:e} forcing \
         periods; the run's work grows with these ratios"
    )]
    OutOfBounds {
        /// The option or argument that gave it, e.g. `--omega`.
        field: String,
        /// The value given.
        omega: f64,
        /// Lowest allowed frequency, rad/s.
        min: f64,
        /// Highest allowed frequency, rad/s.
        max: f64,
        /// The scene's fastest undamped natural frequency, rad/s.
        fastest: f64,
        /// The scene's slowest undamped natural frequency, rad/s.
        slowest: f64,
    },
    /// Below the bound of the scene's fastest compliant contact
    /// ([`MAX_CONTACT_RATES_PER_FREQUENCY`]).
    #[error(
        "{field} = {omega:e} is out of range for this scene: must be ≥ {min:.6e} rad/s, so that \
         the stiffest compliant stop's contact rate √(k_c/μ) ({contact:.6e} rad/s) is at most \
         {MAX_CONTACT_RATES_PER_FREQUENCY:e} times the forcing frequency: a contact shorter \
         than that is not resolved by the times of a forcing period"
    )]
    ContactTooFast {
        /// The option or argument that gave it, e.g. `--omega`.
        field: String,
        /// The value given.
        omega: f64,
        /// Lowest allowed frequency, rad/s.
        min: f64,
        /// The fastest contact rate, rad/s.
        contact: f64,
    },
}

/// The forcing frequencies a scene can be run at: `[ω_fastest / 1e3, ω_slowest × 1e6]`,
/// `ω_slowest` the slowest elastic mode (a structure of free bodies alone has none: no upper
/// bound, and no lower one either when it has no elastic mode at all).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FrequencyBounds {
    /// The scene's slowest undamped natural frequency, rad/s.
    pub slowest: f64,
    /// The scene's fastest undamped natural frequency, rad/s.
    pub fastest: f64,
    /// The fastest contact rate `√(k_c/μ)` of the scene's compliant stops (`μ` the pair's
    /// reduced mass), rad/s; 0 without compliant stops.
    pub contact: f64,
}

impl FrequencyBounds {
    /// The bounds of `scene`, from its natural frequencies.
    pub fn of(scene: &Scene) -> Self {
        Self::of_rates(&natural_frequencies(scene))
    }

    /// The bounds of `structure`, from the natural frequencies of its `M` and `K` and the
    /// contact rates of its compliant stops.
    pub fn of_structure(structure: &Structure) -> Self {
        let mass: Vec<f64> = structure.mass.diagonal().iter().copied().collect();
        let contact = structure
            .stops
            .iter()
            .filter_map(|s| match s.law {
                ContactLaw::Compliant { stiffness, .. } => {
                    let inverse = |end: Option<usize>| end.map_or(0.0, |j| 1.0 / mass[j]);
                    Some((stiffness * (inverse(s.plus) + inverse(s.minus))).sqrt())
                }
                ContactLaw::Rigid { .. } => None,
            })
            .fold(0.0, f64::max);
        Self {
            contact,
            ..Self::of_rates(&eigenfrequencies(&mass, &structure.stiffness))
        }
    }

    /// The bounds from the natural frequencies `rates`; a rigid mode (a free body's
    /// translation, a rate of zero to rounding: at most [`RIGID_RATE`] of the fastest) has no
    /// oscillation to bound and is left out of the slowest.
    fn of_rates(rates: &[f64]) -> Self {
        let fastest = rates.iter().copied().fold(0.0, f64::max);
        Self {
            slowest: rates
                .iter()
                .copied()
                .filter(|&r| r > RIGID_RATE * fastest)
                .fold(f64::INFINITY, f64::min),
            fastest,
            contact: 0.0,
        }
    }

    /// Lowest allowed frequency, rad/s: of the fastest mode, and of the fastest contact.
    pub fn min(&self) -> f64 {
        self.oscillation_min().max(self.contact_min())
    }

    /// Lowest frequency the fastest mode allows ([`MAX_OSCILLATIONS_PER_PERIOD`]).
    fn oscillation_min(&self) -> f64 {
        self.fastest / MAX_OSCILLATIONS_PER_PERIOD
    }

    /// Lowest frequency the fastest contact allows ([`MAX_CONTACT_RATES_PER_FREQUENCY`]).
    fn contact_min(&self) -> f64 {
        self.contact / MAX_CONTACT_RATES_PER_FREQUENCY
    }

    /// Highest allowed frequency, rad/s.
    pub fn max(&self) -> f64 {
        self.slowest * MAX_PERIODS_PER_OSCILLATION
    }

    /// `omega`, if it is finite, positive and within the bounds.
    ///
    /// # Errors
    /// [`FrequencyError`] naming `field`, with the allowed range and the reason.
    pub fn check(&self, field: &str, omega: f64) -> Result<f64, FrequencyError> {
        if !(omega.is_finite() && omega > 0.0) {
            return Err(FrequencyError::NotPositive {
                field: field.to_owned(),
                omega,
            });
        }
        if omega < self.contact_min() && omega <= self.max() {
            return Err(FrequencyError::ContactTooFast {
                field: field.to_owned(),
                omega,
                min: self.contact_min(),
                contact: self.contact,
            });
        }
        if omega < self.min() || omega > self.max() {
            return Err(FrequencyError::OutOfBounds {
                field: field.to_owned(),
                omega,
                min: self.min(),
                max: self.max(),
                fastest: self.fastest,
                slowest: self.slowest,
            });
        }
        Ok(omega)
    }
}

/// The undamped natural frequencies of `structure`'s `M` and `K` (its stops removed), rad/s,
/// ascending; a rigid mode's zero (at most [`RIGID_RATE`] of the fastest) left out.
pub fn structure_natural_frequencies(structure: &Structure) -> Vec<f64> {
    let mass: Vec<f64> = structure.mass.diagonal().iter().copied().collect();
    let mut rates = eigenfrequencies(&mass, &structure.stiffness);
    let fastest = rates.iter().copied().fold(0.0, f64::max);
    rates.retain(|&r| r > RIGID_RATE * fastest);
    rates.sort_by(f64::total_cmp);
    rates
}

/// The slowest decay rate of `structure`'s free motion with the stops removed: the least
/// `−Re λ` over the eigenvalues `λ` of `[[0, I], [−M⁻¹K, −M⁻¹C]]` that are not a rigid mode's
/// zero (`|λ|` at most [`RIGID_RATE`] of the largest), 1/s; `0` for an undamped mode, `None`
/// when there is no elastic mode.
pub fn structure_slowest_decay_rate(structure: &Structure) -> Option<f64> {
    let n = structure.dofs();
    let mut a = DMatrix::<f64>::zeros(2 * n, 2 * n);
    for i in 0..n {
        a[(i, n + i)] = 1.0;
        let m = structure.mass[(i, i)];
        for j in 0..n {
            a[(n + i, j)] = -structure.stiffness[(i, j)] / m;
            a[(n + i, n + j)] = -structure.damping.as_ref().map_or(0.0, |d| d[(i, j)]) / m;
        }
    }
    let rates = a.complex_eigenvalues();
    let largest = rates.iter().map(|l| l.norm()).fold(0.0, f64::max);
    rates
        .iter()
        .filter(|l| l.norm() > RIGID_RATE * largest)
        .map(|l| (-l.re).max(0.0))
        .reduce(f64::min)
}

/// The undamped natural frequencies (rad/s) of the scene's cells in series without stops:
/// outer mass `j` tied to outer mass `j − 1` by its `k_o` (the first to the base), inner mass
/// `j` to outer mass `j` by its `k_i`.
fn natural_frequencies(scene: &Scene) -> Vec<f64> {
    let cells = scene.cell_scenes();
    let n = 2 * cells.len();
    let mut mass = vec![0.0; n];
    let mut stiffness = DMatrix::<f64>::zeros(n, n);
    let mut tie = |a: Option<usize>, b: usize, k: f64| {
        stiffness[(b, b)] += k;
        if let Some(a) = a {
            stiffness[(a, a)] += k;
            stiffness[(a, b)] -= k;
            stiffness[(b, a)] -= k;
        }
    };
    for (j, cell) in cells.iter().enumerate() {
        let (outer, inner) = (2 * j, 2 * j + 1);
        mass[outer] = cell.unit.outer_mass;
        mass[inner] = cell.unit.inner_mass;
        tie(
            j.checked_sub(1).map(|p| 2 * p),
            outer,
            cell.unit.outer_stiffness,
        );
        tie(Some(outer), inner, cell.unit.inner_stiffness);
    }
    eigenfrequencies(&mass, &stiffness)
}

/// The undamped natural frequencies (rad/s) of a diagonal `mass` on `stiffness`.
fn eigenfrequencies(mass: &[f64], stiffness: &DMatrix<f64>) -> Vec<f64> {
    let n = mass.len();
    let scaled = DMatrix::from_fn(n, n, |r, c| stiffness[(r, c)] / (mass[r] * mass[c]).sqrt());
    SymmetricEigen::new(scaled)
        .eigenvalues
        .iter()
        .map(|&l| l.max(0.0).sqrt())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The paper's unit: `ω² = 1.5, 6` exactly (the paper's §2.2).
    #[test]
    fn the_paper_units_bounds_come_from_its_two_modes() {
        let b = FrequencyBounds::of(&Scene::paper());
        assert!((b.slowest - 1.5f64.sqrt()).abs() < 1e-13);
        assert!((b.fastest - 6f64.sqrt()).abs() < 1e-13);
        assert!((b.min() - 6f64.sqrt() / 1e3).abs() < 1e-16);
        assert!((b.max() - 1.5f64.sqrt() * 1e6).abs() < 1e-8);
    }

    /// A chain of identical cells: the finite lattice's modes lie inside the infinite
    /// lattice's pass bands, so the slowest is below the unit's and the fastest above.
    #[test]
    fn a_chains_bounds_come_from_the_chains_modes() {
        let mut scene = Scene::paper();
        scene.cells = Some(8);
        let b = FrequencyBounds::of(&scene);
        assert!(b.slowest < 1.5f64.sqrt() && b.slowest > 0.0);
        assert!(b.fastest > 6f64.sqrt());
        // One cell equals the unit.
        scene.cells = Some(1);
        let one = FrequencyBounds::of(&scene);
        assert!((one.fastest - 6f64.sqrt()).abs() < 1e-13);
    }

    #[test]
    fn frequencies_outside_the_bounds_are_refused_with_the_range() {
        let b = FrequencyBounds::of(&Scene::paper());
        assert_eq!(b.check("--omega", 2.0), Ok(2.0));
        assert_eq!(b.check("--omega", b.min()), Ok(b.min()));
        for bad in [1e-300, 1e-6, 2e-3, 1.3e6, 1e300] {
            let message = b.check("--omega", bad).unwrap_err().to_string();
            assert!(message.starts_with(&format!("--omega = {bad:e} is out of range")));
            assert!(message.contains("must be in [2.449490e-3, 1.224745e6] rad/s"));
        }
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let message = b.check("omega", bad).unwrap_err().to_string();
            assert!(
                message.ends_with("must be finite and > 0 (rad/s)"),
                "{message}"
            );
        }
    }
}
