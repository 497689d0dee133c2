//! What is taken from a submission (`labs/labNN/src/**`), and what else it changed.

use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use framework::Error;

use crate::handout::{copy_file, io};

/// Directories never compared or copied: build output and version control.
const SKIPPED: &[&str] = &[".git", "target", "out"];

/// Files a build rewrites on its own, left out of the comparison.
const REGENERATED: &[&str] = &["Cargo.lock"];

/// The relative paths of the files under `dir`, leaving out [`SKIPPED`] directories.
fn files(dir: &Path) -> Result<BTreeSet<PathBuf>, Error> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeSet<PathBuf>) -> Result<(), Error> {
        for entry in fs::read_dir(dir).map_err(io(dir))? {
            let entry = entry.map_err(io(dir))?;
            let path = entry.path();
            if SKIPPED.iter().any(|s| entry.file_name() == *s) {
                continue;
            }
            if path.is_dir() {
                walk(root, &path, out)?;
            } else if let Ok(relative) = path.strip_prefix(root) {
                out.insert(relative.to_path_buf());
            }
        }
        Ok(())
    }
    let mut out = BTreeSet::new();
    walk(dir, dir, &mut out)?;
    Ok(out)
}

/// Whether `path` (relative to the tree) is graded code: `labs/labNN/src/**`.
fn is_student_code(path: &Path) -> bool {
    let parts: Vec<_> = path.components().map(|c| c.as_os_str()).collect();
    parts.len() >= 4
        && parts[0] == "labs"
        && parts[1].to_string_lossy().starts_with("lab")
        && parts[1] != "raylab"
        && parts[2] == "src"
}

/// The files outside `labs/labNN/src/` in which `submission` differs from `handout`, as
/// `modified: …`, `added: …` and `removed: …` lines. They take no part in grading.
pub fn changed_files(submission: &Path, handout: &Path) -> Result<Vec<String>, Error> {
    let theirs = files(submission)?;
    let ours = files(handout)?;
    let ignored = |p: &Path| is_student_code(p) || REGENERATED.iter().any(|r| p == Path::new(r));
    let mut changes = Vec::new();
    for path in theirs.iter().filter(|p| !ignored(p)) {
        if !ours.contains(path) {
            changes.push(format!("added: {}", path.display()));
        } else {
            let a = fs::read(submission.join(path)).map_err(io(&submission.join(path)))?;
            let b = fs::read(handout.join(path)).map_err(io(&handout.join(path)))?;
            if a != b {
                changes.push(format!("modified: {}", path.display()));
            }
        }
    }
    for path in ours.iter().filter(|p| !ignored(p) && !theirs.contains(*p)) {
        changes.push(format!("removed: {}", path.display()));
    }
    Ok(changes)
}

/// Puts lab `lab`'s code into the grading tree: the submission's `labs/labNN/src/` if it has
/// one, otherwise (or for `None`) the handout's stubs. Returns a note when a submission's code
/// was missing.
pub struct LabIntake {
    pub missing: Option<String>,
    pub rejected: Vec<String>,
}
pub fn install_lab_code(
    submission: Option<&Path>,
    handout: &Path,
    tree: &Path,
    lab: u32,
) -> Result<LabIntake, Error> {
    let src = format!("labs/lab{lab:02}/src");
    let target = tree.join(&src);
    if target.exists() {
        fs::remove_dir_all(&target).map_err(io(&target))?;
    }
    let (from, note) = match submission.map(|s| s.join(&src)) {
        Some(theirs) if theirs.is_dir() => (theirs, None),
        Some(_) => (
            handout.join(&src),
            Some(format!("{src}/ is missing: graded as the handout's stubs")),
        ),
        None => (handout.join(&src), None),
    };
    for file in files(&from)? {
        copy_file(&from.join(&file), &target.join(&file))?;
    }
    Ok(LabIntake {
        missing: note,
        rejected: Vec::new(),
    })
}

/// Replaces lab `lab`'s code in the grading tree by the handout's stubs.
pub fn install_stubs(handout: &Path, tree: &Path, lab: u32) -> Result<(), Error> {
    install_lab_code(None, handout, tree, lab).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_lab_sources_are_student_code() {
        assert!(is_student_code(Path::new("labs/lab01/src/lib.rs")));
        assert!(is_student_code(Path::new("labs/lab07/src/extra/mod.rs")));
        assert!(!is_student_code(Path::new("labs/lab01/tests/checks.rs")));
        assert!(!is_student_code(Path::new(
            "labs/lab01/golden/camera_basis.json"
        )));
        assert!(!is_student_code(Path::new("labs/raylab/src/main.rs")));
        assert!(!is_student_code(Path::new("framework/src/lib.rs")));
        assert!(!is_student_code(Path::new("labs/lab01/Cargo.toml")));
    }
}
