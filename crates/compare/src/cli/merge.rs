//! `rattle merge`: joins the parts of a sharded sweep, map (either table) or basins.

use super::RattleError;
use crate::output::OutputError;
use crate::runs::shard::merge;
use clap::Args;
use std::path::PathBuf;

/// Arguments of `rattle merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// The parts (all `.json` or all `.csv`), in any order.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// The merged file.
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
