//! `rattle boundary`: one regime boundary of a unit or a chain, the curve of one event (fold,
//! branch point, period doubling, Neimark–Sacker, grazing, vanishing impact) of a signature's
//! orbits followed in (ω, a scene parameter).

use super::{load_any, write_record, RattleError};
use crate::api;
use crate::output::{finite, table_row, Format, Row};
use crate::runs::boundary::{BoundaryOptions, BoundaryRecord};
use clap::Args;
use rattle_analytic::BoundarySettings;
use std::fmt::Write as _;
use std::path::PathBuf;

/// Arguments of `rattle boundary`.
#[derive(Debug, Args)]
pub struct BoundaryArgs {
    /// Scene file (JSON), a single unit, a chain of cells or a structure. Omit for the
    /// built-in paper scene (Δ = 0.5, e = 0.8).
    pub scene: Option<PathBuf>,
    /// The impact signature of the orbits: the stops hit over one cycle in time order, `+`
    /// side 1 (r = +Δ), `-` side 2, any rotation (e.g. `+-`, `++--`). On a chain: the
    /// impacts of every pair in time order as `<pair><side>` tokens, pairs (cells) numbered
    /// from 0 (e.g. "0+ 1- 0- 1+"); on a structure, of its stops numbered from 0 in file
    /// order (with one stop, `+-` reads as "0+ 0-").
    #[arg(long, allow_hyphen_values = true)]
    pub signature: String,
    /// Forcing periods per cycle of the signature, in [1, 8].
    #[arg(long, default_value_t = 1)]
    pub period: u32,
    /// The event followed: fold, period-doubling, neimark-sacker, grazing or
    /// vanishing-impact, or branch-point (where the asymmetric orbits leave a symmetric one,
    /// followed on Moore's extended system).
    #[arg(long)]
    pub event: String,
    /// The event followed is the one of its kind nearest this frequency (rad/s, finite, > 0)
    /// on the branches of the signature's orbits found here, continued in ω within
    /// [omega-min, omega-max] at the scene's own value of the parameter.
    #[arg(long)]
    pub omega: f64,
    /// The scene parameter varied, by its JSON path: stops.gap, stops.restitution,
    /// unit.inner_stiffness, damping.outer, … (on a chain the whole chain's field, or one
    /// cell's, e.g. `chain[2].stops.gap`; on a structure: `structure.stops[0].gap_plus`,
    /// `structure.bodies[1].mass`, `structure.springs[0].stiffness`, `forcing.forces[0].amplitude`, …)
    #[arg(long)]
    pub param: String,
    /// Lowest parameter value followed (within the field's physical range).
    #[arg(long, allow_hyphen_values = true)]
    pub min: f64,
    /// Highest parameter value followed (> min, within the field's physical range).
    #[arg(long, allow_hyphen_values = true)]
    pub max: f64,
    /// Parameter values (comma-separated, in [min, max]) at which the curve's ω is solved
    /// exactly (one entry per crossing of the curve).
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub at: Vec<f64>,
    /// Lowest frequency, rad/s (finite, > 0): of the event search and of the curve.
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).omega_min)]
    pub omega_min: f64,
    /// Highest frequency, rad/s (finite, > omega-min): of the event search and of the curve.
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).omega_max)]
    pub omega_max: f64,
    /// Largest step along the curve (in α, impact phases, ω and the parameter together).
    #[arg(long, default_value_t = BoundarySettings::new(0.0, 1.0).max_step)]
    pub max_step: f64,
    /// Print one JSON document (points, at, special points, ends) instead of a summary.
    #[arg(long, conflicts_with = "out")]
    pub json: bool,
    /// Write the points to a `.csv` file (one row per point) or the whole document to a
    /// `.json` file.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

table_row! {
    /// One point of a boundary curve, as a CSV row.
    pub struct BoundaryRow {
        /// The parameter's value.
        pub param_value: Option<f64>,
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// `X_o`, m.
        pub outer_amplitude: Option<f64>,
        /// Real part of the event's multiplier.
        pub critical_multiplier_re: Option<f64>,
        /// Imaginary part of the event's multiplier.
        pub critical_multiplier_im: Option<f64>,
        /// The special point's kind where the point is one (`turning-point`, `grazing`,
        /// `vanishing-impact`, `resonance-1:q`, `crossing`), empty otherwise.
        pub special: Option<&'static str>,
    }
}

/// Runs `rattle boundary`.
///
/// # Errors
/// Bad arguments or scene (exit code 2); no orbit or event to follow, or a start that does
/// not converge (exit code 1).
pub fn run(args: BoundaryArgs) -> Result<String, RattleError> {
    let options = BoundaryOptions {
        signature: args.signature.clone(),
        period: args.period,
        event: args.event.clone(),
        omega: args.omega,
        param: args.param.clone(),
        min: args.min,
        max: args.max,
        at: args.at.clone(),
        omega_min: args.omega_min,
        omega_max: args.omega_max,
        max_step: args.max_step,
    };
    // The options first, before the output's format and the scene (`api::boundary` checks
    // them too).
    options.checked().map_err(RattleError::Argument)?;
    let format = args
        .out
        .as_ref()
        .map(|p| Format::of(p, "--out"))
        .transpose()?;
    if format == Some(Format::JsonLines) {
        return Err(RattleError::Argument(
            "--out: a boundary is written as .csv (points) or .json (the whole document)".into(),
        ));
    }
    let scene = load_any(&args.scene)?;
    let record = api::boundary(&scene, &options)?;
    write(&args, format, &record)
}

/// The output of a run: `--json` prints the record; `--out` writes it (`.json`) or the points
/// (`.csv`); the summary is printed otherwise.
///
/// # Errors
/// [`RattleError::Output`] when the file cannot be written.
fn write(
    args: &BoundaryArgs,
    format: Option<Format>,
    record: &BoundaryRecord,
) -> Result<String, RattleError> {
    let rows = || {
        record.points.iter().map(|p| BoundaryRow {
            param_value: finite(p.param_value),
            omega: finite(p.omega),
            outer_amplitude: finite(p.outer_amplitude),
            critical_multiplier_re: finite(p.critical_multiplier[0]),
            critical_multiplier_im: finite(p.critical_multiplier[1]),
            special: p.special,
        })
    };
    write_record(
        args.json,
        args.out.as_ref(),
        format,
        record,
        BoundaryRow::COLUMNS,
        rows,
        || summary(record),
    )
}

/// The summary printed without `--json`.
fn summary(record: &BoundaryRecord) -> String {
    let mut out = format!(
        "scene {}: {} of the {} orbits over {} period(s), from ω = {:.10} at {} = {}; {} points\n",
        record.scene,
        record.event,
        record.signature,
        record.period,
        record.omega_start,
        record.param,
        record.param_start,
        record.points.len()
    );
    for a in &record.at {
        let _ = writeln!(
            out,
            "at {} = {}: ω = {:.12}",
            record.param, a.param_value, a.omega
        );
    }
    for s in &record.special_points {
        let other = s.other.map(|o| format!(" with {o}")).unwrap_or_default();
        let _ = writeln!(
            out,
            "{}{other} at {} = {}, ω = {:.12}",
            s.kind, record.param, s.param_value, s.omega
        );
    }
    for e in &record.ends {
        let _ = writeln!(
            out,
            "end at {} = {}, ω = {:.10}: {}",
            record.param, e.param_value, e.omega, e.reason
        );
    }
    out
}
