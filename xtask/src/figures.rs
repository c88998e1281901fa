//! `cargo xtask figures`: every figure, the maps' tables and the validation report.

use crate::root;
use clap::Args;
use rattle_compare::figures;
use rattle_compare::output::{write_table, Format, Header};
use rattle_compare::peers::siconos::{SiconosPeer, SICONOS_DATA};
use rattle_compare::peers::work_precision;
use rattle_compare::runs::axis::Axis;
use rattle_compare::runs::basins::{basin_options, BasinGrid};
use rattle_compare::runs::parallel::Progress;
use rattle_compare::scene::simulator::run as simulate;
use rattle_compare::scene::{Scene, StopsSpec};
use rattle_compare::study::chain::{chain_section, chain_study};
use rattle_compare::study::chaos::{
    chaos_samples, poincare_sections, POINCARE_OMEGA, POINCARE_POINTS,
};
use rattle_compare::study::paper::READING_B_GAP_FACTOR;
use rattle_compare::study::report::{agreement, report, siconos_section};
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
    let (size, map_sizes) = if args.quick {
        (StudySize::quick(), MapSizes::quick())
    } else {
        (StudySize::full(), MapSizes::full())
    };
    let out = args.out.unwrap_or_else(root);
    let start = Instant::now();
    let lap = |what: &str| eprintln!("{what}: {:.1} s", start.elapsed().as_secs_f64());
    let options = SimulationOptions {
        max_periods: STUDY_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    eprintln!(
        "study of scene '{}' (reading A: the scene's gap)",
        scene.name
    );
    let main = Study::run(&scene, size, &options, true);
    lap("study, reading A");
    let mut other_scene = scene.clone();
    other_scene.name = format!("{} (half gap)", scene.name);
    other_scene.stops = scene.stops.map(|s| StopsSpec {
        gap: READING_B_GAP_FACTOR * s.gap,
        ..s
    });
    let other = Study::run(&other_scene, size.without_extras(), &options, true);
    lap("study, reading B");
    let elastic_note = elastic_note(&scene, &options);

    let maps = maps(&scene, map_sizes, true);
    lap("maps");
    let data_dir = out.join("data/maps");
    match &maps {
        Some((bandwidth, regimes)) => {
            std::fs::create_dir_all(&data_dir).map_err(|e| e.to_string())?;
            let table = |name: &str| data_dir.join(name);
            write_table(
                &table("bandwidth-map.csv"),
                Format::Csv,
                &Header::default(),
                bandwidth.bandwidth_rows(),
            )
            .map_err(|e| e.to_string())?;
            write_table(
                &table("regime-map.csv"),
                Format::Csv,
                &Header::default(),
                regimes.point_rows(),
            )
            .map_err(|e| e.to_string())?;
        }
        None => {
            eprintln!("no maps: the scene has no stops (a map varies their gap and restitution)")
        }
    }

    let figures_dir = out.join("figures");
    let plots = main.plots(&options, maps.as_ref());
    let mut written = figures::draw(&plots, &figures_dir).map_err(|e| e.to_string())?;
    lap("figures");

    let damped = Scene::load(&root().join(WORK_PRECISION_SCENE)).map_err(|e| e.to_string())?;
    eprintln!("work-precision study on '{}'", damped.name);
    let mut precision = work_precision::study(
        &damped,
        WORK_PRECISION_OMEGA,
        WORK_PRECISION_PERIODS,
        SWEEP_COST_RANGE,
        &options,
    )
    .map_err(|e| e.to_string())?;
    // Siconos's points, as `cargo xtask peers` measured them (absent: the figure goes without).
    let siconos = SiconosPeer::load(&root().join(SICONOS_DATA)).map_err(|e| e.to_string())?;
    precision.siconos = siconos
        .as_ref()
        .and_then(|p| {
            p.work_precision_for(
                WORK_PRECISION_SCENE,
                WORK_PRECISION_OMEGA,
                WORK_PRECISION_PERIODS,
            )
        })
        .cloned();
    written
        .extend(figures::draw_work_precision(&precision, &figures_dir).map_err(|e| e.to_string())?);
    lap("work-precision");

    let basins = rattle_compare::runs::basins::basins(
        &scene,
        BASINS_OMEGA,
        BasinGrid {
            outer: Axis::new(-BASINS_EXTENT, BASINS_EXTENT, size_basins(args.quick)),
            inner: Axis::new(-BASINS_EXTENT, BASINS_EXTENT, size_basins(args.quick)),
        },
        &basin_options(),
        &Progress::new("basins", 0, false),
    );
    written.extend(
        figures::draw_basins(
            &figures::basins::BasinsFigure {
                scene_name: scene.name.clone(),
                basins,
            },
            &figures_dir,
        )
        .map_err(|e| e.to_string())?,
    );
    lap("basins");

    let lyapunov_options = SimulationOptions {
        max_periods: STUDY_MAX_PERIODS,
        ..SimulationOptions::default()
    };
    let samples = chaos_samples(
        &scene,
        &Axis::new(0.1, 4.0, size_lyapunov(args.quick)).values(),
        &lyapunov_options,
        &Progress::new("lyapunov", 0, false),
    );
    written.extend(
        figures::draw_lyapunov(
            &figures::lyapunov::LyapunovFigure {
                scene_name: scene.name.clone(),
                samples: samples.clone(),
            },
            &figures_dir,
        )
        .map_err(|e| e.to_string())?,
    );
    lap("lyapunov");

    // The command's own options (`rattle simulate --omega 1.25 --lyapunov` prints the title's
    // exponents).
    let poincare = poincare_sections(
        &scene,
        POINCARE_OMEGA,
        if args.quick { 500 } else { POINCARE_POINTS },
        rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS,
        &SimulationOptions::default(),
    )
    .map_err(|e| e.to_string())?;
    written.extend(
        figures::draw_poincare(
            &figures::poincare::PoincareFigure {
                scene_name: scene.name.clone(),
                sections: poincare,
            },
            &figures_dir,
        )
        .map_err(|e| e.to_string())?,
    );
    lap("poincare");

    let chains = chain_study(&scene, args.quick, false);
    written.extend(figures::draw_chains(&chains, &figures_dir).map_err(|e| e.to_string())?);
    lap("chains");

    let validation = out.join("validation");
    let doc = serde_json::to_string_pretty(&agreement(&main)).map_err(|e| e.to_string())?;
    write(&validation.join("agreement.json"), &(doc + "\n"))?;
    write(
        &validation.join("report.md"),
        &(report(&main, &other, &elastic_note, &samples)
            + &chain_section(&chains)
            + &siconos_section(siconos.as_ref(), &precision)),
    )?;
    for path in &written {
        eprintln!(
            "wrote {}",
            path.strip_prefix(&out).unwrap_or(path).display()
        );
    }
    if maps.is_some() {
        eprintln!("wrote data/maps/bandwidth-map.csv, data/maps/regime-map.csv");
    }
    eprintln!("wrote validation/agreement.json, validation/report.md");
    eprintln!("figures done in {:.1} s", start.elapsed().as_secs_f64());
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
        restitution: 1.0,
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
