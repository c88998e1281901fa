//! Prints the work-precision study of `data/scenes/paper-damped.json` at ω = 2 rad/s as text
//! (the numbers behind `figures/work-precision.png`): `cargo run --release -p rattle-compare
//! --example work_precision [SCENE] [OMEGA] [PERIODS]`.

use rattle_compare::peers::work_precision::study;
use rattle_compare::scene::Scene;
use rattle_event_driven::SimulationOptions;
use std::path::Path;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let path = args
        .first()
        .map_or("data/scenes/paper-damped.json", String::as_str);
    let scene = Scene::load(Path::new(path))?;
    let omega: f64 = args.get(1).map_or(Ok(2.0), |s| s.parse())?;
    let periods: u64 = args.get(2).map_or(Ok(300), |s| s.parse())?;
    let options = SimulationOptions {
        max_periods: 4000,
        ..SimulationOptions::default()
    };
    let wp = study(&scene, omega, periods, (0.5, 4.0), &options)?;
    println!("analytic solve: {:.3e} s", wp.analytic_seconds);
    for (name, points) in [
        ("event-driven", &wp.event_driven),
        ("baseline", &wp.baseline),
    ] {
        for p in points.iter() {
            println!(
                "{name} tol {:.0e}: {:.3e} s, error {:?}, impacts {}, failure {:?}, diff {:?}",
                p.tolerance,
                p.seconds,
                p.error(),
                p.impacts,
                p.failure,
                p.difference
            );
        }
    }
    for s in &wp.steady {
        println!("steady {:?}", s);
    }
    for s in &wp.sweeps {
        println!("sweep {:?}", s);
    }
    Ok(())
}
