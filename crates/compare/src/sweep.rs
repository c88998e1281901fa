//! Frequency sweeps: every point computed independently and in parallel (rayon), collected in
//! frequency order, so the output is the same whatever the number of threads.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicUsize, Ordering};

/// `points` frequencies evenly spaced from `omega_min` to `omega_max` inclusive.
pub fn frequencies(omega_min: f64, omega_max: f64, points: usize) -> Vec<f64> {
    match points {
        0 => Vec::new(),
        1 => vec![omega_min],
        n => (0..n)
            .map(|i| omega_min + (omega_max - omega_min) * i as f64 / (n - 1) as f64)
            .collect(),
    }
}

/// Maps `work` over `inputs` in parallel, in order; draws a progress line on stderr when it is
/// a terminal and `label` is given. Inputs are handed out one at a time: the cost of a
/// frequency can differ by orders of magnitude from its neighbour's, and coarse blocks would
/// leave a thread idle at the end. For cheap, even work use [`parallel_map_even`].
pub fn parallel_map<I, O, F>(inputs: &[I], label: Option<&str>, work: F) -> Vec<O>
where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
{
    map_with_grain(inputs, label, 1, work)
}

/// [`parallel_map`] for work of even, small cost per input (rayon's adaptive blocks).
pub fn parallel_map_even<I, O, F>(inputs: &[I], label: Option<&str>, work: F) -> Vec<O>
where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
{
    map_with_grain(inputs, label, usize::MAX, work)
}

fn map_with_grain<I, O, F>(inputs: &[I], label: Option<&str>, grain: usize, work: F) -> Vec<O>
where
    I: Sync,
    O: Send,
    F: Fn(&I) -> O + Sync + Send,
{
    use rayon::prelude::*;
    let total = inputs.len();
    let done = AtomicUsize::new(0);
    let show = label.filter(|_| std::io::stderr().is_terminal());
    let out: Vec<O> = inputs
        .par_iter()
        .with_max_len(grain)
        .map(|input| {
            let result = work(input);
            if let Some(label) = show {
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if n == total || n % (total / 100).max(1) == 0 {
                    eprint!(
                        "\r{label}: {n}/{total} ({:.0}%)",
                        100.0 * n as f64 / total as f64
                    );
                }
            }
            result
        })
        .collect();
    if show.is_some() {
        eprintln!();
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frequencies_are_inclusive_and_even() {
        let f = frequencies(1.0, 2.0, 5);
        assert_eq!(f, vec![1.0, 1.25, 1.5, 1.75, 2.0]);
        assert_eq!(frequencies(1.0, 2.0, 1), vec![1.0]);
    }

    #[test]
    fn parallel_map_keeps_order() {
        let inputs: Vec<usize> = (0..1000).collect();
        let out = parallel_map(&inputs, None, |&i| i * 2);
        assert!(out.iter().enumerate().all(|(i, &o)| o == 2 * i));
    }
}

use crate::classify::{compare, ComparedPoint};
use crate::frequency::{analyse, AnalyticPoint};
use crate::json::{csv_row, number};
use crate::scene::Scene;
use crate::simulation::{run, SimulatedPoint};
use rattle_event_driven::{SimulationOptions, Start};
use serde_json::{json, Value};

/// Which solver a sweep runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Solver {
    /// The closed-form solver: linear steady state and symmetric two-impact orbits.
    Analytic,
    /// The event-driven simulator from rest.
    Event,
    /// Both, with the simulator also started on every viable orbit, and a verdict.
    Both,
}

impl Solver {
    /// The solver's name as on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Solver::Analytic => "analytic",
            Solver::Event => "event",
            Solver::Both => "both",
        }
    }
}

/// The result at one frequency of a sweep.
#[derive(Debug, Clone)]
pub enum SweepPoint {
    /// Analytic only.
    Analytic(AnalyticPoint),
    /// Simulator only.
    Event(SimulatedPoint),
    /// Both and the verdict.
    Both(Box<ComparedPoint>),
    /// This frequency failed; the message says why.
    Failed {
        /// The frequency.
        omega: f64,
        /// Why.
        message: String,
    },
}

/// Runs `solver` on `scene` at every frequency of `omegas`, in parallel, in order.
pub fn sweep(
    scene: &Scene,
    omegas: &[f64],
    solver: Solver,
    options: &SimulationOptions,
    progress: bool,
) -> Vec<SweepPoint> {
    let label = progress.then_some("sweep");
    // Analytic points cost about the same; simulations differ by orders of magnitude.
    let grain = match solver {
        Solver::Analytic => usize::MAX,
        Solver::Event | Solver::Both => 1,
    };
    map_with_grain(omegas, label, grain, |&omega| {
        let failed = |message: String| SweepPoint::Failed { omega, message };
        match solver {
            Solver::Analytic => analyse(scene, omega, false)
                .map(SweepPoint::Analytic)
                .unwrap_or_else(|e| failed(e.to_string())),
            Solver::Event => run(scene, omega, &Start::rest(2), options)
                .map(SweepPoint::Event)
                .unwrap_or_else(|e| failed(e.to_string())),
            Solver::Both => compare(scene, omega, options)
                .map(|c| SweepPoint::Both(Box::new(c)))
                .unwrap_or_else(|e| failed(e.to_string())),
        }
    })
}

/// The columns of a sweep table, in order; the same names in JSON and CSV.
pub const COLUMNS: [&str; 26] = [
    "omega",
    "linear_outer_amplitude",
    "linear_transmittance_db",
    "linear_touches_stops",
    "orbits",
    "stable_viable_orbits",
    "branch0_alpha",
    "branch0_outer_amplitude",
    "branch0_transmittance_db",
    "branch0_viable",
    "branch0_stable",
    "branch1_alpha",
    "branch1_outer_amplitude",
    "branch1_transmittance_db",
    "branch1_viable",
    "branch1_stable",
    "simulated_regime",
    "simulated_status",
    "simulated_period",
    "simulated_impacts_per_period",
    "simulated_outer_amplitude",
    "simulated_transmittance_db",
    "simulated_sticking",
    "class",
    "relative_difference",
    "error",
];

fn analytic_cells(p: &AnalyticPoint, gap: Option<f64>, row: &mut [Value]) {
    row[1] = number(p.linear.outer_amplitude);
    row[2] = number(p.linear.transmittance_db);
    row[3] = gap.map_or(Value::Null, |g| json!(p.linear.relative_amplitude > g));
    row[4] = json!(p.orbits.len());
    row[5] = json!(p
        .orbits
        .iter()
        .filter(|(_, o)| o.viable && o.stable)
        .count());
    for (branch, o) in &p.orbits {
        if *branch < 2 {
            let base = 6 + 5 * branch;
            row[base] = number(o.alpha);
            row[base + 1] = number(o.outer_amplitude);
            row[base + 2] = number(o.transmittance_db);
            row[base + 3] = json!(o.viable);
            row[base + 4] = json!(o.stable);
        }
    }
}

fn simulated_cells(s: &SimulatedPoint, row: &mut [Value]) {
    row[16] = json!(s.regime.name());
    row[17] = json!(crate::simulation::status_name(&s.steady));
    row[18] = s.steady.period.map_or(Value::Null, |p| json!(p));
    row[19] = number(s.steady.impacts_per_period);
    row[20] = number(s.outer_amplitude);
    row[21] = s.transmittance_db.map_or(Value::Null, number);
    row[22] = json!(s.steady.sticking);
}

/// One row of the sweep table.
pub fn row(point: &SweepPoint, gap: Option<f64>) -> Vec<Value> {
    let mut row = vec![Value::Null; COLUMNS.len()];
    match point {
        SweepPoint::Analytic(p) => {
            row[0] = number(p.omega);
            analytic_cells(p, gap, &mut row);
        }
        SweepPoint::Event(s) => {
            row[0] = number(s.omega);
            simulated_cells(s, &mut row);
        }
        SweepPoint::Both(c) => {
            row[0] = number(c.analytic.omega);
            analytic_cells(&c.analytic, gap, &mut row);
            simulated_cells(&c.from_rest, &mut row);
            row[23] = json!(c.class.name());
            row[24] = c.difference.map_or(Value::Null, |d| number(d.largest()));
        }
        SweepPoint::Failed { omega, message } => {
            row[0] = number(*omega);
            row[25] = json!(message);
        }
    }
    row
}

/// The sweep as one JSON document: the scene, the solver and one object per frequency.
pub fn to_json(scene: &Scene, solver: Solver, points: &[SweepPoint]) -> Value {
    use rayon::prelude::*;
    let gap = scene.stops.map(|s| s.gap);
    let results: Vec<Value> = points
        .par_iter()
        .map(|p| {
            let mut obj = serde_json::Map::new();
            for (k, v) in COLUMNS.iter().zip(row(p, gap)) {
                obj.insert((*k).to_owned(), v);
            }
            if let SweepPoint::Both(c) = p {
                obj.insert("class_detail".into(), json!(c.class.detail()));
                obj.insert("matched".into(), json!(c.matched));
            }
            Value::Object(obj)
        })
        .collect();
    json!({
        "scene": scene,
        "solver": solver.name(),
        "effects": scene.effects().iter().map(|e| e.name()).collect::<Vec<_>>(),
        "points": points.len(),
        "results": results,
    })
}

/// The sweep as CSV: a header of [`COLUMNS`], one row per frequency; empty cells where a
/// value does not apply or is not finite. Loads with `pandas.read_csv` or MATLAB `readtable`.
pub fn to_csv(scene: &Scene, points: &[SweepPoint]) -> String {
    use rayon::prelude::*;
    let gap = scene.stops.map(|s| s.gap);
    // Rows are formatted in parallel and joined in order.
    let lines: Vec<String> = points.par_iter().map(|p| csv_row(row(p, gap))).collect();
    let mut out = COLUMNS.join(",");
    out.push('\n');
    for line in lines {
        out.push_str(&line);
        out.push('\n');
    }
    out
}

/// One part `index` (1-based) of `count` of a sweep: a contiguous block of its frequencies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// Which part, `1 ≤ index ≤ count`.
    pub index: usize,
    /// How many parts.
    pub count: usize,
}

impl Shard {
    /// Parses `K/N` with `1 ≤ K ≤ N`.
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
}

/// A part of a sharded sweep as JSON: [`to_json`] of its points, with `"points"` the total of
/// the whole sweep and `"shard": {"index", "count"}`.
pub fn to_json_shard(
    scene: &Scene,
    solver: Solver,
    points: &[SweepPoint],
    total: usize,
    shard: Shard,
) -> Value {
    let mut doc = to_json(scene, solver, points);
    doc["points"] = json!(total);
    doc["shard"] = json!({"index": shard.index, "count": shard.count});
    doc
}

/// A part of a sharded sweep as CSV: the line `# shard K/N of P points`, then [`to_csv`].
pub fn to_csv_shard(scene: &Scene, points: &[SweepPoint], total: usize, shard: Shard) -> String {
    format!(
        "# shard {}/{} of {total} points\n{}",
        shard.index,
        shard.count,
        to_csv(scene, points)
    )
}

/// Joins the parts of a sharded sweep (all JSON or all CSV, in any order) into exactly the
/// text the unsharded sweep writes. Every part of `1..=N` must be there once, from the same
/// sweep.
pub fn merge(parts: &[String]) -> Result<String, String> {
    if parts.is_empty() {
        return Err("no parts to merge".into());
    }
    if parts[0].trim_start().starts_with('{') {
        merge_json(parts)
    } else {
        merge_csv(parts)
    }
}

fn check_cover(mut indices: Vec<(usize, usize)>) -> Result<Vec<usize>, String> {
    let count = indices[0].1;
    if indices.iter().any(|&(_, n)| n != count) {
        return Err("the parts come from sweeps cut into different numbers of shards".into());
    }
    indices.sort();
    let got: Vec<usize> = indices.iter().map(|&(k, _)| k).collect();
    let want: Vec<usize> = (1..=count).collect();
    if got != want {
        return Err(format!(
            "shards {got:?} given; need each of 1..={count} once"
        ));
    }
    Ok(got)
}

fn merge_json(parts: &[String]) -> Result<String, String> {
    let mut docs: Vec<Value> = parts
        .iter()
        .enumerate()
        .map(|(i, p)| serde_json::from_str(p).map_err(|e| format!("part {}: {e}", i + 1)))
        .collect::<Result<_, _>>()?;
    let mut keyed = Vec::new();
    for (i, d) in docs.iter().enumerate() {
        let k = d["shard"]["index"]
            .as_u64()
            .ok_or(format!("part {}: not a shard (no \"shard\")", i + 1))?;
        let n = d["shard"]["count"]
            .as_u64()
            .ok_or(format!("part {}: not a shard", i + 1))?;
        keyed.push((k as usize, n as usize));
    }
    check_cover(keyed.clone())?;
    let mut order: Vec<usize> = (0..docs.len()).collect();
    order.sort_by_key(|&i| keyed[i].0);
    let same = |key: &str| docs.iter().all(|d| d[key] == docs[0][key]);
    if !(same("scene") && same("solver") && same("points") && same("effects")) {
        return Err("the parts come from different sweeps (scene, solver or points differ)".into());
    }
    let mut results = Vec::new();
    for &i in &order {
        results.extend(docs[i]["results"].as_array().cloned().unwrap_or_default());
    }
    let mut doc = docs.swap_remove(order[0]);
    if doc["points"].as_u64() != Some(results.len() as u64) {
        return Err(format!(
            "{} results for {} points",
            results.len(),
            doc["points"]
        ));
    }
    doc["results"] = Value::Array(results);
    if let Some(obj) = doc.as_object_mut() {
        obj.remove("shard");
    }
    Ok(format!("{doc:#}\n"))
}

fn merge_csv(parts: &[String]) -> Result<String, String> {
    let mut keyed = Vec::new();
    let mut bodies = Vec::new();
    let mut total = None;
    for (i, p) in parts.iter().enumerate() {
        let (first, rest) = p.split_once('\n').ok_or(format!("part {}: empty", i + 1))?;
        let spec = first
            .strip_prefix("# shard ")
            .and_then(|s| s.strip_suffix(" points"))
            .ok_or(format!(
                "part {}: not a shard (no '# shard K/N of P points' line)",
                i + 1
            ))?;
        let (kn, p_total) = spec
            .split_once(" of ")
            .ok_or(format!("part {}: bad shard line", i + 1))?;
        let shard = Shard::parse(kn).map_err(|e| format!("part {}: {e}", i + 1))?;
        keyed.push((shard.index, shard.count));
        if total.is_some_and(|t| t != p_total) {
            return Err("the parts come from sweeps of different sizes".into());
        }
        total = Some(p_total);
        bodies.push((shard.index, rest));
    }
    check_cover(keyed)?;
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
