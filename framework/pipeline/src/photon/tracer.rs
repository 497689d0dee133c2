//! Photon tracing (DTU `ParticleTracer`): photons emitted from the scene's lights through the
//! lab 08 slot, followed through mirrors and glass, and stored at the first diffuse surface.
//!
//! Photon `i` draws every random number it needs from its own generator (`Rng::new(seed, i)`)
//! and the photons are traced in parallel with rayon but collected in index order, so the map
//! is the same on any number of threads. [`trace_photon`] is the whole path of one photon: the
//! one place a new interaction (absorption in a volume, say) goes.

use glam::{DVec3, Vec2, Vec3};
use rayon::prelude::*;

use super::map::{Photon, PhotonMap, PhotonSettings};
use crate::Pipeline;
use contracts::lab08::{EmittedPhoton, Scatter};
use raylab_core::sampling::Rng;
use raylab_core::scene::{IllumModel, Light, Scene};

/// A photon that has bounced this many times is dropped (counted as
/// [`PhotonTrace::truncated_power`]): the DTU tracer's limit.
pub const MAX_PHOTON_BOUNCES: u32 = 500;

/// Which photons are stored.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StoreRule {
    /// The caustic map: at the first diffuse surface after at least one specular bounce.
    Caustic,
    /// Every photon at the first diffuse surface it reaches, also straight from the light (a
    /// map of the whole first-bounce illumination, for checking the density estimate).
    FirstDiffuse,
}

/// The photons of one trace and where the emitted power went.
#[derive(Debug)]
pub struct PhotonTrace {
    /// The stored photons.
    pub map: PhotonMap,
    /// Photons emitted.
    pub emitted: u32,
    /// The total power the emitted photons carried.
    pub emitted_power: DVec3,
    /// The power of the stored photons.
    pub stored_power: DVec3,
    /// The power of photons that reached a diffuse surface straight from the light and were
    /// not stored (lit directly: the direct lighting computes it).
    pub direct_power: DVec3,
    /// The power of photons that left the scene.
    pub escaped_power: DVec3,
    /// The power of photons dropped after [`MAX_PHOTON_BOUNCES`] bounces.
    pub truncated_power: DVec3,
}

/// What became of one photon.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhotonFate {
    /// Stored at a diffuse surface.
    Stored(Photon),
    /// Reached a diffuse surface straight from the light and was not stored; its power.
    Direct(Vec3),
    /// Left the scene with this power.
    Escaped(Vec3),
    /// Dropped at the bounce limit with this power.
    Truncated(Vec3),
}

/// One light's share of the photons: emitted photons `first .. first + count`.
#[derive(Clone, Copy, Debug)]
struct Share {
    light: usize,
    first: u32,
    count: u32,
}

/// The lights that emit photons (point and area lights; a directional light has no position
/// to emit from and is skipped) and their shares of `emitted` photons, in proportion to the
/// power the lab 08 slot gives each light (one photon's power when it is the only one), or
/// equal shares when that is not a positive finite number.
fn shares(pipeline: &Pipeline, scene: &Scene, emitted: u32) -> Vec<Share> {
    let mut lights = Vec::new();
    for (i, light) in scene.lights.iter().enumerate() {
        let power = match light {
            Light::Point(p) => {
                let mut rng = Rng::new(0, u64::MAX);
                crate::required(&pipeline.calls.photon_mapping)
                    .emit_point_light(p, 1, &mut rng)
                    .power
            }
            Light::Area(area) if !area.faces.is_empty() => {
                let mut rng = Rng::new(0, u64::MAX);
                let face = area.faces[0] as usize;
                let emission = scene.material(scene.mesh.face_materials[face]).emission;
                let normal = scene.mesh.face_normal(face);
                let position = scene.mesh.triangle(face)[0];
                crate::required(&pipeline.calls.photon_mapping)
                    .emit_area_light(position, normal, emission, area.area, 1, &mut rng)
                    .power
            }
            _ => continue,
        };
        lights.push((i, (power.x + power.y + power.z) as f64));
    }
    if lights.is_empty() {
        return Vec::new();
    }
    let total: f64 = lights.iter().map(|(_, p)| p).sum();
    let proportional = total.is_finite() && lights.iter().all(|(_, p)| p.is_finite() && *p > 0.0);
    let mut out = Vec::new();
    let mut first = 0u32;
    let n = lights.len();
    for (k, (light, power)) in lights.into_iter().enumerate() {
        let count = if k + 1 == n {
            emitted - first
        } else if proportional {
            ((emitted as f64 * power / total).round() as u32).min(emitted - first)
        } else {
            emitted / n as u32
        };
        if count > 0 {
            out.push(Share {
                light,
                first,
                count,
            });
        }
        first += count;
    }
    out
}

/// Photon `index` of the light `light`, one of `count` that light emits, from `rng`.
fn emit(
    pipeline: &Pipeline,
    scene: &Scene,
    light: &Light,
    count: u32,
    rng: &mut Rng,
) -> Option<EmittedPhoton> {
    let lab08 = crate::required(&pipeline.calls.photon_mapping);
    match light {
        Light::Point(p) => Some(lab08.emit_point_light(p, count, rng)),
        Light::Area(area) => {
            let u = rng.next_vec2();
            let (i, ux) = area.pick_face(u.x);
            let face = area.faces[i] as usize;
            let position = pipeline
                .shadows()
                .sample_triangle(scene.mesh.triangle(face), Vec2::new(ux, u.y));
            let normal = scene.mesh.face_normal(face);
            let emission = scene.material(scene.mesh.face_materials[face]).emission;
            Some(lab08.emit_area_light(position, normal, emission, area.area, count, rng))
        }
        Light::Directional(_) => None,
    }
}

/// Follows one emitted photon through mirrors and glass to its fate (DTU
/// `ParticleTracer::trace_particle`): at a mirror it is reflected; at glass the lab 08 slot's
/// Russian roulette on the surface's reflectance ([`Pipeline::dielectric_reflectance`])
/// reflects or refracts it (always reflected under total internal reflection), and leaving an
/// absorbing volume it keeps the volume's transmittance of its power
/// ([`Pipeline::medium_transmittance`], lab 10 on); at a diffuse surface (Lambertian or Phong)
/// it is stored according to `rule`.
pub fn trace_photon(
    pipeline: &Pipeline,
    scene: &Scene,
    photon: EmittedPhoton,
    rule: StoreRule,
    rng: &mut Rng,
) -> PhotonFate {
    let mut ray = photon.ray;
    let mut power = photon.power;
    let mut ior = 1.0;
    for depth in 0..MAX_PHOTON_BOUNCES {
        let Some(mut hit) = pipeline.trace_to_closest(scene, &ray) else {
            return PhotonFate::Escaped(power);
        };
        hit.trace_depth = depth;
        hit.ior = ior;
        let material = scene.material(hit.material);
        match material.illum {
            IllumModel::Mirror => ray = pipeline.reflection().reflected_ray(&ray, &hit),
            IllumModel::Transparent
            | IllumModel::AbsorbingVolume
            | IllumModel::Glossy
            | IllumModel::GlossyVolume => {
                // Leaving an absorbing volume, the photon has crossed it (lab 10 on).
                power *= pipeline.medium_transmittance(ray.direction, &hit, material);
                match pipeline
                    .reflection()
                    .refracted_ray(&ray, &hit, material.ior)
                {
                    None => ray = pipeline.reflection().reflected_ray(&ray, &hit),
                    Some((refracted, ior_t)) => {
                        let side =
                            pipeline
                                .reflection()
                                .interface(ray.direction, &hit, material.ior);
                        let cos_i = ray.direction.dot(side.normal).abs();
                        let reflectance = pipeline.dielectric_reflectance(
                            cos_i,
                            side.eta_incident,
                            side.eta_transmitted,
                        );
                        let (scatter, carried) = crate::required(&pipeline.calls.photon_mapping)
                            .russian_roulette(reflectance, power, rng);
                        power = carried;
                        match scatter {
                            Scatter::Reflect => {
                                ray = pipeline.reflection().reflected_ray(&ray, &hit)
                            }
                            Scatter::Refract => {
                                ray = refracted;
                                ior = ior_t;
                            }
                        }
                    }
                }
            }
            IllumModel::Lambertian | IllumModel::Phong => {
                return if depth > 0 || rule == StoreRule::FirstDiffuse {
                    PhotonFate::Stored(Photon {
                        position: hit.position,
                        direction: ray.direction,
                        power,
                    })
                } else {
                    PhotonFate::Direct(power)
                };
            }
        }
    }
    PhotonFate::Truncated(power)
}

/// Emits `settings.emitted` photons from the scene's lights through `pipeline` and traces
/// them in parallel; the map holds the photons `rule` stores, in the order of emission.
pub fn trace_photons(
    pipeline: &Pipeline,
    scene: &Scene,
    settings: &PhotonSettings,
    rule: StoreRule,
) -> PhotonTrace {
    let shares = shares(pipeline, scene, settings.emitted);
    let results: Vec<(Vec3, PhotonFate)> = shares
        .iter()
        .flat_map(|s| (0..s.count).map(move |k| (*s, s.first + k)))
        .collect::<Vec<_>>()
        .into_par_iter()
        .filter_map(|(share, index)| {
            let mut rng = Rng::new(settings.seed, index as u64);
            let light = &scene.lights[share.light];
            let photon = emit(pipeline, scene, light, share.count, &mut rng)?;
            let fate = trace_photon(pipeline, scene, photon, rule, &mut rng);
            Some((photon.power, fate))
        })
        .collect();
    let emitted = shares.iter().map(|s| s.count).sum();
    let mut trace = PhotonTrace {
        map: PhotonMap::new(Vec::new()),
        emitted,
        emitted_power: DVec3::ZERO,
        stored_power: DVec3::ZERO,
        direct_power: DVec3::ZERO,
        escaped_power: DVec3::ZERO,
        truncated_power: DVec3::ZERO,
    };
    let mut stored = Vec::new();
    for (power, fate) in results {
        trace.emitted_power += power.as_dvec3();
        match fate {
            PhotonFate::Stored(p) => {
                trace.stored_power += p.power.as_dvec3();
                stored.push(p);
            }
            PhotonFate::Direct(p) => trace.direct_power += p.as_dvec3(),
            PhotonFate::Escaped(p) => trace.escaped_power += p.as_dvec3(),
            PhotonFate::Truncated(p) => trace.truncated_power += p.as_dvec3(),
        }
    }
    trace.map = PhotonMap::new(stored);
    trace
}

/// The caustic photon map of `scene` traced through `pipeline` with `settings`.
pub fn trace_caustic_photons(
    pipeline: &Pipeline,
    scene: &Scene,
    settings: &PhotonSettings,
) -> PhotonTrace {
    trace_photons(pipeline, scene, settings, StoreRule::Caustic)
}

/// `pipeline` with the caustic photon map of `scene` traced with its own
/// [`photons`](Pipeline::photons) settings, when its integrator is the photon-mapped one
/// (unchanged otherwise: the path tracer finds caustics by its paths); an error names a bad
/// setting.
pub fn with_caustics(pipeline: &Pipeline, scene: &Scene) -> Result<Pipeline, raylab_core::Error> {
    if pipeline.integrator() != crate::Integrator::PhotonMapped {
        return Ok(pipeline.clone());
    }
    pipeline.photons.validate()?;
    let trace = raylab_core::catch_quietly("tracing photons", || {
        trace_caustic_photons(pipeline, scene, &pipeline.photons)
    })?;
    Ok(Pipeline {
        caustics: Some(std::sync::Arc::new(trace.map)),
        ..pipeline.clone()
    })
}
