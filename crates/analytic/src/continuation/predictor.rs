//! The predictor: the unit tangent of a branch, from the bordered Jacobian `[R_X; tᵀ]`, and
//! the tangent at a branch's seed, from the null vector of `R_X`. Both work on any curve
//! defined by `n` equations in `n + 1` unknowns (an `n × (n + 1)` Jacobian): a branch in
//! `X = (x, ω)`, or a boundary curve in `(X, p)`.

use super::system::{BranchModel, System};
use nalgebra::{DMatrix, DVector};

impl<M: BranchModel> System<M> {
    /// The unit tangent at a point with Jacobian `jacobian`, oriented along `previous`
    /// ([`tangent`]).
    pub(crate) fn tangent(&self, jacobian: &DMatrix<f64>, previous: &[f64]) -> Option<Vec<f64>> {
        tangent(jacobian, previous)
    }
}

/// The unit tangent at a point with the `n × (n + 1)` Jacobian `jacobian`, oriented along
/// `previous` (`n + 1` entries): the solution of `[jacobian; previousᵀ] t = e_{n+1}`,
/// normalised.
pub(crate) fn tangent(jacobian: &DMatrix<f64>, previous: &[f64]) -> Option<Vec<f64>> {
    let n = jacobian.nrows();
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

/// The unit null vector of an `n × (n + 1)` Jacobian: its right singular vector of the
/// smallest singular value (of the Jacobian bordered by a row of zeros), unoriented.
pub(crate) fn null_vector(jacobian: &DMatrix<f64>) -> Option<Vec<f64>> {
    let n = jacobian.nrows();
    let mut m = DMatrix::zeros(n + 1, n + 1);
    m.view_mut((0, 0), (n, n + 1)).copy_from(jacobian);
    let svd = m.svd(false, true);
    let v_t = svd.v_t?;
    let k = svd
        .singular_values
        .iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map(|(i, _)| i)?;
    Some(v_t.row(k).iter().copied().collect())
}

/// The tangent at the seed of a branch: the seed's own (`own`), or the null vector of `R_X` oriented
/// towards increasing `ω`.
pub(crate) fn seed_tangent<M: BranchModel>(
    system: &System<M>,
    own: Option<&[f64]>,
    eval: &M::Evaluation,
) -> Option<Vec<f64>> {
    if let Some(t) = own {
        return Some(t.to_vec());
    }
    let n = system.n();
    let mut t = null_vector(M::jacobian(eval))?;
    if t[n] < 0.0 {
        t.iter_mut().for_each(|v| *v = -*v);
    }
    Some(t)
}
