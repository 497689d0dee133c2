//! The test harness of every lab crate: `labs/labNN/tests/checks.rs` is one call of [`run`],
//! which makes one test per exercise of the lab's table, named `exercise_N_M_function`, with
//! libtest's command line (`cargo test -p lab02 exercise_2_2`, `--exact`, `--list`). A new
//! exercise in the table is a new test; nothing else is written by hand.
//!
//! Hidden exercises are tests only when the lab crate is built with its `hidden-exercises`
//! feature, as `raylab grade` builds it: the handout's `cargo test` does not run them.

use std::path::Path;
use std::sync::Arc;

use libtest_mimic::{Arguments, Failed, Trial};

use super::{Exercise, LabContext, LabId, Visibility, run_exercise, verdict};
use pipeline::{LabSlots, Pipeline};

/// What a lab's checks run on.
pub struct LabChecks<S: ?Sized + 'static> {
    /// The lab.
    pub lab: LabId,
    /// The lab crate's directory (its `CARGO_MANIFEST_DIR`).
    pub lab_dir: &'static str,
    /// The lab's exercise table.
    pub exercises: Vec<Exercise<S>>,
    /// The code checked: the student's, or the reference solution.
    pub subject: Arc<S>,
    /// The pipeline for everything else (`reference::pipeline(lab)`).
    pub base: Pipeline,
    /// The labs whose slot of `base` is the answer key (`reference::KEYS`).
    pub key_labs: &'static [u32],
    /// Whether hidden exercises are tests too (the `hidden-exercises` feature).
    pub hidden: bool,
}

/// Runs the tests the command line asks for, one per exercise, and exits with libtest's
/// status. Under `raylab grade` a test ends its process with the check's verdict record
/// ([`verdict`]) instead.
pub fn run<S: ?Sized + LabSlots + Send + Sync + 'static>(checks: LabChecks<S>) -> ! {
    let args = Arguments::from_args();
    let LabChecks {
        lab,
        lab_dir,
        exercises,
        subject,
        base,
        key_labs,
        hidden,
    } = checks;
    // Where the tree lacks this lab's solution, the student's own code is the base of the
    // lab's other exercises.
    let ctx = Arc::new(
        LabContext::new(lab, Path::new(lab_dir), base)
            .with_key_labs(key_labs)
            .with_own_code(&subject),
    );
    let exercises: Vec<Arc<Exercise<S>>> = exercises.into_iter().map(Arc::new).collect();
    let trials = exercises
        .iter()
        .filter(|e| hidden || e.visibility == Visibility::Visible)
        .map(|exercise| {
            let name = exercise.test_name();
            let (exercise, subject, ctx) = (exercise.clone(), subject.clone(), ctx.clone());
            Trial::test(name, move || check(&exercise, &subject, &ctx))
        })
        .collect();
    libtest_mimic::run(&args, trials).exit()
}

/// One exercise's test: the secret of the verdict record is taken before any student code
/// runs; the record, when asked for, ends the process.
fn check<S: ?Sized>(
    exercise: &Exercise<S>,
    subject: &Arc<S>,
    ctx: &LabContext,
) -> Result<(), Failed> {
    let channel = verdict::VerdictChannel::take();
    let outcome = run_exercise(exercise, subject, ctx);
    if let Some(channel) = channel {
        channel.report(&exercise.id, &outcome);
    }
    outcome.map_err(|f| Failed::from(f.message))
}
