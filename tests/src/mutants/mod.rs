//! The mutant corpus: for each lab, wrong implementations drawn from typical student mistakes
//! (each names the exercise that must reject it) and alternative correct implementations that
//! every exercise must accept. Each variant overrides one or two functions of the reference.

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab05;
pub mod lab06;
pub mod lab07;
pub mod lab08;
pub mod lab09;
pub mod lab10;
pub mod lab11;

/// Whether a variant is a mistake or a legitimate alternative.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Wrong: the named exercise must fail.
    Reject(&'static str),
    /// Correct: every exercise must pass.
    Accept,
}
