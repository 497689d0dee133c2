//! # The pipeline
//!
//! The components a render calls — each lab's code by contract in one store, put there by the
//! lab's contract ([`contracts::Part`]) — and the integrators that call them (the DTU
//! `RayTracer` and shaders, the photon-mapped and the path tracer), chosen by what the store
//! holds ([`Integrator`]). The reference crate's `pipeline()` fills the store with the answer
//! key of the course's labs up to one; a lab's checks and `raylab render --pipeline student`
//! replace one lab's code with the student's, so a mistake in one lab does not spread into the
//! others.
//!
//! Beside it stand the frameworks of the labs whose code the integrator drives through their
//! contracts: lab 08's photon tracing ([`photon`]) and lab 06's radiosity ([`radiosity`]), and
//! the render of a scene through a pipeline ([`render`]).

pub mod builtin;
pub mod inspect;
pub mod job;
pub mod path;
pub mod photon;
pub mod radiosity;
pub mod render;

pub use contracts::PartSlot;

use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};

use contracts::lab09::{self, Addressing, TextureFilter};
use contracts::trace::{self, RayAnswer, RayHit, RayKind};
use contracts::{lab01, lab02, lab03, lab04, lab07, lab08, lab10, lab11, lab12};
use raylab_core::math::Ray;

use crate::photon::{PhotonMap, PhotonSettings};
use raylab_core::sampling::Rng;
use raylab_core::scene::{
    AreaLight, IllumModel, Light, Plane, PrimitiveHit, PrimitiveTests, Scene, Sphere,
};
use raylab_core::scene::{EnvironmentMap, Hit, HitSurface, Material, ProbeMapping};

/// What a render shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum View {
    /// Full shading by the pipeline's [`Integrator`].
    #[default]
    Shaded,
    /// The diffuse reflectance of the surface hit (lab 01's flat image).
    BaseColour,
    /// The shading normal mapped from `[−1, 1]` to `[0, 1]`.
    Normals,
    /// Only the caustics (lab 08): the photon map's radiance estimate at diffuse surfaces,
    /// seen through mirrors and glass, without the direct lighting.
    Caustics,
}

/// The components of a render: each lab's code by contract in one store ([`Parts`]), put
/// there by the lab's contract, and the settings of the integrators that call it. What the
/// store holds decides what is drawn ([`Integrator`]): no lab's code, no lab's feature.
#[derive(Clone)]
pub struct Pipeline {
    /// Each lab's code by contract, as [`Pipeline::with_part`] put it in.
    parts: Parts,
    /// The code the integrators call, looked up in `parts` once.
    pub(crate) calls: Calls,
    /// Lab 08: the caustic photon map diffuse surfaces gather from; `None` (no caustics)
    /// until [`prepare`] traces one for a scene's photon-mapped render.
    pub caustics: Option<Arc<PhotonMap>>,
    /// Lab 08: how many photons to trace, and the radiance estimate's `k` and maximum radius.
    pub photons: PhotonSettings,
    /// Lab 12: the distribution of the scene's sky that next-event estimation draws from;
    /// `None` (the sky found by BSDF samples only) until [`prepare`] builds it for a scene.
    pub sky: Option<Arc<lab12::SkyDistribution>>,
    /// Lab 12: which strategies find the light (both, weighted, unless a figure compares them).
    pub path_sampling: path::PathSampling,
    /// What to show.
    pub view: View,
    /// Area lights are sampled with `n × n` stratified samples per shading point (lab 03).
    pub area_light_samples: u32,
    /// Reflected and refracted rays stop after this many bounces (lab 04), and paths (lab 12).
    pub max_depth: u32,
    /// Rays per shading point of ambient occlusion, and their sampler (lab 11).
    pub occlusion_rays: (u32, lab11::HemisphereSampler),
    /// How textures are read between texel centres (lab 09).
    pub texture_filter: TextureFilter,
    /// What textures do outside `[0, 1]` (lab 09).
    pub texture_addressing: Addressing,
}

pub use contracts::Parts;

/// The integrators: which one renders is chosen by what a pipeline holds, in this order.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
pub enum Integrator {
    /// The path tracer (lab 12's path loop), with the surface models labs register.
    Path,
    /// The Whitted ray tracer with caustics from a photon map (lab 08's photon mapping).
    PhotonMapped,
    /// The Whitted ray tracer: the surfaces shaded by the lights (lab 02) with what the labs
    /// held add: shadows and area lights, mirrors and glass, textures, Fresnel, probes.
    Whitted,
    /// The surfaces' diffuse colour alone: no lab shades them.
    Flat,
}

/// The code the integrators call, by contract: what a pipeline's store holds of each, looked
/// up once; `None` where the store holds none, and the integrator goes without.
#[derive(Clone, Default)]
pub(crate) struct Calls {
    pub(crate) camera: Option<Arc<dyn lab01::CameraRays>>,
    /// `None` uses the framework's intersection kernels.
    pub(crate) intersection: Option<Arc<dyn lab02::Intersection>>,
    pub(crate) shading: Option<Arc<dyn lab02::Shading>>,
    pub(crate) shadows: Option<Arc<dyn lab03::Shadows>>,
    pub(crate) reflection: Option<Arc<dyn lab04::Reflection>>,
    pub(crate) antialiasing: Option<Arc<dyn lab07::Antialiasing>>,
    pub(crate) photon_mapping: Option<Arc<dyn lab08::PhotonMapping>>,
    pub(crate) texturing: Option<Arc<dyn lab09::Texturing>>,
    pub(crate) fresnel: Option<Arc<dyn lab10::Fresnel>>,
    pub(crate) ambient_occlusion: Option<Arc<dyn lab11::AmbientOcclusion>>,
    pub(crate) path_tracing: Option<Arc<dyn lab12::PathTracing>>,
}

impl Calls {
    /// What `parts` holds of each contract an integrator calls.
    fn of(parts: &Parts) -> Self {
        Calls {
            camera: parts.get(),
            intersection: parts.get(),
            shading: parts.get(),
            shadows: parts.get(),
            reflection: parts.get(),
            antialiasing: parts.get(),
            photon_mapping: parts.get(),
            texturing: parts.get(),
            fresnel: parts.get(),
            ambient_occlusion: parts.get(),
            path_tracing: parts.get(),
        }
    }
}

/// The code of contract `C` a pipeline must hold for what it was asked, or a panic naming it.
#[track_caller]
pub(crate) fn required<C: ?Sized>(code: &Option<Arc<C>>) -> &C {
    match code {
        Some(code) => code,
        None => panic!(
            "the pipeline holds no code of `{}`, which this render needs",
            std::any::type_name::<C>()
        ),
    }
}

impl Default for Pipeline {
    /// The pipeline with no lab's code in it and the integrators' default settings.
    fn default() -> Self {
        Pipeline {
            parts: Parts::default(),
            calls: Calls::default(),
            caustics: None,
            photons: PhotonSettings::DEFAULT,
            sky: None,
            path_sampling: path::PathSampling::Mis,
            view: View::Shaded,
            area_light_samples: 4,
            max_depth: 10,
            texture_filter: TextureFilter::Bilinear,
            texture_addressing: Addressing::Repeat,
            occlusion_rays: (64, lab11::HemisphereSampler::Cosine),
        }
    }
}

impl Pipeline {
    /// This pipeline with `code` as the code of the contract `S` (`dyn contracts::lab03::Shadows`,
    /// say), and of every extension point the contract serves ([`contracts::Part`]); [`Self::part`]
    /// gives it back.
    pub fn with_part<S: contracts::Part + ?Sized>(mut self, code: Arc<S>) -> Self {
        self.parts.insert(code);
        self.calls = Calls::of(&self.parts);
        self
    }

    /// This pipeline with `student`'s method `function` of the contract `S` in place of the
    /// one it holds, which answers for the contract's other methods (a check of one exercise).
    pub fn with_student_function<S: contracts::Part + contracts::Mix + ?Sized>(
        &self,
        function: &'static str,
        student: &Arc<S>,
    ) -> Self {
        let base = self.code::<S>();
        self.clone().with_part(S::only(function, student, &base))
    }

    /// This pipeline without code under the type `S`: the integrators go without what it
    /// adds (without `dyn lab03::Shadows`, say, nothing casts shadows).
    pub fn without<S: ?Sized + 'static>(mut self) -> Self {
        self.parts.remove::<S>();
        self.calls = Calls::of(&self.parts);
        self
    }

    /// This pipeline with the store's code changed by `change` (the waiting slots of
    /// [`contracts::LABS`], say).
    pub fn with_parts(mut self, change: impl FnOnce(&mut Parts)) -> Self {
        change(&mut self.parts);
        self.calls = Calls::of(&self.parts);
        self
    }

    /// This pipeline without the code of the course's labs after lab `lab`: what it draws is
    /// what the course has taught by then (a report's figure of an earlier lab's image).
    pub fn through(self, lab: u32) -> Self {
        self.with_parts(|parts| {
            for later in contracts::labs_after(lab) {
                (later.remove)(parts);
            }
        })
    }

    /// The code of the contract `S` that [`Self::with_part`] put in; `None` when there is none.
    pub fn part<S: ?Sized + Send + Sync + 'static>(&self) -> Option<Arc<S>> {
        self.parts.get::<S>()
    }

    /// The code of the contract `S`, which the pipeline must hold (a lab's own contract in
    /// its checks' pipeline); a panic naming the contract when it does not.
    #[track_caller]
    pub fn code<S: ?Sized + Send + Sync + 'static>(&self) -> Arc<S> {
        self.part::<S>().unwrap_or_else(|| {
            panic!(
                "the pipeline holds no code of `{}`",
                std::any::type_name::<S>()
            )
        })
    }

    /// The store of the pipeline's code.
    pub fn parts(&self) -> &Parts {
        &self.parts
    }

    /// The pipeline of the course's labs up to `lab` with no lab's code in it: each lab's
    /// [`contracts::Waiting`] slot, the framework's intersection kernels, and the defaults of
    /// the integrators' settings. The answer key fills it (`reference::pipeline`).
    pub fn waiting(lab: u32) -> Self {
        Pipeline::default()
            .with_parts(|parts| {
                for l in contracts::labs_through(lab) {
                    (l.waiting)(parts);
                }
            })
            .with_framework_intersection()
    }

    /// This pipeline intersecting with the framework's kernels (fast, and equal to lab 02's
    /// answer key up to floating-point rounding) rather than lab 02's code.
    pub fn with_framework_intersection(self) -> Self {
        self.without::<dyn lab02::Intersection>()
    }

    /// The integrator that renders with this pipeline's code.
    pub fn integrator(&self) -> Integrator {
        let c = &self.calls;
        if c.path_tracing.is_some() {
            Integrator::Path
        } else if c.shading.is_none() {
            Integrator::Flat
        } else if c.photon_mapping.is_some() {
            Integrator::PhotonMapped
        } else {
            Integrator::Whitted
        }
    }

    /// This pipeline with the code of every contract [traced](contracts::Traced): while
    /// [`contracts::trace::record`] runs on a thread, each call that thread makes is noted
    /// (the pixel inspector, [`inspect`]); otherwise it renders as this one does, a call
    /// costing one relaxed atomic load more. [`Self::part`] gives the traced code too.
    pub fn traced(&self) -> Pipeline {
        let parts = self.parts.traced();
        Pipeline {
            calls: Calls::of(&parts),
            parts,
            ..self.clone()
        }
    }

    /// Lab 01's camera.
    fn camera(&self) -> &dyn lab01::CameraRays {
        required(&self.calls.camera)
    }

    /// Lab 02's shading.
    fn shading(&self) -> &dyn lab02::Shading {
        required(&self.calls.shading)
    }

    /// Lab 04's reflection and refraction.
    pub(crate) fn reflection(&self) -> &dyn lab04::Reflection {
        required(&self.calls.reflection)
    }

    /// Lab 03's shadows.
    pub(crate) fn shadows(&self) -> &dyn lab03::Shadows {
        required(&self.calls.shadows)
    }

    /// Lab 11's probe mappings and ambient occlusion.
    fn ambient_occlusion(&self) -> &dyn lab11::AmbientOcclusion {
        required(&self.calls.ambient_occlusion)
    }
}

/// A camera prepared for one render: the basis computed once through the pipeline.
#[derive(Clone, Copy, Debug)]
pub struct PreparedCamera {
    /// Eye point.
    pub eye: Vec3,
    /// Camera basis from lab 01.
    pub basis: lab01::CameraBasis,
    /// Focal distance in image-plane heights.
    pub focal_distance: f32,
    /// Image size in pixels.
    pub resolution: UVec2,
}

impl Pipeline {
    /// Prepares the scene camera for an image of `resolution` (Exercise 1.2).
    pub fn prepare_camera(&self, scene: &Scene, resolution: UVec2) -> PreparedCamera {
        let c = &scene.camera;
        PreparedCamera {
            eye: c.eye,
            basis: self.camera().camera_basis(c.eye, c.look_at, c.up),
            focal_distance: c.focal_distance,
            resolution,
        }
    }

    /// The camera ray through raster position `raster` (Exercises 1.1, 1.4, 1.5).
    pub fn camera_ray(&self, camera: &PreparedCamera, raster: Vec2) -> Ray {
        let ip = self.camera().image_plane_coords(raster, camera.resolution);
        let dir = self
            .camera()
            .ray_direction(&camera.basis, camera.focal_distance, ip);
        self.camera().camera_ray(camera.eye, dir)
    }

    /// The closest hit along `ray`, through the lab 02 slot; none along a ray that is not
    /// [traceable](Ray::is_traceable).
    pub fn trace_to_closest(&self, scene: &Scene, ray: &Ray) -> Option<Hit> {
        self.closest_hit(scene, ray, RayKind::Other)
    }

    /// [`Self::trace_to_closest`] for a ray of kind `kind`, which the pixel inspector notes
    /// with its hit while it records.
    #[inline]
    fn closest_hit(&self, scene: &Scene, ray: &Ray, kind: RayKind) -> Option<Hit> {
        let hit = match &self.calls.intersection {
            Some(isect) => scene.trace_to_closest_with(ray, &Lab02Tests(isect.as_ref())),
            None => scene.trace_to_closest(ray),
        };
        if trace::is_recording() {
            note_closest_hit(scene, ray, kind, hit.as_ref());
        }
        hit
    }

    /// Whether anything blocks `ray`, through the lab 02 slot; nothing blocks a ray that is
    /// not [traceable](Ray::is_traceable).
    pub fn trace_to_any(&self, scene: &Scene, ray: &Ray) -> bool {
        self.blocked(scene, ray, RayKind::Other)
    }

    /// [`Self::trace_to_any`] for a ray of kind `kind`, which the pixel inspector notes while
    /// it records.
    #[inline]
    fn blocked(&self, scene: &Scene, ray: &Ray, kind: RayKind) -> bool {
        let blocked = match &self.calls.intersection {
            Some(isect) => scene.trace_to_any_with(ray, &Lab02Tests(isect.as_ref())),
            None => scene.trace_to_any(ray),
        };
        if trace::is_recording() {
            trace::note_ray(kind, ray, RayAnswer::Any(blocked));
        }
        blocked
    }

    /// Radiance arriving along a camera ray (the DTU `RayTracer::compute_pixel` body).
    pub fn radiance(&self, scene: &Scene, ray: &Ray, rng: &mut Rng) -> Vec3 {
        if self.view == View::Shaded && self.calls.path_tracing.is_some() {
            return self.path_traced(scene, ray, rng);
        }
        self.radiance_at(scene, ray, RayKind::Camera, 0, 1.0, rng)
    }

    /// Radiance along `ray` (of kind `kind`) after `depth` bounces, travelling in a medium of
    /// index `ior`; NaN along a ray that is not [traceable](Ray::is_traceable), so that the
    /// render marks the pixel. The pixel inspector notes it with the ray.
    fn radiance_at(
        &self,
        scene: &Scene,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        ior: f32,
        rng: &mut Rng,
    ) -> Vec3 {
        if !trace::is_recording() {
            return self.radiance_along(scene, ray, kind, depth, ior, rng);
        }
        let mark = trace::mark();
        let radiance = self.radiance_along(scene, ray, kind, depth, ior, rng);
        trace::note_radiance(mark, radiance);
        radiance
    }

    /// [`Self::radiance_at`], untraced.
    #[inline]
    fn radiance_along(
        &self,
        scene: &Scene,
        ray: &Ray,
        kind: RayKind,
        depth: u32,
        ior: f32,
        rng: &mut Rng,
    ) -> Vec3 {
        if !ray.is_traceable() {
            return Vec3::NAN;
        }
        let Some(mut hit) = self.closest_hit(scene, ray, kind) else {
            return match &scene.environment {
                Some(env) if self.calls.ambient_occlusion.is_some() => {
                    self.environment_radiance(env, ray.direction)
                }
                _ => scene.background,
            };
        };
        hit.trace_depth = depth;
        hit.ior = ior;
        let material = scene.material(hit.material);
        let diffuse = self.diffuse_colour(scene, &mut hit, material);
        match self.view {
            View::Normals => return 0.5 * (hit.shading_normal + Vec3::ONE),
            View::BaseColour => return diffuse,
            View::Shaded | View::Caustics if self.calls.shading.is_none() => return diffuse,
            View::Shaded | View::Caustics => {}
        }
        let emitted = material.emission;
        if self.calls.reflection.is_none() {
            return emitted + self.shade_lambertian(scene, &hit, diffuse, rng);
        }
        match material.illum {
            IllumModel::Mirror => emitted + self.trace_reflected(scene, ray, &hit, rng),
            IllumModel::Transparent
            | IllumModel::AbsorbingVolume
            | IllumModel::Glossy
            | IllumModel::GlossyVolume
                if self.calls.fresnel.is_some() =>
            {
                emitted + self.shade_dielectric(scene, ray, &hit, material, rng)
            }
            IllumModel::Transparent | IllumModel::AbsorbingVolume => {
                emitted + self.trace_refracted(scene, ray, &hit, material.ior, false, rng)
            }
            IllumModel::Glossy | IllumModel::GlossyVolume => {
                // The worksheet's glossy shader: a little Phong and mirror, mostly refraction
                // (lab 10 replaces the weights by the Fresnel reflectance).
                emitted
                    + 0.1 * self.shade_phong(scene, ray, &hit, diffuse, rng)
                    + 0.1 * self.trace_reflected(scene, ray, &hit, rng)
                    + 0.9 * self.trace_refracted(scene, ray, &hit, material.ior, false, rng)
            }
            IllumModel::Phong => {
                emitted
                    + self.direct(|| self.shade_phong(scene, ray, &hit, diffuse, rng))
                    + self.caustic(&hit, diffuse)
            }
            IllumModel::Lambertian => {
                let ambient = match &scene.environment {
                    Some(env) if self.calls.ambient_occlusion.is_some() => {
                        self.direct(|| self.shade_ambient(scene, env, &hit, diffuse, rng))
                    }
                    _ => Vec3::ZERO,
                };
                emitted
                    + self.direct(|| self.shade_lambertian(scene, &hit, diffuse, rng))
                    + ambient
                    + self.caustic(&hit, diffuse)
            }
        }
    }

    /// The probe's radiance from the direction `direction` (unit or not), through lab 11's
    /// mapping of directions to texture coordinates (Exercises 11.5, 11.7).
    pub fn environment_radiance(&self, env: &EnvironmentMap, direction: Vec3) -> Vec3 {
        let d = direction.normalize();
        let uv = match env.mapping {
            ProbeMapping::Angular => self.ambient_occlusion().angular_map_uv(d),
            ProbeMapping::Latlong => self.ambient_occlusion().latlong_uv(d),
        };
        env.texel(uv)
    }

    /// The ambient-occlusion shader at a Lambertian hit lit by the probe (Exercises
    /// 11.1–11.3, 11.9): the accessibility and bent normal from `occlusion_rays` rays traced
    /// with `trace_to_any`, the probe looked up along the bent normal.
    fn shade_ambient(
        &self,
        scene: &Scene,
        env: &EnvironmentMap,
        hit: &Hit,
        diffuse: Vec3,
        rng: &mut Rng,
    ) -> Vec3 {
        let ao = self.ambient_occlusion();
        let n = hit.shading_normal;
        let (rays, sampler) = self.occlusion_rays;
        let draw = |rng: &mut Rng| match sampler {
            lab11::HemisphereSampler::Rejection => ao.sample_hemisphere_rejection(n, rng),
            lab11::HemisphereSampler::Cosine => ao.sample_hemisphere_cosine(n, rng),
        };
        let occluded = |ray: &Ray| self.blocked(scene, ray, RayKind::Occlusion);
        let occlusion = ao.ambient_occlusion(hit.position, n, rays, &draw, &occluded, rng);
        let light = self.environment_radiance(env, occlusion.bent_normal);
        ao.shade_ambient_occlusion(diffuse, &occlusion, light)
    }

    /// The direct lighting `shade` computes, or none in the caustics-only view.
    fn direct(&self, shade: impl FnOnce() -> Vec3) -> Vec3 {
        if self.view == View::Caustics {
            Vec3::ZERO
        } else {
            shade()
        }
    }

    /// The caustic radiance at a diffuse hit (from lab 8 on, with a photon map): the photons
    /// nearest to it through the lab 08 slot's estimate (Exercise 8.4).
    fn caustic(&self, hit: &Hit, diffuse: Vec3) -> Vec3 {
        match &self.caustics {
            Some(map) => {
                let (k, r) = (self.photons.k as usize, self.photons.max_radius);
                let nearby = map.nearest(hit.position, k, r);
                required(&self.calls.photon_mapping).caustic_radiance(
                    diffuse,
                    hit.shading_normal,
                    &nearby,
                    k,
                    r,
                )
            }
            None => Vec3::ZERO,
        }
    }

    /// The reflectance of a dielectric surface for light arriving at `cos_i` (the cosine of
    /// the angle of incidence) from a medium of index `eta_i` into one of `eta_t`: Schlick's
    /// approximation below lab 10 (1 under total internal reflection), lab 10's Fresnel
    /// reflectance from lab 10 on. The photon tracer's roulette at glass takes it (lab 08).
    pub(crate) fn dielectric_reflectance(&self, cos_i: f32, eta_i: f32, eta_t: f32) -> f32 {
        match &self.calls.fresnel {
            Some(fresnel) => fresnel.fresnel_reflectance(cos_i, eta_i, eta_t),
            None => schlick_reflectance(cos_i, eta_i, eta_t),
        }
    }

    /// Radiance along the mirror direction (black past the depth limit).
    fn trace_reflected(&self, scene: &Scene, ray: &Ray, hit: &Hit, rng: &mut Rng) -> Vec3 {
        if hit.trace_depth >= self.max_depth {
            return Vec3::ZERO;
        }
        let reflected = self.reflection().reflected_ray(ray, hit);
        let depth = hit.trace_depth + 1;
        self.radiance_at(scene, &reflected, RayKind::Reflected, depth, hit.ior, rng)
    }

    /// Lab 10's shaders of a dielectric (DTU `Transparent`, `Glossy`, `Volume` and
    /// `GlossyVolume` with Fresnel): the reflected and refracted radiance weighted by the
    /// Fresnel reflectance, plus the Phong highlight (the specular lobe alone) on a glossy
    /// surface, times the transmittance of the medium when the ray has crossed a volume.
    fn shade_dielectric(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: &Hit,
        material: &Material,
        rng: &mut Rng,
    ) -> Vec3 {
        let mut radiance = self.trace_refracted(scene, ray, hit, material.ior, true, rng);
        if matches!(
            material.illum,
            IllumModel::Glossy | IllumModel::GlossyVolume
        ) {
            let lights = self.light_samples(scene, hit, rng);
            radiance += self.reflection().shade_phong(
                Vec3::ZERO,
                material.specular,
                material.shininess,
                hit.shading_normal,
                -ray.direction,
                &lights,
            );
        }
        radiance * self.medium_transmittance(ray.direction, hit, material)
    }

    /// Radiance through a dielectric interface: along the refracted ray lab 04 finds or, when
    /// `fresnel`, `R` times the radiance along the reflected ray plus `1 − R` times that, `R`
    /// the Fresnel reflectance (lab 10); the reflected radiance alone under total internal
    /// reflection (black past the depth limit).
    fn trace_refracted(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: &Hit,
        material_ior: f32,
        fresnel: bool,
        rng: &mut Rng,
    ) -> Vec3 {
        if hit.trace_depth >= self.max_depth {
            return Vec3::ZERO;
        }
        let Some((refracted, ior)) = self.reflection().refracted_ray(ray, hit, material_ior) else {
            return self.trace_reflected(scene, ray, hit, rng);
        };
        let depth = hit.trace_depth + 1;
        if !fresnel {
            return self.radiance_at(scene, &refracted, RayKind::Refracted, depth, ior, rng);
        }
        let side = self
            .reflection()
            .interface(ray.direction, hit, material_ior);
        let cos_i = (-ray.direction.dot(side.normal)).clamp(0.0, 1.0);
        let r = required(&self.calls.fresnel).fresnel_reflectance(
            cos_i,
            side.eta_incident,
            side.eta_transmitted,
        );
        // A NaN reflectance reaches the pixel (`!=` is true for NaN).
        let mut radiance = Vec3::ZERO;
        if r != 0.0 {
            radiance += r * self.trace_reflected(scene, ray, hit, rng);
        }
        if r != 1.0 {
            radiance += (1.0 - r)
                * self.radiance_at(scene, &refracted, RayKind::Refracted, depth, ior, rng);
        }
        radiance
    }

    /// The transmittance of the medium a ray along `direction` has crossed to reach `hit` on
    /// a surface of `material` (lab 10): the Bouguer–Lambert–Beer attenuation over
    /// `hit.distance` when the material is an absorbing volume (`illum 11` or 12) and the ray
    /// leaves it (`direction · shading normal > 0`: it travelled inside), one otherwise and
    /// below lab 10. The shaders and photon tracing call it at every hit of a dielectric.
    pub fn medium_transmittance(&self, direction: Vec3, hit: &Hit, material: &Material) -> Vec3 {
        let volume = matches!(
            material.illum,
            IllumModel::AbsorbingVolume | IllumModel::GlossyVolume
        );
        match &self.calls.fresnel {
            Some(fresnel) if volume && direction.dot(hit.shading_normal) > 0.0 => {
                fresnel.transmittance(hit.distance, material)
            }
            _ => Vec3::ONE,
        }
    }

    /// The diffuse reflectance at a hit: the material's, times its diffuse texture at the hit's
    /// texture coordinates from lab 09 on (which it stores in `hit.texcoord`); projector,
    /// corresponder and lookup all through the lab 09 slot.
    fn diffuse_colour(&self, scene: &Scene, hit: &mut Hit, material: &Material) -> Vec3 {
        let Some(texture) = material.diffuse_texture.as_deref() else {
            return material.diffuse;
        };
        let Some(t) = self.calls.texturing.as_deref() else {
            return material.diffuse;
        };
        hit.texcoord = match hit.surface {
            HitSurface::Unknown => hit.texcoord,
            HitSurface::Plane(i) => t.plane_texcoord(&scene.planes[i as usize], hit.position),
            HitSurface::Sphere(i) => t.sphere_texcoord(&scene.spheres[i as usize], hit.position),
            HitSurface::Triangle { face, barycentrics } => {
                let mesh = &scene.mesh;
                if mesh.texcoords.is_empty() {
                    Vec2::ZERO
                } else {
                    let uvs = mesh.faces[face as usize].map(|v| mesh.texcoords[v as usize]);
                    t.triangle_texcoord(uvs, barycentrics)
                }
            }
        };
        if trace::is_recording() {
            trace::note_texcoord(hit.texcoord);
        }
        let mode = self.texture_addressing;
        let address = |c: f32| t.address(c, mode);
        let texel = match self.texture_filter {
            TextureFilter::Nearest => t.sample_nearest(texture, hit.texcoord, &address),
            TextureFilter::Bilinear => t.sample_bilinear(texture, hit.texcoord, &address),
        };
        material.diffuse * texel
    }

    /// Lambertian reflection of every light at a hit (labs 02 and 03), of reflectance
    /// `diffuse`.
    fn shade_lambertian(&self, scene: &Scene, hit: &Hit, diffuse: Vec3, rng: &mut Rng) -> Vec3 {
        let lights = self.light_samples(scene, hit, rng);
        self.shading()
            .shade_lambertian(diffuse, hit.shading_normal, &lights)
    }

    /// Phong reflection of every light at a hit (lab 04), of diffuse reflectance `diffuse`.
    fn shade_phong(
        &self,
        scene: &Scene,
        ray: &Ray,
        hit: &Hit,
        diffuse: Vec3,
        rng: &mut Rng,
    ) -> Vec3 {
        let lights = self.light_samples(scene, hit, rng);
        let m = scene.material(hit.material);
        self.reflection().shade_phong(
            diffuse,
            m.specular,
            m.shininess,
            hit.shading_normal,
            -ray.direction,
            &lights,
        )
    }

    /// The light arriving at a hit: one sample per point and directional light, and (from
    /// lab 03 on) `n × n` stratified samples per area light; from lab 03 on, samples whose
    /// shadow ray is blocked are dropped.
    pub fn light_samples(
        &self,
        scene: &Scene,
        hit: &Hit,
        rng: &mut Rng,
    ) -> Vec<lab02::LightSample> {
        let shadows = self.calls.shadows.as_deref();
        let mut samples = Vec::new();
        for light in &scene.lights {
            match light {
                Light::Point(p) => samples.push(self.shading().sample_point_light(p, hit.position)),
                Light::Directional(d) => {
                    samples.push(self.shading().sample_directional_light(d, hit.position))
                }
                Light::Area(area) if shadows.is_some() => {
                    self.sample_area_light(scene, area, hit, rng, &mut samples)
                }
                Light::Area(_) => {}
            }
        }
        if let Some(shadows) = shadows {
            samples.retain(|s| {
                let shadow_ray = shadows.shadow_ray(hit.position, s);
                !self.blocked(scene, &shadow_ray, RayKind::Shadow)
            });
        }
        samples
    }

    /// Appends the `n × n` stratified samples of an area light (Exercises 3.2–3.4), each
    /// carrying `1/n²` of the estimate.
    fn sample_area_light(
        &self,
        scene: &Scene,
        area: &AreaLight,
        hit: &Hit,
        rng: &mut Rng,
        out: &mut Vec<lab02::LightSample>,
    ) {
        let n = self.area_light_samples.max(1);
        let weight = 1.0 / (n * n) as f32;
        let pdf_area = 1.0 / area.area;
        let shadows = required(&self.calls.shadows);
        for u in shadows.stratified_samples(n, rng) {
            let (i, ux) = area.pick_face(u.x);
            let face = area.faces[i] as usize;
            let triangle = scene.mesh.triangle(face);
            let point = shadows.sample_triangle(triangle, Vec2::new(ux, u.y));
            let normal = scene.mesh.face_normal(face);
            let emission = scene.material(scene.mesh.face_materials[face]).emission;
            let mut sample =
                shadows.area_light_sample(hit.position, point, normal, emission, pdf_area);
            sample.radiance *= weight;
            out.push(sample);
        }
    }
}

/// Notes a closest-hit query for the pixel inspector: the ray, and the surface it found.
#[cold]
#[inline(never)]
fn note_closest_hit(scene: &Scene, ray: &Ray, kind: RayKind, hit: Option<&Hit>) {
    let hit = hit.map(|hit| RayHit {
        distance: hit.distance,
        position: hit.position,
        geometric_normal: hit.geometric_normal,
        shading_normal: hit.shading_normal,
        material: scene.material(hit.material).name.clone(),
        surface: hit.surface,
        texcoord: None,
    });
    trace::note_ray(kind, ray, RayAnswer::Closest(hit));
}

/// A lab 02 [`Intersection`](lab02::Intersection) as the scene's primitive tests: the adapter
/// through which the scene queries reach a student's (or the reference's) intersection code.
struct Lab02Tests<'a>(&'a dyn lab02::Intersection);

impl PrimitiveTests for Lab02Tests<'_> {
    fn plane(&self, ray: &Ray, plane: &Plane) -> Option<PrimitiveHit> {
        self.0
            .intersect_plane(ray, plane)
            .map(|h| surface_hit(h.distance, h.normal))
    }

    fn triangle(&self, ray: &Ray, &[v0, v1, v2]: &[Vec3; 3]) -> Option<PrimitiveHit> {
        self.0
            .intersect_triangle(ray, v0, v1, v2)
            .map(|h| PrimitiveHit {
                t: h.distance,
                normal: h.normal,
                barycentrics: Vec2::new(h.beta, h.gamma),
            })
    }

    fn sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<PrimitiveHit> {
        self.0
            .intersect_sphere(ray, sphere)
            .map(|h| surface_hit(h.distance, h.normal))
    }
}

/// The primitive hit of a plane or sphere (no barycentrics).
fn surface_hit(t: f32, normal: Vec3) -> PrimitiveHit {
    PrimitiveHit {
        t,
        normal,
        barycentrics: Vec2::ZERO,
    }
}

/// Schlick's approximation of the reflectance of a dielectric surface, 1 under total internal
/// reflection (see [`Pipeline::dielectric_reflectance`]).
fn schlick_reflectance(cos_i: f32, eta_i: f32, eta_t: f32) -> f32 {
    let cos_i = cos_i.abs().min(1.0);
    let r0 = ((eta_i - eta_t) / (eta_i + eta_t)).powi(2);
    let cos = if eta_i > eta_t {
        let sin2_t = (eta_i / eta_t).powi(2) * (1.0 - cos_i * cos_i);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        (1.0 - sin2_t).sqrt()
    } else {
        cos_i
    };
    (r0 + (1.0 - r0) * (1.0 - cos).powi(5)).clamp(0.0, 1.0)
}

#[cfg(test)]
mod tests {
    use super::schlick_reflectance;

    #[test]
    fn schlick_reflectance_of_glass() {
        // Normal incidence: ((n₁ − n₂)/(n₁ + n₂))² = 0.04 from either side.
        assert!((schlick_reflectance(1.0, 1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((schlick_reflectance(1.0, 1.5, 1.0) - 0.04).abs() < 1e-6);
        // Grazing incidence reflects everything.
        assert!((schlick_reflectance(0.0, 1.0, 1.5) - 1.0).abs() < 1e-6);
        // Beyond the critical angle inside glass (sin θ > 1/1.5): total internal reflection.
        assert_eq!(schlick_reflectance(0.7, 1.5, 1.0), 1.0);
        // Rising with the angle of incidence.
        let mut last = 0.0;
        for i in (0..=100).rev() {
            let r = schlick_reflectance(i as f32 / 100.0, 1.0, 1.5);
            assert!(r >= last && (0.0..=1.0).contains(&r), "{r} after {last}");
            last = r;
        }
    }
}
