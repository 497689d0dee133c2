use proptest::strategy::Strategy;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};

/// Checks `property` on `cases` inputs drawn from `strategy` with proptest, from a fixed seed
/// (the same inputs on every run, nothing written to disk). On failure proptest shrinks the
/// input, and the message shows the smallest failing input and what was wrong with it.
pub fn for_all<S>(
    cases: u32,
    strategy: S,
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
    runner
        .run(&strategy, |input| {
            property(input).map_err(TestCaseError::fail)
        })
        .map_err(|e| match e {
            proptest::test_runner::TestError::Fail(reason, input) => {
                format!("for input {input:?}:\n  {}", reason.message())
            }
            proptest::test_runner::TestError::Abort(reason) => {
                format!("property check aborted: {reason}")
            }
        })
}
