//! `rattle orbit`: the analytic picture at one frequency.

use super::{
    check_omega, heading, load_any, load_unit, pretty, Common, RattleError, TrajectoryArgs,
};
use crate::api::{self, SignatureOrbits};
use crate::output::records::{
    ChainOrbitsRecord, OrbitRecord, SignatureOrbitsRecord, ViolationRecord,
};
use crate::scene::analytic::OrbitSearch;
use crate::scene::{AnyScene, Scene};
use clap::Args;
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
    /// pair 0's alone (the other pairs must not impact). On a structure: its stops' impacts
    /// as `<stop><side>` tokens, stops numbered from 0 in file order (with one stop, the
    /// sides alone: `+-` reads as `0+ 0-`).
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
        return signature_run(&args, omega, text);
    }
    if args.trajectory.trajectory.is_some() {
        return Err(RattleError::Argument(
            "--trajectory needs --signature (for the two-impact orbits: --signature +-)".into(),
        ));
    }
    let scene = AnyScene::Cells(load_unit(&args.common.scene, "rattle orbit")?);
    api::check_frequency(&scene, "--omega", omega)?;
    let search = if args.symmetric_only {
        OrbitSearch::Symmetric
    } else {
        OrbitSearch::All
    };
    let found = api::orbits(&scene, omega, search)?;
    if args.common.json {
        return pretty(&found);
    }
    let AnyScene::Cells(scene) = &scene else {
        unreachable!("a unit loaded by `load_unit`")
    };
    let (point, record) = (&found.point, &found.record);
    let mut out = heading(scene, omega);
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

/// `rattle orbit --signature`: every orbit of one signature (on a chain: of an impact
/// sequence of its pairs; on a structure: of its stops), with `--trajectory` the
/// `--orbit`-th sampled (on a structure: a column per body and per stop, as
/// `simulate --trajectory` writes them).
fn signature_run(args: &OrbitArgs, omega: f64, text: &str) -> Result<String, RattleError> {
    let any = load_any(&args.common.scene)?;
    api::check_frequency(&any, "--omega", omega)?;
    let found = api::signature_orbits(&any, omega, text, args.period)?;
    if args.trajectory.trajectory.is_some() {
        args.trajectory.write_tables(api::orbit_trajectory(
            &any,
            &found,
            args.orbit,
            args.trajectory.samples_per_period,
        )?)?;
    }
    if args.common.json {
        return pretty(&found);
    }
    Ok(match (&any, &found) {
        (AnyScene::Cells(scene), SignatureOrbits::Unit { record, .. }) => {
            unit_signature_table(scene, omega, record)
        }
        (AnyScene::Cells(scene), SignatureOrbits::Chain { record }) => {
            chain_table(scene, omega, record)
        }
        (AnyScene::Structure(form), SignatureOrbits::Structure { orbits, record }) => {
            super::structure::orbits_table(form, omega, orbits, record)
        }
        _ => unreachable!("orbits have the form of their scene"),
    })
}

/// The table `rattle orbit --signature` prints for a unit's `record`.
fn unit_signature_table(scene: &Scene, omega: f64, record: &SignatureOrbitsRecord) -> String {
    let mut out = heading(scene, omega);
    let _ = writeln!(
        out,
        "signature {} over {} period(s): {} orbit(s)",
        record.signature,
        record.period,
        record.orbits.len()
    );
    if record.orbits.is_empty() {
        return out;
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
    out
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

/// The table `rattle orbit --signature` prints for a chain's `record`.
fn chain_table(scene: &Scene, omega: f64, record: &ChainOrbitsRecord) -> String {
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
    out
}
