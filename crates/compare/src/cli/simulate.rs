//! `rattle simulate`: the event-driven simulator from rest.

use super::{check_omega, heading, load, pretty, Accuracy, Common, RattleError, TrajectoryArgs};
use crate::output::records::SimulationRecord;
use crate::output::trajectory::simulated_rows;
use crate::output::{write_table, Format, Header};
use crate::scene::simulator::{model, run as simulate, SimulatedPoint};
use crate::scene::Scene;
use clap::Args;
use rattle_event_driven::trajectory::{final_cycle_trajectory, TrajectoryOptions};
use rattle_event_driven::{SimulationOptions, Start};
use std::fmt::Write as _;

/// Arguments of `rattle simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    /// Run exactly N forcing periods and judge the steady state from the tail (default: run
    /// until periodic, up to a cap).
    #[arg(long)]
    pub periods: Option<u64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub accuracy: Accuracy,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub trajectory: TrajectoryArgs,
}

/// Writes the trajectory files of `args` for the run `sim`.
fn write_trajectory(
    args: &TrajectoryArgs,
    scene: &Scene,
    sim: &SimulatedPoint,
    options: &SimulationOptions,
) -> Result<(), RattleError> {
    let Some(path) = &args.trajectory else {
        return Ok(());
    };
    let m = model(scene, sim.omega).map_err(|e| RattleError::Numerical(e.to_string()))?;
    let trajectory = final_cycle_trajectory(
        &m,
        sim.omega,
        &sim.steady,
        &TrajectoryOptions {
            periods: 1,
            samples_per_period: args.samples_per_period,
            base_amplitude: scene.base.amplitude,
            simulation: options.clone(),
        },
    )
    .map_err(|e| RattleError::Numerical(e.to_string()))?;
    let (rows, impacts) = simulated_rows(&trajectory);
    write_table(
        path,
        Format::of(path, "--trajectory")?,
        &Header::default(),
        rows,
    )?;
    if let Some(path) = &args.impacts {
        write_table(
            path,
            Format::of(path, "--impacts")?,
            &Header::default(),
            impacts,
        )?;
    }
    Ok(())
}

/// Runs `rattle simulate`.
///
/// # Errors
/// Bad arguments or scene; a failure of the simulator.
pub fn run(args: SimulateArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.common.omega)?;
    let mut options = args.accuracy.options()?;
    if let Some(n) = args.periods {
        if n == 0 {
            return Err(RattleError::Argument("--periods must be > 0".into()));
        }
        options.fixed_periods = Some(n);
    }
    args.trajectory.check()?;
    let scene = load(&args.common.scene)?;
    let sim = simulate(&scene, omega, &Start::rest(2), &options)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    write_trajectory(&args.trajectory, &scene, &sim, &options)?;
    let record = SimulationRecord::new(&scene, &sim);
    if args.common.json {
        return pretty(&record);
    }
    let mut out = heading(&scene, omega);
    let _ = writeln!(out, "status: {} ({})", record.status, sim.regime.words());
    let _ = writeln!(
        out,
        "period: {}",
        record
            .period
            .map_or("none (not periodic)".to_owned(), |p| format!(
                "{p} forcing period(s)"
            ))
    );
    let _ = writeln!(out, "impacts per period: {}", sim.steady.impacts_per_period);
    let _ = writeln!(
        out,
        "X_o = {:.9}, T = {}",
        sim.outer_amplitude,
        sim.transmittance_db
            .map_or("undefined (no steady state)".to_owned(), |t| format!(
                "{t:.4} dB"
            ))
    );
    let _ = writeln!(
        out,
        "periods run: {}, impacts: {}",
        record.periods_run, record.impacts
    );
    Ok(out)
}
