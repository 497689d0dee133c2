//! Lab 03 — shadows: the checks of its contract ([`contracts::lab03`]) and the
//! generator of their golden data (docs/lab03.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
