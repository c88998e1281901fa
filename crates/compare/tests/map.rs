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
