//! A chain's analytic orbit sampled over its cycle (`rattle orbit CHAIN --signature SEQ
//! --trajectory F`), against the event-driven simulator run from one of its samples: the
//! simulator (its own flow, its own contact search) must meet the same impacts, of the same
//! pairs and sides, at the same forcing times, in the same states.

mod common;

use common::rattle;
use rattle_analytic::{sequence_orbits, ImpactSequence};
use rattle_compare::output::trajectory::analytic_rows;
use rattle_compare::scene::analytic::{chain_model, sample_sequence_orbit, SampleKind};
use rattle_compare::scene::simulator::model;
use rattle_compare::scene::Scene;
use rattle_event_driven::{simulate, SimulationOptions, Start};

/// The undamped 2-cell chain of the paper's cell (gap 0.5, e = 0.8), whose sequence
/// `0+ 1- 0- 1+` has viable (unstable) orbits at ω = 3.3 rad/s (`tests/chain.rs`).
const TWO_CELLS: &str = r#"{"name": "two", "unit": {"outer_mass": 2.0, "inner_mass": 1.0, "outer_stiffness": 6.0, "inner_stiffness": 3.0},
    "base": {"amplitude": 1.0}, "stops": {"gap": 0.5, "restitution": 0.8}, "cells": 2}"#;
const OMEGA: f64 = 3.3;
const GAP: f64 = 0.5;

/// The simulator resolves contact times to `1e-12 T`; the orbit's largest Floquet multiplier
/// is 11 (`rattle orbit … --json`), so over the run's under two periods its impact times and
/// states may sit up to ~1e-10 from the closed form, the bound checked. Measured: they agree
/// to 1e-13 (the test passes with that bound too).
const AGREEMENT: f64 = 1e-10;

#[test]
fn the_simulator_meets_the_sampled_chain_orbits_impacts() {
    let scene = Scene::parse(TWO_CELLS, "two.json").expect("a valid scene");
    let analytic = chain_model(&scene).expect("every cell has stops");
    let sequence = ImpactSequence::parse("0+ 1- 0- 1+", 1).expect("a sequence");
    let orbits = sequence_orbits(&analytic, OMEGA, &sequence).expect("the search runs");
    let viable: Vec<_> = orbits.iter().filter(|o| o.viable).collect();
    assert!(!viable.is_empty());
    let period = std::f64::consts::TAU / OMEGA;
    let simulator = model(&scene, OMEGA).expect("a model");
    for orbit in viable {
        let (samples, impacts) = sample_sequence_orbit(&analytic, orbit, 400);
        assert_eq!(impacts.len(), 4);
        assert_eq!(
            samples.len(),
            400 + 2 * 4,
            "uniform samples and two rows per impact"
        );
        // No penetration of either pair anywhere on the sampled cycle.
        for s in &samples {
            for cell in 0..2 {
                let r = s.state[2 * cell + 1] - s.state[2 * cell];
                assert!(r.abs() <= GAP * (1.0 + 1e-9), "cell {cell}: r = {r}");
            }
        }
        // The simulator from the first uniform sample after the first impact, to the end of
        // the next whole period, whose impacts it reports.
        let start = samples
            .iter()
            .find(|s| s.kind == SampleKind::Sample && s.time > impacts[0].time)
            .expect("a sample after the first impact");
        let run = simulate(
            &simulator,
            OMEGA,
            &Start {
                state: start.state.clone(),
                time: start.time,
            },
            &SimulationOptions {
                fixed_periods: Some(2),
                polish: false,
                ..SimulationOptions::default()
            },
        )
        .expect("simulates");
        assert_eq!(run.cycle_impacts.len(), 4, "{:?}", run.cycle_impacts);
        for ours in &impacts {
            let phase = ours.time.rem_euclid(period);
            let theirs = run
                .cycle_impacts
                .iter()
                .find(|i| {
                    let d = (i.phase - phase).rem_euclid(period);
                    d.min(period - d) <= AGREEMENT * period
                })
                .unwrap_or_else(|| panic!("no simulated impact at phase {phase}"));
            assert_eq!((theirs.pair, theirs.side), (ours.pair, ours.side));
            let scale = ours.before.norm();
            assert!(
                (&theirs.state_before - &ours.before).norm() <= AGREEMENT * scale,
                "{} vs {}",
                theirs.state_before,
                ours.before
            );
        }
        // As table rows: one per cell at each time, r of the row's own cell.
        let (rows, impact_rows) =
            analytic_rows(&samples, &impacts, OMEGA, 1.0, &scene.cell_pairs());
        assert_eq!(rows.len(), 2 * samples.len());
        for pair in rows.chunks(2) {
            assert_eq!((pair[0].cell, pair[1].cell), (0, 1));
            assert_eq!(pair[0].t, pair[1].t);
            for row in pair {
                assert_eq!(row.r, Some(row.u_i.unwrap() - row.u_o.unwrap()));
            }
        }
        for (row, impact) in impact_rows.iter().zip(&impacts) {
            let c = 2 * impact.pair;
            assert_eq!(row.pair, impact.pair);
            assert_eq!(row.u_o, Some(impact.before[c]));
            assert_eq!(
                row.relative_velocity_before,
                Some(impact.before[4 + c + 1] - impact.before[4 + c])
            );
        }
    }
}

/// The command writes the chain's cycle with a `cell` column and the impacts with a `pair`
/// column; an `--orbit` out of range is an argument error naming it.
#[test]
fn orbit_writes_a_chains_trajectory_per_cell() {
    let dir = std::env::temp_dir().join(format!("rattle-chain-trajectory-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let scene = dir.join("two.json");
    std::fs::write(&scene, TWO_CELLS).expect("written");
    let (trajectory, impacts) = (dir.join("t.csv"), dir.join("i.csv"));
    let args = |orbit: &str| -> Vec<String> {
        [
            "orbit",
            scene.to_str().unwrap(),
            "--omega",
            "3.3",
            "--signature",
            "0+ 1- 0- 1+",
            "--orbit",
            orbit,
            "--trajectory",
            trajectory.to_str().unwrap(),
            "--samples-per-period",
            "50",
            "--impacts",
            impacts.to_str().unwrap(),
        ]
        .iter()
        .map(|s| s.to_string())
        .collect()
    };
    let a = args("0");
    let out = rattle(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&trajectory).expect("the trajectory");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,kind,cell,base,u_o,u_i,v_o,v_i,r"));
    let cells: Vec<&str> = lines.map(|l| l.split(',').nth(2).unwrap()).collect();
    assert_eq!(cells.len(), 2 * (50 + 2 * 4));
    assert!(cells.chunks(2).all(|c| c == ["0", "1"]));
    let text = std::fs::read_to_string(&impacts).expect("the impacts");
    assert!(text.starts_with("t,pair,side,relative_velocity_before,"));
    assert_eq!(text.lines().count(), 1 + 4);
    let a = args("99");
    let out = rattle(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("--orbit = 99"));
}

/// `rattle simulate CHAIN --trajectory` writes every cell (the unit's columns and a `cell`
/// column, one row per cell at each time), each row's `r` its own cell's `u_i − u_o` (the
/// simulator's pair functional, equal to the difference up to rounding), within its stops; and
/// the impacts name their pair, with that pair's cell at its stop.
#[test]
fn simulate_writes_a_chains_trajectory_per_cell() {
    let dir = std::env::temp_dir().join(format!("rattle-chain-simulated-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let (trajectory, impacts) = (dir.join("t.csv"), dir.join("i.csv"));
    let out = rattle(&[
        "simulate",
        "data/scenes/paper-chain-5.json",
        "--omega",
        "2",
        "--trajectory",
        trajectory.to_str().unwrap(),
        "--samples-per-period",
        "40",
        "--impacts",
        impacts.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let number = |s: &str| s.parse::<f64>().expect("a number");
    let text = std::fs::read_to_string(&trajectory).expect("the trajectory");
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,kind,cell,base,u_o,u_i,v_o,v_i,r"));
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert!(rows.len() >= 5 * 40);
    for (k, row) in rows.iter().enumerate() {
        assert_eq!(number(row[2]) as usize, k % 5, "one row per cell, in order");
        let (u_o, u_i, r) = (number(row[4]), number(row[5]), number(row[8]));
        assert!(
            (r - (u_i - u_o)).abs() <= 1e-12 * (1.0 + u_o.abs() + u_i.abs()),
            "{row:?}"
        );
        assert!(r.abs() <= GAP * (1.0 + 1e-9), "{row:?}");
    }
    let text = std::fs::read_to_string(&impacts).expect("the impacts");
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("t,pair,side,relative_velocity_before,u_o,u_i,v_o_before,v_i_before")
    );
    let mut pairs = std::collections::BTreeSet::new();
    for line in lines {
        let row: Vec<&str> = line.split(',').collect();
        pairs.insert(row[1].to_owned());
        let side = if row[2] == "1" { 1.0 } else { -1.0 };
        let r = number(row[5]) - number(row[4]);
        assert!((r - side * GAP).abs() <= 1e-9, "{row:?}");
    }
    assert!(pairs.len() > 1, "impacts of several pairs: {pairs:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
