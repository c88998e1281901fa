//! Non-periodic signals through the scene's cell (the exact response from rest that
//! `rattle respond` runs, [`rattle_event_driven::respond()`]): a Hann tone burst along a
//! short chain, in a pass band and in a stop band of the lattice (`figures/tone-burst`), and a
//! slow linear sine sweep of the single cell up and down the paper's axis
//! (`figures/sweep-up-down`), whose envelopes jump at different frequencies.
//!
//! Both run on the scene's cell damped lightly as the maps and the chains are
//! ([`map_scene`]): without damping the free oscillation a burst or a sweep leaves never
//! decays, and a sweep's envelope is that of the transients rather than of the motion the
//! forcing holds.

use crate::scene::signal::{SignalDescription, SignalSpec};
use crate::scene::Scene;
use crate::study::chain::chain_of;
use crate::study::map_scene;
use rattle_analytic::Cell;
use rattle_analytic::{bloch_wave, stop_bands, StopBand};
use rattle_event_driven::{respond_sampled, Excitation, Response, ResponseOptions};
use serde::Serialize;
use std::f64::consts::TAU;

/// Cells of the chain the tone burst runs along: enough for the stop band's decay to show
/// (the lattice's `|Im q|` of about 1.2 per cell at [`BURST_OMEGAS`]`[1]` takes a wave down
/// by `e^(−4.9)`, about 140 times, over four cells), few enough for every trace to read.
pub const BURST_CELLS: usize = 5;
/// The tone bursts' frequencies, rad/s: 1.1 lies in the lattice's acoustic pass band (below
/// its local-resonance stop band, 1.61–2.12 rad/s for the paper's cell), 1.9 inside that stop
/// band. With [`BURST_CYCLES`] the bursts' main spectral lobes, `ω(1 ± 2/N)`, stay within
/// each band (0.96–1.24 and 1.66–2.14 rad/s).
pub const BURST_OMEGAS: [f64; 2] = [1.1, 1.9];
/// Cycles of each tone burst: enough for the main lobe to fit the stop band (see
/// [`BURST_OMEGAS`]).
pub const BURST_CYCLES: f64 = 16.0;
/// The bursts' amplitude, m: 0.6 of the paper's gap (0.5 m), so that the pass band's burst
/// drives the cells onto their stops while the stop band's, decaying along the chain, leaves
/// the far cells clear of them.
pub const BURST_AMPLITUDE: f64 = 0.3;
/// Duration of each burst's response, s: the longer burst (`2πN/ω` = 91 s at 1.1 rad/s) and
/// about ten of its periods after it, to show the ringing it leaves.
pub const BURST_DURATION: f64 = 150.0;
/// Interval of the traces' samples, s: 60 per period of the fastest burst line
/// (`ω(1 + 1/N)` ≈ 2 rad/s), a smooth curve at the figure's width.
pub const BURST_SAMPLE_STEP: f64 = 0.05;

/// The sweep's range, rad/s: the paper's axis (that of `figures/frequency-response`).
pub const SWEEP_OMEGAS: (f64, f64) = (0.1, 4.0);
/// The sweep's rate, rad/s²: over the unit's jump near 1.2–1.7 rad/s a forcing period (about
/// 4.5 s) changes the frequency by about 0.02 rad/s, slow enough for the envelope to follow
/// the motion the forcing holds (the damped unit's transients decay with a time constant of
/// about `2m_o/c_o` = 40 s) yet keep the whole sweep at 780 s, about a quarter of a second of
/// CPU each way.
pub const SWEEP_RATE: f64 = 0.005;
/// The rate of `--quick`, rad/s²: ten times faster, a smoke test of the pipeline.
const QUICK_SWEEP_RATE: f64 = 0.05;
/// Interval of the sweep's samples, s: 60 per period at the sweep's highest frequency; for a
/// sinusoid the per-cycle maximum of `|u_o|` they give is below the true one by at most
/// `1 − cos(ωΔt/2) ≈ (ωΔt)²/8 = 1.3·10⁻³` of it (about 0.01 dB).
pub const SWEEP_SAMPLE_STEP: f64 = 0.025;
/// A sweep's jump is where its envelope first falls this far below its peak after it, dB:
/// half the amplitude, well beyond the envelope's ripple on either side of the jump (at most
/// a few dB from cycle to cycle).
pub const JUMP_DROP_DB: f64 = 6.0;

/// One tone burst through the chain.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BurstPanel {
    /// The burst's frequency `ω`, rad/s.
    pub omega: f64,
    /// Its cycles `N`.
    pub cycles: f64,
    /// Its amplitude `A`, m.
    pub amplitude: f64,
    /// `2πN/ω`, s: the base is at rest after it.
    pub burst_duration: f64,
    /// Whether `ω` lies in a stop band of the undamped lattice.
    pub in_stop_band: bool,
    /// The damped lattice's attenuation per cell `|Im q|` at `ω`.
    pub lattice_attenuation: f64,
    /// The sample times, s.
    pub times: Vec<f64>,
    /// `u_g(t)` at the sample times, m.
    pub base: Vec<f64>,
    /// `u_o,j(t)` of every cell `j` (from the base) at the sample times, m.
    pub outer: Vec<Vec<f64>>,
    /// Every impact: `(t, cell)`.
    pub impacts: Vec<(f64, usize)>,
    /// `max|u_o,j|` of every cell over the run (exact, between samples too), m.
    pub peaks: Vec<f64>,
    /// Impacts per cell.
    pub impacts_per_cell: Vec<usize>,
}

impl BurstPanel {
    /// `20 log10(max|u_o,N| / max|u_o,1|)`, dB: the attenuation from the first cell to the
    /// last (negative when the last moves less).
    pub fn first_to_last_db(&self) -> f64 {
        match (self.peaks.first(), self.peaks.last()) {
            (Some(&a), Some(&b)) if a > 0.0 => 20.0 * (b / a).log10(),
            _ => f64::NAN,
        }
    }
}

/// The tone bursts of `figures/tone-burst`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToneBurstStudy {
    /// The scene the chain is built of (light damping added when undamped).
    pub scene_name: String,
    /// Cells of the chain.
    pub cells: usize,
    /// The run's duration, s.
    pub duration: f64,
    /// The undamped lattice's stop bands around the bursts.
    pub stop_bands: Vec<StopBand>,
    /// One panel per frequency of [`BURST_OMEGAS`].
    pub panels: Vec<BurstPanel>,
}

/// One direction of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepRun {
    /// The sweep's start, rad/s.
    pub from: f64,
    /// Its end, rad/s.
    pub to: f64,
    /// `(ω, T)` per forcing cycle: the instantaneous frequency at the cycle's middle and
    /// `20 log10(max|u_o|/A)` over the cycle, dB.
    pub envelope: Vec<(f64, f64)>,
    /// The envelope's peak `(ω, T)`.
    pub peak: (f64, f64),
    /// Where the envelope first falls [`JUMP_DROP_DB`] below its peak after it, rad/s.
    pub jump: Option<f64>,
    /// Impacts over the sweep.
    pub impacts: u64,
    /// The constant-frequency segments the sweep is solved as.
    pub segments: usize,
}

/// The sweeps of `figures/sweep-up-down`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepStudy {
    /// The scene swept (light damping added when undamped).
    pub scene_name: String,
    /// The rate `R`, rad/s².
    pub rate: f64,
    /// The amplitude `A` (the scene's `u_g`), m.
    pub amplitude: f64,
    /// `|W2 − W1|/R`, s.
    pub sweep_duration: f64,
    /// Up, from the axis's lowest frequency.
    pub up: SweepRun,
    /// Down, from its highest.
    pub down: SweepRun,
}

impl SweepStudy {
    /// The hysteresis width: the distance between the two sweeps' jumps, rad/s.
    pub fn hysteresis(&self) -> Option<f64> {
        Some(self.up.jump? - self.down.jump?)
    }
}

/// Everything the two figures of non-periodic signals draw.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SignalStudy {
    /// The tone bursts along the chain.
    pub burst: ToneBurstStudy,
    /// The sweeps of the single cell.
    pub sweep: SweepStudy,
}

/// What [`respond_rows`] returns beside the rows: the engine's response and the signal as
/// built.
struct Responded {
    response: Response,
    description: SignalDescription,
}

/// The response of `scene` (the unit or chain form, as `rattle respond` runs it) to the base
/// motion `signal` over `duration`, from rest, sampled every `step`: each row
/// `[t, u_g, u…, u̇…]` to `row`, with the body names.
fn respond_rows(
    scene: &Scene,
    signal: &str,
    duration: f64,
    step: f64,
    row: &mut dyn FnMut(&[String], &[f64]),
) -> Result<Responded, String> {
    let fail = |e: &dyn std::fmt::Display| format!("{}, {signal}: {e}", scene.name);
    let structure = scene
        .structure_scene(scene.base.clone())
        .structure()
        .map_err(|e| fail(&e))?;
    let amplitude = structure.base_amplitude.unwrap_or(1.0);
    let built = SignalSpec::parse(signal)
        .and_then(|spec| spec.build(duration, amplitude))
        .map_err(|e| fail(&e))?;
    // Any valid frequency: the response ignores the model's periodic forcing.
    let model = structure.event_model(1.0).map_err(|e| fail(&e))?;
    let excitation = Excitation::new(
        structure.base_stiffness.clone(),
        structure.base_damping.clone(),
    );
    let samples = (duration / step).round().max(1.0) as u64;
    let names = structure.names.clone();
    let mut values = Vec::with_capacity(2 + 2 * names.len());
    let response = respond_sampled(
        &model,
        &excitation,
        &built.signal,
        &ResponseOptions::over(duration),
        samples,
        &mut |s| {
            values.clear();
            values.push(s.t);
            values.push(built.signal.value_and_rate(s.t).0);
            values.extend_from_slice(s.displacements);
            values.extend_from_slice(s.velocities);
            row(&names, &values);
        },
    )
    .map_err(|e| fail(&e))?;
    Ok(Responded {
        response,
        description: built.description,
    })
}

/// The column of `name`'s displacement in a row `[t, u_g, u…, u̇…]`.
fn displacement_column(names: &[String], name: &str) -> Option<usize> {
    names.iter().position(|n| n == name).map(|k| 2 + k)
}

/// A tone burst at `omega` through `cells` cells of `scene`'s cell.
fn burst_panel(
    scene: &Scene,
    cells: usize,
    omega: f64,
    step: f64,
    bands: &[StopBand],
) -> Result<BurstPanel, String> {
    let chain = chain_of(scene, cells);
    let signal =
        format!("tone-burst:omega={omega},cycles={BURST_CYCLES},amplitude={BURST_AMPLITUDE}");
    let (mut times, mut base) = (Vec::new(), Vec::new());
    let mut outer = vec![Vec::new(); cells];
    let mut columns: Option<Vec<usize>> = None;
    let mut names = Vec::new();
    let record = respond_rows(&chain, &signal, BURST_DURATION, step, &mut |bodies, r| {
        let cols = columns.get_or_insert_with(|| {
            names = bodies.to_vec();
            (0..cells)
                .filter_map(|j| displacement_column(bodies, &format!("outer{j}")))
                .collect()
        });
        times.push(r[0]);
        base.push(r[1]);
        for (series, &c) in outer.iter_mut().zip(cols.iter()) {
            series.push(r[c]);
        }
    })?;
    let peaks = (0..cells)
        .map(|j| {
            displacement_column(&names, &format!("outer{j}"))
                .and_then(|c| record.response.summary.peak.get(c - 2).copied())
                .unwrap_or(f64::NAN)
        })
        .collect();
    let impacts: Vec<(f64, usize)> = record
        .response
        .impacts
        .iter()
        .map(|i| (i.t, i.pair))
        .collect();
    let unit_cell = Cell::of_unit(&map_scene(scene).unit_model());
    let burst_duration = match record.description {
        SignalDescription::ToneBurst { burst_duration, .. } => burst_duration,
        _ => TAU * BURST_CYCLES / omega,
    };
    Ok(BurstPanel {
        omega,
        cycles: BURST_CYCLES,
        amplitude: BURST_AMPLITUDE,
        burst_duration,
        in_stop_band: bands.iter().any(|b| b.lower <= omega && omega <= b.upper),
        lattice_attenuation: bloch_wave(&unit_cell, omega).map_or(f64::NAN, |b| b.attenuation),
        times,
        base,
        outer,
        impacts_per_cell: (0..cells)
            .map(|j| impacts.iter().filter(|i| i.1 == j).count())
            .collect(),
        impacts,
        peaks,
    })
}

/// The tone bursts of [`BURST_OMEGAS`] along [`BURST_CELLS`] cells of `scene`'s cell.
fn tone_bursts(scene: &Scene, quick: bool) -> Result<ToneBurstStudy, String> {
    let damped = map_scene(scene);
    let unit_cell = Cell::of_unit(&damped.unit_model());
    let bands = stop_bands(&unit_cell, SWEEP_OMEGAS.0, SWEEP_OMEGAS.1).unwrap_or_default();
    let step = if quick {
        4.0 * BURST_SAMPLE_STEP
    } else {
        BURST_SAMPLE_STEP
    };
    let (pass, stop) = rayon::join(
        || burst_panel(scene, BURST_CELLS, BURST_OMEGAS[0], step, &bands),
        || burst_panel(scene, BURST_CELLS, BURST_OMEGAS[1], step, &bands),
    );
    Ok(ToneBurstStudy {
        scene_name: damped.name.clone(),
        cells: BURST_CELLS,
        duration: BURST_DURATION,
        stop_bands: bands,
        panels: vec![pass?, stop?],
    })
}

/// Per-cycle envelope of a sweep from `from` at `rate` (signed): cycles of the ideal chirp's
/// phase `φ = from·t ± rate·t²/2`, each giving `(φ'(t_mid), max|u|)`.
struct Envelope {
    from: f64,
    rate: f64,
    cycle: i64,
    start: f64,
    last: f64,
    largest: f64,
    points: Vec<(f64, f64)>,
}

impl Envelope {
    fn new(from: f64, rate: f64) -> Envelope {
        Envelope {
            from,
            rate,
            cycle: 0,
            start: 0.0,
            last: 0.0,
            largest: 0.0,
            points: Vec::new(),
        }
    }

    /// The sample `(t, u)`.
    fn push(&mut self, t: f64, u: f64) {
        let phase = self.from * t + 0.5 * self.rate * t * t;
        let cycle = (phase / TAU).floor() as i64;
        if cycle != self.cycle {
            self.close();
            self.cycle = cycle;
            self.start = t;
            self.largest = 0.0;
        }
        self.last = t;
        self.largest = self.largest.max(u.abs());
    }

    /// Ends the cycle under way (when it has a sample).
    fn close(&mut self) {
        if self.last > self.start {
            let middle = 0.5 * (self.start + self.last);
            self.points
                .push((self.from + self.rate * middle, self.largest));
        }
    }
}

/// The envelope's peak and the first frequency after it where it has fallen
/// [`JUMP_DROP_DB`] below it.
fn peak_and_jump(envelope: &[(f64, f64)]) -> ((f64, f64), Option<f64>) {
    let Some((k, &peak)) = envelope
        .iter()
        .enumerate()
        .max_by(|a, b| a.1 .1.total_cmp(&b.1 .1))
    else {
        return ((f64::NAN, f64::NAN), None);
    };
    let jump = envelope[k..]
        .iter()
        .find(|p| p.1 <= peak.1 - JUMP_DROP_DB)
        .map(|p| p.0);
    (peak, jump)
}

/// One direction of the sweep of `scene` (a single cell).
fn sweep_run(
    scene: &Scene,
    (from, to): (f64, f64),
    rate: f64,
    amplitude: f64,
) -> Result<SweepRun, String> {
    let signal = format!("sweep:from={from},to={to},rate={rate}");
    let duration = (to - from).abs() / rate;
    let mut envelope = Envelope::new(from, rate * (to - from).signum());
    let mut column = None;
    let record = respond_rows(
        scene,
        &signal,
        duration,
        SWEEP_SAMPLE_STEP,
        &mut |names, r| {
            if let Some(c) = *column.get_or_insert_with(|| displacement_column(names, "outer")) {
                envelope.push(r[0], r[c]);
            }
        },
    )?;
    envelope.close();
    let points: Vec<(f64, f64)> = envelope
        .points
        .iter()
        .filter(|p| p.1 > 0.0)
        .map(|&(w, x)| (w, 20.0 * (x / amplitude).log10()))
        .collect();
    let (peak, jump) = peak_and_jump(&points);
    Ok(SweepRun {
        from,
        to,
        envelope: points,
        peak,
        jump,
        impacts: record.response.summary.impacts,
        segments: match record.description {
            SignalDescription::Sweep(s) => s.segments,
            _ => 0,
        },
    })
}

/// The sweeps up and down [`SWEEP_OMEGAS`] of `scene`'s cell.
fn sweeps(scene: &Scene, quick: bool) -> Result<SweepStudy, String> {
    let damped = map_scene(scene);
    let rate = if quick { QUICK_SWEEP_RATE } else { SWEEP_RATE };
    let amplitude = damped.base.amplitude;
    let (lo, hi) = SWEEP_OMEGAS;
    let (up, down) = rayon::join(
        || sweep_run(&damped, (lo, hi), rate, amplitude),
        || sweep_run(&damped, (hi, lo), rate, amplitude),
    );
    Ok(SweepStudy {
        scene_name: damped.name.clone(),
        rate,
        amplitude,
        sweep_duration: (hi - lo) / rate,
        up: up?,
        down: down?,
    })
}

/// The study of non-periodic signals through `scene`'s cell (a single unit with stops);
/// `quick` samples the bursts coarser and sweeps ten times faster.
///
/// # Errors
/// A response that fails, with its signal.
pub fn signal_study(scene: &Scene, quick: bool) -> Result<SignalStudy, String> {
    let (burst, sweep) = rayon::join(|| tone_bursts(scene, quick), || sweeps(scene, quick));
    Ok(SignalStudy {
        burst: burst?,
        sweep: sweep?,
    })
}

/// A number or a dash.
fn num(x: Option<f64>, digits: usize) -> String {
    x.filter(|v| v.is_finite())
        .map_or("—".to_owned(), |v| format!("{v:.digits$}"))
}

/// The report's section on non-periodic signals: the bursts' peak and impacts cell by cell
/// and their attenuation along the chain beside the lattice's, and where the sweeps jump.
pub fn signals_section(study: &SignalStudy) -> String {
    use std::fmt::Write as _;
    let mut out = String::new();
    let b = &study.burst;
    let _ = writeln!(out, "\n## Non-periodic signals\n");
    let _ = writeln!(
        out,
        "The exact response from rest (`rattle respond`) of a chain of {} cells of scene '{}' \
         to a Hann tone burst of {} cycles, amplitude {} m, at each frequency below, over {} s \
         (`figures/tone-burst`). The undamped lattice's stop bands: {}. Peak `max|u_o,j|` of \
         each cell j from the base over the run (m), its impacts in brackets; the chain's \
         decay from the first cell to the last, in all and per cell, beside the damped \
         lattice's `−20 log10(e)·|Im q|` per cell:\n",
        b.cells,
        b.scene_name,
        BURST_CYCLES,
        BURST_AMPLITUDE,
        b.duration,
        b.stop_bands
            .iter()
            .map(|s| format!("{:.2}–{:.2} rad/s", s.lower, s.upper))
            .collect::<Vec<_>>()
            .join(", "),
    );
    let header: Vec<String> = (1..=b.cells).map(|j| format!("cell {j}")).collect();
    let _ = writeln!(
        out,
        "| ω (rad/s) | band | {} | last/first (dB) | per cell (dB) | lattice, per cell (dB) |",
        header.join(" | ")
    );
    let _ = writeln!(out, "|{}", " --- |".repeat(b.cells + 5));
    for p in &b.panels {
        let cells: Vec<String> = p
            .peaks
            .iter()
            .zip(&p.impacts_per_cell)
            .map(|(x, n)| format!("{x:.3} ({n})"))
            .collect();
        let total = p.first_to_last_db();
        let _ = writeln!(
            out,
            "| {} | {} | {} | {} | {} | {} |",
            p.omega,
            if p.in_stop_band { "stop" } else { "pass" },
            cells.join(" | "),
            num(Some(total), 1),
            num(Some(total / (b.cells as f64 - 1.0)), 2),
            num(
                Some(-20.0 * std::f64::consts::LOG10_E * p.lattice_attenuation),
                2
            ),
        );
    }
    let s = &study.sweep;
    let _ = writeln!(
        out,
        "\nA linear sine sweep of scene '{}', amplitude {} m, at {} rad/s² over {}–{} rad/s \
         ({} s each way, {} constant-frequency segments), up from rest and down from rest \
         (`figures/sweep-up-down`): the envelope `T = 20 log10(max|u_o|/A)` over each \
         forcing cycle; the jump is where it first falls {JUMP_DROP_DB} dB below its peak.\n",
        s.scene_name,
        s.amplitude,
        s.rate,
        SWEEP_OMEGAS.0,
        SWEEP_OMEGAS.1,
        num(Some(s.sweep_duration), 0),
        s.up.segments,
    );
    let _ = writeln!(
        out,
        "| sweep | impacts | peak ω (rad/s) | peak T (dB) | jump at ω (rad/s) |"
    );
    let _ = writeln!(out, "| --- | --- | --- | --- | --- |");
    for (name, r) in [("up", &s.up), ("down", &s.down)] {
        let _ = writeln!(
            out,
            "| {name} | {} | {} | {} | {} |",
            r.impacts,
            num(Some(r.peak.0), 3),
            num(Some(r.peak.1), 1),
            num(r.jump, 3),
        );
    }
    let _ = writeln!(
        out,
        "\nHysteresis: the up sweep jumps {} rad/s above the down sweep.",
        num(s.hysteresis(), 3)
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_jump_is_the_first_fall_below_the_peak_after_it() {
        let envelope = [
            (1.0, 0.0),
            (1.1, 10.0),
            (1.2, 20.0),
            (1.3, 16.0),
            (1.4, 13.0),
            (1.5, 18.0),
        ];
        let (peak, jump) = peak_and_jump(&envelope);
        assert_eq!(peak, (1.2, 20.0));
        assert_eq!(jump, Some(1.4));
        assert_eq!(peak_and_jump(&envelope[..4]).1, None);
    }

    #[test]
    fn the_envelope_takes_each_cycle_of_the_chirp() {
        // A sweep from 1 rad/s at 0.01 rad/s²: the phase passes 2π at t ≈ 5.98 s and 4π at
        // t ≈ 11.9 s.
        let mut e = Envelope::new(1.0, 0.01);
        for k in 0..=1100 {
            let t = k as f64 * 0.01;
            e.push(t, if t < 5.0 { 1.0 } else { 2.0 });
        }
        e.close();
        assert_eq!(e.points.len(), 2);
        assert_eq!(e.points[0].1, 2.0);
        assert!((e.points[0].0 - (1.0 + 0.01 * 2.99)).abs() < 1e-3);
    }
}
