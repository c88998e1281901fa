//! Basins over named coordinates: a structure's grid (the impact damper, where the motion
//! without impacts and the two-impact motion coexist), deterministic whatever the thread
//! count, its parts merged into the whole file; bad coordinate names refused by name; on the
//! unit, the named default plane is the default plane byte for byte.

use rattle_compare::api;
use rattle_compare::output::Format;
use rattle_compare::runs::basins::{
    basin_options, destination_of, Attractor, BasinPlane, BasinsError,
};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::scene::AnyScene;
use rattle_event_driven::Start;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The repository's root.
const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// The gallery's impact damper: a forced primary, a free body of a tenth of its mass in a
/// clearance of ±0.8.
const DAMPER: &str = "data/scenes/impact-damper.json";

/// Below the primary's resonance, where the free body at rest far from the walls stays
/// untouched and one released near a wall settles on the two-impact motion.
const DAMPER_OMEGA: &str = "0.7";

/// The damper's plane: the primary's displacement over ±0.2, the free body's over ±0.55
/// (inside the clearance ±0.8 for every start).
const DAMPER_PLANE: [&str; 12] = [
    "--x",
    "u:primary",
    "--x-min",
    "-0.2",
    "--x-max",
    "0.2",
    "--y",
    "u:ball",
    "--y-min",
    "-0.55",
    "--y-max",
    "0.55",
];

fn damper() -> AnyScene {
    api::load(Path::new(ROOT).join(DAMPER)).unwrap()
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rattle-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn rattle(args: &[&str], threads: Option<&str>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_rattle"));
    command.args(args).current_dir(ROOT);
    if let Some(n) = threads {
        command.env("RAYON_NUM_THREADS", n);
    }
    command.output().expect("rattle runs")
}

/// `rattle basins` on the damper's plane with `points` per side into `out`, after `extra`.
fn damper_basins(out: &Path, points: &str, extra: &[&str], threads: Option<&str>) -> String {
    let mut args = vec![
        "basins",
        DAMPER,
        "--omega",
        DAMPER_OMEGA,
        "--points",
        points,
    ];
    args.extend(DAMPER_PLANE);
    args.extend(extra);
    args.extend(["--out", out.to_str().unwrap()]);
    let o = rattle(&args, threads);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(out).unwrap()
}

/// Starts with the free body far from the primary's walls stay without impacts (one
/// attractor, the free body floating: a family); those near a wall reach the two-impact
/// motion. The columns name the two coordinates.
#[test]
fn the_damper_has_the_quiet_and_the_impacting_basins() {
    let scene = damper();
    let plane = BasinPlane::new(
        &scene,
        ("u:primary", (-0.2, 0.2)),
        ("u:ball", (-0.55, 0.55)),
        6,
    )
    .unwrap();
    let mut table = Vec::new();
    let b = api::plane_basins(
        &scene,
        0.7,
        &plane,
        &basin_options(),
        None,
        (Format::Csv, &mut table),
        &Progress::hidden(),
    )
    .unwrap();
    let text = String::from_utf8(table).unwrap();
    assert!(
        text.starts_with(
            "primary_start,ball_start,attractor,attractor_words,outer_amplitude,periods_run,\
             body_amplitudes\n"
        ),
        "{text}"
    );
    let quiet = b
        .attractors
        .iter()
        .position(|a| {
            matches!(a, Attractor::Motion { signatures, amplitudes, .. }
                if signatures == &[Some(String::new())] && amplitudes[1].is_none())
        })
        .unwrap_or_else(|| panic!("no attractor without impacts: {:?}", b.attractors));
    let impacting = b
        .attractors
        .iter()
        .position(|a| {
            matches!(a, Attractor::Motion { signatures, amplitudes, period: 1 }
                if signatures == &[Some("+-".to_owned())] && amplitudes.iter().all(Option::is_some))
        })
        .unwrap_or_else(|| panic!("no two-impact attractor: {:?}", b.attractors));
    let at = |ball: f64| {
        b.cells
            .iter()
            .filter(|c| (c.inner - ball).abs() < 1e-9)
            .map(|c| c.attractor)
            .collect::<Vec<_>>()
    };
    // The free body at ±0.11, 0.69 or more from either wall: no start touches it.
    assert!(at(0.11).iter().all(|&a| a == quiet), "{:?}", at(0.11));
    assert!(at(-0.11).iter().all(|&a| a == quiet), "{:?}", at(-0.11));
    // At ±0.55, 0.25 from a wall: starts get the impacting motion.
    assert!(at(0.55).contains(&impacting), "{:?}", at(0.55));
    assert!(at(-0.55).contains(&impacting), "{:?}", at(-0.55));
    assert_eq!(b.counts.iter().sum::<usize>(), 36);
}

#[test]
fn a_structure_grid_on_one_thread_and_on_all_is_one_file() {
    let dir = scratch("basins-structure-threads");
    let one = damper_basins(&dir.join("one.csv"), "5", &[], Some("1"));
    let all = damper_basins(&dir.join("all.csv"), "5", &[], None);
    assert_eq!(one.lines().count(), 1 + 5 * 5);
    assert_eq!(one, all);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A structure's parts, merged in any order, are the whole file byte for byte, CSV and JSON.
#[test]
fn a_structures_merged_parts_are_the_whole_file() {
    let dir = scratch("basins-structure-parts");
    for ext in ["csv", "json"] {
        let whole = damper_basins(&dir.join(format!("whole.{ext}")), "5", &[], None);
        let parts: Vec<String> = (1..=3)
            .rev()
            .map(|k| {
                let path = dir.join(format!("part-{k}.{ext}"));
                let shard = format!("{k}/3");
                damper_basins(&path, "5", &["--shard", &shard], None);
                path.to_str().unwrap().to_owned()
            })
            .collect();
        let merged = dir.join(format!("merged.{ext}"));
        let mut args = vec!["merge"];
        args.extend(parts.iter().map(String::as_str));
        args.extend(["--out", merged.to_str().unwrap()]);
        let o = rattle(&args, None);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        assert_eq!(std::fs::read_to_string(&merged).unwrap(), whole, "{ext}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A coordinate the scene does not have is refused naming the flag and every coordinate; so
/// are a structure without `--x`, the unit's default-plane flags on a structure, and both axes
/// on one coordinate.
#[test]
fn bad_axes_are_refused_by_name() {
    let dir = scratch("basins-structure-refusals");
    let out = dir.join("never.csv");
    let out = out.to_str().unwrap();
    let cases: [(&[&str], &str); 5] = [
        (
            &["--x", "u:nope", "--y", "u:ball"],
            "--x = \"u:nope\": the scene has no such coordinate; the coordinates are \
             u:primary, u:ball, v:primary, v:ball",
        ),
        (
            &["--x", "u:primary", "--y", "w:ball"],
            "--y = \"w:ball\": the scene has no such coordinate",
        ),
        (
            &["--y", "u:ball"],
            "--x is required on a chain or a structure: one of u:primary, u:ball",
        ),
        (
            &["--outer-min", "-1"],
            "--outer-min/--outer-max/--inner-min/--inner-max set the unit's default plane",
        ),
        (
            &["--x", "v:ball", "--y", "v:ball"],
            "--x and --y both name v:ball",
        ),
    ];
    for (axes, message) in cases {
        let mut args = vec!["basins", DAMPER, "--omega", "0.7", "--points", "2"];
        args.extend(axes);
        args.extend(["--out", out]);
        let o = rattle(&args, None);
        let stderr = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {stderr}");
        assert!(stderr.contains(message), "{args:?}: {stderr}");
    }
    assert!(!Path::new(out).exists());
    // The unit's coordinates, listed for a bad name on the unit.
    let o = rattle(
        &["basins", "--omega", "1.9", "--x", "u:o", "--out", out],
        None,
    );
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert!(
        stderr.contains("the coordinates are u:outer, u:inner, v:outer, v:inner"),
        "{stderr}"
    );
    // And the API refuses them as values, naming the flag.
    let e =
        BasinPlane::new(&damper(), ("u:primary", (0.0, 1.0)), ("v:x", (0.0, 1.0)), 2).unwrap_err();
    assert!(
        matches!(e, BasinsError::Coordinate { flag: "--y", .. }),
        "{e}"
    );
    let e = BasinPlane::new(
        &damper(),
        ("u:primary", (1.0, 0.0)),
        ("v:ball", (0.0, 1.0)),
        2,
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("--x-min = 1, --x-max = 0"), "{e}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A start with the free body beyond the clearance is marked, not run.
#[test]
fn a_start_outside_the_clearance_is_not_run() {
    let scene = damper();
    let mut start = Start::rest(2);
    start.state[1] = 0.9;
    let (attractor, amplitude, periods) = destination_of(&scene, 0.7, &start, &basin_options());
    assert_eq!(attractor, Attractor::OutsideClearance);
    assert!(amplitude.is_nan());
    assert_eq!(periods, 0);
}

/// On the unit, `--x u:outer --y u:inner` is the default plane: the same file byte for byte,
/// CSV and JSON, whole and sharded; velocities name their own columns.
#[test]
fn the_units_named_default_plane_is_the_default_plane() {
    let dir = scratch("basins-unit-named");
    let run = |out: &Path, extra: &[&str]| {
        let mut args = vec!["basins", "--omega", "1.9", "--points", "4"];
        args.extend(extra);
        args.extend(["--out", out.to_str().unwrap()]);
        let o = rattle(&args, None);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        std::fs::read_to_string(out).unwrap()
    };
    let legacy = [
        "--outer-min",
        "-1",
        "--outer-max",
        "1.5",
        "--inner-min",
        "-0.5",
    ];
    let named = [
        "--x", "u:outer", "--x-min", "-1", "--x-max", "1.5", "--y", "u:inner", "--y-min", "-0.5",
    ];
    for ext in ["csv", "json"] {
        for shard in [&[][..], &["--shard", "2/3"][..]] {
            let a = run(
                &dir.join(format!("legacy.{ext}")),
                &[&legacy[..], shard].concat(),
            );
            let b = run(
                &dir.join(format!("named.{ext}")),
                &[&named[..], shard].concat(),
            );
            assert_eq!(a, b, "{ext} {shard:?}");
        }
    }
    let v = run(
        &dir.join("velocity.csv"),
        &["--x", "v:outer", "--y", "u:inner"],
    );
    assert!(
        v.starts_with("outer_velocity_start,inner_start,attractor,"),
        "{v}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
