//! `raylab reset N.M`: puts the stub of one exercise back as the handout had it — the function
//! the exercise table names (`labs/labNN/exercises.toml`) in `labs/labNN/src/lib.rs` — and
//! leaves the rest of the file byte for byte as the student has it.
//!
//! The original is the file as the handout's last own commit that changed it holds it
//! (`raylab handout` makes the handout a git repository, committed as `raylab`; its releases
//! change a student's file only when forced to): the stub in a student's clone of the
//! handout. In a repository without such commits, it is the commit that added the file. The function is found by
//! its tokens (`proc-macro2`, whose spans give byte ranges), from its doc comment and
//! attributes to its closing brace.
//!
//! What it replaces is kept: before the file is written, the student's whole file as it was goes
//! to `out/reset/labNN-lib-N.M-YYYYMMDDTHHMMSSZ.rs` of the handout, and the command names it.
//! A copy rather than a refusal of uncommitted changes (unless forced): work not yet committed
//! is exactly what a reset loses, and git could only keep it in a commit — which, made to get
//! past a refusal, would move the lab's submission time (grading takes it from the last commit
//! that changed the lab's sources). `out/` is where a copy changes nothing else: git ignores
//! it (the handout's `.gitignore`), so the clone gets no file to commit or merge; grading never
//! reads it (it takes the regular files of `labs/labNN/src/` and `labs/labNN/answers.md`, and
//! compares no `out/` folder); and no crate's build reads it (cargo compiles what a crate's
//! `src/lib.rs` names, and `out/` is no crate's).

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use clap::Args;
use course::ExerciseInfo;
use proc_macro2::{Delimiter, TokenStream, TokenTree};
use raylab_core::Error;

use crate::git::{git, git_text};

/// Options of `raylab reset`.
#[derive(Args, Debug)]
pub struct ResetArgs {
    /// The exercise whose function to restore, numbered as in the docs and the stubs (e.g.
    /// `1.2`).
    pub exercise: String,
    /// Show the function as you have it and as the handout had it, and change nothing.
    #[arg(long)]
    pub dry_run: bool,
    /// The handout to work in (default: the one the current directory is in).
    #[arg(long, value_name = "DIR")]
    pub handout: Option<PathBuf>,
}

/// A lab's source larger than this is refused rather than read.
const MAX_SOURCE_BYTES: u64 = 4 << 20;

/// The exercise `raylab reset` would reset: one whose stub is one function.
pub fn check(args: &ResetArgs) -> Result<&'static ExerciseInfo, Error> {
    let exercise = crate::hint::find(&args.exercise)?;
    if !is_identifier(&exercise.function) {
        return Err(Error::Invalid {
            what: format!("exercise {}", exercise.id),
            reason: format!(
                "its stub is `{}`, not one function of {}; reset the exercises it is made of one by one",
                exercise.function,
                exercise.lab.source()
            ),
        });
    }
    Ok(exercise)
}

/// Runs `raylab reset`.
pub fn run(args: &ResetArgs) -> Result<(), Error> {
    let root = args
        .handout
        .clone()
        .unwrap_or_else(crate::checkout::workspace_root);
    let exercise = check(args)?;
    let function = exercise.function.as_str();
    let file = exercise.lab.source();
    let path = root.join(&file);
    let size = std::fs::metadata(&path)
        .map_err(|e| Error::io(&path, e))?
        .len();
    if size > MAX_SOURCE_BYTES {
        return Err(Error::Failed {
            what: file.clone(),
            reason: format!(
                "{size} bytes, more than the {MAX_SOURCE_BYTES} a lab's source may have"
            ),
        });
    }
    let current = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
    let original = original_text(&root, &file)?;
    let original_range = only_function(&original, function).map_err(|why| Error::Failed {
        what: format!("the handout's original of {file}"),
        reason: format!("cannot find the stub of exercise {}: {why}", exercise.id),
    })?;
    let range = only_function(&current, function).map_err(|why| Error::Failed {
        what: file.clone(),
        reason: format!("cannot reset exercise {}: {why}", exercise.id),
    })?;
    let stub = &original[original_range.clone()];
    let yours = &current[range.clone()];
    let lines = line_of(&current, range.start)..=line_of(&current, range.end);
    let (first, last) = (lines.start(), lines.end());
    if yours == stub {
        println!(
            "Exercise {}: `{function}` in {file} (lines {first}–{last}) is already the handout's stub; nothing changed.",
            exercise.id
        );
        return Ok(());
    }
    if args.dry_run {
        println!(
            "Exercise {}: would replace `{function}` in {file}, lines {first}–{last}:",
            exercise.id
        );
        for line in from_line_start(&current, range.clone()).lines() {
            println!("- {line}");
        }
        println!("with the handout's stub:");
        for line in from_line_start(&original, original_range).lines() {
            println!("+ {line}");
        }
        println!("(--dry-run: nothing changed)");
        return Ok(());
    }
    let restored = format!("{}{stub}{}", &current[..range.start], &current[range.end..]);
    let kept = keep(
        &root,
        exercise.lab,
        &exercise.id,
        &current,
        crate::utc::now(),
    )?;
    std::fs::write(&path, restored).map_err(|e| Error::io(&path, e))?;
    println!(
        "Exercise {}: restored `{function}` in {file} (your version was lines {first}–{last}) to the handout's stub; every other function is as you left it. Your {file} as it was is kept in {kept} (git ignores out/, and grading never reads it).",
        exercise.id
    );
    Ok(())
}

/// The folder of the handout where [`keep`] puts the files `reset` replaced.
pub const KEPT: &str = "out/reset";

/// Writes `text`, the student's source of `lab` before exercise `exercise` was reset at
/// `seconds` since the Unix epoch, to a new file of [`KEPT`] in the handout `root`, named by
/// the lab, the exercise and the time (UTC), and never over another; its path relative to
/// `root`.
fn keep(
    root: &Path,
    lab: course::LabId,
    exercise: &str,
    text: &str,
    seconds: u64,
) -> Result<String, Error> {
    let dir = root.join(KEPT);
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let [year, month, day, hour, minute, second] = crate::utc::date_time(seconds);
    let stem = format!(
        "{lab}-lib-{exercise}-{year:04}{month:02}{day:02}T{hour:02}{minute:02}{second:02}Z"
    );
    let mut n = 1;
    loop {
        let name = match n {
            1 => format!("{stem}.rs"),
            _ => format!("{stem}-{n}.rs"),
        };
        let path = dir.join(&name);
        match std::fs::File::create_new(&path) {
            Ok(mut file) => {
                std::io::Write::write_all(&mut file, text.as_bytes())
                    .map_err(|e| Error::io(&path, e))?;
                return Ok(format!("{KEPT}/{name}"));
            }
            // Reset twice in one second.
            Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => n += 1,
            Err(e) => return Err(Error::io(&path, e)),
        }
    }
}

/// Whether `name` is a plain Rust identifier (a function's name, not a description).
fn is_identifier(name: &str) -> bool {
    let mut chars = name.chars();
    chars.next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && chars.all(|c| c.is_alphanumeric() || c == '_')
}

/// The handout's original text of `file` (relative to `root`): the file as the last commit
/// of the handout's own (`raylab handout` and its releases) that changed it holds it, or,
/// in a repository with none, as the commit that added it.
fn original_text(root: &Path, file: &str) -> Result<String, Error> {
    let cannot = |why: String| Error::Failed {
        what: format!("the handout's original of {file}"),
        reason: format!(
            "{why}; `raylab reset` takes it from the git history of your clone of the handout repository"
        ),
    };
    let history = |args: &[&str]| {
        git_text(root, args).map_err(|e| cannot(format!("git cannot read the history ({e})")))
    };
    let author = format!("--author=<{}>", crate::git::HANDOUT_EMAIL);
    let released = history(&["log", "-1", &author, "--format=%H", "--", file])?;
    let added = history(&["log", "--diff-filter=A", "--format=%H", "--", file])?;
    let Some(commit) = released.lines().next().or(added.lines().last()) else {
        return Err(cannot("no commit of the repository adds it".into()));
    };
    let bytes = git(root, &["show", &format!("{commit}:./{file}")])
        .map_err(|e| cannot(format!("git cannot show it ({e})")))?;
    String::from_utf8(bytes).map_err(|_| cannot("it is not UTF-8".into()))
}

/// The text of `range` in `text` with the indentation of its first line.
fn from_line_start(text: &str, range: Range<usize>) -> &str {
    let start = text[..range.start].rfind('\n').map_or(0, |i| i + 1);
    &text[start..range.end]
}

/// The 1-based line of byte `offset` in `text`.
pub fn line_of(text: &str, offset: usize) -> usize {
    text.as_bytes()[..offset.min(text.len())]
        .iter()
        .filter(|&&b| b == b'\n')
        .count()
        + 1
}

/// The byte range of the one function named `name` in `source`, from its doc comment and
/// attributes to the end of its body; an error saying why when the source does not parse, or
/// holds no such function or several.
fn only_function(source: &str, name: &str) -> Result<Range<usize>, String> {
    let stream = TokenStream::from_str(source).map_err(|e| {
        format!(
            "the file does not parse at line {} ({e}); fix the braces or quotes there first",
            e.span().start().line
        )
    })?;
    let mut found = Vec::new();
    functions_named(stream, name, &mut found);
    match found.len() {
        0 => Err(format!("it has no function `{name}`")),
        1 => Ok(found.remove(0)),
        n => Err(format!(
            "it has {n} functions named `{name}` (lines {}); keep only the exercise's",
            found
                .iter()
                .map(|r| line_of(source, r.start).to_string())
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// Whether `token` is the identifier `word`.
fn is_word(token: &TokenTree, word: &str) -> bool {
    matches!(token, TokenTree::Ident(ident) if ident == word)
}

/// Adds to `found` the byte range of every function named `name` in `stream`, at any depth
/// (in `impl` blocks, modules, other functions).
fn functions_named(stream: TokenStream, name: &str, found: &mut Vec<Range<usize>>) {
    let tokens: Vec<TokenTree> = stream.into_iter().collect();
    for (i, token) in tokens.iter().enumerate() {
        if let TokenTree::Group(group) = token {
            functions_named(group.stream(), name, found);
        }
        if !is_word(token, "fn") || !tokens.get(i + 1).is_some_and(|t| is_word(t, name)) {
            continue;
        }
        // The body, or the `;` of a declaration without one.
        let end = tokens[i + 2..].iter().find_map(|t| match t {
            TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => {
                Some(g.span().byte_range().end)
            }
            TokenTree::Punct(p) if p.as_char() == ';' => Some(p.span().byte_range().end),
            _ => None,
        });
        let Some(end) = end else { continue };
        // Back over qualifiers (`pub(crate) const unsafe extern "C"`) and attributes, doc
        // comments among them (`///` is `#[doc = "…"]`).
        let mut start = i;
        while start > 0 {
            let before = start.checked_sub(2).map(|b| &tokens[b]);
            match &tokens[start - 1] {
                TokenTree::Ident(ident)
                    if ["pub", "const", "async", "unsafe", "extern", "default"]
                        .iter()
                        .any(|q| ident == q) =>
                {
                    start -= 1
                }
                TokenTree::Literal(_) if before.is_some_and(|t| is_word(t, "extern")) => start -= 1,
                TokenTree::Group(g)
                    if g.delimiter() == Delimiter::Parenthesis
                        && before.is_some_and(|t| is_word(t, "pub")) =>
                {
                    start -= 1
                }
                TokenTree::Group(g)
                    if g.delimiter() == Delimiter::Bracket
                        && matches!(before, Some(TokenTree::Punct(p)) if p.as_char() == '#') =>
                {
                    start -= 2
                }
                _ => break,
            }
        }
        found.push(tokens[start].span().byte_range().start..end);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const STUB: &str = r#"//! A lab.
use x::Y;

impl Camera for Student {
    /// **Exercise 1.1** — the first.
    ///
    /// ```text
    /// x = { a }
    /// ```
    fn first(&self, a: f32) -> f32 {
        todo!("Exercise 1.1: first")
    }

    /// **Exercise 1.2** — the second.
    #[inline]
    pub(crate) fn second(&self) -> Vec<f32> where Self: Sized {
        todo!("Exercise 1.2: second")
    }
}

fn helper() {}
"#;

    #[test]
    fn a_function_is_found_from_its_doc_comment_to_its_closing_brace() {
        let range = only_function(STUB, "second").unwrap();
        assert!(STUB[range.clone()].starts_with("/// **Exercise 1.2**"));
        assert!(STUB[range].ends_with("todo!(\"Exercise 1.2: second\")\n    }"));
        let range = only_function(STUB, "first").unwrap();
        assert!(STUB[range.clone()].starts_with("/// **Exercise 1.1**"));
        assert!(STUB[range].ends_with("first\")\n    }"));
        assert_eq!(
            &STUB[only_function(STUB, "helper").unwrap()],
            "fn helper() {}"
        );
    }

    #[test]
    fn resetting_one_function_keeps_the_rest_byte_for_byte() {
        let student = STUB
            .replace(
                "todo!(\"Exercise 1.1: first\")",
                "a * 2.0 // mine\n        // also mine",
            )
            .replace("todo!(\"Exercise 1.2: second\")", "vec![1.0]")
            .replace(
                "fn helper() {}",
                "fn helper() { /* { */ }\nconst K: &str = \"}\";",
            );
        let range = only_function(&student, "second").unwrap();
        let original = &STUB[only_function(STUB, "second").unwrap()];
        let restored = format!(
            "{}{original}{}",
            &student[..range.start],
            &student[range.end..]
        );
        assert_eq!(
            restored,
            student.replace("vec![1.0]", "todo!(\"Exercise 1.2: second\")")
        );
    }

    #[test]
    fn no_function_several_or_a_broken_file_is_a_reason_not_a_guess() {
        assert!(
            only_function(STUB, "third")
                .unwrap_err()
                .contains("no function `third`")
        );
        let twice = format!("{STUB}\nmod m {{ fn first() {{}} }}\n");
        let error = only_function(&twice, "first").unwrap_err();
        assert!(error.contains("2 functions named `first`"), "{error}");
        let broken = STUB.replace("fn helper() {}", "fn helper() {");
        let error = only_function(&broken, "first").unwrap_err();
        assert!(error.contains("does not parse"), "{error}");
        assert!(!is_identifier("CameraRays (all of it)"));
        assert!(is_identifier("camera_basis"));
    }

    #[test]
    fn what_a_reset_replaces_is_kept_where_git_and_grading_do_not_look() {
        let root = std::env::temp_dir().join(format!("raylab-kept-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&root);
        // 2026-10-12T21:30:05Z.
        let at = 1_791_840_605;
        let lab = course::LabId::of(1);
        let first = keep(&root, lab, "1.2", "mine", at).unwrap();
        assert_eq!(first, "out/reset/lab01-lib-1.2-20261012T213005Z.rs");
        // A second reset in the same second gets a file of its own.
        let second = keep(&root, lab, "1.2", "mine again", at).unwrap();
        assert_eq!(second, "out/reset/lab01-lib-1.2-20261012T213005Z-2.rs");
        for (kept, text) in [(&first, "mine"), (&second, "mine again")] {
            assert_eq!(std::fs::read_to_string(root.join(kept)).unwrap(), text);
        }
        // `out/` is what the handout's `.gitignore` (the repository's) leaves out, so a copy
        // is nothing to commit; and no lab's sources, which grading takes.
        let ignored = include_str!("../../../.gitignore");
        assert!(ignored.lines().any(|line| line == "/out"), "{ignored}");
        assert!(!first.starts_with("labs/"));
        std::fs::remove_dir_all(&root).unwrap();
    }
}
