//! A small Rust lexer for the tidy tests: tokens with their lines, comments told apart from
//! code, string and character literals kept whole (a brace inside a string is not a brace),
//! and the items compiled for tests only (`#[cfg(test)]`, brace-matched) found, so that a test
//! reads what the library compiles.

/// What a token is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// An identifier or keyword (`crate`, `super`, `r#type` as `type`).
    Ident,
    /// A string, character or number literal, or a lifetime.
    Literal,
    /// Punctuation: `::` is one token, every other character one token.
    Punct,
}

/// One token of Rust source.
#[derive(Debug, Clone)]
pub(crate) struct Token {
    pub(crate) kind: Kind,
    pub(crate) text: String,
    /// 1-based line of its first character.
    pub(crate) line: usize,
    /// Byte range in the source.
    pub(crate) start: usize,
    pub(crate) end: usize,
}

impl Token {
    pub(crate) fn is(&self, text: &str) -> bool {
        self.text == text && self.kind != Kind::Literal
    }
}

/// A comment's byte range (markers included) in the source.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Comment {
    pub(crate) start: usize,
    pub(crate) end: usize,
}

/// A source file split into tokens and comments.
#[derive(Debug, Default)]
pub(crate) struct Lexed {
    pub(crate) tokens: Vec<Token>,
    pub(crate) comments: Vec<Comment>,
}

fn is_ident_char(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

/// Splits Rust source into tokens and comments (nested block comments, raw strings, byte and C
/// strings, character literals against lifetimes).
pub(crate) fn lex(text: &str) -> Lexed {
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let at = |i: usize| chars.get(i).map(|&(_, c)| c);
    let offset = |i: usize| chars.get(i).map_or(text.len(), |&(o, _)| o);
    let mut out = Lexed::default();
    let (mut i, mut line) = (0, 1);
    // Advances over chars[from..to], counting lines, and returns the byte range.
    let span = |from: usize, to: usize, line: &mut usize| {
        *line += chars[from..to.min(chars.len())]
            .iter()
            .filter(|(_, c)| *c == '\n')
            .count();
        (offset(from), offset(to))
    };
    while let Some(c) = at(i) {
        let start_line = line;
        let start = i;
        let next = at(i + 1);
        if c.is_whitespace() {
            i += 1;
            span(start, i, &mut line);
            continue;
        }
        if c == '/' && next == Some('/') {
            while at(i).is_some_and(|c| c != '\n') {
                i += 1;
            }
            let (s, e) = span(start, i, &mut line);
            out.comments.push(Comment { start: s, end: e });
            continue;
        }
        if c == '/' && next == Some('*') {
            let mut depth = 0usize;
            while let Some(c) = at(i) {
                match (c, at(i + 1)) {
                    ('/', Some('*')) => (depth += 1, i += 2).1,
                    ('*', Some('/')) => {
                        depth -= 1;
                        i += 2;
                        if depth == 0 {
                            break;
                        }
                    }
                    _ => i += 1,
                }
            }
            let (s, e) = span(start, i, &mut line);
            out.comments.push(Comment { start: s, end: e });
            continue;
        }
        let kind;
        // A raw string: r"…", r#"…"#, br#"…"#, cr"…".
        let raw_at = match (c, next) {
            ('r', Some('"' | '#')) => Some(i + 1),
            ('b' | 'c', Some('r')) if matches!(at(i + 2), Some('"' | '#')) => Some(i + 2),
            _ => None,
        };
        let hashes = raw_at.map(|j| (j..).take_while(|&k| at(k) == Some('#')).count());
        if let (Some(j), Some(n)) = (raw_at, hashes) {
            if at(j + n) == Some('"') {
                i = j + n + 1;
                while let Some(c) = at(i) {
                    i += 1;
                    if c == '"' && (i..i + n).all(|k| at(k) == Some('#')) {
                        i += n;
                        break;
                    }
                }
                kind = Kind::Literal;
            } else {
                // `r#ident`: a raw identifier.
                i = j + n;
                while at(i).is_some_and(is_ident_char) {
                    i += 1;
                }
                let (s, e) = span(start, i, &mut line);
                out.tokens.push(Token {
                    kind: Kind::Ident,
                    text: text[s..e].trim_start_matches("r#").to_owned(),
                    line: start_line,
                    start: s,
                    end: e,
                });
                continue;
            }
        } else if c == '"' || (matches!(c, 'b' | 'c') && next == Some('"')) {
            i += if c == '"' { 1 } else { 2 };
            while let Some(c) = at(i) {
                i += if c == '\\' { 2 } else { 1 };
                if c == '"' {
                    break;
                }
            }
            kind = Kind::Literal;
        } else if c == '\'' || (c == 'b' && next == Some('\'')) {
            let q = if c == '\'' { i } else { i + 1 };
            if at(q + 1) == Some('\\') {
                i = q + 3;
                while at(i).is_some_and(|c| c != '\'') {
                    i += 1;
                }
                i += 1;
            } else if at(q + 2) == Some('\'') {
                i = q + 3;
            } else {
                // A lifetime or label.
                i = q + 1;
                while at(i).is_some_and(is_ident_char) {
                    i += 1;
                }
            }
            kind = Kind::Literal;
        } else if c.is_ascii_digit() {
            i += 1;
            while let Some(c) = at(i) {
                let exponent_sign = matches!(c, '+' | '-')
                    && matches!(at(i - 1), Some('e' | 'E'))
                    && !text[offset(start)..offset(i)].starts_with("0x");
                let decimal_point = c == '.' && at(i + 1).is_some_and(|d| d.is_ascii_digit());
                if is_ident_char(c) || exponent_sign || decimal_point {
                    i += 1;
                } else {
                    break;
                }
            }
            kind = Kind::Literal;
        } else if is_ident_char(c) {
            while at(i).is_some_and(is_ident_char) {
                i += 1;
            }
            kind = Kind::Ident;
        } else if c == ':' && next == Some(':') {
            i += 2;
            kind = Kind::Punct;
        } else {
            i += 1;
            kind = Kind::Punct;
        }
        let (s, e) = span(start, i, &mut line);
        out.tokens.push(Token {
            kind,
            text: text[s..e].to_owned(),
            line: start_line,
            start: s,
            end: e,
        });
    }
    out
}

/// Whether `tokens[i..]` opens with the attribute `#[cfg(test)]`.
fn is_cfg_test(tokens: &[Token], i: usize) -> bool {
    let want = ["#", "[", "cfg", "(", "test", ")", "]"];
    tokens.len() >= i + want.len() && want.iter().zip(&tokens[i..]).all(|(w, t)| t.is(w))
}

/// The index just past the bracket that closes the one opening at `tokens[open]`.
fn matching(tokens: &[Token], open: usize) -> usize {
    let mut depth = 0i64;
    for (k, t) in tokens.iter().enumerate().skip(open) {
        if t.kind != Kind::Punct {
            continue;
        }
        match t.text.as_str() {
            "(" | "[" | "{" => depth += 1,
            ")" | "]" | "}" => {
                depth -= 1;
                if depth == 0 {
                    return k + 1;
                }
            }
            _ => {}
        }
    }
    tokens.len()
}

/// The token ranges compiled for tests only: each `#[cfg(test)]` with the item, statement,
/// field or expression it applies to — up to the `;` or `,` that ends it, or the close of its
/// braced body (`mod tests { … }`, `fn f() { … }`, `if x { … }`), brackets matched; an item
/// with `=` or `use` before its first brace runs on to its `;`.
pub(crate) fn test_only(tokens: &[Token]) -> Vec<std::ops::Range<usize>> {
    let mut ranges = Vec::new();
    let mut i = 0;
    while i < tokens.len() {
        if !is_cfg_test(tokens, i) {
            i += 1;
            continue;
        }
        let start = i;
        let mut k = i + 1; // at `[`
        k = matching(tokens, k);
        // Further outer attributes of the same item.
        while k + 1 < tokens.len() && tokens[k].is("#") && tokens[k + 1].is("[") {
            k = matching(tokens, k + 1);
        }
        // Past the visibility, the item's keyword: a `use`, `let`, `static`, `type` or a `const`
        // that is not a `const fn` runs to its `;` (braces and `=` inside it do not end it).
        let mut first = k;
        if tokens.get(first).is_some_and(|t| t.is("pub")) {
            first += 1;
            if tokens.get(first).is_some_and(|t| t.is("(")) {
                first = matching(tokens, first);
            }
        }
        let keyword = |n: usize| tokens.get(first + n).map_or("", |t| t.text.as_str());
        let runs_to_semicolon = matches!(keyword(0), "use" | "let" | "static" | "type")
            || (keyword(0) == "const" && !matches!(keyword(1), "fn" | "unsafe" | "async"));
        let end = loop {
            let Some(t) = tokens.get(k) else {
                break tokens.len();
            };
            if t.kind != Kind::Punct {
                k += 1;
                continue;
            }
            match t.text.as_str() {
                ";" => break k + 1,
                "," if !runs_to_semicolon => break k + 1,
                ")" | "]" | "}" => break k,
                "(" | "[" => k = matching(tokens, k),
                "{" => {
                    k = matching(tokens, k);
                    if !runs_to_semicolon {
                        break k;
                    }
                }
                _ => k += 1,
            }
        };
        ranges.push(start..end);
        i = end.max(start + 1);
    }
    ranges
}

/// The tokens of `text` that the library compiles: comments and test-only items left out.
pub(crate) fn code_tokens(text: &str) -> Vec<Token> {
    let tokens = lex(text).tokens;
    let mut skip = test_only(&tokens).into_iter().peekable();
    let mut out = Vec::with_capacity(tokens.len());
    for (k, t) in tokens.into_iter().enumerate() {
        while skip.peek().is_some_and(|r| r.end <= k) {
            skip.next();
        }
        if !skip.peek().is_some_and(|r| r.contains(&k)) {
            out.push(t);
        }
    }
    out
}

/// `text` with comments and test-only items blanked (every character but line breaks turned
/// into a space), so that its lines keep their numbers.
pub(crate) fn code_text(text: &str) -> String {
    let lexed = lex(text);
    let mut blank: Vec<(usize, usize)> = lexed.comments.iter().map(|c| (c.start, c.end)).collect();
    for r in test_only(&lexed.tokens) {
        if r.start < r.end {
            blank.push((lexed.tokens[r.start].start, lexed.tokens[r.end - 1].end));
        }
    }
    blank.sort_unstable();
    let mut out = String::with_capacity(text.len());
    let mut blanks = blank.iter().peekable();
    for (o, c) in text.char_indices() {
        while blanks.peek().is_some_and(|&&(_, e)| e <= o) {
            blanks.next();
        }
        let blanked = blanks.peek().is_some_and(|&&(s, e)| s <= o && o < e);
        out.push(if blanked && c != '\n' { ' ' } else { c });
    }
    out
}

/// `text` with everything but its comments' words blanked (comment markers too; line breaks
/// kept), so that prose wrapped over several comment lines reads as one run of words.
pub(crate) fn comment_text(text: &str) -> String {
    let lexed = lex(text);
    let mut out: Vec<char> = text
        .chars()
        .map(|c| if c == '\n' { '\n' } else { ' ' })
        .collect();
    let index: Vec<usize> = text.char_indices().map(|(o, _)| o).collect();
    for c in &lexed.comments {
        let from = index.partition_point(|&o| o < c.start);
        let to = index.partition_point(|&o| o < c.end);
        let body: Vec<char> = text[c.start..c.end].chars().collect();
        // Leading markers (`//`, `///`, `//!`, `/*`, `/**`, `/*!`) and a closing `*/` stay
        // blank; so does the `*` that leads a line of a block comment.
        let lead = body
            .iter()
            .take_while(|&&ch| matches!(ch, '/' | '*' | '!'))
            .count();
        let trail = if body.ends_with(&['*', '/']) && body.len() >= lead + 2 {
            2
        } else {
            0
        };
        let mut line_start = true;
        for (k, &ch) in body.iter().enumerate().take(body.len() - trail).skip(lead) {
            if ch == '\n' {
                line_start = true;
                continue;
            }
            if line_start && (ch.is_whitespace() || ch == '*') {
                continue;
            }
            line_start = false;
            out[from + k] = ch;
        }
        debug_assert!(from + body.len() == to);
    }
    out.into_iter().collect()
}

#[test]
fn literals_and_comments_are_told_from_code() {
    let text = "let s = \"{ // }\"; let c = '{'; let r = r#\"}\"#; // {\n\
                fn f<'a>(x: &'a str) /* { /* } */ } */ -> char { b'}' }\nlet n = 1.5e-3;";
    let lexed = lex(text);
    let braces: Vec<usize> = lexed
        .tokens
        .iter()
        .filter(|t| t.is("{") || t.is("}"))
        .map(|t| t.line)
        .collect();
    assert_eq!(braces, vec![2, 2]);
    assert_eq!(lexed.comments.len(), 2);
    assert!(lexed.tokens.iter().any(|t| t.text == "'a"));
    assert!(lexed.tokens.iter().any(|t| t.text == "1.5e-3"));
    assert!(lexed.tokens.iter().any(|t| t.is("::")) == text.contains("::"));
    let prose = comment_text("x; // a b\n/* c\n * d */ y");
    assert_eq!(
        prose.lines().map(str::trim).collect::<Vec<_>>(),
        ["a b", "c", "d"]
    );
    let quote: Vec<String> = lex(r"'\'' '\\' 'x")
        .tokens
        .into_iter()
        .map(|t| t.text)
        .collect();
    assert_eq!(quote, [r"'\''", r"'\\'", "'x"]);
}

#[test]
fn test_only_items_are_brace_matched() {
    let text = "use a::b;\n#[cfg(test)]\nmod tests {\n    fn t() { let _ = \"}\"; }\n}\n\
                fn after() { crate::c::d(); }\n\
                struct S {\n    #[cfg(test)]\n    x: Cell<u8>,\n    y: u8\n}\n\
                #[cfg(test)]\n#[allow(dead_code)]\nuse crate::e::{f, g};\nfn h() {}";
    let code: Vec<String> = code_tokens(text).into_iter().map(|t| t.text).collect();
    let code = code.join(" ");
    assert!(
        code.contains("fn after ( ) { crate :: c :: d ( ) ; }"),
        "{code}"
    );
    assert!(code.contains("struct S { y : u8 }"), "{code}");
    assert!(!code.contains("tests") && !code.contains("Cell") && !code.contains("crate :: e"));
    assert!(code.ends_with("fn h ( ) { }"), "{code}");
    let blanked = code_text(text);
    assert_eq!(blanked.lines().count(), text.lines().count());
    assert!(blanked
        .lines()
        .nth(5)
        .is_some_and(|l| l.contains("crate::c::d")));
    assert!(blanked.lines().nth(3).is_some_and(|l| l.trim().is_empty()));
}
