//! The one-frequency commands on a scene in the structure form: `rattle simulate`, `rattle
//! orbit --signature` and `rattle compare` (each command's own module hands such a scene
//! here; `rattle sweep`'s is [`crate::runs::structure_sweep`]).

use super::{pretty, RattleError};
use crate::output::finite;
use crate::output::structure::{
    structure_trajectory, StructureAnalyticRecord, StructureAt, StructureSimulationRecord,
};
use crate::output::Format;
use crate::scene::frequency::FrequencyBounds;
use crate::scene::simulator::run_structure;
use crate::scene::structure::StructureForm;
use crate::verdict::structure::{record as compare_record, structure_cross_check};
use rattle_analytic::{sequence_orbits, ImpactSequence};
use rattle_event_driven::trajectory::{final_cycle_trajectory, TrajectoryOptions};
use rattle_event_driven::SimulationOptions;
use serde::Serialize;
use std::fmt::Write as _;

impl StructureForm {
    /// `omega` if the structure can be run at it in bounded time.
    fn check_frequency(&self, omega: f64) -> Result<f64, RattleError> {
        Ok(FrequencyBounds::of_structure(&self.structure).check("--omega", omega)?)
    }

    /// The first line of a table.
    fn heading(&self, omega: f64) -> String {
        let at = StructureAt::new(&self.scene, &self.structure, omega);
        let effects = if at.effects.is_empty() {
            "none (linear, undamped)".to_owned()
        } else {
            at.effects.join(", ")
        };
        format!(
            "structure {} at ω = {omega} rad/s ({} bodies, {} stops; observed: {}); effects: {effects}\n",
            self.scene.name,
            self.structure.dofs(),
            self.structure.stops.len(),
            at.observed
        )
    }

    /// Every body's amplitude as `name = value` words.
    fn bodies(&self, amplitudes: &[f64]) -> String {
        self.structure
            .names
            .iter()
            .zip(amplitudes)
            .map(|(n, a)| format!("{n} = {a:.9}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// `rattle simulate` on a structure: the simulator from rest (or for `periods` periods),
/// reported from the polished cycle when the simulator's Newton polishes it.
///
/// # Errors
/// A frequency outside the structure's bounds; a failure of the simulator.
pub(crate) fn simulate(
    loaded: &StructureForm,
    omega: f64,
    options: &SimulationOptions,
    trajectory: &super::TrajectoryArgs,
    json: bool,
) -> Result<String, RattleError> {
    loaded.check_frequency(omega)?;
    let sim = run_structure(&loaded.structure, omega, &loaded.structure.rest(), options)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    write_trajectory(loaded, &sim, options, trajectory)?;
    let polished = sim.steady.orbit.is_some();
    let record = StructureSimulationRecord::new(&loaded.scene, &loaded.structure, &sim, polished);
    if json {
        return pretty(&record);
    }
    let mut out = loaded.heading(omega);
    out.push_str(&super::status_lines(
        &record.status,
        sim.regime.words(),
        record.period,
    ));
    let _ = writeln!(
        out,
        "impacts per period: {} (by stop: {})",
        sim.steady.impacts_per_period,
        signature_words(&record.pair_impacts_per_period, &record.pair_signatures)
    );
    let _ = writeln!(
        out,
        "amplitudes ({} cycle): {}",
        record.amplitudes_of,
        loaded.bodies(&sim.steady.amplitudes)
    );
    if let Some(t) = record.transmittance_db {
        let _ = writeln!(out, "T = {t:.4} dB (observed body against u_g)");
    }
    if record.family {
        let floating: Vec<&str> = (0..loaded.structure.dofs())
            .filter(|&j| loaded.structure.floating[j].is_some())
            .map(|j| loaded.structure.names[j].as_str())
            .collect();
        let _ = writeln!(
            out,
            "family: no impact, and no spring holds {}: any offset the stops leave room for \
             is as steady as the one this run ended at",
            floating.join(", ")
        );
    }
    let _ = writeln!(
        out,
        "periods run: {}, impacts: {}",
        record.periods_run, record.impacts
    );
    Ok(out)
}

/// Writes `--trajectory` (and `--impacts`) of the final cycle of `sim`, when asked: a column
/// per body and per stop ([`structure_trajectory`]).
fn write_trajectory(
    loaded: &StructureForm,
    sim: &crate::scene::simulator::SimulatedPoint,
    options: &SimulationOptions,
    args: &super::TrajectoryArgs,
) -> Result<(), RattleError> {
    let Some(path) = &args.trajectory else {
        return Ok(());
    };
    let numerical = |e: &dyn std::fmt::Display| RattleError::Numerical(e.to_string());
    let model = loaded
        .structure
        .event_model(sim.omega)
        .map_err(|e| numerical(&e))?;
    let sampled = final_cycle_trajectory(
        &model,
        sim.omega,
        &sim.steady,
        &TrajectoryOptions {
            periods: 1,
            samples_per_period: args.samples_per_period,
            base_amplitude: loaded.structure.base_amplitude.unwrap_or(0.0),
            simulation: options.clone(),
        },
    )
    .map_err(|e| numerical(&e))?;
    let (states, impacts) = structure_trajectory(&loaded.structure, &sampled);
    states.write(path, Format::of(path, "--trajectory")?)?;
    if let Some(path) = &args.impacts {
        impacts.write(path, Format::of(path, "--impacts")?)?;
    }
    Ok(())
}

/// Each stop's impacts per period with its signature, as words.
fn signature_words(per_pair: &[Option<f64>], signatures: &Option<Vec<Option<String>>>) -> String {
    per_pair
        .iter()
        .enumerate()
        .map(|(j, n)| {
            let n = n.map_or("-".to_owned(), |n| n.to_string());
            match signatures.as_ref().and_then(|s| s[j].as_deref()) {
                Some(sig) if !sig.is_empty() => format!("{n} ({sig})"),
                _ => n,
            }
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// `rattle compare` on a structure.
///
/// # Errors
/// A frequency outside the structure's bounds; a failure of the simulator.
pub(crate) fn compare(
    loaded: &StructureForm,
    omega: f64,
    options: &SimulationOptions,
    json: bool,
) -> Result<String, RattleError> {
    loaded.check_frequency(omega)?;
    let check = structure_cross_check(&loaded.structure, omega, options)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let r = compare_record(&loaded.scene, &loaded.structure, &check);
    if json {
        return pretty(&r);
    }
    let mut out = loaded.heading(omega);
    let num = |x: Option<f64>| x.map_or("-".to_owned(), |v| format!("{v:.9}"));
    let _ = writeln!(
        out,
        "simulated from rest: {}, period {}, impacts by stop {}, observed amplitude {}",
        r.simulated.status,
        r.simulated.period.map_or("-".to_owned(), |p| p.to_string()),
        r.simulated
            .pair_signatures
            .as_ref()
            .map_or("-".to_owned(), |s| s
                .iter()
                .map(|x| x.as_deref().unwrap_or("?").to_owned())
                .collect::<Vec<_>>()
                .join(" | ")),
        num(r.simulated.outer_amplitude)
    );
    match &r.analytic {
        Some(a) => {
            let _ = writeln!(
                out,
                "analytic {} orbit from the simulated phases: observed amplitude {}, viable {}, stable {}, energy residual {:.1e}",
                a.sequence,
                num(a.outer_amplitude),
                a.viable,
                a.stable,
                a.energy_residual.unwrap_or(f64::NAN)
            );
        }
        None => {
            let _ = writeln!(
                out,
                "analytic: {}",
                r.analytic_error.as_deref().unwrap_or("nothing to solve")
            );
        }
    }
    out.push_str(&super::class_line(
        r.class,
        &super::detail(&r.class_detail),
        r.relative_difference,
        r.multiplier_difference,
    ));
    Ok(out)
}

/// What `rattle orbit --signature --json` prints for a structure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StructureOrbitsRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: StructureAt,
    /// The impact sequence, canonical.
    pub sequence: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// Every orbit of the sequence the multi-start finds.
    pub orbits: Vec<StructureOrbitRecord>,
}

/// One orbit of a structure's impact sequence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StructureOrbitRecord {
    /// The forcing's phase `θ = ωt + α` at the first impact (`t = 0`), rad in `(−π, π]`: the
    /// base moves as `u_g cos θ`, a force as `F cos(θ + φ)`.
    pub alpha: Option<f64>,
    /// The impacts' times as fractions of the cycle, first 0.
    pub impact_phases: Vec<Option<f64>>,
    /// Each impact's relative velocity just before it, `ṙ⁻`, m/s.
    pub relative_velocities_before: Vec<Option<f64>>,
    /// The orbit's amplitudes, verdicts and multipliers.
    #[serde(flatten)]
    pub orbit: StructureAnalyticRecord,
}

/// A signature as the user writes it for a structure: `<stop><side>` tokens, or with one stop
/// the side characters alone (`+-` reads as `0+ 0-`).
fn sequence_text(text: &str, stops: usize) -> String {
    let bare = !text.is_empty() && text.chars().all(|c| matches!(c, '+' | '-'));
    if stops == 1 && bare {
        text.chars()
            .map(|c| format!("0{c}"))
            .collect::<Vec<_>>()
            .join(" ")
    } else {
        text.to_owned()
    }
}

/// `rattle orbit --signature` on a structure: every orbit of one impact sequence of its stops.
///
/// # Errors
/// A sequence that does not parse, names a stop the structure lacks or a side without a stop
/// ([`RattleError::Argument`]); a failure of the analytic solver.
pub(crate) fn orbits(
    loaded: &StructureForm,
    omega: f64,
    text: &str,
    period: u32,
    json: bool,
) -> Result<String, RattleError> {
    loaded.check_frequency(omega)?;
    let structure = &loaded.structure;
    if structure.stops.is_empty() {
        return Err(RattleError::Argument(format!(
            "--signature: structure '{}' has no stops: it has no impacting orbits",
            loaded.scene.name
        )));
    }
    let argument = |e: &dyn std::fmt::Display| RattleError::Argument(e.to_string());
    let sequence = ImpactSequence::parse(&sequence_text(text, structure.stops.len()), period)
        .map_err(|e| argument(&e))?;
    let model = structure.analytic_model().map_err(|e| argument(&e))?;
    sequence.check(&model).map_err(|e| argument(&e))?;
    let found = sequence_orbits(&model, omega, &sequence)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let record = StructureOrbitsRecord {
        at: StructureAt::new(&loaded.scene, structure, omega),
        sequence: sequence.to_string(),
        period: sequence.period(),
        orbits: found
            .iter()
            .map(|o| StructureOrbitRecord {
                alpha: finite(o.alpha),
                impact_phases: o.impact_phases.iter().map(|&p| finite(p)).collect(),
                relative_velocities_before: o
                    .sequence
                    .impacts()
                    .iter()
                    .zip(&o.states_before_impacts)
                    .map(|(i, x)| {
                        let n = structure.dofs();
                        let w = &model.pairs()[i.pair].direction;
                        finite((0..n).map(|k| w[k] * x[n + k]).sum())
                    })
                    .collect(),
                orbit: StructureAnalyticRecord::new(structure, o),
            })
            .collect(),
    };
    if json {
        return pretty(&record);
    }
    let mut out = loaded.heading(omega);
    let _ = writeln!(
        out,
        "impact sequence {} over {} period(s): {} orbit(s)",
        record.sequence,
        record.period,
        record.orbits.len()
    );
    for (k, (o, r)) in found.iter().zip(&record.orbits).enumerate() {
        let largest = o
            .floquet_multipliers
            .iter()
            .fold(0.0_f64, |a, m| a.max(m.norm()));
        let _ = writeln!(
            out,
            "{k}: α = {:.9}, viable {}, stable {} (max|μ| = {largest:.6}), energy residual {:.1e}; {}",
            o.alpha,
            o.viable,
            o.stable,
            o.energy_residual,
            loaded.bodies(&o.amplitudes)
        );
        if let Some(t) = r.orbit.transmittance_db {
            let _ = writeln!(out, "   T = {t:.4} dB (observed body against u_g)");
        }
    }
    Ok(out)
}
