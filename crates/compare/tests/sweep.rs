//! Sweeps: deterministic whatever the thread count, with the documented columns; and the
//! figures pipeline end to end on a few points, so it cannot rot.

use rattle_compare::scene::Scene;
use rattle_compare::study::{Study, StudySize};
use rattle_compare::sweep::{frequencies, sweep, to_csv, to_json, Solver, COLUMNS};
use rattle_event_driven::SimulationOptions;

fn run_with_threads(threads: usize, solver: Solver) -> (String, String) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let scene = Scene::paper();
        let omegas = frequencies(0.5, 3.5, 9);
        let options = SimulationOptions {
            max_periods: 2000,
            ..SimulationOptions::default()
        };
        let points = sweep(&scene, &omegas, solver, &options, false);
        (
            to_csv(&scene, &points),
            format!("{:#}", to_json(&scene, solver, &points)),
        )
    })
}

#[test]
fn sweeps_are_byte_identical_on_one_and_two_threads() {
    for solver in [Solver::Analytic, Solver::Both] {
        assert_eq!(run_with_threads(1, solver), run_with_threads(2, solver));
    }
}

#[test]
fn csv_and_json_carry_the_documented_columns() {
    let (csv, json) = run_with_threads(2, Solver::Both);
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), COLUMNS.join(","));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 9);
    for row in &rows {
        // Quoted strings contain no commas here, so a plain split counts the cells.
        assert_eq!(row.split(',').count(), COLUMNS.len(), "{row}");
        assert!(!row.contains("NaN") && !row.contains("inf"));
    }
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(doc["solver"], "both");
    let results = doc["results"].as_array().unwrap();
    assert_eq!(results.len(), 9);
    for r in results {
        for c in COLUMNS {
            assert!(r.get(c).is_some(), "missing {c}");
        }
        assert!(r["class"].is_string());
    }
}

#[test]
fn the_figures_pipeline_runs_end_to_end() {
    let dir = std::env::temp_dir().join(format!("rattle-figures-{}", std::process::id()));
    let options = SimulationOptions {
        max_periods: 2000,
        ..SimulationOptions::default()
    };
    let study = Study::run(&Scene::paper(), StudySize::quick(), &options, false);
    assert_eq!(
        study.compared.len() + study.failures.len(),
        StudySize::quick().compared_points
    );
    let written = rattle_compare::figures::generate(&study, &options, &dir).unwrap();
    for name in [
        "linear-time-response",
        "impact-time-response",
        "transmittance",
        "agreement",
        "beta-family",
        "bifurcation",
    ] {
        for ext in ["png", "svg"] {
            let path = dir.join(format!("{name}.{ext}"));
            assert!(written.contains(&path), "{path:?} not written");
            assert!(
                std::fs::metadata(&path).unwrap().len() > 1000,
                "{path:?} is empty"
            );
        }
    }
    let agreement = rattle_compare::validation::agreement(&study);
    for key in [
        "scene",
        "points_compared",
        "max_relative_difference",
        "classification_agreement",
        "by_class",
    ] {
        assert!(agreement.get(key).is_some(), "agreement.json lacks {key}");
    }
    let report = rattle_compare::validation::report(&study, &study, "n/a");
    assert!(report.contains("Nigm–Shabana") && report.contains("1.25"));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn merged_shards_are_byte_identical_to_the_unsharded_sweep() {
    use rattle_compare::sweep::{merge, to_csv_shard, to_json_shard, Shard};
    let scene = Scene::paper();
    let all = frequencies(0.5, 3.5, 11);
    let options = SimulationOptions {
        max_periods: 2000,
        ..SimulationOptions::default()
    };
    let solver = Solver::Both;
    let full = sweep(&scene, &all, solver, &options, false);
    let full_json = format!("{:#}\n", to_json(&scene, solver, &full));
    let full_csv = to_csv(&scene, &full);
    let count = 4;
    let (mut json_parts, mut csv_parts) = (Vec::new(), Vec::new());
    for index in (1..=count).rev() {
        let shard = Shard { index, count };
        let part = sweep(
            &scene,
            &all[shard.range(all.len())],
            solver,
            &options,
            false,
        );
        json_parts.push(format!(
            "{:#}\n",
            to_json_shard(&scene, solver, &part, all.len(), shard)
        ));
        csv_parts.push(to_csv_shard(&scene, &part, all.len(), shard));
    }
    assert_eq!(merge(&json_parts).unwrap(), full_json);
    assert_eq!(merge(&csv_parts).unwrap(), full_csv);
    // A missing part is refused.
    assert!(merge(&json_parts[1..]).is_err());
    assert!(
        Shard::parse("0/3").is_err() && Shard::parse("4/3").is_err() && Shard::parse("x").is_err()
    );
}
