//! Runs over many points: the parallel, ordered machinery ([`parallel`]), frequency sweeps
//! ([`sweep`]) and their shards ([`shard`]), maps over restitution, gap and frequency
//! ([`map`]), and the attenuation bands of a run ([`bands`]).
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
pub mod sweep;
