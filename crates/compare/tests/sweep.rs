//! Sweeps: deterministic whatever the thread count, with the documented columns, the same in
//! every format, streamed as the CLI streams them, checked against stored expected files; and
//! the figures pipeline end to end on a few points, so it cannot rot.

use rattle_compare::output::{writer, Format, Row};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::shard::{merge, Shard};
use rattle_compare::runs::sweep::{header, sweep_rows, Solver, SweepRow};
use rattle_compare::scene::Scene;
use rattle_event_driven::SimulationOptions;
use std::path::Path;

fn options() -> SimulationOptions {
    SimulationOptions {
        max_periods: 2000,
        ..SimulationOptions::default()
    }
}

/// What `rattle sweep` writes for `omegas` (part `shard` of `total` frequencies, if given).
fn written(
    scene: &Scene,
    omegas: &[f64],
    solver: Solver,
    format: Format,
    shard: Option<(Shard, usize)>,
) -> String {
    let mut out = Vec::new();
    {
        let total = shard.map_or(omegas.len(), |(_, t)| t);
        let preamble = shard.map(|(s, t)| s.csv_preamble(t));
        let mut table = writer(
            format,
            &mut out,
            &header(scene, solver, total, shard.map(|(s, _)| s)),
            preamble.as_deref(),
        )
        .unwrap();
        sweep_rows(
            scene,
            omegas,
            solver,
            &options(),
            &Progress::hidden(),
            |row| table.row(&row),
        )
        .unwrap();
        table.finish().unwrap();
    }
    String::from_utf8(out).unwrap()
}

fn run_with_threads(threads: usize, solver: Solver) -> (String, String) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let scene = Scene::paper();
        let omegas = Axis::new(0.5, 3.5, 9).values();
        (
            written(&scene, &omegas, solver, Format::Csv, None),
            written(&scene, &omegas, solver, Format::Json, None),
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
fn csv_json_and_json_lines_carry_the_same_columns() {
    let (csv, json) = run_with_threads(2, Solver::Both);
    let columns = SweepRow::COLUMNS;
    let mut reader = csv::Reader::from_reader(csv.as_bytes());
    assert_eq!(
        reader.headers().unwrap().iter().collect::<Vec<_>>(),
        columns
    );
    let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
    assert_eq!(rows.len(), 9);
    for row in &rows {
        assert_eq!(row.len(), columns.len());
        assert!(row
            .iter()
            .all(|cell| !cell.contains("NaN") && !cell.contains("inf")));
    }
    let doc: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(doc["solver"], "both");
    assert_eq!(doc["points"], 9);
    let results = doc["results"].as_array().unwrap();
    assert_eq!(results.len(), 9);
    for (r, row) in results.iter().zip(&rows) {
        let keys: Vec<&String> = r.as_object().unwrap().keys().collect();
        assert_eq!(keys.len(), columns.len());
        assert!(r["class"].is_string());
        // The same value in both formats, column by column.
        for (c, cell) in columns.iter().zip(row.iter()) {
            let v = &r[*c];
            match v {
                serde_json::Value::Null => assert_eq!(cell, "", "{c}"),
                serde_json::Value::String(s) => assert_eq!(cell, s, "{c}"),
                other => assert_eq!(cell, other.to_string(), "{c}"),
            }
        }
    }
    let scene = Scene::paper();
    let lines = written(
        &scene,
        &Axis::new(0.5, 3.5, 9).values(),
        Solver::Both,
        Format::JsonLines,
        None,
    );
    let objects: Vec<serde_json::Value> = lines
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(&objects, results);
}

/// Compares `text` with the stored file `tests/expected/NAME`; with `RATTLE_BLESS=1` writes it
/// instead (then review the diff before committing).
fn expect_file(name: &str, text: &str) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/expected")
        .join(name);
    if std::env::var_os("RATTLE_BLESS").is_some() {
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
    }
    let stored = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e} (RATTLE_BLESS=1 writes it)", path.display()));
    assert_eq!(text, stored, "{} differs from the output", path.display());
}

/// The analytic sweep's outputs, byte for byte, in each format: a change of a column, of the
/// number formatting or of a number shows here first.
#[test]
fn analytic_sweep_outputs_match_the_stored_files() {
    let scene = Scene::paper();
    let omegas = Axis::new(0.5, 3.5, 7).values();
    for (format, name) in [
        (Format::Csv, "sweep-analytic.csv"),
        (Format::Json, "sweep-analytic.json"),
        (Format::JsonLines, "sweep-analytic.jsonl"),
    ] {
        expect_file(
            name,
            &written(&scene, &omegas, Solver::Analytic, format, None),
        );
    }
}

#[cfg(feature = "figures")]
#[test]
fn the_figures_pipeline_runs_end_to_end() {
    use rattle_compare::study::report::{agreement, report};
    use rattle_compare::study::{maps, MapSizes, Study, StudySize};
    let dir = std::env::temp_dir().join(format!("rattle-figures-{}", std::process::id()));
    let scene = Scene::paper();
    let study = Study::run(&scene, StudySize::quick(), &options(), false);
    assert_eq!(
        study.compared.len() + study.failures.len(),
        StudySize::quick().compared_points
    );
    let maps = maps(&scene, MapSizes::quick(), false);
    assert!(maps.is_some());
    let plots = study.plots(&options(), maps.as_ref());
    let written = rattle_compare::figures::draw(&plots, &dir).unwrap();
    for name in [
        "linear-time-response",
        "impact-time-response",
        "transmittance",
        "agreement",
        "beta-family",
        "bifurcation",
        "bandwidth-map",
        "regime-map",
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
    // The Poincaré figure on a few sections of a periodic motion (3 rad/s, `+-`).
    let sections =
        rattle_compare::study::chaos::poincare_sections(&scene, 3.0, 50, 100, &options()).unwrap();
    let poincare = rattle_compare::figures::draw_poincare(
        &rattle_compare::figures::poincare::PoincareFigure {
            scene_name: scene.name.clone(),
            sections,
        },
        &dir,
    )
    .unwrap();
    for path in &poincare {
        assert!(std::fs::metadata(path).unwrap().len() > 1000, "{path:?}");
    }
    let agreement = serde_json::to_value(agreement(&study)).unwrap();
    for key in [
        "scene",
        "points_compared",
        "max_relative_difference",
        "classification_agreement",
        "by_class",
    ] {
        assert!(agreement.get(key).is_some(), "agreement.json lacks {key}");
    }
    // A chaotic motion (1.24 rad/s: λ₁ = 0.31/s) and a periodic one (3 rad/s, `+-`).
    let chaos = rattle_compare::study::chaos::chaos_samples(
        &scene,
        &[1.24, 3.0],
        &options(),
        &Progress::new("chaos", 0, false),
    );
    let report = report(&study, &study, "n/a", &chaos);
    assert!(report.contains("Nigm–Shabana") && report.contains("1.25"));
    assert!(
        report.contains("1 of 2 frequencies settle from rest on a chaotic motion")
            && report.contains("| 1.240 | 1.240 | 1 | 0.3"),
        "{report}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The study runs its parts at once (the continuation on a thread of its own, fed the compared
/// sweep's seeds when that is done): its every number, the agreement and the report are the
/// same on one thread as on two.
#[cfg(feature = "figures")]
#[test]
fn the_study_is_the_same_on_one_and_two_threads() {
    use rattle_compare::study::report::{agreement, report};
    use rattle_compare::study::{Study, StudySize};
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let study = Study::run(&Scene::paper(), StudySize::quick(), &options(), false);
            (
                format!("{study:?}"),
                serde_json::to_string(&agreement(&study)).unwrap(),
                report(&study, &study, "n/a", &[]),
            )
        })
    };
    let one = run(1);
    assert!(one.0.contains("branches: [Branch"), "no branch followed");
    assert_eq!(one, run(2));
}

#[test]
fn merged_shards_are_byte_identical_to_the_unsharded_sweep() {
    let scene = Scene::paper();
    let all = Axis::new(0.5, 3.5, 11).values();
    let solver = Solver::Both;
    let full_json = written(&scene, &all, solver, Format::Json, None);
    let full_csv = written(&scene, &all, solver, Format::Csv, None);
    let count = 4;
    let (mut json_parts, mut csv_parts) = (Vec::new(), Vec::new());
    for index in (1..=count).rev() {
        let shard = Shard { index, count };
        let part = &all[shard.range(all.len())];
        let of = Some((shard, all.len()));
        json_parts.push(written(&scene, part, solver, Format::Json, of));
        csv_parts.push(written(&scene, part, solver, Format::Csv, of));
    }
    assert_eq!(merge(&json_parts).unwrap(), full_json);
    assert_eq!(merge(&csv_parts).unwrap(), full_csv);
    // A missing part is refused.
    assert!(merge(&json_parts[1..]).is_err());
    assert!(merge(&csv_parts[1..]).is_err());
    assert!(
        Shard::parse("0/3").is_err() && Shard::parse("4/3").is_err() && Shard::parse("x").is_err()
    );
}

#[test]
fn a_chain_of_one_cell_sweeps_as_the_unit() {
    let unit = Scene::paper();
    let omegas = Axis::new(0.5, 3.5, 5).values();
    let rows = |scene: &Scene, solver: Solver| {
        let mut rows = Vec::new();
        sweep_rows(
            scene,
            &omegas,
            solver,
            &options(),
            &Progress::hidden(),
            |row| {
                rows.push(row);
                Ok::<(), std::convert::Infallible>(())
            },
        )
        .unwrap();
        rows
    };
    for (field, value) in [
        ("cells", serde_json::json!(1)),
        ("chain", serde_json::json!([{}])),
    ] {
        let mut doc = serde_json::to_value(&unit).unwrap();
        doc[field] = value;
        let scene = Scene::parse(&doc.to_string(), "one-cell").unwrap();
        assert_eq!(scene.cell_count(), 1);
        for solver in [Solver::Analytic, Solver::Event, Solver::Both] {
            assert_eq!(
                rows(&scene, solver),
                rows(&unit, solver),
                "{field}, {solver:?}"
            );
        }
    }
}
