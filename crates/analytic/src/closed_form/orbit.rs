//! Two-impact periodic orbits: one impact on each stop per forcing period.
//!
//! Time `t = 0` is the side-1 impact (`r = +Δ`); the base moves as `u_g cos(ωt + α)`; the
//! side-2 impact (`r = −Δ`) comes at `t = βT`. Between impacts the motion is the exact flow
//! of [`ForcedFlow`]. An [`Orbit`] built here carries its own verdicts: viability (decided
//! from the rigorous extrema of `r(t)` along both flights) and stability (Floquet multipliers
//! of the monodromy matrix with a saltation matrix at each impact).

use crate::flow::{join, Augmented, Extrema, ForcedFlow, Transition};
use crate::linear::transmittance_db;
use crate::unit::{Stops, Unit};
use nalgebra::{Complex, Matrix2, Matrix4, Vector2, Vector4};

/// Which stop: side 1 at `r = +Δ`, side 2 at `r = −Δ`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Side {
    /// The stop at `r = +Δ`.
    One,
    /// The stop at `r = −Δ`.
    Two,
}

impl Side {
    /// 1 or 2.
    pub fn number(self) -> u8 {
        match self {
            Side::One => 1,
            Side::Two => 2,
        }
    }
}

/// Why a solution of the orbit equations is not a motion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Violation {
    /// Between impacts the inner mass passes through a stop: `r(t)` exceeds `+Δ` (side 1) or
    /// falls below `−Δ` (side 2) by `excess` at time `time` after the side-1 impact.
    Penetration {
        /// The stop passed through.
        side: Side,
        /// Time after the side-1 impact at which the penetration is deepest.
        time: f64,
        /// How far beyond the stop, `> 0`.
        excess: f64,
    },
    /// The impact is approached from outside: `ṙ⁻ ≤ 0` at side 1 or `ṙ⁻ ≥ 0` at side 2.
    WrongApproach {
        /// The stop hit from the wrong side.
        side: Side,
        /// The relative velocity `ṙ⁻` just before that impact.
        relative_velocity: f64,
    },
    /// Between two impacts of a signature orbit, `r(t)` goes beyond a stop and comes back: a
    /// contact that the signature does not have (neither adjacent impact on that stop is
    /// approached from outside).
    ExtraImpact {
        /// The stop reached.
        side: Side,
        /// Time after the first canonical impact at which `r` is furthest beyond the stop.
        time: f64,
        /// How far beyond the stop, `> 0`.
        excess: f64,
    },
}

/// A two-impact periodic orbit of the impacting unit and its verdicts.
#[derive(Debug, Clone, PartialEq)]
pub struct Orbit {
    /// Angular frequency `ω` of the forcing.
    pub omega: f64,
    /// Gap `Δ` at which this orbit exists.
    pub gap: f64,
    /// Fraction of the period from the side-1 to the side-2 impact, in `(0, 1)`.
    pub beta: f64,
    /// Base-motion phase at the side-1 impact, radians in `(−π, π]`.
    pub alpha: f64,
    /// State `(u_o, u_i, u̇_o, u̇_i)` just before the side-1 impact (`t = 0⁻`).
    pub state_before_impact: Vector4<f64>,
    /// State just after the side-1 impact (`t = 0⁺`).
    pub state_after_impact: Vector4<f64>,
    /// State just before the side-2 impact (`t = βT⁻`).
    pub state_before_side2: Vector4<f64>,
    /// State just after the side-2 impact (`t = βT⁺`); the motion between impacts is
    /// [`crate::UnitMotion`]'s.
    pub state_after_side2: Vector4<f64>,
    /// `X_o = max |u_o(t)|` over the period, from the rigorous extrema of the closed form.
    pub outer_amplitude: f64,
    /// `20 log10(X_o / u_g)`.
    pub transmittance_db: f64,
    /// True when no [`Violation`] was found.
    pub viable: bool,
    /// Every condition that fails.
    pub violations: Vec<Violation>,
    /// Eigenvalues of the monodromy matrix (with saltation at both impacts).
    pub floquet_multipliers: Vec<Complex<f64>>,
    /// Asymptotic stability: every Floquet multiplier has modulus `< 1 − 1e-9`
    /// ([`STABILITY_MARGIN`]).
    pub stable: bool,
}

/// Relative tolerance on the stops used for the viability verdict: an interior excursion of
/// `r` beyond a stop by more than `1e-9 Δ` is a penetration. `r` touches `±Δ` at both impacts
/// (the ends of each flight), where the orbit equations are met only to their residual: up to
/// `1e-10` of the state for a family orbit near `β = ½` (the tolerance the tests check). One
/// order above that, an orbit is not declared non-viable by its own rounding at the impacts.
pub const VIABILITY_TOLERANCE: f64 = 1e-9;

/// Margin inside the unit circle for the stability verdict. Without dissipation (`e = 1`, no
/// dashpots) `det(monodromy) = 1` and the multipliers lie on the unit circle up to the
/// rounding of the monodromy (about `1e-12`); the margin keeps such an orbit from being called
/// asymptotically stable by rounding. The same value as [`VIABILITY_TOLERANCE`], by choice.
pub const STABILITY_MARGIN: f64 = 1e-9;

/// Cap on the QR sweeps of one Schur attempt in [`eigenvalues`]. A 4×4 matrix deflates in a
/// few sweeps per eigenvalue; 1000 is reached only by an iteration that cycles (as nalgebra's
/// unbounded one did), and then the next attempt is tried.
pub(crate) const SCHUR_ITERATIONS: usize = 1000;

/// Convergence threshold of the Schur iteration: a subdiagonal entry is deflated when it falls
/// to unit roundoff of its neighbours, the tightest threshold a double can resolve.
pub(crate) const SCHUR_EPSILON: f64 = f64::EPSILON;

/// Shifts `σ` (in units of `max|m_ij|`) of the fallback attempts in [`eigenvalues`]: two
/// unrelated values of opposite sign and of order the matrix's size, so that the shifted
/// iterations follow other paths than the plain one; the shift costs absolute accuracy of
/// order `ε max|m_ij|` only. Chosen, not tuned.
pub(crate) const SCHUR_SHIFTS: [f64; 2] = [0.5, -0.37];

/// Gradient of the relative displacement `r = u_i − u_o` with respect to the state.
pub(crate) fn relative_displacement() -> Vector4<f64> {
    Vector4::new(-1.0, 1.0, 0.0, 0.0)
}

/// The state after an impact: positions kept, velocities mapped by `G`.
pub(crate) fn impact(g: &Matrix2<f64>, x: &Vector4<f64>) -> Vector4<f64> {
    let v = g * Vector2::new(x[2], x[3]);
    Vector4::new(x[0], x[1], v[0], v[1])
}

/// Saltation matrix of an impact on the surface `h = r ∓ Δ`:
/// `S = Ĝ + (f⁺ − Ĝ f⁻) h_xᵀ / (h_x · f⁻)`, `Ĝ = diag(I, G)`.
pub(crate) fn saltation(
    flow: &ForcedFlow,
    g: &Matrix2<f64>,
    before: &Vector4<f64>,
    phase: &Vector2<f64>,
) -> Matrix4<f64> {
    let after = impact(g, before);
    let f_minus = flow.vector_field(before, phase);
    let f_plus = flow.vector_field(&after, phase);
    let mut g_hat = Matrix4::identity();
    g_hat.fixed_view_mut::<2, 2>(2, 2).copy_from(g);
    let hx = relative_displacement();
    g_hat + (f_plus - g_hat * f_minus) * hx.transpose() / hx.dot(&f_minus)
}

/// The impact states and phase that solve the orbit equations, before any verdict.
pub(crate) struct Candidate {
    /// Fraction of the period from the side-1 to the side-2 impact.
    pub beta: f64,
    /// Base phase at the side-1 impact.
    pub alpha: f64,
    /// State at `t = 0⁻`, with `r = +gap`.
    pub before1: Vector4<f64>,
    /// State at `t = βT⁻`, with `r = −gap`.
    pub before2: Vector4<f64>,
}

/// The exact flow over both flights of an orbit.
pub(crate) struct Flights {
    /// Over `βT`, from the side-1 to the side-2 impact.
    pub first: Transition,
    /// Over `(1 − β)T`, back to the side-1 impact.
    pub second: Transition,
    /// True for a symmetric orbit (`u(t + T/2) = −u(t)`): the second flight mirrors the first.
    pub symmetric: bool,
}

/// Builds the orbit through the impact states of `candidate` and checks it.
///
/// The caller guarantees these solve the orbit equations; this function derives the
/// post-impact states, the extrema along both flights, the viability verdict and the Floquet
/// multipliers.
pub(crate) fn assemble(
    unit: &Unit,
    stops: &Stops,
    flow: &ForcedFlow,
    candidate: &Candidate,
    flights: &Flights,
) -> Orbit {
    let Candidate {
        beta,
        alpha,
        before1,
        before2,
    } = *candidate;
    let gap = stops.gap;
    let g = stops.impact_map(unit);
    let period = flow.period();
    let t1 = beta * period;
    let p0 = Vector2::new(alpha.cos(), alpha.sin());
    let (first, second) = (&flights.first, &flights.second);
    let p1 = first.rotation * p0;
    let after1 = impact(&g, &before1);
    let after2 = impact(&g, &before2);

    let hx = relative_displacement();
    let r_fn = join(&hx, &Vector2::zeros());
    let uo_fn = Augmented::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let fns = [r_fn, uo_fn];
    let flight1 = flow.extrema(&join(&after1, &p0), t1, &fns);
    let flight2 = if flights.symmetric {
        flight1
            .iter()
            .map(|e| Extrema {
                max: -e.min,
                argmax: e.argmin,
                min: -e.max,
                argmin: e.argmax,
            })
            .collect()
    } else {
        flow.extrema(&join(&after2, &p1), period - t1, &fns)
    };

    let mut violations = Vec::new();
    let rdot1 = before1[3] - before1[2];
    let rdot2 = before2[3] - before2[2];
    if rdot1 <= 0.0 {
        violations.push(Violation::WrongApproach {
            side: Side::One,
            relative_velocity: rdot1,
        });
    }
    if rdot2 >= 0.0 {
        violations.push(Violation::WrongApproach {
            side: Side::Two,
            relative_velocity: rdot2,
        });
    }
    let tol = VIABILITY_TOLERANCE * gap;
    // Deepest penetration of each stop over both flights (times measured from t = 0).
    let over1 = [
        (flight1[0].max, flight1[0].argmax),
        (flight2[0].max, t1 + flight2[0].argmax),
    ];
    let under2 = [
        (flight1[0].min, flight1[0].argmin),
        (flight2[0].min, t1 + flight2[0].argmin),
    ];
    let (rmax, tmax) =
        over1.into_iter().fold(
            (f64::NEG_INFINITY, 0.0),
            |a, b| if b.0 > a.0 { b } else { a },
        );
    let (rmin, tmin) = under2
        .into_iter()
        .fold((f64::INFINITY, 0.0), |a, b| if b.0 < a.0 { b } else { a });
    if rmax > gap + tol {
        violations.push(Violation::Penetration {
            side: Side::One,
            time: tmax,
            excess: rmax - gap,
        });
    }
    if rmin < -gap - tol {
        violations.push(Violation::Penetration {
            side: Side::Two,
            time: tmin,
            excess: -gap - rmin,
        });
    }

    let outer_amplitude = [flight1[1], flight2[1]]
        .iter()
        .map(|e| e.max.abs().max(e.min.abs()))
        .fold(0.0, f64::max);
    let s1 = saltation(flow, &g, &before1, &p0);
    let s2 = saltation(flow, &g, &before2, &p1);
    let monodromy = s1 * second.homogeneous * s2 * first.homogeneous;
    // A monodromy that is not finite (a grazing impact makes the saltation matrix blow up)
    // gives NaN multipliers (`null` in JSON) and `stable = false`.
    let floquet_multipliers: Vec<Complex<f64>> = eigenvalues(&monodromy)
        .map(|e| e.to_vec())
        .unwrap_or_else(|| vec![Complex::new(f64::NAN, f64::NAN); 4]);
    let stable = floquet_multipliers
        .iter()
        .all(|m| m.norm() < 1.0 - STABILITY_MARGIN);

    Orbit {
        omega: flow.omega(),
        gap,
        beta,
        alpha,
        state_before_impact: before1,
        state_after_impact: after1,
        state_before_side2: before2,
        state_after_side2: after2,
        outer_amplitude,
        transmittance_db: transmittance_db(outer_amplitude, unit.base_amplitude),
        viable: violations.is_empty(),
        violations,
        floquet_multipliers,
        stable,
    }
}

/// Wraps an angle into `(−π, π]`.
pub(crate) fn wrap(angle: f64) -> f64 {
    let w = angle.rem_euclid(std::f64::consts::TAU);
    if w > std::f64::consts::PI {
        w - std::f64::consts::TAU
    } else {
        w
    }
}

/// The eigenvalues of `m`, by the real Schur form with a bounded QR iteration. nalgebra's
/// unbounded iteration can cycle forever on some finite matrices (it did on a monodromy of
/// the damped paper unit at e = 9/39, Δ = 0.6833, ω = 2.7489); when the iteration does not
/// converge, it is run on the transpose, then on shifted copies `m + σI` (eigenvalues
/// `λ + σ`), which change the iteration but not the answer. `None` for a non-finite matrix or
/// when every attempt fails.
pub fn eigenvalues(m: &Matrix4<f64>) -> Option<[Complex<f64>; 4]> {
    if !m.iter().all(|v| v.is_finite()) {
        return None;
    }
    let scale = m.amax().max(f64::MIN_POSITIVE);
    for (matrix, shift) in [
        (*m, 0.0),
        (m.transpose(), 0.0),
        (
            m + Matrix4::identity() * (SCHUR_SHIFTS[0] * scale),
            SCHUR_SHIFTS[0] * scale,
        ),
        (
            m + Matrix4::identity() * (SCHUR_SHIFTS[1] * scale),
            SCHUR_SHIFTS[1] * scale,
        ),
    ] {
        if let Some(schur) =
            nalgebra::linalg::Schur::try_new(matrix, SCHUR_EPSILON, SCHUR_ITERATIONS)
        {
            let e = schur.complex_eigenvalues();
            return Some([e[0], e[1], e[2], e[3]].map(|l| l - shift));
        }
    }
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The monodromy on which nalgebra's unbounded Schur iteration cycled forever (damped
    /// paper unit, e = 9/39, Δ = 0.6833, ω = 2.7489, symmetric branch), column by column.
    fn cycling_monodromy() -> Matrix4<f64> {
        Matrix4::from_column_slice(&[
            -0.5949065900786252,
            -0.54785366462303,
            0.09877288697600826,
            0.12768814862690236,
            -0.2736063407419963,
            -0.24558433817231848,
            -0.24127877581140877,
            -0.10566685059017007,
            -0.08898796197315695,
            -0.12830918791764725,
            -0.48568868720653724,
            -0.48981661360765977,
            0.17069267029308077,
            0.07791231009587478,
            -0.3650431717907076,
            -0.34735400366643376,
        ])
    }

    #[test]
    fn eigenvalues_of_a_matrix_that_defeats_the_plain_iteration() {
        let m = cycling_monodromy();
        let l = eigenvalues(&m).expect("eigenvalues");
        // Sum and product of the eigenvalues are the trace and the determinant, and each
        // makes M − λI singular.
        let sum: Complex<f64> = l.iter().sum();
        let product: Complex<f64> = l.iter().product();
        assert!(
            (sum.re - m.trace()).abs() < 1e-12 && sum.im.abs() < 1e-12,
            "{sum}"
        );
        assert!((product.re - m.determinant()).abs() < 1e-12 && product.im.abs() < 1e-12);
        let mc = m.map(|v| Complex::new(v, 0.0));
        for lambda in l {
            let shifted = mc - nalgebra::Matrix4::<Complex<f64>>::identity() * lambda;
            assert!(shifted.determinant().norm() < 1e-10, "{lambda}");
        }
        // A non-finite matrix has none.
        let mut bad = m;
        bad[(1, 2)] = f64::NAN;
        assert!(eigenvalues(&bad).is_none());
    }
}
