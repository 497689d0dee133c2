//! Hostile submission `symlinks`: the answer key by a symbolic link. This `lib.rs` declares
//! `mod key;` and makes the key's `Lab02` its `Student`; the test puts beside it, in the
//! submission's `labs/lab02/src/`, `key.rs` — a symbolic link to the instructor's
//! `reference/src/lab02.rs` — and more traps for a grader that copies what it finds: a dangling
//! link `dangling.rs` (to `/nonexistent/file.rs`), two links `loop_a` and `loop_b` to each other,
//! and a FIFO `pipe`; outside the lab sources, a link `docs/loop` to itself and a FIFO
//! `notes.fifo` at the submission's root (reading either blocks or fails).
//!
//! The grader must take only regular files and directories (0 of 14 points: without `key.rs`
//! the crate does not compile), never open a FIFO, never follow a link, and finish: the report
//! lists each of `labs/lab02/src/key.rs`, `dangling.rs`, `loop_a`, `loop_b` (as a "symbolic
//! link") and `pipe` (as a "FIFO") as not taken.

mod key;

pub use key::Lab02 as Student;
