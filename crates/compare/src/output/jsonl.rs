//! The JSON Lines writer: one compact object per row, one row per line, nothing else.

use super::TableWriter;
use serde::Serialize;
use std::io::Write;

/// Writes a table as JSON Lines.
pub struct JsonLinesWriter<W: Write> {
    out: W,
}

impl<W: Write> JsonLinesWriter<W> {
    /// A table on `out`.
    pub fn new(out: W) -> Self {
        Self { out }
    }
}

impl<R: Serialize, W: Write> TableWriter<R> for JsonLinesWriter<W> {
    fn row(&mut self, row: &R) -> std::io::Result<()> {
        serde_json::to_writer(&mut self.out, row)?;
        self.out.write_all(b"\n")
    }

    fn finish(mut self: Box<Self>) -> std::io::Result<()> {
        self.out.flush()
    }
}
