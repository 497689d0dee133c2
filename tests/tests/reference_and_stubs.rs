//! The reference passes every exercise of every lab; the stubs fail every exercise with a
//! message that names the exercise and the function.

use std::sync::Arc;

use raylab_tests::{context, for_each_lab, run_all};

fn assert_all_pass(results: Vec<(&str, Result<(), String>)>) {
    for (id, r) in results {
        if let Err(message) = r {
            panic!("the reference fails exercise {id}:\n{message}");
        }
    }
}

fn assert_all_fail_cleanly<S: ?Sized>(
    exercises: &[grading::Exercise<S>],
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

macro_rules! reference_and_stubs_tests {
    ($number:expr, $module:ident, $contract:ident, $key:ident) => {
        mod $module {
            use super::*;

            #[test]
            fn reference_passes() {
                let exercises = raylab_tests::lab_checks::$module::checks::exercises();
                let subject: Arc<dyn contracts::$module::$contract> =
                    Arc::new(reference::$module::$key);
                assert_all_pass(run_all(&exercises, &subject, &context($number)));
            }

            #[test]
            fn stubs_fail_one_exercise_at_a_time() {
                let exercises = raylab_tests::lab_checks::$module::checks::exercises();
                let subject: Arc<dyn contracts::$module::$contract> = Arc::new(::$module::Student);
                assert_all_fail_cleanly(
                    &exercises,
                    run_all(&exercises, &subject, &context($number)),
                );
            }
        }
    };
}

for_each_lab!(reference_and_stubs_tests);

/// The bound on the sum of a hemicube's delta form factors (Exercises 6.2 and 6.3) is not
/// tight against the answer: the reference meets it with a margin of two at every resolution
/// checked, so a correct implementation's rounding never fails it.
#[test]
fn lab06_hemicube_sums_meet_their_bound_with_margin() {
    use lab06_checks::checks::{SUM_RESOLUTIONS, sum_bound};
    use pipeline::radiosity::DeltaFormFactors;
    for n in SUM_RESOLUTIONS {
        let e = (DeltaFormFactors::tabulate(&reference::lab06::Lab06, n).total() - 1.0).abs();
        assert!(e < 0.5 * sum_bound(n), "sum at {n}: {e:e}");
    }
}
