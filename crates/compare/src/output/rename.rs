//! Rows written with some of their columns renamed: a table whose column names depend on the
//! run (a map's axes, a structure's bodies in place of a chain's cells) writes its one row type
//! under the names the run gives, in every format alike.

use super::Row;
use serde::ser::{self, Impossible, Serialize, SerializeStruct, Serializer};

/// `row`, written with each column `from` of `renames` named `to` (a column not listed keeps
/// its name): in CSV the column line ([`Renamed::columns`]), in JSON and JSON Lines the keys.
/// The values and their order are the row's own, byte for byte.
#[derive(Debug, Clone, PartialEq)]
pub struct Renamed<R> {
    /// The row.
    pub row: R,
    /// Each renamed column as `(from, to)`.
    pub renames: &'static [(&'static str, &'static str)],
}

impl<R: Row> Renamed<R> {
    /// `R`'s columns, in order, under `renames`.
    pub fn columns(renames: &[(&'static str, &'static str)]) -> Vec<&'static str> {
        R::COLUMNS
            .iter()
            .map(|&column| renamed(renames, column))
            .collect()
    }
}

/// `column` under `renames`.
fn renamed(renames: &[(&'static str, &'static str)], column: &'static str) -> &'static str {
    renames
        .iter()
        .find(|(from, _)| *from == column)
        .map_or(column, |&(_, to)| to)
}

impl<R: Serialize> Serialize for Renamed<R> {
    fn serialize<S: Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        self.row.serialize(Renaming {
            inner: serializer,
            renames: self.renames,
        })
    }
}

/// The serializer a [`Renamed`] row goes through: a struct's fields handed to `inner` under
/// their new names; anything but a struct is refused (a row is a struct).
struct Renaming<S> {
    inner: S,
    renames: &'static [(&'static str, &'static str)],
}

/// The fields of a renamed struct, handed on to the inner serializer's struct.
struct RenamingStruct<T> {
    inner: T,
    renames: &'static [(&'static str, &'static str)],
}

impl<T: SerializeStruct> SerializeStruct for RenamingStruct<T> {
    type Ok = T::Ok;
    type Error = T::Error;

    fn serialize_field<V: ?Sized + Serialize>(
        &mut self,
        key: &'static str,
        value: &V,
    ) -> Result<(), T::Error> {
        self.inner
            .serialize_field(renamed(self.renames, key), value)
    }

    fn skip_field(&mut self, key: &'static str) -> Result<(), T::Error> {
        self.inner.skip_field(renamed(self.renames, key))
    }

    fn end(self) -> Result<T::Ok, T::Error> {
        self.inner.end()
    }
}

/// The error of a renamed value that is not a struct.
fn not_a_struct<E: ser::Error>(what: &str) -> E {
    E::custom(format!("a renamed row is a struct, not {what}"))
}

/// Refuses each listed `serialize_*` method of [`Renaming`]: a row is a struct.
macro_rules! not_a_struct {
    ($($method:ident($($arg:ty),*) -> $out:ty;)*) => {
        $(
            fn $method(self, $(_: $arg),*) -> Result<$out, S::Error> {
                Err(not_a_struct(stringify!($method)))
            }
        )*
    };
}

impl<S: Serializer> Serializer for Renaming<S> {
    type Ok = S::Ok;
    type Error = S::Error;
    type SerializeSeq = Impossible<S::Ok, S::Error>;
    type SerializeTuple = Impossible<S::Ok, S::Error>;
    type SerializeTupleStruct = Impossible<S::Ok, S::Error>;
    type SerializeTupleVariant = Impossible<S::Ok, S::Error>;
    type SerializeMap = Impossible<S::Ok, S::Error>;
    type SerializeStruct = RenamingStruct<S::SerializeStruct>;
    type SerializeStructVariant = Impossible<S::Ok, S::Error>;

    fn serialize_struct(
        self,
        name: &'static str,
        len: usize,
    ) -> Result<Self::SerializeStruct, S::Error> {
        Ok(RenamingStruct {
            inner: self.inner.serialize_struct(name, len)?,
            renames: self.renames,
        })
    }

    fn serialize_some<T: ?Sized + Serialize>(self, _: &T) -> Result<S::Ok, S::Error> {
        Err(not_a_struct("an option"))
    }

    fn serialize_newtype_struct<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: &T,
    ) -> Result<S::Ok, S::Error> {
        Err(not_a_struct("a newtype"))
    }

    fn serialize_newtype_variant<T: ?Sized + Serialize>(
        self,
        _: &'static str,
        _: u32,
        _: &'static str,
        _: &T,
    ) -> Result<S::Ok, S::Error> {
        Err(not_a_struct("a variant"))
    }

    not_a_struct! {
        serialize_bool(bool) -> S::Ok;
        serialize_i8(i8) -> S::Ok;
        serialize_i16(i16) -> S::Ok;
        serialize_i32(i32) -> S::Ok;
        serialize_i64(i64) -> S::Ok;
        serialize_u8(u8) -> S::Ok;
        serialize_u16(u16) -> S::Ok;
        serialize_u32(u32) -> S::Ok;
        serialize_u64(u64) -> S::Ok;
        serialize_f32(f32) -> S::Ok;
        serialize_f64(f64) -> S::Ok;
        serialize_char(char) -> S::Ok;
        serialize_str(&str) -> S::Ok;
        serialize_bytes(&[u8]) -> S::Ok;
        serialize_none() -> S::Ok;
        serialize_unit() -> S::Ok;
        serialize_unit_struct(&'static str) -> S::Ok;
        serialize_unit_variant(&'static str, u32, &'static str) -> S::Ok;
        serialize_seq(Option<usize>) -> Self::SerializeSeq;
        serialize_tuple(usize) -> Self::SerializeTuple;
        serialize_tuple_struct(&'static str, usize) -> Self::SerializeTupleStruct;
        serialize_tuple_variant(&'static str, u32, &'static str, usize) -> Self::SerializeTupleVariant;
        serialize_map(Option<usize>) -> Self::SerializeMap;
        serialize_struct_variant(&'static str, u32, &'static str, usize) -> Self::SerializeStructVariant;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::output::{table_row, table_text, writer_with_columns, Format, Header};

    table_row! {
        /// A row for the tests.
        pub struct TestRow {
            /// A number.
            pub a: Option<f64>,
            /// A word, with a comma.
            pub b: Option<String>,
            /// A flag.
            pub c: bool,
        }
    }

    fn row() -> TestRow {
        TestRow {
            a: Some(0.25),
            b: Some("x, y".into()),
            c: true,
        }
    }

    fn text(format: Format, renames: &'static [(&'static str, &'static str)]) -> String {
        let mut out = Vec::new();
        {
            let mut w = writer_with_columns::<Renamed<TestRow>, _>(
                format,
                &mut out,
                &Header::default(),
                None,
                &Renamed::<TestRow>::columns(renames),
            )
            .expect("writing to memory");
            w.row(&Renamed {
                row: row(),
                renames,
            })
            .expect("writing to memory");
            w.finish().expect("writing to memory");
        }
        String::from_utf8(out).expect("UTF-8")
    }

    #[test]
    fn no_renames_write_the_row_itself_byte_for_byte() {
        for format in [Format::Csv, Format::Json, Format::JsonLines] {
            assert_eq!(
                text(format, &[]),
                table_text(format, &Header::default(), &[row()])
            );
        }
    }

    #[test]
    fn renamed_columns_are_renamed_in_every_format() {
        const RENAMES: &[(&str, &str)] = &[("a", "x"), ("c", "z")];
        assert_eq!(Renamed::<TestRow>::columns(RENAMES), ["x", "b", "z"]);
        assert_eq!(text(Format::Csv, RENAMES), "x,b,z\n0.25,\"x, y\",true\n");
        assert_eq!(
            text(Format::JsonLines, RENAMES),
            "{\"x\":0.25,\"b\":\"x, y\",\"z\":true}\n"
        );
        assert!(text(Format::Json, RENAMES).contains("{\"x\":0.25,\"b\":\"x, y\",\"z\":true}"));
    }
}
