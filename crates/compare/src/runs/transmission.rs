//! The runs of `rattle transmission`: the plan (sampling, transient cut, segments, the
//! frequencies estimated), every `(level, seed)` record from rest in parallel, its Welch
//! segment sums, and the levels finished from the sums added in seed order.
//!
//! **Sampling.** The base `u_g` and the observed body's displacement are sampled at
//! `t_j = jT/N`, `N = ⌈T · 4·HI/π⌉`: the Nyquist frequency `π/Δt` is at least
//! [`NYQUIST_MULTIPLE`] times the band's top `HI`, so the linear response (confined to the
//! band) is sampled without aliasing, and so are the first harmonics of what the impacts add.
//!
//! **Transient.** The first `T₀` of each record is dropped: `--transient`, or by default
//! [`TRANSIENT_TIME_CONSTANTS`] time constants `1/σ` of the least-damped mode of the linear
//! structure (`σ` its slowest decay rate), at most [`MAX_TRANSIENT_FRACTION`] of `T` (all of
//! that fraction when a mode is undamped); rounded up to a whole sample.
//!
//! **Segments.** `--segment` rounded to the nearest `2^m` samples; by default the longest
//! `2^m` samples that cut a record into at least [`DEFAULT_SEGMENTS`] segments. The
//! frequencies estimated are the bins `ω_j = 2πj/(LΔt)`, `j ≥ 1`, at least
//! [`MAIN_LOBE_BINS`] bins inside `[LO, HI]`: `LO + 2Δω ≤ ω_j ≤ HI − 2Δω`.
//!
//! **Order.** Runs are `(level, seed)` pairs, level by level in the order given and seeds
//! ascending within a level; they are computed in parallel, and each level's segment sums are
//! added in that order, so the result does not depend on the number of threads. A shard
//! (`--shard K/N`) computes a contiguous block of the runs and keeps their sums
//! ([`TransmissionPart`]); [`merge_parts`] adds every part's sums in the same order, giving
//! the same bits as the whole run.

use crate::output::transmission::{
    AttenuationBand, LevelTable, LinearSummary, TransmissionRecord, TransmissionRow,
    TransmissionSettings,
};
use crate::runs::bands::bands;
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::runs::shard::{check_cover, Shard};
use crate::spectrum::welch::{SegmentSums, Welch};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// The Nyquist frequency is at least this multiple of the band's top: four samples per
/// period of the fastest line keeps the estimate's frequencies clear of aliasing by the
/// response's first harmonics (an impact's second and third harmonics of the band's top).
pub const NYQUIST_MULTIPLE: f64 = 4.0;

/// The default transient cut, in time constants of the least-damped mode: the free motion
/// from rest has decayed to `e^{−10} ≈ 4.5·10⁻⁵` of its start by then.
pub const TRANSIENT_TIME_CONSTANTS: f64 = 10.0;

/// The default transient cut is at most this fraction of `T`, so that half of each record is
/// left to estimate from however lightly damped the structure.
pub const MAX_TRANSIENT_FRACTION: f64 = 0.5;

/// The default segment cuts a record into at least this many segments: with 50 % overlap
/// about 7.6 effective averages per record, enough for a confidence radius that is not
/// dominated by the `F` quantile's tail (`α^{−1/(n−1)} − 1` is 0.6 at `n = 7.6`, 95 %).
pub const DEFAULT_SEGMENTS: usize = 8;

/// The Hann window's main lobe reaches this many bins either side of its centre: an
/// estimated frequency keeps that far inside the band, so that its lobe sees input on both
/// sides (nearer the band's edges `H₁` would average `H` over one side of the lobe only, a
/// bias of first order in the bin spacing).
pub const MAIN_LOBE_BINS: usize = 2;

/// At most this many records (seeds) per level: each is a run from rest.
pub const MAX_SEEDS: u64 = 100_000;

/// What the user asks, besides the signal and `T`.
#[derive(Debug, Clone, PartialEq)]
pub struct TransmissionOptions {
    /// `--levels`: the base motion's RMS of each level, m (empty: the signal's own).
    pub levels: Vec<f64>,
    /// `--seeds`: records per level, seeds `S, S + 1, …`, in `1..=`[`MAX_SEEDS`].
    pub seeds: u64,
    /// `--segment`, s (rounded to `2^m` samples); `None`: [`DEFAULT_SEGMENTS`] per record.
    pub segment: Option<f64>,
    /// `--overlap`, in `[0, 1)`.
    pub overlap: f64,
    /// `--confidence`, in `(0, 1)`.
    pub confidence: f64,
    /// `--transient`, s, in `[0, T)`; `None`: the default rule.
    pub transient: Option<f64>,
}

impl Default for TransmissionOptions {
    /// The signal's level, one seed, the default segment and transient, 50 % overlap, 95 %.
    fn default() -> Self {
        TransmissionOptions {
            levels: Vec::new(),
            seeds: 1,
            segment: None,
            overlap: 0.5,
            confidence: 0.95,
            transient: None,
        }
    }
}

/// The signal and the structure the plan is made for.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanInput<'a> {
    /// The signal as given.
    pub signal: &'a str,
    /// `[LO, HI]`, rad/s.
    pub band: [f64; 2],
    /// Its RMS, m (the default level).
    pub rms: f64,
    /// Its seed, the first of each level.
    pub seed: u64,
    /// Its PSD file, if any.
    pub psd: Option<String>,
    /// `T`, s.
    pub duration: f64,
    /// The linear structure's slowest decay rate ([`LinearSummary::slowest_decay_rate`]).
    pub slowest_decay_rate: Option<f64>,
    /// At most this many samples in one record ([`rattle_event_driven::MAX_RESPONSE_SAMPLES`]).
    pub max_samples: u64,
}

/// The plan of a transmission estimate: the settings and the cut.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The settings, as the document states them.
    pub settings: TransmissionSettings,
    /// The cut of each record.
    pub welch: Welch,
    /// The bins estimated, `j` from `bins.start`.
    pub bins: std::ops::Range<usize>,
}

/// `Err` of a message naming `option`: `OPTION = VALUE is out of range: must be ALLOWED`.
fn range<T>(option: &str, value: impl std::fmt::Display, allowed: &str) -> Result<T, String> {
    Err(format!(
        "{option} = {value} is out of range: must be {allowed}"
    ))
}

/// The transient cut, s, and how it was chosen: `transient` (in `[0, T)`), or by default
/// [`TRANSIENT_TIME_CONSTANTS`] time constants of the least-damped mode, at most
/// [`MAX_TRANSIENT_FRACTION`] of `T`.
fn transient_cut(input: &PlanInput, transient: Option<f64>) -> Result<(f64, String), String> {
    let duration = input.duration;
    Ok(match transient {
        Some(t) => {
            if !(t.is_finite() && t >= 0.0 && t < duration) {
                return range("--transient", t, &format!("in [0, T = {duration}) (s)"));
            }
            (t, "given".to_owned())
        }
        None => {
            let cap = MAX_TRANSIENT_FRACTION * duration;
            match input.slowest_decay_rate {
                Some(sigma) if sigma > 0.0 && TRANSIENT_TIME_CONSTANTS / sigma < cap => (
                    TRANSIENT_TIME_CONSTANTS / sigma,
                    format!("10 time constants 1/σ of the least-damped mode (σ = {sigma:.6} 1/s)"),
                ),
                Some(sigma) => (
                    cap,
                    format!(
                        "half of T: 10 time constants of the least-damped mode (σ = {sigma:.6} \
                         1/s) would be longer"
                    ),
                ),
                None => (
                    cap,
                    "half of T: the structure has no elastic mode".to_owned(),
                ),
            }
        }
    })
}

/// `L`: `--segment` (s) rounded to the nearest `2^m` samples of `dt`, within `[4, record]`;
/// by default the longest `2^m` that cuts the `record` samples into at least
/// [`DEFAULT_SEGMENTS`] segments.
fn segment_samples(
    options: &TransmissionOptions,
    duration: f64,
    dt: f64,
    record: usize,
) -> Result<usize, String> {
    Ok(match options.segment {
        Some(s) => {
            if !(s.is_finite() && s > 0.0) {
                return range("--segment", s, "finite and > 0 (s)");
            }
            let exponent = (s / dt).log2().round().clamp(0.0, 62.0);
            let l = 1usize << exponent as u32;
            if l < 4 || l > record {
                return range(
                    "--segment",
                    s,
                    &format!(
                        "between 4 samples ({} s) and the record after the transient cut ({} \
                         samples, {} s), rounded to 2^m samples of Δt = {dt} s",
                        4.0 * dt,
                        record,
                        record as f64 * dt
                    ),
                );
            }
            l
        }
        None => {
            let mut l = 1usize << (usize::BITS - 1 - record.leading_zeros());
            let step = |l: usize| (l - (options.overlap * l as f64).round() as usize).max(1);
            while l >= 4 && 1 + (record - l) / step(l) < DEFAULT_SEGMENTS {
                l /= 2;
            }
            if l < 4 {
                return range(
                    "--duration",
                    duration,
                    "long enough that the record after the transient cut holds 8 segments of at \
                     least 4 samples",
                );
            }
            l
        }
    })
}

/// The plan of `options` on `input`.
///
/// # Errors
/// A message naming the option and its allowed range: `--levels` (each finite, `> 0`),
/// `--seeds` (`1..=100000`, the last seed within `2^64`), `--overlap`, `--confidence`,
/// `--transient` (in `[0, T)`, leaving a segment), `--segment` (at least 4 samples, at most
/// the record, resolving a frequency of the band, worth more than one average), `--duration`
/// (at most the engine's samples).
pub fn plan(input: &PlanInput, options: &TransmissionOptions) -> Result<Plan, String> {
    let duration = input.duration;
    let [lo, hi] = input.band;
    let levels = if options.levels.is_empty() {
        vec![input.rms]
    } else {
        options.levels.clone()
    };
    for (i, &level) in levels.iter().enumerate() {
        if !(level.is_finite() && level > 0.0) {
            return range(&format!("--levels[{i}]"), level, "finite and > 0 (m)");
        }
    }
    if !(1..=MAX_SEEDS).contains(&options.seeds)
        || input.seed.checked_add(options.seeds - 1).is_none()
    {
        return range(
            "--seeds",
            options.seeds,
            "in [1, 100000], the last seed S + N − 1 below 2^64",
        );
    }
    if !(options.confidence > 0.0 && options.confidence < 1.0) {
        return range("--confidence", options.confidence, "in (0, 1)");
    }
    let intervals = (duration * NYQUIST_MULTIPLE * hi / PI).ceil();
    if !(intervals >= 1.0 && intervals <= input.max_samples as f64) {
        return range(
            "--duration",
            duration,
            &format!(
                "short enough that sampling at 4 × the band's top ({} samples) stays within {} \
                 samples",
                intervals, input.max_samples
            ),
        );
    }
    let samples = intervals as u64;
    let dt = duration / samples as f64;
    if !(0.0..1.0).contains(&options.overlap) {
        return range("--overlap", options.overlap, "in [0, 1)");
    }
    let (cut, rule) = transient_cut(input, options.transient)?;
    let first = ((cut / dt).ceil() as u64).min(samples);
    let record = (samples - first + 1) as usize;
    let segment = segment_samples(options, duration, dt, record)?;
    let welch = Welch::new(segment, options.overlap).map_err(|e| match e {
        crate::spectrum::welch::WelchError::Overlap(v) => format!(
            "--overlap = {v} is out of range: must be in [0, 1) and leave a step of at least one \
             sample"
        ),
        e => format!("--segment: {e}"),
    })?;
    let spacing = 2.0 * PI / (segment as f64 * dt);
    let low = ((lo / spacing).ceil() as usize + MAIN_LOBE_BINS).max(1);
    let high = ((hi / spacing).floor() as usize)
        .saturating_sub(MAIN_LOBE_BINS)
        .min(segment / 2);
    if high < low {
        return range(
            "--segment",
            segment as f64 * dt,
            &format!(
                "long enough that a frequency 2πj/segment lies two spacings inside the band \
                 {lo}–{hi} rad/s (spacing {spacing} rad/s)"
            ),
        );
    }
    let per_record = welch.segments(record);
    let averages = welch.effective_averages(per_record);
    let total = averages * options.seeds as f64;
    if total <= 1.0 {
        return range(
            "--segment",
            segment as f64 * dt,
            &format!(
                "short enough for more than one effective average per level (it gives {total}): \
                 shorten --segment, lengthen --duration or add --seeds"
            ),
        );
    }
    let frequencies = (high - low + 1) as u64;
    let alpha = 1.0 - options.confidence;
    let settings = TransmissionSettings {
        signal: input.signal.to_owned(),
        band: input.band,
        psd: input.psd.clone(),
        levels,
        seed: input.seed,
        seeds: options.seeds,
        duration,
        sampling_step: dt,
        samples,
        nyquist: PI / dt,
        nyquist_over_band_top: PI / dt / hi,
        transient: first as f64 * dt,
        transient_rule: rule,
        record_samples: record as u64,
        window: "hann".to_owned(),
        segment_samples: segment as u64,
        segment_duration: segment as f64 * dt,
        overlap: options.overlap,
        segment_step: welch.step() as u64,
        overlap_correlations: welch.overlap_correlations(),
        segments_per_record: per_record as u64,
        effective_averages_per_record: averages,
        effective_averages: total,
        frequency_spacing: spacing,
        confidence: options.confidence,
        frequencies,
        simultaneous_confidence: (1.0 - alpha * frequencies as f64).max(0.0),
        scaling: "one-sided, per rad/s".to_owned(),
    };
    Ok(Plan {
        settings,
        welch,
        bins: low..high + 1,
    })
}

impl Plan {
    /// Every run, level by level in the order given, seeds ascending within a level.
    pub fn runs(&self) -> Vec<RunKey> {
        runs_of(&self.settings)
    }

    /// The estimated frequencies, rad/s.
    pub fn frequencies(&self) -> Vec<f64> {
        let spacing = self.settings.frequency_spacing;
        self.bins.clone().map(|j| j as f64 * spacing).collect()
    }

    /// The first sample kept, `j₀`.
    pub fn first_sample(&self) -> u64 {
        self.settings.samples + 1 - self.settings.record_samples
    }
}

/// Every run of `settings`, level by level in the order given, seeds ascending within a
/// level.
fn runs_of(s: &TransmissionSettings) -> Vec<RunKey> {
    s.levels
        .iter()
        .enumerate()
        .flat_map(|(level, &rms)| {
            (0..s.seeds).map(move |k| RunKey {
                level,
                rms,
                seed: s.seed + k,
            })
        })
        .collect()
}

/// One run: a level and a seed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RunKey {
    /// The level's index in the settings' `levels`.
    pub level: usize,
    /// The level, m.
    pub rms: f64,
    /// The seed.
    pub seed: u64,
}

/// What one run gives: the two sampled records after the cut and the impacts.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecords {
    /// `u_g` at the kept samples.
    pub base: Vec<f64>,
    /// The observed body's displacement at the kept samples.
    pub body: Vec<f64>,
    /// Impacts over the whole run.
    pub impacts: u64,
}

/// One run's segment sums.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunSums {
    /// The run.
    pub run: RunKey,
    /// Impacts over the whole run.
    pub impacts: u64,
    /// The sums at the plan's bins.
    pub sums: SegmentSums,
}

/// The runs `runs` of `plan`, `work` computing each one's records, in parallel (one run per
/// task), their sums in the order of `runs`; `progress` steps once per run.
///
/// # Errors
/// The first error of `work` in the order of `runs`.
pub fn run_all<E: Send>(
    plan: &Plan,
    runs: &[RunKey],
    progress: &Progress,
    work: impl Fn(&RunKey) -> Result<RunRecords, E> + Sync + Send,
) -> Result<Vec<RunSums>, E> {
    parallel_map(runs, Grain::Uneven, progress, |key| {
        let records = work(key)?;
        Ok(RunSums {
            run: *key,
            impacts: records.impacts,
            sums: plan
                .welch
                .sums(&records.base, &records.body, plan.bins.clone()),
        })
    })
    .into_iter()
    .collect()
}

/// The document of `runs` (every run of the plan, in its order), the linear structure's
/// `linear` summary and its response `reference` at each estimated frequency beside them.
pub fn finish(
    (scene, observe): (&str, &str),
    settings: &TransmissionSettings,
    linear: &LinearSummary,
    reference: &[Option<(f64, f64)>],
    runs: &[RunSums],
) -> TransmissionRecord {
    let dt = settings.sampling_step;
    let levels = settings
        .levels
        .iter()
        .enumerate()
        .map(|(index, &level)| {
            let mut level_runs = runs.iter().filter(|r| r.run.level == index);
            let first = level_runs.next().expect("every level has a run");
            let (mut sums, mut impacts, mut records) = (first.sums.clone(), first.impacts, 1);
            for r in level_runs {
                sums.add(&r.sums);
                impacts += r.impacts;
                records += 1;
            }
            let spectra = sums.spectra(dt);
            let rows = spectra
                .transfer(settings.confidence)
                .iter()
                .zip(reference)
                .map(|(t, &h)| TransmissionRow::new(level, t, h, sums.effective_averages))
                .collect();
            LevelTable {
                level,
                records,
                impacts,
                segments: sums.segments as u64,
                effective_averages: sums.effective_averages,
                rows,
            }
        })
        .collect();
    TransmissionRecord {
        scene: scene.to_owned(),
        observe: observe.to_owned(),
        settings: settings.clone(),
        linear: linear.clone(),
        levels,
    }
}

/// The linear summary: the natural frequencies, the slowest decay rate, and the attenuation
/// bands of `|H|` over `frequencies`, edges refined on `magnitude` (`|H(ω)|`).
pub fn linear_summary(
    natural_frequencies: Vec<f64>,
    slowest_decay_rate: Option<f64>,
    frequencies: &[f64],
    magnitude: &dyn Fn(f64) -> f64,
) -> LinearSummary {
    let decibels = |w: f64| 20.0 * magnitude(w).log10();
    let values: Vec<Option<f64>> = frequencies
        .iter()
        .map(|&w| Some(decibels(w)).filter(|d| d.is_finite()))
        .collect();
    let attenuation_bands = bands(frequencies, &values, Some(&decibels))
        .into_iter()
        .map(|(from, to)| AttenuationBand {
            from,
            to: to.is_finite().then_some(to),
        })
        .collect();
    LinearSummary {
        natural_frequencies,
        slowest_decay_rate,
        attenuation_bands,
    }
}

/// One part of a sharded transmission estimate: a block of the runs' segment sums, with what
/// is needed to finish the whole from every part.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TransmissionPart {
    /// `transmission-part`: what the file is.
    pub kind: String,
    /// Which part.
    pub shard: Shard,
    /// The runs of the whole estimate.
    pub total_runs: usize,
    /// Scene name.
    pub scene: String,
    /// The observed body.
    pub observe: String,
    /// The settings of the whole estimate.
    pub settings: TransmissionSettings,
    /// The linear structure.
    pub linear: LinearSummary,
    /// The linear response `H = (re, im)` at each estimated frequency.
    pub reference: Vec<Option<(f64, f64)>>,
    /// This part's runs' sums, in the whole's order.
    pub runs: Vec<RunSums>,
}

/// The `kind` of a [`TransmissionPart`].
pub const PART_KIND: &str = "transmission-part";

/// Whether `text` is a [`TransmissionPart`]'s JSON (by its `kind`).
pub fn is_part(text: &str) -> bool {
    text.trim_start().starts_with('{') && text.contains(&format!("\"kind\":\"{PART_KIND}\""))
}

/// The whole estimate from every part (in any order): each of `1..=N` once, the same
/// scene, settings and reference, every run once in the whole's order.
///
/// # Errors
/// A message when a part is missing, repeated or from another estimate, or the runs do not
/// add up.
pub fn merge_parts(parts: &[TransmissionPart]) -> Result<TransmissionRecord, String> {
    let first = parts.first().ok_or("no parts to merge")?;
    check_cover(&parts.iter().map(|p| p.shard).collect::<Vec<_>>())?;
    for p in parts {
        if (
            &p.scene,
            &p.observe,
            &p.settings,
            &p.linear,
            &p.reference,
            p.total_runs,
        ) != (
            &first.scene,
            &first.observe,
            &first.settings,
            &first.linear,
            &first.reference,
            first.total_runs,
        ) {
            return Err(format!(
                "part {}/{} comes from a different estimate (scene, settings or reference differ)",
                p.shard.index, p.shard.count
            ));
        }
    }
    let mut ordered: Vec<&TransmissionPart> = parts.iter().collect();
    ordered.sort_by_key(|p| p.shard.index);
    let runs: Vec<RunSums> = ordered
        .iter()
        .flat_map(|p| p.runs.iter().cloned())
        .collect();
    let expected = runs_of(&first.settings);
    if runs.len() != first.total_runs || runs.iter().map(|r| r.run).ne(expected.iter().copied()) {
        return Err(format!(
            "{} runs in the parts for the {} of the estimate",
            runs.len(),
            first.total_runs
        ));
    }
    Ok(finish(
        (&first.scene, &first.observe),
        &first.settings,
        &first.linear,
        &first.reference,
        &runs,
    ))
}
