//! Motion that never repeats: the chaotic bands of a frequency axis (where the simulator from
//! rest settles on a motion whose largest Lyapunov exponent is positive beyond its
//! uncertainty, with the exponents, for the report), and the Poincaré sections of one such
//! motion (for `figures/poincare`).

use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::scene::lyapunov::{
    chaos, non_periodic_regime, spectrum, Chaos, SpectrumError, SWEEP_LYAPUNOV_PERIODS,
};
use crate::scene::simulator::{model, run, SimulateError};
use crate::scene::Scene;
use rattle_event_driven::Regime as LyapunovRegime;
use rattle_event_driven::{sample_trajectory, RowKind, TrajectoryError, TrajectoryOptions};
use rattle_event_driven::{ModelError, SimulationOptions};
use std::fmt::Write as _;
use thiserror::Error;

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
        let (low, high) = b.exponents;
        let exponents = if b.samples == 1 {
            format!("{low:.3}")
        } else {
            format!("{low:.3}–{high:.3}")
        };
        let _ = writeln!(
            out,
            "| {:.3} | {:.3} | {} | {exponents} | ≤ {:.3} |",
            b.from, b.to, b.samples, b.uncertainty
        );
    }
    out
}

/// Points of each panel of `figures/poincare`: 20 000 sections and as many impacts.
pub const POINCARE_POINTS: usize = 20_000;

/// The chaotic motion of `figures/poincare`: the paper's unit at 1.25 rad/s (the paper's first
/// resonance peak), where the simulator from rest (the command's defaults, 20 000-period cap)
/// settles on a motion that does not repeat, with exponents over 2000 periods
/// `[0.376, −0.013, −0.016, −1.137] ± 0.009`/s (`rattle simulate --omega 1.25 --lyapunov`):
/// chaotic. It lies among the chaotic bands 1.14–1.34 rad/s of `validation/report.md` (whose
/// 0.02 rad/s grid steps over it, and finds the periodic windows 1.20 and 1.26 rad/s).
pub const POINCARE_OMEGA: f64 = 1.25;

/// One impact of the impact map.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImpactPoint {
    /// Base phase at the impact, `ωt mod 2π ∈ [0, 2π)` (the base at `u_g cos ωt`), rad.
    pub phase: f64,
    /// The relative velocity just before, `ṙ⁻`, m/s.
    pub relative_velocity: f64,
    /// `+1` side 1 (`r = +Δ`), `−1` side 2.
    pub side: i8,
}

/// A motion's Poincaré sections with its Lyapunov exponents: the stroboscopic section at
/// `t = kT` and the impact map, over consecutive periods of the settled motion.
#[derive(Debug, Clone, PartialEq)]
pub struct PoincareSections {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The finite exponents, descending, 1/s (the exponents' run after the settling run).
    pub exponents: Vec<f64>,
    /// The uncertainty of the largest, 1/s.
    pub uncertainty: f64,
    /// Directions collapsed by sticking (exponents `−∞`).
    pub collapsed: usize,
    /// Forcing periods of the exponents' run.
    pub lyapunov_periods: u64,
    /// `chaotic`, `quasi-periodic` or `unsettled` for a motion that did not repeat within the
    /// cap; `None` for a periodic one.
    pub regime: Option<&'static str>,
    /// `(u_o, u̇_o)` at `t = kT` (base phase 0), k = 0, 1, …; m and m/s.
    pub sections: Vec<(f64, f64)>,
    /// The impacts over the same stretch, in time order (the first ones, up to the count
    /// asked for).
    pub impacts: Vec<ImpactPoint>,
    /// Forcing periods sampled.
    pub periods: u64,
}

/// Why no sections were computed.
#[derive(Debug, Error)]
pub enum PoincareError {
    /// The scene does not make a valid model.
    #[error("model: {0}")]
    Model(#[from] ModelError),
    /// The settling run failed.
    #[error("{0}")]
    Simulate(#[from] SimulateError),
    /// The exponents' run failed.
    #[error("{0}")]
    Spectrum(#[from] SpectrumError),
    /// The sampled stretch failed.
    #[error("trajectory: {0}")]
    Trajectory(#[from] TrajectoryError),
}

/// The Poincaré sections of the motion `scene` settles in from rest at `omega` (run with
/// `options`, as `rattle simulate`): its exponents over `lyapunov_periods` periods from where
/// the run ended (as `rattle simulate --lyapunov`), then `points` consecutive sections
/// `t = kT` from there and the first `points` impacts of that stretch (fewer when the stretch
/// has fewer), each impact at its base phase with its approach velocity.
///
/// # Errors
/// [`PoincareError`]: a scene that makes no model, a failed run, exponents' run or sampling
/// (e.g. `lyapunov_periods` below the batches, `points` of zero or beyond the sampler's cap).
pub fn poincare_sections(
    scene: &Scene,
    omega: f64,
    points: usize,
    lyapunov_periods: u64,
    options: &SimulationOptions,
) -> Result<PoincareSections, PoincareError> {
    let sim = run(scene, omega, &crate::scene::simulator::rest(scene), options)?;
    let exponents = spectrum(scene, &sim, lyapunov_periods, options)?;
    let regime = non_periodic_regime(&sim, &exponents);
    let m = model(scene, omega)?;
    // One uniform sample per period falls at each section, the first at the start, the last
    // at the end: `points − 1` periods give `points` sections.
    let periods = (points as u64).saturating_sub(1).max(1);
    let trajectory = sample_trajectory(
        &m,
        omega,
        &sim.steady.final_state,
        &TrajectoryOptions {
            periods,
            samples_per_period: 1,
            base_amplitude: scene.base.amplitude,
            simulation: options.clone(),
        },
    )?;
    let sections = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == RowKind::Sample)
        .take(points)
        .map(|r| (r.displacements[0], r.velocities[0]))
        .collect();
    let impacts = trajectory
        .impacts
        .iter()
        .take(points)
        .map(|i| ImpactPoint {
            phase: (omega * (trajectory.phase + i.time)).rem_euclid(std::f64::consts::TAU),
            relative_velocity: i.relative_velocity_before,
            side: i.side,
        })
        .collect();
    Ok(PoincareSections {
        omega,
        uncertainty: exponents.uncertainty,
        collapsed: exponents.collapsed,
        lyapunov_periods,
        regime,
        exponents: exponents.exponents,
        sections,
        impacts,
        periods,
    })
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

    /// A period-1 two-impact motion (the paper's unit at 3 rad/s, `+-`): every section is the
    /// same point, and the impact map holds the simulator's own two impacts of its cycle, at
    /// their phases, alternating sides.
    #[test]
    fn a_periodic_motion_has_one_section_point_and_its_cycle_impacts() {
        let scene = Scene::paper();
        let omega = 3.0;
        let options = SimulationOptions::default();
        let p = poincare_sections(&scene, omega, 40, 100, &options).unwrap();
        assert_eq!(p.regime, None);
        assert_eq!(p.sections.len(), 40);
        let (u0, v0) = p.sections[0];
        let scale = u0.abs().max(v0.abs());
        for &(u, v) in &p.sections {
            // The run ended periodic to its tolerance (1e-9 relative).
            assert!((u - u0).abs() <= 1e-8 * scale && (v - v0).abs() <= 1e-8 * scale);
        }
        let sim = run(
            &scene,
            omega,
            &crate::scene::simulator::rest(&scene),
            &options,
        )
        .unwrap();
        let cycle: Vec<(f64, i8)> = sim
            .steady
            .cycle_impacts
            .iter()
            .map(|i| ((omega * i.phase).rem_euclid(std::f64::consts::TAU), i.side))
            .collect();
        assert_eq!(cycle.len(), 2);
        // 39 periods hold 78 impacts: the first 40 are kept.
        assert_eq!(p.impacts.len(), 40);
        for (k, i) in p.impacts.iter().enumerate() {
            if k > 0 {
                assert_eq!(i.side, -p.impacts[k - 1].side);
            }
            let (phase, side) = cycle.iter().copied().find(|c| c.1 == i.side).unwrap();
            assert_eq!(i.side, side);
            let off = crate::scene::phase::distance(i.phase, phase);
            assert!(off < 1e-8, "{} vs {phase}", i.phase);
            assert!(i.relative_velocity * f64::from(i.side) > 0.0);
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
