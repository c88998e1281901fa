//! Lyapunov exponents through the `rattle` command: `simulate --lyapunov` on the scenes that
//! stress the tangent flow, and the regime columns of sweeps and maps.

mod common;
use common::rattle;
use serde_json::Value;
use std::path::PathBuf;

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rattle-lyapunov-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The paper's unit with `stops` (a JSON object, or none) and `damping`.
fn scene(dir: &std::path::Path, name: &str, stops: Option<&str>, damping: bool) -> String {
    let mut text = format!(
        r#"{{"name": "{name}", "unit": {{"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0}}, "base": {{"amplitude": 1.0}}"#
    );
    if let Some(s) = stops {
        text += &format!(r#", "stops": {s}"#);
    }
    if damping {
        text += r#", "damping": {"outer": 0.1, "inner": 0.05}"#;
    }
    text += "}";
    let path = dir.join(format!("{name}.json"));
    std::fs::write(&path, text).unwrap();
    path.display().to_string()
}

/// The documented fields, every exponent finite or `null`, or a clear refusal: never a panic.
#[test]
fn simulate_lyapunov_is_finite_or_a_clear_error_on_the_edge_scenes() {
    let dir = scratch("edges");
    let cases = [
        // No stops: the linear unit (undamped: exponents zero within the uncertainty).
        scene(&dir, "no-stops", None, false),
        scene(&dir, "no-stops-damped", None, true),
        // No damping, elastic stops: nothing dissipates.
        scene(
            &dir,
            "elastic",
            Some(r#"{"gap": 0.5, "restitution": 1.0}"#),
            false,
        ),
        // e = 0: the inner mass sticks on a stop.
        scene(
            &dir,
            "plastic",
            Some(r#"{"gap": 0.5, "restitution": 0.0}"#),
            true,
        ),
        scene(
            &dir,
            "plastic-undamped",
            Some(r#"{"gap": 0.5, "restitution": 0.0}"#),
            false,
        ),
    ];
    for path in &cases {
        for omega in ["0.8", "1.25", "2.0"] {
            let out = rattle(&[
                "simulate",
                path,
                "--omega",
                omega,
                "--max-periods",
                "500",
                "--lyapunov",
                "--lyapunov-periods",
                "100",
                "--json",
            ]);
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(!stderr.contains("panicked"), "{path} ω = {omega}: {stderr}");
            if !out.status.success() {
                assert!(stderr.contains("numerical failure"), "{path}: {stderr}");
                continue;
            }
            let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
            let exponents = doc["lyapunov_exponents"].as_array().unwrap();
            let collapsed = doc["lyapunov_collapsed"].as_u64().unwrap() as usize;
            assert_eq!(exponents.len() + collapsed, 4, "{path} ω = {omega}");
            assert!(exponents.iter().all(Value::is_number), "{path}: {doc}");
            assert!(
                doc["lyapunov_uncertainty"].is_number() || exponents.is_empty(),
                "{path}: {doc}"
            );
        }
    }
    // Too few periods: refused by name.
    let out = rattle(&[
        "simulate",
        "--omega",
        "1",
        "--lyapunov",
        "--lyapunov-periods",
        "3",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--lyapunov-periods"));
    let _ = std::fs::remove_dir_all(&dir);
}

/// The paper's unit at ω = 1.25 (Δ = 0.5, e = 0.8) is chaotic: the library's tests find a
/// positive largest exponent on the damped unit at this frequency (`tests/lyapunov.rs` of
/// the simulator), and the sum rule holds while nothing sticks.
#[test]
fn simulate_lyapunov_names_a_chaotic_motion_and_the_table_shows_it() {
    let out = rattle(&[
        "simulate",
        "data/scenes/paper-damped.json",
        "--omega",
        "1.25",
        "--lyapunov",
        "--lyapunov-periods",
        "500",
        "--json",
    ]);
    assert!(out.status.success());
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["status"], "non-periodic");
    assert_eq!(doc["lyapunov_regime"], "chaotic");
    let largest = doc["lyapunov_exponents"][0].as_f64().unwrap();
    assert!(largest > doc["lyapunov_uncertainty"].as_f64().unwrap());
    let table = rattle(&[
        "simulate",
        "data/scenes/paper-damped.json",
        "--omega",
        "1.25",
        "--lyapunov",
        "--lyapunov-periods",
        "500",
    ]);
    let text = String::from_utf8_lossy(&table.stdout);
    assert!(text.contains("lyapunov exponents"), "{text}");
    assert!(text.contains("lyapunov regime: chaotic"), "{text}");
}

/// A periodic motion has no non-periodic regime; without `--lyapunov` nothing is added.
#[test]
fn simulate_without_the_flag_adds_nothing_and_periodic_motions_get_no_regime() {
    let plain: Value = serde_json::from_slice(
        &rattle(&[
            "simulate",
            "data/scenes/paper-damped.json",
            "--omega",
            "2",
            "--json",
        ])
        .stdout,
    )
    .unwrap();
    assert!(plain.get("lyapunov_exponents").is_none());
    let out = rattle(&[
        "simulate",
        "data/scenes/paper-damped.json",
        "--omega",
        "2",
        "--lyapunov",
        "--lyapunov-periods",
        "100",
        "--json",
    ]);
    let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(doc["status"], "periodic");
    assert_eq!(doc["lyapunov_regime"], Value::Null);
    // The stable orbit there (max|μ| = 0.855 by the simulator's multipliers): the largest
    // exponent is log max|μ| / T to the run's uncertainty.
    let mu = doc["floquet_multipliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|m| m[0].as_f64().unwrap().hypot(m[1].as_f64().unwrap()))
        .fold(0.0, f64::max);
    let expected = mu.ln() / (std::f64::consts::TAU / 2.0);
    let largest = doc["lyapunov_exponents"][0].as_f64().unwrap();
    let u = doc["lyapunov_uncertainty"].as_f64().unwrap();
    assert!(
        (largest - expected).abs() <= u.max(1e-6 * expected.abs()),
        "{largest} vs {expected} ± {u}"
    );
}

fn csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let split = |l: &str| l.split(',').map(str::to_owned).collect::<Vec<_>>();
    let header = split(lines.next().unwrap());
    (header, lines.map(split).collect())
}

fn cell<'a>(header: &[String], row: &'a [String], name: &str) -> &'a str {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"));
    &row[i]
}

#[test]
fn sweep_and_map_carry_the_regime_and_the_largest_exponent() {
    let dir = scratch("columns");
    let sweep = dir.join("sweep.csv");
    let out = rattle(&[
        "sweep",
        "data/scenes/paper-damped.json",
        "--omega-min",
        "1.25",
        "--omega-max",
        "2",
        "--points",
        "2",
        "--solver",
        "event",
        "--out",
        sweep.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (header, rows) = csv(&sweep);
    // ω = 1.25: chaotic; ω = 2: the stable orbit, exponent from its multipliers, no regime.
    assert_eq!(cell(&header, &rows[0], "lyapunov_regime"), "chaotic");
    assert!(
        cell(&header, &rows[0], "largest_exponent")
            .parse::<f64>()
            .unwrap()
            > 0.0
    );
    assert_eq!(cell(&header, &rows[1], "lyapunov_regime"), "");
    let periodic: f64 = cell(&header, &rows[1], "largest_exponent").parse().unwrap();
    assert!(periodic < 0.0);
    let map = dir.join("map.csv");
    let out = rattle(&[
        "map",
        "data/scenes/paper-damped.json",
        "--restitution-min",
        "0.8",
        "--restitution-max",
        "0.8",
        "--restitutions",
        "1",
        "--gap-min",
        "0.5",
        "--gap-max",
        "0.5",
        "--gaps",
        "1",
        "--omega-min",
        "1.25",
        "--omega-max",
        "1.25",
        "--points",
        "1",
        "--out",
        map.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (header, rows) = csv(&map);
    assert_eq!(cell(&header, &rows[0], "simulated_regime"), "irregular");
    assert_eq!(cell(&header, &rows[0], "lyapunov_regime"), "chaotic");
    assert!(
        cell(&header, &rows[0], "largest_exponent")
            .parse::<f64>()
            .unwrap()
            > 0.0
    );
    let _ = std::fs::remove_dir_all(&dir);
}
