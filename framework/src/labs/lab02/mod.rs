//! Lab 02 — intersections and Lambertian shading: the checks of its contract ([`crate::contracts::lab02`]) and the
//! generator of their golden data (docs/lab02.md).

mod builtin;
pub mod checks;
mod golden;

pub use golden::generate_golden;
