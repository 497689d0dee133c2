//! Lab 09's checks: one test per exercise of the table in `labs/lab09/exercises.toml` (checks in `labs/lab09/checks`).
//!
//! `cargo test -p lab09` checks your code in `src/lib.rs`, `cargo test -p lab09 exercise_9_6`
//! just Exercise 9.6.
//! `cargo test -p lab09 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

grading::lab_program!(lab09, lab09_checks, reference);
