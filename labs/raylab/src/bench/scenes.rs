//! The benchmark's scenes and ray sets: the Cornell box or a mesh framed by a camera, camera rays
//! through pixel centres, and one diffuse bounce from each of their hits.

use raylab_core::Error;
use raylab_core::glam::{UVec2, Vec2, Vec3};
use raylab_core::math::{Onb, RAY_EPSILON, Ray};
use raylab_core::sampling::Rng;
use raylab_core::scene::{Material, MaterialId, Mesh, ObjData, Scene};

/// A sphere of `rings × segments × 2` triangles with a few percent of radial bumps.
pub fn bumpy_sphere(rings: u32, segments: u32) -> Mesh {
    let mut mesh = Mesh::default();
    for r in 0..=rings {
        let theta = std::f32::consts::PI * r as f32 / rings as f32;
        for s in 0..segments {
            let phi = 2.0 * std::f32::consts::PI * s as f32 / segments as f32;
            let bump = 1.0 + 0.03 * (7.0 * theta).sin() * (11.0 * phi).cos();
            mesh.positions.push(
                bump * Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.cos(),
                    theta.sin() * phi.sin(),
                ),
            );
        }
    }
    for r in 0..rings {
        for s in 0..segments {
            let i = |r: u32, s: u32| r * segments + s % segments;
            let (a, b, c, d) = (i(r, s), i(r, s + 1), i(r + 1, s), i(r + 1, s + 1));
            mesh.faces.push([a, c, b]);
            mesh.faces.push([b, c, d]);
        }
    }
    mesh.face_materials = vec![MaterialId(0); mesh.faces.len()];
    mesh
}

/// The triangles of a scene's mesh, in face order. The benchmark's engines all trace these.
pub fn triangles(scene: &Scene) -> Vec<[Vec3; 3]> {
    (0..scene.mesh.faces.len())
        .map(|f| scene.mesh.triangle(f))
        .collect()
}

/// Camera rays through the pixel centres of an `n × n` image (the reference camera).
pub fn camera_rays(scene: &Scene, n: u32) -> Vec<Ray> {
    let pipeline = reference::pipeline(1);
    let camera = pipeline.prepare_camera(scene, UVec2::splat(n));
    (0..n * n)
        .map(|k| {
            pipeline.camera_ray(
                &camera,
                Vec2::new((k % n) as f32 + 0.5, (k / n) as f32 + 0.5),
            )
        })
        .collect()
}

/// One cosine-distributed diffuse bounce from each hit of `rays` (on the side the ray came from),
/// starting at `tmin = RAY_EPSILON`.
pub fn diffuse_rays(scene: &Scene, rays: &[Ray]) -> Vec<Ray> {
    rays.iter()
        .enumerate()
        .filter_map(|(k, ray)| {
            let hit = scene.trace_to_closest(ray)?;
            let n = if hit.geometric_normal.dot(ray.direction) < 0.0 {
                hit.geometric_normal
            } else {
                -hit.geometric_normal
            };
            let mut rng = Rng::for_sample(5, k as u32, 0, 0);
            let u = rng.next_vec2();
            let (r, phi) = (u.x.sqrt(), 2.0 * std::f32::consts::PI * u.y);
            let local = Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u.x).max(0.0).sqrt());
            Some(Ray::unbounded(
                hit.position,
                Onb::from_w(n).to_world(local).normalize(),
                RAY_EPSILON,
            ))
        })
        .collect()
}

/// A scene of one mesh of grey Lambertian material, framed as `raylab render` frames an OBJ.
pub fn mesh_scene(name: &str, mesh: Mesh) -> Result<Scene, Error> {
    let materials = vec![Material::lambertian("grey", Vec3::splat(0.7))];
    pipeline::job::framed_scene(name, ObjData { mesh, materials }, false)
}
