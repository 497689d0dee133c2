//! One mistake, one exercise: an exercise whose check calls functions of other exercises (1.6
//! renders through all of 1.1–1.5) is judged again with the answer key in place of each of
//! those whose own exercise fails — round after round, each adding the failing functions the
//! last round called, until a round passes or adds none — so that a mistake costs the points of
//! its own exercise only. Every run the judge makes is a run of its own
//! (`contracts::wire::begin_run`): the student's code keeps no state from one to the next.

use std::collections::HashMap;
use std::sync::{Arc, Mutex, PoisonError};

use contracts::{CallLog, Mix};

use crate::{Exercise, Failure, FailureKind, LabContext, run_exercise};

/// What the judge decided about an exercise, and on whose code.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Judgement {
    /// The verdict.
    pub outcome: Result<(), Failure>,
    /// The exercises whose functions were the answer key's in the run that decided the
    /// verdict, in the table's order: empty when the student's code alone was judged.
    pub key_for: Vec<String>,
    /// One sentence saying so when [`Self::key_for`] is not empty (a failure's message holds
    /// it too); empty otherwise.
    pub note: String,
}

impl Judgement {
    fn alone(outcome: Result<(), Failure>) -> Self {
        Self {
            outcome,
            key_for: Vec::new(),
            note: String::new(),
        }
    }
}

/// Judges the exercises of a lab on one student's code, each exercise once: a verdict is kept
/// and given again, also to the judgements of the exercises whose checks call its function.
pub struct Judge<S: ?Sized> {
    table: Vec<Arc<Exercise<S>>>,
    subject: Arc<S>,
    ctx: Arc<LabContext>,
    judged: Mutex<HashMap<String, Judgement>>,
}

/// Judges `exercise` of `table` on `subject` once (see [`Judge`]).
pub fn judge<S: ?Sized + Mix + 'static>(
    exercise: &Exercise<S>,
    table: &[Arc<Exercise<S>>],
    subject: &Arc<S>,
    ctx: &LabContext,
) -> Judgement {
    Judge::new(table, subject, &Arc::new(ctx.clone())).judge(exercise)
}

impl<S: ?Sized + Mix + 'static> Judge<S> {
    /// The judge of `subject` by the lab's exercises `table` in `ctx`.
    pub fn new(table: &[Arc<Exercise<S>>], subject: &Arc<S>, ctx: &Arc<LabContext>) -> Self {
        Self {
            table: table.to_vec(),
            subject: subject.clone(),
            ctx: ctx.clone(),
            judged: Mutex::new(HashMap::new()),
        }
    }

    /// Runs `exercise`'s check on the student's code (see [`run_exercise`]); should it fail,
    /// judges it again with the key in place of the student's functions it called whose own
    /// exercises fail, adding those the next round calls, until a round passes or no new
    /// function fails. It passes when the student's code left in it, with the key's parts, is
    /// right; never on the key's code alone. Where the tree lacks the lab's key (a handout),
    /// the failure names the exercises to fix first instead.
    pub fn judge(&self, exercise: &Exercise<S>) -> Judgement {
        self.judge_within(exercise, &mut Vec::new())
    }

    /// [`Self::judge`], while the exercises of `open` are being judged (the callers of this
    /// one: an exercise among them is not judged again here, which would never end).
    fn judge_within(&self, exercise: &Exercise<S>, open: &mut Vec<String>) -> Judgement {
        if let Some(judged) = self.lock().get(&exercise.id) {
            return judged.clone();
        }
        open.push(exercise.id.clone());
        let judgement = self.rounds(exercise, open);
        open.pop();
        self.lock().insert(exercise.id.clone(), judgement.clone());
        judgement
    }

    fn lock(&self) -> std::sync::MutexGuard<'_, HashMap<String, Judgement>> {
        self.judged.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// Whether `other`'s own exercise passes (judged, or run once when it is in `open`).
    fn passes(&self, other: &Exercise<S>, open: &mut Vec<String>) -> bool {
        if open.contains(&other.id) {
            contracts::wire::begin_run();
            return run_exercise(other, &self.subject, &self.ctx).is_ok();
        }
        self.judge_within(other, open).outcome.is_ok()
    }

    fn rounds(&self, exercise: &Exercise<S>, open: &mut Vec<String>) -> Judgement {
        let key = self.ctx.key().and_then(|base| base.part::<S>());
        let mut keyed: Vec<&Exercise<S>> = Vec::new();
        let mut first: Option<Failure> = None;
        loop {
            let calls = Arc::new(CallLog::default());
            let code = S::mix(
                &self.subject,
                key.as_ref().unwrap_or(&self.subject),
                functions(&keyed),
                &calls,
            );
            contracts::wire::begin_run();
            let outcome = run_exercise(exercise, &code, &self.ctx);
            if keyed.is_empty() {
                match outcome {
                    Ok(()) => return Judgement::alone(Ok(())),
                    Err(failure) if matches!(failure.kind, FailureKind::Waiting(_)) => {
                        return Judgement::alone(Err(failure));
                    }
                    Err(ref failure) => first = Some(failure.clone()),
                }
            }
            let first_failure = || first.clone().expect("the first round failed");
            let failure = match outcome {
                Ok(()) if calls.is_empty() => {
                    return self.judged_on(
                        &keyed,
                        Err(first_failure().with_note(format!(
                            "Every function of yours this check calls fails its own exercise \
                             ({}): there is none of your code left for it to check.",
                            exercises(&keyed)
                        ))),
                    );
                }
                Ok(()) => return self.judged_on(&keyed, Ok(())),
                Err(failure) => failure,
            };
            let failing: Vec<&Exercise<S>> = self
                .table
                .iter()
                .map(|other| &**other)
                .filter(|other| {
                    other.id != exercise.id
                        && other.function != exercise.function
                        && !keyed.iter().any(|k| k.id == other.id)
                        && calls.may_have_called(&other.function)
                })
                .filter(|other| !self.passes(other, open))
                .collect();
            if failing.is_empty() {
                if keyed.is_empty() {
                    return Judgement::alone(Err(failure));
                }
                let judged = self.judged_on(&keyed, Err(failure));
                return Judgement {
                    outcome: judged.outcome.map_err(|f| {
                        f.with_note(
                            "It still fails, so the mistake is in this exercise's own part.".into(),
                        )
                    }),
                    ..judged
                };
            }
            if key.is_none() {
                let fail = if failing.len() == 1 { "fails" } else { "fail" };
                return Judgement::alone(Err(failure.with_note(format!(
                    "This check calls your {}, and {} {fail} on its own: fix that first.",
                    named(&functions(&failing)),
                    exercises(&failing)
                ))));
            }
            keyed.extend(failing);
            keyed.sort_by_key(|k| self.table.iter().position(|e| e.id == k.id));
        }
    }

    /// The judgement decided by a run with the key's code for the functions of `keyed`, whose
    /// outcome was `outcome`: its note says so.
    fn judged_on(&self, keyed: &[&Exercise<S>], outcome: Result<(), Failure>) -> Judgement {
        if keyed.is_empty() {
            return Judgement::alone(outcome);
        }
        let fail = if keyed.len() == 1 { "fails" } else { "fail" };
        let note = format!(
            "This check was judged with the answer key's {} in place of yours ({} {fail} on its \
             own, and is charged there).",
            named(&functions(keyed)),
            exercises(keyed)
        );
        Judgement {
            outcome: outcome.map_err(|f| f.with_note(note.clone())),
            key_for: keyed.iter().map(|e| e.id.clone()).collect(),
            note,
        }
    }
}

/// The functions of `exercises`, each once.
fn functions<S: ?Sized>(exercises: &[&Exercise<S>]) -> Vec<&'static str> {
    let mut functions: Vec<&'static str> = Vec::new();
    for e in exercises {
        if !functions.contains(&e.info.function.as_str()) {
            functions.push(e.info.function.as_str());
        }
    }
    functions
}

/// "`a`", "`a` and `b`".
fn named(functions: &[&str]) -> String {
    list(functions.iter().map(|f| format!("`{f}`")))
}

/// "Exercise 1.1", "Exercises 1.1 and 1.2".
fn exercises<S: ?Sized>(exercises: &[&Exercise<S>]) -> String {
    let ids = list(exercises.iter().map(|e| e.id.clone()));
    if exercises.len() == 1 {
        format!("Exercise {ids}")
    } else {
        format!("Exercises {ids}")
    }
}

/// `a`, `a and b`, `a, b and c`.
fn list(items: impl Iterator<Item = String>) -> String {
    let items: Vec<String> = items.collect();
    match items.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}
