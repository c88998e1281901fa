//! `cargo xtask peers`: Siconos's two schemes on the same unit, beside rattle
//! (`crates/compare/peers/siconos_unit.py`), written to `data/peers/siconos.json` for the
//! work-precision figure and the report's Siconos section.
//!
//! Siconos comes from Debian's packages (`apt-get install python3-siconos`) and runs under the
//! system Python. When it cannot be imported the task says how to install it and exits 0:
//! nothing else needs Siconos, and the committed results stay in place.

use crate::root;
use clap::Args;
use std::path::PathBuf;
use std::process::Command;

/// The Python that Debian's `python3-siconos` installs into.
const SYSTEM_PYTHON: &str = "/usr/bin/python3";
/// The script, relative to the repository's root.
const SCRIPT: &str = "crates/compare/peers/siconos_unit.py";

/// Flags of `cargo xtask peers`.
#[derive(Debug, Args)]
pub struct PeersArgs {
    /// Where to write the results (JSON); default: `data/peers/siconos.json`.
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Timed runs per point (the minimum is kept).
    #[arg(long, default_value_t = 3, value_parser = clap::value_parser!(u32).range(1..=20))]
    repeats: u32,
    /// The Python that has Siconos.
    #[arg(long, value_name = "PYTHON", default_value = SYSTEM_PYTHON)]
    python: PathBuf,
}

/// Whether `python` imports Siconos.
fn has_siconos(python: &PathBuf) -> bool {
    Command::new(python)
        .args(["-c", "import siconos.kernel"])
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Runs the task.
///
/// # Errors
/// When building `rattle` or the script fails (Siconos's own failures are results, written
/// into the JSON, not errors).
pub fn run(args: PeersArgs) -> Result<(), String> {
    if !has_siconos(&args.python) {
        eprintln!(
            "Siconos is not installed for {}: nothing to run (the committed data/peers/siconos.json \
             stays). Install it with\n    apt-get install python3-siconos\nand rerun `cargo xtask peers`.",
            args.python.display()
        );
        return Ok(());
    }
    let root = root();
    let rattle = crate::rattle_binary(&root)?;
    let out = args
        .out
        .unwrap_or_else(|| root.join(rattle_compare::peers::siconos::SICONOS_DATA));
    let status = Command::new(&args.python)
        .arg(root.join(SCRIPT))
        .arg("--rattle")
        .arg(&rattle)
        .arg("--out")
        .arg(&out)
        .arg("--repeats")
        .arg(args.repeats.to_string())
        .current_dir(&root)
        .status()
        .map_err(|e| format!("{}: {e}", args.python.display()))?;
    if !status.success() {
        return Err(format!("{SCRIPT}: {status}"));
    }
    eprintln!(
        "wrote {}; `cargo xtask figures` draws it into figures/work-precision and validation/report.md",
        out.display()
    );
    Ok(())
}
