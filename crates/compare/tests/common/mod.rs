//! What the command-line tests share: running `rattle` from the repository's root.
#![allow(dead_code)]

use serde_json::Value;
use std::path::PathBuf;
use std::process::{Command, Output};

/// Writes `text` as the scene file `name` in this test process's directory `tag`, and returns
/// its path.
///
/// Tests of one process run on several threads and several of them write the same scene: the
/// file is written under a name of this thread and renamed into place, so a reader never sees
/// it half written. (A plain `std::fs::write` truncates the file first: `rattle` could read
/// an empty scene while a neighbouring test rewrites it, "EOF while parsing a value".)
pub fn scene_file(tag: &str, name: &str, text: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("rattle-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("a temporary directory");
    let path = dir.join(name);
    let thread = format!("{:?}", std::thread::current().id());
    let partial = dir.join(format!(
        ".{name}.{}",
        thread.trim_start_matches("ThreadId(").trim_end_matches(')')
    ));
    std::fs::write(&partial, text).expect("the scene is written");
    std::fs::rename(&partial, &path).expect("the scene is put in place");
    path
}

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
