//! Lab 06 — radiosity with the hemicube: the checks of its contract
//! ([`contracts::lab06`]) and the generator of their golden data (docs/lab06.md).

pub mod checks;
pub mod closed_forms;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
