//! Lab 08 — photon-mapped caustics: the checks of its contract ([`contracts::lab08`])
//! and the generator of their golden data (docs/lab08.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
