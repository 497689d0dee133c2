//! Lab 12's checks: one test per exercise of the table in `labs/lab12/exercises.toml` (checks in `labs/lab12/checks`).
//!
//! `cargo test -p lab12` checks your code in `src/lib.rs`, `cargo test -p lab12 exercise_12_1_`
//! just Exercise 12.1 (without the last `_`, 12.10–12.13 as well).
//! `cargo test -p lab12 --features reference` checks the reference solution instead, where
//! the tree holds it.

grading::lab_program!(lab12, lab12_checks, reference);
