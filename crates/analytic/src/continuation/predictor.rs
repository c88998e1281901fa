//! The predictor: the unit tangent of a branch, from the bordered Jacobian `[R_X; tᵀ]`, and
//! the tangent at a branch's seed.

use super::system::{BranchModel, System};
use nalgebra::{DMatrix, DVector};

impl<M: BranchModel> System<M> {
    /// The unit tangent at a point with Jacobian `jacobian`, oriented along `previous`:
    /// the solution of `[R_X; previousᵀ] t = e_{n+1}`, normalised.
    pub(crate) fn tangent(&self, jacobian: &DMatrix<f64>, previous: &[f64]) -> Option<Vec<f64>> {
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
    let mut m = DMatrix::zeros(n + 1, n + 1);
    m.view_mut((0, 0), (n, n + 1)).copy_from(M::jacobian(eval));
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
