//! Lab 01 — the image loop and camera rays: the checks of its contract ([`contracts::lab01`]) and the
//! generator of their golden data (docs/lab01.md).

pub mod checks;
mod golden;
#[cfg(feature = "report")]
pub mod report;

pub use golden::generate_golden;
