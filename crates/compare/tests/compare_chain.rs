//! `rattle compare` on chains of the paper's cell, lightly damped as
//! `data/scenes/paper-chain-5.json` (c_o = 0.1, c_i = 0.05): the simulated cycle from rest,
//! polished by the simulator's own Newton, beside the analytic orbit of its impact sequence.
//!
//! Where the numbers come from: the frequencies are those where `rattle simulate` from rest
//! found a periodic, non-sticking motion in a scan of ω = 0.3 … 3.5 (2 cells: 1.1, 1.7, 1.9,
//! 3.5; 3 cells: 1.2, 1.4, 2.0, 2.2, 2.8, 3.5; the shipped paper-chain-5 at 1.0 and
//! paper-graded-4 at 3.5, found the same way); the non-periodic, sticking and long-period
//! frequencies come from the same scan. The tolerances are the simulator's Newton's: it stops
//! when `|P(y) − y|` is within `NEWTON_TOLERANCE_FACTOR × root_tolerance = 1 × 1e-12` of the
//! state's size (crates/event-driven/src/newton.rs, `NEWTON_TOLERANCE_FACTOR`, and the default
//! `root_tolerance`, `DEFAULT_ROOT_TOLERANCE` in simulate.rs), or at its rounding floor
//! `NEWTON_FLOOR_FACTOR = 1e3` times that, 1e-9; contact times are resolved to 1e-12 T. The
//! analytic crate solves its own equations to rounding. Both solvers' orbits must therefore
//! agree to well within 1e-8 (ten times the floor): states, amplitudes, phases and Floquet
//! multipliers.

mod common;
use common::{json, rattle};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// Writes `text` to a scene file of this test process named `name`, whole (see
/// [`common::scene_file`]).
fn scene_file(name: &str, text: &str) -> PathBuf {
    common::scene_file("compare-chain", name, text)
}

/// The paper's cell, lightly damped, `cells` times in series.
fn chain_scene(cells: usize) -> PathBuf {
    scene_file(
        &format!("paper-chain-{cells}.json"),
        &format!(
            r#"{{
  "name": "paper-chain-{cells}",
  "unit": {{"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0}},
  "base": {{"amplitude": 1.0}},
  "stops": {{"gap": 0.5, "restitution": 0.8}},
  "damping": {{"outer": 0.1, "inner": 0.05}},
  "cells": {cells}
}}"#
        ),
    )
}

/// The simulator's Newton tolerance (1e-12) at its rounding floor (× 1e3), times ten.
const AGREEMENT: f64 = 1e-8;

fn compare(scene: &Path, omega: f64) -> Value {
    let omega = omega.to_string();
    json(&[
        "compare",
        scene.to_str().expect("a UTF-8 path"),
        "--omega",
        &omega,
        "--json",
    ])
}

/// The checks of an agreeing point; returns the analytic sequence.
fn agrees(doc: &Value, cells: usize) -> String {
    assert_eq!(doc["class"], "agreement", "{doc:#}");
    assert_eq!(doc["reason"], Value::Null);
    assert_eq!(doc["cells"], cells);
    let rel = doc["relative_difference"].as_f64().expect("a number");
    let mult = doc["multiplier_difference"].as_f64().expect("a number");
    assert!(rel <= AGREEMENT, "relative difference {rel:e}: {doc:#}");
    assert!(mult <= AGREEMENT, "multiplier difference {mult:e}: {doc:#}");
    let sim = &doc["simulated"];
    let ana = &doc["analytic"];
    assert_eq!(sim["status"], "periodic");
    assert_eq!(ana["viable"], true);
    assert_eq!(ana["stable"], true);
    assert!(ana["energy_residual"].as_f64().expect("a number") <= 1e-10);
    assert_eq!(
        sim["floquet_multipliers"].as_array().map(Vec::len),
        Some(4 * cells),
        "2n multipliers, n = 2 per cell"
    );
    assert_eq!(
        ana["floquet_multipliers"].as_array().map(Vec::len),
        Some(4 * cells)
    );
    let x_sim = sim["outer_amplitude"].as_f64().expect("a number");
    let x_ana = ana["outer_amplitude"].as_f64().expect("a number");
    // The simulated amplitude of the un-polished final cycle repeats to the periodicity
    // tolerance (1e-9), amplified by at most 1/(1 − |μ|).
    assert!(
        (x_sim - x_ana).abs() <= 1e-6 * x_ana,
        "{x_sim} against {x_ana}"
    );
    assert_eq!(
        ana["cell_outer_amplitudes"].as_array().map(Vec::len),
        Some(cells)
    );
    // Every pair's signature read off the analytic sequence is the simulated one.
    let sequence = ana["sequence"].as_str().expect("a string").to_owned();
    let pairs = sim["pair_signatures"].as_array().expect("an array");
    for (j, sig) in pairs.iter().enumerate() {
        let count = sequence
            .split_whitespace()
            .filter(|t| t[..t.len() - 1] == j.to_string())
            .count();
        assert_eq!(
            count,
            sig.as_str().expect("a signature").len(),
            "pair {j} of {sequence}"
        );
    }
    sequence
}

#[test]
fn two_cells_agree_on_each_periodic_motion_from_rest() {
    let scene = chain_scene(2);
    // ω = 1.7: both cells `+-`; 1.9: `+-` and `++--`; 1.1: the first cell clear of its stops,
    // the second `++--`.
    let sequences: Vec<String> = [1.7, 1.9, 1.1]
        .iter()
        .map(|&w| agrees(&compare(&scene, w), 2))
        .collect();
    assert_eq!(sequences[0].split_whitespace().count(), 4);
    assert_eq!(sequences[1].split_whitespace().count(), 6);
    assert!(sequences[2].split_whitespace().all(|t| t.starts_with('1')));
}

#[test]
fn three_cells_agree_on_each_periodic_motion_from_rest() {
    let scene = chain_scene(3);
    // ω = 2.0: every cell `+-`; 2.2: `+-`, `++--`, `+-`; 1.2: a period-2 cycle.
    for w in [2.0, 2.2, 1.2] {
        let doc = compare(&scene, w);
        agrees(&doc, 3);
        if w == 1.2 {
            assert_eq!(doc["analytic"]["period"], 2);
        }
    }
}

#[test]
fn the_shipped_chains_agree_where_they_settle_on_a_cycle() {
    // paper-chain-5 at ω = 1: cells 1, 2 and 5 `++--`, cells 3 and 4 clear of their stops
    // (12 impacts per period); paper-graded-4 at ω = 3.5: only the first cell impacts, `+-`.
    let doc = compare(Path::new("data/scenes/paper-chain-5.json"), 1.0);
    let sequence = agrees(&doc, 5);
    assert_eq!(sequence.split_whitespace().count(), 12);
    assert_eq!(
        doc["simulated"]["pair_signatures"],
        serde_json::json!(["++--", "++--", "", "", "++--"])
    );
    let doc = compare(Path::new("data/scenes/paper-graded-4.json"), 3.5);
    assert_eq!(agrees(&doc, 4), "0+ 0-");
}

#[test]
fn motions_outside_exact_comparison_are_beyond_with_their_reason() {
    let scene = chain_scene(2);
    for (w, reason) in [(1.3, "non-periodic"), (0.9, "sticking")] {
        let doc = compare(&scene, w);
        assert_eq!(doc["class"], "beyond", "ω = {w}: {doc:#}");
        assert_eq!(doc["reason"], reason, "ω = {w}");
        assert_eq!(doc["analytic"], Value::Null);
        assert_eq!(doc["relative_difference"], Value::Null);
        assert_eq!(doc["confirmation"], Value::Null);
    }
}

/// The two-cell chain at ω = 1.5 settles on a cycle of 9 forcing periods. A simulated cycle is
/// solved from its own phases up to 64 periods: it agrees.
#[test]
fn a_long_cycle_of_a_chain_agrees() {
    let doc = compare(&chain_scene(2), 1.5);
    agrees(&doc, 2);
    assert_eq!(doc["simulated"]["period"], 9);
}

#[test]
fn a_cell_without_stops_leaves_the_chain_beyond_the_analytic_chain() {
    // The analytic chain has a contact pair in every cell; here only the second cell has
    // stops, and at ω = 1.1 it settles on `++--` (as in the two-cell chain at that frequency).
    let scene = scene_file(
        "half-stopped.json",
        r#"{"name": "half-stopped", "unit": {"outer_mass": 2.0, "inner_mass": 1.0,
            "outer_stiffness": 6.0, "inner_stiffness": 3.0}, "base": {"amplitude": 1.0},
            "damping": {"outer": 0.1, "inner": 0.05},
            "chain": [{}, {"stops": {"gap": 0.5, "restitution": 0.8}}]}"#,
    );
    let doc = compare(&scene, 1.1);
    assert_eq!(
        doc["simulated"]["pair_signatures"],
        serde_json::json!(["++--"])
    );
    assert_eq!(doc["class"], "beyond", "{doc:#}");
    assert_eq!(doc["reason"], "cell-without-stops");
}

#[test]
fn without_impacts_the_chain_agrees_with_the_linear_chain() {
    // ω = 0.5: the simulator from rest settles clear of every stop.
    let doc = compare(&chain_scene(2), 0.5);
    assert_eq!(doc["class"], "agreement", "{doc:#}");
    assert_eq!(doc["analytic"], Value::Null);
    assert_eq!(doc["simulated"]["impacts_per_period"], 0.0);
    let rel = doc["relative_difference"].as_f64().expect("a number");
    // The un-polished final cycle repeats to the periodicity tolerance, 1e-9.
    assert!(rel <= 1e-7, "{rel:e}");
}

#[test]
fn the_table_names_the_sequence_and_the_class() {
    let scene = chain_scene(2);
    let out = rattle(&[
        "compare",
        scene.to_str().expect("a UTF-8 path"),
        "--omega",
        "1.7",
    ]);
    assert!(out.status.success());
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(text.contains("chain of 2 cells"), "{text}");
    assert!(text.contains("class: agreement"), "{text}");
}

#[test]
fn bad_input_exits_2_naming_the_field() {
    let scene = chain_scene(2);
    let path = scene.to_str().expect("a UTF-8 path");
    let zero_cells = scene_file(
        "zero-cells.json",
        r#"{"name": "z", "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0,
            "inner_stiffness": 3.0}, "base": {"amplitude": 1.0},
            "stops": {"gap": 0.5, "restitution": 0.8}, "cells": 0}"#,
    );
    let bad_gap = scene_file(
        "bad-gap.json",
        r#"{"name": "g", "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0,
            "inner_stiffness": 3.0}, "base": {"amplitude": 1.0},
            "stops": {"gap": 0.5, "restitution": 0.8},
            "chain": [{}, {"stops": {"gap": -1.0, "restitution": 0.8}}]}"#,
    );
    for (args, field) in [
        (vec!["compare", path, "--omega", "-1"], "--omega"),
        (vec!["compare", path, "--omega", "1", "--tol", "1"], "--tol"),
        (
            vec![
                "compare",
                zero_cells.to_str().expect("a UTF-8 path"),
                "--omega",
                "1",
            ],
            "cells",
        ),
        (
            vec![
                "compare",
                bad_gap.to_str().expect("a UTF-8 path"),
                "--omega",
                "1",
            ],
            "chain[1].stops.gap",
        ),
    ] {
        let out = rattle(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(field), "{args:?}: {err}");
    }
}

/// `rattle sweep FILE --solver both … --out OUT` on `scene`, read back as JSON rows.
fn sweep_both(scene: &Path, lo: f64, hi: f64, points: usize, out: &str) -> Vec<Value> {
    let out = scene_file(out, "");
    let (lo, hi, points) = (lo.to_string(), hi.to_string(), points.to_string());
    let run = rattle(&[
        "sweep",
        scene.to_str().expect("a UTF-8 path"),
        "--solver",
        "both",
        "--omega-min",
        &lo,
        "--omega-max",
        &hi,
        "--points",
        &points,
        "--out",
        out.to_str().expect("a UTF-8 path"),
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(&out).expect("the sweep is written");
    let doc: Value = serde_json::from_str(&text).expect("one JSON document");
    assert_eq!(doc["solver"], "both");
    doc["results"].as_array().expect("rows").clone()
}

#[test]
fn a_chain_sweep_with_both_solvers_gives_each_frequency_the_verdict_of_compare() {
    // ω = 0.5, 0.9, 1.3, 1.7 on the 2-cell chain: clear of the stops, sticking,
    // non-periodic and `+-` in both cells (the frequencies of the tests above), so that the
    // rows cover agreements and motions beyond exact comparison.
    let scene = chain_scene(2);
    let rows = sweep_both(&scene, 0.5, 1.7, 4, "sweep-both-2.json");
    assert_eq!(rows.len(), 4);
    let mut classes = Vec::new();
    for row in &rows {
        assert_eq!(row["error"], Value::Null, "{row:#}");
        let omega = row["omega"].as_f64().expect("a frequency");
        let doc = compare(&scene, omega);
        let sim = &doc["simulated"];
        // The same computation: the same numbers, bit for bit.
        for (column, field) in [
            (&row["class"], &doc["class"]),
            (&row["class_detail"], &doc["class_detail"]),
            (&row["relative_difference"], &doc["relative_difference"]),
            (&row["multiplier_difference"], &doc["multiplier_difference"]),
            (&row["simulated_status"], &sim["status"]),
            (&row["simulated_period"], &sim["period"]),
            (&row["simulated_outer_amplitude"], &sim["outer_amplitude"]),
            (
                &row["simulated_impacts_per_period"],
                &sim["impacts_per_period"],
            ),
        ] {
            assert_eq!(column, field, "ω = {omega}: {row:#}\n{doc:#}");
        }
        match doc["analytic"].as_object() {
            Some(a) => {
                assert_eq!(row["analytic_outer_amplitude"], a["outer_amplitude"]);
                assert_eq!(row["analytic_viable"], a["viable"]);
                assert_eq!(row["analytic_stable"], a["stable"]);
                assert_eq!(row["analytic_energy_residual"], a["energy_residual"]);
            }
            None => assert_eq!(row["analytic_outer_amplitude"], Value::Null),
        }
        // The linear chain's last cell, as `rattle sweep --solver analytic` gives it.
        assert!(row["linear_outer_amplitude"].is_f64(), "{row:#}");
        assert_eq!(
            row["orbits"],
            Value::Null,
            "a chain's orbits are not searched"
        );
        assert_eq!(row["matched"].is_string(), doc["class"] == "agreement");
        classes.push(doc["class"].as_str().expect("a class").to_owned());
    }
    assert!(
        classes.iter().any(|c| c != &classes[0]),
        "the frequencies should give more than one class: {classes:?}"
    );
}
