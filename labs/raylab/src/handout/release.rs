//! The handout as a git repository, and its releases as commits.
//!
//! `raylab handout --out DIR` makes DIR a repository on branch `main` with one commit; the
//! instructor publishes it and students clone it. `raylab handout --update DIR` builds the tree
//! again (with more solutions released, or the course's fixes) and brings DIR's work tree to
//! it as one new commit, which students `git pull --no-rebase` (a merge with their own
//! commits; git reads no setting from a repository's tracked files, so a plain `git pull`
//! cannot be made to merge from here). A release never changes a student-owned
//! file that DIR already has — a lab's `labs/labNN/src/**` and `labs/labNN/answers.md` — so
//! the pull merges with the students' own commits without conflicts.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use course::LabId;
use raylab_core::Error;

use super::{HandoutArgs, TreeOptions, build_tree, check_clean, copy_file, io, repository_root};
use crate::git::{git, git_text};

/// The subject of a handout repository's first commit starts with this; `--update` refuses a
/// directory whose history does not start with it.
const FIRST_COMMIT: &str = "raylab handout:";

/// Whether the handout file `path` (relative, `/`-separated) is the student's: the sources of
/// a lab crate (`labs/labNN/src/**`) and its written answers (`labs/labNN/answers.md`). A
/// release never changes one that the handout already has. `labs/raylab/src` is the command
/// line's, not a lab's.
pub fn is_student_owned(path: &str) -> bool {
    let mut parts = path.split('/');
    let (Some("labs"), Some(lab), Some(next)) = (parts.next(), parts.next(), parts.next()) else {
        return false;
    };
    let is_lab = lab.starts_with("lab") && lab.parse::<LabId>().is_ok();
    let rest: Vec<&str> = parts.collect();
    is_lab && ((next == "src" && !rest.is_empty()) || (next == "answers.md" && rest.is_empty()))
}

/// Makes the empty directory `dir` a git repository on branch `main`, before the handout is
/// written into it (so that a machine without git fails before writing anything).
pub fn init_repository(dir: &Path) -> Result<(), Error> {
    fs::create_dir_all(dir).map_err(io(dir))?;
    git(dir, &["init", "--quiet", "--initial-branch=main"])?;
    Ok(())
}

/// Commits the whole handout written into the repository `dir` as its first commit.
pub fn commit_handout(dir: &Path, released: &BTreeSet<LabId>) -> Result<(), Error> {
    git(dir, &["add", "--all"])?;
    let labs = crate::labs::labs();
    let span = match (labs.first(), labs.last()) {
        (Some(first), Some(last)) if first != last => {
            format!("labs {}–{}", first.number(), last.number())
        }
        (Some(only), _) => format!("lab {}", only.number()),
        _ => "no labs".to_string(),
    };
    let message = format!("{FIRST_COMMIT} {span}, {}", solutions_phrase(released));
    git(
        dir,
        &["commit", "--quiet", "--no-verify", "--message", &message],
    )?;
    Ok(())
}

/// "solutions of labs 1, 2" / "solutions of lab 1" / "no solutions released".
fn solutions_phrase(labs: &BTreeSet<LabId>) -> String {
    let numbers: Vec<String> = labs.iter().map(|l| l.number().to_string()).collect();
    match numbers.len() {
        0 => "no solutions released".to_string(),
        1 => format!("solutions of lab {}", numbers[0]),
        _ => format!("solutions of labs {}", numbers.join(", ")),
    }
}

/// The labs whose solution the handout tree `dir` holds (`reference/src/labNN.rs`).
fn released_in(dir: &Path) -> Result<BTreeSet<LabId>, Error> {
    let sources = dir.join("reference/src");
    let mut released = BTreeSet::new();
    for entry in fs::read_dir(&sources).map_err(io(&sources))? {
        let name = entry.map_err(io(&sources))?.file_name();
        let name = name.to_string_lossy();
        if let Some(lab) = name
            .strip_suffix(".rs")
            .filter(|stem| stem.starts_with("lab"))
            .and_then(|stem| stem.parse::<LabId>().ok())
        {
            released.insert(lab);
        }
    }
    Ok(released)
}

/// Refuses `dir` unless it is the top of a handout repository (its first commit is
/// `raylab handout`'s) with nothing uncommitted.
fn check_handout_repository(dir: &Path) -> Result<(), Error> {
    let refuse = |reason: String| Error::Invalid {
        what: format!("--update {}", dir.display()),
        reason,
    };
    if !dir.is_dir() {
        return Err(refuse(
            "expected a handout repository made by `raylab handout --out`; this is not a directory"
                .into(),
        ));
    }
    let top = git_text(dir, &["rev-parse", "--show-toplevel"])
        .map_err(|_| refuse("expected a handout repository made by `raylab handout --out`; this is not a git work tree".into()))?;
    let canonical = |p: &Path| fs::canonicalize(p).map_err(io(p));
    if canonical(Path::new(top.trim()))? != canonical(dir)? {
        return Err(refuse(format!(
            "expected the top of a handout repository; this is inside the repository {}",
            top.trim()
        )));
    }
    let roots = git_text(dir, &["rev-list", "--max-parents=0", "HEAD"]).unwrap_or_default();
    let first = roots.lines().next().unwrap_or("");
    let subject = if first.is_empty() {
        String::new()
    } else {
        git_text(dir, &["log", "-1", "--format=%s", first])?
    };
    if !subject.starts_with(FIRST_COMMIT) || !dir.join("reference/src").is_dir() {
        return Err(refuse(format!(
            "expected a handout repository made by `raylab handout --out`, whose first commit is \"{FIRST_COMMIT} …\""
        )));
    }
    let status = git_text(dir, &["status", "--porcelain=v1", "--untracked-files=all"])?;
    if !status.trim().is_empty() {
        let files: Vec<&str> = status.lines().map(|l| l.get(3..).unwrap_or(l)).collect();
        return Err(refuse(format!(
            "it has uncommitted changes ({}); commit or discard them first, so that a release is only the course's change",
            files.join(", ")
        )));
    }
    Ok(())
}

/// The regular files under `dir`, as `/`-separated paths relative to `base`.
fn files_of(base: &Path, dir: &Path, files: &mut BTreeSet<String>) -> Result<(), Error> {
    for entry in fs::read_dir(dir).map_err(io(dir))? {
        let path = entry.map_err(io(dir))?.path();
        if path.is_dir() {
            files_of(base, &path, files)?;
        } else if let Ok(relative) = path.strip_prefix(base) {
            let parts: Vec<String> = relative
                .components()
                .map(|c| c.as_os_str().to_string_lossy().into_owned())
                .collect();
            files.insert(parts.join("/"));
        }
    }
    Ok(())
}

/// Whether the files `a` and `b` differ (or one of them is missing).
fn differ(a: &Path, b: &Path) -> Result<bool, Error> {
    match (fs::metadata(a), fs::metadata(b)) {
        (Ok(ma), Ok(mb)) if ma.len() != mb.len() => Ok(true),
        (Ok(_), Ok(_)) => Ok(fs::read(a).map_err(io(a))? != fs::read(b).map_err(io(b))?),
        _ => Ok(true),
    }
}

/// What a release does to the handout repository.
#[derive(Debug, Default, PartialEq, Eq)]
struct Plan {
    /// Files the new tree has that the repository lacks or holds differently.
    write: Vec<String>,
    /// Files the repository tracks that the new tree no longer has (never student-owned).
    delete: Vec<String>,
    /// Student-owned files the repository has and the new tree changes.
    student_owned_changes: Vec<String>,
}

/// Compares the tracked files of the repository `dir` with the tree `new`.
fn plan(dir: &Path, tracked: &BTreeSet<String>, new: &Path) -> Result<Plan, Error> {
    let mut new_files = BTreeSet::new();
    files_of(new, new, &mut new_files)?;
    let mut plan = Plan::default();
    for file in &new_files {
        let present = tracked.contains(file);
        if present && !differ(&new.join(file), &dir.join(file))? {
            continue;
        }
        if present && is_student_owned(file) {
            plan.student_owned_changes.push(file.clone());
        }
        plan.write.push(file.clone());
    }
    plan.delete = tracked
        .iter()
        .filter(|f| !new_files.contains(*f) && !is_student_owned(f))
        .cloned()
        .collect();
    Ok(plan)
}

/// A scratch directory for the new tree, removed when dropped.
struct Scratch(PathBuf);

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = fs::remove_dir_all(&self.0);
    }
}

/// Runs `raylab handout --update DIR`.
pub fn update(args: &HandoutArgs, dir: &Path) -> Result<(), Error> {
    check_handout_repository(dir)?;
    let root = repository_root();
    check_clean(&root, args.allow_dirty)?;
    let before = released_in(dir)?;
    let mut released = before.clone();
    released.extend(args.release_solutions.iter().copied());
    let newly: BTreeSet<LabId> = released.difference(&before).copied().collect();

    let scratch =
        Scratch(std::env::temp_dir().join(format!("raylab-handout-update-{}", std::process::id())));
    let _ = fs::remove_dir_all(&scratch.0);
    let options = TreeOptions {
        released: released.clone(),
        ..TreeOptions::default()
    };
    build_tree(&root, &scratch.0, &options)?;

    let listing = git(dir, &["ls-files", "-z"])?;
    let tracked: BTreeSet<String> = String::from_utf8_lossy(&listing)
        .split('\0')
        .filter(|f| !f.is_empty())
        .map(str::to_string)
        .collect();
    let plan = plan(dir, &tracked, &scratch.0)?;
    if !plan.student_owned_changes.is_empty() {
        let files = plan.student_owned_changes.join(", ");
        if !args.force {
            return Err(Error::Invalid {
                what: format!("--update {}", dir.display()),
                reason: format!(
                    "the release would change files that students own and edit: {files}; students who changed them would get a merge conflict when they pull it. Leave them as they are in the course repository, or pass --force to release them anyway"
                ),
            });
        }
        eprintln!(
            "warning: --force: the release changes student-owned files ({files}); students who changed them will get a merge conflict when they pull it"
        );
    }
    let up_to_date = || {
        println!(
            "{}: nothing to release, the handout is already up to date ({}); no commit made",
            dir.display(),
            solutions_phrase(&released)
        );
    };
    if plan.write.is_empty() && plan.delete.is_empty() {
        up_to_date();
        return Ok(());
    }
    for file in &plan.write {
        copy_file(&scratch.0.join(file), &dir.join(file))?;
    }
    for file in &plan.delete {
        let path = dir.join(file);
        fs::remove_file(&path).map_err(io(&path))?;
        // Leave no empty folder behind (git does not track folders).
        let mut parent = path.parent();
        while let Some(folder) = parent.filter(|p| *p != dir) {
            if fs::remove_dir(folder).is_err() {
                break;
            }
            parent = folder.parent();
        }
    }
    git(dir, &["add", "--all"])?;
    // Files the handout's `.gitignore` leaves out (a `*.snap.new` of the course repository's
    // work tree) are no release.
    if git(dir, &["status", "--porcelain=v1"])?.is_empty() {
        up_to_date();
        return Ok(());
    }
    let message = if newly.is_empty() {
        "release: the course's changes to the handout".to_string()
    } else {
        format!("release: {}", solutions_phrase(&newly))
    };
    let details = format!(
        "{} file(s) written, {} deleted; {} in the handout.",
        plan.write.len(),
        plan.delete.len(),
        solutions_phrase(&released)
    );
    git(
        dir,
        &[
            "commit",
            "--quiet",
            "--no-verify",
            "--message",
            &message,
            "--message",
            &details,
        ],
    )?;
    let head = git_text(dir, &["rev-parse", "--short", "HEAD"])?;
    println!(
        "{}: committed {} \"{message}\" ({details}) Publish it (git push) and students run `git pull --no-rebase` (a plain `git pull` stops at \"Need to specify how to reconcile divergent branches\" for a student who has committed).",
        dir.display(),
        head.trim()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn student_owned_files_are_the_labs_sources_and_answers() {
        for owned in [
            "labs/lab01/src/lib.rs",
            "labs/lab12/src/helpers/mod.rs",
            "labs/lab03/answers.md",
        ] {
            assert!(is_student_owned(owned), "{owned}");
        }
        for not_owned in [
            "labs/raylab/src/main.rs",
            "labs/lab01/checks/src/lib.rs",
            "labs/lab01/tests/checks.rs",
            "labs/lab01/src",
            "labs/lab01/answers.md/x",
            "labs/course.toml",
            "reference/src/lab01.rs",
            "README.md",
        ] {
            assert!(!is_student_owned(not_owned), "{not_owned}");
        }
    }

    #[test]
    fn a_plan_keeps_student_files_and_names_the_ones_a_release_would_change() {
        let base = std::env::temp_dir().join(format!("raylab-plan-{}", std::process::id()));
        let _ = fs::remove_dir_all(&base);
        let (dir, new) = (base.join("repo"), base.join("new"));
        let put = |root: &Path, file: &str, text: &str| {
            let path = root.join(file);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(path, text).unwrap();
        };
        put(&dir, "README.md", "old");
        put(&dir, "docs/gone.md", "old");
        put(&dir, "labs/lab01/src/lib.rs", "stub");
        put(&dir, "labs/lab01/src/old.rs", "student's");
        put(&dir, "labs/lab02/src/lib.rs", "stub");
        put(&new, "README.md", "new");
        put(&new, "labs/lab01/src/lib.rs", "stub");
        put(&new, "labs/lab02/src/lib.rs", "changed stub");
        put(&new, "reference/src/lab01.rs", "solution");
        let mut tracked = BTreeSet::new();
        files_of(&dir, &dir, &mut tracked).unwrap();
        assert_eq!(
            plan(&dir, &tracked, &new).unwrap(),
            Plan {
                write: vec![
                    "README.md".into(),
                    "labs/lab02/src/lib.rs".into(),
                    "reference/src/lab01.rs".into()
                ],
                delete: vec!["docs/gone.md".into()],
                student_owned_changes: vec!["labs/lab02/src/lib.rs".into()],
            }
        );
        let _ = fs::remove_dir_all(&base);
    }
}
