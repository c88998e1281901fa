//! Branch-point curves: Moore's extended system ([`crate::continuation::branch_point`]) with
//! the parameter free. The unknowns are `Y = (X, p, β, ψ)` (`X = (α, φ₂ … φₙ, ω)` as for the
//! other events, so that `ω` and `p` keep their places), the equations
//!
//! ```text
//! R(X; p) + β ψ = 0        (n)
//! R_X(X; p)ᵀ ψ   = 0        (n + 1)
//! (ψᵀψ − 1)/2    = 0        (1)
//! ```
//!
//! `2n + 2` equations in `2n + 3` unknowns: a curve, regular where the branch point is simple
//! (two branches crossing transversally, as where the asymmetric orbits leave a symmetric
//! one), whose `β` stays zero along it. `R_X` is exact; `R_XX ψ` (by central differences of
//! the exact `R_X`, as the one-parameter location does) and the column in `p` (central
//! differences of the whole residual) are differences.

use super::curve::{jacobian_of, residual_of, EventCurve};
use super::family::Family;
use super::DIFFERENCE_STEP;
use crate::continuation::branch_point::{extended, left_null_vector};
use crate::continuation::system::BranchModel;
use nalgebra::{DMatrix, DVector};

impl<Fam: Family> EventCurve<Fam> {
    /// `guess = (X, p)` extended by `β = 0` and `ψ`, the left null vector of `R_X` there.
    pub(super) fn branch_guess(&self, mut guess: Vec<f64>) -> Option<Vec<f64>> {
        let n = self.n();
        let psi = self.with_model(guess[n + 1], |model| {
            let eval = model.evaluate(&guess[..=n], true)?;
            left_null_vector(jacobian_of(model, &eval))
        })?;
        guess.push(0.0);
        guess.extend(psi.iter());
        Some(guess)
    }

    /// Moore's residual at `Y` and its Jacobian in `Y` (`2n + 2` rows, `2n + 3` columns in the
    /// order of `Y`).
    pub(super) fn linearise_branch(&self, y: &[f64]) -> Option<(DVector<f64>, DMatrix<f64>)> {
        let n = self.n();
        let m = n + 1;
        let p = y[m];
        let z = DVector::from_iterator(2 * n + 2, y[..m].iter().chain(&y[m + 1..]).copied());
        let (g, dg) = self.with_model(p, |model| {
            let h = |u: &[f64]| {
                let eval = model.evaluate(u, true)?;
                Some((
                    residual_of(model, &eval).clone(),
                    jacobian_of(model, &eval).clone(),
                ))
            };
            extended(&h, &z, n)
        })?;
        let step = DIFFERENCE_STEP * p.abs().max(1.0);
        let at = |q: f64| self.with_model(q, |model| moore_residual(model, &z, n));
        // One-sided at the edge of the parameter's physical range, as for the other events.
        let dp = match (at(p + step), at(p - step)) {
            (Some(up), Some(down)) => (up - down) / (2.0 * step),
            (Some(up), None) => (up - &g) / step,
            (None, Some(down)) => (&g - down) / step,
            (None, None) => return None,
        };
        let rows = 2 * n + 2;
        let mut jacobian = DMatrix::zeros(rows, rows + 1);
        jacobian
            .view_mut((0, 0), (rows, m))
            .copy_from(&dg.columns(0, m));
        jacobian.set_column(m, &dp);
        jacobian
            .view_mut((0, m + 1), (rows, n + 1))
            .copy_from(&dg.columns(m, n + 1));
        Some((g, jacobian))
    }
}

/// Moore's residual at `z = (X, β, ψ)` on `model`.
fn moore_residual<M: BranchModel>(model: &M, z: &DVector<f64>, n: usize) -> Option<DVector<f64>> {
    let m = n + 1;
    let u: Vec<f64> = z.rows(0, m).iter().copied().collect();
    let beta = z[m];
    let psi = z.rows(m + 1, n).into_owned();
    let eval = model.evaluate(&u, true)?;
    let mut g = DVector::zeros(2 * n + 2);
    g.rows_mut(0, n)
        .copy_from(&(M::residual(&eval) + &psi * beta));
    g.rows_mut(n, m).copy_from(&M::jacobian(&eval).tr_mul(&psi));
    g[2 * n + 1] = 0.5 * (psi.dot(&psi) - 1.0);
    Some(g)
}
