//! The `rattle` workbench: scenes, both solvers side by side, and the command line.
//!
//! Data flows from a [`scene::Scene`] (JSON) to each solver's own problem
//! ([`scene::Scene::unit_model`] for the analytic crate), through [`frequency::analyse`] for
//! the analytic picture at one frequency, to [`json`] and the tables of [`cli`].
#![deny(missing_docs)]

pub mod cli;
pub mod frequency;
pub mod json;
pub mod scene;
