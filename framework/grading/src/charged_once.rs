//! One mistake, one exercise: an exercise whose check calls functions of other exercises (1.6
//! renders through all of 1.1–1.5) is judged with the answer key in place of each of those
//! whose own exercise fails, so that a mistake costs the points of its own exercise only.

use std::sync::Arc;

use contracts::{CallLog, Mix};

use crate::{Exercise, Failure, FailureKind, LabContext, run_exercise};

/// Runs `exercise`'s check on `subject` (see [`run_exercise`]); should it fail, runs the own
/// exercises of the student's other functions the check called (from `table`, the lab's
/// exercises), and judges it again with the key's code in place of those that fail: it passes
/// when the rest of the student's code, with the key's parts, is right. Where the tree lacks the
/// lab's key (a handout), the failure names the exercises to fix first instead. A check that,
/// with the key in, calls none of the student's functions is not passed on the key's code alone.
pub fn judge<S: ?Sized + Mix + 'static>(
    exercise: &Exercise<S>,
    table: &[Arc<Exercise<S>>],
    subject: &Arc<S>,
    ctx: &LabContext,
) -> Result<(), Failure> {
    let key = ctx.key().and_then(|base| base.part::<S>());
    let calls = Arc::new(CallLog::default());
    let noted = S::mix(subject, key.as_ref().unwrap_or(subject), Vec::new(), &calls);
    let failure = match run_exercise(exercise, &noted, ctx) {
        Ok(()) => return Ok(()),
        Err(failure) if matches!(failure.kind, FailureKind::Waiting(_)) => return Err(failure),
        Err(failure) => failure,
    };
    let failing: Vec<&Exercise<S>> = table
        .iter()
        .map(|other| &**other)
        .filter(|other| {
            other.id != exercise.id
                && other.function != exercise.function
                && calls.may_have_called(&other.function)
        })
        .filter(|other| run_exercise(other, subject, ctx).is_err())
        .collect();
    if failing.is_empty() {
        return Err(failure);
    }
    let exercises = list(failing.iter().map(|e| format!("Exercise {}", e.id)));
    let fail = if failing.len() == 1 { "fails" } else { "fail" };
    let mut functions: Vec<&'static str> = Vec::new();
    for e in &failing {
        if !functions.contains(&e.info.function.as_str()) {
            functions.push(e.info.function.as_str());
        }
    }
    let named = list(functions.iter().map(|f| format!("`{f}`")));
    let Some(key) = key else {
        return Err(failure.with_note(format!(
            "This check calls your {named}, and {exercises} {fail} on its own: fix that first."
        )));
    };
    let rest = Arc::new(CallLog::default());
    let mixed = S::mix(subject, &key, functions, &rest);
    let outcome = run_exercise(exercise, &mixed, ctx);
    if rest.is_empty() {
        return Err(failure.with_note(format!(
            "Every function of yours this check calls fails its own exercise ({exercises}): \
             there is none of your code left for it to check."
        )));
    }
    outcome.map_err(|again| {
        again.with_note(format!(
            "This check was run again with the answer key's {named} in place of yours ({exercises} \
             {fail} on its own, charged there): it still fails, so the mistake is in this \
             exercise's own part."
        ))
    })
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
