//! The import graph of a crate, file by file, and its circles at every level of the module
//! tree.
//!
//! A file's code is its tokens without comments and without the items compiled for tests only
//! ([`super::rust::test_only`], brace-matched: a `mod tests { … }` block, not the rest of the
//! file after a `#[cfg(test)]` line). Its modules are those its `mod` declarations name
//! (`a.rs` or `a/mod.rs`, and `a/b.rs` for `mod b;` in either). A path in the code — in a
//! `use` tree or inline (`crate::a::f()`, `super::T`, `self::b::C`, `b::f()` for a child
//! module `b` or a name a `use` binds) — is followed segment by segment to the file that
//! defines its item, through the `use` aliases on the way (`pub use` re-exports of the crate
//! root and of any module, private imports that a child reaches by `super::`) and through glob
//! imports (`use super::*`). A file then uses:
//! - the item of every private `use` of an item (a trait imported for its methods included);
//! - the item of a `pub use` whose name its own code names (a re-export alone is an alias, not
//!   a use);
//! - the item of every inline path;
//! - for a glob import, the items its code names that the glob brings in;
//!
//! and never the files of the modules that hold it (its `mod.rs` ancestors and the crate
//! root): a module's own file is where the pieces its parts share live.
//!
//! A circle is one among the modules that one module holds ([`module_circles`]): in the crate
//! root among the top-level modules (`closed_form` and `flow`), in `continuation` among its
//! files (`branches`, `system`), a file in a module's subtree standing for the module.
//!
//! Left out: macros' textual scope, and paths inside an inline `mod name { … }` read as the
//! file's own (the crates have one such module, of constants).

use super::rust::{self, Kind, Token};
use std::collections::{BTreeMap, BTreeSet};

/// One binding of a `use` tree: the path it names and the name it binds (`None` for a glob).
#[derive(Debug, Clone, PartialEq)]
struct Use {
    path: Vec<String>,
    name: Option<String>,
    public: bool,
}

/// What the graph needs of one source file.
#[derive(Debug, Default)]
struct File {
    /// Its path relative to the crate's source folder (`runs/basins.rs`).
    path: String,
    /// Its module path (`["runs", "basins"]`; the crate root `[]`).
    module: Vec<String>,
    /// Its code's tokens outside `use` declarations.
    code: Vec<Token>,
    uses: Vec<Use>,
    /// The names of the items it defines at its top level (inline modules included).
    defined: BTreeSet<String>,
    /// The modules its `mod NAME;` declarations name.
    children: BTreeSet<String>,
}

/// Where a path leads.
#[derive(Debug, Clone, PartialEq)]
enum Target {
    /// A module, by its module path.
    Module(Vec<String>),
    /// An item, by the index of the file that defines it.
    Item(usize),
}

/// The items of a `use` tree starting at `tokens[i]` (after `use` and any leading `::`), under
/// `prefix`; returns the index past the tree.
fn use_tree(
    tokens: &[Token],
    mut i: usize,
    prefix: &[String],
    public: bool,
    out: &mut Vec<Use>,
) -> usize {
    let mut path = prefix.to_vec();
    loop {
        let Some(t) = tokens.get(i) else {
            return i;
        };
        match (t.kind, t.text.as_str()) {
            (Kind::Punct, "::") => i += 1,
            (Kind::Punct, "*") => {
                out.push(Use {
                    path,
                    name: None,
                    public,
                });
                return i + 1;
            }
            (Kind::Punct, "{") => {
                i += 1;
                while let Some(t) = tokens.get(i) {
                    if t.is("}") {
                        return i + 1;
                    }
                    if t.is(",") {
                        i += 1;
                        continue;
                    }
                    let before = i;
                    i = use_tree(tokens, i, &path, public, out);
                    if i == before {
                        i += 1;
                    }
                }
                return i;
            }
            (Kind::Ident, segment) => {
                i += 1;
                let continues = tokens.get(i).is_some_and(|t| t.is("::"));
                // `self` closing a path in a group binds the group's module.
                if !(segment == "self" && !continues && !path.is_empty()) {
                    path.push(segment.to_owned());
                }
                if continues {
                    i += 1;
                    continue;
                }
                let mut name = path.last().cloned();
                if tokens.get(i).is_some_and(|t| t.is("as")) {
                    name = tokens.get(i + 1).map(|t| t.text.clone());
                    i += 2;
                }
                out.push(Use { path, name, public });
                return i;
            }
            _ => return i,
        }
    }
}

/// The module path of a file from its path relative to the crate's source folder:
/// `runs/map.rs` and `runs/map/mod.rs` hold `runs::map`, `lib.rs` the crate root.
fn module_path(path: &str) -> Vec<String> {
    let mut parts: Vec<String> = path
        .trim_end_matches(".rs")
        .split('/')
        .map(str::to_owned)
        .collect();
    if parts.len() == 1 && matches!(parts[0].as_str(), "lib" | "main")
        || parts.last().is_some_and(|p| p == "mod")
    {
        parts.pop();
    }
    parts
}

/// Reads one file: its `use` bindings, `mod` declarations, top-level definitions and the code
/// outside its `use` declarations.
fn read_file(path: &str, text: &str) -> File {
    let tokens = rust::code_tokens(text);
    let mut file = File {
        path: path.to_owned(),
        module: module_path(path),
        ..File::default()
    };
    let mut depth = 0i64;
    let mut i = 0;
    while i < tokens.len() {
        let t = &tokens[i];
        if t.is("use")
            && tokens
                .get(i + 1)
                .is_some_and(|n| n.kind != Kind::Punct || n.is("::"))
        {
            // Visibility: `pub`, `pub(crate)`, `pub(super)`, `pub(in …)` before `use`.
            let public = tokens[..i]
                .iter()
                .rev()
                .take(6)
                .take_while(|p| !p.is(";") && !p.is("}") && !p.is("{"))
                .any(|p| p.is("pub"));
            let start = if tokens.get(i + 1).is_some_and(|n| n.is("::")) {
                i + 2
            } else {
                i + 1
            };
            let end = use_tree(&tokens, start, &[], public, &mut file.uses);
            i = end;
            continue;
        }
        match t.text.as_str() {
            "{" if t.kind == Kind::Punct => depth += 1,
            "}" if t.kind == Kind::Punct => depth -= 1,
            _ => {}
        }
        if depth == 0 && t.kind == Kind::Ident {
            let keyword = t.text.as_str();
            let next = tokens.get(i + 1);
            if let Some(name) = next.filter(|n| n.kind == Kind::Ident) {
                let defines = matches!(
                    keyword,
                    "fn" | "struct" | "enum" | "union" | "trait" | "type" | "const" | "static"
                ) && name.text != "fn";
                if keyword == "mod" && tokens.get(i + 2).is_some_and(|n| n.is(";")) {
                    file.children.insert(name.text.clone());
                } else if defines || keyword == "mod" {
                    file.defined.insert(name.text.clone());
                }
            }
            if keyword == "macro_rules" {
                if let Some(name) = tokens.get(i + 2) {
                    file.defined.insert(name.text.clone());
                }
            }
        }
        file.code.push(t.clone());
        i += 1;
    }
    file
}

/// A crate's files and the modules they hold.
struct Crate {
    files: Vec<File>,
    by_module: BTreeMap<Vec<String>, usize>,
}

/// How deep alias chains are followed before giving up (a guard against a cycle of
/// re-exports, which the compiler refuses anyway).
const MAX_ALIASES: usize = 12;

impl Crate {
    /// The crate whose sources are `sources` (path relative to its source folder → text),
    /// from its root `lib.rs` (or `main.rs`) down its `mod` declarations.
    fn new(sources: &BTreeMap<String, String>) -> Crate {
        let mut krate = Crate {
            files: Vec::new(),
            by_module: BTreeMap::new(),
        };
        let root = ["lib.rs", "main.rs"]
            .into_iter()
            .find(|r| sources.contains_key(*r));
        let mut queue: Vec<String> = root.into_iter().map(str::to_owned).collect();
        while let Some(path) = queue.pop() {
            let file = read_file(&path, &sources[&path]);
            let dir = match file.module.as_slice() {
                [] => String::new(),
                m => format!("{}/", m.join("/")),
            };
            for child in &file.children {
                let candidates = [format!("{dir}{child}.rs"), format!("{dir}{child}/mod.rs")];
                if let Some(found) = candidates.into_iter().find(|c| sources.contains_key(c)) {
                    queue.push(found);
                }
            }
            krate
                .by_module
                .insert(file.module.clone(), krate.files.len());
            krate.files.push(file);
        }
        krate
    }

    fn file_of(&self, module: &[String]) -> Option<&File> {
        self.by_module.get(module).map(|&i| &self.files[i])
    }

    /// Where `segments` lead, read in the module `context`: `crate`, `super`, `self`, a child
    /// module or a name the module binds or defines; `None` for other crates' paths.
    fn resolve(&self, context: &[String], segments: &[String], depth: usize) -> Option<Target> {
        let (first, rest) = segments.split_first()?;
        match first.as_str() {
            "crate" => self.walk(Vec::new(), rest, depth),
            "super" => self.walk(context.split_last()?.1.to_vec(), rest, depth),
            "self" => self.walk(context.to_vec(), rest, depth),
            name => {
                if self.has_name(context, name, depth) {
                    self.walk(context.to_vec(), segments, depth)
                } else {
                    None
                }
            }
        }
    }

    /// Whether the module `module` has `name`: a child module, a definition, a binding or a
    /// name a glob import of it brings in.
    fn has_name(&self, module: &[String], name: &str, depth: usize) -> bool {
        let Some(file) = self.file_of(module) else {
            return false;
        };
        if depth > MAX_ALIASES {
            return false;
        }
        file.children.contains(name)
            || file.defined.contains(name)
            || file.uses.iter().any(|u| u.name.as_deref() == Some(name))
            || file.uses.iter().filter(|u| u.name.is_none()).any(|glob| {
                // A glob of another crate's module (`use std::arch::x86_64::*`) does not
                // bring in the name of its own first segment.
                if glob.path.first().is_some_and(|f| f == name) {
                    return false;
                }
                match self.resolve(module, &glob.path, depth + 1) {
                    Some(Target::Module(m)) => self.has_name(&m, name, depth + 1),
                    _ => false,
                }
            })
    }

    /// Follows `rest` from the module `module`.
    fn walk(&self, mut module: Vec<String>, rest: &[String], depth: usize) -> Option<Target> {
        if depth > MAX_ALIASES {
            return None;
        }
        for (k, segment) in rest.iter().enumerate() {
            match segment.as_str() {
                "super" => {
                    module.pop()?;
                    continue;
                }
                "self" => continue,
                _ => {}
            }
            let index = *self.by_module.get(&module)?;
            let file = &self.files[index];
            if file.children.contains(segment) {
                module.push(segment.clone());
                continue;
            }
            if file.defined.contains(segment) {
                return Some(Target::Item(index));
            }
            let after = &rest[k + 1..];
            let alias = file
                .uses
                .iter()
                .find(|u| u.name.as_deref() == Some(segment.as_str()));
            if let Some(alias) = alias {
                let mut path = alias.path.clone();
                path.extend(after.iter().cloned());
                return self.resolve(&module, &path, depth + 1);
            }
            for glob in file.uses.iter().filter(|u| u.name.is_none()) {
                if let Some(Target::Module(m)) = self.resolve(&module, &glob.path, depth + 1) {
                    if self.has_name(&m, segment, depth + 1) {
                        return self.walk(m, &rest[k..], depth + 1);
                    }
                }
            }
            // Not found (an item a macro defines, say): this file's.
            return Some(Target::Item(index));
        }
        Some(Target::Module(module))
    }

    /// The files each file uses (by relative path), each with the names through which it
    /// does; a file's own ancestors (the files of the modules that hold it) left out.
    fn uses(&self) -> Graph {
        let mut graph = Graph::new();
        for file in &self.files {
            let mut used: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
            let mut add = |target: Option<Target>, through: &[String]| {
                if let Some(Target::Item(i)) = target {
                    let ancestor = file.module.starts_with(&self.files[i].module);
                    if !ancestor {
                        used.entry(self.files[i].path.clone())
                            .or_default()
                            .insert(through.join("::"));
                    }
                }
            };
            let named: BTreeSet<&str> = file
                .code
                .iter()
                .filter(|t| t.kind == Kind::Ident)
                .map(|t| t.text.as_str())
                .collect();
            for u in &file.uses {
                match &u.name {
                    Some(name) if !u.public || named.contains(name.as_str()) => {
                        add(self.resolve(&file.module, &u.path, 0), &u.path);
                    }
                    _ => {}
                }
            }
            for path in inline_paths(&file.code) {
                add(self.resolve(&file.module, &path, 0), &path);
            }
            let globs: Vec<Vec<String>> = file
                .uses
                .iter()
                .filter(|u| u.name.is_none())
                .filter_map(|g| match self.resolve(&file.module, &g.path, 0) {
                    Some(Target::Module(m)) => Some(m),
                    _ => None,
                })
                .collect();
            if !globs.is_empty() {
                for name in lone_names(&file.code) {
                    let own = file.children.contains(&name)
                        || file.defined.contains(&name)
                        || file.uses.iter().any(|u| u.name.as_ref() == Some(&name));
                    if own {
                        continue;
                    }
                    if let Some(m) = globs.iter().find(|m| self.has_name(m, &name, 0)) {
                        let name = [name];
                        add(self.walk(m.clone(), &name, 0), &name);
                    }
                }
            }
            graph.insert(file.path.clone(), used);
        }
        graph
    }
}

/// A file-level import graph: for each file (path relative to the crate's source folder), the
/// files it uses, each with the paths or names through which it does.
pub(crate) type Graph = BTreeMap<String, BTreeMap<String, BTreeSet<String>>>;

/// The paths of `code` of two segments or more (`a::b`, `crate::a::f`, `$crate::x`), each
/// from its first segment: a path's segments run while `::` joins identifiers.
fn inline_paths(code: &[Token]) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < code.len() {
        let starts = code[i].kind == Kind::Ident
            && !(i > 0 && (code[i - 1].is("::") || code[i - 1].is(".")))
            && code.get(i + 1).is_some_and(|t| t.is("::"));
        if !starts {
            i += 1;
            continue;
        }
        let mut path = vec![code[i].text.clone()];
        let mut k = i + 1;
        while k + 1 < code.len() && code[k].is("::") && code[k + 1].kind == Kind::Ident {
            path.push(code[k + 1].text.clone());
            k += 2;
        }
        out.push(path);
        i = k;
    }
    out
}

/// The identifiers of `code` that stand alone: not a field or method (`.name`), not inside a
/// path (`a::name`), not leading one (`name::b`).
fn lone_names(code: &[Token]) -> BTreeSet<String> {
    code.iter()
        .enumerate()
        .filter(|(i, t)| {
            t.kind == Kind::Ident
                && !(*i > 0 && (code[i - 1].is("::") || code[i - 1].is(".")))
                && !code.get(i + 1).is_some_and(|n| n.is("::"))
        })
        .map(|(_, t)| t.text.clone())
        .collect()
}

/// The file-level import graph of the crate whose sources are `sources` (path relative to
/// its source folder → text): for each file, the files whose items its code uses.
pub(crate) fn file_graph(sources: &BTreeMap<String, String>) -> Graph {
    Crate::new(sources).uses()
}

/// The Rust sources under `src`, by path relative to it (`/`-separated).
pub(crate) fn read_sources(src: &std::path::Path) -> BTreeMap<String, String> {
    super::rust_files(src)
        .into_iter()
        .map(|file| {
            let relative = file
                .strip_prefix(src)
                .expect("under src")
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect::<Vec<_>>()
                .join("/");
            let text = std::fs::read_to_string(&file).expect("source files are readable");
            (relative, text)
        })
        .collect()
}

/// The circles of a use graph: its strongly connected groups of more than one node (Tarjan's
/// algorithm), each sorted, in the order found.
pub(crate) fn circles(uses: &BTreeMap<String, BTreeSet<String>>) -> Vec<Vec<String>> {
    struct Walk<'a> {
        uses: &'a BTreeMap<String, BTreeSet<String>>,
        index: BTreeMap<&'a str, (usize, usize)>,
        stack: Vec<&'a str>,
        found: Vec<Vec<String>>,
    }
    fn visit<'a>(w: &mut Walk<'a>, v: &'a str) {
        let n = w.index.len();
        w.index.insert(v, (n, n));
        w.stack.push(v);
        let uses = w.uses;
        for u in uses.get(v).into_iter().flatten() {
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
        index: BTreeMap::new(),
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

/// A circle among the modules that one module holds.
#[derive(Debug, PartialEq)]
pub(crate) struct Circle {
    /// The holding module's path (`continuation`, `runs`; empty for the crate root).
    pub(crate) module: String,
    /// The held modules in the circle, by name, sorted (`basins`, `map`, `shard`).
    pub(crate) members: Vec<String>,
    /// The file-level uses between the members that close it, each with what it names.
    pub(crate) uses: Vec<String>,
}

/// The circles of a crate's modules at every level of its module tree: for each module, the
/// circles among the modules it holds directly, where one uses another when a file in the
/// first's subtree uses a file in the second's (`a/x.rs` using `b/y.rs` is `a` using `b` in
/// the crate root). A module's own file (its `mod.rs`) is no member: what it holds may use it
/// (the shared pieces of a module live there), and it may use them.
pub(crate) fn module_circles(graph: &Graph) -> Vec<Circle> {
    type Level = BTreeMap<String, BTreeSet<String>>;
    let mut levels: BTreeMap<Vec<String>, Level> = BTreeMap::new();
    let mut through: BTreeMap<(Vec<String>, String, String), Vec<String>> = BTreeMap::new();
    for (file, used) in graph {
        let from = module_path(file);
        for (target, names) in used {
            let to = module_path(target);
            let common = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
            if common >= from.len() || common >= to.len() {
                continue; // one holds the other
            }
            let holder = from[..common].to_vec();
            let (a, b) = (from[common].clone(), to[common].clone());
            levels
                .entry(holder.clone())
                .or_default()
                .entry(a.clone())
                .or_default()
                .insert(b.clone());
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            through
                .entry((holder, a, b))
                .or_default()
                .push(format!("{file} → {target} ({})", names.join(", ")));
        }
    }
    let mut found = Vec::new();
    for (holder, level) in &levels {
        for members in circles(level) {
            let mut uses = Vec::new();
            for a in &members {
                for b in &members {
                    if let Some(t) = through.get(&(holder.clone(), a.clone(), b.clone())) {
                        uses.extend(t.iter().cloned());
                    }
                }
            }
            found.push(Circle {
                module: holder.join("::"),
                members,
                uses,
            });
        }
    }
    found
}

#[cfg(test)]
fn tree(files: &[(&str, &str)]) -> BTreeMap<String, String> {
    files
        .iter()
        .map(|(p, t)| ((*p).to_owned(), (*t).to_owned()))
        .collect()
}

/// A small crate with two circles, or none. In the crate root, `a`, `b` and `c` through every
/// kind of path the graph reads: `a.rs` names `crate::b::Beta` after a test module (which
/// itself would close a circle with `d.rs`), `b/mod.rs` re-exports `Beta` from `b/inner.rs`,
/// which names `crate::Gamma`, the crate root's alias of `c.rs`'s item, and `c.rs` imports
/// `super::a::Alpha`. In `b`, `inner` and `other`: `other.rs` imports `Beta` through the glob
/// `super::*` (a re-export of its parent), and `inner.rs` calls `super::other::f`. Without
/// circles, `c.rs` and `inner.rs` leave out their uses of `a` and `other`.
#[cfg(test)]
fn planted(with_circles: bool) -> BTreeMap<String, String> {
    let (c, inner_uses_other) = if with_circles {
        (
            "use super::a::Alpha;\npub struct Gamma(pub Alpha);\n",
            "super::other::f();",
        )
    } else {
        ("pub struct Gamma;\n", "")
    };
    let inner = format!(
        "pub struct Beta;\nimpl Beta {{\n    pub fn gamma(&self) -> usize {{\n        \
         {inner_uses_other}\n        std::mem::size_of::<crate::Gamma>()\n    }}\n}}\n"
    );
    tree(&[
        (
            "lib.rs",
            "mod a;\nmod b;\nmod c;\nmod d;\npub use c::Gamma;\n",
        ),
        (
            "a.rs",
            "pub struct Alpha;\n#[cfg(test)]\nmod tests {\n    use crate::d::Delta;\n    \
             fn t() -> &'static str { \"}\" }\n}\n\
             pub fn beta() -> crate::b::Beta { self::helper(); crate::b::Beta }\nfn helper() {}\n",
        ),
        (
            "b/mod.rs",
            "mod inner;\nmod other;\npub use self::inner::Beta;\n",
        ),
        ("b/inner.rs", &inner),
        (
            "b/other.rs",
            "use super::*;\npub fn f() -> Option<Beta> { None }\n",
        ),
        ("c.rs", c),
        (
            "d.rs",
            "use crate::a::*;\npub struct Delta;\nfn f() { beta(); }\n",
        ),
    ])
}

#[test]
fn planted_import_circles_are_found() {
    let graph = file_graph(&planted(true));
    let used = |file: &str| -> Vec<&str> { graph[file].keys().map(String::as_str).collect() };
    assert_eq!(used("a.rs"), ["b/inner.rs"], "{graph:?}");
    assert_eq!(used("b/inner.rs"), ["b/other.rs", "c.rs"], "{graph:?}");
    assert_eq!(used("b/other.rs"), ["b/inner.rs"], "{graph:?}");
    assert_eq!(used("d.rs"), ["a.rs"], "{graph:?}");
    assert!(used("b/mod.rs").is_empty(), "a re-export is not a use");
    let found: Vec<(String, Vec<String>)> = module_circles(&graph)
        .into_iter()
        .map(|c| (c.module, c.members))
        .collect();
    let s = |x: &[&str]| -> Vec<String> { x.iter().map(|m| (*m).to_owned()).collect() };
    assert_eq!(
        found,
        vec![
            (String::new(), s(&["a", "b", "c"])),
            ("b".to_owned(), s(&["inner", "other"])),
        ],
        "{graph:?}"
    );
}

#[test]
fn no_circle_is_found_where_there_is_none() {
    let graph = file_graph(&planted(false));
    assert_eq!(
        graph["b/inner.rs"].keys().collect::<Vec<_>>(),
        ["c.rs"],
        "{graph:?}"
    );
    assert_eq!(module_circles(&graph), vec![], "{graph:?}");
}

#[test]
fn use_trees_are_read_whole() {
    let text = "pub(crate) use crate::a::{self, b::{C as D, e}, f::*};\nuse super::g;\n";
    let file = read_file("x/y.rs", text);
    let paths: Vec<(String, Option<String>, bool)> = file
        .uses
        .iter()
        .map(|u| (u.path.join("::"), u.name.clone(), u.public))
        .collect();
    let s = |x: &str| x.to_owned();
    assert_eq!(
        paths,
        vec![
            (s("crate::a"), Some(s("a")), true),
            (s("crate::a::b::C"), Some(s("D")), true),
            (s("crate::a::b::e"), Some(s("e")), true),
            (s("crate::a::f"), None, true),
            (s("super::g"), Some(s("g")), false),
        ]
    );
    assert_eq!(file.module, vec![s("x"), s("y")]);
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
