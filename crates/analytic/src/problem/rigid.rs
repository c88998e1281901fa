//! Free bodies: the rigid modes of a [`LinearModel`] and the family of its linear motions
//! clear of the stops.
//!
//! A rigid mode is a displacement `φ` with `Kφ = 0`: translating the structure along `φ`
//! changes no elastic force. The state `(φ, 0)` is then a null vector of the system matrix
//! `A = [[0, I], [−M⁻¹K, −M⁻¹C]]`, so every flight `exp(At)` and every impact map (which acts on
//! velocities only) keeps it: a motion translated along `φ` is again a motion of the flow. A
//! free body (a mass with no spring) is the common case: the impact damper's free mass in the
//! clearance of a primary mass on a spring, whose `K` and `C` vanish on the free mass's
//! coordinate. The basis of the rigid modes ([`LinearModel::rigid_modes`]) is the null space of
//! `K`, from its symmetric eigen-decomposition: the eigenvectors of the eigenvalues at most
//! [`crate::model::RIGID_EIGENVALUE`]` · n · max |λ|` (all of them when `K = 0`), orthonormal.
//!
//! **Boundedness.** `K` and `C` must be positive semidefinite (a negative eigenvalue beyond
//! the same rounding allowance is refused: it has no bounded motion). The forcing is a sum of
//! harmonics of orders `k ≥ 1`, of zero mean over a period, so no constant force acts on a
//! rigid mode and its forced motion is bounded: for `Kφ = 0` the pencil `K − (kω)²M + ikωC` is
//! not singular along `φ` at `ω > 0` (`φᴴ(−(kω)²M + ikωC)φ` has the real part
//! `−(kω)² φᵀMφ < 0`), and the linear steady state of [`LinearModel::linear_steady_state`]
//! exists as for a model without rigid modes (unless an elastic mode is an undamped resonance
//! of the fundamental or of a harmonic). A constant force, which would make a rigid mode
//! drift, cannot be expressed by [`crate::HarmonicForcing`]. A rigid mode along which
//! neither a dashpot (`CΦa = 0`) nor a contact pair (`wᵀΦa = 0` for every pair) acts keeps any
//! velocity it is given forever: such a free body drifts, and the model is refused
//! ([`ModelError::Drift`]). A rigid mode restrained by a dashpot only has a bounded motion
//! whose offset is arbitrary; the cycle equations ask that the impacts of the sequence see
//! every rigid mode ([`crate::SequenceOrbitError::UnrestrainedRigidMode`]).
//!
//! **The family of linear motions.** With rigid modes the linear steady state is not one
//! motion but a family: `u(t) = U(θ) + Φa` for every offset `a ∈ ℝʳ` (the rigid
//! velocities must vanish, or the motion drifts). [`LinearModel::linear_steady_state`] gives
//! the member `a = 0`, the only one without a constant part; [`LinearModel::clear_family`]
//! decides whether some member stays clear of every stop. Pair `p`'s relative coordinate is
//! `r_p(t) = ρ_p(t) + b_pᵀa`, `ρ_p = w_pᵀU(θ)` between its extremes `ρ_p⁻ ≤ ρ_p ≤ ρ_p⁺`
//! (`∓A_p` for a purely harmonic forcing, `A_p` the amplitude of `w_pᵀ(U_c cos θ + U_s sin θ)`;
//! see [`crate::HarmonicState::relative_extremes`]) and `b_p = Φᵀw_p`. It stays inside
//! `[−gap_side2, gap_side1]` exactly when `−gap_side2 − ρ_p⁻ ≤ b_pᵀa ≤ gap_side1 − ρ_p⁺`: for
//! a pair whose coordinate involves a rigid mode (`b_p ≠ 0`) some offset exists alone when the
//! peak-to-peak `ρ_p⁺ − ρ_p⁻ ≤ gap_side1 + gap_side2`; for any other pair the condition is
//! `ρ_p⁺ ≤ gap_side1` and `−ρ_p⁻ ≤ gap_side2` (the condition of a model without rigid modes;
//! `A_p ≤ min(gap_side1, gap_side2)` for a purely harmonic forcing). Since the offsets are
//! shared by the pairs, the family exists when the slabs of all pairs
//! intersect: decided exactly by Fourier–Motzkin elimination of `a`'s `r` entries (the pairs
//! are few), which also gives one member (each entry chosen in the middle of its interval,
//! the last eliminated first).

use crate::model::{couples, ContactPair, HarmonicState, LinearModel, ModelError};
use nalgebra::{DMatrix, DVector};

/// How the linear motion (the family member without offset) meets one pair's stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PairClearance {
    /// `A_p`: amplitude `max_t |ρ_p(t)|` of the pair's relative coordinate in the member
    /// without offset.
    pub amplitude: f64,
    /// `(min_t ρ_p, max_t ρ_p)`: `(−A_p, A_p)` for a purely harmonic forcing; a forcing with
    /// harmonics may reach further to one side than to the other.
    pub extremes: (f64, f64),
    /// Whether the pair's coordinate involves a rigid mode (`|Φᵀw| > `[`crate::model::RIGID_COUPLING`]`|w|`).
    pub involves_rigid: bool,
    /// The pair's own condition: the peak-to-peak `max ρ_p − min ρ_p ≤ gap_side1 + gap_side2`
    /// when it involves a rigid mode (some offset keeps it clear), `max ρ_p ≤ gap_side1` and
    /// `−min ρ_p ≤ gap_side2` otherwise (`A_p ≤ min(gap_side1, gap_side2)` for a purely
    /// harmonic forcing).
    pub clear: bool,
}

/// The family of linear steady states `U(θ) + Φa` at one frequency, and
/// whether some member stays clear of every stop ([`LinearModel::clear_family`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ClearFamily {
    /// The member without offset (`a = 0`), [`LinearModel::linear_steady_state`].
    pub state: HarmonicState,
    /// The rigid modes `Φ` (`n × r`, orthonormal columns; `r = 0` for a model without any).
    pub rigid_modes: DMatrix<f64>,
    /// Each pair's own condition, in the order of [`LinearModel::pairs`].
    pub pairs: Vec<PairClearance>,
    /// Whether one offset keeps every pair clear at once: the slabs
    /// `−gap_side2 − min ρ_p ≤ (Φᵀw_p)ᵀa ≤ gap_side1 − max ρ_p` intersect (a touch counts as
    /// clear).
    pub exists: bool,
    /// One such offset `a` (`r` entries) when `exists`: the motion `u + Φa` is clear.
    pub offset: Option<DVector<f64>>,
}

/// One linear inequality `cᵀa ≤ d` in the offsets.
#[derive(Debug, Clone)]
struct Inequality {
    c: Vec<f64>,
    d: f64,
    /// Sum of the moduli of the terms that made `d`: its rounding is a few ulps of this.
    size: f64,
}

/// Whether `value`, the rounded sum of terms of total modulus `size`, is below zero by more
/// than its rounding (`8 ε size`).
fn below_zero(value: f64, size: f64) -> bool {
    value < -8.0 * f64::EPSILON * size
}

/// A point of `{a : cᵀa ≤ d for every inequality}` in `dims` dimensions, or `None` when the
/// set is empty: Fourier–Motzkin elimination of the last entry first, then back-substitution
/// (each entry in the middle of its interval, or at its one finite end plus nothing, or 0).
fn feasible_point(inequalities: Vec<Inequality>, dims: usize) -> Option<Vec<f64>> {
    let mut stages: Vec<Vec<Inequality>> = Vec::with_capacity(dims + 1);
    stages.push(inequalities);
    for k in (0..dims).rev() {
        let current = &stages[stages.len() - 1];
        let (mut upper, mut lower, mut rest) = (Vec::new(), Vec::new(), Vec::new());
        for q in current {
            if q.c[k] > 0.0 {
                upper.push(q);
            } else if q.c[k] < 0.0 {
                lower.push(q);
            } else {
                rest.push(q.clone());
            }
        }
        for u in &upper {
            for l in &lower {
                // u: c_u a ≤ d_u with c_u,k > 0; l: c_l,k < 0. Combine to cancel a_k.
                let (su, sl) = (-l.c[k], u.c[k]);
                let c: Vec<f64> = (0..dims)
                    .map(|j| {
                        if j == k {
                            0.0
                        } else {
                            su * u.c[j] + sl * l.c[j]
                        }
                    })
                    .collect();
                rest.push(Inequality {
                    c,
                    d: su * u.d + sl * l.d,
                    size: su * u.size + sl * l.size,
                });
            }
        }
        stages.push(rest);
    }
    if stages[dims].iter().any(|q| below_zero(q.d, q.size)) {
        return None;
    }
    let mut a = vec![0.0; dims];
    for k in 0..dims {
        // Stage dims − 1 − k still holds a_k, with a_0 … a_{k−1} chosen and later entries gone.
        let stage = &stages[dims - 1 - k];
        let (mut low, mut high) = (f64::NEG_INFINITY, f64::INFINITY);
        let mut size: f64 = 0.0;
        for q in stage {
            let known: f64 = (0..k).map(|j| q.c[j] * a[j]).sum();
            let room = q.d - known;
            if q.c[k] != 0.0 {
                let terms: f64 = (0..k).map(|j| (q.c[j] * a[j]).abs()).sum();
                size = size.max((q.size + terms) / q.c[k].abs());
            }
            if q.c[k] > 0.0 {
                high = high.min(room / q.c[k]);
            } else if q.c[k] < 0.0 {
                low = low.max(room / q.c[k]);
            }
        }
        if below_zero(high - low, size) {
            return None;
        }
        a[k] = match (low.is_finite(), high.is_finite()) {
            (true, true) => 0.5 * (low + high),
            (true, false) => low,
            (false, true) => high,
            (false, false) => 0.0,
        };
    }
    Some(a)
}

/// The family decision of [`LinearModel::clear_family`] for the state `state` of a model with
/// rigid modes `rigid` and pairs `pairs`.
pub(crate) fn clear_family(
    state: HarmonicState,
    rigid: &DMatrix<f64>,
    pairs: &[ContactPair],
) -> ClearFamily {
    let r = rigid.ncols();
    let mut inequalities = Vec::new();
    let mut clearances = Vec::with_capacity(pairs.len());
    let mut every_pair = true;
    for pair in pairs {
        let (low, high) = state.relative_extremes(pair);
        let amplitude = high.max(-low);
        let b = rigid.transpose() * &pair.direction;
        let involves_rigid = r > 0 && couples(&b, &pair.direction);
        let clear = if involves_rigid {
            high - low <= pair.gap_side1 + pair.gap_side2
        } else {
            high <= pair.gap_side1 && -low <= pair.gap_side2
        };
        every_pair &= clear;
        clearances.push(PairClearance {
            amplitude,
            extremes: (low, high),
            involves_rigid,
            clear,
        });
        if involves_rigid {
            // bᵀa ≤ gap_side1 − max ρ and −bᵀa ≤ gap_side2 + min ρ (an infinite gap: no
            // inequality).
            for (sign, gap, reach) in [(1.0, pair.gap_side1, high), (-1.0, pair.gap_side2, -low)] {
                if gap.is_finite() {
                    inequalities.push(Inequality {
                        c: b.iter().map(|v| sign * v).collect(),
                        d: gap - reach,
                        size: gap + reach.abs(),
                    });
                }
            }
        }
    }
    let offset = if every_pair {
        feasible_point(inequalities, r).map(DVector::from_vec)
    } else {
        None
    };
    ClearFamily {
        state,
        rigid_modes: rigid.clone(),
        pairs: clearances,
        exists: offset.is_some(),
        offset,
    }
}

impl LinearModel {
    /// The family of linear steady states at `omega` (the motion without contact,
    /// `U(θ) + Φa` for every offset `a` along the rigid modes `Φ`, `U(θ)` the sum of the
    /// fundamental's and the harmonics' responses) and whether some member stays clear of
    /// every stop: see the module's derivation. Without rigid modes the family is the one
    /// steady state, and it exists exactly when every pair's relative coordinate stays within
    /// its stops (for a purely harmonic forcing: its amplitude is at most its smaller gap).
    ///
    /// # Errors
    /// As [`LinearModel::linear_steady_state`] ([`ModelError::Unbounded`] at an undamped
    /// resonance).
    pub fn clear_family(&self, omega: f64) -> Result<ClearFamily, ModelError> {
        let state = self.linear_steady_state(omega)?;
        Ok(clear_family(state, self.rigid_modes(), self.pairs()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Fourier–Motzkin on a square `|a₀| ≤ 1, |a₁| ≤ 2` and on `a₀ + a₁ ≤ 1, a₀ ≥ 1, a₁ ≥ 1`
    /// (empty): the point lies inside the first and the second is refused.
    #[test]
    fn feasible_point_decides_slabs() {
        let q = |c: [f64; 2], d: f64| Inequality {
            c: c.to_vec(),
            d,
            size: d.abs(),
        };
        let square = vec![
            q([1.0, 0.0], 1.0),
            q([-1.0, 0.0], 1.0),
            q([0.0, 1.0], 2.0),
            q([0.0, -1.0], 2.0),
        ];
        let a = feasible_point(square, 2).unwrap_or_else(|| panic!("a square is not empty"));
        assert!(a[0].abs() <= 1.0 && a[1].abs() <= 2.0);
        let empty = vec![
            q([1.0, 1.0], 1.0),
            q([-1.0, 0.0], -1.0),
            q([0.0, -1.0], -1.0),
        ];
        assert!(feasible_point(empty, 2).is_none());
    }
}
