//! Lab 10's checks: one test per exercise of the table in `labs/lab10/exercises.toml` (checks in `labs/lab10/checks`).
//!
//! `cargo test -p lab10` checks your code in `src/lib.rs`, `cargo test -p lab10 exercise_10_4`
//! just Exercise 10.4.
//! `cargo test -p lab10 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

grading::lab_program!(lab10, lab10_checks, reference);
