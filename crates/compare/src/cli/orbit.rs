//! `rattle orbit`: the analytic picture at one frequency.

use super::{
    check_frequency, check_omega, heading, load_any, load_unit, pretty, Common, RattleError,
    TrajectoryArgs,
};
use crate::output::records::{
    At, ChainOrbitsRecord, LinearRecord, OrbitRecord, OrbitsRecord, SignatureOrbitRecord,
    SignatureOrbitsRecord, ViolationRecord,
};
use crate::output::trajectory::{analytic_rows, ImpactRow, TrajectoryRow};
use crate::scene::analytic::{
    analyse, chain_linear_model, orbits_of_signature, sample_sequence_orbit,
    sample_signature_orbit, OrbitImpact, OrbitSample, OrbitSearch,
};
use crate::scene::{AnyScene, Scene};
use crate::verdict::chain::{chain_orbits, ChainOrbitsError};
use clap::Args;
use rattle_analytic::Signature;
use std::fmt::Write as _;

/// Arguments of `rattle orbit`.
#[derive(Debug, Args)]
pub struct OrbitArgs {
    #[command(flatten)]
    #[allow(missing_docs)]
    pub common: Common,
    /// Only the symmetric orbits (β = ½); skips the search over β.
    #[arg(long, conflicts_with = "signature")]
    pub symmetric_only: bool,
    /// Every orbit with this impact signature instead: the stops hit over one cycle in time
    /// order, `+` side 1 (r = +Δ), `-` side 2, any rotation (e.g. `+-`, `++--`, `+-+-`).
    /// On a chain: the impacts of every pair in time order as `<pair><side>` tokens, pairs
    /// numbered from 0 at the base (e.g. `0+ 1- 0- 1+`); a signature without numbers is
    /// pair 0's alone (the other pairs must not impact).
    #[arg(long, allow_hyphen_values = true)]
    pub signature: Option<String>,
    /// Forcing periods per cycle of the signature, in [1, 8].
    #[arg(long, default_value_t = 1, requires = "signature")]
    pub period: u32,
    /// With --trajectory: which orbit of the signature to sample (numbered from 0, as
    /// listed).
    #[arg(long, default_value_t = 0, requires = "trajectory")]
    pub orbit: usize,
    #[command(flatten)]
    #[allow(missing_docs)]
    pub trajectory: TrajectoryArgs,
}

/// Runs `rattle orbit`.
///
/// # Errors
/// Bad arguments or scene; a numerical failure of the analytic solver.
pub fn run(args: OrbitArgs) -> Result<String, RattleError> {
    let omega = check_omega("--omega", args.common.omega)?;
    args.trajectory.check()?;
    if let Some(text) = &args.signature {
        let scene = match load_any(&args.common.scene)? {
            AnyScene::Cells(scene) => scene,
            AnyScene::Structure(form) => {
                if args.trajectory.trajectory.is_some() {
                    return Err(RattleError::Argument(
                        "--trajectory is not taken on a scene in the structure form yet: it is \
                         taken on the unit and chain forms"
                            .into(),
                    ));
                }
                return super::structure::orbits(&form, omega, text, args.period, args.common.json);
            }
        };
        check_frequency(&scene, "--omega", omega)?;
        if scene.is_chain() {
            return chain_run(&scene, omega, text, &args);
        }
        let signature = Signature::parse(text, args.period)
            .map_err(|e| RattleError::Argument(e.to_string()))?;
        let scene = load_unit(&args.common.scene, "rattle orbit")?;
        return signature_run(&scene, omega, &signature, &args);
    }
    if args.trajectory.trajectory.is_some() {
        return Err(RattleError::Argument(
            "--trajectory needs --signature (for the two-impact orbits: --signature +-)".into(),
        ));
    }
    let scene = load_unit(&args.common.scene, "rattle orbit")?;
    check_frequency(&scene, "--omega", omega)?;
    let search = if args.symmetric_only {
        OrbitSearch::Symmetric
    } else {
        OrbitSearch::All
    };
    let point =
        analyse(&scene, omega, search).map_err(|e| RattleError::Numerical(e.to_string()))?;
    let record = OrbitsRecord {
        at: At::new(&scene, omega),
        linear: LinearRecord::new(&point.linear, scene.gap()),
        orbits: point
            .orbits
            .iter()
            .map(|(b, o)| OrbitRecord::new(o, *b))
            .collect(),
    };
    if args.common.json {
        return pretty(&record);
    }
    let mut out = heading(&scene, omega);
    let lin = &point.linear;
    if lin.unbounded {
        let _ = writeln!(out, "linear: unbounded (undamped exact resonance)");
    } else {
        let _ = writeln!(
            out,
            "linear: X_o = {:.6}, X_i = {:.6}, |u_i − u_o| = {:.6}, T = {:.3} dB{}",
            lin.outer_amplitude,
            lin.inner_amplitude,
            lin.relative_amplitude,
            lin.transmittance_db,
            match record.linear.touches_stops {
                Some(true) => " (reaches the stops)",
                Some(false) => " (stays clear of the stops)",
                None => "",
            }
        );
    }
    if scene.stops.is_none() {
        let _ = writeln!(out, "no stops: no impacting orbits");
        return Ok(out);
    }
    if record.orbits.is_empty() {
        let _ = writeln!(out, "no two-impact orbit exists at this frequency");
        return Ok(out);
    }
    out.push_str(&orbit_table(&record.orbits));
    Ok(out)
}

/// The `--trajectory` and `--impacts` tables of the `orbit`-th of the `count` orbits of `what`
/// (a signature or an impact sequence) of `scene` at `omega`, sampled by `sample(orbit)`.
///
/// # Errors
/// [`RattleError::Argument`] naming `--orbit` when `orbit` is not below `count`.
fn orbit_tables(
    scene: &Scene,
    omega: f64,
    what: &str,
    count: usize,
    orbit: usize,
    sample: impl FnOnce(usize) -> (Vec<OrbitSample>, Vec<OrbitImpact>),
) -> Result<(Vec<TrajectoryRow>, Vec<ImpactRow>), RattleError> {
    if orbit >= count {
        return Err(RattleError::Argument(format!(
            "--orbit = {orbit} is out of range: {count} orbit(s) of {what} at ω = {omega}, numbered from 0"
        )));
    }
    let (samples, impacts) = sample(orbit);
    Ok(analytic_rows(
        &samples,
        &impacts,
        omega,
        scene.base.amplitude,
        &scene.cell_pairs(),
    ))
}

/// With --trajectory: writes the `--orbit`-th of the `count` orbits of `what` (a signature or
/// an impact sequence), sampled by `sample(k)`.
///
/// # Errors
/// An `--orbit` out of range; a file that cannot be written.
fn write_orbit_trajectory(
    scene: &Scene,
    omega: f64,
    args: &OrbitArgs,
    what: &str,
    count: usize,
    sample: impl FnOnce(usize) -> (Vec<OrbitSample>, Vec<OrbitImpact>),
) -> Result<(), RattleError> {
    if args.trajectory.trajectory.is_none() {
        return Ok(());
    }
    let (rows, impacts) = orbit_tables(scene, omega, what, count, args.orbit, sample)?;
    args.trajectory.write(rows, impacts)
}

/// `rattle orbit --signature`: every orbit of one signature.
fn signature_run(
    scene: &Scene,
    omega: f64,
    signature: &Signature,
    args: &OrbitArgs,
) -> Result<String, RattleError> {
    if scene.stops.is_none() {
        return Err(RattleError::Argument(
            "--signature: the scene has no `stops`, so no impact signature".into(),
        ));
    }
    let orbits = orbits_of_signature(scene, omega, signature);
    write_orbit_trajectory(
        scene,
        omega,
        args,
        &signature.to_string(),
        orbits.len(),
        |k| sample_signature_orbit(scene, &orbits[k], args.trajectory.samples_per_period),
    )?;
    let record = SignatureOrbitsRecord {
        at: At::new(scene, omega),
        signature: signature.to_string(),
        period: signature.period(),
        orbits: orbits.iter().map(SignatureOrbitRecord::new).collect(),
    };
    if args.common.json {
        return pretty(&record);
    }
    let mut out = heading(scene, omega);
    let _ = writeln!(
        out,
        "signature {} over {} period(s): {} orbit(s)",
        record.signature,
        record.period,
        record.orbits.len()
    );
    if record.orbits.is_empty() {
        return Ok(out);
    }
    let _ = writeln!(
        out,
        "{:>5} {:>9} {:>10} {:>9} {:>6} {:>6} {:>9} {:>9}  impact phases; violations",
        "orbit", "alpha", "X_o", "T(dB)", "viable", "stable", "max|μ|", "energy"
    );
    let num = |x: Option<f64>| x.unwrap_or(f64::NAN);
    for (k, o) in record.orbits.iter().enumerate() {
        let phases: Vec<String> = o
            .impact_phases
            .iter()
            .map(|p| format!("{:.6}", num(*p)))
            .collect();
        let _ = writeln!(
            out,
            "{k:>5} {:>9.5} {:>10.6} {:>9.3} {:>6} {:>6} {:>9.4} {:>9.1e}  ({}); {}",
            num(o.alpha),
            num(o.outer_amplitude),
            num(o.transmittance_db),
            o.viable,
            o.stable,
            o.largest_multiplier(),
            num(o.energy_residual),
            phases.join(", "),
            violation_words(&o.violations)
        );
    }
    Ok(out)
}

/// The violations in words, `-` for none.
fn violation_words(violations: &[ViolationRecord]) -> String {
    if violations.is_empty() {
        return "-".to_owned();
    }
    let words: Vec<String> = violations.iter().map(|v| v.words()).collect();
    words.join("; ")
}

/// A table of orbits, one line each, under a header line.
pub(crate) fn orbit_table(orbits: &[OrbitRecord]) -> String {
    let mut out = format!(
        "{:>6} {:>8} {:>9} {:>10} {:>9} {:>6} {:>6} {:>7}  violations\n",
        "branch", "beta", "alpha", "X_o", "T(dB)", "viable", "stable", "max|μ|"
    );
    let num = |x: Option<f64>| x.unwrap_or(f64::NAN);
    for o in orbits {
        let _ = writeln!(
            out,
            "{:>6} {:>8.5} {:>9.5} {:>10.6} {:>9.3} {:>6} {:>6} {:>7.4}  {}",
            o.branch,
            num(o.beta),
            num(o.alpha),
            num(o.outer_amplitude),
            num(o.transmittance_db),
            o.viable,
            o.stable,
            o.largest_multiplier(),
            violation_words(&o.violations)
        );
    }
    out
}

/// `rattle orbit --signature` on a chain: every orbit of one impact sequence of its pairs.
fn chain_run(
    scene: &Scene,
    omega: f64,
    text: &str,
    args: &OrbitArgs,
) -> Result<String, RattleError> {
    let record = chain_orbits(scene, omega, text, args.period).map_err(|e| match e {
        ChainOrbitsError::Numerical(_) => RattleError::Numerical(e.to_string()),
        _ => RattleError::Argument(e.to_string()),
    })?;
    if args.trajectory.trajectory.is_some() {
        let model = chain_linear_model(scene).map_err(|e| RattleError::Argument(e.to_string()))?;
        write_orbit_trajectory(
            scene,
            omega,
            args,
            &record.sequence,
            record.orbits.len(),
            |k| {
                sample_sequence_orbit(
                    &model,
                    &record.orbits[k],
                    args.trajectory.samples_per_period,
                )
            },
        )?;
    }
    if args.common.json {
        return pretty(&record);
    }
    chain_table(scene, omega, &record)
}

/// The table `rattle orbit --signature` prints for a chain's `record`.
fn chain_table(
    scene: &Scene,
    omega: f64,
    record: &ChainOrbitsRecord,
) -> Result<String, RattleError> {
    let mut out = heading(scene, omega);
    let _ = writeln!(
        out,
        "chain of {} cells, impact sequence {} over {} period(s): {} orbit(s)",
        record.cells,
        record.sequence,
        record.period,
        record.orbits.len()
    );
    for (k, o) in record.orbits.iter().enumerate() {
        let largest = o
            .floquet_multipliers
            .iter()
            .fold(0.0_f64, |a, m| a.max(m.norm()));
        let _ = writeln!(
            out,
            "{k}: X_N = {:.6}, T = {:.3} dB, viable {}, stable {} (max|μ| = {largest:.4}), \
             energy residual {:.1e}, cells X_o = {:?}",
            o.outer_amplitude,
            o.transmittance_db,
            o.viable,
            o.stable,
            o.energy_residual,
            o.cell_outer_amplitudes
                .iter()
                .map(|a| (a * 1e6).round() / 1e6)
                .collect::<Vec<_>>()
        );
    }
    Ok(out)
}
