//! Chain scenes through the `rattle` command: the fields a chain adds, a one-cell chain equal
//! to the unit, the simulator's chain against the analytic crate's linear chain, and the
//! commands that take a single unit refusing a chain by name.

use rattle_analytic::{chain_response, Cell};
use rattle_compare::scene::Scene;
use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

fn rattle(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("rattle runs")
}

fn json(args: &[&str]) -> Value {
    let out = rattle(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON document")
}

/// Writes `text` to a scene file of this test process named `name`.
fn scene_file(name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rattle-chain-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join(name);
    std::fs::write(&path, text).expect("the scene is written");
    path
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
        vec![
            "sweep",
            "data/scenes/paper-graded-4.json",
            "--solver",
            "both",
            "--omega-min",
            "1",
            "--omega-max",
            "2",
            "--points",
            "2",
            "--out",
            "refused-sweep.csv",
        ],
    ] {
        let out = rattle(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(!std::path::Path::new("../../refused-sweep.csv").exists());
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(
            (err.contains("`cells`") || err.contains("`chain`")) && err.contains("rattle simulate"),
            "{args:?}: {err}"
        );
    }
}
