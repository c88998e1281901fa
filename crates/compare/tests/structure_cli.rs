//! The `rattle` command on scenes in the structure form: what it prints, and what it refuses
//! with the field's JSON path or the command's name.

mod common;

use common::{json, rattle, scene_file};
use rattle_compare::references::impact_oscillator::ImpactOscillator;

const OSCILLATOR: &str = "data/scenes/impact-oscillator.json";

/// The gallery's impact oscillator (`data/scenes/impact-oscillator.json`) in closed form.
fn reference() -> ImpactOscillator {
    ImpactOscillator {
        mass: 1.0,
        damping: 0.1,
        stiffness: 1.0,
        force: 1.0,
        phase: 0.0,
        gap: 0.5,
        restitution: 0.8,
    }
}

/// `simulate --json` reports every body by name, from the polished cycle: here the stable
/// closed-form orbit's amplitude.
#[test]
fn simulate_reports_the_bodies_from_the_polished_cycle() {
    let omega = 1.8;
    let doc = json(&["simulate", OSCILLATOR, "--omega", "1.8", "--json"]);
    assert_eq!(doc["form"], "structure");
    assert_eq!(doc["observed"], "x");
    assert_eq!(doc["amplitudes_of"], "polished");
    assert_eq!(doc["pair_signatures"], serde_json::json!(["+"]));
    assert!(doc["transmittance_db"].is_null(), "no base: {doc}");
    let x = doc["body_amplitudes"]["x"].as_f64().unwrap();
    let stable = reference()
        .period_one_orbits(omega)
        .unwrap()
        .into_iter()
        .find(|o| o.viable && o.stable)
        .unwrap();
    assert!((x - stable.amplitude).abs() < 1e-8 * x, "{x} {stable:?}");
    assert_eq!(doc["outer_amplitude"], doc["body_amplitudes"]["x"]);
}

/// `orbit --signature +` lists both closed-form orbits, one stable and one unstable; with one
/// stop `+` reads as `0+`.
#[test]
fn orbit_lists_the_stable_and_the_unstable_orbit() {
    let doc = json(&[
        "orbit",
        OSCILLATOR,
        "--omega",
        "1.8",
        "--signature",
        "+",
        "--json",
    ]);
    assert_eq!(doc["sequence"], "0+");
    let orbits = doc["orbits"].as_array().unwrap();
    assert_eq!(orbits.len(), 2);
    let stable: Vec<bool> = orbits
        .iter()
        .map(|o| o["stable"].as_bool().unwrap())
        .collect();
    assert!(stable.contains(&true) && stable.contains(&false), "{doc}");
    assert!(orbits.iter().all(|o| o["viable"] == true), "{doc}");
    for o in orbits {
        let v = o["relative_velocities_before"][0].as_f64().unwrap();
        let matched = reference()
            .period_one_orbits(1.8)
            .unwrap()
            .into_iter()
            .any(|r| (r.velocity_before - v).abs() < 1e-10 * v);
        assert!(matched, "{o}");
    }
    let err = rattle(&["orbit", OSCILLATOR, "--omega", "1.8", "--signature", "-"]);
    assert_eq!(err.status.code(), Some(2));
    let message = String::from_utf8_lossy(&err.stderr);
    assert!(
        message.contains("which has no stop on that side"),
        "{message}"
    );
}

/// `compare` agrees on the gallery's asymmetric unit, with every body named.
#[test]
fn compare_agrees_on_the_asymmetric_unit() {
    let doc = json(&[
        "compare",
        "data/scenes/asymmetric-unit.json",
        "--omega",
        "3.0",
        "--json",
    ]);
    assert_eq!(doc["class"], "agreement", "{doc}");
    assert!(doc["relative_difference"].as_f64().unwrap() < 1e-9);
    assert_eq!(doc["analytic"]["sequence"], "0+ 0-");
    let bodies = doc["analytic"]["body_amplitudes"].as_object().unwrap();
    assert_eq!(bodies.len(), 2);
    // The bodies in the scene's order in the printed document.
    let out = rattle(&[
        "compare",
        "data/scenes/asymmetric-unit.json",
        "--omega",
        "3.0",
        "--json",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    let at = text.find("\"body_amplitudes\"").unwrap();
    let (outer, inner) = (
        text[at..].find("\"outer\"").unwrap(),
        text[at..].find("\"inner\"").unwrap(),
    );
    assert!(outer < inner, "{text}");
    assert!(doc["analytic"]["transmittance_db"].is_number());
}

/// A structure that names a body it lacks is refused with the field's path; the commands
/// that take only the unit form refuse a structure by name; options not taken on a
/// structure are named.
#[test]
fn bad_structures_and_unsupported_uses_are_refused_by_name() {
    let text = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../".to_owned() + OSCILLATOR),
    )
    .unwrap()
    .replace(r#""on": "x""#, r#""on": "y""#);
    let path = scene_file("structure", "bad.json", &text);
    let out = rattle(&["simulate", path.to_str().unwrap(), "--omega", "1.0"]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.contains("bad.json: forcing.forces[0].on: no body named \"y\" (bodies: x)"),
        "{message}"
    );
    let out = rattle(&["orbit", OSCILLATOR, "--omega", "1.0"]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.contains("structure: the structure form is taken by"),
        "{message}"
    );
    let out = rattle(&[
        "orbit",
        OSCILLATOR,
        "--omega",
        "1.0",
        "--signature",
        "+",
        "--trajectory",
        "t.csv",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(message.contains("--trajectory is not taken"), "{message}");
}

/// `simulate --lyapunov` on a structure: the exponents of a periodic motion are
/// `log|μ|/T` of the simulator's own multipliers, within the spectrum's uncertainty.
#[test]
fn a_structures_lyapunov_exponents_are_its_multipliers() {
    let out = rattle(&[
        "simulate",
        OSCILLATOR,
        "--omega",
        "1.8",
        "--lyapunov",
        "--lyapunov-periods",
        "400",
        "--json",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let period = std::f64::consts::TAU / 1.8;
    let mut expected: Vec<f64> = doc["floquet_multipliers"]
        .as_array()
        .expect("a polished orbit")
        .iter()
        .map(|m| m[0].as_f64().unwrap().hypot(m[1].as_f64().unwrap()).ln() / period)
        .collect();
    expected.sort_by(|a, b| b.total_cmp(a));
    let exponents: Vec<f64> = doc["lyapunov_exponents"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| v.as_f64().unwrap())
        .collect();
    let uncertainty = doc["lyapunov_uncertainty"].as_f64().unwrap();
    assert_eq!(exponents.len(), 2);
    for (e, x) in exponents.iter().zip(&expected) {
        assert!(
            (e - x).abs() < 3.0 * uncertainty.max(1e-6),
            "{exponents:?} {expected:?}"
        );
    }
}

/// `sweep --solver both` on a structure: a row per frequency with every body's amplitude and
/// a verdict, no contradiction, the impacting rows in agreement.
#[test]
fn a_structure_sweep_gives_every_frequency_a_verdict() {
    let path = scene_file("structure", "sweep.json", "{}").with_file_name("oscillator-sweep.json");
    let out = rattle(&[
        "sweep",
        OSCILLATOR,
        "--omega-min",
        "0.9",
        "--omega-max",
        "1.7",
        "--points",
        "5",
        "--out",
        path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(doc["form"], "structure");
    assert_eq!(doc["bodies"], serde_json::json!(["x"]));
    let rows = doc["results"].as_array().unwrap();
    assert_eq!(rows.len(), 5);
    for row in rows {
        assert_eq!(row["class"], "agreement", "{row}");
        assert_eq!(row["simulated_pair_signatures"], "+", "{row}");
        let x: f64 = row["simulated_body_amplitudes"]
            .as_str()
            .unwrap()
            .parse()
            .unwrap();
        assert_eq!(Some(x), row["simulated_outer_amplitude"].as_f64());
    }
}

/// `simulate --trajectory --impacts` on a structure: a column per body and per stop; every
/// impact sits on its stop.
#[test]
fn a_structure_trajectory_has_a_column_per_body() {
    let dir = scene_file("structure", "t.json", "{}");
    let (states, impacts) = (dir.with_file_name("t.csv"), dir.with_file_name("i.csv"));
    let out = rattle(&[
        "simulate",
        "data/scenes/asymmetric-unit.json",
        "--omega",
        "3.0",
        "--trajectory",
        states.to_str().unwrap(),
        "--impacts",
        impacts.to_str().unwrap(),
        "--samples-per-period",
        "16",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&states).unwrap();
    assert_eq!(
        text.lines().next(),
        Some("t,kind,base,u_outer,u_inner,v_outer,v_inner,r_0")
    );
    assert!(text.lines().count() > 16);
    let text = std::fs::read_to_string(&impacts).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t,stop,side,relative_velocity_before,u_outer,u_inner,v_outer_before,v_inner_before")
    );
    let mut sides = Vec::new();
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        let (side, outer, inner): (u8, f64, f64) = (
            cells[2].parse().unwrap(),
            cells[4].parse().unwrap(),
            cells[5].parse().unwrap(),
        );
        let stop = if side == 1 { 0.6 } else { -0.25 };
        assert!((inner - outer - stop).abs() < 1e-12, "{line}");
        sides.push(side);
    }
    assert_eq!(sides.len(), 2, "{text}");
}

/// Where the closed form's count of period-1 orbits changes between `lo` and `hi` at `gap`
/// (its two orbits meet at a fold), bisected to rounding.
fn closed_form_fold(gap: f64, (mut lo, mut hi): (f64, f64)) -> f64 {
    let count = |omega: f64| {
        ImpactOscillator { gap, ..reference() }
            .period_one_orbits_sampled(omega, 16)
            .unwrap()
            .len()
    };
    let at_lo = count(lo);
    assert_ne!(at_lo, count(hi), "no fold in [{lo}, {hi}] at gap {gap}");
    while hi - lo > 4.0 * f64::EPSILON * hi {
        let mid = 0.5 * (lo + hi);
        if count(mid) == at_lo {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// `boundaries` on a structure: the events of the motions a sweep settles on, each followed
/// in the gap; the period-1 fold's curve is the closed form's fold at every gap.
#[test]
fn boundaries_on_a_structure_follow_the_closed_form_fold() {
    let doc = json(&[
        "boundaries",
        OSCILLATOR,
        "--param",
        "structure.stops[0].gap_plus",
        "--min",
        "0.4",
        "--max",
        "0.7",
        "--omega-min",
        "1.0",
        "--omega-max",
        "2.5",
        "--points",
        "12",
        "--max-impacts",
        "2",
        "--stable-only",
        "--json",
    ]);
    assert_eq!(doc["param"], "structure.stops[0].gap_plus");
    let curves = doc["curves"].as_array().unwrap();
    let fold = curves
        .iter()
        .find(|c| c["event"] == "fold" && c["signature"] == "0+")
        .unwrap_or_else(|| panic!("the period-1 fold: {doc}"));
    let points = fold["points"].as_array().unwrap();
    assert!(points.len() > 10, "{} points", points.len());
    for p in points.iter().step_by(7) {
        let (gap, omega) = (
            p["param_value"].as_f64().unwrap(),
            p["omega"].as_f64().unwrap(),
        );
        let exact = closed_form_fold(gap, (omega - 1e-3, omega + 1e-3));
        assert!((omega - exact).abs() < 1e-8, "gap {gap}: {omega} {exact}");
    }
    // A path of the unit form is refused on a structure, naming the paths it takes.
    let out = rattle(&[
        "boundaries",
        OSCILLATOR,
        "--param",
        "stops.gap",
        "--min",
        "0.4",
        "--max",
        "0.7",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.contains("--param") && message.contains("structure.bodies[K].mass"),
        "{message}"
    );
}
