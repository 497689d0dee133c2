//! A lab's mutant corpus: realistic wrong implementations of its contract drawn from typical
//! student mistakes (each names the exercise that must reject it) and alternative correct ones
//! every exercise must accept. The corpus is the lab's own, `labs/labNN/tests/corpus.rs` (the
//! instructors' repository only: a handout leaves it out), which ends with
//! [`corpus_tests!`](crate::corpus_tests): the reference passes, the stubs fail one exercise at
//! a time, and the corpus is judged with and without the answer key.

use std::path::Path;
use std::sync::Arc;

use crate::{Exercise, Failure, LabContext, LabId, run_exercise};
use pipeline::Pipeline;

/// Whether a variant is a mistake or a legitimate alternative.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Wrong: the named exercise must fail.
    Reject(&'static str),
    /// Correct: every exercise must pass.
    Accept,
}

/// One variant as [`judge`] takes it: its name, its verdict and the code.
pub type Entry<S> = (&'static str, Verdict, Arc<S>);

/// A variant of a lab's answer key that one value of `C` (what it changes, which implements the
/// lab's contract) stands for: its name and its verdict.
#[derive(Clone, Copy, Debug)]
pub struct Variant<C> {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    /// What the variant changes in the key.
    pub change: C,
}

impl<C> Variant<C> {
    /// The variant `name` with `verdict` that makes `change`.
    pub fn new(name: &'static str, verdict: Verdict, change: C) -> Self {
        Self {
            name,
            verdict,
            change,
        }
    }
}

/// The context of `lab` (whose crate is at `lab_dir`) in `base`, with `keys` as the labs whose
/// slot of `base` counts as the answer key: without `lab` among them the checks judge by golden
/// cases, properties and snapshots alone, as in a handout before the lab's solution is released.
/// Failure images go to a directory of this process under the system's temporary directory.
pub fn context(lab: LabId, lab_dir: &str, base: Pipeline, keys: &[u32]) -> LabContext {
    let mut ctx = LabContext::new(lab, Path::new(lab_dir), base).with_key_labs(keys);
    ctx.failure_dir = std::env::temp_dir()
        .join(format!("raylab-corpus-{}", std::process::id()))
        .join(lab.to_string());
    ctx
}

/// `keys` without `lab`.
pub fn keys_but(lab: LabId, keys: &[u32]) -> Vec<u32> {
    keys.iter()
        .copied()
        .filter(|&l| l != lab.number())
        .collect()
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

/// Panics with the first exercise the reference fails.
pub fn assert_all_pass(results: Vec<(&str, Result<(), String>)>) {
    for (id, r) in results {
        if let Err(message) = r {
            panic!("the reference fails exercise {id}:\n{message}");
        }
    }
}

/// Panics unless every exercise fails on the stubs with a message that names the exercise and
/// its function and says it is not implemented yet.
pub fn assert_all_fail_cleanly<S: ?Sized>(
    exercises: &[Exercise<S>],
    results: Vec<(&str, Result<(), String>)>,
) {
    assert_eq!(exercises.len(), results.len());
    for (exercise, (id, r)) in exercises.iter().zip(results) {
        let message = r.expect_err(&format!("the stub passes exercise {id}"));
        assert!(message.contains(&format!("Exercise {id}")), "{message}");
        assert!(message.contains(&exercise.function), "{message}");
        assert!(message.contains("not implemented yet"), "{message}");
    }
}

/// Runs the corpus through the exercises in `ctx`, printing what each exercise rejects and the
/// rejection rate; returns the failures of the suite (empty when it discriminates: every
/// mistake rejected by its own exercise, every alternative accepted by all).
pub fn judge<S: ?Sized>(
    ctx: &LabContext,
    exercises: &[Exercise<S>],
    variants: Vec<Entry<S>>,
) -> Vec<String> {
    let (lab, number) = (ctx.lab, ctx.lab.number());
    let mut problems = Vec::new();
    let (mut wrong, mut rejected) = (0, 0);
    for (name, verdict, subject) in variants {
        match verdict {
            Verdict::Reject(id) => {
                wrong += 1;
                // A mistake is judged by its own exercise alone.
                let Some(exercise) = exercises.iter().find(|e| e.id == id) else {
                    problems.push(format!("lab {number}: '{name}' names no exercise {id}"));
                    continue;
                };
                match &run_exercise(exercise, &subject, ctx) {
                    Err(Failure { message, .. }) => {
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
                    if let Err(m) = r {
                        problems.push(format!(
                            "lab {number}: exercise {id} rejects the correct '{name}':\n{m}"
                        ));
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

/// Judges every exercise that checks several functions together with [`crate::judge`] on each
/// mistake of the corpus (the key in `ctx`): a mistake is charged to the exercise it names
/// alone, so every such exercise but the one named must pass. Returns the problems.
pub fn charged_once<S: ?Sized + contracts::Mix + 'static>(
    ctx: &LabContext,
    exercises: Vec<Exercise<S>>,
    variants: Vec<Entry<S>>,
) -> Vec<String> {
    let table: Vec<Arc<Exercise<S>>> = exercises.into_iter().map(Arc::new).collect();
    let mut problems = Vec::new();
    let mut judged = 0;
    for (name, verdict, subject) in variants {
        let Verdict::Reject(id) = verdict else {
            continue;
        };
        for composite in table.iter().filter(|e| e.is_composite() && e.id != id) {
            judged += 1;
            if let Err(failure) = crate::judge(composite, &table, &subject, ctx).outcome {
                problems.push(format!(
                    "lab {}: '{name}' (Exercise {id}) also costs Exercise {}:\n{}",
                    ctx.lab.number(),
                    composite.id,
                    failure.message
                ));
            }
        }
    }
    println!(
        "{}: {}/{judged} mistakes charged to their own exercise alone by the composite exercises",
        ctx.lab,
        judged - problems.len()
    );
    problems
}

/// The tests of a lab's corpus, at the end of `labs/labNN/tests/corpus.rs`:
/// `grading::corpus_tests!(lab03, lab03_checks, reference);` after the file's `variants()`, a list of
/// variants with a `name`, a `verdict` and the lab's `contracts::labNN::Contract` implemented;
/// or `grading::corpus_tests!(lab11, lab11_checks, reference, code = change);` when the contract
/// is implemented by each variant's field `change` (a [`Variant`](crate::corpus::Variant)'s).
#[macro_export]
macro_rules! corpus_tests {
    ($lab:ident, $checks:ident, $key:ident $(, code = $code:ident)?) => {
        /// The lab's context in the reference pipeline, with the answer keys `keys`.
        fn corpus_context(keys: &[u32]) -> $crate::LabContext {
            let lab = $checks::checks::LAB;
            $crate::corpus::context(
                lab,
                env!("CARGO_MANIFEST_DIR"),
                $key::pipeline(lab.number()),
                keys,
            )
        }

        /// The corpus as [`judge`]($crate::corpus::judge) takes it.
        fn corpus() -> Vec<$crate::corpus::Entry<::contracts::$lab::Contract>> {
            variants()
                .into_iter()
                .map(|v| {
                    let (name, verdict) = (v.name, v.verdict);
                    let code: ::std::sync::Arc<::contracts::$lab::Contract> =
                        ::std::sync::Arc::new(v $(.$code)?);
                    (name, verdict, code)
                })
                .collect()
        }

        /// The answer key of the lab.
        fn key() -> ::std::sync::Arc<::contracts::$lab::Contract> {
            $key::pipeline($checks::checks::LAB.number())
                .part::<::contracts::$lab::Contract>()
                .expect("the repository holds every lab's answer key")
        }

        #[test]
        fn the_reference_passes_every_exercise() {
            let exercises = $checks::checks::exercises();
            let ctx = corpus_context($key::KEYS);
            $crate::corpus::assert_all_pass($crate::corpus::run_all(&exercises, &key(), &ctx));
        }

        #[test]
        fn the_stubs_fail_one_exercise_at_a_time() {
            let exercises = $checks::checks::exercises();
            let stubs: ::std::sync::Arc<::contracts::$lab::Contract> =
                ::std::sync::Arc::new($lab::Student);
            let ctx = corpus_context($key::KEYS);
            $crate::corpus::assert_all_fail_cleanly(
                &exercises,
                $crate::corpus::run_all(&exercises, &stubs, &ctx),
            );
        }

        /// The key and the stubs called through the contract's wire code (as `raylab grade`
        /// calls a student's code compiled apart), here without leaving the process.
        #[test]
        fn over_the_wire_the_reference_passes_and_the_stubs_fail() {
            use ::contracts::wire::{Loopback, Remote};
            let remote = |code: ::std::sync::Arc<::contracts::$lab::Contract>| {
                let remote: ::std::sync::Arc<::contracts::$lab::Contract> =
                    ::std::sync::Arc::new(Remote::<::contracts::$lab::Contract>::new(
                        ::std::sync::Arc::new(Loopback(code)),
                    ));
                remote
            };
            let exercises = $checks::checks::exercises();
            let ctx = corpus_context($key::KEYS);
            $crate::corpus::assert_all_pass($crate::corpus::run_all(
                &exercises,
                &remote(key()),
                &ctx,
            ));
            $crate::corpus::assert_all_fail_cleanly(
                &exercises,
                $crate::corpus::run_all(
                    &exercises,
                    &remote(::std::sync::Arc::new($lab::Student)),
                    &ctx,
                ),
            );
        }

        #[test]
        fn every_mistake_is_rejected_and_every_alternative_accepted() {
            let exercises = $checks::checks::exercises();
            let ctx = corpus_context($key::KEYS);
            let problems = $crate::corpus::judge(&ctx, &exercises, corpus());
            assert!(problems.is_empty(), "{}", problems.join("\n"));
        }

        /// One mistake, one exercise: an exercise that checks several functions together is
        /// judged with the key in place of those whose own exercise fails.
        #[test]
        fn every_mistake_costs_its_own_exercise_alone() {
            let ctx = corpus_context($key::KEYS);
            let problems =
                $crate::corpus::charged_once(&ctx, $checks::checks::exercises(), corpus());
            assert!(problems.is_empty(), "{}", problems.join("\n"));
        }

        /// As in a handout before the lab's solution is released: every key but the lab's own,
        /// so the checks have only golden cases, properties and snapshots to go by.
        #[test]
        fn every_mistake_is_rejected_and_every_alternative_accepted_without_the_key() {
            let lab = $checks::checks::LAB;
            let ctx = corpus_context(&$crate::corpus::keys_but(lab, $key::KEYS));
            assert!(ctx.key().is_none());
            let mut variants = corpus();
            variants.push(("the reference", $crate::corpus::Verdict::Accept, key()));
            let problems = $crate::corpus::judge(&ctx, &$checks::checks::exercises(), variants);
            assert!(problems.is_empty(), "{}", problems.join("\n"));
        }
    };
}
