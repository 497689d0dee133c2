//! Workspace-level test support: the mutant corpus (realistic wrong implementations each lab's
//! checks must reject, and alternative correct ones they must accept) and helpers to run a
//! lab's exercises on any implementation.

pub mod mutants;
pub mod workflow;

use std::path::{Path, PathBuf};
use std::sync::Arc;

use grading::{Exercise, LabContext, run_exercise};

use mutants::Verdict;

/// Each lab's checks crate under its lab's name.
pub mod lab_checks {
    pub use lab01_checks as lab01;
    pub use lab02_checks as lab02;
    pub use lab03_checks as lab03;
    pub use lab04_checks as lab04;
    pub use lab05_checks as lab05;
    pub use lab06_checks as lab06;
    pub use lab07_checks as lab07;
    pub use lab08_checks as lab08;
    pub use lab09_checks as lab09;
    pub use lab10_checks as lab10;
    pub use lab11_checks as lab11;
}

/// Calls `$each!(number, module, Contract, Key)` for every lab of the course: the tests' one
/// list of the labs' types (the contract `contracts::module::Contract`, the key
/// `reference::module::Key`, the stubs `::module::Student`, the corpus `mutants::module`).
/// `tests/tests/course.rs` checks it against `raylab_core::labs::COURSE`.
#[macro_export]
macro_rules! for_each_lab {
    ($each:ident) => {
        $each!(1, lab01, CameraRays, Lab01);
        $each!(2, lab02, Lab02, Lab02);
        $each!(3, lab03, Shadows, Lab03);
        $each!(4, lab04, Reflection, Lab04);
        $each!(5, lab05, Radiometry, Lab05);
        $each!(6, lab06, Radiosity, Lab06);
        $each!(7, lab07, Antialiasing, Lab07);
        $each!(8, lab08, PhotonMapping, Lab08);
        $each!(9, lab09, Texturing, Lab09);
        $each!(10, lab10, Fresnel, Lab10);
        $each!(11, lab11, AmbientOcclusion, Lab11);
    };
}

/// The mutant corpus of one lab as `judge` takes it: name, verdict and the implementation.
#[macro_export]
macro_rules! corpus {
    ($module:ident, $contract:ident) => {
        $crate::mutants::$module::variants()
            .into_iter()
            .map(|v| {
                (
                    v.name,
                    v.verdict,
                    std::sync::Arc::new(v) as std::sync::Arc<dyn contracts::$module::$contract>,
                )
            })
            .collect::<Vec<_>>()
    };
}

/// The directory of lab `lab`'s crate.
pub fn lab_dir(lab: u32) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("..")
        .join("labs")
        .join(format!("lab{lab:02}"))
}

/// The grading context of lab `lab` with the reference for everything else, every slot the
/// answer key.
pub fn context(lab: u32) -> LabContext {
    keyed_context(lab, reference::KEYS)
}

/// The grading context of lab `lab` with the reference for everything else and `keys` as the
/// labs whose slot counts as the answer key: without `lab` among them, the checks judge by
/// golden cases and properties alone, as in a handout before the lab's solution is released.
pub fn keyed_context(lab: u32, keys: &[u32]) -> LabContext {
    let id = grading::LabId::of(lab);
    let mut ctx = LabContext::new(id, &lab_dir(lab), reference::pipeline(lab)).with_key_labs(keys);
    ctx.failure_dir = std::env::temp_dir()
        .join(format!("raylab-tests-{}", std::process::id()))
        .join(format!("lab{lab:02}"));
    ctx
}

/// Runs every exercise on `subject`: `(exercise id, Ok or the failure message)`.
pub fn run_all<S: ?Sized>(
    exercises: &[Exercise<S>],
    subject: &Arc<S>,
    ctx: &LabContext,
) -> Vec<(&'static str, Result<(), String>)> {
    exercises
        .iter()
        .map(|e| {
            let outcome = run_exercise(e, subject, ctx).map_err(|f| f.message);
            (e.info.id.as_str(), outcome)
        })
        .collect()
}

/// Runs the corpus of one lab through its exercises, printing what each exercise rejects and
/// the rejection rate; returns the failures of the suite (empty when it discriminates: every
/// mistake rejected by its exercise, every alternative accepted by all).
pub fn judge<S: ?Sized>(
    lab: u32,
    exercises: &[Exercise<S>],
    variants: Vec<(&'static str, Verdict, Arc<S>)>,
) -> Vec<String> {
    judge_in(&context(lab), exercises, variants)
}

/// [`judge`] in the context `ctx` (with or without the answer key of its lab).
pub fn judge_in<S: ?Sized>(
    ctx: &LabContext,
    exercises: &[Exercise<S>],
    variants: Vec<(&'static str, Verdict, Arc<S>)>,
) -> Vec<String> {
    let (lab, number) = (ctx.lab, ctx.lab.number());
    let mut problems = Vec::new();
    let (mut wrong, mut rejected) = (0, 0);
    for (name, verdict, subject) in variants {
        match verdict {
            Verdict::Reject(id) => {
                wrong += 1;
                // A mistake is judged by its own exercise alone.
                let exercise = exercises
                    .iter()
                    .find(|e| e.id == id)
                    .expect("known exercise");
                match &run_exercise(exercise, &subject, ctx) {
                    Err(grading::Failure { message, .. }) => {
                        rejected += 1;
                        let first = message.lines().nth(1).unwrap_or_default();
                        println!("{lab} rejects  [{id}] {name}: {first}");
                    }
                    Ok(()) => problems.push(format!(
                        "lab {number}: exercise {id} accepts the mistake '{name}'"
                    )),
                }
            }
            Verdict::Accept => {
                for (id, r) in &run_all(exercises, &subject, ctx) {
                    match r {
                        Ok(()) => {}
                        Err(m) => problems.push(format!(
                            "lab {number}: exercise {id} rejects the correct '{name}':\n{m}"
                        )),
                    }
                }
                println!("{lab} accepts  {name}");
            }
        }
    }
    println!(
        "{lab}: {rejected}/{wrong} mistakes rejected ({:.0}%)",
        100.0 * rejected as f64 / wrong.max(1) as f64
    );
    problems
}
