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
        "1.8",
        "--signature",
        "+",
        "--orbit",
        "2",
        "--trajectory",
        "t.csv",
    ]);
    assert_eq!(out.status.code(), Some(2));
    let message = String::from_utf8_lossy(&out.stderr);
    assert!(
        message.contains("--orbit = 2 is out of range: 2 orbit(s) of 0+ at ω = 1.8"),
        "{message}"
    );
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
        let exact = ImpactOscillator { gap, ..reference() }
            .fold_between(omega - 1e-3, omega + 1e-3)
            .unwrap()
            .unwrap_or_else(|| panic!("no fold near ω = {omega} at gap {gap}"));
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

/// The columns and the rows of a CSV table `rattle` wrote, each row by column name.
fn csv_rows(
    path: &std::path::Path,
) -> (Vec<String>, Vec<std::collections::HashMap<String, String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let columns: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|line| {
            columns
                .iter()
                .cloned()
                .zip(line.split(',').map(String::from))
                .collect()
        })
        .collect();
    (columns, rows)
}

/// The number in `row`'s column `name`.
fn number(row: &std::collections::HashMap<String, String>, name: &str) -> f64 {
    row[name]
        .parse()
        .unwrap_or_else(|_| panic!("{name} in {row:?}"))
}

/// `orbit --signature … --trajectory --impacts` on a structure samples every orbit of the
/// sequence with a column per body and per stop: at each impact, before and after, the
/// stop's relative coordinate sits on its side's gap (the asymmetric unit's two gaps, and the
/// impact damper's free body in its clearance).
#[test]
fn a_structures_sampled_orbit_meets_its_stops_at_its_impacts() {
    let dir = scene_file("structure", "orbit-trajectory.json", "{}");
    for (scene, omega, sequence, gaps, bodies) in [
        (
            "data/scenes/asymmetric-unit.json",
            "3.0",
            "+-",
            (0.6, 0.25),
            ["outer", "inner"],
        ),
        (
            "data/scenes/impact-damper.json",
            "1.0",
            "0+ 0-",
            (0.8, 0.8),
            ["primary", "ball"],
        ),
    ] {
        let orbits = json(&[
            "orbit",
            scene,
            "--omega",
            omega,
            "--signature",
            sequence,
            "--json",
        ]);
        let count = orbits["orbits"].as_array().unwrap().len();
        assert!(count > 0, "{scene}: {orbits}");
        for k in 0..count {
            let states = dir.with_file_name(format!("orbit-{k}.csv"));
            let impacts = dir.with_file_name(format!("orbit-{k}-impacts.csv"));
            let out = rattle(&[
                "orbit",
                scene,
                "--omega",
                omega,
                "--signature",
                sequence,
                "--orbit",
                &k.to_string(),
                "--trajectory",
                states.to_str().unwrap(),
                "--impacts",
                impacts.to_str().unwrap(),
                "--samples-per-period",
                "32",
            ]);
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            let (columns, rows) = csv_rows(&states);
            let u = |b: &str| format!("u_{b}");
            let v = |b: &str| format!("v_{b}");
            let expected = [
                "t".to_owned(),
                "kind".to_owned(),
                "base".to_owned(),
                u(bodies[0]),
                u(bodies[1]),
                v(bodies[0]),
                v(bodies[1]),
                "r_0".to_owned(),
            ];
            assert_eq!(columns, expected, "{scene}");
            assert_eq!(
                rows.len(),
                32 + 2 * 2,
                "{scene}: uniform samples and two rows per impact"
            );
            let at_stop = |r: f64| (r - gaps.0).abs().min((r + gaps.1).abs());
            let mut times = Vec::new();
            for row in rows.iter().filter(|r| r["kind"] != "sample") {
                let r = number(row, "r_0");
                assert!(at_stop(r) < 1e-12, "{scene} orbit {k}: {row:?}");
                let relative = number(row, &u(bodies[1])) - number(row, &u(bodies[0]));
                assert_eq!(
                    r, relative,
                    "{scene} orbit {k}: r_0 is the second body's u − the first's"
                );
                times.push(number(row, "t"));
            }
            let viable = orbits["orbits"][k]["viable"] == true;
            let (impact_columns, impacts) = csv_rows(&impacts);
            assert_eq!(
                impact_columns[..4],
                ["t", "stop", "side", "relative_velocity_before"]
            );
            assert_eq!(impacts.len(), 2, "{scene} orbit {k}");
            let mut sides = Vec::new();
            for (j, i) in impacts.iter().enumerate() {
                assert_eq!(i["stop"], "0");
                let side: u8 = i["side"].parse().unwrap();
                let r = number(i, &u(bodies[1])) - number(i, &u(bodies[0]));
                let gap = if side == 1 { gaps.0 } else { -gaps.1 };
                assert!((r - gap).abs() < 1e-12, "{scene} orbit {k}: {i:?}");
                let approach = number(i, "relative_velocity_before");
                let before = |b: &str| number(i, &format!("v_{b}_before"));
                assert_eq!(approach, before(bodies[1]) - before(bodies[0]));
                // A viable orbit approaches each stop from inside.
                assert!(!viable || approach * gap > 0.0, "{scene} orbit {k}: {i:?}");
                // Each impact is the time of a pair of rows (before, after).
                assert_eq!(times[2 * j], number(i, "t"));
                assert_eq!(times[2 * j + 1], number(i, "t"));
                sides.push(side);
            }
            sides.sort_unstable();
            assert_eq!(sides, [1, 2], "{scene} orbit {k}");
        }
    }
}

/// The analytic orbit and the simulated cycle of the same motion, each written by its
/// command, overlay: the same columns, and the same impact (at the same forcing phase, in the
/// same state) on the impact oscillator's stable orbit.
#[test]
fn a_structures_analytic_and_simulated_cycles_overlay() {
    let dir = scene_file("structure", "overlay.json", "{}");
    let orbits = json(&[
        "orbit",
        OSCILLATOR,
        "--omega",
        "1.8",
        "--signature",
        "+",
        "--json",
    ]);
    let stable = orbits["orbits"]
        .as_array()
        .unwrap()
        .iter()
        .position(|o| o["stable"] == true && o["viable"] == true)
        .expect("a stable orbit at 1.8 rad/s");
    let tables = |command: &str| {
        let (states, impacts) = (
            dir.with_file_name(format!("{command}.csv")),
            dir.with_file_name(format!("{command}-impacts.csv")),
        );
        let mut args = vec![command, OSCILLATOR, "--omega", "1.8"];
        let k = stable.to_string();
        if command == "orbit" {
            args.extend(["--signature", "+", "--orbit", &k]);
        }
        args.extend([
            "--trajectory",
            states.to_str().unwrap(),
            "--impacts",
            impacts.to_str().unwrap(),
        ]);
        let out = rattle(&args);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        (
            std::fs::read_to_string(states).unwrap(),
            std::fs::read_to_string(impacts).unwrap(),
        )
    };
    let (analytic, analytic_impacts) = tables("orbit");
    let (simulated, simulated_impacts) = tables("simulate");
    assert_eq!(analytic.lines().next(), simulated.lines().next());
    assert_eq!(
        analytic_impacts.lines().next(),
        Some("t,stop,side,relative_velocity_before,u_x,v_x_before")
    );
    assert_eq!(
        analytic_impacts.lines().next(),
        simulated_impacts.lines().next()
    );
    let impact = |text: &str| -> Vec<f64> {
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 2, "one impact per cycle: {text}");
        lines[1].split(',').map(|c| c.parse().unwrap()).collect()
    };
    let (a, s) = (impact(&analytic_impacts), impact(&simulated_impacts));
    let period = std::f64::consts::TAU / 1.8;
    let cycles = (a[0] - s[0]) / period;
    assert!(
        (cycles - cycles.round()).abs() < 1e-8,
        "impact times {} and {} are not a whole number of periods apart",
        a[0],
        s[0]
    );
    assert_eq!(a[1..3], s[1..3], "the same stop and side");
    for k in 3..a.len() {
        assert!((a[k] - s[k]).abs() < 1e-8, "column {k}: {a:?} {s:?}");
    }
}

/// `sweep --shard K/N` on a structure: each part says which it is (a JSON `shard` field, a CSV
/// `# shard` line), and `rattle merge` joins two parts into the unsharded file byte for byte,
/// in CSV and in JSON.
#[test]
fn a_structures_sweep_parts_merge_into_the_whole_sweep() {
    let dir = scene_file("structure", "shards.json", "{}");
    let sweep = |out: &std::path::Path, shard: Option<&str>| {
        let mut args = vec![
            "sweep",
            "data/scenes/one-sided-unit.json",
            "--omega-min",
            "0.5",
            "--omega-max",
            "3.5",
            "--points",
            "5",
            "--out",
            out.to_str().unwrap(),
        ];
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        let o = rattle(&args);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    for ext in ["csv", "json"] {
        let whole = sweep(&dir.with_file_name(format!("whole.{ext}")), None);
        let parts: Vec<std::path::PathBuf> = (1..=2)
            .map(|k| dir.with_file_name(format!("part-{k}.{ext}")))
            .collect();
        for (k, part) in parts.iter().enumerate() {
            let text = sweep(part, Some(&format!("{}/2", k + 1)));
            if ext == "csv" {
                assert_eq!(
                    text.lines().next(),
                    Some(format!("# shard {}/2 of 5 points", k + 1).as_str())
                );
            } else {
                let doc: serde_json::Value = serde_json::from_str(&text).unwrap();
                assert_eq!(
                    doc["shard"],
                    serde_json::json!({"index": k + 1, "count": 2})
                );
                assert_eq!(doc["points"], 5);
                assert_eq!(doc["form"], "structure");
                assert_eq!(doc["results"].as_array().unwrap().len(), 2 + k);
            }
        }
        let merged = dir.with_file_name(format!("merged.{ext}"));
        let o = rattle(&[
            "merge",
            parts[1].to_str().unwrap(),
            parts[0].to_str().unwrap(),
            "--out",
            merged.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(std::fs::read_to_string(&merged).unwrap(), whole, "{ext}");
        if ext == "csv" {
            continue;
        }
        // A part of another sweep (another scene) is refused.
        let other = dir.with_file_name("other.json");
        let o = rattle(&[
            "sweep",
            OSCILLATOR,
            "--omega-min",
            "0.5",
            "--omega-max",
            "3.5",
            "--points",
            "5",
            "--shard",
            "2/2",
            "--out",
            other.to_str().unwrap(),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let o = rattle(&[
            "merge",
            parts[0].to_str().unwrap(),
            other.to_str().unwrap(),
            "--out",
            merged.to_str().unwrap(),
        ]);
        assert_eq!(o.status.code(), Some(2));
        let message = String::from_utf8_lossy(&o.stderr);
        assert!(message.contains("different sweeps"), "{message}");
    }
}

/// `simulate --sampled-periods N --samples-per-period 1` on a structure: the Poincaré section
/// of the impact damper's settled two-impact motion is one point, at `t = kT` for
/// `k = 0 … N`, and its impact map holds the two impacts of every period, alternating sides,
/// each at the clearance.
#[test]
fn a_structures_poincare_section_of_a_periodic_motion_is_one_point() {
    let dir = scene_file("structure", "section.txt", "");
    let dir = dir.parent().unwrap();
    let (section, impacts) = (dir.join("section.csv"), dir.join("impacts.csv"));
    let out = rattle(&[
        "simulate",
        "data/scenes/impact-damper.json",
        "--omega",
        "1.0",
        "--trajectory",
        section.to_str().unwrap(),
        "--impacts",
        impacts.to_str().unwrap(),
        "--samples-per-period",
        "1",
        "--sampled-periods",
        "6",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (_, rows) = csv_rows(&section);
    let samples: Vec<_> = rows.iter().filter(|r| r["kind"] == "sample").collect();
    assert_eq!(samples.len(), 7);
    let period = std::f64::consts::TAU / 1.0;
    let first = samples[0];
    let scale = number(first, "u_ball")
        .abs()
        .max(number(first, "v_ball").abs());
    for (k, s) in samples.iter().enumerate() {
        assert!(
            (number(s, "t") - k as f64 * period).abs() < 1e-9 * period,
            "{s:?}"
        );
        // The run ended periodic to its tolerance (1e-9 relative by default); the free ball's
        // offset is neutral, so the section drifts no faster than that.
        for name in ["u_primary", "v_primary", "u_ball", "v_ball"] {
            let d = (number(s, name) - number(first, name)).abs();
            assert!(d < 1e-8 * scale, "{name} at k = {k}: {d}");
        }
    }
    let (_, hits) = csv_rows(&impacts);
    assert_eq!(hits.len(), 12);
    for (k, h) in hits.iter().enumerate() {
        let side = if k % 2 == 0 {
            hits[0]["side"].clone()
        } else {
            hits[1]["side"].clone()
        };
        assert_eq!(h["side"], side, "impact {k}");
        let r = number(h, "u_ball") - number(h, "u_primary");
        assert!((r.abs() - 0.8).abs() < 1e-12, "impact {k}: r = {r}");
    }
    assert_ne!(hits[0]["side"], hits[1]["side"]);
    let out = rattle(&[
        "simulate",
        "data/scenes/impact-damper.json",
        "--omega",
        "1.0",
        "--trajectory",
        section.to_str().unwrap(),
        "--sampled-periods",
        "0",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--sampled-periods = 0"));
}
