//! What the command-line tests share: running `rattle` from the repository's root.
#![allow(dead_code)]

use serde_json::Value;
use std::process::{Command, Output};

/// Runs `rattle ARGS` from the repository's root.
pub fn rattle(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .output()
        .expect("rattle runs")
}

/// Runs `rattle ARGS`, which must succeed, and parses its one JSON document.
pub fn json(args: &[&str]) -> Value {
    let out = rattle(args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("one JSON document")
}
