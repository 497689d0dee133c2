//! `raylab watch`: re-runs a lab's checks whenever its sources change and shows the next
//! exercise to work on, as rustlings does.

use course::LabId;
use std::path::Path;
use std::process::Command;
use std::time::{Duration, SystemTime};

use clap::Args;
use raylab_core::Error;

/// Options of `raylab watch`.
#[derive(Args, Debug)]
pub struct WatchArgs {
    /// The lab to watch (default: the first lab whose `src/lib.rs` still has an unfinished
    /// stub).
    #[arg(long)]
    pub lab: Option<LabId>,
    /// Run the checks once and stop, instead of waiting for the next change.
    #[arg(long)]
    pub once: bool,
}

/// The first lab whose sources still hold a stub (`todo!("Exercise …`), else the last lab.
fn default_lab(root: &Path) -> LabId {
    let labs = crate::labs::labs();
    labs.iter()
        .copied()
        .find(|lab| {
            std::fs::read_to_string(root.join(format!("labs/{lab}/src/lib.rs")))
                .is_ok_and(|text| text.contains("todo!(\"Exercise"))
        })
        .unwrap_or(labs[labs.len() - 1])
}

/// The newest modification time of the files under `dir` (`None` when there are none).
fn newest_change(dir: &Path) -> Option<SystemTime> {
    let mut newest = None;
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for entry in entries.flatten() {
            let Ok(meta) = entry.metadata() else { continue };
            if meta.is_dir() {
                stack.push(entry.path());
            } else if let Ok(m) = meta.modified() {
                newest = newest.max(Some(m));
            }
        }
    }
    newest
}

/// One exercise's result in libtest's output.
#[derive(Debug, PartialEq, Eq)]
pub struct TestLine {
    /// The test's name (`exercise_1_2_camera_basis`).
    pub name: String,
    /// Whether it passed.
    pub passed: bool,
}

/// What a run of a lab's checks printed: each test's result, and each failure's message.
#[derive(Debug, Default)]
pub struct ChecksRun {
    /// The tests in the order they ran.
    pub tests: Vec<TestLine>,
    /// `(test name, message)` of each failure, in order.
    pub failures: Vec<(String, String)>,
}

/// Reads libtest's standard output (without `-q`): the `test NAME ... ok|FAILED` lines and the
/// `---- NAME ----` sections of the failures.
pub fn parse_checks(stdout: &str) -> ChecksRun {
    let mut run = ChecksRun::default();
    let mut current: Option<(String, Vec<&str>)> = None;
    let mut in_failures = false;
    for line in stdout.lines() {
        if let Some(rest) = line.strip_prefix("test ") {
            if let Some((name, result)) = rest.split_once(" ... ") {
                run.tests.push(TestLine {
                    name: name.trim().to_string(),
                    passed: result.trim() == "ok",
                });
                continue;
            }
        }
        if line == "failures:" {
            in_failures = true;
            if let Some((name, text)) = current.take() {
                run.failures
                    .push((name, text.join("\n").trim().to_string()));
            }
            continue;
        }
        if !in_failures {
            continue;
        }
        if let Some(name) = line
            .strip_prefix("---- ")
            .and_then(|l| l.split(' ').next())
            .filter(|_| line.ends_with("----"))
        {
            if let Some((name, text)) = current.take() {
                run.failures
                    .push((name, text.join("\n").trim().to_string()));
            }
            current = Some((name.to_string(), Vec::new()));
        } else if let Some((_, text)) = current.as_mut() {
            text.push(line);
        }
    }
    if let Some((name, text)) = current.take() {
        run.failures
            .push((name, text.join("\n").trim().to_string()));
    }
    run
}

/// The lab and exercise numbers of a test name (`exercise_12_3_sample_bsdf` → `(12, 3)`), for
/// putting the tests in the exercises' order (`None` for another test).
fn exercise_key(test: &str) -> Option<(u32, u32)> {
    let mut parts = test.strip_prefix("exercise_")?.split('_');
    Some((parts.next()?.parse().ok()?, parts.next()?.parse().ok()?))
}

/// The exercise number of a test name (`exercise_1_2_camera_basis` → `1.2`).
fn exercise_of(test: &str) -> String {
    let mut parts = test.trim_start_matches("exercise_").split('_');
    match (parts.next(), parts.next()) {
        (Some(a), Some(b)) => format!("{a}.{b}"),
        _ => test.to_string(),
    }
}

/// Runs the lab's checks once and prints, in the exercises' order, what passes and the next
/// exercise to do; says whether every exercise passes.
fn check_once(root: &Path, lab: LabId) -> Result<bool, Error> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let package = format!("{lab}");
    let output = Command::new(cargo)
        .args([
            "test", "-p", &package, "--test", "checks", "--color", "never",
        ])
        .current_dir(root)
        .output()
        .map_err(|e| Error::io(Path::new("cargo"), e))?;
    let stdout = String::from_utf8_lossy(&output.stdout);
    let mut run = parse_checks(&stdout);
    if run.tests.is_empty() {
        // It did not build: show cargo's errors.
        let stderr = String::from_utf8_lossy(&output.stderr);
        println!("{package} does not compile:\n");
        for line in stderr.lines().filter(|l| {
            let t = l.trim_start();
            !(t.starts_with("Compiling ") || t.starts_with("Blocking "))
        }) {
            println!("{line}");
        }
        return Ok(false);
    }
    // libtest lists the tests as they finish, in parallel: put them in the exercises' order.
    run.tests.sort_by_key(|t| {
        (
            exercise_key(&t.name).unwrap_or((u32::MAX, 0)),
            t.name.clone(),
        )
    });
    run.failures
        .sort_by_key(|(name, _)| (exercise_key(name).unwrap_or((u32::MAX, 0)), name.clone()));
    let passed = run.tests.iter().filter(|t| t.passed).count();
    println!(
        "{package}: {passed} of {} exercises pass\n",
        run.tests.len()
    );
    for t in &run.tests {
        println!(
            "  {} {:<6} {}",
            if t.passed { "✓" } else { "✗" },
            exercise_of(&t.name),
            t.name
        );
    }
    match run.failures.first() {
        Some((name, message)) => println!(
            "\nnext: Exercise {id} (`cargo test -p {package} {name}`; stuck? `cargo run -p raylab -- hint {id}`)\n\n{message}",
            id = exercise_of(name)
        ),
        None => println!("\nevery exercise of {package} passes"),
    }
    Ok(run.failures.is_empty() && passed == run.tests.len())
}

/// Runs `raylab watch`.
pub fn run(args: &WatchArgs) -> Result<(), Error> {
    let root = crate::checkout::workspace_root();
    let lab = match args.lab {
        Some(lab) => {
            crate::labs::check_lab(lab)?;
            lab
        }
        None => default_lab(&root),
    };
    let mut lab = lab;
    let mut sources = root.join(format!("labs/{lab}/src"));
    let mut seen = newest_change(&sources);
    loop {
        // Clear the terminal and go home, as a watcher does, unless this is a single run.
        if !args.once {
            print!("\x1b[2J\x1b[H");
        }
        let all_pass = check_once(&root, lab)?;
        if args.once {
            return Ok(());
        }
        // A lab done, the next one: its checks at once, then its sources watched.
        let labs = crate::labs::labs();
        let next = labs
            .iter()
            .position(|l| *l == lab)
            .and_then(|i| labs.get(i + 1));
        if let (true, Some(&next)) = (all_pass, next) {
            println!("\non to {next}\n");
            std::thread::sleep(Duration::from_secs(2));
            lab = next;
            sources = root.join(format!("labs/{lab}/src"));
            seen = newest_change(&sources);
            continue;
        }
        println!("\nwatching labs/{lab}/src for changes (Ctrl-C to stop)");
        loop {
            std::thread::sleep(Duration::from_millis(400));
            let now = newest_change(&sources);
            if now != seen {
                seen = now;
                break;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_checks_reads_results_and_failure_messages() {
        let out = "\nrunning 3 tests\ntest exercise_1_1_image_plane_coords ... ok\ntest exercise_1_2_camera_basis       ... FAILED\ntest exercise_1_3_field_of_view      ... FAILED\n\nfailures:\n\n---- exercise_1_2_camera_basis ----\nExercise 1.2 is wrong:\nthe basis is not orthonormal\n\n---- exercise_1_3_field_of_view ----\nExercise 1.3 is not implemented yet.\n\n\nfailures:\n    exercise_1_2_camera_basis\n    exercise_1_3_field_of_view\n\ntest result: FAILED. 1 passed; 2 failed\n";
        let run = parse_checks(out);
        assert_eq!(run.tests.len(), 3);
        assert!(run.tests[0].passed && !run.tests[1].passed);
        assert_eq!(run.failures.len(), 2);
        assert_eq!(run.failures[0].0, "exercise_1_2_camera_basis");
        assert_eq!(
            run.failures[0].1,
            "Exercise 1.2 is wrong:\nthe basis is not orthonormal"
        );
        assert_eq!(run.failures[1].1, "Exercise 1.3 is not implemented yet.");
        assert_eq!(exercise_of(&run.failures[1].0), "1.3");
    }

    #[test]
    fn exercises_sort_by_number_not_by_name() {
        let mut names = [
            "exercise_1_10_b",
            "exercise_12_1_a",
            "exercise_1_2_c",
            "exercise_2_1_d",
        ];
        names.sort_by_key(|n| exercise_key(n));
        assert_eq!(
            names,
            [
                "exercise_1_2_c",
                "exercise_1_10_b",
                "exercise_2_1_d",
                "exercise_12_1_a"
            ]
        );
        assert_eq!(exercise_key("a_test"), None);
    }
}
