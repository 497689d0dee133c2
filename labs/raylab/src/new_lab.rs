//! `raylab new-lab NN --title "…"`: a new lab's places, written as a skeleton that compiles and
//! is checked from the start, and its one line in the registry `labs/course.toml`.
//!
//! The skeleton has one exercise, N.1 (the luminance of a colour), with everything a lab has:
//! the contract `framework/contracts/src/labNN.rs`, the student crate `labs/labNN` (stub,
//! exercise table, program, mutant corpus) with its checks crate `labs/labNN/checks` (the
//! check, a golden generator, a report figure), the answer key `reference/src/labNN.rs` and the
//! docs page `docs/labNN.md`; the lab's program then writes its golden data with the key. Right
//! after it `cargo test -p labNN` fails N.1 as not implemented
//! and `cargo test -p labNN --features reference` passes. Nothing else is edited: what lists the
//! labs reads the registry. The README's table of labs gets the lab's row.

use std::fs;
use std::path::{Path, PathBuf};

use clap::Args;
use course::LabId;
use raylab_core::Error;

/// Options of `raylab new-lab`.
#[derive(Args, Debug)]
pub struct NewLabArgs {
    /// The new lab's number, after the course's last lab (`12`).
    pub number: u32,
    /// Its title, as the registry and the docs page show it ("Path tracing").
    #[arg(long)]
    pub title: String,
    /// The name of its contract trait (default: made from the title, `PathTracing`).
    #[arg(long)]
    pub contract: Option<String>,
    /// The repository to add it to (default: the one the current directory is in).
    #[arg(long)]
    pub root: Option<PathBuf>,
}

/// Runs `raylab new-lab`.
pub fn run(args: &NewLabArgs) -> Result<(), Error> {
    let root = args
        .root
        .clone()
        .unwrap_or_else(crate::handout::repository_root);
    let lab = new_lab(&root, args)?;
    eprintln!("{lab}: writing its golden data with the answer key");
    crate::golden::generate(&root, &root, lab)?;
    println!(
        "{lab}: wrote its skeleton and its line in labs/course.toml. Next:\n\
         \x20 cargo test -p {lab}                      # Exercise {n}.1 fails: not implemented yet\n\
         \x20 cargo test -p {lab} --features reference # the answer key passes\n\
         Then write the lab: its contract, stubs, exercise table, checks, key, corpus and docs page.",
        n = lab.number()
    );
    Ok(())
}

/// Writes lab `args.number`'s skeleton into the repository at `root`; refuses a number the
/// course has or a lab whose places exist, before writing anything.
pub fn new_lab(root: &Path, args: &NewLabArgs) -> Result<LabId, Error> {
    let invalid = |what: String, reason: String| Error::Invalid { what, reason };
    let lab = LabId::new(args.number).ok_or_else(|| {
        invalid(
            format!("lab {}", args.number),
            "expected a lab number from 1 to 99".into(),
        )
    })?;
    let title = args.title.trim();
    if title.is_empty() || title.contains(['"', '\\', '\n']) {
        return Err(invalid(
            format!("--title {:?}", args.title),
            "expected a title without quotes, backslashes or line breaks".into(),
        ));
    }
    let contract = match &args.contract {
        Some(name) => name.clone(),
        None => contract_name(title),
    };
    if !is_type_name(&contract) {
        return Err(invalid(
            format!("--contract {contract:?}"),
            "expected a Rust type name in CamelCase (`PathTracing`)".into(),
        ));
    }
    let registry_path = root.join("labs/course.toml");
    let registry = read(&registry_path)?;
    let entries = course::parse_registry(&registry)
        .map_err(|e| invalid(format!("{}", registry_path.display()), format!("line {e}")))?;
    if let Some(last) = entries.last()
        && u32::from(last.number) >= lab.number()
    {
        return Err(invalid(
            format!("lab {}", lab.number()),
            format!(
                "the course's last lab is lab{:02}: a new lab comes after it",
                last.number
            ),
        ));
    }
    let skeleton = Skeleton {
        lab,
        n: lab.number(),
        title: title.to_string(),
        contract,
    };
    let files = skeleton.files();
    for (path, _) in &files {
        let path = root.join(path);
        if path.exists() {
            return Err(invalid(
                format!("{}", path.display()),
                "exists already: the new lab's places must be free".into(),
            ));
        }
    }
    let readme_path = root.join("README.md");
    let readme = read(&readme_path)?;
    let readme = skeleton.readme_with_row(&readme, &entries).ok_or_else(|| {
        invalid(
            format!("{}", readme_path.display()),
            "has no row of the course's last lab in its table of labs".into(),
        )
    })?;
    for (path, text) in &files {
        write(&root.join(path), text)?;
    }
    format_rust(root, &files);
    let mut registry = registry;
    if !registry.ends_with('\n') {
        registry.push('\n');
    }
    registry.push_str(&format!("{lab} = \"{title}\"\n"));
    write(&registry_path, &registry)?;
    write(&readme_path, &readme)?;
    Ok(lab)
}

/// Formats the skeleton's Rust files as `cargo fmt` would (their line breaks depend on the lab's
/// number and names); without rustfmt they stay as written, and compile all the same.
fn format_rust(root: &Path, files: &[(String, String)]) {
    let sources: Vec<PathBuf> = files
        .iter()
        .filter(|(path, _)| path.ends_with(".rs"))
        .map(|(path, _)| root.join(path))
        .collect();
    let formatted = std::process::Command::new("rustfmt")
        .args(["--edition", "2024"])
        .args(&sources)
        .status();
    if !formatted.is_ok_and(|s| s.success()) {
        eprintln!("note: rustfmt did not run: run `cargo fmt` before committing the new lab");
    }
}

/// `PathTracing` from "Path tracing": the title's words, capitalised, letters and digits only.
fn contract_name(title: &str) -> String {
    let name: String = title
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .map(|w| {
            let mut chars = w.chars();
            let first = chars.next().map(|c| c.to_ascii_uppercase());
            first.into_iter().chain(chars).collect::<String>()
        })
        .collect();
    if name.starts_with(|c: char| c.is_ascii_alphabetic()) {
        name
    } else {
        format!("Lab{name}")
    }
}

/// Whether `name` is a plain Rust type name.
fn is_type_name(name: &str) -> bool {
    name.starts_with(|c: char| c.is_ascii_uppercase())
        && name.chars().all(|c| c.is_ascii_alphanumeric())
        && !["Contract", "Student", "Variant"].contains(&name)
}

fn read(path: &Path) -> Result<String, Error> {
    fs::read_to_string(path).map_err(|e| Error::io(path, e))
}

fn write(path: &Path, text: &str) -> Result<(), Error> {
    if let Some(parent) = path.parent() {
        fs::create_dir_all(parent).map_err(|e| Error::io(parent, e))?;
    }
    fs::write(path, text).map_err(|e| Error::io(path, e))
}

/// Each place of a new lab (its path in the repository) and its text, both templates of
/// [`Skeleton::fill`].
const TEMPLATES: &[(&str, &str)] = &[
    (
        "framework/contracts/src/@lab@.rs",
        include_str!("new_lab/contract.rs.txt"),
    ),
    (
        "labs/@lab@/Cargo.toml",
        include_str!("new_lab/Cargo.toml.txt"),
    ),
    (
        "labs/@lab@/exercises.toml",
        include_str!("new_lab/exercises.toml.txt"),
    ),
    ("labs/@lab@/src/lib.rs", include_str!("new_lab/stub.rs.txt")),
    (
        "labs/@lab@/tests/checks.rs",
        include_str!("new_lab/program.rs.txt"),
    ),
    (
        "labs/@lab@/tests/corpus.rs",
        include_str!("new_lab/corpus.rs.txt"),
    ),
    (
        "labs/@lab@/checks/Cargo.toml",
        include_str!("new_lab/checks.Cargo.toml.txt"),
    ),
    (
        "labs/@lab@/checks/src/lib.rs",
        include_str!("new_lab/checks_lib.rs.txt"),
    ),
    (
        "labs/@lab@/checks/src/checks.rs",
        include_str!("new_lab/checks.rs.txt"),
    ),
    (
        "labs/@lab@/checks/src/report.rs",
        include_str!("new_lab/report.rs.txt"),
    ),
    ("reference/src/@lab@.rs", include_str!("new_lab/key.rs.txt")),
    ("docs/@lab@.md", include_str!("new_lab/docs.md.txt")),
];

/// The text of a new lab's places.
struct Skeleton {
    lab: LabId,
    n: u32,
    title: String,
    contract: String,
}

impl Skeleton {
    /// Each file of the skeleton: its path in the repository and its text (the answers file made
    /// from the docs page's questions).
    fn files(&self) -> Vec<(String, String)> {
        let mut files: Vec<(String, String)> = TEMPLATES
            .iter()
            .map(|(path, text)| (self.fill(path), self.fill(text)))
            .collect();
        // The answers file of the docs page's questions.
        let questions = files
            .iter()
            .find(|(path, _)| *path == self.lab.docs())
            .map(|(_, docs)| course::answers::questions(docs))
            .unwrap_or_default();
        if !questions.is_empty() {
            let answers = course::answers::template(self.lab, &self.title, &questions);
            files.push((self.lab.answers(), answers));
        }
        files
    }

    /// Fills the template `text`: `@lab@` (`lab12`), `@n@` (`12`), `@NN@` (`12` with two
    /// digits), `@title@`, `@Contract@`.
    fn fill(&self, text: &str) -> String {
        text.replace("@lab@", &self.lab.to_string())
            .replace("@NN@", &format!("{:02}", self.n))
            .replace("@n@", &self.n.to_string())
            .replace("@title@", &self.title)
            .replace("@Contract@", &self.contract)
    }

    /// `readme` with the new lab's row after the last lab's, in its table of labs.
    fn readme_with_row(&self, readme: &str, entries: &[course::RegistryEntry]) -> Option<String> {
        let last = entries.last()?;
        let last_row = format!("| lab{:02} |", last.number);
        let at = readme.find(&last_row)?;
        let end = at + readme[at..].find('\n')? + 1;
        let row = self.fill(&format!(
            "| @lab@ | {} | [docs/@lab@.md](docs/@lab@.md) |\n",
            self.title.to_lowercase()
        ));
        Some(format!("{}{row}{}", &readme[..end], &readme[end..]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn contract_names_come_from_titles() {
        assert_eq!(contract_name("Path tracing"), "PathTracing");
        assert_eq!(contract_name("Participating media"), "ParticipatingMedia");
        assert_eq!(contract_name("3D textures"), "Lab3DTextures");
        assert!(is_type_name("PathTracing"));
        assert!(!is_type_name("path_tracing"));
        assert!(!is_type_name("Contract"));
    }
}
