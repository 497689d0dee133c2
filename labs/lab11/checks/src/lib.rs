//! Lab 11 — ambient occlusion and HDR light probes: the checks of its contract
//! ([`contracts::lab11`]) and the generator of their golden data and of the lab's
//! probe images (docs/lab11.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::{generate_golden, probe_film};
