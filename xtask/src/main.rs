//! The project's task runner (`cargo xtask <task>`), after rust-analyzer's `xtask/`: typed
//! flags, one module per task, and tidy tests (module `tidy`) that fail when a convention of the
//! repository is broken.
//!
//! Tasks: `figures` (see `cargo xtask figures --help`).

mod figures;
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
}

/// The repository's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_default()
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.task {
        Task::Figures(args) => figures::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("cargo xtask: {e}");
            ExitCode::from(2)
        }
    }
}
