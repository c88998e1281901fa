//! The study behind `cargo xtask figures`: every sweep and simulation the figures and the
//! validation report need, computed once from one scene.

use crate::classify::{compare_with, ComparedPoint};
use crate::figures::beta_family::{Confirmation, Member};
use crate::figures::impact_time_response::{ImpactRow, Samples};
use crate::frequency::{analyse, AnalyticPoint};
use crate::scene::{Scene, StopsSpec};
use crate::simulation::{run, start_on_orbit, Regime, SimulatedPoint};
use crate::sweep::{frequencies, parallel_map, parallel_map_even};
use nalgebra::{Vector2, Vector4};
use rattle_analytic::flow::ForcedFlow;
use rattle_analytic::gap_for_beta;
use rattle_event_driven::{SimulationOptions, Start};

/// Sizes of the study; [`StudySize::full`] for the committed figures, [`StudySize::quick`] for
/// a smoke test.
#[derive(Debug, Clone, Copy)]
pub struct StudySize {
    /// Lowest frequency, rad/s.
    pub omega_min: f64,
    /// Highest frequency, rad/s.
    pub omega_max: f64,
    /// Points of the analytic fine grid.
    pub analytic_points: usize,
    /// Points of the sweep with both solvers.
    pub compared_points: usize,
    /// Points of each bifurcation sweep (up and down).
    pub bifurcation_points: usize,
    /// Points of `β` per family curve.
    pub beta_points: usize,
    /// Whether the compared sweep also starts the simulator on every viable orbit.
    pub start_on_orbits: bool,
}

impl StudySize {
    /// The committed figures: 400 compared frequencies.
    pub fn full() -> Self {
        Self {
            omega_min: 0.1,
            omega_max: 4.0,
            analytic_points: 1561,
            compared_points: 400,
            bifurcation_points: 200,
            beta_points: 197,
            start_on_orbits: true,
        }
    }

    /// Half the compared frequencies, without the bifurcation sweeps, the family and the starts
    /// on the orbits: what a second reading of the scene needs for the report (bands,
    /// Figure 4).
    pub fn without_extras(self) -> Self {
        Self {
            compared_points: self.compared_points.div_ceil(2),
            bifurcation_points: 0,
            beta_points: 0,
            start_on_orbits: false,
            ..self
        }
    }

    /// A few points of everything, so the pipeline cannot rot.
    pub fn quick() -> Self {
        Self {
            omega_min: 0.5,
            omega_max: 3.5,
            analytic_points: 40,
            compared_points: 12,
            bifurcation_points: 12,
            beta_points: 20,
            start_on_orbits: true,
        }
    }
}

/// The family at one frequency, with simulated confirmations.
#[derive(Debug, Clone)]
pub struct FamilyCurve {
    /// Frequency, rad/s.
    pub omega: f64,
    /// Members on the `β` grid.
    pub members: Vec<Member>,
}

/// Everything computed for one scene.
#[derive(Debug, Clone)]
pub struct Study {
    /// The scene.
    pub scene: Scene,
    /// The sizes used.
    pub size: StudySize,
    /// Analytic picture on the fine grid.
    pub analytic: Vec<AnalyticPoint>,
    /// Both solvers on the compared grid.
    pub compared: Vec<ComparedPoint>,
    /// Frequencies that failed in the compared sweep, with the reason.
    pub failures: Vec<(f64, String)>,
    /// Stroboscopic `(ω, u_o)` sweeping up.
    pub bifurcation_up: Vec<(f64, f64)>,
    /// Stroboscopic `(ω, u_o)` sweeping down.
    pub bifurcation_down: Vec<(f64, f64)>,
    /// The family for a few frequencies.
    pub family: Vec<FamilyCurve>,
    /// Simulated checks of stable viable family members.
    pub confirmations: Vec<Confirmation>,
}

/// Frequencies of the family figure.
pub const FAMILY_OMEGAS: [f64; 3] = [1.5, 2.0, 3.0];

impl Study {
    /// Runs the study; `progress` draws progress lines on a terminal.
    pub fn run(
        scene: &Scene,
        size: StudySize,
        options: &SimulationOptions,
        progress: bool,
    ) -> Study {
        let clock = std::time::Instant::now();
        let lap = |what: &str| {
            if progress {
                eprintln!("  {what}: {:.1} s", clock.elapsed().as_secs_f64());
            }
        };
        let grid = frequencies(size.omega_min, size.omega_max, size.analytic_points);
        let analytic: Vec<AnalyticPoint> =
            parallel_map_even(&grid, progress.then_some("analytic"), |&w| {
                analyse(scene, w, false)
            })
            .into_iter()
            .filter_map(Result::ok)
            .collect();

        lap("analytic grid");
        let grid = frequencies(size.omega_min, size.omega_max, size.compared_points);
        let results = parallel_map(&grid, progress.then_some("both solvers"), |&w| {
            compare_with(scene, w, options, size.start_on_orbits).map_err(|e| (w, e.to_string()))
        });
        let mut compared = Vec::new();
        let mut failures = Vec::new();
        for r in results {
            match r {
                Ok(c) => compared.push(c),
                Err(f) => failures.push(f),
            }
        }

        lap("both solvers");
        let grid = frequencies(size.omega_min, size.omega_max, size.bifurcation_points);
        let down_grid: Vec<f64> = grid.iter().rev().copied().collect();
        let directions = [grid, down_grid];
        let mut sweeps = parallel_map(&directions, None, |g| continuation(scene, g, options));
        let bifurcation_down = sweeps.pop().unwrap_or_default();
        let bifurcation_up = sweeps.pop().unwrap_or_default();

        lap("bifurcation sweeps");
        let (family, confirmations) = match scene.stops {
            Some(stops) => family(scene, stops, size.beta_points, options),
            None => (Vec::new(), Vec::new()),
        };
        lap("family");
        Study {
            scene: scene.clone(),
            size,
            analytic,
            compared,
            failures,
            bifurcation_up,
            bifurcation_down,
            family,
            confirmations,
        }
    }

    /// The simulated from-rest points of the compared sweep.
    pub fn simulated(&self) -> Vec<SimulatedPoint> {
        self.compared.iter().map(|c| c.from_rest.clone()).collect()
    }
}

/// Sequential sweep over `omegas`, each frequency started from the previous one's final state
/// at the same forcing phase; returns the stroboscopic `u_o` of each steady state.
fn continuation(scene: &Scene, omegas: &[f64], options: &SimulationOptions) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    let mut start = Start::rest(2);
    let mut last_omega = omegas.first().copied().unwrap_or(1.0);
    for &omega in omegas {
        // Keep the forcing phase: θ = ω_old t_old = ω_new t_new.
        start.time *= last_omega / omega;
        last_omega = omega;
        let Ok(sim) = run(scene, omega, &start, options) else {
            continue;
        };
        if sim.regime != Regime::Undecided {
            let shown = sim.steady.stroboscopic.len().min(16);
            for x in sim.steady.stroboscopic.iter().rev().take(shown) {
                out.push((omega, x[0]));
            }
        }
        start = sim.steady.final_state.clone();
    }
    out
}

/// The family curves for [`FAMILY_OMEGAS`] and simulated confirmations of some stable viable
/// members (gap set to `Δ*(β)`, started on the orbit, impact spacing measured).
fn family(
    scene: &Scene,
    stops: StopsSpec,
    beta_points: usize,
    options: &SimulationOptions,
) -> (Vec<FamilyCurve>, Vec<Confirmation>) {
    let unit = scene.unit_model();
    let ug = unit.base_amplitude;
    let betas: Vec<f64> = (1..=beta_points)
        .map(|j| j as f64 / (beta_points + 1) as f64)
        .collect();
    let mut curves = Vec::new();
    let mut checks = Vec::new();
    for &omega in &FAMILY_OMEGAS {
        let points: Vec<_> = betas
            .iter()
            .filter_map(|&b| gap_for_beta(&unit, stops.restitution, omega, b).ok())
            .collect();
        let members = points
            .iter()
            .map(|p| Member {
                beta: p.beta,
                gap_ratio: p.gap / ug,
                viable: p.orbit.viable,
                stable: p.orbit.stable,
            })
            .collect();
        // Up to three stable viable members, spread over the curve.
        let good: Vec<_> = points
            .iter()
            .filter(|p| p.orbit.viable && p.orbit.stable)
            .collect();
        for k in [1, 3, 5] {
            if let Some(p) = good.get(good.len() * k / 6) {
                checks.push((omega, (*p).clone()));
            }
        }
        curves.push(FamilyCurve { omega, members });
    }
    let confirmations = parallel_map(&checks, None, |(omega, p)| {
        let mut s = scene.clone();
        s.stops = Some(StopsSpec {
            gap: p.gap,
            restitution: stops.restitution,
        });
        let start = start_on_orbit(&s, &p.orbit, crate::classify::START_PERTURBATION);
        let measured = run(&s, *omega, &start, options)
            .ok()
            .filter(|sim| sim.regime == Regime::TwoImpact)
            .and_then(|sim| crate::classify::symmetric_spacing(&sim));
        Confirmation {
            omega: *omega,
            gap_ratio: p.gap / ug,
            beta: p.beta,
            measured_beta: measured,
        }
    });
    (curves, confirmations)
}

/// Stroboscopic `u_o(kT)` (base phase 0) of an analytic symmetric orbit.
pub fn stroboscopic_outer(scene: &Scene, orbit: &rattle_analytic::Orbit) -> f64 {
    let flow = ForcedFlow::new(&scene.unit_model(), orbit.omega);
    let period = flow.period();
    // t since the side-1 impact at which ω t + α ≡ 0.
    let t = (-orbit.alpha / orbit.omega).rem_euclid(period);
    let half = orbit.beta * period;
    let p0 = Vector2::new(orbit.alpha.cos(), orbit.alpha.sin());
    if t <= half {
        flow.transition(t).apply(&orbit.state_after_impact, &p0).0[0]
    } else {
        // Second flight of a symmetric orbit: u(t) = −u(t − T/2).
        let x: Vector4<f64> = flow
            .transition(t - half)
            .apply(&orbit.state_after_impact, &p0)
            .0;
        -x[0]
    }
}

/// Frequencies of the paper's Figure 4.
pub const FIGURE4_OMEGAS: [f64; 2] = [1.0, 2.0];

/// The rows of the impact-time-response figure (the paper's Figure 4).
pub fn impact_rows(scene: &Scene, options: &SimulationOptions) -> Vec<ImpactRow> {
    let unit = scene.unit_model();
    FIGURE4_OMEGAS
        .iter()
        .map(|&omega| {
            let period = std::f64::consts::TAU / omega;
            let n = 400;
            let times: Vec<f64> = (0..=n)
                .map(|k| 2.0 * period * k as f64 / n as f64)
                .collect();
            let lin = rattle_analytic::linear_response(&unit, omega);
            let at = |a: nalgebra::Complex<f64>, t: f64| {
                (a * nalgebra::Complex::new(0.0, omega * t).exp()).re
            };
            let linear: Samples = times
                .iter()
                .map(|&t| (t, at(lin.outer, t), at(lin.inner, t)))
                .collect();
            let point = analyse(scene, omega, false).ok();
            let orbit = point.and_then(|p| {
                let mut viable: Vec<_> = p
                    .orbits
                    .into_iter()
                    .map(|(_, o)| o)
                    .filter(|o| o.viable)
                    .collect();
                viable.sort_by_key(|o| !o.stable);
                viable.into_iter().next()
            });
            let mut opts = options.clone();
            opts.record_trajectory = true;
            match orbit {
                Some(o) => {
                    let flow = ForcedFlow::new(&unit, omega);
                    let p0 = Vector2::new(o.alpha.cos(), o.alpha.sin());
                    let half = 0.5 * period;
                    let curve: Samples = times
                        .iter()
                        .map(|&t| {
                            let local = t.rem_euclid(period);
                            let (sign, tau) = if local <= half {
                                (1.0, local)
                            } else {
                                (-1.0, local - half)
                            };
                            let x = flow.transition(tau).apply(&o.state_after_impact, &p0).0 * sign;
                            (t, x[0], x[1])
                        })
                        .collect();
                    opts.fixed_periods = Some(40);
                    let start = start_on_orbit(scene, &o, crate::classify::START_PERTURBATION);
                    let simulated = run(scene, omega, &start, &opts)
                        .map(|sim| last_periods(&sim, period, o.alpha / omega))
                        .unwrap_or_default();
                    ImpactRow {
                        omega,
                        linear,
                        orbit: Some(curve),
                        simulated,
                        note: format!(
                            "two-impact orbit ({}), simulated points on it",
                            if o.stable { "stable" } else { "unstable" }
                        ),
                    }
                }
                None => {
                    opts.fixed_periods = Some(400);
                    let sim = run(scene, omega, &Start::rest(2), &opts);
                    let (simulated, words) = match sim {
                        Ok(sim) => (last_periods(&sim, period, 0.0), sim.regime.words()),
                        Err(_) => (Vec::new(), "simulation failed"),
                    };
                    ImpactRow {
                        omega,
                        linear,
                        orbit: None,
                        simulated,
                        note: format!("no viable two-impact orbit; simulated from rest: {words}"),
                    }
                }
            }
        })
        .collect()
}

/// The last two forcing periods of a recorded trajectory, on the clock `t − offset` shifted
/// into `[0, 2T)`.
fn last_periods(sim: &SimulatedPoint, period: f64, offset: f64) -> Samples {
    let Some(traj) = sim.steady.trajectory.as_ref() else {
        return Vec::new();
    };
    let end = traj.last().map_or(0.0, |p| p.0);
    let first = traj.first().map_or(0.0, |p| p.0);
    let from = (end - 2.0 * period).max(first);
    let shift = ((from - offset) / period).floor() * period + offset;
    traj.iter()
        .filter(|p| p.0 >= from)
        .map(|(t, x)| {
            (
                t - shift
                    - if t - shift >= 2.0 * period {
                        2.0 * period
                    } else {
                        0.0
                    },
                x[0],
                x[1],
            )
        })
        .collect()
}
