//! Running a lab program's tests as libtest does: the filters of the command line, the tests on
//! `--test-threads` threads, each result printed as it comes, the failures in the tests' order
//! at the end.

use std::io::Write;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Mutex, mpsc};
use std::time::Instant;

use super::cli::Arguments;
use super::printer::{Conclusion, Outcome, Printer};

/// One test: its name and what it runs (`Err` with the failure's message).
pub struct Trial {
    /// The test's name, which filters match.
    pub name: String,
    test: Box<dyn FnOnce() -> Result<(), String> + Send>,
}

impl Trial {
    /// A test named `name` that runs `test`.
    pub fn test(
        name: impl Into<String>,
        test: impl FnOnce() -> Result<(), String> + Send + 'static,
    ) -> Self {
        Self {
            name: name.into(),
            test: Box::new(test),
        }
    }

    /// Runs the test; a panic is its failure (`test panicked: MESSAGE`).
    fn run(self) -> Outcome {
        match catch_unwind(AssertUnwindSafe(self.test)) {
            Ok(Ok(())) => Outcome::Passed,
            Ok(Err(message)) => Outcome::Failed(message),
            Err(payload) => {
                let message = payload
                    .downcast_ref::<String>()
                    .map(String::as_str)
                    .or_else(|| payload.downcast_ref::<&str>().copied());
                Outcome::Failed(match message {
                    Some(message) => format!("test panicked: {message}"),
                    None => "test panicked".to_string(),
                })
            }
        }
    }
}

/// Whether the command line's filters keep the test `name`: it matches a filter (or there is
/// none) and no `--skip`; with `--exact` a match is the whole name. A lab program has no
/// ignored tests, so `--ignored` keeps none.
pub fn selected(arguments: &Arguments, name: &str) -> bool {
    let matches = |filter: &String| {
        if arguments.exact {
            name == filter
        } else {
            name.contains(filter.as_str())
        }
    };
    (arguments.filters.is_empty() || arguments.filters.iter().any(matches))
        && !arguments.skip.iter().any(matches)
        && !arguments.ignored
}

/// Runs (or with `--list` lists) the tests of `trials` the command line selects, printing to
/// `out` (coloured when `colored`), and says how it went.
pub fn run(
    arguments: &Arguments,
    trials: Vec<Trial>,
    out: impl Write,
    colored: bool,
) -> Conclusion {
    let started = Instant::now();
    let total = trials.len();
    let trials: Vec<Trial> = trials
        .into_iter()
        .filter(|t| selected(arguments, &t.name))
        .collect();
    let names: Vec<String> = trials.iter().map(|t| t.name.clone()).collect();
    let name_refs: Vec<&str> = names.iter().map(String::as_str).collect();
    let mut printer = Printer::new(out, arguments.format, colored, &name_refs);
    let mut conclusion = Conclusion {
        filtered_out: total - trials.len(),
        ..Conclusion::default()
    };
    if arguments.list {
        printer.list(&name_refs);
        return Conclusion::default();
    }
    printer.title(trials.len());
    // (index in the table, message) of each failure.
    let mut failures: Vec<(usize, String)> = Vec::new();
    let mut record = |index: usize, outcome: Outcome, printer: &mut Printer<_>| {
        printer.outcome(&outcome);
        match outcome {
            Outcome::Passed => conclusion.passed += 1,
            Outcome::Failed(message) => {
                conclusion.failed += 1;
                failures.push((index, message));
            }
            Outcome::Ignored => conclusion.ignored += 1,
        }
    };
    // `--bench` runs the benchmarks only, and a lab program has none.
    let outcome_of = |trial: Trial| {
        if arguments.bench {
            Outcome::Ignored
        } else {
            trial.run()
        }
    };
    let threads = arguments
        .test_threads
        .or_else(|| std::thread::available_parallelism().ok())
        .map_or(1, usize::from);
    if threads == 1 {
        // In the main thread, each test announced before it runs (what it prints follows).
        for (index, trial) in trials.into_iter().enumerate() {
            printer.start(&names[index]);
            let outcome = outcome_of(trial);
            record(index, outcome, &mut printer);
        }
    } else {
        let count = trials.len();
        let queue = Mutex::new(trials.into_iter().enumerate());
        let (sender, results) = mpsc::channel();
        std::thread::scope(|scope| {
            for _ in 0..threads.min(count) {
                let sender = sender.clone();
                let (queue, outcome_of) = (&queue, &outcome_of);
                scope.spawn(move || {
                    loop {
                        // A test that panicked cannot poison the queue: it runs outside the lock.
                        let next = queue.lock().unwrap_or_else(|e| e.into_inner()).next();
                        let Some((index, trial)) = next else { break };
                        if sender.send((index, outcome_of(trial))).is_err() {
                            break;
                        }
                    }
                });
            }
            drop(sender);
            // Each test announced once it has finished, so that lines do not interleave.
            for (index, outcome) in results.iter().take(count) {
                printer.start(&names[index]);
                record(index, outcome, &mut printer);
            }
        });
    }
    if !failures.is_empty() {
        failures.sort_by_key(|(index, _)| *index);
        let listed: Vec<(&str, &str)> = failures
            .iter()
            .map(|(index, message)| (names[*index].as_str(), message.as_str()))
            .collect();
        printer.failures(&listed);
    }
    printer.summary(&conclusion, started.elapsed());
    conclusion
}

#[cfg(test)]
mod tests {
    use super::super::cli::{Command, parse};
    use super::*;
    use std::ffi::OsString;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};

    fn arguments(args: &[&str]) -> Arguments {
        match parse(args.iter().map(OsString::from)) {
            Ok(Command::Run(arguments)) => arguments,
            other => panic!("{other:?}"),
        }
    }

    /// Four tests: `exercise_1_1_a` and `exercise_1_3_c` pass, `exercise_1_2_b` fails,
    /// `exercise_1_10_d` panics.
    fn table() -> Vec<Trial> {
        vec![
            Trial::test("exercise_1_1_a", || Ok(())),
            Trial::test("exercise_1_2_b", || Err("1.2 is wrong".into())),
            Trial::test("exercise_1_3_c", || Ok(())),
            Trial::test("exercise_1_10_d", || panic!("boom {}", 10)),
        ]
    }

    fn run_table(args: &[&str]) -> (Conclusion, String) {
        let mut out = Vec::new();
        let conclusion = run(&arguments(args), table(), &mut out, false);
        (conclusion, String::from_utf8(out).unwrap())
    }

    /// The output with its timing, which varies, as `X.XX`.
    fn without_time(out: &str) -> String {
        let at = out.rfind("finished in ").expect("a summary") + "finished in ".len();
        let end = at + out[at..].find('s').unwrap();
        format!("{}X.XX{}", &out[..at], &out[end..])
    }

    #[test]
    fn filters_keep_names_holding_any_of_them_and_skips_drop_them() {
        let selected_by = |args: &[&str]| -> Vec<String> {
            let arguments = arguments(args);
            table()
                .into_iter()
                .map(|t| t.name)
                .filter(|n| selected(&arguments, n))
                .collect()
        };
        assert_eq!(selected_by(&[]).len(), 4);
        assert_eq!(
            selected_by(&["exercise_1_1"]),
            ["exercise_1_1_a", "exercise_1_10_d"]
        );
        assert_eq!(
            selected_by(&["exercise_1_1", "--exact"]),
            Vec::<String>::new()
        );
        assert_eq!(
            selected_by(&["exercise_1_1_a", "exercise_1_3_c", "--exact"]),
            ["exercise_1_1_a", "exercise_1_3_c"]
        );
        assert_eq!(
            selected_by(&["_b", "_c"]),
            ["exercise_1_2_b", "exercise_1_3_c"]
        );
        assert_eq!(
            selected_by(&["--skip", "exercise_1_1", "--skip=_c"]),
            ["exercise_1_2_b"]
        );
        assert_eq!(
            selected_by(&["--skip", "exercise_1_1", "--exact"]).len(),
            4,
            "an exact skip matches whole names only"
        );
        assert!(selected_by(&["--ignored"]).is_empty());
        assert_eq!(selected_by(&["--include-ignored"]).len(), 4);
    }

    #[test]
    fn a_list_names_the_selected_tests_and_runs_none() {
        let ran = Arc::new(AtomicUsize::new(0));
        let trials = ["exercise_1_1_a", "exercise_1_2_b"]
            .map(|name| {
                let ran = ran.clone();
                Trial::test(name, move || {
                    ran.fetch_add(1, Ordering::SeqCst);
                    Ok(())
                })
            })
            .into();
        let mut out = Vec::new();
        let conclusion = run(&arguments(&["--list", "_b"]), trials, &mut out, false);
        assert_eq!(String::from_utf8(out).unwrap(), "exercise_1_2_b: test\n");
        assert_eq!(conclusion, Conclusion::default());
        assert_eq!(ran.load(Ordering::SeqCst), 0);
    }

    #[test]
    fn one_thread_runs_in_order_and_reports_failures_and_panics() {
        let (conclusion, out) = run_table(&["--test-threads=1"]);
        assert_eq!(
            conclusion,
            Conclusion {
                passed: 2,
                failed: 2,
                ignored: 0,
                filtered_out: 0
            }
        );
        assert_eq!(conclusion.exit_code(), 101);
        assert_eq!(
            without_time(&out),
            "\nrunning 4 tests\n\
             test exercise_1_1_a  ... ok\n\
             test exercise_1_2_b  ... FAILED\n\
             test exercise_1_3_c  ... ok\n\
             test exercise_1_10_d ... FAILED\n\
             \nfailures:\n\n\
             ---- exercise_1_2_b ----\n1.2 is wrong\n\n\
             ---- exercise_1_10_d ----\ntest panicked: boom 10\n\n\
             \nfailures:\n    exercise_1_2_b\n    exercise_1_10_d\n\
             \ntest result: FAILED. 2 passed; 2 failed; 0 ignored; 0 measured; 0 filtered out; \
             finished in X.XXs\n\n"
        );
    }

    #[test]
    fn several_threads_print_every_result_and_the_failures_in_the_tables_order() {
        let (conclusion, out) = run_table(&["--test-threads", "3", "-q"]);
        assert_eq!((conclusion.passed, conclusion.failed), (2, 2));
        let marks = out.lines().nth(2).unwrap();
        let mut sorted: Vec<char> = marks.chars().collect();
        sorted.sort();
        assert_eq!(sorted, ['.', '.', 'F', 'F'], "{out}");
        let first = out.find("---- exercise_1_2_b ----").unwrap();
        let second = out.find("---- exercise_1_10_d ----").unwrap();
        assert!(first < second, "{out}");
        assert!(
            out.contains(
                "\nfailures:\n    exercise_1_2_b\n    exercise_1_10_d\n\n\
                 test result: FAILED. 2 passed; 2 failed;"
            ),
            "{out}"
        );
    }

    #[test]
    fn a_passing_selection_is_ok_and_counts_the_rest_as_filtered_out() {
        let (conclusion, out) = run_table(&["exercise_1_1_a", "exercise_1_3_c", "--exact"]);
        assert_eq!(conclusion.exit_code(), 0);
        assert_eq!(
            without_time(&out),
            "\nrunning 2 tests\n\
             test exercise_1_1_a ... ok\n\
             test exercise_1_3_c ... ok\n\
             \ntest result: ok. 2 passed; 0 failed; 0 ignored; 0 measured; 2 filtered out; \
             finished in X.XXs\n\n"
        );
    }

    #[test]
    fn bench_runs_nothing_and_ignores_every_test() {
        let (conclusion, out) = run_table(&["--bench", "--test-threads=1"]);
        assert_eq!(
            (conclusion.passed, conclusion.failed, conclusion.ignored),
            (0, 0, 4)
        );
        assert!(out.contains("test exercise_1_10_d ... ignored\n"), "{out}");
        assert_eq!(conclusion.exit_code(), 0);
    }

    #[test]
    fn the_graders_single_test_has_no_padding() {
        let (_, out) = run_table(&[
            "exercise_1_2_b",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ]);
        assert!(
            out.starts_with("\nrunning 1 test\ntest exercise_1_2_b ... FAILED\n"),
            "{out}"
        );
    }
}
