//! Tidy tests: conventions of the repository that a reviewer would otherwise have to catch.

use crate::root;
use std::path::{Path, PathBuf};

/// The modules of `rattle-compare` from the bottom up: a module may use those at its own rank
/// or below, never one above it (data flows one way, from scene to figure).
const LAYERS: [&str; 8] = [
    "scene", "output", "verdict", "runs", "peers", "study", "figures", "cli",
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

/// The lines of a file that are code: up to its `#[cfg(test)]` module, comments dropped.
fn code_lines(path: &Path) -> Vec<(usize, String)> {
    let text = std::fs::read_to_string(path).expect("source files are readable");
    text.lines()
        .enumerate()
        .take_while(|(_, l)| l.trim() != "#[cfg(test)]")
        .filter(|(_, l)| !l.trim_start().starts_with("//"))
        .map(|(i, l)| (i + 1, l.to_owned()))
        .collect()
}

/// The top-level module of `rattle-compare` a source file belongs to.
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).ok()?;
    let first = rel.components().next()?.as_os_str().to_str()?;
    Some(first.trim_end_matches(".rs").to_owned())
}

/// The modules a line names as `crate::NAME`.
fn crate_paths(line: &str) -> Vec<String> {
    line.match_indices("crate::")
        .map(|(i, m)| {
            line[i + m.len()..]
                .chars()
                .take_while(|c| c.is_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

/// The solver-side crates whose top-level modules may not use each other in a circle
/// (`crate::a` in `b` and `crate::b` in `a`, directly or through others): all three.
const CIRCLE_FREE: [&str; 3] = [
    "crates/analytic/src",
    "crates/event-driven/src",
    "crates/compare/src",
];

/// The top-level modules of the crate at `src` and, for each, the modules its code lines name
/// as `crate::NAME` (itself and unknown names left out).
fn module_uses(src: &Path) -> std::collections::BTreeMap<String, Vec<String>> {
    let mut uses: std::collections::BTreeMap<String, Vec<String>> = Default::default();
    let files = rust_files(src);
    for file in &files {
        if let Some(module) = module_of(src, file) {
            uses.entry(module).or_default();
        }
    }
    for file in &files {
        let Some(module) = module_of(src, file) else {
            continue;
        };
        let named: Vec<String> = code_lines(file)
            .iter()
            .flat_map(|(_, line)| crate_paths(line))
            .filter(|used| *used != module && uses.contains_key(used))
            .collect();
        let entry = uses.entry(module).or_default();
        entry.extend(named);
        entry.sort();
        entry.dedup();
    }
    uses
}

/// The circles of a use graph: its strongly connected groups of more than one module
/// (Tarjan's algorithm), each sorted.
fn circles(uses: &std::collections::BTreeMap<String, Vec<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        uses: &'a std::collections::BTreeMap<String, Vec<String>>,
        index: std::collections::BTreeMap<&'a str, (usize, usize)>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(w: &mut Walk<'a>, v: &'a str) {
        let n = w.index.len();
        w.index.insert(v, (n, n));
        w.stack.push(v);
        let uses = w.uses;
        for u in &uses[v] {
            let low = match w.index.get(u.as_str()) {
                None => {
                    visit(w, u);
                    w.index[u.as_str()].1
                }
                Some(&(i, _)) if w.stack.contains(&u.as_str()) => i,
                Some(_) => continue,
            };
            let entry = w.index.get_mut(v).expect("visited");
            entry.1 = entry.1.min(low);
        }
        let (i, low) = w.index[v];
        if i == low {
            let at = w.stack.iter().rposition(|m| *m == v).expect("on the stack");
            let mut group: Vec<String> = w.stack.drain(at..).map(str::to_owned).collect();
            if group.len() > 1 {
                group.sort();
                w.found.push(group);
            }
        }
    }
    let mut w = Walk {
        uses,
        index: Default::default(),
        stack: Vec::new(),
        found: Vec::new(),
    };
    for v in uses.keys() {
        if !w.index.contains_key(v.as_str()) {
            visit(&mut w, v);
        }
    }
    w.found
}

#[test]
fn no_import_circle_in_the_solver_crates() {
    for krate in CIRCLE_FREE {
        let uses = module_uses(&root().join(krate));
        assert!(
            uses.len() > 6,
            "only {} modules in {krate}: has the crate moved?",
            uses.len()
        );
        let found = circles(&uses);
        assert!(found.is_empty(), "import circles in {krate}: {found:?}");
    }
}

#[test]
fn an_import_circle_is_found() {
    let uses = [
        ("a", vec!["b"]),
        ("b", vec!["c"]),
        ("c", vec!["a"]),
        ("d", vec!["a"]),
    ]
    .into_iter()
    .map(|(m, u)| (m.to_owned(), u.into_iter().map(str::to_owned).collect()))
    .collect();
    assert_eq!(circles(&uses), vec![vec!["a", "b", "c"]]);
}

#[test]
fn no_module_of_compare_uses_one_above_it() {
    let src = root().join("crates/compare/src");
    let rank = |m: &str| LAYERS.iter().position(|l| *l == m);
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in rust_files(&src) {
        let Some(module) = module_of(&src, &file) else {
            continue;
        };
        let Some(own) = rank(&module) else {
            continue; // lib.rs, main.rs
        };
        checked += 1;
        for (n, line) in code_lines(&file) {
            for used in crate_paths(&line) {
                if rank(&used).is_some_and(|r| r > own) {
                    broken.push(format!("{}:{n}: {module} uses {used}", file.display()));
                }
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

/// The package and the command are both thin layers over the library (issue #25): the package
/// calls the library's functions, never the command's.
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

#[test]
fn the_crate_paths_of_a_line_are_found() {
    assert_eq!(
        crate_paths("use crate::runs::map::{Map}; crate::scene::Scene"),
        vec!["runs".to_owned(), "scene".to_owned()]
    );
}

/// Longest a function of a solver crate may be, in lines from its `fn` line to its closing
/// brace (issue #22: no function over 150 lines).
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
