//! The tables of the one-frequency commands on a scene in the structure form: `rattle
//! simulate`, `rattle orbit --signature` and `rattle compare` (each command's own module
//! computes through [`crate::api`] and hands a structure's record here; `rattle sweep`'s rows
//! are [`crate::runs::structure_sweep`]'s).

use crate::output::structure::{
    StructureAt, StructureCompareRecord, StructureOrbitsRecord, StructureSimulationRecord,
};
use crate::scene::simulator::SimulatedPoint;
use crate::scene::structure::StructureForm;
use rattle_analytic::SequenceOrbit;
use std::fmt::Write as _;

impl StructureForm {
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

/// The table `rattle simulate` prints for a structure's `record` of the run `sim`.
pub(crate) fn simulation_table(
    loaded: &StructureForm,
    omega: f64,
    sim: &SimulatedPoint,
    record: &StructureSimulationRecord,
) -> String {
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
    if let (Some(contacts), Some(time)) =
        (record.contacts_per_period, record.contact_time_per_period)
    {
        let _ = writeln!(
            out,
            "contacts per period: {contacts} (compliant stops), in contact {time:.6e} s per period"
        );
    }
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
    out
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

/// The table `rattle compare` prints for a structure's record `r`.
pub(crate) fn comparison_table(
    loaded: &StructureForm,
    omega: f64,
    r: &StructureCompareRecord,
) -> String {
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
    out
}

/// The table `rattle orbit --signature` prints for a structure's orbits `found` and their
/// `record`.
pub(crate) fn orbits_table(
    loaded: &StructureForm,
    omega: f64,
    found: &[SequenceOrbit],
    record: &StructureOrbitsRecord,
) -> String {
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
    out
}
