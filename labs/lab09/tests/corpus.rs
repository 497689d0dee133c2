//! Lab 09's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use std::f32::consts::{PI, TAU};

use contracts::lab09::{Addressing, Texturing};
use raylab_core::glam::{Vec2, Vec3};
use raylab_core::math::Onb;
use raylab_core::scene::{Plane, Sphere, Texture};
use reference::lab09::Lab09 as Reference;

use grading::corpus::Verdict;

type PlaneFn = fn(&Plane, Vec3) -> Vec2;
type SphereFn = fn(&Sphere, Vec3) -> Vec2;
type TriangleFn = fn([Vec2; 3], Vec2) -> Vec2;
type AddressFn = fn(f32, Addressing) -> f32;
type LookupFn = fn(&Texture, Vec2, &dyn Fn(f32) -> f32) -> Vec3;

/// A lab 09 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    plane: Option<PlaneFn>,
    sphere: Option<SphereFn>,
    triangle: Option<TriangleFn>,
    address: Option<AddressFn>,
    nearest: Option<LookupFn>,
    bilinear: Option<LookupFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    plane: None,
    sphere: None,
    triangle: None,
    address: None,
    nearest: None,
    bilinear: None,
};

impl Texturing for Variant {
    fn plane_texcoord(&self, plane: &Plane, position: Vec3) -> Vec2 {
        match self.plane {
            Some(f) => f(plane, position),
            None => Reference.plane_texcoord(plane, position),
        }
    }
    fn sphere_texcoord(&self, sphere: &Sphere, position: Vec3) -> Vec2 {
        match self.sphere {
            Some(f) => f(sphere, position),
            None => Reference.sphere_texcoord(sphere, position),
        }
    }
    fn triangle_texcoord(&self, uvs: [Vec2; 3], barycentrics: Vec2) -> Vec2 {
        match self.triangle {
            Some(f) => f(uvs, barycentrics),
            None => Reference.triangle_texcoord(uvs, barycentrics),
        }
    }
    fn address(&self, t: f32, mode: Addressing) -> f32 {
        match self.address {
            Some(f) => f(t, mode),
            None => Reference.address(t, mode),
        }
    }
    fn sample_nearest(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3 {
        match self.nearest {
            Some(f) => f(texture, uv, address),
            None => Reference.sample_nearest(texture, uv, address),
        }
    }
    fn sample_bilinear(&self, texture: &Texture, uv: Vec2, address: &dyn Fn(f32) -> f32) -> Vec3 {
        match self.bilinear {
            Some(f) => f(texture, uv, address),
            None => Reference.sample_bilinear(texture, uv, address),
        }
    }
}

/// The reference's address for every mode but `mode`, which `f` answers.
fn address_with(t: f32, mode: Addressing, only: Addressing, f: fn(f32) -> f32) -> f32 {
    if mode == only {
        f(t)
    } else {
        Reference.address(t, mode)
    }
}

/// The unit direction from a sphere's centre to `p`.
fn direction(s: &Sphere, p: Vec3) -> Vec3 {
    ((p - s.center) / s.radius).normalize()
}

/// A bilinear lookup with the neighbours' columns and rows (rows from the bottom) from
/// `index(k, n, address)` and the texel-centre offset `half`.
fn bilinear_by(
    texture: &Texture,
    uv: Vec2,
    address: &dyn Fn(f32) -> f32,
    half: f32,
    index: fn(f32, u32, &dyn Fn(f32) -> f32) -> u32,
) -> Vec3 {
    let (w, h) = (texture.width, texture.height);
    let x = uv.x * w as f32 - half;
    let y = uv.y * h as f32 - half;
    let (x0, y0) = (x.floor(), y.floor());
    let (s, t) = (x - x0, y - y0);
    let (i0, i1) = (index(x0, w, address), index(x0 + 1.0, w, address));
    let (j0, j1) = (
        h - 1 - index(y0, h, address),
        h - 1 - index(y0 + 1.0, h, address),
    );
    let bottom = texture.texel(i0, j0).lerp(texture.texel(i1, j0), s);
    let top = texture.texel(i0, j1).lerp(texture.texel(i1, j1), s);
    bottom.lerp(top, t)
}

/// The reference's neighbour: the texel at the addressed centre of `k`.
fn addressed(k: f32, n: u32, address: &dyn Fn(f32) -> f32) -> u32 {
    let t = address((k + 0.5) / n as f32);
    ((t * n as f32).floor().max(0.0) as u32).min(n - 1)
}

/// Every lab 09 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // ---- Exercise 9.1 mistakes
        Variant {
            name: "plane: multiplied by tex_scale instead of divided",
            verdict: Verdict::Reject("9.1"),
            plane: Some(|pl, p| Vec2::new(p.dot(pl.tangent), p.dot(pl.bitangent)) * pl.tex_scale),
            ..NONE
        },
        Variant {
            name: "plane: tex_scale ignored",
            verdict: Verdict::Reject("9.1"),
            plane: Some(|pl, p| Vec2::new(p.dot(pl.tangent), p.dot(pl.bitangent))),
            ..NONE
        },
        Variant {
            name: "plane: u and v swapped",
            verdict: Verdict::Reject("9.1"),
            plane: Some(|pl, p| Vec2::new(p.dot(pl.bitangent), p.dot(pl.tangent)) / pl.tex_scale),
            ..NONE
        },
        Variant {
            name: "plane: the normal instead of the bitangent for v",
            verdict: Verdict::Reject("9.1"),
            plane: Some(|pl, p| Vec2::new(p.dot(pl.tangent), p.dot(pl.normal)) / pl.tex_scale),
            ..NONE
        },
        Variant {
            name: "plane: world x and z as u and v (right for the ground only)",
            verdict: Verdict::Reject("9.1"),
            plane: Some(|pl, p| Vec2::new(p.x, p.z) / pl.tex_scale),
            ..NONE
        },
        Variant {
            name: "plane: its own frame from the normal instead of the plane's tangents",
            verdict: Verdict::Reject("9.1"),
            plane: Some(|pl, p| {
                let onb = Onb::from_w(pl.normal);
                Vec2::new(p.dot(onb.u), p.dot(onb.v)) / pl.tex_scale
            }),
            ..NONE
        },
        // ---- Exercise 9.2 mistakes
        Variant {
            name: "sphere: longitude atan2(z, x) (another convention)",
            verdict: Verdict::Reject("9.2"),
            sphere: Some(|s, p| {
                let d = direction(s, p);
                Vec2::new(0.5 + d.z.atan2(d.x) / TAU, 0.5 + d.y.asin() / PI)
            }),
            ..NONE
        },
        Variant {
            name: "sphere: v from the north pole (acos(y)/π)",
            verdict: Verdict::Reject("9.2"),
            sphere: Some(|s, p| {
                let d = direction(s, p);
                Vec2::new(0.5 + d.x.atan2(d.z) / TAU, d.y.clamp(-1.0, 1.0).acos() / PI)
            }),
            ..NONE
        },
        Variant {
            name: "sphere: u without the ½ offset (in [−½, ½])",
            verdict: Verdict::Reject("9.2"),
            sphere: Some(|s, p| {
                let d = direction(s, p);
                Vec2::new(d.x.atan2(d.z) / TAU, 0.5 + d.y.asin() / PI)
            }),
            ..NONE
        },
        Variant {
            name: "sphere: v linear in y instead of the latitude",
            verdict: Verdict::Reject("9.2"),
            sphere: Some(|s, p| {
                let d = direction(s, p);
                Vec2::new(0.5 + d.x.atan2(d.z) / TAU, 0.5 + 0.5 * d.y)
            }),
            ..NONE
        },
        Variant {
            name: "sphere: the centre not subtracted",
            verdict: Verdict::Reject("9.2"),
            sphere: Some(|s, p| {
                let d = (p / s.radius).normalize();
                Vec2::new(
                    0.5 + d.x.atan2(d.z) / TAU,
                    0.5 + d.y.clamp(-1.0, 1.0).asin() / PI,
                )
            }),
            ..NONE
        },
        Variant {
            name: "sphere: atan(x/z) instead of atan2 (half the longitudes wrong)",
            verdict: Verdict::Reject("9.2"),
            sphere: Some(|s, p| {
                let d = direction(s, p);
                Vec2::new(0.5 + (d.x / d.z).atan() / TAU, 0.5 + d.y.asin() / PI)
            }),
            ..NONE
        },
        // ---- Exercise 9.3 mistakes
        Variant {
            name: "triangle: β and γ on the wrong vertices (β for vertex 2)",
            verdict: Verdict::Reject("9.3"),
            triangle: Some(|uv, b| (1.0 - b.x - b.y) * uv[0] + b.y * uv[1] + b.x * uv[2]),
            ..NONE
        },
        Variant {
            name: "triangle: 1 − β − γ on vertex 1",
            verdict: Verdict::Reject("9.3"),
            triangle: Some(|uv, b| b.x * uv[0] + (1.0 - b.x - b.y) * uv[1] + b.y * uv[2]),
            ..NONE
        },
        Variant {
            name: "triangle: vertex 0 forgotten (β·uv₁ + γ·uv₂)",
            verdict: Verdict::Reject("9.3"),
            triangle: Some(|uv, b| b.x * uv[1] + b.y * uv[2]),
            ..NONE
        },
        Variant {
            name: "triangle: the mean of the vertices",
            verdict: Verdict::Reject("9.3"),
            triangle: Some(|uv, _| (uv[0] + uv[1] + uv[2]) / 3.0),
            ..NONE
        },
        // ---- Exercise 9.4 mistakes
        Variant {
            name: "address: repeat by t % 1 (negative t stays negative)",
            verdict: Verdict::Reject("9.4"),
            address: Some(|t, m| address_with(t, m, Addressing::Repeat, |t| t % 1.0)),
            ..NONE
        },
        Variant {
            name: "address: repeat by f32::fract (truncates towards zero)",
            verdict: Verdict::Reject("9.4"),
            address: Some(|t, m| address_with(t, m, Addressing::Repeat, f32::fract)),
            ..NONE
        },
        Variant {
            name: "address: mirror as the repeat of |t|",
            verdict: Verdict::Reject("9.4"),
            address: Some(|t, m| {
                address_with(t, m, Addressing::Mirror, |t| t.abs() - t.abs().floor())
            }),
            ..NONE
        },
        Variant {
            name: "address: mirror's parity from ⌊t⌋ cast to u32 (negative periods even)",
            verdict: Verdict::Reject("9.4"),
            address: Some(|t, m| {
                address_with(t, m, Addressing::Mirror, |t| {
                    let r = t - t.floor();
                    if (t.floor() as u32) % 2 == 1 {
                        1.0 - r
                    } else {
                        r
                    }
                })
            }),
            ..NONE
        },
        Variant {
            name: "address: mirror flips every repeat (1 − repeat)",
            verdict: Verdict::Reject("9.4"),
            address: Some(|t, m| address_with(t, m, Addressing::Mirror, |t| 1.0 - (t - t.floor()))),
            ..NONE
        },
        Variant {
            name: "address: clamp repeats instead",
            verdict: Verdict::Reject("9.4"),
            address: Some(|t, m| address_with(t, m, Addressing::Clamp, |t| t - t.floor())),
            ..NONE
        },
        // ---- Exercise 9.5 mistakes
        Variant {
            name: "nearest: the hand-in's ⌊u·(w − 1) + ½⌋ (not the closest centre)",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (address(uv.x), address(uv.y));
                let i = ((u * (w - 1) as f32 + 0.5).floor() as u32).min(w - 1);
                let j = (((1.0 - v) * (h - 1) as f32 + 0.5).floor() as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        Variant {
            name: "nearest: v not flipped (row 0 at v = 0)",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (address(uv.x), address(uv.y));
                let i = ((u * w as f32) as u32).min(w - 1);
                let j = ((v * h as f32) as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        Variant {
            name: "nearest: rounded instead of floored (round(u·w))",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (address(uv.x), address(uv.y));
                let i = ((u * w as f32).round() as u32).min(w - 1);
                let j = (((1.0 - v) * h as f32).round() as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        Variant {
            name: "nearest: its own wrapping instead of the corresponder it is given",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, _| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (uv.x - uv.x.floor(), uv.y - uv.y.floor());
                let i = ((u * w as f32) as u32).min(w - 1);
                let j = (((1.0 - v) * h as f32) as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        Variant {
            name: "nearest: the width for the rows too",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (address(uv.x), address(uv.y));
                let i = ((u * w as f32) as u32).min(w - 1);
                let j = (((1.0 - v) * w as f32) as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        Variant {
            name: "nearest: address applied to u only (v used as it is)",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (address(uv.x), uv.y);
                let i = ((u * w as f32).floor().max(0.0) as u32).min(w - 1);
                let j = (((1.0 - v) * h as f32).floor().max(0.0) as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        Variant {
            name: "nearest: the column not clamped (u = 1 reads one past the last column)",
            verdict: Verdict::Reject("9.5"),
            nearest: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let (u, v) = (address(uv.x), address(uv.y));
                let i = (u * w as f32).floor().max(0.0) as u32;
                let j = (((1.0 - v) * h as f32).floor().max(0.0) as u32).min(h - 1);
                tex.texel(i, j)
            }),
            ..NONE
        },
        // ---- Exercise 9.6 mistakes
        Variant {
            name: "bilinear: s and t swapped (s blends the rows, t the columns)",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let x = uv.x * w as f32 - 0.5;
                let y = uv.y * h as f32 - 0.5;
                let (x0, y0) = (x.floor(), y.floor());
                let (s, t) = (x - x0, y - y0);
                let (i0, i1) = (addressed(x0, w, address), addressed(x0 + 1.0, w, address));
                let (j0, j1) = (
                    h - 1 - addressed(y0, h, address),
                    h - 1 - addressed(y0 + 1.0, h, address),
                );
                let bottom = tex.texel(i0, j0).lerp(tex.texel(i1, j0), t);
                let top = tex.texel(i0, j1).lerp(tex.texel(i1, j1), t);
                bottom.lerp(top, s)
            }),
            ..NONE
        },
        Variant {
            name: "bilinear: the nearest texel instead",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| Reference.sample_nearest(tex, uv, address)),
            ..NONE
        },
        Variant {
            name: "bilinear: no half-texel offset (the hand-in's a = u·w)",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| bilinear_by(tex, uv, address, 0.0, addressed)),
            ..NONE
        },
        Variant {
            name: "bilinear: the weights swapped (1 − s on the right neighbour)",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let x = uv.x * w as f32 - 0.5;
                let y = uv.y * h as f32 - 0.5;
                let (x0, y0) = (x.floor(), y.floor());
                let (s, t) = (x - x0, y - y0);
                let (i0, i1) = (addressed(x0, w, address), addressed(x0 + 1.0, w, address));
                let (j0, j1) = (
                    h - 1 - addressed(y0, h, address),
                    h - 1 - addressed(y0 + 1.0, h, address),
                );
                let bottom = tex.texel(i0, j0).lerp(tex.texel(i1, j0), 1.0 - s);
                let top = tex.texel(i0, j1).lerp(tex.texel(i1, j1), 1.0 - s);
                bottom.lerp(top, 1.0 - t)
            }),
            ..NONE
        },
        Variant {
            name: "bilinear: neighbours clamped into the image instead of addressed (seam)",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| {
                let u = Vec2::new(address(uv.x), address(uv.y));
                bilinear_by(tex, u, address, 0.5, |k, n, _| {
                    (k.max(0.0) as u32).min(n - 1)
                })
            }),
            ..NONE
        },
        Variant {
            name: "bilinear: v not flipped (rows from the top blended as if from the bottom)",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let x = uv.x * w as f32 - 0.5;
                let y = uv.y * h as f32 - 0.5;
                let (x0, y0) = (x.floor(), y.floor());
                let (s, t) = (x - x0, y - y0);
                let (i0, i1) = (addressed(x0, w, address), addressed(x0 + 1.0, w, address));
                let (j0, j1) = (addressed(y0, h, address), addressed(y0 + 1.0, h, address));
                let bottom = tex.texel(i0, j0).lerp(tex.texel(i1, j0), s);
                let top = tex.texel(i0, j1).lerp(tex.texel(i1, j1), s);
                bottom.lerp(top, t)
            }),
            ..NONE
        },
        Variant {
            name: "bilinear: interpolated along u only",
            verdict: Verdict::Reject("9.6"),
            bilinear: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let x = uv.x * w as f32 - 0.5;
                let x0 = x.floor();
                let s = x - x0;
                let (i0, i1) = (addressed(x0, w, address), addressed(x0 + 1.0, w, address));
                let v = address(uv.y);
                let j = (((1.0 - v) * h as f32) as u32).min(h - 1);
                tex.texel(i0, j).lerp(tex.texel(i1, j), s)
            }),
            ..NONE
        },
        // ---- Correct alternatives
        Variant {
            name: "alternative: mirror as the triangle wave 1 − |(t mod 2) − 1|, repeat by rem_euclid",
            verdict: Verdict::Accept,
            address: Some(|t, m| match m {
                Addressing::Repeat => t.rem_euclid(1.0).min(1.0),
                Addressing::Mirror => 1.0 - (t.rem_euclid(2.0) - 1.0).abs(),
                Addressing::Clamp => t.clamp(0.0, 1.0),
            }),
            ..NONE
        },
        Variant {
            name: "alternative: spherical v by acos from the south pole, u from atan2 shifted by π",
            verdict: Verdict::Accept,
            sphere: Some(|s, p| {
                let d = direction(s, p);
                Vec2::new(
                    (PI + d.x.atan2(d.z)) / TAU,
                    1.0 - d.y.clamp(-1.0, 1.0).acos() / PI,
                )
            }),
            ..NONE
        },
        Variant {
            name: "alternative: bilinear blending the rows first, then the columns; plane from an explicit origin −d·n",
            verdict: Verdict::Accept,
            plane: Some(|pl, p| {
                let q = p + pl.d * pl.normal;
                Vec2::new(q.dot(pl.tangent), q.dot(pl.bitangent)) / pl.tex_scale
            }),
            bilinear: Some(|tex, uv, address| {
                let (w, h) = (tex.width, tex.height);
                let x = uv.x * w as f32 - 0.5;
                let y = uv.y * h as f32 - 0.5;
                let (x0, y0) = (x.floor(), y.floor());
                let (s, t) = (x - x0, y - y0);
                let (i0, i1) = (addressed(x0, w, address), addressed(x0 + 1.0, w, address));
                let (j0, j1) = (
                    h - 1 - addressed(y0, h, address),
                    h - 1 - addressed(y0 + 1.0, h, address),
                );
                let left = tex.texel(i0, j0) * (1.0 - t) + tex.texel(i0, j1) * t;
                let right = tex.texel(i1, j0) * (1.0 - t) + tex.texel(i1, j1) * t;
                left * (1.0 - s) + right * s
            }),
            ..NONE
        },
    ]
}

grading::corpus_tests!(lab09, lab09_checks, reference);
