//! `rattle transmission`: the Welch estimate of the transmissibility under random base motion
//! against the exact linear response, its independence of the thread count, its shards, and
//! its refusals.

use nalgebra::Complex;
use rattle_compare::api::{self, ApiError, TransmissionRequest};
use rattle_compare::output::transmission::{TransmissionRecord, TransmissionRow};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::runs::shard::Shard;
use rattle_compare::scene::AnyScene;
use std::process::Command;

/// A body on a spring and a dashpot to the base, `ω_n = 1` rad/s, `ζ = 0.1`, and a stop at
/// `0.2` m from the frame that the smallest level below never reaches.
const SCENE: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/scenes/base-isolated.json"
);

fn scene() -> AnyScene {
    api::load(SCENE).expect("the scene loads")
}

/// `H₁` of a row, complex.
fn estimate(row: &TransmissionRow) -> Complex<f64> {
    Complex::from_polar(row.h1_magnitude.unwrap(), row.h1_phase.unwrap())
}

/// The linear `H` of a row, complex.
fn linear(row: &TransmissionRow) -> Complex<f64> {
    Complex::from_polar(row.linear_magnitude.unwrap(), row.linear_phase.unwrap())
}

/// The frequencies where `|h(row) − reference(row)| > r`, and the largest
/// `|h − reference|/r` over all.
fn outside(
    rows: &[TransmissionRow],
    h: impl Fn(&TransmissionRow) -> Complex<f64>,
    reference: impl Fn(&TransmissionRow) -> Complex<f64>,
) -> (Vec<f64>, f64) {
    let mut out = Vec::new();
    let mut worst: f64 = 0.0;
    for row in rows {
        let q = (h(row) - reference(row)).norm() / row.h1_radius.unwrap();
        worst = worst.max(q);
        if q > 1.0 {
            out.push(row.omega);
        }
    }
    (out, worst)
}

/// The estimate on the linear scene, its radii at a confidence that holds for every
/// frequency of the band at once: `1 − α/N`, `α = 0.05`, over its `N` frequencies
/// (Bonferroni).
fn linear_estimate() -> TransmissionRecord {
    let scene = scene();
    let mut request = TransmissionRequest::new("random:band=0.2-2.5,rms=0.01,seed=1", 1000.0);
    request.options.seeds = 4;
    // 320 s = 32 time constants 1/(ζω_n) = 10 s: the window's smoothing of the resonance
    // peak (of relative size about (Δω/ζω_n)², Δω = 2π/320 s, below 1 % of |H|) stays small
    // beside the radius, which the segment ends' share of the response (the response to
    // input before a segment, tapered by the window) sets at 1–4 % of |H| here.
    request.options.segment = Some(320.0);
    let frequencies = api::prepare_transmission(&scene, &request)
        .unwrap()
        .plan()
        .settings
        .frequencies;
    request.options.confidence = 1.0 - 0.05 / frequencies as f64;
    let record = api::transmission(&scene, &request).unwrap();
    assert_eq!(record.settings.frequencies, frequencies);
    assert!(record.settings.simultaneous_confidence >= 0.95 - 1e-12);
    record
}

#[test]
fn on_a_linear_scene_h1_is_within_its_radius_of_the_exact_response_everywhere_in_the_band() {
    let record = linear_estimate();
    let level = &record.levels[0];
    assert_eq!(
        level.impacts, 0,
        "the stop is never reached: the scene is linear"
    );
    assert_eq!(level.records, 4);
    assert!(level.rows.len() > 100, "{} frequencies", level.rows.len());
    let (bad, worst) = outside(&level.rows, estimate, linear);
    eprintln!(
        "largest |H1 - H|/r over {} frequencies: {worst:.3} (n = {:.2})",
        level.rows.len(),
        level.effective_averages
    );
    assert!(bad.is_empty(), "outside the radius at {bad:?}");
    // The check can fail: the estimate moved by 3r along itself, …
    let moved = |row: &TransmissionRow| {
        let h = estimate(row);
        h * (1.0 + 3.0 * row.h1_radius.unwrap() / h.norm())
    };
    let (bad, _) = outside(&level.rows, moved, linear);
    assert_eq!(
        bad.len(),
        level.rows.len(),
        "moved by 3r, every point is outside"
    );
    // … or the reference of a structure 2 % stiffer in frequency (ω_n = 1.02).
    let structure = match scene() {
        AnyScene::Structure(form) => form.structure,
        AnyScene::Cells(_) => unreachable!("a structure scene"),
    };
    let shifted = |row: &TransmissionRow| structure.base_response(row.omega / 1.02).unwrap();
    let (bad, _) = outside(&level.rows, estimate, shifted);
    assert!(!bad.is_empty(), "a wrong reference is caught");
    // The reference is the structure's own: H = (1 + 0.2iω)/(1 − ω² + 0.2iω).
    for row in &level.rows {
        let w = row.omega;
        let exact = Complex::new(1.0, 0.2 * w) / Complex::new(1.0 - w * w, 0.2 * w);
        assert!((linear(row) - exact).norm() < 1e-12 * exact.norm());
    }
    assert_eq!(record.linear.natural_frequencies.len(), 1);
    assert!((record.linear.natural_frequencies[0] - 1.0).abs() < 1e-12);
    // |H| = 1 at ω = √2 exactly for a base spring and dashpot.
    let band = &record.linear.attenuation_bands[0];
    assert!((band.from - 2f64.sqrt()).abs() < 1e-9 && band.to.is_none());
}

/// A small estimate: two levels (the higher one reaches the stop), two seeds each.
fn small_request() -> TransmissionRequest {
    let mut request = TransmissionRequest::new("random:band=0.2-2.5,rms=0.01,seed=5", 300.0);
    request.options.seeds = 2;
    request.options.levels = vec![0.01, 0.05];
    request
}

#[test]
fn the_bits_do_not_depend_on_the_thread_count() {
    let scene = scene();
    let request = small_request();
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| api::transmission(&scene, &request).unwrap())
    };
    let (one, two) = (on(1), on(2));
    assert!(one.levels[1].impacts > 0, "the higher level impacts");
    assert_eq!(
        serde_json::to_string(&one).unwrap(),
        serde_json::to_string(&two).unwrap()
    );
}

#[test]
fn shards_merged_equal_the_whole() {
    let scene = scene();
    let prepared = api::prepare_transmission(&scene, &small_request()).unwrap();
    let whole = prepared.run(&Progress::hidden()).unwrap();
    let parts: Vec<_> = (1..=3)
        .rev()
        .map(|index| {
            let part = prepared
                .run_part(Shard { index, count: 3 }, &Progress::hidden())
                .unwrap();
            // Through the part's file form, as `rattle merge` reads it.
            serde_json::from_str(&serde_json::to_string(&part).unwrap()).unwrap()
        })
        .collect();
    let merged = api::merge_transmission(&parts).unwrap();
    assert_eq!(merged, whole);
    assert_eq!(
        serde_json::to_string(&merged).unwrap(),
        serde_json::to_string(&whole).unwrap()
    );
    let missing = api::merge_transmission(&parts[..2])
        .unwrap_err()
        .to_string();
    assert!(missing.contains("need each of 1..=3 once"), "{missing}");
}

#[test]
fn the_command_writes_parts_that_merge_into_the_whole_table() {
    let dir = std::env::temp_dir().join(format!("rattle-transmission-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let rattle = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_rattle"))
            .args(args)
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{args:?}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8(out.stdout).unwrap()
    };
    let common = [
        "transmission",
        SCENE,
        "--signal",
        "random:band=0.2-2.5,rms=0.01,seed=5",
        "--duration",
        "300",
        "--seeds",
        "2",
        "--levels",
        "0.01,0.05",
    ];
    fn with<'a>(common: &[&'a str], extra: &[&'a str]) -> Vec<&'a str> {
        [common, extra].concat()
    }
    rattle(&with(&common, &["--out", "whole.csv"]));
    rattle(&with(&common, &["--shard", "2/2", "--out", "p2.json"]));
    rattle(&with(&common, &["--shard", "1/2", "--out", "p1.json"]));
    rattle(&["merge", "p2.json", "p1.json", "--out", "merged.csv"]);
    let read = |name: &str| std::fs::read_to_string(dir.join(name)).unwrap();
    let whole = read("whole.csv");
    assert_eq!(read("merged.csv"), whole);
    assert!(whole.starts_with(
        "level,omega,h1_magnitude,h1_phase,h1_radius,transmissibility,coherence,\
         linear_magnitude,linear_phase,averages\n"
    ));
    let json = rattle(&with(&common, &["--json"]));
    let document: serde_json::Value = serde_json::from_str(&json).unwrap();
    assert_eq!(document["levels"].as_array().unwrap().len(), 2);
    assert_eq!(
        document["levels"][0]["rows"].as_array().unwrap().len() * 2,
        whole.lines().count() - 1
    );
    // A part must be a .json file; a transmission estimate is not JSON Lines.
    for (extra, expected) in [
        (
            &["--shard", "1/2", "--out", "p.csv"][..],
            "--shard: a part is written to --out F.json",
        ),
        (
            &["--out", "t.jsonl"][..],
            "--out t.jsonl: must be .csv or .json",
        ),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_rattle"))
            .args(with(&common, extra))
            .current_dir(&dir)
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(2), "{extra:?}");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(expected), "{extra:?}: {stderr}");
    }
    assert!(!dir.join("p.csv").exists() && !dir.join("t.jsonl").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// A change to a request.
type Change = dyn Fn(&mut TransmissionRequest);

#[test]
fn bad_input_is_refused_naming_the_option() {
    let scene = scene();
    let refused = |change: &Change| {
        let mut request = small_request();
        change(&mut request);
        match api::prepare_transmission(&scene, &request) {
            Err(ApiError::Argument(message)) => message,
            other => panic!("not refused as an argument: {other:?}"),
        }
    };
    let cases: [(&str, &Change); 12] = [
        ("--duration = -1", &|r| r.duration = -1.0),
        ("--signal tone-burst", &|r| {
            r.signal = "tone-burst:omega=1,cycles=3".into()
        }),
        ("--signal random: rms", &|r| {
            r.signal = "random:band=0.2-2.5,rms=0,seed=1".into()
        }),
        ("--levels[1] = 0", &|r| r.options.levels = vec![0.1, 0.0]),
        ("--seeds = 0", &|r| r.options.seeds = 0),
        ("--overlap = 1", &|r| r.options.overlap = 1.0),
        ("--confidence = 1", &|r| r.options.confidence = 1.0),
        ("--transient = 300", &|r| r.options.transient = Some(300.0)),
        ("--segment = 1000", &|r| r.options.segment = Some(1000.0)),
        ("--segment = 0.5", &|r| r.options.segment = Some(0.5)),
        ("--segment = 2", &|r| r.options.segment = Some(2.0)),
        ("--duration = 3", &|r| r.duration = 3.0),
    ];
    for (expected, change) in cases {
        let message = refused(change);
        assert!(message.starts_with(expected), "{expected}: {message}");
    }
}
