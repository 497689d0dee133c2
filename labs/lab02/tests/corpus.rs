//! Lab 02's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use std::f32::consts::PI;

use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use raylab_core::glam::{DVec3, Vec3};
use raylab_core::math::Ray;
use raylab_core::scene::{DirectionalLight, Plane, PointLight, Sphere};
use reference::lab02::Lab02 as Reference;

use grading::corpus::Verdict;

type PlaneFn = fn(&Ray, &Plane) -> Option<SurfaceHit>;
type TriangleFn = fn(&Ray, Vec3, Vec3, Vec3) -> Option<TriangleHit>;
type SphereFn = fn(&Ray, &Sphere) -> Option<SurfaceHit>;
type PointFn = fn(&PointLight, Vec3) -> LightSample;
type DirectionalFn = fn(&DirectionalLight, Vec3) -> LightSample;
type LambertianFn = fn(Vec3, Vec3, &[LightSample]) -> Vec3;

/// The reference lab 02 with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    plane: Option<PlaneFn>,
    triangle: Option<TriangleFn>,
    sphere: Option<SphereFn>,
    point: Option<PointFn>,
    directional: Option<DirectionalFn>,
    lambertian: Option<LambertianFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    plane: None,
    triangle: None,
    sphere: None,
    point: None,
    directional: None,
    lambertian: None,
};

impl Intersection for Variant {
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        self.plane
            .map_or_else(|| Reference.intersect_plane(ray, plane), |f| f(ray, plane))
    }
    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        self.triangle.map_or_else(
            || Reference.intersect_triangle(ray, v0, v1, v2),
            |f| f(ray, v0, v1, v2),
        )
    }
    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        self.sphere.map_or_else(
            || Reference.intersect_sphere(ray, sphere),
            |f| f(ray, sphere),
        )
    }
}

impl Shading for Variant {
    fn sample_point_light(&self, light: &PointLight, p: Vec3) -> LightSample {
        self.point
            .map_or_else(|| Reference.sample_point_light(light, p), |f| f(light, p))
    }
    fn sample_directional_light(&self, light: &DirectionalLight, p: Vec3) -> LightSample {
        self.directional.map_or_else(
            || Reference.sample_directional_light(light, p),
            |f| f(light, p),
        )
    }
    fn shade_lambertian(&self, rho: Vec3, n: Vec3, lights: &[LightSample]) -> Vec3 {
        self.lambertian.map_or_else(
            || Reference.shade_lambertian(rho, n, lights),
            |f| f(rho, n, lights),
        )
    }
}

/// Möller–Trumbore without the range checks selected by the flags (for the mutants).
fn triangle_with(
    ray: &Ray,
    v0: Vec3,
    v1: Vec3,
    v2: Vec3,
    check_sum: bool,
    check_tmin: bool,
) -> Option<TriangleHit> {
    let (e1, e2) = (v1 - v0, v2 - v0);
    let p = ray.direction.cross(e2);
    let det = e1.dot(p);
    if det == 0.0 {
        return None;
    }
    let s = ray.origin - v0;
    let beta = s.dot(p) / det;
    let q = s.cross(e1);
    let gamma = ray.direction.dot(q) / det;
    let t = e2.dot(q) / det;
    let inside = beta >= 0.0 && gamma >= 0.0 && (!check_sum || beta + gamma <= 1.0);
    let in_range = t <= ray.tmax && (!check_tmin || t >= ray.tmin);
    (inside && in_range).then(|| TriangleHit {
        distance: t,
        beta,
        gamma,
        normal: e1.cross(e2).normalize(),
    })
}

fn sphere_roots(ray: &Ray, s: &Sphere) -> Option<(f32, f32)> {
    let oc = ray.origin - s.center;
    let b = oc.dot(ray.direction);
    let c = oc.length_squared() - s.radius * s.radius;
    let disc = b * b - c;
    (disc >= 0.0).then(|| (-b - disc.sqrt(), -b + disc.sqrt()))
}

fn sphere_hit(ray: &Ray, s: &Sphere, t: f32) -> SurfaceHit {
    SurfaceHit {
        distance: t,
        normal: (ray.at(t) - s.center) / s.radius,
    }
}

/// Every lab 02 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        Variant {
            name: "plane: ignores tmin (hits behind the eye)",
            verdict: Verdict::Reject("2.1"),
            plane: Some(|ray, plane| {
                let t = -(ray.origin.dot(plane.normal) + plane.d) / ray.direction.dot(plane.normal);
                (t.is_finite() && t <= ray.tmax).then_some(SurfaceHit {
                    distance: t,
                    normal: plane.normal,
                })
            }),
            ..NONE
        },
        Variant {
            name: "plane: wrong sign of d (t = (o·n + d)/(ω·n))",
            verdict: Verdict::Reject("2.1"),
            plane: Some(|ray, plane| {
                let t = (ray.origin.dot(plane.normal) + plane.d) / ray.direction.dot(plane.normal);
                ray.accepts(t).then_some(SurfaceHit {
                    distance: t,
                    normal: plane.normal,
                })
            }),
            ..NONE
        },
        Variant {
            name: "plane: no test of ω·n = 0 (a parallel ray's t = ±∞ passes tmax = ∞)",
            verdict: Verdict::Reject("2.1"),
            plane: Some(|ray, plane| {
                let t = -(ray.origin.dot(plane.normal) + plane.d) / ray.direction.dot(plane.normal);
                ray.accepts(t).then_some(SurfaceHit {
                    distance: t,
                    normal: plane.normal,
                })
            }),
            ..NONE
        },
        Variant {
            name: "plane: t = ±∞ refused but not NaN (a ray in the plane hits at t = NaN)",
            verdict: Verdict::Reject("2.1"),
            plane: Some(|ray, plane| {
                let t = -(ray.origin.dot(plane.normal) + plane.d) / ray.direction.dot(plane.normal);
                if t.is_infinite() || t < ray.tmin || t > ray.tmax {
                    return None;
                }
                Some(SurfaceHit {
                    distance: t,
                    normal: plane.normal,
                })
            }),
            ..NONE
        },
        Variant {
            name: "plane: |ω·n| < 1e-4 taken as parallel (grazing rays miss)",
            verdict: Verdict::Reject("2.1"),
            plane: Some(|ray, plane| {
                if ray.direction.dot(plane.normal).abs() < 1e-4 {
                    return None;
                }
                Reference.intersect_plane(ray, plane)
            }),
            ..NONE
        },
        Variant {
            name: "triangle: accepts β + γ > 1 (a parallelogram)",
            verdict: Verdict::Reject("2.2"),
            triangle: Some(|r, a, b, c| triangle_with(r, a, b, c, false, true)),
            ..NONE
        },
        Variant {
            name: "triangle: ignores tmin",
            verdict: Verdict::Reject("2.2"),
            triangle: Some(|r, a, b, c| triangle_with(r, a, b, c, true, false)),
            ..NONE
        },
        Variant {
            name: "triangle: β and γ swapped",
            verdict: Verdict::Reject("2.2"),
            triangle: Some(|r, a, b, c| {
                Reference
                    .intersect_triangle(r, a, b, c)
                    .map(|h| TriangleHit {
                        beta: h.gamma,
                        gamma: h.beta,
                        ..h
                    })
            }),
            ..NONE
        },
        Variant {
            name: "triangle: normal not normalized",
            verdict: Verdict::Reject("2.2"),
            triangle: Some(|r, a, b, c| {
                Reference
                    .intersect_triangle(r, a, b, c)
                    .map(|h| TriangleHit {
                        normal: (b - a).cross(c - a),
                        ..h
                    })
            }),
            ..NONE
        },
        // Fixed epsilons that hold at the scale of the checks' usual scenes and fail on a mesh
        // of small triangles or a far-away camera.
        Variant {
            name: "plane: an absolute epsilon t > 1e-3 besides tmin",
            verdict: Verdict::Reject("2.1"),
            plane: Some(|r, p| {
                Reference
                    .intersect_plane(r, p)
                    .filter(|h| h.distance > 1e-3)
            }),
            ..NONE
        },
        Variant {
            name: "triangle: parallel test with an absolute epsilon (|det| < 1e-6)",
            verdict: Verdict::Reject("2.2"),
            triangle: Some(|r, a, b, c| {
                let det = (b - a).dot(r.direction.cross(c - a));
                if det.abs() < 1e-6 {
                    return None;
                }
                Reference.intersect_triangle(r, a, b, c)
            }),
            ..NONE
        },
        Variant {
            name: "triangle: an absolute epsilon t > 1e-3 besides tmin",
            verdict: Verdict::Reject("2.2"),
            triangle: Some(|r, a, b, c| {
                Reference
                    .intersect_triangle(r, a, b, c)
                    .filter(|h| h.distance > 1e-3)
            }),
            ..NONE
        },
        Variant {
            name: "sphere: a miss when the discriminant is below an absolute 1e-6",
            verdict: Verdict::Reject("2.3"),
            sphere: Some(|r, s| {
                let oc = r.origin - s.center;
                let half_b = oc.dot(r.direction);
                let disc = half_b * half_b
                    - r.direction.length_squared() * (oc.length_squared() - s.radius * s.radius);
                if disc < 1e-6 {
                    return None;
                }
                Reference.intersect_sphere(r, s)
            }),
            ..NONE
        },
        Variant {
            name: "sphere: returns the far root",
            verdict: Verdict::Reject("2.3"),
            sphere: Some(|ray, s| {
                let (_, far) = sphere_roots(ray, s)?;
                ray.accepts(far).then(|| sphere_hit(ray, s, far))
            }),
            ..NONE
        },
        Variant {
            name: "sphere: only the near root (misses from inside)",
            verdict: Verdict::Reject("2.3"),
            sphere: Some(|ray, s| {
                let (near, _) = sphere_roots(ray, s)?;
                ray.accepts(near).then(|| sphere_hit(ray, s, near))
            }),
            ..NONE
        },
        Variant {
            name: "sphere: normal points inwards",
            verdict: Verdict::Reject("2.3"),
            sphere: Some(|ray, s| {
                Reference.intersect_sphere(ray, s).map(|h| SurfaceHit {
                    normal: -h.normal,
                    ..h
                })
            }),
            ..NONE
        },
        Variant {
            name: "point light: no inverse-square law",
            verdict: Verdict::Reject("2.4"),
            point: Some(|l, p| LightSample {
                radiance: l.intensity,
                ..Reference.sample_point_light(l, p)
            }),
            ..NONE
        },
        Variant {
            name: "point light: divides by r instead of r²",
            verdict: Verdict::Reject("2.4"),
            point: Some(|l, p| {
                let s = Reference.sample_point_light(l, p);
                LightSample {
                    radiance: l.intensity / s.distance,
                    ..s
                }
            }),
            ..NONE
        },
        Variant {
            name: "point light: direction from the light to the point",
            verdict: Verdict::Reject("2.4"),
            point: Some(|l, p| {
                let s = Reference.sample_point_light(l, p);
                LightSample {
                    direction: -s.direction,
                    ..s
                }
            }),
            ..NONE
        },
        Variant {
            name: "directional light: direction not reversed",
            verdict: Verdict::Reject("2.5"),
            directional: Some(|l, _p| LightSample {
                direction: l.direction,
                distance: f32::INFINITY,
                radiance: l.emission,
            }),
            ..NONE
        },
        Variant {
            // Every relation of a directional light holds; only its value (golden cases, the
            // key) is wrong.
            name: "directional light: emission divided by π",
            verdict: Verdict::Reject("2.5"),
            directional: Some(|l, _p| LightSample {
                direction: -l.direction,
                distance: f32::INFINITY,
                radiance: l.emission / std::f32::consts::PI,
            }),
            ..NONE
        },
        Variant {
            name: "Lambertian: missing 1/π",
            verdict: Verdict::Reject("2.6"),
            lambertian: Some(|rho, n, lights| {
                lights
                    .iter()
                    .map(|l| rho * l.radiance * n.dot(l.direction).max(0.0))
                    .sum()
            }),
            ..NONE
        },
        Variant {
            name: "Lambertian: cosine not clamped (light from below subtracts)",
            verdict: Verdict::Reject("2.6"),
            lambertian: Some(|rho, n, lights| {
                lights
                    .iter()
                    .map(|l| rho / PI * l.radiance * n.dot(l.direction))
                    .sum()
            }),
            ..NONE
        },
        Variant {
            name: "Lambertian: no cosine",
            verdict: Verdict::Reject("2.6"),
            lambertian: Some(|rho, n, lights| {
                lights
                    .iter()
                    .filter(|l| n.dot(l.direction) > 0.0)
                    .map(|l| rho / PI * l.radiance)
                    .sum()
            }),
            ..NONE
        },
        // Correct alternatives.
        Variant {
            name: "triangle: plane intersection, then barycentrics from sub-triangle areas (f64)",
            verdict: Verdict::Accept,
            triangle: Some(|ray, v0, v1, v2| {
                let [a, b, c] = [v0, v1, v2].map(|v| v.as_dvec3());
                let (o, d) = (ray.origin.as_dvec3(), ray.direction.as_dvec3());
                let n: DVec3 = (b - a).cross(c - a);
                let dn = d.dot(n);
                if dn == 0.0 {
                    return None;
                }
                let t = (a - o).dot(n) / dn;
                if !(t >= ray.tmin as f64 && t <= ray.tmax as f64) {
                    return None;
                }
                let p = o + t * d;
                let nn = n.dot(n);
                let beta = (c - a).cross(p - a).dot(n) / -nn;
                let gamma = (b - a).cross(p - a).dot(n) / nn;
                (beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0).then(|| TriangleHit {
                    distance: t as f32,
                    beta: beta as f32,
                    gamma: gamma as f32,
                    normal: n.normalize().as_vec3(),
                })
            }),
            ..NONE
        },
        Variant {
            name: "sphere: geometric solution (project the centre onto the ray)",
            verdict: Verdict::Accept,
            sphere: Some(|ray, s| {
                let l = s.center - ray.origin;
                let tca = l.dot(ray.direction);
                let d2 = l.length_squared() - tca * tca;
                let r2 = s.radius * s.radius;
                if d2 > r2 {
                    return None;
                }
                let thc = (r2 - d2).sqrt();
                [tca - thc, tca + thc]
                    .into_iter()
                    .find(|&t| ray.accepts(t))
                    .map(|t| sphere_hit(ray, s, t))
            }),
            plane: Some(|ray, plane| {
                // Through a point of the plane: t = (p0 − o)·n / (ω·n).
                let p0 = -plane.d * plane.normal;
                let dn = ray.direction.dot(plane.normal);
                let t = (p0 - ray.origin).dot(plane.normal) / dn;
                (dn != 0.0 && ray.accepts(t)).then_some(SurfaceHit {
                    distance: t,
                    normal: plane.normal,
                })
            }),
            ..NONE
        },
        Variant {
            name: "lights and Lambertian written another way",
            verdict: Verdict::Accept,
            point: Some(|l, p| {
                let v = l.position - p;
                let r2 = v.length_squared();
                LightSample {
                    direction: v / r2.sqrt(),
                    distance: r2.sqrt(),
                    radiance: l.intensity * r2.recip(),
                }
            }),
            lambertian: Some(|rho, n, lights| {
                let irradiance: Vec3 = lights
                    .iter()
                    .map(|l| l.radiance * n.dot(l.direction).max(0.0))
                    .sum();
                rho * irradiance * std::f32::consts::FRAC_1_PI
            }),
            ..NONE
        },
    ]
}

grading::corpus_tests!(lab02, lab02_checks, reference);
