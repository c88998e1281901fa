//! The CSV writer: a column line, then one line per row (the `csv` crate; fields quoted only
//! where they must be).

use super::TableWriter;
use serde::Serialize;
use std::io::Write;

/// Writes a table as CSV.
pub struct CsvWriter<W: Write> {
    inner: ::csv::Writer<W>,
}

impl<W: Write> CsvWriter<W> {
    /// Starts the table on `out`: the `preamble` line if any (e.g. `# shard 1/4 of 400
    /// points`), then the line of `columns`.
    ///
    /// # Errors
    /// The underlying writer's.
    pub fn new(mut out: W, preamble: Option<&str>, columns: &[&str]) -> std::io::Result<Self> {
        if let Some(line) = preamble {
            writeln!(out, "{line}")?;
        }
        let mut inner = ::csv::WriterBuilder::new()
            .has_headers(false)
            .from_writer(out);
        inner.write_record(columns)?;
        Ok(Self { inner })
    }
}

impl<R: Serialize, W: Write> TableWriter<R> for CsvWriter<W> {
    fn row(&mut self, row: &R) -> std::io::Result<()> {
        Ok(self.inner.serialize(row)?)
    }

    fn finish(mut self: Box<Self>) -> std::io::Result<()> {
        self.inner.flush()
    }
}
