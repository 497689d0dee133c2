//! Lab 11's checks: one test per exercise of the table in `labs/lab11/exercises.toml` (checks in `labs/lab11/checks`).
//!
//! `cargo test -p lab11` checks your code in `src/lib.rs`, `cargo test -p lab11 exercise_11_3`
//! just Exercise 11.3.
//! `cargo test -p lab11 --features reference` checks the reference solution instead, where
//! the tree holds it. No check of one exercise calls your code for another, so you can do them
//! in any order.

grading::lab_program!(lab11, lab11_checks, reference);
