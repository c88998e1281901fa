//! The infinite lattice of identical cells: Bloch waves, their attenuation per cell, and the
//! pass and stop bands of the undamped lattice, all in closed form.
//!
//! Eliminating each inner mass (see [`crate::chain`]) leaves a chain of outer masses of
//! effective dynamic mass `m_eff(ω) = m_o + m_i s_i / (s_i − m_i ω²)`, `s_i = k_i + iωc_i`,
//! joined by `κ = k_o + iωc_o`: `κ (2U_j − U_{j−1} − U_{j+1}) = ω² m_eff U_j`. A Bloch wave
//! `U_{j+1} = λ U_j`, `λ = e^{−iq}`, solves it when `κ (2 − λ − 1/λ) = ω² m_eff`, that is
//!
//! `cos q = (λ + 1/λ)/2 = 1 − h`, `h = ω² m_eff(ω) / (2κ)`.
//!
//! The two roots `λ`, `1/λ` are the waves running either way; the one with `|λ| ≤ 1` decays
//! away from a source at the base, by `attenuation = −ln|λ| = |Im q|` nepers per cell.
//!
//! Undamped, `h` is real: the lattice passes waves where `0 ≤ h ≤ 2` (`|cos q| ≤ 1`, `q`
//! real) and stops them elsewhere. With `z = ω²`, `z_r = k_i/m_i` (the local resonance, where
//! `m_eff` is infinite) and `z_a = z_r (m_o + m_i)/m_o` (where `m_eff = 0`), `h = 0` at
//! `z = 0, z_a`, and `h = 2` where `z (m_o (z_r − z) + m_i z_r) = 4 k_o (z_r − z)`, the
//! quadratic `m_o z² − (z_r (m_o + m_i) + 4k_o) z + 4k_o z_r = 0`. Its value at `z_r` is
//! `−m_i z_r² < 0` and at `z_a` is `4k_o (z_r − z_a) < 0`, so its roots `z₁ < z_r < z_a < z₂`
//! bracket both, and the bands are, in `ω`:
//!
//! - pass `[0, ω₁]` (the acoustic branch, `q` from 0 to π);
//! - stop `(ω₁, ω_a)`, the local-resonance band: `cos q < −1` up to `ω_r = √z_r`, where the
//!   attenuation is infinite, then `cos q > 1`;
//! - pass `[ω_a, ω₂]` (the optical branch, `q` from 0 to π);
//! - stop `(ω₂, ∞)`, the Bragg band (`cos q < −1`).

use nalgebra::Complex;
use serde::Serialize;

use crate::chain::{check, Cell};
use crate::model::ModelError;

/// The effective dynamic mass of a cell, `m_eff(ω) = m_o + m_i s_i / (s_i − m_i ω²)`,
/// `s_i = k_i + iωc_i`: the force per unit acceleration the cell's outer mass offers, its inner
/// mass included. `+∞` (real) exactly at an undamped local resonance `m_i ω² = k_i`.
pub fn effective_mass(cell: &Cell, omega: f64) -> Complex<f64> {
    let (_, ci) = cell.dashpots();
    let s = Complex::new(cell.inner_stiffness, omega * ci);
    let d = s - cell.inner_mass * omega * omega;
    if d == Complex::new(0.0, 0.0) {
        return Complex::new(f64::INFINITY, 0.0);
    }
    cell.outer_mass + s * cell.inner_mass / d
}

/// The Bloch wave of the infinite lattice of one cell at one frequency: `U_{j+1} = λ U_j` with
/// `λ = e^{−iq}` the root with `|λ| ≤ 1` (the wave that decays away from the base).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlochWave {
    /// The angular frequency `ω`.
    pub omega: f64,
    /// `cos q = 1 − ω² m_eff / (2κ)`; `−∞` at an undamped local resonance.
    pub cos_wavenumber: Complex<f64>,
    /// `q = i ln λ`, with `Re q ∈ (−π, π]` (undamped: `q ∈ [0, π]` in a pass band, `q = iα` or
    /// `π + iα` in a stop band, `α ≤ 0`). `Im q = −∞` at an undamped local resonance.
    pub wavenumber: Complex<f64>,
    /// `λ = e^{−iq}`, `|λ| ≤ 1`; where `|λ| = 1` (an undamped pass band) the root with
    /// `Im λ ≤ 0`, so that `q ≥ 0`.
    pub multiplier: Complex<f64>,
    /// Attenuation per cell `−ln|λ| = |Im q| ≥ 0` in nepers (`8.686` dB per neper): exactly 0
    /// in an undamped pass band, `+∞` at an undamped local resonance.
    pub attenuation: f64,
}

fn check_cell(cell: &Cell) -> Result<(), ModelError> {
    cell.validate_as("cell")
}

/// The Bloch wave of the lattice of `cell` at `omega`, damped or not.
///
/// # Errors
/// [`ModelError::OutOfRange`] naming `cell.outer_mass`, …, `cell.damping.inner` (as
/// [`Cell::validate`]), or `omega` if it is not finite and `≥ 0`.
pub fn bloch_wave(cell: &Cell, omega: f64) -> Result<BlochWave, ModelError> {
    check_cell(cell)?;
    check("omega".to_string(), omega, omega >= 0.0, ">= 0")?;
    let m_eff = effective_mass(cell, omega);
    if m_eff.re.is_infinite() {
        return Ok(BlochWave {
            omega,
            cos_wavenumber: Complex::new(f64::NEG_INFINITY, 0.0),
            wavenumber: Complex::new(std::f64::consts::PI, f64::NEG_INFINITY),
            multiplier: Complex::new(0.0, 0.0),
            attenuation: f64::INFINITY,
        });
    }
    let (co, _) = cell.dashpots();
    let kappa = Complex::new(cell.outer_stiffness, omega * co);
    let h = m_eff * (omega * omega) / (kappa * 2.0);
    let cos_wavenumber = Complex::new(1.0, 0.0) - h;
    if h.im == 0.0 && (0.0..=2.0).contains(&h.re) {
        // Undamped pass band: 1 − cos q = 2 sin²(q/2) = h, accurate at both ends.
        let q = 2.0 * (h.re / 2.0).sqrt().asin();
        return Ok(BlochWave {
            omega,
            cos_wavenumber,
            wavenumber: Complex::new(q, 0.0),
            multiplier: Complex::new(q.cos(), -q.sin()),
            attenuation: 0.0,
        });
    }
    // λ² − 2cλ + 1 = 0, c² − 1 = −h (2 − h) without cancellation near c = ±1; the root of
    // larger modulus first (no cancellation), its reciprocal is the decaying one.
    let root = (-h * (Complex::new(2.0, 0.0) - h)).sqrt();
    let (plus, minus) = (cos_wavenumber + root, cos_wavenumber - root);
    let growing = if plus.norm() >= minus.norm() {
        plus
    } else {
        minus
    };
    let multiplier = growing.inv();
    let mut wavenumber = Complex::new(0.0, 1.0) * multiplier.ln();
    if wavenumber.re <= -std::f64::consts::PI {
        wavenumber.re += std::f64::consts::TAU;
    }
    Ok(BlochWave {
        omega,
        cos_wavenumber,
        wavenumber,
        multiplier,
        attenuation: growing.norm().ln(),
    })
}

/// The band edges of the undamped lattice of a cell (dashpots ignored), in rad/s; see the
/// module notes for the bands they bound.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BandEdges {
    /// `ω₁`: top of the acoustic pass band, bottom of the local-resonance stop band
    /// (`cos q = −1`).
    pub acoustic_upper: f64,
    /// `ω_r = √(k_i/m_i)`: the local resonance inside the stop band (`m_eff` infinite).
    pub local_resonance: f64,
    /// `ω_a = √(k_i (m_o + m_i) / (m_o m_i))`: top of the local-resonance stop band, bottom
    /// of the optical pass band (`m_eff = 0`, `cos q = 1`).
    pub optical_lower: f64,
    /// `ω₂`: top of the optical pass band, bottom of the Bragg stop band (`cos q = −1`).
    pub optical_upper: f64,
}

/// The band edges of the undamped lattice of `cell`: `ω_r² = z_r = k_i/m_i`,
/// `ω_a² = z_r (m_o + m_i)/m_o`, and `ω₁², ω₂²` the roots of
/// `m_o z² − B z + 4k_o z_r = 0`, `B = z_r (m_o + m_i) + 4k_o`, from
/// `√(B² − 16 m_o k_o z_r) = √((z_r (m_o + m_i) − 4k_o)² + 16 k_o m_i z_r)` (no cancellation),
/// `z₂ = (B + √…)/(2m_o)`, `z₁ = 8k_o z_r / (B + √…)`.
///
/// # Errors
/// [`ModelError::OutOfRange`] naming the first bad field of `cell` as `cell.outer_mass`, ….
pub fn band_edges(cell: &Cell) -> Result<BandEdges, ModelError> {
    check_cell(cell)?;
    let (mo, mi, ko, ki) = (
        cell.outer_mass,
        cell.inner_mass,
        cell.outer_stiffness,
        cell.inner_stiffness,
    );
    let zr = ki / mi;
    let za = zr * (mo + mi) / mo;
    let b = zr * (mo + mi) + 4.0 * ko;
    let root = ((zr * (mo + mi) - 4.0 * ko).powi(2) + 16.0 * ko * mi * zr).sqrt();
    let z2 = (b + root) / (2.0 * mo);
    let z1 = 8.0 * ko * zr / (b + root);
    Ok(BandEdges {
        acoustic_upper: z1.sqrt(),
        local_resonance: zr.sqrt(),
        optical_lower: za.sqrt(),
        optical_upper: z2.sqrt(),
    })
}

/// Which mechanism opens a stop band.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum StopBandKind {
    /// `(ω₁, ω_a)`: around the inner masses' resonance `ω_r`, where `m_eff` is very large or
    /// negative.
    LocalResonance,
    /// `(ω₂, ∞)`: above the optical branch, neighbouring cells in antiphase (`Re q = π`).
    Bragg,
}

/// A stop band of the undamped lattice, clipped to the range asked for: every `ω` strictly
/// inside `(lower, upper)` has attenuation `> 0`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct StopBand {
    /// Lower end, rad/s: a band edge, or `omega_min` if the band starts below it.
    pub lower: f64,
    /// Upper end, rad/s: a band edge, or `omega_max` if the band goes on above it.
    pub upper: f64,
    /// The mechanism.
    pub kind: StopBandKind,
}

/// The stop bands of the undamped lattice of `cell` (dashpots ignored) that overlap
/// `[omega_min, omega_max]`, clipped to it, in ascending order: at most the local-resonance
/// band `(ω₁, ω_a)` and the Bragg band `(ω₂, ∞)` of [`band_edges`].
///
/// # Errors
/// [`ModelError::OutOfRange`] naming the first bad field of `cell` (`cell.outer_mass`, …),
/// `omega_min` if it is not finite and `≥ 0`, or `omega_max` if it is not finite and
/// `> omega_min`.
pub fn stop_bands(
    cell: &Cell,
    omega_min: f64,
    omega_max: f64,
) -> Result<Vec<StopBand>, ModelError> {
    let edges = band_edges(cell)?;
    check("omega_min".to_string(), omega_min, omega_min >= 0.0, ">= 0")?;
    check(
        "omega_max".to_string(),
        omega_max,
        omega_max > omega_min,
        "> omega_min",
    )?;
    let bands = [
        (
            edges.acoustic_upper,
            edges.optical_lower,
            StopBandKind::LocalResonance,
        ),
        (edges.optical_upper, f64::INFINITY, StopBandKind::Bragg),
    ];
    Ok(bands
        .into_iter()
        .filter(|&(lower, upper, _)| lower < omega_max && upper > omega_min)
        .map(|(lower, upper, kind)| StopBand {
            lower: lower.max(omega_min),
            upper: upper.min(omega_max),
            kind,
        })
        .collect())
}
