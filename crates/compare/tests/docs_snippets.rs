//! The guide's commands, run: every fenced shell block of `README.md`, `docs/*.md` and
//! `crates/python/README.md`, so that a command, a flag or a quoted output that no longer
//! holds fails here instead of in a reader's terminal.
//!
//! How a block is read:
//!
//! - A fence's language says what it holds: `sh`, `bash`, `shell` and `console` are shell
//!   blocks, read here; `python` blocks are run by `crates/python/tests/test_docs_snippets.py`;
//!   `json` and `text` are not commands. A fence without a language is refused, so that no
//!   command hides in one.
//! - Lines ending in `\` continue on the next line; `# …` ends a line's comment, and a line
//!   that starts with `#` is a comment; `A && B` is two commands.
//! - A block with lines starting `$ ` is a transcript: those lines are the commands and the
//!   lines after each are its expected output. Each expected line must be one of the output's
//!   lines (standard output, then standard error), in the order given; one ending in `...` or
//!   `…` matches any line that starts with the text before it, and a line `...` alone stands
//!   for lines left out.
//! - A command whose program is `rattle` (after optional `NAME=value` settings) is run by
//!   `sh` with `rattle` the binary built for this test, in a temporary directory holding a
//!   copy of `data/scenes`, one directory per block so that a block's commands see each
//!   other's files; `cargo run [--release] -p rattle-compare -- ARGS` is run as `rattle ARGS`.
//!   It must exit 0 and print what the transcript shows.
//! - Every other command must be in [`NOT_RUN_HERE`] with the reason it is not run here, or in
//!   a block marked `<!-- test: not run: REASON -->`. A command that is neither fails the test.
//!
//! Directives, each an HTML comment on its own line directly above the fence (several may be
//! stacked), visible in the page's source and applied by this test and the Python one alike:
//!
//! - `<!-- test: OLD => NEW -->`: every `OLD` in the block's commands (or Python code) becomes
//!   `NEW` for the test run: how a study too big for a test (`--points 400`) runs at a small
//!   size. It must match somewhere in the block.
//! - `<!-- test: not run: REASON -->`: the block is not run, for the reason given.
//! - `<!-- test: exit N -->`: the block's commands must exit with code `N` (a refusal shown).

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// The repository's root.
const ROOT: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../..");

/// A command that runs longer than this has hung or grown past a test's size.
const TIMEOUT: Duration = Duration::from_secs(180);

/// The guide's commands that are not `rattle` and are not run here, with the reason. Each
/// entry must still appear in the guide (a stale entry fails the test).
const NOT_RUN_HERE: &[(&str, &str)] = &[
    ("cargo test --workspace", "the command that runs this test"),
    (
        "cargo xtask figures",
        "rewrites the committed figures, tables and validation report (minutes of CPU); \
         run by hand when the solvers change",
    ),
    (
        "cargo xtask soak",
        "the long checks, minutes on two cores; its bad-input list is \
         crates/compare/tests/cli.rs's, run by cargo test",
    ),
    (
        "cargo xtask peers",
        "needs Siconos (python3-siconos); its results are committed in data/peers/",
    ),
    (
        "cargo install --path crates/compare",
        "installs into the user's ~/.cargo/bin; this test runs the same crate's binary as \
         cargo test builds it",
    ),
    (
        "cargo build --release -p rattle-compare --bin rattle",
        "a release build of the binary this test runs in the test profile",
    ),
    (
        "pip install ./crates/python",
        ".ci/python runs it, in a fresh virtual environment, before the Python tests",
    ),
    (
        "pip install \"./crates/python[pandas]\"",
        "downloads pandas from the package index; .ci/python installs the package itself",
    ),
    (
        "pip install \"./crates/python[plot]\"",
        "downloads matplotlib from the package index; .ci/python installs the package itself",
    ),
    (
        "pip install matplotlib",
        "downloads matplotlib from the package index",
    ),
    (
        "pip install \"./crates/python[pandas]\" dask distributed",
        "downloads pandas and Dask from the package index; .ci/python installs the package \
         and Dask itself",
    ),
    (
        "python crates/python/benches/dask_overhead.py",
        "a benchmark of minutes on a Dask cluster, with the package installed",
    ),
];

/// What a directive above a fence asks.
#[derive(Debug, Clone, PartialEq)]
enum Directive {
    /// `OLD => NEW`: the test runs the block with `OLD` replaced by `NEW`.
    Replace(String, String),
    /// `not run: REASON`.
    NotRun(String),
    /// `exit N`: the commands must exit with code `N`.
    Exit(i32),
}

/// One fenced block of a Markdown page.
#[derive(Debug, Clone)]
struct Block {
    /// Where it is: the page and the fence's line.
    place: String,
    /// The fence's language.
    language: String,
    /// The lines between the fences.
    lines: Vec<String>,
    /// The directives directly above the fence.
    directives: Vec<Directive>,
}

/// One command of a shell block, with the output a transcript shows after it.
#[derive(Debug, Clone, PartialEq)]
struct Step {
    /// The command, its continuation lines joined and its comment removed.
    text: String,
    /// The transcript's output lines after it (empty outside transcripts).
    expected: Vec<String>,
}

/// Parses a directive's text (between `<!-- test:` and `-->`).
fn directive(text: &str) -> Result<Directive, String> {
    let text = text.trim();
    if let Some(reason) = text.strip_prefix("not run:") {
        let reason = reason.trim();
        if reason.is_empty() {
            return Err("`not run:` without a reason".into());
        }
        return Ok(Directive::NotRun(reason.into()));
    }
    if let Some(code) = text.strip_prefix("exit ") {
        return code
            .trim()
            .parse()
            .map(Directive::Exit)
            .map_err(|_| format!("`exit {code}`: not an exit code"));
    }
    match text.split_once(" => ") {
        Some((old, new)) if !old.trim().is_empty() => {
            Ok(Directive::Replace(old.trim().into(), new.trim().into()))
        }
        _ => Err(format!(
            "`{text}`: expected `OLD => NEW`, `not run: REASON` or `exit N`"
        )),
    }
}

/// Every fenced block of `markdown` (the page `page`), with its directives; an error for a
/// fence without a language, an unclosed fence, a malformed directive, or a directive that is
/// not directly above a fence.
fn blocks(markdown: &str, page: &str) -> Result<Vec<Block>, String> {
    let lines: Vec<&str> = markdown.lines().collect();
    let mut found = Vec::new();
    let mut pending: Vec<(usize, Directive)> = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = lines[i].trim();
        if let Some(comment) = line.strip_prefix("<!-- test:") {
            let text = comment
                .strip_suffix("-->")
                .ok_or_else(|| format!("{page}:{}: a directive ends with `-->`", i + 1))?;
            pending.push((
                i + 1,
                directive(text).map_err(|e| format!("{page}:{}: {e}", i + 1))?,
            ));
            i += 1;
            continue;
        }
        if let Some(info) = line.strip_prefix("```") {
            let language = info.split_whitespace().next().unwrap_or("").to_owned();
            if language.is_empty() {
                return Err(format!("{page}:{}: a fence without a language", i + 1));
            }
            let start = i;
            let mut body = Vec::new();
            i += 1;
            while i < lines.len() && lines[i].trim() != "```" {
                body.push(lines[i].to_owned());
                i += 1;
            }
            if i == lines.len() {
                return Err(format!("{page}:{}: the fence is never closed", start + 1));
            }
            found.push(Block {
                place: format!("{page}:{}", start + 1),
                language,
                lines: body,
                directives: pending.drain(..).map(|(_, d)| d).collect(),
            });
            i += 1;
            continue;
        }
        if let Some((at, _)) = pending.first() {
            return Err(format!(
                "{page}:{at}: a directive must stand directly above a fence"
            ));
        }
        i += 1;
    }
    match pending.first() {
        Some((at, _)) => Err(format!("{page}:{at}: a directive above no fence")),
        None => Ok(found),
    }
}

/// Whether `language` marks a shell block.
fn is_shell(language: &str) -> bool {
    matches!(language, "sh" | "bash" | "shell" | "console")
}

/// The position of the first ` #` (or a `#` at the start) outside quotes: where a shell
/// comment starts.
fn comment_start(line: &str) -> Option<usize> {
    let mut quote = None;
    let mut previous = ' ';
    for (i, c) in line.char_indices() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, '#') if previous.is_whitespace() => return Some(i),
            _ => {}
        }
        previous = c;
    }
    None
}

/// The commands of a shell block, each with its transcript output.
fn steps(lines: &[String]) -> Vec<Step> {
    let transcript = lines.iter().any(|l| l.starts_with("$ "));
    let mut out: Vec<Step> = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let line = &lines[i];
        i += 1;
        let command = if transcript {
            match line.strip_prefix("$ ") {
                Some(command) => command,
                None => {
                    if let Some(step) = out.last_mut() {
                        if !line.trim().is_empty() {
                            step.expected.push(line.trim_end().to_owned());
                        }
                    }
                    continue;
                }
            }
        } else {
            line.as_str()
        };
        let mut text = command.to_owned();
        while text.trim_end().ends_with('\\') && i < lines.len() {
            let kept = text.trim_end();
            text = format!("{} {}", &kept[..kept.len() - 1], lines[i].trim());
            i += 1;
        }
        if let Some(at) = comment_start(&text) {
            text.truncate(at);
        }
        let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
        if !text.is_empty() {
            out.push(Step {
                text,
                expected: Vec::new(),
            });
        }
    }
    out
}

/// `text` split at ` && ` outside quotes.
fn and_parts(text: &str) -> Vec<String> {
    let mut parts = Vec::new();
    let mut quote = None;
    let mut start = 0;
    for (i, c) in text.char_indices() {
        match (quote, c) {
            (None, '\'' | '"') => quote = Some(c),
            (Some(q), _) if c == q => quote = None,
            (None, '&') if text[i..].starts_with("&& ") && text[..i].ends_with(' ') => {
                parts.push(text[start..i].trim().to_owned());
                start = i + 2;
            }
            _ => {}
        }
    }
    parts.push(text[start..].trim().to_owned());
    parts.retain(|p| !p.is_empty());
    parts
}

/// The `rattle` command line a command of the guide runs, or `None` for another program:
/// `[NAME=value …] rattle ARGS`, or `cargo run [--release] -p rattle-compare -- ARGS` as
/// `rattle ARGS`.
fn as_rattle(command: &str) -> Option<String> {
    for prefix in [
        "cargo run --release -p rattle-compare -- ",
        "cargo run -p rattle-compare -- ",
    ] {
        if let Some(args) = command.strip_prefix(prefix) {
            return Some(format!("rattle {args}"));
        }
    }
    let program = command.split_whitespace().find(|word| {
        let name = word.split('=').next().unwrap_or("");
        !(word.contains('=')
            && !name.is_empty()
            && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
    })?;
    (program == "rattle").then(|| command.to_owned())
}

/// What the test does with one command of the guide.
#[derive(Debug, Clone, PartialEq)]
enum Plan {
    /// Runs `script` with `sh -c`; it must exit `exit` and print `expected`.
    Run {
        script: String,
        expected: Vec<String>,
        exit: i32,
    },
    /// Not run, for this reason.
    Skip(String),
}

/// The plan of every command of a shell block, each with the command as written, or the
/// reasons the block cannot be planned (a directive that matches nothing, a command neither
/// run nor listed).
fn plan(block: &Block, used: &mut [bool]) -> Result<Vec<(String, Plan)>, Vec<String>> {
    let mut errors = Vec::new();
    let not_run = block.directives.iter().find_map(|d| match d {
        Directive::NotRun(reason) => Some(reason.clone()),
        _ => None,
    });
    let exit = block
        .directives
        .iter()
        .find_map(|d| match d {
            Directive::Exit(code) => Some(*code),
            _ => None,
        })
        .unwrap_or(0);
    let mut steps = steps(&block.lines);
    for d in &block.directives {
        if let Directive::Replace(old, new) = d {
            let mut matched = false;
            for step in &mut steps {
                if step.text.contains(old.as_str()) {
                    step.text = step.text.replace(old.as_str(), new);
                    matched = true;
                }
            }
            if !matched {
                errors.push(format!(
                    "{}: the directive `{old} => {new}` matches no command of the block",
                    block.place
                ));
            }
        }
    }
    let mut plans = Vec::new();
    for step in steps {
        if let Some(reason) = &not_run {
            plans.push((step.text.clone(), Plan::Skip(reason.clone())));
            continue;
        }
        let parts = and_parts(&step.text);
        let last = parts.len().saturating_sub(1);
        for (k, part) in parts.into_iter().enumerate() {
            if let Some(script) = as_rattle(&part) {
                let expected = if k == last {
                    step.expected.clone()
                } else {
                    Vec::new()
                };
                plans.push((
                    part,
                    Plan::Run {
                        script,
                        expected,
                        exit,
                    },
                ));
            } else if let Some(k) = NOT_RUN_HERE.iter().position(|(c, _)| *c == part) {
                used[k] = true;
                plans.push((part, Plan::Skip(NOT_RUN_HERE[k].1.to_owned())));
            } else {
                errors.push(format!(
                    "{}: `{part}` is neither a `rattle` command nor listed in NOT_RUN_HERE or \
                     under a `<!-- test: not run: REASON -->` directive",
                    block.place
                ));
            }
        }
    }
    if errors.is_empty() {
        Ok(plans)
    } else {
        Err(errors)
    }
}

/// Whether the output line `line` is what the transcript's `expected` line shows.
fn line_matches(expected: &str, line: &str) -> bool {
    let expected = expected.trim_end();
    for ellipsis in ["...", "…"] {
        if let Some(prefix) = expected.strip_suffix(ellipsis) {
            return line.starts_with(prefix.trim_end());
        }
    }
    line.trim_end() == expected
}

/// The first expected line not found, in order, among `output`'s lines.
fn missing_line<'a>(expected: &'a [String], output: &str) -> Option<&'a str> {
    let mut lines = output.lines();
    expected
        .iter()
        .map(String::as_str)
        .filter(|e| !matches!(e.trim(), "..." | "…"))
        .find(|e| !lines.any(|line| line_matches(e, line)))
}

/// A fresh working directory for a block: `data/scenes` copied in, and `bin/rattle` pointing
/// at the binary under test. Tests of one process run at once, so each directory is numbered.
fn workdir() -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let k = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let dir = std::env::temp_dir().join(format!("rattle-docs-{}-{k}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let scenes = dir.join("data/scenes");
    std::fs::create_dir_all(&scenes).expect("a temporary directory");
    for entry in std::fs::read_dir(Path::new(ROOT).join("data/scenes")).expect("data/scenes") {
        let path = entry.expect("a readable directory").path();
        if path.is_file() {
            std::fs::copy(&path, scenes.join(path.file_name().expect("a file name")))
                .expect("the scene is copied");
        }
    }
    std::fs::create_dir_all(dir.join("bin")).expect("a temporary directory");
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_rattle"), dir.join("bin/rattle"))
        .expect("the binary is linked");
    dir
}

/// Runs `script` with `sh -c` in `dir`, `rattle` resolving to the binary under test: its exit
/// code (`None` when killed at [`TIMEOUT`]), standard output and standard error.
fn run(script: &str, dir: &Path) -> (Option<i32>, String, String) {
    let path = format!(
        "{}:{}",
        dir.join("bin").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let (out, err) = (dir.join(".stdout"), dir.join(".stderr"));
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(script)
        .current_dir(dir)
        .env("PATH", path)
        .stdin(Stdio::null())
        .stdout(std::fs::File::create(&out).expect("a file for standard output"))
        .stderr(std::fs::File::create(&err).expect("a file for standard error"))
        .spawn()
        .expect("sh runs");
    let deadline = Instant::now() + TIMEOUT;
    let code = loop {
        if let Some(status) = child.try_wait().expect("the command can be waited on") {
            break status.code();
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let read = |p: &Path| String::from_utf8_lossy(&std::fs::read(p).unwrap_or_default()).into();
    (code, read(&out), read(&err))
}

/// Runs a block's plans in a fresh directory: the failures, and a line per command for the
/// test's log.
fn run_block(place: &str, plans: &[(String, Plan)]) -> (Vec<String>, Vec<String>) {
    let mut failures = Vec::new();
    let mut log = Vec::new();
    let needs_dir = plans.iter().any(|(_, p)| matches!(p, Plan::Run { .. }));
    let dir = needs_dir.then(workdir);
    for (command, plan) in plans {
        match plan {
            Plan::Skip(reason) => log.push(format!("{place}: not run: `{command}`: {reason}")),
            Plan::Run {
                script,
                expected,
                exit,
            } => {
                let dir = dir.as_ref().expect("a directory for a block that runs");
                let start = Instant::now();
                let (code, out, err) = run(script, dir);
                let seconds = start.elapsed().as_secs_f64();
                log.push(format!("{place}: ran `{script}` in {seconds:.2} s"));
                let output = format!("{out}{err}");
                if code != Some(*exit) {
                    failures.push(format!(
                        "{place}: `{script}` exited {code:?}, not {exit}:\n{}",
                        tail(&output)
                    ));
                } else if let Some(line) = missing_line(expected, &output) {
                    failures.push(format!(
                        "{place}: `{script}` does not print `{line}`; it printed:\n{}",
                        tail(&output)
                    ));
                }
            }
        }
    }
    if let Some(dir) = dir {
        let _ = std::fs::remove_dir_all(dir);
    }
    (failures, log)
}

/// The last lines of a command's output, for a failure's message.
fn tail(output: &str) -> String {
    let lines: Vec<&str> = output.lines().collect();
    lines[lines.len().saturating_sub(20)..].join("\n")
}

/// Checks the shell blocks of the pages `(name, text)`, `threads` blocks at a time: the
/// failures (an empty list when every command runs as the pages say), the log, and which
/// [`NOT_RUN_HERE`] entries the pages use.
fn check(pages: &[(String, String)], threads: usize) -> (Vec<String>, Vec<String>, Vec<bool>) {
    let mut failures = Vec::new();
    let mut used = vec![false; NOT_RUN_HERE.len()];
    let mut planned = Vec::new();
    for (name, text) in pages {
        match blocks(text, name) {
            Err(e) => failures.push(e),
            Ok(found) => {
                for block in found.into_iter().filter(|b| is_shell(&b.language)) {
                    match plan(&block, &mut used) {
                        Ok(plans) => planned.push((block.place, plans)),
                        Err(errors) => failures.extend(errors),
                    }
                }
            }
        }
    }
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..threads.max(1) {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some((place, plans)) = planned.get(k) else {
                    break;
                };
                let result = run_block(place, plans);
                results.lock().expect("no thread panics").push((k, result));
            });
        }
    });
    let mut results = results.into_inner().expect("no thread panicked");
    results.sort_by_key(|(k, _)| *k);
    let mut log = Vec::new();
    for (_, (f, l)) in results {
        failures.extend(f);
        log.extend(l);
    }
    (failures, log, used)
}

/// The pages whose commands the guide shows: the README, every page of `docs/`, and the
/// Python package's README.
fn guide() -> Vec<(String, String)> {
    let root = Path::new(ROOT);
    let mut names = vec!["README.md".to_owned(), "crates/python/README.md".to_owned()];
    let mut docs: Vec<String> = std::fs::read_dir(root.join("docs"))
        .expect("docs/ exists")
        .map(|e| e.expect("a readable directory").path())
        .filter(|p| p.extension().is_some_and(|e| e == "md"))
        .map(|p| format!("docs/{}", p.file_name().expect("a name").to_string_lossy()))
        .collect();
    docs.sort();
    names.extend(docs);
    names
        .into_iter()
        .map(|name| {
            let text = std::fs::read_to_string(root.join(&name)).expect("the page is readable");
            (name, text)
        })
        .collect()
}

#[test]
fn every_command_in_the_guide_runs_as_shown() {
    let start = Instant::now();
    let pages = guide();
    assert!(pages.len() > 10, "the guide's pages are found");
    let (mut failures, log, used) = check(&pages, 2);
    for ((command, _), used) in NOT_RUN_HERE.iter().zip(&used) {
        if !*used {
            failures.push(format!(
                "NOT_RUN_HERE lists `{command}`, which no page shows any more"
            ));
        }
    }
    let ran = log.iter().filter(|l| l.contains(": ran `")).count();
    println!("{}", log.join("\n"));
    println!(
        "{ran} commands run, {} not run, in {:.1} s",
        log.len() - ran,
        start.elapsed().as_secs_f64()
    );
    assert!(ran > 30, "the guide's commands are found and run ({ran})");
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}

/// One planted page through the whole check.
fn check_one(markdown: &str) -> (Vec<String>, Vec<String>) {
    let (failures, log, _) = check(&[("planted.md".to_owned(), markdown.to_owned())], 1);
    (failures, log)
}

#[test]
fn a_mistyped_command_fails() {
    let (failures, _) = check_one("```sh\nrattle simulte --omega 2.0\n```\n");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("planted.md:1") && failures[0].contains("exited Some(2)"));
    let (failures, _) = check_one("```sh\nrattle simulate --omega 2.0 --periods\n```\n");
    assert_eq!(failures.len(), 1, "{failures:?}");
    let (failures, log) = check_one("```sh\nrattle simulate --omega 2.0\n```\n");
    assert!(failures.is_empty(), "{failures:?}");
    assert_eq!(log.len(), 1, "{log:?}");
}

#[test]
fn a_command_neither_run_nor_listed_fails() {
    let (failures, _) = check_one("Text.\n\n```sh\nmake figures\n```\n");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("`make figures`"), "{failures:?}");
    let (failures, log) =
        check_one("<!-- test: not run: needs make -->\n```sh\nmake figures\n```\n");
    assert!(failures.is_empty(), "{failures:?}");
    assert!(log[0].contains("not run: `make figures`: needs make"));
    let (failures, log) = check_one("```sh\ncargo xtask figures   # every figure\n```\n");
    assert!(
        failures.is_empty() && log[0].contains("not run"),
        "{failures:?}"
    );
}

#[test]
fn an_override_is_applied_and_must_match() {
    let page = "<!-- test: --periods 2000 => --periods 3 -->\n```sh\n\
                rattle simulate --omega 2.0 --periods 2000\n```\n";
    let (failures, log) = check_one(page);
    assert!(failures.is_empty(), "{failures:?}");
    assert!(log[0].contains("--periods 3`"), "{log:?}");
    let (failures, _) = check_one(&page.replace("--periods 2000\n", "--periods 200\n"));
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("matches no command"), "{failures:?}");
}

#[test]
fn a_transcript_checks_the_output_shown() {
    let shown = "```console\n$ rattle simulate --omega 1e-3\nrattle: --omega = 1e-3 is out of range...\n```\n";
    let (failures, _) = check_one(&format!("<!-- test: exit 2 -->\n{shown}"));
    assert!(failures.is_empty(), "{failures:?}");
    // The same refusal without the directive: it exits 2, not 0.
    let (failures, _) = check_one(shown);
    assert_eq!(failures.len(), 1, "{failures:?}");
    // Output that the command does not print.
    let (failures, _) =
        check_one("```console\n$ rattle simulate --omega 2.0\n...\nregime: three-impact\n```\n");
    assert_eq!(failures.len(), 1, "{failures:?}");
    assert!(failures[0].contains("does not print `regime: three-impact`"));
    // Lines out of order.
    let (failures, _) = check_one(
        "```console\n$ rattle simulate --omega 2.0 --periods 10\nperiods run: 10...\nscene paper...\n```\n",
    );
    assert_eq!(failures.len(), 1, "{failures:?}");
    let (failures, _) = check_one(
        "```console\n$ rattle simulate --omega 2.0 --periods 10\nscene paper...\nperiods run: 10...\n```\n",
    );
    assert!(failures.is_empty(), "{failures:?}");
}

#[test]
fn blocks_are_read_as_a_shell_reads_them() {
    let page = "# Title\n\n<!-- test: a => b -->\n<!-- test: exit 1 -->\n```sh\n\
                rattle map x.json --restitutions 40 \\\n    --gaps 40   # the grid\n\
                # a comment line\n\
                cargo install --path crates/compare && rattle orbit --signature \"0+ 1- # x\"\n\
                RAYON_NUM_THREADS=8 rattle map\n```\n\n```json\n{}\n```\n";
    let found = blocks(page, "p.md").expect("the page is read");
    assert_eq!(found.len(), 2);
    assert_eq!(found[0].place, "p.md:5");
    assert_eq!(
        found[0].directives,
        vec![
            Directive::Replace("a".into(), "b".into()),
            Directive::Exit(1)
        ]
    );
    assert_eq!(found[1].language, "json");
    assert!(found[1].directives.is_empty());
    let texts: Vec<String> = steps(&found[0].lines).into_iter().map(|s| s.text).collect();
    assert_eq!(
        texts,
        [
            "rattle map x.json --restitutions 40 --gaps 40",
            "cargo install --path crates/compare && rattle orbit --signature \"0+ 1- # x\"",
            "RAYON_NUM_THREADS=8 rattle map",
        ]
    );
    assert_eq!(
        and_parts(&texts[1]),
        [
            "cargo install --path crates/compare",
            "rattle orbit --signature \"0+ 1- # x\""
        ]
    );
    assert_eq!(as_rattle(&texts[2]).as_deref(), Some(texts[2].as_str()));
    assert_eq!(
        as_rattle("cargo run --release -p rattle-compare -- orbit --omega 2.0").as_deref(),
        Some("rattle orbit --omega 2.0")
    );
    assert_eq!(as_rattle("cargo install --path crates/compare"), None);
    assert_eq!(as_rattle("export RAYON_NUM_THREADS=4"), None);
    assert!(blocks("```\nrattle orbit\n```\n", "p.md").is_err());
    assert!(blocks("```sh\nrattle orbit\n", "p.md").is_err());
    assert!(blocks("<!-- test: nonsense -->\n```sh\nrattle\n```\n", "p.md").is_err());
    assert!(blocks(
        "<!-- test: a => b -->\n\ntext\n```sh\nrattle\n```\n",
        "p.md"
    )
    .is_err());
    assert!(blocks("<!-- test: not run: -->\n```sh\nx\n```\n", "p.md").is_err());
}

/// The options of other programs that the guide names, with the program: every other
/// `--option` written in the guide must be an option of a `rattle` command.
const OTHER_PROGRAMS_OPTIONS: &[(&str, &str)] = &[
    ("cargo", "--all"),
    ("cargo", "--all-targets"),
    ("cargo", "--bench"),
    ("cargo", "--bin"),
    ("cargo", "--check"),
    ("cargo", "--example"),
    ("cargo", "--no-default-features"),
    ("cargo", "--no-deps"),
    ("cargo", "--open"),
    ("cargo", "--path"),
    ("cargo", "--release"),
    ("cargo", "--workspace"),
    ("cargo xtask", "--bad-scenes"),
    ("cargo xtask", "--quick"),
    ("cargo xtask", "--scene"),
    ("cargo xtask", "--scenes"),
    ("cargo xtask", "--seed"),
    ("cargo xtask", "--structures"),
    ("criterion", "--measurement-time"),
    ("criterion", "--noplot"),
    ("criterion", "--warm-up-time"),
    ("sbatch", "--array"),
    ("sbatch", "--cpus-per-task"),
    ("sbatch", "--dependency"),
    ("scipy_compliant.py", "--method"),
    ("scipy_compliant.py", "--rattle"),
    ("scipy_compliant.py", "--repeats"),
    ("scipy_compliant.py", "--stiffness"),
];

/// Every `--option` in `text`: two dashes, then a lower-case word with dashes.
fn options(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for (i, _) in text.match_indices("--") {
        let before = text[..i].chars().next_back();
        if before.is_some_and(|c| c.is_alphanumeric() || c == '-') {
            continue;
        }
        let name: String = text[i + 2..]
            .chars()
            .take_while(|c| c.is_ascii_lowercase() || *c == '-')
            .collect();
        let name = name.trim_end_matches('-');
        if name.chars().next().is_some_and(|c| c.is_ascii_lowercase()) {
            found.push(format!("--{name}"));
        }
    }
    found
}

#[test]
fn every_option_the_guide_names_exists() {
    let commands = [
        "orbit",
        "family",
        "simulate",
        "compare",
        "continue",
        "boundary",
        "boundaries",
        "sweep",
        "merge",
        "map",
        "basins",
        "respond",
        "transmission",
    ];
    let mut known = std::collections::BTreeSet::new();
    for command in commands {
        let out = Command::new(env!("CARGO_BIN_EXE_rattle"))
            .args([command, "--help"])
            .output()
            .expect("rattle runs");
        assert!(out.status.success(), "rattle {command} --help");
        known.extend(options(&String::from_utf8_lossy(&out.stdout)));
    }
    assert!(
        known.contains("--omega") && known.contains("--shard"),
        "{known:?}"
    );
    let mut used = vec![false; OTHER_PROGRAMS_OPTIONS.len()];
    let mut unknown = Vec::new();
    for (page, text) in guide() {
        for option in options(&text) {
            if let Some(k) = OTHER_PROGRAMS_OPTIONS
                .iter()
                .position(|(_, o)| *o == option)
            {
                used[k] = true;
            } else if !known.contains(&option) {
                unknown.push(format!("{page}: {option}"));
            }
        }
    }
    unknown.dedup();
    assert!(
        unknown.is_empty(),
        "options no rattle command has: {unknown:?}"
    );
    for ((program, option), used) in OTHER_PROGRAMS_OPTIONS.iter().zip(used) {
        assert!(
            used,
            "OTHER_PROGRAMS_OPTIONS lists {program}'s {option}, which no page names"
        );
    }
}

#[test]
fn options_are_found_in_prose() {
    assert_eq!(
        options("`--omega W`, --max-periods, a -- b, x--y, --Upper, `--shard K/N`—"),
        ["--omega", "--max-periods", "--shard"]
    );
}
