//! `rattle boundary` as a user meets it: the documented JSON fields, the curve through the
//! event the command started from, the CSV points, and bad input exiting 2 naming the field.

mod common;
use common::{json, rattle};

/// The period-doubling curve of the paper scene's `+-` orbits near ω = 2.85 over the gap.
const PERIOD_DOUBLING: [&str; 13] = [
    "boundary",
    "--signature",
    "+-",
    "--event",
    "period-doubling",
    "--omega",
    "2.85",
    "--param",
    "stops.gap",
    "--min",
    "0.45",
    "--max",
    "0.55",
];

#[test]
fn boundary_json_has_the_documented_fields_and_passes_through_its_start() {
    let mut args = PERIOD_DOUBLING.to_vec();
    args.extend(["--at", "0.47,0.5,0.53", "--json"]);
    let doc = json(&args);
    for key in [
        "signature",
        "period",
        "event",
        "param",
        "points",
        "at",
        "special_points",
        "ends",
    ] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    assert_eq!(doc["event"], "period-doubling");
    assert_eq!(doc["param"], "stops.gap");
    let points = doc["points"].as_array().unwrap();
    assert!(points.len() > 10, "{} points", points.len());
    for p in points {
        let mu = p["critical_multiplier"].as_array().unwrap();
        let (re, im) = (mu[0].as_f64().unwrap(), mu[1].as_f64().unwrap());
        // A multiplier at −1 on every point (the doubling test is held to 1e-8).
        assert!((re + 1.0).hypot(im) < 1e-8, "μ = {re} + {im}i");
        let gap = p["param_value"].as_f64().unwrap();
        assert!((0.45..=0.55).contains(&gap));
        assert!(p["omega"].is_number() && p["outer_amplitude"].is_number());
    }
    let at = doc["at"].as_array().unwrap();
    assert_eq!(at.len(), 3, "{at:?}");
    // At the scene's own gap the curve's ω is the event the command started from.
    let start = doc["omega_start"].as_f64().unwrap();
    let here = at.iter().find(|a| a["param_value"] == 0.5).unwrap();
    assert!((here["omega"].as_f64().unwrap() - start).abs() < 1e-9);
    let reasons: Vec<&str> = doc["ends"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["reason"].as_str().unwrap())
        .collect();
    assert_eq!(reasons.len(), 2);
    assert!(
        reasons.contains(&"param-min") && reasons.contains(&"param-max"),
        "{reasons:?}"
    );
}

#[test]
fn boundary_json_lists_the_special_points_among_its_points() {
    let mut args = PERIOD_DOUBLING.to_vec();
    let k = args.iter().position(|a| *a == "--min").unwrap();
    args[k + 1] = "0.35";
    args.push("--json");
    let doc = json(&args);
    let specials = doc["special_points"].as_array().unwrap();
    // Measured (as in the library's test): going down in gap from 0.5 the doubling curve's
    // orbit grazes near gap 0.3839, ω = 2.8701, then the curve turns near gap 0.3544.
    let kinds: Vec<&str> = specials
        .iter()
        .map(|s| s["kind"].as_str().unwrap())
        .collect();
    assert_eq!(kinds, ["grazing", "turning-point"], "{specials:?}");
    let graze = &specials[0];
    assert!(graze["flight"].is_u64() && graze["other"].is_null());
    assert!((graze["param_value"].as_f64().unwrap() - 0.3839).abs() < 1e-4);
    assert!((graze["omega"].as_f64().unwrap() - 2.8701).abs() < 1e-4);
    let points = doc["points"].as_array().unwrap();
    for s in specials {
        let p = points
            .iter()
            .find(|p| p["param_value"] == s["param_value"] && p["omega"] == s["omega"])
            .unwrap_or_else(|| panic!("{s:?} is not a point"));
        assert_eq!(p["special"], s["kind"]);
    }
    let marked = points.iter().filter(|p| !p["special"].is_null()).count();
    assert_eq!(marked, specials.len());
}

#[test]
fn boundary_writes_the_points_as_csv() {
    let path = std::env::temp_dir().join(format!("rattle-boundary-{}.csv", std::process::id()));
    let mut args = PERIOD_DOUBLING.to_vec();
    args.extend(["--out", path.to_str().unwrap()]);
    let out = rattle(&args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let _ = std::fs::remove_file(&path);
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "param_value,omega,outer_amplitude,critical_multiplier_re,critical_multiplier_im,special"
    );
    assert!(lines.count() > 10);
}

#[test]
fn bad_boundary_arguments_exit_2_and_name_the_field() {
    let replace = |option: &str, value: &'static str| {
        let mut args = PERIOD_DOUBLING.to_vec();
        let k = args.iter().position(|a| *a == option).unwrap();
        args[k + 1] = value;
        args
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (replace("--event", "cusp"), "--event"),
        (replace("--param", "stops.width"), "stops.width"),
        (replace("--min", "0"), "--min"),
        (replace("--max", "0.4"), "--max"),
        (replace("--omega", "-1"), "--omega"),
        (replace("--signature", "+x"), "--signature"),
        (
            [PERIOD_DOUBLING.as_slice(), &["--at", "0.6"]].concat(),
            "--at",
        ),
    ];
    for (args, field) in cases {
        let out = rattle(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(field), "{args:?}: {stderr}");
    }
}

/// The damped 2-cell chain of the paper's cell (the analytic crate's
/// `tests/boundary_chain.rs`): its `0+ 1- 0- 1+` orbits at ω = 3.3 have a Neimark–Sacker
/// point on their branch.
const DAMPED_CHAIN: &str = r#"{"name": "damped-two", "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
    "base": {"amplitude": 1.0}, "stops": {"gap": 0.5, "restitution": 0.8},
    "damping": {"outer": 0.1, "inner": 0.05}, "cells": 2}"#;

#[test]
fn boundary_on_a_chain_follows_a_whole_chain_field_or_one_cells() {
    let path = common::scene_file("boundary", "damped-two.json", DAMPED_CHAIN);
    let path = path.to_str().unwrap();
    let run = |param: &str| {
        json(&[
            "boundary",
            path,
            "--signature",
            "0+ 1- 0- 1+",
            "--event",
            "neimark-sacker",
            "--omega",
            "3.3",
            "--param",
            param,
            "--min",
            "0.76",
            "--max",
            "0.84",
            "--at",
            "0.78,0.8",
            "--omega-min",
            "2.8",
            "--omega-max",
            "4.0",
            "--json",
        ])
    };
    let whole = run("stops.restitution");
    let cell = run("chain[1].stops.restitution");
    assert_eq!(whole["signature"], "0+ 1- 0- 1+");
    assert_eq!(cell["param"], "chain[1].stops.restitution");
    let at = |doc: &serde_json::Value, value: f64| {
        doc["at"]
            .as_array()
            .unwrap()
            .iter()
            .find(|a| a["param_value"] == value)
            .unwrap_or_else(|| panic!("no at {value}: {doc}"))["omega"]
            .as_f64()
            .unwrap()
    };
    // Both start from the same event at the scene's own restitution, and pass through it.
    assert_eq!(whole["omega_start"], cell["omega_start"]);
    let start = whole["omega_start"].as_f64().unwrap();
    assert!((at(&whole, 0.8) - start).abs() < 1e-9);
    assert!((at(&cell, 0.8) - start).abs() < 1e-9);
    // Away from it, one cell's restitution moves the event less than both cells' do.
    let (w, c) = (at(&whole, 0.78) - start, at(&cell, 0.78) - start);
    assert!(w.abs() > c.abs() && c != 0.0, "whole {w}, cell {c}");
    for doc in [&whole, &cell] {
        for p in doc["points"].as_array().unwrap() {
            let mu = p["critical_multiplier"].as_array().unwrap();
            let modulus = mu[0].as_f64().unwrap().hypot(mu[1].as_f64().unwrap());
            assert!((modulus - 1.0).abs() < 1e-8, "|μ| = {modulus}");
        }
    }
}

/// The branch point of the paper scene's symmetric `+-` orbits near ω = 2.922 (the analytic
/// crate's `tests/boundary.rs`), followed over the gap.
#[test]
fn boundary_follows_a_branch_point_over_the_gap() {
    let doc = json(&[
        "boundary",
        "--signature",
        "+-",
        "--event",
        "branch-point",
        "--omega",
        "2.92",
        "--param",
        "stops.gap",
        "--min",
        "0.45",
        "--max",
        "0.55",
        "--at",
        "0.5",
        "--omega-min",
        "2.8",
        "--omega-max",
        "3.0",
        "--json",
    ]);
    assert_eq!(doc["event"], "branch-point");
    let start = doc["omega_start"].as_f64().unwrap();
    assert!((start - 2.922).abs() < 1e-3, "{start}");
    let at = doc["at"].as_array().unwrap();
    assert_eq!(at.len(), 1, "{at:?}");
    assert!((at[0]["omega"].as_f64().unwrap() - start).abs() < 1e-9);
    for p in doc["points"].as_array().unwrap() {
        let mu = p["critical_multiplier"].as_array().unwrap();
        let (re, im) = (mu[0].as_f64().unwrap(), mu[1].as_f64().unwrap());
        assert!((re - 1.0).hypot(im) < 1e-8, "μ = {re} + {im}i");
    }
}
