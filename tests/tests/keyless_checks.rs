//! The checks without the answer key: each lab's exercises judge the lab's mutant corpus in a
//! context whose key labs leave that lab out (as in a handout, or a grading tree, before the
//! lab's solution is released), so they have only golden cases, properties and snapshots to
//! go by. Every mistake must still be rejected by its exercise and every alternative (and the
//! reference itself) accepted; `-- --nocapture` prints the rejection rate per lab.

use std::sync::Arc;

use framework::contracts;
use framework::labs::{lab01, lab02, lab03, lab04, lab07};
use raylab_tests::mutants::Verdict;
use raylab_tests::{judge_in, keyed_context, mutants};

/// The context of `lab` with every key but its own.
fn keyless(lab: u32) -> framework::grading::LabContext {
    let keys: Vec<u32> = reference::KEYS
        .iter()
        .copied()
        .filter(|&l| l != lab)
        .collect();
    let ctx = keyed_context(lab, &keys);
    assert!(ctx.key().is_none() && keys.iter().all(|&l| ctx.has_key(l)));
    ctx
}

fn assert_discriminates(problems: Vec<String>) {
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab01_without_key() {
    let mut variants: Vec<_> = mutants::lab01::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab01::CameraRays>,
            )
        })
        .collect();
    variants.push((
        "the reference",
        Verdict::Accept,
        Arc::new(reference::lab01::Lab01),
    ));
    assert_discriminates(judge_in(&keyless(1), &lab01::checks::exercises(), variants));
}

#[test]
fn lab02_without_key() {
    let mut variants: Vec<_> = mutants::lab02::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab02::Lab02>,
            )
        })
        .collect();
    variants.push((
        "the reference",
        Verdict::Accept,
        Arc::new(reference::lab02::Lab02),
    ));
    assert_discriminates(judge_in(&keyless(2), &lab02::checks::exercises(), variants));
}

#[test]
fn lab03_without_key() {
    let mut variants: Vec<_> = mutants::lab03::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab03::Shadows>,
            )
        })
        .collect();
    variants.push((
        "the reference",
        Verdict::Accept,
        Arc::new(reference::lab03::Lab03),
    ));
    assert_discriminates(judge_in(&keyless(3), &lab03::checks::exercises(), variants));
}

#[test]
fn lab04_without_key() {
    let mut variants: Vec<_> = mutants::lab04::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab04::Reflection>,
            )
        })
        .collect();
    variants.push((
        "the reference",
        Verdict::Accept,
        Arc::new(reference::lab04::Lab04),
    ));
    assert_discriminates(judge_in(&keyless(4), &lab04::checks::exercises(), variants));
}

#[test]
fn lab07_without_key() {
    let mut variants: Vec<_> = mutants::lab07::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab07::Antialiasing>,
            )
        })
        .collect();
    variants.push((
        "the reference",
        Verdict::Accept,
        Arc::new(reference::lab07::Lab07),
    ));
    assert_discriminates(judge_in(&keyless(7), &lab07::checks::exercises(), variants));
}
