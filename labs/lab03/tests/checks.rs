//! Lab 03's checks: one test per exercise of the table in `labs/lab03/exercises.toml` (checks in `labs/lab03/checks`).
//!
//! `cargo test -p lab03` checks your code in `src/lib.rs`, `cargo test -p lab03 exercise_3_2`
//! just Exercise 3.2.
//! `cargo test -p lab03 --features reference` checks the reference solution instead, where
//! the tree holds it. Each exercise runs with `reference::pipeline` for everything else: the
//! answer key where the tree holds it (so one unfinished exercise does not fail the others),
//! and in a handout, for this lab before its solution is released, your own code; a check
//! that needs another lab whose solution is not released yet says it waits for that lab.

grading::lab_program!(lab03, lab03_checks, reference);
