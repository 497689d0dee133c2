//! The fastest pure-Rust peer: obvhs's compressed 8-wide BVH (CWBVH, built with PLOC), traced
//! with obvhs's own Möller–Trumbore test or with the framework's watertight kernel (which tells
//! the two BVHs apart from the two triangle tests).

use std::cell::Cell;
use std::time::Duration;

use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh_from_tris;
use obvhs::ray::{Ray as ObRay, RayHit as ObHit};
use obvhs::triangle::Triangle;
use raylab_core::geometry::TriangleRay;
use raylab_core::glam::{Vec3, Vec3A};
use raylab_core::math::Ray;

use super::engine::{Engine, EngineHit, Work};

/// Which triangle test the obvhs engine runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kernel {
    /// obvhs's `Triangle::intersect` (Möller–Trumbore, not watertight).
    Obvhs,
    /// The framework's `intersect_triangle` (Woop et al., watertight), with the ray's part
    /// prepared once per ray (`TriangleRay`) as the core does.
    Framework,
}

/// obvhs's CWBVH over a triangle list, with the triangles stored in the BVH's leaf order.
pub struct Obvhs {
    bvh: CwBvh,
    /// Triangles in leaf order (`leaf_tris[i]` is face `bvh.primitive_indices[i]`).
    leaf_tris: Vec<Triangle>,
    leaf_verts: Vec<[Vec3; 3]>,
    kernel: Kernel,
}

impl Obvhs {
    /// Builds obvhs's CWBVH (`BvhBuildParams::medium_build`, which obvhs tunes to take about
    /// Embree's build time) over `triangles`.
    pub fn build(triangles: &[[Vec3; 3]], kernel: Kernel) -> Self {
        let tris: Vec<Triangle> = triangles
            .iter()
            .map(|&[v0, v1, v2]| Triangle {
                v0: v0.into(),
                v1: v1.into(),
                v2: v2.into(),
            })
            .collect();
        let bvh = build_cwbvh_from_tris(
            &tris,
            BvhBuildParams::medium_build(),
            &mut Duration::default(),
        );
        let order = bvh.primitive_indices.iter().map(|&i| i as usize);
        Obvhs {
            leaf_tris: order.clone().map(|i| tris[i]).collect(),
            leaf_verts: order.map(|i| triangles[i]).collect(),
            bvh,
            kernel,
        }
    }

    /// The ray parameter of a hit on leaf triangle `i` within `ob`'s interval, or infinity
    /// (`prepared` is `ray`'s, for the framework's kernel).
    #[inline(always)]
    fn test(&self, ray: &Ray, prepared: &TriangleRay, ob: &ObRay, i: usize) -> f32 {
        match self.kernel {
            Kernel::Obvhs => self.leaf_tris[i].intersect(ob),
            Kernel::Framework => {
                let [v0, v1, v2] = self.leaf_verts[i];
                let r = Ray {
                    tmax: ob.tmax,
                    ..*ray
                };
                prepared.distance(&r, v0, v1, v2).unwrap_or(f32::INFINITY)
            }
        }
    }
}

fn ob_ray(ray: &Ray) -> ObRay {
    ObRay::new(
        Vec3A::from(ray.origin),
        Vec3A::from(ray.direction),
        ray.tmin,
        ray.tmax,
    )
}

impl Engine for Obvhs {
    fn closest(&self, ray: &Ray) -> Option<EngineHit> {
        let mut hit = ObHit::none();
        let prepared = TriangleRay::new(ray);
        self.bvh
            .ray_traverse(ob_ray(ray), &mut hit, |ob, i| {
                self.test(ray, &prepared, ob, i)
            })
            .then(|| EngineHit {
                t: hit.t,
                prim: Some(self.bvh.primitive_indices[hit.primitive_id as usize]),
            })
    }

    fn any(&self, ray: &Ray) -> bool {
        let prepared = TriangleRay::new(ray);
        !self
            .bvh
            .ray_traverse_miss(ob_ray(ray), |ob, i| self.test(ray, &prepared, ob, i))
    }

    fn work(&self, rays: &[Ray]) -> Option<(Work, Work)> {
        let tests = Cell::new(0u64);
        let count = |ray: &Ray, ob: &ObRay, i: usize| {
            tests.set(tests.get() + 1);
            self.test(ray, &TriangleRay::new(ray), ob, i)
        };
        for ray in rays {
            let mut hit = ObHit::none();
            self.bvh
                .ray_traverse(ob_ray(ray), &mut hit, |ob, i| count(ray, ob, i));
        }
        let closest = tests.replace(0);
        for ray in rays {
            self.bvh
                .ray_traverse_miss(ob_ray(ray), |ob, i| count(ray, ob, i));
        }
        let any = tests.get();
        let per_ray = |n: u64| Work {
            nodes: None,
            leaves: None,
            triangles: n as f64 / rays.len().max(1) as f64,
        };
        Some((per_ray(closest), per_ray(any)))
    }
}
