//! Sharded runs: part `K` of `N` of a sweep computes a contiguous block of its frequencies, of
//! a map a block of its whole `(e, Δ/u_g)` lines, of basins a block of its starts; [`merge`]
//! joins the parts into exactly the file the unsharded run writes.

use serde::{Deserialize, Serialize};

/// One part `index` (1-based) of `count` of a sweep: a contiguous block of its frequencies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct Shard {
    /// Which part, `1 ≤ index ≤ count`.
    pub index: usize,
    /// How many parts.
    pub count: usize,
}

impl Shard {
    /// Parses `K/N` with `1 ≤ K ≤ N`.
    ///
    /// # Errors
    /// A message naming `--shard` and the allowed form.
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {text}: must be K/N with 1 ≤ K ≤ N, e.g. 3/8");
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = k.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if index == 0 || index > count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The indices of this part among `total` frequencies: block `index` of `count` nearly
    /// equal contiguous blocks.
    pub fn range(&self, total: usize) -> std::ops::Range<usize> {
        let start = (self.index - 1) * total / self.count;
        let end = self.index * total / self.count;
        start..end
    }

    /// The comment line a CSV part starts with: `# shard K/N of P points`.
    pub fn csv_preamble(&self, total: usize) -> String {
        self.csv_preamble_of(total, "points")
    }

    /// The comment line a CSV part of a table of `total` rows of `unit` (`points`, `lines`,
    /// `starts`) starts with: `# shard K/N of P unit`.
    pub fn csv_preamble_of(&self, total: usize, unit: &str) -> String {
        format!("# shard {}/{} of {total} {unit}", self.index, self.count)
    }
}

/// The merge of every sharded run's parts (sweeps', maps' and basins'), which the runs' module
/// holds: it hands basins' parts to [`super::basins`] and the others to `merge_tables`.
pub use super::merge;

/// Joins the parts of a sharded sweep or map (its points or its bandwidth table; all JSON or
/// all CSV, in any order, at least one) into exactly the text the unsharded run writes.
///
/// # Errors
/// A message when a part is not a shard, when parts are missing, repeated or from different
/// sweeps, or when the rows do not add up to the sweep's points.
pub(crate) fn merge_tables(parts: &[String]) -> Result<String, String> {
    if parts[0].trim_start().starts_with('{') {
        merge_json(parts)
    } else {
        merge_csv(parts)
    }
}

/// Checks that `shards` are each of `1..=N` once.
pub(crate) fn check_cover(shards: &[Shard]) -> Result<(), String> {
    let count = shards[0].count;
    if shards.iter().any(|s| s.count != count) {
        return Err("the parts come from sweeps cut into different numbers of shards".into());
    }
    let mut got: Vec<usize> = shards.iter().map(|s| s.index).collect();
    got.sort_unstable();
    if got != (1..=count).collect::<Vec<_>>() {
        return Err(format!(
            "shards {got:?} given; need each of 1..={count} once"
        ));
    }
    Ok(())
}

/// A JSON part as written by the JSON table writer: its header line (ending `"results":[`)
/// without the shard field, the shard, and its row lines without separators.
struct JsonPart<'a> {
    header: String,
    shard: Shard,
    points: u64,
    rows: Vec<&'a str>,
}

fn json_part(i: usize, text: &str) -> Result<JsonPart<'_>, String> {
    let bad = |what: &str| format!("part {}: {what}", i + 1);
    let mut lines = text.lines();
    let first = lines.next().ok_or_else(|| bad("empty"))?;
    let head: serde_json::Value = serde_json::from_str(&format!("{first}]}}"))
        .map_err(|e| bad(&format!("not a sweep document ({e})")))?;
    let shard: Shard = match (
        head["shard"]["index"].as_u64(),
        head["shard"]["count"].as_u64(),
    ) {
        (Some(k), Some(n)) => Shard {
            index: k as usize,
            count: n as usize,
        },
        _ => return Err(bad("not a shard (no \"shard\")")),
    };
    let field = serde_json::to_string(&shard).map_err(|e| bad(&e.to_string()))?;
    let header = first.replacen(&format!(",\"shard\":{field}"), "", 1);
    let points = ["points", "lines", "starts"]
        .iter()
        .find_map(|key| head[key].as_u64())
        .ok_or_else(|| bad("no \"points\""))?;
    let mut rows: Vec<&str> = lines.collect();
    if rows.pop() != Some("]}") {
        return Err(bad("truncated (no closing \"]}\")"));
    }
    let rows = rows
        .into_iter()
        .map(|r| r.strip_suffix(',').unwrap_or(r))
        .collect();
    Ok(JsonPart {
        header,
        shard,
        points,
        rows,
    })
}

fn merge_json(parts: &[String]) -> Result<String, String> {
    let mut parsed: Vec<JsonPart> = parts
        .iter()
        .enumerate()
        .map(|(i, p)| json_part(i, p))
        .collect::<Result<_, _>>()?;
    check_cover(&parsed.iter().map(|p| p.shard).collect::<Vec<_>>())?;
    if parsed.iter().any(|p| p.header != parsed[0].header) {
        return Err("the parts come from different sweeps (scene, solver or points differ)".into());
    }
    parsed.sort_by_key(|p| p.shard.index);
    let rows: Vec<&str> = parsed.iter().flat_map(|p| p.rows.iter().copied()).collect();
    if rows.len() as u64 != parsed[0].points {
        return Err(format!(
            "{} results for {} points",
            rows.len(),
            parsed[0].points
        ));
    }
    let mut out = parsed[0].header.clone();
    for (i, row) in rows.iter().enumerate() {
        out.push_str(if i == 0 { "\n" } else { ",\n" });
        out.push_str(row);
    }
    out.push_str("\n]}\n");
    Ok(out)
}

fn merge_csv(parts: &[String]) -> Result<String, String> {
    let mut shards = Vec::new();
    let mut bodies = Vec::new();
    let mut total = None;
    for (i, p) in parts.iter().enumerate() {
        let (first, rest) = p.split_once('\n').ok_or(format!("part {}: empty", i + 1))?;
        let spec = first
            .strip_prefix("# shard ")
            .and_then(|s| {
                s.strip_suffix(" points")
                    .or_else(|| s.strip_suffix(" lines"))
            })
            .ok_or(format!(
                "part {}: not a shard (no '# shard K/N of P points' line)",
                i + 1
            ))?;
        let (kn, p_total) = spec
            .split_once(" of ")
            .ok_or(format!("part {}: bad shard line", i + 1))?;
        let shard = Shard::parse(kn).map_err(|e| format!("part {}: {e}", i + 1))?;
        shards.push(shard);
        if total.is_some_and(|t| t != p_total) {
            return Err("the parts come from sweeps of different sizes".into());
        }
        total = Some(p_total);
        bodies.push((shard.index, rest));
    }
    check_cover(&shards)?;
    bodies.sort_by_key(|b| b.0);
    let header = bodies[0].1.lines().next().unwrap_or_default();
    let mut out = format!("{header}\n");
    for (_, body) in &bodies {
        let mut lines = body.lines();
        if lines.next() != Some(header) {
            return Err("the parts have different columns".into());
        }
        for line in lines {
            out.push_str(line);
            out.push('\n');
        }
    }
    let rows = out.lines().count() - 1;
    if total.and_then(|t| t.parse::<usize>().ok()) != Some(rows) {
        return Err(format!("{rows} rows for {} points", total.unwrap_or("?")));
    }
    Ok(out)
}
