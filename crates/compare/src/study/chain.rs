//! The metamaterial study: chains of the scene's cell, linear (closed form by transfer
//! matrices) and impacting (the simulator from rest), their transmittance against frequency
//! beside the infinite lattice's stop bands, and the wave's decay cell by cell.
//!
//! Chains are damped lightly as the maps are ([`map_scene`]): without damping no motion clear
//! of the stops ever settles.

use crate::runs::axis::Axis;
use crate::runs::map::{MAP_MAX_PERIODS, MAP_PERIODICITY_TOLERANCE};
use crate::runs::parallel::{parallel_map, Grain, Progress};
use crate::scene::simulator::{rest, run};
use crate::scene::Scene;
use crate::study::map_scene;
use rattle_analytic::{bloch_wave, stop_bands, StopBand};
use rattle_analytic::{chain_response, Cell};
use rattle_event_driven::SimulationOptions;
use serde::Serialize;

/// Chain lengths of the transmission figure.
pub const CHAIN_LENGTHS: [usize; 4] = [1, 2, 4, 8];
/// Frequencies of the closed-form linear curves over [`CHAIN_OMEGAS`] (cheap: a transfer
/// matrix per cell).
pub const LINEAR_POINTS: usize = 800;
/// Frequencies of the impacting chains (from rest, each run to its steady state or to
/// [`MAP_MAX_PERIODS`]); 60 per chain (step 0.066 rad/s) keep the four chains within about
/// 4 s on two threads (100 took 6.3 s).
pub const IMPACTING_POINTS: usize = 60;
/// The frequency axis of the chain study, rad/s: the paper's.
pub const CHAIN_OMEGAS: (f64, f64) = (0.1, 4.0);
/// Cells of the chain whose wave is followed cell by cell.
pub const WAVE_CELLS: usize = 8;
/// Frequencies of the wave figure, rad/s: 1.9 lies in the lattice's local-resonance stop band
/// (1.61–2.12 rad/s for the paper's cell), where the linear wave decays cell by cell; 1.2 in
/// the pass band below it, where the linear chain transmits.
pub const WAVE_OMEGAS: [f64; 2] = [1.2, 1.9];

/// One frequency of an impacting chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainPoint {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// The last cell's transmittance `20 log10(X_N/u_g)`, dB (`None` without a steady state).
    pub transmittance_db: Option<f64>,
    /// The simulated regime's name.
    pub regime: Option<&'static str>,
    /// `max|u_o,j|` of every cell over the final cycle, m.
    pub cell_outer_amplitudes: Vec<f64>,
}

/// One chain length: the linear curve and the impacting points.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainCurve {
    /// Number of cells.
    pub cells: usize,
    /// `(ω, T)` of the linear chain (stops ignored), dB; unbounded points left out.
    pub linear: Vec<(f64, f64)>,
    /// The impacting chain from rest.
    pub impacting: Vec<ChainPoint>,
}

/// The wave along a chain at one frequency.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainWave {
    /// Angular frequency, rad/s.
    pub omega: f64,
    /// `|U_o,j|` of the linear chain, per cell, m.
    pub linear: Vec<f64>,
    /// The impacting chain from rest: `max|u_o,j|` per cell, m (empty on a failure).
    pub impacting: Vec<f64>,
    /// The simulated regime's name.
    pub regime: Option<&'static str>,
    /// The infinite lattice's attenuation per cell `|Im q|` at this frequency (damped).
    pub lattice_attenuation: f64,
    /// The lattice's decay from the linear chain's first cell: `X_1 e^(−|Im q|(j − 1))`, m.
    pub lattice_decay: Vec<f64>,
}

/// Everything the chain figures draw.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChainStudy {
    /// The scene the chains are built of (light damping added when undamped).
    pub scene_name: String,
    /// The cell's undamped lattice stop bands within [`CHAIN_OMEGAS`].
    pub stop_bands: Vec<StopBand>,
    /// One curve per chain length of [`CHAIN_LENGTHS`].
    pub curves: Vec<ChainCurve>,
    /// The waves of [`WAVE_OMEGAS`] along [`WAVE_CELLS`] cells.
    pub waves: Vec<ChainWave>,
}

/// The simulator's options for the chains: the maps' (a transmittance to about 1e-4, not the
/// last digits; no Newton polish).
pub fn chain_options() -> SimulationOptions {
    SimulationOptions {
        periodicity_tolerance: MAP_PERIODICITY_TOLERANCE,
        max_periods: MAP_MAX_PERIODS,
        polish: false,
        ..SimulationOptions::default()
    }
}

/// `scene`'s cell (damped as [`map_scene`]) repeated `cells` times.
pub fn chain_of(scene: &Scene, cells: usize) -> Scene {
    let mut chain = map_scene(scene);
    chain.chain = None;
    chain.cells = (cells > 1).then_some(cells);
    chain
}

/// The analytic crate's cell of a one-cell scene.
fn cell(scene: &Scene) -> Cell {
    Cell::of_unit(&scene.unit_model())
}

/// The study of chains of `scene`'s cell (`scene` must be a single unit with stops); `quick`
/// runs a few points of everything.
pub fn chain_study(scene: &Scene, quick: bool, progress: bool) -> ChainStudy {
    let (linear_points, impacting_points) = if quick {
        (40, 8)
    } else {
        (LINEAR_POINTS, IMPACTING_POINTS)
    };
    let damped = map_scene(scene);
    let unit_cell = cell(&damped);
    let base = damped.base.amplitude;
    let linear_axis = Axis::new(CHAIN_OMEGAS.0, CHAIN_OMEGAS.1, linear_points).values();
    let impacting_axis = Axis::new(CHAIN_OMEGAS.0, CHAIN_OMEGAS.1, impacting_points).values();
    let options = chain_options();
    let jobs: Vec<(usize, f64)> = CHAIN_LENGTHS
        .iter()
        .flat_map(|&n| impacting_axis.iter().map(move |&w| (n, w)))
        .chain(WAVE_OMEGAS.iter().map(|&w| (WAVE_CELLS, w)))
        .collect();
    let bar = Progress::new("chains", jobs.len(), progress);
    let simulated = parallel_map(&jobs, Grain::Uneven, &bar, |&(n, omega)| {
        let chain = chain_of(scene, n);
        match run(&chain, omega, &rest(&chain), &options) {
            Ok(sim) => ChainPoint {
                omega,
                transmittance_db: sim.transmittance_db,
                regime: Some(sim.regime.name()),
                cell_outer_amplitudes: sim.cell_outer_amplitudes(),
            },
            Err(_) => ChainPoint {
                omega,
                transmittance_db: None,
                regime: None,
                cell_outer_amplitudes: Vec::new(),
            },
        }
    });
    let linear = |n: usize, omega: f64| chain_response(&vec![unit_cell; n], base, omega).ok();
    let curves = CHAIN_LENGTHS
        .iter()
        .enumerate()
        .map(|(k, &n)| ChainCurve {
            cells: n,
            linear: linear_axis
                .iter()
                .filter_map(|&w| {
                    let r = linear(n, w)?;
                    (!r.unbounded && r.transmittance_db.is_finite())
                        .then_some((w, r.transmittance_db))
                })
                .collect(),
            impacting: simulated[k * impacting_points..(k + 1) * impacting_points].to_vec(),
        })
        .collect();
    let waves = WAVE_OMEGAS
        .iter()
        .zip(&simulated[CHAIN_LENGTHS.len() * impacting_points..])
        .map(|(&omega, sim)| {
            let linear = linear(WAVE_CELLS, omega)
                .map(|r| r.cell_outer_amplitudes)
                .unwrap_or_default();
            let attenuation = bloch_wave(&unit_cell, omega)
                .map(|b| b.attenuation)
                .unwrap_or(f64::NAN);
            let first = linear.first().copied().unwrap_or(f64::NAN);
            ChainWave {
                omega,
                lattice_decay: (0..WAVE_CELLS)
                    .map(|j| first * (-attenuation * j as f64).exp())
                    .collect(),
                linear,
                impacting: sim.cell_outer_amplitudes.clone(),
                regime: sim.regime,
                lattice_attenuation: attenuation,
            }
        })
        .collect();
    ChainStudy {
        scene_name: damped.name.clone(),
        stop_bands: stop_bands(&unit_cell, CHAIN_OMEGAS.0, CHAIN_OMEGAS.1).unwrap_or_default(),
        curves,
        waves,
    }
}

/// The frequency bands where `points` (ascending) attenuate, `T < 0` dB, as `(from, to)`
/// runs of consecutive points.
fn attenuating_runs(points: &[(f64, Option<f64>)]) -> Vec<(f64, f64)> {
    let mut runs: Vec<(f64, f64)> = Vec::new();
    let mut open: Option<(f64, f64)> = None;
    for &(w, t) in points {
        match (t.is_some_and(|t| t < 0.0), open) {
            (true, Some((from, _))) => open = Some((from, w)),
            (true, None) => open = Some((w, w)),
            (false, Some(run)) => {
                runs.push(run);
                open = None;
            }
            (false, None) => {}
        }
    }
    runs.extend(open);
    runs
}

fn runs_text(runs: &[(f64, f64)]) -> String {
    if runs.is_empty() {
        return "none".to_owned();
    }
    runs.iter()
        .map(|(a, b)| format!("{a:.2}–{b:.2}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The report's section on chains: the attenuation bands (`T < 0` dB) of each chain, linear
/// and impacting, beside the lattice's stop bands, and the wave's decay along the chain.
pub fn chain_section(study: &ChainStudy) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let _ = writeln!(out, "\n## Chains of the cell (the metamaterial)\n");
    let _ = writeln!(
        out,
        "Chains of N cells of scene '{}' in series, the last cell's transmittance \
         `T = 20 log10(X_N/u_g)` over {}–{} rad/s (`figures/chain-transmission`): the linear \
         chain in closed form (transfer matrices, {} frequencies), the impacting chain \
         simulated from rest ({} frequencies, the maps' periodicity tolerance and cap). The \
         infinite lattice's stop bands (undamped, closed form): {}.\n",
        study.scene_name,
        CHAIN_OMEGAS.0,
        CHAIN_OMEGAS.1,
        study.curves.first().map_or(0, |c| c.linear.len()),
        study.curves.first().map_or(0, |c| c.impacting.len()),
        runs_text(
            &study
                .stop_bands
                .iter()
                .map(|b| (b.lower, b.upper))
                .collect::<Vec<_>>()
        ),
    );
    let _ = writeln!(
        out,
        "| cells | linear: attenuation bands (rad/s) | impacting: attenuation bands (rad/s) |"
    );
    let _ = writeln!(out, "| --- | --- | --- |");
    for c in &study.curves {
        let linear: Vec<(f64, Option<f64>)> = c.linear.iter().map(|&(w, t)| (w, Some(t))).collect();
        let impacting: Vec<(f64, Option<f64>)> = c
            .impacting
            .iter()
            .map(|p| (p.omega, p.transmittance_db))
            .collect();
        let _ = writeln!(
            out,
            "| {} | {} | {} |",
            c.cells,
            runs_text(&attenuating_runs(&linear)),
            runs_text(&attenuating_runs(&impacting))
        );
    }
    let _ = writeln!(
        out,
        "\nThe wave along {WAVE_CELLS} cells (`figures/chain-wave`), outer amplitude of the \
         first and the last cell:\n"
    );
    let _ = writeln!(
        out,
        "| ω (rad/s) | lattice attenuation per cell | linear X_1 → X_N (m) | impacting X_1 → X_N (m), motion |"
    );
    let _ = writeln!(out, "| --- | --- | --- | --- |");
    let ends = |v: &[f64]| match (v.first(), v.last()) {
        (Some(a), Some(b)) => format!("{a:.3e} → {b:.3e}"),
        _ => "—".to_owned(),
    };
    for w in &study.waves {
        let _ = writeln!(
            out,
            "| {} | {:.3} | {} | {}, {} |",
            w.omega,
            w.lattice_attenuation,
            ends(&w.linear),
            ends(&w.impacting),
            w.regime.unwrap_or("failed")
        );
    }
    out
}
