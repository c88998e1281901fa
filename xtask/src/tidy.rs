//! Tidy tests: conventions of the repository that a reviewer would otherwise have to catch.

mod history;
mod imports;
mod rust;

use crate::root;
use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

/// The modules of `rattle-compare` from the bottom up: a module may use those at its own rank
/// or below, never one above it (data flows one way, from scene to figure).
const LAYERS: [&str; 10] = [
    "spectrum", "scene", "output", "verdict", "runs", "peers", "study", "figures", "api", "cli",
];

fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_owned()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).expect("source folders are readable") {
            let path = entry.expect("directory entries are readable").path();
            if path.is_dir() {
                stack.push(path);
            } else if path.extension().is_some_and(|e| e == "rs") {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}

/// The lines of a file that are code (numbered from 1): comments and the items compiled for
/// tests only (`#[cfg(test)]`, brace-matched) blanked, blank lines left out.
fn code_lines(path: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(path).expect("source files are readable");
    rust::code_text(&text)
        .lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty())
        .map(|(i, l)| (i + 1, l.to_owned()))
        .collect()
}

/// The top-level module of `rattle-compare` a source file belongs to (`runs` for
/// `runs/map.rs`, `lib` for `lib.rs`).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    top_module(&rel.to_string_lossy())
}

/// The top-level module of a path relative to a crate's source folder.
fn top_module(relative: &str) -> Option<String> {
    let first = relative.split(['/', '\\']).next()?;
    Some(first.trim_end_matches(".rs").to_owned())
}

/// The crates whose modules may not use each other in a circle, at any level of their module
/// tree (a file of `a` naming an item of `b` and one of `b` an item of `a`, directly or
/// through others; see [`imports::module_circles`]): all three.
const CIRCLE_FREE: [&str; 3] = [
    "crates/analytic/src",
    "crates/event-driven/src",
    "crates/compare/src",
];

/// Import circles that are known and not yet broken, each a crate's source folder, the
/// module that holds the circle (`""` for the crate root), its members (sorted, as
/// [`imports::module_circles`] gives them) and what closes it. Each is to be broken by moving
/// the shared piece to the module that owns it (here the Schur constants to `flow`,
/// `transmittance_db` or the chain's cell check to one side of `linear` and `problem`, the
/// engine's run state apart from the steps that read it), and its entry removed. The test
/// fails on any other circle, and on an entry here that no longer matches a circle (a circle
/// that is broken leaves the list; one that grows is a new circle).
const KNOWN_CIRCLES: &[(&str, &str, &[&str], &str)] = &[
    (
        "crates/analytic/src",
        "",
        &["closed_form", "flow"],
        "the closed forms build on the unit's flows (`crate::flow::ForcedFlow`), and \
         `flow/model_flight.rs` takes the Schur iteration's constants from \
         `closed_form/orbit.rs` (`crate::orbit::SCHUR_*`)",
    ),
    (
        "crates/analytic/src",
        "",
        &["linear", "problem"],
        "`problem/chain.rs` calls `crate::linear::transmittance_db`, and `linear/lattice.rs` \
         names `crate::chain::Cell` and `crate::chain::check`",
    ),
    (
        "crates/event-driven/src",
        "engine",
        &[
            "contact", "flight", "pressed", "state", "stuck", "tangent", "trace",
        ],
        "the engine's steps are methods of one `Engine` spread over its files: the run state \
         (`state.rs`) holds the trace, the stuck and the pressed (compliant contact) phases and \
         the tangent, whose steps read it",
    ),
];

#[test]
fn no_import_circle_in_the_solver_crates() {
    let mut unexpected = Vec::new();
    let mut known_found = BTreeSet::new();
    for krate in CIRCLE_FREE {
        let graph = imports::file_graph(&imports::read_sources(&root().join(krate)));
        assert!(
            graph.len() > 20,
            "only {} files in {krate}: has the crate moved?",
            graph.len()
        );
        for circle in imports::module_circles(&graph) {
            let known = KNOWN_CIRCLES.iter().position(|(k, module, members, _)| {
                *k == krate && circle.module == *module && circle.members == *members
            });
            match known {
                Some(i) => {
                    known_found.insert(i);
                }
                None => unexpected.push(format!(
                    "{krate}, in module `{}`: {{{}}}, closed by\n    {}",
                    if circle.module.is_empty() {
                        "crate"
                    } else {
                        &circle.module
                    },
                    circle.members.join(", "),
                    circle.uses.join("\n    ")
                )),
            }
        }
    }
    let stale: Vec<String> = KNOWN_CIRCLES
        .iter()
        .enumerate()
        .filter(|(i, _)| !known_found.contains(i))
        .map(|(_, (krate, module, members, _))| format!("{krate}, `{module}`: {members:?}"))
        .collect();
    assert!(
        unexpected.is_empty(),
        "import circles (move the shared piece to the module that owns it):\n{}",
        unexpected.join("\n")
    );
    assert!(
        stale.is_empty(),
        "KNOWN_CIRCLES entries that match no circle any more (remove them):\n{}",
        stale.join("\n")
    );
}

#[test]
fn no_module_of_compare_uses_one_above_it() {
    let src = root().join("crates/compare/src");
    let rank = |m: &str| LAYERS.iter().position(|l| *l == m);
    let graph = imports::file_graph(&imports::read_sources(&src));
    let mut broken = Vec::new();
    let mut checked = 0;
    for (file, used) in &graph {
        let Some(own) = top_module(file).and_then(|m| rank(&m)) else {
            continue; // lib.rs
        };
        checked += 1;
        for target in used.keys() {
            let above = top_module(target)
                .and_then(|m| rank(&m))
                .is_some_and(|r| r > own);
            if above {
                broken.push(format!("{file} uses {target}"));
            }
        }
    }
    assert!(
        checked > 20,
        "only {checked} files checked: has the crate moved?"
    );
    assert!(
        broken.is_empty(),
        "uses against the layering:\n{}",
        broken.join("\n")
    );
}

/// Whether Rust source `text` names the command's module `rattle_compare::cli`, as a path
/// (`rattle_compare::cli::…`) or in a group (`use rattle_compare::{cli, …}`), whatever the
/// spacing and line breaks.
fn uses_the_command(text: &str) -> bool {
    let code: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    if code.contains("rattle_compare::cli") {
        return true;
    }
    code.match_indices("rattle_compare::{").any(|(i, m)| {
        // The group's top-level items, up to its closing brace.
        let mut depth = 0usize;
        let mut item = String::new();
        for c in code[i + m.len()..].chars() {
            match c {
                '{' => depth += 1,
                '}' if depth == 0 => break,
                '}' => depth -= 1,
                ',' if depth == 0 => {
                    if item == "cli" || item.starts_with("cli::") {
                        return true;
                    }
                    item.clear();
                    continue;
                }
                _ => {}
            }
            item.push(c);
        }
        item == "cli" || item.starts_with("cli::")
    })
}

/// The package and the command are both thin layers over the library: the package calls the
/// library's functions, never the command's.
#[test]
fn the_python_package_does_not_use_the_command() {
    let src = root().join("crates/python/src");
    let files = rust_files(&src);
    assert!(
        !files.is_empty(),
        "no sources in {}: has the crate moved?",
        src.display()
    );
    let broken: Vec<String> = files
        .iter()
        .filter(|file| {
            uses_the_command(&std::fs::read_to_string(file).expect("source files are readable"))
        })
        .map(|file| file.display().to_string())
        .collect();
    assert!(
        broken.is_empty(),
        "the Python package uses the command's module `rattle_compare::cli` (call the library \
         instead): {}",
        broken.join(", ")
    );
}

#[test]
fn a_use_of_the_command_is_found() {
    assert!(uses_the_command(
        "use rattle_compare::cli::{Accuracy, RattleError};"
    ));
    assert!(uses_the_command(
        "    rattle_compare::cli::refuse_chain(scene, f)"
    ));
    assert!(uses_the_command(
        "use rattle_compare::{\n    cli,\n    scene::Scene,\n};"
    ));
    assert!(uses_the_command(
        "use rattle_compare::{output::{Row, Format}, cli::simulate::LyapunovArgs};"
    ));
    assert!(!uses_the_command(
        "use rattle_compare::scene::simulator::Accuracy;"
    ));
    assert!(!uses_the_command(
        "use rattle_compare::{output::{cli_like, Row}, scene::Scene};"
    ));
}

#[test]
fn only_figures_draw_and_figures_only_draw() {
    let src = root().join("crates/compare/src");
    let mut broken = Vec::new();
    for file in rust_files(&src) {
        let module = module_of(&src, &file).unwrap_or_default();
        for (n, line) in code_lines(&file) {
            let at = || format!("{}:{n}", file.display());
            if module != "figures" && line.contains("plotters") {
                broken.push(format!("{}: plotters outside figures/", at()));
            }
            // A figure calls no solver (it may name the solvers' data types): its data come
            // computed from the study.
            if module == "figures" && calls_a_solver(&line) {
                broken.push(format!("{}: a figure calls a solver", at()));
            }
        }
    }
    assert!(broken.is_empty(), "{}", broken.join("\n"));
}

/// Whether `line` calls a function of a solver crate (`rattle_analytic::x(`, `…::y::f(`) or
/// imports one (`use rattle_analytic::{f, …}` with a lower-case item).
fn calls_a_solver(line: &str) -> bool {
    ["rattle_analytic::", "rattle_event_driven::"]
        .iter()
        .any(|krate| {
            line.match_indices(krate).any(|(i, m)| {
                let path: String = line[i + m.len()..]
                    .chars()
                    .take_while(|c| {
                        c.is_alphanumeric()
                            || *c == '_'
                            || *c == ':'
                            || *c == '{'
                            || *c == ','
                            || *c == ' '
                    })
                    .collect();
                let mut items = path.split([':', '{', ',', ' ']).filter(|s| !s.is_empty());
                let last_is_function = items.clone().next_back().is_some_and(|item| {
                    item.starts_with(|c: char| c.is_lowercase())
                        && line[i + m.len() + path.len()..].starts_with('(')
                });
                // The imported leaves: the items in braces, or the last segment.
                let leaves: Vec<&str> = match path.split_once('{') {
                    Some((_, inner)) => inner.split([',', ' ']).filter(|s| !s.is_empty()).collect(),
                    None => items.next_back().into_iter().collect(),
                };
                let imports_function = line.trim_start().starts_with("use ")
                    && leaves
                        .iter()
                        .any(|item| item.starts_with(|c: char| c.is_lowercase()));
                last_is_function || imports_function
            })
        })
}

#[test]
fn library_code_never_unwraps() {
    let mut broken = Vec::new();
    for krate in ["analytic", "event-driven", "compare"] {
        for file in rust_files(&root().join("crates").join(krate).join("src")) {
            for (n, line) in code_lines(&file) {
                if line.contains(".unwrap()") {
                    broken.push(format!("{}:{n}", file.display()));
                }
            }
        }
    }
    assert!(
        broken.is_empty(),
        "`.unwrap()` in library code (return an error, or `.expect` an invariant and say why):\n{}",
        broken.join("\n")
    );
}

#[test]
fn ci_checks_what_the_brief_asks() {
    let ci = std::fs::read_to_string(root().join(".ci/run")).expect(".ci/run exists");
    for step in [
        "cargo fmt --all --check",
        "cargo clippy --workspace --all-targets -- -D warnings",
        "cargo test --workspace",
        "cargo doc --workspace --no-deps",
        "RUSTDOCFLAGS=\"-D warnings\"",
    ] {
        assert!(ci.contains(step), ".ci/run does not run `{step}`");
    }
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md exists");
    assert!(readme.contains("cargo xtask figures") && readme.contains("cargo test --workspace"));
}

#[test]
fn every_committed_figure_is_in_the_readme() {
    let readme = std::fs::read_to_string(root().join("README.md")).expect("README.md exists");
    let mut missing = Vec::new();
    for entry in std::fs::read_dir(root().join("figures")).expect("figures/ exists") {
        let path = entry.expect("readable").path();
        if path.extension().is_some_and(|e| e == "png") {
            let name = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            if !readme.contains(&format!("figures/{name}")) {
                missing.push(name.to_owned());
            }
        }
    }
    assert!(
        missing.is_empty(),
        "figures not shown in README.md: {missing:?}"
    );
}

#[test]
fn solver_calls_are_told_from_solver_types() {
    assert!(calls_a_solver(
        "let r = rattle_analytic::linear_response(&u, w);"
    ));
    assert!(calls_a_solver(
        "use rattle_analytic::{linear_response, Orbit};"
    ));
    assert!(calls_a_solver(
        "rattle_event_driven::simulate(&m, w, &s, &o)"
    ));
    assert!(!calls_a_solver(
        "let o: Option<&rattle_analytic::Orbit> = None;"
    ));
    assert!(!calls_a_solver("use rattle_analytic::Orbit;"));
}

/// Longest a function of a solver crate may be, in lines from its `fn` line to its closing
/// brace: a longer one is split into named steps.
const MAX_FUNCTION_LINES: usize = 150;

/// Whether a trimmed line opens a function: `fn name` after optional visibility and
/// qualifiers.
fn opens_function(trimmed: &str) -> Option<String> {
    let mut rest = trimmed;
    if let Some(after) = rest.strip_prefix("pub") {
        rest = match after.strip_prefix('(') {
            Some(inner) => inner.split_once(')')?.1,
            None => after,
        }
        .trim_start();
    }
    for qualifier in ["const ", "async ", "unsafe ", "extern \"C\" "] {
        rest = rest.strip_prefix(qualifier).unwrap_or(rest);
    }
    let name: String = rest
        .strip_prefix("fn ")?
        .chars()
        .take_while(|c| c.is_alphanumeric() || *c == '_')
        .collect();
    (!name.is_empty()).then_some(name)
}

/// The net braces `{` minus `}` of the code of `line`, string and character literals and
/// comments left out; `in_block_comment` carries a `/* … */` comment over lines (raw strings
/// spanning lines are not told apart: the solver crates have none with braces).
fn brace_balance(line: &str, in_block_comment: &mut usize) -> i64 {
    let chars: Vec<char> = line.chars().collect();
    let (mut i, mut net) = (0, 0i64);
    while i < chars.len() {
        let (c, next) = (chars[i], chars.get(i + 1).copied());
        if *in_block_comment > 0 {
            match (c, next) {
                ('*', Some('/')) => (*in_block_comment -= 1, i += 1).1,
                ('/', Some('*')) => (*in_block_comment += 1, i += 1).1,
                _ => {}
            }
        } else {
            match (c, next) {
                ('/', Some('/')) => break,
                ('/', Some('*')) => (*in_block_comment += 1, i += 1).1,
                ('"', _) => {
                    i += 1;
                    while i < chars.len() && chars[i] != '"' {
                        i += if chars[i] == '\\' { 2 } else { 1 };
                    }
                }
                // A character literal ('{', '\n'); a lifetime ('a) has no closing quote there.
                ('\'', Some('\\')) => {
                    i += 2;
                    while i < chars.len() && chars[i] != '\'' {
                        i += 1;
                    }
                }
                ('\'', Some(_)) if chars.get(i + 2) == Some(&'\'') => i += 2,
                ('{', _) => net += 1,
                ('}', _) => net -= 1,
                _ => {}
            }
        }
        i += 1;
    }
    net
}

/// Every function of the Rust source `text` longer than `max` lines: its first line, name and
/// length (from the `fn` line to its closing brace; a body-less declaration has none).
fn long_functions(text: &str, max: usize) -> Vec<(usize, String, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut found = Vec::new();
    for (start, line) in lines.iter().enumerate() {
        let Some(name) = opens_function(line.trim_start()) else {
            continue;
        };
        let (mut depth, mut opened, mut comment) = (0i64, false, 0usize);
        for (n, body) in lines.iter().enumerate().skip(start) {
            if !opened && depth == 0 && body.trim_end().ends_with(';') && !body.contains('{') {
                break; // a declaration without a body
            }
            depth += brace_balance(body, &mut comment);
            opened |= depth > 0;
            if opened && depth <= 0 {
                let length = n - start + 1;
                if length > max {
                    found.push((start + 1, name.clone(), length));
                }
                break;
            }
        }
    }
    found
}

#[test]
fn no_function_over_150_lines_in_the_solver_crates() {
    let mut long = Vec::new();
    let mut checked = 0;
    for krate in CIRCLE_FREE {
        for file in rust_files(&root().join(krate)) {
            let relative = file.strip_prefix(root()).unwrap_or(&file).to_owned();
            let shown = relative.display().to_string();
            checked += 1;
            let text = std::fs::read_to_string(&file).expect("source files are readable");
            for (line, name, length) in long_functions(&text, MAX_FUNCTION_LINES) {
                long.push(format!("{shown}:{line}: fn {name} is {length} lines"));
            }
        }
    }
    assert!(
        checked > 50,
        "only {checked} files checked: have the crates moved?"
    );
    assert!(
        long.is_empty(),
        "functions over {MAX_FUNCTION_LINES} lines (split them into steps):\n{}",
        long.join("\n")
    );
}

#[test]
fn a_long_function_is_found() {
    let body = "    let s = \"}}\"; let c = '}'; // }\n".repeat(3);
    let text = format!(
        "pub(crate) fn short() {{\n{body}}}\nfn declared();\n\
         pub fn long<'a>(x: &'a str) -> &'a str {{\n    /* {{ */\n{body}{body}    x\n}}\n"
    );
    assert_eq!(long_functions(&text, 8), vec![(7, "long".to_owned(), 10)]);
    assert_eq!(long_functions(&text, 10), vec![]);
    assert_eq!(
        opens_function("pub(crate) const fn f() {"),
        Some("f".to_owned())
    );
    assert_eq!(opens_function("let fn_name = 1;"), None);
}

/// Longest a source file may be, in lines: a longer one is split by job into a module folder,
/// its `mod.rs` re-exporting each part's items (as `runs/basins/` is split), or a Python
/// package's modules re-exported by its `__init__.py`.
const MAX_FILE_LINES: usize = 1000;

/// The folders of every crate (`crates/NAME/…`) whose source files are held to
/// [`MAX_FILE_LINES`] (`python`: a Python package's own modules).
const CRATE_FOLDERS: [&str; 5] = ["src", "tests", "examples", "benches", "python"];

/// The endings of the source files held to [`MAX_FILE_LINES`]: Rust, and the Python of the
/// package and its tests.
const SOURCE_ENDINGS: [&str; 2] = [".rs", ".py"];

/// Whether `relative`, a path from the repository's root, is a source file held to
/// [`MAX_FILE_LINES`]: Rust or Python ([`SOURCE_ENDINGS`]) under one of a crate's
/// [`CRATE_FOLDERS`] or under `xtask/src`, and in no `target` or hidden folder (build output,
/// not source).
fn is_source_file(relative: &str) -> bool {
    let parts: Vec<&str> = relative.split(['/', '\\']).collect();
    let held = match parts.as_slice() {
        ["crates", _, folder, _, ..] => CRATE_FOLDERS.contains(folder),
        ["xtask", "src", _, ..] => true,
        _ => false,
    };
    let built = parts[..parts.len() - 1]
        .iter()
        .any(|p| *p == "target" || p.starts_with('.'));
    held && !built && SOURCE_ENDINGS.iter().any(|e| relative.ends_with(e))
}

/// The source files of the repository at `root` that [`is_source_file`] picks, by path from the
/// root (`/`-separated), with their text.
fn source_files(root: &Path) -> BTreeMap<String, String> {
    let mut stack = vec![root.join("xtask/src")];
    for entry in std::fs::read_dir(root.join("crates")).expect("crates/ is readable") {
        let krate = entry.expect("directory entries are readable").path();
        stack.extend(CRATE_FOLDERS.iter().map(|f| krate.join(f)));
    }
    stack.retain(|d| d.is_dir());
    let mut out = BTreeMap::new();
    while let Some(dir) = stack.pop() {
        for entry in std::fs::read_dir(&dir).expect("source folders are readable") {
            let path = entry.expect("directory entries are readable").path();
            let name = path
                .file_name()
                .and_then(|n| n.to_str())
                .unwrap_or_default();
            let relative = path
                .strip_prefix(root)
                .unwrap_or(&path)
                .to_string_lossy()
                .replace('\\', "/");
            if path.is_dir() {
                if !(name == "target" || name.starts_with('.')) {
                    stack.push(path);
                }
            } else if is_source_file(&relative) {
                let text = std::fs::read_to_string(&path).expect("source files are readable");
                out.insert(relative, text);
            }
        }
    }
    out
}

/// Every file of `sources` (path and text) longer than `max` lines, with its length, in path
/// order.
fn long_files(sources: &BTreeMap<String, String>, max: usize) -> Vec<(String, usize)> {
    sources
        .iter()
        .map(|(path, text)| (path.clone(), text.lines().count()))
        .filter(|(_, length)| *length > max)
        .collect()
}

#[test]
fn no_source_file_over_1000_lines() {
    let sources = source_files(&root());
    assert!(
        sources.len() > 100,
        "only {} files checked: has the repository moved?",
        sources.len()
    );
    let long: Vec<String> = long_files(&sources, MAX_FILE_LINES)
        .into_iter()
        .map(|(path, length)| format!("{path}: {length} lines"))
        .collect();
    assert!(
        long.is_empty(),
        "source files over {MAX_FILE_LINES} lines (split each by job into a module folder, its \
         `mod.rs` re-exporting the parts' items):\n{}",
        long.join("\n")
    );
}

#[test]
fn a_long_source_file_is_found() {
    let lines = |n: usize| "fn f() {}\n".repeat(n);
    let planted: BTreeMap<String, String> = [
        ("crates/a/src/lib.rs", lines(MAX_FILE_LINES)),
        ("crates/a/src/deep/long.rs", lines(MAX_FILE_LINES + 1)),
        ("crates/python/tests/t.rs", lines(1200)),
        ("xtask/src/main.rs", lines(3)),
    ]
    .into_iter()
    .map(|(path, text)| (path.to_owned(), text))
    .collect();
    assert_eq!(
        long_files(&planted, MAX_FILE_LINES),
        [
            ("crates/a/src/deep/long.rs".to_owned(), 1001),
            ("crates/python/tests/t.rs".to_owned(), 1200)
        ]
    );
    for picked in [
        "crates/a/src/lib.rs",
        "crates/python/src/deep/m.rs",
        "crates/a/tests/t.rs",
        "crates/a/examples/e.rs",
        "crates/a/benches/b.rs",
        "xtask/src/tidy/rust.rs",
        "crates/python/python/rattle/__init__.py",
        "crates/python/tests/test_x.py",
    ] {
        assert!(is_source_file(picked), "{picked} is left out");
    }
    for skipped in [
        "crates/a/target/debug/build/x.rs",
        "crates/a/src/target/x.rs",
        "crates/a/src/.cache/x.rs",
        "target/debug/x.rs",
        "crates/a/peers/x.rs",
        "crates/a/build.rs",
        "crates/a/src/notes.md",
        "xtask/build.rs",
        "docs/x.rs",
        "validation/peers/x.py",
    ] {
        assert!(!is_source_file(skipped), "{skipped} is picked");
    }
}

/// The crates whose every public item has one path, at the crate's root: their modules are
/// private (the test fixtures behind the `fixtures` feature aside).
const FLAT_CRATES: [&str; 2] = [
    "crates/analytic/src/lib.rs",
    "crates/event-driven/src/lib.rs",
];

/// The second public paths in `sources` (path and text): a file that declares `pub mod m`
/// and also re-exports from `m` (`pub use m::…`, `pub use self::m::…`) gives each re-exported
/// item two paths; a crate of [`FLAT_CRATES`] that declares a public module other than
/// `test_models` gives its items a path besides the root's. Each as `path: line`.
fn second_public_paths(sources: &BTreeMap<String, String>) -> Vec<String> {
    let mut out = Vec::new();
    for (path, text) in sources {
        let code = rust::code_text(text);
        let public: BTreeSet<&str> = code
            .lines()
            .filter_map(|l| l.trim().strip_prefix("pub mod "))
            .map(|rest| rest.trim_end_matches(';').trim())
            .collect();
        for line in code.lines().map(str::trim) {
            let Some(used) = line.strip_prefix("pub use ") else {
                continue;
            };
            let used = used.strip_prefix("self::").unwrap_or(used);
            let module = used.split("::").next().unwrap_or_default();
            if used.contains("::") && public.contains(module) {
                out.push(format!("{path}: {line}"));
            }
        }
        if FLAT_CRATES.contains(&path.as_str()) {
            out.extend(
                public
                    .iter()
                    .filter(|m| **m != "test_models")
                    .map(|m| format!("{path}: pub mod {m};")),
            );
        }
    }
    out
}

#[test]
fn every_public_item_has_one_path() {
    let sources = source_files(&root());
    for flat in FLAT_CRATES {
        assert!(sources.contains_key(flat), "{flat} is not read");
    }
    let second = second_public_paths(&sources);
    assert!(
        second.is_empty(),
        "items with a second public path (keep the module private and the item at one \
         path):\n{}",
        second.join("\n")
    );
}

#[test]
fn a_second_public_path_is_found() {
    let planted: BTreeMap<String, String> = [
        (
            "crates/analytic/src/lib.rs",
            "mod flow;\npub mod linear;\n#[cfg(feature = \"fixtures\")]\npub mod test_models;\n\
             pub use flow::join;\n",
        ),
        (
            "crates/a/src/output/mod.rs",
            "pub mod rename;\nmod csv;\npub use self::rename::Renamed;\npub use csv::Writer;\n",
        ),
        ("crates/a/src/lib.rs", "pub mod api;\npub use std::fmt;\n"),
    ]
    .into_iter()
    .map(|(path, text)| (path.to_owned(), text.to_owned()))
    .collect();
    assert_eq!(
        second_public_paths(&planted),
        [
            "crates/a/src/output/mod.rs: pub use self::rename::Renamed;",
            "crates/analytic/src/lib.rs: pub mod linear;",
        ]
    );
}
