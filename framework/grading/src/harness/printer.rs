//! What a run of a lab's program prints, byte for byte as libtest-mimic 0.8 (libtest's
//! formats) printed it: `raylab grade`, `status` and `watch` read it.

use std::io::{IsTerminal, Write};
use std::time::Duration;

use super::cli::{Color, Format};

/// The outcome of one test.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Outcome {
    /// It passed.
    Passed,
    /// It failed, with its message.
    Failed(String),
    /// It was not run (`--bench`: a lab program has no benchmarks).
    Ignored,
}

/// The counts of a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Conclusion {
    /// Tests that passed.
    pub passed: usize,
    /// Tests that failed.
    pub failed: usize,
    /// Tests not run.
    pub ignored: usize,
    /// Tests the filters left out.
    pub filtered_out: usize,
}

impl Conclusion {
    /// libtest's exit status: 0 when no test failed, 101 otherwise.
    pub fn exit_code(&self) -> i32 {
        if self.failed > 0 {
            super::cli::ERROR_EXIT_CODE
        } else {
            0
        }
    }
}

/// Whether the outcomes printed on standard output are coloured: as libtest-mimic's terminal
/// stream decided, `auto` colours a terminal unless `NO_COLOR` is set, `CLICOLOR=0`, or `TERM`
/// is unset or `dumb` (`CLICOLOR_FORCE` colours anything).
pub fn colors_on_stdout(color: Color) -> bool {
    let set = |name: &str| std::env::var_os(name).is_some_and(|v| !v.is_empty());
    match color {
        Color::Always => true,
        Color::Never => false,
        Color::Auto => {
            let clicolor = std::env::var_os("CLICOLOR");
            if set("NO_COLOR") {
                false
            } else if set("CLICOLOR_FORCE") {
                true
            } else if clicolor.as_ref().is_some_and(|v| v == "0") {
                false
            } else {
                // Without `TERM`, only Windows' consoles are taken to have colours.
                let term_colors = std::env::var_os("TERM").map_or(cfg!(windows), |t| t != "dumb")
                    || clicolor.is_some()
                    || std::env::var_os("CI").is_some();
                std::io::stdout().is_terminal() && term_colors
            }
        }
    }
}

/// Prints a run to `out`. Write errors (a closed pipe) are ignored: the exit status still
/// says how the run went.
pub struct Printer<W: Write> {
    out: W,
    format: Format,
    colored: bool,
    /// The longest name's length in characters: pretty lines align their outcomes.
    name_width: usize,
}

impl<W: Write> Printer<W> {
    /// A printer of the tests `names` (those the filters left) in `format`.
    pub fn new(out: W, format: Format, colored: bool, names: &[&str]) -> Self {
        let name_width = names.iter().map(|n| n.chars().count()).max().unwrap_or(0);
        Self {
            out,
            format,
            colored,
            name_width,
        }
    }

    /// `--list`: one `NAME: test` line per test, in either format.
    pub fn list(&mut self, names: &[&str]) {
        for name in names {
            let _ = writeln!(self.out, "{name}: test");
        }
        let _ = self.out.flush();
    }

    /// The first line, after an empty one: `running N tests`.
    pub fn title(&mut self, tests: usize) {
        let plural = if tests == 1 { "" } else { "s" };
        let _ = write!(self.out, "\nrunning {tests} test{plural}\n");
        let _ = self.out.flush();
    }

    /// Announces a test, `test NAME ... ` (pretty; nothing when terse), before its outcome.
    pub fn start(&mut self, name: &str) {
        if self.format == Format::Pretty {
            let _ = write!(self.out, "test {name:<0$} ... ", self.name_width);
            let _ = self.out.flush();
        }
    }

    /// A test's outcome: `ok`, `FAILED` or `ignored` ending its line (pretty), or `.`, `F`
    /// or `i` (terse).
    pub fn outcome(&mut self, outcome: &Outcome) {
        match self.format {
            Format::Pretty => {
                self.word(outcome);
                let _ = writeln!(self.out);
            }
            Format::Terse => {
                let mark = match outcome {
                    Outcome::Passed => ".",
                    Outcome::Failed(_) => "F",
                    Outcome::Ignored => "i",
                };
                self.paint(outcome, mark);
            }
        }
        let _ = self.out.flush();
    }

    /// The failures, each `---- NAME ----` with its message, then their names.
    pub fn failures(&mut self, failures: &[(&str, &str)]) {
        let _ = write!(self.out, "\nfailures:\n\n");
        for (name, message) in failures {
            let _ = write!(self.out, "---- {name} ----\n{message}\n\n");
        }
        let _ = write!(self.out, "\nfailures:\n");
        for (name, _) in failures {
            let _ = writeln!(self.out, "    {name}");
        }
    }

    /// The last line: `test result: ok. P passed; F failed; …; finished in X.XXs`.
    pub fn summary(&mut self, conclusion: &Conclusion, elapsed: Duration) {
        let _ = write!(self.out, "\ntest result: ");
        self.word(&if conclusion.failed > 0 {
            Outcome::Failed(String::new())
        } else {
            Outcome::Passed
        });
        let _ = write!(
            self.out,
            ". {} passed; {} failed; {} ignored; 0 measured; {} filtered out; finished in {:.2}s\n\n",
            conclusion.passed,
            conclusion.failed,
            conclusion.ignored,
            conclusion.filtered_out,
            elapsed.as_secs_f64()
        );
        let _ = self.out.flush();
    }

    /// `ok`, `FAILED` or `ignored`.
    fn word(&mut self, outcome: &Outcome) {
        let word = match outcome {
            Outcome::Passed => "ok",
            Outcome::Failed(_) => "FAILED",
            Outcome::Ignored => "ignored",
        };
        self.paint(outcome, word);
    }

    /// `text` in the outcome's colour (green, red, yellow) when colours are on.
    fn paint(&mut self, outcome: &Outcome, text: &str) {
        if !self.colored {
            let _ = self.out.write_all(text.as_bytes());
            return;
        }
        let color = match outcome {
            Outcome::Passed => 32,
            Outcome::Failed(_) => 31,
            Outcome::Ignored => 33,
        };
        let _ = write!(self.out, "\x1b[{color}m{text}\x1b[0m");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn printed(
        format: Format,
        colored: bool,
        print: impl FnOnce(&mut Printer<&mut Vec<u8>>),
    ) -> String {
        let mut out = Vec::new();
        let mut printer = Printer::new(&mut out, format, colored, &["a_test", "longer_test"]);
        print(&mut printer);
        String::from_utf8(out).unwrap()
    }

    #[test]
    fn a_list_is_one_line_per_test_in_both_formats() {
        for format in [Format::Pretty, Format::Terse] {
            let out = printed(format, false, |p| p.list(&["a_test", "longer_test"]));
            assert_eq!(out, "a_test: test\nlonger_test: test\n");
        }
    }

    #[test]
    fn pretty_lines_align_the_outcomes_and_the_summary_ends_with_an_empty_line() {
        let out = printed(Format::Pretty, false, |p| {
            p.title(2);
            p.start("a_test");
            p.outcome(&Outcome::Passed);
            p.start("longer_test");
            p.outcome(&Outcome::Failed("wrong".into()));
            p.failures(&[("longer_test", "wrong\nsecond line")]);
            p.summary(
                &Conclusion {
                    passed: 1,
                    failed: 1,
                    ignored: 0,
                    filtered_out: 3,
                },
                Duration::from_millis(1234),
            );
        });
        assert_eq!(
            out,
            "\nrunning 2 tests\n\
             test a_test      ... ok\n\
             test longer_test ... FAILED\n\
             \nfailures:\n\n---- longer_test ----\nwrong\nsecond line\n\n\
             \nfailures:\n    longer_test\n\
             \ntest result: FAILED. 1 passed; 1 failed; 0 ignored; 0 measured; 3 filtered out; \
             finished in 1.23s\n\n"
        );
    }

    #[test]
    fn terse_prints_one_character_per_test() {
        let out = printed(Format::Terse, false, |p| {
            p.title(1);
            p.start("a_test");
            p.outcome(&Outcome::Passed);
            p.start("longer_test");
            p.outcome(&Outcome::Failed("wrong".into()));
            p.outcome(&Outcome::Ignored);
            p.summary(&Conclusion::default(), Duration::ZERO);
        });
        assert_eq!(
            out,
            "\nrunning 1 test\n.Fi\ntest result: ok. 0 passed; 0 failed; 0 ignored; 0 measured; \
             0 filtered out; finished in 0.00s\n\n"
        );
    }

    #[test]
    fn colours_wrap_the_outcomes_only() {
        let out = printed(Format::Pretty, true, |p| {
            p.start("a_test");
            p.outcome(&Outcome::Passed);
            p.start("a_test");
            p.outcome(&Outcome::Failed("wrong".into()));
            p.start("a_test");
            p.outcome(&Outcome::Ignored);
        });
        assert_eq!(
            out,
            "test a_test      ... \x1b[32mok\x1b[0m\n\
             test a_test      ... \x1b[31mFAILED\x1b[0m\n\
             test a_test      ... \x1b[33mignored\x1b[0m\n"
        );
        let out = printed(Format::Terse, true, |p| p.outcome(&Outcome::Passed));
        assert_eq!(out, "\x1b[32m.\x1b[0m");
    }

    #[test]
    fn always_and_never_decide_alone() {
        assert!(colors_on_stdout(Color::Always));
        assert!(!colors_on_stdout(Color::Never));
    }

    #[test]
    fn only_failures_fail_the_run() {
        let mut conclusion = Conclusion {
            passed: 2,
            ignored: 1,
            filtered_out: 4,
            ..Conclusion::default()
        };
        assert_eq!(conclusion.exit_code(), 0);
        conclusion.failed = 1;
        assert_eq!(conclusion.exit_code(), 101);
    }
}
