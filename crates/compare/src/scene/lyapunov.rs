//! Lyapunov exponents of a scene's steady motion, and the regime they give a motion that does
//! not repeat (`chaotic`, `quasi-periodic`, `unsettled`).

use crate::scene::simulator::{model, Regime, SimulatedPoint};
use crate::scene::structure::Structure;
use crate::scene::Scene;
use rattle_event_driven::{
    lyapunov_after_steady_state, LyapunovError, LyapunovOptions, LyapunovSpectrum,
    Regime as LyapunovRegime, BATCHES,
};
use rattle_event_driven::{Model, ModelError, SimulationOptions};
use thiserror::Error;

/// Why a scene's exponents were not computed.
#[derive(Debug, Error)]
pub enum SpectrumError {
    /// The scene does not make a valid model.
    #[error("model: {0}")]
    Model(#[from] ModelError),
    /// The exponents' run failed.
    #[error("lyapunov: {0}")]
    Lyapunov(#[from] LyapunovError),
}

/// Forcing periods of an exponents' run below the least the spectrum needs (one per batch of
/// its uncertainty, [`BATCHES`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Error)]
#[error("--lyapunov-periods = {0} is out of range: must be at least {BATCHES}")]
pub struct PeriodsError(pub u64);

/// `periods` if an exponents' run over that many forcing periods can give the spectrum and
/// its uncertainty: at least [`BATCHES`].
///
/// # Errors
/// [`PeriodsError`], naming `--lyapunov-periods` and its range, for fewer.
pub fn check_periods(periods: u64) -> Result<u64, PeriodsError> {
    if periods < BATCHES {
        Err(PeriodsError(periods))
    } else {
        Ok(periods)
    }
}

/// The exponents of the motion `sim` settled in on `scene`, over `periods` more forcing
/// periods from where its run ended.
///
/// # Errors
/// [`SpectrumError::Model`] when the scene makes no valid model, [`SpectrumError::Lyapunov`]
/// when the run fails, `periods` is below the batches or the tangent flow overflows.
pub fn spectrum(
    scene: &Scene,
    sim: &SimulatedPoint,
    periods: u64,
    simulation: &SimulationOptions,
) -> Result<LyapunovSpectrum, SpectrumError> {
    model_spectrum(&model(scene, sim.omega)?, sim, periods, simulation)
}

/// [`spectrum`] on a structure scene: the exponents of the motion `sim` settled in on
/// `structure`, one per state coordinate (two per body).
///
/// # Errors
/// As [`spectrum`].
pub fn structure_spectrum(
    structure: &Structure,
    sim: &SimulatedPoint,
    periods: u64,
    simulation: &SimulationOptions,
) -> Result<LyapunovSpectrum, SpectrumError> {
    model_spectrum(&structure.event_model(sim.omega)?, sim, periods, simulation)
}

/// The exponents' run on the simulator's `model` from where the run of `sim` ended.
fn model_spectrum(
    model: &Model,
    sim: &SimulatedPoint,
    periods: u64,
    simulation: &SimulationOptions,
) -> Result<LyapunovSpectrum, SpectrumError> {
    let options = LyapunovOptions {
        periods,
        simulation: simulation.clone(),
        ..LyapunovOptions::default()
    };
    Ok(lyapunov_after_steady_state(
        model,
        sim.omega,
        &sim.steady,
        &options,
    )?)
}

/// The regime the exponents give the motion, for a motion that did not repeat within the
/// cap only (`None` for a periodic motion, whose multipliers already say all, or a scene
/// without dissipation, which has no attractor).
pub fn non_periodic_regime(
    sim: &SimulatedPoint,
    spectrum: &LyapunovSpectrum,
) -> Option<&'static str> {
    (sim.regime == Regime::Irregular).then(|| spectrum.regime().name())
}

/// Forcing periods of the exponents' run at a non-periodic point of a sweep: the library's
/// default, [`rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS`] (the largest exponent
/// of a chaotic point of the paper's unit known to 3 % of itself).
pub const SWEEP_LYAPUNOV_PERIODS: u64 = rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS;

/// The largest exponent of a motion and, for a motion that does not repeat, its regime: the
/// sweep's and the map's columns.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Chaos {
    /// The largest Lyapunov exponent, 1/s: from the exponents' run for a non-periodic motion,
    /// `log max|μ| / (pT)` of the simulator's own multipliers for a polished periodic one;
    /// `None` otherwise (no dissipation, a periodic cycle Newton could not polish, a failure).
    pub largest_exponent: Option<f64>,
    /// Its uncertainty, 1/s (0 for one from multipliers, exact to Newton's tolerance).
    pub uncertainty: Option<f64>,
    /// `chaotic`, `quasi-periodic` or `unsettled` for a non-periodic motion.
    pub regime: Option<LyapunovRegime>,
}

/// The largest exponent and the regime of `sim` on `scene`. Periodic motions cost nothing
/// (their multipliers are already there: the exponents of a `p`-periodic motion are exactly
/// `log|μ_i|/(pT)`); only a motion that did not repeat gets an exponents' run of `periods`
/// forcing periods (about 1.4× a plain simulation of as many periods). A scene without
/// dissipation has no attractor to characterise and gets none.
///
/// # Errors
/// As [`spectrum`], for a non-periodic motion.
pub fn chaos(
    scene: &Scene,
    sim: &SimulatedPoint,
    periods: u64,
    simulation: &SimulationOptions,
) -> Result<Chaos, SpectrumError> {
    chaos_of(sim, || spectrum(scene, sim, periods, simulation))
}

/// [`chaos`] on a structure scene: the exponents' run, when the motion did not repeat, is
/// [`structure_spectrum`]'s.
///
/// # Errors
/// As [`structure_spectrum`], for a non-periodic motion.
pub fn structure_chaos(
    structure: &Structure,
    sim: &SimulatedPoint,
    periods: u64,
    simulation: &SimulationOptions,
) -> Result<Chaos, SpectrumError> {
    chaos_of(sim, || {
        structure_spectrum(structure, sim, periods, simulation)
    })
}

/// [`chaos`] of `sim`, the exponents' run of a non-periodic motion given by `spectrum`.
fn chaos_of(
    sim: &SimulatedPoint,
    spectrum: impl FnOnce() -> Result<LyapunovSpectrum, SpectrumError>,
) -> Result<Chaos, SpectrumError> {
    match sim.regime {
        Regime::NoDissipation => Ok(Chaos::default()),
        Regime::Irregular => {
            let s = spectrum()?;
            Ok(Chaos {
                largest_exponent: s.largest(),
                uncertainty: s.largest().map(|_| s.uncertainty),
                regime: s.largest().map(|_| s.regime()),
            })
        }
        _ => {
            let largest = sim.steady.orbit.as_ref().and_then(|o| {
                let cycle = f64::from(o.periods) * std::f64::consts::TAU / sim.omega;
                o.floquet_multipliers
                    .iter()
                    .map(|m| m.norm().ln() / cycle)
                    .max_by(f64::total_cmp)
            });
            Ok(Chaos {
                largest_exponent: largest,
                uncertainty: largest.map(|_| 0.0),
                regime: None,
            })
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_periods_are_at_least_the_batches() {
        assert_eq!(check_periods(BATCHES), Ok(BATCHES));
        assert_eq!(
            check_periods(BATCHES - 1).unwrap_err().to_string(),
            format!(
                "--lyapunov-periods = {} is out of range: must be at least {BATCHES}",
                BATCHES - 1
            )
        );
    }
}
