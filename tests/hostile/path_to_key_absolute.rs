//! Hostile submission `path_to_key_absolute`: hands in the answer key instead of code. A
//! `#[path]` attribute points the module `key` at the instructor's `reference/src/lab02.rs` by
//! its absolute path; `Student` is the key's `Lab02`. The test puts the repository's absolute
//! path in for `@REPO@`.
//!
//! The grader must not compile it (0 of 14 points): a `#[path]` attribute in a student crate is
//! flagged before any build, and the report says so ("flagged") and quotes the offending
//! `#[path …]` line. Not a line of the key may reach any report.

#[path = "@REPO@/reference/src/lab02.rs"]
mod key;

pub use key::Lab02 as Student;
