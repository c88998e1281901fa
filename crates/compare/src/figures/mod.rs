//! Every figure of `cargo xtask figures`, one module each; [`generate`] computes their data.

pub mod agreement;
pub mod bandwidth_map;
pub mod beta_family;
pub mod bifurcation;
pub mod impact_time_response;
pub mod linear_time_response;
pub mod regime_map;
pub mod transmittance;
pub mod work_precision;

use crate::classify::MATCH_TOLERANCE;
use crate::map::{Axis, Map, MapGrid, MapSettings};
use crate::plot::{save, PlotError};
use crate::scene::{DampingSpec, Scene};
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

/// Grid sizes of the two maps drawn by [`generate_maps`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapSizes {
    /// Restitutions of the bandwidth map, over `[0, 1]`.
    pub restitutions: usize,
    /// Gaps of both maps, over `Δ/u_g ∈ [0.05, 1]`.
    pub gaps: usize,
    /// Frequencies of the bandwidth map's lines, over `[0.1, 4]` rad/s.
    pub bandwidth_points: usize,
    /// Frequencies of the regime map, over `[0.1, 4]` rad/s.
    pub regime_points: usize,
}

impl MapSizes {
    /// The grids of `cargo xtask figures` (about a minute on two cores; `rattle map` runs
    /// finer grids).
    pub fn full() -> MapSizes {
        MapSizes {
            restitutions: 21,
            gaps: 20,
            bandwidth_points: 200,
            regime_points: 300,
        }
    }

    /// A few points of everything.
    pub fn quick() -> MapSizes {
        MapSizes {
            restitutions: 3,
            gaps: 3,
            bandwidth_points: 20,
            regime_points: 20,
        }
    }
}

/// The scene the maps are drawn for: `scene` itself when it is damped; otherwise the same
/// unit with the light dashpots of `data/scenes/paper-damped.json` (`c_o = 0.1`,
/// `c_i = 0.05` N·s/m), because without damping no motion clear of the stops ever settles
/// and there would be no transmittance to map there. The name says which.
pub fn map_scene(scene: &Scene) -> Scene {
    if scene.unit_model().damping.is_some() {
        return scene.clone();
    }
    let mut damped = scene.clone();
    damped.damping = Some(DampingSpec {
        outer: 0.1,
        inner: 0.05,
    });
    damped.name = format!("{} + light damping", scene.name);
    damped
}

/// Computes and draws `bandwidth-map` (over restitution and gap) and `regime-map` (over
/// frequency and gap, at the scene's restitution) for [`map_scene`]`(scene)`, and writes
/// their tables into `data_dir` (`bandwidth-map.csv`: one row per `(e, Δ/u_g)`;
/// `regime-map.csv`: one row per point). Returns the files written.
pub fn generate_maps(
    scene: &Scene,
    sizes: MapSizes,
    figures_dir: &Path,
    data_dir: &Path,
    progress: bool,
) -> Result<Vec<PathBuf>, PlotError> {
    let scene = map_scene(scene);
    let settings = MapSettings::default();
    let gaps = Axis {
        min: 0.05,
        max: 1.0,
        count: sizes.gaps,
    };
    let fail = |path: &Path| {
        let path = path.to_owned();
        move |message: String| PlotError { path, message }
    };
    let bandwidth_grid = MapGrid {
        restitution: Axis {
            min: 0.0,
            max: 1.0,
            count: sizes.restitutions,
        },
        gap_over_base_amplitude: gaps,
        omega: Axis {
            min: 0.1,
            max: 4.0,
            count: sizes.bandwidth_points,
        },
    };
    let restitution = scene.stops.map_or(0.8, |s| s.restitution);
    let regime_grid = MapGrid {
        restitution: Axis {
            min: restitution,
            max: restitution,
            count: 1,
        },
        gap_over_base_amplitude: gaps,
        omega: Axis {
            min: 0.1,
            max: 4.0,
            count: sizes.regime_points,
        },
    };
    let mut written = Vec::new();
    std::fs::create_dir_all(data_dir).map_err(|e| fail(data_dir)(e.to_string()))?;
    let bandwidth = Map::run(&scene, bandwidth_grid, &settings, progress)
        .map_err(|e| fail(figures_dir)(e.to_string()))?;
    let table = data_dir.join("bandwidth-map.csv");
    std::fs::write(&table, bandwidth.bandwidth_csv()).map_err(|e| fail(&table)(e.to_string()))?;
    written.push(table);
    written.extend(save(
        &bandwidth_map::BandwidthMap {
            scene_name: scene.name.clone(),
            map: bandwidth,
        },
        figures_dir,
    )?);
    let regimes = Map::run(&scene, regime_grid, &settings, progress)
        .map_err(|e| fail(figures_dir)(e.to_string()))?;
    let table = data_dir.join("regime-map.csv");
    std::fs::write(&table, regimes.points_csv()).map_err(|e| fail(&table)(e.to_string()))?;
    written.push(table);
    written.extend(save(
        &regime_map::RegimeMap {
            scene_name: scene.name.clone(),
            map: regimes,
        },
        figures_dir,
    )?);
    Ok(written)
}
