//! Lab 12's framework: the path tracer's side of
//! [`PathTracing::path_radiance`](contracts::lab12::PathTracing::path_radiance) — the scene's
//! queries, the light sampler and the lab's other functions, handed to the path loop as
//! closures.
//!
//! Light comes from the scene's lights and from the background of rays that leave the scene.
//! Next-event estimation chooses one of the lights with equal probability: of the emitting
//! triangles (the scene's [`AreaLight`]) one with probability proportional to its area, then
//! a point on it through Exercise 12.4; a point or directional light is a delta light, which
//! only next-event estimation finds (`EmitterSample::delta`).

use glam::Vec3;

use contracts::lab12::{EmitterSample, PathHit, PathMaterial, PathVertex};
use raylab_core::math::Ray;
use raylab_core::sampling::Rng;
use raylab_core::scene::{AreaLight, HitSurface, IllumModel, Light, Material, Scene};

use crate::Pipeline;

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
        let code = self.path_tracing.as_ref();
        let count = lights(scene).count();
        let choice = 1.0 / count.max(1) as f32;
        let emitters = emitters(scene);
        let trace = |r: &Ray| self.path_hit(scene, emitters, choice, r);
        let occluded = |r: &Ray| self.trace_to_any(scene, r);
        let sample_light = |position: Vec3, rng: &mut Rng| -> Option<EmitterSample> {
            if count == 0 {
                return None;
            }
            let u = rng.next_f32() * count as f32;
            let (k, u) = ((u as usize).min(count - 1), u.fract());
            match lights(scene).nth(k)? {
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
        let sample_bsdf = |v: &PathVertex, wo: Vec3, rng: &mut Rng| {
            code.sample_bsdf(&v.material, v.normal, wo, rng)
        };
        let bsdf = |v: &PathVertex, wo: Vec3, wi: Vec3| code.bsdf(&v.material, v.normal, wo, wi);
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
    /// triangles.
    fn path_hit(
        &self,
        scene: &Scene,
        lights: Option<&AreaLight>,
        choice: f32,
        ray: &Ray,
    ) -> PathHit {
        let Some(mut hit) = self.trace_to_closest(scene, ray) else {
            let radiance = match &scene.environment {
                Some(env) if self.lab >= 11 => self.environment_radiance(env, ray.direction),
                _ => scene.background,
            };
            return PathHit::Escaped {
                radiance,
                light_pdf: 0.0,
            };
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
                    * self.path_tracing.emitter_pdf(
                        scene.mesh.triangle(face as usize),
                        ray.origin,
                        to.normalize(),
                        to.length(),
                    );
            }
        }
        PathHit::Surface(PathVertex {
            position: hit.position,
            normal,
            material: path_material(material, diffuse),
            emitted,
            light_pdf,
        })
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
