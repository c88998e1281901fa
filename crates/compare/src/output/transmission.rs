//! `rattle transmission`: the Welch estimate of a structure's transmissibility under random
//! base motion, level by level, beside the linear structure's exact response; one document
//! (JSON) or one row per level and frequency (CSV).

use crate::output::{finite, table_row};
use serde::{Deserialize, Serialize};

/// Every number the estimate was made with, fixed before the first run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransmissionSettings {
    /// The random signal as given (`random:band=LO-HI,rms=A,seed=S[,psd=FILE]`).
    pub signal: String,
    /// `[LO, HI]`, rad/s.
    pub band: [f64; 2],
    /// The PSD file shaping the spectrum, if any.
    pub psd: Option<String>,
    /// The levels, the signal's RMS base displacement of each, m.
    pub levels: Vec<f64>,
    /// The first seed; the records of a level use `seed, seed + 1, …`.
    pub seed: u64,
    /// The records per level (seeds).
    pub seeds: u64,
    /// `T`, s: each record's duration from rest.
    pub duration: f64,
    /// `Δt = T/N`, s: the sampling step of the base and the observed body.
    pub sampling_step: f64,
    /// `N`: the sampling intervals of `[0, T]`.
    pub samples: u64,
    /// `π/Δt`, rad/s: the Nyquist frequency.
    pub nyquist: f64,
    /// `π/(Δt · HI)`: the Nyquist frequency over the band's top, at least 4.
    pub nyquist_over_band_top: f64,
    /// The time cut from each record's start, s (a whole number of samples).
    pub transient: f64,
    /// How the transient cut was chosen: `given`, or the rule and its numbers.
    pub transient_rule: String,
    /// The samples left in each record after the cut.
    pub record_samples: u64,
    /// The window: `hann` (periodic, `sin²(πn/L)`).
    pub window: String,
    /// `L`, samples per segment (a power of two).
    pub segment_samples: u64,
    /// `L·Δt`, s.
    pub segment_duration: f64,
    /// The overlap of consecutive segments, as given.
    pub overlap: f64,
    /// `D`, samples from one segment's start to the next.
    pub segment_step: u64,
    /// `ρ_k`, the window's correlation with itself shifted by `k` segment steps (`k ≥ 1`).
    pub overlap_correlations: Vec<f64>,
    /// `K`, segments per record.
    pub segments_per_record: u64,
    /// `n`, the effective independent averages of one record.
    pub effective_averages_per_record: f64,
    /// `n` per level: the records' effective averages summed.
    pub effective_averages: f64,
    /// `2π/(L·Δt)`, rad/s: the spacing of the estimated frequencies.
    pub frequency_spacing: f64,
    /// The pointwise confidence of each radius, `1 − α`.
    pub confidence: f64,
    /// The frequencies in each level's table.
    pub frequencies: u64,
    /// `1 − α·N`: the confidence that every radius of a level holds at once (Bonferroni over
    /// its `N` frequencies; `0` when that is below zero).
    pub simultaneous_confidence: f64,
    /// The spectra's scaling: one-sided, per rad/s.
    pub scaling: String,
}

/// A frequency range where the linear structure attenuates (`|H| < 1`), within the estimated
/// frequencies.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct AttenuationBand {
    /// Its lower edge, rad/s (the lowest estimated frequency when it starts below it).
    pub from: f64,
    /// Its upper edge, rad/s (`null`: still attenuating at the highest estimated frequency).
    pub to: Option<f64>,
}

/// The linear structure (its stops removed) beside the estimate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LinearSummary {
    /// The undamped natural frequencies, rad/s, ascending (rigid modes left out).
    pub natural_frequencies: Vec<f64>,
    /// The slowest decay rate of the free motion, 1/s (`0`: an undamped mode; `null`: no
    /// elastic mode).
    pub slowest_decay_rate: Option<f64>,
    /// Where `|H(ω)| < 1` over the estimated frequencies, edges refined on the exact `|H|`.
    pub attenuation_bands: Vec<AttenuationBand>,
}

table_row! {
    /// One level at one frequency: the estimate and the linear reference.
    pub struct TransmissionRow {
        /// The level: the base motion's RMS, m.
        pub level: f64,
        /// `ω`, rad/s.
        pub omega: f64,
        /// `|H₁|`, `H₁ = S_xy/S_xx` (observed body's displacement over the base's).
        pub h1_magnitude: Option<f64>,
        /// `arg H₁`, rad, in `(−π, π]`.
        pub h1_phase: Option<f64>,
        /// The radius of `H₁`'s confidence disc at the settings' pointwise confidence.
        pub h1_radius: Option<f64>,
        /// `√(S_yy/S_xx)`.
        pub transmissibility: Option<f64>,
        /// `γ² = |S_xy|²/(S_xx S_yy)`.
        pub coherence: Option<f64>,
        /// `|H(ω)|` of the linear structure, its stops removed.
        pub linear_magnitude: Option<f64>,
        /// `arg H(ω)`, rad, in `(−π, π]`.
        pub linear_phase: Option<f64>,
        /// `n`, the effective independent averages behind the estimate.
        pub averages: f64,
    }
}

impl TransmissionRow {
    /// The row of `level` at one estimated frequency, beside the linear `H = (re, im)`.
    pub fn new(
        level: f64,
        t: &crate::spectrum::welch::Transfer,
        linear: Option<(f64, f64)>,
        averages: f64,
    ) -> TransmissionRow {
        TransmissionRow {
            level,
            omega: t.omega,
            h1_magnitude: finite(t.magnitude),
            h1_phase: finite(t.phase),
            h1_radius: finite(t.radius),
            transmissibility: finite(t.transmissibility),
            coherence: finite(t.coherence),
            linear_magnitude: linear.and_then(|(re, im)| finite(re.hypot(im))),
            linear_phase: linear.and_then(|(re, im)| finite(im.atan2(re))),
            averages,
        }
    }
}

/// One level: its counts and its table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LevelTable {
    /// The base motion's RMS, m.
    pub level: f64,
    /// The records (seeds) averaged.
    pub records: u64,
    /// Impacts over all its records.
    pub impacts: u64,
    /// `K`, segments over all its records.
    pub segments: u64,
    /// `n`, the effective independent averages.
    pub effective_averages: f64,
    /// The estimate at every frequency, ascending.
    pub rows: Vec<TransmissionRow>,
}

/// `rattle transmission --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TransmissionRecord {
    /// Scene name.
    pub scene: String,
    /// The observed body, whose displacement is the output.
    pub observe: String,
    /// How the estimate was made.
    pub settings: TransmissionSettings,
    /// The linear structure.
    pub linear: LinearSummary,
    /// One table per level, in the order given.
    pub levels: Vec<LevelTable>,
}

impl TransmissionRecord {
    /// Every level's rows, level by level: the CSV table.
    pub fn rows(&self) -> impl Iterator<Item = TransmissionRow> + '_ {
        self.levels.iter().flat_map(|l| l.rows.iter().cloned())
    }
}
