//! The parts of sharded basins read back (JSON or CSV, [`is_basins_part`]) and joined into
//! exactly the whole grid's table ([`merge_parts`]).

use super::attractor::{number, Attractor, Reached};
use super::output::{plane_rows, BasinRow, PlaneRow, BODY_AMPLITUDES};
use crate::output::{CsvWriter, JsonWriter, Row, TableWriter};
use crate::runs::shard::{check_cover, Shard};
use serde::Deserialize;

/// Whether `text` is a part of sharded basins (its header or first line lists the part's
/// attractors).
pub fn is_basins_part(text: &str) -> bool {
    let first = text.lines().next().unwrap_or_default();
    (first.starts_with("# shard ") && first.contains(" starts, attractors: "))
        || (first.starts_with('{') && first.contains(",\"attractors\":"))
}

/// One part of sharded basins, read back: its shard, the whole grid's starts, the opening of
/// the whole grid's JSON document (for a JSON part), its columns (none for a JSON part
/// without rows) and its starts with every body's amplitude of each (empty without a
/// `body_amplitudes` column).
struct BasinsPart {
    shard: Shard,
    total: usize,
    opening: Option<String>,
    columns: Vec<String>,
    reached: Vec<Reached>,
    amplitudes: Vec<Vec<Option<f64>>>,
}

/// A number cell of a part: empty or `null` is NaN (as [`finite`] wrote it).
///
/// [`finite`]: crate::output::finite
fn number_cell(text: &str) -> Result<f64, String> {
    if text.is_empty() || text == "null" {
        return Ok(f64::NAN);
    }
    text.parse()
        .map_err(|_| format!("{text:?} is not a number"))
}

/// Whether `columns` are a basins table's: two starts' (`…_start`), [`BasinRow`]'s others, and
/// optionally [`BODY_AMPLITUDES`].
fn basins_columns(columns: &[String]) -> bool {
    let rest = BasinRow::COLUMNS[2..].iter().map(|c| (*c).to_owned());
    (columns.len() == 6 || (columns.len() == 7 && columns[6] == BODY_AMPLITUDES))
        && columns[..2].iter().all(|c| c.ends_with("_start"))
        && columns[2..6].iter().cloned().eq(rest)
}

/// A start of a part from its cells: the attractor is the part's `attractors[attractor]`, a
/// periodic one with the start's own `X_o` or, with a `body_amplitudes` cell, its own body
/// amplitudes (as `reach` in `run.rs` found it). Returns the start and its body amplitudes.
fn reached_of(
    attractors: &[Attractor],
    [outer, inner, attractor, amplitude, periods]: [&str; 5],
    bodies: Option<&str>,
) -> Result<(Reached, Vec<Option<f64>>), String> {
    let outer_amplitude = number_cell(amplitude)?;
    let index: usize = attractor
        .parse()
        .map_err(|_| format!("attractor {attractor:?} is not a number"))?;
    let mut attractor = attractors
        .get(index)
        .cloned()
        .ok_or_else(|| format!("attractor {index} is not in the part's list"))?;
    if let Attractor::Periodic {
        outer_amplitude: x, ..
    } = &mut attractor
    {
        *x = outer_amplitude;
    }
    if let (Attractor::Motion { amplitudes, .. }, Some(cell)) = (&mut attractor, bodies) {
        let n = amplitudes.len();
        let own: Vec<Option<f64>> = if cell.is_empty() || cell == "null" {
            vec![None; n]
        } else {
            cell.trim_matches('"')
                .split(';')
                .map(|x| number_cell(x).map(|x| x.is_finite().then_some(x)))
                .collect::<Result<_, _>>()?
        };
        if own.len() != n {
            return Err(format!("{BODY_AMPLITUDES} {cell:?}: {n} bodies expected"));
        }
        *amplitudes = own;
    }
    let own = attractor.body_amplitudes().to_vec();
    Ok((
        Reached {
            outer: number_cell(outer)?,
            inner: number_cell(inner)?,
            attractor,
            outer_amplitude,
            periods_run: periods
                .parse()
                .map_err(|_| format!("periods_run {periods:?} is not a count"))?,
        },
        own,
    ))
}

/// A JSON object's entries in the order written.
struct Entries(Vec<(String, serde_json::Value)>);

impl<'de> Deserialize<'de> for Entries {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visit;
        impl<'de> serde::de::Visitor<'de> for Visit {
            type Value = Entries;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a JSON object")
            }
            fn visit_map<A: serde::de::MapAccess<'de>>(
                self,
                mut map: A,
            ) -> Result<Entries, A::Error> {
                let mut entries = Vec::new();
                while let Some(entry) = map.next_entry()? {
                    entries.push(entry);
                }
                Ok(Entries(entries))
            }
        }
        deserializer.deserialize_map(Visit)
    }
}

fn json_basins_part(text: &str) -> Result<BasinsPart, String> {
    let mut lines = text.lines();
    let first = lines.next().unwrap_or_default();
    let head: serde_json::Value = serde_json::from_str(&format!("{first}]}}"))
        .map_err(|e| format!("not a basins document ({e})"))?;
    let shard: Shard =
        serde_json::from_value(head["shard"].clone()).map_err(|e| format!("shard: {e}"))?;
    let attractors: Vec<Attractor> = serde_json::from_value(head["attractors"].clone())
        .map_err(|e| format!("attractors: {e}"))?;
    let total = head["starts"].as_u64().ok_or("no \"starts\"")? as usize;
    let cut = first.rfind(",\"starts\":").ok_or("no \"starts\"")?;
    let opening = format!("{},\"results\":[", &first[..cut]);
    let mut rows: Vec<&str> = lines.collect();
    if rows.pop() != Some("]}") {
        return Err("truncated (no closing \"]}\")".into());
    }
    let mut columns: Vec<String> = Vec::new();
    let mut reached = Vec::with_capacity(rows.len());
    let mut amplitudes = Vec::with_capacity(rows.len());
    for line in rows {
        let Entries(row): Entries =
            serde_json::from_str(line.trim_end_matches(',')).map_err(|e| format!("a row: {e}"))?;
        let names: Vec<String> = row.iter().map(|(k, _)| k.clone()).collect();
        if !basins_columns(&names) {
            return Err("the columns are not those of a basins table".into());
        }
        if columns.is_empty() {
            columns = names;
        } else if columns != names {
            return Err("the rows' columns differ".into());
        }
        let cell = |k: usize| match &row[k].1 {
            serde_json::Value::Null => String::new(),
            v => v.to_string(),
        };
        let bodies = (row.len() == 7).then(|| cell(6));
        let (r, own) = reached_of(
            &attractors,
            [&cell(0), &cell(1), &cell(2), &cell(4), &cell(5)],
            bodies.as_deref(),
        )?;
        reached.push(r);
        amplitudes.push(own);
    }
    Ok(BasinsPart {
        shard,
        total,
        opening: Some(opening),
        columns,
        reached,
        amplitudes,
    })
}

fn csv_basins_part(text: &str) -> Result<BasinsPart, String> {
    let (first, body) = text.split_once('\n').ok_or("empty")?;
    let bad = || "not a basins part (no '# shard K/N of P starts, attractors: [...]' line)";
    let spec = first.strip_prefix("# shard ").ok_or_else(bad)?;
    let (kn, rest) = spec.split_once(" of ").ok_or_else(bad)?;
    let (total, list) = rest.split_once(" starts, attractors: ").ok_or_else(bad)?;
    let shard = Shard::parse(kn)?;
    let total: usize = total.parse().map_err(|_| bad())?;
    let attractors: Vec<Attractor> =
        serde_json::from_str(list).map_err(|e| format!("attractors: {e}"))?;
    let mut reader = ::csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(body.as_bytes());
    let columns: Vec<String> = reader
        .headers()
        .map_err(|e| e.to_string())?
        .iter()
        .map(str::to_owned)
        .collect();
    if !basins_columns(&columns) {
        return Err("the columns are not those of a basins table".into());
    }
    let bodies = columns.len() == 7;
    let mut reached = Vec::new();
    let mut amplitudes = Vec::new();
    for record in reader.records() {
        let r = record.map_err(|e| e.to_string())?;
        let cell = |k: usize| r.get(k).unwrap_or_default();
        let (one, own) = reached_of(
            &attractors,
            [cell(0), cell(1), cell(2), cell(4), cell(5)],
            bodies.then(|| cell(6)),
        )?;
        reached.push(one);
        amplitudes.push(own);
    }
    Ok(BasinsPart {
        shard,
        total,
        opening: None,
        columns,
        reached,
        amplitudes,
    })
}

/// Joins the parts of sharded basins (all JSON or all CSV, in any order) into exactly the
/// table the unsharded run writes: the starts in grid order, the attractors numbered by first
/// appearance over the whole grid, each start's attractor decided as the whole grid decides
/// it ([`number`]).
///
/// # Errors
/// A message when a part is not a basins part, when parts are missing, repeated or from
/// different grids, or when the rows do not add up to the grid's starts.
pub fn merge_parts(parts: &[String]) -> Result<String, String> {
    let mut parsed: Vec<BasinsPart> = parts
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let part = if p.trim_start().starts_with('{') {
                json_basins_part(p)
            } else {
                csv_basins_part(p)
            };
            part.map_err(|e| format!("part {}: {e}", i + 1))
        })
        .collect::<Result<_, _>>()?;
    check_cover(&parsed.iter().map(|p| p.shard).collect::<Vec<_>>())?;
    let columns = parsed
        .iter()
        .find(|p| !p.columns.is_empty())
        .map(|p| p.columns.clone())
        .unwrap_or_default();
    if parsed.iter().any(|p| {
        p.opening != parsed[0].opening
            || p.total != parsed[0].total
            || !(p.columns.is_empty() || p.columns == columns)
    }) {
        return Err(
            "the parts come from different basins (scene, frequency, grid or coordinates differ)"
                .into(),
        );
    }
    parsed.sort_by_key(|p| p.shard.index);
    let total = parsed[0].total;
    let opening = parsed[0].opening.clone();
    let mut reached: Vec<Reached> = Vec::with_capacity(total);
    let mut amplitudes: Vec<Vec<Option<f64>>> = Vec::with_capacity(total);
    for p in parsed {
        reached.extend(p.reached);
        amplitudes.extend(p.amplitudes);
    }
    if reached.len() != total {
        return Err(format!("{} starts for a grid of {total}", reached.len()));
    }
    if columns.len() < 6 {
        return Err("no part has rows".into());
    }
    let starts = [columns[0].clone(), columns[1].clone()];
    let bodies = (columns.len() == 7).then_some(&amplitudes[..]);
    let (attractors, _, cells) = number(reached);
    let mut out = Vec::new();
    let keyed = opening.is_some();
    let mut table: Box<dyn TableWriter<PlaneRow>> = match &opening {
        Some(opening) => {
            Box::new(JsonWriter::with_opening(&mut out, opening).map_err(|e| e.to_string())?)
        }
        None => {
            let names: Vec<&str> = columns.iter().map(String::as_str).collect();
            Box::new(CsvWriter::new(&mut out, None, &names).map_err(|e| e.to_string())?)
        }
    };
    for row in plane_rows(&starts, &attractors, &cells, bodies, keyed) {
        table.row(&row).map_err(|e| e.to_string())?;
    }
    table.finish().map_err(|e| e.to_string())?;
    String::from_utf8(out).map_err(|e| e.to_string())
}
