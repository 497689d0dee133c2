//! Every lab's checks reject the realistic mistakes of its mutant corpus, each in the exercise
//! it belongs to, and accept the alternative correct implementations.

use raylab_tests::{corpus, for_each_lab, judge};

macro_rules! corpus_test {
    ($number:expr, $module:ident, $contract:ident, $key:ident) => {
        mod $module {
            use super::*;

            #[test]
            fn corpus() {
                let exercises = raylab_tests::lab_checks::$module::checks::exercises();
                let problems = judge($number, &exercises, corpus!($module, $contract));
                assert!(problems.is_empty(), "{}", problems.join("\n"));
            }
        }
    };
}

for_each_lab!(corpus_test);
