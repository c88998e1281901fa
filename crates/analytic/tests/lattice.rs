//! The infinite lattice: band edges of the paper's cell by hand, edges at `cos q = ±1`, an edge
//! found again by bisection on the dispersion relation written here, Bloch waves that solve the
//! lattice's equations, and finite chains whose transmission falls with `N` at the lattice's
//! attenuation per cell inside a stop band and does not fall in a pass band.

use nalgebra::{Complex, Matrix2};
use rattle_analytic::test_models::{damped_paper_unit, paper_unit};
use rattle_analytic::*;

fn paper_cell() -> Cell {
    Cell::of_unit(&paper_unit())
}

fn damped_paper_cell() -> Cell {
    Cell::of_unit(&damped_paper_unit())
}

/// Other cells, so that no coincidence of the paper's numbers hides an error.
fn other_cells() -> [Cell; 2] {
    [
        Cell {
            outer_mass: 3.5,
            inner_mass: 0.4,
            outer_stiffness: 2.0,
            inner_stiffness: 7.0,
            damping: None,
        },
        Cell {
            outer_mass: 0.3,
            inner_mass: 2.2,
            outer_stiffness: 4.0,
            inner_stiffness: 0.9,
            damping: None,
        },
    ]
}

/// `cos q = 1 − ω² m_eff / (2 k_o)` of the undamped lattice, written out here:
/// `m_eff = m_o + m_i k_i / (k_i − m_i ω²)`.
fn cos_q(cell: &Cell, omega: f64) -> f64 {
    let w2 = omega * omega;
    let m_eff = cell.outer_mass
        + cell.inner_mass * cell.inner_stiffness / (cell.inner_stiffness - cell.inner_mass * w2);
    1.0 - w2 * m_eff / (2.0 * cell.outer_stiffness)
}

/// The paper's cell (`m_o = 2, m_i = 1, k_o = 6, k_i = 3`) by hand: `z_r = 3`,
/// `z_a = 3 · 3/2 = 9/2`, and `2z² − 33z + 72 = 0`, `z = (33 ∓ √513)/4`.
#[test]
fn paper_band_edges_by_hand() {
    let e = band_edges(&paper_cell()).unwrap();
    let want = [
        (e.acoustic_upper, (33.0 - 513f64.sqrt()) / 4.0),
        (e.local_resonance, 3.0),
        (e.optical_lower, 4.5),
        (e.optical_upper, (33.0 + 513f64.sqrt()) / 4.0),
    ];
    for (got, z) in want {
        assert!(
            (got * got - z).abs() <= 4.0 * f64::EPSILON * z,
            "{got}² vs {z}"
        );
    }
    // ω₁ = 1.6086, ω_a = 2.1213, ω₂ = 3.7299: beside the unit's attenuation band 1.5–2.2.
    assert!((e.acoustic_upper - 1.6086).abs() < 1e-4);
    assert!((e.optical_upper - 3.7299).abs() < 1e-4);
}

#[test]
fn band_edges_are_at_cos_q_plus_or_minus_one() {
    const EDGE: f64 = 1e-12;
    for cell in [paper_cell()].into_iter().chain(other_cells()) {
        let e = band_edges(&cell).unwrap();
        assert!(e.acoustic_upper < e.local_resonance);
        assert!(e.local_resonance < e.optical_lower);
        assert!(e.optical_lower < e.optical_upper);
        for (omega, c) in [
            (e.acoustic_upper, -1.0),
            (e.optical_lower, 1.0),
            (e.optical_upper, -1.0),
        ] {
            let wave = bloch_wave(&cell, omega).unwrap();
            assert!(
                (wave.cos_wavenumber - Complex::new(c, 0.0)).norm() <= EDGE,
                "ω = {omega}: cos q = {}",
                wave.cos_wavenumber
            );
            assert!((cos_q(&cell, omega) - c).abs() <= EDGE);
        }
    }
}

/// Bisection on `cos q + 1` (or `cos q − 1`) of [`cos_q`] between a pass-band and a stop-band
/// frequency, to adjacent floats: the edge of [`band_edges`] lies within a few ulps.
#[test]
fn band_edges_found_again_by_bisection() {
    let bisect = |cell: &Cell, mut a: f64, mut b: f64, level: f64| {
        let g = |w: f64| cos_q(cell, w) - level;
        assert!(g(a) * g(b) < 0.0, "no sign change in [{a}, {b}]");
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if g(m) * g(a) > 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        0.5 * (a + b)
    };
    let cell = paper_cell();
    let e = band_edges(&cell).unwrap();
    for (found, edge) in [
        (bisect(&cell, 1.0, 1.7, -1.0), e.acoustic_upper),
        (bisect(&cell, 1.8, 2.5, 1.0), e.optical_lower),
        (bisect(&cell, 3.0, 5.0, -1.0), e.optical_upper),
    ] {
        assert!(
            (found - edge).abs() <= 1e-14 * edge,
            "bisection {found} vs {edge}"
        );
    }
}

/// `λ` solves the lattice: with `U_o,j = λ^j`, `U_i,j = s_i U_o,j / (s_i − m_i ω²)`, the outer
/// mass's equation `−ω² m_o U_o + s_i (U_o − U_i) + κ (2U_o − U_o,j−1 − U_o,j+1) = 0` holds;
/// `λ` is the smaller eigenvalue of the cell's transfer matrix
/// `[[1, 1/κ], [−ω² m_eff, 1 − ω² m_eff/κ]]` (determinant 1); `cos q` and `e^{−iq}` agree.
#[test]
fn bloch_waves_solve_the_lattice() {
    for cell in [paper_cell(), damped_paper_cell()]
        .into_iter()
        .chain(other_cells())
    {
        for omega in [0.2, 0.9, 1.62, 1.7, 1.75, 2.0, 2.6, 3.5, 3.8, 6.0] {
            let wave = bloch_wave(&cell, omega).unwrap();
            let (co, ci) = cell.damping.map_or((0.0, 0.0), |d| (d.outer, d.inner));
            let w2 = omega * omega;
            let s = Complex::new(cell.inner_stiffness, omega * ci);
            let kappa = Complex::new(cell.outer_stiffness, omega * co);
            let l = wave.multiplier;
            let outer = Complex::new(1.0, 0.0);
            let inner = s * outer / (s - cell.inner_mass * w2);
            let residual = -outer * w2 * cell.outer_mass
                + s * (outer - inner)
                + kappa * (outer * 2.0 - outer / l - outer * l);
            let size = (w2 * cell.outer_mass + s.norm() * (1.0 + inner.norm()))
                + kappa.norm() * (2.0 + 1.0 / l.norm() + l.norm());
            assert!(
                residual.norm() <= 1e-13 * size,
                "ω = {omega}: residual {residual}"
            );
            assert!(l.norm() <= 1.0 + 1e-15);
            assert!((wave.attenuation + l.norm().ln()).abs() <= 1e-14);
            assert!((wave.wavenumber.im.abs() - wave.attenuation).abs() <= 1e-13);
            let lq = (Complex::new(0.0, -1.0) * wave.wavenumber).exp();
            assert!((lq - l).norm() <= 1e-13, "e^(-iq) {lq} vs λ {l}");
            let c = wave.wavenumber.cos();
            assert!((c - wave.cos_wavenumber).norm() <= 1e-12 * (1.0 + c.norm()));
            // The transfer matrix of a cell: eigenvalues λ and 1/λ.
            let m_eff = effective_mass(&cell, omega);
            let t = Matrix2::new(
                Complex::new(1.0, 0.0),
                kappa.inv(),
                -m_eff * w2,
                Complex::new(1.0, 0.0) - m_eff * w2 / kappa,
            );
            let char_poly =
                |z: Complex<f64>| (t[(0, 0)] - z) * (t[(1, 1)] - z) - t[(0, 1)] * t[(1, 0)];
            let scale = 1.0 + t.norm();
            assert!(char_poly(l).norm() <= 1e-12 * scale * scale);
            if cell.damping.is_none() {
                let inside = cos_q(&cell, omega).abs() <= 1.0;
                assert_eq!(wave.attenuation == 0.0, inside, "ω = {omega}");
            } else {
                assert!(wave.attenuation > 0.0);
            }
        }
    }
    // At the undamped local resonance exactly: infinite attenuation, no NaN.
    let cell = Cell {
        inner_mass: 1.0,
        inner_stiffness: 4.0,
        ..paper_cell()
    };
    let wave = bloch_wave(&cell, 2.0).unwrap();
    assert_eq!(wave.attenuation, f64::INFINITY);
    assert_eq!(wave.multiplier, Complex::new(0.0, 0.0));
}

/// Least-squares slope of `ln|U_o,N|` against `N` for `N = 4 … 16`.
fn decay_slope(cell: &Cell, omega: f64) -> (f64, Vec<f64>) {
    let ns: Vec<usize> = (4..=16).collect();
    let logs: Vec<f64> = ns
        .iter()
        .map(|&n| {
            let r = chain_response(&vec![*cell; n], 1.0, omega).unwrap();
            assert!(!r.unbounded);
            r.outer_amplitude.ln()
        })
        .collect();
    let mean_n = ns.iter().sum::<usize>() as f64 / ns.len() as f64;
    let mean_l = logs.iter().sum::<f64>() / logs.len() as f64;
    let (mut sxy, mut sxx) = (0.0, 0.0);
    for (&n, &l) in ns.iter().zip(&logs) {
        sxy += (n as f64 - mean_n) * (l - mean_l);
        sxx += (n as f64 - mean_n).powi(2);
    }
    (sxy / sxx, logs)
}

/// Inside a stop band the last cell's amplitude of an `N`-cell chain falls like `|λ|^N`: the
/// free end reflects a growing wave `λ^{−N}` of relative size `|λ|^{2N}`, so the slope of
/// `ln|U_N|` over `N = 4 … 16` is `−α` (`α` the attenuation) to within a few percent once
/// `|λ|^8 = e^{−8α}` is small: the tolerance is the smaller of the issue's 2 % and
/// `α e^{−8α}` (the reflection at `N = 4` with a reflection coefficient of order 1) plus a
/// rounding floor of `1e-12`; the damped paper cell too, at its damped attenuation. Measured: `3e-5 α` at worst (`α = 0.83`), `2e-8 α` or better
/// wherever `α > 1.5`.
/// The frequencies (80 % of the way from `ω₁` to `ω_r`, 10 % from `ω_r` to `ω_a`, `1.3 ω₂`)
/// are chosen where the attenuation is at least 0.5 per cell (`|λ|^8 ≤ e^{−4}`;
/// checked), in the local-resonance band on both sides of `ω_r` and in the Bragg band. (Near a
/// band edge the attenuation is small and the reflection decays too slowly for `N ≤ 16`: with
/// `k_o = 40` in place of 4, the third cell below attenuated 0.14 per cell midway between
/// `ω_r` and `ω_a`, where the slope fitted over `N = 4 … 16` came out 13 % short.) `|U_16|` also falls far below the bound
/// that holds in every pass band (next test).
#[test]
fn finite_chains_decay_at_the_lattice_attenuation_in_stop_bands() {
    for cell in [paper_cell(), damped_paper_cell()]
        .into_iter()
        .chain(other_cells())
    {
        let e = band_edges(&cell).unwrap();
        let inside = [
            e.acoustic_upper + 0.8 * (e.local_resonance - e.acoustic_upper),
            e.local_resonance + 0.1 * (e.optical_lower - e.local_resonance),
            1.3 * e.optical_upper,
        ];
        for omega in inside {
            let wave = bloch_wave(&cell, omega).unwrap();
            assert!(wave.attenuation >= 0.5, "ω = {omega}: {}", wave.attenuation);
            let (slope, logs) = decay_slope(&cell, omega);
            let alpha = wave.attenuation;
            let tolerance = (0.02 * alpha).min(alpha * (-8.0 * alpha).exp() + 1e-12);
            assert!(
                (slope + alpha).abs() <= tolerance,
                "ω = {omega}: slope {slope} vs attenuation {} ({logs:?})",
                wave.attenuation
            );
            let bound = eigenvector_condition(&cell, &wave);
            assert!(
                logs[12] < -bound.ln() - 3.0,
                "ω = {omega}: {logs:?}, {bound}"
            );
        }
    }
}

/// `‖V‖ ‖V⁻¹‖` (Frobenius) of the eigenvectors `(1, κ(λ − 1))`, `(1, κ(1/λ − 1))` of the
/// undamped cell's transfer matrix `[[1, 1/κ], [−ω² m_eff, 1 − ω² m_eff/κ]]`.
fn eigenvector_condition(cell: &Cell, wave: &BlochWave) -> f64 {
    let kappa = cell.outer_stiffness;
    let (l, li) = (wave.multiplier, wave.multiplier.inv());
    let one = Complex::new(1.0, 0.0);
    let v = Matrix2::new(one, one, (l - one) * kappa, (li - one) * kappa);
    let vinv = v.try_inverse().unwrap();
    v.norm() * vinv.norm()
}

/// In a pass band the undamped lattice does not attenuate, and neither does the finite chain:
/// `|U_N| = u_g / |P₂₂(N)|` with `P = T^N` bounded by the conditioning of `T`'s eigenvectors,
/// so `|U_N|` stays above `u_g / (‖V‖ ‖V⁻¹‖)` for every `N` (Frobenius norms, an upper bound);
/// in the stop bands above, `|U_16|` falls far below that same kind of bound.
#[test]
fn finite_chains_do_not_decay_in_pass_bands() {
    for cell in [paper_cell()].into_iter().chain(other_cells()) {
        let e = band_edges(&cell).unwrap();
        for omega in [
            0.4 * e.acoustic_upper,
            0.8 * e.acoustic_upper,
            0.5 * (e.optical_lower + e.optical_upper),
        ] {
            let wave = bloch_wave(&cell, omega).unwrap();
            assert_eq!(wave.attenuation, 0.0);
            let bound = eigenvector_condition(&cell, &wave);
            let (_, logs) = decay_slope(&cell, omega);
            for (k, log) in logs.iter().enumerate() {
                assert!(
                    *log >= -bound.ln() - 1e-9,
                    "ω = {omega}, N = {}: ln|U_N| = {log} < −ln {bound}",
                    k + 4
                );
            }
        }
    }
}

#[test]
fn stop_bands_are_the_edges_clipped_to_the_range() {
    let cell = damped_paper_cell();
    let e = band_edges(&cell).unwrap();
    let all = stop_bands(&cell, 0.0, 10.0).unwrap();
    assert_eq!(
        all,
        vec![
            StopBand {
                lower: e.acoustic_upper,
                upper: e.optical_lower,
                kind: StopBandKind::LocalResonance
            },
            StopBand {
                lower: e.optical_upper,
                upper: 10.0,
                kind: StopBandKind::Bragg
            },
        ]
    );
    let clipped = stop_bands(&cell, 2.0, 3.0).unwrap();
    assert_eq!(clipped.len(), 1);
    assert_eq!((clipped[0].lower, clipped[0].upper), (2.0, e.optical_lower));
    assert!(stop_bands(&cell, 2.2, 3.5).unwrap().is_empty());
    let json = serde_json::to_string(&stop_bands(&cell, 3.0, 4.0).unwrap()).unwrap();
    assert_eq!(
        json,
        format!(
            r#"[{{"lower":{},"upper":4.0,"kind":"bragg"}}]"#,
            e.optical_upper
        )
    );
    // Every frequency strictly inside a stop band attenuates; none outside.
    for k in 1..400 {
        let omega = 0.025 * k as f64;
        let wave = bloch_wave(&paper_cell(), omega).unwrap();
        let inside = all.iter().any(|b| b.lower < omega && omega < b.upper);
        assert_eq!(wave.attenuation > 0.0, inside, "ω = {omega}");
    }
}

#[test]
fn bad_lattice_input_is_refused_naming_the_field() {
    let field = |e: ModelError| match e {
        ModelError::OutOfRange { field, .. } => field,
        other => panic!("{other:?}"),
    };
    let bad = Cell {
        inner_stiffness: 0.0,
        ..paper_cell()
    };
    assert_eq!(field(band_edges(&bad).unwrap_err()), "cell.inner_stiffness");
    assert_eq!(
        field(bloch_wave(&bad, 1.0).unwrap_err()),
        "cell.inner_stiffness"
    );
    let cell = paper_cell();
    assert_eq!(field(bloch_wave(&cell, f64::NAN).unwrap_err()), "omega");
    assert_eq!(
        field(stop_bands(&cell, -1.0, 2.0).unwrap_err()),
        "omega_min"
    );
    assert_eq!(field(stop_bands(&cell, 2.0, 2.0).unwrap_err()), "omega_max");
    assert_eq!(
        field(stop_bands(&cell, 0.0, f64::INFINITY).unwrap_err()),
        "omega_max"
    );
}

/// Sixty-four cells deep in a stop band the last amplitude is `~e^{−64α}` (`1e-95` at `ω = 10`
/// for the paper's cell): the sweep neither overflows nor underflows, and away from the free
/// end (whose reflection is `|λ|^{2(N−j)}` relative) each cell's amplitude is the previous
/// one's times `|λ|`, to rounding.
#[test]
fn long_chains_deep_in_a_stop_band_decay_cell_by_cell() {
    let cell = paper_cell();
    for omega in [1.7, 2.0, 10.0] {
        let wave = bloch_wave(&cell, omega).unwrap();
        let r = chain_response(&vec![cell; MAX_CELLS], 1.0, omega).unwrap();
        assert!(!r.unbounded);
        for a in &r.cell_outer_amplitudes {
            assert!(a.is_finite() && *a > 0.0, "ω = {omega}: {a}");
        }
        for j in 1..48 {
            let ratio = r.cell_outer_amplitudes[j] / r.cell_outer_amplitudes[j - 1];
            let want = wave.multiplier.norm();
            assert!(
                (ratio - want).abs() <= 1e-10 * want,
                "ω = {omega}, cell {j}: {ratio} vs |λ| = {want}"
            );
        }
    }
}
