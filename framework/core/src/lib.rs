//! # raylab's rendering core
//!
//! Everything a render needs that is not a lab's lesson and knows no lab: the data types of
//! `raylab-types` ([`math`], [`sampling`], [`scene`]'s shapes, lights and materials), the
//! framework's own intersection kernels ([`geometry`]), the BVH ([`accel`]), scenes loaded from
//! OBJ/MTL files, scene files and the embedded scenes ([`scene`]), film, tone maps and image
//! files under a load budget ([`film`]), and the deterministic parallel tile loop
//! ([`render`]) that a pipeline fills pixel by pixel.
//!
//! See `docs/architecture.md` for the map of the crates and how data flows between them.

pub mod accel;
mod error;
pub mod film;
pub mod geometry;
mod panic;
pub mod progress;
pub mod render;
pub mod scene;
#[cfg(test)]
mod test_rng;

pub use error::{Error, PanicError};
pub use panic::{
    CaughtPanic, catch_panic, catch_quietly, exercise_in, panic_message, quietly, resume_panic,
};
pub use raylab_types::{glam, math, sampling};
