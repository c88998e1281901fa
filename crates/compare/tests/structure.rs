//! Structures as the user draws them, checked against answers neither solver computed: the
//! impact oscillator's period-1 orbit in closed form (a stable and an unstable one, driven by a
//! force and by the base), both solvers on one-sided and asymmetric units, and the unit and a
//! chain written as structures against their own forms.

use nalgebra::DVector;
use rattle_analytic::{sequence_orbits, ImpactSequence, SequenceOrbit};
use rattle_compare::references::impact_oscillator::{ImpactOscillator, PeriodOneOrbit};
use rattle_compare::scene::simulator::{polished_cycle, run_structure};
use rattle_compare::scene::structure::{Structure, StructureScene};
use rattle_compare::scene::{analytic::chain_model, simulator, AnyScene, Scene};
use rattle_compare::verdict::structure::structure_cross_check;
use rattle_event_driven::{periodic_orbit, simulate, SimulationOptions, Start};
use std::f64::consts::TAU;

/// The closed form and the analytic solver's cycle equations solve the same equations in
/// different ways (a quadratic in closed form; Newton on the exact flow): they agree to a few
/// thousand roundings of the state.
const CLOSED_FORM: f64 = 1e-10;

/// The simulator's periodic orbit is polished by its Newton to its tolerance (1e-12 relative
/// by default, [`SimulationOptions::root_tolerance`] times the Newton factor); its impact time
/// and velocity follow to that order, its multipliers to a few times it.
const SIMULATED: f64 = 1e-9;

fn structure(text: &str) -> Structure {
    let scene: StructureScene = serde_json::from_str(text).expect("the scene parses");
    scene.structure().expect("the structure is valid")
}

fn oscillator_scene(drive: &str, gap: f64, restitution: f64) -> String {
    format!(
        r#"{{"name": "impact-oscillator",
            "structure": {{
              "bodies":   [{{"name": "x", "mass": 1.0}}],
              "springs":  [{{"between": ["{drive}", "x"], "stiffness": 1.0}}],
              "dashpots": [{{"between": ["{drive}", "x"], "damping": 0.1}}],
              "stops":    [{{"between": ["frame", "x"], "gap_plus": {gap}, "restitution": {restitution}}}]}},
            "forcing": {}}}"#,
        if drive == "base" {
            r#"{"base": {"amplitude": 0.7}}"#.to_owned()
        } else {
            r#"{"forces": [{"on": "x", "amplitude": 1.0, "phase": 0.4}]}"#.to_owned()
        }
    )
}

/// The closed form of the scene: a force `F cos(ωt + φ)`; the base `u_g cos ωt` through `k`
/// and `c` is the force `u_g √(k² + c²ω²) cos(ωt + atan2(cω, k))`.
fn closed_form(drive: &str, gap: f64, restitution: f64, omega: f64) -> ImpactOscillator {
    let (force, phase) = if drive == "base" {
        (0.7 * 1.0f64.hypot(0.1 * omega), (0.1 * omega).atan2(1.0))
    } else {
        (1.0, 0.4)
    };
    ImpactOscillator {
        mass: 1.0,
        damping: 0.1,
        stiffness: 1.0,
        force,
        phase,
        gap,
        restitution,
    }
}

fn phase_distance(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(TAU);
    d.min(TAU - d)
}

/// The analytic orbit of `0+` matching `reference` by its phase, and the force's phase
/// offset `φ` the analytic `α` is measured from.
fn analytic_match<'a>(
    orbits: &'a [SequenceOrbit],
    reference: &PeriodOneOrbit,
    phase_offset: f64,
) -> &'a SequenceOrbit {
    orbits
        .iter()
        .min_by(|a, b| {
            let d =
                |o: &SequenceOrbit| phase_distance(o.alpha + phase_offset, reference.forcing_phase);
            d(a).total_cmp(&d(b))
        })
        .expect("an analytic orbit")
}

/// The closed form at a frequency with a stable and an unstable viable orbit (the pair that
/// meets at the fold), driven by a force and by the base: the analytic solver finds both, with
/// the same phase, velocity, viability, stability and multipliers.
#[test]
fn the_analytic_solver_finds_the_closed_form_orbits() {
    for drive in ["frame", "base"] {
        let (gap, restitution, omega) = (0.5, 0.8, 1.8);
        let s = structure(&oscillator_scene(drive, gap, restitution));
        let reference = closed_form(drive, gap, restitution, omega)
            .period_one_orbits(omega)
            .unwrap();
        assert_eq!(reference.len(), 2, "{drive}");
        assert!(reference.iter().all(|o| o.viable), "{reference:?}");
        assert_eq!(
            reference.iter().filter(|o| o.stable).count(),
            1,
            "one stable, one unstable: {reference:?}"
        );
        let model = s.analytic_model().unwrap();
        let sequence = ImpactSequence::parse("0+", 1).unwrap();
        let found = sequence_orbits(&model, omega, &sequence).unwrap();
        assert_eq!(found.len(), 2, "{drive}");
        // The analytic forcing is `f_c cos θ + f_s sin θ`, θ = ωt + α: for a force that is
        // `F cos(θ + φ)`, for the base `u_g (k cos θ − cω sin θ) = F cos(θ + atan2(cω, k))`.
        let offset = closed_form(drive, gap, restitution, omega).phase;
        for r in &reference {
            let a = analytic_match(&found, r, offset);
            let v = a.states_before_impacts[0][1];
            let phase = a.alpha + offset;
            assert!(
                phase_distance(phase, r.forcing_phase) < CLOSED_FORM,
                "{drive}: {phase} {r:?}"
            );
            assert!(
                (v - r.velocity_before).abs() < CLOSED_FORM * r.velocity_before,
                "{v} {r:?}"
            );
            assert!((a.states_before_impacts[0][0] - gap).abs() < CLOSED_FORM);
            assert_eq!((a.viable, a.stable), (r.viable, r.stable), "{drive}: {r:?}");
            let mut mu: Vec<_> = a.floquet_multipliers.iter().map(|m| [m.re, m.im]).collect();
            let mut expected = r.multipliers.to_vec();
            for list in [&mut mu, &mut expected] {
                list.sort_by(|p, q| p[1].total_cmp(&q[1]).then(p[0].total_cmp(&q[0])));
            }
            for (m, e) in mu.iter().zip(&expected) {
                assert!(
                    (m[0] - e[0]).hypot(m[1] - e[1]) < CLOSED_FORM,
                    "{drive}: {mu:?} {expected:?}"
                );
            }
            assert!(
                (a.amplitudes[0] - r.amplitude).abs() < 1e-8 * r.amplitude,
                "{} {}",
                a.amplitudes[0],
                r.amplitude
            );
        }
    }
}

/// The simulator from rest settles on the stable closed-form orbit; its Newton started on the
/// unstable one (mid-flight) converges to it and reports its multipliers, one outside the unit
/// circle.
#[test]
fn the_simulator_finds_the_closed_form_orbits() {
    for drive in ["frame", "base"] {
        let (gap, restitution, omega) = (0.5, 0.8, 1.8);
        let s = structure(&oscillator_scene(drive, gap, restitution));
        let reference = closed_form(drive, gap, restitution, omega);
        let orbits = reference.period_one_orbits(omega).unwrap();
        let period = TAU / omega;
        let stable = orbits.iter().find(|o| o.stable).unwrap();
        // Driven by the force, the run starts from rest; driven by the base (weaker here),
        // the motion without impacts coexists, so the run starts a little off the stable
        // orbit, just after its impact.
        let start = if drive == "base" {
            Start {
                state: DVector::from_vec(vec![
                    gap * (1.0 - 1e-3),
                    -restitution * stable.velocity_before * (1.0 + 1e-3),
                ]),
                time: stable.impact_time,
            }
        } else {
            s.rest()
        };
        let sim = run_structure(&s, omega, &start, &SimulationOptions::default()).unwrap();
        let orbit = sim.steady.orbit.as_deref().expect("a polished orbit");
        let model = s.event_model(omega).unwrap();
        let cycle = polished_cycle(&model, omega, orbit, &SimulationOptions::default()).unwrap();
        assert_eq!(cycle.impacts.len(), 1, "{drive}");
        let impact = &cycle.impacts[0];
        let time = impact.time.rem_euclid(period);
        let dt = (time - stable.impact_time).abs();
        assert!(
            dt.min(period - dt) < SIMULATED * period,
            "{drive}: {time} {stable:?}"
        );
        let v = impact.state_before[1];
        assert!(
            (v - stable.velocity_before).abs() < SIMULATED * v,
            "{v} {stable:?}"
        );
        assert!(
            (sim.outer_amplitude - stable.amplitude).abs() < 1e-8 * stable.amplitude,
            "{} {stable:?}",
            sim.outer_amplitude
        );
        let unstable = orbits.iter().find(|o| !o.stable).unwrap();
        // The state half a period after the unstable orbit's impact, from the closed form.
        let model = s.event_model(omega).unwrap();
        let start = Start {
            state: DVector::from_vec(vec![gap, -restitution * unstable.velocity_before]),
            time: unstable.impact_time,
        };
        let half = SimulationOptions {
            fixed_periods: Some(1),
            ..SimulationOptions::default()
        };
        // Half a period of free flight: no impact on the way (the orbit is viable).
        let mid = simulate(&model, omega, &start, &half).unwrap().final_state;
        let found = periodic_orbit(&model, omega, &mid, 1, &SimulationOptions::default()).unwrap();
        assert_eq!(found.impact_sides, vec![1]);
        let largest = found
            .floquet_multipliers
            .iter()
            .map(|m| m.norm())
            .fold(0.0, f64::max);
        let expected = unstable
            .multipliers
            .iter()
            .map(|[re, im]| re.hypot(*im))
            .fold(0.0, f64::max);
        assert!(
            largest > 1.0 && (largest - expected).abs() < SIMULATED * expected,
            "{largest} {expected}"
        );
        let phase = (found.time + found.impact_phases[0] * period).rem_euclid(period);
        let dt = (phase - unstable.impact_time).abs();
        assert!(
            dt.min(period - dt) < SIMULATED * period,
            "{phase} {unstable:?}"
        );
    }
}

/// The paper's unit with stops on one side only, and with two different gaps: both solvers
/// agree at frequencies with impacts, and a one-sided signature names the side it has.
#[test]
fn one_sided_and_asymmetric_units_agree_both_ways() {
    let unit = |stop: &str| {
        format!(
            r#"{{"structure": {{
                 "bodies": [{{"name": "outer", "mass": 2.0}}, {{"name": "inner", "mass": 1.0}}],
                 "springs": [{{"between": ["base", "outer"], "stiffness": 6.0}},
                             {{"between": ["outer", "inner"], "stiffness": 3.0}}],
                 "dashpots": [{{"between": ["base", "outer"], "damping": 0.1}}],
                 "stops": [{{"between": ["outer", "inner"], {stop}, "restitution": 0.8}}]}},
               "forcing": {{"base": {{"amplitude": 1.0}}}},
               "observe": "outer"}}"#
        )
    };
    for stop in [
        r#""gap_plus": 0.4"#,
        r#""gap_minus": 0.3"#,
        r#""gap_plus": 0.6, "gap_minus": 0.25"#,
    ] {
        let s = structure(&unit(stop));
        let mut impacting = 0;
        for omega in [1.0, 1.2, 1.4, 2.0, 2.6, 3.0] {
            let check = structure_cross_check(&s, omega, &SimulationOptions::default()).unwrap();
            let class = check.class.name();
            assert_ne!(
                class, "contradiction",
                "{stop} at {omega}: {:?}",
                check.class
            );
            if class == "agreement" && !check.simulated.steady.cycle_impacts.is_empty() {
                impacting += 1;
                let sides: Vec<i8> = check
                    .simulated
                    .steady
                    .cycle_impacts
                    .iter()
                    .map(|i| i.side)
                    .collect();
                if !stop.contains("gap_minus") {
                    assert!(sides.iter().all(|&s| s == 1), "{sides:?}");
                }
                if !stop.contains("gap_plus") {
                    assert!(sides.iter().all(|&s| s == -1), "{sides:?}");
                }
            }
        }
        assert!(impacting >= 2, "{stop}: {impacting} impacting agreements");
    }
    let model = structure(&unit(r#""gap_plus": 0.4"#))
        .analytic_model()
        .unwrap();
    let sequence = ImpactSequence::parse("0+ 0-", 1).unwrap();
    let e = sequence.check(&model).unwrap_err().to_string();
    assert!(e.contains("side - of pair 0, which has no stop"), "{e}");
}

/// The paper's unit written as a structure is the same model: the simulator's polished orbit
/// and multipliers from rest agree with the unit form's to 1e-12.
#[test]
fn the_unit_as_a_structure_is_the_unit() {
    let paper = Scene::paper();
    let s = structure(
        r#"{"structure": {
             "bodies": [{"name": "outer", "mass": 2.0}, {"name": "inner", "mass": 1.0}],
             "springs": [{"between": ["base", "outer"], "stiffness": 6.0},
                         {"between": ["outer", "inner"], "stiffness": 3.0}],
             "stops": [{"between": ["outer", "inner"], "gap": 0.5, "restitution": 0.8}]},
           "forcing": {"base": {"amplitude": 1.0}},
           "observe": "outer"}"#,
    );
    for omega in [1.2, 1.9, 2.0, 3.3] {
        let options = SimulationOptions::default();
        let unit = simulator::run(&paper, omega, &simulator::rest(&paper), &options).unwrap();
        let general = run_structure(&s, omega, &s.rest(), &options).unwrap();
        let (a, b) = (unit.steady.orbit.unwrap(), general.steady.orbit.unwrap());
        let d = (&a.state - &b.state).norm() / a.state.norm();
        assert!(d < 1e-12, "{omega}: {d}");
        assert_eq!(a.impact_sides, b.impact_sides);
        let mu = |o: &rattle_event_driven::PeriodicOrbit| {
            o.floquet_multipliers
                .iter()
                .map(|m| m.norm())
                .fold(0.0, f64::max)
        };
        assert!((mu(&a) - mu(&b)).abs() < 1e-12, "{omega}");
    }
}

/// A chain of five cells written as a structure assembles the chain's matrices bit for bit
/// (the springs listed in the chain's order of sums).
#[test]
fn a_chain_as_a_structure_is_the_chain() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../data/scenes/paper-chain-5.json"
    ))
    .unwrap();
    let chain = Scene::parse(&text, "chain").unwrap();
    let mut bodies = Vec::new();
    let (mut springs, mut dashpots, mut stops) = (Vec::new(), Vec::new(), Vec::new());
    for j in 0..5 {
        bodies.push(format!(r#"{{"name": "o{j}", "mass": 2.0}}"#));
        bodies.push(format!(r#"{{"name": "i{j}", "mass": 1.0}}"#));
        let previous = if j == 0 {
            "base".to_owned()
        } else {
            format!("o{}", j - 1)
        };
        springs.push((
            j,
            format!(r#"{{"between": ["{previous}", "o{j}"], "stiffness": 6.0}}"#),
        ));
        springs.push((
            j,
            format!(r#"{{"between": ["o{j}", "i{j}"], "stiffness": 3.0}}"#),
        ));
        dashpots.push(format!(
            r#"{{"between": ["{previous}", "o{j}"], "damping": 0.1}}"#
        ));
        dashpots.push(format!(
            r#"{{"between": ["o{j}", "i{j}"], "damping": 0.05}}"#
        ));
        stops.push(format!(
            r#"{{"between": ["o{j}", "i{j}"], "gap": 0.5, "restitution": 0.8}}"#
        ));
    }
    let list = |v: Vec<String>| v.join(", ");
    let text = format!(
        r#"{{"name": "chain-as-structure", "structure": {{"bodies": [{}], "springs": [{}], "dashpots": [{}], "stops": [{}]}}, "forcing": {{"base": {{"amplitude": 1.0}}}}, "observe": "o4"}}"#,
        list(bodies),
        list(springs.into_iter().map(|(_, s)| s).collect()),
        list(dashpots),
        list(stops)
    );
    let AnyScene::Structure(form) = AnyScene::parse(&text, "test").unwrap() else {
        panic!("a structure scene")
    };
    let s = form.structure;
    let expected = chain_model(&chain).unwrap();
    let model = s.analytic_model().unwrap();
    assert_eq!(model.mass(), expected.mass());
    assert_eq!(model.stiffness(), expected.stiffness());
    assert_eq!(model.damping(), expected.damping());
    assert_eq!(model.forcing(), expected.forcing());
    assert_eq!(model.pairs(), expected.pairs());
    // The simulator's models run alike: the same polished orbit from rest, with impacts.
    let omega = 3.3;
    let options = SimulationOptions::default();
    let a = simulator::run(&chain, omega, &simulator::rest(&chain), &options).unwrap();
    let b = run_structure(&s, omega, &s.rest(), &options).unwrap();
    let (a, b) = (a.steady.orbit.unwrap(), b.steady.orbit.unwrap());
    assert!(!a.impact_sides.is_empty());
    assert_eq!(a.state, b.state);
}

/// A body held on a stop against the frame has no coordinate left free: it stays at the stop,
/// at rest, while the force pushes it there, and leaves when the push changes sign. The
/// plastic impact oscillator (`r = 0`): every sample on the stop has zero velocity and a push
/// `F cos(ωt + φ) − kσ ≥ 0`, and each stay on the stop ends within one sample of the push's
/// sign change.
#[test]
fn a_body_held_on_the_frame_leaves_when_the_push_changes_sign() {
    use rattle_event_driven::{sample_trajectory, TrajectoryOptions};
    let (gap, omega) = (0.5, 0.6);
    let s = structure(&oscillator_scene("frame", gap, 0.0));
    let model = s.event_model(omega).unwrap();
    let samples = 20_000u64;
    let trajectory = sample_trajectory(
        &model,
        omega,
        &s.rest(),
        &TrajectoryOptions {
            periods: 30,
            samples_per_period: samples,
            base_amplitude: 0.0,
            simulation: SimulationOptions::default(),
        },
    )
    .unwrap();
    let push = |t: f64| (omega * t + 0.4).cos() - gap;
    let spacing = TAU / omega / samples as f64;
    let (mut held, mut releases) = (0, 0);
    // Uniform samples only: an impact's rows may sit on the stop at rest for an instant (a
    // plastic impact that leaves at once where the push pulls).
    let rows: Vec<_> = trajectory
        .rows
        .iter()
        .filter(|r| r.kind == rattle_event_driven::RowKind::Sample)
        .collect();
    for (k, row) in rows.iter().enumerate() {
        let on_stop = (row.displacements[0] - gap).abs() < 1e-12;
        if on_stop && row.velocities[0].abs() < 1e-12 {
            held += 1;
            assert!(
                push(row.time) > -1e-9,
                "held at t = {} with push {}",
                row.time,
                push(row.time)
            );
            if let Some(next) = rows.get(k + 1).filter(|r| r.displacements[0] < gap - 1e-12) {
                // Left the stop between these two rows: the push changed sign there (or
                // within one sample spacing of them).
                releases += 1;
                assert!(
                    push(next.time + spacing) < 0.0 && push(row.time - spacing) > 0.0,
                    "left between {} and {}",
                    row.time,
                    next.time
                );
            }
        }
        assert!(
            row.displacements[0] <= gap + 1e-12,
            "{}",
            row.displacements[0]
        );
    }
    assert!(
        held > 1000 && releases >= 10,
        "{held} samples held, {releases} releases"
    );
}

/// A body on its own undamped spring, untouched by the forcing and the stops, keeps a Floquet
/// multiplier on the unit circle in both solvers: the impact oscillator beside it agrees, and
/// the verdict is `beyond` (neutral), not a contradiction.
#[test]
fn an_unexcited_undamped_body_makes_the_verdict_neutral() {
    let text = oscillator_scene("frame", 0.5, 0.8).replace(
        r#"[{"name": "x", "mass": 1.0}]"#,
        r#"[{"name": "x", "mass": 1.0}, {"name": "idle", "mass": 2.0}]"#,
    );
    let text = text.replace(
        r#""springs":  ["#,
        r#""springs":  [{"between": ["frame", "idle"], "stiffness": 3.0}, "#,
    );
    let s = structure(&text);
    let check = structure_cross_check(&s, 1.8, &SimulationOptions::default()).unwrap();
    assert_eq!(check.class.name(), "beyond", "{:?}", check.class);
    assert_eq!(check.reason.map(|r| r.name()), Some("neutral"));
    assert!(check.relative_difference.unwrap() < 1e-9);
}

/// The closed form's fold within 1e-3 of `omega` at `gap` (restitution 0.8).
fn closed_form_fold(drive: &str, gap: f64, omega: f64) -> f64 {
    closed_form(drive, gap, 0.8, omega)
        .fold_between(omega - 1e-3, omega + 1e-3)
        .expect("in the closed form's range")
        .unwrap_or_else(|| panic!("no fold within 1e-3 of ω = {omega} at gap {gap}"))
}

/// The continuation of the oscillator's period-1 orbits, through its fold: every point is a
/// closed-form orbit at its frequency (phase and amplitude), and the fold is the closed
/// form's.
#[test]
fn continuation_follows_the_closed_form_branch_through_its_fold() {
    use rattle_analytic::ContinuationSettings;
    use rattle_compare::api::{self, ContinuedBranches};
    let text = oscillator_scene("frame", 0.5, 0.8);
    let scene = api::parse(&text).expect("a valid scene");
    let settings = ContinuationSettings {
        follow_switches: false,
        ..ContinuationSettings::new(1.2, 2.5)
    };
    let continued = api::continuation(&scene, "+", 1, 1.8, Some(0), &settings).expect("followed");
    let ContinuedBranches::Structure { followed, .. } = &continued.branches else {
        panic!("a structure's branches")
    };
    let branch = &followed.continuation.branches[0];
    assert!(branch.points.len() > 20, "{} points", branch.points.len());
    let offset = closed_form("frame", 0.5, 0.8, 1.0).phase;
    for p in &branch.points {
        let reference = closed_form("frame", 0.5, 0.8, p.omega)
            .period_one_orbits(p.omega)
            .expect("in range");
        let nearest = reference
            .iter()
            .min_by(|a, b| {
                let d = |o: &PeriodOneOrbit| phase_distance(p.alpha + offset, o.forcing_phase);
                d(a).total_cmp(&d(b))
            })
            .unwrap_or_else(|| panic!("no closed-form orbit at ω = {}", p.omega));
        // Points are corrected onto the branch to the corrector's acceptance (1e-10); the
        // closed form's amplitude is sampled on its viability grid (see the test above).
        assert!(
            phase_distance(p.alpha + offset, nearest.forcing_phase) < 1e-8,
            "ω = {}: {} {nearest:?}",
            p.omega,
            p.alpha
        );
        assert!(
            (p.amplitudes[0] - nearest.amplitude).abs() < 1e-8 * nearest.amplitude,
            "ω = {}: {} {nearest:?}",
            p.omega,
            p.amplitudes[0]
        );
        assert_eq!(p.stable, nearest.stable, "ω = {}", p.omega);
    }
    let fold = followed
        .continuation
        .events
        .iter()
        .find(|e| e.kind == rattle_analytic::EventKind::Fold)
        .expect("the branch folds");
    let exact = closed_form_fold("frame", 0.5, fold.omega);
    assert!((fold.omega - exact).abs() < 1e-8, "{} {exact}", fold.omega);
    // The record names the body and carries the observed body's amplitude.
    let json = serde_json::to_value(&continued).expect("serializes");
    let first = &json["points"][0];
    assert_eq!(first["outer_amplitude"], first["body_amplitudes"]["x"]);
}

/// The fold followed in the gap: at each gap asked for, the curve's frequency is the closed
/// form's fold at that gap.
#[test]
fn the_fold_boundary_in_the_gap_is_the_closed_form_fold() {
    use rattle_compare::api;
    use rattle_compare::runs::boundary::BoundaryOptions;
    let scene = api::parse(&oscillator_scene("frame", 0.5, 0.8)).expect("a valid scene");
    let options = BoundaryOptions {
        signature: "+".into(),
        period: 1,
        event: "fold".into(),
        omega: 1.85,
        param: "structure.stops[0].gap_plus".into(),
        min: 0.35,
        max: 0.8,
        at: vec![0.4, 0.6, 0.75],
        omega_min: 1.0,
        omega_max: 2.6,
        max_step: 0.02,
    };
    let record = api::boundary(&scene, &options).expect("followed");
    assert_eq!(record.param, "structure.stops[0].gap_plus");
    assert!(record.at.len() >= 3, "{:?}", record.at);
    for a in &record.at {
        let exact = closed_form_fold("frame", a.param_value, a.omega);
        assert!(
            (a.omega - exact).abs() < 1e-8,
            "gap {}: {} {exact}",
            a.param_value,
            a.omega
        );
    }
    // A path of the other form is refused naming the flag and the paths a structure takes.
    let e = api::boundary(
        &scene,
        &BoundaryOptions {
            param: "stops.gap".into(),
            ..options.clone()
        },
    )
    .expect_err("a unit's path");
    let text = e.to_string();
    assert!(
        text.contains("--param") && text.contains("structure.stops[K].gap_plus"),
        "{text}"
    );
    let e = api::boundary(
        &scene,
        &BoundaryOptions {
            param: "structure.stops[0].gap_minus".into(),
            ..options
        },
    )
    .expect_err("a one-sided stop");
    assert!(e.to_string().contains("no side 2"), "{e}");
}
