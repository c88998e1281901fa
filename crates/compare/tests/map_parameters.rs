//! `rattle map --x PATH --y PATH`: the map over any two scene parameters, on a unit and on a
//! structure, against sweeps of the scene with both parameters set by hand; the map over
//! restitution and gap as one choice of its axes; refusals naming the flag; parts merged.

use rattle_compare::api;
use rattle_compare::output::Format;
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::map::{
    stream_any, AnyMapGrid, MapAxes, MapColumns, MapGrid, MapLine, MapPointRow, MapSettings,
};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::structure_sweep::structure_point;
use rattle_compare::runs::sweep::{point, Solver, SweepRow};
use rattle_compare::scene::parameter::AnyParameter;
use rattle_compare::scene::simulator::{rest, run};
use rattle_compare::scene::AnyScene;
use rattle_compare::study::gallery::continued_runs;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const SCENES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes");

/// The text of a gallery scene.
fn text(name: &str) -> String {
    std::fs::read_to_string(Path::new(SCENES).join(name)).expect("the gallery scene")
}

/// `text` with the number at each JSON pointer set to its value: a scene set by hand.
fn set_by_hand(text: &str, numbers: &[(&str, f64)]) -> AnyScene {
    let mut doc: Value = serde_json::from_str(text).expect("JSON");
    for (pointer, value) in numbers {
        *doc.pointer_mut(pointer).expect("the field exists") = Value::from(*value);
    }
    AnyScene::parse(&doc.to_string(), "by hand").expect("a valid scene")
}

/// The map's rows of `grid` on `scene`, as the JSON objects of `rattle map --out F.json`.
fn map_rows(scene: &AnyScene, grid: &AnyMapGrid) -> Vec<Value> {
    let document = api::map_document(scene, grid, &MapSettings::default(), None).expect("a map");
    let mut doc: Value = serde_json::from_str(&document).expect("JSON");
    doc["results"].take().as_array().expect("rows").clone()
}

/// The lines of the map of `grid` on `scene`.
fn map_lines(scene: &AnyScene, grid: &AnyMapGrid) -> Vec<MapLine> {
    let mut lines = Vec::new();
    stream_any(
        scene,
        grid,
        &MapSettings::default(),
        None,
        &Progress::hidden(),
        |l| {
            lines.push(l);
            Ok::<(), std::convert::Infallible>(())
        },
    )
    .expect("a map");
    lines
}

fn parameters(scene: &AnyScene, x: &str, y: &str) -> MapAxes {
    MapAxes::Parameters {
        x: AnyParameter::parse(scene, x).expect("a path"),
        y: AnyParameter::parse(scene, y).expect("a path"),
    }
}

/// The simulated columns a map row shares with a sweep row (on a structure the amplitude
/// list is every body's, on a unit every cell's).
const SIMULATED: [&str; 7] = [
    "simulated_regime",
    "simulated_period",
    "simulated_impacts_per_period",
    "simulated_pair_impacts_per_period",
    "simulated_outer_amplitude",
    "simulated_transmittance_db",
    "simulated_body_amplitudes",
];

/// The asymmetric unit written as a structure (base-driven, damped): its stop's two sides are
/// the map's axes, from close (impacts) to far (clear of the stops).
const ASYMMETRIC: &str = "asymmetric-unit.json";
const GAP_PLUS: (&str, &str) = ("structure.stops[0].gap_plus", "/structure/stops/0/gap_plus");
const GAP_MINUS: (&str, &str) = (
    "structure.stops[0].gap_minus",
    "/structure/stops/0/gap_minus",
);

/// At each frequency alone (every line's one point from rest), a structure's map over two
/// stop sides is, point for point and bit for bit, `rattle sweep` of the scene with both sides
/// set by hand: the simulator's columns (`--solver event`, with the map's simulator options)
/// and, where the linear steady state keeps the stop clear, the prediction
/// (`--solver analytic`'s linear transmittance; none where it touches).
#[test]
fn a_structure_s_map_is_sweeps_of_the_scene_set_by_hand() {
    let text = text(ASYMMETRIC);
    let scene = AnyScene::parse(&text, ASYMMETRIC).expect("the gallery scene");
    let options = MapSettings::default().simulation;
    let (mut clear, mut touching) = (0, 0);
    for omega in [0.6, 1.7, 2.6] {
        let grid = AnyMapGrid {
            axes: parameters(&scene, GAP_PLUS.0, GAP_MINUS.0),
            x: Axis::new(0.6, 4.0, 2),
            y: Axis::new(0.25, 4.0, 2),
            omega: Axis::new(omega, omega, 1),
        };
        let rows = map_rows(&scene, &grid);
        assert_eq!(rows.len(), 4);
        let lines = [(0.6, 0.25), (0.6, 4.0), (4.0, 0.25), (4.0, 4.0)];
        for (row, (x, y)) in rows.iter().zip(lines) {
            assert_eq!((row["x"].as_f64(), row["y"].as_f64()), (Some(x), Some(y)));
            let AnyScene::Structure(form) =
                set_by_hand(&text, &[(GAP_PLUS.1, x), (GAP_MINUS.1, y)])
            else {
                panic!("a structure");
            };
            let swept = serde_json::to_value(structure_point(
                &form.structure,
                omega,
                Solver::Event,
                &options,
            ))
            .expect("JSON");
            for column in SIMULATED {
                assert_eq!(
                    row[column], swept[column],
                    "ω = {omega}, ({x}, {y}): {column}"
                );
            }
            let linear = serde_json::to_value(structure_point(
                &form.structure,
                omega,
                Solver::Analytic,
                &options,
            ))
            .expect("JSON");
            if linear["linear_touches_stops"] == Value::Bool(false) {
                clear += 1;
                assert_eq!(row["analytic_candidates"], 1, "ω = {omega}, ({x}, {y})");
                assert_eq!(
                    row["analytic_transmittance_db"], linear["linear_transmittance_db"],
                    "ω = {omega}, ({x}, {y})"
                );
                // Clear of the stops and damped, the simulator settles on the linear motion.
                assert_eq!(row["analytic_match"], true, "ω = {omega}, ({x}, {y})");
            } else {
                touching += 1;
                assert_eq!(row["analytic_candidates"], 0, "ω = {omega}, ({x}, {y})");
                assert_eq!(row["analytic_transmittance_db"], Value::Null);
            }
        }
    }
    assert!(
        clear > 0 && touching > 0,
        "{clear} clear, {touching} touching"
    );
}

/// Along a line the map continues every frequency from the previous one's final state: the
/// structure's line is the gallery's continued up-sweep of the scene set by hand, bit for bit.
#[test]
fn a_structure_s_line_is_the_continued_up_sweep_of_its_scene() {
    let text = text(ASYMMETRIC);
    let scene = AnyScene::parse(&text, ASYMMETRIC).expect("the gallery scene");
    let grid = AnyMapGrid {
        axes: parameters(&scene, GAP_PLUS.0, GAP_MINUS.0),
        x: Axis::new(0.6, 0.6, 1),
        y: Axis::new(0.25, 0.5, 2),
        omega: Axis::new(1.6, 2.4, 5),
    };
    let lines = map_lines(&scene, &grid);
    assert_eq!(lines.len(), 2);
    for line in &lines {
        let AnyScene::Structure(form) =
            set_by_hand(&text, &[(GAP_PLUS.1, line.x), (GAP_MINUS.1, line.y)])
        else {
            panic!("a structure");
        };
        let mut swept = Vec::new();
        continued_runs(
            &form.structure,
            grid.omega.values().into_iter(),
            &MapSettings::default().simulation,
            |p| swept.push(p.clone()),
        );
        assert_eq!(swept.len(), line.points.len());
        for (p, s) in line.points.iter().zip(&swept) {
            assert_eq!(p.omega, s.omega);
            assert_eq!(p.regime, Some(s.regime), "ω = {}", p.omega);
            assert_eq!(p.period, s.steady.period);
            assert_eq!(p.periods_run, s.steady.periods_run);
            assert_eq!(p.outer_amplitude.to_bits(), s.outer_amplitude.to_bits());
            assert_eq!(p.amplitudes, s.steady.amplitudes);
            assert_eq!(p.transmittance_db, s.transmittance_db);
        }
    }
    // Both lines impact somewhere: the map is not only the linear structure.
    assert!(lines
        .iter()
        .all(|l| l.points.iter().any(|p| p.impacts_per_period > 0.0)));
}

/// The paper's damped unit over its inner mass and inner dashpot (paths other than the stops'):
/// at each frequency alone, `rattle sweep --solver event` of the unit set by hand; along a
/// line, the simulator continued from each frequency's final state.
#[test]
fn a_unit_s_map_over_its_inner_mass_and_dashpot_is_sweeps_set_by_hand() {
    let text = text("paper-damped.json");
    let scene = AnyScene::parse(&text, "paper-damped.json").expect("the gallery scene");
    let options = MapSettings::default().simulation;
    let by_hand = |x: f64, y: f64| match set_by_hand(
        &text,
        &[("/unit/inner_mass", x), ("/damping/inner", y)],
    ) {
        AnyScene::Cells(s) => s,
        AnyScene::Structure(_) => panic!("a unit"),
    };
    let axes = parameters(&scene, "unit.inner_mass", "damping.inner");
    for omega in [1.2, 2.3] {
        let grid = AnyMapGrid {
            axes,
            x: Axis::new(0.8, 1.2, 2),
            y: Axis::new(0.05, 0.2, 2),
            omega: Axis::new(omega, omega, 1),
        };
        for row in map_rows(&scene, &grid) {
            let (x, y) = (row["x"].as_f64().unwrap(), row["y"].as_f64().unwrap());
            let unit = by_hand(x, y);
            let swept = serde_json::to_value(SweepRow::new(
                &unit,
                &point(&unit, omega, Solver::Event, &options),
            ))
            .expect("JSON");
            for column in SIMULATED
                .iter()
                .map(|c| c.replace("body_amplitudes", "cell_outer_amplitudes"))
            {
                assert_eq!(
                    row[&column], swept[&column],
                    "ω = {omega}, ({x}, {y}): {column}"
                );
            }
        }
    }
    let grid = AnyMapGrid {
        axes,
        x: Axis::new(0.8, 0.8, 1),
        y: Axis::new(0.2, 0.2, 1),
        omega: Axis::new(1.0, 2.5, 6),
    };
    let line = &map_lines(&scene, &grid)[0];
    let unit = by_hand(0.8, 0.2);
    let mut start = rest(&unit);
    for p in &line.points {
        let s = run(&unit, p.omega, &start, &options).expect("a run");
        start = s.steady.final_state.clone();
        assert_eq!(p.regime, Some(s.regime), "ω = {}", p.omega);
        assert_eq!(p.outer_amplitude.to_bits(), s.outer_amplitude.to_bits());
        assert_eq!(p.transmittance_db, s.transmittance_db);
    }
}

/// The map over restitution and gap is one choice of the map's axes: on a unit with `u_g = 1`
/// it is the map over the paths `stops.restitution` and `stops.gap`, row for row and value for
/// value, under its own column names and header.
#[test]
fn the_map_over_restitution_and_gap_is_the_map_over_their_paths() {
    let text = text("paper-damped.json");
    let scene = AnyScene::parse(&text, "paper-damped.json").expect("the gallery scene");
    let stops = MapGrid {
        restitution: Axis::new(0.3, 0.9, 2),
        gap_over_base_amplitude: Axis::new(0.2, 0.7, 2),
        omega: Axis::new(1.5, 2.5, 4),
    };
    let paths = AnyMapGrid {
        axes: parameters(&scene, "stops.restitution", "stops.gap"),
        x: stops.restitution,
        y: stops.gap_over_base_amplitude,
        omega: stops.omega,
    };
    let document = api::map_document(&scene, &stops.into(), &MapSettings::default(), None)
        .expect("the default map");
    assert!(document.contains(
        r#""grid":{"restitution":{"min":0.3,"max":0.9,"count":2},"gap_over_base_amplitude":{"min":0.2,"max":0.7,"count":2},"omega":{"min":1.5,"max":2.5,"count":4}}"#
    ));
    let document = api::map_document(&scene, &paths, &MapSettings::default(), None)
        .expect("the map over two paths");
    assert!(document.contains(
        r#""grid":{"x":{"path":"stops.restitution","min":0.3,"max":0.9,"count":2},"y":{"path":"stops.gap","min":0.2,"max":0.7,"count":2},"omega""#
    ));
    let csv = |grid: &AnyMapGrid| {
        let mut out = Vec::new();
        api::map(
            &scene,
            grid,
            &MapSettings::default(),
            None,
            (Format::Csv, &mut out),
            None::<(Format, Vec<u8>)>,
            &Progress::hidden(),
        )
        .expect("a map");
        String::from_utf8(out).expect("UTF-8")
    };
    let (by_stops, by_paths) = (csv(&stops.into()), csv(&paths));
    let (stops_columns, stops_rows) = by_stops.split_once('\n').unwrap();
    let (paths_columns, paths_rows) = by_paths.split_once('\n').unwrap();
    assert_eq!(
        stops_columns,
        <MapPointRow as rattle_compare::output::Row>::COLUMNS.join(",")
    );
    assert!(stops_columns.starts_with("restitution,gap_over_base_amplitude,omega,"));
    assert_eq!(paths_columns, MapColumns::PARAMETERS.points().join(","));
    assert!(paths_columns.starts_with("x,y,omega,"));
    assert_eq!(stops_rows.lines().count(), 16);
    assert_eq!(stops_rows, paths_rows);
}

fn rattle(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args(args)
        .output()
        .expect("rattle runs")
}

fn scene_path(name: &str) -> String {
    Path::new(SCENES).join(name).to_str().unwrap().to_owned()
}

/// A bad path, a parameter's value out of its range, the same path twice, a lone `--x`, the
/// restitution's flags beside `--x`, and a structure without `--x`/`--y`: exit 2 before
/// anything is written, naming the flag (and the path's range).
#[test]
fn bad_parameter_axes_exit_2_and_name_the_flag() {
    let damped = scene_path("paper-damped.json");
    let oscillator = scene_path("impact-oscillator.json");
    let unit_axes = |x: &str, lo: &str, y: &str| {
        vec![
            "--x".to_owned(),
            x.into(),
            "--x-min".into(),
            lo.into(),
            "--x-max".into(),
            "1".into(),
            "--y".into(),
            y.into(),
            "--y-min".into(),
            "0.1".into(),
            "--y-max".into(),
            "0.2".into(),
        ]
    };
    let cases: Vec<(String, Vec<String>, Vec<&str>)> = vec![
        (
            damped.clone(),
            unit_axes("stops.gapp", "0.5", "stops.gap"),
            vec!["--x: parameter `stops.gapp` is not a scene field"],
        ),
        (
            damped.clone(),
            unit_axes("unit.inner_mass", "-1", "stops.gap"),
            vec!["--x-min = -1", "unit.inner_mass", "must be > 0"],
        ),
        (
            damped.clone(),
            unit_axes("stops.restitution", "0.5", "stops.gap")
                .into_iter()
                .map(|a| if a == "1" { "1.5".into() } else { a })
                .collect(),
            vec!["--x-max = 1.5", "stops.restitution", "[0, 1]"],
        ),
        (
            damped.clone(),
            unit_axes("stops.gap", "0.5", "stops.gap"),
            vec!["--y: the same parameter as --x"],
        ),
        (
            damped.clone(),
            vec!["--x".into(), "stops.gap".into()],
            vec!["--x is given without --y"],
        ),
        (
            damped.clone(),
            [
                unit_axes("unit.inner_mass", "0.5", "stops.gap"),
                vec!["--gaps".into(), "3".into()],
            ]
            .concat(),
            vec!["--gaps is not taken with --x and --y"],
        ),
        (
            oscillator.clone(),
            vec![],
            vec!["structure form", "--x and --y"],
        ),
        (
            oscillator.clone(),
            unit_axes(
                "structure.stops[0].gap_minus",
                "0.5",
                "structure.stops[0].restitution",
            ),
            vec!["--x: parameter `structure.stops[0].gap_minus`", "no side 2"],
        ),
        (
            oscillator,
            unit_axes(
                "structure.bodies[0].mass",
                "0",
                "structure.stops[0].restitution",
            ),
            vec!["--x-min = 0", "structure.bodies[0].mass", "> 0"],
        ),
    ];
    let never = std::env::temp_dir().join(format!("rattle-never-{}.csv", std::process::id()));
    for (scene, args, words) in cases {
        let mut all = vec!["map".to_owned(), scene];
        all.extend(args.iter().cloned());
        all.extend(["--points".into(), "2".into(), "--out".into()]);
        all.push(never.to_str().unwrap().into());
        let out = rattle(&all.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let message = String::from_utf8_lossy(&out.stderr);
        for word in words {
            assert!(message.contains(word), "{args:?}: {message}");
        }
        assert!(!never.exists(), "{args:?}: a file was written");
    }
}

/// Sharded by whole lines with `--x`/`--y`, on a structure and on a unit, both tables: the
/// merged parts are the unsharded files byte for byte.
#[test]
fn parameter_maps_merge_from_their_parts_byte_for_byte() {
    let dir: PathBuf =
        std::env::temp_dir().join(format!("rattle-map-xy-parts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let structure = [
        scene_path("impact-oscillator.json"),
        "--x".into(),
        "structure.stops[0].gap_plus".into(),
        "--x-min".into(),
        "0.2".into(),
        "--x-max".into(),
        "1.0".into(),
        "--x-count".into(),
        "3".into(),
        "--y".into(),
        "structure.stops[0].restitution".into(),
        "--y-min".into(),
        "0.5".into(),
        "--y-max".into(),
        "0.9".into(),
        "--y-count".into(),
        "2".into(),
        "--omega-min".into(),
        "0.8".into(),
        "--omega-max".into(),
        "1.6".into(),
    ];
    let unit = [
        scene_path("paper-graded-4.json"),
        "--x".into(),
        "chain[2].stops.gap".into(),
        "--x-min".into(),
        "0.2".into(),
        "--x-max".into(),
        "0.6".into(),
        "--x-count".into(),
        "2".into(),
        "--y".into(),
        "unit.inner_mass".into(),
        "--y-min".into(),
        "0.9".into(),
        "--y-max".into(),
        "1.1".into(),
        "--y-count".into(),
        "2".into(),
        "--omega-min".into(),
        "1.5".into(),
        "--omega-max".into(),
        "2.5".into(),
    ];
    for (name, flags, (points, bandwidth)) in [
        ("structure", &structure, ("csv", "json")),
        ("unit", &unit, ("json", "csv")),
    ] {
        let run = |shard: Option<&str>, tag: &str| {
            let files = (
                dir.join(format!("{name}-{tag}.{points}")),
                dir.join(format!("{name}-{tag}-b.{bandwidth}")),
            );
            let mut args: Vec<&str> = vec!["map"];
            args.extend(flags.iter().map(String::as_str));
            args.extend(["--points", "4"]);
            if let Some(s) = shard {
                args.extend(["--shard", s]);
            }
            args.extend(["--out", files.0.to_str().unwrap()]);
            args.extend(["--bandwidth-out", files.1.to_str().unwrap()]);
            let o = rattle(&args);
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            files
        };
        let whole = run(None, "whole");
        let parts: Vec<_> = ["3/3", "1/3", "2/3"]
            .iter()
            .enumerate()
            .map(|(k, s)| run(Some(s), &format!("part{k}")))
            .collect();
        for pick in [0, 1] {
            let merged = dir.join(format!("{name}-merged-{pick}"));
            let mut args = vec!["merge".to_owned()];
            for p in &parts {
                let file = if pick == 0 { &p.0 } else { &p.1 };
                args.push(file.to_str().unwrap().to_owned());
            }
            args.extend(["--out".into(), merged.to_str().unwrap().into()]);
            let o = rattle(&args.iter().map(String::as_str).collect::<Vec<_>>());
            assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
            let expected = if pick == 0 { &whole.0 } else { &whole.1 };
            assert_eq!(
                std::fs::read(&merged).unwrap(),
                std::fs::read(expected).unwrap(),
                "{name}, table {pick}"
            );
        }
        // The columns name the axes `x` and `y`; a structure lists every body.
        let table = std::fs::read_to_string(&whole.0).unwrap();
        let header = if points == "csv" {
            table.lines().next().unwrap().to_owned()
        } else {
            table.lines().nth(1).unwrap().to_owned()
        };
        assert!(header.starts_with(if points == "csv" {
            "x,y,omega,"
        } else {
            "{\"x\":"
        }));
        assert_eq!(
            header.contains("simulated_body_amplitudes"),
            name == "structure",
            "{header}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
