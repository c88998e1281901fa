//! The chaotic bands of a frequency axis: where the simulator from rest settles on a motion
//! whose largest Lyapunov exponent is positive beyond its uncertainty, with the exponents, for
//! the report.

use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::scene::lyapunov::{chaos, Chaos, SWEEP_LYAPUNOV_PERIODS};
use crate::scene::simulator::run;
use crate::scene::Scene;
use rattle_event_driven::lyapunov::Regime as LyapunovRegime;
use rattle_event_driven::SimulationOptions;
use std::fmt::Write as _;

/// One frequency of the axis: the largest exponent of the motion from rest and its regime.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChaosSample {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The exponent, its uncertainty and the regime ([`Chaos`]); default on a failure.
    pub chaos: Chaos,
    /// The simulated transmittance, dB (`None` without a steady state or on a failure).
    pub transmittance_db: Option<f64>,
}

/// The samples of `scene` at `omegas` (the simulator from rest, then [`chaos`] with
/// [`SWEEP_LYAPUNOV_PERIODS`] for a motion that does not repeat), in parallel, in order.
pub fn chaos_samples(
    scene: &Scene,
    omegas: &[f64],
    options: &SimulationOptions,
    progress: &Progress,
) -> Vec<ChaosSample> {
    parallel_map(omegas, Grain::Uneven, progress, |&omega| {
        match run(scene, omega, &crate::scene::simulator::rest(scene), options) {
            Ok(sim) => ChaosSample {
                omega,
                chaos: chaos(scene, &sim, SWEEP_LYAPUNOV_PERIODS, options).unwrap_or_default(),
                transmittance_db: sim.transmittance_db,
            },
            Err(_) => ChaosSample {
                omega,
                chaos: Chaos::default(),
                transmittance_db: None,
            },
        }
    })
}

/// A run of consecutive chaotic samples.
#[derive(Debug, Clone, PartialEq)]
pub struct ChaoticBand {
    /// First and last chaotic frequency of the run, rad/s.
    pub from: f64,
    /// Last chaotic frequency.
    pub to: f64,
    /// Samples in the run.
    pub samples: usize,
    /// The smallest and largest of their largest exponents, 1/s.
    pub exponents: (f64, f64),
    /// The largest uncertainty among them, 1/s.
    pub uncertainty: f64,
}

/// The chaotic bands of `samples` (ascending frequency): each maximal run of samples whose
/// regime is [`LyapunovRegime::Chaotic`].
pub fn chaotic_bands(samples: &[ChaosSample]) -> Vec<ChaoticBand> {
    let mut bands: Vec<ChaoticBand> = Vec::new();
    let mut open = false;
    for s in samples {
        let chaotic = s.chaos.regime == Some(LyapunovRegime::Chaotic);
        match (chaotic, s.chaos.largest_exponent) {
            (true, Some(l)) => {
                let u = s.chaos.uncertainty.unwrap_or(f64::NAN);
                match bands.last_mut() {
                    Some(b) if open => {
                        b.to = s.omega;
                        b.samples += 1;
                        b.exponents = (b.exponents.0.min(l), b.exponents.1.max(l));
                        b.uncertainty = b.uncertainty.max(u);
                    }
                    _ => bands.push(ChaoticBand {
                        from: s.omega,
                        to: s.omega,
                        samples: 1,
                        exponents: (l, l),
                        uncertainty: u,
                    }),
                }
                open = true;
            }
            _ => open = false,
        }
    }
    bands
}

/// The chaotic bands as a Markdown section body: one table row per band (frequencies, samples,
/// range of the largest exponent, largest uncertainty), or a sentence when there is none.
pub fn chaotic_bands_text(samples: &[ChaosSample]) -> String {
    let bands = chaotic_bands(samples);
    let chaotic: usize = bands.iter().map(|b| b.samples).sum();
    let mut out = format!(
        "{chaotic} of {} frequencies settle from rest on a chaotic motion (largest Lyapunov \
         exponent positive beyond its uncertainty, {SWEEP_LYAPUNOV_PERIODS} periods).\n",
        samples.len()
    );
    if bands.is_empty() {
        return out;
    }
    out += "\n| ω from (rad/s) | ω to (rad/s) | samples | largest exponent λ₁ (1/s) | uncertainty (1/s) |\n";
    out += "| --- | --- | --- | --- | --- |\n";
    for b in &bands {
        let _ = writeln!(
            out,
            "| {:.3} | {:.3} | {} | {:.3}–{:.3} | ≤ {:.3} |",
            b.from, b.to, b.samples, b.exponents.0, b.exponents.1, b.uncertainty
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample(omega: f64, regime: Option<LyapunovRegime>, l: f64) -> ChaosSample {
        ChaosSample {
            omega,
            chaos: Chaos {
                largest_exponent: Some(l),
                uncertainty: Some(0.01),
                regime,
            },
            transmittance_db: None,
        }
    }

    #[test]
    fn consecutive_chaotic_samples_make_one_band() {
        let c = Some(LyapunovRegime::Chaotic);
        let samples = [
            sample(1.0, c, 0.2),
            sample(1.1, c, 0.4),
            sample(1.2, None, -0.1),
            sample(1.3, c, 0.3),
        ];
        let bands = chaotic_bands(&samples);
        assert_eq!(bands.len(), 2);
        assert_eq!(
            (bands[0].from, bands[0].to, bands[0].samples),
            (1.0, 1.1, 2)
        );
        assert_eq!(bands[0].exponents, (0.2, 0.4));
        assert_eq!((bands[1].from, bands[1].to), (1.3, 1.3));
        assert!(chaotic_bands_text(&samples).contains("| 1.000 | 1.100 | 2 |"));
    }
}
