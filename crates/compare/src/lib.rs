//! The `rattle` workbench: scenes, both solvers side by side, sweeps, maps, figures and the
//! command line.
//!
//! One folder per job; data flows one way, from scene to figure, and no module imports one
//! listed above it (a tidy test checks this):
//!
//! | module | job |
//! | --- | --- |
//! | [`cli`] | the `rattle` command, a file per subcommand |
//! | [`figures`] | drawing only: data in, pixels out (cargo feature `figures`) |
//! | [`study`] | everything the figures and the report show; the paper's claims ([`study::paper`]) |
//! | [`peers`] | the Dormand–Prince baseline and the accuracy-versus-cost study |
//! | [`runs`] | parallel ordered runs: sweeps, shards, maps |
//! | [`verdict`] | the analytic candidates and how the two solvers relate at one frequency |
//! | [`output`] | typed rows and records, one writer per format |
//! | [`scene`] | the scene format, its validation, and the adapters to each solver |
//! | [`references`] | closed-form answers computed apart from both solvers, to check them against |
#![deny(missing_docs)]

pub mod api;
pub mod cli;
#[cfg(feature = "figures")]
pub mod figures;
pub mod output;
pub mod peers;
pub mod references;
pub mod runs;
pub mod scene;
pub mod study;
pub mod verdict;
