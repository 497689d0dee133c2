//! The reference passes every exercise of every lab; the stubs fail every exercise with a
//! message that names the exercise and the function.

use std::sync::Arc;

use framework::contracts;
use framework::labs::{lab01, lab02, lab03, lab04, lab07};
use raylab_tests::{context, run_all};

fn assert_all_pass(results: Vec<(&str, Result<(), String>)>) {
    for (id, r) in results {
        if let Err(message) = r {
            panic!("the reference fails exercise {id}:\n{message}");
        }
    }
}

fn assert_all_fail_cleanly<S: ?Sized>(
    exercises: &[framework::grading::Exercise<S>],
    results: Vec<(&str, Result<(), String>)>,
) {
    assert_eq!(exercises.len(), results.len());
    for (exercise, (id, r)) in exercises.iter().zip(results) {
        let message = r.expect_err(&format!("the stub passes exercise {id}"));
        assert!(message.contains(&format!("Exercise {id}")), "{message}");
        assert!(message.contains(exercise.function), "{message}");
        assert!(message.contains("not implemented yet"), "{message}");
    }
}

#[test]
fn reference_passes_lab01() {
    let subject: Arc<dyn contracts::lab01::CameraRays> = Arc::new(reference::lab01::Lab01);
    assert_all_pass(run_all(&lab01::checks::exercises(), &subject, &context(1)));
}

#[test]
fn reference_passes_lab02() {
    let subject: Arc<dyn contracts::lab02::Lab02> = Arc::new(reference::lab02::Lab02);
    assert_all_pass(run_all(&lab02::checks::exercises(), &subject, &context(2)));
}

#[test]
fn reference_passes_lab03() {
    let subject: Arc<dyn contracts::lab03::Shadows> = Arc::new(reference::lab03::Lab03);
    assert_all_pass(run_all(&lab03::checks::exercises(), &subject, &context(3)));
}

#[test]
fn stubs_fail_lab03_one_exercise_at_a_time() {
    let exercises = lab03::checks::exercises();
    let subject: Arc<dyn contracts::lab03::Shadows> = Arc::new(::lab03::Student);
    assert_all_fail_cleanly(&exercises, run_all(&exercises, &subject, &context(3)));
}

#[test]
fn reference_passes_lab04() {
    let subject: Arc<dyn contracts::lab04::Reflection> = Arc::new(reference::lab04::Lab04);
    assert_all_pass(run_all(&lab04::checks::exercises(), &subject, &context(4)));
}

#[test]
fn stubs_fail_lab04_one_exercise_at_a_time() {
    let exercises = lab04::checks::exercises();
    let subject: Arc<dyn contracts::lab04::Reflection> = Arc::new(::lab04::Student);
    assert_all_fail_cleanly(&exercises, run_all(&exercises, &subject, &context(4)));
}

#[test]
fn reference_passes_lab07() {
    let subject: Arc<dyn contracts::lab07::Antialiasing> = Arc::new(reference::lab07::Lab07);
    assert_all_pass(run_all(&lab07::checks::exercises(), &subject, &context(7)));
}

#[test]
fn stubs_fail_lab07_one_exercise_at_a_time() {
    let exercises = lab07::checks::exercises();
    let subject: Arc<dyn contracts::lab07::Antialiasing> = Arc::new(::lab07::Student);
    assert_all_fail_cleanly(&exercises, run_all(&exercises, &subject, &context(7)));
}

#[test]
fn stubs_fail_lab01_one_exercise_at_a_time() {
    let exercises = lab01::checks::exercises();
    let subject: Arc<dyn contracts::lab01::CameraRays> = Arc::new(::lab01::Student);
    assert_all_fail_cleanly(&exercises, run_all(&exercises, &subject, &context(1)));
}

#[test]
fn stubs_fail_lab02_one_exercise_at_a_time() {
    let exercises = lab02::checks::exercises();
    let subject: Arc<dyn contracts::lab02::Lab02> = Arc::new(::lab02::Student);
    assert_all_fail_cleanly(&exercises, run_all(&exercises, &subject, &context(2)));
}
