//! Lab 12's framework: the path tracer's side of
//! [`PathTracing::path_radiance`](contracts::lab12::PathTracing::path_radiance) — the scene's
//! queries, the light sampler and the lab's other functions, handed to the path loop as
//! closures.
//!
//! Light comes from the scene's lights and from the background of rays that leave the scene.
//! Next-event estimation chooses one of the lights with equal probability: of the emitting
//! triangles (the scene's [`AreaLight`]) one with probability proportional to its area, then
//! a point on it through Exercise 12.4; a point or directional light is a delta light, which
//! only next-event estimation finds (`EmitterSample::delta`); a latitude–longitude sky, once
//! [`with_sky`] has built its distribution (Exercise 12.11), a direction drawn from it by
//! Exercise 12.12.

use std::sync::Arc;

use glam::Vec3;

use contracts::lab12::{
    BsdfValue, EmitterSample, PathHit, PathMaterial, PathVertex, SkyDistribution,
};
use contracts::surface::SurfaceModel;
use contracts::trace::RayKind;
use raylab_core::Error;
use raylab_core::math::Ray;
use raylab_core::sampling::Rng;
use raylab_core::scene::{
    AreaLight, EnvironmentMap, HitSurface, IllumModel, Light, Material, ProbeMapping, Scene,
};

use crate::{Pipeline, required};

/// Which strategies of the path tracer find the light of the scene's sampled lights (its
/// emitting triangles and sky; delta lights are found by next-event estimation whatever this
/// says).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PathSampling {
    /// Both, weighted by the power heuristic: multiple importance sampling.
    #[default]
    Mis,
    /// Only directions drawn from the BSDF: the light sampler draws nothing.
    Bsdf,
    /// Only next-event estimation: its samples weigh 1, and a bounce that finds a light it
    /// could have drawn weighs 0 (the density of the light sampler there is infinite to the
    /// power heuristic; the BSDF's density is 0 to it).
    Light,
}

/// The glossy exponent of a mirror (`illum 3`): a lobe a tenth of a degree wide.
pub const MIRROR_EXPONENT: f32 = 1e5;

/// The glossy exponent of roughness `r`: `2/r² − 2`, the Phong exponent whose lobe matches a
/// Beckmann microfacet distribution of that roughness (Walter et al. 2007).
pub fn roughness_exponent(r: f32) -> f32 {
    2.0 / (r * r) - 2.0
}

/// The path tracer's material for `material`, whose diffuse colour at the hit is `diffuse`
/// (textured from lab 09 on): the diffuse colour under a glossy lobe of `Ks` with the Phong
/// exponent `Ns` (`illum 2`, and the dielectrics, whose refraction the path tracer leaves
/// out), a mirror a lobe of `Ks` (white if black) without a diffuse part, a Lambertian surface
/// no lobe. A material's roughness (`Pr`) sets the lobe's exponent instead.
pub fn path_material(material: &Material, diffuse: Vec3) -> PathMaterial {
    let mut path = path_lobe(material, diffuse);
    if let Some(r) = material.roughness
        && path.glossy != Vec3::ZERO
    {
        path.exponent = roughness_exponent(r);
    }
    path
}

/// [`path_material`] by the material's `illum` alone.
fn path_lobe(material: &Material, diffuse: Vec3) -> PathMaterial {
    match material.illum {
        IllumModel::Lambertian => PathMaterial {
            diffuse,
            glossy: Vec3::ZERO,
            exponent: 0.0,
        },
        IllumModel::Mirror => PathMaterial {
            diffuse: Vec3::ZERO,
            glossy: if material.specular == Vec3::ZERO {
                Vec3::ONE
            } else {
                material.specular
            },
            exponent: MIRROR_EXPONENT,
        },
        _ => PathMaterial {
            diffuse,
            glossy: material.specular,
            exponent: material.shininess,
        },
    }
}

/// The lights next-event estimation chooses from, each with the same probability.
fn lights(scene: &Scene) -> impl Iterator<Item = &Light> {
    scene
        .lights
        .iter()
        .filter(|l| !matches!(l, Light::Area(area) if area.faces.is_empty()))
}

/// The scene's emitting triangles, if it has any.
fn emitters(scene: &Scene) -> Option<&AreaLight> {
    scene.lights.iter().find_map(|l| match l {
        Light::Area(area) if !area.faces.is_empty() => Some(area),
        _ => None,
    })
}

/// The probability with which the light sampler chooses face number `i` of `area`, once it
/// has chosen the emitting triangles.
fn face_probability(area: &AreaLight, i: usize) -> f32 {
    area.cdf[i] - if i == 0 { 0.0 } else { area.cdf[i - 1] }
}

/// `pipeline` with the distribution of `scene`'s sky for next-event estimation, built by
/// Exercise 12.11 from the luminance of each texel (Exercise 12.1), when it is at lab 12 or
/// later and the scene has a latitude–longitude probe; without one otherwise (an angular probe
/// is found by BSDF samples only). An error names what is wrong with the distribution.
pub fn with_sky(pipeline: &Pipeline, scene: &Scene) -> Result<Pipeline, Error> {
    let probe = scene.environment.as_ref().filter(|env| {
        env.mapping == ProbeMapping::Latlong && pipeline.calls.path_tracing.is_some()
    });
    let Some(env) = probe else {
        return Ok(Pipeline {
            sky: None,
            ..pipeline.clone()
        });
    };
    let code = required(&pipeline.calls.path_tracing);
    let (width, height) = (env.texture.width, env.texture.height);
    let sky = raylab_core::catch_quietly("building the sky's distribution", || {
        let luminance: Vec<f32> = env
            .texture
            .texels
            .iter()
            .map(|&texel| {
                let y = code.luminance(texel * env.scale);
                if y.is_finite() { y.max(0.0) } else { 0.0 }
            })
            .collect();
        code.sky_distribution(&luminance, width, height)
    })?;
    let defect = if (sky.width, sky.height) != (width, height) {
        Some(format!(
            "it is {} × {} texels; the probe is {width} × {height}",
            sky.width, sky.height
        ))
    } else {
        sky.defect()
    };
    if let Some(reason) = defect {
        return Err(Error::Failed {
            what: format!(
                "the distribution of the sky {} (Exercise 12.11)",
                env.texture.path.display()
            ),
            reason,
        });
    }
    Ok(Pipeline {
        sky: Some(Arc::new(sky)),
        ..pipeline.clone()
    })
}

/// The sky next-event estimation draws from: the scene's probe with its distribution.
fn sky<'a>(
    pipeline: &'a Pipeline,
    scene: &'a Scene,
) -> Option<(&'a EnvironmentMap, &'a SkyDistribution)> {
    match (&scene.environment, &pipeline.sky) {
        (Some(env), Some(sky)) if pipeline.calls.ambient_occlusion.is_some() => Some((env, sky)),
        _ => None,
    }
}

impl Pipeline {
    /// The radiance along a camera ray by the path tracer of lab 12 (Exercise 12.8 with the
    /// lab's other functions as its closures); NaN along a ray that is not traceable.
    pub(crate) fn path_traced(&self, scene: &Scene, ray: &Ray, rng: &mut Rng) -> Vec3 {
        if !ray.is_traceable() {
            return Vec3::NAN;
        }
        let ray = Ray {
            direction: ray.direction.normalize(),
            ..*ray
        };
        let code = required(&self.calls.path_tracing);
        let strategy = self.path_sampling;
        let sky = sky(self, scene);
        let count = lights(scene).count() + usize::from(sky.is_some());
        let choice = 1.0 / count.max(1) as f32;
        let emitters = emitters(scene);
        // The path loop's first ray is the camera ray, the others its bounces.
        let first = std::cell::Cell::new(true);
        let modelled = ModelledVertices::default();
        let trace = |r: &Ray| {
            let kind = if first.replace(false) {
                RayKind::Camera
            } else {
                RayKind::Bounce
            };
            let (mut hit, model) = self.path_hit(scene, emitters, sky, choice, r, kind);
            if let (PathHit::Surface(vertex), Some(model)) = (&hit, model) {
                modelled.note(vertex, model);
            }
            let light_pdf = match &mut hit {
                PathHit::Surface(v) => &mut v.light_pdf,
                PathHit::Escaped { light_pdf, .. } => light_pdf,
            };
            *light_pdf = match strategy {
                PathSampling::Mis => *light_pdf,
                PathSampling::Bsdf => 0.0,
                PathSampling::Light if *light_pdf > 0.0 => f32::INFINITY,
                PathSampling::Light => 0.0,
            };
            hit
        };
        let occluded = |r: &Ray| self.blocked(scene, r, RayKind::Shadow);
        let sample_light = |position: Vec3, rng: &mut Rng| -> Option<EmitterSample> {
            if count == 0 || strategy == PathSampling::Bsdf {
                return None;
            }
            let u = rng.next_f32() * count as f32;
            let (k, u) = ((u as usize).min(count - 1), u.fract());
            let Some(light) = lights(scene).nth(k) else {
                let (env, sky) = sky?;
                let sample = code.sample_sky(sky, rng)?;
                return Some(EmitterSample {
                    direction: sample.direction,
                    distance: f32::INFINITY,
                    radiance: self.environment_radiance(env, sample.direction),
                    pdf: sample.pdf * choice,
                    delta: false,
                });
            };
            match light {
                Light::Area(area) => {
                    let (i, _) = area.pick_face(u);
                    let face = area.faces[i] as usize;
                    let radiance = scene.material(scene.mesh.face_materials[face]).emission;
                    let sample =
                        code.sample_emitter(scene.mesh.triangle(face), radiance, position, rng)?;
                    Some(EmitterSample {
                        pdf: sample.pdf * face_probability(area, i) * choice,
                        ..sample
                    })
                }
                Light::Point(point) => {
                    let to = point.position - position;
                    let distance = to.length();
                    Some(EmitterSample {
                        direction: to / distance,
                        distance,
                        radiance: point.intensity / (distance * distance),
                        pdf: choice,
                        delta: true,
                    })
                }
                Light::Directional(sun) => Some(EmitterSample {
                    direction: -sun.direction.normalize(),
                    distance: f32::INFINITY,
                    radiance: sun.emission,
                    pdf: choice,
                    delta: true,
                }),
            }
        };
        let sample_bsdf = |v: &PathVertex, wo: Vec3, rng: &mut Rng| match modelled.of(v) {
            Some(at) => at
                .model
                .sample_bsdf(at.material, at.diffuse, v.normal, wo, rng),
            None => code.sample_bsdf(&v.material, v.normal, wo, rng),
        };
        let bsdf = |v: &PathVertex, wo: Vec3, wi: Vec3| {
            let value = match modelled.of(v) {
                Some(at) => at.model.bsdf(at.material, at.diffuse, v.normal, wo, wi),
                None => code.bsdf(&v.material, v.normal, wo, wi),
            };
            match strategy {
                PathSampling::Light => BsdfValue { pdf: 0.0, ..value },
                _ => value,
            }
        };
        let power_heuristic = |a: f32, b: f32| code.power_heuristic(a, b);
        let roulette = |t: Vec3, rng: &mut Rng| code.roulette(t, rng);
        code.path_radiance(
            &ray,
            self.max_depth,
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

    /// What `ray` finds, as the path loop sees it: the surface with its material, its
    /// emitted radiance and the light sampler's density of it from the ray's origin; or the
    /// background.
    /// `choice` is the probability with which the light sampler chooses the emitting
    /// triangles, or the sky; `kind` is the ray's, for the pixel inspector. With the surface,
    /// the surface model a lab registered that draws it, when its material names one.
    fn path_hit<'a>(
        &'a self,
        scene: &'a Scene,
        lights: Option<&AreaLight>,
        sky: Option<(&EnvironmentMap, &SkyDistribution)>,
        choice: f32,
        ray: &Ray,
        kind: RayKind,
    ) -> (PathHit, Option<ModelAt<'a>>) {
        let Some(mut hit) = self.closest_hit(scene, ray, kind) else {
            let radiance = match &scene.environment {
                Some(env) if self.calls.ambient_occlusion.is_some() => {
                    self.environment_radiance(env, ray.direction)
                }
                _ => scene.background,
            };
            let light_pdf = sky.map_or(0.0, |(_, sky)| {
                choice * required(&self.calls.path_tracing).sky_pdf(sky, ray.direction)
            });
            let escaped = PathHit::Escaped {
                radiance,
                light_pdf,
            };
            return (escaped, None);
        };
        let material = scene.material(hit.material);
        let diffuse = self.diffuse_colour(scene, &mut hit, material);
        let back = -ray.direction;
        let facing = hit.geometric_normal.dot(back) >= 0.0;
        let normal = if facing {
            hit.shading_normal
        } else {
            -hit.shading_normal
        };
        // An emitter emits on the side its normal faces: a triangle's (v1 − v0) × (v2 − v0).
        let front = match hit.surface {
            HitSurface::Triangle { face, .. } => {
                let [a, b, c] = scene.mesh.triangle(face as usize);
                (b - a).cross(c - a).dot(back) > 0.0
            }
            _ => facing,
        };
        let (mut emitted, mut light_pdf) = (Vec3::ZERO, 0.0);
        if material.is_emissive() && front {
            emitted = material.emission;
            if let (Some(area), HitSurface::Triangle { face, .. }) = (lights, hit.surface)
                && let Ok(i) = area.faces.binary_search(&face)
            {
                let to = hit.position - ray.origin;
                light_pdf = choice
                    * face_probability(area, i)
                    * required(&self.calls.path_tracing).emitter_pdf(
                        scene.mesh.triangle(face as usize),
                        ray.origin,
                        to.normalize(),
                        to.length(),
                    );
            }
        }
        let model = material
            .model
            .as_deref()
            .and_then(|name| self.parts().surface(name))
            .map(|model| ModelAt {
                model: model.as_ref(),
                material,
                diffuse,
            });
        let vertex = PathHit::Surface(PathVertex {
            position: hit.position,
            normal,
            material: path_material(material, diffuse),
            emitted,
            light_pdf,
        });
        (vertex, model)
    }
}

/// A surface a lab's surface model draws: the model, the scene's material and its diffuse
/// colour at the hit.
#[derive(Clone, Copy)]
struct ModelAt<'a> {
    model: &'a dyn SurfaceModel,
    material: &'a Material,
    diffuse: Vec3,
}

/// The vertices of one path that a lab's surface model draws, by their position and normal: the
/// path loop hands a vertex back to the BSDF's closures as it got it, and they find its model
/// here (the rest take lab 12's lobes). The most recent [`Self::LIMIT`] are kept.
#[derive(Default)]
struct ModelledVertices<'a>(std::cell::RefCell<Vec<([u32; 6], ModelAt<'a>)>>);

impl<'a> ModelledVertices<'a> {
    const LIMIT: usize = 256;

    /// The bits a vertex is known by.
    fn key(v: &PathVertex) -> [u32; 6] {
        let [a, b, c] = v.position.to_array().map(f32::to_bits);
        let [d, e, f] = v.normal.to_array().map(f32::to_bits);
        [a, b, c, d, e, f]
    }

    fn note(&self, v: &PathVertex, model: ModelAt<'a>) {
        let mut seen = self.0.borrow_mut();
        if seen.len() == Self::LIMIT {
            seen.remove(0);
        }
        seen.push((Self::key(v), model));
    }

    fn of(&self, v: &PathVertex) -> Option<ModelAt<'a>> {
        let seen = self.0.borrow();
        if seen.is_empty() {
            return None;
        }
        let key = Self::key(v);
        seen.iter()
            .rev()
            .find(|(k, _)| *k == key)
            .map(|(_, at)| *at)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn materials_map_to_the_path_tracers_lobes() {
        let mut phong = Material::lambertian("phong", Vec3::splat(0.5));
        phong.illum = IllumModel::Phong;
        phong.specular = Vec3::splat(0.3);
        phong.shininess = 40.0;
        let m = path_material(&phong, phong.diffuse);
        assert_eq!((m.glossy, m.exponent), (Vec3::splat(0.3), 40.0));
        // Roughness overrides Ns: 1 is the widest lobe, 0.5 the exponent 6.
        phong.roughness = Some(1.0);
        assert_eq!(path_material(&phong, phong.diffuse).exponent, 0.0);
        phong.roughness = Some(0.5);
        assert_eq!(path_material(&phong, phong.diffuse).exponent, 6.0);
        // A Lambertian surface has no lobe to roughen; a mirror no diffuse part.
        let mut matte = Material::lambertian("matte", Vec3::splat(0.7));
        matte.roughness = Some(0.3);
        let m = path_material(&matte, matte.diffuse);
        assert_eq!((m.glossy, m.exponent), (Vec3::ZERO, 0.0));
        let mut mirror = Material::lambertian("mirror", Vec3::splat(0.7));
        mirror.illum = IllumModel::Mirror;
        let m = path_material(&mirror, mirror.diffuse);
        assert_eq!(
            (m.diffuse, m.glossy, m.exponent),
            (Vec3::ZERO, Vec3::ONE, MIRROR_EXPONENT)
        );
    }
}
