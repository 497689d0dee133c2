//! Lab 05 — radiometry: the checks of its contract ([`contracts::lab05`]) and the
//! generator of their golden data (docs/lab05.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
