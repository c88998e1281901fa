//! The bad-input list of the soak: every bad argument that `crates/compare/tests/cli.rs`
//! checks, run through the `rattle` command (exit code 2, the option or field named on
//! stderr), and random bad scenes (a valid random scene with one field broken), each refused
//! by `Scene::parse` naming the field, and the first [`SCENES_THROUGH_COMMAND`] of them also
//! by `rattle simulate`.

use super::{random_scene, Rng};
use rattle_compare::scene::Scene;
use serde_json::{json, Value};
use std::path::Path;
use std::process::Command;

/// Bad scenes also written to a file and given to `rattle simulate`.
const SCENES_THROUGH_COMMAND: u64 = 200;

/// The bad arguments of `crates/compare/tests/cli.rs` and the text stderr must contain.
const BAD_ARGUMENTS: &[(&[&str], &str)] = &[
    (&["orbit", "--omega", "nan"], "--omega"),
    (&["orbit", "--omega", "inf"], "--omega"),
    (&["orbit", "--omega", "0"], "--omega"),
    (&["orbit", "--omega", "-1"], "--omega"),
    (
        &["orbit", "no/such/scene.json", "--omega", "1"],
        "no/such/scene.json",
    ),
    (&["family", "--omega", "1", "--beta", "1.5"], "--beta"),
    (&["orbit", "--omega", "2", "--signature", ""], "--signature"),
    (
        &["orbit", "--omega", "2", "--signature", "+x-"],
        "--signature",
    ),
    (
        &[
            "orbit",
            "--omega",
            "2",
            "--signature",
            "+-",
            "--period",
            "0",
        ],
        "--period",
    ),
    (
        &[
            "orbit",
            "--omega",
            "2",
            "--signature",
            "+-",
            "--period",
            "99",
        ],
        "--period",
    ),
    (
        &[
            "continue",
            "--omega",
            "3",
            "--omega-min",
            "2.7",
            "--omega-max",
            "3.1",
            "--signature",
            "+x",
        ],
        "--signature",
    ),
    (
        &[
            "continue",
            "--omega",
            "3",
            "--omega-min",
            "2.7",
            "--omega-max",
            "3.1",
            "--signature",
            "+-",
            "--period",
            "0",
        ],
        "--period",
    ),
    (
        &[
            "continue",
            "--omega",
            "3",
            "--omega-min",
            "2.7",
            "--omega-max",
            "3.1",
            "--signature",
            "+-",
            "--orbit",
            "99",
        ],
        "--orbit",
    ),
    (
        &[
            "continue",
            "--omega",
            "3",
            "--omega-min",
            "2.7",
            "--omega-max",
            "3.1",
            "--signature",
            "+-",
            "--max-step",
            "0",
        ],
        "--max-step",
    ),
    (
        &[
            "continue",
            "--omega",
            "3",
            "--omega-min",
            "2.7",
            "--omega-max",
            "3.1",
            "--signature",
            "+-",
            "--max-branches",
            "0",
        ],
        "--max-branches",
    ),
    (
        &[
            "continue",
            "--signature",
            "+-",
            "--omega",
            "5",
            "--omega-min",
            "2.7",
            "--omega-max",
            "3.1",
        ],
        "--omega",
    ),
    (
        &["simulate", "--omega", "2", "--trajectory", "t.txt"],
        "--trajectory",
    ),
    (
        &[
            "simulate",
            "--omega",
            "2",
            "--trajectory",
            "t.csv",
            "--samples-per-period",
            "0",
        ],
        "--samples-per-period",
    ),
    (
        &["orbit", "--omega", "2", "--trajectory", "t.csv"],
        "--signature",
    ),
    (
        &[
            "orbit",
            "--omega",
            "2",
            "--signature",
            "+-",
            "--orbit",
            "99",
            "--trajectory",
            "t.csv",
        ],
        "--orbit",
    ),
    (
        &[
            "sweep",
            "--omega-min",
            "1",
            "--omega-max",
            "2",
            "--points",
            "2",
            "--out",
            "s.txt",
        ],
        "--out",
    ),
    (
        &[
            "sweep",
            "--omega-min",
            "1",
            "--omega-max",
            "2",
            "--points",
            "2",
            "--out",
            "s.jsonl",
            "--shard",
            "1/2",
        ],
        "--shard",
    ),
];

/// Runs `rattle args` from `root`; `None` when it exits 2 with `expected` on stderr, else what
/// it did.
fn refused(rattle: &Path, root: &Path, args: &[&str], expected: &str) -> Option<String> {
    let out = match Command::new(rattle).args(args).current_dir(root).output() {
        Ok(out) => out,
        Err(e) => return Some(format!("rattle {args:?}: {e}")),
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    (out.status.code() != Some(2) || !stderr.contains(expected)).then(|| {
        format!(
            "rattle {args:?}: exit {:?}, stderr without `{expected}`: {stderr}",
            out.status.code()
        )
    })
}

/// Random bad scene `index`: its JSON and the texts its refusal must contain.
fn bad_scene(seed: u64, index: u64) -> (String, [String; 2]) {
    let (scene, _) = random_scene(seed, index);
    let mut doc = serde_json::to_value(&scene).unwrap_or(Value::Null);
    let mut rng = Rng::new(seed ^ 0xbad, index);
    let positive = [
        ("unit", "outer_mass"),
        ("unit", "inner_mass"),
        ("unit", "outer_stiffness"),
        ("unit", "inner_stiffness"),
        ("base", "amplitude"),
        ("stops", "gap"),
    ];
    let broken = -rng.uniform(0.0, 10.0);
    let (block, field, value, words): (&str, &str, Value, &str) = match rng.below(6) {
        0 | 1 => {
            let (block, field) = positive[rng.below(positive.len() as u64) as usize];
            (block, field, json!(broken), "> 0")
        }
        2 => {
            let e = if rng.below(2) == 0 {
                1.0 - broken
            } else {
                broken - 1e-9
            };
            ("stops", "restitution", json!(e), "[0, 1]")
        }
        3 => {
            let field = ["outer", "inner"][rng.below(2) as usize];
            if doc["damping"].is_null() {
                doc["damping"] = json!({"outer": 0.1, "inner": 0.1});
            }
            ("damping", field, json!(broken - 1e-9), ">= 0")
        }
        4 => {
            let (block, field) = positive[rng.below(positive.len() as u64) as usize];
            (block, field, json!(format!("{}", -broken)), "invalid type")
        }
        _ => ("stops", "gapp", json!(1.0), "unknown field"),
    };
    doc[block][field] = value;
    let text = serde_json::to_string(&doc).unwrap_or_default();
    (text, [format!("{block}.{field}"), words.to_owned()])
}

/// Random bad scenes refused in-process (and the first few by the command); returns the
/// failures.
fn bad_scenes(rattle: &Path, root: &Path, seed: u64, count: u64) -> Vec<String> {
    let dir = std::env::temp_dir().join(format!("rattle-soak-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    let mut failures = Vec::new();
    for k in 0..count {
        let (text, expected) = bad_scene(seed, k);
        match Scene::parse(&text, "soak.json") {
            Ok(_) => failures.push(format!("bad scene {k} accepted: {text}")),
            Err(e) => {
                let message = e.to_string();
                if !expected.iter().all(|x| message.contains(x.as_str())) {
                    failures.push(format!("bad scene {k}: `{message}` lacks {expected:?}"));
                }
            }
        }
        if k < SCENES_THROUGH_COMMAND {
            let path = dir.join(format!("bad-{k}.json"));
            if std::fs::write(&path, &text).is_ok() {
                let file = path.display().to_string();
                let args = ["simulate", file.as_str(), "--omega", "1"];
                failures.extend(refused(rattle, root, &args, &expected[0]));
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    failures
}

/// The bad-input list: the command's bad arguments, then `count` random bad scenes.
pub fn soak(rattle: &Path, root: &Path, seed: u64, count: u64) -> Vec<String> {
    let mut failures: Vec<String> = BAD_ARGUMENTS
        .iter()
        .filter_map(|(args, expected)| refused(rattle, root, args, expected))
        .collect();
    failures.extend(bad_scenes(rattle, root, seed, count));
    eprintln!(
        "bad input: {} arguments and {count} scenes ({} through `rattle simulate`); {} failed",
        BAD_ARGUMENTS.len(),
        count.min(SCENES_THROUGH_COMMAND),
        failures.len()
    );
    failures
}
