//! The grading library: exercises and how they are run, property checks, golden cases and
//! snapshot comparison. A lab crate's `cargo test`, the reference's CI run and `raylab grade`
//! all go through [`run_exercise`], so they judge student code the same way.

mod charged_once;
pub mod chi2;
pub mod corpus;
mod golden;
pub mod graded;
pub mod harness;
pub mod part_snapshots;
pub mod prerequisite;
mod property;
pub mod radiometry;
pub mod scenes;
mod snapshot;
pub mod stats;
mod strata;
pub mod strategies;
pub mod task;
pub mod verdict;
#[cfg(feature = "view")]
pub mod view_task;

pub use charged_once::{Judge, Judgement, judge};
pub use course::{DeniedItem, ExerciseInfo, LabId, Visibility};
pub use golden::{GoldenCase, GoldenFile, compare_f32, compare_vec2, compare_vec3};
pub use property::{for_all, for_all_named};
pub use snapshot::{
    PixelTolerance, SnapshotReport, compare_snapshot, mark_non_finite, write_failure_images,
    write_reference_pngs,
};
pub use strata::{StrataNames, cell_name, cell_of, check_one_per_cell};

use std::path::{Path, PathBuf};
use std::sync::Arc;

use pipeline::Pipeline;

/// The check of one exercise: `Ok` when the student's code is right, otherwise what is wrong.
pub type Check<S> = fn(&Arc<S>, &LabContext) -> Result<(), String>;

/// One exercise of a lab: its row of the lab's exercise table (`labs/labNN/exercises.toml`)
/// and its check.
pub struct Exercise<S: ?Sized> {
    /// What the table says of it: number, function, title, points, visibility, hint.
    pub info: &'static ExerciseInfo,
    /// The check.
    pub check: Check<S>,
}

impl<S: ?Sized> std::ops::Deref for Exercise<S> {
    type Target = ExerciseInfo;

    fn deref(&self) -> &ExerciseInfo {
        self.info
    }
}

/// `[("exercise_1_1", exercise_1_1), …]`: a lab's checks by the names of their functions,
/// `exercise_N_M` for Exercise N.M, for [`exercises`].
#[macro_export]
macro_rules! checks {
    ($($check:ident),* $(,)?) => {
        vec![$((stringify!($check), $check as $crate::Check<_>)),*]
    };
}

/// The exercises of lab `lab`: every row of its table with the check named for it
/// (`exercise_N_M`, see [`checks!`](crate::checks)), in the table's order.
///
/// # Panics
/// When the table does not parse, or a row has no check or a check no row: the lab's checks
/// and its table disagree, which `cargo test` shows its author at once.
pub fn exercises<S: ?Sized>(lab: LabId, checks: Vec<(&'static str, Check<S>)>) -> Vec<Exercise<S>> {
    let table = course::lab(lab).unwrap_or_else(|e| panic!("{e}"));
    let name = |id: &str| format!("exercise_{}", id.replace('.', "_"));
    if let Some((orphan, _)) = checks
        .iter()
        .find(|(c, _)| !table.exercises.iter().any(|e| name(&e.id) == *c))
    {
        panic!(
            "{lab}'s check `{orphan}` has no row in {}/exercises.toml",
            lab.folder()
        );
    }
    table
        .exercises
        .iter()
        .map(|info| Exercise {
            info,
            check: checks
                .iter()
                .find(|(c, _)| *c == name(&info.id))
                .unwrap_or_else(|| {
                    panic!(
                        "Exercise {} of {}/exercises.toml has no check `{}` in its lab's checks",
                        info.id,
                        lab.folder(),
                        name(&info.id)
                    )
                })
                .1,
        })
        .collect()
}

/// Where a lab's data lives and what the rest of the pipeline is.
#[derive(Clone)]
pub struct LabContext {
    /// The lab.
    pub lab: LabId,
    /// The lab crate's directory (holding `golden/` and `snapshots/`).
    pub lab_dir: PathBuf,
    /// Where failing checks write their images.
    pub failure_dir: PathBuf,
    /// The pipeline for everything that is not this lab (the reference, where present).
    pub base: Pipeline,
    /// The labs whose slot of `base` is the answer key (`reference::KEYS`); a slot of any other
    /// lab holds the student's own code (a handout before that lab's solution is released).
    pub key_labs: Vec<LabId>,
}

impl LabContext {
    /// The context of lab `lab` whose crate lives in `lab_dir` (its `CARGO_MANIFEST_DIR`).
    /// Failure images go to `$CARGO_TARGET_DIR/raylab-failures/labNN` (default target dir:
    /// `target/` at the workspace root).
    pub fn new(lab: LabId, lab_dir: &Path, base: Pipeline) -> Self {
        // The workspace's `target/`, two levels above the lab's directory, named without `..`:
        // failure messages show the images' paths.
        let target = std::env::var_os("CARGO_TARGET_DIR")
            .map(PathBuf::from)
            .unwrap_or_else(|| match lab_dir.ancestors().nth(2) {
                Some(root) if lab_dir.is_absolute() => root.join("target"),
                _ => lab_dir.join("../../target"),
            });
        Self {
            lab,
            lab_dir: lab_dir.to_path_buf(),
            failure_dir: target.join("raylab-failures").join(lab.to_string()),
            base,
            key_labs: Vec::new(),
        }
    }

    /// This context with `labs` as the labs whose slot of `base` is the answer key (pass
    /// `reference::KEYS`). Without it no slot counts as the key, and the checks judge by golden
    /// cases and properties alone.
    pub fn with_key_labs(mut self, labs: &[u32]) -> Self {
        self.key_labs = labs.iter().filter_map(|&n| LabId::new(n)).collect();
        self
    }

    /// This context with `student`, the code checked, in `base`'s slots of this lab where they
    /// are not the answer key (a handout before the lab's solution is released): the base of
    /// the lab's other exercises is then the student's own code. Call after
    /// [`Self::with_key_labs`].
    pub fn with_own_code<S: ?Sized + contracts::Part>(mut self, student: &Arc<S>) -> Self {
        if !self.has_key(self.lab) {
            self.base = self.base.with_part(student.clone());
        }
        self
    }

    /// Whether `base`'s slot of lab `lab` is the answer key.
    pub fn has_key(&self, lab: LabId) -> bool {
        self.key_labs.contains(&lab)
    }

    /// The answer key of this context's lab: `base`, when its slot of the lab is the key. A
    /// check compares the student's function with the key's on random inputs when it is
    /// present, and relies on golden cases and properties when it is not.
    pub fn key(&self) -> Option<&Pipeline> {
        self.has_key(self.lab).then_some(&self.base)
    }

    /// The answer key's code of the contract `S`, when the context holds the key
    /// ([`Self::key`]).
    pub fn key_code<S: ?Sized + Send + Sync + 'static>(&self) -> Option<Arc<S>> {
        self.key().map(|k| k.code::<S>())
    }

    /// Path of a golden-case file of this lab.
    pub fn golden_path(&self, name: &str) -> PathBuf {
        self.lab_dir.join("golden").join(name)
    }

    /// Path of a snapshot image of this lab.
    pub fn snapshot_path(&self, name: &str) -> PathBuf {
        self.lab_dir.join("snapshots").join(name)
    }

    /// The golden-case file `name` of this lab (`golden/NAME`); an error says how to restore
    /// it.
    pub fn golden<I, O>(&self, name: &str) -> Result<GoldenFile<I, O>, String>
    where
        I: serde::Serialize + serde::de::DeserializeOwned,
        O: serde::Serialize + serde::de::DeserializeOwned,
    {
        GoldenFile::load(&self.golden_path(name))
            .map_err(|e| self.unreadable(&format!("golden/{name}"), e))
    }

    /// Records `f` (the reference) on `inputs` as the golden-case file `name` of exercise
    /// `exercise` of this lab (`raylab golden`), and says which file.
    pub fn record_golden<I, O>(
        &self,
        name: &str,
        exercise: &str,
        inputs: &[I],
        f: impl Fn(&I) -> O,
    ) -> Result<PathBuf, raylab_core::Error>
    where
        I: Clone + serde::Serialize + serde::de::DeserializeOwned,
        O: serde::Serialize + serde::de::DeserializeOwned,
    {
        let path = self.golden_path(name);
        GoldenFile::record(exercise, inputs, f).save(&path)?;
        Ok(path)
    }

    /// The message of this lab's file `relative` (`golden/x.json`, `snapshots/y.exr`) that
    /// cannot be read, `error`: the file comes with the lab, and the handout is a git
    /// repository, so the command that puts it back as it was handed out.
    pub fn unreadable(&self, relative: &str, error: impl std::fmt::Display) -> String {
        format!(
            "{error}; the file comes with the lab: restore it with `git checkout -- {}/{relative}`",
            self.lab.folder()
        )
    }
}

/// Runs one exercise's check on `subject`, turning panics (an unfinished stub, an index out of bounds …)
/// into a failure. The failure's kind says what happened; its message names the exercise, the
/// function to fix, and the docs.
pub fn run_exercise<S: ?Sized>(
    exercise: &Exercise<S>,
    subject: &Arc<S>,
    ctx: &LabContext,
) -> Result<(), Failure> {
    let outcome = match raylab_core::quietly(|| {
        raylab_core::catch_panic(|| (exercise.check)(subject, ctx))
    }) {
        Ok(result) => result,
        Err(panic) => Err(match panic.location {
            Some(at) => format!("panicked at {at}: {}", panic.message),
            None => format!("panicked: {}", panic.message),
        }),
    };
    outcome.map_err(|reason| failure(exercise.info, reason))
}

/// The failure of `exercise` whose check (or the code it ran) said `reason`: a panic of an
/// unfinished stub is the exercise not started, or blocked by the exercise whose stub it is.
fn failure(exercise: &ExerciseInfo, reason: String) -> Failure {
    let lab = exercise.lab;
    let place = format!(
        "Exercise {} — `{}` ({}) in {}",
        exercise.id,
        exercise.function,
        exercise.title,
        lab.source()
    );
    let docs = format!("see {}, Exercise {}", lab.docs(), exercise.id);
    let (kind, message) = if let Some(other) = waiting_lab(&reason) {
        (
            FailureKind::Waiting(other),
            format!(
                "{place} cannot be checked until lab {other}'s solution is released: the check needs its code ({reason}).\n({docs})"
            ),
        )
    } else if reason.contains(contracts::wire::OUT_OF_WORK) {
        (
            FailureKind::TimedOut,
            format!("{place} timed out: {reason}\n({docs})"),
        )
    } else {
        match unfinished_exercise(&reason) {
            Some(other) if other == exercise.id => (
                FailureKind::NotStarted,
                format!("{place} is not implemented yet.\n({docs})"),
            ),
            Some(other) => (
                FailureKind::Blocked(other.to_string()),
                format!(
                    "{place} cannot be checked until Exercise {other} is done (it is not implemented yet: {reason}).\n({docs})"
                ),
            ),
            None if is_crash(&reason) => (
                FailureKind::Crashed,
                format!("{place} failed: {reason}\n({docs})"),
            ),
            None => (
                FailureKind::Wrong,
                format!("{place} is wrong:\n{reason}\n({docs})"),
            ),
        }
    };
    Failure {
        exercise: exercise.id.clone(),
        kind,
        reason,
        message,
    }
}

/// Whether a check's failure is a panic of the code it ran: raised in the check itself
/// ("panicked at …") or caught by a framework component the check called and returned as its
/// error (a render's "rendering 'default' panicked: …", a [`raylab_core::PanicError`]).
fn is_crash(reason: &str) -> bool {
    reason.starts_with("panicked")
        || reason
            .lines()
            .next()
            .is_some_and(|first| first.contains(" panicked: "))
}

/// What became of a check that did not accept the student's code.
#[derive(Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FailureKind {
    /// The exercise's own stub is unfinished (`todo!()`).
    NotStarted,
    /// The check met the unfinished stub of another exercise, this one (`"2.1"`).
    Blocked(String),
    /// The check needs the code of another lab (this one) whose solution the tree does not
    /// hold yet (a [`contracts::Waiting`] slot).
    Waiting(u32),
    /// The student's code (or the check, on its output) panicked.
    Crashed,
    /// The student's code ran past its budget of work (`contracts::wire::OUT_OF_WORK`: an
    /// endless loop, stopped after the same work on every machine).
    TimedOut,
    /// The check ran to its end and rejected the answer.
    Wrong,
}

/// A check's failure, as data: what happened, to which exercise, and the message for the
/// student.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Failure {
    /// The exercise, e.g. `"2.2"`.
    pub exercise: String,
    /// What happened.
    pub kind: FailureKind,
    /// What the check (or the panic) said.
    pub reason: String,
    /// The whole message: the exercise's place, what happened, the reason and the docs.
    pub message: String,
}

impl Failure {
    /// This failure with `note` after its message (and its reason).
    pub fn with_note(mut self, note: String) -> Self {
        self.reason = format!("{}\n{note}", self.reason);
        self.message = format!("{}\n{note}", self.message);
        self
    }
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// The lab a [`contracts::Waiting`] slot's panic in `message` names, if it holds one.
fn waiting_lab(message: &str) -> Option<u32> {
    let rest =
        &message[message.find(contracts::WAITING_FOR_LAB)? + contracts::WAITING_FOR_LAB.len()..];
    let end = rest
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(rest.len());
    rest[..end].parse().ok()
}

/// The exercise named by an unfinished stub's panic ("not yet implemented: Exercise N.M: …"),
/// if `message` holds one.
fn unfinished_exercise(message: &str) -> Option<&str> {
    let rest = &message[message.find("not yet implemented: Exercise ")? + 30..];
    let end = rest
        .find(|c: char| !(c.is_ascii_digit() || c == '.'))
        .unwrap_or(rest.len());
    Some(rest[..end].trim_end_matches('.'))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_failure_says_what_became_of_the_check() {
        let info = &course::lab(LabId::of(1)).unwrap().exercises[2];
        let id = info.id.clone();
        let kind = |reason: &str| {
            let f = failure(info, reason.to_string());
            assert_eq!(f.exercise, id);
            assert!(
                f.message.starts_with(&format!("Exercise {id} ")),
                "{}",
                f.message
            );
            assert!(f.message.contains("docs/lab01.md"), "{}", f.message);
            f.kind
        };
        assert_eq!(kind("expected 1, got 2"), FailureKind::Wrong);
        assert_eq!(
            kind("panicked at labs/lab01/src/lib.rs:3:5: index out of bounds"),
            FailureKind::Crashed
        );
        assert_eq!(
            kind(&format!(
                "panicked at x.rs:1:1: not yet implemented: Exercise {id}: the field of view"
            )),
            FailureKind::NotStarted
        );
        assert_eq!(
            kind("panicked at x.rs:1:1: not yet implemented: Exercise 1.1: pixel to image plane"),
            FailureKind::Blocked("1.1".into())
        );
        let waiting = contracts::Waiting::<dyn contracts::lab02::Shading>::new(2);
        let panic = raylab_core::catch_panic(|| -> () { waiting.unavailable("shade") })
            .unwrap_err()
            .message;
        assert_eq!(kind(&format!("panicked: {panic}")), FailureKind::Waiting(2));
        // A wrong answer is wrong, even when a later line of its reason speaks of a panic.
        assert_eq!(
            kind("the image differs\n  (a pixel's code panicked: see the z-score image)"),
            FailureKind::Wrong
        );
        assert_eq!(
            kind(&format!(
                "rendering 'default' panicked: {} for one call: 10 units",
                contracts::wire::OUT_OF_WORK
            )),
            FailureKind::TimedOut
        );
    }

    #[test]
    fn a_panic_caught_by_a_component_the_check_called_is_a_crash() {
        let render = raylab_core::PanicError {
            context: "rendering 'default'".into(),
            message: "a bug".into(),
        };
        assert!(is_crash(&render.to_string()));
        assert!(is_crash("panicked at labs/lab01/src/lib.rs:3:5: boom"));
        // A wrong answer stays wrong, even when a later line of its reason speaks of a panic.
        assert!(!is_crash("expected 0.5, got 0.25"));
        assert!(!is_crash(
            "the image differs\n  (a pixel's code panicked: see the z-score image)"
        ));
    }
}
