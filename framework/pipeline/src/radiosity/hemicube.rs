//! The hemicube (Cohen and Greenberg 1985): five faces of a unit half-cube over a patch — the
//! top face `z = 1`, `x, y ∈ [−1, 1]`, and four side faces of half height — each cut into
//! pixels. The item buffer holds the patch seen through each pixel's centre, found by casting
//! a ray from the patch's centre through it into the patch mesh's BVH (where the DTU
//! framework renders the faces with OpenGL into a colour buffer of patch ids).

use glam::Vec3;
use rayon::prelude::*;

use contracts::lab06::{HemicubeFace, ItemBuffer, pixel_centre};
use raylab_core::math::{Onb, Ray};

use super::PatchMesh;

/// The item buffer of the hemicube on patch `shooter` of `mesh` at `resolution` (made
/// even), its `z` axis along the patch's normal: one ray from the patch's centre through
/// the centre of every pixel.
pub fn item_buffer(mesh: &PatchMesh, shooter: usize, resolution: u32) -> ItemBuffer {
    let patch = &mesh.patches[shooter];
    item_buffer_at(mesh, patch.centre, patch.normal, resolution)
}

/// The item buffer of a hemicube at `origin` with axis `normal`.
pub fn item_buffer_at(mesh: &PatchMesh, origin: Vec3, normal: Vec3, resolution: u32) -> ItemBuffer {
    let resolution = resolution.max(2).next_multiple_of(2);
    let frame = Onb::from_w(normal);
    let tmin = 1e-6 * mesh.extent();
    let faces = HemicubeFace::ALL.map(|face| {
        let (w, h) = face.size(resolution);
        (0..w * h)
            .into_par_iter()
            .map(|k| {
                let c = pixel_centre(face, resolution, k % w, k / w);
                let dir = frame.to_world(face.direction(c)).normalize();
                let ray = Ray::unbounded(origin, dir, tmin);
                mesh.closest_patch(&ray).map(|h| h.patch)
            })
            .collect()
    });
    ItemBuffer { resolution, faces }
}
