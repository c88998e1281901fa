//! Welch's estimator of the transfer function between two uniformly sampled records.
//!
//! **Segments.** The records `x` (input) and `y` (output), both sampled at the step `Δt`, are
//! cut into `K` segments of `L = 2^m` samples, each starting `D = L − round(overlap·L)`
//! samples after the previous (`overlap` 0.5: half the segment), the last whole segment ending
//! at or before the records' end. Each segment is weighted by the periodic Hann window
//! `w_n = sin²(πn/L)`, `n = 0..L`, and transformed, `X_j = Σ_n w_n x_n e^{−2πi jn/L}` (no mean
//! is removed: a record whose band excludes zero frequency leaks nothing into it through the
//! window's side lobes, which fall as `j⁻³`).
//!
//! **Spectra.** One-sided, per unit angular frequency, at `ω_j = 2πj/(LΔt)`, `j = 0..=L/2`:
//! `S_xx(ω_j) = c_j ⟨|X_j|²⟩`, `S_yy = c_j ⟨|Y_j|²⟩`, `S_xy = c_j ⟨X̄_j Y_j⟩`, `⟨·⟩` the mean
//! over the segments, `c_j = Δt/(π Σ_n w_n²)` (halved at `j = 0` and `j = L/2`, which have no
//! mirror). So `∫₀^∞ S_xx dω` is the mean square: exactly, per segment,
//! `Σ_j S_xx(ω_j) Δω = Σ_n w_n² x_n² / Σ_n w_n²` with `Δω = 2π/(LΔt)`, the window-weighted
//! mean square (Parseval).
//!
//! **Transfer function.** `H₁ = S_xy/S_xx` (its magnitude and its phase `arg H₁` in
//! `(−π, π]`, for `x = Re(X e^{iωt})`, `y = Re(H X e^{iωt})`: a delay `τ` is the phase
//! `−ωτ`), the transmissibility `√(S_yy/S_xx)`, and the coherence
//! `γ² = |S_xy|²/(S_xx S_yy)`, in `[0, 1]`.
//!
//! **Averages.** Overlapping segments of one record are not independent. For a Gaussian
//! record, two segments `k` apart give periodograms with correlation `ρ_k²`,
//! `ρ_k = Σ_n w_n w_{n+kD} / Σ_n w_n²` (the window's overlap with itself shifted by `kD`,
//! zero once `kD ≥ L`; `1/6` for Hann at 50 % to rounding, `Σ sin²cos²/Σ sin⁴` over the
//! overlapping half), so the mean of `K` of them has the variance of
//! `n = K / (1 + 2 Σ_{k=1}^{K−1} (1 − k/K) ρ_k²)` independent ones (Welch 1967):
//! the **effective number of averages** ([`Welch::effective_averages`]; `K/(1 + 2ρ₁²)` for
//! large `K` at 50 %). Records that are independent of each other (different seeds) add
//! their segment sums and their effective averages ([`SegmentSums::add`]).
//!
//! **Confidence.** For `n` complex averages, the least-squares regression of `Y` on `X` gives
//! `|Ĥ − H|² · Σ|X|² / (RSS/(n − 1)) ~ F_{2, 2(n−1)}`, `RSS = Σ|Y|² (1 − γ²)`, so
//! `|Ĥ₁ − H|² ≤ F_{2,2(n−1);α}/(n − 1) · (1 − γ²) S_yy/S_xx` with probability `1 − α`. The
//! upper tail of `F_{2,m}` is `(1 + 2f/m)^{−m/2}` in closed form, so
//! `F_{2,m;α} = (m/2)(α^{−2/m} − 1)` ([`f_quantile`]) and the **confidence radius** is
//! `r² = (α^{−1/(n−1)} − 1)(1 − γ²) S_yy/S_xx` ([`confidence_radius`]). The statement is
//! pointwise, at one frequency; one over `N` frequencies at once holds with confidence at
//! least `1 − α` when each uses `α/N` (Bonferroni). The radius covers the random error of
//! the estimate (what of `y` is not linear in `x` within a segment: noise, the response to
//! input before the segment, impacts); the window's smoothing bias, `H` averaged over the
//! window's main lobe (`±2` bins), is not in it, and is small where `H` changes little over
//! two bins.

use super::fft;
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::ops::Range;
use thiserror::Error;

/// Shortest segment, samples: the Hann window of 4 samples is the shortest with a zero,
/// a peak and a bin between zero frequency and the Nyquist frequency.
pub const MIN_SEGMENT: usize = 4;

/// A cut of the records refused: the field and what it must be.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum WelchError {
    /// The segment is not a power of two of at least [`MIN_SEGMENT`] samples.
    #[error("segment = {0} samples is out of range: must be a power of two ≥ 4")]
    Segment(usize),
    /// The overlap is not in `[0, 1)`, or leaves no step between segments.
    #[error(
        "overlap = {0} is out of range: must be in [0, 1) and leave a step of at least one sample"
    )]
    Overlap(f64),
}

/// How the records are cut: segments of `segment` samples overlapping by the fraction
/// `overlap`, each weighted by the periodic Hann window.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Welch {
    segment: usize,
    overlap: f64,
}

impl Welch {
    /// Segments of `segment = L` samples (a power of two, at least [`MIN_SEGMENT`]), each
    /// `L − round(overlap·L)` samples after the previous.
    ///
    /// # Errors
    /// [`WelchError`] naming the field.
    pub fn new(segment: usize, overlap: f64) -> Result<Welch, WelchError> {
        if !(segment.is_power_of_two() && segment >= MIN_SEGMENT) {
            return Err(WelchError::Segment(segment));
        }
        if !((0.0..1.0).contains(&overlap)) || (overlap * segment as f64).round() >= segment as f64
        {
            return Err(WelchError::Overlap(overlap));
        }
        Ok(Welch { segment, overlap })
    }

    /// `L`, samples.
    pub fn segment(&self) -> usize {
        self.segment
    }

    /// The overlap as given.
    pub fn overlap(&self) -> f64 {
        self.overlap
    }

    /// `D = L − round(overlap·L)`, samples from one segment's start to the next.
    pub fn step(&self) -> usize {
        self.segment - (self.overlap * self.segment as f64).round() as usize
    }

    /// The periodic Hann window `w_n = sin²(πn/L)`, `n = 0..L`.
    pub fn window(&self) -> Vec<f64> {
        let l = self.segment as f64;
        (0..self.segment)
            .map(|n| {
                let s = libm::sin(PI * n as f64 / l);
                s * s
            })
            .collect()
    }

    /// `K`: the whole segments in a record of `samples` samples.
    pub fn segments(&self, samples: usize) -> usize {
        if samples < self.segment {
            0
        } else {
            1 + (samples - self.segment) / self.step()
        }
    }

    /// `ρ_k = Σ_n w_n w_{n+kD} / Σ_n w_n²` for `k = 1, 2, …` while `kD < L`.
    pub fn overlap_correlations(&self) -> Vec<f64> {
        let w = self.window();
        let power: f64 = w.iter().map(|v| v * v).sum();
        let d = self.step();
        (1..)
            .map(|k| k * d)
            .take_while(|&shift| shift < self.segment)
            .map(|shift| {
                w[..self.segment - shift]
                    .iter()
                    .zip(&w[shift..])
                    .map(|(a, b)| a * b)
                    .sum::<f64>()
                    / power
            })
            .collect()
    }

    /// `n = K / (1 + 2 Σ_{k=1}^{K−1} (1 − k/K) ρ_k²)`: the independent averages `K`
    /// overlapping segments of one record are worth (`0` for `K = 0`).
    pub fn effective_averages(&self, segments: usize) -> f64 {
        if segments == 0 {
            return 0.0;
        }
        let k_total = segments as f64;
        let sum: f64 = self
            .overlap_correlations()
            .iter()
            .enumerate()
            .take(segments - 1)
            .map(|(i, rho)| (1.0 - (i + 1) as f64 / k_total) * rho * rho)
            .sum();
        k_total / (1.0 + 2.0 * sum)
    }

    /// The segment sums `Σ|X_j|²`, `Σ|Y_j|²`, `Σ X̄_j Y_j` of the records `x` and `y` at the
    /// bins `bins` (within `0..=L/2`), over every whole segment.
    ///
    /// # Panics
    /// If `x` and `y` differ in length or `bins` reaches past `L/2`.
    pub fn sums(&self, x: &[f64], y: &[f64], bins: Range<usize>) -> SegmentSums {
        assert_eq!(x.len(), y.len(), "the two records have the same length");
        assert!(bins.end <= self.segment / 2 + 1, "bins within 0..=L/2");
        let l = self.segment;
        let w = self.window();
        let count = bins.len();
        let mut sums = SegmentSums {
            segment: l,
            first_bin: bins.start,
            segments: 0,
            effective_averages: 0.0,
            xx: vec![0.0; count],
            yy: vec![0.0; count],
            xy_re: vec![0.0; count],
            xy_im: vec![0.0; count],
        };
        let segments = self.segments(x.len());
        let (mut xr, mut xi, mut yr, mut yi) =
            (vec![0.0; l], vec![0.0; l], vec![0.0; l], vec![0.0; l]);
        for k in 0..segments {
            let start = k * self.step();
            for n in 0..l {
                xr[n] = w[n] * x[start + n];
                yr[n] = w[n] * y[start + n];
            }
            xi.fill(0.0);
            yi.fill(0.0);
            fft::forward(&mut xr, &mut xi);
            fft::forward(&mut yr, &mut yi);
            for (i, j) in bins.clone().enumerate() {
                sums.xx[i] += xr[j] * xr[j] + xi[j] * xi[j];
                sums.yy[i] += yr[j] * yr[j] + yi[j] * yi[j];
                // X̄Y = (a − ib)(c + id) = (ac + bd) + i(ad − bc).
                sums.xy_re[i] += xr[j] * yr[j] + xi[j] * yi[j];
                sums.xy_im[i] += xr[j] * yi[j] - xi[j] * yr[j];
            }
        }
        sums.segments = segments;
        sums.effective_averages = self.effective_averages(segments);
        sums
    }
}

/// The raw sums over the segments of one or more independent records, at a block of bins:
/// what is added across records before the spectra are finished.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SegmentSums {
    /// `L`, samples.
    pub segment: usize,
    /// The first bin `j` of the lists.
    pub first_bin: usize,
    /// `K`, the segments summed.
    pub segments: usize,
    /// The effective number of independent averages they are worth (summed over records).
    pub effective_averages: f64,
    /// `Σ|X_j|²`.
    pub xx: Vec<f64>,
    /// `Σ|Y_j|²`.
    pub yy: Vec<f64>,
    /// `Re Σ X̄_j Y_j`.
    pub xy_re: Vec<f64>,
    /// `Im Σ X̄_j Y_j`.
    pub xy_im: Vec<f64>,
}

impl SegmentSums {
    /// Adds the sums of another, independent record of the same cut (its segments and
    /// effective averages add too).
    ///
    /// # Panics
    /// If the two are of different segments or bins.
    pub fn add(&mut self, other: &SegmentSums) {
        assert!(
            self.segment == other.segment
                && self.first_bin == other.first_bin
                && self.xx.len() == other.xx.len(),
            "sums of the same cut"
        );
        self.segments += other.segments;
        self.effective_averages += other.effective_averages;
        for (a, b) in [
            (&mut self.xx, &other.xx),
            (&mut self.yy, &other.yy),
            (&mut self.xy_re, &other.xy_re),
            (&mut self.xy_im, &other.xy_im),
        ] {
            for (s, o) in a.iter_mut().zip(b) {
                *s += o;
            }
        }
    }

    /// The one-sided spectra of records sampled at the step `dt`, s.
    pub fn spectra(&self, dt: f64) -> Spectra {
        let l = self.segment;
        let welch = Welch {
            segment: l,
            overlap: 0.0,
        };
        let power: f64 = welch.window().iter().map(|v| v * v).sum();
        let k = self.segments as f64;
        let bins = self.first_bin..self.first_bin + self.xx.len();
        let scale: Vec<f64> = bins
            .clone()
            .map(|j| {
                let edge = if j == 0 || j == l / 2 { 0.5 } else { 1.0 };
                edge * dt / (PI * power) / k
            })
            .collect();
        let times = |v: &[f64]| v.iter().zip(&scale).map(|(a, c)| a * c).collect();
        Spectra {
            omega: bins
                .map(|j| 2.0 * PI * j as f64 / (l as f64 * dt))
                .collect(),
            sxx: times(&self.xx),
            syy: times(&self.yy),
            sxy_re: times(&self.xy_re),
            sxy_im: times(&self.xy_im),
            segments: self.segments,
            effective_averages: self.effective_averages,
        }
    }
}

/// One-sided spectra per unit angular frequency (units² · s/rad) at a block of bins.
#[derive(Debug, Clone, PartialEq)]
pub struct Spectra {
    /// `ω_j = 2πj/(LΔt)`, rad/s.
    pub omega: Vec<f64>,
    /// `S_xx`.
    pub sxx: Vec<f64>,
    /// `S_yy`.
    pub syy: Vec<f64>,
    /// `Re S_xy`.
    pub sxy_re: Vec<f64>,
    /// `Im S_xy`.
    pub sxy_im: Vec<f64>,
    /// `K`, the segments averaged.
    pub segments: usize,
    /// `n`, the effective independent averages.
    pub effective_averages: f64,
}

/// The estimate at one frequency.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transfer {
    /// `ω`, rad/s.
    pub omega: f64,
    /// `H₁ = S_xy/S_xx`, real and imaginary parts.
    pub h1: [f64; 2],
    /// `|H₁|`.
    pub magnitude: f64,
    /// `arg H₁`, rad, in `(−π, π]`.
    pub phase: f64,
    /// The confidence radius `r` of `H₁` ([`confidence_radius`]).
    pub radius: f64,
    /// `√(S_yy/S_xx)`.
    pub transmissibility: f64,
    /// `γ² = |S_xy|²/(S_xx S_yy)`, in `[0, 1]`.
    pub coherence: f64,
}

impl Spectra {
    /// The transfer function at every bin, each radius at the pointwise `confidence`
    /// (`1 − α`, in `(0, 1)`).
    pub fn transfer(&self, confidence: f64) -> Vec<Transfer> {
        (0..self.omega.len())
            .map(|i| {
                let (sxx, syy) = (self.sxx[i], self.syy[i]);
                let (re, im) = (self.sxy_re[i], self.sxy_im[i]);
                let cross = re * re + im * im;
                let coherence = (cross / (sxx * syy)).clamp(0.0, 1.0);
                let h1 = [re / sxx, im / sxx];
                Transfer {
                    omega: self.omega[i],
                    h1,
                    magnitude: h1[0].hypot(h1[1]),
                    phase: h1[1].atan2(h1[0]),
                    radius: confidence_radius(
                        self.effective_averages,
                        coherence,
                        syy / sxx,
                        1.0 - confidence,
                    ),
                    transmissibility: (syy / sxx).sqrt(),
                    coherence,
                }
            })
            .collect()
    }
}

/// `F_{2,m;α} = (m/2)(α^{−2/m} − 1)`: the value the `F` distribution with `2` and `m`
/// degrees of freedom exceeds with probability `α` (its upper tail is `(1 + 2f/m)^{−m/2}`).
pub fn f_quantile(m: f64, alpha: f64) -> f64 {
    m / 2.0 * (alpha.powf(-2.0 / m) - 1.0)
}

/// The radius `r` of the confidence disc of `H₁` from `n` effective complex averages, the
/// coherence `γ²` and `S_yy/S_xx`, at confidence `1 − α`:
/// `r² = F_{2,2(n−1);α}/(n − 1) · (1 − γ²) S_yy/S_xx = (α^{−1/(n−1)} − 1)(1 − γ²) S_yy/S_xx`.
/// Infinite for `n ≤ 1` (no residual to estimate the scatter from); a coherence rounded
/// above 1 counts as 1.
pub fn confidence_radius(n: f64, coherence: f64, ratio: f64, alpha: f64) -> f64 {
    if n <= 1.0 {
        return f64::INFINITY;
    }
    ((alpha.powf(-1.0 / (n - 1.0)) - 1.0) * (1.0 - coherence).max(0.0) * ratio).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record with no structure: a fixed linear congruential sequence in `[−1, 1)`.
    fn noise(samples: usize, seed: u64) -> Vec<f64> {
        let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
        (0..samples)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                (state >> 11) as f64 / (1u64 << 52) as f64 - 1.0
            })
            .collect()
    }

    #[test]
    fn twice_the_input_is_a_gain_of_two_exactly() {
        let welch = Welch::new(64, 0.5).unwrap();
        let x = noise(1000, 3);
        let y: Vec<f64> = x.iter().map(|v| 2.0 * v).collect();
        let sums = welch.sums(&x, &y, 1..33);
        assert_eq!(sums.segments, 30);
        for t in sums.spectra(0.1).transfer(0.95) {
            assert_eq!(t.h1, [2.0, 0.0]);
            assert_eq!(t.coherence, 1.0);
            assert_eq!(t.radius, 0.0);
            assert_eq!(t.transmissibility, 2.0);
        }
    }

    #[test]
    fn a_sinusoid_on_a_bin_gives_its_power_exactly() {
        // A cos(ω_j t + φ) on bin 5 of L = 64: the Hann window spreads it over bins 4, 5, 6,
        // whose sum times the bin spacing is the mean square A²/2.
        let (l, dt, a) = (64usize, 0.05, 1.5);
        let welch = Welch::new(l, 0.5).unwrap();
        let omega = 2.0 * PI * 5.0 / (l as f64 * dt);
        let x: Vec<f64> = (0..4 * l)
            .map(|n| a * (omega * n as f64 * dt + 0.3).cos())
            .collect();
        let s = welch.sums(&x, &x, 0..l / 2 + 1).spectra(dt);
        let spacing = 2.0 * PI / (l as f64 * dt);
        let around: f64 = s.sxx[4..=6].iter().sum::<f64>() * spacing;
        assert!((around - a * a / 2.0).abs() < 1e-13 * a * a, "{around}");
        let elsewhere: f64 = s.sxx.iter().sum::<f64>() * spacing - around;
        assert!(elsewhere.abs() < 1e-25, "{elsewhere}");
        assert!((s.omega[5] - omega).abs() < 1e-14);
    }

    #[test]
    fn the_spectrum_sums_to_the_window_weighted_mean_square() {
        let (l, dt) = (128usize, 0.01);
        let welch = Welch::new(l, 0.0).unwrap();
        let x = noise(l, 11);
        let w = welch.window();
        let weighted: f64 = w.iter().zip(&x).map(|(w, x)| w * w * x * x).sum::<f64>()
            / w.iter().map(|w| w * w).sum::<f64>();
        let s = welch.sums(&x, &x, 0..l / 2 + 1).spectra(dt);
        let spacing = 2.0 * PI / (l as f64 * dt);
        let total: f64 = s.sxx.iter().sum::<f64>() * spacing;
        assert!(
            (total - weighted).abs() < 1e-14 * weighted,
            "{total} {weighted}"
        );
    }

    #[test]
    fn a_delay_of_whole_samples_is_the_phase_minus_omega_tau() {
        // Lines on bins 5, 9, 13 (three bins apart or more, so no bin sees two lines through
        // the window's main lobe); y is x delayed by d samples, exactly.
        let (l, dt, d) = (64usize, 0.02, 3usize);
        let welch = Welch::new(l, 0.5).unwrap();
        let line = |n: f64| {
            [5.0, 9.0, 13.0]
                .iter()
                .map(|&j| (2.0 * PI * j * n / l as f64 + j).cos())
                .sum::<f64>()
        };
        let x: Vec<f64> = (0..4 * l).map(|n| line(n as f64)).collect();
        let y: Vec<f64> = (0..4 * l).map(|n| line(n as f64 - d as f64)).collect();
        let transfer = welch.sums(&x, &y, 0..l / 2 + 1).spectra(dt).transfer(0.95);
        for j in [5usize, 9, 13] {
            let t = transfer[j];
            let expected = -t.omega * d as f64 * dt;
            let wrapped = (t.phase - expected + PI).rem_euclid(2.0 * PI) - PI;
            assert!(wrapped.abs() < 1e-12, "bin {j}: {} vs {expected}", t.phase);
            assert!((t.magnitude - 1.0).abs() < 1e-12);
            assert!((t.coherence - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn hann_at_half_overlap_correlates_by_one_sixth() {
        let welch = Welch::new(1024, 0.5).unwrap();
        let rho = welch.overlap_correlations();
        assert_eq!(rho.len(), 1);
        assert!((rho[0] - 1.0 / 6.0).abs() < 1e-12, "{}", rho[0]);
        // Many segments: K/(1 + 2ρ²) to O(1/K).
        let n = welch.effective_averages(1000);
        assert!((n - 1000.0 / (1.0 + 2.0 / 36.0)).abs() < 0.1, "{n}");
        assert_eq!(welch.effective_averages(1), 1.0);
        // No overlap: independent segments.
        assert_eq!(Welch::new(64, 0.0).unwrap().effective_averages(7), 7.0);
    }

    #[test]
    fn the_f_quantile_is_the_table_value_and_the_tail_integral() {
        // F_{2,10;0.05} = 4.1028 (the tables, to their four decimals).
        assert!((f_quantile(10.0, 0.05) - 4.1028).abs() < 5e-5);
        // ∫_f^∞ (1 + 2x/m)^{−(m/2 + 1)} dx = α, by Simpson's rule on x = f + u/(1 − u).
        for (m, alpha) in [(4.0, 0.1), (10.0, 0.05), (38.0, 0.01)] {
            let f = f_quantile(m, alpha);
            let density = |x: f64| (1.0 + 2.0 * x / m).powf(-(m / 2.0 + 1.0));
            let steps = 20_000;
            let h = 1.0 / steps as f64;
            let integrand = |u: f64| {
                if u >= 1.0 {
                    0.0
                } else {
                    density(f + u / (1.0 - u)) / ((1.0 - u) * (1.0 - u))
                }
            };
            let tail: f64 = (0..=steps)
                .map(|i| {
                    let weight = if i == 0 || i == steps {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    weight * integrand(i as f64 * h)
                })
                .sum::<f64>()
                * h
                / 3.0;
            assert!(
                (tail - alpha).abs() < 1e-9 * alpha.max(1.0),
                "{m} {alpha}: {tail}"
            );
        }
        // The radius is F/(n − 1) times the residual ratio.
        let (n, g, ratio, alpha) = (6.0, 0.9, 2.0, 0.05);
        let r = confidence_radius(n, g, ratio, alpha);
        let expected = f_quantile(2.0 * (n - 1.0), alpha) / (n - 1.0) * (1.0 - g) * ratio;
        assert!((r * r - expected).abs() < 1e-14);
        assert_eq!(confidence_radius(1.0, g, ratio, alpha), f64::INFINITY);
    }

    #[test]
    fn sums_of_two_records_add() {
        let welch = Welch::new(32, 0.5).unwrap();
        let (x1, x2) = (noise(200, 1), noise(150, 2));
        let mut a = welch.sums(&x1, &x1, 1..10);
        let b = welch.sums(&x2, &x2, 1..10);
        a.add(&b);
        assert_eq!(a.segments, welch.segments(200) + welch.segments(150));
        let expected = welch.effective_averages(welch.segments(200))
            + welch.effective_averages(welch.segments(150));
        assert_eq!(a.effective_averages, expected);
    }

    #[test]
    fn bad_cuts_are_refused() {
        assert_eq!(Welch::new(48, 0.5), Err(WelchError::Segment(48)));
        assert_eq!(Welch::new(2, 0.5), Err(WelchError::Segment(2)));
        assert_eq!(Welch::new(64, 1.0), Err(WelchError::Overlap(1.0)));
        assert_eq!(Welch::new(64, -0.1), Err(WelchError::Overlap(-0.1)));
        assert_eq!(Welch::new(4, 0.9), Err(WelchError::Overlap(0.9)));
    }
}
