//! Outputs: typed rows and records, and one writer per table format.
//!
//! Every table is a row struct declared with `table_row!`: its
//! field names are the column names, the same in CSV, JSON and JSON Lines. A writer takes rows
//! one at a time, in order, and writes each at once, so memory does not grow with the number of
//! rows. Values that do not apply, and numbers that are not finite, are empty cells in CSV and
//! `null` in JSON, never `NaN` or infinity.
//!
//! One-document results (an orbit, a simulation) are `#[derive(Serialize)]` records in
//! [`records`].

mod csv;
mod json;
mod jsonl;
pub mod records;
mod rename;
pub mod respond;
pub mod structure;
pub mod trajectory;
pub mod transmission;

pub use self::csv::CsvWriter;
pub use self::json::{Header, JsonWriter};
pub use self::jsonl::JsonLinesWriter;
pub use self::rename::Renamed;

use serde::Serialize;
use std::io::Write;
use std::path::{Path, PathBuf};
use thiserror::Error;

/// A number, or `None` when it is not finite: how every output writes a float.
pub fn finite(x: f64) -> Option<f64> {
    x.is_finite().then_some(x)
}

/// A list of numbers as one table cell (a cell holds one value in every format): the numbers
/// separated by `;`, each written as the table writes a number (`0.25;1e-7`), an empty
/// element where one is not finite (`0.25;;1.5`); `None` (an empty cell, `null`) for an empty
/// list or one without a finite number, as a number column writes a number that is not
/// finite. One cell of a one-cell scene is a one-element list, `0.25`. It loads with
/// `[float(x) if x else float("nan") for x in cell.split(";")]` (Python) or
/// `str2double(split(cell, ";"))` (MATLAB).
pub fn number_list(values: &[f64]) -> Option<String> {
    if !values.iter().any(|x| x.is_finite()) {
        return None;
    }
    Some(
        values
            .iter()
            .map(|&x| serde_json::Number::from_f64(x).map_or_else(String::new, |n| n.to_string()))
            .collect::<Vec<_>>()
            .join(";"),
    )
}

/// A row of a table: a `Serialize` struct whose field names, in order, are [`Row::COLUMNS`].
/// Declare row types with `table_row!` so the two cannot drift.
pub trait Row: Serialize {
    /// The column names, in order.
    const COLUMNS: &'static [&'static str];
}

/// Declares a row struct (`#[derive(Debug, Clone, PartialEq, Serialize)]`) and its
/// [`Row::COLUMNS`] from the same field list: the field names are the column names.
macro_rules! table_row {
    (
        $(#[$meta:meta])*
        pub struct $name:ident {
            $( $(#[$field_meta:meta])* pub $field:ident : $type:ty, )*
        }
    ) => {
        $(#[$meta])*
        #[derive(Debug, Clone, PartialEq, serde::Serialize)]
        pub struct $name {
            $( $(#[$field_meta])* pub $field: $type, )*
        }

        impl $crate::output::Row for $name {
            const COLUMNS: &'static [&'static str] = &[$(stringify!($field)),*];
        }
    };
}
pub(crate) use table_row;

/// A table's file format, chosen by the file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// `.csv`: a header line of the columns, one line per row; loads with `pandas.read_csv`
    /// or MATLAB `readtable`.
    Csv,
    /// `.json`: one compact document, `{…header…, "results": [row, …]}`, one row per line.
    Json,
    /// `.jsonl`: one JSON object per row, one per line (`pandas.read_json(lines=True)`).
    JsonLines,
}

/// A table could not be written.
#[derive(Debug, Error)]
pub enum OutputError {
    /// The file's extension names no format.
    #[error("{option} {path}: the extension must be .csv, .json or .jsonl")]
    Extension {
        /// The command-line option that named the file.
        option: String,
        /// The path as given.
        path: PathBuf,
    },
    /// Writing failed.
    #[error("cannot write {path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
}

impl Format {
    /// The format named by `path`'s extension (`.csv`, `.json`, `.jsonl`).
    ///
    /// # Errors
    /// [`OutputError::Extension`], naming `option` (e.g. `--out`), for any other extension.
    pub fn of(path: &Path, option: &str) -> Result<Format, OutputError> {
        match path.extension().and_then(|e| e.to_str()) {
            Some("csv") => Ok(Format::Csv),
            Some("json") => Ok(Format::Json),
            Some("jsonl") => Ok(Format::JsonLines),
            _ => Err(OutputError::Extension {
                option: option.to_owned(),
                path: path.to_owned(),
            }),
        }
    }
}

/// Writes rows of one table, in order, as they come.
pub trait TableWriter<R: Serialize> {
    /// Writes one row.
    ///
    /// # Errors
    /// The underlying writer's.
    fn row(&mut self, row: &R) -> std::io::Result<()>;

    /// Ends the table and flushes.
    ///
    /// # Errors
    /// The underlying writer's.
    fn finish(self: Box<Self>) -> std::io::Result<()>;
}

/// A writer of `format` on `out`. `header` is written by the JSON writer before the rows (the
/// other formats carry no header); `preamble` is a comment line the CSV writer puts before
/// its column line (e.g. `# shard 1/4 of 400 points`).
///
/// # Errors
/// The underlying writer's, when the header or the column line cannot be written.
pub fn writer<'w, R: Row + 'w, W: Write + 'w>(
    format: Format,
    out: W,
    header: &Header,
    preamble: Option<&str>,
) -> std::io::Result<Box<dyn TableWriter<R> + 'w>> {
    writer_with_columns(format, out, header, preamble, R::COLUMNS)
}

/// [`writer`] of rows whose columns are named at run time (a [`Renamed`] row): `columns` is
/// the CSV column line, which must name the rows' fields in order.
///
/// # Errors
/// As [`writer`].
pub fn writer_with_columns<'w, R: Serialize + 'w, W: Write + 'w>(
    format: Format,
    out: W,
    header: &Header,
    preamble: Option<&str>,
    columns: &[&str],
) -> std::io::Result<Box<dyn TableWriter<R> + 'w>> {
    Ok(match format {
        Format::Csv => Box::new(CsvWriter::new(out, preamble, columns)?),
        Format::Json => Box::new(JsonWriter::new(out, header)?),
        Format::JsonLines => Box::new(JsonLinesWriter::new(out)),
    })
}

/// Writes every row of `rows` to the file `path` in `format` (created or truncated, buffered).
///
/// # Errors
/// [`OutputError::Io`] naming the file.
pub fn write_table<R: Row>(
    path: &Path,
    format: Format,
    header: &Header,
    rows: impl IntoIterator<Item = R>,
) -> Result<(), OutputError> {
    let io = |source| OutputError::Io {
        path: path.to_owned(),
        source,
    };
    let file = std::fs::File::create(path).map_err(io)?;
    let mut w = writer::<R, _>(format, std::io::BufWriter::new(file), header, None).map_err(io)?;
    for row in rows {
        w.row(&row).map_err(io)?;
    }
    w.finish().map_err(io)
}

/// The table as text in `format`, for tests and small tables.
///
/// # Panics
/// Never: writing to memory cannot fail, and rows serialise to JSON and CSV by construction.
pub fn table_text<R: Row>(format: Format, header: &Header, rows: &[R]) -> String {
    let mut out = Vec::new();
    {
        let mut w = writer::<R, _>(format, &mut out, header, None).expect("writing to memory");
        for row in rows {
            w.row(row).expect("writing to memory");
        }
        w.finish().expect("writing to memory");
    }
    String::from_utf8(out).expect("the writers write UTF-8")
}

#[cfg(test)]
mod tests {
    use super::*;

    table_row! {
        /// A row for the tests.
        pub struct TestRow {
            /// A number.
            pub x: Option<f64>,
            /// A word.
            pub word: Option<String>,
            /// A flag.
            pub flag: bool,
        }
    }

    fn rows() -> Vec<TestRow> {
        vec![
            TestRow {
                x: Some(1.0),
                word: Some("a, b".into()),
                flag: true,
            },
            TestRow {
                x: finite(f64::NAN),
                word: None,
                flag: false,
            },
            TestRow {
                x: Some(1e-7),
                word: Some("plain".into()),
                flag: false,
            },
        ]
    }

    #[test]
    fn columns_are_the_field_names_in_order() {
        assert_eq!(TestRow::COLUMNS, &["x", "word", "flag"]);
    }

    #[test]
    fn the_three_formats_write_the_same_rows() {
        let mut header = Header::default();
        header.push("name", &"t");
        let csv = table_text(Format::Csv, &header, &rows());
        assert_eq!(
            csv,
            "x,word,flag\n1.0,\"a, b\",true\n,,false\n1e-7,plain,false\n"
        );
        let json = table_text(Format::Json, &header, &rows());
        assert_eq!(
            json,
            "{\"name\":\"t\",\"results\":[\n{\"x\":1.0,\"word\":\"a, b\",\"flag\":true},\n\
             {\"x\":null,\"word\":null,\"flag\":false},\n{\"x\":1e-7,\"word\":\"plain\",\"flag\":false}\n]}\n"
        );
        let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(doc["results"].as_array().unwrap().len(), 3);
        let lines = table_text(Format::JsonLines, &header, &rows());
        assert_eq!(lines.lines().count(), 3);
        for (line, row) in lines.lines().zip(rows()) {
            assert_eq!(line, serde_json::to_string(&row).unwrap());
        }
    }

    #[test]
    fn a_list_is_one_cell_of_numbers_as_the_tables_write_them() {
        assert_eq!(number_list(&[]), None);
        assert_eq!(number_list(&[f64::NAN]), None);
        assert_eq!(number_list(&[f64::INFINITY, f64::INFINITY]), None);
        assert_eq!(number_list(&[0.25]).as_deref(), Some("0.25"));
        assert_eq!(
            number_list(&[1.0, 1e-7, f64::NAN, f64::INFINITY, 1.5]).as_deref(),
            Some("1.0;1e-7;;;1.5")
        );
        // Each element reads back as the number, as a number column's cell does.
        let x = [0.1 + 0.2, std::f64::consts::PI, 6.02e23];
        let text = number_list(&x).unwrap();
        let back: Vec<f64> = text.split(';').map(|e| e.parse().unwrap()).collect();
        assert_eq!(back, x);
        let row = TestRow {
            x: Some(x[0]),
            word: None,
            flag: false,
        };
        let csv = table_text(Format::Csv, &Header::default(), &[row]);
        assert!(csv.contains(text.split(';').next().unwrap()), "{csv}");
    }

    #[test]
    fn an_empty_table_is_still_a_table() {
        let header = Header::default();
        assert_eq!(
            table_text::<TestRow>(Format::Csv, &header, &[]),
            "x,word,flag\n"
        );
        let json = table_text::<TestRow>(Format::Json, &header, &[]);
        assert_eq!(json, "{\"results\":[\n]}\n");
        assert!(serde_json::from_str::<serde_json::Value>(&json).is_ok());
    }

    #[test]
    fn the_extension_names_the_format() {
        assert_eq!(
            Format::of(Path::new("a.csv"), "--out").unwrap(),
            Format::Csv
        );
        assert_eq!(
            Format::of(Path::new("a.jsonl"), "--out").unwrap(),
            Format::JsonLines
        );
        let e = Format::of(Path::new("a.txt"), "--out")
            .unwrap_err()
            .to_string();
        assert!(e.contains("--out a.txt") && e.contains(".jsonl"), "{e}");
    }
}
