//! Branch switching: the seeds of the branches that leave a branch point (the other root of
//! the algebraic branching equation), a period doubling (the doubled cycle's branch point)
//! and a grazing (the label with the grazing impact inserted).

use super::corrector::Constraint;
use super::result::{Event, EventKind};
use super::system::{doubled, grazed, BranchModel, Label, Node, System};
use nalgebra::{DMatrix, DVector};

/// Central-difference step (relative to the largest unknown) for the second derivatives of
/// the branching equation at a branch point: truncation `O(ε²) ≈ 1e-12`, rounding of the
/// exact Jacobians `O(ε_mach/ε) ≈ 1e-10`; ample for a direction that the corrector then
/// follows onto the branch.
pub(crate) const BRANCHING_DIFFERENCE: f64 = 1e-6;

/// A probe from a branch point that lands back on the known branch has a secant within
/// `1 − cos ≈ (κ step)²/8` of its tangent, about `1e-8` for the switch step and curvatures of
/// order one; the two branches' tangents, though both dominated by `α` in these coordinates,
/// were measured at cosines up to 0.94 on the paper unit. This threshold separates the two.
pub(crate) const PROBE_COSINE: f64 = 0.9999;

/// Size of the first step onto a switched branch, relative to `initial_step`: small, so the
/// corrector stays on the new branch near the bifurcation.
pub(crate) const SWITCH_STEP: f64 = 0.1;

/// A branch still to be followed.
pub(crate) struct Seed<L> {
    pub(crate) signature: L,
    pub(crate) x: Vec<f64>,
    /// Direction to follow (both ways); `None`: the null vector of `R_X`.
    pub(crate) tangent: Option<Vec<f64>>,
    pub(crate) from_event: Option<usize>,
    /// Born at a grazing: impact `j` of the new label is the graze; a direction on which it
    /// is approached from outside is dropped.
    pub(crate) grazing_impact: Option<usize>,
    /// Switching depth: 0 for the start, one more than its parent's for a switch.
    pub(crate) depth: usize,
}

impl<M: BranchModel> System<M> {
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
            let jp = M::jacobian(&self.evaluate(&plus)?).clone();
            let jm = M::jacobian(&self.evaluate(&minus)?).clone();
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
}

/// The seed of the branch that leaves at `event` (found at `node` on `system`'s branch).
///
/// At a branch point (and at a period doubling, a branch point of the doubled cycle) the
/// null space of `R_X` holds both branches' tangents, not in general orthogonal in these
/// coordinates: the direction orthogonal to the known tangent is only a start. A corrector
/// step of length `step` along it lands on the new branch, and the secant from the
/// bifurcation to that point is the new branch's direction ([`System::probe`]).
pub(crate) fn switch_seed<M: BranchModel>(
    system: &System<M>,
    node: &Node,
    event: &Event<M::Label>,
    event_index: usize,
    step: f64,
) -> Option<Seed<M::Label>> {
    let n = system.n();
    match event.kind {
        EventKind::BranchPoint => {
            let eval = system.evaluate(&node.x)?;
            let t = system.other_direction(&node.x, M::jacobian(&eval), &node.tangent)?;
            let t = system.probe(&node.x, &t, &node.tangent, step)?;
            Some(Seed {
                signature: system.label().clone(),
                x: node.x.clone(),
                tangent: Some(t),
                from_event: Some(event_index),
                grazing_impact: None,
                depth: 0,
            })
        }
        EventKind::PeriodDoubling => {
            let signature = doubled(system.label())?;
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
            let doubled_system = System::new(system.model.relabel(signature.clone()));
            let eval = doubled_system.evaluate(&x2)?;
            let t = doubled_system.other_direction(&x2, M::jacobian(&eval), &t2)?;
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
            let pair = event.pair?;
            let impact = node.tests.graze[f * system.model.pairs() + pair].1;
            let (signature, k) = grazed(system.label(), f, impact)?;
            // Times of the new impacts (old impacts and the graze), in the inserted order.
            let mut times = vec![0.0];
            times.extend_from_slice(&node.x[1..n]);
            times.insert(f + 1, phase);
            let m = n + 1;
            let shift = times[k];
            let angle = std::f64::consts::TAU * f64::from(system.label().period());
            let mut x = vec![node.x[0] + angle * shift];
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
