//! The grading tree's fingerprint: a SHA-256 hash of every file but the student's lab sources,
//! taken when the tree is built and compared after each submission, so that a tree changed by
//! one submission never grades the next.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};

use raylab_core::Error;
use sha2::{Digest, Sha256};

use super::submission::is_lab_sources;
use crate::handout::io;

/// What each file of a tree holds (links by their target), leaving out `labs/labNN/src/`.
pub struct Manifest(BTreeMap<PathBuf, [u8; 32]>);

impl Manifest {
    /// The manifest of the tree at `tree`.
    pub fn of(tree: &Path) -> Result<Self, Error> {
        let mut files = BTreeMap::new();
        walk(tree, tree, &mut files)?;
        Ok(Self(files))
    }

    /// One hash of the whole manifest (every path with its file's hash), as 16 hex digits: two
    /// trees of the same files have the same digest.
    pub fn digest(&self) -> String {
        let mut all = Sha256::new();
        for (path, hash) in &self.0 {
            all.update(path.to_string_lossy().as_bytes());
            all.update([0]);
            all.update(hash);
        }
        all.finalize()[..8]
            .iter()
            .map(|b| format!("{b:02x}"))
            .collect()
    }

    /// The files in which `tree` differs from this manifest: `changed: P`, `added: P`,
    /// `removed: P`.
    pub fn changes(&self, tree: &Path) -> Result<Vec<String>, Error> {
        let now = Self::of(tree)?;
        let mut changes = Vec::new();
        for (path, hash) in &now.0 {
            match self.0.get(path) {
                None => changes.push(format!("added: {}", path.display())),
                Some(h) if h != hash => changes.push(format!("changed: {}", path.display())),
                Some(_) => {}
            }
        }
        for path in self.0.keys().filter(|p| !now.0.contains_key(*p)) {
            changes.push(format!("removed: {}", path.display()));
        }
        Ok(changes)
    }
}

fn walk(root: &Path, dir: &Path, files: &mut BTreeMap<PathBuf, [u8; 32]>) -> Result<(), Error> {
    for entry in fs::read_dir(dir).map_err(io(dir))? {
        let entry = entry.map_err(io(dir))?;
        let path = entry.path();
        let relative = path.strip_prefix(root).unwrap_or(&path).to_path_buf();
        let kind = entry.file_type().map_err(io(&path))?;
        let hash = if kind.is_dir() {
            if !is_lab_sources(&relative) {
                walk(root, &path, files)?;
            }
            continue;
        } else if kind.is_file() {
            Sha256::digest(fs::read(&path).map_err(io(&path))?)
        } else if kind.is_symlink() {
            let target = fs::read_link(&path).map_err(io(&path))?;
            Sha256::digest(format!("link to {}", target.display()))
        } else {
            Sha256::digest("a special file")
        };
        files.insert(relative, hash.into());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn changes_outside_the_lab_sources_are_found() {
        let tree = std::env::temp_dir().join(format!("raylab-manifest-{}", std::process::id()));
        let _ = fs::remove_dir_all(&tree);
        fs::create_dir_all(tree.join("labs/lab02/src")).unwrap();
        fs::create_dir_all(tree.join("labs/lab02/tests")).unwrap();
        fs::write(tree.join("labs/lab02/src/lib.rs"), "a").unwrap();
        fs::write(tree.join("labs/lab02/tests/checks.rs"), "b").unwrap();
        let manifest = Manifest::of(&tree).unwrap();
        fs::write(tree.join("labs/lab02/src/lib.rs"), "student code").unwrap();
        assert!(manifest.changes(&tree).unwrap().is_empty());
        fs::write(tree.join("labs/lab02/tests/checks.rs"), "c").unwrap();
        fs::write(tree.join("extra"), "").unwrap();
        assert_eq!(
            manifest.changes(&tree).unwrap(),
            ["added: extra", "changed: labs/lab02/tests/checks.rs"]
        );
        fs::remove_dir_all(&tree).unwrap();
    }

    #[test]
    fn the_digest_follows_the_files_and_not_where_they_are() {
        let dir = std::env::temp_dir().join(format!("raylab-digest-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        for tree in ["a", "b"] {
            fs::create_dir_all(dir.join(tree).join("src")).unwrap();
            fs::write(dir.join(tree).join("src/lib.rs"), "fn f() {}").unwrap();
        }
        let digest = |tree: &str| Manifest::of(&dir.join(tree)).unwrap().digest();
        assert_eq!(digest("a"), digest("b"));
        assert_eq!(digest("a").len(), 16);
        fs::write(dir.join("b/src/lib.rs"), "fn g() {}").unwrap();
        assert_ne!(digest("a"), digest("b"));
        fs::rename(dir.join("a/src/lib.rs"), dir.join("a/src/main.rs")).unwrap();
        fs::write(dir.join("b/src/lib.rs"), "fn f() {}").unwrap();
        assert_ne!(digest("a"), digest("b"), "a file's path counts too");
        fs::remove_dir_all(&dir).unwrap();
    }
}
