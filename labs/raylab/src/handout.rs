//! `raylab handout`: the student tree — framework, lab stubs, their checks, golden data and
//! snapshots, and the solutions of the released labs only. `raylab grade` builds its grading
//! tree the same way, with the whole answer key (`TreeOptions::answer_key`).
//!
//! The tree is this repository with three changes (hidden exercises need none: their tests
//! exist only with a lab crate's `hidden-exercises` feature, which grading turns on):
//! - `reference/` holds only the released labs' solutions; its `pipeline()` — the base every
//!   check runs an exercise in — takes a released lab's solution and the student's own code for
//!   the labs not released;
//! - a lab whose solution is not released has nothing for its `reference` feature to switch
//!   to: its program says so and stops;
//! - the instructor's parts stay behind: `tests/` (and its package in `Cargo.lock`, which is
//!   written as cargo resolves the handout's workspace: the first build in a clone changes
//!   nothing), each lab's tests but its program
//!   (`labs/labNN/tests/checks.rs`; the mutant corpus holds solutions), the command line's
//!   tests (`labs/raylab/tests/`: the similarity test's class holds lab 2 solutions), `.ci/`,
//!   and the `instructor` feature of the command line (`golden`, `handout`, `grade`).
//!
//! The handout is a git repository, and releases are its commits (`release`): students clone
//! it and `git pull --no-rebase` each release. Every release holds every lab's crate — the labs are
//! listed in `labs/course.toml`, which the `course` crate embeds and checks against the lab
//! folders, and the contracts, the pipeline's slots and the `reference` crate are made per lab
//! of that list — and differs from the last in the solutions released and the course's fixes.

use course::LabId;
use std::collections::BTreeSet;
use std::fs;
use std::path::{Path, PathBuf};

use clap::Args;
use raylab_core::Error;

mod release;

/// Options of `raylab handout`.
#[derive(Args, Debug)]
#[command(group(clap::ArgGroup::new("handout_dir").required(true).args(["out", "update"])))]
pub struct HandoutArgs {
    /// Directory to write the handout to (must not exist, or be empty): a git repository on
    /// branch `main` with one commit, to publish for students to clone.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Release into the handout repository DIR (made by `--out`): build the handout again and
    /// commit the difference, for students to `git pull --no-rebase`. Solutions released before stay
    /// released. Files students own (`labs/labNN/src/**`, `labs/labNN/answers.md`) that DIR
    /// already has are never changed.
    #[arg(long, value_name = "DIR")]
    pub update: Option<PathBuf>,
    /// Labs whose reference solution goes into the handout, e.g. `--release-solutions 1,2`
    /// (default: none; with `--update`, the ones to release in addition to those out already).
    #[arg(long, value_delimiter = ',')]
    pub release_solutions: Vec<LabId>,
    /// With `--update`: release even though it changes files students own (a stub fixed in the
    /// course repository); students who changed such a file get a merge conflict when they pull it.
    #[arg(long, conflicts_with = "out")]
    pub force: bool,
    /// Build the handout even though files that go into it differ from the last commit (they
    /// are named on stderr). Without it such a tree is refused: a handout should be a commit.
    #[arg(long)]
    pub allow_dirty: bool,
}

/// What goes into a tree built from the repository.
#[derive(Clone, Debug, Default)]
pub struct TreeOptions {
    /// Labs whose solution is in the tree.
    pub released: BTreeSet<LabId>,
    /// The whole answer key instead (the grading tree): `reference/` as in the repository, and
    /// every lab's checks run on the student's code with the key in every other slot. Its
    /// sources are kept out of sight while student code compiles (`grade::sandbox`).
    pub answer_key: bool,
    /// A pre-release tag for the tree's own crates (`0.1.0-TAG`), so that their builds never
    /// share artifacts with another tree's in one target directory: cargo names a path crate's
    /// artifacts by its place in the workspace and its version, so two trees of the same layout
    /// and version would share them, and one tree's file dates could make the other's changed
    /// code look up to date.
    pub version_tag: Option<String>,
    /// A tag for the framework alone (`0.1.0-TAG`), made from its content (the grader takes
    /// the digest of its files' manifest): trees whose framework is the same share its build in
    /// a target directory, where their own crates (the student's code among them) share nothing.
    pub framework_tag: Option<String>,
}

/// The repository the command acts on: the course tree of the current directory
/// ([`crate::checkout`]).
pub fn repository_root() -> PathBuf {
    crate::checkout::workspace_root()
}

/// Runs `raylab handout`.
pub fn run(args: &HandoutArgs) -> Result<(), Error> {
    let out = match (&args.out, &args.update) {
        (_, Some(dir)) => return release::update(args, dir),
        (Some(out), None) => out,
        (None, None) => {
            return Err(Error::Failed {
                what: "raylab handout".into(),
                reason: "expected --out DIR (a new handout) or --update DIR (a release)".into(),
            });
        }
    };
    if out.exists() && fs::read_dir(out).map_err(io(out))?.next().is_some() {
        return Err(Error::Invalid {
            what: format!("--out {}", out.display()),
            reason: "expected a directory that does not exist yet, or an empty one".into(),
        });
    }
    let root = repository_root();
    check_clean(&root, args.allow_dirty)?;
    let options = TreeOptions {
        released: args.release_solutions.iter().copied().collect(),
        answer_key: false,
        version_tag: None,
        framework_tag: None,
    };
    // The refusals that need no tree come before the repository is made.
    check_releasable(&root, &options.released)?;
    release::init_repository(out)?;
    build_tree(&root, out, &options)?;
    release::commit_handout(out, &options.released)?;
    let released = if options.released.is_empty() {
        "none".to_string()
    } else {
        format!("{:?}", options.released)
    };
    println!(
        "handout written to {} (solutions released: {released}): a git repository on branch main with one commit; publish it for students to clone, and release with `raylab handout --update {}`",
        out.display(),
        out.display()
    );
    Ok(())
}

/// What a handout is made of, relative to the repository root.
const HANDOUT_SOURCES: &[&str] = &[
    ".gitignore",
    "Cargo.lock",
    "Cargo.toml",
    "docs",
    "framework",
    "labs",
    "reference",
];

/// The docs a handout leaves out: how grading works and what it costs are the instructors'.
const INSTRUCTOR_DOCS: &[&str] = &["docs/instructors.md", "docs/performance.md"];

/// The files of [`HANDOUT_SOURCES`] that differ from the last commit of the git work tree at
/// `root` (changed, staged, deleted or untracked and not ignored); `None` when `root` is not a
/// git work tree or git cannot be run.
fn uncommitted_files(root: &Path) -> Option<Vec<String>> {
    let output = std::process::Command::new("git")
        .args([
            "status",
            "--porcelain=v1",
            "-z",
            "--untracked-files=all",
            "--",
        ])
        .args(HANDOUT_SOURCES)
        .current_dir(root)
        .stdin(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .output()
        .ok()?;
    if !output.status.success() {
        return None;
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let mut files = Vec::new();
    let mut entries = text.split('\0').filter(|e| !e.is_empty());
    while let Some(entry) = entries.next() {
        let (status, path) = entry.split_at(entry.len().min(3));
        // A rename's entry is followed by the name it had.
        if status.starts_with('R') || status.starts_with('C') {
            entries.next();
        }
        files.push(path.to_string());
    }
    Some(files)
}

/// Builds the tree of `options` from the repository at `root` into `out`.
pub fn build_tree(root: &Path, out: &Path, options: &TreeOptions) -> Result<(), Error> {
    check_releasable(root, &options.released)?;
    fs::create_dir_all(out).map_err(io(out))?;
    if root.join(".gitignore").exists() {
        copy_file(&root.join(".gitignore"), &out.join(".gitignore"))?;
    }
    let lock = root.join("Cargo.lock");
    if lock.exists() {
        let left_out = package_name(&root.join("tests/Cargo.toml"))?;
        let text = lock_without(&read(&lock)?, &[left_out]).map_err(|reason| Error::Invalid {
            what: lock.display().to_string(),
            reason,
        })?;
        write(&out.join("Cargo.lock"), &text)?;
    }
    copy_dir(&root.join("framework"), &out.join("framework"))?;
    if let Some(tag) = &options.framework_tag {
        let tagged = format!("\nversion = \"{}-{tag}\"\n", env!("CARGO_PKG_VERSION"));
        for entry in fs::read_dir(out.join("framework")).map_err(io(&out.join("framework")))? {
            let manifest = entry
                .map_err(io(&out.join("framework")))?
                .path()
                .join("Cargo.toml");
            if !manifest.is_file() {
                continue;
            }
            let shown = manifest
                .strip_prefix(out)
                .unwrap_or(&manifest)
                .display()
                .to_string();
            write(
                &manifest,
                &replace_once(
                    &read(&manifest)?,
                    "\nversion.workspace = true\n",
                    &tagged,
                    &shown,
                )?,
            )?;
        }
    }
    copy_dir(&root.join("docs"), &out.join("docs"))?;
    for doc in INSTRUCTOR_DOCS {
        fs::remove_file(out.join(doc)).map_err(io(&out.join(doc)))?;
    }
    let mut manifest = replace_once(
        &read(&root.join("Cargo.toml"))?,
        "    \"tests\",\n",
        "",
        "Cargo.toml",
    )?;
    if let Some(tag) = &options.version_tag {
        let version = format!("\nversion = \"{}\"\n", env!("CARGO_PKG_VERSION"));
        let tagged = format!("\nversion = \"{}-{tag}\"\n", env!("CARGO_PKG_VERSION"));
        manifest = replace_once(&manifest, &version, &tagged, "Cargo.toml")?;
    }
    write(&out.join("Cargo.toml"), &manifest)?;
    write(&out.join("README.md"), &readme(&options.released))?;

    copy_dir(&root.join("labs/raylab"), &out.join("labs/raylab"))?;
    // The command line's tests are the instructors' (their fixtures hold solutions of labs).
    let cli_tests = out.join("labs/raylab/tests");
    fs::remove_dir_all(&cli_tests).map_err(io(&cli_tests))?;
    let cli_manifest = out.join("labs/raylab/Cargo.toml");
    write(
        &cli_manifest,
        &replace_once(
            &read(&cli_manifest)?,
            "default = [\"instructor\"]",
            "default = []",
            "labs/raylab/Cargo.toml",
        )?,
    )?;

    copy_file(
        &root.join("labs/course.toml"),
        &out.join("labs/course.toml"),
    )?;
    for lab in crate::labs::labs() {
        let name = format!("{lab}");
        let to = out.join("labs").join(&name);
        copy_dir(&root.join("labs").join(&name), &to)?;
        // Of a lab's tests only its program goes: the mutant corpus and the statistics tests
        // hold the answer key's code and mistakes to reject.
        let tests = to.join("tests");
        for entry in fs::read_dir(&tests).map_err(io(&tests))? {
            let path = entry.map_err(io(&tests))?.path();
            if path.file_name().is_some_and(|n| n != "checks.rs") {
                if path.is_dir() {
                    fs::remove_dir_all(&path).map_err(io(&path))?;
                } else {
                    fs::remove_file(&path).map_err(io(&path))?;
                }
            }
        }
    }
    if options.answer_key {
        copy_dir(&root.join("reference"), &out.join("reference"))
    } else {
        write_reference(root, out, &options.released)
    }
}

/// The `[package] name` of the manifest at `path`.
fn package_name(path: &Path) -> Result<String, Error> {
    let text = read(path)?;
    let manifest: toml::Table = toml::from_str(&text).map_err(|e| Error::Parse {
        path: path.to_path_buf(),
        line: e
            .span()
            .map_or(0, |s| crate::reset::line_of(&text, s.start)),
        reason: e.message().to_string(),
    })?;
    manifest
        .get("package")
        .and_then(|p| p.get("name"))
        .and_then(toml::Value::as_str)
        .map(str::to_string)
        .ok_or_else(|| Error::Parse {
            path: path.to_path_buf(),
            line: 0,
            reason: "no `[package]` with a `name`".into(),
        })
}

/// The line that starts a package's dependencies in a `Cargo.lock`, with the end of the line
/// before it.
const DEPENDENCIES: &str = "\ndependencies = [\n";

/// One `[[package]]` of a `Cargo.lock`.
struct LockedPackage<'a> {
    /// Its text, after the `[[package]]` line.
    text: &'a str,
    name: &'a str,
    version: &'a str,
    /// `None` for a package of the workspace (a path).
    source: Option<&'a str>,
    /// Its dependencies as the file names them: "name", "name version" or
    /// "name version (source)".
    dependencies: Vec<&'a str>,
}

impl<'a> LockedPackage<'a> {
    /// Reads one package's text; `None` when it has no name or no version.
    fn parse(text: &'a str) -> Option<Self> {
        let field = |key: &str| {
            text.lines().find_map(|line| {
                line.strip_prefix(key)?
                    .strip_prefix(" = \"")?
                    .strip_suffix('"')
            })
        };
        let dependencies = text
            .split_once(DEPENDENCIES)
            .map(|(_, list)| {
                list.lines()
                    .take_while(|line| *line != "]")
                    .filter_map(|line| line.trim().strip_prefix('"')?.strip_suffix("\","))
                    .collect()
            })
            .unwrap_or_default();
        Some(Self {
            text,
            name: field("name")?,
            version: field("version")?,
            source: field("source"),
            dependencies,
        })
    }

    /// Whether the dependency `spec` ("name", "name version", "name version (source)") names
    /// this package.
    fn is(&self, spec: &str) -> bool {
        let mut parts = spec.splitn(3, ' ');
        let name = parts.next() == Some(self.name);
        let version = parts.next().is_none_or(|v| v == self.version);
        let source = parts
            .next()
            .is_none_or(|s| Some(s.trim_start_matches('(').trim_end_matches(')')) == self.source);
        name && version && source
    }
}

/// The lock file `lock` (the repository's `Cargo.lock`) of the workspace without the packages
/// `left_out`: without them and every package only they need, each dependency named as cargo
/// names it (with its version only where two packages of that name remain, with its source
/// only where two of that name and version do). That is the file cargo itself writes for the
/// handout's workspace: any other one, cargo rewrites at a student's first build, and the
/// handout's clone starts with a changed file.
fn lock_without(lock: &str, left_out: &[String]) -> Result<String, String> {
    const SEPARATOR: &str = "\n[[package]]\n";
    let mut parts = lock.split(SEPARATOR);
    let header = parts.next().unwrap_or_default();
    let packages = parts
        .enumerate()
        .map(|(k, text)| {
            LockedPackage::parse(text)
                .ok_or_else(|| format!("package {} has no name or no version", k + 1))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let find = |from: &LockedPackage, spec: &str| -> Result<usize, String> {
        let found: Vec<usize> = (0..packages.len())
            .filter(|&k| packages[k].is(spec))
            .collect();
        match found[..] {
            [one] => Ok(one),
            _ => Err(format!(
                "the dependency \"{spec}\" of {} {} names {} packages, not one",
                from.name,
                from.version,
                found.len()
            )),
        }
    };
    // What the workspace's packages need, and what those need.
    let mut kept = vec![false; packages.len()];
    let mut next: Vec<usize> = (0..packages.len())
        .filter(|&k| {
            packages[k].source.is_none() && !left_out.iter().any(|n| n == packages[k].name)
        })
        .collect();
    while let Some(k) = next.pop() {
        if std::mem::replace(&mut kept[k], true) {
            continue;
        }
        for spec in &packages[k].dependencies {
            next.push(find(&packages[k], spec)?);
        }
    }
    let same = |k: usize, version: bool| {
        (0..packages.len())
            .filter(|&j| {
                kept[j]
                    && packages[j].name == packages[k].name
                    && (!version || packages[j].version == packages[k].version)
            })
            .count()
    };
    let mut out = header.to_string();
    for package in packages
        .iter()
        .zip(&kept)
        .filter_map(|(p, &k)| k.then_some(p))
    {
        out.push_str(SEPARATOR);
        // The list of dependencies is written again, the rest as it is.
        let Some((head, list)) = package.text.split_once(DEPENDENCIES) else {
            out.push_str(package.text);
            continue;
        };
        let end = match list.find("\n]") {
            _ if list.starts_with(']') => 0,
            Some(end) => end + 1,
            None => list.len(),
        };
        let rest = &list[end..];
        out.push_str(head);
        out.push_str(DEPENDENCIES);
        for spec in &package.dependencies {
            let j = find(package, spec)?;
            let dependency = &packages[j];
            let mut named = dependency.name.to_string();
            if same(j, false) > 1 {
                named = format!("{named} {}", dependency.version);
            }
            if same(j, true) > 1
                && let Some(source) = dependency.source
            {
                named = format!("{named} ({source})");
            }
            out.push_str(&format!(" \"{named}\",\n"));
        }
        out.push_str(rest);
    }
    Ok(out)
}

/// Refuses a repository `root` whose files differ from the last commit, unless `allow_dirty`
/// (then they are named on stderr): what is handed out or uploaded should be a commit.
pub fn check_clean(root: &Path, allow_dirty: bool) -> Result<(), Error> {
    match uncommitted_files(root) {
        Some(files) if !files.is_empty() => {
            let list = files.join(", ");
            if !allow_dirty {
                return Err(Error::Failed {
                    what: format!("the repository {} has uncommitted changes", root.display()),
                    reason: format!(
                        "these files differ from the last commit: {list}; commit them, or pass --allow-dirty to take them as they are"
                    ),
                });
            }
            eprintln!(
                "warning: --allow-dirty: these uncommitted changes go in as they are: {list}"
            );
        }
        Some(_) => {}
        None => eprintln!(
            "note: {} is not a git work tree (or git is not installed): the copy takes the files as they are",
            root.display()
        ),
    }
    Ok(())
}

/// A released lab's solution may use another lab's solution (`crate::labNN`); that lab must
/// be released too.
fn check_releasable(root: &Path, released: &BTreeSet<LabId>) -> Result<(), Error> {
    for &lab in released {
        crate::labs::check_lab(lab)?;
        let source = read(&root.join(format!("reference/src/{lab}.rs")))?;
        for other in crate::labs::labs() {
            if source.contains(&format!("crate::{other}")) && !released.contains(&other) {
                return Err(Error::Invalid {
                    what: format!("--release-solutions {released:?}"),
                    reason: format!(
                        "the solution of lab {} uses the solution of lab {}; release lab {} as well",
                        lab.number(),
                        other.number(),
                        other.number()
                    ),
                });
            }
        }
    }
    Ok(())
}

/// Writes `reference/`: its manifest and `lib.rs`, and the released solutions only, so that
/// `pipeline()` holds a waiting slot for each lab not released (it lists the solutions
/// present; see `reference/src/lib.rs`).
fn write_reference(root: &Path, out: &Path, released: &BTreeSet<LabId>) -> Result<(), Error> {
    let dir = out.join("reference");
    fs::create_dir_all(dir.join("src")).map_err(io(&dir))?;
    for file in ["Cargo.toml", "build.rs", "src/lib.rs"] {
        copy_file(&root.join("reference").join(file), &dir.join(file))?;
    }
    for &lab in released {
        let file = format!("src/{lab}.rs");
        copy_file(&root.join("reference").join(&file), &dir.join(&file))?;
    }
    // With no solution released, `src/` holds `lib.rs` alone in every handout, and is dated as
    // that file: a handout built again is up to date (its build script watches the directory).
    // A released solution dates the directory now, so that a target directory in which
    // another handout's `reference` was built compiles this one's files.
    if released.is_empty() {
        let lib = root.join("reference/src/lib.rs");
        let modified = fs::metadata(&lib)
            .and_then(|m| m.modified())
            .map_err(io(&lib))?;
        set_modified(&dir.join("src"), modified)?;
    }
    Ok(())
}

/// The handout's README: what is in it and how to work with it.
fn readme(released: &BTreeSet<LabId>) -> String {
    let mut labs = String::new();
    for lab in course::labs() {
        let title = course::title(lab).unwrap_or_default();
        let solution = if released.contains(&lab) {
            format!("`reference/src/{lab}.rs`")
        } else {
            "not released yet".to_string()
        };
        labs.push_str(&format!(
            "| {lab} | {title} | [docs/{lab}.md](docs/{lab}.md) | {solution} |\n"
        ));
    }
    format!(
        r#"# raylab — the labs

Each lab is a crate in `labs/`. Read `docs/labNN.md`, then fill in the functions in
`labs/labNN/src/lib.rs` (each stub says which exercise it is, what to compute and where the
formula comes from) and run that lab's checks. You need a Rust toolchain (1.87 or newer).

| lab | topic | docs | solution |
| --- | --- | --- | --- |
{labs}
```sh
cargo test -p lab01                   # one test per exercise
cargo test -p lab01 exercise_1_2      # just Exercise 1.2
cargo run -p raylab -- status         # which exercises pass, and which one is next
cargo run -p raylab -- hint 1.2       # the next step when you are stuck on Exercise 1.2
cargo run -p raylab -- watch --lab 1  # re-run lab 1's checks each time you save
cargo run -p raylab -- render --lab 1 --pipeline student   # the image your code makes
cargo run -p raylab -- report --lab 1 --pipeline student   # the figures of your report
cargo run -p raylab -- reset 1.2      # put Exercise 1.2's stub back as it was handed out
```

This folder is a git repository: commit your work as you go (`git add -A` then `git commit`).
Your instructor releases solutions and fixes as new commits; `git pull --no-rebase` merges
each release with your commits. A release never changes a file that is yours —
`labs/labNN/src/` and `labs/labNN/answers.md` — so the pull merges without conflicts (commit
before you pull). `cargo run -p raylab -- reset N.M` puts the function of Exercise N.M back as
the handout had it (from the handout's own commits in your clone's history) and leaves your
other functions as they are; your file as it was is kept in `out/reset/` (the command names
the copy; git ignores `out/`, and grading never reads it). `--dry-run` shows both versions
and changes nothing.

Each exercise is checked with your code for its lab and, for the labs before it, the pipeline of
`reference::pipeline`: the solutions released so far. A check that needs a lab whose solution is
not released yet waits for it — it says "waiting for lab N's solution", which is not a mistake
of yours — until the release that brings it. A failing test names the exercise and the function
to fix; for images it writes your render, the expected image and a difference heat map to
`target/raylab-failures/labNN/`.

The reference images are in the labs from the start: `labs/labNN/snapshots/NAME.png` is what
the image check `NAME` expects (the `.exr` beside it holds the exact radiance it compares
with). `render` and `report` show what your code does so far: a pixel that reaches an
unfinished stub (`todo!()`) or panics is magenta, one whose radiance is NaN or infinite is
cyan, and the command names each unfinished exercise and the pixels it cost. `--pipeline
reference` (the default) is `reference::pipeline` too: the pixels that need a lab whose
solution is not released yet are magenta, waiting for it (the command says so); compare with
the snapshot PNGs instead.

Answer each lab's questions in `labs/labNN/answers.md`. To show a figure of your report there,
write `![caption](figures/NAME.png)` with NAME a figure in `out/report/labNN/`: `report` copies
it into `labs/labNN/figures/`, which git keeps (it ignores `out/`), and grading shows it to your
instructor with your answer.

Hand in the whole directory. Only the regular files of `labs/labNN/src/` are graded (no
symbolic links, nothing over 1 MiB), with your answers and their figures: the tests, golden data and snapshots come from the
course's own copy, and a change to any other file is reported to your instructor. Your lab is
compiled where it sees its own `src/` and nothing else, so code that reads files outside it at
compile time (`#[path]`, `include_str!`, …) does not compile, and `unsafe` code is not allowed. Grading runs your code in a sandbox with time and memory
limits. Some exercises have tests that run only at grading.
"#
    )
}

/// Copies the directory `from` to `to`, leaving out build output (`target/`, `out/`) and
/// version control. Like [`copy_file`], it keeps the dates, the directories' too: a build script
/// that watches a directory (`cargo::rerun-if-changed=src`, to see a file come or go) is judged
/// by the directory's date, and a copy dated now would have cargo build its crate, and all
/// above it, again in every new tree.
pub fn copy_dir(from: &Path, to: &Path) -> Result<(), Error> {
    fs::create_dir_all(to).map_err(io(to))?;
    for entry in fs::read_dir(from).map_err(io(from))? {
        let entry = entry.map_err(io(from))?;
        let name = entry.file_name();
        if [".git", "target", "out"].iter().any(|n| name == *n) {
            continue;
        }
        let path = entry.path();
        if path.is_dir() {
            copy_dir(&path, &to.join(&name))?;
        } else {
            copy_file(&path, &to.join(&name))?;
        }
    }
    if let Ok(modified) = fs::metadata(from).and_then(|m| m.modified()) {
        set_modified(to, modified)?;
    }
    Ok(())
}

/// Copies one file, creating the directories above it. The copy keeps the file's modification
/// time, so that cargo, which judges a path crate's sources by their dates, finds an unchanged
/// tree built again (by the next `raylab grade` in the same directory) up to date.
pub fn copy_file(from: &Path, to: &Path) -> Result<(), Error> {
    if let Some(parent) = to.parent() {
        fs::create_dir_all(parent).map_err(io(parent))?;
    }
    fs::copy(from, to).map_err(io(from))?;
    if let Ok(modified) = fs::metadata(from).and_then(|m| m.modified()) {
        set_modified(to, modified)?;
    }
    Ok(())
}

/// Dates the file or directory at `path` as `modified` (a handle opened for reading is enough:
/// the date is the owner's to set).
fn set_modified(path: &Path, modified: std::time::SystemTime) -> Result<(), Error> {
    fs::File::open(path)
        .and_then(|f| f.set_modified(modified))
        .map_err(io(path))
}

fn read(path: &Path) -> Result<String, Error> {
    fs::read_to_string(path).map_err(io(path))
}

fn write(path: &Path, text: &str) -> Result<(), Error> {
    fs::write(path, text).map_err(io(path))
}

/// `text` with the one occurrence of `from` replaced by `to`; an error naming `place` when
/// `from` is not there (the repository changed in a way the handout does not know).
fn replace_once(text: &str, from: &str, to: &str, place: &str) -> Result<String, Error> {
    if text.matches(from).count() != 1 {
        return Err(Error::Failed {
            what: place.to_string(),
            reason: format!(
                "expected exactly one occurrence of {from:?} to rewrite for the handout"
            ),
        });
    }
    Ok(text.replacen(from, to, 1))
}

/// Maps an I/O error to one naming `path`.
pub fn io(path: &Path) -> impl Fn(std::io::Error) -> Error + '_ {
    move |source| Error::io(path, source)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Runs git in `dir`.
    fn git(dir: &Path, args: &[&str]) {
        let status = std::process::Command::new("git")
            .args([
                "-c",
                "user.name=t",
                "-c",
                "user.email=t@t",
                "-c",
                "commit.gpgsign=false",
            ])
            .args(args)
            .current_dir(dir)
            .output()
            .expect("git runs")
            .status;
        assert!(status.success(), "git {args:?}");
    }

    /// A lock file of the packages `(name, version, source, dependencies)`.
    fn lock(packages: &[(&str, &str, Option<&str>, &[&str])]) -> String {
        let mut text = "# This file is automatically @generated by Cargo.\n# It is not intended for manual editing.\nversion = 4\n".to_string();
        for (name, version, source, dependencies) in packages {
            text.push_str(&format!(
                "\n[[package]]\nname = \"{name}\"\nversion = \"{version}\"\n"
            ));
            if let Some(source) = source {
                text.push_str(&format!("source = \"{source}\"\nchecksum = \"00{name}\"\n"));
            }
            if !dependencies.is_empty() {
                text.push_str("dependencies = [\n");
                for d in *dependencies {
                    text.push_str(&format!(" \"{d}\",\n"));
                }
                text.push_str("]\n");
            }
        }
        text
    }

    #[test]
    fn the_handouts_lock_file_leaves_out_what_only_the_tests_need() {
        const IO: Option<&str> = Some("registry+https://github.com/rust-lang/crates.io-index");
        const MIRROR: Option<&str> = Some("registry+https://mirror.example/index");
        let repository = lock(&[
            ("core", "0.1.0", None, &["glam 0.30.0", "half"]),
            ("glam", "0.30.0", IO, &[]),
            ("glam", "0.34.0", IO, &[]),
            ("half", "2.7.0", IO, &[]),
            (
                "lab01",
                "0.1.0",
                None,
                &[
                    "core",
                    "log 0.4.0 (registry+https://github.com/rust-lang/crates.io-index)",
                ],
            ),
            ("log", "0.4.0", IO, &[]),
            ("log", "0.4.0", MIRROR, &[]),
            (
                "raylab-tests",
                "0.1.0",
                None,
                &[
                    "core",
                    "glam 0.34.0",
                    "lab01",
                    "log 0.4.0 (registry+https://mirror.example/index)",
                    "only-tests",
                ],
            ),
            ("only-tests", "1.0.0", IO, &["half"]),
        ]);
        // Without a package left out, the file is the same.
        assert_eq!(lock_without(&repository, &[]).unwrap(), repository);
        // Without the tests: what only they need goes, and a name left to one package loses
        // its version (and source).
        let handout = lock(&[
            ("core", "0.1.0", None, &["glam", "half"]),
            ("glam", "0.30.0", IO, &[]),
            ("half", "2.7.0", IO, &[]),
            ("lab01", "0.1.0", None, &["core", "log"]),
            ("log", "0.4.0", IO, &[]),
        ]);
        assert_eq!(
            lock_without(&repository, &["raylab-tests".into()]).unwrap(),
            handout
        );
        let broken = repository.replace(" \"half\",\n]", " \"halff\",\n]");
        assert_eq!(
            lock_without(&broken, &["raylab-tests".into()]).unwrap_err(),
            "the dependency \"halff\" of core 0.1.0 names 0 packages, not one"
        );
    }

    #[test]
    fn uncommitted_files_names_what_would_go_into_the_handout() {
        let dir = std::env::temp_dir().join(format!("raylab-dirty-{}", std::process::id()));
        let _ = fs::remove_dir_all(&dir);
        fs::create_dir_all(dir.join("framework/src")).unwrap();
        assert_eq!(uncommitted_files(&dir), None, "not a work tree yet");
        git(&dir, &["init", "-q"]);
        fs::write(dir.join("framework/src/lib.rs"), "// v1\n").unwrap();
        fs::write(dir.join("notes.txt"), "not handed out\n").unwrap();
        git(&dir, &["add", "framework"]);
        git(&dir, &["commit", "-q", "-m", "v1"]);
        assert_eq!(uncommitted_files(&dir), Some(Vec::new()));
        fs::write(dir.join("framework/src/lib.rs"), "// v2\n").unwrap();
        fs::create_dir_all(dir.join("labs/lab01/src")).unwrap();
        fs::write(dir.join("labs/lab01/src/new.rs"), "\n").unwrap();
        assert_eq!(
            uncommitted_files(&dir),
            Some(vec![
                "framework/src/lib.rs".to_string(),
                "labs/lab01/src/new.rs".to_string()
            ])
        );
        // The refusal names the repository and its state, not an invalid value.
        assert_eq!(
            check_clean(&dir, false).unwrap_err().to_string(),
            format!(
                "the repository {} has uncommitted changes: these files differ from the last commit: framework/src/lib.rs, labs/lab01/src/new.rs; commit them, or pass --allow-dirty to take them as they are",
                dir.display()
            )
        );
        assert!(check_clean(&dir, true).is_ok());
        let _ = fs::remove_dir_all(&dir);
    }
}

/// What the handout's README and `raylab render --help` tell students about a lab whose
/// solution is not released, held against what the code does.
#[cfg(test)]
mod student_facing_claims {
    use clap::ValueEnum;
    use pipeline::Pipeline;
    use pipeline::render::render_partial;
    use raylab_core::render::RenderSettings;
    use raylab_core::scene::builtin_scene;

    use super::*;
    use crate::render::PipelineChoice;

    /// A render in a pipeline that waits for labs 1 and 2 (a handout before any release): every
    /// pixel panicked, each naming lab 1 as the one it waits for.
    fn waiting_render() -> raylab_core::render::PartialRender {
        let scene = builtin_scene("default").unwrap();
        let settings = RenderSettings {
            width: 8,
            height: 6,
            ..RenderSettings::default()
        };
        render_partial(&scene, &Pipeline::waiting(2), &settings).unwrap()
    }

    #[test]
    fn a_lab_not_released_is_waited_for_as_the_texts_say() {
        let text = readme(&BTreeSet::new());
        // The README quotes the words of the check that waits: the waiting slot's message.
        let quoted = "waiting for lab N's solution";
        assert!(text.contains(quoted), "{text}");
        let rendered = waiting_render();
        let failures = rendered.failures.sorted();
        assert_eq!(failures.len(), 1, "{failures:?}");
        assert_eq!(failures[0].pixels, 8 * 6);
        let message = &failures[0].panic.message;
        assert!(
            message.contains(&quoted.replace('N', "1")),
            "the waiting slot says {message:?}; the README quotes {quoted:?}"
        );
        // Those pixels are the magenta ones the README and `--help` speak of.
        assert!(rendered.panicked.iter().all(|&p| p));
        assert!(text.contains("magenta, waiting for it"), "{text}");
        let help = PipelineChoice::Reference
            .to_possible_value()
            .and_then(|v| v.get_help().map(ToString::to_string))
            .unwrap_or_default();
        assert!(help.contains("waiting for it"), "{help}");
        // No text says a released pipeline runs the student's own code in another lab's place.
        for said in [&text, &help] {
            assert!(!said.contains("your own code for the labs"), "{said}");
            assert!(!said.contains("runs your own code"), "{said}");
        }
    }
}
