//! `cargo xtask soak`: the property tests of `crates/compare/tests/properties.rs` scaled up to
//! thousands of random scenes through both solvers, and the bad-input list (every bad argument
//! of `crates/compare/tests/cli.rs`, and random bad scenes, each of which must be refused with
//! the field named), with progress and a summary. Seeds are fixed: the same command checks the
//! same scenes on any machine and with any number of threads.
//!
//! Per random scene (the strategy of `properties.rs`: masses 0.5–5, stiffnesses 0.5–10,
//! `u_g` 0.1–3, gap 0.05–2, `e` 0–1, dashpots 0–0.5 or none, ω 0.3–5):
//! - the analytic symmetric orbits are finite and half-period symmetric (`u(t + T/2) = −u(t)`
//!   to 1e-10 of the orbit's size);
//! - 20 periods from rest are finite, never penetrate a stop (beyond 1e-9 of the motion's
//!   size), and no impact gains energy or changes momentum (1e-12);
//! - every stable viable symmetric orbit that decays fast enough to be decided within 6000
//!   periods (largest multiplier below 0.99) is held by the simulator started on it.
//!
//! Random structures (`--structures`) run through both solvers as well ([`structures`]), and
//! each is driven from rest by a random recorded signal through the respond engine
//! ([`signals`]: the energy balance over the record, no impact gaining energy).

use crate::root;
use clap::Args;
use rattle_analytic::symmetric_orbits;
use rattle_analytic::ForcedFlow;
use rattle_compare::scene::simulator::{model, run as simulate};
use rattle_compare::scene::{BaseSpec, DampingSpec, Scene, StopsSpec, UnitSpec};
use rattle_compare::verdict::{compare, Starts};
use rattle_event_driven::{SimulationOptions, Start};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

mod bad_input;
mod signals;
mod structures;

/// The seed of `properties.rs`.
const DEFAULT_SEED: u64 = 0x007a_771e;

/// Flags of `cargo xtask soak`.
#[derive(Debug, Args)]
pub struct SoakArgs {
    /// Random scenes to run through both solvers.
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(1..=10_000_000))]
    scenes: u64,
    /// Random bad scenes to refuse (in-process; the first 200 also through `rattle simulate`).
    #[arg(long, default_value_t = 10_000, value_parser = clap::value_parser!(u64).range(0..=10_000_000))]
    bad_scenes: u64,
    /// Random structures (bodies, springs, dashpots, one-sided and asymmetric stops, forces,
    /// harmonics) to run through both solvers, each also driven by a random recorded
    /// signal through the respond engine.
    #[arg(long, default_value_t = 2_000, value_parser = clap::value_parser!(u64).range(0..=10_000_000))]
    structures: u64,
    /// Seed of the random scenes (scene `k` is drawn from `seed` and `k` alone).
    #[arg(long, default_value_t = DEFAULT_SEED)]
    seed: u64,
}

/// SplitMix64: a small, fixed generator, so the scenes do not depend on a crate's version.
pub struct Rng(u64);

impl Rng {
    /// The generator of scene `index` under `seed`.
    pub fn new(seed: u64, index: u64) -> Rng {
        let mut rng = Rng(seed ^ index.wrapping_mul(0xd1b5_4a32_d192_ed03));
        rng.next_u64();
        rng
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    /// Uniform in `0..n`.
    pub fn below(&mut self, n: u64) -> u64 {
        self.next_u64() % n
    }
}

/// Random scene `index` and its frequency (the ranges of `properties.rs`).
pub fn random_scene(seed: u64, index: u64) -> (Scene, f64) {
    let mut rng = Rng::new(seed, index);
    let unit = UnitSpec {
        outer_mass: rng.uniform(0.5, 5.0),
        inner_mass: rng.uniform(0.5, 5.0),
        outer_stiffness: rng.uniform(0.5, 10.0),
        inner_stiffness: rng.uniform(0.5, 10.0),
    };
    let base = BaseSpec::fundamental(rng.uniform(0.1, 3.0));
    let stops = StopsSpec::rigid(rng.uniform(0.05, 2.0), rng.uniform(0.0, 1.0));
    let damping = (rng.below(2) == 1).then(|| DampingSpec {
        outer: rng.uniform(0.0, 0.5),
        inner: rng.uniform(0.0, 0.5),
    });
    let omega = rng.uniform(0.3, 5.0);
    let scene = Scene {
        name: format!("soak-{index}"),
        unit,
        base,
        stops: Some(stops),
        damping,
        cells: None,
        chain: None,
    };
    (scene, omega)
}

/// What one scene's checks found: items checked per property, or the first failure.
#[derive(Debug, Default, Clone, Copy)]
struct Tally {
    orbits: usize,
    impacts: usize,
    held: usize,
}

/// The analytic symmetric orbits are finite and half-period symmetric; returns how many.
fn analytic_symmetry(scene: &Scene, omega: f64) -> Result<usize, String> {
    let unit = scene.unit_model();
    let stops = scene.stops_model().ok_or("no stops")?;
    let orbits = symmetric_orbits(&unit, &stops, omega)
        .map_err(|e| format!("the analytic solver declined: {e}"))?;
    let flow = ForcedFlow::new(&unit, omega);
    for o in &orbits {
        let finite = o.alpha.is_finite()
            && o.outer_amplitude.is_finite()
            && o.floquet_multipliers
                .iter()
                .all(|m| m.re.is_finite() && m.im.is_finite());
        if !finite {
            return Err("an orbit with a number that is not finite".into());
        }
        let p0 = nalgebra::Vector2::new(o.alpha.cos(), o.alpha.sin());
        let (x, _) = flow
            .transition(0.5 * flow.period())
            .apply(&o.state_after_impact, &p0);
        let scale = o.state_before_impact.norm().max(o.gap).max(1.0);
        let residual = (x + o.state_before_impact).norm();
        if residual >= 1e-10 * scale {
            return Err(format!("half-period residual {residual:e}"));
        }
    }
    Ok(orbits.len())
}

/// 20 periods from rest: finite, no penetration, no energy gained at an impact; returns the
/// impacts checked.
fn simulation_sound(scene: &Scene, omega: f64) -> Result<usize, String> {
    let options = SimulationOptions {
        fixed_periods: Some(20),
        record_trajectory: true,
        ..SimulationOptions::default()
    };
    let sim = simulate(scene, omega, &Start::rest(2), &options)
        .map_err(|e| format!("simulation failed: {e}"))?;
    if !sim.outer_amplitude.is_finite() {
        return Err("outer amplitude not finite".into());
    }
    let gap = scene.stops.map_or(f64::INFINITY, |s| s.gap);
    let size = sim.steady.amplitudes.iter().fold(gap, |a, b| a.max(*b));
    for (t, x) in sim.steady.trajectory.iter().flatten() {
        let r = x[1] - x[0];
        if r.abs() > gap + 1e-9 * size {
            return Err(format!("t = {t}: |r| = {} > {gap}", r.abs()));
        }
    }
    let m = model(scene, omega).map_err(|e| e.to_string())?;
    let (mo, mi) = (scene.unit.outer_mass, scene.unit.inner_mass);
    let energy = |v: &nalgebra::DVector<f64>| 0.5 * (mo * v[0] * v[0] + mi * v[1] * v[1]);
    let momentum = |v: &nalgebra::DVector<f64>| mo * v[0] + mi * v[1];
    for imp in &sim.steady.cycle_impacts {
        let before = imp.state_before.rows(2, 2).into_owned();
        let after = m.impact_velocities(0, &before, None);
        if energy(&after) > energy(&before) * (1.0 + 1e-12) {
            return Err(format!("an impact gained energy at t = {}", imp.time));
        }
        if (momentum(&after) - momentum(&before)).abs() > 1e-12 * (1.0 + momentum(&before).abs()) {
            return Err(format!("an impact changed momentum at t = {}", imp.time));
        }
    }
    Ok(sim.steady.cycle_impacts.len())
}

/// Every stable viable symmetric orbit decidable within the cap is held by the simulator
/// started on it; returns how many were.
fn orbits_held(scene: &Scene, omega: f64) -> Result<usize, String> {
    let options = SimulationOptions {
        max_periods: 6000,
        ..SimulationOptions::default()
    };
    let p = compare(scene, omega, &options, Starts::RestAndOrbits)
        .map_err(|e| format!("a solver failed: {e}"))?;
    let mut decided = 0;
    for t in &p.trials {
        let Some((_, orbit)) = p.analytic.orbits.iter().find(|(b, _)| *b == t.branch) else {
            return Err(format!("trial of branch {} without its orbit", t.branch));
        };
        let slowest = orbit
            .floquet_multipliers
            .iter()
            .map(|m| m.norm())
            .fold(0.0, f64::max);
        if orbit.stable && slowest < 0.99 {
            if !t.held {
                return Err(format!("branch {} not held: {:?}", t.branch, t.difference));
            }
            decided += 1;
        }
    }
    Ok(decided)
}

/// The three properties on scene `index`.
fn check_scene(seed: u64, index: u64) -> Result<Tally, String> {
    let (scene, omega) = random_scene(seed, index);
    Ok(Tally {
        orbits: analytic_symmetry(&scene, omega)?,
        impacts: simulation_sound(&scene, omega)?,
        held: orbits_held(&scene, omega)?,
    })
}

/// Prints progress every `every` items: `what: done/total, failures, seconds`.
fn progress(what: &str, done: &AtomicUsize, failed: &AtomicUsize, total: u64, start: Instant) {
    let n = done.fetch_add(1, Ordering::Relaxed) + 1;
    let every = (total as usize / 20).max(1);
    if n.is_multiple_of(every) || n as u64 == total {
        eprintln!(
            "{what}: {n}/{total}, {} failed, {:.1} s",
            failed.load(Ordering::Relaxed),
            start.elapsed().as_secs_f64()
        );
    }
}

/// The random scenes through both solvers; returns the failures, each with its scene's index.
fn soak_scenes(seed: u64, scenes: u64) -> Vec<String> {
    let start = Instant::now();
    let (done, failed) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let results: Vec<Result<Tally, String>> = (0..scenes)
        .into_par_iter()
        .map(|k| {
            let r = check_scene(seed, k);
            if r.is_err() {
                failed.fetch_add(1, Ordering::Relaxed);
            }
            progress("scenes", &done, &failed, scenes, start);
            r
        })
        .collect();
    let mut total = Tally::default();
    let mut failures = Vec::new();
    for (k, r) in results.into_iter().enumerate() {
        match r {
            Ok(t) => {
                total.orbits += t.orbits;
                total.impacts += t.impacts;
                total.held += t.held;
            }
            Err(e) => failures.push(format!("scene {k} (--seed {seed}): {e}")),
        }
    }
    eprintln!(
        "scenes: {scenes} in {:.1} s; {} symmetric orbits symmetric, {} impacts without energy \
         gained, {} stable viable orbits held; {} failed",
        start.elapsed().as_secs_f64(),
        total.orbits,
        total.impacts,
        total.held,
        failures.len()
    );
    failures
}

/// Runs the task.
///
/// # Errors
/// When a check fails (every failure listed, with the scene's index to reproduce it), or the
/// `rattle` command cannot be built.
pub fn run(args: SoakArgs) -> Result<(), String> {
    let root = root();
    let rattle = crate::rattle_binary(&root)?;
    let mut failures = bad_input::soak(&rattle, &root, args.seed, args.bad_scenes);
    failures.extend(soak_scenes(args.seed, args.scenes));
    failures.extend(structures::soak_structures(args.seed, args.structures));
    failures.extend(signals::soak_signals(args.seed, args.structures));
    if failures.is_empty() {
        eprintln!("soak: every check passed");
        Ok(())
    } else {
        for f in &failures {
            eprintln!("FAILED {f}");
        }
        Err(format!("{} checks failed", failures.len()))
    }
}
