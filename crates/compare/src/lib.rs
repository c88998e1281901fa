//! The `rattle` workbench: scenes, both solvers side by side, sweeps, maps, figures and the
//! command line.
//!
//! Start at [`api`]: one call per job of the `rattle` command (load a scene, simulate, solve
//! its orbits, compare the two solvers, sweep, continue, follow a boundary, map, basins), each
//! taking a loaded scene and plain options and returning the record the command prints with
//! `--json`:
//!
//! ```
//! use rattle_compare::api;
//! use rattle_event_driven::SimulationOptions;
//!
//! let scene = api::load(concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/paper.json"))?;
//! let sim = api::simulate(&scene, 2.0, &SimulationOptions::default())?;
//! println!("X_o = {:.6} m", sim.point().outer_amplitude);
//! println!("{}", serde_json::to_string_pretty(&sim)?); // as `rattle simulate … --json`
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! The records' fields are documented on their types ([`output::records`],
//! [`output::structure`]); the scene format on [`scene::Scene`] and the repository's
//! `docs/scenes.md`.
//!
//! One folder per job; data flows one way, from scene to figure, and no module imports one
//! listed above it (a tidy test checks this):
//!
//! | module | job |
//! | --- | --- |
//! | [`cli`] | the `rattle` command, a file per subcommand |
//! | [`api`] | the front door: one call per job, records out (the command's and the Python package's) |
//! | [`figures`] | drawing only: data in, pixels out (cargo feature `figures`) |
//! | [`study`] | everything the figures and the report show; the paper's claims ([`study::paper`]) |
//! | [`peers`] | the Dormand–Prince baseline and the accuracy-versus-cost study |
//! | [`runs`] | parallel ordered runs: sweeps, shards, maps |
//! | [`verdict`] | the analytic candidates and how the two solvers relate at one frequency |
//! | [`output`] | typed rows and records, one writer per format |
//! | [`scene`] | the scene format, its validation, and the adapters to each solver |
//! | [`spectrum`] | the FFT and Welch's estimator of a transfer function from two records |
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
pub mod spectrum;
pub mod study;
pub mod verdict;
