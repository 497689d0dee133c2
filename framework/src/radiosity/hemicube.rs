//! The hemicube (Cohen and Greenberg 1985): five faces of a unit half-cube over a patch — the
//! top face `z = 1`, `x, y ∈ [−1, 1]`, and four side faces of half height — each cut into
//! pixels. The item buffer holds the patch seen through each pixel's centre, found by casting
//! a ray from the patch's centre through it into the patch mesh's BVH (where the DTU
//! framework renders the faces with OpenGL into a colour buffer of patch ids).

use glam::{Vec2, Vec3};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::contracts::lab06::Radiosity;
use crate::math::{Onb, Ray};

use super::PatchMesh;

/// One face of the hemicube.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum HemicubeFace {
    /// The top face, `z = 1`: `resolution × resolution` pixels.
    Top,
    /// The side face `x = 1` (`u` along `y`): `resolution × resolution/2` pixels.
    PlusU,
    /// The side face `x = −1` (`u` along `−y`).
    MinusU,
    /// The side face `y = 1` (`u` along `−x`).
    PlusV,
    /// The side face `y = −1` (`u` along `x`).
    MinusV,
}

impl HemicubeFace {
    /// The five faces, the top first.
    pub const ALL: [HemicubeFace; 5] = [
        HemicubeFace::Top,
        HemicubeFace::PlusU,
        HemicubeFace::MinusU,
        HemicubeFace::PlusV,
        HemicubeFace::MinusV,
    ];

    /// Pixels across and up the face at hemicube `resolution` (even).
    pub fn size(self, resolution: u32) -> (u32, u32) {
        match self {
            HemicubeFace::Top => (resolution, resolution),
            _ => (resolution, resolution / 2),
        }
    }

    /// The direction, in the patch's frame (`z` along its normal), through the point `c` of
    /// the face: `(x, y)` on the top face, `(u, z)` on a side face.
    pub fn direction(self, c: Vec2) -> Vec3 {
        match self {
            HemicubeFace::Top => Vec3::new(c.x, c.y, 1.0),
            HemicubeFace::PlusU => Vec3::new(1.0, c.x, c.y),
            HemicubeFace::MinusU => Vec3::new(-1.0, -c.x, c.y),
            HemicubeFace::PlusV => Vec3::new(-c.x, 1.0, c.y),
            HemicubeFace::MinusV => Vec3::new(c.x, -1.0, c.y),
        }
    }
}

/// The centre of pixel `(i, j)` (`j` up the face) of a face at `resolution`: `(x, y)` on the
/// top face, `(u, z)` on a side face.
pub fn pixel_centre(face: HemicubeFace, resolution: u32, i: u32, j: u32) -> Vec2 {
    let step = 2.0 / resolution as f32;
    let a = -1.0 + (i as f32 + 0.5) * step;
    match face {
        HemicubeFace::Top => Vec2::new(a, -1.0 + (j as f32 + 0.5) * step),
        _ => Vec2::new(a, (j as f32 + 0.5) * step),
    }
}

/// The area of one pixel of a hemicube at `resolution`, `(2/resolution)²`.
pub fn pixel_area(resolution: u32) -> f32 {
    let step = 2.0 / resolution as f32;
    step * step
}

/// The patch seen through each pixel of the five faces, `None` where no patch is.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ItemBuffer {
    /// Pixels across the top face (even).
    pub resolution: u32,
    /// The faces in the order of [`HemicubeFace::ALL`], each row by row (`i` fastest).
    pub faces: [Vec<Option<u32>>; 5],
}

impl ItemBuffer {
    /// The item buffer of the hemicube on patch `shooter` of `mesh` at `resolution` (made
    /// even), its `z` axis along the patch's normal: one ray from the patch's centre through
    /// the centre of every pixel.
    pub fn render(mesh: &PatchMesh, shooter: usize, resolution: u32) -> Self {
        let patch = &mesh.patches[shooter];
        Self::render_at(mesh, patch.centre, patch.normal, resolution)
    }

    /// The item buffer of a hemicube at `origin` with axis `normal`.
    pub fn render_at(mesh: &PatchMesh, origin: Vec3, normal: Vec3, resolution: u32) -> Self {
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
        Self { resolution, faces }
    }

    /// The ids seen on `face`.
    pub fn face(&self, face: HemicubeFace) -> &[Option<u32>] {
        &self.faces[face as usize]
    }
}

/// The delta form factor of every pixel of a hemicube, tabulated once per resolution by the
/// lab's `delta_form_factor_top` and `delta_form_factor_side` (the four side faces share one
/// table: the formula sees only `(u, z)`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DeltaFormFactors {
    /// Pixels across the top face.
    pub resolution: u32,
    /// The top face's pixels, row by row (the layout of [`ItemBuffer::faces`]`[0]`).
    pub top: Vec<f32>,
    /// A side face's pixels, row by row from the patch's plane up.
    pub side: Vec<f32>,
}

impl DeltaFormFactors {
    /// The table at `resolution` (made even) from `radiosity`'s delta form factors.
    pub fn tabulate(radiosity: &dyn Radiosity, resolution: u32) -> Self {
        let resolution = resolution.max(2).next_multiple_of(2);
        let area = pixel_area(resolution);
        let table = |face: HemicubeFace| {
            let (w, h) = face.size(resolution);
            (0..w * h)
                .map(|k| {
                    let c = pixel_centre(face, resolution, k % w, k / w);
                    match face {
                        HemicubeFace::Top => radiosity.delta_form_factor_top(c.x, c.y, area),
                        _ => radiosity.delta_form_factor_side(c.x, c.y, area),
                    }
                })
                .collect()
        };
        Self {
            resolution,
            top: table(HemicubeFace::Top),
            side: table(HemicubeFace::PlusU),
        }
    }

    /// The delta form factors of `face`'s pixels, in the layout of [`ItemBuffer::face`].
    pub fn face(&self, face: HemicubeFace) -> &[f32] {
        match face {
            HemicubeFace::Top => &self.top,
            _ => &self.side,
        }
    }

    /// The sum over the whole hemicube (1 up to the discretisation).
    pub fn total(&self) -> f64 {
        self.top.iter().map(|&d| d as f64).sum::<f64>()
            + 4.0 * self.side.iter().map(|&d| d as f64).sum::<f64>()
    }
}
