//! The project's task runner (`cargo xtask <task>`), after rust-analyzer's `xtask/`: typed
//! flags, one module per task, and tidy tests (module `tidy`) that fail when a convention of the
//! repository is broken.
//!
//! Tasks: `figures`, `soak` and `peers` (see `cargo xtask TASK --help`).

mod figures;
mod peers;
mod soak;
#[cfg(test)]
mod tidy;

use clap::{Parser, Subcommand};
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// The repository's tasks.
#[derive(Debug, Parser)]
#[command(name = "cargo xtask")]
struct Cli {
    #[command(subcommand)]
    task: Task,
}

#[derive(Debug, Subcommand)]
enum Task {
    /// Regenerates every figure (PNG and SVG in `figures/`), the maps' tables (`data/maps/`)
    /// and the validation outputs (`validation/agreement.json`, `validation/report.md`).
    Figures(figures::FiguresArgs),
    /// Thousands of random scenes through both solvers (the property tests scaled up) and the
    /// bad-input list, with fixed seeds; exits 1 listing every failure.
    Soak(soak::SoakArgs),
    /// Siconos's event-driven and Moreau–Jean schemes on the same unit
    /// (`crates/compare/peers/siconos_unit.py`, Debian's `python3-siconos`), written to
    /// `data/peers/siconos.json`; without Siconos it says how to install it and exits 0.
    Peers(peers::PeersArgs),
}

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

/// Builds the `rattle` command in release (as the README builds it) and returns its path.
///
/// # Errors
/// When cargo cannot be run or the build fails.
pub fn rattle_binary(root: &Path) -> Result<PathBuf, String> {
    let status = std::process::Command::new("cargo")
        .args([
            "build",
            "--release",
            "-p",
            "rattle-compare",
            "--bin",
            "rattle",
        ])
        .current_dir(root)
        .status()
        .map_err(|e| format!("cargo build: {e}"))?;
    if !status.success() {
        return Err(format!("cargo build of rattle: {status}"));
    }
    let target = std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("target"));
    Ok(root.join(target).join("release/rattle"))
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.task {
        Task::Figures(args) => figures::run(args),
        Task::Soak(args) => soak::run(args),
        Task::Peers(args) => peers::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("cargo xtask: {e}");
            ExitCode::from(2)
        }
    }
}
