//! `rattle respond --json`: the response to a signal from rest, as one document, and the
//! columns of its uniformly sampled table.

use crate::output::finite;
use crate::output::records::ByBody;
use crate::scene::signal::{Input, SignalDescription};
use crate::scene::structure::Structure;
use rattle_event_driven::{Response, ResponseState};
use serde::Serialize;

/// One impact of the response.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RespondImpact {
    /// Its time, s.
    pub t: f64,
    /// The stop (the structure's stop index, the cell of a unit or a chain).
    pub pair: usize,
    /// `1`: the `+gap` side, `2`: the `−gap` side.
    pub side: u8,
    /// The stop's relative velocity just before, m/s.
    pub relative_velocity_before: f64,
}

/// A stop coming to rest on its stop (a stick) or leaving it (a release).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RespondHold {
    /// Its time, s.
    pub t: f64,
    /// The stop.
    pub pair: usize,
    /// `1`: the `+gap` side, `2`: the `−gap` side.
    pub side: u8,
    /// `true`: a stick, `false`: a release.
    pub stick: bool,
}

/// What the run amounts to over `[0, T]`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RespondSummary {
    /// Impacts.
    pub impacts: u64,
    /// Sticks (a stop coming to rest on its stop).
    pub sticks: u64,
    /// Releases.
    pub releases: u64,
    /// Grazes (touches without an approach).
    pub grazes: u64,
    /// Every body's `√(∫₀ᵀ u² dt / T)` by name, m.
    pub rms: ByBody,
    /// Every body's `max |u|` over `[0, T]` by name, m.
    pub peak: ByBody,
    /// `∫₀ᵀ u̇ᵀ C u̇ dt + Σ` impacts' and sticks' kinetic energy lost, J.
    pub energy_dissipated: f64,
    /// The dashpots' share of it, J.
    pub dissipated_by_dashpots: f64,
    /// The impacts' and sticks' share of it, J.
    pub dissipated_by_impacts: f64,
    /// `∫₀ᵀ f(t)ᵀ u̇ dt`, the work of the forcing (`f = K_b u_g + C_b u̇_g` for a base
    /// motion), J.
    pub work: f64,
    /// `E(T) = ½u̇ᵀMu̇ + ½uᵀKu`, J.
    pub final_energy: f64,
    /// `work − E(T) − energy_dissipated`, J: zero up to the quadratures' and the contact
    /// times' accuracy.
    pub energy_balance_residual: f64,
}

/// `rattle respond --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RespondRecord {
    /// Scene name.
    pub scene: String,
    /// The bodies, in the order of every state's lists.
    pub bodies: Vec<String>,
    /// `base` (a base displacement through the springs and dashpots tied to the base) or
    /// `force` (a force on the body `on`).
    pub input: Input,
    /// The body a force acts on (`null` for a base motion).
    pub on: Option<String>,
    /// `T`, s.
    pub duration: f64,
    /// The signal: its kind, parameters and derived numbers.
    pub signal: SignalDescription,
    /// The time scale the contact thresholds are relative to, s.
    pub time_scale: f64,
    /// Every impact, in time order.
    pub impacts: Vec<RespondImpact>,
    /// Every stick and release, in time order.
    pub holds: Vec<RespondHold>,
    /// The states at `--at`, in the order given.
    pub at: Vec<ResponseState>,
    /// The state at `T`.
    pub final_state: ResponseState,
    /// The summary.
    pub summary: RespondSummary,
}

impl RespondRecord {
    /// The record of `response` of `structure` (named `scene`) to the signal `description`
    /// acting as `input` (on the body `on`).
    pub fn new(
        scene: &str,
        structure: &Structure,
        (input, on): (Input, Option<String>),
        description: SignalDescription,
        response: &Response,
    ) -> RespondRecord {
        let s = &response.summary;
        let dissipated = s.dissipated_by_dashpots + s.dissipated_by_impacts;
        RespondRecord {
            scene: scene.to_owned(),
            bodies: structure.names.clone(),
            input,
            on,
            duration: response.duration,
            signal: description,
            time_scale: response.time_scale,
            impacts: response
                .impacts
                .iter()
                .map(|i| RespondImpact {
                    t: i.t,
                    pair: i.pair,
                    side: i.side,
                    relative_velocity_before: i.relative_velocity_before,
                })
                .collect(),
            holds: response
                .holds
                .iter()
                .map(|h| RespondHold {
                    t: h.t,
                    pair: h.pair,
                    side: h.side,
                    stick: h.stick,
                })
                .collect(),
            at: response.states.clone(),
            final_state: response.final_state.clone(),
            summary: RespondSummary {
                impacts: s.impacts,
                sticks: s.sticks,
                releases: s.releases,
                grazes: s.grazes,
                rms: ByBody::new(structure, &s.rms),
                peak: ByBody::new(structure, &s.peak),
                energy_dissipated: dissipated,
                dissipated_by_dashpots: s.dissipated_by_dashpots,
                dissipated_by_impacts: s.dissipated_by_impacts,
                work: s.work,
                final_energy: s.final_energy,
                energy_balance_residual: s.energy_imbalance(),
            },
        }
    }

    /// The largest of `|work|`, `E(T)` and the energy dissipated: the scale of the residual.
    pub fn energy_scale(&self) -> f64 {
        let s = &self.summary;
        s.work.abs().max(s.final_energy).max(s.energy_dissipated)
    }
}

/// The columns of the sampled table: `t`, the signal (`u_g` or `F`), then `u:NAME` and
/// `v:NAME` of every body.
pub fn sample_columns(structure: &Structure, input: Input) -> Vec<String> {
    let mut columns = vec!["t".to_owned(), input.column().to_owned()];
    columns.extend(structure.names.iter().map(|n| format!("u:{n}")));
    columns.extend(structure.names.iter().map(|n| format!("v:{n}")));
    columns
}

/// One row of the sampled table as cells: `t`, the signal's value, the displacements and
/// the velocities.
pub fn sample_cells(values: &[f64]) -> Vec<crate::output::structure::Cell> {
    values
        .iter()
        .map(|&x| crate::output::structure::Cell::Number(finite(x)))
        .collect()
}
