//! Runs over many points: the parallel, ordered machinery ([`parallel`]), frequency sweeps
//! ([`sweep`]; of a structure, [`structure_sweep`]) and their shards ([`shard`], whose parts [`merge`] joins), maps over
//! restitution, gap and frequency ([`map`]), and the attenuation bands of a run ([`bands`]).
//!
//! Every run hands its points out in parallel and returns (or writes) them in input order, so
//! its output does not depend on the number of threads.

pub mod axis;
pub mod bands;
pub mod basins;
pub mod boundaries;
pub mod boundary;
pub mod continuation;
pub mod map;
pub mod parallel;
pub mod shard;
pub mod structure_sweep;
pub mod sweep;
pub mod transmission;

/// Joins the parts of a sharded sweep, map (its points or its bandwidth table) or basins (all
/// JSON or all CSV, in any order) into exactly the text the unsharded run writes: basins'
/// parts by [`basins::merge_parts`], the others by `shard::merge_tables`. Also
/// [`shard::merge`].
///
/// # Errors
/// A message when a part is not a shard, when parts are missing, repeated or from different
/// sweeps, or when the rows do not add up to the sweep's points.
pub fn merge(parts: &[String]) -> Result<String, String> {
    if parts.is_empty() {
        return Err("no parts to merge".into());
    }
    if basins::is_basins_part(&parts[0]) {
        return basins::merge_parts(parts);
    }
    shard::merge_tables(parts)
}
