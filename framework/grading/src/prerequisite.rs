//! Tests that need more than a Rust toolchain — bubblewrap (the grading sandbox), Chromium
//! (the pages checked in a browser), the `wasm32-unknown-unknown` target (graded code) — run
//! where it is installed. Elsewhere such a test says once that it was skipped and how to
//! install what it needs, and passes; under `CI=true` a missing prerequisite fails it instead,
//! so that CI runs every test.

use std::io::Write;
use std::os::fd::AsFd;
use std::path::Path;

/// Whether the program `program` is on the `PATH`; if not, [`skip_or_fail`] with how to install
/// it (`install`, e.g. "apt-get install bubblewrap").
pub fn program_or_skip(test: &str, program: &str, install: &str) -> bool {
    let found = std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()));
    found || skip_or_fail(test, &format!("`{program}`"), install)
}

/// Whether the toolchain's standard library for `target` is installed; if not,
/// [`skip_or_fail`] with the `rustup` command that installs it.
pub fn rust_target_or_skip(test: &str, target: &str) -> bool {
    let sysroot = std::process::Command::new("rustc")
        .args(["--print", "sysroot"])
        .output()
        .ok()
        .filter(|o| o.status.success())
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string());
    let found = sysroot.is_some_and(|root| {
        Path::new(&root)
            .join("lib/rustlib")
            .join(target)
            .join("lib")
            .is_dir()
    });
    found
        || skip_or_fail(
            test,
            &format!("the {target} target"),
            &format!("rustup target add {target}"),
        )
}

/// The test `test` cannot run without `missing`: under `CI=true` a panic, otherwise a notice on
/// standard error and `false` (skip it).
pub fn skip_or_fail(test: &str, missing: &str, install: &str) -> bool {
    let ci = std::env::var("CI").is_ok_and(|v| !v.is_empty() && v != "false" && v != "0");
    if ci {
        panic!("{test} needs {missing}, which is not installed, and CI runs every test: {install}");
    }
    let notice = format!(
        "skipped: {test} needs {missing}, which is not installed ({install}; CI=true makes it required)"
    );
    // Written to a copy of the process's standard error, past the test harness's capture of
    // `eprintln!`, so that a passing test still says it was skipped.
    let written = std::io::stderr()
        .as_fd()
        .try_clone_to_owned()
        // One write of the whole line, so that the notices of tests running at once do not
        // interleave.
        .and_then(|fd| std::fs::File::from(fd).write_all(format!("{notice}\n").as_bytes()));
    if written.is_err() {
        eprintln!("{notice}");
    }
    false
}
