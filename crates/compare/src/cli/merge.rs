//! `rattle merge`: joins the parts of a sharded sweep, map (either table), basins or
//! transmission estimate.

use super::RattleError;
use crate::output::OutputError;
use crate::runs::shard::merge;
use crate::runs::transmission::{is_part, TransmissionPart};
use clap::Args;
use std::path::PathBuf;

/// Arguments of `rattle merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The parts (all `.json` or all `.csv`; a transmission estimate's are `.json`), in any
    /// order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged file (of a transmission estimate: `.json`, the document, or `.csv`, its
    /// rows).
    #[arg(long)]
    pub out: PathBuf,
}

/// Runs `rattle merge`.
///
/// # Errors
/// A part that cannot be read or is not a shard of the same sweep; an unwritable output.
pub fn run(args: MergeArgs) -> Result<String, RattleError> {
    let parts: Vec<String> = args
        .parts
        .iter()
        .map(|p| {
            std::fs::read_to_string(p)
                .map_err(|e| RattleError::Argument(format!("cannot read {}: {e}", p.display())))
        })
        .collect::<Result<_, _>>()?;
    if parts.first().is_some_and(|p| is_part(p)) {
        return merge_transmission(&args, &parts);
    }
    let merged = merge(&parts).map_err(RattleError::Argument)?;
    std::fs::write(&args.out, merged).map_err(|source| OutputError::Io {
        path: args.out.clone(),
        source,
    })?;
    Ok(format!(
        "wrote {} from {} parts\n",
        args.out.display(),
        parts.len()
    ))
}

/// Joins the parts of a sharded transmission estimate and writes the whole to --out.
fn merge_transmission(args: &MergeArgs, parts: &[String]) -> Result<String, RattleError> {
    let format = crate::output::Format::of(&args.out, "--out")?;
    if format == crate::output::Format::JsonLines {
        return Err(RattleError::Argument(format!(
            "--out {}: a transmission estimate is written as .json or .csv",
            args.out.display()
        )));
    }
    let parsed: Vec<TransmissionPart> = parts
        .iter()
        .zip(&args.parts)
        .map(|(text, path)| {
            serde_json::from_str(text).map_err(|e| {
                RattleError::Argument(format!("{}: not a transmission part ({e})", path.display()))
            })
        })
        .collect::<Result<_, _>>()?;
    let record = crate::api::merge_transmission(&parsed)?;
    super::transmission::write_record(&record, &args.out, format)?;
    Ok(format!(
        "wrote {} from {} parts\n",
        args.out.display(),
        parts.len()
    ))
}
