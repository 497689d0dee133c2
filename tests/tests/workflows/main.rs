//! The instructor's workflows end to end, in one test executable so that libtest runs them side
//! by side: most of their time is spent waiting (on a build of one crate, a time limit, a
//! sandbox), which the other fills. One at a time:
//!
//! ```text
//! cargo test -p raylab-tests --test workflows answer_figures -- --nocapture
//! cargo test -p raylab-tests --test workflows cold_grading -- --nocapture
//! cargo test -p raylab-tests --test workflows handout_and_grade -- --nocapture
//! cargo test -p raylab-tests --test workflows hostile_submissions -- --nocapture
//! cargo test -p raylab-tests --test workflows new_lab -- --nocapture
//! cargo test -p raylab-tests --test workflows printed_commands -- --nocapture
//! cargo test -p raylab-tests --test workflows term -- --nocapture
//! ```

mod answer_figures;
mod cold_grading;
mod handout_and_grade;
mod hostile_submissions;
mod new_lab;
mod printed_commands;
mod term;
