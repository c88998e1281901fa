//! The native half of the `rattle` Python package, imported as `rattle._rattle`.
//!
//! Every function here does what the matching `rattle` command does, on the same library calls
//! of `rattle-compare`, and returns the same serializable record the command prints with
//! `--json`, as JSON text: the pure-Python half (`python/rattle/`) turns it into
//! objects with attributes and `.to_dict()`. Going through the command's own JSON makes the
//! dictionaries equal to the command's output by construction (same keys, same order, lists
//! where it has lists, `None` where it has `null`), and costs microseconds (measured in the
//! crate's README note).
//!
//! Contracts at the boundary:
//! - the computation runs with the GIL released (`Python::detach`), sweeps on rayon's pool;
//! - bad input is a `ValueError` whose message is the command's (a scene's field path and
//!   allowed range word for word; options named as the Python parameters, e.g. `tol` for
//!   `--tol`); an unreadable scene file an `OSError`; a numerical failure a `RuntimeError`
//!   (`numerical failure: …`, as the command says it);
//! - a panic never crosses the boundary: it is caught and raised as a `RuntimeError` that says
//!   it is a bug.
//!
//! One module per command ([`scene`], [`orbit`], [`simulate`], [`compare`], [`sweep`],
//! [`continuation`], [`boundary`], [`map`], [`basins`], [`merge`], [`respond`],
//! [`transmission`]), what they share in
//! [`common`] and the tables handed to numpy, column by column from the command's row types,
//! in [`table`]; this file only registers them.
#![deny(missing_docs)]

use pyo3::prelude::*;

mod basins;
mod boundary;
mod common;
mod compare;
mod continuation;
mod map;
mod merge;
mod orbit;
mod respond;
mod scene;
mod simulate;
mod sweep;
mod table;
mod transmission;

/// The native module.
#[pymodule]
fn _rattle(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    // The command's `--lyapunov-periods` default.
    m.add(
        "LYAPUNOV_PERIODS",
        rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS,
    )?;
    common::register(m)?;
    scene::register(m)?;
    orbit::register(m)?;
    simulate::register(m)?;
    compare::register(m)?;
    continuation::register(m)?;
    boundary::register(m)?;
    sweep::register(m)?;
    map::register(m)?;
    basins::register(m)?;
    merge::register(m)?;
    respond::register(m)?;
    transmission::register(m)?;
    table::register(m)?;
    Ok(())
}
