//! Lab 09 — texture mapping: the checks of its contract ([`contracts::lab09`]) and the
//! generator of their golden data (docs/lab09.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
