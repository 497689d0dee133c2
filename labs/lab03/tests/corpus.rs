//! Lab 03's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use contracts::lab02::LightSample;
use contracts::lab03::Shadows;
use raylab_core::glam::{DVec3, Vec2, Vec3};
use raylab_core::math::{RAY_EPSILON, Ray};
use raylab_core::sampling::Rng;
use reference::lab03::Lab03 as Reference;

use grading::corpus::Verdict;

type ShadowRayFn = fn(Vec3, &LightSample) -> Ray;
type StratifiedFn = fn(u32, &mut Rng) -> Vec<Vec2>;
type TriangleFn = fn([Vec3; 3], Vec2) -> Vec3;
type AreaSampleFn = fn(Vec3, Vec3, Vec3, Vec3, f32) -> LightSample;

/// A lab 03 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    shadow_ray: Option<ShadowRayFn>,
    stratified: Option<StratifiedFn>,
    triangle: Option<TriangleFn>,
    area: Option<AreaSampleFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    shadow_ray: None,
    stratified: None,
    triangle: None,
    area: None,
};

impl Shadows for Variant {
    fn shadow_ray(&self, position: Vec3, light: &LightSample) -> Ray {
        self.shadow_ray.map_or_else(
            || Reference.shadow_ray(position, light),
            |f| f(position, light),
        )
    }
    fn stratified_samples(&self, n: u32, rng: &mut Rng) -> Vec<Vec2> {
        match self.stratified {
            Some(f) => f(n, rng),
            None => Reference.stratified_samples(n, rng),
        }
    }
    fn sample_triangle(&self, triangle: [Vec3; 3], u: Vec2) -> Vec3 {
        self.triangle.map_or_else(
            || Reference.sample_triangle(triangle, u),
            |f| f(triangle, u),
        )
    }
    fn area_light_sample(
        &self,
        position: Vec3,
        light_point: Vec3,
        light_normal: Vec3,
        emission: Vec3,
        pdf_area: f32,
    ) -> LightSample {
        self.area.map_or_else(
            || Reference.area_light_sample(position, light_point, light_normal, emission, pdf_area),
            |f| f(position, light_point, light_normal, emission, pdf_area),
        )
    }
}

/// `n × n` samples at `(i + u.x, j + u.y)/n`, with `u` drawn by `jitter` for each cell.
fn grid(n: u32, mut jitter: impl FnMut(u32, u32) -> Vec2) -> Vec<Vec2> {
    let mut out = Vec::new();
    for j in 0..n {
        for i in 0..n {
            out.push((Vec2::new(i as f32, j as f32) + jitter(i, j)) / n as f32);
        }
    }
    out
}

/// The area sample with a custom radiance factor `f(cos θ', r, pdf)`.
fn area_with(
    p: Vec3,
    q: Vec3,
    n: Vec3,
    le: Vec3,
    pdf: f32,
    f: fn(f32, f32, f32) -> f32,
) -> LightSample {
    let v = q - p;
    let r = v.length();
    let w = v / r;
    LightSample {
        direction: w,
        distance: r,
        radiance: le * f(-n.dot(w), r, pdf),
    }
}

/// Every lab 03 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // Exercise 3.1.
        Variant {
            name: "shadow ray: tmin = 0 (shadow acne)",
            verdict: Verdict::Reject("3.1"),
            shadow_ray: Some(|p, l| Ray::new(p, l.direction, 0.0, l.distance - RAY_EPSILON)),
            ..NONE
        },
        Variant {
            name: "shadow ray: tmax = ∞ for a point light (occluders behind the light)",
            verdict: Verdict::Reject("3.1"),
            shadow_ray: Some(|p, l| Ray::unbounded(p, l.direction, RAY_EPSILON)),
            ..NONE
        },
        Variant {
            name: "shadow ray: tmax = light.distance (the area light shadows itself)",
            verdict: Verdict::Reject("3.1"),
            shadow_ray: Some(|p, l| Ray::new(p, l.direction, RAY_EPSILON, l.distance)),
            ..NONE
        },
        Variant {
            name: "shadow ray: from the light towards the point",
            verdict: Verdict::Reject("3.1"),
            shadow_ray: Some(|p, l| {
                Ray::new(p, -l.direction, RAY_EPSILON, l.distance - RAY_EPSILON)
            }),
            ..NONE
        },
        Variant {
            name: "shadow ray: offset of 0.01 (light leaks where objects touch)",
            verdict: Verdict::Reject("3.1"),
            shadow_ray: Some(|p, l| Ray::new(p, l.direction, 0.01, l.distance - 0.01)),
            ..NONE
        },
        // Exercise 3.2.
        Variant {
            name: "stratified: cell centres, no jitter (banded penumbrae)",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, _| grid(n, |_, _| Vec2::splat(0.5))),
            ..NONE
        },
        Variant {
            name: "stratified: row index ignored (every sample in the first row)",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, rng| {
                let mut out = Vec::new();
                for _j in 0..n {
                    for i in 0..n {
                        out.push((Vec2::new(i as f32, 0.0) + rng.next_vec2()) / n as f32);
                    }
                }
                out
            }),
            ..NONE
        },
        Variant {
            name: "stratified: one jitter shared by all cells",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, rng| {
                let u = rng.next_vec2();
                grid(n, |_, _| u)
            }),
            ..NONE
        },
        Variant {
            name: "stratified: the same random number for x and y",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, rng| {
                grid(n, |_, _| {
                    let u = rng.next_f32();
                    Vec2::splat(u)
                })
            }),
            ..NONE
        },
        Variant {
            name: "stratified: n² independent uniform samples (no strata)",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, rng| (0..n * n).map(|_| rng.next_vec2()).collect()),
            ..NONE
        },
        Variant {
            name: "stratified: a generator of its own, ignoring rng",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, _| {
                let mut own = Rng::new(0, 0);
                grid(n, |_, _| own.next_vec2())
            }),
            ..NONE
        },
        Variant {
            name: "stratified: draws from a copy of rng (the caller's generator never advances)",
            verdict: Verdict::Reject("3.2"),
            stratified: Some(|n, rng| {
                let mut copy = rng.clone();
                grid(n, |_, _| copy.next_vec2())
            }),
            ..NONE
        },
        // Exercise 3.3.
        Variant {
            name: "triangle: u₁ without the square root (crowds towards v1, v2)",
            verdict: Verdict::Reject("3.3"),
            triangle: Some(|[a, b, c], u| (1.0 - u.x) * a + u.x * (1.0 - u.y) * b + u.x * u.y * c),
            ..NONE
        },
        Variant {
            name: "triangle: (1 − u₁ − u₂, u₁, u₂) unfolded (a parallelogram)",
            verdict: Verdict::Reject("3.3"),
            triangle: Some(|[a, b, c], u| (1.0 - u.x - u.y) * a + u.x * b + u.y * c),
            ..NONE
        },
        Variant {
            name: "triangle: (1 − u₁ − u₂, u₁, u₂) pushed back onto the edge when u₁ + u₂ > 1",
            verdict: Verdict::Reject("3.3"),
            triangle: Some(|[a, b, c], u| {
                let s = u.x + u.y;
                let (b1, b2) = if s > 1.0 {
                    (u.x / s, u.y / s)
                } else {
                    (u.x, u.y)
                };
                (1.0 - b1 - b2) * a + b1 * b + b2 * c
            }),
            ..NONE
        },
        Variant {
            name: "triangle: square root on both numbers",
            verdict: Verdict::Reject("3.3"),
            triangle: Some(|[a, b, c], u| {
                let (s, t) = (u.x.sqrt(), u.y.sqrt());
                (1.0 - s) * a + s * (1.0 - t) * b + s * t * c
            }),
            ..NONE
        },
        // Exercise 3.4.
        Variant {
            name: "area sample: missing cos θ' at the light",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, pdf| {
                    if c > 0.0 { 1.0 / (r * r * pdf) } else { 0.0 }
                })
            }),
            ..NONE
        },
        Variant {
            name: "area sample: missing 1/r²",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, _, pdf| c.max(0.0) / pdf)
            }),
            ..NONE
        },
        Variant {
            name: "area sample: not divided by the pdf",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, _| c.max(0.0) / (r * r))
            }),
            ..NONE
        },
        Variant {
            name: "area sample: multiplied by the pdf",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, pdf| c.max(0.0) * pdf / (r * r))
            }),
            ..NONE
        },
        Variant {
            name: "area sample: two-sided light (|cos θ'|)",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, pdf| c.abs() / (r * r * pdf))
            }),
            ..NONE
        },
        Variant {
            name: "area sample: cos θ' = n'·ω (sign of the light normal)",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, pdf| (-c).max(0.0) / (r * r * pdf))
            }),
            ..NONE
        },
        // Guards with absolute constants that hold in metre-sized scenes and bias a small
        // light (a lamp of 1 cm or less) seen from close by.
        Variant {
            name: "area sample: r² clamped to at least 1e-4 against fireflies",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, pdf| {
                    c.max(0.0) / ((r * r).max(1e-4) * pdf)
                })
            }),
            ..NONE
        },
        Variant {
            name: "area sample: no light from a sample closer than 1e-3 (a guard against dividing by zero)",
            verdict: Verdict::Reject("3.4"),
            area: Some(|p, q, n, le, pdf| {
                area_with(p, q, n, le, pdf, |c, r, pdf| {
                    if r < 1e-3 {
                        0.0
                    } else {
                        c.max(0.0) / (r * r * pdf)
                    }
                })
            }),
            ..NONE
        },
        // Correct alternatives.
        Variant {
            name: "offsets of 1e-3 and a relative tmax, columns first, Heitz's triangle mapping",
            verdict: Verdict::Accept,
            shadow_ray: Some(|p, l| Ray::new(p, l.direction, 1e-3, l.distance * (1.0 - 1e-4))),
            stratified: Some(|n, rng| {
                let mut out = Vec::new();
                for i in 0..n {
                    for j in 0..n {
                        let x = rng.next_f32();
                        let y = rng.next_f32();
                        out.push(Vec2::new(i as f32 + x, j as f32 + y) / n as f32);
                    }
                }
                out
            }),
            // Heitz 2019, "A low-distortion map between triangle and square".
            triangle: Some(|[a, b, c], u| {
                let (b0, b1) = if u.y > u.x {
                    let b0 = u.x / 2.0;
                    (b0, u.y - b0)
                } else {
                    let b1 = u.y / 2.0;
                    (u.x - b1, b1)
                };
                b0 * a + b1 * b + (1.0 - b0 - b1) * c
            }),
            ..NONE
        },
        Variant {
            name: "fold the square (u₁ + u₂ > 1 → 1 − u), cells in reverse order, solid-angle pdf in f64",
            verdict: Verdict::Accept,
            stratified: Some(|n, rng| {
                let mut out = grid(n, |_, _| rng.next_vec2());
                out.reverse();
                out
            }),
            triangle: Some(|[a, b, c], u| {
                let u = if u.x + u.y > 1.0 { Vec2::ONE - u } else { u };
                a + u.x * (b - a) + u.y * (c - a)
            }),
            area: Some(|p, q, n, le, pdf| {
                let v: DVec3 = (q - p).as_dvec3();
                let r2 = v.length_squared();
                let w = v / r2.sqrt();
                let cos_light = -n.as_dvec3().dot(w);
                // p_ω = p_A·r²/cos θ', and L_i/p_ω is the estimate.
                let radiance = if cos_light > 0.0 {
                    le.as_dvec3() / (pdf as f64 * r2 / cos_light)
                } else {
                    DVec3::ZERO
                };
                LightSample {
                    direction: w.as_vec3(),
                    distance: r2.sqrt() as f32,
                    radiance: radiance.as_vec3(),
                }
            }),
            ..NONE
        },
    ]
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use grading::stats::compare_noisy;
    use lab03_checks::checks::{self, Part};

    use super::*;

    /// The soft-shadow Z-test on its own (without the property checks that reject these
    /// mistakes first): it fails the mistakes that change the image's mean — a missing cosine,
    /// 1/r² or pdf, a shadow ray reaching beyond the light — and passes the alternatives, whose
    /// random numbers map to the light differently.
    #[test]
    fn the_soft_shadow_z_test_alone_discriminates() {
        let ctx = corpus_context(reference::KEYS);
        let renders = (checks::REFERENCE_SEEDS.end - checks::REFERENCE_SEEDS.start) as u32;
        let reference = ctx
            .noisy_reference(checks::SNAPSHOT_AREA, renders)
            .expect("the snapshot exists");
        let tol = checks::AREA_TOLERANCE;
        let part_of = |id: &str| match id {
            "3.1" => Part::ShadowRay,
            "3.2" => Part::Stratified,
            "3.3" => Part::Triangle,
            _ => Part::AreaSample,
        };
        for v in variants() {
            let parts = match v.verdict {
                Verdict::Accept => vec![Part::Stratified, Part::Triangle, Part::AreaSample],
                Verdict::Reject(id) => vec![part_of(id)],
            };
            let must_fail = [
                "missing cos",
                "missing 1/r²",
                "pdf",
                "tmax = ∞",
                "shadows itself",
                "tmin = 0",
                "first row",
                "without the square root",
            ]
            .iter()
            .any(|m| v.name.contains(m));
            let s: Arc<dyn Shadows> = Arc::new(v);
            for part in parts {
                let pipeline =
                    checks::part_pipeline(part, &s, &ctx.base, checks::SNAPSHOT_LIGHT_SAMPLES);
                let student = checks::area_statistics(&pipeline, checks::STUDENT_SEEDS).unwrap();
                let report = compare_noisy(&student, &reference, &tol);
                match v.verdict {
                    Verdict::Accept => assert!(
                        report.passes(&tol),
                        "'{}' ({part:?}) fails the Z-test: {report:?}",
                        v.name
                    ),
                    Verdict::Reject(_) if must_fail => assert!(
                        !report.passes(&tol),
                        "'{}' passes the Z-test: {report:?}",
                        v.name
                    ),
                    Verdict::Reject(_) => {}
                }
            }
        }
    }
}

grading::corpus_tests!(lab03, lab03_checks, reference);
