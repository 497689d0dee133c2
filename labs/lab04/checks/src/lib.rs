//! Lab 04 — reflection and refraction: the checks of its contract ([`contracts::lab04`]) and the
//! generator of their golden data (docs/lab04.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
