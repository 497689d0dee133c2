//! Helpers of the end-to-end tests of the instructor's workflow (`handout`, `grade`): where the
//! repository and its target directory are, and submissions made from a handout.

use std::fs;
use std::path::{Path, PathBuf};

/// The repository's root.
pub fn root() -> PathBuf {
    fs::canonicalize(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
        .expect("the repository exists")
}

/// Cargo's target directory of this test run.
pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"))
}

/// The text of `path`; panics naming it.
pub fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The reference solution of lab `lab` as a student would hand it in: the answer key's code
/// with its type renamed to `Student` (lab 07 computes its own strata instead of calling lab 03).
pub fn correct_code(lab: u32) -> String {
    let code = read(&root().join(format!("reference/src/lab{lab:02}.rs")))
        .replace(&format!("Lab{lab:02}"), "Student");
    if lab != 7 {
        return code;
    }
    code.replace(
        "crate::lab03::Lab03.stratified_samples(subdivisions, rng)",
        "let n = subdivisions;\n        (0..n * n)\n            .map(|k| (Vec2::new((k % n) as f32, (k / n) as f32) + rng.next_vec2()) / n as f32)\n            .collect()",
    )
    .replace("use framework::contracts::lab03::Shadows;\n", "")
}

/// Copies the directory `from` to `to`, leaving out `target/`.
pub fn copy_tree(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_name() == "target" {
            continue;
        }
        if entry.path().is_dir() {
            copy_tree(&entry.path(), &to.join(entry.file_name()));
        } else {
            fs::copy(entry.path(), to.join(entry.file_name())).unwrap();
        }
    }
}
