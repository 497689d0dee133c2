//! Lab 07 — anti-aliasing: the checks of its contract ([`contracts::lab07`]) and the
//! generator of their golden data (docs/lab07.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
