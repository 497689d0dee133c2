//! Lab 08's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use std::f32::consts::PI;

use contracts::lab08::{EmittedPhoton, NearbyPhoton, PhotonMapping, Scatter};
use raylab_core::glam::Vec3;
use raylab_core::math::{Onb, RAY_EPSILON, Ray};
use raylab_core::sampling::Rng;
use raylab_core::scene::PointLight;
use reference::lab08::Lab08 as Reference;

use grading::corpus::Verdict;

type PointFn = fn(&PointLight, u32, &mut Rng) -> EmittedPhoton;
type AreaFn = fn(Vec3, Vec3, Vec3, f32, u32, &mut Rng) -> EmittedPhoton;
type RouletteFn = fn(f32, Vec3, &mut Rng) -> (Scatter, Vec3);
type RadianceFn = fn(Vec3, Vec3, &[NearbyPhoton], usize, f32) -> Vec3;

/// A lab 08 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    point: Option<PointFn>,
    area: Option<AreaFn>,
    roulette: Option<RouletteFn>,
    radiance: Option<RadianceFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    point: None,
    area: None,
    roulette: None,
    radiance: None,
};

impl PhotonMapping for Variant {
    fn emit_point_light(&self, light: &PointLight, emitted: u32, rng: &mut Rng) -> EmittedPhoton {
        match self.point {
            Some(f) => f(light, emitted, rng),
            None => Reference.emit_point_light(light, emitted, rng),
        }
    }
    fn emit_area_light(
        &self,
        position: Vec3,
        normal: Vec3,
        emitted_radiance: Vec3,
        light_area: f32,
        emitted: u32,
        rng: &mut Rng,
    ) -> EmittedPhoton {
        match self.area {
            Some(f) => f(position, normal, emitted_radiance, light_area, emitted, rng),
            None => Reference.emit_area_light(
                position,
                normal,
                emitted_radiance,
                light_area,
                emitted,
                rng,
            ),
        }
    }
    fn russian_roulette(&self, reflectance: f32, power: Vec3, rng: &mut Rng) -> (Scatter, Vec3) {
        match self.roulette {
            Some(f) => f(reflectance, power, rng),
            None => Reference.russian_roulette(reflectance, power, rng),
        }
    }
    fn caustic_radiance(
        &self,
        diffuse: Vec3,
        normal: Vec3,
        photons: &[NearbyPhoton],
        k: usize,
        max_radius: f32,
    ) -> Vec3 {
        match self.radiance {
            Some(f) => f(diffuse, normal, photons, k, max_radius),
            None => Reference.caustic_radiance(diffuse, normal, photons, k, max_radius),
        }
    }
}

/// A point in the cube `[−1, 1]³` from three numbers of `rng`.
fn in_cube(rng: &mut Rng) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - Vec3::ONE
}

/// A uniformly random unit direction by rejection sampling in the unit ball.
fn in_ball(rng: &mut Rng) -> Vec3 {
    loop {
        let p = in_cube(rng);
        if p.length_squared() <= 1.0 && p.length_squared() > 1e-12 {
            return p;
        }
    }
}

/// A point-light photon along `direction` with `power`.
fn point_photon(light: &PointLight, direction: Vec3, power: Vec3) -> EmittedPhoton {
    EmittedPhoton {
        ray: Ray::unbounded(light.position, direction, 0.0),
        power,
    }
}

/// An area-light photon from `position` along the local direction `local` about `normal`.
fn area_photon(position: Vec3, normal: Vec3, local: Vec3, power: Vec3) -> EmittedPhoton {
    EmittedPhoton {
        ray: Ray::unbounded(position, Onb::from_w(normal).to_world(local), RAY_EPSILON),
        power,
    }
}

/// The disc's radius² of the estimate: the farthest photon's with `k` found.
fn radius2(photons: &[NearbyPhoton], k: usize, max_radius: f32) -> f32 {
    if photons.len() >= k {
        photons.last().map_or(0.0, |p| p.distance_squared)
    } else {
        max_radius * max_radius
    }
}

/// The power of the photons arriving at the front of the surface.
fn front_flux(photons: &[NearbyPhoton], normal: Vec3) -> Vec3 {
    photons
        .iter()
        .filter(|p| p.direction.dot(normal) < 0.0)
        .map(|p| p.power)
        .sum()
}

/// Every lab 08 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // ---- Exercise 8.1 mistakes
        Variant {
            name: "point light: the photon carries the light's whole power",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, _, rng| {
                point_photon(l, in_ball(rng).normalize(), 4.0 * PI * l.intensity)
            }),
            ..NONE
        },
        Variant {
            name: "point light: power I/N (the 4π of the sphere forgotten)",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                point_photon(l, in_ball(rng).normalize(), l.intensity / n as f32)
            }),
            ..NONE
        },
        Variant {
            name: "point light: power 2πI/N (a hemisphere's solid angle)",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                point_photon(
                    l,
                    in_ball(rng).normalize(),
                    2.0 * PI * l.intensity / n as f32,
                )
            }),
            ..NONE
        },
        Variant {
            name: "point light: a point of the cube normalised without rejecting the corners",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                point_photon(
                    l,
                    in_cube(rng).normalize(),
                    4.0 * PI * l.intensity / n as f32,
                )
            }),
            ..NONE
        },
        Variant {
            name: "point light: the point in the ball is not normalised",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                point_photon(l, in_ball(rng), 4.0 * PI * l.intensity / n as f32)
            }),
            ..NONE
        },
        Variant {
            name: "point light: polar angle uniform instead of its cosine (bunched at the poles)",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                let (theta, phi) = (PI * rng.next_f32(), 2.0 * PI * rng.next_f32());
                let d = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                point_photon(l, d, 4.0 * PI * l.intensity / n as f32)
            }),
            ..NONE
        },
        Variant {
            name: "point light: only the upper hemisphere (|z|)",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                let d = in_ball(rng).normalize();
                point_photon(
                    l,
                    Vec3::new(d.x, d.y, d.z.abs()),
                    4.0 * PI * l.intensity / n as f32,
                )
            }),
            ..NONE
        },
        Variant {
            name: "point light: the generator copied, so every photon goes the same way",
            verdict: Verdict::Reject("8.1"),
            point: Some(|l, n, rng| {
                let mut copy = rng.clone();
                point_photon(
                    l,
                    in_ball(&mut copy).normalize(),
                    4.0 * PI * l.intensity / n as f32,
                )
            }),
            ..NONE
        },
        // ---- Exercise 8.2 mistakes
        Variant {
            name: "area light: uniform over the hemisphere instead of cosine-weighted",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let (z, phi) = (rng.next_f32(), 2.0 * PI * rng.next_f32());
                let r = (1.0 - z * z).max(0.0).sqrt();
                area_photon(
                    p,
                    nrm,
                    Vec3::new(r * phi.cos(), r * phi.sin(), z),
                    PI * le * a / n as f32,
                )
            }),
            ..NONE
        },
        Variant {
            name: "area light: disc radius ξ instead of √ξ",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let (r, phi) = (rng.next_f32(), 2.0 * PI * rng.next_f32());
                let z = (1.0 - r * r).max(0.0).sqrt();
                area_photon(
                    p,
                    nrm,
                    Vec3::new(r * phi.cos(), r * phi.sin(), z),
                    PI * le * a / n as f32,
                )
            }),
            ..NONE
        },
        Variant {
            name: "area light: one random number for both the disc's radius and the angle",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let u = rng.next_f32();
                let (r, phi) = (u.sqrt(), 2.0 * PI * u);
                area_photon(
                    p,
                    nrm,
                    Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - u).max(0.0).sqrt()),
                    PI * le * a / n as f32,
                )
            }),
            ..NONE
        },
        Variant {
            name: "area light: power L·A/N (the π of the cosine lobe forgotten)",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let mut e = Reference.emit_area_light(p, nrm, le, a, n, rng);
                e.power = le * a / n as f32;
                e
            }),
            ..NONE
        },
        Variant {
            name: "area light: power 2π·L·A/N",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let mut e = Reference.emit_area_light(p, nrm, le, a, n, rng);
                e.power = 2.0 * PI * le * a / n as f32;
                e
            }),
            ..NONE
        },
        Variant {
            name: "area light: emits from its back (about −n)",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| Reference.emit_area_light(p, -nrm, le, a, n, rng)),
            ..NONE
        },
        Variant {
            name: "area light: the ray starts at t = 0 on the light's surface",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let mut e = Reference.emit_area_light(p, nrm, le, a, n, rng);
                e.ray.tmin = 0.0;
                e
            }),
            ..NONE
        },
        Variant {
            name: "area light: the power is not shared among the photons",
            verdict: Verdict::Reject("8.2"),
            area: Some(|p, nrm, le, a, n, rng| {
                let mut e = Reference.emit_area_light(p, nrm, le, a, n, rng);
                e.power = PI * le * a;
                e
            }),
            ..NONE
        },
        // ---- Exercise 8.3 mistakes
        Variant {
            name: "roulette: reflects with probability 1 − R",
            verdict: Verdict::Reject("8.3"),
            roulette: Some(|r, power, rng| {
                if rng.next_f32() < r {
                    (Scatter::Refract, power)
                } else {
                    (Scatter::Reflect, power)
                }
            }),
            ..NONE
        },
        Variant {
            name: "roulette: also weights the power by R or 1 − R",
            verdict: Verdict::Reject("8.3"),
            roulette: Some(|r, power, rng| {
                if rng.next_f32() < r {
                    (Scatter::Reflect, power * r)
                } else {
                    (Scatter::Refract, power * (1.0 - r))
                }
            }),
            ..NONE
        },
        Variant {
            name: "roulette: always refracts unless R > ½ (no random number)",
            verdict: Verdict::Reject("8.3"),
            roulette: Some(|r, power, _| {
                if r > 0.5 {
                    (Scatter::Reflect, power)
                } else {
                    (Scatter::Refract, power)
                }
            }),
            ..NONE
        },
        Variant {
            name: "roulette: reflects with probability R², a second draw",
            verdict: Verdict::Reject("8.3"),
            roulette: Some(|r, power, rng| {
                if rng.next_f32() < r && rng.next_f32() < r {
                    (Scatter::Reflect, power)
                } else {
                    (Scatter::Refract, power)
                }
            }),
            ..NONE
        },
        Variant {
            name: "roulette: a fresh generator of its own every call",
            verdict: Verdict::Reject("8.3"),
            roulette: Some(|r, power, rng| {
                let _ = rng.next_u32();
                let mut own = Rng::new(1, 1);
                if own.next_f32() < r {
                    (Scatter::Reflect, power)
                } else {
                    (Scatter::Refract, power)
                }
            }),
            ..NONE
        },
        // ---- Exercise 8.4 mistakes
        Variant {
            name: "estimate: the irradiance without the diffuse BRDF ρ/π",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|_, n, ps, k, r| front_flux(ps, n) / (PI * radius2(ps, k, r))),
            ..NONE
        },
        Variant {
            name: "estimate: ρ times the irradiance (the 1/π of the BRDF forgotten)",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| d * front_flux(ps, n) / (PI * radius2(ps, k, r))),
            ..NONE
        },
        Variant {
            name: "estimate: divides by πr instead of πr²",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| {
                d / PI * front_flux(ps, n) / (PI * radius2(ps, k, r).sqrt())
            }),
            ..NONE
        },
        Variant {
            name: "estimate: always the maximum radius, even with k photons found",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, _, r| d / PI * front_flux(ps, n) / (PI * r * r)),
            ..NONE
        },
        Variant {
            name: "estimate: the nearest photon's distance as the disc's radius",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| {
                let r2 = if ps.len() >= k {
                    ps.first().map_or(0.0, |p| p.distance_squared)
                } else {
                    r * r
                };
                if r2 <= 0.0 {
                    return Vec3::ZERO;
                }
                d / PI * front_flux(ps, n) / (PI * r2)
            }),
            ..NONE
        },
        Variant {
            name: "estimate: counts the photons that arrived from behind the surface",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, _, ps, k, r| {
                let r2 = radius2(ps, k, r);
                if r2 <= 0.0 {
                    return Vec3::ZERO;
                }
                d / PI * ps.iter().map(|p| p.power).sum::<Vec3>() / (PI * r2)
            }),
            ..NONE
        },
        Variant {
            name: "estimate: the mean photon power instead of the sum",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| {
                let r2 = radius2(ps, k, r);
                if r2 <= 0.0 || ps.is_empty() {
                    return Vec3::ZERO;
                }
                d / PI * front_flux(ps, n) / ps.len() as f32 / (PI * r2)
            }),
            ..NONE
        },
        Variant {
            name: "estimate: the grey reflectance (mean of ρ's channels)",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| {
                let r2 = radius2(ps, k, r);
                if r2 <= 0.0 {
                    return Vec3::ZERO;
                }
                Vec3::splat((d.x + d.y + d.z) / 3.0) / PI * front_flux(ps, n) / (PI * r2)
            }),
            ..NONE
        },
        Variant {
            name: "estimate: photons weighted by cos θ at the surface",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| {
                let r2 = radius2(ps, k, r);
                if r2 <= 0.0 {
                    return Vec3::ZERO;
                }
                let flux: Vec3 = ps
                    .iter()
                    .map(|p| p.power * (-p.direction.dot(n)).max(0.0))
                    .sum();
                d / PI * flux / (PI * r2)
            }),
            ..NONE
        },
        Variant {
            name: "estimate: no rule for a disc of no area (divides by r² = 0)",
            verdict: Verdict::Reject("8.4"),
            radiance: Some(|d, n, ps, k, r| {
                if ps.is_empty() {
                    return Vec3::ZERO;
                }
                d / PI * front_flux(ps, n) / (PI * radius2(ps, k, r))
            }),
            ..NONE
        },
        // ---- Correct alternatives
        Variant {
            name: "directions from z = 1 − 2ξ and a uniform azimuth; cosine lobe by Malley's method in another basis; roulette on 1 − ξ",
            verdict: Verdict::Accept,
            point: Some(|l, n, rng| {
                let (z, phi) = (1.0 - 2.0 * rng.next_f32(), 2.0 * PI * rng.next_f32());
                let s = (1.0 - z * z).max(0.0).sqrt();
                point_photon(
                    l,
                    Vec3::new(s * phi.cos(), s * phi.sin(), z),
                    l.intensity * (4.0 * PI / n as f32),
                )
            }),
            area: Some(|p, nrm, le, a, n, rng| {
                let (u1, u2) = (rng.next_f32(), rng.next_f32());
                let t = if nrm.x.abs() < 0.9 { Vec3::X } else { Vec3::Y };
                let b1 = nrm.cross(t).normalize();
                let b2 = nrm.cross(b1);
                let (r, phi) = (u1.sqrt(), 2.0 * PI * u2);
                let d =
                    (r * phi.cos() * b1 + r * phi.sin() * b2 + (1.0 - u1).max(0.0).sqrt() * nrm)
                        .normalize();
                EmittedPhoton {
                    ray: Ray::unbounded(p, d, RAY_EPSILON),
                    power: le * (a * PI) / n as f32,
                }
            }),
            roulette: Some(|r, power, rng| {
                if 1.0 - rng.next_f32() <= r {
                    (Scatter::Reflect, power)
                } else {
                    (Scatter::Refract, power)
                }
            }),
            ..NONE
        },
        Variant {
            name: "the estimate summed in reverse, the radius from the largest distance found by a fold; rejection by a different draw order",
            verdict: Verdict::Accept,
            point: Some(|l, n, rng| {
                let d = loop {
                    let z = 2.0 * rng.next_f32() - 1.0;
                    let y = 2.0 * rng.next_f32() - 1.0;
                    let x = 2.0 * rng.next_f32() - 1.0;
                    let p = Vec3::new(x, y, z);
                    if p.length_squared() < 1.0 && p.length_squared() > 1e-12 {
                        break p.normalize();
                    }
                };
                point_photon(l, d, 4.0 * PI * l.intensity / n as f32)
            }),
            radiance: Some(|d, n, ps, k, r| {
                let r2 = if ps.len() < k {
                    r * r
                } else {
                    ps.iter().fold(0.0f32, |m, p| m.max(p.distance_squared))
                };
                if r2 <= 0.0 {
                    return Vec3::ZERO;
                }
                let mut flux = Vec3::ZERO;
                for p in ps.iter().rev() {
                    if n.dot(p.direction) < 0.0 {
                        flux += p.power;
                    }
                }
                flux * d / (PI * PI * r2)
            }),
            ..NONE
        },
    ]
}

grading::corpus_tests!(lab08, lab08_checks, reference);
