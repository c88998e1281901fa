//! The `rattle` workbench: scenes, both solvers side by side, sweeps, figures and the
//! command line.
//!
//! Data flows from a [`scene::Scene`] (JSON) to each solver's own problem
//! ([`scene::Scene::unit_model`] for the analytic crate, [`simulation::model`] for the
//! event-driven one); [`frequency::analyse`] gives the analytic picture at one frequency,
//! [`simulation::run`] the simulated steady state, [`classify::compare`] both and a verdict;
//! [`sweep`] runs any of them over frequencies in parallel; [`study::Study`] gathers what
//! [`figures`] draws and [`validation`] reports; [`map`] runs lines of frequencies over
//! restitution and gap for the regime and bandwidth maps.
#![deny(missing_docs)]

pub mod bands;
pub mod baseline;
pub mod classify;
pub mod cli;
pub mod figures;
pub mod frequency;
pub mod json;
pub mod map;
pub mod plot;
pub mod scene;
pub mod simulation;
pub mod study;
pub mod sweep;
pub mod validation;
pub mod work_precision;
