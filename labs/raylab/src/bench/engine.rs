//! What the benchmark compares: an engine answers closest-hit and any-hit queries over one
//! triangle mesh. This file holds the interface and the framework's own core.

use raylab_core::Error;
use raylab_core::accel::{TraversalStats, TriangleBvh};
use raylab_core::glam::Vec3;
use raylab_core::math::Ray;
use raylab_core::scene::Scene;

/// A closest hit: the ray parameter and, where the engine tells, which triangle (face index).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EngineHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Face index of the triangle hit, if the engine reports it.
    pub prim: Option<u32>,
}

/// Work per query, averaged over a ray set: BVH nodes, leaves and triangle tests.
#[derive(Clone, Copy, Debug, Default)]
pub struct Work {
    /// Interior nodes visited per ray (`None` when the engine cannot count them).
    pub nodes: Option<f64>,
    /// Leaves reached per ray (`None` when the engine cannot count them).
    pub leaves: Option<f64>,
    /// Triangle tests per ray.
    pub triangles: f64,
}

/// A ray tracer over the triangles of one scene.
pub trait Engine: Sync {
    /// The closest hit along `ray` in `[tmin, tmax]`.
    fn closest(&self, ray: &Ray) -> Option<EngineHit>;
    /// Whether anything lies along `ray` in `[tmin, tmax]`.
    fn any(&self, ray: &Ray) -> bool;
    /// The work of closest-hit and any-hit queries for `rays`, where the engine can count it.
    fn work(&self, _rays: &[Ray]) -> Option<(Work, Work)> {
        None
    }
}

/// The framework's core at the level of Embree's query: the SAH BVH over the triangles (in leaf
/// order, four to a block) with the built-in watertight triangle test run on four triangles at
/// once, returning the hit's `t` and face — what `Scene::trace_to_closest` does before it fills
/// in the hit record.
pub struct Core {
    bvh: TriangleBvh,
}

impl Core {
    /// Builds the BVH over `triangles`.
    pub fn build(triangles: &[[Vec3; 3]]) -> Self {
        Core {
            bvh: TriangleBvh::build(triangles),
        }
    }
}

impl Engine for Core {
    fn closest(&self, ray: &Ray) -> Option<EngineHit> {
        self.bvh.closest_hit_watertight(ray).map(|h| EngineHit {
            t: h.t,
            prim: Some(h.face),
        })
    }

    fn any(&self, ray: &Ray) -> bool {
        self.bvh.any_hit_watertight(ray)
    }

    fn work(&self, rays: &[Ray]) -> Option<(Work, Work)> {
        let (mut closest, mut any) = (TraversalStats::default(), TraversalStats::default());
        for ray in rays {
            self.bvh.closest_hit_watertight_counted(ray, &mut closest);
            self.bvh.any_hit_watertight_counted(ray, &mut any);
        }
        let per_ray = |s: TraversalStats| Work {
            nodes: Some(s.nodes as f64 / rays.len().max(1) as f64),
            leaves: Some(s.leaves as f64 / rays.len().max(1) as f64),
            triangles: s.primitives as f64 / rays.len().max(1) as f64,
        };
        Some((per_ray(closest), per_ray(any)))
    }
}

/// The full scene query the labs call, `Scene::trace_to_closest` / `trace_to_any`: the core plus
/// the hit record (position, interpolated shading normal, texture coordinates, material).
pub struct SceneQuery<'a>(pub &'a Scene);

impl Engine for SceneQuery<'_> {
    fn closest(&self, ray: &Ray) -> Option<EngineHit> {
        self.0.trace_to_closest(ray).map(|h| EngineHit {
            t: h.distance,
            prim: None,
        })
    }

    fn any(&self, ray: &Ray) -> bool {
        self.0.trace_to_any(ray)
    }
}

/// Checks that a scene is a triangle mesh only, which is all the peers are given.
pub fn check_triangles_only(scene: &Scene) -> Result<(), Error> {
    if scene.planes.is_empty() && scene.spheres.is_empty() {
        Ok(())
    } else {
        Err(Error::Scene {
            scene: scene.name.clone(),
            reason: "the benchmark compares triangle meshes; this scene has planes or spheres"
                .into(),
        })
    }
}
