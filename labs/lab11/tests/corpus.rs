//! Lab 11's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use std::f32::consts::{FRAC_1_PI, PI};

use contracts::lab11::{AmbientOcclusion, HemisphereSample, Occlusion};
use raylab_core::glam::{Vec2, Vec3};
use raylab_core::math::{Onb, RAY_EPSILON, Ray};
use raylab_core::sampling::Rng;
use reference::lab11::Lab11 as Reference;

use grading::corpus::{Variant, Verdict};

/// What a variant changes: the answer key with that one change, as the lab's contract.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Change {
    CubeWithoutBall,
    WholeSpherePdf,
    LowerHemisphereKept,
    EqualAngleUniform,
    ReflectBelow,
    UniformByInversion,
    DiscRadiusWithoutRoot,
    CosinePdfWithoutPi,
    UniformForCosine,
    FrameAboutZ,
    CosineByAcos,
    IgnoresPdf,
    AssumesUniform,
    TminZero,
    BentOverAllRays,
    BentUnweighted,
    DividesByFree,
    PdfWithoutPi,
    NoMantissaScale,
    NoHalfStep,
    ListingWithoutBias,
    ZeroExponentNotBlack,
    BackToCentre,
    AngularVUp,
    AngularRadiusOne,
    AngularNeverNone,
    AngularZFlipped,
    LatlongAzimuthFromXz,
    LatlongVOverTwoPi,
    LatlongNoShift,
    LatlongByAcos,
    ShaderExtraOneOverPi,
    ShaderIgnoresAccessibility,
}

use Change::*;

/// Every variant of lab 11: the reference with one function changed.
fn variants() -> Vec<Variant<Change>> {
    let v = Variant::new;
    let r = Verdict::Reject;
    let ok = Verdict::Accept;
    vec![
        v(
            "cube points without the ball test",
            r("11.1"),
            CubeWithoutBall,
        ),
        v("pdf 1/(4π), the whole sphere's", r("11.1"), WholeSpherePdf),
        v(
            "points below the surface kept",
            r("11.1"),
            LowerHemisphereKept,
        ),
        v("θ and φ uniform, pdf 1/(2π)", r("11.1"), EqualAngleUniform),
        v(
            "points below the surface reflected, not rejected",
            ok,
            ReflectBelow,
        ),
        v("uniform by inversion, cos θ = u₁", ok, UniformByInversion),
        v(
            "the hand-in's disc radius r = u₁ (no square root)",
            r("11.2"),
            DiscRadiusWithoutRoot,
        ),
        v("pdf cos θ without 1/π", r("11.2"), CosinePdfWithoutPi),
        v(
            "θ = acos u₁: uniform, pdf cos θ/π",
            r("11.2"),
            UniformForCosine,
        ),
        v("the frame about +z, not the normal", r("11.2"), FrameAboutZ),
        v("the hand-in's θ = acos √u₁", ok, CosineByAcos),
        v(
            "the fraction of free rays, pdf ignored",
            r("11.3"),
            IgnoresPdf,
        ),
        v(
            "2·V·cos θ: the uniform sampler assumed",
            r("11.3"),
            AssumesUniform,
        ),
        v("rays with tmin = 0", r("11.3"), TminZero),
        v("the bent normal over every ray", r("11.3"), BentOverAllRays),
        v(
            "the bent normal the plain mean of the free directions (no weight)",
            r("11.3"),
            BentUnweighted,
        ),
        v(
            "divided by the free rays, not all",
            r("11.3"),
            DividesByFree,
        ),
        v("V cos θ/pdf without 1/π", r("11.3"), PdfWithoutPi),
        v(
            "m·2^(e − 128): the mantissa not a fraction",
            r("11.4"),
            NoMantissaScale,
        ),
        v("m/256·2^(e − 128): no half step", r("11.4"), NoHalfStep),
        v(
            "the hand-in's listing (c + ½)·2^(e − 8) without the bias",
            r("11.4"),
            ListingWithoutBias,
        ),
        v("exponent 0 not black", r("11.4"), ZeroExponentNotBlack),
        v(
            "the hand-in's (½, ½) for small (x, y), also straight back",
            r("11.5"),
            BackToCentre,
        ),
        v("v = ½ + r·y: the image upside down", r("11.5"), AngularVUp),
        v(
            "radius 1 at the rim: r = θ/(π·s)",
            r("11.5"),
            AngularRadiusOne,
        ),
        v("Some outside the disc", r("11.6"), AngularNeverNone),
        v("z of the wrong sign", r("11.6"), AngularZFlipped),
        v(
            "u from the azimuth atan2(z, x)",
            r("11.7"),
            LatlongAzimuthFromXz,
        ),
        v("v = θ/(2π)", r("11.7"), LatlongVOverTwoPi),
        v("φ = 2πu, not shifted by ½", r("11.8"), LatlongNoShift),
        v(
            "the latitude by acos y, the longitude from (x, −z)",
            ok,
            LatlongByAcos,
        ),
        v(
            "the hand-in's shader with 1/π",
            r("11.9"),
            ShaderExtraOneOverPi,
        ),
        v(
            "accessibility left out",
            r("11.9"),
            ShaderIgnoresAccessibility,
        ),
    ]
}

fn cube(rng: &mut Rng) -> Vec3 {
    Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * 2.0 - 1.0
}

fn local(normal: Vec3, x: f32, y: f32, z: f32) -> Vec3 {
    Onb::from_w(normal).to_world(Vec3::new(x, y, z)).normalize()
}

impl AmbientOcclusion for Change {
    fn sample_hemisphere_rejection(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample {
        let uniform = |direction| HemisphereSample {
            direction,
            pdf: 0.5 * FRAC_1_PI,
        };
        match *self {
            CubeWithoutBall => loop {
                let p = cube(rng);
                if p.dot(normal) >= 0.0 && p.length_squared() > 1e-6 {
                    return uniform(p.normalize());
                }
            },
            WholeSpherePdf => HemisphereSample {
                pdf: 0.25 * FRAC_1_PI,
                ..Reference.sample_hemisphere_rejection(normal, rng)
            },
            LowerHemisphereKept => loop {
                let p = cube(rng);
                if p.length_squared() <= 1.0 && p.length_squared() > 1e-6 {
                    return uniform(p.normalize());
                }
            },
            EqualAngleUniform => {
                let u = rng.next_vec2();
                let (t, f) = (0.5 * PI * u.x, 2.0 * PI * u.y);
                uniform(local(normal, t.sin() * f.cos(), t.sin() * f.sin(), t.cos()))
            }
            ReflectBelow => loop {
                let p = cube(rng);
                if p.length_squared() <= 1.0 && p.length_squared() > 1e-6 {
                    let p = if p.dot(normal) < 0.0 {
                        p - 2.0 * p.dot(normal) * normal
                    } else {
                        p
                    };
                    return uniform(p.normalize());
                }
            },
            UniformByInversion => {
                let u = rng.next_vec2();
                let (z, f) = (u.x, 2.0 * PI * u.y);
                let s = (1.0 - z * z).max(0.0).sqrt();
                uniform(local(normal, s * f.cos(), s * f.sin(), z))
            }
            _ => Reference.sample_hemisphere_rejection(normal, rng),
        }
    }

    fn sample_hemisphere_cosine(&self, normal: Vec3, rng: &mut Rng) -> HemisphereSample {
        let with_pdf = |direction: Vec3| HemisphereSample {
            direction,
            pdf: direction.dot(normal).max(0.0) * FRAC_1_PI,
        };
        match *self {
            DiscRadiusWithoutRoot => {
                let u = rng.next_vec2();
                let (r, f) = (u.x, 2.0 * PI * u.y);
                with_pdf(local(
                    normal,
                    r * f.cos(),
                    r * f.sin(),
                    (1.0 - r * r).max(0.0).sqrt(),
                ))
            }
            CosinePdfWithoutPi => {
                let s = Reference.sample_hemisphere_cosine(normal, rng);
                HemisphereSample {
                    pdf: s.direction.dot(normal),
                    ..s
                }
            }
            UniformForCosine => {
                let u = rng.next_vec2();
                let (t, f) = (u.x.acos(), 2.0 * PI * u.y);
                with_pdf(local(normal, t.sin() * f.cos(), t.sin() * f.sin(), t.cos()))
            }
            FrameAboutZ => {
                let s = Reference.sample_hemisphere_cosine(Vec3::Z, rng);
                HemisphereSample {
                    direction: s.direction,
                    pdf: s.direction.z.max(0.0) * FRAC_1_PI,
                }
            }
            CosineByAcos => {
                let u = rng.next_vec2();
                let (t, f) = (u.x.sqrt().acos(), 2.0 * PI * u.y);
                with_pdf(local(normal, t.sin() * f.cos(), t.sin() * f.sin(), t.cos()))
            }
            _ => Reference.sample_hemisphere_cosine(normal, rng),
        }
    }

    fn ambient_occlusion(
        &self,
        position: Vec3,
        normal: Vec3,
        samples: u32,
        sampler: &dyn Fn(&mut Rng) -> HemisphereSample,
        occluded: &dyn Fn(&Ray) -> bool,
        rng: &mut Rng,
    ) -> Occlusion {
        let weight: fn(f32, f32) -> f32 = match *self {
            IgnoresPdf => |_, _| 1.0,
            AssumesUniform => |cos, _| 2.0 * cos,
            PdfWithoutPi => |cos, pdf| cos / pdf,
            TminZero | BentOverAllRays | BentUnweighted | DividesByFree => {
                |cos, pdf| cos / (PI * pdf)
            }
            _ => {
                return Reference
                    .ambient_occlusion(position, normal, samples, sampler, occluded, rng);
            }
        };
        let tmin = if *self == TminZero { 0.0 } else { RAY_EPSILON };
        let (mut sum, mut bent, mut free) = (0.0, Vec3::ZERO, 0);
        for _ in 0..samples {
            let s = sampler(rng);
            let blocked = occluded(&Ray::unbounded(position, s.direction, tmin));
            let w = weight(s.direction.dot(normal).max(0.0), s.pdf);
            if *self == BentOverAllRays {
                bent += w * s.direction;
            }
            if !blocked {
                sum += w;
                free += 1;
                if *self == BentUnweighted {
                    bent += s.direction;
                } else if *self != BentOverAllRays {
                    bent += w * s.direction;
                }
            }
        }
        let n = if *self == DividesByFree {
            free.max(1)
        } else {
            samples.max(1)
        };
        Occlusion {
            accessibility: sum / n as f32,
            bent_normal: bent.try_normalize().unwrap_or(normal),
        }
    }

    fn rgbe_to_rgb(&self, rgbe: [u8; 4]) -> Vec3 {
        let [r, g, b, e] = rgbe;
        let m = Vec3::new(r as f32, g as f32, b as f32);
        let e = i32::from(e);
        match *self {
            NoMantissaScale if e > 0 => (m + 0.5) * f32::exp2((e - 128) as f32),
            NoHalfStep if e > 0 => m * f32::exp2((e - 136) as f32),
            ListingWithoutBias if e > 0 => (m + 0.5) * f32::exp2((e - 8) as f32),
            ZeroExponentNotBlack => (m + 0.5) * f32::exp2((e - 136) as f32),
            _ => Reference.rgbe_to_rgb(rgbe),
        }
    }

    fn angular_map_uv(&self, d: Vec3) -> Vec2 {
        let s = (d.x * d.x + d.y * d.y).sqrt();
        match *self {
            BackToCentre if s < 1e-3 => Vec2::splat(0.5),
            AngularVUp => {
                let uv = Reference.angular_map_uv(d);
                Vec2::new(uv.x, 1.0 - uv.y)
            }
            AngularRadiusOne if s > 0.0 => {
                let r = (-d.z).clamp(-1.0, 1.0).acos() / (PI * s);
                Vec2::new(0.5 + r * d.x, 0.5 - r * d.y)
            }
            _ => Reference.angular_map_uv(d),
        }
    }

    fn angular_map_direction(&self, uv: Vec2) -> Option<Vec3> {
        match *self {
            AngularNeverNone => {
                let c = (uv - Vec2::splat(0.5)).clamp_length_max(0.5);
                Reference.angular_map_direction(Vec2::splat(0.5) + c)
            }
            AngularZFlipped => Reference
                .angular_map_direction(uv)
                .map(|d| Vec3::new(d.x, d.y, -d.z)),
            _ => Reference.angular_map_direction(uv),
        }
    }

    fn latlong_uv(&self, d: Vec3) -> Vec2 {
        match *self {
            LatlongAzimuthFromXz => {
                let uv = Reference.latlong_uv(d);
                Vec2::new(0.5 + d.z.atan2(d.x) / (2.0 * PI), uv.y)
            }
            LatlongVOverTwoPi => {
                let uv = Reference.latlong_uv(d);
                Vec2::new(uv.x, 0.5 * uv.y)
            }
            LatlongByAcos => Vec2::new(
                0.5 + d.x.atan2(-d.z) / (2.0 * PI),
                d.y.clamp(-1.0, 1.0).acos() / PI,
            ),
            _ => Reference.latlong_uv(d),
        }
    }

    fn latlong_direction(&self, uv: Vec2) -> Vec3 {
        match *self {
            LatlongNoShift => Reference.latlong_direction(Vec2::new(uv.x + 0.5, uv.y)),
            _ => Reference.latlong_direction(uv),
        }
    }

    fn shade_ambient_occlusion(
        &self,
        diffuse: Vec3,
        occlusion: &Occlusion,
        environment: Vec3,
    ) -> Vec3 {
        match *self {
            ShaderExtraOneOverPi => FRAC_1_PI * occlusion.accessibility * diffuse * environment,
            ShaderIgnoresAccessibility => diffuse * environment,
            _ => Reference.shade_ambient_occlusion(diffuse, occlusion, environment),
        }
    }
}

grading::corpus_tests!(lab11, lab11_checks, reference, code = change);
