//! A simple branch point of `H(u) = 0`, `H: ℝⁿ⁺¹ → ℝⁿ`, located by a regular defining system.
//!
//! At a branch point `H_u` loses rank: the corrector of a continuation converges only linearly
//! there, and the points it returns near one carry errors of about `√ε`, so that a bracket of a
//! test function pins the branch point to about 1e-8 and no better (measured on the paper's
//! `+-` orbit near 2.1925686 rad/s). Moore's extended system (G. Moore, *The numerical treatment of
//! non-trivial bifurcation points*, Numer. Funct. Anal. Optim. 2, 1980) is regular at a simple
//! branch point, where two branches cross transversally:
//!
//! ```text
//! H(u) + β ψ = 0        (n equations)
//! H_u(u)ᵀ ψ   = 0        (n + 1)
//! (ψᵀψ − 1)/2 = 0        (1)
//! ```
//!
//! in the `2n + 2` unknowns `(u, β, ψ)`: `ψ` is the left null vector of `H_u` and `β` the
//! unfolding, zero at a branch point of the system itself. A nonzero `β` at the solution means
//! the system has no branch point there (an imperfect bifurcation): the caller rejects it.
//! Newton on this system needs `H_uu`, taken here by central differences of the exact `H_u`;
//! the residual is exact, so the iterates converge (linearly, at the rate of that difference's
//! error, about 1e-10) to the branch point to rounding.

use nalgebra::{DMatrix, DVector};

/// A branch point: where `H` and `H_u` are as the defining system asks.
#[derive(Debug, Clone)]
pub(crate) struct BranchPoint {
    /// The point `u` (the continuation's unknowns, the parameter last).
    pub(crate) u: Vec<f64>,
    /// The unfolding `β`: zero, up to rounding, at a branch point of `H` itself.
    pub(crate) unfolding: f64,
}

/// Iterations of Newton on the extended system: from a bracket's point (within about 1e-8),
/// three to five reach rounding (central differences leave a contraction of about 1e-10 per
/// step); twelve leave room, and more means no convergence.
const ITERATIONS: usize = 12;

/// The relative step of the central differences of `H_u`: `ε^{1/3}`, which balances their
/// truncation (`h²`) against the rounding of `H_u` (`ε/h`).
const DIFFERENCE_STEP: f64 = 6e-6;

/// Newton stops when its step is this many units of rounding of `u`.
const STEP_ROUNDING: f64 = 1e-14;

/// A solution more than this far (in `|Δu|∞`) from the starting point is another point, not
/// the branch point the bracket found: rejected.
const MAX_MOVE: f64 = 1e-4;

/// The branch point of `h` near `u0`, or `None` if Newton on the extended system does not
/// converge near `u0`.
///
/// `h(u)` returns `H(u)` (length `n`) and `H_u(u)` (`n × (n + 1)`), or `None` where the
/// problem is not defined.
pub(crate) fn solve_branch_point<F>(h: F, u0: &[f64]) -> Option<BranchPoint>
where
    F: Fn(&[f64]) -> Option<(DVector<f64>, DMatrix<f64>)>,
{
    let m = u0.len();
    let n = m - 1;
    let (_, jacobian) = h(u0)?;
    let mut z = DVector::zeros(2 * n + 2);
    z.rows_mut(0, m).copy_from_slice(u0);
    z.rows_mut(m + 1, n)
        .copy_from(&left_null_vector(&jacobian)?);
    for _ in 0..ITERATIONS {
        let (g, dg) = extended(&h, &z, n)?;
        let step = dg.lu().solve(&g)?;
        z -= &step;
        let scale = z.rows(0, m).amax().max(1.0);
        if !z.iter().all(|v| v.is_finite()) {
            return None;
        }
        if step.rows(0, m).amax() <= STEP_ROUNDING * scale {
            let u: Vec<f64> = z.rows(0, m).iter().copied().collect();
            let moved = u
                .iter()
                .zip(u0)
                .map(|(a, b)| (a - b).abs())
                .fold(0.0, f64::max);
            return (moved <= MAX_MOVE).then_some(BranchPoint { u, unfolding: z[m] });
        }
    }
    None
}

/// The unit left singular vector of `jacobian` (`n × (n + 1)`) of its smallest singular
/// value: `ψ` with `ψᵀ H_u ≈ 0` near a branch point.
pub(crate) fn left_null_vector(jacobian: &DMatrix<f64>) -> Option<DVector<f64>> {
    let svd = jacobian.clone().svd(true, false);
    let u = svd.u?;
    let k = svd.singular_values.imin();
    Some(u.column(k).into_owned())
}

/// The extended system's residual and Jacobian at `z = (u, β, ψ)`.
pub(crate) fn extended<F>(h: &F, z: &DVector<f64>, n: usize) -> Option<(DVector<f64>, DMatrix<f64>)>
where
    F: Fn(&[f64]) -> Option<(DVector<f64>, DMatrix<f64>)>,
{
    let m = n + 1;
    let u: Vec<f64> = z.rows(0, m).iter().copied().collect();
    let beta = z[m];
    let psi = z.rows(m + 1, n).into_owned();
    let (r, hu) = h(&u)?;
    let mut g = DVector::zeros(2 * n + 2);
    g.rows_mut(0, n).copy_from(&(&r + &psi * beta));
    g.rows_mut(n, m).copy_from(&hu.tr_mul(&psi));
    g[2 * n + 1] = 0.5 * (psi.dot(&psi) - 1.0);
    let mut dg = DMatrix::zeros(2 * n + 2, 2 * n + 2);
    dg.view_mut((0, 0), (n, m)).copy_from(&hu);
    dg.view_mut((0, m), (n, 1)).copy_from(&psi);
    for i in 0..n {
        dg[(i, m + 1 + i)] = beta;
    }
    dg.view_mut((n, 0), (m, m))
        .copy_from(&second_derivative(h, &u, &psi)?);
    dg.view_mut((n, m + 1), (m, n)).copy_from(&hu.transpose());
    dg.view_mut((2 * n + 1, m + 1), (1, n))
        .copy_from(&psi.transpose());
    Some((g, dg))
}

/// `∂(H_uᵀ ψ)/∂u` at `u` (`(n + 1) × (n + 1)`), column `j` by central differences of the
/// exact `H_u` along `u_j`.
fn second_derivative<F>(h: &F, u: &[f64], psi: &DVector<f64>) -> Option<DMatrix<f64>>
where
    F: Fn(&[f64]) -> Option<(DVector<f64>, DMatrix<f64>)>,
{
    let m = u.len();
    let mut out = DMatrix::zeros(m, m);
    let mut shifted = u.to_vec();
    for j in 0..m {
        let step = DIFFERENCE_STEP * u[j].abs().max(1.0);
        shifted[j] = u[j] + step;
        let (_, plus) = h(&shifted)?;
        shifted[j] = u[j] - step;
        let (_, minus) = h(&shifted)?;
        shifted[j] = u[j];
        let column = (plus - minus).tr_mul(psi) / (2.0 * step);
        out.set_column(j, &column);
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The classical pitchfork `H(x, λ) = λ x − x³`, `ℝ² → ℝ`: the trivial branch `x = 0` and
    /// the parabola `λ = x²` cross at its branch point, exactly `u = (0, 0)` with `β = 0`.
    fn pitchfork(u: &[f64]) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let (x, l) = (u[0], u[1]);
        let r = DVector::from_vec(vec![l * x - x * x * x]);
        let j = DMatrix::from_row_slice(1, 2, &[l - 3.0 * x * x, x]);
        Some((r, j))
    }

    /// Starts within `MAX_MOVE` of it, as a bracket's point is.
    #[test]
    fn the_pitchfork_is_located_at_its_exact_branch_point() {
        for start in [[1e-5, 2e-5], [-2e-5, 1e-5], [1e-5, -1e-5]] {
            let bp = solve_branch_point(pitchfork, &start).expect("converges");
            assert!(bp.u[0].abs() < 1e-15 && bp.u[1].abs() < 1e-15, "{bp:?}");
            assert!(bp.unfolding.abs() < 1e-15, "{bp:?}");
        }
    }

    /// An imperfect pitchfork `λ x − x³ + δ` has no branch point: the extended system's
    /// solution has `β = δ` (its unfolding), which the caller rejects.
    #[test]
    fn an_imperfect_pitchfork_has_its_unfolding_as_beta() {
        let delta = 1e-4;
        let h = |u: &[f64]| {
            let (r, j) = pitchfork(u)?;
            Some((r.add_scalar(delta), j))
        };
        let bp = solve_branch_point(h, &[1e-5, 1e-5]).expect("converges");
        assert!((bp.unfolding.abs() - delta).abs() < 1e-15, "{bp:?}");
    }

    /// A transcritical crossing in `ℝ³ → ℝ²`, exactly at the origin with `β = 0`.
    #[test]
    fn a_transcritical_crossing_in_three_unknowns_is_located() {
        // H(x, y, λ) = (λ x − x² + y², y − x): on y = x the first reduces to λ x, the branch
        // x = y = 0 (any λ) crossing the branch λ = 0 (any x = y) at the origin.
        let h = |u: &[f64]| {
            let (x, y, l) = (u[0], u[1], u[2]);
            let r = DVector::from_vec(vec![l * x - x * x + y * y, y - x]);
            let j = DMatrix::from_row_slice(2, 3, &[l - 2.0 * x, 2.0 * y, x, -1.0, 1.0, 0.0]);
            Some((r, j))
        };
        let bp = solve_branch_point(h, &[2e-5, 1e-5, -1e-5]).expect("converges");
        assert!(bp.u.iter().all(|v| v.abs() < 1e-15), "{bp:?}");
        assert!(bp.unfolding.abs() < 1e-15, "{bp:?}");
    }
}
