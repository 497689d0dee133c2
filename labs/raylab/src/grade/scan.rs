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
//!
//! A file is read as rustc reads it: without a byte order mark, each CRLF made LF, and without
//! a shebang line by rustc's own rule (`#!` not followed by `[`, past whitespace and comments
//! that are not doc comments), so that `#!/**/[allow(unused)] #[path = "…"] mod key;` is an
//! attribute and a module to the scan as it is to rustc. Then rustc's own lexer
//! (`ra_ap_rustc_lexer`) and proc-macro2 both read it, and a file they read differently is
//! refused, not scanned: a frontmatter (`---`), a token only one of them accepts, an
//! identifier rustc reads as another name (in Unicode normal form C), or any other token that
//! is not the same token, at the same place, to both.

use course::LabId;
use std::fs;
use std::ops::Range;
use std::path::{Component, Path, PathBuf};

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};
use ra_ap_rustc_lexer::{Cursor, DocStyle, FrontmatterAllowed, LiteralKind, TokenKind};

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
    /// outside labs/lab02/src/`. A file that does not lex as Rust is flagged as not compiling,
    /// and one that rustc reads otherwise than the scan as not scanned.
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
        match lex(&as_rustc_reads(&text)) {
            Ok(tokens) => {
                scanner.scan(tokens, Context::default());
                flags.extend(scanner.flags);
                denied_uses.extend(scanner.denied);
            }
            Err(Unread::Unlexed) => flags.push(unlexed),
            Err(Unread::At { line, why }) => flags.push(format!("{}:{line}: {why}", scanner.file)),
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

/// `text` as rustc lexes it: without a byte order mark, each CRLF made LF (as rustc's source
/// map does, in one pass: `\r\r\n` becomes `\r\n`), and without a shebang line, by rustc's own
/// rule (`ra_ap_rustc_lexer::strip_shebang`: `#!` is a shebang unless the first token after it
/// that is not whitespace or a comment, a doc comment excepted, is `[`). The shebang's line is
/// left empty, so that line numbers stay the same.
fn as_rustc_reads(text: &str) -> String {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let text = text.replace("\r\n", "\n");
    match ra_ap_rustc_lexer::strip_shebang(&text) {
        Some(shebang) => text[shebang..].to_string(),
        None => text,
    }
}

/// Why a file's tokens are not scanned.
#[derive(Debug)]
enum Unread {
    /// proc-macro2 cannot lex it.
    Unlexed,
    /// Rustc reads it otherwise than the scan would: at line `line`, for the reason `why`.
    At { line: usize, why: String },
}

/// What a token is, as the two lexers' tokens are compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Piece {
    Ident,
    Literal,
    Punct(char),
    Open(Delimiter),
    Close(Delimiter),
    /// A doc comment (an attribute to both), inner or not.
    Doc {
        inner: bool,
    },
}

/// A token of a file: what it is, and its bytes.
type Token = (Piece, Range<usize>);

/// What in a file rustc's lexer reads in a way the scan cannot follow, and its bytes.
#[derive(Debug)]
enum Unfollowed {
    /// A frontmatter (`---` … `---` at the top), which proc-macro2 does not know.
    Frontmatter(Range<usize>),
    /// A token rustc rejects (an unknown character, an unterminated literal or comment, a
    /// reserved prefix, …): the file does not compile.
    Rejected(Range<usize>),
    /// An identifier rustc reads as another name: its Unicode normal form C.
    Renamed(Range<usize>),
}

impl Unfollowed {
    /// Why the scan does not read `text`, where this is.
    fn unread(self, text: &str) -> Unread {
        let (bytes, why) = match self {
            Unfollowed::Frontmatter(bytes) => (
                bytes,
                "cannot be scanned: it opens with a frontmatter (`---`), which the scan does not read"
                    .to_string(),
            ),
            Unfollowed::Rejected(bytes) => {
                let shown = token_text(&text[bytes.clone()]);
                let why =
                    format!("does not parse as Rust (rustc rejects `{shown}`); it will not compile");
                (bytes, why)
            }
            Unfollowed::Renamed(bytes) => {
                let shown = token_text(&text[bytes.clone()]);
                let why = format!(
                    "cannot be scanned: rustc reads the identifier `{shown}` as another name (its Unicode normal form C)"
                );
                (bytes, why)
            }
        };
        Unread::At {
            line: line_of(text, bytes.start),
            why,
        }
    }
}

/// The line of `text` that its byte `at` is on, counted from 1 (as proc-macro2 counts them).
fn line_of(text: &str, at: usize) -> usize {
    text[..at].matches('\n').count() + 1
}

/// `text` (as [`as_rustc_reads`] gives it) lexed by proc-macro2, if rustc's lexer reads the
/// same tokens in it (comments and whitespace aside) at the same places; otherwise why not.
fn lex(text: &str) -> Result<TokenStream, Unread> {
    let rustc = rustc_tokens(text);
    // proc-macro2 may not lex a frontmatter at all, but that is not why the file is unread.
    if let Err(frontmatter @ Unfollowed::Frontmatter(_)) = rustc {
        return Err(frontmatter.unread(text));
    }
    let tokens: TokenStream = text.parse().map_err(|_| Unread::Unlexed)?;
    let rustc = rustc.map_err(|unfollowed| unfollowed.unread(text))?;
    let mut scanned = Vec::new();
    scanned_tokens(tokens.clone(), &mut scanned);
    let Some(i) = (0..rustc.len().max(scanned.len())).find(|&i| rustc.get(i) != scanned.get(i))
    else {
        return Ok(tokens);
    };
    // The bytes of both tokens, where each lexer has one.
    let bytes = [rustc.get(i), scanned.get(i)]
        .into_iter()
        .flatten()
        .map(|(_, bytes)| bytes.clone())
        .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end))
        .unwrap_or_default();
    Err(Unread::At {
        line: line_of(text, bytes.start),
        why: format!(
            "cannot be scanned: rustc and the scan read `{}` as different tokens",
            token_text(&text[bytes])
        ),
    })
}

/// The tokens rustc's lexer reads in `text` (as [`as_rustc_reads`] gives it), whitespace and
/// comments left out (doc comments kept), as rustc's parser takes them from it
/// (`rustc_parse::lexer`); or the first thing in it that the scan cannot follow.
fn rustc_tokens(text: &str) -> Result<Vec<Token>, Unfollowed> {
    let mut tokens = Vec::new();
    let mut cursor = Cursor::new(text, FrontmatterAllowed::Yes);
    let mut start = 0;
    loop {
        let token = cursor.advance_token();
        let bytes = start..start + token.len as usize;
        start = bytes.end;
        let source = &text[bytes.clone()];
        let piece = match token.kind {
            TokenKind::Eof => return Ok(tokens),
            TokenKind::Whitespace
            | TokenKind::LineComment { doc_style: None }
            | TokenKind::BlockComment {
                doc_style: None,
                terminated: true,
            } => continue,
            TokenKind::LineComment {
                doc_style: Some(style),
            }
            | TokenKind::BlockComment {
                doc_style: Some(style),
                terminated: true,
            } => Piece::Doc {
                inner: style == DocStyle::Inner,
            },
            TokenKind::Frontmatter { .. } => return Err(Unfollowed::Frontmatter(bytes)),
            // rustc takes an identifier in its normal form C (`nfc_normalize`).
            TokenKind::Ident | TokenKind::RawIdent
                if !source.is_ascii() && !unicode_normalization::is_nfc(source) =>
            {
                return Err(Unfollowed::Renamed(bytes));
            }
            TokenKind::Ident | TokenKind::RawIdent => Piece::Ident,
            // proc-macro2 reads a lifetime as a joint `'` and an identifier.
            TokenKind::Lifetime {
                starts_with_number: false,
            }
            | TokenKind::RawLifetime => {
                tokens.push((Piece::Punct('\''), bytes.start..bytes.start + 1));
                tokens.push((Piece::Ident, bytes.start + 1..bytes.end));
                continue;
            }
            TokenKind::Literal { kind, .. } if well_formed(kind) => Piece::Literal,
            TokenKind::OpenParen => Piece::Open(Delimiter::Parenthesis),
            TokenKind::CloseParen => Piece::Close(Delimiter::Parenthesis),
            TokenKind::OpenBrace => Piece::Open(Delimiter::Brace),
            TokenKind::CloseBrace => Piece::Close(Delimiter::Brace),
            TokenKind::OpenBracket => Piece::Open(Delimiter::Bracket),
            TokenKind::CloseBracket => Piece::Close(Delimiter::Bracket),
            TokenKind::Semi
            | TokenKind::Comma
            | TokenKind::Dot
            | TokenKind::At
            | TokenKind::Pound
            | TokenKind::Tilde
            | TokenKind::Question
            | TokenKind::Colon
            | TokenKind::Dollar
            | TokenKind::Eq
            | TokenKind::Bang
            | TokenKind::Lt
            | TokenKind::Gt
            | TokenKind::Minus
            | TokenKind::And
            | TokenKind::Or
            | TokenKind::Plus
            | TokenKind::Star
            | TokenKind::Slash
            | TokenKind::Caret
            | TokenKind::Percent => Piece::Punct(source.chars().next().unwrap_or_default()),
            // What rustc reports as an error: an unterminated comment or literal, a malformed
            // number or raw string, a lifetime starting with a digit, an unknown character or
            // prefix (`foo"…"`, `k#…`), an emoji, and (edition 2024) `#"…"` and `##`.
            _ => return Err(Unfollowed::Rejected(bytes)),
        };
        tokens.push((piece, bytes));
    }
}

/// Whether rustc accepts a literal of `kind` (terminated, with digits, a raw string's
/// delimiters right).
fn well_formed(kind: LiteralKind) -> bool {
    match kind {
        LiteralKind::Int { empty_int, .. } => !empty_int,
        LiteralKind::Float { empty_exponent, .. } => !empty_exponent,
        LiteralKind::Char { terminated }
        | LiteralKind::Byte { terminated }
        | LiteralKind::Str { terminated }
        | LiteralKind::ByteStr { terminated }
        | LiteralKind::CStr { terminated } => terminated,
        LiteralKind::RawStr { n_hashes }
        | LiteralKind::RawByteStr { n_hashes }
        | LiteralKind::RawCStr { n_hashes } => n_hashes.is_some(),
    }
}

/// Adds the tokens proc-macro2 read in `stream` to `tokens`, in rustc's terms: a group as its
/// delimiters around its tokens, and a doc comment (which proc-macro2 gives as `#`, `!` if
/// inner, and `[doc = "…"]`, each with the comment's span) as one token.
fn scanned_tokens(stream: TokenStream, tokens: &mut Vec<Token>) {
    let trees: Vec<TokenTree> = stream.into_iter().collect();
    let mut i = 0;
    while let Some(tree) = trees.get(i) {
        let bytes = tree.span().byte_range();
        i += 1;
        match tree {
            // A `#` of its own is one byte; a longer one is a doc comment's.
            TokenTree::Punct(punct) if punct.as_char() == '#' && bytes.len() != 1 => {
                let same = |tree: Option<&TokenTree>| {
                    tree.is_some_and(|tree| tree.span().byte_range() == bytes)
                };
                let inner = is_punct(trees.get(i), '!') && same(trees.get(i));
                let attribute = i + usize::from(inner);
                if matches!(trees.get(attribute), Some(TokenTree::Group(_)))
                    && same(trees.get(attribute))
                {
                    i = attribute + 1;
                    tokens.push((Piece::Doc { inner }, bytes));
                } else {
                    tokens.push((Piece::Punct('#'), bytes));
                }
            }
            TokenTree::Punct(punct) => tokens.push((Piece::Punct(punct.as_char()), bytes)),
            TokenTree::Ident(_) => tokens.push((Piece::Ident, bytes)),
            TokenTree::Literal(_) => tokens.push((Piece::Literal, bytes)),
            TokenTree::Group(group) => {
                let delimiter = group.delimiter();
                tokens.push((Piece::Open(delimiter), group.span_open().byte_range()));
                scanned_tokens(group.stream(), tokens);
                tokens.push((Piece::Close(delimiter), group.span_close().byte_range()));
            }
        }
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

/// The source text of `span` for a line, as [`excerpt_of`] shows it.
fn excerpt(span: Span, fallback: impl FnOnce() -> String) -> String {
    excerpt_of(&span.source_text().unwrap_or_else(fallback))
}

/// `text` for a line: whitespace runs made one space, control characters escaped, at most 120
/// characters.
fn excerpt_of(text: &str) -> String {
    let text = text.split_whitespace().collect::<Vec<_>>().join(" ");
    let text = shown(Path::new(&text));
    if text.chars().count() > 120 {
        let cut: String = text.chars().take(119).collect();
        format!("{cut}…")
    } else {
        text
    }
}

/// The text of tokens for a line, as [`excerpt_of`] shows it but with every character other
/// than an ASCII letter, digit, symbol or space escaped (`\u{a0}`): what the lexers read
/// differently may be a character that looks like another, or like nothing.
fn token_text(text: &str) -> String {
    let escaped: String = text
        .chars()
        .map(|c| match c {
            ' ' => " ".to_string(),
            c if c.is_ascii_graphic() => c.to_string(),
            c if c.is_ascii_whitespace() => " ".to_string(),
            c => c.escape_unicode().to_string(),
        })
        .collect();
    excerpt_of(&escaped)
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

    /// A first line that starts with `#!` and rustc reads as code: `#!` and `[` with
    /// whitespace and comments (not doc comments) between them.
    #[test]
    fn shebang_like_lines_that_rustc_reads_as_code_are_scanned() {
        let outside = "names a file outside labs/lab02/src/";
        for (code, line, flagged) in [
            (
                r#"#!/**/[allow(unused)] #[path = "../../../reference/src/lab01.rs"] mod key;"#,
                1,
                r#"#[path = "../../../reference/src/lab01.rs"]"#,
            ),
            (
                r#"#!/**/[allow(unused)] const K: &str = include_str!("../../../reference/src/lab01.rs");"#,
                1,
                r#"include_str!("../../../reference/src/lab01.rs")"#,
            ),
            (
                r#"#!/**/[allow(unused)] const K: &[u8] = include_bytes!("/work/reference/src/lab01.rs");"#,
                1,
                r#"include_bytes!("/work/reference/src/lab01.rs")"#,
            ),
            (
                r#"#!/**/[allow(unused)] include!("../../../reference/src/lab01.rs");"#,
                1,
                r#"include!("../../../reference/src/lab01.rs")"#,
            ),
            (
                "#!//x\n[allow(unused)] #[path = \"../k.rs\"] mod key;",
                2,
                r#"#[path = "../k.rs"]"#,
            ),
            (
                r#"#! /*a/*b*/c*/ [allow(unused)] #[path = "../k.rs"] mod key;"#,
                1,
                r#"#[path = "../k.rs"]"#,
            ),
            (
                "#!\n\t/* a */ // b\n[allow(unused)] const K: &str = include_str!(\"/etc/passwd\");",
                3,
                r#"include_str!("/etc/passwd")"#,
            ),
        ] {
            assert_eq!(
                flags(code),
                [format!("labs/lab02/src/lib.rs:{line}: {flagged} {outside}")],
                "{code}"
            );
        }
        let found = flags(
            r#"#!/**/[allow(unused)] const K: &str = include_str!(concat!(env!("PWD"), "/reference/src/lab01.rs"));"#,
        );
        assert_eq!(found.len(), 1, "{found:?}");
        assert!(
            found[0]
                .ends_with("may name a file outside labs/lab02/src/ (not a plain string literal)"),
            "{found:?}"
        );
        // An inner attribute that starts the file is code, with or without a space.
        assert_eq!(
            flags("#![cfg_attr(all(), path = \"../k.rs\")]\nmod key;").len(),
            1
        );
        assert_eq!(
            flags("#! [cfg_attr(all(), path = \"../k.rs\")]\nmod key;").len(),
            1
        );
    }

    /// A first line that rustc skips: `#!` followed by anything but `[`, where a doc comment
    /// is not skipped on the way.
    #[test]
    fn shebang_lines_are_skipped_and_the_lines_after_them_scanned() {
        let key = r#"include_str!("../../key.rs") names a file outside labs/lab02/src/"#;
        for first in [
            "#!/usr/bin/env run-cargo-script",
            "#!/usr/bin/env run-cargo-script include_str!(\"/etc/passwd\")",
            r#"#!/** doc */[allow(unused)] const P: &str = include_str!("/etc/passwd");"#,
            r#"#! /// doc [allow(unused)] const P: &str = include_str!("/etc/passwd");"#,
            r#"#!/*! doc */ [path = "../p.rs"] mod p;"#,
            "#!",
        ] {
            let code = format!("{first}\nconst K: &str = include_str!(\"../../key.rs\");\n");
            assert_eq!(
                flags(&code),
                [format!("labs/lab02/src/lib.rs:2: {key}")],
                "{first}"
            );
        }
    }

    #[test]
    fn byte_order_marks_and_crlf_are_read_as_rustc_reads_them() {
        assert_eq!(
            flags(
                "\u{feff}#!/**/[allow(unused)] #[path = \"../../../reference/src/lab01.rs\"] mod key;"
            ),
            [
                r#"labs/lab02/src/lib.rs:1: #[path = "../../../reference/src/lab01.rs"] names a file outside labs/lab02/src/"#
            ]
        );
        assert_eq!(
            flags(
                "\u{feff}#!/usr/bin/env run-cargo-script\r\nconst K: &str = include_str!(\"../../key.rs\");\r\n"
            ),
            [
                r#"labs/lab02/src/lib.rs:2: include_str!("../../key.rs") names a file outside labs/lab02/src/"#
            ]
        );
        // Lines ending in CRLF keep their numbers; doc comments and strings are read as with LF.
        assert_eq!(
            flags(
                "//! Lab 2.\r\n/// The key.\r\n#[path = \"../../../reference/src/lab02.rs\"]\r\nmod key;\r\n"
            ),
            [
                r#"labs/lab02/src/lib.rs:3: #[path = "../../../reference/src/lab02.rs"] names a file outside labs/lab02/src/"#
            ]
        );
        assert!(flags("/// Fine.\r\nfn f() -> &'static str { \"a\r\nb\" }\r\n").is_empty());
    }

    #[test]
    fn a_file_is_read_as_rustc_reads_it_without_bom_crlf_or_shebang() {
        assert_eq!(as_rustc_reads("\u{feff}fn f() {}\r\n"), "fn f() {}\n");
        // Only the first byte order mark; each CRLF of the file once, a lone CR kept.
        assert_eq!(
            as_rustc_reads("\u{feff}\u{feff}a\r\r\nb\rc\r\n"),
            "\u{feff}a\r\nb\rc\n"
        );
        assert_eq!(
            as_rustc_reads("#!/usr/bin/env run-cargo-script\r\nfn main() {}\r\n"),
            "\nfn main() {}\n"
        );
        assert_eq!(as_rustc_reads("#!/** doc */[x]\ny"), "\ny");
        assert_eq!(as_rustc_reads("#!//x\n[x]\ny"), "#!//x\n[x]\ny");
        assert_eq!(as_rustc_reads("#!/*a/*b*/c*/[x]"), "#!/*a/*b*/c*/[x]");
        assert_eq!(as_rustc_reads("\u{feff}#!\r\n[x]"), "#!\n[x]");
    }

    #[test]
    fn files_rustc_reads_otherwise_are_refused() {
        let refused = |code: &str| {
            let found = flags(code);
            assert_eq!(found.len(), 1, "{code:?}: {found:?}");
            found.into_iter().next().unwrap_or_default()
        };
        let frontmatter =
            "cannot be scanned: it opens with a frontmatter (`---`), which the scan does not read";
        assert_eq!(
            refused("---\n[dependencies]\n---\n\n#[path = \"../k.rs\"] mod key;\n"),
            format!("labs/lab02/src/lib.rs:1: {frontmatter}")
        );
        assert_eq!(
            refused(
                "#!/usr/bin/env -S cargo +nightly -Zscript\n---cargo\n[package]\nedition = \"2024\"\n---\nfn main() {}\n"
            ),
            format!("labs/lab02/src/lib.rs:2: {frontmatter}")
        );
        // A no-break space: rustc rejects it, proc-macro2 reads whitespace.
        assert_eq!(
            refused("const\u{a0}K: u8 = 1;"),
            r"labs/lab02/src/lib.rs:1: does not parse as Rust (rustc rejects `\u{a0}`); it will not compile"
        );
        // Reserved in edition 2024, two `#` to proc-macro2.
        assert_eq!(
            refused("macro_rules! m { (##) => {}; }"),
            "labs/lab02/src/lib.rs:1: does not parse as Rust (rustc rejects `##`); it will not compile"
        );
        // A group to rustc, one literal token to proc-macro2.
        assert_eq!(
            refused("fn f() {\n    g(/*ERROR*/);\n}"),
            "labs/lab02/src/lib.rs:2: cannot be scanned: rustc and the scan read `(/*ERROR*/)` as different tokens"
        );
        // The Kelvin sign, which rustc reads as `K`.
        assert_eq!(
            refused("fn f() -> \u{212a}ey { todo!() }"),
            r"labs/lab02/src/lib.rs:1: cannot be scanned: rustc reads the identifier `\u{212a}ey` as another name (its Unicode normal form C)"
        );
        // Identifiers in normal form C are read as written, as are comments rustc skips.
        assert!(flags("fn θ(φ: f32) -> f32 { φ /* ∞ */ } // ☀\n").is_empty());
    }
}
