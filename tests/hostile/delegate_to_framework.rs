//! Hostile submission `delegate_to_framework`: the intersection exercises are not written but
//! handed to the framework — each builds a scene of the one shape it is given and asks
//! `Scene::trace_to_closest` for the hit, which the framework's own kernels compute. The light
//! and shading exercises are honest.
//!
//! A student crate depends on the contracts alone, so the framework's scene (`raylab_core`) is
//! not there to name: the lab does not compile, and every exercise's reason names
//! `raylab_core`. No points (the honest half is in the same crate).

use std::f32::consts::PI;

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use raylab_core::scene::{
    CameraSetup, DirectionalLight, Material, MaterialId, Mesh, Plane, PointLight, Scene,
    SceneDescription, Sphere,
};

/// Delegates the intersections to the framework's scene.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

/// A scene of nothing but `planes`, `spheres` and `mesh`.
fn scene_of(planes: Vec<Plane>, spheres: Vec<Sphere>, mesh: Mesh) -> Option<Scene> {
    Scene::new(SceneDescription {
        name: "one shape".into(),
        camera: Some(CameraSetup {
            eye: Vec3::new(0.0, 0.0, 1.0),
            look_at: Vec3::ZERO,
            up: Vec3::Y,
            focal_distance: 1.0,
        }),
        materials: vec![Material::lambertian("grey", Vec3::splat(0.5))],
        planes,
        spheres,
        mesh,
        ..SceneDescription::default()
    })
    .ok()
}

impl Intersection for Student {
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        let hit = scene_of(vec![Plane { material: MaterialId(0), ..*plane }], Vec::new(), Mesh::default())?.trace_to_closest(ray)?;
        Some(SurfaceHit {
            distance: hit.distance,
            normal: plane.normal,
        })
    }

    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        let mesh = Mesh {
            positions: vec![v0, v1, v2],
            faces: vec![[0, 1, 2]],
            face_materials: vec![MaterialId(0)],
            ..Mesh::default()
        };
        let hit = scene_of(Vec::new(), Vec::new(), mesh)?.trace_to_closest(ray)?;
        let p = ray.at(hit.distance);
        let (e1, e2, s) = (v1 - v0, v2 - v0, p - v0);
        let n = e1.cross(e2);
        Some(TriangleHit {
            distance: hit.distance,
            beta: s.cross(e2).dot(n) / n.length_squared(),
            gamma: e1.cross(s).dot(n) / n.length_squared(),
            normal: n.normalize(),
        })
    }

    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        let hit = scene_of(Vec::new(), vec![Sphere { material: MaterialId(0), ..*sphere }], Mesh::default())?.trace_to_closest(ray)?;
        Some(SurfaceHit {
            distance: hit.distance,
            normal: (ray.at(hit.distance) - sphere.center) / sphere.radius,
        })
    }
}

impl Shading for Student {
    fn sample_point_light(&self, light: &PointLight, position: Vec3) -> LightSample {
        let to_light = light.position - position;
        let distance = to_light.length();
        LightSample {
            direction: to_light / distance,
            distance,
            radiance: light.intensity / (distance * distance),
        }
    }

    fn sample_directional_light(&self, light: &DirectionalLight, _position: Vec3) -> LightSample {
        LightSample {
            direction: -light.direction.normalize(),
            distance: f32::INFINITY,
            radiance: light.emission,
        }
    }

    fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {
        lights
            .iter()
            .map(|l| rho_d / PI * l.radiance * normal.dot(l.direction).max(0.0))
            .sum()
    }
}
