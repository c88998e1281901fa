//! `rattle respond` and `api::respond` against exact answers: rest under a zero record, the
//! periodic simulator's steady state reached through a finely sampled record of its harmonic
//! (within the interpolation's derived bound), the closed form of a linear unit under a tone
//! burst, the random generator's determinism, RMS and band, a PSD file's law on the lines,
//! `--out` never leaving a partial table under its name, `--json` with `--out`, and every
//! refusal by name.

mod common;

use common::{json, rattle, scene_file};
use nalgebra::{DMatrix, SymmetricEigen};
use rattle_compare::api::{self, ResponseRequest};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::scene::signal::random::{record, RandomSpec};
use rattle_compare::scene::signal::{SignalDescription, SignalSpec};
use rattle_event_driven::SimulationOptions;
use serde_json::Value;
use std::f64::consts::TAU;
use std::path::PathBuf;

fn file(name: &str, text: &str) -> String {
    scene_file("respond", name, text).display().to_string()
}

fn numbers(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

#[test]
fn a_record_of_zeros_leaves_the_unit_at_rest() {
    let path = file("zeros.csv", "t,u_g\n0,0\n0.5,0\n2,0\n7.5,0\n");
    let doc = json(&[
        "respond",
        "data/scenes/paper-damped.json",
        "--signal",
        &path,
        "--duration",
        "20",
        "--at",
        "0,3.7,20",
        "--json",
    ]);
    assert_eq!(doc["impacts"].as_array().unwrap().len(), 0);
    assert_eq!(doc["signal"]["kind"], "file");
    assert_eq!(doc["signal"]["samples"], 4);
    for state in doc["at"].as_array().unwrap() {
        assert!(numbers(&state["displacements"]).iter().all(|&u| u == 0.0));
        assert!(numbers(&state["velocities"]).iter().all(|&v| v == 0.0));
    }
    let summary = &doc["summary"];
    for key in ["rms", "peak"] {
        assert_eq!(summary[key]["outer"], 0.0);
        assert_eq!(summary[key]["inner"], 0.0);
    }
    assert_eq!(summary["work"], 0.0);
    assert_eq!(summary["energy_dissipated"], 0.0);
    // The sampled table: every cell zero but the times.
    let out = std::env::temp_dir().join(format!("rattle-respond-zeros-{}.csv", std::process::id()));
    let run = rattle(&[
        "respond",
        "data/scenes/paper-damped.json",
        "--signal",
        &path,
        "--duration",
        "20",
        "--out",
        out.to_str().unwrap(),
        "--samples",
        "40",
    ]);
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(&out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some("t,u_g,u:outer,u:inner,v:outer,v:inner"));
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), 41);
    for row in rows {
        assert!(
            row.split(',')
                .skip(1)
                .all(|c| c.parse::<f64>().unwrap() == 0.0),
            "{row}"
        );
    }
    std::fs::remove_file(out).ok();
}

/// The damped paper unit: `M = diag(2, 1)`, `K = [[9, −3], [−3, 3]]`, `C = K/60` (its dashpots
/// are in proportion to its springs, checked here), driven through `k_o = 6`, `c_o = 0.1`.
/// With mass-normalised modes `φ_r`, `a_r = ζ_r ω_r`, `b_r = ω_r √(1 − ζ_r²)`, the response
/// of coordinate `j` to an impulse on the outer mass is
/// `g_j = Σ_r φ_rj φ_r0 e^{−a_r t} sin(b_r t)/b_r`. The record's interpolation moves the
/// base by `δs`, `|δs| ≤ E = h²ω²/8` (`u_g = 1`), and the force by `k_o δs + c_o δṡ`; after
/// an integration by parts of the dashpot's share (`δs = 0` at `t = 0`, `g(0) = 0`),
/// `|Δu_j| ≤ E Σ_r |φ_rj φ_r0| (k_o/(a_r b_r) + c_o (1 + a_r/b_r)/a_r)` and
/// `|Δu̇_j| ≤ E Σ_r |φ_rj φ_r0| (k_o (1 + a_r/b_r)/a_r + c_o (1 + (2a_r + |a_r²/b_r − b_r|)/a_r))`
/// (`∫|g_r| ≤ 1/(a b)`, `∫|ġ_r| ≤ (1 + a/b)/a`, `ġ_r(0) = 1`, `∫|g̈_r| ≤ (2a + |a²/b − b|)/a`).
/// At `ω = 0.8` the steady state has no impact (the simulator's), so the bound holds once
/// the transient from rest (which may impact) has decayed: `e^{−a_1 t} < 10⁻⁸` after 200
/// periods.
fn interpolation_bounds(per_period: u32, omega: f64) -> [[f64; 2]; 2] {
    let m: [f64; 2] = [2.0, 1.0];
    let k = DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]);
    let (k_o, c_o) = (6.0, 0.1);
    let scaled = DMatrix::from_fn(2, 2, |i, j| k[(i, j)] / (m[i] * m[j]).sqrt());
    let eigen = SymmetricEigen::new(scaled);
    let h = TAU / omega / f64::from(per_period);
    let e = h * h * omega * omega / 8.0;
    let mut bounds = [[0.0; 2]; 2];
    for r in 0..2 {
        let w = eigen.eigenvalues[r].sqrt();
        let zeta: f64 = w / 120.0;
        let (a, b) = (zeta * w, w * (1.0 - zeta * zeta).sqrt());
        let phi: Vec<f64> = (0..2)
            .map(|j| eigen.eigenvectors[(j, r)] / m[j].sqrt())
            .collect();
        for j in 0..2 {
            let p = (phi[j] * phi[0]).abs();
            bounds[0][j] += e * p * (k_o / (a * b) + c_o * (1.0 + a / b) / a);
            bounds[1][j] += e
                * p
                * (k_o * (1.0 + a / b) / a + c_o * (1.0 + (2.0 * a + (a * a / b - b).abs()) / a));
        }
    }
    bounds
}

#[test]
fn a_sampled_harmonic_reaches_the_periodic_steady_state() {
    let scene = api::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/paper-damped.json"
    ))
    .unwrap();
    let omega = 0.8;
    let structure = match &scene {
        rattle_compare::scene::AnyScene::Cells(s) => {
            s.structure_scene(s.base.clone()).structure().unwrap()
        }
        _ => unreachable!(),
    };
    let damping = structure.damping.clone().unwrap();
    assert!((damping - &structure.stiffness / 60.0).abs().max() < 1e-15);
    let simulation = api::simulate(&scene, omega, &SimulationOptions::default()).unwrap();
    let steady = &simulation.point().steady;
    assert_eq!(steady.impacts_per_period, 0.0);
    let orbit = steady.orbit.as_ref().expect("a polished cycle");
    let period = TAU / omega;
    let periods = 200;
    let mut errors = Vec::new();
    for per_period in [1000u32, 2000] {
        let n = periods * per_period;
        let mut text = String::from("t,u_g\n");
        for j in 0..=n {
            let t = period * f64::from(j) / f64::from(per_period);
            text += &format!("{t},{}\n", (omega * t).cos());
        }
        let path = file(&format!("cosine-{per_period}.csv"), &text);
        let at: Vec<f64> = (periods - 3..periods)
            .map(|k| f64::from(k) * period + orbit.phase)
            .collect();
        let request = ResponseRequest {
            signal: path,
            duration: f64::from(periods) * period,
            at: at.clone(),
            on: None,
        };
        let record = api::respond(&scene, &request).unwrap();
        let bounds = interpolation_bounds(per_period, omega);
        let mut worst: f64 = 0.0;
        #[allow(clippy::needless_range_loop)] // j indexes four lists alike
        for state in &record.at {
            for j in 0..2 {
                let du = (state.displacements[j] - orbit.state[j]).abs();
                let dv = (state.velocities[j] - orbit.state[2 + j]).abs();
                assert!(
                    du <= bounds[0][j],
                    "{per_period}: |Δu_{j}| {du:e} > {:e}",
                    bounds[0][j]
                );
                assert!(
                    dv <= bounds[1][j],
                    "{per_period}: |Δv_{j}| {dv:e} > {:e}",
                    bounds[1][j]
                );
                worst = worst.max(du);
            }
        }
        println!(
            "{per_period} samples a period: |Δu| {worst:e} (bounds {:e}, {:e})",
            bounds[0][0], bounds[0][1]
        );
        errors.push(worst);
    }
    // Second order: halving the step quarters the error.
    let ratio = errors[0] / errors[1];
    println!("ratio {ratio}");
    assert!((3.5..4.5).contains(&ratio), "ratio {ratio}");
}

/// The undamped linear unit (`paper-linear`: no stops, no dashpots) under a tone burst of
/// the base: `q̈_r + ω_r² q_r = φ_r0 k_o s(t)` for each mass-normalised mode, `s` the burst's
/// three sinusoids `S_i sin ν_i t` on `[0, T_b]`, each from rest
/// `q = φ_r0 k_o S (sin νt − (ν/ω_r) sin ω_r t)/(ω_r² − ν²)`, free after `T_b`.
#[test]
fn a_tone_burst_on_the_linear_unit_is_its_closed_form() {
    let (omega, cycles, amplitude) = (1.0, 4.0, 0.3);
    let burst_end = TAU * cycles / omega;
    let times: Vec<f64> = (0..=30).map(|j| 1.7 * f64::from(j)).collect();
    let at = times
        .iter()
        .map(|t| t.to_string())
        .collect::<Vec<_>>()
        .join(",");
    let doc = json(&[
        "respond",
        "data/scenes/paper-linear.json",
        "--signal",
        &format!("tone-burst:omega={omega},cycles={cycles},amplitude={amplitude}"),
        "--duration",
        "51",
        "--at",
        &at,
        "--json",
    ]);
    assert_eq!(doc["signal"]["kind"], "tone-burst");
    let m: [f64; 2] = [2.0, 1.0];
    let k_o = 6.0;
    let k = DMatrix::from_row_slice(2, 2, &[9.0, -3.0, -3.0, 3.0]);
    let eigen = SymmetricEigen::new(DMatrix::from_fn(2, 2, |i, j| {
        k[(i, j)] / (m[i] * m[j]).sqrt()
    }));
    let sines = [
        (omega, 0.5 * amplitude),
        (omega * (1.0 + 1.0 / cycles), -0.25 * amplitude),
        (omega * (1.0 - 1.0 / cycles), -0.25 * amplitude),
    ];
    // One mode's (q, q̇) at t ≤ T_b.
    let forced = |w: f64, p0: f64, t: f64| {
        sines.iter().fold((0.0, 0.0), |(q, v), &(nu, s)| {
            let g = p0 * k_o * s / (w * w - nu * nu);
            (
                q + g * ((nu * t).sin() - nu / w * (w * t).sin()),
                v + g * nu * ((nu * t).cos() - (w * t).cos()),
            )
        })
    };
    let exact = |t: f64| {
        let mut u = [0.0; 2];
        for r in 0..2 {
            let w = eigen.eigenvalues[r].sqrt();
            let phi: Vec<f64> = (0..2)
                .map(|j| eigen.eigenvectors[(j, r)] / m[j].sqrt())
                .collect();
            let q = if t <= burst_end {
                forced(w, phi[0], t).0
            } else {
                let (qb, vb) = forced(w, phi[0], burst_end);
                let s = t - burst_end;
                qb * (w * s).cos() + vb / w * (w * s).sin()
            };
            for j in 0..2 {
                u[j] += phi[j] * q;
            }
        }
        u
    };
    let mut scale: f64 = 0.0;
    let mut worst: f64 = 0.0;
    for (state, &t) in doc["at"].as_array().unwrap().iter().zip(&times) {
        let u = numbers(&state["displacements"]);
        let e = exact(t);
        for j in 0..2 {
            scale = scale.max(e[j].abs());
            worst = worst.max((u[j] - e[j]).abs());
        }
    }
    println!("tone burst: worst {worst:e} of {scale:e}");
    assert!(worst <= 1e-10 * scale, "{worst:e} of {scale:e}");
}

fn random_document(seed: u64, threads: &str) -> String {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args([
            "respond",
            "data/scenes/paper-damped.json",
            "--signal",
            &format!("random:band=1-3,rms=0.2,seed={seed}"),
            "--duration",
            "300",
            "--at",
            "50,300",
            "--json",
        ])
        .env("RAYON_NUM_THREADS", threads)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout).unwrap()
}

#[test]
fn the_random_signal_is_deterministic_with_its_rms_and_band() {
    // Same seed, same bits, on one thread or two; another seed, another motion.
    let one = random_document(11, "1");
    assert_eq!(one, random_document(11, "2"));
    assert_ne!(one, random_document(12, "1"));
    let doc: Value = serde_json::from_str(&one).unwrap();
    assert_eq!(doc["signal"]["kind"], "random");
    assert_eq!(doc["signal"]["solved_as"], "record");
    // The record: a power-of-two FFT of the lines in the band, interpolated.
    let (lo, hi, rms, duration) = (1.0, 3.0, 0.2, 2000.0);
    let spec = RandomSpec {
        band: [lo, hi],
        rms,
        seed: 5,
        psd: None,
    };
    let lines = spec.lines(duration).unwrap();
    assert!(lines.iter().all(|s| (lo..=hi).contains(&s.frequency)));
    let k_lo = (lo * duration / TAU).ceil() as usize;
    let k_hi = (hi * duration / TAU).floor() as usize;
    assert_eq!(lines.len(), k_hi - k_lo + 1);
    let built = SignalSpec::parse("random:band=1-3,rms=0.2,seed=5")
        .unwrap()
        .build(duration, 1.0)
        .unwrap();
    let SignalDescription::Random(d) = &built.description else {
        panic!()
    };
    let n = d.samples - 1;
    let values = record(&lines, duration, n);
    // The record's nodes are the engine signal's values there.
    for j in (0..=n).step_by(997) {
        let t = if j == n {
            duration
        } else {
            duration * j as f64 / n as f64
        };
        assert_eq!(built.signal.value_and_rate(t).0, values[j], "node {j}");
    }
    // Over the whole record the mean square is rms² (Parseval: the lines are orthogonal).
    let mean_square = values[..n].iter().map(|v| v * v).sum::<f64>() / n as f64;
    let whole = (mean_square.sqrt() - rms).abs() / rms;
    println!("whole record: RMS off by {whole:e}");
    assert!(whole <= 1e-12, "{whole:e}");
    // Over each quarter (W = 500 s) it fluctuates as a Gaussian process's would: relative
    // standard deviation of the mean square √(2π/(B W)) = 0.079 for B = 2 rad/s; within
    // four of them.
    let sigma = (TAU / ((hi - lo) * duration / 4.0)).sqrt();
    for q in 0..4 {
        let part = &values[q * n / 4..(q + 1) * n / 4];
        let ms = part.iter().map(|v| v * v).sum::<f64>() / part.len() as f64;
        let off = (ms / (rms * rms) - 1.0).abs();
        println!("quarter {q}: mean square off by {off:.4} (σ {sigma:.4})");
        assert!(off <= 4.0 * sigma, "quarter {q}: {off}");
    }
    // The spectrum: nothing outside the band's bins but rounding (a direct DFT of the record
    // at bins below, inside and above the band).
    let bin = |k: usize| bin_amplitude(&values[..n], k);
    let inside = bin((k_lo + k_hi) / 2);
    let line = lines[(k_lo + k_hi) / 2 - k_lo];
    assert!((inside - line.cos.hypot(line.sin)).abs() < 1e-9);
    for k in [1, k_lo / 2, k_lo - 1, k_hi + 1, 2 * k_hi, 3 * k_hi + 7] {
        let leak = bin(k);
        assert!(leak < 1e-12 * rms, "bin {k}: {leak:e}");
    }
}

fn refusal(args: &[&str]) -> String {
    let out = rattle(args);
    assert_eq!(
        out.status.code(),
        Some(2),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stdout)
    );
    String::from_utf8_lossy(&out.stderr).into_owned()
}

#[test]
fn bad_input_is_refused_by_name() {
    let unit = "data/scenes/paper-damped.json";
    let run = |signal: &str, extra: &[&str]| {
        let mut args = vec!["respond", unit, "--signal", signal, "--duration", "10"];
        args.extend_from_slice(extra);
        refusal(&args)
    };
    let cases: Vec<(String, &[&str], &str)> = vec![
        (
            file("decreasing.csv", "t,u_g\n0,0\n1,0.1\n0.5,0\n"),
            &[],
            "t on line 4",
        ),
        (
            file("repeated.csv", "t,u_g\n0,0\n1,0.1\n1,0\n"),
            &[],
            "t on line 4",
        ),
        (
            file("late.csv", "t,u_g\n0.5,0\n1,0.1\n"),
            &[],
            "t on line 2",
        ),
        (file("nan.csv", "t,u_g\n0,0\n1,nan\n"), &[], "u_g on line 3"),
        (file("inf.csv", "t,u_g\n0,0\ninf,1\n"), &[], "t on line 3"),
        (file("missing.csv", "t\n0\n1\n"), &[], "columns"),
        (file("extra.csv", "t,u_g,x\n0,0,0\n"), &[], "columns"),
        (file("ragged.csv", "t,u_g\n0,0\n1,0,3\n"), &[], "columns"),
        (file("force.csv", "t,F\n0,0\n1,1\n"), &[], "--on"),
        (
            file("force2.csv", "t,F\n0,0\n1,1\n"),
            &["--on", "middle"],
            "--on = middle",
        ),
        (
            file("base.csv", "t,u_g\n0,0\n1,1\n"),
            &["--on", "outer"],
            "--on",
        ),
        ("random:band=3-1,rms=0.1,seed=1".into(), &[], "band"),
        ("random:band=2-2,rms=0.1,seed=1".into(), &[], "band"),
        ("random:band=1-3,rms=0,seed=1".into(), &[], "rms"),
        ("random:band=1-3,rms=-1,seed=1".into(), &[], "rms"),
        ("tone-burst:omega=1,cycles=0.5".into(), &[], "cycles"),
        ("sweep:from=1,to=2,rate=0".into(), &[], "rate"),
        ("sweep:from=1,to=2,rate=-1".into(), &[], "rate"),
        ("sweep:from=1,to=1,rate=0.1".into(), &[], "to"),
        (
            "tone-burst:omega=1,cycles=3".into(),
            &["--on", "outer"],
            "--on",
        ),
        (
            "tone-burst:omega=1,cycles=3".into(),
            &["--at", "1,11"],
            "--at[1]",
        ),
        (
            "tone-burst:omega=1,cycles=3".into(),
            &["--at", "-1"],
            "--at[0]",
        ),
    ];
    for (signal, extra, field) in &cases {
        let message = run(signal, extra);
        println!("{message}");
        assert!(message.contains(field), "{signal} {extra:?}: {message}");
    }
    // The duration: finite, > 0, at most 1e7 periods of the fastest oscillation (the unit's
    // ω₂ = √6 rad/s: 2.6e7 s).
    for duration in ["0", "-1", "inf", "3e7"] {
        let message = refusal(&[
            "respond",
            unit,
            "--signal",
            "tone-burst:omega=1,cycles=3",
            "--duration",
            duration,
        ]);
        assert!(message.contains("--duration"), "{duration}: {message}");
    }
    // The API names the same fields.
    let scene = api::load(PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/paper-damped.json"
    )))
    .unwrap();
    let request = ResponseRequest {
        signal: "random:band=1-3,rms=0,seed=1".into(),
        duration: 10.0,
        at: Vec::new(),
        on: None,
    };
    let e = api::prepare_response(&scene, &request)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rms"), "{e}");
    let prepared = api::prepare_response(
        &scene,
        &ResponseRequest {
            signal: "tone-burst:omega=1,cycles=3".into(),
            ..request
        },
    )
    .unwrap();
    let e = prepared
        .run(Some(0), &Progress::hidden(), &mut |_| Ok(()))
        .unwrap_err()
        .to_string();
    assert!(e.contains("--samples"), "{e}");
}

/// The lines of `random:band=1-3,rms=0.2,seed=9` over 200 s (64 lines, `k = 32..=95`), flat
/// or shaped by the PSD file `psd`.
fn shaped_lines(psd: Option<&str>) -> Vec<rattle_event_driven::Sinusoid> {
    RandomSpec {
        band: [1.0, 3.0],
        rms: 0.2,
        seed: 9,
        psd: psd.map(PathBuf::from),
    }
    .lines(200.0)
    .unwrap()
}

/// `Σ a_k²/2`, the multisine's mean square over the run.
fn mean_square(lines: &[rattle_event_driven::Sinusoid]) -> f64 {
    lines
        .iter()
        .map(|s| (s.cos * s.cos + s.sin * s.sin) / 2.0)
        .sum()
}

#[test]
fn a_psd_file_shapes_the_random_lines_by_its_law() {
    let flat = shaped_lines(None);
    assert_eq!(flat.len(), 64);
    // PSD ∝ ω², a row at every line (the interpolation is then the row's value exactly): the
    // same phases (the generator draws one point per line whatever its amplitude), and each
    // amplitude the flat one times `ω_k √(n / Σ ω_j²)`, so that the mean square stays rms².
    let rows: String = flat
        .iter()
        .map(|s| format!("{},{}\n", s.frequency, s.frequency * s.frequency))
        .collect();
    let squared = file("psd-squared.csv", &format!("omega,psd\n{rows}"));
    let shaped = shaped_lines(Some(&squared));
    let norm = (flat.len() as f64 / flat.iter().map(|s| s.frequency.powi(2)).sum::<f64>()).sqrt();
    for (f, s) in flat.iter().zip(&shaped) {
        assert_eq!(f.frequency, s.frequency);
        let gain = f.frequency * norm;
        let amplitude = s.cos.hypot(s.sin);
        assert!(
            (s.cos - gain * f.cos).abs() <= 1e-14 * amplitude,
            "{f:?} {s:?}"
        );
        assert!(
            (s.sin - gain * f.sin).abs() <= 1e-14 * amplitude,
            "{f:?} {s:?}"
        );
    }
    for lines in [&flat, &shaped] {
        assert!(
            (mean_square(lines) - 0.04).abs() <= 1e-15,
            "{}",
            mean_square(lines)
        );
    }
    // A PSD zero over the upper half of the band (between lines 63 and 64, linear between its
    // rows): no line there, exactly, and the lower half's amplitudes √2 times the flat ones.
    let spacing = TAU / 200.0;
    let half = file(
        "psd-half.csv",
        &format!(
            "omega,psd\n0,1\n{},1\n{},0\n10,0\n",
            63.25 * spacing,
            63.75 * spacing
        ),
    );
    let halved = shaped_lines(Some(&half));
    for (f, s) in flat.iter().zip(&halved) {
        let k = (f.frequency / spacing).round();
        if k >= 64.0 {
            assert!(s.cos == 0.0 && s.sin == 0.0, "line {k}: {s:?}");
        } else {
            let amplitude = s.cos.hypot(s.sin);
            let gain = std::f64::consts::SQRT_2;
            assert!(
                (s.cos - gain * f.cos).abs() <= 1e-14 * amplitude,
                "line {k}"
            );
            assert!(
                (s.sin - gain * f.sin).abs() <= 1e-14 * amplitude,
                "line {k}"
            );
        }
    }
    // Through the command: the record's spectrum has nothing at the upper half's bins.
    let doc = json(&[
        "respond",
        "data/scenes/paper-damped.json",
        "--signal",
        &format!("random:band=1-3,rms=0.2,seed=9,psd={half}"),
        "--duration",
        "200",
        "--json",
    ]);
    assert_eq!(doc["signal"]["psd"], half.as_str());
    assert_eq!(doc["signal"]["lines"], 64);
    assert_eq!(doc["signal"]["solved_as"], "sinusoids");
    let n = 1024;
    let values = record(&halved, 200.0, n);
    let bin = |k: usize| bin_amplitude(&values[..n], k);
    for k in [32, 48, 63] {
        let line = halved[k - 32];
        assert!((bin(k) - line.cos.hypot(line.sin)).abs() < 1e-12, "bin {k}");
    }
    for k in [64, 80, 95] {
        assert!(bin(k) < 1e-14, "bin {k}: {:e}", bin(k));
    }
}

#[test]
fn bad_psd_files_are_refused_by_name() {
    let cases = [
        ("psd-negative.csv", "omega,psd\n0,1\n2,-1\n", "psd"),
        ("psd-zero.csv", "omega,psd\n0,0\n10,0\n", "psd"),
        ("psd-outside.csv", "omega,psd\n5,1\n10,1\n", "psd"),
        ("psd-header.csv", "omega,S\n0,1\n10,1\n", "columns"),
        ("psd-ragged.csv", "omega,psd\n0,1\n10\n", "columns"),
        (
            "psd-order.csv",
            "omega,psd\n0,1\n4,1\n2,1\n",
            "omega on line 4",
        ),
        ("psd-nan.csv", "omega,psd\n0,1\n10,nan\n", "psd on line 3"),
    ];
    for (name, text, field) in cases {
        let path = file(name, text);
        let message = refusal(&[
            "respond",
            "data/scenes/paper-damped.json",
            "--signal",
            &format!("random:band=1-3,rms=0.1,seed=1,psd={path}"),
            "--duration",
            "10",
        ]);
        println!("{message}");
        assert!(message.contains(&path), "{name}: {message}");
        assert!(message.contains(field), "{name}: {message}");
    }
    let message = refusal(&[
        "respond",
        "data/scenes/paper-damped.json",
        "--signal",
        "random:band=1-3,rms=0.1,seed=1,psd=/nonexistent/psd.csv",
        "--duration",
        "10",
    ]);
    assert!(message.contains("file"), "{message}");
}

/// A fresh empty directory for `--out` files.
fn out_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rattle-respond-{tag}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The names in `dir`.
fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

#[test]
fn a_failed_or_interrupted_out_run_leaves_nothing_half_written() {
    let dir = out_dir("atomic");
    let out = dir.join("response.csv");
    let out_text = out.to_str().unwrap().to_owned();
    let args = |duration: &str, extra: &[&str]| {
        let mut args = vec![
            "respond",
            "data/scenes/paper-damped.json",
            "--signal",
            "tone-burst:omega=2,cycles=5,amplitude=0.3",
            "--duration",
            duration,
            "--out",
            &out_text,
        ];
        args.extend_from_slice(extra);
        args.into_iter().map(str::to_owned).collect::<Vec<_>>()
    };
    let run = |extra: &[&str]| {
        let owned = args("40", extra);
        rattle(&owned.iter().map(String::as_str).collect::<Vec<_>>())
    };
    // Refused by the run itself, once the file would have been opened: nothing is left, and
    // a file already under the name stays as it was.
    std::fs::write(&out, "kept\n").unwrap();
    for samples in ["0", "10000001"] {
        let failed = run(&["--samples", samples]);
        assert_eq!(failed.status.code(), Some(2));
        assert!(String::from_utf8_lossy(&failed.stderr).contains("--samples"));
        assert_eq!(listing(&dir), ["response.csv"]);
        assert_eq!(std::fs::read_to_string(&out).unwrap(), "kept\n");
    }
    // Failing after the whole run (the name is a directory, so the final rename fails): the
    // temporary file beside it is removed and the error names the path.
    std::fs::remove_file(&out).unwrap();
    std::fs::create_dir(&out).unwrap();
    let failed = run(&["--samples", "400"]);
    assert!(!failed.status.success());
    let message = String::from_utf8_lossy(&failed.stderr);
    assert!(message.contains(&out_text), "{message}");
    assert_eq!(listing(&dir), ["response.csv"]);
    assert!(out.is_dir() && listing(&out).is_empty());
    std::fs::remove_dir(&out).unwrap();
    // Killed mid-run: the name never holds a partial table (the temporary file stays, hidden
    // beside it, as `.response.csv.PID.part`).
    let owned = args("4000", &["--samples", "10000000"]);
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args(&owned)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    let part = format!(".response.csv.{}.part", child.id());
    let started = std::time::Instant::now();
    while std::fs::metadata(dir.join(&part)).map_or(0, |m| m.len()) == 0 {
        assert!(
            started.elapsed().as_secs() < 60,
            "no rows written within 60 s"
        );
        assert!(child.try_wait().unwrap().is_none(), "the run ended early");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    child.kill().unwrap();
    child.wait().unwrap();
    assert!(!out.exists(), "a partial table under the final name");
    assert_eq!(listing(&dir), [part]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn json_with_out_prints_the_document_and_writes_the_table() {
    let dir = out_dir("json-out");
    let both = dir.join("both.csv");
    let alone = dir.join("alone.csv");
    let base = [
        "respond",
        "data/scenes/paper-damped.json",
        "--signal",
        "tone-burst:omega=2,cycles=5,amplitude=0.3",
        "--duration",
        "40",
        "--at",
        "10",
        "--samples",
        "500",
    ];
    let with = |extra: &[&str]| {
        let mut args = base.to_vec();
        args.extend_from_slice(extra);
        rattle(&args)
    };
    let printed = with(&["--out", both.to_str().unwrap(), "--json"]);
    assert!(printed.status.success());
    let written = with(&["--out", alone.to_str().unwrap()]);
    assert!(written.status.success());
    // stdout is the document alone (no `wrote` line), the same as without --out.
    let doc: Value = serde_json::from_slice(&printed.stdout).unwrap();
    let mut plain = base.to_vec();
    plain.truncate(base.len() - 2);
    plain.push("--json");
    assert_eq!(doc, json(&plain));
    assert!(String::from_utf8_lossy(&written.stdout).contains("wrote"));
    // The table is the one --out alone writes.
    let table = std::fs::read_to_string(&both).unwrap();
    assert_eq!(table, std::fs::read_to_string(&alone).unwrap());
    assert_eq!(table.lines().count(), 502);
    std::fs::remove_dir_all(&dir).ok();
}

/// The amplitude of bin `k` of `values` (`N` samples over one period) by a direct DFT:
/// `(2/N)|Σ_j v_j e^{−2πi kj/N}|`, the amplitude of a sinusoid on that bin.
fn bin_amplitude(values: &[f64], k: usize) -> f64 {
    let n = values.len();
    let (mut re, mut im) = (0.0, 0.0);
    for (j, v) in values.iter().enumerate() {
        let (s, c) = (TAU * ((k * j) % n) as f64 / n as f64).sin_cos();
        re += v * c;
        im += v * s;
    }
    (re * re + im * im).sqrt() * 2.0 / n as f64
}
