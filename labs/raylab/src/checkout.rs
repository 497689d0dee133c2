//! Which course tree a command acts on. A student's command (`status`, `report`, `render`,
//! `watch`, `view`, `reset`) acts on the tree the current directory is in — the handout or clone
//! the student works in — even when this program was built in another one (a target directory
//! shared between clones). An instructor's command (`golden`, `handout`, `grade`, `new-lab`,
//! `gradescope`, `similarity`) carries the course it was built from (its registry, its answer
//! key), so it acts on that tree, and refuses to run in another one rather than surprise.

use std::path::{Path, PathBuf};

#[cfg(feature = "instructor")]
use raylab_core::Error;

/// The tree this program was built from: two levels above this crate's directory, without `..`
/// in it, so that the paths messages show are the ones to type.
pub fn built_tree() -> PathBuf {
    let manifest_dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    manifest_dir
        .ancestors()
        .nth(2)
        .map_or_else(|| manifest_dir.join("../.."), Path::to_path_buf)
}

/// The course tree that holds `dir`: its nearest ancestor (itself included) with a
/// `Cargo.toml` and the course registry `labs/course.toml`.
pub fn tree_holding(dir: &Path) -> Option<PathBuf> {
    dir.ancestors()
        .find(|d| d.join("Cargo.toml").is_file() && d.join("labs/course.toml").is_file())
        .map(Path::to_path_buf)
}

/// The tree a student's command acts on: the one the current directory is in, else the one this
/// program was built from.
pub fn workspace_root() -> PathBuf {
    std::env::current_dir()
        .ok()
        .and_then(|dir| tree_holding(&dir))
        .unwrap_or_else(built_tree)
}

#[cfg(feature = "instructor")]
/// The repository an instructor's command acts on: the one this program was built from; an
/// error naming both when the current directory is in another course tree.
pub fn instructor_tree() -> Result<PathBuf, Error> {
    let built = built_tree();
    let Some(here) = std::env::current_dir()
        .ok()
        .and_then(|dir| tree_holding(&dir))
    else {
        return Ok(built);
    };
    let same = |a: &Path, b: &Path| match (a.canonicalize(), b.canonicalize()) {
        (Ok(a), Ok(b)) => a == b,
        _ => a == b,
    };
    if same(&here, &built) {
        Ok(built)
    } else {
        Err(Error::Invalid {
            what: format!("the course tree {}", here.display()),
            reason: format!(
                "this raylab was built from {} and acts on that repository: run `cargo run -p raylab -- …` in {} to act on it",
                built.display(),
                here.display()
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tree_is_found_from_any_directory_inside_it() {
        let tree = std::env::temp_dir().join(format!("raylab-checkout-{}", std::process::id()));
        let inner = tree.join("labs/lab01/src");
        std::fs::create_dir_all(&inner).unwrap();
        std::fs::write(tree.join("Cargo.toml"), "").unwrap();
        assert_eq!(tree_holding(&inner), None, "no registry yet");
        std::fs::write(tree.join("labs/course.toml"), "").unwrap();
        assert_eq!(tree_holding(&inner).as_deref(), Some(tree.as_path()));
        assert_eq!(tree_holding(&tree).as_deref(), Some(tree.as_path()));
        // A crate's own Cargo.toml below the tree is not the tree.
        std::fs::write(tree.join("labs/lab01/Cargo.toml"), "").unwrap();
        assert_eq!(tree_holding(&inner).as_deref(), Some(tree.as_path()));
        std::fs::remove_dir_all(&tree).unwrap();
    }

    #[test]
    fn this_repository_is_the_tree_it_was_built_from() {
        let built = built_tree();
        assert_eq!(tree_holding(&built.join("labs/raylab/src")), Some(built));
    }
}
