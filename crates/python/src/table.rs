//! The command's tables handed to numpy, one array per column, for any row type of
//! `rattle-compare` (a [`Row`]): the columns are the row type's [`Row::COLUMNS`], in order,
//! and each column's array type follows from its field's Rust type, so that no column is
//! listed here by hand:
//!
//! - a number (`f64`), or an optional count (`Option<usize>`, `Option<u32>`…): `float64`, NaN
//!   where the row has none (`null` in the command's JSON);
//! - a count that is always there (`usize`, `u64`…): `int64`;
//! - a flag (`bool`, `Option<bool>`): `bool`, `False` where the row has none;
//! - words and `;`-separated lists (`&str`, `String`, optional or not): `object`, `str` or
//!   `None`.
//!
//! A row is read through its `Serialize` implementation (the one the command's writers use):
//! each field's value as the JSON the command writes, and its type's name
//! ([`std::any::type_name`]). The types are read once per row type, on a row the library
//! builds from trivial inputs ([`TableRow`]), so that a table's array types are the same
//! whatever its rows, an empty table's included.

use numpy::PyArray1;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyString;
use rattle_compare::output::structure::{structure_trajectory, Cell, NamedTable};
use rattle_compare::output::trajectory::{analytic_rows, ImpactRow, TrajectoryRow};
use rattle_compare::output::transmission::TransmissionRow;
use rattle_compare::output::Row;
use rattle_compare::runs::basins::{rows as basin_rows, Attractor, BasinCell, BasinRow};
use rattle_compare::runs::map::{line, scene_at, MapColumns, MapPointRow, MapSettings};
use rattle_compare::runs::structure_sweep::{structure_point, StructureSweepRow};
use rattle_compare::runs::sweep::{point, Solver, SweepRow};
use rattle_compare::scene::analytic::{OrbitImpact, OrbitSample, SampleKind};
use rattle_compare::scene::structure::Structure;
use rattle_compare::scene::{AnyScene, Scene};
use rattle_event_driven::{RowKind, SimulationOptions, Trajectory, TrajectoryImpact};
use serde::ser::{self, Impossible, Serialize, SerializeStruct, Serializer};
use serde_json::Value;
use std::any::type_name;
use std::fmt;
use std::sync::OnceLock;

/// A table handed to Python: `(column name, numpy array)` pairs in the command's order.
pub(crate) type PyColumns<'py> = Vec<(String, Bound<'py, PyAny>)>;

/// How a column is handed to numpy (its name, as `table_kinds` gives it, in [`Kind::name`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `float64`, NaN where the row has none.
    Number,
    /// `int64`: a count every row has.
    Count,
    /// `bool`, `False` where the row has none.
    Flag,
    /// `object`: `str`, or `None` where the row has none.
    Text,
}

impl Kind {
    /// The kind of a field of the Rust type named `name` ([`std::any::type_name`]); `None`
    /// for a type no table has.
    fn of_type(name: &str) -> Option<Kind> {
        let (optional, inner) = match name
            .strip_prefix("core::option::Option<")
            .and_then(|inner| inner.strip_suffix('>'))
        {
            Some(inner) => (true, inner),
            None => (false, name),
        };
        match inner {
            "f64" | "f32" => Some(Kind::Number),
            "u8" | "u16" | "u32" | "u64" | "usize" | "i8" | "i16" | "i32" | "i64" | "isize" => {
                Some(if optional { Kind::Number } else { Kind::Count })
            }
            "bool" => Some(Kind::Flag),
            "&str" | "alloc::string::String" => Some(Kind::Text),
            _ => None,
        }
    }

    /// The kind's name for the Python half: `number`, `count`, `flag` or `text`.
    fn name(self) -> &'static str {
        match self {
            Kind::Number => "number",
            Kind::Count => "count",
            Kind::Flag => "flag",
            Kind::Text => "text",
        }
    }
}

/// One field of a row: its column, its Rust type's name and its value as the command's JSON.
struct Field {
    /// The column name (the field's name).
    name: &'static str,
    /// The field's Rust type, by [`std::any::type_name`].
    type_name: &'static str,
    /// The value, as the command's JSON writes it.
    value: Value,
}

/// Why a value could not be read as a row (a bug: every row type is a struct of plain
/// fields).
#[derive(Debug)]
struct NotARow(String);

impl fmt::Display for NotARow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for NotARow {}

impl ser::Error for NotARow {
    fn custom<T: fmt::Display>(message: T) -> Self {
        NotARow(message.to_string())
    }
}

/// The serializer that reads a row struct into its [`Field`]s; anything else is refused.
struct RowReader;

/// The fields read so far.
struct Fields(Vec<Field>);

impl SerializeStruct for Fields {
    type Ok = Vec<Field>;
    type Error = NotARow;

    fn serialize_field<T: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &T,
    ) -> Result<(), NotARow> {
        let value = serde_json::to_value(value).map_err(|e| NotARow(e.to_string()))?;
        self.0.push(Field {
            name: key,
            type_name: type_name::<T>(),
            value,
        });
        Ok(())
    }

    fn end(self) -> Result<Vec<Field>, NotARow> {
        Ok(self.0)
    }
}

/// Refuses each listed `serialize_*` method of [`RowReader`]: a row is a struct.
macro_rules! not_a_row {
    ($($method:ident($($arg:ty),*) -> $out:ty;)*) => {
        $(
            fn $method(self, $(_: $arg),*) -> Result<$out, NotARow> {
                Err(NotARow(format!("a row is a struct, not {}", stringify!($method))))
            }
        )*
    };
}

impl Serializer for RowReader {
    type Ok = Vec<Field>;
    type Error = NotARow;
    type SerializeSeq = Impossible<Vec<Field>, NotARow>;
    type SerializeTuple = Impossible<Vec<Field>, NotARow>;
    type SerializeTupleStruct = Impossible<Vec<Field>, NotARow>;
    type SerializeTupleVariant = Impossible<Vec<Field>, NotARow>;
    type SerializeMap = Impossible<Vec<Field>, NotARow>;
    type SerializeStruct = Fields;
    type SerializeStructVariant = Impossible<Vec<Field>, NotARow>;

    fn serialize_struct(self, _: &'static str, len: usize) -> Result<Fields, NotARow> {
        Ok(Fields(Vec::with_capacity(len)))
    }

    fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<Vec<Field>, NotARow> {
        Err(NotARow("a row is a struct, not an option".to_owned()))
    }

    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: &T,
    ) -> Result<Vec<Field>, NotARow> {
        Err(NotARow("a row is a struct, not a newtype".to_owned()))
    }

    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<Vec<Field>, NotARow> {
        Err(NotARow("a row is a struct, not a variant".to_owned()))
    }

    not_a_row! {
        serialize_bool(bool) -> Vec<Field>;
        serialize_i8(i8) -> Vec<Field>;
        serialize_i16(i16) -> Vec<Field>;
        serialize_i32(i32) -> Vec<Field>;
        serialize_i64(i64) -> Vec<Field>;
        serialize_u8(u8) -> Vec<Field>;
        serialize_u16(u16) -> Vec<Field>;
        serialize_u32(u32) -> Vec<Field>;
        serialize_u64(u64) -> Vec<Field>;
        serialize_f32(f32) -> Vec<Field>;
        serialize_f64(f64) -> Vec<Field>;
        serialize_char(char) -> Vec<Field>;
        serialize_str(&str) -> Vec<Field>;
        serialize_bytes(&[u8]) -> Vec<Field>;
        serialize_none() -> Vec<Field>;
        serialize_unit() -> Vec<Field>;
        serialize_unit_struct(&'static str) -> Vec<Field>;
        serialize_unit_variant(&'static str, u32, &'static str) -> Vec<Field>;
        serialize_seq(Option<usize>) -> Self::SerializeSeq;
        serialize_tuple(usize) -> Self::SerializeTuple;
        serialize_tuple_struct(&'static str, usize) -> Self::SerializeTupleStruct;
        serialize_tuple_variant(&'static str, u32, &'static str, usize) -> Self::SerializeTupleVariant;
        serialize_map(Option<usize>) -> Self::SerializeMap;
        serialize_struct_variant(&'static str, u32, &'static str, usize) -> Self::SerializeStructVariant;
    }
}

/// The fields of `row`, in its columns' order.
fn fields<R: Row>(row: &R) -> Result<Vec<Field>, NotARow> {
    row.serialize(RowReader)
}

/// Each column of `R` with its kind, read on `row`; an error if the fields are not
/// [`Row::COLUMNS`] or a field's type has no kind (bugs).
fn kinds_of<R: Row>(row: Option<R>) -> Result<Vec<(&'static str, Kind)>, String> {
    let row = row.ok_or_else(|| format!("no row of {} to read", type_name::<R>()))?;
    let fields = fields(&row).map_err(|e| e.to_string())?;
    let names: Vec<&str> = fields.iter().map(|f| f.name).collect();
    if names != R::COLUMNS {
        return Err(format!(
            "the fields {names:?} of {} differ from its columns {:?}",
            type_name::<R>(),
            R::COLUMNS
        ));
    }
    fields
        .iter()
        .map(|f| {
            Kind::of_type(f.type_name)
                .map(|kind| (f.name, kind))
                .ok_or_else(|| format!("column {}: no array type for {}", f.name, f.type_name))
        })
        .collect()
}

/// A row type whose table is handed to numpy: its columns' kinds, read once on a row the
/// library builds from trivial inputs.
pub(crate) trait TableRow: Row + Sized {
    /// Each column with its kind, in [`Row::COLUMNS`] order; an error names a bug.
    fn kinds() -> &'static Result<Vec<(&'static str, Kind)>, String>;
}

/// Implements [`TableRow`] for `$row`, its kinds read once on the row `$sample` gives.
macro_rules! table_row_kinds {
    ($row:ty, $sample:expr) => {
        impl TableRow for $row {
            fn kinds() -> &'static Result<Vec<(&'static str, Kind)>, String> {
                static KINDS: OnceLock<Result<Vec<(&'static str, Kind)>, String>> = OnceLock::new();
                KINDS.get_or_init(|| kinds_of::<$row>($sample))
            }
        }
    };
}

// A sweep's row: the paper scene's analytic solution at one frequency (closed form).
table_row_kinds!(SweepRow, {
    let scene = Scene::paper();
    let p = point(&scene, 1.0, Solver::Analytic, &SimulationOptions::default());
    Some(SweepRow::new(&scene, &p))
});

/// A structure of one body held by a spring between stops, forced: the structure the kinds of
/// a structure's row types are read on.
const ONE_BODY: &str = r#"{"name": "one-body",
    "structure": {"bodies": [{"name": "x", "mass": 1.0}],
                  "springs": [{"between": ["frame", "x"], "stiffness": 1.0}],
                  "stops": [{"between": ["frame", "x"], "gap": 1.0, "restitution": 0.5}]},
    "forcing": {"forces": [{"on": "x", "amplitude": 1.0}]}}"#;

// A structure sweep's row: the one-body structure's linear steady state at one frequency.
table_row_kinds!(StructureSweepRow, {
    match AnyScene::parse(ONE_BODY, "built-in") {
        Ok(AnyScene::Structure(form)) => Some(structure_point(
            &form.structure,
            0.5,
            Solver::Analytic,
            &SimulationOptions::default(),
        )),
        _ => None,
    }
});

// A map's row: one point of one line, simulated for a single forcing period.
table_row_kinds!(MapPointRow, {
    let settings = MapSettings {
        simulation: SimulationOptions {
            max_periods: 1,
            ..SimulationOptions::default()
        },
        lyapunov_periods: None,
        ..MapSettings::default()
    };
    let scene = AnyScene::Cells(scene_at(&Scene::paper(), 0.8, 0.5));
    let line = line(&scene, 0.8, 0.5, &[1.0], &settings);
    let row = MapPointRow::of_line(&line).next();
    row
});

// A basins row: one start that reached the failed attractor.
table_row_kinds!(BasinRow, {
    let cell = BasinCell {
        outer: 0.0,
        inner: 0.0,
        attractor: 0,
        outer_amplitude: 0.0,
        periods_run: 0,
    };
    basin_rows(&[Attractor::Failed], &[cell]).next()
});

/// One sampled state and one impact of a unit at rest, as the analytic solver samples them.
fn trajectory_sample() -> (Vec<TrajectoryRow>, Vec<ImpactRow>) {
    let sample = OrbitSample {
        time: 0.0,
        kind: SampleKind::Sample,
        state: vec![0.0; 4].into(),
    };
    let impact = OrbitImpact {
        time: 0.0,
        pair: 0,
        side: 1,
        before: vec![0.0; 4].into(),
    };
    analytic_rows(&[sample], &[impact], 1.0, 1.0, &[Some(0)])
}

table_row_kinds!(TrajectoryRow, trajectory_sample().0.pop());

// A transmission row: every field given, as a level's row at one frequency.
table_row_kinds!(TransmissionRow, {
    Some(TransmissionRow {
        level: 1.0,
        omega: 1.0,
        h1_magnitude: Some(1.0),
        h1_phase: Some(0.0),
        h1_radius: Some(0.0),
        transmissibility: Some(1.0),
        coherence: Some(1.0),
        linear_magnitude: Some(1.0),
        linear_phase: Some(0.0),
        averages: 1.0,
    })
});
table_row_kinds!(ImpactRow, trajectory_sample().1.pop());

/// A `RuntimeError` for a table that does not read as its columns (a bug).
fn bug(message: &str) -> PyErr {
    PyRuntimeError::new_err(format!(
        "internal error (a bug in rattle, please report it): {message}"
    ))
}

/// The kinds of `R`'s columns, or the bug that kept them from being read.
fn kinds<R: TableRow>() -> PyResult<&'static [(&'static str, Kind)]> {
    R::kinds().as_deref().map_err(|e| bug(e))
}

/// One column's array from its values, as `kind` says.
fn array<'py>(
    py: Python<'py>,
    name: &str,
    kind: Kind,
    values: Vec<Value>,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(match kind {
        Kind::Number => {
            let numbers: Vec<f64> = values
                .iter()
                .map(|v| v.as_f64().unwrap_or(f64::NAN))
                .collect();
            PyArray1::from_vec(py, numbers).into_any()
        }
        Kind::Count => {
            let counts = values
                .iter()
                .map(|v| v.as_i64())
                .collect::<Option<Vec<i64>>>()
                .ok_or_else(|| bug(&format!("column {name}: a count that is not an int64")))?;
            PyArray1::from_vec(py, counts).into_any()
        }
        Kind::Flag => {
            let flags: Vec<bool> = values
                .iter()
                .map(|v| v.as_bool().unwrap_or(false))
                .collect();
            PyArray1::from_vec(py, flags).into_any()
        }
        Kind::Text => {
            let objects: Vec<Py<PyAny>> = values
                .into_iter()
                .map(|v| match v {
                    Value::String(s) => PyString::new(py, &s).into_any().unbind(),
                    _ => py.None(),
                })
                .collect();
            PyArray1::from_vec(py, objects).into_any()
        }
    })
}

/// The columns of `rows`, in [`Row::COLUMNS`] order, each a numpy array of its kind.
///
/// # Errors
/// A `RuntimeError` if a row does not read as its columns (a bug).
pub(crate) fn columns<'py, R: TableRow>(py: Python<'py>, rows: &[R]) -> PyResult<PyColumns<'py>> {
    let kinds = kinds::<R>()?;
    let mut values: Vec<Vec<Value>> = kinds
        .iter()
        .map(|_| Vec::with_capacity(rows.len()))
        .collect();
    for row in rows {
        let fields = fields(row).map_err(|e| bug(&e.to_string()))?;
        if fields.len() != kinds.len() {
            return Err(bug(&format!(
                "a row of {} has {} fields, not {}",
                type_name::<R>(),
                fields.len(),
                kinds.len()
            )));
        }
        for (column, field) in values.iter_mut().zip(fields) {
            column.push(field.value);
        }
    }
    kinds
        .iter()
        .zip(values)
        .map(|(&(name, kind), values)| Ok((name.to_owned(), array(py, name, kind, values)?)))
        .collect()
}

/// The two tables of a structure's trajectory with one row and one impact, at rest: the
/// library's tables for `structure`, their columns and cells' kinds those of any of its
/// trajectories ([`structure_trajectory`]).
fn structure_sample(structure: &Structure) -> (NamedTable, NamedTable) {
    let n = structure.dofs();
    let trajectory = Trajectory {
        rows: vec![rattle_event_driven::TrajectoryRow {
            time: 0.0,
            kind: RowKind::Sample,
            base: 0.0,
            displacements: vec![0.0; n],
            velocities: vec![0.0; n],
            relative: vec![0.0; structure.stops.len()],
        }],
        impacts: vec![TrajectoryImpact {
            time: 0.0,
            pair: 0,
            side: 1,
            relative_velocity_before: 0.0,
            displacements: vec![0.0; n],
            velocities_before: vec![0.0; n],
        }],
        period: 1.0,
        phase: 0.0,
    };
    structure_trajectory(structure, &trajectory)
}

/// The kind of a cell of a [`NamedTable`].
fn cell_kind(cell: &Cell) -> Kind {
    match cell {
        Cell::Number(_) => Kind::Number,
        Cell::Word(_) => Kind::Text,
        Cell::Count(_) => Kind::Count,
    }
}

/// The columns of `table`, a table of a structure's trajectory (`sample` says which: `0`
/// the states, `1` the impacts), in its order, each a numpy array of the kind the library's
/// table for `structure` gives the column, whatever the rows ([`structure_sample`]).
///
/// # Errors
/// A `RuntimeError` if the table's columns or rows are not the sample's (a bug).
fn named_columns<'py>(
    py: Python<'py>,
    table: &NamedTable,
    sample: &NamedTable,
) -> PyResult<PyColumns<'py>> {
    let first = sample
        .rows
        .first()
        .ok_or_else(|| bug("no sample row of a structure's table"))?;
    if sample.columns != table.columns || first.len() != table.columns.len() {
        return Err(bug(&format!(
            "a structure's table has the columns {:?}, its sample {:?}",
            table.columns, sample.columns
        )));
    }
    let mut values: Vec<Vec<Value>> = table
        .columns
        .iter()
        .map(|_| Vec::with_capacity(table.rows.len()))
        .collect();
    for row in &table.rows {
        if row.len() != table.columns.len() {
            return Err(bug(&format!(
                "a row of a structure's table has {} cells, not {}",
                row.len(),
                table.columns.len()
            )));
        }
        for (column, cell) in values.iter_mut().zip(row) {
            column.push(serde_json::to_value(cell).map_err(|e| bug(&e.to_string()))?);
        }
    }
    table
        .columns
        .iter()
        .zip(first)
        .zip(values)
        .map(|((name, cell), values)| Ok((name.clone(), array(py, name, cell_kind(cell), values)?)))
        .collect()
}

/// The two tables of a structure's trajectory (the states, the impacts) as columns, each of
/// the kind the library gives it ([`named_columns`]).
///
/// # Errors
/// A `RuntimeError` if a table does not read as its columns (a bug).
pub(crate) fn structure_columns<'py>(
    py: Python<'py>,
    structure: &Structure,
    states: &NamedTable,
    impacts: &NamedTable,
) -> PyResult<(PyColumns<'py>, PyColumns<'py>)> {
    let (sample_states, sample_impacts) = structure_sample(structure);
    Ok((
        named_columns(py, states, &sample_states)?,
        named_columns(py, impacts, &sample_impacts)?,
    ))
}

/// The kinds of a map's points table whose columns `columns` names ([`MapColumns`]): those of
/// [`MapPointRow`], column for column, under the names the map writes; read once into `cell`.
fn map_kinds(
    columns: MapColumns,
    cell: &'static OnceLock<Vec<(&'static str, Kind)>>,
) -> PyResult<&'static [(&'static str, Kind)]> {
    let kinds = kinds::<MapPointRow>()?;
    Ok(cell.get_or_init(|| {
        columns
            .points()
            .into_iter()
            .zip(kinds)
            .map(|(name, &(_, kind))| (name, kind))
            .collect()
    }))
}

/// The kinds of the table called `table`.
fn table_kinds_of(table: &str) -> PyResult<&'static [(&'static str, Kind)]> {
    static PARAMETERS: OnceLock<Vec<(&'static str, Kind)>> = OnceLock::new();
    static STRUCTURE: OnceLock<Vec<(&'static str, Kind)>> = OnceLock::new();
    match table {
        "map" => kinds::<MapPointRow>(),
        "map-parameters" => map_kinds(MapColumns::PARAMETERS, &PARAMETERS),
        "map-structure" => map_kinds(MapColumns::STRUCTURE, &STRUCTURE),
        "basins" => kinds::<BasinRow>(),
        "sweep" => kinds::<SweepRow>(),
        "structure-sweep" => kinds::<StructureSweepRow>(),
        "trajectory" => kinds::<TrajectoryRow>(),
        "impacts" => kinds::<ImpactRow>(),
        "transmission" => kinds::<TransmissionRow>(),
        _ => Err(PyValueError::new_err(format!("no table {table:?}"))),
    }
}

/// The columns of the command's tables, in order: `"map"` (the points of the map over
/// restitution and gap), `"map-parameters"` (of a unit's or chain's map over two parameters,
/// `x` and `y`), `"map-structure"` (of a structure's), `"basins"`, `"sweep"`,
/// `"structure-sweep"` (a structure's sweep), `"trajectory"`, `"impacts"`, `"transmission"`
/// (the rows of every level of a transmission estimate).
#[pyfunction]
fn table_columns(table: &str) -> PyResult<Vec<&'static str>> {
    Ok(table_kinds_of(table)?
        .iter()
        .map(|&(name, _)| name)
        .collect())
}

/// The columns of the command's tables with their kinds, in order, as `(name, kind)` pairs:
/// `number` (`float64`, NaN for `null`), `count` (`int64`), `flag` (`bool`, `False` for
/// `null`) or `text` (`object`); the tables as [`table_columns`] names them.
#[pyfunction]
fn table_kinds(table: &str) -> PyResult<Vec<(&'static str, &'static str)>> {
    Ok(table_kinds_of(table)?
        .iter()
        .map(|&(name, kind)| (name, kind.name()))
        .collect())
}

/// Registers `table_columns` and `table_kinds`.
pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(table_columns, m)?)?;
    m.add_function(wrap_pyfunction!(table_kinds, m)?)?;
    Ok(())
}
