//! `rattle simulate`: the event-driven simulator from rest.

use super::{
    check_frequency, check_omega, heading, load_any, pretty, Accuracy, Common, RattleError,
    TrajectoryArgs,
};
use crate::output::records::{LyapunovRecord, SimulationRecord, WithLyapunov};
use crate::output::trajectory::simulated_rows;
use crate::scene::lyapunov::{check_periods, spectrum};
use crate::scene::simulator::{model, run as simulate, SimulatedPoint};
use crate::scene::{AnyScene, Scene};
use clap::Args;
use rattle_event_driven::lyapunov::DEFAULT_LYAPUNOV_PERIODS;
use rattle_event_driven::trajectory::{final_cycle_trajectory, TrajectoryOptions};
use rattle_event_driven::SimulationOptions;
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
    #[command(flatten)]
    #[allow(missing_docs)]
    pub lyapunov: LyapunovArgs,
}

/// Writes the trajectory files of `args` for the run `sim`.
fn write_trajectory(
    args: &TrajectoryArgs,
    scene: &Scene,
    sim: &SimulatedPoint,
    options: &SimulationOptions,
) -> Result<(), RattleError> {
    if args.trajectory.is_none() {
        return Ok(());
    }
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
    let (rows, impacts) = simulated_rows(&trajectory, &scene.cell_pairs());
    args.write(rows, impacts)
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
    let scene = match load_any(&args.common.scene)? {
        AnyScene::Cells(scene) => scene,
        AnyScene::Structure(form) => {
            refuse_for_structure(&args)?;
            return super::structure::simulate(
                &form,
                omega,
                &options,
                &args.trajectory,
                args.common.json,
            );
        }
    };
    check_frequency(&scene, "--omega", omega)?;
    let sim = simulate(
        &scene,
        omega,
        &crate::scene::simulator::rest(&scene),
        &options,
    )
    .map_err(|e| RattleError::Numerical(e.to_string()))?;
    write_trajectory(&args.trajectory, &scene, &sim, &options)?;
    let record = SimulationRecord::new(&scene, &sim);
    let exponents = lyapunov_record(&args.lyapunov, &scene, &sim, &options)?;
    if args.common.json {
        return pretty(&WithLyapunov {
            record: &record,
            lyapunov: exponents.as_ref(),
        });
    }
    let mut out = heading(&scene, omega);
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
    if let Some(l) = &exponents {
        write_lyapunov(&mut out, l);
    }
    Ok(out)
}

/// The options `rattle simulate` does not take on a structure scene yet, refused by name.
fn refuse_for_structure(args: &SimulateArgs) -> Result<(), RattleError> {
    if args.lyapunov.lyapunov {
        return Err(RattleError::Argument(
            "--lyapunov is not taken on a scene in the structure form yet: it is taken on the \
             unit and chain forms"
                .into(),
        ));
    }
    Ok(())
}

impl LyapunovArgs {
    /// Checks the flags: with `--lyapunov`, at least
    /// [`BATCHES`](rattle_event_driven::lyapunov::BATCHES) periods ([`check_periods`]).
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

/// The exponents of `sim` when `--lyapunov` asks for them: the library's [`spectrum`] and
/// [`LyapunovRecord::new`].
///
/// # Errors
/// [`RattleError::Argument`] as [`LyapunovArgs::check`]; [`RattleError::Numerical`] when the
/// exponents' run fails.
fn lyapunov_record(
    args: &LyapunovArgs,
    scene: &Scene,
    sim: &SimulatedPoint,
    options: &SimulationOptions,
) -> Result<Option<LyapunovRecord>, RattleError> {
    if !args.lyapunov {
        return Ok(None);
    }
    args.check()?;
    let spectrum = spectrum(scene, sim, args.lyapunov_periods, options)
        .map_err(|e| RattleError::Numerical(e.to_string()))?;
    Ok(Some(LyapunovRecord::new(sim, &spectrum)))
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
