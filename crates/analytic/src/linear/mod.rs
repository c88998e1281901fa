//! The linear unit (no stops): modes and the closed-form steady state.

pub mod lattice;

use crate::unit::Unit;
use nalgebra::{Complex, Matrix2, SymmetricEigen};

/// Undamped exact resonance is declared when `|det(K − ω²M)|` is within this many ulps
/// (`ε ≈ 2.2e-16`) of the size of its terms, `scale = (k_o + k_i + ω² m_o)(k_i + ω² m_i)`.
/// Reasoning (not a measurement): at the paper's `ω₁` (`scale = 54`, `d det/dω² = −9`) an ulp
/// of `ω² = 1.5`, as left by `ω = sqrt(1.5)` squared, moves the determinant by `9ε ≈ ε·scale/6`,
/// and its two products (both 9) cancel with rounding of a few `9ε`: a few `ε·scale` in all.
/// 64 leaves about an order of margin above that, and is still `~1e-14` relative, far from
/// any frequency a sweep means to resolve.
pub(crate) const RESONANCE_ULPS: f64 = 64.0;

/// Natural frequencies and mass-normalised mode shapes of the undamped unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Modes {
    /// `ω_n²`, ascending.
    pub natural_frequencies_squared: [f64; 2],
    /// Mass-normalised mode shapes as columns (`Φᵀ M Φ = I`), rows `(u_o, u_i)`; each column's
    /// inner-mass component is made positive.
    pub shapes: Matrix2<f64>,
    /// Modal forces `P = Φᵀ f` per unit `cos ωt`, with `f = (k_o u_g, 0)` (paper eq. 5).
    pub modal_forces: [f64; 2],
}

/// Modes of `unit`: the generalised eigenproblem `K φ = ω² M φ`, solved as the symmetric
/// problem `M^{-1/2} K M^{-1/2}`.
pub fn modes(unit: &Unit) -> Modes {
    let s = Matrix2::new(
        1.0 / unit.outer_mass.sqrt(),
        0.0,
        0.0,
        1.0 / unit.inner_mass.sqrt(),
    );
    let eig = SymmetricEigen::new(s * unit.stiffness() * s);
    let mut order = [0usize, 1];
    order.sort_by(|&a, &b| eig.eigenvalues[a].total_cmp(&eig.eigenvalues[b]));
    let mut shapes = Matrix2::zeros();
    let mut w2 = [0.0; 2];
    for (col, &k) in order.iter().enumerate() {
        let mut phi = s * eig.eigenvectors.column(k);
        if phi[1] < 0.0 {
            phi = -phi;
        }
        shapes.set_column(col, &phi);
        w2[col] = eig.eigenvalues[k];
    }
    let f0 = unit.outer_stiffness * unit.base_amplitude;
    Modes {
        natural_frequencies_squared: w2,
        shapes,
        modal_forces: [shapes[(0, 0)] * f0, shapes[(0, 1)] * f0],
    }
}

/// The steady state of the linear unit: `u(t) = Re{U e^{iωt}}`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearResponse {
    /// Complex amplitude of the outer mass, `U_o` (infinite parts when unbounded).
    pub outer: Complex<f64>,
    /// Complex amplitude of the inner mass, `U_i`.
    pub inner: Complex<f64>,
    /// `X_o = |U_o| = max |u_o(t)|`; `+∞` at undamped exact resonance.
    pub outer_amplitude: f64,
    /// `X_i = |U_i|`; `+∞` at undamped exact resonance.
    pub inner_amplitude: f64,
    /// Amplitude of the relative motion `|U_i − U_o|`: the linear motion stays clear of stops
    /// with gap `Δ` exactly when this is `≤ Δ`.
    pub relative_amplitude: f64,
    /// `20 log10(X_o / u_g)`; `+∞` when unbounded.
    pub transmittance_db: f64,
    /// True at undamped exact resonance (`det(K − ω² M) = 0` to rounding): no bounded steady
    /// state exists.
    pub unbounded: bool,
}

/// Closed-form steady state of the linear unit at angular frequency `omega`:
/// `(K − ω² M + iωC) U = ((k_o + iω c_o) u_g, 0)`.
///
/// Undamped exact resonance (the determinant vanishes to within `RESONANCE_ULPS = 64.0` ulps of its
/// terms) is
/// reported as `unbounded` with infinite amplitudes, never NaN.
pub fn linear_response(unit: &Unit, omega: f64) -> LinearResponse {
    let w2 = omega * omega;
    let (mo, mi, ko, ki) = (
        unit.outer_mass,
        unit.inner_mass,
        unit.outer_stiffness,
        unit.inner_stiffness,
    );
    let (co, ci) = unit.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
    let d00 = Complex::new(ko + ki - w2 * mo, omega * (co + ci));
    let d01 = Complex::new(-ki, -omega * ci);
    let d11 = Complex::new(ki - w2 * mi, omega * ci);
    let det = d00 * d11 - d01 * d01;
    let scale = (ko + ki + w2 * mo) * (ki + w2 * mi);
    let force = Complex::new(ko, omega * co) * unit.base_amplitude;
    if det.norm() <= RESONANCE_ULPS * f64::EPSILON * scale {
        let inf = Complex::new(f64::INFINITY, 0.0);
        return LinearResponse {
            outer: inf,
            inner: inf,
            outer_amplitude: f64::INFINITY,
            inner_amplitude: f64::INFINITY,
            relative_amplitude: f64::INFINITY,
            transmittance_db: f64::INFINITY,
            unbounded: true,
        };
    }
    let outer = d11 * force / det;
    let inner = -d01 * force / det;
    LinearResponse {
        outer,
        inner,
        outer_amplitude: outer.norm(),
        inner_amplitude: inner.norm(),
        relative_amplitude: (inner - outer).norm(),
        transmittance_db: transmittance_db(outer.norm(), unit.base_amplitude),
        unbounded: false,
    }
}

/// Transmittance `T = 20 log10(X_o / u_g)` in dB.
pub fn transmittance_db(outer_amplitude: f64, base_amplitude: f64) -> f64 {
    20.0 * (outer_amplitude / base_amplitude).log10()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_models::{
        damped_paper_unit, damped_steady_state, paper_modes, paper_steady_state,
        paper_steady_states_exact, paper_unit, SteadyStateAnswer,
    };

    /// Rounding of a 2×2 symmetric eigen-solve and of the mass normalisation: a few `ε` of
    /// `‖M^{-1/2} K M^{-1/2}‖ ≈ 6`.
    const EIGEN_ROUNDING: f64 = 1e-13;

    #[test]
    fn paper_natural_frequencies_and_modal_forces() {
        let (unit, answer) = paper_modes();
        let m = modes(&unit);
        for n in 0..2 {
            let (got, want) = (
                m.natural_frequencies_squared[n],
                answer.natural_frequencies_squared[n],
            );
            assert!(
                (got - want).abs() < EIGEN_ROUNDING,
                "ω²_{n}: {got} vs {want}"
            );
            // The sign of a modal force follows its shape's sign convention.
            let (got, want) = (m.modal_forces[n].abs(), answer.modal_force_magnitudes[n]);
            assert!(
                (got - want).abs() < EIGEN_ROUNDING,
                "P_{n}: {got} vs {want}"
            );
            for row in 0..2 {
                let (got, want) = (m.shapes[(row, n)], answer.shapes[n][row]);
                assert!(
                    (got - want).abs() < EIGEN_ROUNDING,
                    "φ_{n}[{row}]: {got} vs {want}"
                );
            }
        }
        // Paper §2.2: (P1, P2) = (2.4495, 3.4641), to the paper's four decimals.
        assert!((m.modal_forces[0].abs() - 2.4495).abs() < 5e-5);
        assert!((m.modal_forces[1].abs() - 3.4641).abs() < 5e-5);
    }

    /// `linear_response` agrees with a hand answer to the rounding its own resonance test
    /// allows: relative error `RESONANCE_ULPS ε · scale / |det|`.
    fn assert_matches(unit: &Unit, answer: &SteadyStateAnswer) {
        let r = linear_response(unit, answer.omega);
        assert!(!r.unbounded, "ω = {}", answer.omega);
        let size = answer.outer.norm().max(answer.inner.norm());
        let tol = RESONANCE_ULPS * f64::EPSILON * answer.determinant_scale
            / answer.determinant_norm
            * size;
        for (got, want, name) in [
            (r.outer, answer.outer, "U_o"),
            (r.inner, answer.inner, "U_i"),
        ] {
            assert!(
                (got - want).norm() <= tol,
                "ω = {}: {name} = {got} vs {want} (tol {tol:e})",
                answer.omega
            );
        }
        assert!((r.outer_amplitude - answer.outer.norm()).abs() <= tol);
        assert!((r.relative_amplitude - (answer.inner - answer.outer).norm()).abs() <= 2.0 * tol);
    }

    #[test]
    fn undamped_steady_state_is_the_hand_solution() {
        let (unit, table) = paper_steady_states_exact();
        for answer in &table {
            assert_matches(&unit, answer);
        }
        for k in 1..=80 {
            let omega = 0.0537 * k as f64;
            let (unit, answer) = paper_steady_state(omega);
            assert_matches(&unit, &answer);
        }
    }

    #[test]
    fn damped_steady_state_is_the_cramer_solution() {
        for k in 1..=80 {
            let omega = 0.0537 * k as f64;
            let (unit, answer) = damped_steady_state(omega);
            assert_matches(&unit, &answer);
        }
        // At the undamped resonances, where only the dashpots keep it finite.
        let (_, modal) = paper_modes();
        for w2 in modal.natural_frequencies_squared {
            let (unit, answer) = damped_steady_state(w2.sqrt());
            assert_matches(&unit, &answer);
        }
    }

    #[test]
    fn anti_resonance_silences_the_outer_mass() {
        let (unit, modal) = paper_modes();
        let w = modal.anti_resonance;
        assert!((w - 1.732).abs() < 5e-4, "paper: 1.732");
        // The hand answer there: U_o = 0, U_i = −2.
        let (_, table) = paper_steady_states_exact();
        let answer = table
            .iter()
            .find(|a| a.omega == w)
            .expect("ω² = 3 in the table");
        assert_eq!(answer.outer, Complex::new(0.0, 0.0));
        assert_matches(&unit, answer);
        // Just off it, the outer mass moves.
        assert!(linear_response(&unit, w * 1.01).outer_amplitude > 1e-3);
    }

    #[test]
    fn undamped_resonance_is_unbounded_not_nan() {
        let (unit, modal) = paper_modes();
        for w2 in modal.natural_frequencies_squared {
            let r = linear_response(&unit, w2.sqrt());
            assert!(r.unbounded, "ω² = {w2}");
            assert_eq!(r.outer_amplitude, f64::INFINITY);
            assert!(!r.transmittance_db.is_nan());
            let damped = linear_response(&damped_paper_unit(), w2.sqrt());
            assert!(!damped.unbounded && damped.outer_amplitude.is_finite());
        }
    }

    #[test]
    fn steady_state_satisfies_the_equations_of_motion() {
        for unit in [paper_unit(), damped_paper_unit()] {
            for omega in [0.3, 1.0, 2.0, 3.7] {
                let r = linear_response(&unit, omega);
                // Residual of M ü + C u̇ + K u − f for u = Re{U e^{iωt}} at t = 0.37.
                let t = 0.37;
                let ph = Complex::new(0.0, omega * t).exp();
                let u = |a: Complex<f64>| (a * ph).re;
                let v = |a: Complex<f64>| (a * ph * Complex::new(0.0, omega)).re;
                let acc = |a: Complex<f64>| (a * ph * (-omega * omega)).re;
                let x = nalgebra::Vector2::new(u(r.outer), u(r.inner));
                let xd = nalgebra::Vector2::new(v(r.outer), v(r.inner));
                let xdd = nalgebra::Vector2::new(acc(r.outer), acc(r.inner));
                let co = unit.damping.map_or(0.0, |d| d.outer);
                let f = nalgebra::Vector2::new(
                    unit.outer_stiffness * (omega * t).cos() - co * omega * (omega * t).sin(),
                    0.0,
                ) * unit.base_amplitude;
                let res = unit.mass() * xdd + unit.damping_matrix() * xd + unit.stiffness() * x - f;
                assert!(res.norm() < 1e-12 * (1.0 + x.norm()), "ω={omega}: {res}");
            }
        }
    }
}
