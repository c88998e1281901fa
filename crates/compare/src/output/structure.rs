//! The records of a structure scene: what `rattle simulate --json`, `rattle compare --json`
//! and `rattle orbit --signature --json` print for a scene in the structure form, and the
//! tables of its trajectories (`--trajectory`, `--impacts`), simulated or analytic. Every body
//! is named by the scene's own name for it.

use crate::output::finite;
use crate::output::records::{multipliers, ByBody, ChainConfirmationRecord};
use crate::scene::analytic::{OrbitImpact, OrbitSample, SampleKind};
use crate::scene::simulator::SimulatedPoint;
use crate::scene::structure::{Structure, StructureScene};
use rattle_analytic::SequenceOrbit;
use serde::ser::{Serialize, SerializeMap, Serializer};

/// Where a structure's result was computed.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StructureAt {
    /// Scene name.
    pub scene: String,
    /// The scene's form: `structure`.
    pub form: &'static str,
    /// Angular frequency, rad/s.
    pub omega: Option<f64>,
    /// The structure's active effects: `stops`, `damping`, `harmonics`.
    pub effects: Vec<&'static str>,
    /// The observed body: the one behind `outer_amplitude` and `transmittance_db`.
    pub observed: String,
    /// The forcing's higher harmonics as the scene gives them (absent: the fundamental alone).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub harmonics: Vec<HarmonicRecord>,
}

/// One higher harmonic of a structure's forcing, as the scene gives it:
/// `amplitude · cos(order · ωt + phase)` of the base motion or of a force.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct HarmonicRecord {
    /// What it drives: `base`, or the body a force acts on.
    pub on: String,
    /// The order `k ≥ 2`.
    pub order: u32,
    /// Its amplitude: m for the base, N for a force.
    pub amplitude: f64,
    /// Its phase against the fundamental's `ωt`, rad.
    pub phase: f64,
}

impl HarmonicRecord {
    /// Every harmonic of `scene`'s forcing: the base's, then each force's, in file order.
    pub fn of(scene: &StructureScene) -> Vec<HarmonicRecord> {
        let record = |on: &str, h: &crate::scene::HarmonicSpec| HarmonicRecord {
            on: on.to_owned(),
            order: h.order,
            amplitude: h.amplitude,
            phase: h.phase,
        };
        let base = scene.forcing.base.iter().flat_map(|b| {
            b.harmonics
                .iter()
                .map(|h| record(crate::scene::structure::BASE, h))
        });
        let forces = scene
            .forcing
            .forces
            .iter()
            .flat_map(|f| f.harmonics.iter().map(|h| record(&f.on, h)));
        base.chain(forces).collect()
    }
}

impl StructureAt {
    /// `scene` at `omega`.
    pub fn new(scene: &StructureScene, structure: &Structure, omega: f64) -> Self {
        let mut effects = Vec::new();
        if !structure.stops.is_empty() {
            effects.push("stops");
        }
        if structure.is_damped() {
            effects.push("damping");
        }
        if !structure.harmonics.is_empty() {
            effects.push("harmonics");
        }
        Self {
            scene: scene.name.clone(),
            form: "structure",
            omega: finite(omega),
            effects,
            observed: structure.names[structure.observe].clone(),
            harmonics: HarmonicRecord::of(scene),
        }
    }
}

/// The transmittance `20 log10(X / u_g)` of the observed body's amplitude `X`, when the base
/// moves.
fn transmittance(structure: &Structure, amplitudes: &[f64]) -> Option<f64> {
    structure.transmittance_db(*amplitudes.get(structure.observe)?)
}

/// What `rattle simulate --json` prints for a structure.
///
/// # Examples
///
/// ```
/// use rattle_compare::api::{self, Simulation};
/// use rattle_event_driven::SimulationOptions;
///
/// let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/impact-oscillator.json");
/// let scene = api::load(path)?;
/// let Simulation::Structure { record, .. } =
///     api::simulate(&scene, 1.5, &SimulationOptions::default())?
/// else {
///     unreachable!("a scene of the structure form")
/// };
/// // One entry per stop, every body named by the scene's name for it.
/// assert_eq!(record.pair_impacts_per_period.len(), 1);
/// let json = serde_json::to_value(&record).unwrap();
/// assert!(json["body_amplitudes"].is_object());
/// # Ok::<(), rattle_compare::api::ApiError>(())
/// ```
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StructureSimulationRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: StructureAt,
    /// `periodic`, `non-periodic` or `no-dissipation`, `, sticking` appended when the final
    /// cycle sticks.
    pub status: String,
    /// The regime's name.
    pub regime: &'static str,
    /// Least period in forcing periods, when periodic.
    pub period: Option<u32>,
    /// Impacts per forcing period over the final cycle.
    pub impacts_per_period: Option<f64>,
    /// Impacts per forcing period of each stop (contact pair, in file order).
    pub pair_impacts_per_period: Vec<Option<f64>>,
    /// Each stop's canonical impact signature over the final cycle (`""` for a stop without
    /// impacts, `null` for one beyond what a signature holds; the list `null` when not
    /// periodic or sticking); a compliant stop's contact phases marked `c` (`+c-c`).
    pub pair_signatures: Option<Vec<Option<String>>>,
    /// Contact phases of compliant stops per forcing period over the final cycle (only for a
    /// structure with compliant stops; rigid impacts are `impacts_per_period`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contacts_per_period: Option<f64>,
    /// Time in contact with compliant stops per forcing period over the final cycle, s
    /// (summed over stops; only for a structure with compliant stops).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_time_per_period: Option<f64>,
    /// `max |u|` of the observed body over the steady cycle, m.
    pub outer_amplitude: Option<f64>,
    /// `20 log10(outer_amplitude / u_g)`; `null` without a moving base or a steady state.
    pub transmittance_db: Option<f64>,
    /// `max |u|` of every body over the steady cycle, m, by name.
    pub body_amplitudes: ByBody,
    /// Which cycle the amplitudes are of: `polished` (one cycle run from the simulator's own
    /// Newton-polished periodic orbit) or `final` (the last simulated cycle, when there is no
    /// polished orbit).
    pub amplitudes_of: &'static str,
    /// Whether the final cycle sticks.
    pub sticking: bool,
    /// Why the run ended.
    pub stopped_by: &'static str,
    /// Forcing periods simulated.
    pub periods_run: u64,
    /// Impacts over the run.
    pub impacts: u64,
    /// The simulator's own Floquet multipliers `[re, im]` of the polished cycle.
    pub floquet_multipliers: Option<Vec<[Option<f64>; 2]>>,
    /// Why the cycle could not be polished, when it could not.
    pub orbit_error: Option<String>,
    /// Whether the motion is one member of a family: periodic without impacts on a structure
    /// with floating bodies (no spring holds them), which keep whatever offset the run left
    /// them at. Any offset the stops leave room for is as steady, so their amplitudes are one
    /// member's.
    pub family: bool,
}

impl StructureSimulationRecord {
    /// The record of `sim` on `structure`; `polished` says whether its amplitudes are those
    /// of the polished cycle.
    pub fn new(
        scene: &StructureScene,
        structure: &Structure,
        sim: &SimulatedPoint,
        polished: bool,
    ) -> Self {
        let s = &sim.steady;
        let pairs = structure.stops.len();
        Self {
            at: StructureAt::new(scene, structure, sim.omega),
            status: sim.status_name(),
            regime: sim.regime.name(),
            period: s.period,
            impacts_per_period: finite(s.impacts_per_period),
            pair_impacts_per_period: sim
                .pair_impacts_per_period(pairs)
                .into_iter()
                .map(finite)
                .collect(),
            pair_signatures: signatures(sim, pairs),
            contacts_per_period: structure
                .has_compliant_stops()
                .then(|| sim.contacts_per_period()),
            contact_time_per_period: structure
                .has_compliant_stops()
                .then_some(s.contact_time_per_period),
            outer_amplitude: finite(sim.outer_amplitude),
            transmittance_db: sim.transmittance_db.and_then(finite),
            body_amplitudes: ByBody::new(structure, &s.amplitudes),
            amplitudes_of: if polished { "polished" } else { "final" },
            sticking: s.sticking,
            stopped_by: sim.stopped_by(),
            periods_run: s.periods_run,
            impacts: s.impacts,
            floquet_multipliers: s
                .orbit
                .as_ref()
                .map(|o| multipliers(&o.floquet_multipliers)),
            orbit_error: s.orbit_error.clone(),
            family: s.family,
        }
    }
}

/// Each pair's signature as text (`""` without impacts, `null` beyond a signature).
pub fn signatures(sim: &SimulatedPoint, pairs: usize) -> Option<Vec<Option<String>>> {
    sim.pair_signatures(pairs).map(|list| {
        list.into_iter()
            .map(|r| r.ok().map(|s| s.map(|s| s.to_string()).unwrap_or_default()))
            .collect()
    })
}

/// The simulated side of a structure's cross-check.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StructureSimulatedRecord {
    /// As [`StructureSimulationRecord::status`].
    pub status: String,
    /// Least period, when periodic.
    pub period: Option<u32>,
    /// Each stop's signature, as [`StructureSimulationRecord::pair_signatures`].
    pub pair_signatures: Option<Vec<Option<String>>>,
    /// Impacts per forcing period.
    pub impacts_per_period: Option<f64>,
    /// Contact phases of compliant stops per forcing period (only for a structure with
    /// compliant stops).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contacts_per_period: Option<f64>,
    /// Time in contact with compliant stops per forcing period, s (only for a structure with
    /// compliant stops).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub contact_time_per_period: Option<f64>,
    /// The observed body's amplitude, m.
    pub outer_amplitude: Option<f64>,
    /// Every body's amplitude over the polished cycle (the final cycle without one), m.
    pub body_amplitudes: ByBody,
    /// The simulator's own Floquet multipliers.
    pub floquet_multipliers: Option<Vec<[Option<f64>; 2]>>,
}

/// The analytic side of a structure's cross-check: the orbit of the simulated sequence.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StructureAnalyticRecord {
    /// The impact sequence, canonical (`0+ 1- …`).
    pub sequence: String,
    /// Forcing periods per cycle.
    pub period: u32,
    /// The observed body's amplitude, m.
    pub outer_amplitude: Option<f64>,
    /// `20 log10(outer_amplitude / u_g)`, when the base moves.
    pub transmittance_db: Option<f64>,
    /// Every body's amplitude, m, from rigorous extrema.
    pub body_amplitudes: ByBody,
    /// No contact condition violated.
    pub viable: bool,
    /// Every multiplier inside the unit circle.
    pub stable: bool,
    /// The analytic Floquet multipliers.
    pub floquet_multipliers: Vec<[Option<f64>; 2]>,
    /// The cycle's energy residual, relative.
    pub energy_residual: Option<f64>,
}

impl StructureAnalyticRecord {
    /// The record of the analytic `orbit` on `structure`.
    pub fn new(structure: &Structure, orbit: &SequenceOrbit) -> Self {
        Self {
            sequence: orbit.sequence.to_string(),
            period: orbit.period,
            outer_amplitude: orbit
                .amplitudes
                .get(structure.observe)
                .copied()
                .and_then(finite),
            transmittance_db: transmittance(structure, &orbit.amplitudes),
            body_amplitudes: ByBody::new(structure, &orbit.amplitudes),
            viable: orbit.viable,
            stable: orbit.stable,
            floquet_multipliers: multipliers(&orbit.floquet_multipliers),
            energy_residual: finite(orbit.energy_residual),
        }
    }
}

/// What `rattle compare --json` prints for a structure scene.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct StructureCompareRecord {
    /// The scene and the frequency.
    #[serde(flatten)]
    pub at: StructureAt,
    /// The simulator from rest.
    pub simulated: StructureSimulatedRecord,
    /// The analytic orbit of the simulated impact sequence; `null` when there is none to look
    /// for or the analytic solver finds none (`analytic_error`).
    pub analytic: Option<StructureAnalyticRecord>,
    /// Why the analytic solver found no orbit of the simulated sequence.
    pub analytic_error: Option<String>,
    /// `agreement`, `contradiction` or `beyond`.
    pub class: &'static str,
    /// Why the class is not `agreement`, one word (as for a chain); `null` for an agreement.
    pub reason: Option<&'static str>,
    /// The reason in words.
    pub class_detail: String,
    /// The largest relative difference of the two solvers' orbits: the state before the first
    /// impact of the sequence, every body's amplitude, the impact phases and the forcing phase
    /// at the first impact over π (without impacts: every body's amplitude against the linear
    /// steady state's).
    pub relative_difference: Option<f64>,
    /// The largest distance between the two solvers' Floquet multipliers, matched one to one.
    pub multiplier_difference: Option<f64>,
    /// The viable analytic orbit confirmed by the simulator's Newton started on it.
    pub confirmation: Option<ChainConfirmationRecord>,
}

/// A table whose columns are named at run time (a structure's bodies and stops): its column
/// names and rows of cells, each a number (`None`: empty or `null`) or a word.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedTable {
    /// The column names, in order.
    pub columns: Vec<String>,
    /// The rows, each with one cell per column.
    pub rows: Vec<Vec<Cell>>,
}

/// One cell of a [`NamedTable`].
#[derive(Debug, Clone, PartialEq)]
pub enum Cell {
    /// A number (`None`: not finite, written empty or `null`).
    Number(Option<f64>),
    /// A word.
    Word(&'static str),
    /// A count.
    Count(usize),
}

impl Serialize for Cell {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match self {
            Cell::Number(x) => x.serialize(serializer),
            Cell::Word(w) => w.serialize(serializer),
            Cell::Count(n) => n.serialize(serializer),
        }
    }
}

impl Cell {
    /// The cell as CSV text: a number as JSON writes it (it reads back bit for bit), empty
    /// when not finite.
    fn text(&self) -> String {
        match self {
            Cell::Number(x) => x
                .and_then(serde_json::Number::from_f64)
                .map_or_else(String::new, |n| n.to_string()),
            Cell::Word(w) => (*w).to_owned(),
            Cell::Count(n) => n.to_string(),
        }
    }
}

/// One row of a [`NamedTable`] as a JSON object, its cells in column order.
struct NamedRow<'a>(&'a [String], &'a [Cell]);

impl Serialize for NamedRow<'_> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let mut map = serializer.serialize_map(Some(self.0.len()))?;
        for (name, cell) in self.0.iter().zip(self.1) {
            map.serialize_entry(name, cell)?;
        }
        map.end()
    }
}

impl NamedTable {
    /// Writes the table to `path` in `format`: CSV (a line of column names, a line per row),
    /// JSON (`{"results": [ {column: cell, …}, … ]}`) or JSON Lines (an object per line).
    ///
    /// # Errors
    /// [`crate::output::OutputError::Io`] when the file cannot be written.
    pub fn write(
        &self,
        path: &std::path::Path,
        format: crate::output::Format,
    ) -> Result<(), crate::output::OutputError> {
        let io = |source| crate::output::OutputError::Io {
            path: path.to_owned(),
            source,
        };
        let file = std::fs::File::create(path).map_err(io)?;
        let mut out =
            NamedWriter::new(format, std::io::BufWriter::new(file), &self.columns).map_err(io)?;
        for row in &self.rows {
            out.row(row).map_err(io)?;
        }
        out.finish().map_err(io)
    }
}

/// Writes the rows of a table whose columns are named at run time, one at a time as they
/// come: CSV (a line of column names, a line per row), JSON (`{"results": [ {column: cell,
/// …}, … ]}`, a row per line) or JSON Lines (an object per line).
pub struct NamedWriter<W: std::io::Write> {
    format: crate::output::Format,
    columns: Vec<String>,
    csv: Option<::csv::Writer<W>>,
    out: Option<W>,
    rows: usize,
}

impl<W: std::io::Write> NamedWriter<W> {
    /// Starts the table of `columns` on `out` in `format`.
    ///
    /// # Errors
    /// The writer's.
    pub fn new(
        format: crate::output::Format,
        mut out: W,
        columns: &[String],
    ) -> std::io::Result<Self> {
        use crate::output::Format;
        let mut writer = NamedWriter {
            format,
            columns: columns.to_vec(),
            csv: None,
            out: None,
            rows: 0,
        };
        match format {
            Format::Csv => {
                let mut csv = ::csv::WriterBuilder::new()
                    .has_headers(false)
                    .from_writer(out);
                csv.write_record(columns)?;
                writer.csv = Some(csv);
            }
            Format::Json => {
                write!(out, "{{\"results\":[")?;
                writer.out = Some(out);
            }
            Format::JsonLines => writer.out = Some(out),
        }
        Ok(writer)
    }

    /// Writes one row, a cell per column.
    ///
    /// # Errors
    /// The writer's.
    pub fn row(&mut self, row: &[Cell]) -> std::io::Result<()> {
        use crate::output::Format;
        self.rows += 1;
        if let Some(csv) = self.csv.as_mut() {
            return Ok(csv.write_record(row.iter().map(Cell::text))?);
        }
        let json =
            serde_json::to_string(&NamedRow(&self.columns, row)).map_err(std::io::Error::other)?;
        let Some(out) = self.out.as_mut() else {
            return Ok(());
        };
        match self.format {
            Format::Json => {
                let sep = if self.rows == 1 { "\n" } else { ",\n" };
                write!(out, "{sep}{json}")
            }
            _ => writeln!(out, "{json}"),
        }
    }

    /// Ends the table and flushes.
    ///
    /// # Errors
    /// The writer's.
    pub fn finish(mut self) -> std::io::Result<()> {
        if let Some(mut csv) = self.csv.take() {
            return csv.flush();
        }
        if let Some(mut out) = self.out.take() {
            if self.format == crate::output::Format::Json {
                writeln!(out, "\n]}}")?;
            }
            out.flush()?;
        }
        Ok(())
    }
}

/// The columns of a structure's two trajectory tables: the states' (`t, kind, base`, then
/// `u_NAME` and `v_NAME` of every body and `r_K` of every stop) and the impacts' (`t, stop,
/// side, relative_velocity_before`, then `u_NAME` and `v_NAME_before` of every body). Both
/// solvers' tables have them, so that a simulated cycle and an analytic orbit overlay column
/// for column.
fn trajectory_columns(structure: &Structure) -> (Vec<String>, Vec<String>) {
    let names = &structure.names;
    let mut states: Vec<String> = ["t", "kind", "base"].map(String::from).to_vec();
    states.extend(names.iter().map(|n| format!("u_{n}")));
    states.extend(names.iter().map(|n| format!("v_{n}")));
    states.extend((0..structure.stops.len()).map(|k| format!("r_{k}")));
    let mut impacts: Vec<String> = ["t", "stop", "side", "relative_velocity_before"]
        .map(String::from)
        .to_vec();
    impacts.extend(names.iter().map(|n| format!("u_{n}")));
    impacts.extend(names.iter().map(|n| format!("v_{n}_before")));
    (states, impacts)
}

/// Numbers as cells, each `None` where it is not finite.
fn number_cells(values: &[f64]) -> impl Iterator<Item = Cell> + '_ {
    values.iter().map(|&x| Cell::Number(finite(x)))
}

/// One row of a structure's states table: time `t`, the row's `kind`, the base's displacement
/// (`None` without a moving base), every body's displacement `u` and velocity `v`, and every
/// stop's relative coordinate `r`.
fn state_cells(
    t: f64,
    kind: &'static str,
    base: Option<f64>,
    (u, v, r): (&[f64], &[f64], &[f64]),
) -> Vec<Cell> {
    let mut cells = vec![
        Cell::Number(finite(t)),
        Cell::Word(kind),
        Cell::Number(base.and_then(finite)),
    ];
    cells.extend(number_cells(u));
    cells.extend(number_cells(v));
    cells.extend(number_cells(r));
    cells
}

/// One row of a structure's impacts table: time `t`, the stop (numbered from 0), the side
/// (`+1` is side 1, else side 2), the relative velocity just before, and every body's
/// displacement `u` and velocity `v` just before.
fn impact_cells(
    t: f64,
    stop: usize,
    side: i8,
    relative_velocity_before: f64,
    (u, v): (&[f64], &[f64]),
) -> Vec<Cell> {
    let mut cells = vec![
        Cell::Number(finite(t)),
        Cell::Count(stop),
        Cell::Count(if side > 0 { 1 } else { 2 }),
        Cell::Number(finite(relative_velocity_before)),
    ];
    cells.extend(number_cells(u));
    cells.extend(number_cells(v));
    cells
}

/// A structure's simulated trajectory as two tables: the states (`t, kind, base`, then
/// `u_NAME` and `v_NAME` of every body and `r_K` of every stop), and the impacts (`t, stop,
/// side, relative_velocity_before`, then `u_NAME` and `v_NAME_before` of every body).
pub fn structure_trajectory(
    structure: &Structure,
    trajectory: &rattle_event_driven::Trajectory,
) -> (NamedTable, NamedTable) {
    use rattle_event_driven::RowKind;
    let (columns, impact_columns) = trajectory_columns(structure);
    let t0 = trajectory.phase;
    let rows = trajectory
        .rows
        .iter()
        .map(|row| {
            let kind = match row.kind {
                RowKind::Sample => "sample",
                RowKind::BeforeImpact => "before_impact",
                RowKind::AfterImpact => "after_impact",
                RowKind::AfterStick => "after_stick",
            };
            state_cells(
                t0 + row.time,
                kind,
                structure.base_amplitude.map(|_| row.base),
                (&row.displacements, &row.velocities, &row.relative),
            )
        })
        .collect();
    let impacts = trajectory
        .impacts
        .iter()
        .map(|i| {
            impact_cells(
                t0 + i.time,
                i.pair,
                i.side,
                i.relative_velocity_before,
                (&i.displacements, &i.velocities_before),
            )
        })
        .collect();
    (
        NamedTable { columns, rows },
        NamedTable {
            columns: impact_columns,
            rows: impacts,
        },
    )
}

/// A structure's analytic orbit, sampled by
/// [`crate::scene::analytic::sample_sequence_orbit`] on [`Structure::analytic_model`], as the
/// two tables of [`structure_trajectory`], with the same columns: the base's displacement
/// `u_g cos ωt` at `omega` (empty without a moving base), every stop's `r` and each impact's
/// `ṙ⁻` from the bodies' displacements and velocities ([`crate::scene::structure::Stop::relative`]).
///
/// # Panics
/// If a sampled state has fewer than two entries per body of `structure`, or an impact names
/// a stop it does not have.
pub fn structure_orbit_trajectory(
    structure: &Structure,
    samples: &[OrbitSample],
    impacts: &[OrbitImpact],
    omega: f64,
) -> (NamedTable, NamedTable) {
    let n = structure.dofs();
    let (columns, impact_columns) = trajectory_columns(structure);
    let relative =
        |u: &[f64]| -> Vec<f64> { structure.stops.iter().map(|s| s.relative(u)).collect() };
    let rows = samples
        .iter()
        .map(|s| {
            let (u, v) = (&s.state.as_slice()[..n], &s.state.as_slice()[n..2 * n]);
            let kind = match s.kind {
                SampleKind::Sample => "sample",
                SampleKind::BeforeImpact => "before_impact",
                SampleKind::AfterImpact => "after_impact",
            };
            let base = structure
                .base_amplitude
                .map(|ug| ug * (omega * s.time).cos());
            state_cells(s.time, kind, base, (u, v, &relative(u)))
        })
        .collect();
    let impacts = impacts
        .iter()
        .map(|i| {
            let (u, v) = (&i.before.as_slice()[..n], &i.before.as_slice()[n..2 * n]);
            impact_cells(
                i.time,
                i.pair,
                i.side,
                structure.stops[i.pair].relative(v),
                (u, v),
            )
        })
        .collect();
    (
        NamedTable { columns, rows },
        NamedTable {
            columns: impact_columns,
            rows: impacts,
        },
    )
}

/// What `rattle orbit --signature --json` prints for a structure.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
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
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
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
