//! The project's task runner (`cargo xtask <task>`), after rust-analyzer's `xtask/`.
//!
//! Tasks:
//! - `figures [--scene FILE] [--quick] [--out DIR]`: regenerate every figure (PNG and SVG in
//!   `figures/`) and the validation outputs (`validation/agreement.json`, `validation/report.md`)
//!   on the built-in paper scene or on `FILE`; the accuracy-versus-cost figures
//!   (`work-precision`, `steady-state-cost`) always use `data/scenes/paper-damped.json` at 2 rad/s. `--quick` runs a few points of everything (a smoke
//!   test); `--out DIR` writes `DIR/figures` and `DIR/validation` instead of the repository's.

use rattle_compare::figures::MapSizes;
use rattle_compare::scene::{Scene, StopsSpec};
use rattle_compare::study::{Study, StudySize};
use rattle_compare::validation::{agreement, report};
use rattle_event_driven::SimulationOptions;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// Frequency of the work-precision case, rad/s.
const WORK_PRECISION_OMEGA: f64 = 2.0;
/// Periods both integrators run from rest in the work-precision study.
const WORK_PRECISION_PERIODS: u64 = 300;

fn write(path: &Path, text: &str) -> Result<(), String> {
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    std::fs::write(path, text).map_err(|e| format!("{}: {e}", path.display()))
}

fn figures(args: &[String]) -> Result<(), String> {
    let mut scene = Scene::paper();
    let mut size = StudySize::full();
    let mut quick = false;
    let mut out = root();
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--scene" => {
                let path = it.next().ok_or("--scene needs a file")?;
                scene = Scene::load(Path::new(path)).map_err(|e| e.to_string())?;
            }
            "--quick" => {
                size = StudySize::quick();
                quick = true;
            }
            "--out" => out = PathBuf::from(it.next().ok_or("--out needs a directory")?),
            other => return Err(format!("unknown argument {other}")),
        }
    }
    let start = Instant::now();
    // The cap keeps the full study within a minute on two cores; points that need longer to
    // settle are reported as not periodic (the report counts them).
    let options = SimulationOptions {
        max_periods: 4000,
        ..SimulationOptions::default()
    };
    eprintln!(
        "study of scene '{}' (reading A: the scene's gap)",
        scene.name
    );
    let main = Study::run(&scene, size, &options, true);
    // Reading B of "sides 0.5 m apart": the same unit with half the gap.
    let mut other_scene = scene.clone();
    other_scene.name = format!("{} (half gap)", scene.name);
    other_scene.stops = scene.stops.map(|s| StopsSpec {
        gap: 0.5 * s.gap,
        ..s
    });
    eprintln!("study of scene '{}' (reading B)", other_scene.name);
    let other = Study::run(&other_scene, size.without_extras(), &options, true);
    let mut elastic = scene.clone();
    elastic.stops = scene.stops.map(|s| StopsSpec {
        restitution: 1.0,
        ..s
    });
    let elastic_note = elastic_note(&elastic, &options);

    let figures_dir = out.join("figures");
    let mut written = rattle_compare::figures::generate(&main, &options, &figures_dir)
        .map_err(|e| e.to_string())?;
    // Accuracy against cost, on the damped paper scene at ω = 2 rad/s, where the simulator
    // from rest settles on the analytic stable viable orbit (max|μ| = 0.855: 300 periods
    // bring the transient below 1e-16).
    let damped_path = root().join("data/scenes/paper-damped.json");
    let damped = Scene::load(&damped_path).map_err(|e| e.to_string())?;
    eprintln!("work-precision study on '{}'", damped.name);
    let precision = rattle_compare::work_precision::study(
        &damped,
        WORK_PRECISION_OMEGA,
        WORK_PRECISION_PERIODS,
        (0.5, 4.0),
        &options,
    )
    .map_err(|e| e.to_string())?;
    written.extend(
        rattle_compare::figures::generate_work_precision(&precision, &figures_dir)
            .map_err(|e| e.to_string())?,
    );
    // Design maps over restitution and gap, and the regime over frequency and gap.
    let map_sizes = if quick {
        MapSizes::quick()
    } else {
        MapSizes::full()
    };
    if scene.stops.is_some() {
        eprintln!(
            "maps of '{}'",
            rattle_compare::figures::map_scene(&scene).name
        );
        written.extend(
            rattle_compare::figures::generate_maps(
                &scene,
                map_sizes,
                &figures_dir,
                &out.join("data/maps"),
                true,
            )
            .map_err(|e| e.to_string())?,
        );
    } else {
        eprintln!("no maps: the scene has no stops (a map varies their gap and restitution)");
    }
    let validation = out.join("validation");
    let doc = agreement(&main);
    write(&validation.join("agreement.json"), &format!("{doc:#}\n"))?;
    write(
        &validation.join("report.md"),
        &report(&main, &other, &elastic_note),
    )?;
    for path in &written {
        eprintln!(
            "wrote {}",
            path.strip_prefix(&out).unwrap_or(path).display()
        );
    }
    eprintln!("wrote validation/agreement.json, validation/report.md");
    eprintln!("figures done in {:.1} s", start.elapsed().as_secs_f64());
    Ok(())
}

/// What the simulator says about the fully elastic, undamped unit at 1 and 2 rad/s.
fn elastic_note(scene: &Scene, options: &SimulationOptions) -> String {
    if scene.unit_model().damping.is_some() {
        return "the scene is damped: elastic impacts still dissipate through the dashpots".into();
    }
    [1.0, 2.0]
        .iter()
        .map(|&w| {
            match rattle_compare::simulation::run(
                scene,
                w,
                &rattle_event_driven::Start::rest(2),
                options,
            ) {
                Ok(sim) => format!(
                    "ω = {w}: e = 1, no damping → {}",
                    rattle_compare::simulation::status_name(&sim.steady)
                ),
                Err(e) => format!("ω = {w}: {e}"),
            }
        })
        .collect::<Vec<_>>()
        .join("; ")
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.first().map(String::as_str) {
        Some("figures") => match figures(&args[1..]) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("cargo xtask figures: {e}");
                ExitCode::from(2)
            }
        },
        _ => {
            eprintln!("usage: cargo xtask figures [--scene FILE] [--quick] [--out DIR]");
            ExitCode::from(2)
        }
    }
}
