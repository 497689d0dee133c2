//! # raylab framework
//!
//! Everything in a rendering course that is not the lesson: math, scene loading, the BVH,
//! sampling, film and image output, deterministic parallel rendering, the lab contracts
//! ([`contracts`]: one module per lab, the traits students implement), the
//! [`Pipeline`](pipeline::Pipeline) that composes them, the grading library, and each lab's
//! checks ([`labs`]).
//!
//! See `docs/architecture.md` for the map of the crates and how data flows between them.

pub mod accel;
pub mod contracts;
mod error;
pub mod film;
pub mod geometry;
pub mod grading;
pub mod labs;
pub mod math;
mod panic;
pub mod photon;
pub mod pipeline;
pub mod radiosity;
pub mod render;
pub mod sampling;
pub mod scene;
#[cfg(test)]
mod test_rng;

pub use error::{Error, PanicError};
pub use glam;
pub use panic::catch_quietly;
