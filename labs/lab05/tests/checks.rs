//! Lab 05's checks: one test per exercise of the table in `labs/lab05/exercises.toml` (checks in `labs/lab05/checks`).
//!
//! `cargo test -p lab05` checks your code in `src/lib.rs`, `cargo test -p lab05 exercise_5_8`
//! just Exercise 5.8.
//! `cargo test -p lab05 --features reference` checks the reference solution instead, where
//! the tree holds it. No check of one exercise calls your code for another, so you can do them
//! in any order.

grading::lab_program!(lab05, lab05_checks, reference);
