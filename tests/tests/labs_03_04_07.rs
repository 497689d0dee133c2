//! Labs 03, 04 and 07: the reference passes every exercise, the stubs fail each one cleanly,
//! and the mutant corpus is rejected and accepted as it should be.

use std::sync::Arc;

use framework::grading::Exercise;
use framework::labs::{lab03, lab04, lab07};
use raylab_tests::{context, judge, mutants, run_all};

fn check_lab<S: ?Sized>(lab: u32, exercises: &[Exercise<S>], reference: Arc<S>, stub: Arc<S>) {
    let ctx = context(lab);
    for (id, r) in run_all(exercises, &reference, &ctx) {
        if let Err(m) = r {
            panic!("the reference fails exercise {id}:\n{m}");
        }
    }
    for (exercise, (id, r)) in exercises.iter().zip(run_all(exercises, &stub, &ctx)) {
        let m = r.expect_err(&format!("the stub passes exercise {id}"));
        assert!(
            m.contains(&format!("Exercise {id}")) && m.contains(exercise.function),
            "{m}"
        );
        assert!(m.contains("not implemented yet"), "{m}");
    }
}

#[test]
fn lab03_reference_passes_and_stubs_fail() {
    check_lab::<dyn lab03::Shadows>(
        3,
        &lab03::checks::exercises(),
        Arc::new(reference::lab03::Lab03),
        Arc::new(::lab03::Student),
    );
}

#[test]
fn lab04_reference_passes_and_stubs_fail() {
    check_lab::<dyn lab04::Reflection>(
        4,
        &lab04::checks::exercises(),
        Arc::new(reference::lab04::Lab04),
        Arc::new(::lab04::Student),
    );
}

#[test]
fn lab07_reference_passes_and_stubs_fail() {
    check_lab::<dyn lab07::Antialiasing>(
        7,
        &lab07::checks::exercises(),
        Arc::new(reference::lab07::Lab07),
        Arc::new(::lab07::Student),
    );
}

#[test]
fn lab03_corpus() {
    let variants = mutants::lab03::variants()
        .into_iter()
        .map(|v| (v.name, v.verdict, Arc::new(v) as Arc<dyn lab03::Shadows>))
        .collect();
    let problems = judge(3, &lab03::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn lab04_corpus() {
    let variants = mutants::lab04::variants()
        .into_iter()
        .map(|v| (v.name, v.verdict, Arc::new(v) as Arc<dyn lab04::Reflection>))
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
                Arc::new(v) as Arc<dyn lab07::Antialiasing>,
            )
        })
        .collect();
    let problems = judge(7, &lab07::checks::exercises(), variants);
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}
