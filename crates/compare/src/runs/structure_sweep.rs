//! Frequency sweeps of a structure scene: at every frequency, in parallel and in frequency
//! order, the linear steady state (`analytic`), the simulator from rest reported from its
//! polished cycle (`event`), or the verdict of `rattle compare` on the structure (`both`); each
//! point one [`StructureSweepRow`].

use crate::output::{finite, number_list, table_row, Header};
use crate::runs::parallel::{for_each_ordered, Progress};
use crate::runs::shard::Shard;
use crate::runs::sweep::Solver;
use crate::scene::simulator::{run_structure, SimulatedPoint};
use crate::scene::structure::{Structure, StructureForm};
use crate::verdict::structure::structure_cross_check;
use rattle_analytic::transmittance_db;
use rattle_event_driven::SimulationOptions;

table_row! {
    /// One frequency of a structure's sweep. A cell is empty (CSV) or `null` (JSON) where it
    /// does not apply to the solver, or is not finite. Lists are `;`-separated, one element
    /// per body (in the scene's order) or per stop (in file order).
    pub struct StructureSweepRow {
        /// Angular frequency, rad/s.
        pub omega: Option<f64>,
        /// The linear steady state's amplitude of the observed body, m (stops ignored; `null`
        /// at an undamped resonance).
        pub linear_outer_amplitude: Option<f64>,
        /// Its transmittance against `u_g`, dB (with a moving base).
        pub linear_transmittance_db: Option<f64>,
        /// Whether the linear motion reaches a stop.
        pub linear_touches_stops: Option<bool>,
        /// The linear amplitude of every body, m: a list.
        pub linear_body_amplitudes: Option<String>,
        /// Simulated regime from rest.
        pub simulated_regime: Option<&'static str>,
        /// Simulator status (`periodic`, `non-periodic`, `no-dissipation`, `, sticking`).
        pub simulated_status: Option<String>,
        /// Least period, forcing periods.
        pub simulated_period: Option<u32>,
        /// Impacts per forcing period over the final cycle, all stops'.
        pub simulated_impacts_per_period: Option<f64>,
        /// Impacts per forcing period of each stop: a list.
        pub simulated_pair_impacts_per_period: Option<String>,
        /// Each stop's canonical signature over the final cycle, `;`-separated (empty for a
        /// stop without impacts; the cell empty when not periodic or sticking).
        pub simulated_pair_signatures: Option<String>,
        /// The observed body's amplitude over the steady cycle, m.
        pub simulated_outer_amplitude: Option<f64>,
        /// Its transmittance against `u_g`, dB (with a moving base).
        pub simulated_transmittance_db: Option<f64>,
        /// Every body's amplitude over the steady cycle, m: a list.
        pub simulated_body_amplitudes: Option<String>,
        /// Whether the amplitudes are of the simulator's polished cycle.
        pub simulated_polished: Option<bool>,
        /// The verdict (`--solver both`).
        pub class: Option<&'static str>,
        /// Why the verdict is not `agreement`, one word.
        pub reason: Option<&'static str>,
        /// The largest relative difference of the two solvers' orbits.
        pub relative_difference: Option<f64>,
        /// The largest distance between the two solvers' Floquet multipliers.
        pub multiplier_difference: Option<f64>,
        /// The analytic orbit's impact sequence (`--solver both`).
        pub analytic_sequence: Option<String>,
        /// Why this frequency failed.
        pub error: Option<String>,
    }
}

impl StructureSweepRow {
    fn empty(omega: f64) -> Self {
        Self {
            omega: finite(omega),
            linear_outer_amplitude: None,
            linear_transmittance_db: None,
            linear_touches_stops: None,
            linear_body_amplitudes: None,
            simulated_regime: None,
            simulated_status: None,
            simulated_period: None,
            simulated_impacts_per_period: None,
            simulated_pair_impacts_per_period: None,
            simulated_pair_signatures: None,
            simulated_outer_amplitude: None,
            simulated_transmittance_db: None,
            simulated_body_amplitudes: None,
            simulated_polished: None,
            class: None,
            reason: None,
            relative_difference: None,
            multiplier_difference: None,
            analytic_sequence: None,
            error: None,
        }
    }

    /// The linear columns.
    fn set_linear(&mut self, s: &Structure, omega: f64) {
        let Ok(model) = s.analytic_model() else {
            return;
        };
        let Ok(state) = model.linear_steady_state(omega) else {
            return;
        };
        let amplitudes: Vec<f64> = state.amplitudes().iter().copied().collect();
        self.linear_outer_amplitude = finite(amplitudes[s.observe]);
        self.linear_transmittance_db = s
            .base_amplitude
            .and_then(|ug| finite(transmittance_db(amplitudes[s.observe], ug)));
        self.linear_touches_stops = Some(crate::verdict::structure::linear_reaches_stops(
            &model, &state,
        ));
        self.linear_body_amplitudes = number_list(&amplitudes);
    }

    /// The simulated columns of `sim` on `s`.
    fn set_simulated(&mut self, s: &Structure, sim: &SimulatedPoint) {
        let pairs = s.stops.len();
        self.simulated_regime = Some(sim.regime.name());
        self.simulated_status = Some(sim.status_name());
        self.simulated_period = sim.steady.period;
        self.simulated_impacts_per_period = finite(sim.steady.impacts_per_period);
        self.simulated_pair_impacts_per_period = number_list(&sim.pair_impacts_per_period(pairs));
        self.simulated_pair_signatures = sim.pair_signatures(pairs).map(|list| {
            list.into_iter()
                .map(|r| match r {
                    Ok(Some(sig)) => sig.to_string(),
                    Ok(None) => String::new(),
                    Err(_) => "?".to_owned(),
                })
                .collect::<Vec<_>>()
                .join(";")
        });
        self.simulated_outer_amplitude = finite(sim.outer_amplitude);
        self.simulated_transmittance_db = sim.transmittance_db.and_then(finite);
        self.simulated_body_amplitudes = number_list(&sim.steady.amplitudes);
        self.simulated_polished = Some(sim.steady.orbit.is_some());
    }
}

/// The row of `solver` on `s` at `omega`.
pub fn structure_point(
    s: &Structure,
    omega: f64,
    solver: Solver,
    options: &SimulationOptions,
) -> StructureSweepRow {
    let mut row = StructureSweepRow::empty(omega);
    row.set_linear(s, omega);
    match solver {
        Solver::Analytic => {}
        Solver::Event => match run_structure(s, omega, &s.rest(), options) {
            Ok(sim) => row.set_simulated(s, &sim),
            Err(e) => row.error = Some(e.to_string()),
        },
        Solver::Both => match structure_cross_check(s, omega, options) {
            Ok(check) => {
                row.set_simulated(s, &check.simulated);
                if let Some(cycle) = &check.polished {
                    row.simulated_body_amplitudes = number_list(&cycle.amplitudes);
                }
                row.class = Some(check.class.name());
                row.reason = check.reason.map(|r| r.name());
                row.relative_difference = check.relative_difference.and_then(finite);
                row.multiplier_difference = check.multiplier_difference.and_then(finite);
                row.analytic_sequence = check.analytic.as_ref().map(|o| o.sequence.to_string());
            }
            Err(e) => row.error = Some(e.to_string()),
        },
    }
    row
}

/// [`structure_point`] at every frequency of `omegas`, in parallel, each row handed to `sink`
/// in frequency order.
///
/// # Errors
/// The first error of `sink`.
pub fn structure_sweep_rows<E>(
    s: &Structure,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
    progress: &Progress,
    sink: impl FnMut(StructureSweepRow) -> Result<(), E>,
) -> Result<(), E> {
    for_each_ordered(
        omegas,
        solver.grain(),
        progress,
        |&omega| structure_point(s, omega, solver, options),
        sink,
    )
}

/// The header of a structure sweep's JSON document: the scene as written, the solver, the
/// bodies' names, the number of frequencies of the whole sweep (`points`) and, for a part of
/// a sharded sweep, which part it is (`shard`, last, as [`crate::runs::sweep::header`] puts
/// it: [`crate::runs::shard::merge`] drops it to compare the parts' headers and write the
/// whole sweep's).
pub fn structure_header(
    form: &StructureForm,
    solver: Solver,
    points: usize,
    shard: Option<Shard>,
) -> Header {
    let mut h = Header::default();
    h.push("scene", &form.scene);
    h.push("form", &"structure");
    h.push("solver", &solver.name());
    h.push("bodies", &form.structure.names);
    h.push("observed", &form.structure.names[form.structure.observe]);
    h.push("points", &points);
    if let Some(s) = shard {
        h.push("shard", &s);
    }
    h
}
