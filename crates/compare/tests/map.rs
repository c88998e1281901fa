//! `rattle map`: the map over restitution, gap and frequency.

use rattle_analytic::linear_response;
use rattle_compare::map::{Axis, Map, MapGrid, MapSettings, POINT_COLUMNS};
use rattle_compare::scene::Scene;
use rattle_compare::simulation::Regime;
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
            .install(|| Map::run(&scene, g, &settings, false).unwrap())
    };
    let (one, two) = (run(1), run(2));
    assert_eq!(one.points_csv(), two.points_csv());
    assert_eq!(one.bandwidth_csv(), two.bandwidth_csv());
    // Header and one row per point.
    let csv = one.points_csv();
    let mut lines = csv.lines();
    assert_eq!(lines.next().unwrap(), POINT_COLUMNS.join(","));
    assert_eq!(lines.count(), 2 * 3 * 12);
}

#[test]
fn a_unit_that_never_reaches_its_stops_is_the_linear_unit() {
    // Δ/u_g = 50: the damped unit's relative motion stays far inside the stops at every
    // frequency, so the simulated steady state is the linear one and the analytic prediction
    // is the linear motion.
    let scene = damped();
    let g = grid(1, (50.0, 50.0, 1), 15);
    let map = Map::run(&scene, g, &MapSettings::default(), false).unwrap();
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

#[test]
fn bandwidth_counts_the_attenuating_samples() {
    let scene = damped();
    let g = grid(1, (0.3, 0.3, 1), 40);
    let map = Map::run(&scene, g, &MapSettings::default(), false).unwrap();
    let line = &map.lines[0];
    let step = g.omega.step();
    let b = line.simulated_bandwidth(step);
    let below: Vec<f64> = line
        .points
        .iter()
        .filter(|p| p.transmittance_db.is_some_and(|t| t < 0.0))
        .map(|p| p.omega)
        .collect();
    assert_eq!(b.attenuating_points, below.len());
    assert!((b.bandwidth - below.len() as f64 * step).abs() < 1e-12);
    assert_eq!(b.first_band_start, below.first().copied());
    // This damped unit attenuates above its second resonance.
    assert!(b.attenuating_points > 0);
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
