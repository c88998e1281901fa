//! What a newcomer meets first: a summary line for every branch continuation lists, and a
//! malformed scene's message naming the field and the line.

mod common;
use common::{rattle, scene_file};

#[test]
fn a_branch_listed_but_not_followed_says_why() {
    // At depth 0 every branch that leaves the start's branches is listed without points.
    let out = rattle(&[
        "continue",
        "--signature",
        "+-",
        "--omega",
        "2.9",
        "--omega-min",
        "2.8",
        "--omega-max",
        "3.0",
        "--max-depth",
        "0",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = String::from_utf8_lossy(&out.stdout);
    let branches: Vec<&str> = text.lines().filter(|l| l.starts_with("branch ")).collect();
    let listed: Vec<&&str> = branches
        .iter()
        .filter(|l| l.contains("listed, not followed (max-depth)"))
        .collect();
    assert!(
        !listed.is_empty(),
        "no branch listed without points:\n{text}"
    );
    assert!(
        branches.iter().any(|l| l.contains(" points on ω ∈ [")),
        "no branch followed:\n{text}"
    );
    assert!(!text.contains("inf"), "{text}");
}

#[test]
fn a_malformed_scene_names_the_last_field_read() {
    let cases = [
        (
            "{\"name\": \"x\", \"unit\": {",
            "unit: not valid JSON: EOF while parsing",
        ),
        (
            "{",
            ".: not valid JSON: EOF while parsing an object (line 1, column 1)",
        ),
        (
            "not json",
            ".: not valid JSON: expected ident (line 1, column 2)",
        ),
        ("{\"unit\": 3}", "unit: invalid type: integer `3`"),
    ];
    for (k, (text, message)) in cases.into_iter().enumerate() {
        let path = scene_file("front-door", &format!("bad-{k}.json"), text);
        let out = rattle(&[
            "simulate",
            path.to_str().expect("a UTF-8 path"),
            "--omega",
            "2",
        ]);
        assert_eq!(out.status.code(), Some(2));
        let err = String::from_utf8_lossy(&out.stderr);
        let expected = format!("rattle: {}: {message}", path.display());
        assert!(err.starts_with(&expected), "{err} (expected {expected}…)");
        assert!(!err.contains('?'), "{err}");
    }
}
