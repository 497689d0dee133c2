//! Lab 10 — Fresnel reflectance and absorption: the checks of its contract
//! ([`contracts::lab10`]) and the generator of their golden data (docs/lab10.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
