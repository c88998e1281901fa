//! Chain scenes through the `rattle` command: the fields a chain adds, a one-cell chain equal
//! to the unit, the simulator's chain against the analytic crate's linear chain, and the
//! commands that take a single unit refusing a chain by name.

mod common;
use common::{json, rattle};
use rattle_analytic::{chain_response, Cell};
use rattle_compare::scene::Scene;
use serde_json::Value;
use std::path::PathBuf;

/// Writes `text` to a scene file of this test process named `name`, whole (see
/// [`common::scene_file`]).
fn scene_file(name: &str, text: &str) -> PathBuf {
    common::scene_file("chain", name, text)
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .expect("an array")
        .iter()
        .map(|x| x.as_f64().expect("a number"))
        .collect()
}

#[test]
fn simulate_on_a_chain_reports_every_cell_and_pair() {
    let doc = json(&[
        "simulate",
        "data/scenes/paper-chain-5.json",
        "--omega",
        "1.0",
        "--json",
    ]);
    let cells = numbers(&doc["cell_outer_amplitudes"]);
    assert_eq!(cells.len(), 5);
    assert_eq!(doc["outer_amplitude"].as_f64(), cells.last().copied());
    let pairs = numbers(&doc["pair_impacts_per_period"]);
    assert_eq!(pairs.len(), 5);
    let total = doc["impacts_per_period"].as_f64().expect("a number");
    assert!((pairs.iter().sum::<f64>() - total).abs() < 1e-12 * total.max(1.0));
    // The chain's cycle has no one signature: each pair has its own.
    assert!(doc["signature"].is_null());
    assert_eq!(doc["status"], "periodic");
    let sigs = doc["pair_signatures"].as_array().expect("pair signatures");
    assert_eq!(sigs.len(), 5);
    for (sig, &count) in sigs.iter().zip(&pairs) {
        let sig = sig.as_str().expect("a signature");
        assert_eq!(
            sig.len() as f64,
            count,
            "{sig} against {count} impacts per period"
        );
    }
}

#[test]
fn a_chain_of_one_cell_is_the_unit_bit_for_bit() {
    let paper = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/paper-damped.json"
    ))
    .expect("the scene");
    let listed = paper.trim_end().trim_end_matches('}').to_owned() + r#", "chain": [{}]}"#;
    let counted = paper.trim_end().trim_end_matches('}').to_owned() + r#", "cells": 1}"#;
    for omega in ["0.7", "2.0", "2.5"] {
        let unit = rattle(&[
            "simulate",
            "data/scenes/paper-damped.json",
            "--omega",
            omega,
            "--json",
        ]);
        for (name, text) in [("listed.json", &listed), ("counted.json", &counted)] {
            let path = scene_file(name, text);
            let chain = rattle(&[
                "simulate",
                path.to_str().unwrap(),
                "--omega",
                omega,
                "--json",
            ]);
            assert!(chain.status.success());
            assert_eq!(chain.stdout, unit.stdout, "{name} at ω = {omega}");
        }
    }
}

/// Stops far beyond any motion: the simulated chain is the linear chain, which the analytic
/// crate solves in closed form (transfer matrices); the two agree to the simulator's
/// periodicity tolerance (1e-9 relative by default, amplitudes from closed-form extrema).
#[test]
fn a_chain_with_huge_gaps_is_the_analytic_linear_chain() {
    let text = r#"{
        "name": "far stops",
        "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
        "base": {"amplitude": 1.0},
        "stops": {"gap": 1000.0, "restitution": 0.8},
        "damping": {"outer": 0.3, "inner": 0.2},
        "chain": [{}, {"unit": {"outer_mass": 1.5, "inner_mass": 0.5, "outer_stiffness": 4.0, "inner_stiffness": 2.0}}, {}]
    }"#;
    let path = scene_file("far.json", text);
    let scene = Scene::load(&path).expect("a valid scene");
    let cells: Vec<Cell> = scene
        .cell_scenes()
        .iter()
        .map(|c| Cell::of_unit(&c.unit_model()))
        .collect();
    for omega in [0.5, 1.3, 1.9, 3.0] {
        let doc = json(&[
            "simulate",
            path.to_str().unwrap(),
            "--omega",
            &omega.to_string(),
            "--json",
        ]);
        assert_eq!(doc["regime"], "no-impact", "ω = {omega}");
        let simulated = numbers(&doc["cell_outer_amplitudes"]);
        let linear = chain_response(&cells, 1.0, omega).expect("a bounded response");
        for (j, (s, l)) in simulated
            .iter()
            .zip(&linear.cell_outer_amplitudes)
            .enumerate()
        {
            assert!(
                (s - l).abs() <= 1e-7 * l.max(1e-3),
                "ω = {omega}, cell {j}: {s} against {l}"
            );
        }
        let t = doc["transmittance_db"].as_f64().expect("a number");
        assert!((t - linear.transmittance_db).abs() < 1e-6, "ω = {omega}");
    }
}

#[test]
fn single_unit_commands_refuse_a_chain_naming_it() {
    for args in [
        vec!["orbit", "data/scenes/paper-chain-5.json", "--omega", "2"],
        vec![
            "family",
            "data/scenes/paper-chain-5.json",
            "--omega",
            "2",
            "--beta",
            "0.4",
        ],
    ] {
        let out = rattle(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            (err.contains("`cells`") || err.contains("`chain`")) && err.contains("rattle simulate"),
            "{args:?}: {err}"
        );
    }
}

/// The 2-cell undamped chain of the paper's cell at ω = 3.3 rad/s has a viable (unstable)
/// orbit with each pair `+-` in the order `0+ 1- 0- 1+` (found by the analytic crate's own
/// tests, `crates/analytic/tests/sequence_orbits.rs`); the command lists it with its energy
/// balance closed (≤ 1e-10, the issue's bound) and each pair's signature.
#[test]
fn orbit_on_a_chain_lists_the_orbits_of_a_sequence_of_its_pairs() {
    let text = r#"{"name": "two", "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
        "base": {"amplitude": 1.0}, "stops": {"gap": 0.5, "restitution": 0.8}, "cells": 2}"#;
    let path = scene_file("two.json", text);
    let path = path.to_str().unwrap();
    let doc = json(&[
        "orbit",
        path,
        "--omega",
        "3.3",
        "--signature",
        "1- 0- 1+ 0+",
        "--json",
    ]);
    assert_eq!(doc["cells"], 2);
    assert_eq!(doc["sequence"], "0+ 1- 0- 1+");
    let orbits = doc["orbits"].as_array().expect("orbits");
    let viable: Vec<&Value> = orbits.iter().filter(|o| o["viable"] == true).collect();
    assert!(!viable.is_empty(), "{doc}");
    for o in viable {
        assert_eq!(o["pair_signatures"], serde_json::json!(["+-", "+-"]));
        assert!(o["energy_residual"].as_f64().expect("a number") <= 1e-10);
        let cells = numbers(&o["cell_outer_amplitudes"]);
        assert_eq!(cells.len(), 2);
        assert_eq!(o["outer_amplitude"].as_f64(), cells.last().copied());
    }
    for (signature, needle) in [
        ("0+ 2-", "pair 2"),
        ("0x", "--signature"),
        ("", "--signature"),
    ] {
        let out = rattle(&["orbit", path, "--omega", "3.3", "--signature", signature]);
        assert_eq!(out.status.code(), Some(2), "{signature:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(needle), "{signature:?}: {err}");
    }
}

/// A map of a chain whose stops (every cell's, the map's gap) lie far beyond the motion: every
/// point settles without impacts on the analytic crate's linear chain, to the map's match
/// tolerance.
#[test]
fn a_map_of_a_chain_with_far_stops_matches_the_linear_chain() {
    let text = r#"{"name": "damped graded", "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
        "base": {"amplitude": 1.0}, "stops": {"gap": 0.5, "restitution": 0.8},
        "damping": {"outer": 0.3, "inner": 0.2},
        "chain": [{}, {"stops": {"gap": 0.1, "restitution": 0.3}}, {}]}"#;
    let path = scene_file("map.json", text);
    let out = std::env::temp_dir().join(format!("rattle-chain-map-{}.csv", std::process::id()));
    let o = rattle(&[
        "map",
        path.to_str().unwrap(),
        "--restitutions",
        "1",
        "--gaps",
        "1",
        "--gap-min",
        "100",
        "--gap-max",
        "100",
        "--points",
        "12",
        "--max-periods",
        "3000",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut reader = csv::Reader::from_path(&out).expect("the map's file");
    let headers = reader.headers().expect("a header").clone();
    let column = |name: &str| headers.iter().position(|h| h == name).expect(name);
    let (regime, matched) = (column("simulated_regime"), column("analytic_match"));
    let (outer, cells) = (
        column("simulated_outer_amplitude"),
        column("simulated_cell_outer_amplitudes"),
    );
    let pairs = column("simulated_pair_impacts_per_period");
    let mut rows = 0;
    for row in reader.records() {
        let row = row.expect("a row");
        assert_eq!(&row[regime], "no-impact", "{row:?}");
        assert_eq!(&row[matched], "true", "{row:?}");
        // Every cell listed, the last one the outer amplitude; every cell has the map's
        // stops, none hit.
        let cells: Vec<&str> = row[cells].split(';').collect();
        assert_eq!(cells.len(), 3, "{row:?}");
        assert_eq!(cells[2], &row[outer]);
        assert_eq!(&row[pairs], "0.0;0.0;0.0", "{row:?}");
        rows += 1;
    }
    assert_eq!(rows, 12);
}

/// The list columns of a chain's sweep hold, number for number, the lists of
/// `rattle simulate --json` at the same frequency (one run, two outputs).
#[test]
fn a_chain_sweeps_list_columns_are_the_simulations_lists() {
    let out = std::env::temp_dir().join(format!("rattle-chain-sweep-{}.csv", std::process::id()));
    let o = rattle(&[
        "sweep",
        "data/scenes/paper-chain-5.json",
        "--solver",
        "event",
        "--omega-min",
        "1",
        "--omega-max",
        "1",
        "--points",
        "1",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let mut reader = csv::Reader::from_path(&out).expect("the sweep's file");
    let headers = reader.headers().expect("a header").clone();
    let row = reader
        .records()
        .next()
        .expect("one row")
        .expect("a readable row");
    let cell = |name: &str| &row[headers.iter().position(|h| h == name).expect(name)];
    let list = |name: &str| -> Vec<f64> {
        cell(name)
            .split(';')
            .map(|x| x.parse().expect("a number"))
            .collect()
    };
    let doc = json(&[
        "simulate",
        "data/scenes/paper-chain-5.json",
        "--omega",
        "1",
        "--json",
    ]);
    assert_eq!(
        list("simulated_cell_outer_amplitudes"),
        numbers(&doc["cell_outer_amplitudes"])
    );
    assert_eq!(
        list("simulated_pair_impacts_per_period"),
        numbers(&doc["pair_impacts_per_period"])
    );
    // The simulator alone: the analytic lists are empty cells.
    assert_eq!(cell("linear_cell_outer_amplitudes"), "");
}
