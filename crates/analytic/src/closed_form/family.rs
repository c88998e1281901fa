//! Two-impact orbits for any `β`: the gap `Δ*(β)` that admits them, and the asymmetric orbits
//! of a given gap.
//!
//! Unknowns per unit gap: the states just before both impacts (`u_o` and both velocities at
//! `t = 0⁻` and at `t = βT⁻`) and the phase `(cos α, sin α)`. The flight from the side-1 impact
//! to the side-2 impact and the flight back close the period: eight linear equations
//! `N(β) w = Δ g(β)`, homogeneous in the gap and the forcing together. So each `β` admits one
//! gap, `Δ*(β) = 1 / |(cos α, sin α)_w|` for the solution `w` at unit gap.
//!
//! With symmetric stops `N(½)` is exactly singular. There `w` is the limit `β → ½`: with left
//! and right null vectors `u`, `n` of `N₀ = N(½)` and `N₁ = dN/dβ`, the solution
//! `w₀ = w_p + λ n` is the one whose first-order correction is solvable,
//! `uᵀ(g₁ − N₁ w₀) = 0`. Within `10⁻⁴` of `½` a quadratic through `½` and `½ ± 10⁻⁴` bridges
//! the ill-conditioned neighbourhood.

use crate::flow::{ForcedFlow, Transition};
use crate::orbit::{assemble, wrap, Candidate, Flights, Orbit};
use crate::unit::{Stops, Unit};
use nalgebra::{Matrix2, SMatrix, SVector, Vector4};
use thiserror::Error;

type Matrix8 = SMatrix<f64, 8, 8>;
type Vector8 = SVector<f64, 8>;

/// Half-width of the neighbourhood of `β = ½` bridged by interpolation. The smallest singular
/// value of `N(β)` vanishes linearly at `½`, so a direct solve at `|β − ½| = h` loses about
/// `ε/h` (relative); the quadratic through `½ ± h` errs by `O(h³)`. The two balance at
/// `h = ε^{1/4} ≈ 1.2e-4`: `10⁻⁴`, with an error of order `10⁻¹²` either way.
pub const NEAR_HALF: f64 = 1e-4;

/// The fewest grid intervals [`asymmetric_orbits`] accepts: grid points `j/samples`,
/// `0 < j < samples`, so 4 is the least grid with a bracketing interval on each side of `½`
/// (where mirror pairs `β`, `1 − β` live).
pub(crate) const MIN_SAMPLES: usize = 4;

/// Cap on the regula falsi (Illinois) iterations per bracket. Illinois converges
/// superlinearly (order ≈ 1.44), so a converging bracket stops long before; the cap bounds a
/// bracket that stalls.
const ROOT_ITERATIONS: usize = 200;

/// Regula falsi stops when the relative gap residual `|Δ*(β) − Δ| / Δ` is below this: ten times
/// tighter than [`GAP_ACCEPTANCE`], so that a root that converges is accepted.
const ROOT_RESIDUAL: f64 = 1e-13;

/// Regula falsi stops when the bracket on `β ∈ (0, 1)` is narrower than this: about nine ulps
/// of `½` (`ulp(½) ≈ 1.1e-16`), where further steps no longer move `β`.
const ROOT_BRACKET: f64 = 1e-15;

/// Cap on the implicit QR sweeps of the half-period system's SVD. An 8 × 8 decomposition of
/// finite entries converges in a few dozen; nalgebra's uncapped `svd` never returns on entries
/// that are not finite (a flow over `T = 2π/ω` with `ω = 1e-300` overflows), so the cap turns
/// that into [`FamilyError::Singular`] instead of a hang.
const SVD_MAX_ITERATIONS: usize = 10_000;

/// A root is an orbit of the given gap when `|Δ*(β) − Δ| < GAP_ACCEPTANCE · Δ`. `Δ*(β)` comes
/// from an 8×8 solve that near `½` carries errors of order `10⁻¹²` (see [`NEAR_HALF`]).
pub const GAP_ACCEPTANCE: f64 = 1e-12;

/// Roots within this distance of `½` are the symmetric orbits (left to
/// [`crate::symmetric_orbits`]). By mirror symmetry `Δ*(β) = Δ*(1 − β)` is even about `½`, so
/// the regula falsi's gap residual `1e-13` pins `β` only to about `√1e-13 ≈ 3e-7` of `½` (for a
/// curvature of order one): `10⁻⁶` cannot tell such a root from `½`. Reasoned, not measured.
pub(crate) const SYMMETRIC_EXCLUSION: f64 = 1e-6;

/// A failure of the family computation.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum FamilyError {
    /// `β` must lie strictly between 0 and 1.
    #[error("beta = {0} is out of range: must be in (0, 1)")]
    BetaOutOfRange(f64),
    /// The orbit equations are singular at this `β` (away from `½`).
    #[error("the two-impact equations are singular at beta = {beta}, omega = {omega}")]
    Singular {
        /// The fraction of the period.
        beta: f64,
        /// The frequency.
        omega: f64,
    },
    /// The forcing phase drops out of the solution: no finite gap admits this `β`.
    #[error("no finite gap admits beta = {beta} at omega = {omega}")]
    NoFiniteGap {
        /// The fraction of the period.
        beta: f64,
        /// The frequency.
        omega: f64,
    },
}

/// One member of the two-impact family: the gap that admits side-2 impacts at `βT`, and the orbit.
#[derive(Debug, Clone, PartialEq)]
pub struct FamilyPoint {
    /// Fraction of the period between the side-1 and the side-2 impact.
    pub beta: f64,
    /// `Δ*(β)`, the gap that admits the orbit.
    pub gap: f64,
    /// The orbit itself at that gap, with its verdicts.
    pub orbit: Orbit,
}

/// The blocks of the family equations at one `β`.
struct Blocks {
    first: Transition,
    second: Transition,
}

/// Builds `N w − g` as `(N, g)`; with `constants = false`, only the parts that depend on the
/// flow blocks (this is how the derivative `dN/dβ` is formed from derivative blocks).
fn equations(
    e1: &nalgebra::Matrix4<f64>,
    f1: &nalgebra::Matrix4x2<f64>,
    e2: &nalgebra::Matrix4<f64>,
    f2r: &nalgebra::Matrix4x2<f64>,
    g: &Matrix2<f64>,
    constants: bool,
) -> (Matrix8, Vector8) {
    let both = Vector4::new(1.0, 1.0, 0.0, 0.0);
    let vo = Vector4::new(0.0, 0.0, g[(0, 0)], g[(1, 0)]);
    let vi = Vector4::new(0.0, 0.0, g[(0, 1)], g[(1, 1)]);
    let inner = Vector4::new(0.0, 1.0, 0.0, 0.0);
    let c = if constants { 1.0 } else { 0.0 };
    let mut n = Matrix8::zeros();
    let mut rhs = Vector8::zeros();
    // Flight 1: E1 x1⁺ + F1 p − x2⁻ = 0, with x1 = (u_o1, u_o1 + Δ, ·), x2 = (u_o2, u_o2 − Δ, ·).
    // Flight 2: E2 x2⁺ + F2 R1 p − x1⁻ = 0.
    for (row, (e, f, sign)) in [(e1, f1, 1.0), (e2, f2r, -1.0)].into_iter().enumerate() {
        let own = 3 * row; // columns of the state that starts this flight
        let other = 3 * (1 - row); // columns of the state that ends it
        let mut blk = n.fixed_view_mut::<4, 8>(4 * row, 0);
        blk.set_column(own, &(e * both));
        blk.set_column(own + 1, &(e * vo));
        blk.set_column(own + 2, &(e * vi));
        blk.set_column(other, &(-both * c));
        blk.set_column(other + 1, &(-Vector4::new(0.0, 0.0, c, 0.0)));
        blk.set_column(other + 2, &(-Vector4::new(0.0, 0.0, 0.0, c)));
        blk.fixed_view_mut::<4, 2>(0, 6).copy_from(f);
        // Gap terms moved to the right: start offset sign·Δ, end offset −sign·Δ.
        rhs.fixed_rows_mut::<4>(4 * row)
            .copy_from(&(-(e * inner) * sign - inner * c * sign));
    }
    (n, rhs)
}

impl Blocks {
    fn new(flow: &ForcedFlow, beta: f64) -> Self {
        let t1 = beta * flow.period();
        Self {
            first: flow.transition(t1),
            second: flow.transition(flow.period() - t1),
        }
    }

    fn system(&self, g: &Matrix2<f64>) -> (Matrix8, Vector8) {
        let f2r = self.second.forced * self.first.rotation;
        equations(
            &self.first.homogeneous,
            &self.first.forced,
            &self.second.homogeneous,
            &f2r,
            g,
            true,
        )
    }
}

/// Solution per unit gap at `β` (away from ½).
fn solve_direct(flow: &ForcedFlow, g: &Matrix2<f64>, beta: f64) -> Result<Vector8, FamilyError> {
    let (n, rhs) = Blocks::new(flow, beta).system(g);
    let omega = flow.omega();
    n.lu()
        .solve(&rhs)
        .filter(|w| w.iter().all(|v| v.is_finite()))
        .ok_or(FamilyError::Singular { beta, omega })
}

/// Solution per unit gap at exactly `β = ½`, as the limit `β → ½`.
fn solve_half(flow: &ForcedFlow, g: &Matrix2<f64>) -> Result<Vector8, FamilyError> {
    let period = flow.period();
    let half = 0.5 * period;
    let blocks = Blocks::new(flow, 0.5);
    let (n0, g0) = blocks.system(g);
    // d/dβ of the blocks: dt1/dβ = T, d(T − t1)/dβ = −T.
    let rate = flow.transition_rate(half);
    let de1 = rate.homogeneous * period;
    let df1 = rate.forced * period;
    let de2 = -rate.homogeneous * period;
    let dr1 = rate.rotation * period;
    let df2r = -rate.forced * period * blocks.first.rotation + blocks.second.forced * dr1;
    let (n1, g1) = equations(&de1, &df1, &de2, &df2r, g, false);

    let singular = || FamilyError::Singular {
        beta: 0.5,
        omega: flow.omega(),
    };
    let svd = n0
        .try_svd(true, true, f64::EPSILON, SVD_MAX_ITERATIONS)
        .ok_or_else(singular)?;
    let (u_all, v_t) = (svd.u.ok_or_else(singular)?, svd.v_t.ok_or_else(singular)?);
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)
        .unwrap_or(7);
    let u = u_all.column(k).into_owned();
    let n = v_t.row(k).transpose();
    // Particular solution in the range of N₀: pseudo-inverse without the null direction.
    let mut wp = Vector8::zeros();
    for i in 0..8 {
        if i != k {
            let coef = u_all.column(i).dot(&g0) / svd.singular_values[i];
            wp += v_t.row(i).transpose() * coef;
        }
    }
    let denom = u.dot(&(n1 * n));
    if denom == 0.0 || !denom.is_finite() {
        return Err(FamilyError::Singular {
            beta: 0.5,
            omega: flow.omega(),
        });
    }
    let lambda = (u.dot(&g1) - u.dot(&(n1 * wp))) / denom;
    Ok(wp + n * lambda)
}

/// Solution per unit gap at any `β ∈ (0, 1)`, continuous through `½`.
fn solve(flow: &ForcedFlow, g: &Matrix2<f64>, beta: f64) -> Result<Vector8, FamilyError> {
    let d = beta - 0.5;
    if d == 0.0 {
        solve_half(flow, g)
    } else if d.abs() < NEAR_HALF {
        // Quadratic through (−h, w₋), (0, w₀), (h, w₊).
        let h = NEAR_HALF;
        let wm = solve_direct(flow, g, 0.5 - h)?;
        let w0 = solve_half(flow, g)?;
        let wp = solve_direct(flow, g, 0.5 + h)?;
        let x = d / h;
        Ok(w0 + (wp - wm) * (0.5 * x) + (wp - w0 * 2.0 + wm) * (0.5 * x * x))
    } else {
        solve_direct(flow, g, beta)
    }
}

/// The gap `Δ*(β)` that admits a two-impact orbit with the side-2 impact `βT` after the
/// side-1 impact, for `unit` with the given `restitution` at angular frequency `omega`; with
/// the orbit, its phase, viability and stability.
///
/// Continuous in `β` through `½`, where it equals one of the symmetric orbits of
/// [`crate::symmetric_orbits`] at gap `Δ*(½)`. The unit and `restitution` are not validated
/// here (see [`Unit::validate`], [`Stops::validate`]).
///
/// # Errors
/// - [`FamilyError::BetaOutOfRange`] unless `0 < β < 1` (NaN included).
/// - [`FamilyError::Singular`] when the eight orbit equations cannot be solved at this `β`
///   (an LU solve without a finite solution away from `½`, or a vanishing first-order
///   condition at `½`).
/// - [`FamilyError::NoFiniteGap`] when the phase `(cos α, sin α)` of the unit-gap solution is
///   zero or not finite, so that no finite gap admits this `β`.
pub fn gap_for_beta(
    unit: &Unit,
    restitution: f64,
    omega: f64,
    beta: f64,
) -> Result<FamilyPoint, FamilyError> {
    if !(beta > 0.0 && beta < 1.0) {
        return Err(FamilyError::BetaOutOfRange(beta));
    }
    let flow = ForcedFlow::new(unit, omega);
    let g = Stops {
        gap: 1.0,
        restitution,
    }
    .impact_map(unit);
    let w = solve(&flow, &g, beta)?;
    let phase_norm = (w[6] * w[6] + w[7] * w[7]).sqrt();
    if !(phase_norm > 0.0 && phase_norm.is_finite()) {
        return Err(FamilyError::NoFiniteGap { beta, omega });
    }
    let gap = 1.0 / phase_norm;
    let alpha = wrap(w[7].atan2(w[6]));
    let y = w * gap;
    let before1 = Vector4::new(y[0], y[0] + gap, y[1], y[2]);
    let before2 = Vector4::new(y[3], y[3] - gap, y[4], y[5]);
    let stops = Stops { gap, restitution };
    let blocks = Blocks::new(&flow, beta);
    let flights = Flights {
        first: blocks.first,
        second: blocks.second,
        symmetric: false,
    };
    let candidate = Candidate {
        beta,
        alpha,
        before1,
        before2,
    };
    let orbit = assemble(unit, &stops, &flow, &candidate, &flights);
    Ok(FamilyPoint { beta, gap, orbit })
}

/// Every asymmetric two-impact orbit (`β ≠ ½`) of `unit` with `stops` at `omega`: the roots
/// of `Δ*(β) = Δ` on `(0, 1)`.
///
/// Roots are bracketed on a grid of `samples` intervals (at least `MIN_SAMPLES = 4`) and refined
/// by regula falsi (Illinois) to `|Δ*(β) − Δ| < 1e-12 Δ` ([`GAP_ACCEPTANCE`]); two roots within
/// one grid interval can be missed. Roots within `10⁻⁶` of `½` (`SYMMETRIC_EXCLUSION = 1e-6`) are
/// the symmetric orbits and are left to [`crate::symmetric_orbits`]. Mirror images come in
/// pairs `β`, `1 − β`. A `β` at which [`gap_for_beta`] fails is skipped, never reported.
pub fn asymmetric_orbits(unit: &Unit, stops: &Stops, omega: f64, samples: usize) -> Vec<Orbit> {
    let samples = samples.max(MIN_SAMPLES);
    let f = |beta: f64| {
        gap_for_beta(unit, stops.restitution, omega, beta)
            .map(|p| (p.gap - stops.gap) / stops.gap)
            .unwrap_or(f64::NAN)
    };
    let grid: Vec<(f64, f64)> = (1..samples)
        .map(|j| {
            let b = j as f64 / samples as f64;
            (b, f(b))
        })
        .collect();
    let mut orbits = Vec::new();
    for pair in grid.windows(2) {
        let ((mut a, mut fa), (mut b, mut fb)) = (pair[0], pair[1]);
        if !(fa.is_finite() && fb.is_finite()) || fa.signum() == fb.signum() {
            continue;
        }
        let mut side = 0i8;
        let mut root = 0.5 * (a + b);
        for _ in 0..ROOT_ITERATIONS {
            root = (a * fb - b * fa) / (fb - fa);
            let fr = f(root);
            if !fr.is_finite() || fr.abs() < ROOT_RESIDUAL || (b - a) < ROOT_BRACKET {
                break;
            }
            if fr.signum() == fb.signum() {
                b = root;
                fb = fr;
                if side == -1 {
                    fa *= 0.5;
                }
                side = -1;
            } else {
                a = root;
                fa = fr;
                if side == 1 {
                    fb *= 0.5;
                }
                side = 1;
            }
        }
        if (root - 0.5).abs() < SYMMETRIC_EXCLUSION {
            continue;
        }
        if let Ok(point) = gap_for_beta(unit, stops.restitution, omega, root) {
            if ((point.gap - stops.gap) / stops.gap).abs() < GAP_ACCEPTANCE {
                orbits.push(point.orbit);
            }
        }
    }
    orbits
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `rattle orbit --omega 1e-300` hangs in an uncapped SVD: the flow over a period of
    /// `2π/1e-300` overflows. The family solve ends with an error instead.
    #[test]
    fn an_overflowing_flow_ends_in_an_error_not_a_hang() {
        let unit = crate::test_models::paper_unit();
        for omega in [1e-300, 1e-200] {
            for beta in [0.3, 0.5] {
                assert!(
                    gap_for_beta(&unit, 0.8, omega, beta).is_err(),
                    "{omega} {beta}"
                );
            }
        }
        // And a frequency in range still solves.
        assert!(gap_for_beta(&unit, 0.8, 2.0, 0.3).is_ok());
    }
}
