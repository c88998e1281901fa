//! `rattle sweep`: a frequency sweep, streamed to a file.

use super::{check_frequency, check_omega, load_any, Accuracy, RattleError};
use crate::api;
use crate::output::{writer, Format, OutputError};
use crate::runs::axis::Axis;
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::runs::structure_sweep::structure_header;
use crate::runs::sweep::{header, Solver, SweepRow};
use crate::scene::frequency::FrequencyBounds;
use crate::scene::structure::StructureForm;
use crate::scene::AnyScene;
use clap::Args;
use rattle_event_driven::SimulationOptions;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Arguments of `rattle sweep`.
#[derive(Debug, Args)]
pub struct SweepArgs {
    /// Scene file (JSON). Omit for the built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// Lowest angular frequency, rad/s (finite, > 0).
    #[arg(long)]
    pub omega_min: f64,
    /// Highest angular frequency, rad/s (finite, ≥ omega-min).
    #[arg(long)]
    pub omega_max: f64,
    /// Number of frequencies, evenly spaced, ends included (≥ 1).
    #[arg(long)]
    pub points: usize,
    /// Which solver: analytic, event (simulator from rest) or both (with a verdict per point;
    /// on a chain, the verdict of `rattle compare` on the chain).
    #[arg(long, value_enum, default_value_t = Solver::Both)]
    pub solver: Solver,
    /// Output file: `.csv`, `.json` or `.jsonl`, by extension; rows are written as they are
    /// computed, in frequency order.
    #[arg(long)]
    pub out: PathBuf,
    /// Compute only part K of N (a contiguous block of the frequencies), e.g. `--shard 3/8`,
    /// on a scene of any form; join the parts with `rattle merge` (CSV or JSON parts) into
    /// the file the whole sweep writes, byte for byte.
    #[arg(long)]
    pub shard: Option<String>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub accuracy: Accuracy,
}

/// What an agreeing row agrees on, for the summary: the unit's signature, a chain's impact
/// sequence over its periods, or `linear`.
fn agreed_motion(row: &SweepRow) -> String {
    match (&row.simulated_signature, &row.matched) {
        (Some(signature), _) => signature.clone(),
        (None, Some(matched)) if !matched.starts_with("linear") => matched.clone(),
        _ => "linear".to_owned(),
    }
}

/// Runs `rattle sweep`.
///
/// # Errors
/// Bad arguments or scene; an output file that cannot be written.
pub fn run(args: SweepArgs) -> Result<String, RattleError> {
    let lo = check_omega("--omega-min", args.omega_min)?;
    let hi = check_omega("--omega-max", args.omega_max)?;
    if hi < lo {
        return Err(RattleError::Argument(format!(
            "--omega-max = {hi} is out of range: must be ≥ --omega-min = {lo}"
        )));
    }
    if args.points == 0 {
        return Err(RattleError::Argument("--points must be ≥ 1".into()));
    }
    let format = Format::of(&args.out, "--out")?;
    let shard = args
        .shard
        .as_deref()
        .map(Shard::parse)
        .transpose()
        .map_err(RattleError::Argument)?;
    if shard.is_some() && format == Format::JsonLines {
        return Err(RattleError::Argument(
            "--shard: parts must be .csv or .json (a .jsonl file has no header to say which part it is)".into(),
        ));
    }
    let options = args.accuracy.options()?;
    let scene = match load_any(&args.scene)? {
        AnyScene::Cells(scene) => scene,
        AnyScene::Structure(form) => {
            return structure_run(&args, &form, (lo, hi), (format, shard), &options);
        }
    };
    check_frequency(&scene, "--omega-min", lo)?;
    check_frequency(&scene, "--omega-max", hi)?;
    let all = Axis::new(lo, hi, args.points).values();
    let omegas = match shard {
        Some(s) => &all[s.range(all.len())],
        None => &all[..],
    };
    let io = |source| {
        RattleError::Output(OutputError::Io {
            path: args.out.clone(),
            source,
        })
    };
    let file = std::fs::File::create(&args.out).map_err(io)?;
    let preamble = shard.map(|s| s.csv_preamble(all.len()));
    let mut table = writer(
        format,
        std::io::BufWriter::new(file),
        &header(&scene, args.solver, all.len(), shard),
        preamble.as_deref(),
    )
    .map_err(io)?;
    let progress = Progress::new("sweep", omegas.len(), true);
    let mut by_class: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut by_signature: BTreeMap<String, usize> = BTreeMap::new();
    api::sweep_each(&scene, omegas, args.solver, &options, &progress, |row| {
        if let Some(class) = row.class {
            *by_class.entry(class).or_insert(0) += 1;
            if class == "agreement" {
                *by_signature.entry(agreed_motion(&row)).or_insert(0) += 1;
            }
        }
        table.row(&row).map_err(io)
    })?;
    table.finish().map_err(io)?;
    let mut out = format!(
        "wrote {} ({} frequencies, solver {})\n",
        args.out.display(),
        omegas.len(),
        args.solver.name()
    );
    if !by_class.is_empty() {
        let classes: Vec<String> = by_class.iter().map(|(k, n)| format!("{k} {n}")).collect();
        let signatures: Vec<String> = by_signature
            .iter()
            .map(|(k, n)| format!("{k} {n}"))
            .collect();
        out += &format!(
            "classes: {}\nagreement by signature: {}\n",
            classes.join(", "),
            signatures.join(", ")
        );
    }
    Ok(out)
}

/// `rattle sweep` on a structure: every row streamed to `--out` in `format` (only part
/// `shard` of the frequencies with a shard, its header and CSV preamble saying which, as a
/// unit's parts do, so that `rattle merge` joins them), the classes summarised.
///
/// # Errors
/// A frequency outside the structure's bounds; an output file that cannot be written.
fn structure_run(
    args: &SweepArgs,
    form: &StructureForm,
    (lo, hi): (f64, f64),
    (format, shard): (Format, Option<Shard>),
    options: &SimulationOptions,
) -> Result<String, RattleError> {
    let bounds = FrequencyBounds::of_structure(&form.structure);
    bounds.check("--omega-min", lo)?;
    bounds.check("--omega-max", hi)?;
    let all = Axis::new(lo, hi, args.points).values();
    let omegas = match shard {
        Some(s) => &all[s.range(all.len())],
        None => &all[..],
    };
    let io = |source| {
        RattleError::Output(OutputError::Io {
            path: args.out.clone(),
            source,
        })
    };
    let file = std::fs::File::create(&args.out).map_err(io)?;
    let preamble = shard.map(|s| s.csv_preamble(all.len()));
    let mut table = writer(
        format,
        std::io::BufWriter::new(file),
        &structure_header(form, args.solver, all.len(), shard),
        preamble.as_deref(),
    )
    .map_err(io)?;
    let progress = Progress::new("sweep", omegas.len(), true);
    let mut by_class: BTreeMap<&'static str, usize> = BTreeMap::new();
    api::structure_sweep_each(form, omegas, args.solver, options, &progress, |row| {
        if let Some(class) = row.class {
            *by_class.entry(class).or_insert(0) += 1;
        }
        table.row(&row).map_err(io)
    })?;
    table.finish().map_err(io)?;
    let mut out = format!(
        "wrote {} ({} frequencies, solver {}, structure {})\n",
        args.out.display(),
        omegas.len(),
        args.solver.name(),
        form.scene.name
    );
    if !by_class.is_empty() {
        let classes: Vec<String> = by_class.iter().map(|(k, n)| format!("{k} {n}")).collect();
        out += &format!("classes: {}\n", classes.join(", "));
    }
    Ok(out)
}
