//! Flags what a lab's code would read at compile time from outside its own `labs/labNN/src/`:
//! `include!`, `include_str!`, `include_bytes!`, `#[path]` and the like, which could put the
//! instructor's answer key into a submission's build.
//!
//! The rules work on the raw token stream of every `.rs` file (lexed by `proc-macro2`, not
//! parsed into items), so they also see inside `macro_rules!` bodies and macro calls. A name
//! is resolved lexically against a base directory and must stay inside `src/`; the grading
//! tree holds no symbolic links there, so that is what the file system does too. The base is:
//! - the file's directory, for an `include*!` written in a file;
//! - `src/` itself, for an `include*!` inside a `macro_rules!` body (it resolves where the
//!   macro is used, which may be any file) and for an attribute's file (`#[path]` resolves
//!   from the directory of the module it is in, which for an included file or a macro
//!   expansion is not this file's; from `src/` itself is the strictest case, so a name that
//!   stays inside from there stays inside from any module). This flags a few names rustc would
//!   resolve inside, like `#[path = "../common.rs"]` in `src/shapes/sphere.rs`, and lets none
//!   out.
//!
//! Every `.rs` file under `src/` is scanned, so code reached by `include!` or `#[path]` must be
//! a `.rs` file too: another name is flagged, as its contents are not scanned.

use course::LabId;
use std::fs;
use std::path::{Component, Path, PathBuf};

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};

use grading::DeniedItem;

use super::submission::{MAX_FILE_BYTES, read_regular, shown};

/// Macros that read the file their string literal names.
const INCLUDES: &[&str] = &["include", "include_str", "include_bytes"];

/// Keys of attributes whose value names a file: `#[path]` on a module, and the files of
/// `#[debugger_visualizer]` (embedded into the binary).
const FILE_KEYS: &[&str] = &["path", "natvis_file", "gdb_script_file"];

/// Inline assembly, which can pull any file into the build (`.incbin`, `.include`).
const ASSEMBLY: &[&str] = &["asm", "global_asm", "naked_asm"];

/// The most entries looked at under `src/` (the copy holds at most 256).
const MAX_ENTRIES: usize = 4096;

/// The deepest directory looked at under `src/` (the copy is at most 8 levels deep).
const MAX_DEPTH: usize = 16;

/// What the scan of a lab's code found.
#[derive(Debug, Default)]
pub struct LabScan {
    /// One line per occurrence, in the `.rs` files under `tree/labs/labNN/src`, of something
    /// that reads a file outside that directory at compile time, or may:
    /// `labs/lab02/src/lib.rs:3: #[path = "../../../reference/src/lab02.rs"] names a file
    /// outside labs/lab02/src/`. A file that does not lex as Rust is flagged as not compiling.
    pub flags: Vec<String>,
    /// Every place that names one of the lab's denied framework items as an identifier (in code
    /// or a macro body; not in a comment or a string).
    pub denied: Vec<DeniedUse>,
}

/// Scans the `.rs` files under `tree/labs/labNN/src`, each read and lexed once, for what
/// [`LabScan`] holds; `denied` are the lab's denied framework items.
pub fn scan_lab(tree: &Path, lab: LabId, denied: &[DeniedItem]) -> LabScan {
    let src = PathBuf::from(format!("labs/{lab}/src"));
    let root = tree.join(&src);
    let mut flags = Vec::new();
    let mut denied_uses = Vec::new();
    let mut files = Vec::new();
    let mut entries = 0;
    rust_files(
        &root,
        &src,
        Path::new(""),
        1,
        &mut entries,
        &mut files,
        &mut flags,
    );
    for relative in files {
        let mut scanner = Scanner {
            src: shown(&src),
            file: shown(&src.join(&relative)),
            dir: relative
                .parent()
                .into_iter()
                .flat_map(Path::components)
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect(),
            flags: Vec::new(),
            denied_items: denied,
            denied: Vec::new(),
        };
        let unlexed = format!(
            "{}: does not parse as Rust; it will not compile",
            scanner.file
        );
        let bytes = match read_regular(&root.join(&relative), MAX_FILE_BYTES) {
            Ok(bytes) => bytes,
            Err(refusal) => {
                let reason = refusal.rejection();
                flags.push(format!("{}: cannot be scanned: {reason}", scanner.file));
                continue;
            }
        };
        let Ok(text) = String::from_utf8(bytes) else {
            flags.push(unlexed);
            continue;
        };
        match without_shebang(&text).parse::<TokenStream>() {
            Ok(tokens) => {
                scanner.scan(tokens, Context::default());
                flags.extend(scanner.flags);
                denied_uses.extend(scanner.denied);
            }
            Err(_) => flags.push(unlexed),
        }
        // The spans of this file are not used again: let the lexer forget its text.
        proc_macro2::extra::invalidate_current_thread_spans();
    }
    LabScan {
        flags,
        denied: denied_uses,
    }
}

/// A framework item that answers an exercise, named in a lab's code.
#[derive(Clone, Debug)]
pub struct DeniedUse {
    /// The exercises it answers.
    pub exercises: Vec<String>,
    /// Where, and what the item computes: `labs/lab02/src/lib.rs:12: \`trace_to_closest\`
    /// (the closest hit of a ray …)`.
    pub line: String,
}

/// Collects the `.rs` files of `root/relative` (whose entries are `depth` levels below `root`,
/// shown as `src`) into `files`, sorted, without following a symbolic link.
fn rust_files(
    root: &Path,
    src: &Path,
    relative: &Path,
    depth: usize,
    entries: &mut usize,
    files: &mut Vec<PathBuf>,
    flags: &mut Vec<String>,
) {
    if *entries > MAX_ENTRIES {
        return;
    }
    let shown_dir = shown(&src.join(relative));
    let listed: Result<Vec<_>, _> = fs::read_dir(root.join(relative))
        .and_then(|dir| dir.take(MAX_ENTRIES + 1 - *entries).collect());
    let mut listed = match listed {
        Ok(listed) => listed,
        Err(err) => {
            flags.push(format!("{shown_dir}: cannot be scanned: {err}"));
            return;
        }
    };
    *entries += listed.len();
    if *entries > MAX_ENTRIES {
        flags.push(format!(
            "{shown_dir}: cannot be scanned: more than {MAX_ENTRIES} entries"
        ));
        return;
    }
    listed.sort_by_key(fs::DirEntry::file_name);
    for entry in listed {
        let path = relative.join(entry.file_name());
        match entry.file_type() {
            Ok(file_type) if file_type.is_dir() && depth < MAX_DEPTH => {
                rust_files(root, src, &path, depth + 1, entries, files, flags);
            }
            Ok(file_type) if file_type.is_dir() => flags.push(format!(
                "{}: cannot be scanned: more than {MAX_DEPTH} levels deep",
                shown(&src.join(&path))
            )),
            _ if path.extension().is_some_and(|e| e == "rs") => files.push(path),
            _ => {}
        }
    }
}

/// `text` without the shebang line rustc skips (`#!` not starting an inner attribute `#![`),
/// its line left empty so that line numbers stay the same.
fn without_shebang(text: &str) -> String {
    let body = text.strip_prefix('\u{feff}').unwrap_or(text);
    match body.strip_prefix("#!") {
        Some(rest) if !rest.trim_start().starts_with('[') => {
            let line_end = body.find('\n').unwrap_or(body.len());
            body[line_end..].to_string()
        }
        _ => body.to_string(),
    }
}

/// Where in an attribute a group's tokens are: which of them may start an attribute of their
/// own (its name is the first token).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
enum Starts {
    /// None: not an attribute, or inside an attribute's arguments.
    #[default]
    None,
    /// The first token: `#[HERE …]`, `#[unsafe(HERE …)]`.
    First,
    /// The first token and each one after a comma: `#[cfg_attr(HERE, HERE, HERE)]`.
    AfterCommas,
}

/// What surrounds the tokens being scanned.
#[derive(Clone, Copy, Debug, Default)]
struct Context {
    /// The attribute (`#` through `]`) the tokens are in, if any.
    attribute: Option<Span>,
    /// Which tokens start an attribute.
    starts: Starts,
    /// Whether the tokens are inside a `macro_rules!` body.
    macro_rules: bool,
}

/// Scans the tokens of one file.
struct Scanner<'a> {
    /// The lab's code directory, shown: `labs/lab02/src`.
    src: String,
    /// The file, shown: `labs/lab02/src/shapes/mod.rs`.
    file: String,
    /// The file's directory, as components below `src/`.
    dir: Vec<String>,
    /// The flags found so far.
    flags: Vec<String>,
    /// The lab's denied framework items.
    denied_items: &'a [DeniedItem],
    /// The places found so far that name one of them.
    denied: Vec<DeniedUse>,
}

/// `name` without the `r#` of a raw identifier.
fn unraw(name: &str) -> &str {
    name.strip_prefix("r#").unwrap_or(name)
}

/// Whether the use of the denied item `item` at `tokens[i]` counts (see [`DeniedItem::counts`]):
/// the receiver of `x.name` or the qualifier of `Q::name`, if there is one.
fn counts_here(item: &DeniedItem, tokens: &[TokenTree], i: usize) -> bool {
    let dot = i >= 1 && is_punct(tokens.get(i - 1), '.');
    let path = i >= 2 && is_punct(tokens.get(i - 1), ':') && is_punct(tokens.get(i - 2), ':');
    let qualifier = match (dot, path) {
        (true, _) if i >= 2 => tokens.get(i - 2),
        (_, true) if i >= 3 => tokens.get(i - 3),
        _ => None,
    }
    .and_then(|t| match t {
        TokenTree::Ident(q) => Some(q.to_string()),
        _ => None,
    });
    item.counts(dot || path, qualifier.as_deref().map(unraw))
}

/// Whether `token` is the punctuation `c`.
fn is_punct(token: Option<&TokenTree>, c: char) -> bool {
    matches!(token, Some(TokenTree::Punct(p)) if p.as_char() == c)
}

/// Whether `token` is the identifier `name` (raw or not).
fn is_ident(token: Option<&TokenTree>, name: &str) -> bool {
    matches!(token, Some(TokenTree::Ident(i)) if unraw(&i.to_string()) == name)
}

/// The value of a plain string literal (cooked or raw, no suffix); `None` for anything else.
fn string_literal(token: Option<&TokenTree>) -> Option<String> {
    match token {
        Some(TokenTree::Literal(literal)) => match syn::Lit::new(literal.clone()) {
            syn::Lit::Str(string) if string.suffix().is_empty() => Some(string.value()),
            _ => None,
        },
        _ => None,
    }
}

/// `name` resolved lexically against `base` (components below `src/`), as components below
/// `src/`; `None` when it is absolute or leaves `src/` at any point.
fn resolve(base: &[String], name: &str) -> Option<PathBuf> {
    let mut parts = base.to_vec();
    for component in Path::new(name).components() {
        match component {
            Component::Normal(part) => parts.push(part.to_string_lossy().into_owned()),
            Component::CurDir => {}
            Component::ParentDir => {
                parts.pop()?;
            }
            Component::RootDir | Component::Prefix(_) => return None,
        }
    }
    (!parts.is_empty()).then(|| parts.iter().collect())
}

/// The source text of `span` for a line: whitespace runs made one space, control characters
/// escaped, at most 120 characters.
fn excerpt(span: Span, fallback: impl FnOnce() -> String) -> String {
    let text = span.source_text().unwrap_or_else(fallback);
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let text = shown(Path::new(&text));
    if text.chars().count() > 120 {
        let cut: String = text.chars().take(119).collect();
        format!("{cut}…")
    } else {
        text
    }
}

/// Whether `tokens[i]` may start an attribute of its own, in a group of `starts`.
fn is_start(starts: Starts, tokens: &[TokenTree], i: usize) -> bool {
    match starts {
        Starts::None => false,
        Starts::First => i == 0,
        Starts::AfterCommas => i == 0 || is_punct(tokens.get(i - 1), ','),
    }
}

/// The context of the group `tokens[i]`, in `context`: an attribute's brackets, a
/// `cfg_attr(…)` or `unsafe(…)` inside one, a `macro_rules!` body, or plain tokens.
fn inner_context(tokens: &[TokenTree], i: usize, context: Context) -> Context {
    let Some(TokenTree::Group(group)) = tokens.get(i) else {
        return context;
    };
    let before = |n: usize| i.checked_sub(n).and_then(|j| tokens.get(j));
    let mut inner = Context {
        starts: Starts::None,
        ..context
    };
    if group.delimiter() == Delimiter::Bracket {
        let hash = if is_punct(before(1), '#') {
            before(1)
        } else if is_punct(before(1), '!') && is_punct(before(2), '#') {
            before(2)
        } else {
            None
        };
        if let Some(hash) = hash {
            let span = hash.span().join(group.span()).unwrap_or(group.span());
            inner.attribute = Some(context.attribute.unwrap_or(span));
            inner.starts = Starts::First;
        }
    } else if group.delimiter() == Delimiter::Parenthesis && context.attribute.is_some() && i > 0 {
        if is_ident(before(1), "cfg_attr") {
            inner.starts = Starts::AfterCommas;
        } else if is_ident(before(1), "unsafe") && is_start(context.starts, tokens, i - 1) {
            inner.starts = Starts::First;
        }
    }
    if is_ident(before(3), "macro_rules")
        && is_punct(before(2), '!')
        && matches!(before(1), Some(TokenTree::Ident(_)))
    {
        inner.macro_rules = true;
    }
    inner
}

impl Scanner<'_> {
    /// Adds the flag `what` for the code at `span`.
    fn flag(&mut self, span: Span, what: String) {
        self.flags
            .push(format!("{}:{}: {what}", self.file, span.start().line));
    }

    /// Scans `stream`, whose surroundings are `context`.
    fn scan(&mut self, stream: TokenStream, context: Context) {
        let tokens: Vec<TokenTree> = stream.into_iter().collect();
        for (i, token) in tokens.iter().enumerate() {
            let starts_attribute = is_start(context.starts, &tokens, i);
            match token {
                TokenTree::Ident(ident) => {
                    let name = ident.to_string();
                    let name = unraw(&name);
                    if let Some(item) = self
                        .denied_items
                        .iter()
                        .find(|d| d.name == name && counts_here(d, &tokens, i))
                    {
                        self.denied.push(DeniedUse {
                            exercises: item.exercises.clone(),
                            line: format!(
                                "{}:{}: `{name}` ({}) answers Exercise {}",
                                self.file,
                                ident.span().start().line,
                                item.computes,
                                item.exercises.join(", ")
                            ),
                        });
                    }
                    if INCLUDES.contains(&name) {
                        self.include(name, &tokens, i, context);
                    } else if ASSEMBLY.contains(&name) {
                        let src = &self.src;
                        let what = format!(
                            "{name} can put any file into the build (.incbin), so it may read a file outside {src}/"
                        );
                        self.flag(ident.span(), what);
                    } else if FILE_KEYS.contains(&name)
                        && (starts_attribute || is_punct(tokens.get(i + 1), '='))
                    {
                        if let Some(attribute) = context.attribute {
                            self.file_key(name, &tokens, i, attribute);
                        }
                    }
                }
                TokenTree::Punct(punct) if punct.as_char() == '$' && starts_attribute => {
                    if let Some(attribute) = context.attribute {
                        let text = excerpt(attribute, || token.to_string());
                        let src = &self.src;
                        let what = format!(
                            "{text} is an attribute made from macro input, so it may name a file outside {src}/"
                        );
                        self.flag(attribute, what);
                    }
                }
                TokenTree::Group(group) => {
                    self.scan(group.stream(), inner_context(&tokens, i, context));
                }
                _ => {}
            }
        }
    }

    /// Checks the `include*` identifier `tokens[i]`: fine only as `name!("…")` naming a file
    /// inside `src/` (a `.rs` file for `include!`).
    fn include(&mut self, name: &str, tokens: &[TokenTree], i: usize, context: Context) {
        let src = self.src.clone();
        let ident = &tokens[i];
        let (Some(TokenTree::Group(group)), true) =
            (tokens.get(i + 2), is_punct(tokens.get(i + 1), '!'))
        else {
            let what = format!(
                "{name} named outside a call {name}!(\"…\") may read a file outside {src}/"
            );
            self.flag(ident.span(), what);
            return;
        };
        let span = ident.span().join(group.span()).unwrap_or(ident.span());
        let text = excerpt(span, || format!("{name}!{group}"));
        let arguments: Vec<TokenTree> = group.stream().into_iter().collect();
        let value = match arguments.as_slice() {
            [argument] => string_literal(Some(argument)),
            _ => None,
        };
        let Some(value) = value else {
            let what =
                format!("{text} may name a file outside {src}/ (not a plain string literal)");
            self.flag(span, what);
            return;
        };
        let base = if context.macro_rules {
            &[][..]
        } else {
            &self.dir[..]
        };
        match resolve(base, &value) {
            None if context.macro_rules && resolve(&self.dir, &value).is_some() => {
                let what = format!(
                    "{text} may name a file outside {src}/ (inside macro_rules! its name is relative to the file that uses the macro)"
                );
                self.flag(span, what);
            }
            None => {
                let what = format!("{text} names a file outside {src}/");
                self.flag(span, what);
            }
            Some(path) if name == "include" && path.extension().is_none_or(|e| e != "rs") => {
                let what = format!(
                    "{text} names a file that is not a .rs file, whose code is not checked"
                );
                self.flag(span, what);
            }
            Some(_) => {}
        }
    }

    /// Checks the attribute key `tokens[i]` (`path`, …) of `attribute`: fine only as
    /// `key = "…"` naming a file inside `src/` from `src/` itself (a `.rs` file for `path`).
    fn file_key(&mut self, name: &str, tokens: &[TokenTree], i: usize, attribute: Span) {
        let src = self.src.clone();
        let text = excerpt(attribute, || name.to_string());
        let value = is_punct(tokens.get(i + 1), '=')
            .then(|| string_literal(tokens.get(i + 2)))
            .flatten();
        let Some(value) = value else {
            let what =
                format!("{text} may name a file outside {src}/ (not a plain string literal)");
            self.flag(attribute, what);
            return;
        };
        match resolve(&[], &value) {
            None if resolve(&self.dir, &value).is_some() => {
                let what = format!(
                    "{text} may name a file outside {src}/ (it is resolved from the module's directory, which may be above this file's)"
                );
                self.flag(attribute, what);
            }
            None => {
                let what = format!("{text} names a file outside {src}/");
                self.flag(attribute, what);
            }
            Some(path) if name == "path" && path.extension().is_none_or(|e| e != "rs") => {
                let what = format!(
                    "{text} names a file that is not a .rs file, whose code is not checked"
                );
                self.flag(attribute, what);
            }
            Some(_) => {}
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A grading tree under the system's temporary directory, removed on drop.
    struct Tree(PathBuf);

    impl Tree {
        /// A tree whose lab 2 holds `files` (path below `src/`, contents).
        fn with(files: &[(&str, &[u8])]) -> Tree {
            Tree::with_lab(LabId::of(2), files)
        }

        /// A tree whose lab `lab` holds `files` (path below `src/`, contents).
        fn with_lab(lab: LabId, files: &[(&str, &[u8])]) -> Tree {
            static COUNT: AtomicUsize = AtomicUsize::new(0);
            let dir = std::env::temp_dir().join(format!(
                "raylab-scan-{}-{}",
                std::process::id(),
                COUNT.fetch_add(1, Ordering::Relaxed)
            ));
            for (path, contents) in files {
                let path = dir.join(format!("labs/{lab}/src")).join(path);
                fs::create_dir_all(path.parent().unwrap()).unwrap();
                fs::write(path, contents).unwrap();
            }
            Tree(dir)
        }
    }

    impl Drop for Tree {
        fn drop(&mut self) {
            let _ = fs::remove_dir_all(&self.0);
        }
    }

    /// The flags of lab 2 holding only `lib.rs` with `code`.
    fn flags(code: &str) -> Vec<String> {
        flags_in("lib.rs", code)
    }

    /// The flags of lab 2 holding only the file `path` with `code`.
    fn flags_in(path: &str, code: &str) -> Vec<String> {
        let tree = Tree::with(&[(path, code.as_bytes())]);
        scan_lab(&tree.0, LabId::of(2), &[]).flags
    }

    #[test]
    fn includes_inside_src_are_fine() {
        assert!(flags(r#"const T: &str = include_str!("data/table.txt");"#).is_empty());
        assert!(flags(r#"const T: &[u8] = include_bytes!(r"./data/../data/t.bin");"#).is_empty());
        assert!(flags(r#"include!("generated.rs");"#).is_empty());
        assert!(flags(r#"const T: &str = ::core::include_str! { "a.txt" };"#).is_empty());
        assert!(
            flags_in(
                "shapes/sphere.rs",
                r#"const T: &str = include_str!("../t.txt");"#
            )
            .is_empty()
        );
    }

    #[test]
    fn includes_reaching_outside_are_flagged() {
        assert_eq!(
            flags(
                "\n\nconst K: &str = include_str!(concat!(env!(\"PWD\"), \"/reference/src/lab07.rs\"));"
            ),
            [
                r#"labs/lab02/src/lib.rs:3: include_str!(concat!(env!("PWD"), "/reference/src/lab07.rs")) may name a file outside labs/lab02/src/ (not a plain string literal)"#
            ]
        );
        assert_eq!(
            flags(r#"const K: &str = include_str!("../../../reference/src/lab02.rs");"#),
            [
                r#"labs/lab02/src/lib.rs:1: include_str!("../../../reference/src/lab02.rs") names a file outside labs/lab02/src/"#
            ]
        );
        assert_eq!(
            flags(r#"const K: &[u8] = include_bytes!("/etc/passwd");"#),
            [
                r#"labs/lab02/src/lib.rs:1: include_bytes!("/etc/passwd") names a file outside labs/lab02/src/"#
            ]
        );
        assert_eq!(flags(r#"include!("../src/lib.rs");"#).len(), 1);
        assert_eq!(
            flags(r#"const K: &[u8] = include_bytes!(b"key.rs");"#).len(),
            1
        );
        assert_eq!(
            flags(r#"const K: &str = include_str!("key.rs"suffix);"#).len(),
            1
        );
        assert_eq!(
            flags(r#"const K: &str = include_str!("a.txt", "b.txt");"#).len(),
            1
        );
        assert_eq!(
            flags(r#"const K: &str = r#include_str!("../../x");"#).len(),
            1
        );
        assert_eq!(
            flags(r#"include!("table.in");"#),
            [
                r#"labs/lab02/src/lib.rs:1: include!("table.in") names a file that is not a .rs file, whose code is not checked"#
            ]
        );
    }

    #[test]
    fn includes_named_without_a_call_are_flagged() {
        assert_eq!(
            flags("use std::include_str as inc;\nconst K: &str = inc!(\"../../../key.rs\");"),
            [
                r#"labs/lab02/src/lib.rs:1: include_str named outside a call include_str!("…") may read a file outside labs/lab02/src/"#
            ]
        );
        assert_eq!(flags("use core::{include_bytes as b};").len(), 1);
        assert_eq!(flags("m!(include);").len(), 1);
    }

    #[test]
    fn includes_inside_macro_rules_are_flagged_unless_inside_from_src() {
        let code = r#"
macro_rules! key {
    ($p:literal) => { include_str!($p) };
    () => { include_str!(concat!("../../../", "reference/src/lab02.rs")) };
    (alias) => { use std::include_str as inc; };
    (fine) => { include_str!("data/table.txt") };
}
"#;
        let found = flags(code);
        assert_eq!(found.len(), 3, "{found:#?}");
        assert!(found[0].starts_with("labs/lab02/src/lib.rs:3: include_str!($p) may name"));
        assert!(found[1].starts_with("labs/lab02/src/lib.rs:4: include_str!(concat!"));
        assert!(found[2].starts_with("labs/lab02/src/lib.rs:5: include_str named outside"));
        // Relative to this file's directory it stays inside, but not from every user's.
        let found = flags_in(
            "shapes/m.rs",
            r#"macro_rules! t { () => { include_str!("../t.txt") } }"#,
        );
        assert_eq!(
            found,
            [
                r#"labs/lab02/src/shapes/m.rs:1: include_str!("../t.txt") may name a file outside labs/lab02/src/ (inside macro_rules! its name is relative to the file that uses the macro)"#
            ]
        );
    }

    #[test]
    fn path_attributes_inside_src_are_fine() {
        assert!(flags(r#"#[path = "util.rs"] mod helpers;"#).is_empty());
        assert!(flags(r#"#[path = "shapes/../util.rs"] mod helpers;"#).is_empty());
        assert!(flags(r#"#[cfg_attr(test, path = "mock.rs")] mod helpers;"#).is_empty());
        assert!(
            flags(r#"#[doc = "path = ../../x"] pub fn path() { let path = "../../x"; }"#)
                .is_empty()
        );
        assert!(flags("#[derive(Debug)] #[serde(rename = \"path\")] struct S;").is_empty());
    }

    #[test]
    fn path_attributes_reaching_outside_are_flagged() {
        assert_eq!(
            flags("//! Lab 2.\n\n#[path = \"../../../../../../reference/src/lab02.rs\"]\nmod key;"),
            [
                r#"labs/lab02/src/lib.rs:3: #[path = "../../../../../../reference/src/lab02.rs"] names a file outside labs/lab02/src/"#
            ]
        );
        assert_eq!(
            flags(r#"#[cfg_attr(all(), path = "/work/reference/src/lab02.rs")] mod key;"#),
            [
                r#"labs/lab02/src/lib.rs:1: #[cfg_attr(all(), path = "/work/reference/src/lab02.rs")] names a file outside labs/lab02/src/"#
            ]
        );
        assert_eq!(
            flags("#![cfg_attr(x, cfg_attr(y, path = \"../k.rs\"))]").len(),
            1
        );
        assert_eq!(flags(r#"#[path = "notes.txt"] mod notes;"#).len(), 1);
        assert_eq!(
            flags(r#"#[debugger_visualizer(gdb_script_file = "../../../key.py")] mod m {}"#).len(),
            1
        );
        assert_eq!(
            flags_in(
                "shapes/sphere.rs",
                r#"#[path = "../common.rs"] mod common;"#
            ),
            [
                r#"labs/lab02/src/shapes/sphere.rs:1: #[path = "../common.rs"] may name a file outside labs/lab02/src/ (it is resolved from the module's directory, which may be above this file's)"#
            ]
        );
    }

    #[test]
    fn path_attributes_from_macro_input_are_flagged() {
        let code = r#"
macro_rules! m {
    ($p:literal) => { #[path = $p] mod key; };
    ($($a:tt)*) => { #[$($a)*] mod key; };
    ($c:tt) => { #[cfg_attr(all(), $c)] mod key; };
    (r) => { #[r#path = concat!("../", "k.rs")] mod key; };
}
"#;
        let found = flags(code);
        assert_eq!(found.len(), 4, "{found:#?}");
        assert!(found[0].starts_with(
            "labs/lab02/src/lib.rs:3: #[path = $p] may name a file outside labs/lab02/src/"
        ));
        assert!(found[1].starts_with(
            "labs/lab02/src/lib.rs:4: #[$($a)*] is an attribute made from macro input"
        ));
        assert!(
            found[2].starts_with("labs/lab02/src/lib.rs:5: #[cfg_attr(all(), $c)] is an attribute")
        );
        assert!(found[3].starts_with("labs/lab02/src/lib.rs:6: #[r#path = concat!"));
        // A value from macro input for another key is fine.
        assert!(flags("macro_rules! d { ($d:expr) => { #[doc = $d] fn f() {} }; }").is_empty());
    }

    #[test]
    fn assembly_and_unlexable_files_are_flagged() {
        assert_eq!(
            flags(r#"core::arch::global_asm!(".incbin \"/work/reference/src/lab02.rs\"");"#),
            [
                "labs/lab02/src/lib.rs:1: global_asm can put any file into the build (.incbin), so it may read a file outside labs/lab02/src/"
            ]
        );
        assert_eq!(
            flags("fn f() { \"unterminated }"),
            ["labs/lab02/src/lib.rs: does not parse as Rust; it will not compile"]
        );
        let tree = Tree::with(&[("lib.rs", b"fn f() {}\n"), ("bad.rs", b"fn \xff() {}")]);
        assert_eq!(
            scan_lab(&tree.0, LabId::of(2), &[]).flags,
            ["labs/lab02/src/bad.rs: does not parse as Rust; it will not compile"]
        );
    }

    #[test]
    fn every_rs_file_is_scanned_and_others_are_not() {
        let tree = Tree::with(&[
            ("lib.rs", b"#![doc = \"lab 2\"]\nmod shapes;\n"),
            (
                "shapes/mod.rs",
                b"#!/bin/sh\n\nconst K: &str = include_str!(\"../../key.rs\");\n",
            ),
            ("shapes/a/b.rs", b"include!(\"../../../../x.rs\");\n"),
            ("data/notes.txt", b"include_str!(\"/etc/passwd\")"),
        ]);
        assert_eq!(
            scan_lab(&tree.0, LabId::of(2), &[]).flags,
            [
                r#"labs/lab02/src/shapes/a/b.rs:1: include!("../../../../x.rs") names a file outside labs/lab02/src/"#,
                r#"labs/lab02/src/shapes/mod.rs:3: include_str!("../../key.rs") names a file outside labs/lab02/src/"#,
            ]
        );
    }

    #[test]
    fn denied_items_are_found_in_code_not_in_comments_or_strings() {
        let items = &[DeniedItem {
            name: "trace_to_closest".into(),
            own: Vec::new(),
            exercises: vec!["2.1".into()],
            computes: "the framework's closest hit".into(),
        }];
        let tree = Tree::with(&[(
            "lib.rs",
            b"// trace_to_closest in a comment\nconst S: &str = \"trace_to_closest\";\nfn f(s: &Scene) { s.r#trace_to_closest(r) }\nmacro_rules! m { () => { x.trace_to_closest(y) } }\n",
        )]);
        let scan = scan_lab(&tree.0, LabId::of(2), items);
        assert!(scan.flags.is_empty(), "{:?}", scan.flags);
        let uses = scan.denied;
        let lines: Vec<&str> = uses.iter().map(|u| u.line.as_str()).collect();
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(
            lines[0].starts_with("labs/lab02/src/lib.rs:3: `trace_to_closest`"),
            "{lines:?}"
        );
        assert!(
            lines[1].starts_with("labs/lab02/src/lib.rs:4: "),
            "{lines:?}"
        );
        assert_eq!(uses[0].exercises, &["2.1"]);
        assert!(scan_lab(&tree.0, LabId::of(2), &[]).denied.is_empty());
    }

    /// glam's `reflect` and `refract` answer Exercises 4.1 and 4.4, but the names are also the
    /// contract's own methods: only calls on another receiver or path count.
    #[test]
    fn a_denied_name_that_is_also_the_contracts_counts_only_on_another_receiver() {
        let honest = b"impl Reflection for Student {\n    fn reflect(&self, d: Vec3, n: Vec3) -> Vec3 { d - 2.0 * d.dot(n) * n }\n    fn reflected_ray(&self, r: &Ray, h: &Hit) -> Ray { let a = self.reflect(r.direction, h.shading_normal); let b = Self::reflect(self, a, h.shading_normal); let c = Reflection::reflect(self, b, h.shading_normal); todo!() }\n    fn refract(&self, d: Vec3, n: Vec3, a: f32, b: f32) -> Option<Vec3> { None }\n}\nfn helper(d: Vec3) -> Vec3 { reflect_twice(d) }\n";
        let tree = Tree::with_lab(LabId::of(4), &[("lib.rs", honest)]);
        let denied = &course::lab(course::LabId::of(4)).unwrap().denied;
        let scan = scan_lab(&tree.0, LabId::of(4), denied);
        assert!(
            scan.denied.is_empty(),
            "{:?}",
            scan.denied.iter().map(|u| &u.line).collect::<Vec<_>>()
        );

        let delegating = b"fn a(d: Vec3, n: Vec3) -> Vec3 { d.reflect(n) }\nfn b(d: Vec3, n: Vec3) -> Vec3 { Vec3::reflect(d, n) }\nfn c(d: Vec3, n: Vec3) -> Vec3 { (d * 1.0).refract(n, 1.5) }\nfn e(d: Vec3, n: Vec3) -> Vec3 { raylab_core::glam::Vec3::refract(d, n, 1.5) }\n";
        let tree = Tree::with_lab(LabId::of(4), &[("lib.rs", delegating)]);
        let lines: Vec<String> = scan_lab(&tree.0, LabId::of(4), denied)
            .denied
            .into_iter()
            .map(|u| u.line)
            .collect();
        assert_eq!(lines.len(), 4, "{lines:?}");
        assert!(
            lines[0].starts_with("labs/lab04/src/lib.rs:1: `reflect` (glam's reflection"),
            "{lines:?}"
        );
        assert!(lines[3].contains("answers Exercise 4.4"), "{lines:?}");
    }
}
