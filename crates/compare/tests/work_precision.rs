//! The Runge–Kutta baseline against closed forms and the analytic orbit, and the
//! work-precision study's error against each solver's accuracy knob.

use rattle_compare::peers::baseline::{self, Dopri5, Tolerances};
use rattle_compare::peers::work_precision::{baseline_point, event_driven_point, reference};
use rattle_compare::scene::simulator::start_on_orbit;
use rattle_compare::scene::Scene;
use std::path::Path;
use std::time::Duration;

fn damped_scene() -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../data/scenes/paper-damped.json");
    Scene::load(&path).expect("the damped paper scene loads")
}

/// Two damped oscillators `ẍ + 2ζω_n ẋ + ω_n² x = 0` (ω_n = 1 and 3, ζ = 0.05, 0.1), from
/// `x = 1, ẋ = 0`: closed form `e^{−ζω_n t}(cos ω_d t + ζω_n/ω_d sin ω_d t)`.
fn damped_oscillators(rtol: f64) -> f64 {
    let modes = [(1.0_f64, 0.05_f64), (3.0, 0.1)];
    let field = move |_t: f64, y: &baseline::State| {
        let (w0, z0) = modes[0];
        let (w1, z1) = modes[1];
        [
            y[2],
            y[3],
            -2.0 * z0 * w0 * y[2] - w0 * w0 * y[0],
            -2.0 * z1 * w1 * y[3] - w1 * w1 * y[1],
        ]
    };
    let end = 10.0;
    let mut rk = Dopri5::new(
        field,
        Tolerances { rtol, atol: rtol },
        0.0,
        [1.0, 1.0, 0.0, 0.0],
        1.0,
    );
    while rk.time < end {
        rk.step((end - rk.time).min(1.0)).expect("steps");
    }
    let mut worst: f64 = 0.0;
    for (k, &(w, z)) in modes.iter().enumerate() {
        let wd = w * (1.0 - z * z).sqrt();
        let exact = (-z * w * end).exp() * ((wd * end).cos() + z * w / wd * (wd * end).sin());
        worst = worst.max((rk.state[k] - exact).abs());
    }
    worst
}

#[test]
fn dormand_prince_matches_the_closed_form_to_its_tolerance() {
    let mut previous = f64::INFINITY;
    for rtol in [1e-5, 1e-7, 1e-9, 1e-11] {
        let error = damped_oscillators(rtol);
        // The global error of a tolerance-controlled integration over a few periods stays
        // within a small multiple of the tolerance.
        assert!(error < 50.0 * rtol, "rtol {rtol:e}: error {error:e}");
        assert!(
            error < previous,
            "rtol {rtol:e}: error {error:e} not below {previous:e}"
        );
        previous = error;
    }
}

#[test]
fn dense_output_matches_the_step_ends_and_the_closed_form_inside() {
    let field = |_t: f64, y: &baseline::State| [y[2], y[3], -y[0], -4.0 * y[1]];
    let mut rk = Dopri5::new(
        field,
        Tolerances::relative(1e-10),
        0.0,
        [1.0, 0.0, 0.0, 2.0],
        0.5,
    );
    for _ in 0..20 {
        let start = rk.state;
        let dense = rk.step(0.5).expect("steps");
        let at_start = dense.state(dense.t0);
        let at_end = dense.state(dense.t0 + dense.h);
        for i in 0..4 {
            assert_eq!(at_start[i], start[i]);
            assert!((at_end[i] - rk.state[i]).abs() <= 4.0 * f64::EPSILON * 2.0);
        }
        let t = dense.t0 + 0.37 * dense.h;
        let y = dense.state(t);
        assert!((y[0] - t.cos()).abs() < 1e-8, "u at {t}: {}", y[0]);
        assert!((y[1] - (2.0 * t).sin()).abs() < 1e-8, "v at {t}: {}", y[1]);
    }
}

#[test]
fn event_location_finds_the_impacts_of_the_analytic_orbit() {
    let scene = damped_scene();
    let omega = 2.0;
    let orbit = reference(&scene, omega).expect("a stable viable orbit at 2 rad/s");
    let start = start_on_orbit(&scene, &orbit, 0.0);
    let state = [
        start.state[0],
        start.state[1],
        start.state[2],
        start.state[3],
    ];
    let run = baseline::run(
        &scene,
        omega,
        start.time,
        state,
        3,
        Tolerances::relative(1e-11),
        1_000_000,
    )
    .expect("runs");
    let period = std::f64::consts::TAU / omega;
    let impacts = &run.last_period_impacts;
    assert_eq!(impacts.len(), 2, "{impacts:?}");
    let side1 = impacts
        .iter()
        .find(|i| i.side == 1)
        .expect("a side-1 impact");
    let side2 = impacts
        .iter()
        .find(|i| i.side == -1)
        .expect("a side-2 impact");
    // Side 1 at base phase α, side 2 a fraction β of the period later.
    let phase = |t: f64| (omega * t - orbit.alpha).rem_euclid(std::f64::consts::TAU);
    let wrapped = |p: f64| p.min(std::f64::consts::TAU - p);
    assert!(
        wrapped(phase(side1.time)) < 1e-7,
        "side 1 at {}",
        side1.time
    );
    let beta = ((side2.time - side1.time) / period).rem_euclid(1.0);
    assert!(
        (beta - orbit.beta).abs() < 1e-7,
        "β = {beta}, orbit {}",
        orbit.beta
    );
    let s = side1.state_before;
    let d = (0..4)
        .map(|i| (s[i] - orbit.state_before_impact[i]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(
        d < 1e-7 * orbit.state_before_impact.norm(),
        "state off by {d:e}"
    );
    assert!((run.outer_amplitude - orbit.outer_amplitude).abs() < 1e-7 * orbit.outer_amplitude);
}

#[test]
fn event_driven_error_is_bounded_by_and_falls_with_the_root_tolerance() {
    let scene = damped_scene();
    let orbit = reference(&scene, 2.0).expect("reference orbit");
    let budget = Duration::from_millis(1);
    let mut previous = f64::INFINITY;
    for tol in [1e-4, 1e-8, 1e-12, 1e-14] {
        let point = event_driven_point(&scene, &orbit, 300, tol, budget);
        assert_eq!(point.failure, None, "root tolerance {tol:e}");
        let error = point.error().expect("a two-impact motion");
        // Bounded by the knob (contact times to tol × T) and never worse than a looser knob,
        // up to a rounding floor.
        assert!(
            error <= tol.max(1e-13),
            "tolerance {tol:e}: error {error:e}"
        );
        assert!(
            error <= previous.max(1e-14),
            "tolerance {tol:e}: error {error:e} above {previous:e}"
        );
        previous = error;
    }
    assert!(previous < 1e-13, "tightest error {previous:e}");
}

#[test]
fn baseline_error_falls_with_rtol() {
    let scene = damped_scene();
    let orbit = reference(&scene, 2.0).expect("reference orbit");
    let budget = Duration::from_millis(1);
    let loose = baseline_point(&scene, &orbit, 300, 1e-4, budget);
    let tight = baseline_point(&scene, &orbit, 300, 1e-9, budget);
    let (loose, tight) = (
        loose.error().expect("two-impact motion"),
        tight.error().expect("two-impact motion"),
    );
    assert!(
        tight < 1e-3 * loose,
        "rtol 1e-4: {loose:e}, rtol 1e-9: {tight:e}"
    );
    assert!(tight < 1e-7, "rtol 1e-9: {tight:e}");
}
