//! Building a submission's labs in the grading tree and running each exercise's test in a
//! process of its own, with a time limit.

use std::collections::BTreeMap;
use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use framework::Error;
use framework::grading::ExerciseInfo;

use crate::handout::io;

/// Where cargo runs: the grading tree and the target directory shared by every submission (so
/// the framework is compiled once per class, not once per student).
pub struct Workspace {
    /// The grading tree (`raylab handout` with the hidden tests put back).
    pub tree: PathBuf,
    /// `CARGO_TARGET_DIR` of the builds.
    pub target: PathBuf,
    /// Where each exercise runs, in an empty directory of its own.
    pub runs: PathBuf,
}

/// How a build went.
pub struct Build {
    /// The checks' test executable of each lab that built.
    pub executables: BTreeMap<u32, PathBuf>,
    /// The compiler's complaint for each lab that did not.
    pub errors: BTreeMap<u32, String>,
}

impl Workspace {
    fn cargo(&self) -> Command {
        let mut command = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()));
        command
            .current_dir(&self.tree)
            .env("CARGO_TARGET_DIR", &self.target)
            .env("CARGO_TERM_COLOR", "never")
            .stdin(Stdio::null());
        command
    }

    /// `cargo build --lib -p PACKAGE`: `Err` with the compiler's messages when it does not
    /// compile.
    pub fn build_lib(&self, package: &str) -> Result<Result<(), String>, Error> {
        let output = self
            .cargo()
            .args([
                "build",
                "--quiet",
                "--message-format=short",
                "--lib",
                "-p",
                package,
            ])
            .output()
            .map_err(io(&self.tree))?;
        Ok(if output.status.success() {
            Ok(())
        } else {
            Err(compiler_errors(&String::from_utf8_lossy(&output.stderr)))
        })
    }

    /// `cargo test --no-run` for the checks of `labs`: the executable of each lab that built, the
    /// compiler's messages for each that did not.
    pub fn build_checks(&self, labs: &[u32]) -> Result<Build, Error> {
        let mut command = self.cargo();
        command.args([
            "test",
            "--no-run",
            "--no-fail-fast",
            "--message-format=json-render-diagnostics",
        ]);
        for lab in labs {
            command.arg("-p").arg(format!("lab{lab:02}"));
        }
        let output = command.output().map_err(io(&self.tree))?;
        let mut executables = BTreeMap::new();
        for line in String::from_utf8_lossy(&output.stdout).lines() {
            let Ok(message) = serde_json::from_str::<serde_json::Value>(line) else {
                continue;
            };
            let (Some(executable), Some(target)) = (
                message["executable"].as_str(),
                message["target"]["name"].as_str(),
            ) else {
                continue;
            };
            let source = Path::new(message["target"]["src_path"].as_str().unwrap_or_default());
            if target != "checks" {
                continue;
            }
            let checks_of = |l: &u32| source.ends_with(format!("labs/lab{l:02}/tests/checks.rs"));
            if let Some(&lab) = labs.iter().find(|l| checks_of(l)) {
                executables.insert(lab, PathBuf::from(executable));
            }
        }
        let stderr = compiler_errors(&String::from_utf8_lossy(&output.stderr));
        let errors = labs
            .iter()
            .filter(|l| !executables.contains_key(l))
            .map(|&l| (l, stderr.clone()))
            .collect();
        Ok(Build {
            executables,
            errors,
        })
    }
}

/// The error lines of cargo's output, without its progress lines; at most 60 lines.
fn compiler_errors(stderr: &str) -> String {
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| {
            let t = l.trim_start();
            !(t.starts_with("Compiling ")
                || t.starts_with("Finished ")
                || t.starts_with("Blocking "))
        })
        .collect();
    let mut text = lines
        .iter()
        .take(60)
        .copied()
        .collect::<Vec<_>>()
        .join("\n");
    if lines.len() > 60 {
        text.push_str(&format!("\n… ({} more lines)", lines.len() - 60));
    }
    text
}

/// The outcome of running one exercise's test.
pub struct Run {
    /// The test passed.
    pub passed: bool,
    /// Why it failed (the check's message, the panic, the time-out), or empty.
    pub output: String,
    /// Images the check wrote (student render, expected image, difference heat map).
    pub images: Vec<PathBuf>,
    /// Wall time of the run.
    pub seconds: f64,
}

/// The test names of a checks executable.
pub fn list_tests(executable: &Path) -> Result<Vec<String>, Error> {
    let output = Command::new(executable)
        .args(["--list", "--format", "terse"])
        .stdin(Stdio::null())
        .output()
        .map_err(io(executable))?;
    Ok(String::from_utf8_lossy(&output.stdout)
        .lines()
        .filter_map(|l| l.strip_suffix(": test"))
        .map(str::to_string)
        .collect())
}

/// Runs the test `test` of `executable` in a process of its own, in the empty directory
/// `scratch`, killing it after `timeout`.
pub fn run_exercise(
    executable: &Path,
    test: &str,
    info: &ExerciseInfo,
    scratch: &Path,
    timeout: Duration,
) -> Result<Run, Error> {
    fs::create_dir_all(scratch).map_err(io(scratch))?;
    let log_path = scratch.join("output.txt");
    let log = File::create(&log_path).map_err(io(&log_path))?;
    let log_err = log.try_clone().map_err(io(&log_path))?;
    let start = Instant::now();
    let mut child = Command::new(executable)
        .args([test, "--exact", "--nocapture", "--test-threads=1"])
        .current_dir(scratch)
        .env("CARGO_TARGET_DIR", scratch)
        .env("RUST_BACKTRACE", "0")
        .stdin(Stdio::null())
        .stdout(log)
        .stderr(log_err)
        .spawn()
        .map_err(io(executable))?;
    let status = loop {
        if let Some(status) = child.try_wait().map_err(io(executable))? {
            break Some(status);
        }
        if start.elapsed() >= timeout {
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(10));
    };
    let seconds = start.elapsed().as_secs_f64();
    let text = fs::read_to_string(&log_path).unwrap_or_default();
    let images = failure_images(
        &scratch
            .join("raylab-failures")
            .join(format!("lab{:02}", info.lab)),
    );
    let (passed, output) = match status {
        None => (
            false,
            format!(
                "Exercise {} — `{}` did not finish within {} s and was stopped (an infinite loop?).",
                info.id,
                info.function,
                timeout.as_secs()
            ),
        ),
        Some(s) if s.success() => (true, String::new()),
        Some(s) => (false, failure_message(&text, test, s.code().is_none())),
    };
    Ok(Run {
        passed,
        output,
        images,
        seconds,
    })
}

/// The check's message from a failed test's output: what the test printed after libtest's
/// `test NAME ... ` and before its verdict, or a note on how the process died.
fn failure_message(output: &str, test: &str, killed_by_signal: bool) -> String {
    let start = format!("test {test} ... ");
    let message = match output.find(&start) {
        Some(at) => output[at + start.len()..]
            .lines()
            .take_while(|l| *l != "FAILED" && !l.starts_with("failures:"))
            .filter(|l| !l.starts_with("note: run with `RUST_BACKTRACE"))
            .collect::<Vec<_>>()
            .join("\n")
            .trim()
            .to_string(),
        None => String::new(),
    };
    match (killed_by_signal, message.is_empty()) {
        (true, _) => format!(
            "the test process crashed (a stack overflow or an abort) before the check could finish.\n{message}"
        )
        .trim()
        .to_string(),
        (false, false) => message,
        (false, true) => output.trim().to_string(),
    }
}

/// The PNG files a failing check wrote into `dir`: the student's render first, then the
/// reference, then the difference.
fn failure_images(dir: &Path) -> Vec<PathBuf> {
    let mut images: Vec<PathBuf> = fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .collect();
    images.sort_by_key(|p| {
        let name = p
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let rank = if name.ends_with("-student") {
            0
        } else if name.ends_with("-reference") {
            1
        } else {
            2
        };
        (rank, name)
    });
    images
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_message_is_what_the_check_printed() {
        let output = "\nrunning 1 test\ntest exercise_1_2_camera_basis ... Exercise 1.2 — `camera_basis` is wrong:\nup is not unit\n(see docs/lab01.md, Exercise 1.2)\nFAILED\n\nfailures:\n\nfailures:\n    exercise_1_2_camera_basis\n";
        assert_eq!(
            failure_message(output, "exercise_1_2_camera_basis", false),
            "Exercise 1.2 — `camera_basis` is wrong:\nup is not unit\n(see docs/lab01.md, Exercise 1.2)"
        );
        assert!(
            failure_message("running 1 test\n", "t", true).starts_with("the test process crashed")
        );
        assert_eq!(failure_message("garbage", "t", false), "garbage");
    }

    #[test]
    fn progress_lines_are_not_errors() {
        let text = compiler_errors(
            "   Compiling lab01 v0.1.0\nerror[E0308]: mismatched types\n    Finished `dev`",
        );
        assert_eq!(text, "error[E0308]: mismatched types");
    }
}
