//! Lab 08's framework: the photon map (`map.rs`: photons in a k-d tree with its k-nearest and
//! radius queries; `kdtree.rs`: the tree) and the photon tracer (`tracer.rs`: emission through the lab 08 contract,
//! the path of a photon through mirrors and glass, the caustic map of a scene). The map stands
//! below the pipeline (the integrator gathers from it); the tracer at the level of the
//! pipeline, whose slots it calls.

mod kdtree;
mod map;
mod tracer;

pub use map::{Photon, PhotonMap, PhotonSettings};
pub use tracer::{
    MAX_PHOTON_BOUNCES, PhotonFate, PhotonTrace, StoreRule, trace_caustic_photons, trace_photon,
    trace_photons, with_caustics,
};
