//! `rattle boundaries` as a user meets it: every curve passes through the event it started
//! from at the scene's own gap, the events are those `rattle continue` finds, the JSON and
//! CSV outputs agree, and bad input exits 2 naming the field.

mod common;
use common::{json, rattle};
use serde_json::Value;

/// The paper scene's boundaries over the gap near its scene value, from the continuation of
/// the motions of a three-frequency sweep of 2.8–3 rad/s (a few curves: `+-` and `+-+-`).
const ARGS: [&str; 15] = [
    "boundaries",
    "--param",
    "stops.gap",
    "--min",
    "0.4",
    "--max",
    "0.6",
    "--omega-min",
    "2.8",
    "--omega-max",
    "3.0",
    "--points",
    "3",
    "--max-points",
    "100",
];

fn number(v: &Value) -> f64 {
    v.as_f64().expect("a number")
}

#[test]
fn every_curve_passes_through_its_event_at_the_scene_gap() {
    let doc = json(&[ARGS.as_slice(), &["--json"]].concat());
    for key in ["param", "min", "max", "curves", "skipped"] {
        assert!(doc.get(key).is_some(), "missing {key}");
    }
    assert_eq!(doc["param"], "stops.gap");
    assert_eq!(doc["param_start"], 0.5);
    let curves = doc["curves"].as_array().unwrap();
    assert!(curves.len() >= 3, "{} curves", curves.len());
    for c in curves {
        let start = number(&c["omega_start"]);
        assert_eq!(c["param_start"], 0.5);
        // The curve's ω solved on its defining system at the scene's gap: one crossing is the
        // event of the one-parameter continuation it started from.
        let nearest = c["at"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|a| a["param_value"] == 0.5)
            .map(|a| (number(&a["omega"]) - start).abs())
            .fold(f64::INFINITY, f64::min);
        assert!(nearest < 1e-8, "{}: {nearest:e}", c["event"]);
        for p in c["points"].as_array().unwrap() {
            let gap = number(&p["param_value"]);
            assert!((0.4..=0.6).contains(&gap), "{gap}");
            let w = number(&p["omega"]);
            assert!((2.8..=3.0).contains(&w), "{w}");
        }
        assert_eq!(c["ends"].as_array().unwrap().len(), 2);
    }
    // The `+-` period doubling is the one `rattle continue` finds on the asymmetric `+-`
    // branch leaving the symmetric one at its branch point.
    let doubling = curves
        .iter()
        .find(|c| c["signature"] == "+-" && c["event"] == "period-doubling")
        .expect("the +- period doubling");
    let cont = json(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "2.95",
        "--omega-min",
        "2.8",
        "--omega-max",
        "3.0",
        "--max-branches",
        "2",
        "--json",
    ]);
    let found = cont["events"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|e| e["kind"] == "period-doubling")
        .map(|e| (number(&e["omega"]) - number(&doubling["omega_start"])).abs())
        .fold(f64::INFINITY, f64::min);
    assert!(found < 1e-8, "{found:e}");
    // The branch point where the asymmetric `+-` branch leaves the symmetric one is followed
    // too (Moore's extended system with the gap free), and its curve passes through it (the
    // loop above); none is skipped for its kind.
    assert!(
        curves.iter().any(|c| c["event"] == "branch-point"),
        "no branch-point curve: {:?}",
        doc["skipped"]
    );
    let skipped = doc["skipped"].as_array().unwrap();
    assert!(
        !skipped.iter().any(|s| s["kind"] == "branch-point"),
        "{skipped:?}"
    );
}

#[test]
fn csv_rows_are_the_json_points() {
    let dir = std::env::temp_dir();
    let csv = dir.join(format!("rattle-boundaries-{}.csv", std::process::id()));
    let doc_path = dir.join(format!("rattle-boundaries-{}.json", std::process::id()));
    for path in [&csv, &doc_path] {
        let out = rattle(&[ARGS.as_slice(), &["--out", path.to_str().unwrap()]].concat());
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let text = std::fs::read_to_string(&csv).unwrap();
    let doc: Value = serde_json::from_str(&std::fs::read_to_string(&doc_path).unwrap()).unwrap();
    let _ = std::fs::remove_file(&csv);
    let _ = std::fs::remove_file(&doc_path);
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "curve,from_event,event,signature,period,param_value,omega,outer_amplitude,critical_multiplier_re,critical_multiplier_im"
    );
    let points: Vec<(usize, &Value, &Value)> = doc["curves"]
        .as_array()
        .unwrap()
        .iter()
        .enumerate()
        .flat_map(|(k, c)| {
            c["points"]
                .as_array()
                .unwrap()
                .iter()
                .map(move |p| (k, c, p))
        })
        .collect();
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), points.len());
    for (row, (k, c, p)) in rows.iter().zip(points) {
        let f: Vec<&str> = row.split(',').collect();
        assert_eq!(f[0].parse::<usize>().unwrap(), k);
        assert_eq!(
            f[1].parse::<u64>().unwrap(),
            c["from_event"].as_u64().unwrap()
        );
        assert_eq!(f[2], c["event"].as_str().unwrap());
        assert_eq!(f[3], c["signature"].as_str().unwrap());
        // Both print the shortest representation that reads back exactly.
        assert_eq!(f[5].parse::<f64>().unwrap(), number(&p["param_value"]));
        assert_eq!(f[6].parse::<f64>().unwrap(), number(&p["omega"]));
        assert_eq!(f[7].parse::<f64>().unwrap(), number(&p["outer_amplitude"]));
    }
}

#[test]
fn bad_boundaries_arguments_exit_2_and_name_the_field() {
    let replace = |option: &str, value: &'static str| {
        let mut args = ARGS.to_vec();
        let k = args.iter().position(|a| *a == option).unwrap();
        args[k + 1] = value;
        args
    };
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (replace("--param", "stops.width"), "stops.width"),
        (replace("--min", "0"), "--min"),
        (replace("--min", "0.55"), "--min"),
        (replace("--max", "0.3"), "--max"),
        (replace("--omega-max", "2.5"), "--omega-max"),
        (replace("--points", "0"), "--points"),
        (replace("--max-points", "0"), "--max-points"),
        ([ARGS.as_slice(), &["--out", "b.jsonl"]].concat(), "--out"),
        (
            [ARGS.as_slice(), &["--max-impacts", "1"]].concat(),
            "--max-impacts",
        ),
    ];
    for (args, field) in cases {
        let out = rattle(&args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(field), "{args:?}: {stderr}");
    }
}

/// The stage of `cargo xtask figures` (`study::boundaries`) on the quick study: every curve
/// starts at an event of the study's own continuation and passes through it at the scene's
/// value to 1e-8; the data files load and agree; the curves are the same on one thread as on
/// two; the figure is drawn.
#[cfg(feature = "figures")]
#[test]
fn the_figures_stage_follows_the_study_events() {
    use rattle_compare::scene::Scene;
    use rattle_compare::study::boundaries::study_boundaries;
    use rattle_compare::study::{Study, StudySize};
    use rattle_event_driven::SimulationOptions;
    let options = SimulationOptions {
        max_periods: 4000,
        ..SimulationOptions::default()
    };
    let study = Study::run(&Scene::paper(), StudySize::quick(), &options, false);
    let in_pool = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| study_boundaries(&study, true))
    };
    let bounds = in_pool(1);
    assert_eq!(format!("{bounds:?}"), format!("{:?}", in_pool(2)));
    let events = &study.branches.events;
    for b in [&bounds.gap, &bounds.restitution] {
        let record = b.record.as_ref().expect("followed");
        assert_eq!(record.events, events.len());
        assert!(!record.curves.is_empty(), "no curve over {}", record.param);
        for c in &record.curves {
            let event = &events[c.from_event];
            assert_eq!(c.boundary.event, event.kind.name());
            assert_eq!(c.boundary.omega_start, event.omega);
            let nearest = c
                .boundary
                .at
                .iter()
                .map(|a| (a.omega - event.omega).abs())
                .fold(f64::INFINITY, f64::min);
            assert!(nearest < 1e-8, "{}: {nearest:e}", c.boundary.event);
        }
        // Every event is a curve, on a curve, or skipped.
        let on_curves: usize = record
            .curves
            .iter()
            .map(|c| 1 + c.same_as_events.len())
            .sum();
        assert_eq!(on_curves + record.skipped.len(), events.len());
    }
    let dir = std::env::temp_dir().join(format!("rattle-boundaries-stage-{}", std::process::id()));
    let written = bounds.write(&dir).unwrap();
    assert_eq!(written.len(), 4);
    for stem in ["gap", "restitution"] {
        let doc: Value = serde_json::from_str(
            &std::fs::read_to_string(dir.join(format!("{stem}.json"))).unwrap(),
        )
        .unwrap();
        let points: usize = doc["curves"]
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c["points"].as_array().unwrap().len())
            .sum();
        let csv = std::fs::read_to_string(dir.join(format!("{stem}.csv"))).unwrap();
        assert_eq!(csv.lines().count(), points + 1, "{stem}");
    }
    let figure = bounds.figure(&study, None);
    let drawn = rattle_compare::figures::draw_boundaries(&figure, &dir).unwrap();
    for path in &drawn {
        assert!(std::fs::metadata(path).unwrap().len() > 1000, "{path:?}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
