//! Exercise 12.8: the path loop in furnaces scripted by closures.

use std::sync::Arc;

use glam::Vec3;

use contracts::lab12::{BsdfSample, BsdfValue, EmitterSample, PathMaterial, PathTracing};
use contracts::math::Onb;
use contracts::sampling::Rng;
use grading::LabContext;
use grading::stats::{family_z_limit, mean_and_standard_error};
use grading::strategies::unit_vector;

use super::SIGNIFICANCE;
use super::cornell::check_cornell;

/// A world made of closures for the path loop: every ray meets, at distance one, a surface
/// facing it that emits `emitted` and reflects diffusely with albedo `albedo` (a furnace), or,
/// with `sky`, leaves a scene of one bounce into a uniform sky. Its BSDF sampler is the uniform
/// hemisphere and its light sampler the uniform sphere: neither is the lab's, and a correct path
/// loop is right for any.
#[derive(Clone, Copy, Debug)]
pub struct Furnace {
    /// Diffuse albedo of every surface.
    pub albedo: f32,
    /// Emitted radiance of every surface.
    pub emitted: f32,
    /// Whether the light sampler draws anything (else it returns `None`).
    pub lights: bool,
    /// `Some(L)`: the camera ray meets one surface and every later ray a sky of radiance `L`.
    pub sky: Option<f32>,
    /// `Some(E)`: the light sampler draws only a delta light along [`SUN`], at distance one,
    /// that delivers the irradiance `E`.
    pub sun: Option<f32>,
    /// The path's bounces.
    pub max_depth: u32,
}

/// The direction towards the delta light of a furnace with a sun.
pub const SUN: Vec3 = Vec3::new(0.267_261_24, 0.534_522_5, 0.801_783_7);

impl Furnace {
    /// The expected radiance along a camera ray in `direction`: `E (1 + ρ + … + ρ^D)` in the
    /// furnace, `E + ρ L` under the sky; with a sun (depth 1) `E (1 + ρ)` and the sun's
    /// `ρ/π E_s cos θ` at the first vertex, whose normal faces the ray.
    pub fn expected(&self, direction: Vec3) -> f64 {
        let (rho, e) = (f64::from(self.albedo), f64::from(self.emitted));
        let sun = self.sun.map_or(0.0, |sun| {
            let cos = f64::from((-direction).dot(SUN).max(0.0));
            rho / std::f64::consts::PI * f64::from(sun) * cos
        });
        sun + match self.sky {
            Some(_) if self.max_depth == 0 => e,
            Some(l) => e + rho * f64::from(l),
            None => {
                e * (0..=self.max_depth)
                    .map(|k| rho.powi(k as i32))
                    .sum::<f64>()
            }
        }
    }
}

/// A uniform direction of the hemisphere about `n` from `rng`.
fn uniform_hemisphere(n: Vec3, rng: &mut Rng) -> Vec3 {
    let u = rng.next_vec2();
    let cos = u.x;
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    let phi = std::f32::consts::TAU * u.y;
    Onb::from_w(n)
        .to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
        .normalize()
}

/// What the path loop asked of a [`Furnace`]: problems with the rays it traced.
#[derive(Default)]
struct Asked {
    problems: Vec<String>,
}

/// One estimate of `s.path_radiance` in `world` along a ray from the origin along `direction`.
fn furnace_estimate(
    s: &dyn PathTracing,
    world: &Furnace,
    direction: Vec3,
    rng: &mut Rng,
    asked: &std::cell::RefCell<Asked>,
) -> Vec3 {
    use contracts::lab12::{PathHit, PathVertex};
    use contracts::math::Ray;
    let camera = Ray::unbounded(Vec3::ZERO, direction, 0.0);
    let material = PathMaterial {
        diffuse: Vec3::splat(world.albedo),
        glossy: Vec3::ZERO,
        exponent: 0.0,
    };
    let traced = std::cell::Cell::new(0u32);
    let vertex_at = |r: &Ray| PathVertex {
        position: r.origin + r.direction,
        normal: -r.direction,
        material,
        emitted: Vec3::splat(world.emitted),
        light_pdf: if world.lights {
            1.0 / (4.0 * std::f32::consts::PI)
        } else {
            0.0
        },
    };
    let trace = |r: &Ray| {
        let n = traced.get();
        traced.set(n + 1);
        let offset = r.tmin > 0.0;
        if n > 0 && !offset {
            asked.borrow_mut().problems.push(format!(
                "a ray after a bounce, {r:?}, has tmin = {}: start rays off a surface at RAY_EPSILON, or they find the surface they leave",
                r.tmin
            ));
        }
        match world.sky {
            Some(l) if n > 0 => PathHit::Escaped {
                radiance: Vec3::splat(l),
                light_pdf: 0.0,
            },
            _ => PathHit::Surface(vertex_at(r)),
        }
    };
    let occluded = |r: &Ray| {
        let ok = r.tmin > 0.0 && r.tmax < 1.0 && r.tmax >= 0.99;
        if !ok {
            asked.borrow_mut().problems.push(format!(
                "the shadow ray {r:?} to a point of a light at distance 1 should have tmin > 0 and tmax a little short of 1 (not past the light, where the light itself blocks it)"
            ));
        }
        false
    };
    let sample_light = |_p: Vec3, rng: &mut Rng| -> Option<EmitterSample> {
        if let Some(sun) = world.sun {
            return Some(EmitterSample {
                direction: SUN,
                distance: 1.0,
                radiance: Vec3::splat(sun),
                pdf: 1.0,
                delta: true,
            });
        }
        if !world.lights || world.sky.is_some() {
            return None;
        }
        let u = rng.next_vec2();
        let z = 1.0 - 2.0 * u.x;
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * u.y;
        Some(EmitterSample {
            direction: Vec3::new(r * phi.cos(), r * phi.sin(), z),
            distance: 1.0,
            radiance: Vec3::splat(world.emitted),
            pdf: 1.0 / (4.0 * std::f32::consts::PI),
            delta: false,
        })
    };
    let lambert = world.albedo / std::f32::consts::PI;
    let uniform = 1.0 / std::f32::consts::TAU;
    let bsdf = |v: &PathVertex, wo: Vec3, wi: Vec3| {
        if v.normal.dot(wi) > 0.0 && v.normal.dot(wo) > 0.0 {
            BsdfValue {
                value: Vec3::splat(lambert),
                pdf: uniform,
            }
        } else {
            BsdfValue {
                value: Vec3::ZERO,
                pdf: 0.0,
            }
        }
    };
    let sample_bsdf = |v: &PathVertex, _wo: Vec3, rng: &mut Rng| {
        Some(BsdfSample {
            direction: uniform_hemisphere(v.normal, rng),
            value: Vec3::splat(lambert),
            pdf: uniform,
        })
    };
    // Weights of the two strategies and a roulette that are not the lab's (its 12.6 and 12.7
    // stay unanswered here): the balance heuristic, whose weights add up to one as well, and a
    // fixed probability of going on. A correct loop is unbiased with any.
    let power_heuristic = |a: f32, b: f32| if a > 0.0 { a / (a + b) } else { 0.0 };
    let roulette = |_t: Vec3, rng: &mut Rng| (rng.next_f32() < 0.75).then_some(1.0 / 0.75);
    s.path_radiance(
        &camera,
        world.max_depth,
        &trace,
        &occluded,
        &sample_light,
        &sample_bsdf,
        &bsdf,
        &power_heuristic,
        &roulette,
        rng,
    )
}

/// The furnaces of the check: emission at the first vertex alone, direct light by both
/// strategies, deep paths with roulette, each strategy alone, a black surface, a sky.
pub const FURNACES: [Furnace; 9] = [
    Furnace {
        albedo: 0.5,
        emitted: 1.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 0,
    },
    Furnace {
        albedo: 0.5,
        emitted: 1.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 1,
    },
    Furnace {
        albedo: 0.8,
        emitted: 2.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 3,
    },
    Furnace {
        albedo: 0.8,
        emitted: 1.0,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 40,
    },
    Furnace {
        albedo: 0.8,
        emitted: 1.0,
        lights: false,
        sky: None,
        sun: None,
        max_depth: 6,
    },
    Furnace {
        albedo: 0.0,
        emitted: 0.7,
        lights: true,
        sky: None,
        sun: None,
        max_depth: 5,
    },
    Furnace {
        albedo: 0.6,
        emitted: 0.0,
        lights: false,
        sky: Some(1.5),
        sun: None,
        max_depth: 4,
    },
    Furnace {
        albedo: 0.6,
        emitted: 0.25,
        lights: false,
        sky: Some(2.0),
        sun: None,
        max_depth: 0,
    },
    Furnace {
        albedo: 0.7,
        emitted: 0.0,
        lights: false,
        sky: None,
        sun: Some(3.0),
        max_depth: 1,
    },
];

/// Paths per furnace.
const FURNACE_PATHS: usize = 6_000;

/// Exercise 12.8: in furnaces scripted by closures the mean of the estimates is
/// `E (1 + ρ + … + ρ^D)` (every path of length up to `D` counted once, whichever strategy found
/// it), under a sky `E + ρ L`; rays after a bounce and shadow rays are offset; the generator is
/// the only randomness; then the Cornell box by the student's loop against the reference's
/// renders, pixel by pixel.
pub(super) fn exercise_12_8(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let z_limit = family_z_limit(SIGNIFICANCE, FURNACES.len());
    let directions = grading::strategies::samples(unit_vector(), 16, 81);
    for (k, world) in FURNACES.iter().enumerate() {
        let asked = std::cell::RefCell::new(Asked::default());
        let mut rng = Rng::new(800 + k as u64, 12);
        let mut values = Vec::with_capacity(FURNACE_PATHS);
        for i in 0..FURNACE_PATHS {
            let d = directions[i % directions.len()];
            let l = furnace_estimate(s.as_ref(), world, d, &mut rng, &asked);
            if !l.is_finite() {
                return Err(format!(
                    "path_radiance in the furnace {world:?} returned {l}: a path's radiance is finite"
                ));
            }
            // What the path brought beyond its expectation: zero on average, and exactly
            // zero where nothing is random (the delta light's direct light).
            values.push(f64::from(l.x) - world.expected(d));
            if let Some(problem) = asked.borrow().problems.first() {
                return Err(format!("path_radiance in the furnace {world:?}: {problem}"));
            }
        }
        let (residual, error) = mean_and_standard_error(&values, FURNACE_PATHS);
        let expected =
            directions.iter().map(|&d| world.expected(d)).sum::<f64>() / directions.len() as f64;
        let mean = expected + residual;
        if residual.abs() > z_limit * error + 1e-4 * expected.max(1.0) {
            let what = match world.sky {
                Some(l) => format!(
                    "a surface of albedo {} emitting {} under a sky of radiance {l}",
                    world.albedo, world.emitted
                ),
                None => format!(
                    "a furnace whose every surface has albedo {} and emits {}{}",
                    world.albedo,
                    world.emitted,
                    world.sun.map_or(String::new(), |e| format!(
                        ", lit by a delta light of irradiance {e} (weight one: no BSDF sample finds it)"
                    ))
                ),
            };
            return Err(format!(
                "path_radiance in {what}, at most {} bounces{}: the mean of {FURNACE_PATHS} paths is {mean:.4} ± {error:.4}, expected {expected:.4} (E·(1 + ρ + … + ρ^D), each light path counted once: emission found by a bounce weighted by power_heuristic(bsdf pdf, light_pdf), next-event estimation by power_heuristic(light pdf, bsdf pdf), the first vertex's emission in full)",
                world.max_depth,
                if world.lights {
                    ", lights sampled"
                } else {
                    ", no light sampling"
                },
            ));
        }
    }
    // The generator is the only randomness, and it advances.
    let world = FURNACES[3];
    let asked = std::cell::RefCell::new(Asked::default());
    let mut rng = Rng::new(5, 5);
    let mut twin = rng.clone();
    let a = furnace_estimate(s.as_ref(), &world, Vec3::Y, &mut rng, &asked);
    let b = furnace_estimate(s.as_ref(), &world, Vec3::Y, &mut twin, &asked);
    let c = furnace_estimate(s.as_ref(), &world, Vec3::Y, &mut rng, &asked);
    if a != b {
        return Err(format!(
            "path_radiance returned {a} and then {b} from generators in the same state: draw every random number from `rng`, passed on to the closures"
        ));
    }
    if a == c {
        return Err(format!(
            "path_radiance returned {a} twice in a row in a furnace of depth {}: pass `rng` to the closures that draw, so that it advances",
            world.max_depth
        ));
    }
    super::sky::check_sky_furnace(s, ctx)?;
    check_cornell(s, ctx)
}
