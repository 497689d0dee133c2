//! Which course tree a command acts on: the one that holds the current directory — the
//! repository, a handout or a clone — found from there upwards as cargo and git find their
//! roots (a directory with `Cargo.toml` and the registry `labs/course.toml`), whichever tree
//! this program was built in (one target directory may serve several clones). Outside every
//! course tree, the one it was built from, and the command says so when it first reads it. A tree whose registry
//! lists other labs than the one compiled into this program is refused, naming both: the
//! command would not know its labs.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

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

/// The tree commands act on, once [`resolve`] has found it, and whether the current directory
/// is in it (`false`: in no course tree, so it is the tree this program was built from).
static ROOT: OnceLock<(PathBuf, bool)> = OnceLock::new();

/// Finds the tree this run acts on (see the module's documentation), once, before a command
/// runs; an error when the current directory is in a course tree of another registry.
pub fn resolve() -> Result<&'static Path, Error> {
    if let Some((root, _)) = ROOT.get() {
        return Ok(root);
    }
    let root = match current_tree() {
        Some(tree) => {
            check_registry(&tree)?;
            (tree, true)
        }
        None => (built_tree(), false),
    };
    Ok(&ROOT.get_or_init(|| root).0)
}

/// The course tree holding the current directory, if any.
fn current_tree() -> Option<PathBuf> {
    tree_holding(&std::env::current_dir().ok()?)
}

/// What a command says when it runs outside every course tree (from `cwd`) and acts on `built`.
fn outside_note(cwd: Option<&Path>, built: &Path) -> String {
    let here = cwd.map_or_else(
        || "the current directory".to_string(),
        |d| d.display().to_string(),
    );
    format!(
        "note: {here} is in no course tree (no Cargo.toml with labs/course.toml there or above): acting on {}, the tree this raylab was built from",
        built.display()
    )
}

/// The tree commands act on: [`resolve`]'s, or the one this program was built from when a
/// test calls a command's code directly.
pub fn workspace_root() -> PathBuf {
    let root = resolve().map_or_else(|_| built_tree(), Path::to_path_buf);
    if ROOT.get().is_some_and(|(_, found)| !found) {
        static SAID: std::sync::Once = std::sync::Once::new();
        SAID.call_once(|| {
            let cwd = std::env::current_dir().ok();
            eprintln!("{}", outside_note(cwd.as_deref(), &root));
        });
    }
    root
}

/// An error when `tree`'s registry lists other labs (numbers or titles) than the one this
/// program was compiled with.
fn check_registry(tree: &Path) -> Result<(), Error> {
    let file = tree.join("labs/course.toml");
    let text = std::fs::read_to_string(&file).map_err(|e| Error::io(&file, e))?;
    let theirs: Option<Vec<(u8, String)>> = course::parse_registry(&text)
        .ok()
        .map(|entries| entries.into_iter().map(|e| (e.number, e.title)).collect());
    let ours: Vec<(u8, String)> = course::labs()
        .into_iter()
        .map(|lab| {
            (
                lab.number() as u8,
                course::title(lab).unwrap_or("").to_string(),
            )
        })
        .collect();
    if theirs.as_ref() == Some(&ours) {
        return Ok(());
    }
    Err(Error::Invalid {
        what: format!("the course tree {}", tree.display()),
        reason: format!(
            "its labs/course.toml lists other labs than this raylab knows, which was built from {}: run `cargo run -p raylab -- …` in {} to build it there",
            built_tree().display(),
            tree.display()
        ),
    })
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
    fn this_repository_is_the_tree_it_was_built_from_and_its_registry_is_known() {
        let built = built_tree();
        assert_eq!(
            tree_holding(&built.join("labs/raylab/src")),
            Some(built.clone())
        );
        check_registry(&built).unwrap();
    }

    #[test]
    fn a_tree_of_another_registry_is_refused_naming_it() {
        let tree = std::env::temp_dir().join(format!("raylab-registry-{}", std::process::id()));
        std::fs::create_dir_all(tree.join("labs")).unwrap();
        let ours = std::fs::read_to_string(built_tree().join("labs/course.toml")).unwrap();
        for (what, text) in [
            ("a lab more", format!("{ours}lab99 = \"Elsewhere\"\n")),
            (
                "a title changed",
                ours.replacen("lab01 = \"", "lab01 = \"Not ", 1),
            ),
            ("none", "[labs]\n".to_string()),
        ] {
            std::fs::write(tree.join("labs/course.toml"), text).unwrap();
            let error = check_registry(&tree).expect_err(what).to_string();
            assert!(error.contains(&*tree.to_string_lossy()), "{what}: {error}");
        }
        std::fs::write(tree.join("labs/course.toml"), ours).unwrap();
        check_registry(&tree).unwrap();
        std::fs::remove_dir_all(&tree).unwrap();
    }
}
