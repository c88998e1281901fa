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

/// Runs `rattle ARGS` from the repository's root, killed after `seconds`: `None` if it had
/// not ended by then (a hang the test must report, not wait out).
pub fn rattle_within(args: &[&str], seconds: u64) -> Option<Output> {
    use std::process::Stdio;
    use std::time::{Duration, Instant};
    let mut child = Command::new(env!("CARGO_BIN_EXE_rattle"))
        .args(args)
        .current_dir(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("rattle runs");
    let deadline = Instant::now() + Duration::from_secs(seconds);
    while Instant::now() < deadline {
        if child.try_wait().expect("rattle can be waited on").is_some() {
            return Some(
                child
                    .wait_with_output()
                    .expect("rattle's output is readable"),
            );
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let _ = child.kill();
    let _ = child.wait();
    None
}
