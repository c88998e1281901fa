//! Random base motion: a random-phase multisine (the spectral representation of a stationary
//! Gaussian process), the same bits for the same seed on every machine.
//!
//! **Construction.** Over a run of duration `T` the lines are `ω_k = k·2π/T` for every whole
//! `k ≥ 1` with `LO ≤ ω_k ≤ HI`, so the spectrum is confined to the band exactly. Each line has
//! the amplitude `a_k ∝ √S(ω_k)` (`S = 1` for a flat band, else the PSD file's `omega,psd`
//! interpolated linearly, zero outside its range) scaled so that `Σ a_k²/2 = rms²`, and a
//! phase `φ_k` uniform on the circle:
//! `u_g(t) = Σ_k a_k cos(ω_k t + φ_k)`. The lines are orthogonal over `[0, T]`, so the mean
//! square over the run is `rms²` exactly; over a shorter window `W` it fluctuates about it as a
//! Gaussian process's does, by about `√(2π/(B W))` relative for a flat band of width
//! `B = HI − LO` rad/s; the values are close to Gaussian when there are many lines
//! (central limit).
//!
//! **Randomness.** `seed` starts SplitMix64, which seeds xoshiro256**; each line draws points
//! uniform in the square `[−1, 1)²` until one falls inside the unit disc (and not within
//! `10⁻⁶` of its centre), and `(cos φ_k, sin φ_k)` is that point over its length. Only
//! integer arithmetic, `+ − × ÷` and `√` (correctly rounded by IEEE 754) are used, and no
//! thread: the phases are the same bits everywhere.
//!
//! **What is solved.** With at most [`MAX_SINUSOIDS`] lines the multisine is one segment of
//! sinusoids, solved exactly. With more, it is sampled at `N = 2^m` uniform times `t_j = jT/N`
//! by an inverse FFT ([`crate::spectrum::fft::inverse`]: radix 2, its twiddles
//! `e^{2πim/N}` from the `libm` crate's `sincos`, the same bits everywhere) and the record interpolated linearly, which errs by at most
//! `(h²/8) max|ü_g| ≤ (h²/8) Σ a_k ω_k²` (`h = T/N`): `N` is the smallest power of two that
//! makes this at most `10⁻³ × rms` (`interpolation_bound` in the description).

use super::{sinusoid, BuiltSignal, Input, Params, SignalDescription, SignalSpecError};
use super::{MAX_SEGMENTS, SIGNAL_ACCURACY};
use rattle_event_driven::{Segment, Shape, Signal, Sinusoid, MAX_SINUSOIDS};
use serde::Serialize;
use std::f64::consts::TAU;
use std::path::PathBuf;

/// A random signal as written.
#[derive(Debug, Clone, PartialEq)]
pub struct RandomSpec {
    /// `[LO, HI]`, rad/s.
    pub band: [f64; 2],
    /// The RMS, m.
    pub rms: f64,
    /// The generator's seed.
    pub seed: u64,
    /// A PSD file (`omega,psd`) shaping the spectrum; `None`: flat.
    pub psd: Option<PathBuf>,
}

/// A random signal as solved.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RandomDescription {
    /// `[LO, HI]`, rad/s.
    pub band: [f64; 2],
    /// The RMS, m.
    pub rms: f64,
    /// The seed.
    pub seed: u64,
    /// The PSD file, if any.
    pub psd: Option<String>,
    /// `2π/T`, rad/s.
    pub line_spacing: f64,
    /// The lines in the band.
    pub lines: usize,
    /// The lowest and highest line, rad/s.
    pub line_range: [f64; 2],
    /// `sinusoids` (solved exactly) or `record` (sampled and interpolated linearly).
    pub solved_as: &'static str,
    /// The record's samples, `N + 1` (`0` for sinusoids).
    pub samples: usize,
    /// The record's step `h = T/N`, s (`0` for sinusoids).
    pub step: f64,
    /// `(h²/8) Σ a_k ω_k²`: the largest difference between the record and the multisine, m.
    pub interpolation_bound: f64,
}

impl RandomSpec {
    /// Reads the parameters.
    pub(super) fn parse(p: &mut Params<'_>) -> Result<RandomSpec, SignalSpecError> {
        let kind = p.kind;
        let band_text = p.required("band")?;
        let rms = p.required_number("rms")?;
        let seed_text = p.required("seed")?;
        let psd = p.take("psd").map(PathBuf::from);
        // `LO-HI`, split at the `-` that leaves two numbers (an exponent may hold one).
        let band = band_text
            .match_indices('-')
            .filter_map(|(i, _)| {
                let lo = band_text[..i].trim().parse::<f64>().ok()?;
                let hi = band_text[i + 1..].trim().parse::<f64>().ok()?;
                Some([lo, hi])
            })
            .next()
            .filter(|[lo, hi]| lo.is_finite() && hi.is_finite())
            .ok_or_else(|| {
                SignalSpecError::range(kind, "band", band_text, "LO-HI, two finite numbers (rad/s)")
            })?;
        if !(band[0] >= 0.0 && band[1] > band[0]) {
            return Err(SignalSpecError::range(
                kind,
                "band",
                band_text,
                "0 ≤ LO < HI (a band that is not empty, rad/s)",
            ));
        }
        if rms <= 0.0 {
            return Err(SignalSpecError::range(kind, "rms", rms, "> 0"));
        }
        let seed = seed_text.parse::<u64>().map_err(|_| {
            SignalSpecError::range(kind, "seed", seed_text, "a whole number in [0, 2^64)")
        })?;
        Ok(RandomSpec {
            band,
            rms,
            seed,
            psd,
        })
    }

    /// The multisine's lines over a run of `duration`: `a_k cos(ω_k t + φ_k)` as the engine's
    /// sinusoids `(ω_k, a_k cos φ_k, −a_k sin φ_k)`, by increasing frequency.
    ///
    /// # Errors
    /// [`SignalSpecError`] naming `band` (no line `k·2π/T` in it) or the PSD file's field
    /// (unreadable, bad columns, zero over the band).
    pub fn lines(&self, duration: f64) -> Result<Vec<Sinusoid>, SignalSpecError> {
        let spacing = TAU / duration;
        let [lo, hi] = self.band;
        let first = ((lo / spacing).ceil() as u64).max(1);
        let last = (hi / spacing).floor() as u64;
        if last < first {
            return Err(SignalSpecError::range(
                "random",
                "band",
                format!("{lo}-{hi}"),
                &format!(
                    "wide enough to hold a line k·2π/T (spacing {spacing} rad/s): widen the band \
                     or lengthen --duration"
                ),
            ));
        }
        if (last - first + 1) as usize > MAX_SEGMENTS {
            return Err(SignalSpecError::range(
                "random",
                "band",
                format!("{lo}-{hi}"),
                "narrow enough to hold at most 4194304 lines k·2π/T: narrow it or shorten --duration",
            ));
        }
        let frequencies: Vec<f64> = (first..=last).map(|k| k as f64 * TAU / duration).collect();
        let shape: Vec<f64> = match &self.psd {
            None => vec![1.0; frequencies.len()],
            Some(path) => psd_shape(path, &frequencies)?,
        };
        let square: f64 = shape.iter().sum::<f64>() / 2.0;
        if square <= 0.0 {
            let path = self.psd.as_deref().map(super::shown).unwrap_or_default();
            return Err(SignalSpecError::new(
                &path,
                "psd",
                "is zero at every line of the band: it must be positive somewhere in it",
            ));
        }
        let scale = self.rms / square.sqrt();
        let mut generator = Xoshiro::new(self.seed);
        Ok(frequencies
            .iter()
            .zip(&shape)
            .map(|(&w, &s)| {
                let (c, sn) = generator.unit_circle();
                let a = scale * s.sqrt();
                sinusoid(w, a * c, -a * sn)
            })
            .collect())
    }

    /// The signal over `[0, duration]`.
    pub(super) fn build(&self, duration: f64) -> Result<BuiltSignal, SignalSpecError> {
        let lines = self.lines(duration)?;
        let amplitude = |s: &Sinusoid| s.cos.hypot(s.sin);
        let mut description = RandomDescription {
            band: self.band,
            rms: self.rms,
            seed: self.seed,
            psd: self.psd.as_deref().map(super::shown),
            line_spacing: TAU / duration,
            lines: lines.len(),
            line_range: [lines[0].frequency, lines[lines.len() - 1].frequency],
            solved_as: "sinusoids",
            samples: 0,
            step: 0.0,
            interpolation_bound: 0.0,
        };
        if lines.len() <= MAX_SINUSOIDS {
            let signal = Signal::from_segments(vec![Segment {
                start: 0.0,
                end: f64::INFINITY,
                shape: Shape::Sinusoids(lines),
            }])
            .map_err(|e| SignalSpecError::new("random", "band", e.to_string()))?;
            return Ok(BuiltSignal {
                signal,
                input: Input::Base,
                description: SignalDescription::Random(description),
            });
        }
        let curvature: f64 = lines
            .iter()
            .map(|s| amplitude(s) * s.frequency * s.frequency)
            .sum();
        let longest = (8.0 * SIGNAL_ACCURACY * self.rms / curvature).sqrt();
        let last_k = (lines[lines.len() - 1].frequency * duration / TAU).round();
        let needed = (duration / longest).ceil().max(4.0 * (last_k + 1.0));
        if needed > MAX_SEGMENTS as f64 {
            return Err(SignalSpecError::range(
                "random",
                "band",
                format!("{}-{}", self.band[0], self.band[1]),
                &format!(
                    "narrow enough that the record needs at most 4194304 samples (it needs \
                     {needed:.0}): narrow the band or shorten --duration"
                ),
            ));
        }
        let n = (needed as usize).next_power_of_two();
        let values = record(&lines, duration, n);
        let samples: Vec<(f64, f64)> = values
            .iter()
            .enumerate()
            .map(|(j, &v)| {
                let t = if j == n {
                    duration
                } else {
                    duration * j as f64 / n as f64
                };
                (t, v)
            })
            .collect();
        let signal = Signal::from_samples(&samples)
            .map_err(|e| SignalSpecError::new("random", "band", e.to_string()))?;
        let h = duration / n as f64;
        description.solved_as = "record";
        description.samples = n + 1;
        description.step = h;
        description.interpolation_bound = h * h / 8.0 * curvature;
        Ok(BuiltSignal {
            signal,
            input: Input::Base,
            description: SignalDescription::Random(description),
        })
    }
}

/// The multisine `lines` (frequencies `k·2π/T`) at `t_j = jT/n`, `j = 0..=n` (`n` a power of
/// two above twice the highest `k`), by an inverse FFT; the last equals the first (period `T`).
pub fn record(lines: &[Sinusoid], duration: f64, n: usize) -> Vec<f64> {
    let mut re = vec![0.0; n];
    let mut im = vec![0.0; n];
    for s in lines {
        let k = (s.frequency * duration / TAU).round() as usize;
        // a cos(ωt + φ) = Re(a e^{iφ} e^{iωt}): a cos φ = s.cos, a sin φ = −s.sin.
        re[k] = s.cos;
        im[k] = -s.sin;
    }
    crate::spectrum::fft::inverse(&mut re, &mut im);
    re.push(re[0]);
    re
}

/// The PSD file's shape `S(ω_k)` at `frequencies`: linear between its rows, zero outside.
fn psd_shape(path: &std::path::Path, frequencies: &[f64]) -> Result<Vec<f64>, SignalSpecError> {
    let columns = super::file::read_columns(path, "omega", &["psd"], false)?;
    let rows = columns.rows;
    if let Some((i, &(_, p))) = rows.iter().enumerate().find(|(_, r)| r.1 < 0.0) {
        return Err(SignalSpecError::new(
            &super::shown(path),
            "psd",
            format!("on row {} = {p} is out of range: must be ≥ 0", i + 1),
        ));
    }
    Ok(frequencies
        .iter()
        .map(|&w| {
            let i = rows.partition_point(|r| r.0 <= w);
            if i == 0 || (i == rows.len() && w > rows[rows.len() - 1].0) {
                return 0.0;
            }
            if i == rows.len() {
                return rows[i - 1].1;
            }
            let ((x0, y0), (x1, y1)) = (rows[i - 1], rows[i]);
            y0 + (y1 - y0) * (w - x0) / (x1 - x0)
        })
        .collect())
}

/// xoshiro256** seeded by SplitMix64 (Blackman and Vigna): integer arithmetic only.
pub struct Xoshiro {
    state: [u64; 4],
}

impl Xoshiro {
    /// The generator of `seed`.
    pub fn new(seed: u64) -> Xoshiro {
        let mut x = seed;
        let mut next = || {
            x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = x;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        };
        Xoshiro {
            state: [next(), next(), next(), next()],
        }
    }

    /// The next 64 bits.
    pub fn next_u64(&mut self) -> u64 {
        let s = &mut self.state;
        let result = s[1].wrapping_mul(5).rotate_left(7).wrapping_mul(9);
        let t = s[1] << 17;
        s[2] ^= s[0];
        s[3] ^= s[1];
        s[1] ^= s[2];
        s[0] ^= s[3];
        s[2] ^= t;
        s[3] = s[3].rotate_left(45);
        result
    }

    /// Uniform in `[−1, 1)`, on a grid of `2⁻⁵²`.
    fn symmetric(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (2.0 / (1u64 << 53) as f64) - 1.0
    }

    /// `(cos φ, sin φ)` with `φ` uniform on the circle, by rejection from the square.
    pub fn unit_circle(&mut self) -> (f64, f64) {
        loop {
            let (x, y) = (self.symmetric(), self.symmetric());
            let r2 = x * x + y * y;
            if (1e-12..=1.0).contains(&r2) {
                let r = r2.sqrt();
                return (x / r, y / r);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_generator_is_the_reference_sequence() {
        // SplitMix64 from 0 gives 0xE220A8397B1DCDAF first (Vigna's reference).
        let mut g = Xoshiro::new(0);
        let first = g.state[0];
        assert_eq!(first, 0xE220_A839_7B1D_CDAF);
        let (c, s) = g.unit_circle();
        assert!((c * c + s * s - 1.0).abs() < 1e-15);
    }
}
