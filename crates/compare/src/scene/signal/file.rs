//! Signal records and spectra from CSV files: a header line naming the two columns, then one
//! line per sample, each two finite numbers (blank lines and lines starting with `#` are
//! skipped).

use super::{shown, BuiltSignal, Input, SignalDescription, SignalSpecError};
use rattle_event_driven::Signal;
use std::path::Path;

/// The two columns of a file: its header's second column and its rows `(x, y)`.
pub struct Columns {
    /// The second column's name, one of those allowed.
    pub name: &'static str,
    /// The rows.
    pub rows: Vec<(f64, f64)>,
}

/// Reads `path`, a CSV file with the header `first,SECOND` where `SECOND` is one of `seconds`;
/// the first column starts at `0` when `from_zero` and increases strictly.
///
/// # Errors
/// [`SignalSpecError`] naming the file and the field: `file` (unreadable), `columns` (a
/// header other than those allowed, a row without exactly two cells), the column whose cell
/// is not a finite number (with its line), the first column out of order (decreasing or
/// repeated, or not starting at 0).
pub fn read_columns(
    path: &Path,
    first: &str,
    seconds: &[&'static str],
    from_zero: bool,
) -> Result<Columns, SignalSpecError> {
    let spec = shown(path);
    let text = std::fs::read_to_string(path)
        .map_err(|e| SignalSpecError::new(&spec, "file", format!("cannot be read: {e}")))?;
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'));
    let allowed = seconds
        .iter()
        .map(|s| format!("`{first},{s}`"))
        .collect::<Vec<_>>()
        .join(" or ");
    let header: Vec<&str> = lines
        .next()
        .map(|(_, l)| l.split(',').map(str::trim).collect())
        .unwrap_or_default();
    let name = match header.as_slice() {
        [a, b] if *a == first => seconds.iter().find(|s| *s == b).copied(),
        _ => None,
    }
    .ok_or_else(|| {
        SignalSpecError::new(
            &spec,
            "columns",
            format!(
                "`{}` are not the columns: the header must be {allowed}",
                header.join(",")
            ),
        )
    })?;
    let mut rows: Vec<(f64, f64)> = Vec::new();
    for (line, l) in lines {
        let cells: Vec<&str> = l.split(',').map(str::trim).collect();
        if cells.len() != 2 {
            return Err(SignalSpecError::new(
                &spec,
                "columns",
                format!(
                    "on line {line} has {} cells: every row has the two columns {first},{name}",
                    cells.len()
                ),
            ));
        }
        let number = |cell: &str, column: &str| {
            cell.parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| {
                    SignalSpecError::new(
                        &spec,
                        column,
                        format!("on line {line} = {cell} is out of range: must be a finite number"),
                    )
                })
        };
        let x = number(cells[0], first)?;
        let y = number(cells[1], name)?;
        match rows.last() {
            None if from_zero && x != 0.0 => {
                return Err(SignalSpecError::new(
                    &spec,
                    first,
                    format!("on line {line} = {x} is out of range: the first must be 0"),
                ))
            }
            Some(&(previous, _)) if x <= previous => {
                return Err(SignalSpecError::new(
                    &spec,
                    first,
                    format!(
                        "on line {line} = {x} is out of range: must be after the previous \
                         {previous} (strictly increasing, none repeated)"
                    ),
                ))
            }
            _ => {}
        }
        rows.push((x, y));
    }
    if rows.is_empty() {
        return Err(SignalSpecError::new(
            &spec,
            "columns",
            "has no rows: at least one sample",
        ));
    }
    Ok(Columns { name, rows })
}

/// The record in `path` (`t,u_g` or `t,F`) as a signal: the piecewise-linear interpolation
/// of its samples, held at the last value after the last.
///
/// # Errors
/// As [`read_columns`].
pub fn build(path: &Path) -> Result<BuiltSignal, SignalSpecError> {
    let columns = read_columns(path, "t", &["u_g", "F"], true)?;
    let spec = shown(path);
    let signal = Signal::from_samples(&columns.rows)
        .map_err(|e| SignalSpecError::new(&spec, "t", e.to_string()))?;
    let input = if columns.name == "F" {
        Input::Force
    } else {
        Input::Base
    };
    let rows = &columns.rows;
    let shortest_step = rows
        .windows(2)
        .map(|w| w[1].0 - w[0].0)
        .fold(f64::INFINITY, f64::min);
    Ok(BuiltSignal {
        signal,
        input,
        description: SignalDescription::File {
            path: spec,
            column: columns.name,
            samples: rows.len(),
            last_time: rows[rows.len() - 1].0,
            shortest_step: if shortest_step.is_finite() {
                shortest_step
            } else {
                0.0
            },
        },
    })
}
