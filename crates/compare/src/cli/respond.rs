//! `rattle respond`: the exact response to a non-periodic signal from rest.

use super::{load_any, pretty, RattleError};
use crate::api::{self, ResponseRequest};
use crate::output::respond::{sample_cells, RespondRecord};
use crate::output::structure::NamedWriter;
use crate::output::{Format, OutputError};
use crate::runs::parallel::Progress;
use clap::Args;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Samples taken only to show progress when no table is written.
const PROGRESS_STEPS: u64 = 1000;

/// Arguments of `rattle respond`.
#[derive(Debug, Args)]
pub struct RespondArgs {
    /// Scene file (JSON), of any form. Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The signal, in place of the scene's harmonic base motion: `F.csv`, a record with the
    /// columns `t,u_g` (base displacement, m) or `t,F` (force, N, on the body --on names),
    /// `t` from 0 strictly increasing, interpolated linearly and held at its last value;
    /// `tone-burst:omega=W,cycles=N[,amplitude=A]`, the Hann-windowed burst
    /// `A·½(1 − cos(Wt/N))·sin Wt` on `[0, 2πN/W]` (N ≥ 1; exactly three sinusoids);
    /// `sweep:from=W1,to=W2,rate=R[,amplitude=A][,steps=N]`, a linear sine sweep at R rad/s²,
    /// up or down, held at W2 after |W2 − W1|/R: continuous, solved as phase-continuous
    /// constant-frequency segments at each segment's mid frequency (the phase exact at every
    /// boundary, within R·Δ²/8 ≤ 1e-3 rad of the ideal chirp inside a segment of length Δ,
    /// the instantaneous frequency stepping by R·Δ ≤ 1e-3 × min(W1, W2)), or with `steps=N`
    /// N sinusoids at the frequencies from W1 to W2, each |W2 − W1|/(N R) long, phase 0 at
    /// each step, the state carried across; `random:band=LO-HI,rms=A,seed=S[,psd=FILE]`, a
    /// random-phase multisine on the lines k·2π/T in [LO, HI] rad/s (flat, or shaped by
    /// the csv FILE `omega,psd`), mean square A² over [0, T] exactly, the same bits for the
    /// same seed everywhere; above 64 lines sampled by FFT and interpolated within 1e-3 × A.
    /// A burst's or a sweep's amplitude defaults to the scene's u_g (m).
    #[arg(long, allow_hyphen_values = true)]
    pub signal: String,
    /// The duration T of the run from rest, s (finite, > 0, at most 1e7 periods of the
    /// fastest of the structure's natural frequencies and the signal's).
    #[arg(long, allow_hyphen_values = true)]
    pub duration: f64,
    /// Times at which to report the state, comma-separated, each in [0, T] (the document's
    /// `at`).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub at: Vec<f64>,
    /// The body a force record (`t,F`) acts on, by its name in the scene (a unit's `outer`,
    /// `inner`; a chain's `outer0`, `inner0`, `outer1`, …).
    #[arg(long)]
    pub on: Option<String>,
    /// Print one JSON document: `impacts`, `holds`, the states `at`, `final_state`, the
    /// `summary` (impacts, every body's RMS and peak by name, energy dissipated, work, final
    /// energy, the energy balance's residual) and the `signal`'s description. With --out,
    /// the table is written as well and the document printed in place of the summary.
    #[arg(long)]
    pub json: bool,
    /// Write the uniformly sampled response to this `.csv`/`.json`/`.jsonl` file as it runs
    /// (written to a temporary file beside it, renamed when complete): columns `t`, `u_g`
    /// (or `F`), then `u:NAME` and `v:NAME` of every body.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Sample intervals of --out, N + 1 rows at t = jT/N, in [1, 10000000] (default: 64 per
    /// period of the fastest of the structure's natural frequencies and the signal's, at
    /// most 1000000).
    #[arg(long, requires = "out")]
    pub samples: Option<u64>,
}

/// Runs `rattle respond`.
///
/// # Errors
/// Bad arguments, scene or signal (exit 2, naming the field); an output file that cannot be
/// written; a failure of the engine.
pub fn run(args: RespondArgs) -> Result<String, RattleError> {
    let format = args
        .out
        .as_deref()
        .map(|p| Format::of(p, "--out"))
        .transpose()?;
    let scene = load_any(&args.scene)?;
    let prepared = api::prepare_response(
        &scene,
        &ResponseRequest {
            signal: args.signal.clone(),
            duration: args.duration,
            at: args.at.clone(),
            on: args.on.clone(),
        },
    )?;
    let record = match (&args.out, format) {
        (Some(path), Some(format)) => {
            let samples = args.samples.unwrap_or_else(|| prepared.default_samples());
            let record = write_samples(&prepared, path, format, samples)?;
            (record, Some((path, samples)))
        }
        _ => {
            let progress = Progress::new("respond", PROGRESS_STEPS as usize + 1, true);
            let record = prepared.run(Some(PROGRESS_STEPS), &progress, &mut |_| Ok(()))?;
            (record, None)
        }
    };
    let (record, written) = record;
    if args.json {
        return pretty(&record);
    }
    let mut out = summary(&record);
    if let Some((path, samples)) = written {
        let _ = writeln!(out, "wrote {} ({} samples)", path.display(), samples + 1);
    }
    Ok(out)
}

/// Runs `prepared` with `samples` intervals streamed to `path` in `format`, through a
/// temporary file beside it renamed when complete (removed on failure).
fn write_samples(
    prepared: &api::PreparedResponse,
    path: &Path,
    format: Format,
    samples: u64,
) -> Result<RespondRecord, RattleError> {
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
        let file = std::fs::File::create(&temporary).map_err(io)?;
        let mut table =
            NamedWriter::new(format, std::io::BufWriter::new(file), &prepared.columns())
                .map_err(io)?;
        let progress = Progress::new("respond", samples as usize + 1, true);
        let mut failure: Option<std::io::Error> = None;
        let record = prepared.run(Some(samples), &progress, &mut |row| {
            table.row(&sample_cells(row)).map_err(|e| {
                let message = e.to_string();
                failure = Some(e);
                crate::api::ApiError::Numerical(message)
            })
        });
        if let Some(e) = failure {
            return Err(io(e));
        }
        let record = record?;
        table.finish().map_err(io)?;
        std::fs::rename(&temporary, path).map_err(io)?;
        Ok(record)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
    result
}

/// The short summary printed without --json.
fn summary(r: &RespondRecord) -> String {
    let mut out = String::new();
    let by_body = |values: &crate::output::records::ByBody| {
        values
            .0
            .iter()
            .map(|(n, v)| format!("{n} = {}", v.map_or("-".to_owned(), |v| format!("{v:.9}"))))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let input = match &r.on {
        Some(body) => format!("force on {body}"),
        None => "base motion".to_owned(),
    };
    let _ = writeln!(
        out,
        "scene {}: response from rest over T = {} s to {} ({input})",
        r.scene,
        r.duration,
        r.signal.words()
    );
    let s = &r.summary;
    let _ = writeln!(
        out,
        "impacts: {} (sticks {}, releases {})",
        s.impacts, s.sticks, s.releases
    );
    let _ = writeln!(out, "rms: {}", by_body(&s.rms));
    let _ = writeln!(out, "peak: {}", by_body(&s.peak));
    let _ = writeln!(
        out,
        "energy: work {:.6e} J = final {:.6e} + dissipated {:.6e} (dashpots {:.6e}, impacts {:.6e}); residual {:.1e}",
        s.work,
        s.final_energy,
        s.energy_dissipated,
        s.dissipated_by_dashpots,
        s.dissipated_by_impacts,
        s.energy_balance_residual
    );
    for state in &r.at {
        let _ = writeln!(
            out,
            "at t = {}: u = [{}]",
            state.t,
            state
                .displacements
                .iter()
                .map(|u| format!("{u:.9}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    out
}
