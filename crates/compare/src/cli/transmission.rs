//! `rattle transmission`: the Welch estimate of the transmissibility under random base
//! motion, level by level, beside the linear structure's exact response.

use super::{load_any, pretty, RattleError};
use crate::api::{self, TransmissionRequest};
use crate::output::transmission::{TransmissionRecord, TransmissionRow};
use crate::output::{writer, Format, Header, OutputError};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::runs::transmission::TransmissionOptions;
use clap::Args;
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Arguments of `rattle transmission`.
#[derive(Debug, Args)]
pub struct TransmissionArgs {
    /// Scene file (JSON), of any form, with a spring or dashpot tied to the base. Omit for the
    /// built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The random base motion `random:band=LO-HI,rms=A,seed=S[,psd=FILE]` (as `rattle
    /// respond`'s): a random-phase multisine on the lines k·2π/T in [LO, HI] rad/s; each
    /// level replaces its rms, and each record of a level uses the seeds S, S + 1, ….
    #[arg(long, allow_hyphen_values = true)]
    pub signal: String,
    /// The duration T of each record from rest, s (finite, > 0; at most 1e7 samples at the
    /// sampling step, which puts the Nyquist frequency at 4 × HI or just above).
    #[arg(long, allow_hyphen_values = true)]
    pub duration: f64,
    /// The levels, comma-separated: the base motion's RMS of each, m (each finite, > 0;
    /// default: the signal's rms).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub levels: Vec<f64>,
    /// Records per level, independent (seeds S, S + 1, …, S + N − 1), in [1, 100000].
    #[arg(long, default_value_t = 1)]
    pub seeds: u64,
    /// The segment length, s, rounded to the nearest 2^m samples, at least 4 samples and at
    /// most the record left after the transient cut, long enough that a frequency 2πj/segment
    /// lies two spacings inside the band, and giving more than one effective average per
    /// level (default: the longest 2^m samples that cut that record into at least 8
    /// segments). The estimated frequencies are those 2πj/segment at least two spacings
    /// inside the band (the Hann window's main lobe).
    #[arg(long, allow_hyphen_values = true)]
    pub segment: Option<f64>,
    /// The overlap of consecutive segments, in [0, 1).
    #[arg(long, default_value_t = 0.5, allow_hyphen_values = true)]
    pub overlap: f64,
    /// The pointwise confidence of each radius, in (0, 1); every radius of a level holds at
    /// once with confidence at least 1 − N(1 − c) over its N frequencies (Bonferroni: the
    /// document's `simultaneous_confidence`).
    #[arg(long, default_value_t = 0.95, allow_hyphen_values = true)]
    pub confidence: f64,
    /// The time cut from the start of each record, s, in [0, T) (default: 10 time constants
    /// of the least-damped mode of the linear structure, at most T/2).
    #[arg(long, allow_hyphen_values = true)]
    pub transient: Option<f64>,
    /// Compute only part K of N of the (level, seed) runs (a contiguous block, levels in the
    /// order given, seeds ascending), e.g. `--shard 2/4`, written to --out F.json with the
    /// runs' raw segment sums; `rattle merge` joins the parts into the whole's .json or .csv,
    /// the same bits as the unsharded run.
    #[arg(long, requires = "out")]
    pub shard: Option<String>,
    /// Print the document as JSON: `settings`, `linear` (natural frequencies, slowest decay
    /// rate, attenuation bands) and per level `level`, `records`, `impacts`, `segments`,
    /// `effective_averages` and its `rows`.
    #[arg(long)]
    pub json: bool,
    /// Write the estimate to this file: `.json`, the document; `.csv`, one row per level
    /// and frequency, columns `level, omega, h1_magnitude, h1_phase, h1_radius,
    /// transmissibility, coherence, linear_magnitude, linear_phase, averages`. Written
    /// beside it and renamed when complete.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// The format of a transmission `--out`: `.json` or `.csv`.
fn format_of(path: &Path) -> Result<Format, RattleError> {
    match Format::of(path, "--out")? {
        Format::JsonLines => Err(RattleError::Argument(format!(
            "--out {}: must be .csv or .json (the estimate is one document)",
            path.display()
        ))),
        f => Ok(f),
    }
}

/// Writes `text` to `path` through a temporary file beside it, renamed when complete
/// (removed on failure): no half-written file.
fn write_whole(
    path: &Path,
    write: impl FnOnce(&mut dyn std::io::Write) -> std::io::Result<()>,
) -> Result<(), RattleError> {
    let io = |source| {
        RattleError::Output(OutputError::Io {
            path: path.to_owned(),
            source,
        })
    };
    let name = path
        .file_name()
        .map_or_else(|| "out".into(), |n| n.to_string_lossy().into_owned());
    let temporary = path.with_file_name(format!(".{name}.{}.part", std::process::id()));
    let result = (|| {
        let mut file = std::io::BufWriter::new(std::fs::File::create(&temporary)?);
        write(&mut file)?;
        file.flush()?;
        drop(file);
        std::fs::rename(&temporary, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result.map_err(io)
}

/// Writes `record` to `path` in `format` (`.json`: the document, `.csv`: its rows).
///
/// # Errors
/// [`RattleError::Output`] naming the file.
pub fn write_record(
    record: &TransmissionRecord,
    path: &Path,
    format: Format,
) -> Result<(), RattleError> {
    let text = match format {
        Format::Json => Some(pretty(record)?),
        _ => None,
    };
    write_whole(path, |out| match &text {
        Some(text) => out.write_all(text.as_bytes()),
        None => {
            let mut table =
                writer::<TransmissionRow, _>(Format::Csv, out, &Header::default(), None)?;
            for row in record.rows() {
                table.row(&row)?;
            }
            table.finish()
        }
    })
}

/// Runs `rattle transmission`.
///
/// # Errors
/// Bad arguments, scene or signal (exit 2, naming the option); an output file that cannot be
/// written; a failure of the engine.
pub fn run(args: TransmissionArgs) -> Result<String, RattleError> {
    let format = args.out.as_deref().map(format_of).transpose()?;
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()
        .map_err(RattleError::Argument)?;
    if shard.is_some() && format != Some(Format::Json) {
        return Err(RattleError::Argument(
            "--shard: a part is written to --out F.json (it holds the runs' raw sums); rattle \
             merge writes the whole as .json or .csv"
                .into(),
        ));
    }
    let scene = load_any(&args.scene)?;
    let request = TransmissionRequest {
        signal: args.signal.clone(),
        duration: args.duration,
        options: TransmissionOptions {
            levels: args.levels.clone(),
            seeds: args.seeds,
            segment: args.segment,
            overlap: args.overlap,
            confidence: args.confidence,
            transient: args.transient,
        },
    };
    let prepared = api::prepare_transmission(&scene, &request)?;
    if let (Some(shard), Some(path)) = (shard, &args.out) {
        let runs = shard.range(prepared.runs().len()).len();
        let progress = Progress::new("transmission runs", runs, true);
        let part = prepared.run_part(shard, &progress)?;
        let text =
            serde_json::to_string(&part).map_err(|e| RattleError::Numerical(e.to_string()))?;
        write_whole(path, |out| out.write_all(format!("{text}\n").as_bytes()))?;
        return Ok(format!(
            "wrote {} (part {}/{}: {runs} of {} runs)\n",
            path.display(),
            shard.index,
            shard.count,
            part.total_runs
        ));
    }
    let progress = Progress::new("transmission runs", prepared.runs().len(), true);
    let record = prepared.run(&progress)?;
    if let (Some(path), Some(format)) = (&args.out, format) {
        write_record(&record, path, format)?;
    }
    if args.json {
        return pretty(&record);
    }
    let mut out = summary(&record);
    if let Some(path) = &args.out {
        let _ = writeln!(out, "wrote {}", path.display());
    }
    Ok(out)
}

/// The short summary printed without --json: the settings, then per level its counts and
/// the peak of `|H₁|` beside the linear peak.
pub fn summary(r: &TransmissionRecord) -> String {
    let s = &r.settings;
    let mut out = String::new();
    let _ = writeln!(
        out,
        "scene {}: transmissibility u_{} / u_g under {} over T = {} s",
        r.scene, r.observe, s.signal, s.duration
    );
    let _ = writeln!(
        out,
        "sampling Δt = {:.6e} s (Nyquist {:.4} rad/s = {:.3} × band top); transient cut {:.4} s ({})",
        s.sampling_step, s.nyquist, s.nyquist_over_band_top, s.transient, s.transient_rule
    );
    let _ = writeln!(
        out,
        "Hann segments of {} samples ({:.4} s), overlap {}, {} per record, n = {:.3} per record; {} frequencies {:.4}–{:.4} rad/s every {:.4}",
        s.segment_samples,
        s.segment_duration,
        s.overlap,
        s.segments_per_record,
        s.effective_averages_per_record,
        s.frequencies,
        r.levels[0].rows.first().map_or(f64::NAN, |row| row.omega),
        r.levels[0].rows.last().map_or(f64::NAN, |row| row.omega),
        s.frequency_spacing
    );
    let natural = r
        .linear
        .natural_frequencies
        .iter()
        .map(|w| format!("{w:.4}"))
        .collect::<Vec<_>>()
        .join(", ");
    let _ = writeln!(
        out,
        "linear structure: natural frequencies {natural} rad/s; confidence {} pointwise, {:.4} over a level's frequencies",
        s.confidence, s.simultaneous_confidence
    );
    for level in &r.levels {
        let peak = |value: &dyn Fn(&TransmissionRow) -> Option<f64>| {
            level
                .rows
                .iter()
                .filter_map(|row| value(row).map(|v| (v, row.omega)))
                .fold(
                    (f64::NAN, f64::NAN),
                    |best, x| if best.0 >= x.0 { best } else { x },
                )
        };
        let (h, wh) = peak(&|row| row.h1_magnitude);
        let (l, wl) = peak(&|row| row.linear_magnitude);
        let _ = writeln!(
            out,
            "level {} m: {} records, {} impacts, {} segments, n = {:.3}; peak |H1| {h:.4} at {wh:.4} rad/s (linear {l:.4} at {wl:.4})",
            level.level, level.records, level.impacts, level.segments, level.effective_averages
        );
    }
    out
}
