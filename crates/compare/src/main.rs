//! The `rattle` command. See `rattle --help`.

use clap::Parser;
use rattle_compare::cli::{run, Cli};
use std::io::Write;

fn main() {
    let cli = Cli::parse();
    match run(cli) {
        Ok(out) => {
            let mut stdout = std::io::stdout().lock();
            // A closed pipe (e.g. `| head`) is not an error of ours.
            let _ = stdout.write_all(out.as_bytes());
        }
        Err(e) => {
            eprintln!("rattle: {e}");
            std::process::exit(e.exit_code());
        }
    }
}
