//! Radiosity's framework (lab 06, docs/lab06.md): the scene meshed into patches
//! ([`patches`]), the hemicube's item buffer of patch ids found by ray casting ([`hemicube`]),
//! and the progressive-refinement driver and the images of a solution ([`solver`]), which
//! call the lab's contract for every formula.
//!
//! The data they exchange with the contract (patches, item buffers, delta form factors) are
//! the contract's own types (`contracts::lab06`).

pub mod hemicube;
pub mod patches;
pub mod solver;

pub use contracts::lab06::{DeltaFormFactors, HemicubeFace, ItemBuffer, Patch};
pub use hemicube::{item_buffer, item_buffer_at};
pub use patches::{MeshingOptions, PatchHit, PatchMesh};
