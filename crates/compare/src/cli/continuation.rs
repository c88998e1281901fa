//! `rattle continue`: the branches through every orbit of a signature (on a chain: an impact
//! sequence) at one frequency, followed in ω with their bifurcations.

use super::{check_omega, load_any, write_record, RattleError};
use crate::api::{self, ContinuedBranches};
use crate::output::records::ContinuationRecord;
use crate::output::{finite, number_list, table_row, Format, Renamed, Row};
use crate::runs::continuation::{Followed, SequenceFollowed};
use crate::scene::structure::Structure;
use clap::Args;
use rattle_analytic::{ContinuationPoint, ContinuationSettings};
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `rattle continue`.
#[derive(Debug, Args)]
pub struct ContinueArgs {
    /// Scene file (JSON), a single unit, a chain of cells or a structure. Omit for the built-in
    /// paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The impact signature to follow: the stops hit over one cycle in time order, `+` side 1
    /// (r = +Δ), `-` side 2, any rotation (e.g. `+-`, `++--`). On a chain: the impacts of
    /// every pair in time order as `<pair><side>` tokens, pairs (cells) numbered from 0 (e.g.
    /// "0+ 1- 0- 1+"); each point then carries every cell's outer amplitude. On a structure:
    /// of its stops, numbered from 0 in file order (with one stop, `+-` reads as "0+ 0-");
    /// each point then carries every body's amplitude.
    #[arg(long, allow_hyphen_values = true)]
    pub signature: String,
    /// Forcing periods per cycle of the signature, in [1, 8].
    #[arg(long, default_value_t = 1)]
    pub period: u32,
    /// Frequency at which the start orbits are found, rad/s (finite, > 0, in
    /// [omega-min, omega-max]).
    #[arg(long)]
    pub omega: f64,
    /// Lowest frequency followed, rad/s (finite, > 0).
    #[arg(long)]
    pub omega_min: f64,
    /// Highest frequency followed, rad/s (finite, > omega-min).
    #[arg(long)]
    pub omega_max: f64,
    /// Follow only the K-th orbit found at --omega (numbered from 0, as `rattle orbit
    /// --signature` lists them); by default every one.
    #[arg(long)]
    pub orbit: Option<usize>,
    /// Do not follow the branches that leave at branch points, period doublings and grazings.
    #[arg(long)]
    pub no_switch: bool,
    /// Largest step along the branch (in α, impact phases and ω together), ≥ 1e-9.
    #[arg(long, default_value_t = ContinuationSettings::default().max_step)]
    pub max_step: f64,
    /// Cap on the branches followed per start orbit, ≥ 1.
    #[arg(long, default_value_t = ContinuationSettings::default().max_branches)]
    pub max_branches: usize,
    /// Switching depth: a start orbit's branch has depth 0, a branch switched onto from one
    /// of depth d has depth d + 1; the branches leaving a branch of depth D are not followed
    /// but listed without points, ending `max-depth` (0: no switching, the cuts listed).
    #[arg(long, default_value_t = ContinuationSettings::default().max_depth)]
    pub max_depth: usize,
    /// Print one JSON document (points, events, ends) instead of a summary.
    #[arg(long, conflicts_with = "out")]
    pub json: bool,
    /// Write the points to a `.csv` file (one row per point) or the whole document to a
    /// `.json` file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

table_row! {
    /// One point of a continued branch, as a CSV row.
    pub struct ContinuationRow {
        /// Index of its branch.
        pub branch: usize,
        /// The branch's canonical signature.
        pub signature: String,
        /// Forcing periods per cycle.
        pub period: u32,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// Base phase at the first canonical impact, rad.
        pub alpha: Option<f64>,
        /// `X_o`, m.
        pub outer_amplitude: Option<f64>,
        /// `T`, dB.
        pub transmittance_db: Option<f64>,
        /// Every Floquet multiplier inside the unit circle.
        pub stable: bool,
        /// No penetration, every impact from inside, no extra impact.
        pub viable: bool,
        /// The largest modulus of a Floquet multiplier.
        pub largest_multiplier: Option<f64>,
    }
}

table_row! {
    /// One point of a chain's or a structure's continued branch, as a CSV row: the unit's
    /// columns (for a structure, of its observed body) and every amplitude of the sequence's
    /// model, under the name its form gives them (`cell_outer_amplitudes` on a chain,
    /// `body_amplitudes` on a structure).
    pub struct SequenceContinuationRow {
        /// Index of its branch.
        pub branch: usize,
        /// The branch's canonical impact sequence.
        pub signature: String,
        /// Forcing periods per cycle.
        pub period: u32,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// The forcing's phase at the first canonical impact, rad.
        pub alpha: Option<f64>,
        /// The observed amplitude (a chain's last cell's `X_o`, a structure's observed body), m.
        pub outer_amplitude: Option<f64>,
        /// `20 log10(outer_amplitude / u_g)`, dB, when the base moves.
        pub transmittance_db: Option<f64>,
        /// Every Floquet multiplier inside the unit circle.
        pub stable: bool,
        /// No penetration, every impact from inside, no extra impact.
        pub viable: bool,
        /// The largest modulus of a Floquet multiplier.
        pub largest_multiplier: Option<f64>,
        /// The amplitudes, m: a list, `;`-separated.
        pub amplitudes: Option<String>,
    }
}

/// A chain's amplitudes column: `max|u_o,j|` of every cell, from the base out.
const CELL_AMPLITUDES: &[(&str, &str)] = &[("amplitudes", "cell_outer_amplitudes")];

/// A structure's amplitudes column: `max|u|` of every body in the scene's order.
const BODY_AMPLITUDES: &[(&str, &str)] = &[("amplitudes", "body_amplitudes")];

/// The rows of every point of a chain's `f`, its amplitudes named as [`CELL_AMPLITUDES`].
fn chain_rows(f: &SequenceFollowed) -> impl Iterator<Item = Renamed<SequenceContinuationRow>> + '_ {
    sequence_rows(f, |p| {
        (
            finite(p.outer_amplitude),
            finite(p.transmittance_db),
            &p.cell_outer_amplitudes,
        )
    })
    .map(|row| Renamed {
        row,
        renames: CELL_AMPLITUDES,
    })
}

/// The rows of every point of a structure's `f`, its amplitudes named as [`BODY_AMPLITUDES`].
fn structure_rows<'a>(
    structure: &'a Structure,
    f: &'a SequenceFollowed,
) -> impl Iterator<Item = Renamed<SequenceContinuationRow>> + 'a {
    sequence_rows(f, move |p| {
        let observed = p.amplitudes.get(structure.observe).copied();
        (
            observed.and_then(finite),
            observed.and_then(|x| structure.transmittance_db(x)),
            &p.amplitudes,
        )
    })
    .map(|row| Renamed {
        row,
        renames: BODY_AMPLITUDES,
    })
}

/// The rows of every point of `f`, with `observed` giving a point's observed amplitude, its
/// transmittance and the amplitudes listed.
fn sequence_rows<'a>(
    f: &'a SequenceFollowed,
    observed: impl Fn(&ContinuationPoint) -> (Option<f64>, Option<f64>, &[f64]) + Copy + 'a,
) -> impl Iterator<Item = SequenceContinuationRow> + 'a {
    f.continuation.branches.iter().flat_map(move |b| {
        b.points.iter().map(move |p| {
            let (outer_amplitude, transmittance_db, amplitudes) = observed(p);
            SequenceContinuationRow {
                branch: b.index,
                signature: b.signature.to_string(),
                period: b.period,
                omega: finite(p.omega),
                alpha: finite(p.alpha),
                outer_amplitude,
                transmittance_db,
                stable: p.stable,
                viable: p.viable,
                largest_multiplier: largest_multiplier(p),
                amplitudes: number_list(amplitudes),
            }
        })
    })
}

/// The largest modulus of `p`'s Floquet multipliers.
fn largest_multiplier(p: &ContinuationPoint) -> Option<f64> {
    p.floquet_multipliers
        .iter()
        .map(|m| m.norm())
        .reduce(f64::max)
        .and_then(finite)
}

/// The rows of every point of `f`.
fn rows(f: &Followed) -> impl Iterator<Item = ContinuationRow> + '_ {
    f.branches.branches.iter().flat_map(|b| {
        b.points.iter().map(move |p| ContinuationRow {
            branch: b.index,
            signature: b.signature.to_string(),
            period: b.period,
            omega: finite(p.omega),
            alpha: finite(p.alpha),
            outer_amplitude: finite(p.outer_amplitude),
            transmittance_db: finite(p.transmittance_db),
            stable: p.stable,
            viable: p.viable,
            largest_multiplier: largest_multiplier(p),
        })
    })
}

/// Runs `rattle continue`.
///
/// # Errors
/// Bad arguments or scene (exit code 2); no orbit to follow or a refused start (exit code 1).
pub fn run(args: ContinueArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.omega)?;
    let settings = settings(&args)?;
    if !(args.omega_min..=args.omega_max).contains(&omega) {
        return Err(RattleError::Argument(format!(
            "--omega = {omega} is out of range: must be in [--omega-min, --omega-max] = [{}, {}]",
            args.omega_min, args.omega_max
        )));
    }
    let format = args
        .out
        .as_ref()
        .map(|p| Format::of(p, "--out"))
        .transpose()?;
    if format == Some(Format::JsonLines) {
        return Err(RattleError::Argument(
            "--out: a continuation is written as .csv (points) or .json (the whole document)"
                .into(),
        ));
    }
    let scene = load_any(&args.scene)?;
    api::check_frequency(&scene, "--omega-min", args.omega_min)?;
    api::check_frequency(&scene, "--omega-max", args.omega_max)?;
    let continued = api::continuation(
        &scene,
        &args.signature,
        args.period,
        omega,
        args.orbit,
        &settings,
    )?;
    match &continued.branches {
        ContinuedBranches::Unit(followed) => write(
            &args,
            format,
            &continued.record,
            ContinuationRow::COLUMNS,
            || rows(followed),
        ),
        ContinuedBranches::Chain(followed) => write(
            &args,
            format,
            &continued.record,
            &Renamed::<SequenceContinuationRow>::columns(CELL_AMPLITUDES),
            || chain_rows(followed),
        ),
        ContinuedBranches::Structure {
            followed,
            structure,
        } => write(
            &args,
            format,
            &continued.record,
            &Renamed::<SequenceContinuationRow>::columns(BODY_AMPLITUDES),
            || structure_rows(structure, followed),
        ),
    }
}

/// The continuation settings of the arguments.
///
/// # Errors
/// [`RattleError::Argument`] naming the option out of range.
fn settings(args: &ContinueArgs) -> Result<ContinuationSettings, RattleError> {
    let mut settings = ContinuationSettings {
        max_step: args.max_step,
        max_branches: args.max_branches,
        max_depth: args.max_depth,
        follow_switches: !args.no_switch,
        ..ContinuationSettings::new(args.omega_min, args.omega_max)
    };
    if !(args.max_step.is_finite() && args.max_step >= settings.min_step) {
        return Err(RattleError::Argument(format!(
            "--max-step = {} is out of range: must be finite and ≥ {:e}",
            args.max_step, settings.min_step
        )));
    }
    if args.max_branches == 0 {
        return Err(RattleError::Argument(
            "--max-branches = 0 is out of range: must be ≥ 1".into(),
        ));
    }
    if settings.initial_step > settings.max_step {
        settings.initial_step = settings.max_step;
    }
    settings
        .validate()
        .map_err(|e| RattleError::Argument(e.to_string()))?;
    Ok(settings)
}

/// The output of a run: `--json` prints `record`; `--out` writes it (`.json`) or the points'
/// `rows` under `columns` (`.csv`); the summary is printed otherwise.
///
/// # Errors
/// [`RattleError::Output`] when the file cannot be written.
fn write<R: serde::Serialize, I: Iterator<Item = R>>(
    args: &ContinueArgs,
    format: Option<Format>,
    record: &ContinuationRecord,
    columns: &[&str],
    rows: impl FnOnce() -> I,
) -> Result<String, RattleError> {
    write_record(
        args.json,
        args.out.as_ref(),
        format,
        record,
        columns,
        rows,
        || summary(record),
    )
}

/// The summary printed without `--json`.
fn summary(record: &ContinuationRecord) -> String {
    let value = |v: Option<f64>| v.unwrap_or(f64::NAN);
    let mut out = format!(
        "scene {}: {} orbit(s) of {} over {} period(s) at ω = {}; followed from {:?}\n",
        record.scene,
        record.start_orbits,
        record.signature,
        record.period,
        value(record.omega_start),
        record.followed_starts
    );
    for b in &record.branches {
        let points = record.points.iter().filter(|p| p.branch == b.branch);
        let (lo, hi) = points
            .clone()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(value(p.omega)), hi.max(value(p.omega)))
            });
        let stable = points.filter(|p| p.stable && p.viable).count();
        // A branch listed at the switching depth or the branch cap has no points: its end says
        // why, instead of an empty ω range.
        let followed = if b.points == 0 {
            let why = record.ends.iter().find(|e| e.branch == b.branch);
            format!(
                "listed, not followed ({})",
                why.map_or("no points".to_owned(), |e| e.reason.to_string())
            )
        } else {
            format!(
                "{} points on ω ∈ [{lo:.6}, {hi:.6}], {stable} stable and viable",
                b.points
            )
        };
        let _ = writeln!(
            out,
            "branch {}: {} over {} period(s), {followed}{}",
            b.branch,
            b.signature,
            b.period,
            b.from_event
                .map_or(String::new(), |e| format!(", from event {e}"))
        );
    }
    for (k, e) in record.events.iter().enumerate() {
        let _ = writeln!(
            out,
            "event {k}: {} on branch {} at ω = {:.10}{}",
            e.kind,
            e.branch,
            value(e.omega),
            e.signature_after
                .as_ref()
                .map_or(String::new(), |s| format!(" → {s}"))
        );
    }
    for e in &record.ends {
        let _ = writeln!(
            out,
            "end of branch {} at ω = {:.10}: {}{}",
            e.branch,
            value(e.omega),
            e.reason,
            e.joins.map_or(String::new(), |b| format!(" branch {b}"))
        );
    }
    let _ = writeln!(out, "{} points in all", record.points.len());
    out
}
