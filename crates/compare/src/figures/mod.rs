//! Every figure of `cargo xtask figures`, one module each; [`generate`] computes their data.

pub mod agreement;
pub mod beta_family;
pub mod bifurcation;
pub mod impact_time_response;
pub mod linear_time_response;
pub mod transmittance;
pub mod work_precision;

use crate::classify::MATCH_TOLERANCE;
use crate::plot::{save, PlotError};
use crate::study::{impact_rows, stroboscopic_outer, Study};
use crate::work_precision::WorkPrecision;
use rattle_event_driven::SimulationOptions;
use std::path::{Path, PathBuf};

/// Claimed bands `(from, to, label)` and marks `(ω, label)`.
type Claims = (Vec<(f64, f64, String)>, Vec<(f64, String)>);

/// The paper's claimed attenuation bands and marks, for the transmittance figure.
fn paper_claims() -> Claims {
    (
        vec![
            (1.5, 2.2, "paper: linear band 1.5–2.2".into()),
            (2.9, f64::INFINITY, "paper: linear band 2.9–∞".into()),
            (1.0, f64::INFINITY, "paper: impacting band 1.0–∞".into()),
        ],
        vec![
            (1.25, "paper peak 1.25".into()),
            (1.72, "paper valley 1.72".into()),
            (2.45, "paper peak 2.45".into()),
        ],
    )
}

/// Draws every figure of `study` into `dir`; returns the files written.
pub fn generate(
    study: &Study,
    options: &SimulationOptions,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let scene = &study.scene;
    let name = scene.name.clone();
    let gap = scene.stops.map_or(0.0, |s| s.gap);
    let mut written = Vec::new();
    written.extend(save(
        &linear_time_response::LinearTimeResponse {
            scene: scene.clone(),
            omegas: vec![0.5, 1.0, 2.0],
        },
        dir,
    )?);
    written.extend(save(
        &impact_time_response::ImpactTimeResponse {
            scene_name: name.clone(),
            gap,
            rows: impact_rows(scene, options),
        },
        dir,
    )?);
    let (claimed_bands, claimed_marks) = paper_claims();
    written.extend(save(
        &transmittance::Transmittance {
            scene_name: name.clone(),
            analytic: study.analytic.clone(),
            simulated: study.simulated(),
            claimed_bands,
            claimed_marks,
        },
        dir,
    )?);
    written.extend(save(
        &agreement::Agreement {
            scene_name: name.clone(),
            points: study.compared.clone(),
            tolerance: MATCH_TOLERANCE,
        },
        dir,
    )?);
    written.extend(save(
        &beta_family::BetaFamily {
            scene_name: name.clone(),
            restitution: scene.stops.map_or(f64::NAN, |s| s.restitution),
            curves: study
                .family
                .iter()
                .map(|c| (c.omega, c.members.clone()))
                .collect(),
            confirmations: study.confirmations.clone(),
        },
        dir,
    )?);
    let analytic = study
        .analytic
        .iter()
        .flat_map(|p| p.orbits.iter().filter(|(_, o)| o.viable))
        .map(|(_, o)| (o.omega, stroboscopic_outer(scene, o), o.stable))
        .collect();
    written.extend(save(
        &bifurcation::Bifurcation {
            scene_name: name,
            omega_range: (study.size.omega_min, study.size.omega_max),
            up: study.bifurcation_up.clone(),
            down: study.bifurcation_down.clone(),
            analytic,
        },
        dir,
    )?);
    Ok(written)
}

/// Draws the accuracy-versus-cost figures (`work-precision`, `steady-state-cost`) of `study`
/// into `dir`; returns the files written.
pub fn generate_work_precision(
    study: &WorkPrecision,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let mut written = save(
        &work_precision::WorkPrecisionFigure {
            study: study.clone(),
        },
        dir,
    )?;
    written.extend(save(
        &work_precision::SteadyStateCost {
            study: study.clone(),
        },
        dir,
    )?);
    Ok(written)
}
