//! Every figure of `cargo xtask figures`, one module each: data in ([`crate::study::plots`],
//! [`crate::peers::work_precision`]), pixels out. Nothing here computes a result.

pub mod agreement;
pub mod bandwidth_map;
pub mod basins;
pub mod beta_family;
pub mod bifurcation;
pub mod boundaries;
pub mod broadband_transmission;
pub mod chain;
pub mod frequency_response;
pub mod impact_damper;
pub mod impact_oscillator;
pub mod impact_time_response;
pub mod linear_time_response;
pub mod lyapunov;
pub mod plot;
pub mod poincare;
pub mod regime_map;
pub mod sweep_up_down;
pub mod tone_burst;
pub mod transmittance;
pub mod work_precision;

use crate::peers::work_precision::WorkPrecision;
use crate::study::plots::Plots;
use plot::{save, PlotError};
use std::path::{Path, PathBuf};

/// Draws every figure of `plots` into `dir` (PNG and SVG); returns the files written.
///
/// # Errors
/// The first figure that cannot be drawn or written, with its path.
pub fn draw(plots: &Plots, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let mut written = Vec::new();
    written.extend(save(&plots.linear_time_response, dir)?);
    written.extend(save(&plots.impact_time_response, dir)?);
    written.extend(save(&plots.transmittance, dir)?);
    written.extend(save(&plots.agreement, dir)?);
    written.extend(save(&plots.frequency_response, dir)?);
    written.extend(save(&plots.beta_family, dir)?);
    written.extend(save(&plots.bifurcation, dir)?);
    if let Some((bandwidth, regimes)) = &plots.maps {
        written.extend(save(bandwidth, dir)?);
        written.extend(save(regimes, dir)?);
    }
    Ok(written)
}

/// Draws the accuracy-versus-cost figures (`work-precision`, `steady-state-cost`) of `study`
/// into `dir`; returns the files written.
///
/// # Errors
/// The first figure that cannot be drawn or written, with its path.
pub fn draw_work_precision(study: &WorkPrecision, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
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

/// Draws the basins figure (`basins`) into `dir`; returns the files written.
///
/// # Errors
/// The figure cannot be drawn or written, with its path.
pub fn draw_basins(figure: &basins::BasinsFigure, dir: &Path) -> Result<Vec<PathBuf>, PlotError> {
    save(figure, dir)
}

/// Draws the Lyapunov figure (`lyapunov`) into `dir`; returns the files written.
///
/// # Errors
/// The figure cannot be drawn or written, with its path.
pub fn draw_lyapunov(
    figure: &lyapunov::LyapunovFigure,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    save(figure, dir)
}

/// Draws the chain figures (`chain-transmission`, `chain-wave`) into `dir`; returns the files
/// written.
///
/// # Errors
/// A figure cannot be drawn or written, with its path.
pub fn draw_chains(
    study: &crate::study::chain::ChainStudy,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let mut written = save(&chain::ChainTransmission(study), dir)?;
    written.extend(save(&chain::ChainWave(study), dir)?);
    Ok(written)
}

/// Draws the Poincaré sections figure (`poincare`) into `dir`; returns the files written.
///
/// # Errors
/// The figure cannot be drawn or written, with its path.
pub fn draw_poincare(
    figure: &poincare::PoincareFigure,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    save(figure, dir)
}

/// Draws the regime boundaries figure (`boundaries`) into `dir`; returns the files written.
///
/// # Errors
/// The figure cannot be drawn or written, with its path.
pub fn draw_boundaries(
    figure: &crate::study::boundaries::BoundariesFigure,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    save(figure, dir)
}

/// Draws the impact dampers' response with and without the free body (`impact-damper`) into
/// `dir`; returns the files written.
///
/// # Errors
/// The figure cannot be drawn or written, with its path.
pub fn draw_impact_damper(
    study: &crate::study::damper::DamperStudy,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    save(study, dir)
}

/// Draws the impact oscillator's bifurcation diagram (`impact-oscillator`) into `dir`; returns
/// the files written.
///
/// # Errors
/// The figure cannot be drawn or written, with its path.
pub fn draw_impact_oscillator(
    study: &crate::study::gallery::OscillatorStudy,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    save(study, dir)
}

/// Draws `broadband-transmission` of the broadband study; returns the paths written.
///
/// # Errors
/// A figure cannot be drawn or written, with its path.
pub fn draw_broadband(
    study: &crate::study::broadband::BroadbandStudy,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    save(&broadband_transmission::BroadbandTransmission(study), dir)
}

/// Draws the figures of non-periodic signals (`tone-burst`, `sweep-up-down`) into `dir`, the
/// sweeps beside the steady states of `chains`' one-cell chain; returns the files written.
///
/// # Errors
/// A figure cannot be drawn or written, with its path.
pub fn draw_signals(
    study: &crate::study::signals::SignalStudy,
    chains: &crate::study::chain::ChainStudy,
    dir: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let mut written = save(&tone_burst::ToneBurst(&study.burst), dir)?;
    written.extend(save(
        &sweep_up_down::SweepUpDown {
            study: &study.sweep,
            steady: chains.curves.iter().find(|c| c.cells == 1),
        },
        dir,
    )?);
    Ok(written)
}
