//! Acceleration structures: a bounding volume hierarchy built with the surface area heuristic.

mod bvh;

pub use bvh::Bvh;
