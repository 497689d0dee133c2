//! # Lab 09 — texture mapping
//!
//! A texture glues an image onto a surface: every hit point gets texture coordinates `(u, v)`
//! (the *projector function*: a plane's frame, a sphere's longitude and latitude, a
//! triangle's interpolated vertex coordinates), coordinates outside `[0, 1]` are brought back
//! into it (the *corresponder function*: repeat, mirror or clamp), and the image is read there
//! (the nearest texel, or the bilinear blend of four). The framework multiplies the texel into
//! the material's diffuse colour when the pipeline is at lab 9 and the material has a `map_Kd`.
//!
//! Read `docs/lab09.md` first. Then fill in the functions below in order and run
//!
//! ```text
//! cargo test -p lab09                # every exercise
//! cargo test -p lab09 exercise_9_5   # one exercise
//! raylab report --lab 9 --pipeline student
//! ```
//!
//! Texture coordinates follow the OBJ convention: `(0, 0)` is the bottom-left corner of the
//! image, `u` goes right and `v` up. `texture.texel(i, j)` is column `i` from the left and row
//! `j` from the top, `0 ≤ i < texture.width`, `0 ≤ j < texture.height`.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

use contracts::glam::{Vec2, Vec3};
use contracts::lab09::{Addressing, Texturing};
use contracts::scene::{Plane, Sphere, Texture};

/// Your texture mapping. The framework calls it through the `Texturing` trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Texturing for Student {
    /// **Exercise 9.1** — the plane's texture coordinates (docs/lab09.md, §9.1; DTU
    /// `Plane::intersect`).
    ///
    /// Express `position` in the plane's own frame: `u` along `plane.tangent`, `v` along
    /// `plane.bitangent`, measured from the plane's point `−d·n` closest to the origin, and
    /// divide by `plane.tex_scale` (world units per repeat of the texture).
    fn plane_texcoord(&self, plane: &Plane, position: Vec3) -> Vec2 {
        todo!("Exercise 9.1: plane_texcoord (docs/lab09.md, Exercise 9.1)")
    }

    /// **Exercise 9.2** — spherical texture coordinates (docs/lab09.md, §9.2).
    ///
    /// With `d` the unit direction from `sphere.center` to `position`: `u` is the longitude
    /// about the y axis (`0.5` towards `+z`, growing towards `+x`, the seam towards `−z`) and
    /// `v` the latitude (`0` at the south pole `−y`, `1` at the north pole), both in `[0, 1]`.
    fn sphere_texcoord(&self, sphere: &Sphere, position: Vec3) -> Vec2 {
        todo!("Exercise 9.2: sphere_texcoord (docs/lab09.md, Exercise 9.2)")
    }

    /// **Exercise 9.3** — a triangle's texture coordinates (docs/lab09.md, §9.3).
    ///
    /// Interpolate the vertices' coordinates `uvs` with the barycentric coordinates
    /// `(β, γ) = (barycentrics.x, barycentrics.y)`: vertex 0 weighs `1 − β − γ`, vertex 1 `β`,
    /// vertex 2 `γ`.
    fn triangle_texcoord(&self, uvs: [Vec2; 3], barycentrics: Vec2) -> Vec2 {
        todo!("Exercise 9.3: triangle_texcoord (docs/lab09.md, Exercise 9.3)")
    }

    /// **Exercise 9.4** — the corresponder functions (docs/lab09.md, §9.4; ELUMI §4.5.2).
    ///
    /// Map any finite `t` (negative ones too) into `[0, 1]`: `Repeat` keeps the fractional
    /// part (`t − ⌊t⌋`), `Mirror` flips every other repeat, `Clamp` clamps to `[0, 1]`.
    fn address(&self, t: f32, mode: Addressing) -> f32 {
        todo!("Exercise 9.4: address (docs/lab09.md, Exercise 9.4)")
    }

    /// **Exercise 9.5** — nearest-texel lookup (docs/lab09.md, §9.5; DTU
    /// `Texture::sample_nearest`).
    ///
    /// Apply `address` to `uv.x` and `uv.y`, then return the texel whose centre is closest:
    /// the one whose square contains the point. Remember that rows count from the top while
    /// `v` goes up, and that `address` may return exactly `1`.
    fn sample_nearest(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3 {
        todo!("Exercise 9.5: sample_nearest (docs/lab09.md, Exercise 9.5)")
    }

    /// **Exercise 9.6** — bilinear lookup (docs/lab09.md, §9.6; DTU `Texture::sample_linear`).
    ///
    /// Find the four texels whose centres surround `uv` (texel `k`'s centre is `k + ½` texels
    /// from the edge), each neighbour through `address` (apply it to the neighbour's centre
    /// coordinate), and blend them with the point's fractional position between the centres.
    fn sample_bilinear(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3 {
        todo!("Exercise 9.6: sample_bilinear (docs/lab09.md, Exercise 9.6)")
    }
}
