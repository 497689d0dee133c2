//! Reference solution of lab 09 (docs/lab09.md).

use std::f32::consts::{PI, TAU};

use contracts::glam::{Vec2, Vec3};
use contracts::lab09::{Addressing, Texturing};
use contracts::scene::{Plane, Sphere, Texture};

/// The reference texture mapping.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab09;

/// The column (or row counted from the bottom) of the texel of a texture `n` texels across
/// whose centre `k + ½` lies at the addressed coordinate: `k` may be outside `[0, n)`.
fn addressed_texel(k: f32, n: u32, address: &dyn Fn(f32) -> f32) -> u32 {
    let t = address((k + 0.5) / n as f32);
    ((t * n as f32).floor().max(0.0) as u32).min(n - 1)
}

impl Texturing for Lab09 {
    fn plane_texcoord(&self, plane: &Plane, position: Vec3) -> Vec2 {
        // The origin −d·n is orthogonal to both tangents, so it drops out of the dot products.
        Vec2::new(position.dot(plane.tangent), position.dot(plane.bitangent)) / plane.tex_scale
    }

    fn sphere_texcoord(&self, sphere: &Sphere, position: Vec3) -> Vec2 {
        let d = ((position - sphere.center) / sphere.radius).normalize_or_zero();
        let u = 0.5 + d.x.atan2(d.z) / TAU;
        let v = 0.5 + d.y.clamp(-1.0, 1.0).asin() / PI;
        Vec2::new(u.clamp(0.0, 1.0), v)
    }

    fn triangle_texcoord(&self, uvs: [Vec2; 3], barycentrics: Vec2) -> Vec2 {
        let (beta, gamma) = (barycentrics.x, barycentrics.y);
        (1.0 - beta - gamma) * uvs[0] + beta * uvs[1] + gamma * uvs[2]
    }

    fn address(&self, t: f32, mode: Addressing) -> f32 {
        let repeat = |t: f32| t - t.floor();
        match mode {
            Addressing::Repeat => repeat(t),
            Addressing::Mirror => {
                // ELUMI: the sign (−1)^⌊t⌋ flips every other period; 1 − repeat(t) rather
                // than repeat(−t) keeps the odd whole numbers at 1, where mirror is continuous.
                let odd = t.floor().rem_euclid(2.0) == 1.0;
                if odd { 1.0 - repeat(t) } else { repeat(t) }
            }
            Addressing::Clamp => t.clamp(0.0, 1.0),
        }
    }

    fn sample_nearest(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3 {
        let (w, h) = (texture.width, texture.height);
        let u = address(uv.x);
        let v = address(uv.y);
        let i = ((u * w as f32).floor().max(0.0) as u32).min(w - 1);
        let j = (((1.0 - v) * h as f32).floor().max(0.0) as u32).min(h - 1);
        texture.texel(i, j)
    }

    fn sample_bilinear(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3 {
        let (w, h) = (texture.width, texture.height);
        // Texel-centre coordinates: texel k's centre is at k + ½ texels.
        let x = uv.x * w as f32 - 0.5;
        let y = uv.y * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (s, t) = (x - x0, y - y0);
        let i0 = addressed_texel(x0, w, address);
        let i1 = addressed_texel(x0 + 1.0, w, address);
        // Rows counted from the bottom, then turned into rows from the top.
        let j0 = h - 1 - addressed_texel(y0, h, address);
        let j1 = h - 1 - addressed_texel(y0 + 1.0, h, address);
        let bottom = texture.texel(i0, j0).lerp(texture.texel(i1, j0), s);
        let top = texture.texel(i0, j1).lerp(texture.texel(i1, j1), s);
        bottom.lerp(top, t)
    }
}
