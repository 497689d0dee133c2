//! Every lab's checks reject the realistic mistakes of its mutant corpus, each in the exercise
//! it belongs to, and accept the alternative correct implementations.

use std::sync::Arc;

use framework::contracts;
use framework::labs::{lab01, lab02, lab03, lab04, lab07};
use raylab_tests::judge;
use raylab_tests::mutants;

#[test]
fn lab01_corpus() {
    let variants = mutants::lab01::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab01::CameraRays>,
            )
        })
        .collect();
    let problems = judge(1, &lab01::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab02_corpus() {
    let variants = mutants::lab02::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab02::Lab02>,
            )
        })
        .collect();
    let problems = judge(2, &lab02::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab03_corpus() {
    let variants = mutants::lab03::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab03::Shadows>,
            )
        })
        .collect();
    let problems = judge(3, &lab03::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab04_corpus() {
    let variants = mutants::lab04::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab04::Reflection>,
            )
        })
        .collect();
    let problems = judge(4, &lab04::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab07_corpus() {
    let variants = mutants::lab07::variants()
        .into_iter()
        .map(|v| {
            (
                v.name,
                v.verdict,
                Arc::new(v) as Arc<dyn contracts::lab07::Antialiasing>,
            )
        })
        .collect();
    let problems = judge(7, &lab07::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
