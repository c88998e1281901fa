//! Loads a scene, simulates it from rest at one frequency and prints what the simulator
//! settled on: the regime, the period, the outer amplitude and the transmittance, then the
//! record `rattle simulate … --json` prints.
//!
//! ```text
//! cargo run -p rattle-compare --example simulate_scene -- data/scenes/paper.json 2.0
//! ```
//!
//! Without arguments it simulates the repository's `data/scenes/paper.json` at ω = 2 rad/s.

use rattle_compare::api;
use rattle_event_driven::SimulationOptions;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args.next().unwrap_or_else(|| {
        concat!(env!("CARGO_MANIFEST_DIR"), "/../../data/scenes/paper.json").to_owned()
    });
    let omega: f64 = args.next().map_or(Ok(2.0), |w| w.parse())?;

    let scene = api::load(&path)?;
    let sim = api::simulate(&scene, omega, &SimulationOptions::default())?;
    let point = sim.point();
    println!("scene {} at ω = {omega} rad/s", scene.name());
    println!("regime: {}", point.regime.words());
    println!("impacts per period: {}", point.steady.impacts_per_period);
    println!("outer amplitude X_o = {:.6} m", point.outer_amplitude);
    match point.transmittance_db {
        Some(t) => println!("transmittance T = {t:.3} dB"),
        None => println!("transmittance undefined (no steady state)"),
    }
    println!("{}", serde_json::to_string_pretty(&sim)?);
    Ok(())
}
