//! Random structures through both solvers: one to four bodies, each held by a spring to the
//! frame, the base or an earlier body; one to three stops between two bodies or a body and the
//! frame, two-sided, asymmetric or one-sided; driven by the base, by forces, or both, one
//! structure in two with one to three higher harmonics on each; and one structure in three
//! carries a free body (no spring, no dashpot) in a two-sided clearance of a body or between
//! two walls of the frame, as an impact damper's; one in four has one compliant stop. Per
//! structure, at a random frequency:
//! - 20 periods from rest are finite, never pass a rigid stop (beyond 1e-9 of the motion's
//!   size), no impact gains energy or changes the momentum of the bodies it involves (1e-12),
//!   and every contact of a compliant stop leaves it moving out;
//! - the cross-check of `rattle compare` is never a contradiction, and a periodic impacting
//!   motion that both solvers find agrees.
//!
//! A run the simulator declines by design (a rigid stop held while a compliant one is in
//! contact, which it refuses by name) is counted apart and listed by index, not failed.
//!
//! Bad structures (a name that does not exist, a body that nothing holds, a gap of zero, a stop
//! against the base) are refused naming their field.

use super::{progress, Rng};
use nalgebra::DVector;
use rattle_compare::scene::simulator::{run_structure, SimulateError};
use rattle_compare::scene::structure::{
    BodySpec, DashpotSpec, ForceSpec, ForcingSpec, SpringSpec, StopSpec, Structure, StructureScene,
    StructureSpec,
};
use rattle_compare::scene::{BaseSpec, HarmonicSpec};
use rattle_compare::verdict::structure::structure_cross_check;
use rattle_event_driven::{SimulationError, SimulationOptions};
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

/// A random structure `index` under `seed` and its frequency.
pub fn random_structure(seed: u64, index: u64) -> (StructureScene, f64) {
    // Structures draw from their own stream: the unit scenes' indices stay what they were.
    let mut rng = Rng::new(seed ^ 0x5354_5255_4354, index);
    let n = 1 + rng.below(4) as usize;
    let name = |j: usize| format!("b{j}");
    let bodies = (0..n)
        .map(|j| BodySpec {
            name: name(j),
            mass: rng.uniform(0.5, 5.0),
        })
        .collect();
    let mut springs = Vec::new();
    let mut dashpots = Vec::new();
    let mut tied_to_base = false;
    for j in 0..n {
        // Held by the frame, the base or an earlier body: no body is free.
        let to = match rng.below(if j == 0 { 2 } else { 3 }) {
            0 => "frame".to_owned(),
            1 => {
                tied_to_base = true;
                "base".to_owned()
            }
            _ => name(rng.below(j as u64) as usize),
        };
        springs.push(SpringSpec {
            between: [to.clone(), name(j)],
            stiffness: rng.uniform(0.5, 10.0),
        });
        if rng.below(2) == 1 {
            dashpots.push(DashpotSpec {
                between: [to, name(j)],
                damping: rng.uniform(0.0, 0.5),
            });
        }
    }
    let stops = (0..1 + rng.below(3))
        .map(|_| {
            let b = rng.below(n as u64) as usize;
            let a = match rng.below(n as u64 + 1) as usize {
                k if k == n || k == b => "frame".to_owned(),
                k => name(k),
            };
            let (plus, minus) = (rng.uniform(0.05, 2.0), rng.uniform(0.05, 2.0));
            let (gap_plus, gap_minus) = match rng.below(3) {
                0 => (Some(plus), None),
                1 => (None, Some(minus)),
                _ => (Some(plus), Some(minus)),
            };
            StopSpec {
                between: [a, name(b)],
                gap: None,
                gap_plus,
                gap_minus,
                restitution: Some(rng.uniform(0.0, 1.0)),
                contact_stiffness: None,
                contact_damping: None,
            }
        })
        .collect();
    let forces = if !tied_to_base || rng.below(2) == 1 {
        vec![ForceSpec {
            on: name(rng.below(n as u64) as usize),
            amplitude: rng.uniform(0.1, 3.0),
            phase: rng.uniform(-3.0, 3.0),
            harmonics: Vec::new(),
        }]
    } else {
        Vec::new()
    };
    let base = tied_to_base.then(|| BaseSpec::fundamental(rng.uniform(0.1, 3.0)));
    let omega = rng.uniform(0.3, 5.0);
    // Drawn after the rest, so that the structures without one are those of the same index
    // before free bodies were drawn.
    let (mut bodies, mut stops): (Vec<BodySpec>, Vec<StopSpec>) = (bodies, stops);
    if rng.below(3) == 0 {
        let host = match rng.below(n as u64 + 1) as usize {
            k if k == n => "frame".to_owned(),
            k => name(k),
        };
        bodies.push(BodySpec {
            name: "free".into(),
            mass: rng.uniform(0.05, 1.0),
        });
        stops.push(StopSpec {
            between: [host, "free".into()],
            gap: None,
            gap_plus: Some(rng.uniform(0.05, 2.0)),
            gap_minus: Some(rng.uniform(0.05, 2.0)),
            restitution: Some(rng.uniform(0.0, 1.0)),
            contact_stiffness: None,
            contact_damping: None,
        });
    }
    // Drawn last, so that the structures without harmonics are those of the same index
    // before harmonics were drawn: one structure in two has them on its base or its force.
    let (mut base, mut forces) = (base, forces);
    if rng.below(2) == 0 {
        if let Some(base) = base.as_mut() {
            base.harmonics = random_harmonics(&mut rng, base.amplitude);
        }
        if let Some(force) = forces.first_mut() {
            force.harmonics = random_harmonics(&mut rng, force.amplitude);
        }
    }
    // Drawn after the harmonics, so that the structures without a compliant stop are those
    // of the same index before compliant stops were drawn: one structure in four has one of
    // its stops compliant, of contact stiffness 10 to 1e5 N/m (up to 1e5 times its springs')
    // and a damping ratio up to about 0.7 for its lightest pair.
    if rng.below(4) == 0 {
        let k = rng.below(stops.len() as u64) as usize;
        let stiffness = 10f64.powf(rng.uniform(1.0, 5.0));
        let stop = &mut stops[k];
        stop.restitution = None;
        stop.contact_stiffness = Some(stiffness);
        stop.contact_damping = Some(rng.uniform(0.0, 0.3) * stiffness.sqrt());
    }
    let scene = StructureScene {
        name: format!("soak-structure-{index}"),
        structure: StructureSpec {
            bodies,
            springs,
            dashpots,
            stops,
        },
        forcing: ForcingSpec { base, forces },
        // The last body unless that is the free one.
        observe: Some(name(n - 1)),
    };
    (scene, omega)
}

/// One to three harmonics of distinct orders in `2..=6`, each of amplitude up to half the
/// fundamental's `amplitude` at a random phase: a forcing of the same period that bends its
/// shape, with orders whose searches stay cheap.
fn random_harmonics(rng: &mut Rng, amplitude: f64) -> Vec<HarmonicSpec> {
    let mut orders: Vec<u32> = (2..=6).collect();
    (0..1 + rng.below(3))
        .map(|_| HarmonicSpec {
            order: orders.remove(rng.below(orders.len() as u64) as usize),
            amplitude: rng.uniform(0.0, 0.5) * amplitude,
            phase: rng.uniform(-3.0, 3.0),
        })
        .collect()
}

/// Why a run of the soak is declined by design rather than failed: the simulator does not run
/// a rigid stop held (sticking) while a compliant stop is in contact, and says so by name.
const DECLINED: &str = "declined by design";

/// A simulator's failure as the soak's words: [`DECLINED`] for a rigid hold during a
/// compliant contact, the failure itself otherwise.
fn failure(what: &str, e: &SimulateError) -> String {
    match e {
        SimulateError::Simulation(SimulationError::HoldWithCompliantContact(_)) => {
            DECLINED.to_owned()
        }
        _ => format!("{what}: {e}"),
    }
}

/// 20 periods from rest are finite, inside every stop, and no impact gains energy or changes
/// momentum; returns the impacts checked.
fn simulation_sound(s: &Structure, omega: f64) -> Result<usize, String> {
    let options = SimulationOptions {
        fixed_periods: Some(20),
        record_trajectory: true,
        ..SimulationOptions::default()
    };
    let sim = run_structure(s, omega, &s.rest(), &options)
        .map_err(|e| failure("simulation failed", &e))?;
    if !sim.steady.amplitudes.iter().all(|a| a.is_finite()) {
        return Err("an amplitude is not finite".into());
    }
    let model = s.event_model(omega).map_err(|e| e.to_string())?;
    let n = s.dofs();
    let size = sim.steady.amplitudes.iter().fold(0.0f64, |a, b| a.max(*b));
    for (t, x) in sim.steady.trajectory.iter().flatten() {
        // A compliant stop is entered by design; its contacts are checked below.
        let rigid = s
            .stops
            .iter()
            .enumerate()
            .filter(|(_, stop)| stop.law.restitution().is_some());
        for (p, stop) in rigid {
            let pair = &model.contacts()[p];
            let r = pair.relative(&x.as_slice()[..n]);
            let tolerance = 1e-9 * size.max(stop.gap_plus.min(stop.gap_minus));
            if r > stop.gap_plus + tolerance || r < -stop.gap_minus - tolerance {
                return Err(format!("t = {t}: stop {p} passed, r = {r}"));
            }
        }
    }
    let masses: Vec<f64> = s.mass.diagonal().iter().copied().collect();
    let energy =
        |v: &DVector<f64>| 0.5 * v.iter().zip(&masses).map(|(v, m)| m * v * v).sum::<f64>();
    for imp in &sim.steady.cycle_impacts {
        let before = imp.state_before.rows(n, n).into_owned();
        let after = model.impact_velocities(imp.pair, &before, None);
        if energy(&after) > energy(&before) * (1.0 + 1e-12) + 1e-300 {
            return Err(format!("an impact gained energy at t = {}", imp.time));
        }
        // Against the frame momentum is not conserved; between two bodies it is.
        let stop = &s.stops[imp.pair];
        if let (Some(i), Some(j)) = (stop.plus, stop.minus) {
            let p = |v: &DVector<f64>| masses[i] * v[i] + masses[j] * v[j];
            let scale = masses[i] * before[i].abs() + masses[j] * before[j].abs();
            if (p(&after) - p(&before)).abs() > 1e-12 * (1.0 + scale) {
                return Err(format!("an impact changed momentum at t = {}", imp.time));
            }
        }
    }
    // Every contact of a compliant stop enters it, leaves it moving out, and ends where it
    // began: at the stop.
    for c in &sim.steady.cycle_contacts {
        let side = f64::from(c.side);
        if !(c.max_penetration.is_finite()
            && c.max_penetration >= 0.0
            && side * c.exit_velocity <= 0.0
            && c.exit_time > c.entry_time)
        {
            return Err(format!(
                "a contact of stop {} from t = {} to {} is not one: entry ṙ = {}, exit ṙ = {}, \
                 largest penetration {}",
                c.pair,
                c.entry_time,
                c.exit_time,
                c.entry_velocity,
                c.exit_velocity,
                c.max_penetration
            ));
        }
    }
    Ok(sim.steady.cycle_impacts.len() + sim.steady.cycle_contacts.len())
}

/// The cross-check is no contradiction; returns 1 for an impacting agreement.
fn cross_checked(s: &Structure, omega: f64) -> Result<usize, String> {
    let options = SimulationOptions {
        max_periods: 3000,
        ..SimulationOptions::default()
    };
    let check =
        structure_cross_check(s, omega, &options).map_err(|e| failure("a solver failed", &e))?;
    match check.class.name() {
        "contradiction" => Err(format!("contradiction: {}", check.class.detail())),
        "agreement"
            if !(check.simulated.steady.cycle_impacts.is_empty()
                && check.simulated.steady.cycle_contacts.is_empty()) =>
        {
            Ok(1)
        }
        _ => Ok(0),
    }
}

/// The random structures through both solvers; returns the failures.
pub fn soak_structures(seed: u64, count: u64) -> Vec<String> {
    let start = Instant::now();
    let (done, failed) = (AtomicUsize::new(0), AtomicUsize::new(0));
    let results: Vec<Result<(usize, usize), String>> = (0..count)
        .into_par_iter()
        .map(|k| {
            let (scene, omega) = random_structure(seed, k);
            let r = scene
                .structure()
                .map_err(|e| format!("a valid random structure was refused: {e}"))
                .and_then(|s| Ok((simulation_sound(&s, omega)?, cross_checked(&s, omega)?)));
            if r.as_ref().is_err_and(|e| e != DECLINED) {
                failed.fetch_add(1, Ordering::Relaxed);
            }
            progress("structures", &done, &failed, count, start);
            r
        })
        .collect();
    let (mut impacts, mut agreements, mut declined) = (0, 0, Vec::new());
    let mut failures = Vec::new();
    for (k, r) in results.into_iter().enumerate() {
        match r {
            Ok((i, a)) => {
                impacts += i;
                agreements += a;
            }
            Err(e) if e == DECLINED => declined.push(k),
            Err(e) => failures.push(format!("structure {k} (--seed {seed}): {e}")),
        }
    }
    failures.extend(bad_structures(seed));
    eprintln!(
        "structures: {count} in {:.1} s; {impacts} impacts and contacts checked, \
         {agreements} impacting motions in agreement; {DECLINED}: {} with a rigid hold during a \
         compliant contact {declined:?}; {} failed",
        start.elapsed().as_secs_f64(),
        declined.len(),
        failures.len()
    );
    failures
}

/// A way to spoil a valid structure, and the field its refusal must name.
type Spoil = (&'static str, Box<dyn Fn(&mut StructureScene)>);

/// Bad structures, each refused naming its field.
fn bad_structures(seed: u64) -> Vec<String> {
    let (good, _) = random_structure(seed, 0);
    let cases: Vec<Spoil> = vec![
        (
            "structure.springs[0].between[1]",
            Box::new(|s| s.structure.springs[0].between[1] = "nobody".into()),
        ),
        (
            "structure.stops[0].gap",
            Box::new(|s| {
                let stop = &mut s.structure.stops[0];
                stop.gap = Some(0.3);
                stop.gap_plus = Some(0.3);
            }),
        ),
        (
            "structure.stops[0].between",
            Box::new(|s| s.structure.stops[0].between[0] = "base".into()),
        ),
        (
            "structure.stops",
            Box::new(|s| {
                s.structure.bodies.push(BodySpec {
                    name: "loose".into(),
                    mass: 1.0,
                })
            }),
        ),
        (
            "structure.bodies[0].mass",
            Box::new(|s| s.structure.bodies[0].mass = f64::NAN),
        ),
    ];
    cases
        .into_iter()
        .filter_map(|(field, spoil)| {
            let mut bad = good.clone();
            spoil(&mut bad);
            match bad.structure() {
                Err(e) if e.field == field => None,
                Err(e) => Some(format!(
                    "bad structure refused naming {} instead of {field}: {e}",
                    e.field
                )),
                Ok(_) => Some(format!("bad structure accepted: {field}")),
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A few random structures pass every check (the soak's own smoke test).
    #[test]
    fn random_structures_pass() {
        let failures = soak_structures(super::super::DEFAULT_SEED, 12);
        assert!(failures.is_empty(), "{failures:?}");
    }
}
