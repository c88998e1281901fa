//! `rattle simulate`: the event-driven simulator from rest.

use super::{
    check_omega, heading, load_any, pretty, Accuracy, Common, RattleError, TrajectoryArgs,
};
use crate::api::{self, Simulation, Stretch};
use crate::output::records::{LyapunovRecord, SimulationRecord, WithLyapunov};
use crate::scene::lyapunov::check_periods;
use crate::scene::simulator::SimulatedPoint;
use crate::scene::{AnyScene, Scene};
use clap::Args;
use rattle_event_driven::SimulationOptions;
use rattle_event_driven::DEFAULT_LYAPUNOV_PERIODS;
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
    /// Sample N forcing periods continued from where the run ended instead of the final
    /// cycle: with `--samples-per-period 1` the `sample` rows of --trajectory are the
    /// stroboscopic (Poincaré) section at t = kT and --impacts the impact map, of a motion
    /// periodic or not (N ≥ 1, N × samples per period ≤ 10 000 000).
    #[arg(long, requires = "trajectory")]
    pub sampled_periods: Option<u64>,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub lyapunov: LyapunovArgs,
}

/// Writes the trajectory files of `args` for `simulation`, when asked for
/// ([`api::simulation_trajectory`]).
fn write_trajectory(
    args: &SimulateArgs,
    scene: &AnyScene,
    simulation: &Simulation,
    options: &SimulationOptions,
) -> Result<(), RattleError> {
    let tables = &args.trajectory;
    if tables.trajectory.is_none() {
        return Ok(());
    }
    let stretch = args
        .sampled_periods
        .map_or(Stretch::FinalCycle, Stretch::Continued);
    tables.write_tables(api::simulation_trajectory(
        scene,
        simulation,
        tables.samples_per_period,
        stretch,
        options,
    )?)
}

/// The `--lyapunov` flags of `rattle simulate`.
#[derive(Debug, Args)]
pub struct LyapunovArgs {
    /// After the steady-state run, compute the Lyapunov exponents over more periods.
    #[arg(long)]
    pub lyapunov: bool,
    /// Forcing periods of the exponents' run (at least 10).
    #[arg(long, default_value_t = DEFAULT_LYAPUNOV_PERIODS)]
    pub lyapunov_periods: u64,
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
    args.lyapunov.check()?;
    let any = load_any(&args.common.scene)?;
    api::check_frequency(&any, "--omega", omega)?;
    let simulation = api::simulate(&any, omega, &options)?;
    write_trajectory(&args, &any, &simulation, &options)?;
    let exponents = if args.lyapunov.lyapunov {
        Some(api::lyapunov(
            &any,
            &simulation,
            args.lyapunov.lyapunov_periods,
            &options,
        )?)
    } else {
        None
    };
    let (scene, sim, record) = match (&any, &simulation) {
        (AnyScene::Cells(scene), Simulation::Cells { point, record }) => (scene, point, record),
        (AnyScene::Structure(form), Simulation::Structure { point, record }) => {
            if args.common.json {
                return pretty(&WithLyapunov {
                    record,
                    lyapunov: exponents.as_ref(),
                });
            }
            let mut out = super::structure::simulation_table(form, omega, point, record);
            if let Some(l) = &exponents {
                write_lyapunov(&mut out, l);
            }
            return Ok(out);
        }
        _ => unreachable!("a simulation has the form of its scene"),
    };
    if args.common.json {
        return pretty(&WithLyapunov {
            record,
            lyapunov: exponents.as_ref(),
        });
    }
    Ok(table(scene, omega, sim, record, exponents.as_ref()))
}

/// The table `rattle simulate` prints for a unit or a chain.
fn table(
    scene: &Scene,
    omega: f64,
    sim: &SimulatedPoint,
    record: &SimulationRecord,
    exponents: Option<&LyapunovRecord>,
) -> String {
    let mut out = heading(scene, omega);
    out.push_str(&super::status_lines(
        &record.status,
        sim.regime.words(),
        record.period,
    ));
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
    if scene.is_chain() {
        let _ = writeln!(
            out,
            "last cell's X_o above; every cell's X_o: {}",
            sim.cell_outer_amplitudes()
                .iter()
                .map(|a| format!("{a:.6}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        let per_pair = sim.pair_impacts_per_period(scene.pair_count());
        let signatures = sim.pair_signatures(scene.pair_count());
        let _ = writeln!(
            out,
            "impacts per period by pair: {}",
            per_pair
                .iter()
                .enumerate()
                .map(|(j, n)| match signatures.as_ref().map(|s| &s[j]) {
                    Some(Ok(Some(sig))) => format!("{n} ({sig})"),
                    _ => format!("{n}"),
                })
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let _ = writeln!(
        out,
        "periods run: {}, impacts: {}",
        record.periods_run, record.impacts
    );
    if let Some(l) = exponents {
        write_lyapunov(&mut out, l);
    }
    out
}

impl LyapunovArgs {
    /// Checks the flags: with `--lyapunov`, at least
    /// [`BATCHES`](rattle_event_driven::BATCHES) periods ([`check_periods`]).
    ///
    /// # Errors
    /// [`RattleError::Argument`] naming `--lyapunov-periods` and its range.
    pub fn check(&self) -> Result<(), RattleError> {
        if self.lyapunov {
            check_periods(self.lyapunov_periods)
                .map_err(|e| RattleError::Argument(e.to_string()))?;
        }
        Ok(())
    }
}

/// The table lines of the exponents.
fn write_lyapunov(out: &mut String, l: &LyapunovRecord) {
    let list = |v: &[Option<f64>]| {
        v.iter()
            .map(|x| x.map_or("null".to_owned(), |x| format!("{x:.6}")))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let _ = writeln!(
        out,
        "lyapunov exponents (1/s, {} periods): [{}] ± {}{}",
        l.lyapunov_periods,
        list(&l.lyapunov_exponents),
        l.lyapunov_uncertainty
            .map_or("undefined".to_owned(), |u| format!("{u:.6}")),
        if l.lyapunov_collapsed > 0 {
            format!(", {} collapsed by sticking (−∞)", l.lyapunov_collapsed)
        } else {
            String::new()
        }
    );
    if let Some(r) = l.lyapunov_regime {
        let _ = writeln!(out, "lyapunov regime: {r}");
    }
}
