//! Accuracy against cost: the event-driven simulator over its root tolerance and the
//! conventional Runge–Kutta baseline ([`crate::peers::baseline`]) over its `rtol`, both measured against
//! the analytic two-impact orbit (the exact reference) of a stable, viable period-1 motion;
//! the analytic solve as a single point; and what reaching a steady state and sweeping cost.
//!
//! Both integrators start from rest at `t = 0` and run a fixed number of forcing periods, enough
//! for the exact transient to decay far below the smallest error shown; the error is read off
//! the last period. Times are minima over repeated runs (the machine is shared: minima are the
//! least noisy statistic).

use crate::peers::baseline::{self, BaselineError, Tolerances};
use crate::peers::siconos::SiconosWorkPrecision;
use crate::runs::axis::Axis;
use crate::runs::parallel::Progress;
use crate::runs::sweep::{sweep, Solver};
use crate::scene::analytic::{analyse, OrbitSearch};
use crate::scene::simulator::{run, SimulateError};
use crate::scene::Scene;
use crate::verdict::{difference, Difference};
use nalgebra::Vector4;
use rattle_analytic::{Orbit, OrbitError};
use rattle_event_driven::SimulationOptions;
use std::time::{Duration, Instant};

use thiserror::Error;

/// The event-driven simulator's root tolerances studied.
pub const ROOT_TOLERANCES: [f64; 6] = [1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 1e-14];

/// The baseline's relative tolerances studied.
pub const RELATIVE_TOLERANCES: [f64; 11] = [
    1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12,
];

/// The periodicity tolerances of the steady-state cost study.
pub const PERIODICITY_TOLERANCES: [f64; 6] = [1e-3, 1e-5, 1e-7, 1e-9, 1e-11, 1e-13];

/// The sweep sizes of the sweep cost study: enough to show how the cost grows with the size;
/// a 160-point event sweep (1.6 s with its repeats) would take `cargo xtask figures` past a
/// minute.
pub const SWEEP_POINTS: [usize; 4] = [10, 20, 40, 80];

/// Step cap of a baseline run: far above the 300-period study's need at `rtol = 1e-12`
/// (about 10⁵ steps), so only a stalled integration meets it.
pub const BASELINE_MAX_STEPS: u64 = 50_000_000;

/// Time spent timing one point (after its minimum number of repeats): the minimum of 40 to
/// 200 repeats for the sub-millisecond event-driven and steady-state points, of 3 for the
/// baseline's slowest. Measured (`cargo run --release -p rattle-compare --example
/// work_precision`): at 20 ms per point every one of the study's 31 minima is the one a
/// larger budget (40 or 150 ms) gives, within the spread of repeated runs (1 to 5 %, the
/// ratio of the medians 0.975 to 1.016 with no sign to it), at a fraction of the time: at
/// 150 ms the study alone is a seventh of `cargo xtask figures` (see the performance page,
/// `docs/performance.md`).
pub const POINT_BUDGET: Duration = Duration::from_millis(20);

/// A result whose error is above this (relative) is a failure: another motion.
pub const FAILURE_ERROR: f64 = 0.1;

/// Why the study cannot run.
#[derive(Debug, Error)]
pub enum StudyError {
    /// The analytic solver failed.
    #[error("analytic: {0}")]
    Analytic(#[from] OrbitError),
    /// No stable viable orbit at this frequency: no exact reference.
    #[error("no stable viable two-impact orbit at omega = {0}")]
    NoReference(f64),
    /// The simulator failed on the reference case.
    #[error("simulator: {0}")]
    Simulate(#[from] SimulateError),
}

/// One run of a solver at one setting of its accuracy knob.
#[derive(Debug, Clone, PartialEq)]
pub struct PrecisionPoint {
    /// The knob: root tolerance or `rtol`.
    pub tolerance: f64,
    /// Minimum wall time of one solve, seconds.
    pub seconds: f64,
    /// Differences from the analytic orbit, when the run ended on a two-impact motion.
    pub difference: Option<Difference>,
    /// Why the run counts as failed (missed impact, other motion, integrator error), if it does.
    pub failure: Option<String>,
    /// Impacts over the run.
    pub impacts: u64,
}

impl PrecisionPoint {
    /// The error plotted: the largest relative difference (outer amplitude, impact state,
    /// phase / π), or `None` when there is no two-impact motion to compare.
    pub fn error(&self) -> Option<f64> {
        self.difference.map(|d| d.largest())
    }
}

/// The cost of running from rest until the stroboscopic map repeats to a tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct SteadyCost {
    /// Periodicity tolerance.
    pub periodicity_tolerance: f64,
    /// Periods run until the repetition was seen (`None` if it was not within the cap).
    pub periods_run: Option<u64>,
    /// Minimum wall time, seconds.
    pub seconds: f64,
    /// Error against the analytic orbit at the end.
    pub error: Option<f64>,
}

/// The cost of a sweep.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepCost {
    /// Which solver.
    pub solver: Solver,
    /// Number of frequencies.
    pub points: usize,
    /// Wall time, seconds: minimum of repeats (at least 2; the analytic sweeps more).
    pub seconds: f64,
}

/// Everything the work-precision figures draw.
#[derive(Debug, Clone)]
pub struct WorkPrecision {
    /// Scene name.
    pub scene_name: String,
    /// Angular frequency of the case, rad/s.
    pub omega: f64,
    /// Periods run from rest by both integrators.
    pub periods: u64,
    /// The reference orbit.
    pub orbit: Orbit,
    /// The event-driven simulator over [`ROOT_TOLERANCES`].
    pub event_driven: Vec<PrecisionPoint>,
    /// The Runge–Kutta baseline over [`RELATIVE_TOLERANCES`].
    pub baseline: Vec<PrecisionPoint>,
    /// Minimum wall time of the analytic solve (linear response, both symmetric branches,
    /// viability, Floquet multipliers), seconds.
    pub analytic_seconds: f64,
    /// Cost of a steady state over [`PERIODICITY_TOLERANCES`] (event-driven, from rest).
    pub steady: Vec<SteadyCost>,
    /// Cost of sweeps over [`SWEEP_POINTS`].
    pub sweeps: Vec<SweepCost>,
    /// Frequency range of the sweeps.
    pub sweep_range: (f64, f64),
    /// Siconos's two schemes on the same case, as measured by its script (not run by
    /// [`study`], which leaves this `None`: the caller attaches the committed results,
    /// [`crate::peers::siconos::SiconosPeer::work_precision_for`]).
    pub siconos: Option<SiconosWorkPrecision>,
}

/// Minimum time of `work` over repeats: at least `min_repeats`, then until `budget` is spent
/// (at most 1000 runs). Returns the minimum and the last result.
pub fn min_time<T>(min_repeats: usize, budget: Duration, mut work: impl FnMut() -> T) -> (f64, T) {
    let start = Instant::now();
    let mut best = f64::INFINITY;
    let mut runs = 0;
    loop {
        let t = Instant::now();
        let out = work();
        best = best.min(t.elapsed().as_secs_f64());
        runs += 1;
        if runs >= 1000 || (runs >= min_repeats && start.elapsed() >= budget) {
            return (best, out);
        }
    }
}

/// The stable viable orbit of `scene` at `omega` (the reference).
pub fn reference(scene: &Scene, omega: f64) -> Result<Orbit, StudyError> {
    analyse(scene, omega, OrbitSearch::Symmetric)?
        .stable_viable_orbits()
        .next()
        .map(|(_, o)| o.clone())
        .ok_or(StudyError::NoReference(omega))
}

/// The event-driven simulator from rest for `periods` periods at `root_tolerance`.
pub fn event_driven_point(
    scene: &Scene,
    orbit: &Orbit,
    periods: u64,
    root_tolerance: f64,
    budget: Duration,
) -> PrecisionPoint {
    let options = SimulationOptions {
        root_tolerance,
        fixed_periods: Some(periods),
        // The integrator alone is timed: its error is read off the run, not the polished cycle.
        polish: false,
        ..SimulationOptions::default()
    };
    let (seconds, result) = min_time(3, budget, || {
        run(
            scene,
            orbit.omega,
            &crate::scene::simulator::rest(scene),
            &options,
        )
    });
    match result {
        Ok(sim) => {
            let diff = difference(&sim, orbit);
            let failure = match diff {
                None => Some(format!("settled on {}", sim.regime.name())),
                Some(d) if d.largest() > FAILURE_ERROR => Some("another motion".into()),
                Some(_) => None,
            };
            PrecisionPoint {
                tolerance: root_tolerance,
                seconds,
                difference: diff,
                failure,
                impacts: sim.steady.impacts,
            }
        }
        Err(e) => PrecisionPoint {
            tolerance: root_tolerance,
            seconds,
            difference: None,
            failure: Some(e.to_string()),
            impacts: 0,
        },
    }
}

/// Compares a baseline run's last period with `orbit`: `None` unless it has exactly one
/// impact on each side.
pub fn baseline_difference(run: &baseline::BaselineRun, orbit: &Orbit) -> Option<Difference> {
    let impacts = &run.last_period_impacts;
    if impacts.len() != 2 || impacts[0].side == impacts[1].side {
        return None;
    }
    let side1 = impacts.iter().find(|i| i.side > 0)?;
    let s = side1.state_before;
    let state = Vector4::new(s[0], s[1], s[2], s[3]);
    Some(Difference::between(
        &state,
        orbit.omega * side1.time,
        run.outer_amplitude,
        orbit,
    ))
}

/// The Runge–Kutta baseline from rest for `periods` periods at `rtol`.
pub fn baseline_point(
    scene: &Scene,
    orbit: &Orbit,
    periods: u64,
    rtol: f64,
    budget: Duration,
) -> PrecisionPoint {
    let (seconds, result): (f64, Result<_, BaselineError>) = min_time(3, budget, || {
        baseline::run(
            scene,
            orbit.omega,
            0.0,
            [0.0; 4],
            periods,
            Tolerances::relative(rtol),
            BASELINE_MAX_STEPS,
        )
    });
    match result {
        Ok(r) => {
            let diff = baseline_difference(&r, orbit);
            let failure = match diff {
                None => Some(format!(
                    "{} impacts in the last period",
                    r.last_period_impacts.len()
                )),
                Some(d) if d.largest() > FAILURE_ERROR => Some("another motion".into()),
                Some(_) => None,
            };
            PrecisionPoint {
                tolerance: rtol,
                seconds,
                difference: diff,
                failure,
                impacts: r.impacts,
            }
        }
        Err(e) => PrecisionPoint {
            tolerance: rtol,
            seconds,
            difference: None,
            failure: Some(e.to_string()),
            impacts: 0,
        },
    }
}

/// Runs the whole study on `scene` at `omega` with `periods` periods from rest; sweeps over
/// `sweep_range` with the simulator capped by `options`.
pub fn study(
    scene: &Scene,
    omega: f64,
    periods: u64,
    sweep_range: (f64, f64),
    options: &SimulationOptions,
) -> Result<WorkPrecision, StudyError> {
    let orbit = reference(scene, omega)?;
    let budget = POINT_BUDGET;
    let (analytic_seconds, _) =
        min_time(20, budget, || analyse(scene, omega, OrbitSearch::Symmetric));
    let event_driven = ROOT_TOLERANCES
        .iter()
        .map(|&tol| event_driven_point(scene, &orbit, periods, tol, budget))
        .collect();
    let baseline = RELATIVE_TOLERANCES
        .iter()
        .map(|&rtol| baseline_point(scene, &orbit, periods, rtol, budget))
        .collect();
    let steady = PERIODICITY_TOLERANCES
        .iter()
        .map(|&tol| {
            let options = SimulationOptions {
                periodicity_tolerance: tol,
                ..options.clone()
            };
            let (seconds, result) = min_time(3, budget, || {
                run(
                    scene,
                    omega,
                    &crate::scene::simulator::rest(scene),
                    &options,
                )
            });
            let (periods_run, error) = match result {
                Ok(sim) => (
                    (sim.steady.status == rattle_event_driven::Status::Periodic)
                        .then_some(sim.steady.periods_run),
                    difference(&sim, &orbit).map(|d| d.largest()),
                ),
                Err(_) => (None, None),
            };
            SteadyCost {
                periodicity_tolerance: tol,
                periods_run,
                seconds,
                error,
            }
        })
        .collect();
    let mut sweeps = Vec::new();
    // Warm the thread pool first: the first parallel call pays for starting it.
    let _ = sweep(
        scene,
        &[omega],
        Solver::Analytic,
        options,
        &Progress::hidden(),
    );
    for solver in [Solver::Analytic, Solver::Event] {
        for &points in &SWEEP_POINTS {
            let omegas = Axis::new(sweep_range.0, sweep_range.1, points).values();
            let (seconds, _) = min_time(2, budget, || {
                sweep(scene, &omegas, solver, options, &Progress::hidden())
            });
            sweeps.push(SweepCost {
                solver,
                points,
                seconds,
            });
        }
    }
    Ok(WorkPrecision {
        scene_name: scene.name.clone(),
        omega,
        periods,
        orbit,
        event_driven,
        baseline,
        analytic_seconds,
        steady,
        sweeps,
        sweep_range,
        siconos: None,
    })
}
