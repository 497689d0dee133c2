//! The command line of a lab's program: the part of libtest's that students, their editors and
//! `raylab grade` use, parsed as libtest parses it. Anything else is an error naming the
//! argument, with libtest's exit status 101.
//!
//! The harness parses it itself rather than through a command-line library: the first
//! `cargo test -p labNN` of a handout compiles the harness, and a parser generator's crates
//! were seconds of that build's critical path.

use std::ffi::OsString;
use std::num::NonZeroUsize;

/// How the run's results are printed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Format {
    /// One line per test (`test NAME ... ok`).
    #[default]
    Pretty,
    /// One character per test (`.` or `F`): `--format terse`, `-q`.
    Terse,
}

/// Whether the outcomes are coloured.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Color {
    /// When standard output is a terminal that takes colours (and `NO_COLOR` is not set).
    #[default]
    Auto,
    /// Always.
    Always,
    /// Never.
    Never,
}

/// What the command line asks for.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Arguments {
    /// The positional filters: a test runs when its name holds any of them (or, with
    /// `--exact`, is one of them); none runs every test.
    pub filters: Vec<String>,
    /// `--exact`: filters and skips match whole names.
    pub exact: bool,
    /// `--skip FILTER`, each time it is given: tests matching one do not run.
    pub skip: Vec<String>,
    /// `--list`: list the tests instead of running them.
    pub list: bool,
    /// `--format`, or terse for `-q`.
    pub format: Format,
    /// `--nocapture`: accepted; the harness never captures a test's output.
    pub nocapture: bool,
    /// `--show-output`: accepted; the harness never captures a test's output.
    pub show_output: bool,
    /// `--test-threads N`; `None` for as many as the machine runs in parallel.
    pub test_threads: Option<NonZeroUsize>,
    /// `--ignored`: run only the ignored tests (a lab program has none).
    pub ignored: bool,
    /// `--include-ignored`: run the ignored tests too.
    pub include_ignored: bool,
    /// `--color`.
    pub color: Color,
    /// `--bench`: run the benchmarks only (a lab program has none: every test is ignored).
    pub bench: bool,
}

/// What a command line is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Command {
    /// Run (or list) the tests.
    Run(Arguments),
    /// `-h`/`--help`: print [`HELP`].
    Help,
}

/// The text of `--help`.
pub const HELP: &str = "\
Usage: PROGRAM [OPTIONS] [FILTERS...]

Runs the lab's checks, one test per exercise. A test runs when its name contains one of the
FILTERS (all tests without one).

Options:
        --exact         Exactly match filters rather than by substring
        --skip FILTER   Skip tests whose names contain FILTER (this flag can be used
                        multiple times)
        --list          List all tests and benchmarks
        --format pretty|terse
                        Configure formatting of output:
                        pretty = Print verbose output;
                        terse = Display one character per test
    -q, --quiet         Display one character per test instead of one line. Alias to
                        --format=terse
        --nocapture     Accepted for libtest's sake: a test's output is never captured
        --show-output   Accepted for libtest's sake: a test's output is never captured
        --test-threads n_threads
                        Number of threads used for running tests in parallel
        --ignored       Run only ignored tests
        --include-ignored
                        Run ignored and not ignored tests
        --color auto|always|never
                        Configure coloring of output:
                        auto = colorize if stdout is a tty (default);
                        always = always colorize output;
                        never = never colorize output
        --bench         Run benchmarks instead of tests (there are none)
    -h, --help          Display this message
";

/// A command line the harness does not take: the message names the argument.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UsageError(pub String);

impl std::fmt::Display for UsageError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// libtest's exit status for a command line it does not take (and for failed tests).
pub const ERROR_EXIT_CODE: i32 = 101;

/// Parses the program's own command line: prints the help and exits with 0 for `--help`,
/// prints the error and exits with [`ERROR_EXIT_CODE`] for a command line it does not take.
pub fn from_env() -> Arguments {
    match parse(std::env::args_os().skip(1)) {
        Ok(Command::Run(arguments)) => arguments,
        Ok(Command::Help) => {
            print!("{HELP}");
            std::process::exit(0)
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(ERROR_EXIT_CODE)
        }
    }
}

/// The options that take a value.
const VALUED: [&str; 4] = ["skip", "format", "test-threads", "color"];

/// Parses `args` (without the program's name) as libtest does: options anywhere, a value after
/// its option or after `=`, every other argument (and each one after `--`) a filter.
pub fn parse<I: IntoIterator<Item = OsString>>(args: I) -> Result<Command, UsageError> {
    let mut arguments = Arguments::default();
    let mut seen: Vec<&'static str> = Vec::new();
    let (mut help, mut quiet) = (false, false);
    // The values are checked once the whole line is read: `--help` wins over a bad one.
    let (mut format, mut color, mut threads) = (None, None, None);
    let mut args = args.into_iter();
    while let Some(arg) = args.next() {
        let arg = utf8(arg)?;
        if arg == "--" {
            for filter in args.by_ref() {
                arguments.filters.push(utf8(filter)?);
            }
            break;
        }
        let (name, inline) = if let Some(long) = arg.strip_prefix("--") {
            match long.split_once('=') {
                Some((name, value)) => (name.to_string(), Some(value.to_string())),
                None => (long.to_string(), None),
            }
        } else if arg.len() > 1 && arg.starts_with('-') {
            match arg.as_str() {
                "-q" => ("quiet".to_string(), None),
                "-h" => ("help".to_string(), None),
                _ => return Err(unrecognized(&arg)),
            }
        } else {
            arguments.filters.push(arg);
            continue;
        };
        let Some(option) = OPTIONS.iter().copied().find(|o| *o == name) else {
            return Err(unrecognized(&arg));
        };
        if option != "skip" {
            if seen.contains(&option) {
                return Err(UsageError(format!(
                    "option `--{option}` given more than once"
                )));
            }
            seen.push(option);
        }
        let value = if VALUED.contains(&option) {
            match inline {
                Some(value) => Some(value),
                None => Some(utf8(args.next().ok_or_else(|| {
                    UsageError(format!("option `--{option}` needs a value"))
                })?)?),
            }
        } else if inline.is_some() {
            return Err(UsageError(format!(
                "option `--{option}` does not take a value (`{arg}`)"
            )));
        } else {
            None
        };
        let value = value.unwrap_or_default();
        match option {
            "help" => help = true,
            "exact" => arguments.exact = true,
            "skip" => arguments.skip.push(value),
            "list" => arguments.list = true,
            "format" => format = Some(value),
            "quiet" => quiet = true,
            "nocapture" => arguments.nocapture = true,
            "show-output" => arguments.show_output = true,
            "test-threads" => threads = Some(value),
            "ignored" => arguments.ignored = true,
            "include-ignored" => arguments.include_ignored = true,
            "color" => color = Some(value),
            "bench" => arguments.bench = true,
            _ => unreachable!("every name of OPTIONS has its arm"),
        }
    }
    if help {
        return Ok(Command::Help);
    }
    if arguments.ignored && arguments.include_ignored {
        return Err(UsageError(
            "the options --include-ignored and --ignored are mutually exclusive".into(),
        ));
    }
    // As in libtest, an explicit `--format` wins over `-q`.
    arguments.format = match (format, quiet) {
        (Some(format), _) => parse_format(&format)?,
        (None, true) => Format::Terse,
        (None, false) => Format::Pretty,
    };
    if let Some(threads) = threads {
        arguments.test_threads = Some(parse_threads(&threads)?);
    }
    if let Some(color) = color {
        arguments.color = parse_color(&color)?;
    }
    Ok(Command::Run(arguments))
}

/// The long names of the options (`-q` is `quiet`, `-h` is `help`).
const OPTIONS: [&str; 13] = [
    "help",
    "exact",
    "skip",
    "list",
    "format",
    "quiet",
    "nocapture",
    "show-output",
    "test-threads",
    "ignored",
    "include-ignored",
    "color",
    "bench",
];

fn utf8(arg: OsString) -> Result<String, UsageError> {
    arg.into_string().map_err(|arg| {
        UsageError(format!(
            "argument `{}` is not valid UTF-8",
            arg.to_string_lossy()
        ))
    })
}

fn unrecognized(arg: &str) -> UsageError {
    UsageError(format!(
        "unrecognized option `{arg}` (`--help` lists the options this program takes)"
    ))
}

fn parse_format(value: &str) -> Result<Format, UsageError> {
    match value {
        "pretty" => Ok(Format::Pretty),
        "terse" => Ok(Format::Terse),
        "json" | "junit" => Err(UsageError(format!(
            "the `{value}` format is not supported by this program's harness: `--format` must be \
             pretty or terse"
        ))),
        _ => Err(UsageError(format!(
            "argument for --format must be pretty or terse (was {value})"
        ))),
    }
}

fn parse_color(value: &str) -> Result<Color, UsageError> {
    match value {
        "auto" => Ok(Color::Auto),
        "always" => Ok(Color::Always),
        "never" => Ok(Color::Never),
        _ => Err(UsageError(format!(
            "argument for --color must be auto, always, or never (was {value})"
        ))),
    }
}

fn parse_threads(value: &str) -> Result<NonZeroUsize, UsageError> {
    match value.parse::<usize>() {
        Ok(0) => Err(UsageError(
            "argument for --test-threads must not be 0".into(),
        )),
        Ok(n) => Ok(NonZeroUsize::new(n).expect("not 0")),
        Err(e) => Err(UsageError(format!(
            "argument for --test-threads must be a number > 0 (was {value}: {e})"
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parsed(args: &[&str]) -> Result<Command, UsageError> {
        parse(args.iter().map(OsString::from))
    }

    fn run(args: &[&str]) -> Arguments {
        match parsed(args) {
            Ok(Command::Run(arguments)) => arguments,
            other => panic!("{args:?}: {other:?}"),
        }
    }

    fn error(args: &[&str]) -> String {
        match parsed(args) {
            Err(UsageError(message)) => message,
            other => panic!("{args:?} is accepted: {other:?}"),
        }
    }

    #[test]
    fn no_arguments_run_every_test_pretty_on_every_core() {
        assert_eq!(run(&[]), Arguments::default());
        let arguments = run(&[]);
        assert_eq!(arguments.format, Format::Pretty);
        assert_eq!(arguments.color, Color::Auto);
        assert_eq!(arguments.test_threads, None);
    }

    #[test]
    fn positional_arguments_are_filters_wherever_they_stand() {
        let arguments = run(&["exercise_1_1", "--exact", "exercise_1_2"]);
        assert_eq!(arguments.filters, ["exercise_1_1", "exercise_1_2"]);
        assert!(arguments.exact);
        // A lone `-` is a filter, as in libtest; everything after `--` is one too.
        assert_eq!(run(&["-"]).filters, ["-"]);
        assert_eq!(
            run(&["a", "--", "--list", "-q"]).filters,
            ["a", "--list", "-q"]
        );
        assert!(!run(&["--", "--list"]).list);
    }

    #[test]
    fn the_graders_command_lines_parse() {
        let list = run(&["--list", "--format", "terse"]);
        assert!(list.list);
        assert_eq!(list.format, Format::Terse);
        let one = run(&[
            "exercise_1_2_camera_basis",
            "--exact",
            "--nocapture",
            "--test-threads=1",
        ]);
        assert_eq!(one.filters, ["exercise_1_2_camera_basis"]);
        assert!(one.exact && one.nocapture);
        assert_eq!(one.test_threads, NonZeroUsize::new(1));
    }

    #[test]
    fn each_flag_sets_its_field() {
        assert!(run(&["--exact"]).exact);
        assert!(run(&["--list"]).list);
        assert!(run(&["--nocapture"]).nocapture);
        assert!(run(&["--show-output"]).show_output);
        assert!(run(&["--ignored"]).ignored);
        assert!(run(&["--include-ignored"]).include_ignored);
        assert!(run(&["--bench"]).bench);
        assert_eq!(parsed(&["-h"]), Ok(Command::Help));
        // As in libtest, help wins over a bad value, not over an unknown option.
        assert_eq!(parsed(&["--format=yaml", "--help"]), Ok(Command::Help));
        assert!(parsed(&["--help", "--bogus"]).is_err());
    }

    #[test]
    fn options_take_their_value_after_them_or_after_an_equals_sign() {
        for args in [
            &["--format", "terse"][..],
            &["--format=terse"],
            &["-q"],
            &["--quiet"],
        ] {
            assert_eq!(run(args).format, Format::Terse, "{args:?}");
        }
        assert_eq!(run(&["--format=pretty"]).format, Format::Pretty);
        // An explicit format wins over `-q`, as in libtest.
        assert_eq!(run(&["-q", "--format", "pretty"]).format, Format::Pretty);
        assert_eq!(
            run(&["--test-threads", "3"]).test_threads,
            NonZeroUsize::new(3)
        );
        assert_eq!(
            run(&["--test-threads=2"]).test_threads,
            NonZeroUsize::new(2)
        );
        assert_eq!(run(&["--color", "never"]).color, Color::Never);
        assert_eq!(run(&["--color=always"]).color, Color::Always);
        assert_eq!(run(&["--color=auto"]).color, Color::Auto);
        // A value is the next argument whatever it looks like.
        assert_eq!(run(&["--skip", "--exact"]).skip, ["--exact"]);
        assert_eq!(run(&["--skip="]).skip, [""]);
    }

    #[test]
    fn skip_is_repeatable() {
        let arguments = run(&["--skip", "exercise_1_1", "--skip=exercise_1_2", "x"]);
        assert_eq!(arguments.skip, ["exercise_1_1", "exercise_1_2"]);
        assert_eq!(arguments.filters, ["x"]);
    }

    #[test]
    fn unknown_options_are_errors_naming_them() {
        assert!(error(&["--bogus"]).contains("`--bogus`"));
        assert!(error(&["--logfile=x"]).contains("`--logfile=x`"));
        assert!(error(&["-x"]).contains("`-x`"));
        assert!(error(&["-qh"]).contains("`-qh`"));
        assert!(error(&["-Z", "unstable-options"]).contains("`-Z`"));
        assert!(error(&["--test"]).contains("`--test`"));
    }

    #[test]
    fn bad_values_are_errors_naming_the_option_and_value() {
        for (args, expected) in [
            (&["--format", "json"][..], "`json` format"),
            (
                &["--format=yaml"],
                "--format must be pretty or terse (was yaml)",
            ),
            (
                &["--color", "red"],
                "--color must be auto, always, or never (was red)",
            ),
            (&["--test-threads", "0"], "--test-threads must not be 0"),
            (
                &["--test-threads=many"],
                "--test-threads must be a number > 0 (was many",
            ),
            (&["--test-threads=-1"], "(was -1"),
            (&["--skip"], "`--skip` needs a value"),
            (&["x", "--format"], "`--format` needs a value"),
            (&["--list=yes"], "`--list` does not take a value"),
            (&["--list", "--list"], "`--list` given more than once"),
            (
                &["--format", "terse", "--format=pretty"],
                "`--format` given more than once",
            ),
            (&["-q", "--quiet"], "`--quiet` given more than once"),
            (&["--ignored", "--include-ignored"], "mutually exclusive"),
        ] {
            let message = error(args);
            assert!(message.contains(expected), "{args:?}: {message}");
        }
    }

    #[cfg(unix)]
    #[test]
    fn an_argument_that_is_not_utf8_is_an_error() {
        use std::os::unix::ffi::OsStringExt;
        let args = vec![OsString::from_vec(vec![b'a', 0xff])];
        let Err(UsageError(message)) = parse(args) else {
            panic!("accepted")
        };
        assert!(message.contains("not valid UTF-8"), "{message}");
    }
}
