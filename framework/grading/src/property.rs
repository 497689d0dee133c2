use proptest::strategy::Strategy;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};

/// Checks `property` on `cases` inputs drawn from `strategy` with proptest, from a fixed seed
/// (the same inputs on every run, nothing written to disk). On failure proptest shrinks the
/// input, and the message shows the smallest failing input (its debug form: see
/// [`for_all_named`] for inputs a student should read in words) and what was wrong with it.
pub fn for_all<S>(
    cases: u32,
    strategy: S,
    property: impl Fn(S::Value) -> Result<(), String>,
) -> Result<(), String>
where
    S: Strategy,
    S::Value: std::fmt::Debug,
{
    for_all_named(
        cases,
        strategy,
        |input| format!("input {input:?}"),
        property,
    )
}

/// [`for_all`] whose message names the smallest failing input as `name` says, in the words of
/// the exercise ("the resolution 1×1 (resolution.x = 1, resolution.y = 1)"), instead of by
/// its debug form (`UVec2(1, 1)`).
pub fn for_all_named<S>(
    cases: u32,
    strategy: S,
    name: impl Fn(&S::Value) -> String,
    property: impl Fn(S::Value) -> Result<(), String>,
) -> Result<(), String>
where
    S: Strategy,
    S::Value: std::fmt::Debug,
{
    let config = Config {
        cases,
        failure_persistence: None,
        max_shrink_iters: 2048,
        ..Config::default()
    };
    let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]);
    let mut runner = TestRunner::new_with_rng(config, rng);
    // A panic of the student's code is caught here rather than by proptest, so that the
    // message keeps where it was raised and the exercise counts as crashed, not wrong.
    let panicked = std::cell::RefCell::new(None::<String>);
    let result = runner.run(&strategy, |input| {
        match raylab_core::catch_panic(|| property(input)) {
            Ok(outcome) => outcome.map_err(TestCaseError::fail),
            Err(panic) => {
                let place = match &panic.location {
                    Some(at) => format!("panicked at {at}: "),
                    None => "panicked: ".to_string(),
                };
                let reason = format!("{place}{}", panic.message);
                *panicked.borrow_mut() = Some(reason.clone());
                Err(TestCaseError::fail(reason))
            }
        }
    });
    result.map_err(|e| match e {
        proptest::test_runner::TestError::Fail(reason, input) => {
            let reason = reason.message();
            // The smallest failing input panicked: the message leads with the panic.
            if panicked.borrow().as_deref() == Some(reason) && reason.starts_with("panicked") {
                format!("{reason}\n  for {}", name(&input))
            } else {
                format!("for {}:\n  {reason}", name(&input))
            }
        }
        proptest::test_runner::TestError::Abort(reason) => {
            format!("property check aborted: {reason}")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_panic_is_reported_as_a_panic_with_its_place_and_the_smallest_input() {
        let message = raylab_core::quietly(|| {
            for_all(64, 0u32..1000, |x| {
                let v: Vec<u32> = Vec::new();
                if x >= 10 {
                    Ok(v[x as usize]).map(|_| ())
                } else {
                    Ok(())
                }
            })
        })
        .unwrap_err();
        assert!(message.starts_with("panicked at "), "{message}");
        assert!(message.contains("property.rs:"), "{message}");
        assert!(message.contains("index out of bounds"), "{message}");
        assert!(message.ends_with("for input 10"), "{message}");
    }

    #[test]
    fn a_wrong_answer_names_the_input_first() {
        let message = for_all(64, 0u32..1000, |x| {
            if x >= 10 {
                Err(format!("{x} is too big"))
            } else {
                Ok(())
            }
        })
        .unwrap_err();
        assert_eq!(message, "for input 10:\n  10 is too big");
    }

    #[test]
    fn a_named_input_is_shown_by_its_name() {
        let message = for_all_named(
            64,
            (0u32..1000, 0u32..1000),
            |(w, h)| format!("the resolution {w}×{h}"),
            |(w, h)| {
                if w + h >= 10 {
                    Err("too big".into())
                } else {
                    Ok(())
                }
            },
        )
        .unwrap_err();
        assert!(message.starts_with("for the resolution "), "{message}");
        assert!(!message.contains('('), "{message}");
    }
}
