//! Embree 3 (the C library, through the `embree3` crate) as the benchmark's reference: one
//! triangle geometry in a scene of default build quality, with default flags or with the
//! `ROBUST` flag, queried one ray at a time with `rtcIntersect1` / `rtcOccluded1`. Only built
//! with the `embree` feature.

use embree3::{
    BufferUsage, Config, Device, Format, GeometryKind, IntersectContext, Ray as EmRay, RayHit,
    Scene as EmScene, SceneFlags,
};
use raylab_core::Error;
use raylab_core::glam::Vec3;
use raylab_core::math::Ray;

use super::engine::{Engine, EngineHit};

/// An Embree device and a committed scene over one triangle mesh.
pub struct Embree {
    // The scene holds a reference count on the device; keep both for the engine's lifetime.
    scene: EmScene<'static>,
    _device: Device,
}

/// Embree's "no geometry" id.
const INVALID_ID: u32 = u32::MAX;

impl Embree {
    /// Creates a device with one build thread (as the other builders have) and builds the scene
    /// over `triangles`; `robust` sets the scene's `ROBUST` flag, which Embree documents as
    /// avoiding the optimizations that reduce arithmetic accuracy, so that rays do not slip
    /// through the edges of neighbouring primitives — what the core's conservative traversal
    /// and watertight test guarantee.
    pub fn build(triangles: &[[Vec3; 3]], robust: bool) -> Result<Self, Error> {
        let fail = |what: &str, e: embree3::Error| Error::Failed {
            what: format!("Embree {what}"),
            reason: format!("{e:?}"),
        };
        let device = Device::with_config(Config {
            threads: 1,
            ..Config::default()
        })
        .map_err(|e| fail("device", e))?;
        let mut geometry = device
            .create_geometry(GeometryKind::TRIANGLE)
            .map_err(|e| fail("geometry", e))?;
        let n = triangles.len();
        geometry
            .set_new_buffer::<[f32; 3]>(BufferUsage::VERTEX, 0, Format::FLOAT3, 12, 3 * n)
            .map_err(|e| fail("vertex buffer", e))?
            .iter_mut()
            .zip(triangles.iter().flatten())
            .for_each(|(dst, &v)| *dst = flat(v));
        geometry
            .set_new_buffer::<[u32; 3]>(BufferUsage::INDEX, 0, Format::UINT3, 12, n)
            .map_err(|e| fail("index buffer", e))?
            .iter_mut()
            .zip(0u32..)
            .for_each(|(dst, f)| *dst = [3 * f, 3 * f + 1, 3 * f + 2]);
        let geometry = geometry.commit();
        let mut scene = device.create_scene().map_err(|e| fail("scene", e))?;
        if robust {
            scene.set_flags(scene.get_flags() | SceneFlags::ROBUST);
        }
        scene.attach_geometry(&geometry);
        scene.commit();
        Ok(Embree {
            scene,
            _device: device,
        })
    }
}

fn em_ray(ray: &Ray) -> EmRay {
    EmRay::segment(flat(ray.origin), flat(ray.direction), ray.tmin, ray.tmax)
}

impl Engine for Embree {
    fn closest(&self, ray: &Ray) -> Option<EngineHit> {
        let mut ctx = IntersectContext::incoherent();
        let mut hit = RayHit::from_ray(em_ray(ray));
        self.scene.intersect(&mut ctx, &mut hit);
        (hit.hit.geomID != INVALID_ID).then_some(EngineHit {
            t: hit.ray.tfar,
            prim: Some(hit.hit.primID),
        })
    }

    fn any(&self, ray: &Ray) -> bool {
        let mut ctx = IntersectContext::incoherent();
        self.scene.occluded(&mut ctx, &mut em_ray(ray))
    }
}

/// A vector as the `[f32; 3]` Embree's buffers and rays take.
fn flat(v: Vec3) -> [f32; 3] {
    v.to_array()
}
