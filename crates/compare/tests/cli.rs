//! The `rattle` command as a user meets it: fields, exit codes, messages.

mod common;
use common::{json, rattle, rattle_within};
use serde_json::Value;

#[test]
fn orbit_json_has_the_documented_fields() {
    let doc = json(&["orbit", "--omega", "2.0", "--json"]);
    for key in ["omega", "effects", "linear", "orbits"] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    for key in ["outer_amplitude", "inner_amplitude", "transmittance_db"] {
        assert!(doc["linear"][key].is_number(), "linear.{key}");
    }
    assert_eq!(doc["effects"], serde_json::json!(["stops"]));
    let orbits = doc["orbits"].as_array().unwrap();
    assert!(!orbits.is_empty());
    for o in orbits {
        for key in [
            "beta",
            "branch",
            "alpha",
            "outer_amplitude",
            "transmittance_db",
            "viable",
            "violations",
            "floquet_multipliers",
            "stable",
        ] {
            assert!(o.get(key).is_some(), "orbit missing {key}");
        }
        assert_eq!(o["state_after_impact"].as_array().unwrap().len(), 4);
        assert_eq!(o["floquet_multipliers"].as_array().unwrap().len(), 4);
    }
    // The paper unit at ω = 2 has a viable, stable symmetric orbit.
    assert!(orbits
        .iter()
        .any(|o| o["beta"] == 0.5 && o["viable"] == true && o["stable"] == true));
}

#[test]
fn no_orbit_is_not_an_error() {
    let doc = json(&["orbit", "--omega", "0.6", "--json", "--symmetric-only"]);
    assert_eq!(doc["orbits"], serde_json::json!([]));
    let doc = json(&[
        "orbit",
        "data/scenes/paper-linear.json",
        "--omega",
        "1.0",
        "--json",
    ]);
    assert_eq!(doc["orbits"], serde_json::json!([]));
    assert_eq!(doc["effects"], serde_json::json!([]));
}

#[test]
fn undamped_resonance_is_null_never_nan() {
    let out = rattle(&[
        "orbit",
        "data/scenes/paper-linear.json",
        "--omega",
        "1.224744871391589",
        "--json",
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    let doc: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(doc["linear"]["outer_amplitude"], Value::Null);
    assert_eq!(doc["linear"]["unbounded"], true);
}

#[test]
fn family_json_has_the_documented_fields() {
    let doc = json(&["family", "--omega", "2.0", "--beta", "0.3", "--json"]);
    for key in [
        "omega",
        "beta",
        "gap",
        "alpha",
        "viable",
        "violations",
        "stable",
    ] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    assert!(doc["gap"].as_f64().unwrap() > 0.0);
}

#[test]
fn bad_input_exits_2_and_names_the_problem() {
    for omega in ["nan", "inf", "0", "-1"] {
        let out = rattle(&["orbit", "--omega", omega]);
        assert_eq!(out.status.code(), Some(2), "--omega {omega}");
        assert!(String::from_utf8_lossy(&out.stderr).contains("--omega"));
    }
    let out = rattle(&["orbit", "no/such/scene.json", "--omega", "1"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("no/such/scene.json"));
    let out = rattle(&["family", "--omega", "1", "--beta", "1.5"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--beta"));
}

/// `rattle orbit --omega 1e-300`, `rattle simulate --omega 1e-6` and `rattle sweep
/// --omega-min 1e-300 …` would run for a very long time: every command refuses a
/// frequency outside the scene's bounds (at most 1e3 free oscillations of the fastest mode per
/// forcing period, at most 1e6 forcing periods per free oscillation of the slowest mode) with
/// the field and the range, at once.
#[test]
fn frequencies_that_would_not_end_are_refused_at_once_with_the_range() {
    let out = "target/never-written.csv";
    let grid = [
        "--outer-min",
        "-1",
        "--outer-max",
        "1",
        "--inner-min",
        "-1",
        "--inner-max",
        "1",
    ];
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (vec!["orbit", "--omega", "1e-300"], "--omega"),
        (
            vec!["orbit", "--omega", "1e-300", "--signature", "++--"],
            "--omega",
        ),
        (
            vec![
                "orbit",
                "data/scenes/paper-chain-5.json",
                "--omega",
                "1e-6",
                "--signature",
                "0+ 0-",
            ],
            "--omega",
        ),
        (vec!["simulate", "--omega", "1e-6"], "--omega"),
        (vec!["simulate", "--omega", "1e300"], "--omega"),
        (
            vec![
                "simulate",
                "data/scenes/paper-chain-5.json",
                "--omega",
                "1e-6",
            ],
            "--omega",
        ),
        (vec!["compare", "--omega", "1e-6"], "--omega"),
        (
            vec!["family", "--omega", "1e-300", "--beta", "0.3"],
            "--omega",
        ),
        (
            vec![
                "sweep",
                "--omega-min",
                "1e-300",
                "--omega-max",
                "1e-299",
                "--points",
                "3",
                "--out",
                out,
            ],
            "--omega-min",
        ),
        (
            vec![
                "sweep",
                "--omega-min",
                "1",
                "--omega-max",
                "1e200",
                "--points",
                "3",
                "--out",
                out,
            ],
            "--omega-max",
        ),
        (
            vec![
                "map",
                "--omega-min",
                "1e-6",
                "--omega-max",
                "2",
                "--points",
                "3",
                "--out",
                out,
            ],
            "--omega-min",
        ),
        (
            vec![
                "continue",
                "--signature",
                "+-",
                "--omega",
                "1",
                "--omega-min",
                "1e-300",
                "--omega-max",
                "2",
            ],
            "--omega-min",
        ),
        (
            [
                &["basins", "--omega", "1e-6", "--points", "2", "--out", out][..],
                &grid[..],
            ]
            .concat(),
            "--omega",
        ),
    ];
    for (args, field) in cases {
        let ran = rattle_within(&args, 20).unwrap_or_else(|| panic!("{args:?} ran past 20 s"));
        let stderr = String::from_utf8_lossy(&ran.stderr);
        assert_eq!(ran.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(
            stderr.contains(&format!("{field} = ")),
            "{args:?}: {stderr}"
        );
        assert!(
            stderr.contains("out of range for this scene: must be in ["),
            "{stderr}"
        );
    }
    assert!(!std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../",
        "target/never-written.csv"
    ))
    .exists());
}

/// On the paper's unit from rest, `rattle sweep --solver both --omega-min 0.5 --omega-max 4
/// --points 200` meets these two periodic motions of 20 impacts, and of 34 impacts over 12
/// periods: longer than a signature may be (16 impacts). A simulated cycle is solved from its
/// own phases whatever its length: both agree with the analytic orbit.
#[test]
fn long_simulated_cycles_are_compared_with_their_analytic_orbit() {
    for (omega, impacts, period) in [
        ("1.4673366834170856", 20, 1),
        ("0.9045226130653266", 34, 12),
    ] {
        let doc = json(&["compare", "--omega", omega, "--json"]);
        let signature = doc["simulated"]["signature"].as_str().unwrap();
        assert_eq!(
            (signature.len(), doc["simulated"]["period"].as_u64()),
            (impacts, Some(period))
        );
        assert_eq!(
            doc["class"], "agreement",
            "{omega}: {}",
            doc["class_detail"]
        );
        assert_eq!(doc["analytic"]["signature"], signature);
    }
}

/// A hard point of the study's 400-frequency sweep of the paper's unit: at
/// ω = 1.4586466165413536 the sections from rest first repeat on a 28-impact cycle that both
/// solvers find unstable (a multiplier 1.0039). The simulator runs past a cycle its own Newton
/// finds unstable, and both solvers agree on the stable cycle beside it,
/// to the simulator's Newton tolerance at its rounding floor, times ten (1e-8, as
/// `compare_chain.rs`).
#[test]
fn a_run_passing_an_unstable_cycle_goes_on_and_agrees() {
    let doc = json(&["compare", "--omega", "1.4586466165413536", "--json"]);
    assert_eq!(doc["class"], "agreement", "{}", doc["class_detail"]);
    assert_eq!(doc["analytic"]["stable"], true);
    assert_eq!(doc["simulated"]["impacts_per_period"], 28.0);
    let rel = doc["relative_difference"].as_f64().expect("a number");
    assert!(rel <= 1e-8, "{rel:e}");
}

#[test]
fn simulate_json_has_the_documented_fields() {
    let doc = json(&[
        "simulate",
        "data/scenes/paper-damped.json",
        "--omega",
        "2.0",
        "--json",
    ]);
    for key in [
        "omega",
        "effects",
        "status",
        "period",
        "impacts_per_period",
        "outer_amplitude",
        "transmittance_db",
        "periods_run",
        "impacts",
    ] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    assert_eq!(doc["effects"], serde_json::json!(["stops", "damping"]));
    assert_eq!(doc["status"], "periodic");
    assert_eq!(doc["period"], 1);
    assert_eq!(doc["impacts_per_period"], 2.0);
    // A fixed number of periods is honoured.
    let doc = json(&["simulate", "--omega", "2.0", "--periods", "7", "--json"]);
    assert_eq!(doc["periods_run"], 7);
    // The undamped elastic scene never settles, and says so.
    let doc = json(&[
        "simulate",
        "data/scenes/paper-elastic.json",
        "--omega",
        "2.0",
        "--json",
    ]);
    assert_eq!(doc["status"], "no-dissipation");
    assert_eq!(doc["transmittance_db"], serde_json::Value::Null);
}

#[test]
fn sweep_writes_the_same_rows_in_every_format_and_refuses_bad_files() {
    let dir = std::env::temp_dir().join(format!("rattle-cli-sweep-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = |ext: &str| dir.join(format!("s.{ext}")).display().to_string();
    for ext in ["csv", "json", "jsonl"] {
        let out = rattle(&[
            "sweep",
            "--omega-min",
            "0.5",
            "--omega-max",
            "3",
            "--points",
            "6",
            "--solver",
            "analytic",
            "--out",
            &path(ext),
        ]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(path("json")).unwrap()).unwrap();
    let rows = doc["results"].as_array().unwrap();
    let lines: Vec<Value> = std::fs::read_to_string(path("jsonl"))
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows, &lines);
    let csv = std::fs::read_to_string(path("csv")).unwrap();
    assert_eq!(csv.lines().count(), 1 + rows.len());
    // Unknown extension, and a JSON Lines shard: bad input, named.
    for (out, field) in [(path("txt"), "--out"), (path("jsonl"), "--shard")] {
        let mut args = vec![
            "sweep",
            "--omega-min",
            "1",
            "--omega-max",
            "2",
            "--points",
            "2",
            "--out",
            &out,
        ];
        if field == "--shard" {
            args.extend(["--shard", "1/2"]);
        }
        let o = rattle(&args);
        assert_eq!(o.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&o.stderr).contains(field),
            "{args:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Sorted `(re, im)` pairs of a JSON multiplier list, for comparison.
fn sorted_multipliers(v: &Value) -> Vec<(f64, f64)> {
    let mut m: Vec<(f64, f64)> = v
        .as_array()
        .expect("multipliers")
        .iter()
        .map(|p| (p[0].as_f64().unwrap(), p[1].as_f64().unwrap()))
        .collect();
    m.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    m
}

#[test]
fn orbits_of_a_signature_and_the_simulators_own_cycle_agree() {
    // The paper scene at ω = 2: one viable `+-` orbit, the stable symmetric one; from rest the
    // simulator settles on it, and its own Newton names the cycle `+-`.
    let sig = json(&["orbit", "--omega", "2", "--signature", "-+", "--json"]);
    assert_eq!(sig["signature"], "+-");
    let viable: Vec<&Value> = sig["orbits"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|o| o["viable"] == true)
        .collect();
    assert_eq!(viable.len(), 1);
    let general = viable[0];
    assert!(general["energy_residual"].as_f64().unwrap() <= 1e-10);
    let symmetric = json(&["orbit", "--omega", "2", "--symmetric-only", "--json"]);
    let branch = symmetric["orbits"]
        .as_array()
        .unwrap()
        .iter()
        .find(|o| o["viable"] == true && o["stable"] == true)
        .expect("a stable viable symmetric orbit");
    for key in ["alpha", "outer_amplitude"] {
        let (a, b) = (
            general[key].as_f64().unwrap(),
            branch[key].as_f64().unwrap(),
        );
        assert!(
            (a - b).abs() <= 1e-12 * b.abs().max(1.0),
            "{key}: {a} vs {b}"
        );
    }
    let sim = json(&["simulate", "--omega", "2", "--json"]);
    assert_eq!(sim["signature"], "+-");
    let (own, analytic) = (
        sorted_multipliers(&sim["floquet_multipliers"]),
        sorted_multipliers(&general["floquet_multipliers"]),
    );
    for (a, b) in own.iter().zip(&analytic) {
        assert!(
            (a.0 - b.0).hypot(a.1 - b.1) < 1e-8,
            "simulator {own:?} vs analytic {analytic:?}"
        );
    }
}

#[test]
fn bad_signatures_exit_2_and_name_the_field() {
    for (args, field) in [
        (vec!["--signature", ""], "--signature"),
        (vec!["--signature", "+x-"], "--signature"),
        (vec!["--signature", "+-", "--period", "0"], "--period"),
        (vec!["--signature", "+-", "--period", "99"], "--period"),
    ] {
        let mut all = vec!["orbit", "--omega", "2"];
        all.extend(args.iter().copied());
        let out = rattle(&all);
        assert_eq!(out.status.code(), Some(2), "{all:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains(field),
            "{all:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}

#[test]
fn compare_agrees_on_a_four_impact_orbit_and_names_what_it_cannot_compare() {
    // ω = 1 on the paper scene: the simulator from rest settles on a `++--` cycle (no
    // two-impact orbit is viable there); the analytic crate solves `++--` from the simulated
    // phases and finds the same orbit, viable and stable, to rounding.
    let doc = json(&["compare", "--omega", "1", "--json"]);
    assert_eq!(doc["simulated"]["signature"], "++--");
    assert_eq!(doc["analytic"]["signature"], "++--");
    assert_eq!(doc["class"], "agreement", "{doc:#}");
    assert!(doc["relative_difference"].as_f64().unwrap() < 1e-10);
    assert!(doc["multiplier_difference"].as_f64().unwrap() < 1e-8);
    assert!(doc["analytic"]["energy_residual"].as_f64().unwrap() < 1e-10);
    let confirmed = doc["confirmed_orbits"].as_array().unwrap();
    assert!(!confirmed.is_empty() && confirmed.iter().all(|k| k["confirmed"] == true));
    // ω = 2.9: the viable `+-` orbits include an unstable one, which no run from rest can
    // reach; the simulator's own Newton, started on it, confirms it all the same.
    let doc = json(&["compare", "--omega", "2.9", "--json"]);
    let unstable: Vec<&Value> = doc["confirmed_orbits"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|k| k["stable"] == false)
        .collect();
    assert!(!unstable.is_empty(), "{doc:#}");
    for k in unstable {
        assert_eq!(k["confirmed"], true, "{k:#}");
        assert!(k["state_difference"].as_f64().unwrap() < 1e-9);
        assert!(k["multiplier_difference"].as_f64().unwrap() < 1e-8);
    }
    // ω = 0.5 on the undamped paper scene: no dissipation, nothing to compare exactly.
    let doc = json(&["compare", "--omega", "0.5", "--json"]);
    assert_eq!(doc["class"], "beyond");
    assert!(doc["analytic"].is_null());
    // A plastic unit sticks: outside exact comparison, said so.
    let doc = json(&[
        "compare",
        "validation/hard-cases/plastic.json",
        "--omega",
        "2",
        "--json",
    ]);
    assert_eq!(doc["class"], "beyond", "{doc:#}");
    assert!(doc["class_detail"].as_str().unwrap().contains("sticking"));
}

#[test]
fn continue_json_follows_the_branches_and_locates_the_branch_point() {
    // The symmetric `+-` orbits of the paper scene at ω = 3 continued over [2.7, 3.1]: the
    // asymmetric pair β, 1 − β leaves the symmetric branch where Δ*(½) = Δ (Nigm–Shabana's
    // family, computed here on its own by bisection), and the command follows it.
    let doc = json(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "3",
        "--omega-min",
        "2.7",
        "--omega-max",
        "3.1",
        "--json",
    ]);
    assert_eq!(doc["signature"], "+-");
    assert_eq!(doc["period"], 1);
    let points = doc["points"].as_array().unwrap();
    assert!(points.len() > 10);
    for p in points {
        for key in [
            "branch",
            "omega",
            "outer_amplitude",
            "transmittance_db",
            "stable",
            "viable",
            "floquet_multipliers",
        ] {
            assert!(p.get(key).is_some(), "point lacks {key}");
        }
        let w = p["omega"].as_f64().unwrap();
        assert!((2.7 - 1e-12..=3.1 + 1e-12).contains(&w), "{w}");
    }
    let kinds = [
        "fold",
        "branch-point",
        "period-doubling",
        "neimark-sacker",
        "grazing",
        "vanishing-impact",
    ];
    let events = doc["events"].as_array().unwrap();
    for e in events {
        assert!(kinds.contains(&e["kind"].as_str().unwrap()), "{e}");
        assert!(e["branch"].as_u64().is_some() && e["omega"].is_number());
    }
    let scene = rattle_compare::scene::Scene::paper();
    let (unit, stops) = (scene.unit_model(), scene.stops_model().unwrap());
    let excess = |w: f64| {
        rattle_analytic::gap_for_beta(&unit, stops.restitution, w, 0.5)
            .unwrap()
            .gap
            - stops.gap
    };
    let (mut lo, mut hi) = (2.8, 3.0);
    assert!(excess(lo) * excess(hi) < 0.0);
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if excess(lo) * excess(mid) <= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    let branch_point = events
        .iter()
        .find(|e| e["kind"] == "branch-point" && e["branch"] == 0)
        .expect("a branch point on the symmetric branch");
    assert!(
        (branch_point["omega"].as_f64().unwrap() - 0.5 * (lo + hi)).abs() < 1e-8,
        "{branch_point} vs {}",
        0.5 * (lo + hi)
    );
    let branches = doc["branches"].as_array().unwrap();
    assert!(branches.len() >= 2, "the asymmetric branch is followed too");
    let ends = doc["ends"].as_array().unwrap();
    assert!(!ends.is_empty());
    for e in ends {
        assert!(e["reason"].is_string() && e["branch"].as_u64().is_some());
    }
}

#[test]
fn continue_lists_each_event_once_and_says_where_branches_join_or_the_depth_cuts() {
    // A branch and its mirror image are one branch, each event listed once.
    let doc = json(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "3",
        "--omega-min",
        "2.7",
        "--omega-max",
        "3.1",
        "--max-depth",
        "1",
        "--json",
    ]);
    let branches = doc["branches"].as_array().unwrap();
    let ends = doc["ends"].as_array().unwrap();
    assert_eq!(ends.len(), 2 * branches.len());
    let mut joins = 0;
    let mut cut = 0;
    for e in ends {
        let b = &branches[e["branch"].as_u64().unwrap() as usize];
        match e["reason"].as_str().unwrap() {
            "joins" => {
                joins += 1;
                assert!(e["joins"].as_u64().unwrap() < branches.len() as u64, "{e}");
            }
            "max-depth" => {
                cut += 1;
                assert!(e["joins"].is_null() && b["points"] == 0, "{e} {b}");
            }
            _ => assert!(e["joins"].is_null(), "{e}"),
        }
    }
    assert!(joins > 0 && cut > 0, "{joins} joins, {cut} cut");
    let events = doc["events"].as_array().unwrap();
    let key = |e: &serde_json::Value| {
        let b = &branches[e["branch"].as_u64().unwrap() as usize];
        (
            e["kind"].as_str().unwrap().to_owned(),
            b["signature"].as_str().unwrap().len(),
            b["period"].as_u64().unwrap(),
        )
    };
    for (i, a) in events.iter().enumerate() {
        for b in &events[i + 1..] {
            let close = |k: &str| (a[k].as_f64().unwrap() - b[k].as_f64().unwrap()).abs() < 1e-9;
            assert!(
                !(key(a) == key(b) && close("omega") && close("outer_amplitude")),
                "{a} and {b}"
            );
        }
    }
}

#[test]
fn bad_continuation_arguments_exit_2_and_name_the_field() {
    let base = [
        "continue",
        "--omega",
        "3",
        "--omega-min",
        "2.7",
        "--omega-max",
        "3.1",
    ];
    for (extra, field) in [
        (vec!["--signature", "+x"], "--signature"),
        (vec!["--signature", "+-", "--period", "0"], "--period"),
        (vec!["--signature", "+-", "--orbit", "99"], "--orbit"),
        (vec!["--signature", "+-", "--max-step", "0"], "--max-step"),
        (
            vec!["--signature", "+-", "--max-branches", "0"],
            "--max-branches",
        ),
        (vec!["--signature", "+-", "--max-depth", "x"], "--max-depth"),
    ] {
        let mut all: Vec<&str> = base.to_vec();
        all.extend(extra.iter().copied());
        let out = rattle(&all);
        assert_eq!(out.status.code(), Some(2), "{all:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(field), "{all:?}: {stderr}");
    }
    let out = rattle(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "5",
        "--omega-min",
        "2.7",
        "--omega-max",
        "3.1",
    ]);
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--omega"));
}

#[test]
fn continue_writes_the_points_as_csv() {
    let path = std::env::temp_dir().join(format!("rattle-continue-{}.csv", std::process::id()));
    let out = rattle(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "3",
        "--omega-min",
        "2.95",
        "--omega-max",
        "3.05",
        "--no-switch",
        "--out",
        path.to_str().unwrap(),
    ]);
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
        "branch,signature,period,omega,alpha,outer_amplitude,transmittance_db,stable,viable,largest_multiplier"
    );
    assert!(lines.count() > 5);
}

/// The rows of a CSV file written by the command, as (header, records).
fn csv_rows(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines
        .next()
        .unwrap()
        .split(',')
        .map(str::to_owned)
        .collect();
    let rows = lines
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    (header, rows)
}

fn column(header: &[String], name: &str) -> usize {
    header.iter().position(|h| h == name).unwrap()
}

#[test]
fn simulated_and_analytic_cycles_overlay_through_their_trajectories() {
    // ω = 2 on the paper scene: the simulator from rest settles on the stable viable `+-`
    // orbit. Its final cycle and the analytic orbit, each sampled from its own closed form,
    // must show the same impacts at the same forcing times, and obey the stops and the
    // restitution law in every row.
    let dir = std::env::temp_dir().join(format!("rattle-trajectory-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = |name: &str| dir.join(name).to_str().unwrap().to_owned();
    let out = rattle(&[
        "simulate",
        "--omega",
        "2",
        "--trajectory",
        &file("sim.csv"),
        "--impacts",
        &file("sim-impacts.csv"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let doc = json(&["orbit", "--omega", "2", "--signature", "+-", "--json"]);
    let k = doc["orbits"]
        .as_array()
        .unwrap()
        .iter()
        .position(|o| o["viable"] == true && o["stable"] == true)
        .expect("a stable viable +- orbit at ω = 2");
    let out = rattle(&[
        "orbit",
        "--omega",
        "2",
        "--signature",
        "+-",
        "--orbit",
        &k.to_string(),
        "--trajectory",
        &file("orbit.csv"),
        "--impacts",
        &file("orbit-impacts.csv"),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let (gap, e) = (0.5, 0.8);
    for name in ["sim.csv", "orbit.csv"] {
        let (h, rows) = csv_rows(&dir.join(name));
        assert_eq!(h.join(","), "t,kind,cell,base,u_o,u_i,v_o,v_i,r");
        let (r, kind) = (column(&h, "r"), column(&h, "kind"));
        let (v_o, v_i) = (column(&h, "v_o"), column(&h, "v_i"));
        let value = |row: &Vec<String>, c: usize| row[c].parse::<f64>().unwrap();
        for row in &rows {
            assert!(value(row, r).abs() <= gap * (1.0 + 1e-9), "{name}: {row:?}");
        }
        let mut jumps = 0;
        for pair in rows.windows(2) {
            if pair[0][kind] == "before_impact" {
                assert_eq!(pair[1][kind], "after_impact", "{name}");
                let before = value(&pair[0], v_i) - value(&pair[0], v_o);
                let after = value(&pair[1], v_i) - value(&pair[1], v_o);
                assert!((after + e * before).abs() <= 1e-12 * before.abs(), "{name}");
                jumps += 1;
            }
        }
        assert_eq!(jumps, 2, "{name}: two impacts per cycle");
    }
    let (h, sim) = csv_rows(&dir.join("sim-impacts.csv"));
    let (h_orbit, orbit) = csv_rows(&dir.join("orbit-impacts.csv"));
    assert_eq!(
        h.join(","),
        "t,pair,side,relative_velocity_before,u_o,u_i,v_o_before,v_i_before"
    );
    assert_eq!(h_orbit, h);
    let period = std::f64::consts::TAU / 2.0;
    let (t, side, u_o) = (column(&h, "t"), column(&h, "side"), column(&h, "u_o"));
    for a in &orbit {
        let ta: f64 = a[t].parse().unwrap();
        let matched = sim.iter().any(|s| {
            let ts: f64 = s[t].parse().unwrap();
            let dt = (ts - ta).rem_euclid(period);
            let dt = dt.min(period - dt);
            let du = (s[u_o].parse::<f64>().unwrap() - a[u_o].parse::<f64>().unwrap()).abs();
            s[side] == a[side] && dt < 1e-8 && du < 1e-8
        });
        assert!(
            matched,
            "analytic impact {a:?} not in the simulated cycle {sim:?}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn bad_trajectory_options_exit_2_and_name_the_option() {
    for (args, option) in [
        (
            vec!["simulate", "--omega", "2", "--trajectory", "t.txt"],
            "--trajectory",
        ),
        (
            vec![
                "simulate",
                "--omega",
                "2",
                "--trajectory",
                "t.csv",
                "--samples-per-period",
                "0",
            ],
            "--samples-per-period",
        ),
        (
            vec!["orbit", "--omega", "2", "--trajectory", "t.csv"],
            "--signature",
        ),
        (
            vec![
                "orbit",
                "--omega",
                "2",
                "--signature",
                "+-",
                "--orbit",
                "99",
                "--trajectory",
                "t.csv",
            ],
            "--orbit",
        ),
    ] {
        let out = rattle(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(option), "{args:?}: {stderr}");
    }
}

/// A 2-cell chain of the paper's damped unit (`paper-chain-5.json` with two cells): on it the
/// sequence `0+ 1- 0- 1+` has a viable orbit at ω = 3.3 (`tests/continuation_chain.rs` of the
/// analytic crate follows it).
const PAPER_CHAIN_2: &str = r#"{
  "name": "paper-chain-2",
  "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
  "base": {"amplitude": 1.0},
  "stops": {"gap": 0.5, "restitution": 0.8},
  "damping": {"outer": 0.1, "inner": 0.05},
  "cells": 2
}"#;

#[test]
fn continue_on_a_chain_gives_every_cells_outer_amplitude_per_point() {
    let scene = common::scene_file("cli-continue", "paper-chain-2.json", PAPER_CHAIN_2);
    let scene = scene.to_str().unwrap();
    let args = [
        "continue",
        scene,
        "--signature",
        "0+ 1- 0- 1+",
        "--omega",
        "3.3",
        "--omega-min",
        "3.2",
        "--omega-max",
        "3.4",
        "--max-depth",
        "0",
    ];
    let doc = json(&[&args[..], &["--json"]].concat());
    assert_eq!(doc["cells"], 2);
    assert_eq!(doc["signature"], "0+ 1- 0- 1+");
    let points = doc["points"].as_array().unwrap();
    assert!(points.len() > 20, "{} points", points.len());
    for p in points {
        let cells = p["cell_outer_amplitudes"].as_array().unwrap();
        assert_eq!(cells.len(), 2);
        assert_eq!(cells[1], p["outer_amplitude"]);
        assert!(cells[0].as_f64().unwrap() > 0.0);
    }
    let branches = doc["branches"].as_array().unwrap();
    assert_eq!(branches[0]["signature"], "0+ 1- 0- 1+");
    assert_eq!(doc["ends"].as_array().unwrap().len(), 2 * branches.len());
    let kinds: Vec<&str> = doc["events"]
        .as_array()
        .unwrap()
        .iter()
        .map(|e| e["kind"].as_str().unwrap())
        .collect();
    assert!(kinds.contains(&"neimark-sacker"), "{kinds:?}");

    // The CSV: one row per point, with the cells' amplitudes `;`-separated.
    let dir = std::env::temp_dir().join(format!("rattle-cli-continue-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("chain.csv");
    let out = rattle(&[&args[..], &["--out", csv.to_str().unwrap()]].concat());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let column = header
        .iter()
        .position(|c| *c == "cell_outer_amplitudes")
        .expect("a cell_outer_amplitudes column");
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), points.len());
    assert_eq!(
        rows[0].split(',').nth(column).unwrap().split(';').count(),
        2
    );

    // A single unit's document has neither field.
    let unit = json(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "3",
        "--omega-min",
        "2.9",
        "--omega-max",
        "3.1",
        "--max-depth",
        "0",
        "--json",
    ]);
    assert!(unit.get("cells").is_none());
    assert!(unit["points"][0].get("cell_outer_amplitudes").is_none());
}
