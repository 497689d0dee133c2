//! The checks without the answer key: each lab's exercises judge the lab's mutant corpus in a
//! context whose key labs leave that lab out (as in a handout before the lab's solution is
//! released), so they have only golden cases, properties and snapshots to go by. Every
//! mistake must still be rejected by its exercise and every alternative (and the reference
//! itself) accepted; `-- --nocapture` prints the rejection rate per lab.

use raylab_tests::mutants::Verdict;
use raylab_tests::{corpus, for_each_lab, judge_in, keyed_context};

/// The context of `lab` with every key but its own.
fn keyless(lab: u32) -> grading::LabContext {
    let keys: Vec<u32> = reference::KEYS
        .iter()
        .copied()
        .filter(|&l| l != lab)
        .collect();
    let ctx = keyed_context(lab, &keys);
    assert!(ctx.key().is_none() && keys.iter().all(|&l| ctx.has_key(course::LabId::of(l))));
    ctx
}

macro_rules! keyless_test {
    ($number:expr, $module:ident, $contract:ident, $key:ident) => {
        mod $module {
            use super::*;

            #[test]
            fn without_key() {
                let mut variants = corpus!($module, $contract);
                variants.push((
                    "the reference",
                    Verdict::Accept,
                    std::sync::Arc::new(reference::$module::$key),
                ));
                let exercises = raylab_tests::lab_checks::$module::checks::exercises();
                let problems = judge_in(&keyless($number), &exercises, variants);
                assert!(problems.is_empty(), "{}", problems.join("\n"));
            }
        }
    };
}

for_each_lab!(keyless_test);
