//! Every command a student is told to run works where the student is, a fresh handout: the
//! ones `raylab hint` prints for each exercise, `raylab status` for the labs and the next
//! exercise, and the checks' failure messages (a golden file missing). A `cargo test` must run
//! at least one test there, a `cargo run -p raylab -- …` must have arguments the command
//! accepts (checked without building or rendering anything: the `RAYLAB_CHECK_ARGUMENTS` mode
//! of `raylab`), a `git` command must succeed, and every file the messages name must exist.
//!
//! The handout is kept in `target/raylab-printed-commands/` to be looked at.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

use raylab_tests::workflow::{
    cargo_in as cargo, correct_code, output_text, root, target_dir, workflow_target_dir,
};

/// The commands in `text`: each `cargo …`, `git …` or `raylab …` between backticks, and a
/// `cargo …` that ends a line after a colon (the failure messages' "see it …: cargo run -p
/// raylab -- view …").
fn commands(text: &str) -> Vec<String> {
    let mut found = Vec::new();
    for (i, span) in text.split('`').enumerate() {
        if i % 2 == 1
            && ["cargo ", "git ", "raylab "]
                .iter()
                .any(|c| span.starts_with(c))
        {
            found.push(span.to_string());
        }
    }
    for line in text.lines() {
        if let Some((_, command)) = line.split_once(": cargo ")
            && !command.contains('`')
        {
            found.push(format!("cargo {}", command.trim()));
        }
    }
    found
}

/// The files `text` names: each word that starts with `labs/`, `docs/` or `target/` (a path
/// in the handout) or is an absolute path under the target directory `target`.
fn named_files(text: &str, handout: &Path, target: &Path) -> Vec<PathBuf> {
    text.split_whitespace()
        .map(|word| word.trim_matches(|c: char| "`'\"(),;:.".contains(c)))
        .filter_map(|word| {
            if ["labs/", "docs/", "target/"]
                .iter()
                .any(|d| word.starts_with(d))
            {
                Some(handout.join(word))
            } else if Path::new(word).starts_with(target) {
                Some(PathBuf::from(word))
            } else {
                None
            }
        })
        .collect()
}

/// The tests `cargo test ARGS` runs in `handout`: its arguments as printed, with `--list`.
fn tests_run(handout: &Path, target: &Path, args: &[&str]) -> Result<usize, String> {
    let mut all = args.to_vec();
    all.insert(1, "-q");
    if !all.contains(&"--") {
        all.push("--");
    }
    all.extend(["--list", "--format", "terse"]);
    let (ok, out) = cargo(handout, target, &all);
    if !ok {
        return Err(format!("it fails:\n{out}"));
    }
    Ok(out.lines().filter(|l| l.ends_with(": test")).count())
}

/// Runs `command` in `handout` as a student would; what is wrong with it.
fn run(command: &str, handout: &Path, target: &Path, raylab: &Path) -> Result<(), String> {
    let words: Vec<&str> = command.split_whitespace().collect();
    match words.as_slice() {
        ["cargo", "test", ..] => match tests_run(handout, target, &words[1..])? {
            0 => Err("it runs no test".into()),
            _ => Ok(()),
        },
        ["cargo", "run", "-p", "raylab", "--", args @ ..] => {
            let output = Command::new(raylab)
                .args(args)
                .current_dir(handout)
                .env("RAYLAB_CHECK_ARGUMENTS", "1")
                .output()
                .expect("the handout's raylab runs");
            let said = output_text(&output);
            match output.status.success() && said.contains("arguments accepted") {
                true => Ok(()),
                false => Err(format!("raylab refuses its arguments: {said}")),
            }
        }
        ["git", args @ ..] => {
            let output = Command::new("git")
                .args(args)
                .current_dir(handout)
                .output()
                .expect("git runs");
            match output.status.success() {
                true => Ok(()),
                false => Err(format!("it fails: {}", output_text(&output))),
            }
        }
        // A handout has the command line as a crate of its workspace, not a program on the PATH.
        ["raylab", ..] => {
            Err("there is no `raylab` program; the command is `cargo run -p raylab -- …`".into())
        }
        _ => Err("a command this test does not know how to run".into()),
    }
}

#[test]
fn printed_commands_work_in_a_fresh_handout() {
    let started = Instant::now();
    let phase = |what: &str| eprintln!("{:7.1} s  {what}", started.elapsed().as_secs_f64());
    let work = target_dir().join("raylab-printed-commands");
    let handout = work.join("handout");
    let _ = fs::remove_dir_all(&handout);
    fs::create_dir_all(&work).unwrap();
    let (ok, out) = cargo(
        &root(),
        &target_dir(),
        &[
            "run",
            "--quiet",
            "-p",
            "raylab",
            "--",
            "handout",
            "--allow-dirty",
            "--out",
            handout.to_str().unwrap(),
        ],
    );
    assert!(ok, "{out}");
    phase("handout written");
    let target = workflow_target_dir();
    phase("target directory seeded");
    // The handout's own command line (without the instructor's commands), kept beside the
    // handout: the other workflow tests build theirs in the same target directory.
    let (ok, out) = cargo(&handout, &target, &["build", "-q", "-p", "raylab"]);
    assert!(ok, "{out}");
    let raylab = work.join("raylab");
    fs::copy(target.join("debug/raylab"), &raylab).unwrap();
    phase("its raylab built");

    // What each message printed, by what printed it.
    let mut printed: BTreeMap<String, String> = BTreeMap::new();
    let raylab_says = |args: &[&str]| {
        let output = Command::new(&raylab)
            .args(args)
            .current_dir(&handout)
            .env("CARGO_TARGET_DIR", &target)
            .output()
            .expect("the handout's raylab runs");
        assert!(
            output.status.success(),
            "raylab {args:?}: {}",
            output_text(&output)
        );
        output_text(&output)
    };
    for lab in course::labs() {
        for exercise in &course::lab(lab).unwrap().exercises {
            let text = raylab_says(&["hint", &exercise.id]);
            printed.insert(format!("raylab hint {}", exercise.id), text);
        }
    }
    // Every lab's table, and the next exercise of the handout's stubs, Exercise 1.1.
    printed.insert("raylab status".into(), raylab_says(&["status"]));
    phase("hints and status read");

    // The checks' failure message on correct code of lab 1 whose lab has lost a golden file.
    // (A snapshot's failure, with its `raylab view` command, needs another lab's solution
    // released: labs/raylab/tests/cli.rs runs that command.)
    fs::write(handout.join("labs/lab01/src/lib.rs"), correct_code(1)).unwrap();
    let golden = handout.join("labs/lab01/golden/camera_basis.json");
    fs::remove_file(&golden).unwrap();
    let (ok, out) = cargo(&handout, &target, &["test", "-q", "-p", "lab01"]);
    assert!(!ok, "lab01's checks pass without a golden file:\n{out}");
    assert!(
        out.contains("git checkout -- labs/lab01/golden/camera_basis.json"),
        "{out}"
    );
    printed.insert("cargo test -p lab01".into(), out);
    phase("lab01's checks failed");

    let mut wrong = Vec::new();
    let mut ran = std::collections::BTreeSet::new();
    for (by, text) in &printed {
        for command in commands(text) {
            if !ran.insert(command.clone()) {
                continue;
            }
            if let Err(why) = run(&command, &handout, &target, &raylab) {
                wrong.push(format!("`{command}`, printed by {by}: {why}"));
            }
        }
    }
    phase(&format!("{} commands run", ran.len()));
    // The files the messages name are there (the golden file once its command has run).
    for (by, text) in &printed {
        for file in named_files(text, &handout, &target) {
            if !file.exists() {
                wrong.push(format!(
                    "{by} names {}, which does not exist",
                    file.display()
                ));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
    // The git command put the golden file back: lab 1's checks pass again.
    assert!(golden.is_file() && ran.iter().any(|c| c.starts_with("git checkout")));
    let (ok, out) = cargo(&handout, &target, &["test", "-q", "-p", "lab01"]);
    assert!(ok, "{out}");
}
