//! Lab 04's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use std::f32::consts::PI;

use contracts::lab02::LightSample;
use contracts::lab04::{Interface, Reflection};
use raylab_core::glam::{DVec3, Vec3};
use raylab_core::math::{RAY_EPSILON, Ray};
use raylab_core::scene::Hit;
use reference::lab04::Lab04 as Reference;

use grading::corpus::Verdict;

type ReflectFn = fn(Vec3, Vec3) -> Vec3;
type ReflectedRayFn = fn(&Ray, &Hit) -> Ray;
type InterfaceFn = fn(Vec3, &Hit, f32) -> Interface;
type RefractFn = fn(Vec3, Vec3, f32, f32) -> Option<Vec3>;
type RefractedRayFn = fn(&Ray, &Hit, f32) -> Option<(Ray, f32)>;
type PhongFn = fn(Vec3, Vec3, f32, Vec3, Vec3, &[LightSample]) -> Vec3;

/// A lab 04 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    reflect: Option<ReflectFn>,
    reflected_ray: Option<ReflectedRayFn>,
    interface: Option<InterfaceFn>,
    refract: Option<RefractFn>,
    refracted_ray: Option<RefractedRayFn>,
    phong: Option<PhongFn>,
    lobe: Option<Lobe>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    reflect: None,
    reflected_ray: None,
    interface: None,
    refract: None,
    refracted_ray: None,
    phong: None,
    lobe: None,
};

impl Reflection for Variant {
    fn reflect(&self, direction: Vec3, normal: Vec3) -> Vec3 {
        self.reflect.map_or_else(
            || Reference.reflect(direction, normal),
            |f| f(direction, normal),
        )
    }
    fn reflected_ray(&self, ray: &Ray, hit: &Hit) -> Ray {
        self.reflected_ray
            .map_or_else(|| Reference.reflected_ray(ray, hit), |f| f(ray, hit))
    }
    fn interface(&self, direction: Vec3, hit: &Hit, material_ior: f32) -> Interface {
        self.interface.map_or_else(
            || Reference.interface(direction, hit, material_ior),
            |f| f(direction, hit, material_ior),
        )
    }
    fn refract(&self, direction: Vec3, normal: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
        self.refract.map_or_else(
            || Reference.refract(direction, normal, eta_i, eta_t),
            |f| f(direction, normal, eta_i, eta_t),
        )
    }
    fn refracted_ray(&self, ray: &Ray, hit: &Hit, material_ior: f32) -> Option<(Ray, f32)> {
        self.refracted_ray.map_or_else(
            || Reference.refracted_ray(ray, hit, material_ior),
            |f| f(ray, hit, material_ior),
        )
    }
    fn shade_phong(
        &self,
        rho_d: Vec3,
        rho_s: Vec3,
        shininess: f32,
        normal: Vec3,
        view: Vec3,
        lights: &[LightSample],
    ) -> Vec3 {
        if let Some(lobe) = self.lobe {
            return phong_with(lobe, rho_d, rho_s, shininess, normal, view, lights);
        }
        self.phong.map_or_else(
            || Reference.shade_phong(rho_d, rho_s, shininess, normal, view, lights),
            |f| f(rho_d, rho_s, shininess, normal, view, lights),
        )
    }
}

/// `(η, cos θ₁, sin²θ₂)` of a refraction (the normal facing the incident side).
fn snell(w: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> (f32, f32, f32) {
    let eta = eta_i / eta_t;
    let cos_i = -w.dot(n);
    (eta, cos_i, eta * eta * (1.0 - cos_i * cos_i))
}

/// The parts of a (possibly wrong) Phong model.
#[derive(Clone, Copy)]
struct Lobe {
    /// Factor of `ρ_d` (`1/π`).
    diffuse_norm: f32,
    /// Factor of `ρ_s` given the shininess (`(s+2)/(2π)`).
    norm: fn(f32) -> f32,
    /// The highlight given `n`, `ω_i`, `v`, `s` (`max(0, r·v)^s`).
    highlight: fn(Vec3, Vec3, Vec3, f32) -> f32,
}

/// Phong with the given lobe, the rest as in the reference.
fn phong_with(
    lobe: Lobe,
    rho_d: Vec3,
    rho_s: Vec3,
    s: f32,
    n: Vec3,
    v: Vec3,
    lights: &[LightSample],
) -> Vec3 {
    let Lobe {
        diffuse_norm,
        norm,
        highlight,
    } = lobe;
    lights
        .iter()
        .map(|l| {
            let cos = n.dot(l.direction);
            if cos <= 0.0 {
                return Vec3::ZERO;
            }
            (rho_d * diffuse_norm + rho_s * norm(s) * highlight(n, l.direction, v, s))
                * l.radiance
                * cos
        })
        .sum()
}

/// The normalized Phong model, as [`Lobe`] parts.
const PHONG: Lobe = Lobe {
    diffuse_norm: 1.0 / PI,
    norm: |s| (s + 2.0) / (2.0 * PI),
    highlight: |n, w, v, s| (2.0 * n.dot(w) * n - w).dot(v).max(0.0).powf(s),
};

/// Every lab 04 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // 4.1
        Variant {
            name: "reflect: wrong sign, r = ω + 2(ω·n)n",
            verdict: Verdict::Reject("4.1"),
            reflect: Some(|w, n| w + 2.0 * w.dot(n) * n),
            ..NONE
        },
        Variant {
            name: "reflect: the formula for a vector pointing away, r = 2(ω·n)n − ω, applied to ω",
            verdict: Verdict::Reject("4.1"),
            reflect: Some(|w, n| 2.0 * w.dot(n) * n - w),
            ..NONE
        },
        // 4.2
        Variant {
            name: "reflected ray: tmin = 0 (the ray hits its own surface)",
            verdict: Verdict::Reject("4.2"),
            reflected_ray: Some(|ray, hit| {
                Ray::unbounded(
                    hit.position,
                    Reference.reflect(ray.direction, hit.shading_normal),
                    0.0,
                )
            }),
            ..NONE
        },
        Variant {
            name: "reflected ray: copies the incoming ray's tmax (the distance to this hit)",
            verdict: Verdict::Reject("4.2"),
            reflected_ray: Some(|ray, hit| {
                Ray::new(
                    hit.position,
                    Reference.reflect(ray.direction, hit.shading_normal),
                    RAY_EPSILON,
                    ray.tmax,
                )
            }),
            ..NONE
        },
        Variant {
            name: "reflected ray: about the geometric normal (faceted reflections on smooth meshes)",
            verdict: Verdict::Reject("4.2"),
            reflected_ray: Some(|ray, hit| {
                Ray::unbounded(
                    hit.position,
                    Reference.reflect(ray.direction, hit.geometric_normal),
                    RAY_EPSILON,
                )
            }),
            ..NONE
        },
        // 4.3
        Variant {
            name: "interface: normal not flipped when leaving",
            verdict: Verdict::Reject("4.3"),
            interface: Some(|w, hit, ior| Interface {
                normal: hit.shading_normal,
                ..Reference.interface(w, hit, ior)
            }),
            ..NONE
        },
        Variant {
            name: "interface: η₁ and η₂ swapped",
            verdict: Verdict::Reject("4.3"),
            interface: Some(|w, hit, ior| {
                let side = Reference.interface(w, hit, ior);
                Interface {
                    eta_incident: side.eta_transmitted,
                    eta_transmitted: side.eta_incident,
                    ..side
                }
            }),
            ..NONE
        },
        Variant {
            name: "interface: entering when ω·n > 0 (sign of the test inverted)",
            verdict: Verdict::Reject("4.3"),
            interface: Some(|w, hit, ior| Reference.interface(-w, hit, ior)),
            ..NONE
        },
        Variant {
            name: "interface: always enters from air (η₁ = 1 instead of hit.ior)",
            verdict: Verdict::Reject("4.3"),
            interface: Some(|w, hit, ior| {
                let side = Reference.interface(w, hit, ior);
                if w.dot(hit.shading_normal) < 0.0 {
                    Interface {
                        eta_incident: 1.0,
                        ..side
                    }
                } else {
                    side
                }
            }),
            ..NONE
        },
        Variant {
            name: "interface: the geometric normal instead of the shading normal (faceted glass on smooth meshes)",
            verdict: Verdict::Reject("4.3"),
            interface: Some(|w, hit, ior| {
                let faceted = Hit {
                    shading_normal: hit.geometric_normal,
                    ..*hit
                };
                Reference.interface(w, &faceted, ior)
            }),
            ..NONE
        },
        Variant {
            name: "interface: decides entering or leaving by the geometric normal, returns ± the shading normal (wrong rays at the rims of smooth glass)",
            verdict: Verdict::Reject("4.3"),
            interface: Some(|w, hit, ior| {
                let n = hit.shading_normal;
                if w.dot(hit.geometric_normal) < 0.0 {
                    Interface {
                        normal: n,
                        eta_incident: hit.ior,
                        eta_transmitted: ior,
                    }
                } else {
                    Interface {
                        normal: -n,
                        eta_incident: ior,
                        eta_transmitted: 1.0,
                    }
                }
            }),
            ..NONE
        },
        // 4.4
        Variant {
            name: "refract: η inverted (η₂/η₁)",
            verdict: Verdict::Reject("4.4"),
            refract: Some(|w, n, ei, et| Reference.refract(w, n, et, ei)),
            ..NONE
        },
        Variant {
            name: "refract: total internal reflection never reported (NaN direction)",
            verdict: Verdict::Reject("4.4"),
            refract: Some(|w, n, ei, et| {
                let (eta, cos_i, sin2_t) = snell(w, n, ei, et);
                let cos_t = (1.0 - sin2_t).sqrt();
                Some(eta * w + (eta * cos_i - cos_t) * n)
            }),
            ..NONE
        },
        Variant {
            name: "refract: TIR threshold off (tests η·sin²θ₁ > 1 instead of η·sin θ₁ > 1)",
            verdict: Verdict::Reject("4.4"),
            refract: Some(|w, n, ei, et| {
                let (eta, cos_i, sin2_t) = snell(w, n, ei, et);
                if eta * (1.0 - cos_i * cos_i) > 1.0 {
                    return None;
                }
                let cos_t = (1.0 - sin2_t).max(0.0).sqrt();
                Some(eta * w + (eta * cos_i - cos_t) * n)
            }),
            ..NONE
        },
        Variant {
            name: "refract: + cos θ₂ instead of − (the refracted ray stays on the incident side)",
            verdict: Verdict::Reject("4.4"),
            refract: Some(|w, n, ei, et| {
                let (eta, cos_i, sin2_t) = snell(w, n, ei, et);
                (sin2_t <= 1.0).then(|| eta * w + (eta * cos_i + (1.0 - sin2_t).sqrt()) * n)
            }),
            ..NONE
        },
        Variant {
            name: "refract: drops the η cos θ₁ n term (not a unit vector, Snell fails)",
            verdict: Verdict::Reject("4.4"),
            refract: Some(|w, n, ei, et| {
                let (eta, _, sin2_t) = snell(w, n, ei, et);
                (sin2_t <= 1.0).then(|| eta * w - (1.0 - sin2_t).sqrt() * n)
            }),
            ..NONE
        },
        // 4.5
        Variant {
            name: "refracted ray: keeps the old medium's index (hit.ior)",
            verdict: Verdict::Reject("4.5"),
            refracted_ray: Some(|ray, hit, ior| {
                Reference
                    .refracted_ray(ray, hit, ior)
                    .map(|(r, _)| (r, hit.ior))
            }),
            ..NONE
        },
        Variant {
            name: "refracted ray: tmin = 0",
            verdict: Verdict::Reject("4.5"),
            refracted_ray: Some(|ray, hit, ior| {
                Reference
                    .refracted_ray(ray, hit, ior)
                    .map(|(r, eta)| (Ray { tmin: 0.0, ..r }, eta))
            }),
            ..NONE
        },
        Variant {
            name: "refracted ray: no bookkeeping (shading normal as is, from air into the material)",
            verdict: Verdict::Reject("4.5"),
            refracted_ray: Some(|ray, hit, ior| {
                Reference
                    .refract(ray.direction, hit.shading_normal, 1.0, ior)
                    .map(|d| (Ray::unbounded(hit.position, d, RAY_EPSILON), ior))
            }),
            ..NONE
        },
        Variant {
            name: "refracted ray: refracts about the geometric normal (faceted glass on smooth meshes)",
            verdict: Verdict::Reject("4.5"),
            refracted_ray: Some(|ray, hit, ior| {
                let faceted = Hit {
                    shading_normal: hit.geometric_normal,
                    ..*hit
                };
                Reference.refracted_ray(ray, &faceted, ior)
            }),
            ..NONE
        },
        Variant {
            name: "refracted ray: decides entering or leaving by the geometric normal, refracts about the shading normal",
            verdict: Verdict::Reject("4.5"),
            refracted_ray: Some(|ray, hit, ior| {
                let n = hit.shading_normal;
                let (normal, eta_i, eta_t) = if ray.direction.dot(hit.geometric_normal) < 0.0 {
                    (n, hit.ior, ior)
                } else {
                    (-n, ior, 1.0)
                };
                Reference
                    .refract(ray.direction, normal, eta_i, eta_t)
                    .map(|d| (Ray::unbounded(hit.position, d, RAY_EPSILON), eta_t))
            }),
            ..NONE
        },
        // 4.6
        Variant {
            name: "Phong: without the normalization (s+2)/(2π)",
            verdict: Verdict::Reject("4.6"),
            lobe: Some(Lobe {
                norm: |_| 1.0,
                ..PHONG
            }),
            ..NONE
        },
        Variant {
            name: "Phong: half vector (n·h)^s instead of (r·v)^s",
            verdict: Verdict::Reject("4.6"),
            lobe: Some(Lobe {
                highlight: |n, w, v, s| n.dot((w + v).normalize()).max(0.0).powf(s),
                ..PHONG
            }),
            ..NONE
        },
        Variant {
            name: "Phong: highlight without max(0, ·)",
            verdict: Verdict::Reject("4.6"),
            lobe: Some(Lobe {
                highlight: |n, w, v, s| (2.0 * n.dot(w) * n - w).dot(v).powf(s),
                ..PHONG
            }),
            ..NONE
        },
        Variant {
            name: "Phong: the worksheet's unnormalized form (no 1/π, no (s+2)/(2π))",
            verdict: Verdict::Reject("4.6"),
            lobe: Some(Lobe {
                diffuse_norm: 1.0,
                norm: |_| 1.0,
                ..PHONG
            }),
            ..NONE
        },
        Variant {
            name: "Phong: reflects ω_i instead of −ω_i (the highlight points into the surface)",
            verdict: Verdict::Reject("4.6"),
            lobe: Some(Lobe {
                highlight: |n, w, v, s| (w - 2.0 * n.dot(w) * n).dot(v).max(0.0).powf(s),
                ..PHONG
            }),
            ..NONE
        },
        // Correct alternatives.
        Variant {
            name: "Heckbert's forms in f64 (eq. 4.8/4.9 with the normal facing the ray), DTU-style tmin 1e-3 and tmax f32::MAX",
            verdict: Verdict::Accept,
            reflect: Some(|w, n| {
                let (w, n) = (w.as_dvec3(), n.as_dvec3());
                let c1 = -n.dot(w);
                (w + 2.0 * c1 * n).as_vec3()
            }),
            reflected_ray: Some(|ray, hit| {
                let (w, n) = (ray.direction.as_dvec3(), hit.shading_normal.as_dvec3());
                let r = w + 2.0 * -n.dot(w) * n;
                Ray::new(hit.position, r.as_vec3(), 1e-3, f32::MAX)
            }),
            interface: Some(|w, hit, ior| {
                let leaving = w.dot(hit.shading_normal) >= 0.0;
                let (normal, eta_incident, eta_transmitted) = match leaving {
                    false => (hit.shading_normal, hit.ior, ior),
                    true => (-hit.shading_normal, ior, 1.0),
                };
                Interface {
                    normal,
                    eta_incident,
                    eta_transmitted,
                }
            }),
            refract: Some(|w, n, ei, et| {
                let (w, n) = (w.as_dvec3(), n.as_dvec3());
                let eta = ei as f64 / et as f64;
                let c1 = -n.dot(w);
                let radicand = 1.0 - eta * eta * (1.0 - c1 * c1);
                if radicand < 0.0 {
                    return None;
                }
                let c2 = radicand.sqrt();
                Some((eta * w + (eta * c1 - c2) * n).normalize().as_vec3())
            }),
            refracted_ray: Some(|ray, hit, ior| {
                let entering = ray.direction.dot(hit.shading_normal) < 0.0;
                let (n, e1, e2) = if entering {
                    (hit.shading_normal, hit.ior, ior)
                } else {
                    (-hit.shading_normal, ior, 1.0)
                };
                let (w, n) = (ray.direction.as_dvec3(), n.as_dvec3());
                let eta = e1 as f64 / e2 as f64;
                let c1 = -n.dot(w);
                let radicand = 1.0 - eta * eta * (1.0 - c1 * c1);
                (radicand >= 0.0).then(|| {
                    let t: DVec3 = eta * w + (eta * c1 - radicand.sqrt()) * n;
                    (Ray::new(hit.position, t.as_vec3(), 1e-3, f32::MAX), e2)
                })
            }),
            ..NONE
        },
        Variant {
            name: "Snell by angles (tangent basis, sin θ₂ = η sin θ₁) and Phong through the mirrored view",
            verdict: Verdict::Accept,
            refract: Some(|w, n, ei, et| {
                let cos_i = (-w.dot(n)).clamp(0.0, 1.0);
                let tangent = w + cos_i * n;
                let sin_i = tangent.length();
                let sin_t = ei / et * sin_i;
                if sin_t > 1.0 {
                    return None;
                }
                let cos_t = (1.0 - sin_t * sin_t).sqrt();
                let along = if sin_i > 1e-7 {
                    tangent / sin_i
                } else {
                    Vec3::ZERO
                };
                Some(sin_t * along - cos_t * n)
            }),
            phong: Some(|rho_d, rho_s, s, n, v, lights| {
                // r_i·v = ω_i·r_v with r_v the mirror direction of −v: reflect the view once.
                let r_v = 2.0 * n.dot(v) * n - v;
                let mut diffuse = Vec3::ZERO;
                let mut glossy = Vec3::ZERO;
                for l in lights.iter().filter(|l| n.dot(l.direction) > 0.0) {
                    let e = l.radiance * n.dot(l.direction);
                    diffuse += e;
                    let c = l.direction.dot(r_v);
                    if c > 0.0 {
                        glossy += e * c.powf(s);
                    }
                }
                rho_d * diffuse / PI + rho_s * glossy * (s + 2.0) * 0.5 / PI
            }),
            ..NONE
        },
    ]
}

grading::corpus_tests!(lab04, lab04_checks, reference);
