//! Radiosity's framework (lab 06, docs/lab06.md): the scene meshed into patches
//! ([`patches`]), the hemicube's item buffer of patch ids found by ray casting ([`hemicube`]),
//! and the progressive-refinement driver and the images of a solution ([`solver`]), which
//! call the lab's contract for every formula.
//!
//! `patches` and `hemicube` stand on `scene` and `accel` only (the contract's data types come
//! from them); `solver` stands beside the pipeline: it calls the contract.

pub mod hemicube;
pub mod patches;
pub mod solver;

pub use hemicube::{DeltaFormFactors, HemicubeFace, ItemBuffer};
pub use patches::{MeshingOptions, Patch, PatchHit, PatchMesh};
