//! Lab 07's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use contracts::lab07::Antialiasing;
use raylab_core::glam::{UVec2, Vec2, Vec3};
use raylab_core::sampling::Rng;
use reference::lab07::Lab07 as Reference;

use grading::corpus::Verdict;

type JittersFn = fn(u32, &mut Rng) -> Vec<Vec2>;
type PixelFn = fn(UVec2, &[Vec2], &mut dyn FnMut(Vec2) -> Vec3) -> Vec3;

/// A lab 07 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    jitters: Option<JittersFn>,
    pixel: Option<PixelFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    jitters: None,
    pixel: None,
};

impl Antialiasing for Variant {
    fn compute_jitters(&self, subdivisions: u32, rng: &mut Rng) -> Vec<Vec2> {
        match self.jitters {
            Some(f) => f(subdivisions, rng),
            None => Reference.compute_jitters(subdivisions, rng),
        }
    }
    fn compute_pixel(
        &self,
        pixel: UVec2,
        jitters: &[Vec2],
        radiance: &mut dyn FnMut(Vec2) -> Vec3,
    ) -> Vec3 {
        match self.pixel {
            Some(f) => f(pixel, jitters, radiance),
            None => Reference.compute_pixel(pixel, jitters, radiance),
        }
    }
}

/// Row-major subpixels `(i, j)` with the jitter `f(i, j, s, rng)`.
fn per_subpixel(s: u32, rng: &mut Rng, f: impl Fn(u32, u32, f32, &mut Rng) -> Vec2) -> Vec<Vec2> {
    let mut out = Vec::with_capacity((s * s) as usize);
    for j in 0..s {
        for i in 0..s {
            out.push(f(i, j, s as f32, rng));
        }
    }
    out
}

/// The sum of the radiance over `pixel + jitter`.
fn radiance_sum(pixel: UVec2, jitters: &[Vec2], radiance: &mut dyn FnMut(Vec2) -> Vec3) -> Vec3 {
    jitters.iter().map(|&j| radiance(pixel.as_vec2() + j)).sum()
}

/// Every lab 07 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // ---- Exercise 7.1 mistakes
        Variant {
            name: "jitters: one random offset shared by every subpixel",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                let u = rng.next_vec2();
                per_subpixel(s, rng, |i, j, s, _| (Vec2::new(i as f32, j as f32) + u) / s)
            }),
            ..NONE
        },
        Variant {
            name: "jitters: subpixel index off by one ((i + 1 + ξ)/s)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                per_subpixel(s, rng, |i, j, s, rng| {
                    (Vec2::new((i + 1) as f32, (j + 1) as f32) + rng.next_vec2()) / s
                })
            }),
            ..NONE
        },
        Variant {
            name: "jitters: ξ/s, not offset to the subpixel (all in the first subpixel)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| per_subpixel(s, rng, |_, _, s, rng| rng.next_vec2() / s)),
            ..NONE
        },
        Variant {
            name: "jitters: scaled by s instead of 1/s ((i + ξ)·s)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                per_subpixel(s, rng, |i, j, s, rng| {
                    (Vec2::new(i as f32, j as f32) + rng.next_vec2()) * s
                })
            }),
            ..NONE
        },
        Variant {
            name: "jitters: subpixel centres (a regular grid, no jitter)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                per_subpixel(s, rng, |i, j, s, _| {
                    (Vec2::new(i as f32, j as f32) + Vec2::splat(0.5)) / s
                })
            }),
            ..NONE
        },
        Variant {
            name: "jitters: subpixel corners (i/s, j/s)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                per_subpixel(s, rng, |i, j, s, _| Vec2::new(i as f32, j as f32) / s)
            }),
            ..NONE
        },
        Variant {
            name: "jitters: one random number for both coordinates",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                per_subpixel(s, rng, |i, j, s, rng| {
                    let u = rng.next_f32();
                    (Vec2::new(i as f32, j as f32) + Vec2::splat(u)) / s
                })
            }),
            ..NONE
        },
        Variant {
            name: "jitters: a fresh Rng::new(0, 0) instead of the one passed in",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, _| Reference.compute_jitters(s, &mut Rng::new(0, 0))),
            ..NONE
        },
        Variant {
            name: "jitters: s² uniform random points in the pixel (not stratified)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| per_subpixel(s, rng, |_, _, _, rng| rng.next_vec2())),
            ..NONE
        },
        Variant {
            name: "jitters: s points, one per row, instead of s²",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                (0..s)
                    .map(|j| (Vec2::new(0.0, j as f32) + rng.next_vec2()) / s as f32)
                    .collect()
            }),
            ..NONE
        },
        Variant {
            name: "jitters: a copy of rng per subpixel (rng.clone().next_vec2())",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                per_subpixel(s, rng, |i, j, s, rng| {
                    (Vec2::new(i as f32, j as f32) + rng.clone().next_vec2()) / s
                })
            }),
            ..NONE
        },
        Variant {
            // Every jitter is right, but the renderer goes on drawing from `rng` (area-light
            // samples, lab 3) and gets the jitters' numbers again.
            name: "jitters: drawn from a copy of rng (the caller's generator is not advanced)",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| Reference.compute_jitters(s, &mut rng.clone())),
            ..NONE
        },
        Variant {
            // The caller's generator moves, but only by one number: what it gives next is the
            // second number of the jitters again.
            name: "jitters: drawn from a copy of rng, then rng moved on by one number",
            verdict: Verdict::Reject("7.1"),
            jitters: Some(|s, rng| {
                let jitters = Reference.compute_jitters(s, &mut rng.clone());
                rng.next_u32();
                jitters
            }),
            ..NONE
        },
        // ---- Exercise 7.2 mistakes
        Variant {
            name: "pixel: the sum, not the average",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(radiance_sum),
            ..NONE
        },
        Variant {
            name: "pixel: divides by s = √n instead of s²",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|pixel, jitters, radiance| {
                radiance_sum(pixel, jitters, radiance) / (jitters.len() as f32).sqrt()
            }),
            ..NONE
        },
        Variant {
            name: "pixel: the pixel's corner for every ray (jitter forgotten)",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|pixel, jitters, radiance| {
                let sum: Vec3 = jitters.iter().map(|_| radiance(pixel.as_vec2())).sum();
                sum / jitters.len() as f32
            }),
            ..NONE
        },
        Variant {
            name: "pixel: the jitter alone as the raster position",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|_, jitters, radiance| {
                let sum: Vec3 = jitters.iter().map(|&j| radiance(j)).sum();
                sum / jitters.len() as f32
            }),
            ..NONE
        },
        Variant {
            // Within the bounds, independent of the order, right for a constant radiance: only
            // the value itself (golden cases, the key) tells it from the mean.
            name: "pixel: the midrange (min + max)/2 instead of the mean",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|pixel, jitters, radiance| {
                let values: Vec<Vec3> = jitters
                    .iter()
                    .map(|&j| radiance(pixel.as_vec2() + j))
                    .collect();
                let lo = values.iter().fold(Vec3::INFINITY, |a, v| a.min(*v));
                let hi = values.iter().fold(Vec3::NEG_INFINITY, |a, v| a.max(*v));
                0.5 * (lo + hi)
            }),
            ..NONE
        },
        Variant {
            name: "pixel: the first subpixel ray only",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|pixel, jitters, radiance| radiance(pixel.as_vec2() + jitters[0])),
            ..NONE
        },
        Variant {
            name: "pixel: the pixel centre for every ray",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|pixel, jitters, radiance| {
                let sum: Vec3 = jitters
                    .iter()
                    .map(|_| radiance(pixel.as_vec2() + 0.5))
                    .sum();
                sum / jitters.len() as f32
            }),
            ..NONE
        },
        Variant {
            name: "pixel: the last jitter skipped (0..n − 1)",
            verdict: Verdict::Reject("7.2"),
            pixel: Some(|pixel, jitters, radiance| {
                let n = jitters.len();
                let sum: Vec3 = jitters[..n - 1]
                    .iter()
                    .map(|&j| radiance(pixel.as_vec2() + j))
                    .sum();
                sum / n as f32
            }),
            ..NONE
        },
        // ---- Correct alternatives
        Variant {
            name: "column-major subpixels",
            verdict: Verdict::Accept,
            jitters: Some(|s, rng| {
                let mut out = Vec::new();
                for i in 0..s {
                    for j in 0..s {
                        out.push((Vec2::new(i as f32, j as f32) + rng.next_vec2()) / s as f32);
                    }
                }
                out
            }),
            ..NONE
        },
        Variant {
            name: "two next_f32() per subpixel, i·(1/s) + ξ·(1/s), in f64; incremental average",
            verdict: Verdict::Accept,
            jitters: Some(|s, rng| {
                let step = 1.0 / s as f64;
                (0..s * s)
                    .map(|k| {
                        let (i, j) = ((k % s) as f64, (k / s) as f64);
                        let x = rng.next_f32() as f64;
                        let y = rng.next_f32() as f64;
                        Vec2::new((i * step + x * step) as f32, (j * step + y * step) as f32)
                    })
                    .collect()
            }),
            pixel: Some(|pixel, jitters, radiance| {
                let mut mean = Vec3::ZERO;
                for (k, &j) in jitters.iter().enumerate() {
                    let l = radiance(Vec2::new(pixel.x as f32 + j.x, pixel.y as f32 + j.y));
                    mean += (l - mean) / (k + 1) as f32;
                }
                mean
            }),
        },
        Variant {
            name: "subpixels from the last to the first; average in reverse order",
            verdict: Verdict::Accept,
            jitters: Some(|s, rng| {
                let mut out = Vec::new();
                for j in (0..s).rev() {
                    for i in (0..s).rev() {
                        let u = rng.next_vec2();
                        out.push(Vec2::new(
                            (i as f32 + u.x) / s as f32,
                            (j as f32 + u.y) / s as f32,
                        ));
                    }
                }
                out
            }),
            pixel: Some(|pixel, jitters, radiance| {
                let w = 1.0 / jitters.len() as f32;
                jitters.iter().rev().fold(Vec3::ZERO, |acc, &j| {
                    acc + w * radiance(pixel.as_vec2() + j)
                })
            }),
        },
    ]
}

grading::corpus_tests!(lab07, lab07_checks, reference);
