//! Hostile submission `path_to_key`: hands in the answer key instead of code. A `#[path]`
//! attribute points the module `key` at the instructor's `reference/src/lab02.rs`, reached from
//! the grading tree's `labs/lab02/src/` with `..` components; `Student` is the key's `Lab02`.
//! The test puts the relative path in for `@KEY_RELATIVE@`.
//!
//! The grader must not compile it (0 of 14 points): a `#[path]` attribute in a student crate is
//! flagged before any build, and the report says so ("flagged") and quotes the offending
//! `#[path …]` line. Not a line of the key may reach any report.

#[path = "@KEY_RELATIVE@"]
mod key;

pub use key::Lab02 as Student;
