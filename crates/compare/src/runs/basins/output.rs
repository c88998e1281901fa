//! The tables of basins: one row per start ([`BasinRow`], [`PlaneRow`]) with the plane's
//! columns, the JSON header, and the writers of the whole grid's table or of one part's.

use super::attractor::{Attractor, BasinCell, Basins};
use super::plane::{BasinGrid, BasinPlane};
use super::run::{basins_part, plane_basins_part};
use crate::output::{
    finite, number_list, table_row, CsvWriter, Format, Header, JsonLinesWriter, JsonWriter, Row,
    TableWriter,
};
use crate::runs::parallel::Progress;
use crate::runs::shard::Shard;
use crate::scene::{AnyScene, Scene};
use rattle_event_driven::SimulationOptions;
use serde::ser::{SerializeMap, SerializeTuple};
use serde::{Serialize, Serializer};
use std::io::Write;

table_row! {
    /// One start of a basins grid.
    pub struct BasinRow {
        /// Outer displacement at the start, m.
        pub outer_start: Option<f64>,
        /// Inner displacement at the start, m.
        pub inner_start: Option<f64>,
        /// The attractor's number (first appearance in grid order).
        pub attractor: usize,
        /// The attractor in words.
        pub attractor_words: String,
        /// `X_o` of the motion reached, m.
        pub outer_amplitude: Option<f64>,
        /// Forcing periods run.
        pub periods_run: u64,
    }
}

/// The rows of `cells` numbered into `attractors`, in grid order.
pub fn rows<'a>(
    attractors: &'a [Attractor],
    cells: &'a [BasinCell],
) -> impl Iterator<Item = BasinRow> + 'a {
    cells.iter().map(|c| BasinRow {
        outer_start: finite(c.outer),
        inner_start: finite(c.inner),
        attractor: c.attractor,
        attractor_words: attractors[c.attractor].words(),
        outer_amplitude: finite(c.outer_amplitude),
        periods_run: c.periods_run,
    })
}

/// The header of a basins JSON table: the scene and the frequency.
pub fn header(scene: &Scene, omega: f64) -> Header {
    let mut h = Header::default();
    h.push("scene", scene);
    h.push("omega", &omega);
    h
}

/// The header of a basins JSON table on a scene of any form: the scene as written and the
/// frequency.
fn any_header(scene: &AnyScene, omega: f64) -> Header {
    match scene {
        AnyScene::Cells(scene) => header(scene, omega),
        AnyScene::Structure(form) => {
            let mut h = Header::default();
            h.push("scene", &form.scene);
            h.push("omega", &omega);
            h
        }
    }
}

/// The column of every body's amplitude in a chain's or a structure's basins table.
pub const BODY_AMPLITUDES: &str = "body_amplitudes";

/// One row of a basins table with the plane's columns: a [`BasinRow`] whose first two cells
/// are named by the plane's coordinates, and on a chain or a structure every body's amplitude
/// as a list cell ([`number_list`], an empty element for a body without amplitude).
#[derive(Debug, Clone, PartialEq)]
pub struct PlaneRow {
    /// The columns of the two starts ([`BasinPlane::columns`]).
    pub columns: [String; 2],
    /// The row's cells.
    pub row: BasinRow,
    /// The `body_amplitudes` cell; `None` on the unit, whose table has no such column.
    pub body_amplitudes: Option<Option<String>>,
    /// Written as a JSON object (JSON and JSON Lines), else as a CSV record.
    pub keyed: bool,
}

impl Serialize for PlaneRow {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        let r = &self.row;
        let extra = usize::from(self.body_amplitudes.is_some());
        if self.keyed {
            let mut m = serializer.serialize_map(Some(6 + extra))?;
            m.serialize_entry(&self.columns[0], &r.outer_start)?;
            m.serialize_entry(&self.columns[1], &r.inner_start)?;
            m.serialize_entry("attractor", &r.attractor)?;
            m.serialize_entry("attractor_words", &r.attractor_words)?;
            m.serialize_entry("outer_amplitude", &r.outer_amplitude)?;
            m.serialize_entry("periods_run", &r.periods_run)?;
            if let Some(b) = &self.body_amplitudes {
                m.serialize_entry(BODY_AMPLITUDES, b)?;
            }
            m.end()
        } else {
            let mut t = serializer.serialize_tuple(6 + extra)?;
            t.serialize_element(&r.outer_start)?;
            t.serialize_element(&r.inner_start)?;
            t.serialize_element(&r.attractor)?;
            t.serialize_element(&r.attractor_words)?;
            t.serialize_element(&r.outer_amplitude)?;
            t.serialize_element(&r.periods_run)?;
            if let Some(b) = &self.body_amplitudes {
                t.serialize_element(b)?;
            }
            t.end()
        }
    }
}

impl Row for PlaneRow {
    /// The default plane's columns; a plane's table names its first two by its coordinates
    /// and adds [`BODY_AMPLITUDES`] on a chain or a structure ([`PlaneRow::columns`]).
    const COLUMNS: &'static [&'static str] = BasinRow::COLUMNS;
}

/// The columns of a basins table: the two starts', then [`BasinRow`]'s others, then
/// [`BODY_AMPLITUDES`] when `bodies`.
fn table_columns(starts: &[String; 2], bodies: bool) -> Vec<String> {
    let mut columns: Vec<String> = starts.to_vec();
    columns.extend(BasinRow::COLUMNS[2..].iter().map(|c| (*c).to_owned()));
    if bodies {
        columns.push(BODY_AMPLITUDES.to_owned());
    }
    columns
}

/// A `body_amplitudes` cell: the list, an empty element for a body without amplitude.
fn amplitudes_cell(amplitudes: &[Option<f64>]) -> Option<String> {
    let values: Vec<f64> = amplitudes.iter().map(|a| a.unwrap_or(f64::NAN)).collect();
    number_list(&values)
}

/// The rows of a plane's table: `cells` numbered into `attractors` with `body_amplitudes`
/// (`None`: the unit's table, without that column).
pub(super) fn plane_rows<'a>(
    columns: &'a [String; 2],
    attractors: &'a [Attractor],
    cells: &'a [BasinCell],
    body_amplitudes: Option<&'a [Vec<Option<f64>>]>,
    keyed: bool,
) -> impl Iterator<Item = PlaneRow> + 'a {
    rows(attractors, cells)
        .enumerate()
        .map(move |(k, row)| PlaneRow {
            columns: columns.clone(),
            row,
            body_amplitudes: body_amplitudes.map(|b| amplitudes_cell(&b[k])),
            keyed,
        })
}

/// A table writer of `format` for a plane's rows with `columns`.
fn plane_writer<'w, W: Write + 'w>(
    format: Format,
    out: W,
    header: &Header,
    preamble: Option<&str>,
    columns: &[String],
) -> std::io::Result<Box<dyn TableWriter<PlaneRow> + 'w>> {
    let names: Vec<&str> = columns.iter().map(String::as_str).collect();
    Ok(match format {
        Format::Csv => Box::new(CsvWriter::new(out, preamble, &names)?),
        Format::Json => Box::new(JsonWriter::new(out, header)?),
        Format::JsonLines => Box::new(JsonLinesWriter::new(out)),
    })
}

/// Computes the unit's basins over its outer and inner displacements (or one part of them,
/// [`basins_part`]) and writes their table to `out` in `format`: [`write_plane_basins`] on the
/// default plane ([`BasinPlane::unit`]), the table `rattle basins --out …` writes without
/// `--x`/`--y`.
///
/// # Errors
/// The writer's.
pub fn write_basins<W: Write>(
    scene: &Scene,
    omega: f64,
    grid: BasinGrid,
    options: &SimulationOptions,
    shard: Option<Shard>,
    out: (Format, W),
    progress: &Progress,
) -> std::io::Result<Basins> {
    let b = basins_part(scene, omega, grid, options, shard, progress);
    write_table(&AnyScene::Cells(scene.clone()), b, shard, out)
}

/// Computes the basins of `scene` (any form) over `plane` (or one part of them,
/// [`plane_basins_part`]) and writes their table to `out` in `format`: the table
/// `rattle basins --out …` writes. Its columns are the two starts' ([`BasinPlane::columns`]),
/// `attractor`, `attractor_words`, `outer_amplitude`, `periods_run`, and on a chain or a
/// structure `body_amplitudes`. A part's JSON header adds the whole grid's `starts`, its
/// `shard` and its `attractors` (numbered within the part, in full); a CSV part starts with
/// `# shard K/N of P starts, attractors: [...]` (the same list, JSON). Its rows are numbered
/// within the part; [`crate::runs::shard::merge`] numbers them over the whole grid and writes
/// exactly the whole grid's table. Returns the basins computed (of the part: its cells and
/// attractors).
///
/// # Errors
/// The writer's.
pub fn write_plane_basins<W: Write>(
    scene: &AnyScene,
    omega: f64,
    plane: &BasinPlane,
    options: &SimulationOptions,
    shard: Option<Shard>,
    out: (Format, W),
    progress: &Progress,
) -> std::io::Result<Basins> {
    let b = plane_basins_part(scene, omega, plane, options, shard, progress);
    write_table(scene, b, shard, out)
}

/// Writes the table of `b` (part `shard` of the grid, or all of it).
fn write_table<W: Write>(
    scene: &AnyScene,
    b: Basins,
    shard: Option<Shard>,
    (format, out): (Format, W),
) -> std::io::Result<Basins> {
    let mut h = any_header(scene, b.omega);
    let total = b.grid.starts();
    let preamble = match shard {
        Some(s) => {
            h.push("starts", &total);
            h.push("shard", &s);
            h.push("attractors", &b.attractors);
            let list = serde_json::to_string(&b.attractors).map_err(std::io::Error::other)?;
            Some(format!(
                "{}, attractors: {list}",
                s.csv_preamble_of(total, "starts")
            ))
        }
        None => None,
    };
    let bodies = !matches!(scene, AnyScene::Cells(s) if !s.is_chain());
    let starts = b.plane.columns();
    let columns = table_columns(&starts, bodies);
    let mut table = plane_writer(format, out, &h, preamble.as_deref(), &columns)?;
    let amplitudes = bodies.then_some(&b.body_amplitudes[..]);
    let keyed = format != Format::Csv;
    for row in plane_rows(&starts, &b.attractors, &b.cells, amplitudes, keyed) {
        table.row(&row)?;
    }
    table.finish()?;
    Ok(b)
}
