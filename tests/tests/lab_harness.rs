//! A lab's program end to end, as students (`cargo test -p lab01 -- ARGS`) and `raylab grade`
//! run it: libtest's command line (`grading::harness::cli`) and output
//! (`grading::harness::printer`), on the answer key and on the stubs.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::OnceLock;

/// The five tests of lab 01, in its table's order.
const LAB01_TESTS: [&str; 5] = [
    "exercise_1_1_image_plane_coords",
    "exercise_1_2_camera_basis",
    "exercise_1_3_field_of_view",
    "exercise_1_4_ray_direction",
    "exercise_1_5_camera_ray",
];

/// The workspace's root.
fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

/// `cargo test -q -p lab01 --test checks [--features reference] ARGS`.
fn cargo_test(reference: bool, args: &[&str]) -> Output {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let mut command = Command::new(cargo);
    command
        .current_dir(root())
        .args(["test", "-q", "-p", "lab01", "--test", "checks"]);
    if reference {
        command.args(["--features", "reference"]);
    }
    command.args(args).output().expect("cargo runs")
}

/// Lab 01's program (the stubs', or the answer key's), built once.
fn program(reference: bool) -> &'static Path {
    static PROGRAMS: [OnceLock<PathBuf>; 2] = [OnceLock::new(), OnceLock::new()];
    PROGRAMS[usize::from(reference)].get_or_init(|| {
        let out = cargo_test(reference, &["--no-run", "--message-format=json"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| serde_json::from_str::<serde_json::Value>(l).ok())
            .filter(|m| m["reason"] == "compiler-artifact" && m["target"]["name"] == "checks")
            .find_map(|m| m["executable"].as_str().map(PathBuf::from))
            .expect("cargo names the checks' executable")
    })
}

/// Lab 01's program run with `args`, in the lab's directory as cargo runs it: the exit status
/// and what it printed on standard output and standard error.
fn lab01(reference: bool, args: &[&str]) -> (Option<i32>, String, String) {
    let out = Command::new(program(reference))
        .current_dir(root().join("labs/lab01"))
        .args(args)
        .output()
        .expect("the program runs");
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// `NAME: test` for each name.
fn listed(names: &[&str]) -> String {
    names.iter().map(|n| format!("{n}: test\n")).collect()
}

#[test]
fn cargo_test_passes_the_command_line_to_the_program() {
    let out = cargo_test(true, &["--", "--list", "--format", "terse"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&out.stdout), listed(&LAB01_TESTS));
    let out = cargo_test(false, &[LAB01_TESTS[1], "--", "--exact"]);
    assert_eq!(out.status.code(), Some(101));
    assert!(
        String::from_utf8_lossy(&out.stdout)
            .contains(&format!("\nfailures:\n    {}\n", LAB01_TESTS[1])),
        "{}",
        String::from_utf8_lossy(&out.stdout)
    );
}

#[test]
fn list_prints_the_tables_tests_filtered_as_libtest_filters() {
    for args in [
        &["--list"][..],
        &["--list", "--format", "terse"],
        &["-q", "--list"],
    ] {
        let (code, out, err) = lab01(true, args);
        assert_eq!(code, Some(0), "{args:?}: {err}");
        assert_eq!(out, listed(&LAB01_TESTS), "{args:?}");
    }
    for (args, expected) in [
        (&["--list", "exercise_1_2", "exercise_1_4"][..], &[1, 3][..]),
        (&["--list", "exercise_1_1", "--exact"], &[]),
        (&["--list", "--exact", "exercise_1_3_field_of_view"], &[2]),
        (
            &["--list", "--skip", "exercise_1_1", "--skip=camera"],
            &[2, 3],
        ),
        (&["--list", "--ignored"], &[]),
    ] {
        let (code, out, err) = lab01(true, args);
        assert_eq!(code, Some(0), "{args:?}: {err}");
        let names: Vec<&str> = expected.iter().map(|&i| LAB01_TESTS[i]).collect();
        assert_eq!(out, listed(&names), "{args:?}");
    }
}

#[test]
fn the_answer_key_passes_every_test_and_exits_with_0() {
    let (code, out, err) = lab01(true, &["--test-threads", "2"]);
    assert_eq!(code, Some(0), "{out}{err}");
    assert!(out.starts_with("\nrunning 5 tests\n"), "{out}");
    for name in LAB01_TESTS {
        let padding = " ".repeat(LAB01_TESTS[0].len() - name.len());
        assert!(
            out.contains(&format!("\ntest {name}{padding} ... ok\n")),
            "{name}: {out}"
        );
    }
    assert!(
        out.contains(
            "\ntest result: ok. 5 passed; 0 failed; 0 ignored; 0 measured; 0 filtered out; \
             finished in "
        ) && out.ends_with("s\n\n"),
        "{out}"
    );
    let (code, out, err) = lab01(true, &["-q", "exercise_1_2", "exercise_1_5"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.starts_with("\nrunning 2 tests\n..\ntest result: ok. 2 passed; 0 failed; 0 ignored; 0 measured; 3 filtered out;"),
        "{out}"
    );
}

#[test]
fn a_stub_fails_its_test_with_the_checks_message_and_exit_status_101() {
    // As `raylab grade` runs one exercise.
    let (code, out, err) = lab01(
        false,
        &[LAB01_TESTS[0], "--exact", "--nocapture", "--test-threads=1"],
    );
    assert_eq!(code, Some(101), "{out}{err}");
    assert!(
        out.starts_with(&format!(
            "\nrunning 1 test\ntest {} ... FAILED\n",
            LAB01_TESTS[0]
        )),
        "{out}"
    );
    assert!(
        out.contains(&format!(
            "\nfailures:\n\n---- {} ----\nExercise 1.1 — `image_plane_coords`",
            LAB01_TESTS[0]
        )) && out.contains("is not implemented yet"),
        "{out}"
    );
    assert!(
        out.contains(&format!(
            "\nfailures:\n    {}\n\ntest result: FAILED. 0 passed; 1 failed; 0 ignored; 0 measured; 4 filtered out; finished in ",
            LAB01_TESTS[0]
        )),
        "{out}"
    );
    // Every stub fails, the failures listed in the table's order whatever order they end in.
    let (code, out, _) = lab01(false, &["--test-threads=4"]);
    assert_eq!(code, Some(101), "{out}");
    let summary: String = LAB01_TESTS.iter().map(|n| format!("    {n}\n")).collect();
    assert!(
        out.contains(&format!(
            "\nfailures:\n{summary}\ntest result: FAILED. 0 passed; 5 failed;"
        )),
        "{out}"
    );
}

#[test]
fn a_command_line_it_does_not_take_is_an_error_naming_the_argument() {
    for (args, named) in [
        (&["--frobnicate"][..], "`--frobnicate`"),
        (&["--format", "json"], "`json`"),
        (&["--test-threads=0"], "--test-threads"),
        (&["--color", "purple"], "(was purple)"),
    ] {
        let (code, out, err) = lab01(true, args);
        assert_eq!(code, Some(101), "{args:?}: {out}{err}");
        assert!(
            err.contains("error: ") && err.contains(named),
            "{args:?}: {err}"
        );
        assert!(!out.contains("running"), "{args:?} ran tests: {out}");
    }
    let (code, out, err) = lab01(true, &["--help"]);
    assert_eq!(code, Some(0), "{err}");
    assert!(
        out.contains("--exact") && out.contains("--test-threads"),
        "{out}"
    );
}
