//! `rattle continue`: the branches through every orbit of a signature at one frequency,
//! followed in ω with their bifurcations.

use super::{check_frequency, check_omega, load_unit, pretty, RattleError};
use crate::output::records::ContinuationPointRecord;
use crate::output::{finite, table_row, writer, Format, Header, OutputError};
use crate::runs::continuation::{follow, FollowError, Followed};
use clap::Args;
use rattle_analytic::continuation::ContinuationSettings;
use rattle_analytic::Signature;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `rattle continue`.
#[derive(Debug, Args)]
pub struct ContinueArgs {
    /// Scene file (JSON). Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The impact signature to follow: the stops hit over one cycle in time order, `+` side 1
    /// (r = +Δ), `-` side 2, any rotation (e.g. `+-`, `++--`).
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
            largest_multiplier: p
                .floquet_multipliers
                .iter()
                .map(|m| m.norm())
                .reduce(f64::max)
                .and_then(finite),
        })
    })
}

/// Runs `rattle continue`.
///
/// # Errors
/// Bad arguments or scene (exit code 2); no orbit to follow or a refused start (exit code 1).
pub fn run(args: ContinueArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.omega)?;
    let signature = Signature::parse(&args.signature, args.period)
        .map_err(|e| RattleError::Argument(e.to_string()))?;
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
    let scene = load_unit(&args.scene, "rattle continue")?;
    check_frequency(&scene, "--omega-min", args.omega_min)?;
    check_frequency(&scene, "--omega-max", args.omega_max)?;
    let followed =
        follow(&scene, &signature, omega, args.orbit, &settings).map_err(|e| match e {
            FollowError::OrbitIndex { .. } | FollowError::NoStops => {
                RattleError::Argument(e.to_string())
            }
            FollowError::Continuation(ref c) if c.to_string().contains("out of range") => {
                RattleError::Argument(e.to_string())
            }
            _ => RattleError::Numerical(e.to_string()),
        })?;
    let record = followed.record(&scene.name);
    if args.json {
        return pretty(&record);
    }
    if let (Some(path), Some(format)) = (&args.out, format) {
        let io = |source| {
            RattleError::Output(OutputError::Io {
                path: path.clone(),
                source,
            })
        };
        if format == Format::Json {
            std::fs::write(path, pretty(&record)?).map_err(io)?;
        } else {
            let file = std::fs::File::create(path).map_err(io)?;
            let mut table = writer::<ContinuationRow, _>(
                format,
                std::io::BufWriter::new(file),
                &Header::default(),
                None,
            )
            .map_err(io)?;
            for row in rows(&followed) {
                table.row(&row).map_err(io)?;
            }
            table.finish().map_err(io)?;
        }
    }
    Ok(summary(&scene.name, &followed, &record.points))
}

/// The summary printed without `--json`.
fn summary(scene: &str, f: &Followed, points: &[ContinuationPointRecord]) -> String {
    let mut out = format!(
        "scene {scene}: {} orbit(s) of {} over {} period(s) at ω = {}; followed from {:?}\n",
        f.start_orbits.len(),
        f.signature,
        f.signature.period(),
        f.omega_start,
        f.followed_starts
    );
    for b in &f.branches.branches {
        let (lo, hi) = b
            .points
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                (lo.min(p.omega), hi.max(p.omega))
            });
        let stable = b.points.iter().filter(|p| p.stable && p.viable).count();
        let _ = writeln!(
            out,
            "branch {}: {} over {} period(s), {} points on ω ∈ [{lo:.6}, {hi:.6}], {stable} stable and viable{}",
            b.index,
            b.signature,
            b.period,
            b.points.len(),
            b.from_event
                .map_or(String::new(), |e| format!(", from event {e}"))
        );
    }
    for (k, e) in f.branches.events.iter().enumerate() {
        let _ = writeln!(
            out,
            "event {k}: {} on branch {} at ω = {:.10}{}",
            e.kind.name(),
            e.branch,
            e.omega,
            e.signature_after
                .as_ref()
                .map_or(String::new(), |s| format!(" → {s}"))
        );
    }
    for e in &f.branches.ends {
        let _ = writeln!(
            out,
            "end of branch {} at ω = {:.10}: {}{}",
            e.branch,
            e.omega,
            e.reason.name(),
            e.joins.map_or(String::new(), |b| format!(" branch {b}"))
        );
    }
    let _ = writeln!(out, "{} points in all", points.len());
    out
}
