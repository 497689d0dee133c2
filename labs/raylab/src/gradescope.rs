//! `raylab gradescope`: the autograder bundle for Gradescope, for a course that grades one
//! container per submission on Gradescope's machines instead of a class on one machine.
//!
//! Gradescope unpacks the bundle (zipped) into `/autograder/source`, runs its `setup.sh` once
//! when it builds the autograder's image, then runs `run_autograder` in a fresh container for
//! each submission, with the student's files in `/autograder/submission`; the score is what
//! `/autograder/results/results.json` says. The bundle is this repository (the answer key
//! included: the container is the grader's) with those two scripts at its root:
//!
//! - `setup.sh` installs the packages grading needs and the Rust toolchain this command was
//!   built with, builds `raylab` from the pinned lock file, and grades the handout once so that
//!   the framework and every dependency are compiled into the image;
//! - `run_autograder` runs `raylab grade` on the submission — the same code and reports as on
//!   one machine — with `--results-json`, in bubblewrap where the container allows it and
//!   otherwise each exercise as the unprivileged user `nobody` (`--run-as`).

use course::LabId;
use std::fs;
use std::os::unix::fs::PermissionsExt;
use std::path::{Path, PathBuf};

use clap::Args;
use raylab_core::Error;

use crate::handout::{copy_file, io, repository_root};

/// Options of `raylab gradescope`.
#[derive(Args, Debug)]
pub struct GradescopeArgs {
    /// Directory to write the bundle to (must not exist, or be empty); zip its contents
    /// (`cd DIR && zip -qr ../autograder.zip .`) and upload that as the autograder.
    #[arg(long)]
    pub out: PathBuf,
    /// The lab this assignment grades (repeatable, `--lab 1 --lab 2`, for an assignment of
    /// several): its students see only these labs' tests.
    #[arg(long = "lab", value_name = "N", required = true)]
    pub labs: Vec<LabId>,
    /// Labs whose solution was released in the students' handout (as for `raylab grade`).
    #[arg(long, value_delimiter = ',')]
    pub release_solutions: Vec<LabId>,
    /// Seconds an exercise may run before it is stopped and fails.
    #[arg(long, default_value_t = 60)]
    pub timeout: u64,
    /// Write the bundle even though files of the repository differ from the last commit.
    #[arg(long)]
    pub allow_dirty: bool,
    /// The course file of `raylab grade --course` (checked, and copied into the bundle): its
    /// late penalty, grace period and cap apply to the due date Gradescope gives each
    /// submission, extensions included.
    #[arg(long, value_name = "FILE")]
    pub course: Option<PathBuf>,
}

/// The course file's name in the bundle.
const COURSE_FILE: &str = "course-term.toml";

/// Where the autograder's files live in Gradescope's container; `run_autograder` takes
/// another root from `$AUTOGRADER` (a test's stand-in directory).
const AUTOGRADER: &str = "/autograder";

/// The repository's entries that the bundle leaves out: version control, builds, outputs, CI.
const LEFT_OUT: &[&str] = &[".git", "target", "out", ".ci"];

/// Runs `raylab gradescope`.
pub fn run(args: &GradescopeArgs) -> Result<(), Error> {
    crate::handout::check_clean(&repository_root(), args.allow_dirty)?;
    if args.out.exists()
        && fs::read_dir(&args.out)
            .map_err(io(&args.out))?
            .next()
            .is_some()
    {
        return Err(Error::Invalid {
            what: format!("--out {}", args.out.display()),
            reason: "expected a directory that does not exist yet, or an empty one".into(),
        });
    }
    for &lab in &args.labs {
        crate::labs::check_lab(lab)?;
    }
    if let Some(course) = &args.course {
        crate::grade::term::CourseTerms::load(course, None)?;
    }
    write_bundle(args, &repository_root(), &args.out)?;
    println!(
        "Gradescope autograder written to {}: zip its contents (cd {} && zip -qr ../autograder.zip .) and upload the zip as the assignment's autograder (docs/instructors.md, Gradescope)",
        fs::canonicalize(&args.out)
            .map_err(io(&args.out))?
            .display(),
        args.out.display()
    );
    Ok(())
}

/// Writes the bundle of the repository `root` into `out`.
fn write_bundle(args: &GradescopeArgs, root: &Path, out: &Path) -> Result<(), Error> {
    fs::create_dir_all(out).map_err(io(out))?;
    for entry in fs::read_dir(root).map_err(io(root))? {
        let entry = entry.map_err(io(root))?;
        let name = entry.file_name();
        if LEFT_OUT.iter().any(|n| name == *n) {
            continue;
        }
        let path = entry.path();
        if path.is_dir() {
            crate::handout::copy_dir(&path, &out.join(&name))?;
        } else {
            copy_file(&path, &out.join(&name))?;
        }
    }
    // The repository's README is the course's; the bundle's says what the bundle is.
    let readme = out.join("README.md");
    fs::write(&readme, bundle_readme(args)).map_err(io(&readme))?;
    if let Some(course) = &args.course {
        copy_file(course, &out.join(COURSE_FILE))?;
    }
    script(&out.join("setup.sh"), &setup_script(args, &toolchain()?))?;
    script(&out.join("run_autograder"), &run_script(args))
}

/// The command line that writes this bundle again (with `--out autograder`).
fn rebuild_command(args: &GradescopeArgs) -> String {
    let mut command = format!(
        "cargo run -p raylab -- gradescope --out autograder {}",
        lab_options(args)
    );
    if let Some(course) = &args.course {
        command.push_str(&format!(" --course {}", course.display()));
    }
    command
}

/// `--timeout T --lab N … [--release-solutions …]`: the options of the labs the bundle grades,
/// as it was written with them and as it grades.
fn lab_options(args: &GradescopeArgs) -> String {
    let mut options = format!("--timeout {}", args.timeout);
    for lab in &args.labs {
        options.push_str(&format!(" --lab {}", lab.number()));
    }
    if !args.release_solutions.is_empty() {
        let labs: Vec<String> = args
            .release_solutions
            .iter()
            .map(|l| l.number().to_string())
            .collect();
        options.push_str(&format!(" --release-solutions {}", labs.join(",")));
    }
    options
}

/// The bundle's README.md: what the bundle is, the labs and exercises it grades, how to upload
/// it, what students see, and how to write it again.
fn bundle_readme(args: &GradescopeArgs) -> String {
    let mut exercises = String::new();
    let mut points = 0;
    for &lab in &args.labs {
        let title = course::title(lab).unwrap_or_default();
        for e in crate::labs::exercises(lab) {
            points += e.points;
            let shown = match e.visibility {
                course::Visibility::Visible => "from the first submission",
                course::Visibility::Hidden => "after the instructor publishes the grades",
            };
            exercises.push_str(&format!(
                "| {} | {title} | {} (`{}`) | {} | {shown} |\n",
                e.id, e.title, e.function, e.points
            ));
        }
    }
    let labs: Vec<String> = args.labs.iter().map(|l| l.number().to_string()).collect();
    let labs = if labs.len() == 1 {
        format!("lab {}", labs[0])
    } else {
        format!("labs {}", labs.join(", "))
    };
    let solutions = if args.release_solutions.is_empty() {
        "none".to_string()
    } else {
        let released: Vec<String> = args
            .release_solutions
            .iter()
            .map(|l| l.number().to_string())
            .collect();
        format!("labs {}", released.join(", "))
    };
    format!(
        r#"# raylab autograder: {labs}

This folder is a Gradescope autograder written by `raylab gradescope`. It grades {labs} of
the raylab course ({points} points) exactly as `raylab grade` does on one machine: each exercise
of a submission's `labs/labNN/src/` is compiled and run on its own, with the answer key for
everything else, and scored on its check's verdict. It holds the course repository (the answer
key included: keep the bundle to yourself), `setup.sh` and `run_autograder`.

| exercise | lab | what | points | students see its test |
| --- | --- | --- | --- | --- |
{exercises}
Solutions released to students (their handout's `reference/`): {solutions}. Each exercise may
run for {timeout} seconds.

## Uploading it

1. Zip the folder's contents (not the folder): `cd autograder && zip -qr ../autograder.zip .`
2. On Gradescope, make a "Programming Assignment", choose the Ubuntu base image, and upload
   `autograder.zip` under "Configure Autograder". Building the image runs `setup.sh` (it
   installs the Rust toolchain and compiles the framework and answer key: allow several
   minutes); use "Test Autograder" with a copy of the handout to see a result.
3. Students submit their copy of the handout: a zip of the folder, or their GitHub repository.
   Only the regular files of `labs/labNN/src/` of {labs} are graded; a change to any other file
   is reported in the output, not graded.

## What students see

One test per exercise: its name, points, whether it passed and why not (the check's message:
the smallest input on which the code is wrong, or what an image check found). The exercises
marked above "after the instructor publishes the grades" are hidden until then. The overall
output lists files not taken, changes outside `labs/labNN/src/` and how the code was isolated.
Every other lab of the course is left out: students see only {labs}.

## Writing it again

From the course repository, at the commit the students' handout was made from:

```sh
{rebuild}
```

`raylab gradescope` refuses a repository with uncommitted changes (`--allow-dirty` takes them).
docs/instructors.md, "On Gradescope", has the details of `setup.sh` and `run_autograder`.
"#,
        timeout = args.timeout,
        rebuild = rebuild_command(args),
    )
}

/// Writes an executable script.
fn script(path: &Path, text: &str) -> Result<(), Error> {
    fs::write(path, text).map_err(io(path))?;
    fs::set_permissions(path, fs::Permissions::from_mode(0o755)).map_err(io(path))
}

/// The version of the Rust toolchain (`rustc --version`) that builds the grading here: the
/// one the bundle installs.
fn toolchain() -> Result<String, Error> {
    let output = std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .map_err(|e| Error::io(Path::new("rustc"), e))?;
    let text = String::from_utf8_lossy(&output.stdout);
    text.split_whitespace()
        .nth(1)
        .filter(|v| v.split('.').all(|n| n.parse::<u32>().is_ok()))
        .map(str::to_string)
        .ok_or_else(|| Error::Failed {
            what: "rustc --version".into(),
            reason: format!("expected `rustc X.Y.Z (…)`, got {text:?}"),
        })
}

/// The `raylab grade` options the bundle grades with, after the submission and `--out`.
fn grade_options(args: &GradescopeArgs) -> String {
    let mut options = lab_options(args);
    if args.course.is_some() {
        options.push_str(&format!(" --course \"$source/{COURSE_FILE}\""));
    }
    options
}

/// `setup.sh`: run once, as root, when Gradescope builds the autograder's image.
fn setup_script(args: &GradescopeArgs, toolchain: &str) -> String {
    format!(
        r#"#!/usr/bin/env bash
# The autograder's setup, written by `raylab gradescope`: Gradescope runs it once, as root, when it
# builds the image every submission is graded in. It installs what grading needs and compiles
# everything but the student's code, so that a submission builds only its own labs.
set -euo pipefail
source={AUTOGRADER}/source
apt-get update -qq
DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    ca-certificates curl build-essential bubblewrap util-linux git >/dev/null
if ! command -v rustup >/dev/null 2>&1 && [ ! -x "$HOME/.cargo/bin/rustup" ]; then
    curl --proto '=https' --tlsv1.2 -sSf https://sh.rustup.rs \
        | sh -s -- -y --profile minimal --default-toolchain {toolchain}
fi
. "$HOME/.cargo/env"
rustup default {toolchain}
# A submission's labs are compiled to WebAssembly, where they run apart from the checks.
rustup target add wasm32-unknown-unknown
cd "$source"
cargo build --locked -p raylab --features instructor
# Grade the handout's stubs once: the framework, the answer key and every dependency are then
# compiled in {AUTOGRADER}/target, which run_autograder builds in.
./target/debug/raylab handout --allow-dirty --out /tmp/raylab-handout
AUTOGRADER={AUTOGRADER} RAYLAB_SUBMISSION=/tmp/raylab-handout ./run_autograder || true
rm -rf /tmp/raylab-handout {AUTOGRADER}/results/results.json
# The answer key's sources are the grader's: student code that runs as another user cannot read them.
chmod 700 "$source"
echo "raylab autograder ready ({options})"
"#,
        options = grade_options(args),
    )
}

/// `run_autograder`: run by Gradescope for each submission, as root, in a fresh container.
fn run_script(args: &GradescopeArgs) -> String {
    format!(
        r#"#!/usr/bin/env bash
# Grades one submission, written by `raylab gradescope`: Gradescope runs it as root in a fresh
# container made from the image setup.sh prepared, with the student's files in
# $AUTOGRADER/submission, and reads the score from $AUTOGRADER/results/results.json. The grading
# is `raylab grade`'s, with its reports; student code runs in bubblewrap where the container
# allows it and otherwise, each exercise, as the unprivileged user nobody.
set -uo pipefail
AUTOGRADER="${{AUTOGRADER:-{AUTOGRADER}}}"
source="$AUTOGRADER/source"
raylab="${{RAYLAB:-$source/target/debug/raylab}}"
target="${{RAYLAB_TARGET_DIR:-$AUTOGRADER/target}}"
grading="${{RAYLAB_GRADING_DIR:-$AUTOGRADER/grading}}"
results="$AUTOGRADER/results"
mkdir -p "$results"
[ -f "$HOME/.cargo/env" ] && . "$HOME/.cargo/env"

# The submission: the student's copy of the handout, uploaded as it is or as one folder.
submission="${{RAYLAB_SUBMISSION:-$AUTOGRADER/submission}}"
if [ ! -d "$submission/labs" ]; then
    for dir in "$submission"/*/; do
        if [ -d "$dir/labs" ]; then submission="${{dir%/}}"; fi
    done
fi

# $RAYLAB_RUN_AS chooses the unprivileged user even where bubblewrap would start.
if [ -n "${{RAYLAB_RUN_AS:-}}" ]; then
    isolation="--run-as $RAYLAB_RUN_AS"
elif bwrap --unshare-all --die-with-parent --ro-bind / / true 2>/dev/null; then
    isolation=""
else
    isolation="--run-as 65534"
fi

if [ ! -x "$raylab" ]; then
    printf '{{"score": 0, "output": "The autograder is not set up: raylab was not built (setup.sh).", "tests": []}}\n' \
        > "$results/results.json"
    exit 0
fi
# Gradescope's metadata of the submission: its time and due date (the student's extension's).
metadata=()
if [ -f "$AUTOGRADER/submission_metadata.json" ]; then
    metadata=(--gradescope-metadata "$AUTOGRADER/submission_metadata.json")
fi
"$raylab" grade "$submission" --out "$grading" --target-dir "$target" \
    --results-json "$results/results.json" {options} "${{metadata[@]}}" $isolation
status=$?
echo "raylab grade ended with status $status"
exit 0
"#,
        options = grade_options(args),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn args(labs: Vec<u32>, released: Vec<u32>) -> GradescopeArgs {
        GradescopeArgs {
            out: PathBuf::from("x"),
            labs: labs.into_iter().map(LabId::of).collect(),
            release_solutions: released.into_iter().map(LabId::of).collect(),
            timeout: 30,
            allow_dirty: false,
            course: None,
        }
    }

    #[test]
    fn the_scripts_grade_the_chosen_labs_with_the_pinned_toolchain() {
        let args = args(vec![3, 4], vec![1, 2]);
        let setup = setup_script(&args, "1.95.0");
        assert!(setup.contains("--default-toolchain 1.95.0"), "{setup}");
        assert!(setup.contains("cargo build --locked -p raylab"), "{setup}");
        let readme = bundle_readme(&args);
        assert!(
            readme.starts_with("# raylab autograder: labs 3, 4\n"),
            "{readme}"
        );
        assert!(
            readme.contains("| 3.1 | Shadows and area lights |"),
            "{readme}"
        );
        assert!(!readme.contains("| 2.1 |"), "{readme}");
        assert!(
            readme.contains(
                "gradescope --out autograder --timeout 30 --lab 3 --lab 4 --release-solutions 1,2"
            ),
            "{readme}"
        );
        let run = run_script(&args);
        assert!(
            run.contains(
                "--timeout 30 --lab 3 --lab 4 --release-solutions 1,2 \"${metadata[@]}\" $isolation"
            ),
            "{run}"
        );
        assert!(
            run.contains("--results-json \"$results/results.json\""),
            "{run}"
        );
        assert!(
            run.contains(
                "metadata=(--gradescope-metadata \"$AUTOGRADER/submission_metadata.json\")"
            ),
            "{run}"
        );
        let with_course = GradescopeArgs {
            course: Some(PathBuf::from("term.toml")),
            ..args
        };
        assert!(
            run_script(&with_course)
                .contains("--release-solutions 1,2 --course \"$source/course-term.toml\""),
            "{run}"
        );
    }
}
