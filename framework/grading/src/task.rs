//! A lab's program: the lab's test executable (`labs/labNN/tests/checks.rs`) also does the
//! command line's work that needs the lab's code. `raylab status`, `raylab render --pipeline
//! student` and the others build it (`cargo test -p labNN --no-run`) and run it with a
//! [`Task`] in [`TASK_VAR`]; so the command line links no lab's code, and a lab that does not
//! compile stops only its own row.

use std::io::Write;
use std::path::PathBuf;

use pipeline::Pipeline;
use pipeline::job::{RenderJob, ReportJob};
use serde::{Deserialize, Serialize};

use crate::verdict::Record;

/// Holds the task (JSON) when the command line runs a lab's program.
pub const TASK_VAR: &str = "RAYLAB_LAB_TASK";

/// The start of a line of a task's answer on standard output.
pub const ANSWER_TAG: &str = "RAYLAB-ANSWER ";

/// What the command line asks of a lab's program.
#[derive(Clone, Debug, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Task {
    /// Run every exercise's check (the hidden ones too when the program has them) and answer
    /// with one [`Record`] per exercise, in the table's order.
    Status,
    /// Do the render on the pipeline with the lab's code, the student's or the key's as the
    /// program was built, in the lab's slots.
    Render(RenderJob),
    /// Make the lab's report figures on that pipeline (a program built with the lab's
    /// `report` feature).
    Report(ReportJob),
    /// Record the lab's golden cases and snapshots from the answer key (a program built with
    /// the lab's `reference` feature) into this lab directory, and beside each snapshot image
    /// its PNG; answer with the paths written, one per line.
    Golden(PathBuf),
    /// Serve the page of `raylab view` until stopped (a program built with the lab's `view`
    /// feature).
    View(ViewJob),
}

/// `raylab view`: what the page shows and where it is served.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ViewJob {
    /// A built-in scene's name, a scene file (.toml) or an OBJ file.
    pub scene: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The seed of the first pass.
    pub seed: u64,
    /// The port on 127.0.0.1; 0 lets the system choose.
    pub port: u16,
    /// Whose code the program renders with, in words ("Student", "Reference").
    pub whose: String,
    /// Also render the answer key beside it, when the program holds it.
    pub compare: bool,
    /// End the program when its standard input closes: `raylab view` holds the other end,
    /// so the server ends with the command however the command ends.
    #[serde(default)]
    pub end_with_stdin: bool,
    /// A pixel the page inspects as it opens, in the difference view where there is one (the
    /// worst pixel of a failing image check).
    #[serde(default)]
    pub inspect: Option<[u32; 2]>,
}

/// What makes a lab's report in its program: the lab's figures (its checks' `report`
/// module) through the given pipeline.
pub type MakeReport = fn(&ReportJob, Pipeline) -> Result<(), raylab_core::Error>;

impl Task {
    /// The task the command line set, if any.
    ///
    /// # Panics
    /// When [`TASK_VAR`] holds no task: the command line and the program disagree.
    pub fn from_env() -> Option<Self> {
        let text = std::env::var(TASK_VAR).ok()?;
        Some(serde_json::from_str(&text).unwrap_or_else(|e| {
            panic!("{TASK_VAR} holds no task this program knows ({e}): rebuild it")
        }))
    }

    /// The task as the value of [`TASK_VAR`].
    pub fn to_env(&self) -> String {
        serde_json::to_string(self).expect("a task serializes")
    }
}

/// Prints one line of a task's answer.
pub fn answer(record: &Record) {
    let json = serde_json::to_string(record).expect("a record serializes");
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "\n{ANSWER_TAG}{json}");
    let _ = out.flush();
}

/// Prints one line of a task's answer that is not a record: a path written, say.
pub fn answer_line(line: &str) {
    let mut out = std::io::stdout().lock();
    let _ = writeln!(out, "\n{ANSWER_TAG}{line}");
    let _ = out.flush();
}

/// The lines of a program's answer, in the order printed.
pub fn answer_lines(output: &str) -> Vec<&str> {
    output
        .lines()
        .filter_map(|line| line.strip_prefix(ANSWER_TAG))
        .collect()
}

/// The records of a program's answer, in the order printed; lines that are not answers (the
/// student's code may print anything) are passed over.
pub fn answers(output: &str) -> Vec<Record> {
    answer_lines(output)
        .into_iter()
        .filter_map(|json| serde_json::from_str(json).ok())
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FailureKind;

    #[test]
    fn answers_survive_the_student_s_output() {
        let record = Record {
            exercise: "1.2".into(),
            passed: false,
            kind: Some(FailureKind::Blocked("1.1".into())),
            message: "line one\nline two".into(),
            reason: "line two".into(),
            key_for: vec!["1.1".into()],
        };
        let json = serde_json::to_string(&record).unwrap();
        let output = format!("noise{ANSWER_TAG}{{\"broken\nmore noise\n{ANSWER_TAG}{json}\ntail");
        assert_eq!(answers(&output), vec![record]);
        let task = Task::Status;
        assert!(matches!(
            serde_json::from_str::<Task>(&task.to_env()).unwrap(),
            Task::Status
        ));
    }
}
