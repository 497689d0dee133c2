//! A lab's program: its test executable, built by cargo and run with a task
//! ([`grading::task`]). The command line does every piece of work that needs a lab's code this
//! way, so it links no lab: a lab that does not compile stops only what needs that lab.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use course::LabId;
use grading::task::Task;
use raylab_core::Error;

use crate::checkout::workspace_root;

/// The cargo that runs this command (`cargo run` says which), else the one on the `PATH`.
fn cargo() -> Command {
    Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
}

/// A lab's built program.
pub struct LabProgram {
    /// Its test executable.
    pub executable: PathBuf,
}

/// Why a lab's program could not be built.
#[derive(Debug)]
pub enum BuildFailure {
    /// The lab's code (or its checks) does not compile: the compiler's first error.
    Compile(String),
    /// Cargo itself could not be run, or said nothing usable.
    Cargo(Error),
}

impl std::fmt::Display for BuildFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Compile(first) => write!(f, "does not compile:\n{first}"),
            Self::Cargo(e) => write!(f, "{e}"),
        }
    }
}

impl LabProgram {
    /// Builds lab `lab`'s program with the lab crate's `features` (`cargo test -p labNN --test
    /// checks --no-run`); cargo's progress goes to standard error as it builds.
    pub fn build(lab: LabId, features: &[&str]) -> Result<Self, BuildFailure> {
        Self::build_in(&workspace_root(), lab, features)
    }

    /// [`Self::build`] in the workspace at `root`.
    pub fn build_in(root: &Path, lab: LabId, features: &[&str]) -> Result<Self, BuildFailure> {
        let mut command = cargo();
        command
            .current_dir(root)
            .args([
                "test",
                "--no-run",
                "--message-format=json",
                "--test",
                "checks",
            ])
            .arg("-p")
            .arg(lab.to_string())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped());
        if !features.is_empty() {
            command.arg("--features").arg(features.join(","));
        }
        let failed = |e: std::io::Error| {
            BuildFailure::Cargo(Error::Failed {
                what: format!("cargo test -p {lab} --no-run"),
                reason: format!("could not run cargo: {e}"),
            })
        };
        let mut child = command.spawn().map_err(failed)?;
        // Cargo's own lines ("Compiling …") pass through; the compiler's messages come as JSON.
        let stderr = child.stderr.take().expect("piped");
        let relay = std::thread::spawn(move || {
            let mut last = Vec::new();
            for line in BufReader::new(stderr).lines().map_while(Result::ok) {
                if line.trim_start().starts_with("Compiling") {
                    eprintln!("{line}");
                }
                last.push(line);
            }
            last
        });
        let mut executable = None;
        let mut first_error = None;
        for line in BufReader::new(child.stdout.take().expect("piped"))
            .lines()
            .map_while(Result::ok)
        {
            let Ok(message) = serde_json::from_str::<serde_json::Value>(&line) else {
                continue;
            };
            match message["reason"].as_str() {
                Some("compiler-artifact") if message["target"]["name"] == "checks" => {
                    if let Some(path) = message["executable"].as_str() {
                        executable = Some(PathBuf::from(path));
                    }
                }
                Some("compiler-message")
                    if first_error.is_none() && message["message"]["level"] == "error" =>
                {
                    first_error = message["message"]["rendered"].as_str().map(str::to_string);
                }
                _ => {}
            }
        }
        let status = child.wait().map_err(failed)?;
        let cargo_said = relay.join().unwrap_or_default();
        match (executable, status.success()) {
            (Some(executable), true) => Ok(Self { executable }),
            _ => Err(match first_error {
                Some(error) => BuildFailure::Compile(error.trim_end().to_string()),
                None => BuildFailure::Cargo(Error::Failed {
                    what: format!("cargo test -p {lab} --no-run"),
                    reason: cargo_said.join("\n"),
                }),
            }),
        }
    }

    /// The program, ready to run `task` (in the working directory of this command, where the
    /// task's relative paths lead).
    pub fn command(&self, task: &Task) -> Command {
        let mut command = Command::new(&self.executable);
        command.env(grading::task::TASK_VAR, task.to_env());
        command
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Messages show paths below the workspace's root (Dolos's `target/dolos`, say): without
    /// `..` in them, they are the paths to type.
    #[test]
    fn the_workspace_root_is_named_without_parent_steps() {
        let root = workspace_root();
        assert!(
            root.join("labs/raylab/Cargo.toml").is_file(),
            "{}",
            root.display()
        );
        assert!(
            !root
                .components()
                .any(|c| c == std::path::Component::ParentDir),
            "{}",
            root.display()
        );
    }
}
