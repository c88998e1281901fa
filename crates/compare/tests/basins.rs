//! Basins of attraction: deterministic whatever the thread count, and a start on a stable
//! orbit coloured by that orbit.

use rattle_compare::runs::basins::{basin_options, destination, Attractor};
use rattle_compare::scene::analytic::{analyse, OrbitSearch};
use rattle_compare::scene::simulator::start_on_orbit;
use rattle_compare::scene::Scene;
use std::process::Command;

/// The coexistence frequency of the paper's unit (`validation/hard-cases/coexistence.json`,
/// `tests/hard_cases.rs`): from rest a four-impact motion, beside a stable symmetric orbit.
const COEXISTENCE_OMEGA: f64 = 1.86;

fn basins_file(threads: &str, out: &std::path::Path) -> String {
    let o = Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args([
            "basins",
            "--omega",
            "1.86",
            "--outer-min",
            "-1.5",
            "--outer-max",
            "1.5",
            "--inner-min",
            "-1.5",
            "--inner-max",
            "1.5",
            "--points",
            "12",
            "--out",
            out.to_str().unwrap(),
        ])
        .env("RAYON_NUM_THREADS", threads)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("rattle runs");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(out).unwrap()
}

#[test]
fn the_same_grid_on_one_and_two_threads_gives_identical_files() {
    let dir = std::env::temp_dir().join(format!("rattle-basins-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let one = basins_file("1", &dir.join("one.csv"));
    let two = basins_file("2", &dir.join("two.csv"));
    assert_eq!(one.lines().count(), 1 + 12 * 12);
    assert_eq!(one, two);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_start_exactly_on_a_stable_orbit_is_coloured_by_that_orbit() {
    let scene = Scene::paper();
    let analytic = analyse(&scene, COEXISTENCE_OMEGA, OrbitSearch::Symmetric).unwrap();
    let (_, orbit) = analytic
        .stable_viable_orbits()
        .next()
        .expect("a stable symmetric orbit at the coexistence frequency");
    let start = start_on_orbit(&scene, orbit, 0.0);
    let (attractor, _, _) = destination(&scene, COEXISTENCE_OMEGA, &start, &basin_options());
    let expected = Attractor::Periodic {
        signature: Some("+-".into()),
        period: 1,
        outer_amplitude: orbit.outer_amplitude,
    };
    assert!(attractor.same(&expected), "{attractor:?} vs {expected:?}");
    // From rest the unit goes elsewhere: the two are different attractors.
    let (from_rest, _, _) = destination(
        &scene,
        COEXISTENCE_OMEGA,
        &rattle_compare::runs::basins::start_at_rest(0.0, 0.0),
        &basin_options(),
    );
    assert!(!from_rest.same(&expected), "{from_rest:?}");
}

/// The start at rest at the origin on the paper's unit at ω = 1.9 rad/s converges slowly on the
/// `++--` orbit (λ₁ = −0.008 /s): it repeats to the basins' periodicity tolerance only after
/// the cap (400 periods), yet a run four times longer shows where it goes. The basins attribute
/// it to that attractor by proximity to the reference grid's, well before the cap.
#[test]
fn a_slow_start_is_attributed_to_the_attractor_a_long_run_reaches() {
    use rattle_compare::runs::axis::Axis;
    use rattle_compare::runs::basins::{
        basin_options, basins, destination, start_at_rest, Attractor, BasinGrid, BASIN_MAX_PERIODS,
    };
    use rattle_compare::runs::parallel::Progress;
    use rattle_compare::scene::Scene;
    let scene = Scene::paper();
    let omega = 1.9;
    let origin = start_at_rest(0.0, 0.0);
    let (capped, _, periods) = destination(&scene, omega, &origin, &basin_options());
    assert_eq!(capped, Attractor::NotPeriodic, "{periods} periods");
    let long = rattle_event_driven::SimulationOptions {
        max_periods: 4 * BASIN_MAX_PERIODS,
        ..basin_options()
    };
    let (truth, _, _) = destination(&scene, omega, &origin, &long);
    assert!(matches!(truth, Attractor::Periodic { .. }), "{truth:?}");
    let grid = BasinGrid {
        outer: Axis::new(-1.5, 1.5, 11),
        inner: Axis::new(-1.5, 1.5, 11),
    };
    let b = basins(&scene, omega, grid, &basin_options(), &Progress::hidden());
    let cell = b
        .cells
        .iter()
        .find(|c| c.outer == 0.0 && c.inner == 0.0)
        .expect("the origin is on the grid");
    assert!(
        b.attractors[cell.attractor].same(&truth),
        "{:?}",
        b.attractors[cell.attractor]
    );
    assert!(
        cell.periods_run < BASIN_MAX_PERIODS,
        "{} periods",
        cell.periods_run
    );
}

/// Basins cut into parts: merged, any number of parts (more than the starts too) in any order
/// gives exactly the table of the whole grid, CSV and JSON, attractors numbered over the
/// whole grid (at ω = 1.9 rad/s over ±4 m, 6 × 6 starts: `not periodic` first, then `++--`
/// for 3 starts, so a part without the first start numbers them otherwise).
#[test]
fn merged_parts_are_the_whole_grid_byte_for_byte() {
    use rattle_compare::output::Format;
    use rattle_compare::runs::axis::Axis;
    use rattle_compare::runs::basins::{basin_options, write_basins, BasinGrid};
    use rattle_compare::runs::parallel::Progress;
    use rattle_compare::runs::shard::{merge, Shard};
    let grid = BasinGrid {
        outer: Axis::new(-4.0, 4.0, 6),
        inner: Axis::new(-4.0, 4.0, 6),
    };
    let table = |format: Format, shard: Option<Shard>| {
        let mut out = Vec::new();
        write_basins(
            &Scene::paper(),
            1.9,
            grid,
            &basin_options(),
            shard,
            (format, &mut out),
            &Progress::hidden(),
        )
        .unwrap();
        String::from_utf8(out).unwrap()
    };
    for (format, counts) in [
        (Format::Csv, &[1, 2, 5, 40][..]),
        (Format::Json, &[3, 7][..]),
    ] {
        let whole = table(format, None);
        let attractors: std::collections::BTreeSet<&str> = whole
            .lines()
            .skip(1)
            .filter_map(|l| l.split(',').nth(2))
            .collect();
        if format == Format::Csv {
            assert!(attractors.len() >= 2, "{whole}");
        }
        for &count in counts {
            let parts: Vec<String> = (1..=count)
                .rev()
                .map(|index| table(format, Some(Shard { index, count })))
                .collect();
            assert_eq!(merge(&parts).unwrap(), whole, "{count} parts, {format:?}");
            // A part missing, or one repeated, is refused.
            if count > 1 {
                assert!(merge(&parts[1..]).is_err());
                let mut twice = parts.clone();
                twice[0] = parts[1].clone();
                assert!(merge(&twice).is_err());
            }
        }
    }
}

#[test]
fn the_command_merges_its_basins_parts_into_the_whole_file() {
    let dir = std::env::temp_dir().join(format!("rattle-basins-parts-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let run = |shard: Option<&str>, out: &std::path::Path| {
        let mut args = vec![
            "basins",
            "--omega",
            "1.86",
            "--outer-min",
            "-1.5",
            "--outer-max",
            "1.5",
            "--inner-min",
            "-1.5",
            "--inner-max",
            "1.5",
            "--points",
            "5",
        ];
        if let Some(s) = shard {
            args.extend(["--shard", s]);
        }
        let o = Command::new(env!("CARGO_BIN_EXE_rattle"))
            .args(&args)
            .args(["--out", out.to_str().unwrap()])
            .output()
            .expect("rattle runs");
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    let whole = dir.join("whole.json");
    run(None, &whole);
    let parts: Vec<_> = (1..=2)
        .map(|k| dir.join(format!("part-{k}.json")))
        .collect();
    run(Some("1/2"), &parts[0]);
    run(Some("2/2"), &parts[1]);
    let merged = dir.join("merged.json");
    let o = Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args([
            "merge",
            parts[1].to_str().unwrap(),
            parts[0].to_str().unwrap(),
        ])
        .args(["--out", merged.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(
        std::fs::read(&merged).unwrap(),
        std::fs::read(&whole).unwrap()
    );
    let _ = std::fs::remove_dir_all(&dir);
}
