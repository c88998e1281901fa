//! No history in the repository's prose: comments and documents say what the code does and
//! why, in the present tense. The project's history is git's (commit messages) and the
//! performance page's; a comment that names a work session, an issue number or a commit goes
//! stale with the next change and sends the reader somewhere the code is not.

use super::rust;
use crate::root;
use std::path::{Path, PathBuf};

/// What a history mention is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Mention {
    /// A work session: the word "stop" followed by its number.
    Session,
    /// An issue: "issue" followed by a number, with or without `#`, or a `#` and a number.
    Issue,
    /// A commit hash: a standalone word of 7 to 40 lower-case hexadecimal digits with at least
    /// one digit and one letter (so neither a plain number nor a word like `deadbeef`).
    Commit,
}

/// A word of prose: a maximal run of letters, digits and `_`, with its byte range.
#[derive(Debug, Clone, Copy)]
struct Word<'a> {
    text: &'a str,
    start: usize,
    end: usize,
}

fn words(prose: &str) -> Vec<Word<'_>> {
    let is_word = |c: char| c.is_alphanumeric() || c == '_';
    let mut out = Vec::new();
    let mut start = None;
    for (o, c) in prose.char_indices().chain([(prose.len(), ' ')]) {
        match (start, is_word(c)) {
            (None, true) => start = Some(o),
            (Some(s), false) => {
                out.push(Word {
                    text: &prose[s..o],
                    start: s,
                    end: o,
                });
                start = None;
            }
            _ => {}
        }
    }
    out
}

/// Whether `word` is a number on its own: digits, not the start of a decimal (`0.5`).
fn is_count(prose: &str, word: &Word) -> bool {
    let decimal = prose[word.end..].starts_with('.')
        && prose[word.end + 1..]
            .chars()
            .next()
            .is_some_and(|c| c.is_ascii_digit());
    !word.text.is_empty() && word.text.chars().all(|c| c.is_ascii_digit()) && !decimal
}

/// The history mentions of `prose`: each one's kind and byte range.
pub(crate) fn mentions(prose: &str) -> Vec<(Mention, std::ops::Range<usize>)> {
    let words = words(prose);
    let mut found: Vec<(Mention, std::ops::Range<usize>)> = Vec::new();
    for (k, word) in words.iter().enumerate() {
        let taken = found.last().is_some_and(|(_, r)| r.end > word.start);
        let next = words.get(k + 1);
        let between = next.map_or("", |n| &prose[word.end..n.start]);
        let lower = word.text.to_ascii_lowercase();
        // A session: only white space between the word and the number.
        if matches!(lower.as_str(), "stop" | "stops")
            && between.chars().all(char::is_whitespace)
            && !between.is_empty()
            && next.is_some_and(|n| is_count(prose, n))
        {
            let n = next.expect("checked");
            found.push((Mention::Session, word.start..n.end));
        }
        // An issue, its number with or without `#`.
        let after_issue = between.trim_start().trim_start_matches('#');
        if matches!(lower.as_str(), "issue" | "issues")
            && after_issue.is_empty()
            && !between.is_empty()
            && between.trim().len() <= 1
            && next.is_some_and(|n| is_count(prose, n))
        {
            let n = next.expect("checked");
            found.push((Mention::Issue, word.start..n.end));
        } else if !taken && is_count(prose, word) && word.text.len() <= 5 && word.start > 0 {
            // A `#` right before the number, itself not after a word character, an `&` (an
            // HTML entity) or another `#`.
            let before = &prose[..word.start];
            let hash = before.ends_with('#')
                && !before[..before.len() - 1]
                    .chars()
                    .next_back()
                    .is_some_and(|c| c.is_alphanumeric() || matches!(c, '_' | '&' | '#'));
            if hash {
                found.push((Mention::Issue, word.start - 1..word.end));
            }
        }
        let hex = word
            .text
            .chars()
            .all(|c| c.is_ascii_digit() || ('a'..='f').contains(&c));
        // A number's digits are no hash: the fraction of a decimal (`2.449490e-3`) or a
        // mantissa with its exponent's `e` (`1224745e6`).
        let fraction = prose[..word.start].ends_with('.')
            && prose[..word.start - 1]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_ascii_digit());
        let exponent = word.text.matches('e').count() == 1
            && word.text.chars().all(|c| c.is_ascii_digit() || c == 'e')
            && word.text.starts_with(|c: char| c.is_ascii_digit());
        if hex
            && !fraction
            && !exponent
            && (7..=40).contains(&word.text.len())
            && word.text.chars().any(|c| c.is_ascii_digit())
            && word.text.chars().any(|c| c.is_ascii_alphabetic())
        {
            found.push((Mention::Commit, word.start..word.end));
        }
    }
    found
}

/// The prose of a file: a Rust source's comments (its code and string literals are behaviour,
/// not prose), a Markdown or Python file whole.
fn prose(path: &Path, text: &str) -> String {
    if path.extension().is_some_and(|e| e == "rs") {
        rust::comment_text(text)
    } else {
        text.to_owned()
    }
}

/// The files whose prose is checked: Rust, Python and Markdown files under `crates/`, `xtask/`
/// and `docs/`, and `README.md` (build output, caches and hidden folders left out).
fn checked_files() -> Vec<PathBuf> {
    let mut out = vec![root().join("README.md")];
    let mut stack: Vec<PathBuf> = ["crates", "xtask", "docs"]
        .iter()
        .map(|d| root().join(d))
        .filter(|d| d.is_dir())
        .collect();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("folders are readable") {
            let path = entry.expect("directory entries are readable").path();
            let name = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            if path.is_dir() {
                let skipped = name.starts_with('.')
                    || matches!(name, "target" | "__pycache__" | "node_modules" | "venv");
                if !skipped {
                    stack.push(path);
                }
            } else if path
                .extension()
                .is_some_and(|e| e == "rs" || e == "py" || e == "md")
            {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

#[test]
fn no_history_in_comments_and_documents() {
    let files = checked_files();
    assert!(
        files.len() > 100,
        "only {} files: has the repository moved?",
        files.len()
    );
    let mut found = Vec::new();
    for file in &files {
        let text = std::fs::read_to_string(file).expect("checked files are readable");
        let prose = prose(file, &text);
        for (kind, range) in mentions(&prose) {
            let line = prose[..range.start].matches('\n').count() + 1;
            let shown = file.strip_prefix(root()).unwrap_or(file).display();
            let words = prose[range]
                .split_whitespace()
                .collect::<Vec<_>>()
                .join(" ");
            found.push(format!("{shown}:{line}: {kind:?} `{words}`"));
        }
    }
    assert!(
        found.is_empty(),
        "{} history mentions (say what the code does and why; the history is git's, and \
         measurements are the performance page's, docs/performance.md):\n{}",
        found.len(),
        found.join("\n")
    );
}

#[test]
fn history_mentions_are_found_and_only_they() {
    let kinds =
        |prose: &str| -> Vec<Mention> { mentions(prose).into_iter().map(|m| m.0).collect() };
    use Mention::{Commit, Issue, Session};
    assert_eq!(kinds("as measured at stop 12, before"), [Session]);
    assert_eq!(kinds("Stop\n    29's build"), [Session]);
    assert_eq!(kinds("see issue #12 and Issue 16"), [Issue, Issue]);
    assert_eq!(kinds("the target of #24."), [Issue]);
    assert_eq!(kinds("(main 2f00f23, against b5cf96f)"), [Commit, Commit]);
    assert_eq!(
        kinds("commit 34fee8c0d1a2b3c4d5e6f708192a3b4c5d6e7f80"),
        [Commit]
    );
    for clean in [
        "each stop 0.5 m from rest; the stop bands; stops at ±gap",
        "the 0x5851f42d4c957f2d multiplier, seed 1442695040888963407",
        "ω = 1.4586466165413536, tolerance 1e-12, 8766.7e6 instructions",
        "must be in [2.449490e-3, 1.224745e6] rad/s, 1234567e8",
        "#[cfg(test)] r#\"raw\"# &#123; color #1f77b4, ##12",
        "deadbeef facade, 40 periods, issue tracker",
        "a_1234abcd5 x1234abcd",
    ] {
        assert_eq!(kinds(clean), [], "{clean}");
    }
    // In a Rust source only the comments count.
    let source = "let h = \"b5cf96f\"; // at stop 3\nlet x = 0x1234abcd; /* #24 */";
    let found: Vec<Mention> = mentions(&rust::comment_text(source))
        .into_iter()
        .map(|m| m.0)
        .collect();
    assert_eq!(found, [Session, Issue]);
}
