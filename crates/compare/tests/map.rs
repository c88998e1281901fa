//! `rattle map`: the map over restitution, gap and frequency.

use rattle_analytic::linear_response;
use rattle_compare::output::{table_text, Format, Header, Row};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::map::{Bandwidth, Map, MapGrid, MapPointRow, MapSettings};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::scene::simulator::Regime;
use rattle_compare::scene::Scene;
use std::process::Command;

fn damped() -> Scene {
    Scene::parse(
        r#"{"name": "damped",
            "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
            "base": {"amplitude": 1.0}, "stops": {"gap": 0.5, "restitution": 0.8},
            "damping": {"outer": 0.3, "inner": 0.15}}"#,
        "test",
    )
    .unwrap()
}

fn grid(restitutions: usize, gaps: (f64, f64, usize), points: usize) -> MapGrid {
    MapGrid {
        restitution: Axis {
            min: 0.2,
            max: 0.9,
            count: restitutions,
        },
        gap_over_base_amplitude: Axis {
            min: gaps.0,
            max: gaps.1,
            count: gaps.2,
        },
        omega: Axis {
            min: 0.5,
            max: 3.5,
            count: points,
        },
    }
}

#[test]
fn the_map_does_not_depend_on_the_number_of_threads() {
    let scene = damped();
    let g = grid(2, (0.1, 0.8, 3), 12);
    let settings = MapSettings::default();
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| Map::run(&scene, g, &settings, &Progress::hidden()).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let points = |m: &Map| {
        table_text(
            Format::Csv,
            &Header::default(),
            &m.point_rows().collect::<Vec<_>>(),
        )
    };
    let bandwidth = |m: &Map| {
        table_text(
            Format::Json,
            &Header::default(),
            &m.bandwidth_rows().collect::<Vec<_>>(),
        )
    };
    assert_eq!(points(&one), points(&two));
    assert_eq!(bandwidth(&one), bandwidth(&two));
    // Header and one row per point.
    let csv = points(&one);
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), MapPointRow::COLUMNS.join(","));
    assert_eq!(lines.count(), 2 * 3 * 12);
}

#[test]
fn a_unit_that_never_reaches_its_stops_is_the_linear_unit() {
    // Δ/u_g = 50: the damped unit's relative motion stays far inside the stops at every
    // frequency, so the simulated steady state is the linear one and the analytic prediction
    // is the linear motion.
    let scene = damped();
    let g = grid(1, (50.0, 50.0, 1), 15);
    let map = Map::run(&scene, g, &MapSettings::default(), &Progress::hidden()).unwrap();
    let unit = scene.unit_model();
    for p in &map.lines[0].points {
        assert_eq!(p.regime, Some(Regime::NoImpact), "ω = {}", p.omega);
        let linear = linear_response(&unit, p.omega);
        let t = p.transmittance_db.expect("a transmittance");
        assert!(
            (t - linear.transmittance_db).abs() < 1e-3,
            "ω = {}: {t} vs {}",
            p.omega,
            linear.transmittance_db
        );
        assert!(p.analytic_match, "ω = {}", p.omega);
        assert!(p.analytic_transmittance_db.is_some());
    }
}

/// A hand-made line with its answer: samples at ω = 1, 1.5, …, 5.5; below 0 dB at 2, 2.5
/// (a band) and at 4.5 … 5.5 (open above); 3.0 has no value.
#[test]
fn bandwidth_of_a_hand_made_line() {
    let omegas: Vec<f64> = (0..10).map(|i| 1.0 + 0.5 * i as f64).collect();
    let values = [
        Some(3.0),
        Some(-1.0),
        Some(-2.0),
        Some(1.0),
        None,
        Some(0.5),
        Some(2.0),
        Some(-0.1),
        Some(-4.0),
        Some(-5.0),
    ];
    let b = Bandwidth::of(&omegas, &values, 0.5);
    assert_eq!(b.attenuating_points, 5);
    assert_eq!(b.valued_points, 9);
    assert_eq!(b.bandwidth, 2.5);
    assert_eq!(b.first_band_start, Some(1.5));
    assert_eq!(b.bands, vec![(1.5, 2.0), (4.5, f64::INFINITY)]);
}

/// Far stops: the attenuating samples are exactly those where the linear damped unit's
/// closed-form transmittance (the analytic crate's, not the map's) is below 0 dB.
#[test]
fn bandwidth_of_a_unit_clear_of_its_stops_is_the_linear_one() {
    let scene = damped();
    let g = grid(1, (50.0, 50.0, 1), 40);
    let map = Map::run(&scene, g, &MapSettings::default(), &Progress::hidden()).unwrap();
    let unit = scene.unit_model();
    let below: Vec<f64> = g
        .omega
        .values()
        .into_iter()
        .filter(|&w| linear_response(&unit, w).transmittance_db < 0.0)
        .collect();
    let b = map.lines[0].simulated_bandwidth(g.omega.step());
    assert!(!below.is_empty());
    assert_eq!(b.attenuating_points, below.len());
    assert_eq!(b.first_band_start, below.first().copied());
}

#[test]
fn bad_map_arguments_exit_2_and_name_the_field() {
    let rattle = env!("CARGO_BIN_EXE_rattle");
    for (args, field) in [
        (vec!["--restitution-max", "1.5"], "--restitution-max"),
        (vec!["--gap-min", "0"], "--gap-min"),
        (vec!["--points", "0"], "--points"),
        (vec!["--omega-min", "nan"], "--omega-min"),
    ] {
        let out = Command::new(rattle)
            .arg("map")
            .args(&args)
            .args(["--out", "/dev/null/never.csv"])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let message = String::from_utf8_lossy(&out.stderr);
        assert!(message.contains(field), "{args:?}: {message}");
    }
}

/// A map cut into parts by whole lines: merged, any number of parts (more than the lines too)
/// in any order gives exactly the tables of the whole map, points and bandwidths, CSV and JSON.
#[test]
fn merged_parts_are_the_whole_map_byte_for_byte() {
    use rattle_compare::runs::map::write_map;
    use rattle_compare::runs::shard::{merge, Shard};
    let scene = damped();
    let g = grid(2, (0.1, 0.8, 3), 8);
    let settings = MapSettings::default();
    let tables = |formats: (Format, Format), shard: Option<Shard>| {
        let (mut points, mut bandwidth) = (Vec::new(), Vec::new());
        write_map(
            &scene,
            &g,
            &settings,
            shard,
            (formats.0, &mut points),
            Some((formats.1, &mut bandwidth)),
            &Progress::hidden(),
        )
        .unwrap();
        (
            String::from_utf8(points).unwrap(),
            String::from_utf8(bandwidth).unwrap(),
        )
    };
    for (formats, counts) in [
        ((Format::Csv, Format::Json), &[1, 2, 4, 9][..]),
        ((Format::Json, Format::Csv), &[3][..]),
    ] {
        let (points, bandwidth) = tables(formats, None);
        assert_eq!(
            points.lines().count(),
            1 + 2 * 3 * 8 + usize::from(formats.0 == Format::Json)
        );
        for &count in counts {
            let parts: Vec<(String, String)> = (1..=count)
                .rev()
                .map(|index| tables(formats, Some(Shard { index, count })))
                .collect();
            let (p, b): (Vec<String>, Vec<String>) = parts.into_iter().unzip();
            assert_eq!(merge(&p).unwrap(), points, "{count} parts");
            assert_eq!(merge(&b).unwrap(), bandwidth, "{count} parts");
        }
    }
}

#[test]
fn the_command_merges_its_map_parts_into_the_whole_files() {
    let dir = std::env::temp_dir().join(format!("rattle-map-parts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |shard: Option<&str>, name: &str| {
        let (points, bandwidth) = (
            dir.join(format!("{name}.csv")),
            dir.join(format!("{name}-b.json")),
        );
        let mut args = vec![
            "map",
            "--restitutions",
            "2",
            "--gaps",
            "2",
            "--points",
            "5",
            "--omega-min",
            "1.5",
            "--omega-max",
            "2.5",
        ];
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        let o = Command::new(env!("CARGO_BIN_EXE_rattle"))
            .args(&args)
            .args(["--out", points.to_str().unwrap()])
            .args(["--bandwidth-out", bandwidth.to_str().unwrap()])
            .output()
            .expect("rattle runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        (points, bandwidth)
    };
    let whole = run(None, "whole");
    let parts: Vec<_> = ["1/3", "2/3", "3/3"]
        .iter()
        .enumerate()
        .map(|(k, s)| run(Some(s), &format!("part-{k}")))
        .collect();
    for (merged, pick) in [("merged.csv", 0), ("merged-b.json", 1)] {
        let merged = dir.join(merged);
        let files: Vec<String> = parts
            .iter()
            .rev()
            .map(|p| if pick == 0 { &p.0 } else { &p.1 })
            .map(|p| p.to_str().unwrap().to_owned())
            .collect();
        let o = Command::new(env!("CARGO_BIN_EXE_rattle"))
            .arg("merge")
            .args(&files)
            .args(["--out", merged.to_str().unwrap()])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let expected = if pick == 0 { &whole.0 } else { &whole.1 };
        assert_eq!(
            std::fs::read(&merged).unwrap(),
            std::fs::read(expected).unwrap()
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
