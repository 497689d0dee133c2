//! Lab 07's checks: one test per exercise of the table in `labs/lab07/exercises.toml` (checks in `labs/lab07/checks`).
//!
//! `cargo test -p lab07` checks your code in `src/lib.rs`, `cargo test -p lab07 exercise_7_2`
//! just Exercise 7.2.
//! `cargo test -p lab07 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

grading::lab_program!(lab07, lab07_checks, reference);
