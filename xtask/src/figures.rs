//! `cargo xtask figures`: every figure, the maps' tables and the validation report.

use crate::root;
use clap::Args;
use rattle_compare::api::TransmissionRequest;
use rattle_compare::figures;
use rattle_compare::output::{write_table, Format, Header};
use rattle_compare::peers::siconos::{SiconosPeer, SICONOS_DATA};
use rattle_compare::peers::work_precision::{self, WorkPrecision};
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::basins::{basin_options, BasinGrid, Basins};
use rattle_compare::runs::map::Map;
use rattle_compare::runs::parallel::Progress;
use rattle_compare::scene::simulator::run as simulate;
use rattle_compare::scene::{Scene, StopsSpec};
use rattle_compare::study::boundaries::{study_boundaries, StudyBoundaries};
use rattle_compare::study::broadband::{
    broadband_case, broadband_section, broadband_setups, BroadbandStudy,
};
use rattle_compare::study::chain::{chain_section, chain_study, ChainStudy};
use rattle_compare::study::chaos::{
    chaos_samples, poincare_sections, ChaosSample, PoincareSections, POINCARE_OMEGA,
    POINCARE_POINTS,
};
use rattle_compare::study::damper::{
    damper_study, DamperStudy, DAMPER_BRANCH_POINTS, DAMPER_POINTS,
};
use rattle_compare::study::gallery::{
    oscillator_study, OscillatorStudy, BRANCH_POINTS, OSCILLATOR_POINTS,
};
use rattle_compare::study::paper::READING_B_GAP_FACTOR;
use rattle_compare::study::report::{agreement, report, siconos_section};
use rattle_compare::study::signals::{signal_study, signals_section, SignalStudy};
use rattle_compare::study::{maps, MapSizes, Study, StudySize};
use rattle_event_driven::SimulationOptions;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Flags of `cargo xtask figures`.
#[derive(Debug, Args)]
pub struct FiguresArgs {
    /// Scene file (JSON); default: the built-in paper scene.
    #[arg(long)]
    scene: Option<PathBuf>,
    /// A few points of everything (a smoke test of the pipeline).
    #[arg(long)]
    quick: bool,
    /// Write `DIR/figures`, `DIR/data/maps` and `DIR/validation` instead of the repository's.
    #[arg(long, value_name = "DIR")]
    out: Option<PathBuf>,
}

/// The accuracy-versus-cost case: the damped paper scene at 2 rad/s, where the simulator from
/// rest settles on the analytic stable viable orbit (max|μ| = 0.855: 300 periods bring the
/// transient below 1e-16).
const WORK_PRECISION_SCENE: &str = "data/scenes/paper-damped.json";
/// Frequency of the work-precision case, rad/s.
const WORK_PRECISION_OMEGA: f64 = 2.0;
/// Periods both integrators run from rest in the work-precision study.
const WORK_PRECISION_PERIODS: u64 = 300;
/// Frequencies of the sweep-cost study, rad/s.
const SWEEP_COST_RANGE: (f64, f64) = (0.5, 4.0);
/// Period cap of the study's simulations: keeps the full study within a minute on two cores;
/// points that need longer to settle are reported as not periodic (the report counts them).
const STUDY_MAX_PERIODS: u64 = 4000;
/// Frequencies at which the fully elastic, undamped unit is simulated for the report, rad/s.
const ELASTIC_OMEGAS: [f64; 2] = [1.0, 2.0];

/// Frequency of the basins figure, rad/s: on the paper's unit (Δ = 0.5, e = 0.8, undamped)
/// the starts at rest split there between a four-impact motion `++--` (39 971 of 40 000), the
/// symmetric two-impact orbit `+-` (16) and motions that do not repeat within the cap (13)
/// (`rattle basins --omega 1.9 … --points 200`, ±1.5 m; at the coexistence frequency 1.86 of
/// the hard cases nearly every start at rest reaches `++--`).
const BASINS_OMEGA: f64 = 1.9;
/// Half-width of the basins grid in both displacements, m: three gaps either side.
const BASINS_EXTENT: f64 = 1.5;
/// Starts per side of the basins grid: the 200 × 200, 10.7 s of `cargo xtask figures`
/// (12.1–14.5 s for `rattle basins --points 200` on two threads, whole process, with the
/// machine about a quarter slower than quiet; 90 × 90 took 7.7 s before every start was
/// watched at every period).
const BASINS_POINTS: usize = 200;

/// Frequencies of the Lyapunov figure over the paper's axis 0.1–4 rad/s (step 0.02 rad/s);
/// each non-periodic point runs 2000 periods of exponents, periodic ones take theirs from
/// their Floquet multipliers (the Newton polish, on for this run).
const LYAPUNOV_POINTS: usize = 196;

fn size_lyapunov(quick: bool) -> usize {
    if quick {
        8
    } else {
        LYAPUNOV_POINTS
    }
}

fn size_basins(quick: bool) -> usize {
    if quick {
        10
    } else {
        BASINS_POINTS
    }
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

/// The clock of one run: each stage's wall time, printed as the stage ends.
struct Clock {
    start: Instant,
}

impl Clock {
    /// `work()`, printing `label`, its wall time and when it started and ended on this clock.
    fn stage<T>(&self, label: &str, work: impl FnOnce() -> T) -> T {
        let from = self.start.elapsed().as_secs_f64();
        let out = work();
        let to = self.start.elapsed().as_secs_f64();
        eprintln!(
            "{label}: {:.1} s (from {from:.1} s to {to:.1} s)",
            to - from
        );
        out
    }
}

/// CPU time (user + system) of this process so far, seconds, from `/proc/self/stat` (in
/// clock ticks of 1/100 s, Linux's `USER_HZ`); `None` where that file is not.
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    // The fields after the command name (which may hold spaces) in parentheses: the state is
    // field 3; utime and stime are fields 14 and 15.
    let fields: Vec<&str> = stat.rsplit_once(')')?.1.split_whitespace().collect();
    let ticks = |k: usize| fields.get(k - 3)?.parse::<f64>().ok();
    Some((ticks(14)? + ticks(15)?) / 100.0)
}

/// Everything the figures and the report show, but the work-precision study.
struct Computed {
    main: Study,
    other: Study,
    elastic_note: String,
    maps: Option<(Map, Map)>,
    basins: Basins,
    samples: Vec<ChaosSample>,
    poincare: Result<PoincareSections, String>,
    chains: ChainStudy,
    boundaries: StudyBoundaries,
    oscillator: OscillatorStudy,
    damper: DamperStudy,
    signals: Result<SignalStudy, String>,
    broadband: Result<BroadbandStudy, String>,
}

/// The scene's copy with the gap of the study's second reading.
fn reading_b(scene: &Scene) -> Scene {
    let mut other = scene.clone();
    other.name = format!("{} (half gap)", scene.name);
    other.stops = scene.stops.map(|s| StopsSpec {
        gap: READING_B_GAP_FACTOR * s.gap,
        ..s
    });
    other
}

/// Every stage but the work-precision study, all at once: rayon shares the threads between
/// them (and the study's continuation has a thread of its own, see [`Study::run`]). Each
/// stage's result does not depend on the order the stages run in or on the thread count.
fn compute(scene: &Scene, quick: bool, clock: &Clock) -> Computed {
    let (size, map_sizes) = if quick {
        (StudySize::quick(), MapSizes::quick())
    } else {
        (StudySize::full(), MapSizes::full())
    };
    let options = SimulationOptions {
        max_periods: STUDY_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let (mut main, mut other, mut elastic, mut maps_done) = (None, None, None, None);
    let (mut basins, mut samples, mut poincare, mut chains) = (None, None, None, None);
    let (mut boundaries, mut oscillator, mut damper) = (None, None, None);
    let (mut signals, mut broadband) = (None, None);
    // Stages handed out longest first: another thread takes the earliest spawned, this one
    // the latest.
    rayon::scope(|s| {
        s.spawn(|_| {
            // Its parts' times printed (indented) as they end.
            let study = clock.stage("study, reading A", || {
                Study::run(scene, size, &options, true)
            });
            // The events of the study's own continuation, each followed over the gap and the
            // restitution.
            boundaries = Some(clock.stage("boundaries", || study_boundaries(&study, quick)));
            main = Some(study);
        });
        s.spawn(|_| maps_done = Some(clock.stage("maps", || maps(scene, map_sizes, false))));
        s.spawn(|_| basins = Some(clock.stage("basins", || basins_of(scene, quick))));
        s.spawn(|_| {
            other = Some(clock.stage("study, reading B", || {
                Study::run(&reading_b(scene), size.without_extras(), &options, false)
            }))
        });
        s.spawn(|_| samples = Some(clock.stage("lyapunov", || lyapunov_samples(scene, quick))));
        s.spawn(|_| chains = Some(clock.stage("chains", || chain_study(scene, quick, false))));
        s.spawn(|_| poincare = Some(clock.stage("poincare", || poincare_of(scene, quick))));
        s.spawn(|_| elastic = Some(clock.stage("elastic note", || elastic_note(scene, &options))));
        s.spawn(|_| {
            oscillator = Some(clock.stage("impact oscillator", || {
                let (points, branch) = if quick {
                    (12, 200)
                } else {
                    (OSCILLATOR_POINTS, BRANCH_POINTS)
                };
                oscillator_study(points, branch)
            }))
        });
        s.spawn(|_| {
            damper = Some(clock.stage("impact dampers", || {
                let (points, branch) = if quick {
                    (12, 100)
                } else {
                    (DAMPER_POINTS, DAMPER_BRANCH_POINTS)
                };
                damper_study(points, branch)
            }))
        });
        s.spawn(|_| {
            broadband =
                Some(clock.stage("broadband transmission", || broadband_study(scene, quick)))
        });
        s.spawn(|_| signals = Some(clock.stage("signals", || signal_study(scene, quick))));
    });
    // Every slot is filled once the scope has ended (a stage's panic is carried on by it).
    let filled = "every stage has run";
    Computed {
        main: main.expect(filled),
        other: other.expect(filled),
        elastic_note: elastic.expect(filled),
        maps: maps_done.expect(filled),
        basins: basins.expect(filled),
        samples: samples.expect(filled),
        poincare: poincare.expect(filled),
        chains: chains.expect(filled),
        boundaries: boundaries.expect(filled),
        oscillator: oscillator.expect(filled),
        damper: damper.expect(filled),
        signals: signals.expect(filled),
        broadband: broadband.expect(filled),
    }
}

/// The broadband study of `scene`: the unit and the chain, each through `rattle
/// transmission`'s estimate at the study's levels, and the answer of each.
fn broadband_study(scene: &Scene, quick: bool) -> Result<BroadbandStudy, String> {
    let cases = broadband_setups(scene, quick)?
        .iter()
        .map(|setup| {
            let request = TransmissionRequest {
                signal: setup.signal.clone(),
                duration: setup.duration,
                options: setup.options.clone(),
            };
            let record = rattle_compare::api::transmission(&setup.scene, &request)
                .map_err(|e| format!("broadband, {}: {e}", setup.label))?;
            Ok(broadband_case(setup, record))
        })
        .collect::<Result<Vec<_>, String>>()?;
    Ok(BroadbandStudy {
        scene_name: scene.name.clone(),
        cases,
    })
}

/// The basins figure's grid at [`BASINS_OMEGA`].
fn basins_of(scene: &Scene, quick: bool) -> Basins {
    let side = Axis::new(-BASINS_EXTENT, BASINS_EXTENT, size_basins(quick));
    rattle_compare::runs::basins::basins(
        scene,
        BASINS_OMEGA,
        BasinGrid {
            outer: side,
            inner: side,
        },
        &basin_options(),
        &Progress::hidden(),
    )
}

/// The Lyapunov figure's samples over the paper's axis.
fn lyapunov_samples(scene: &Scene, quick: bool) -> Vec<ChaosSample> {
    let options = SimulationOptions {
        max_periods: STUDY_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    chaos_samples(
        scene,
        &Axis::new(0.1, 4.0, size_lyapunov(quick)).values(),
        &options,
        &Progress::hidden(),
    )
}

/// The Poincaré figure's sections, with the command's own options (`rattle simulate --omega
/// 1.25 --lyapunov` prints the title's exponents).
fn poincare_of(scene: &Scene, quick: bool) -> Result<PoincareSections, String> {
    poincare_sections(
        scene,
        POINCARE_OMEGA,
        if quick { 500 } else { POINCARE_POINTS },
        rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS,
        &SimulationOptions::default(),
    )
    .map_err(|e| e.to_string())
}

/// The work-precision study, with Siconos's points as `cargo xtask peers` measured them
/// (absent: the figure goes without). It times the solvers, so it runs alone.
fn precision_study(damped: &Scene, siconos: Option<&SiconosPeer>) -> Result<WorkPrecision, String> {
    let options = SimulationOptions {
        max_periods: STUDY_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let mut precision = work_precision::study(
        damped,
        WORK_PRECISION_OMEGA,
        WORK_PRECISION_PERIODS,
        SWEEP_COST_RANGE,
        &options,
    )
    .map_err(|e| e.to_string())?;
    precision.siconos = siconos
        .and_then(|p| {
            p.work_precision_for(
                WORK_PRECISION_SCENE,
                WORK_PRECISION_OMEGA,
                WORK_PRECISION_PERIODS,
            )
        })
        .cloned();
    Ok(precision)
}

/// Writes the maps' tables into `data_dir`.
fn write_maps(maps: &(Map, Map), data_dir: &Path) -> Result<(), String> {
    let (bandwidth, regimes) = maps;
    std::fs::create_dir_all(data_dir).map_err(|e| e.to_string())?;
    write_table(
        &data_dir.join("bandwidth-map.csv"),
        Format::Csv,
        &Header::default(),
        bandwidth.bandwidth_rows(),
    )
    .map_err(|e| e.to_string())?;
    write_table(
        &data_dir.join("regime-map.csv"),
        Format::Csv,
        &Header::default(),
        regimes.point_rows(),
    )
    .map_err(|e| e.to_string())
}

/// Draws every figure of `c` and `precision` into `dir`, in two halves on rayon's threads
/// (the machine's cores are idle once the work-precision study has run); returns the files
/// written, in the same order whatever the thread count.
fn draw_all(c: &Computed, precision: &WorkPrecision, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let (first, second) = rayon::join(|| draw_study(c, precision, dir), || draw_the_rest(c, dir));
    let mut written = first?;
    written.extend(second?);
    Ok(written)
}

/// The study's figures (those of [`Study::plots`]) and the work-precision figure.
fn draw_study(c: &Computed, precision: &WorkPrecision, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let options = SimulationOptions {
        max_periods: STUDY_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let plots = c.main.plots(&options, c.maps.as_ref());
    let mut written = figures::draw(&plots, dir).map_err(|e| e.to_string())?;
    written.extend(figures::draw_work_precision(precision, dir).map_err(|e| e.to_string())?);
    Ok(written)
}

/// The basins, Lyapunov, Poincaré, chain, boundaries, impact oscillator, impact damper and
/// signal figures.
fn draw_the_rest(c: &Computed, dir: &Path) -> Result<Vec<PathBuf>, String> {
    let name = &c.main.scene.name;
    let mut written = figures::draw_basins(
        &figures::basins::BasinsFigure {
            scene_name: name.clone(),
            basins: c.basins.clone(),
        },
        dir,
    )
    .map_err(|e| e.to_string())?;
    written.extend(
        figures::draw_lyapunov(
            &figures::lyapunov::LyapunovFigure {
                scene_name: name.clone(),
                samples: c.samples.clone(),
            },
            dir,
        )
        .map_err(|e| e.to_string())?,
    );
    written.extend(
        figures::draw_poincare(
            &figures::poincare::PoincareFigure {
                scene_name: name.clone(),
                sections: c.poincare.clone()?,
            },
            dir,
        )
        .map_err(|e| e.to_string())?,
    );
    written.extend(figures::draw_chains(&c.chains, dir).map_err(|e| e.to_string())?);
    written.extend(
        figures::draw_boundaries(&c.boundaries.figure(&c.main, c.maps.as_ref()), dir)
            .map_err(|e| e.to_string())?,
    );
    written.extend(figures::draw_impact_oscillator(&c.oscillator, dir).map_err(|e| e.to_string())?);
    written.extend(figures::draw_impact_damper(&c.damper, dir).map_err(|e| e.to_string())?);
    written.extend(
        figures::draw_signals(c.signals.as_ref().map_err(Clone::clone)?, &c.chains, dir)
            .map_err(|e| e.to_string())?,
    );
    written.extend(
        figures::draw_broadband(c.broadband.as_ref().map_err(Clone::clone)?, dir)
            .map_err(|e| e.to_string())?,
    );
    Ok(written)
}

/// Runs the task.
pub fn run(args: FiguresArgs) -> Result<(), String> {
    let scene = match &args.scene {
        Some(path) => Scene::load(path).map_err(|e| e.to_string())?,
        None => Scene::paper(),
    };
    if scene.is_chain() {
        return Err(format!(
            "scene '{}' is a chain of {} cells: the figures are drawn for one cell (the chain \
             figures build their chains of it)",
            scene.name,
            scene.cell_count()
        ));
    }
    let damped = Scene::load(&root().join(WORK_PRECISION_SCENE)).map_err(|e| e.to_string())?;
    let siconos = SiconosPeer::load(&root().join(SICONOS_DATA)).map_err(|e| e.to_string())?;
    let out = args.out.unwrap_or_else(root);
    let clock = Clock {
        start: Instant::now(),
    };
    eprintln!(
        "figures of scene '{}' (reading A: the scene's gap; reading B: half of it); every stage \
         at once, then the work-precision study alone",
        scene.name
    );
    let c = compute(&scene, args.quick, &clock);
    let precision = clock.stage("work-precision", || {
        precision_study(&damped, siconos.as_ref())
    })?;
    let written = clock.stage("figures drawn, tables and report written", || {
        let mut written = draw_all(&c, &precision, &out.join("figures"))?;
        match &c.maps {
            Some(maps) => write_maps(maps, &out.join("data/maps"))?,
            None => eprintln!(
                "no maps: the scene has no stops (a map varies their gap and restitution)"
            ),
        }
        written.extend(c.boundaries.write(&out.join("data/boundaries"))?);
        let validation = out.join("validation");
        let doc = serde_json::to_string_pretty(&agreement(&c.main)).map_err(|e| e.to_string())?;
        write(&validation.join("agreement.json"), &(doc + "\n"))?;
        write(
            &validation.join("report.md"),
            &(report(&c.main, &c.other, &c.elastic_note, &c.samples)
                + &chain_section(&c.chains)
                + &signals_section(c.signals.as_ref().map_err(Clone::clone)?)
                + &broadband_section(c.broadband.as_ref().map_err(Clone::clone)?)
                + &c.boundaries.section(&c.main, c.maps.as_ref())
                + &siconos_section(siconos.as_ref(), &precision)),
        )?;
        Ok::<_, String>(written)
    })?;
    for path in &written {
        eprintln!(
            "wrote {}",
            path.strip_prefix(&out).unwrap_or(path).display()
        );
    }
    if c.maps.is_some() {
        eprintln!("wrote data/maps/bandwidth-map.csv, data/maps/regime-map.csv");
    }
    eprintln!("wrote validation/agreement.json, validation/report.md");
    let cpu = cpu_seconds().map_or(String::new(), |s| format!(", {s:.1} s of CPU"));
    eprintln!(
        "figures done in {:.1} s{cpu}",
        clock.start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// What the simulator says about the scene's unit made fully elastic, at
/// [`ELASTIC_OMEGAS`].
fn elastic_note(scene: &Scene, options: &SimulationOptions) -> String {
    if scene.is_damped() {
        return "the scene is damped: elastic impacts still dissipate through the dashpots".into();
    }
    let mut elastic = scene.clone();
    elastic.stops = scene.stops.map(|s| StopsSpec {
        restitution: Some(1.0),
        ..s
    });
    ELASTIC_OMEGAS
        .iter()
        .map(|&w| {
            match simulate(
                &elastic,
                w,
                &rattle_compare::scene::simulator::rest(&elastic),
                options,
            ) {
                Ok(sim) => format!("ω = {w}: e = 1, no damping → {}", sim.status_name()),
                Err(e) => format!("ω = {w}: {e}"),
            }
        })
        .collect::<Vec<_>>()
        .join("; ")
}
