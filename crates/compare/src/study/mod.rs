//! The study behind `cargo xtask figures`: everything the figures and the validation report
//! show, computed once from one scene. [`plots`] holds each figure's data, [`paper`] the
//! paper's claims and numbers, [`report`] the validation outputs.

pub mod boundaries;
pub mod broadband;
pub mod chain;
pub mod chaos;
pub mod damper;
pub mod gallery;
pub mod paper;
pub mod plots;
pub mod report;
pub mod signals;

use crate::runs::axis::Axis;
use crate::runs::continuation::Branches;
use crate::runs::map::{Map, MapGrid, MapSettings};
use crate::runs::parallel::{for_each_block, parallel_map, Grain, Progress};
use crate::scene::analytic::orbits_of_signature;
use crate::scene::analytic::{analyse, AnalyticPoint, OrbitSearch};
use crate::scene::simulator::{run, start_on_orbit, Regime, SimulatedPoint, START_PERTURBATION};
use crate::scene::{DampingSpec, Scene, StopsSpec};
use crate::verdict::{compare, ComparedPoint, Starts, MATCH_TOLERANCE};
use plots::{
    linear_samples, orbit_samples, stroboscopic_outer, Agreement, AgreementPoint, BandwidthMap,
    BetaFamily, Bifurcation, Confirmation, FrequencyResponse, ImpactRow, ImpactTimeResponse,
    LinearPanel, LinearTimeResponse, Member, Plots, RegimeMap, Samples, Transmittance,
};
use rattle_analytic::gap_for_beta;
use rattle_analytic::ContinuationSettings;
use rattle_analytic::{Signature, SignatureOrbit};
use rattle_event_driven::SimulationOptions;
use std::sync::mpsc::{Receiver, Sender};

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
    /// Whether to continue the branches of the frequency response.
    pub continuation: bool,
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
            continuation: true,
        }
    }

    /// Half the compared frequencies, without the bifurcation sweeps, the family, the starts
    /// on the orbits and the continuation: what a second reading of the scene needs for the report (bands,
    /// Figure 4).
    pub fn without_extras(self) -> Self {
        Self {
            compared_points: self.compared_points.div_ceil(2),
            bifurcation_points: 0,
            beta_points: 0,
            start_on_orbits: false,
            continuation: false,
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
            continuation: true,
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
    /// Branches continued in ω from the symmetric two-impact orbits and from the analytic orbit
    /// of every periodic simulated motion of the compared sweep.
    pub branches: Branches,
}

/// Frequencies at which the `+-` orbits seed the study's continuation: one in each region of
/// the paper unit's axis (below ω₁, between the modes, around the anti-resonance, above ω₂).
pub const TWO_IMPACT_SEEDS: [f64; 4] = [0.5, 1.5, 2.2, 3.0];

/// The study's continuation settings within `[omega_min, omega_max]`: at most
/// [`STUDY_BRANCHES`] branches of [`STUDY_BRANCH_POINTS`] points from each seed, so that
/// the period-doubling cascades of the paper unit (each doubling a branch of twice the
/// impacts) do not dominate `cargo xtask figures`.
pub fn study_continuation(omega_min: f64, omega_max: f64) -> ContinuationSettings {
    ContinuationSettings {
        max_branches: STUDY_BRANCHES,
        max_points_per_branch: STUDY_BRANCH_POINTS,
        ..ContinuationSettings::new(omega_min, omega_max)
    }
}

/// Branches followed from each seed of the study (the seed's own, then switches).
pub const STUDY_BRANCHES: usize = 4;
/// Points per branch in the study (both directions together).
pub const STUDY_BRANCH_POINTS: usize = 1500;

/// The viable `+-` orbits at [`TWO_IMPACT_SEEDS`] within the study's frequencies: the first
/// seeds of the study's continuation.
pub fn two_impact_seeds(scene: &Scene, size: &StudySize) -> Vec<SignatureOrbit> {
    let Ok(two_impact) = Signature::parse("+-", 1) else {
        return Vec::new();
    };
    TWO_IMPACT_SEEDS
        .iter()
        .filter(|&&w| w >= size.omega_min && w <= size.omega_max)
        .flat_map(|&w| orbits_of_signature(scene, w, &two_impact))
        .filter(|o| o.viable)
        .collect()
}

/// The viable analytic orbit of each periodic simulated motion of `compared`, in the compared
/// grid's order: the seeds of the study's continuation after the `+-` orbits.
pub fn compared_seeds(compared: &[ComparedPoint]) -> Vec<SignatureOrbit> {
    compared
        .iter()
        .filter_map(|p| p.cross.analytic.clone())
        .filter(|o| o.viable)
        .collect()
}

/// Every branch through the seeds: the `+-` orbits ([`two_impact_seeds`]), then each batch of
/// seeds `later` delivers ([`compared_seeds`]), in that order, each seed skipped when a branch
/// already followed passes through it. Seeds the continuation refuses are skipped.
///
/// The seeds are followed one after another, each against the branches of those before, so
/// the branches are those of one serial run over all the seeds whatever the thread count;
/// the `+-` seeds are followed while `later` is still being computed. The batches are not
/// waited for without stops or without `size.continuation`. `progress` prints how long the
/// following took and how many branches it added, for each kind of seed.
fn branches(
    scene: &Scene,
    size: &StudySize,
    later: Receiver<Vec<SignatureOrbit>>,
    progress: bool,
) -> Branches {
    let mut out = Branches::default();
    let (Some(stops), true) = (scene.stops_model(), size.continuation) else {
        return out;
    };
    let unit = scene.unit_model();
    let settings = study_continuation(size.omega_min, size.omega_max);
    // A refused seed (Newton fails to restart it) leaves the other seeds' branches; the time
    // spent following and the branches added are told per kind of seed.
    let mut follow = |seeds: &[SignatureOrbit], told: &mut (usize, usize, f64)| {
        let (clock, before) = (std::time::Instant::now(), out.branches.len());
        let _ = out.extend_all(&unit, &stops, seeds, &settings);
        told.0 += seeds.len();
        told.1 += out.branches.len() - before;
        told.2 += clock.elapsed().as_secs_f64();
    };
    let tell = |what: &str, (seeds, branches, seconds): (usize, usize, f64)| {
        if progress {
            eprintln!("  continuation from {seeds} {what}: {seconds:.1} s, {branches} branches");
        }
    };
    let mut told = (0, 0, 0.0);
    follow(&two_impact_seeds(scene, size), &mut told);
    tell("`+-` seeds", told);
    let mut told = (0, 0, 0.0);
    for seeds in later {
        follow(&seeds, &mut told);
    }
    tell("seeds of the compared sweep", told);
    out
}

/// `work()`, printing `label` and how long it took when `progress` is on.
fn timed<T>(label: &str, progress: bool, work: impl FnOnce() -> T) -> T {
    let clock = std::time::Instant::now();
    let out = work();
    if progress {
        eprintln!("  {label}: {:.1} s", clock.elapsed().as_secs_f64());
    }
    out
}

/// The analytic picture of `scene` on the study's fine grid.
fn analytic_grid(scene: &Scene, size: &StudySize, progress: &Progress) -> Vec<AnalyticPoint> {
    let grid = Axis::new(size.omega_min, size.omega_max, size.analytic_points).values();
    parallel_map(&grid, Grain::Even, progress, |&w| {
        analyse(scene, w, OrbitSearch::Symmetric)
    })
    .into_iter()
    .filter_map(Result::ok)
    .collect()
}

/// Frequencies of the compared sweep per block: after each block, the seeds of its periodic
/// motions go to the continuation, which follows them while the next blocks are compared (ten
/// blocks over the 400 frequencies of [`StudySize::full`]).
pub const COMPARED_BLOCK: usize = 40;

/// Both solvers on the study's compared grid: the points compared and the frequencies that
/// failed, with the reason. After each block of [`COMPARED_BLOCK`] frequencies, its
/// [`compared_seeds`] are sent to `seeds` (the order of the grid kept); a closed channel
/// (the continuation needs no seeds) is no failure.
fn compared_sweep(
    scene: &Scene,
    size: &StudySize,
    options: &SimulationOptions,
    progress: &Progress,
    seeds: &Sender<Vec<SignatureOrbit>>,
) -> (Vec<ComparedPoint>, Vec<(f64, String)>) {
    let grid = Axis::new(size.omega_min, size.omega_max, size.compared_points).values();
    let starts = if size.start_on_orbits {
        Starts::RestAndOrbits
    } else {
        Starts::Rest
    };
    let mut compared = Vec::new();
    let mut failures = Vec::new();
    for_each_block(
        &grid,
        Grain::Uneven,
        COMPARED_BLOCK,
        progress,
        |&w| compare(scene, w, options, starts).map_err(|e| (w, e.to_string())),
        |block| {
            let first = compared.len();
            for r in block {
                match r {
                    Ok(c) => compared.push(c),
                    Err(f) => failures.push(f),
                }
            }
            let _ = seeds.send(compared_seeds(&compared[first..]));
        },
    );
    (compared, failures)
}

/// Stroboscopic `(ω, u_o)` points of a sweep.
type Stroboscopic = Vec<(f64, f64)>;

/// The stroboscopic sweeps up and down the study's bifurcation grid (each sequential, the two
/// in parallel).
fn bifurcation_sweeps(
    scene: &Scene,
    size: &StudySize,
    options: &SimulationOptions,
) -> (Stroboscopic, Stroboscopic) {
    let grid = Axis::new(size.omega_min, size.omega_max, size.bifurcation_points).values();
    let down_grid: Vec<f64> = grid.iter().rev().copied().collect();
    rayon::join(
        || continuation(scene, &grid, options),
        || continuation(scene, &down_grid, options),
    )
}

impl Study {
    /// Runs the study; `progress` draws progress bars on a terminal and prints how long each
    /// part took.
    ///
    /// The parts run concurrently: the continuation of the branches on a thread of its own
    /// (from the start, beginning with the `+-` seeds; the seeds of each block of the compared
    /// sweep follow as soon as the block is done), the analytic grid and the compared sweep
    /// beside the bifurcation sweeps and the family, on rayon's threads. Every part is sequential where its result depends
    /// on an order, so the study does not depend on the number of threads.
    ///
    /// # Panics
    /// When a part panics (the panic is carried on).
    pub fn run(
        scene: &Scene,
        size: StudySize,
        options: &SimulationOptions,
        progress: bool,
    ) -> Study {
        let bar = |label: &str, n: usize| Progress::new(label, n, progress);
        let (seeds, later) = std::sync::mpsc::channel();
        std::thread::scope(|threads| {
            let follower = threads.spawn(|| {
                timed("continuation", progress, || {
                    branches(scene, &size, later, progress)
                })
            });
            let (
                (analytic, (compared, failures)),
                ((bifurcation_up, bifurcation_down), (family, confirmations)),
            ) = rayon::join(
                || {
                    let analytic = timed("analytic grid", progress, || {
                        analytic_grid(scene, &size, &bar("analytic", size.analytic_points))
                    });
                    let compared = timed("both solvers", progress, || {
                        compared_sweep(
                            scene,
                            &size,
                            options,
                            &bar("both solvers", size.compared_points),
                            &seeds,
                        )
                    });
                    // The last seeds are sent: the follower ends with them.
                    drop(seeds);
                    (analytic, compared)
                },
                || {
                    rayon::join(
                        || {
                            timed("bifurcation sweeps", progress, || {
                                bifurcation_sweeps(scene, &size, options)
                            })
                        },
                        || {
                            timed("family", progress, || match scene.stops {
                                Some(stops) => family(scene, stops, size.beta_points, options),
                                None => (Vec::new(), Vec::new()),
                            })
                        },
                    )
                },
            );
            let branches = follower
                .join()
                .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
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
                branches,
            }
        })
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
    let mut start = crate::scene::simulator::rest(scene);
    let mut last_omega = omegas.first().copied().unwrap_or(1.0);
    for &omega in omegas {
        // Keep the forcing phase: θ = ω_old t_old = ω_new t_new.
        start.time *= last_omega / omega;
        last_omega = omega;
        let Ok(sim) = run(scene, omega, &start, options) else {
            continue;
        };
        if sim.regime != Regime::NoDissipation {
            let shown = sim.steady.stroboscopic.len().min(16);
            for x in sim.steady.stroboscopic.iter().rev().take(shown) {
                out.push((omega, x[0]));
            }
        }
        start = sim.steady.final_state.clone();
    }
    out
}

/// The family curves for [`paper::FAMILY_OMEGAS`] and simulated confirmations of some stable viable
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
    for &omega in &paper::FAMILY_OMEGAS {
        let points: Vec<_> = betas
            .iter()
            .filter_map(|&b| gap_for_beta(&unit, stops.rigid_restitution(), omega, b).ok())
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
    let confirmations = parallel_map(&checks, Grain::Uneven, &Progress::hidden(), |(omega, p)| {
        let mut s = scene.clone();
        s.stops = Some(StopsSpec::rigid(p.gap, stops.rigid_restitution()));
        let start = start_on_orbit(&s, &p.orbit, START_PERTURBATION);
        let measured = run(&s, *omega, &start, options)
            .ok()
            .filter(|sim| sim.regime == Regime::TwoImpact)
            .and_then(|sim| sim.impact_spacing());
        Confirmation {
            omega: *omega,
            gap_ratio: p.gap / ug,
            beta: p.beta,
            measured_beta: measured,
        }
    });
    (curves, confirmations)
}

/// Grid sizes of the two maps.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MapSizes {
    /// Restitutions of the bandwidth map, over `[0, 1]`.
    pub restitutions: usize,
    /// Gaps of both maps, over `Δ/u_g ∈ [0.05, 1]`.
    pub gaps: usize,
    /// Frequencies of the bandwidth map's lines, over `[0.1, 4]` rad/s.
    pub bandwidth_points: usize,
    /// Frequencies of the regime map, over `[0.1, 4]` rad/s.
    pub regime_points: usize,
}

impl MapSizes {
    /// The grids of `cargo xtask figures` (`rattle map` runs finer grids): the bandwidth map
    /// 11 × 16 × 80 (steps 0.1 in e, the paper's 0.8 included, 0.063 in Δ/u_g, 0.049 rad/s),
    /// the regime map 16 × 300 (0.013 rad/s). A bandwidth map twice as fine (21 × 16 × 160)
    /// would alone cost about 50 s of CPU (3.8 times this one's 13 s), more than the whole
    /// command's 30 s on two cores.
    pub fn full() -> MapSizes {
        MapSizes {
            restitutions: 11,
            gaps: 16,
            bandwidth_points: 80,
            regime_points: 300,
        }
    }

    /// A few points of everything.
    pub fn quick() -> MapSizes {
        MapSizes {
            restitutions: 3,
            gaps: 3,
            bandwidth_points: 20,
            regime_points: 20,
        }
    }
}

/// The light dashpots the maps add to an undamped scene, N·s/m: those of
/// `data/scenes/paper-damped.json`.
pub const MAP_DAMPING: DampingSpec = DampingSpec {
    outer: 0.1,
    inner: 0.05,
};

/// The gaps of both maps, `Δ/u_g`.
const MAP_GAPS: (f64, f64) = (0.05, 1.0);

/// The frequencies of both maps, rad/s.
const MAP_OMEGAS: (f64, f64) = (0.1, 4.0);

/// The scene the maps are drawn for: `scene` itself when it is damped; otherwise the same
/// unit with [`MAP_DAMPING`], because without damping no motion clear of the stops ever
/// settles and there would be no transmittance to map there. The name says which.
pub fn map_scene(scene: &Scene) -> Scene {
    if scene.is_damped() {
        return scene.clone();
    }
    let mut damped = scene.clone();
    damped.damping = Some(MAP_DAMPING);
    damped.name = format!("{} + light damping", scene.name);
    damped
}

/// The bandwidth map (over restitution and gap) and the regime map (over frequency and gap at
/// the scene's restitution) of [`map_scene`]`(scene)`, computed at once; `None` without stops.
pub fn maps(scene: &Scene, sizes: MapSizes, progress: bool) -> Option<(Map, Map)> {
    let restitution = scene.stops?.restitution?;
    let scene = map_scene(scene);
    let settings = MapSettings::default();
    let gaps = Axis::new(MAP_GAPS.0, MAP_GAPS.1, sizes.gaps);
    let bandwidth_grid = MapGrid {
        restitution: Axis::new(0.0, 1.0, sizes.restitutions),
        gap_over_base_amplitude: gaps,
        omega: Axis::new(MAP_OMEGAS.0, MAP_OMEGAS.1, sizes.bandwidth_points),
    };
    let regime_grid = MapGrid {
        restitution: Axis::new(restitution, restitution, 1),
        gap_over_base_amplitude: gaps,
        omega: Axis::new(MAP_OMEGAS.0, MAP_OMEGAS.1, sizes.regime_points),
    };
    // The bandwidth map shows no regime: no exponents there.
    let bandwidth_settings = MapSettings {
        lyapunov_periods: None,
        ..settings.clone()
    };
    let run = |grid: MapGrid, settings: &MapSettings, label: &str| {
        let lines = grid.restitution.count * grid.gap_over_base_amplitude.count;
        Map::run(
            &scene,
            grid,
            settings,
            &Progress::new(label, lines, progress),
        )
    };
    // Both grids are valid by construction and the scene has stops. The two maps run at once
    // (each map's lines in parallel, each line sequential: the maps do not depend on it).
    let (bandwidth, regimes) = rayon::join(
        || run(bandwidth_grid, &bandwidth_settings, "bandwidth map"),
        || run(regime_grid, &settings, "regime map"),
    );
    Some((bandwidth.ok()?, regimes.ok()?))
}

impl Study {
    /// Every figure's data: this study's, Figures 2 and 4 simulated with `options`, and the
    /// figures of `maps` when given.
    pub fn plots(&self, options: &SimulationOptions, maps: Option<&(Map, Map)>) -> Plots {
        let scene = &self.scene;
        let name = scene.name.clone();
        let gap = scene.gap().unwrap_or(0.0);
        let (claimed_bands, claimed_marks) = paper::claims();
        let analytic = self
            .analytic
            .iter()
            .flat_map(|p| p.orbits.iter().filter(|(_, o)| o.viable))
            .map(|(_, o)| (o.omega, stroboscopic_outer(scene, o), o.stable))
            .collect();
        Plots {
            linear_time_response: LinearTimeResponse {
                scene_name: name.clone(),
                gap,
                panels: paper::FIGURE2_OMEGAS
                    .iter()
                    .filter_map(|&w| analyse(scene, w, OrbitSearch::Symmetric).ok())
                    .map(|p| LinearPanel {
                        omega: p.omega,
                        samples: linear_samples(&p),
                        outer_amplitude: p.linear.outer_amplitude,
                        inner_amplitude: p.linear.inner_amplitude,
                    })
                    .collect(),
            },
            impact_time_response: ImpactTimeResponse {
                scene_name: name.clone(),
                gap,
                rows: impact_rows(scene, options),
            },
            transmittance: Transmittance {
                scene_name: name.clone(),
                analytic: self.analytic.clone(),
                simulated: self.simulated(),
                claimed_bands,
                claimed_marks,
            },
            frequency_response: FrequencyResponse::new(
                &name,
                &self.analytic,
                &self.branches,
                &self.compared,
            ),
            agreement: Agreement {
                scene_name: name.clone(),
                points: self.compared.iter().map(AgreementPoint::of).collect(),
                tolerance: MATCH_TOLERANCE,
            },
            beta_family: BetaFamily {
                scene_name: name.clone(),
                restitution: scene.stops.map_or(f64::NAN, |s| s.rigid_restitution()),
                curves: self
                    .family
                    .iter()
                    .map(|c| (c.omega, c.members.clone()))
                    .collect(),
                confirmations: self.confirmations.clone(),
                non_viable_bound: paper::NON_VIABLE_BETA,
            },
            bifurcation: Bifurcation {
                scene_name: name,
                omega_range: (self.size.omega_min, self.size.omega_max),
                up: self.bifurcation_up.clone(),
                down: self.bifurcation_down.clone(),
                analytic,
            },
            maps: maps.map(|(b, r)| (BandwidthMap::of(b), RegimeMap::of(r))),
        }
    }
}

/// Periods the Figure 4 simulation runs when started on the orbit (the nudge decays well
/// below a pixel), and from rest when there is no orbit (long enough for the paper's unit's
/// slowest transients).
const FIGURE4_PERIODS: (u64, u64) = (40, 400);

/// The rows of the impact-time-response figure (the paper's Figure 4).
fn impact_rows(scene: &Scene, options: &SimulationOptions) -> Vec<ImpactRow> {
    paper::FIGURE4_OMEGAS
        .iter()
        .filter_map(|&omega| {
            let point = analyse(scene, omega, OrbitSearch::Symmetric).ok()?;
            let period = std::f64::consts::TAU / omega;
            let linear = linear_samples(&point);
            let mut viable: Vec<_> = point
                .orbits
                .into_iter()
                .map(|(_, o)| o)
                .filter(|o| o.viable)
                .collect();
            viable.sort_by_key(|o| !o.stable);
            let mut opts = options.clone();
            opts.record_trajectory = true;
            Some(match viable.into_iter().next() {
                Some(o) => {
                    opts.fixed_periods = Some(FIGURE4_PERIODS.0);
                    let start = start_on_orbit(scene, &o, START_PERTURBATION);
                    let simulated = run(scene, omega, &start, &opts)
                        .map(|sim| last_periods(&sim, period, o.alpha / omega))
                        .unwrap_or_default();
                    ImpactRow {
                        omega,
                        linear,
                        orbit: Some(orbit_samples(scene, &o)),
                        simulated,
                        note: format!(
                            "two-impact orbit ({}), simulated points on it",
                            if o.stable { "stable" } else { "unstable" }
                        ),
                    }
                }
                None => {
                    opts.fixed_periods = Some(FIGURE4_PERIODS.1);
                    let (simulated, words) =
                        match run(scene, omega, &crate::scene::simulator::rest(scene), &opts) {
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
            })
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
