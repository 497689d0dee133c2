//! Lab 09 — texture mapping (docs/lab09.md).
//!
//! The texturing pipeline of Akenine-Möller et al. as ELUMI follows it: a *projector function*
//! turns a surface point into texture coordinates `(u, v)` (the plane's tangent frame, the
//! sphere's spherical coordinates, the triangle's interpolated vertex coordinates), a
//! *corresponder function* maps coordinates outside `[0, 1]` back into it (repeat, mirror,
//! clamp), and a lookup reads the texture there (nearest texel or bilinear). With a pipeline at
//! lab 9 or later, the integrator calls these for every hit on a surface whose material has a
//! diffuse texture (`map_Kd`) and multiplies the texel into the material's diffuse colour.
//!
//! Texture coordinates follow the OBJ convention: `(0, 0)` is the image's bottom-left corner,
//! `u` runs to the right and `v` up, while a [`Texture`] stores its rows top row first.

use glam::{Vec2, Vec3};

use crate::scene::{Plane, Sphere, Texture};

/// What happens to texture coordinates outside `[0, 1]` (ELUMI's corresponder functions).
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum Addressing {
    /// The texture repeats: `t` and `t + 1` look up the same place.
    #[default]
    Repeat,
    /// The texture repeats flipped every other time: periodic with period 2 and symmetric
    /// about every integer.
    Mirror,
    /// Coordinates are clamped to `[0, 1]`: the edge texels stretch out to infinity.
    Clamp,
}

impl Addressing {
    /// Every addressing mode.
    pub const ALL: [Addressing; 3] = [Addressing::Repeat, Addressing::Mirror, Addressing::Clamp];
}

/// How a texture is read between texel centres.
#[derive(
    Clone, Copy, Debug, Default, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize,
)]
pub enum TextureFilter {
    /// The texel whose centre is closest (point sampling).
    Nearest,
    /// Bilinear interpolation of the four texels around the point.
    #[default]
    Bilinear,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab09`.
pub type Contract = dyn Texturing;

/// Lab 09's contract (the DTU framework's `Plane::intersect` and `Sphere::intersect` texture
/// coordinates, the triangle's interpolated `texcoord`, ELUMI's corresponder functions, and
/// `Texture::sample_nearest` / `Texture::sample_linear`).
#[crate::contract]
pub trait Texturing: Send + Sync {
    /// Exercise 9.1 — `plane_texcoord`: the texture coordinates of the point `position` of
    /// `plane`: its coordinates in the plane's frame (`plane.tangent` for `u`,
    /// `plane.bitangent` for `v`) measured from the plane's point closest to the world origin
    /// (`−d·n`), in units of `plane.tex_scale` (world units per repeat of the texture).
    fn plane_texcoord(&self, plane: &Plane, position: Vec3) -> Vec2;

    /// Exercise 9.2 — `sphere_texcoord`: the spherical texture coordinates of the point
    /// `position` of `sphere`. With `d` the unit direction from the centre: `u ∈ [0, 1]` is the
    /// longitude about the `y` axis, `½` towards `+z` and increasing towards `+x` (the seam is
    /// towards `−z`), `v ∈ [0, 1]` the latitude from the south pole (`d = −y`, `v = 0`) to the
    /// north pole (`v = 1`), linear in the angles.
    fn sphere_texcoord(&self, sphere: &Sphere, position: Vec3) -> Vec2;

    /// Exercise 9.3 — `triangle_texcoord`: the texture coordinates at the point of barycentric
    /// coordinates `(β, γ) = barycentrics` of a triangle whose vertices have the texture
    /// coordinates `uvs` (vertex 0 has weight `1 − β − γ`, vertex 1 `β`, vertex 2 `γ`).
    fn triangle_texcoord(&self, uvs: [Vec2; 3], barycentrics: Vec2) -> Vec2;

    /// Exercise 9.4 — `address`: the corresponder function `mode` applied to one texture
    /// coordinate `t` (any finite number, negative too): a number in `[0, 1]`, equal to `t`
    /// where `t` is in `[0, 1)`.
    fn address(&self, t: f32, mode: Addressing) -> f32;

    /// Exercise 9.5 — `sample_nearest`: the texel of `texture` whose centre is closest to the
    /// texture coordinates `uv` after the corresponder `address` (call it on `u` and on `v`).
    /// Texel `(i, j)` (column `i`, row `j` from the top, [`Texture::texel`]) covers
    /// `[i/w, (i+1)/w] × [1 − (j+1)/h, 1 − j/h]` of texture space.
    fn sample_nearest(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3;

    /// Exercise 9.6 — `sample_bilinear`: the bilinear interpolation of the four texels of
    /// `texture` whose centres surround `uv`, each neighbour found through the corresponder
    /// `address` (so the texture is continuous across texel edges and, repeated, across the
    /// seam); at a texel's centre, that texel.
    fn sample_bilinear(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3;
}
