//! The framework's own ray–primitive kernels, used by the BVH traversal for every lab after
//! lab02 (where students write their own, see `contracts::lab02`).
//!
//! The kernels are crate-private: they answer Exercises 2.1–2.3, and a student's lab02 code
//! must not be able to hand the question back to them. Only the prepared ray of the triangle
//! test is public, and only its distance query, for `raylab bench`'s peer BVHs.

mod plane;
mod sphere;
mod triangle;

pub(crate) use plane::intersect_plane;
pub(crate) use sphere::intersect_sphere;
pub use triangle::TriangleRay;
pub(crate) use triangle::{TriangleBlock, intersect_triangle};
