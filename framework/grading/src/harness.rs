//! The test harness of every lab crate: `labs/labNN/tests/checks.rs` is one call of [`run`],
//! which makes one test per exercise of the lab's table, named `exercise_N_M_function`, with
//! libtest's command line (`cargo test -p lab02 exercise_2_2`, `--exact`, `--list`; [`cli`])
//! and output ([`printer`]). A new exercise in the table is a new test; nothing else is
//! written by hand.
//!
//! Hidden exercises are tests only when the lab crate is built with its `hidden-exercises`
//! feature, as `raylab grade` builds it: the handout's `cargo test` does not run them.

use std::path::Path;
use std::sync::Arc;

pub mod cli;
pub mod printer;
pub mod trials;

use trials::Trial;

use super::task::{self, MakeReport, Task};
use super::{Exercise, Judge, LabContext, LabId, Visibility, verdict};
use pipeline::Pipeline;

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
    /// The lab's report figures, when the program is built with them (the `report` feature).
    pub report: Option<MakeReport>,
    /// The generator of the lab's golden cases and snapshots, run on the answer key.
    pub generate_golden: GenerateGolden<S>,
}

/// Writes a lab's golden cases and snapshots from the answer key into the lab directory of the
/// context, and says which files it wrote.
pub type GenerateGolden<S> =
    fn(&Arc<S>, &LabContext) -> Result<Vec<std::path::PathBuf>, raylab_core::Error>;

/// Runs the tests the command line asks for, one per exercise, and exits with libtest's
/// status; or, run by `raylab` with a task ([`crate::task`]), does the task. Under `raylab grade` a test ends its process with the check's verdict record
/// ([`verdict`]) instead.
pub fn run<S: ?Sized + contracts::Mix + contracts::Part>(checks: LabChecks<S>) -> ! {
    let task = Task::from_env();
    let LabChecks {
        lab,
        lab_dir,
        exercises,
        subject,
        base,
        key_labs,
        hidden,
        report,
        generate_golden,
    } = checks;
    // Where the tree lacks this lab's solution, the student's own code is the base of the
    // lab's other exercises.
    let ctx = Arc::new(
        LabContext::new(lab, Path::new(lab_dir), base)
            .with_key_labs(key_labs)
            .with_own_code(&subject),
    );
    let exercises: Arc<[Arc<Exercise<S>>]> = exercises
        .into_iter()
        .filter(|e| hidden || e.visibility == Visibility::Visible)
        .map(Arc::new)
        .collect();
    match task {
        None => {}
        Some(Task::Status) => {
            let judge = Judge::new(&exercises, &subject, &ctx);
            for exercise in exercises.iter() {
                let judgement = judge.judge(exercise);
                task::answer(&verdict::Record::of(&exercise.id, &judgement));
            }
            std::process::exit(0)
        }
        Some(Task::Render(job)) => {
            finish(job.run(ctx.base.clone().with_part(subject)));
        }
        Some(Task::Report(job)) => {
            let Some(report) = report else {
                eprintln!("error: this program of {lab} was built without its `report` feature");
                std::process::exit(2)
            };
            finish(report(&job, ctx.base.clone().with_part(subject)));
        }
        Some(Task::View(job)) => {
            #[cfg(feature = "view")]
            {
                // The key beside the student's code, when the program holds it.
                let key = ctx.key().filter(|_| job.compare).cloned();
                finish(crate::view_task::serve(
                    &job,
                    ctx.base.clone().with_part(subject),
                    key,
                ));
            }
            #[cfg(not(feature = "view"))]
            {
                let _ = job;
                eprintln!("error: this program of {lab} was built without its `view` feature");
                std::process::exit(2)
            }
        }
        Some(Task::Golden(dir)) => {
            if !ctx.has_key(lab) {
                eprintln!("error: golden data comes from the answer key: build with `reference`");
                std::process::exit(2)
            }
            let ctx = LabContext::new(lab, &dir, ctx.base.clone());
            finish(generate_golden(&subject, &ctx).and_then(|written| {
                let pngs = crate::write_reference_pngs(&written)?;
                for path in written.iter().chain(&pngs) {
                    task::answer_line(&path.display().to_string());
                }
                Ok(())
            }));
        }
    }
    let arguments = cli::from_env();
    // One judge for every test: a verdict one test reached (a callee's, for a check that calls
    // other exercises' functions) is not reached again by another.
    let judge = Arc::new(Judge::new(&exercises, &subject, &ctx));
    let trials = exercises
        .iter()
        .map(|exercise| {
            let name = exercise.test_name();
            let (exercise, judge) = (exercise.clone(), judge.clone());
            Trial::test(name, move || check(&exercise, &judge))
        })
        .collect();
    let colored = printer::colors_on_stdout(arguments.color);
    let conclusion = trials::run(&arguments, trials, std::io::stdout(), colored);
    std::process::exit(conclusion.exit_code())
}

/// The answer key of `lab` in `base` (the program built with the lab's `reference` feature);
/// where the tree does not hold it (a handout before its release), the program ends, saying so.
pub fn key_of<S: ?Sized + Send + Sync + 'static>(lab: LabId, base: &Pipeline) -> Arc<S> {
    base.part::<S>().unwrap_or_else(|| {
        eprintln!(
            "error: the solution of {lab} is not in this tree (it is not released yet), so \
             `--features reference` has nothing to check; `cargo test -p {lab}` checks your own code"
        );
        std::process::exit(1)
    })
}

/// The whole of a lab's program, `labs/labNN/tests/checks.rs`: `grading::lab_program!(lab03,
/// lab03_checks, reference);` names its lab crate, its checks crate and the answer key's crate
/// (the macro names no crate its caller does not: grading depends on none of them); the lab's
/// contract is `contracts::lab03::Contract`.
/// The program checks the student's code (`labNN::Student`), or with the lab's `reference`
/// feature the answer key, in `reference::pipeline`, with the lab's report figures when built
/// with its `report` feature.
#[macro_export]
macro_rules! lab_program {
    ($lab:ident, $checks:ident, $key:ident) => {
        fn main() {
            let lab = $checks::checks::LAB;
            let base = $key::pipeline(lab.number());
            #[cfg(feature = "reference")]
            let subject = $crate::harness::key_of::<::contracts::$lab::Contract>(lab, &base);
            #[cfg(not(feature = "reference"))]
            let subject: ::std::sync::Arc<::contracts::$lab::Contract> =
                ::std::sync::Arc::new($lab::Student);
            $crate::harness::run($crate::harness::LabChecks {
                lab,
                lab_dir: env!("CARGO_MANIFEST_DIR"),
                exercises: $checks::checks::exercises(),
                subject,
                base,
                key_labs: $key::KEYS,
                hidden: cfg!(feature = "hidden-exercises"),
                #[cfg(feature = "report")]
                report: Some($checks::report::make),
                #[cfg(not(feature = "report"))]
                report: None,
                generate_golden: $checks::generate_golden,
            })
        }
    };
}

/// Ends a task's process: 0 when it succeeded, 1 with the error on standard error.
fn finish(outcome: Result<(), raylab_core::Error>) -> ! {
    match outcome {
        Ok(()) => std::process::exit(0),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1)
        }
    }
}

/// One exercise's test, judged by the lab's [`Judge`] (a mistake charged to its own
/// exercise): the secret of the verdict record is taken before any student code runs; the
/// record, when asked for, ends the process.
fn check<S: ?Sized + contracts::Mix + contracts::Part>(
    exercise: &Exercise<S>,
    judge: &Judge<S>,
) -> Result<(), String> {
    let channel = verdict::VerdictChannel::take();
    let judgement = judge.judge(exercise);
    if let Some(channel) = channel {
        channel.report(&exercise.id, &judgement);
    }
    judgement.outcome.map_err(|f| f.message)
}
