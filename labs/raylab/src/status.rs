//! `raylab status`: which exercises of each lab pass with the student's code, and which to do
//! next.

use std::process::Stdio;

use clap::Args;
use course::LabId;
use grading::task::{self, Task};
use grading::{FailureKind, Visibility};
use raylab_core::Error;

use crate::lab_program::LabProgram;

/// Options of `raylab status`.
#[derive(Args, Debug)]
pub struct StatusArgs {
    /// Only this lab (default: every lab).
    #[arg(long)]
    pub lab: Option<LabId>,
}

/// The outcome of one exercise.
enum State {
    Passed,
    NotStarted,
    Blocked(String),
    /// Needs the code of this lab, whose solution is not released yet.
    Waiting(u32),
    Failing(String),
}

/// One exercise's row: its number, function, points, state, and the command that runs its test.
type Row = (String, String, u32, State, String);

/// Runs lab `lab`'s exercises on the student's code in the lab's program: a row per exercise
/// of its table, or why the program did not build or run.
fn judge(lab: LabId) -> Result<Vec<Row>, String> {
    // A handout has no tests for hidden exercises; the instructor's tree shows them all.
    let features: &[&str] = if cfg!(feature = "instructor") {
        &["hidden-exercises"]
    } else {
        &[]
    };
    let program = LabProgram::build(lab, features).map_err(|e| e.to_string())?;
    let output = program
        .command(&Task::Status)
        .current_dir(crate::checkout::workspace_root().join(lab.folder()))
        .stdin(Stdio::null())
        .stderr(Stdio::null())
        .output()
        .map_err(|e| format!("could not run {}: {e}", program.executable.display()))?;
    let records = task::answers(&String::from_utf8_lossy(&output.stdout));
    let exercises = crate::labs::exercises(lab);
    Ok(exercises
        .iter()
        .filter(|e| cfg!(feature = "instructor") || e.visibility == Visibility::Visible)
        .map(|e| {
            let state = match records.iter().find(|r| r.exercise == e.id) {
                Some(r) if r.passed => State::Passed,
                Some(r) => match &r.kind {
                    Some(FailureKind::NotStarted) => State::NotStarted,
                    Some(FailureKind::Blocked(other)) => State::Blocked(other.clone()),
                    Some(FailureKind::Waiting(lab)) => State::Waiting(*lab),
                    _ => State::Failing(r.reason.lines().next().unwrap_or_default().into()),
                },
                // The program ended before this exercise's record: an exit or a crash of the
                // code an earlier check ran, or of this one.
                None => State::Failing(format!(
                    "the checks stopped before this exercise ({}): run `{}`",
                    output.status,
                    e.test_command()
                )),
            };
            (
                e.id.to_string(),
                e.function.to_string(),
                e.points,
                state,
                e.test_command(),
            )
        })
        .collect())
}

/// Runs `raylab status`: lab by lab, each built, run and printed before the next is built.
pub fn run(args: &StatusArgs) -> Result<(), Error> {
    let labs: Vec<LabId> = match args.lab {
        Some(l) => {
            crate::labs::check_lab(l)?;
            vec![l]
        }
        None => crate::labs::labs(),
    };
    let mut next: Option<String> = None;
    let mut broken = Vec::new();
    for lab in labs {
        let rows = match judge(lab) {
            Ok(rows) => rows,
            Err(why) => {
                println!("{lab}  not checked: its code {why}\n");
                broken.push(lab);
                continue;
            }
        };
        let earned: u32 = rows
            .iter()
            .filter(|r| matches!(r.3, State::Passed))
            .map(|r| r.2)
            .sum();
        let total: u32 = rows.iter().map(|r| r.2).sum();
        // A handout runs the visible exercises only; grading adds the hidden ones.
        let hidden: u32 = if cfg!(feature = "instructor") {
            0
        } else {
            crate::labs::exercises(lab)
                .iter()
                .filter(|e| e.visibility == Visibility::Hidden)
                .map(|e| e.points)
                .sum()
        };
        match hidden {
            0 => println!("{lab}  {earned}/{total} points"),
            h => {
                println!("{lab}  {earned}/{total} points (+{h} hidden points, checked when graded)")
            }
        }
        for (id, function, points, state, test) in &rows {
            let (mark, detail) = match state {
                State::Passed => ("passed     ", String::new()),
                State::NotStarted => ("not started", String::new()),
                State::Blocked(other) => {
                    ("waiting    ", format!("  (needs Exercise {other} first)"))
                }
                State::Waiting(other) => (
                    "waiting    ",
                    format!("  (needs lab {other}'s solution, not released yet)"),
                ),
                State::Failing(why) => ("failing    ", format!("  {why}")),
            };
            println!("  {id:<5} {mark} {function:<26} {points} pt{detail}");
            if next.is_none() && !matches!(state, State::Passed) {
                next = Some(format!(
                    "Exercise {id} (`{function}` in labs/{lab}/src/lib.rs, docs/{lab}.md); check it with `{test}`; stuck? `cargo run -p raylab -- hint {id}`"
                ));
            }
        }
    }
    match next {
        Some(n) => println!("\nnext: {n}"),
        None if broken.is_empty() => println!("\nevery exercise passes"),
        None => {}
    }
    if let Some(first) = broken.first() {
        println!(
            "\n{} not checked: fix the first error above, then `cargo test -p {first}`",
            broken
                .iter()
                .map(LabId::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    Ok(())
}
