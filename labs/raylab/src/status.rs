//! `raylab status`: which exercises of each lab pass with the student's code, and which to do
//! next.

use course::LabId;
use std::path::PathBuf;
use std::sync::Arc;

use clap::Args;
use grading::{Exercise, FailureKind, LabContext, Visibility, run_exercise};
use pipeline::LabSlots;
use raylab_core::Error;

use crate::students::{LabCode, LabVisitor};

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

/// Runs a lab's exercises on the student's code.
struct Judge;

impl LabVisitor for Judge {
    type Output = Vec<(String, String, u32, State)>;

    fn visit<S: ?Sized + LabSlots + Send + Sync + 'static>(self, code: LabCode<S>) -> Self::Output {
        judge(code.number, &code.exercises, code.student)
    }
}

fn judge<S: ?Sized + LabSlots>(
    lab: LabId,
    exercises: &[Exercise<S>],
    student: Arc<S>,
) -> Vec<(String, String, u32, State)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join(format!("{lab}"));
    let ctx = LabContext::new(lab, &dir, reference::pipeline(lab.number()))
        .with_key_labs(reference::KEYS)
        .with_own_code(&student);
    exercises
        .iter()
        // A handout has no tests for hidden exercises; the instructor's tree shows them all.
        .filter(|e| cfg!(feature = "instructor") || e.visibility == Visibility::Visible)
        .map(|e| {
            let state = match run_exercise(e, &student, &ctx) {
                Ok(()) => State::Passed,
                Err(f) => match f.kind {
                    FailureKind::NotStarted => State::NotStarted,
                    FailureKind::Blocked(other) => State::Blocked(other),
                    FailureKind::Waiting(lab) => State::Waiting(lab),
                    FailureKind::Crashed | FailureKind::Wrong => {
                        State::Failing(f.reason.lines().next().unwrap_or_default().to_string())
                    }
                },
            };
            (e.id.to_string(), e.function.to_string(), e.points, state)
        })
        .collect()
}

/// Runs `raylab status`.
pub fn run(args: &StatusArgs) -> Result<(), Error> {
    let labs: Vec<LabId> = match args.lab {
        Some(l) => {
            crate::students::check_lab(l)?;
            vec![l]
        }
        None => crate::students::labs(),
    };
    let mut next: Option<String> = None;
    for lab in labs {
        let rows = crate::students::visit(lab, Judge)?;
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
            crate::students::exercises(lab)
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
        for (id, function, points, state) in &rows {
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
                    "Exercise {id} (`{function}` in labs/{lab}/src/lib.rs, docs/{lab}.md); check it with `cargo test -p {lab} exercise_{}`; stuck? `raylab hint {id}`",
                    id.replace('.', "_")
                ));
            }
        }
    }
    match next {
        Some(n) => println!("\nnext: {n}"),
        None => println!("\nevery exercise passes"),
    }
    Ok(())
}
