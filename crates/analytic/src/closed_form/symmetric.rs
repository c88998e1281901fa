//! Symmetric two-impact orbits (`β = ½`) from the half-period symmetry.
//!
//! With symmetric stops the square Nigm–Shabana system is exactly singular at `β = ½`. The
//! symmetric orbit instead obeys `u(t + T/2) = −u(t)`: the state just after the side-1 impact,
//! carried by the exact flow over half a period, must arrive at minus the state just before it.
//! With unknowns `y = (u_o(0), u̇_o(0⁻), u̇_i(0⁻))` and the phase `p = (cos α, sin α)` this reads
//! `N_a y + F p = b`: four linear equations. The left null vector `L` of the 4×3 block `N_a`
//! eliminates `y` and leaves one linear condition on the phase, `L·F p = L·b`, a line cut by the
//! circle `|p| = 1` in 0 or 2 points: the two branches.

use crate::flow::ForcedFlow;
use crate::orbit::{assemble, wrap, Candidate, Flights, Orbit};
use crate::unit::{Stops, Unit};
use nalgebra::{Matrix4x3, Vector2, Vector3, Vector4};
use thiserror::Error;

/// A failure of the orbit computation that is not "no orbit exists".
#[derive(Debug, Clone, PartialEq, Error)]
pub enum OrbitError {
    /// The symmetry equations lose rank (below `DEGENERACY_TOLERANCE = 1e-13`): the phase is not
    /// determined by them.
    #[error("the symmetric-orbit equations are degenerate at ω = {omega} (rank < 3)")]
    Degenerate {
        /// The frequency at which it happened.
        omega: f64,
    },
    /// The periodicity solve `(I − M_cycle) y₁ = …` or the Newton Jacobian of a signature's
    /// contact conditions is singular.
    #[error("the impact-signature cycle equations are singular at ω = {omega}")]
    SingularCycle {
        /// The frequency at which it happened.
        omega: f64,
    },
    /// Newton on a signature's contact conditions did not converge.
    #[error("Newton on the impact-signature equations did not converge at ω = {omega} (residual {residual:e})")]
    NoConvergence {
        /// The frequency.
        omega: f64,
        /// The largest contact residual reached.
        residual: f64,
    },
    /// The forcing frequency is not finite and positive.
    #[error("omega = {omega} is out of range: must be finite and > 0")]
    InvalidFrequency {
        /// The rejected frequency.
        omega: f64,
    },
    /// A guess for a signature orbit is not `(α, φ₂, …, φₙ)` with `0 < φ₂ < … < φₙ < 1`.
    #[error("the guess has {len} entries: must be alpha and {impacts} - 1 ordered impact phases in (0, 1)")]
    InvalidGuess {
        /// Number of impacts of the signature.
        impacts: usize,
        /// Number of entries given.
        len: usize,
    },
}

/// Rank test of the symmetry equations: `N_a` is taken to have lost rank when its left null
/// vector `L` (whose norm is the product of the singular values of `N_a`) is below this
/// fraction of the product of its column norms (Hadamard's bound, so the ratio lies in
/// `[0, 1]`). Each minor carries rounding of a few `ε ≈ 2.2e-16` of that product; `1e-13`
/// (about 450 `ε`) leaves a margin of two orders above rounding. Reasoned, not measured.
pub(crate) const DEGENERACY_TOLERANCE: f64 = 1e-13;

/// Relative cutoff of the SVD solve for the impact state: zero, so no singular value is
/// dropped. `N_a` has full column rank once it passes `DEGENERACY_TOLERANCE = 1e-13`, and the
/// right-hand side lies in its range on the phase line, so the solve is exact.
const SVD_CUTOFF: f64 = 0.0;

/// Left null vector of a 4×3 matrix of full column rank, by the generalised cross product
/// `L_i = (−1)^i det(N without row i)`. Its norm relative to the product of the column norms
/// measures how far the matrix is from losing rank.
fn left_null(n: &Matrix4x3<f64>) -> Vector4<f64> {
    let minor = |skip: usize| {
        let rows: Vec<usize> = (0..4).filter(|&r| r != skip).collect();
        nalgebra::Matrix3::from_fn(|i, j| n[(rows[i], j)]).determinant()
    };
    Vector4::new(minor(0), -minor(1), minor(2), -minor(3))
}

/// Every symmetric two-impact orbit (`β = ½`) of `unit` with `stops` at angular frequency
/// `omega`: zero, one (tangency) or two branches, each with its viability and stability.
///
/// Branch 0 is `α = φ + acos(g/ρ)`, branch 1 is `α = φ − acos(g/ρ)`, where the phase condition
/// reads `ρ cos(α − φ) = g` with the sign of `L` chosen so that `g ≥ 0`. An empty list means
/// no symmetric orbit exists (the phase line misses the unit circle). The unit and stops are
/// not validated here (see [`Unit::validate`], [`Stops::validate`]).
///
/// # Errors
/// [`OrbitError::Degenerate`] when the symmetry equations lose rank
/// (`DEGENERACY_TOLERANCE = 1e-13`), so that they do not determine the phase.
pub fn symmetric_orbits(unit: &Unit, stops: &Stops, omega: f64) -> Result<Vec<Orbit>, OrbitError> {
    let flow = ForcedFlow::new(unit, omega);
    let half = flow.transition(0.5 * flow.period());
    let e = half.homogeneous;
    let g = stops.impact_map(unit);
    let gap = stops.gap;

    let both = Vector4::new(1.0, 1.0, 0.0, 0.0);
    let vo = Vector4::new(0.0, 0.0, g[(0, 0)], g[(1, 0)]);
    let vi = Vector4::new(0.0, 0.0, g[(0, 1)], g[(1, 1)]);
    let n_a = Matrix4x3::from_columns(&[
        e * both + both,
        e * vo + Vector4::new(0.0, 0.0, 1.0, 0.0),
        e * vi + Vector4::new(0.0, 0.0, 0.0, 1.0),
    ]);
    let d = Vector4::new(0.0, gap, 0.0, 0.0);
    let rhs = -(e * d + d);

    let mut l = left_null(&n_a);
    let scale: f64 = n_a.column_iter().map(|c| c.norm()).product();
    if l.norm() <= DEGENERACY_TOLERANCE * scale {
        return Err(OrbitError::Degenerate { omega });
    }
    let mut g_line = l.dot(&rhs);
    if g_line < 0.0 {
        l = -l;
        g_line = -g_line;
    }
    let a = half.forced.transpose() * l; // (a_c, a_s): a_c cos α + a_s sin α = g
    let rho = a.norm();
    let ratio = g_line / rho;
    if ratio.is_nan() || ratio > 1.0 {
        return Ok(Vec::new());
    }
    let phi = a[1].atan2(a[0]);
    let spread = ratio.acos();
    let svd = n_a.svd(true, true);
    let alphas: Vec<f64> = if spread == 0.0 {
        vec![phi]
    } else {
        vec![phi + spread, phi - spread]
    };
    let flights = Flights {
        first: half,
        second: half,
        symmetric: true,
    };
    let mut orbits = Vec::with_capacity(alphas.len());
    for alpha in alphas {
        let alpha = wrap(alpha);
        let p = Vector2::new(alpha.cos(), alpha.sin());
        let y: Vector3<f64> = svd
            .solve(&(rhs - half.forced * p), SVD_CUTOFF)
            .expect("SVD computed with both U and V");
        let before1 = Vector4::new(y[0], y[0] + gap, y[1], y[2]);
        let candidate = Candidate {
            beta: 0.5,
            alpha,
            before1,
            before2: -before1,
        };
        orbits.push(assemble(unit, stops, &flow, &candidate, &flights));
    }
    Ok(orbits)
}
