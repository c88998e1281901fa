//! The JSON writer: one compact document, its header fields first, then `"results"` with one
//! row object per line (so that a document can be read by any JSON parser and shards can be
//! joined line by line).

use super::TableWriter;
use serde::Serialize;
use std::io::Write;

/// The fields a JSON table document carries before its rows, in the order given.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Header {
    /// Each key with its value as compact JSON text, in the value's own field order.
    fields: Vec<(String, String)>,
}

impl Header {
    /// Appends the field `key` with `value`.
    ///
    /// # Panics
    /// If `value` cannot be represented in JSON (a map with non-string keys): the values
    /// pushed by this crate are scenes, numbers, strings and small objects.
    pub fn push(&mut self, key: &str, value: &impl Serialize) {
        let value = serde_json::to_string(value).expect("header values are JSON");
        self.fields.push((key.to_owned(), value));
    }

    /// The fields, in order, each value as compact JSON text.
    pub fn fields(&self) -> &[(String, String)] {
        &self.fields
    }
}

/// Writes a table as one JSON document.
pub struct JsonWriter<W: Write> {
    out: W,
    rows: usize,
}

impl<W: Write> JsonWriter<W> {
    /// Starts the document on `out`: `{`, the header's fields, `"results":[`.
    ///
    /// # Errors
    /// The underlying writer's.
    pub fn new(mut out: W, header: &Header) -> std::io::Result<Self> {
        out.write_all(b"{")?;
        for (key, value) in &header.fields {
            serde_json::to_writer(&mut out, key)?;
            out.write_all(b":")?;
            out.write_all(value.as_bytes())?;
            out.write_all(b",")?;
        }
        out.write_all(b"\"results\":[")?;
        Ok(Self { out, rows: 0 })
    }
}

impl<W: Write> JsonWriter<W> {
    /// Starts the document on `out` with `opening`, the text of a document's start up to and
    /// including `"results":[` as [`JsonWriter::new`] writes it (for joining the parts of a
    /// sharded table).
    ///
    /// # Errors
    /// The underlying writer's.
    pub fn with_opening(mut out: W, opening: &str) -> std::io::Result<Self> {
        out.write_all(opening.as_bytes())?;
        Ok(Self { out, rows: 0 })
    }
}

impl<R: Serialize, W: Write> TableWriter<R> for JsonWriter<W> {
    fn row(&mut self, row: &R) -> std::io::Result<()> {
        self.out
            .write_all(if self.rows == 0 { b"\n" } else { b",\n" })?;
        serde_json::to_writer(&mut self.out, row)?;
        self.rows += 1;
        Ok(())
    }

    fn finish(mut self: Box<Self>) -> std::io::Result<()> {
        self.out.write_all(b"\n]}\n")?;
        self.out.flush()
    }
}
