//! Lab 02 — intersections and Lambertian shading: the checks of its contract ([`contracts::lab02`]) and the
//! generator of their golden data (docs/lab02.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
