//! Lab 11's exercises and their checks.
//!
//! - The samplers (11.1, 11.2) are judged by their distribution: unit directions on the
//!   normal's side whose reported `pdf` is the density, a generator that advances, and a χ²
//!   test of the directions against the density about several normals
//!   ([`grading::chi2`]: cells pooled to an expected count of at least 5, significance
//!   0.01 with Šidák's correction over the normals).
//! - Ambient occlusion (11.3) with samplers of the check's own (not the exercises'): the rays
//!   it traces, exact answers where every ray is free or blocked, and the closed forms of an
//!   open plane (1), a corner by an infinite wall (½, and its bent normal) and a groove
//!   between two long walls, by a Z-test at the same significance; the key where present.
//! - The RGBE conversion (11.4): black at exponent 0, a doubling per exponent step, one
//!   channel per mantissa, agreement with the `image` crate's Radiance decoder on the lab's
//!   probe file within one step of the mantissa, the key and the golden cases.
//! - The probe mappings (11.5–11.8): ranges, unit directions, the key and the golden cases,
//!   and the round trip through the *recorded* inverse (each mapping against the golden
//!   cases of its inverse exercise), so no exercise needs another's code.
//! - The shader (11.9): linearity, the white furnace (a white surface that sees the whole of
//!   a uniform environment reflects its radiance), the key and the golden cases.

use std::cell::{Cell, RefCell};
use std::f64::consts::PI;
use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab11::{AmbientOcclusion, HemisphereSample, Occlusion};
use grading::chi2::SphereGrid;
use grading::stats::{normal_two_sided_quantile, sidak};
use grading::strategies::unit_vector;
use grading::{Exercise, GoldenFile, LabContext, for_all};
use raylab_core::film::RgbeImage;
use raylab_core::math::{Onb, RAY_EPSILON, Ray};
use raylab_core::sampling::Rng;
use raylab_core::scene::TextureFile;
use raylab_core::scene::{
    CameraSetup, Material, MaterialId, Mesh, Plane, Scene, SceneDescription, Texture,
};

/// Golden file of Exercise 11.4.
pub const GOLDEN_RGBE: &str = "rgbe_to_rgb.json";
/// Golden file of Exercise 11.5.
pub const GOLDEN_ANGULAR_UV: &str = "angular_map_uv.json";
/// Golden file of Exercise 11.6.
pub const GOLDEN_ANGULAR_DIRECTION: &str = "angular_map_direction.json";
/// Golden file of Exercise 11.7.
pub const GOLDEN_LATLONG_UV: &str = "latlong_uv.json";
/// Golden file of Exercise 11.8.
pub const GOLDEN_LATLONG_DIRECTION: &str = "latlong_direction.json";
/// Golden file of Exercise 11.9.
pub const GOLDEN_SHADE: &str = "shade_ambient_occlusion.json";
/// The lab's Radiance probe (an angular map of the procedural sky), in `probes/`.
pub const SKY_PROBE: &str = "sky-angular.hdr";
/// The lab's OpenEXR probe (a latitude–longitude map of the procedural studio), in `probes/`.
pub const STUDIO_PROBE: &str = "studio-latlong.exr";

/// Family-wise significance of the statistical checks (the χ² tests of 11.1 and 11.2, the
/// Z-tests of 11.3), split over their cases by Šidák's correction.
pub const SIGNIFICANCE: f64 = 0.01;
/// Directions per χ² test.
pub const CHI2_SAMPLES: usize = 40_000;
/// The χ² grid: 10 cells of `cos θ` over the hemisphere (20 over the sphere), 24 of `φ`.
pub const CHI2_GRID: SphereGrid = SphereGrid {
    cos_theta_cells: 20,
    phi_cells: 24,
};
/// Tolerance of texture coordinates against the key and golden cases.
pub const UV_TOL: f32 = 2e-4;
/// Tolerance, radians, of a direction against the key and golden cases.
pub const ANGLE_TOL: f32 = 1e-3;
/// Random inputs per property.
const CASES: u32 = 256;

/// This lab.
pub const LAB: course::LabId = course::LabId::of(11);

/// The exercises of lab 11 (`labs/lab11/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn AmbientOcclusion>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_11_1,
            exercise_11_2,
            exercise_11_3,
            exercise_11_4,
            exercise_11_5,
            exercise_11_6,
            exercise_11_7,
            exercise_11_8,
            exercise_11_9
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Shared pieces

fn key(ctx: &LabContext) -> Option<Arc<dyn AmbientOcclusion>> {
    ctx.key()
        .map(|p| p.code::<dyn contracts::lab11::AmbientOcclusion>())
}

fn load<I, O>(ctx: &LabContext, name: &str) -> Result<GoldenFile<I, O>, String>
where
    I: serde::Serialize + serde::de::DeserializeOwned,
    O: serde::Serialize + serde::de::DeserializeOwned,
{
    ctx.golden(name)
}

/// The normals the samplers and ambient occlusion are checked about: the axes, a grazing
/// tilt off one, and general directions.
pub fn test_normals() -> Vec<Vec3> {
    vec![
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::Y,
        Vec3::NEG_X,
        Vec3::new(1e-4, -1.0, 2e-4).normalize(),
        Vec3::new(0.3, -0.5, 0.8).normalize(),
        Vec3::new(-0.7, 0.2, -0.1).normalize(),
    ]
}

/// The angle in radians between two directions (`π` when either is not finite).
fn angle(a: Vec3, b: Vec3) -> f32 {
    let (a, b) = (a.normalize(), b.normalize());
    if !(a.is_finite() && b.is_finite()) {
        return std::f32::consts::PI;
    }
    // atan2 of |a × b| and a · b is accurate at small angles.
    a.cross(b).length().atan2(a.dot(b))
}

/// A unit direction, or the reason it is not one.
fn check_unit(what: &str, d: Vec3) -> Result<(), String> {
    if !d.is_finite() || (d.length() - 1.0).abs() > 1e-4 {
        return Err(format!(
            "{what} is {d} (length {}); expected a unit vector",
            d.length()
        ));
    }
    Ok(())
}

/// Directions at given angles as unit vectors: `θ` from `axis`, `φ` about it.
fn spherical(axis: Vec3, theta: f64, phi: f64) -> Vec3 {
    let onb = Onb::from_w(axis);
    let (s, c) = theta.sin_cos();
    onb.to_world(Vec3::new(
        (s * phi.cos()) as f32,
        (s * phi.sin()) as f32,
        c as f32,
    ))
    .normalize()
}

/// Directions for the mappings: random ones, the axes and near-axis ones (the poles of the
/// maps, and the seam of the latitude–longitude map at +z).
pub fn direction_strategy() -> impl Strategy<Value = Vec3> + Clone {
    prop_oneof![
        4 => unit_vector(),
        1 => prop::sample::select(vec![
            Vec3::X,
            Vec3::NEG_X,
            Vec3::Y,
            Vec3::NEG_Y,
            Vec3::Z,
            Vec3::NEG_Z,
        ]),
        1 => (prop::sample::select(vec![Vec3::Y, Vec3::NEG_Y, Vec3::NEG_Z, Vec3::Z]), 1e-3..0.05f64, 0.0..std::f64::consts::TAU)
            .prop_map(|(axis, theta, phi)| spherical(axis, theta, phi)),
    ]
}

/// Texture coordinates for the inverse mappings, over and just outside `[0, 1]²`.
pub fn uv_strategy() -> impl Strategy<Value = Vec2> + Clone {
    prop_oneof![
        4 => (0.0..1.0f32, 0.0..1.0f32).prop_map(|(u, v)| Vec2::new(u, v)),
        1 => prop::sample::select(vec![
            Vec2::new(0.5, 0.5),
            Vec2::new(0.0, 0.5),
            Vec2::new(1.0, 0.5),
            Vec2::new(0.5, 0.0),
            Vec2::new(0.5, 1.0),
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.25, 0.75),
        ]),
    ]
}

/// RGBE pixels: random ones and the edges of the exponent range.
pub fn rgbe_strategy() -> impl Strategy<Value = [u8; 4]> + Clone {
    prop_oneof![
        4 => any::<[u8; 4]>(),
        1 => (any::<[u8; 3]>(), prop::sample::select(vec![0u8, 1, 127, 128, 129, 200, 254, 255]))
            .prop_map(|(m, e)| [m[0], m[1], m[2], e]),
    ]
}

// ---------------------------------------------------------------------------------------------
// 11.1, 11.2: the samplers

/// Which sampler a check is about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Sampler {
    Rejection,
    Cosine,
}

impl Sampler {
    fn draw(self, s: &dyn AmbientOcclusion, n: Vec3, rng: &mut Rng) -> HemisphereSample {
        match self {
            Sampler::Rejection => s.sample_hemisphere_rejection(n, rng),
            Sampler::Cosine => s.sample_hemisphere_cosine(n, rng),
        }
    }

    fn call(self) -> &'static str {
        match self {
            Sampler::Rejection => "sample_hemisphere_rejection",
            Sampler::Cosine => "sample_hemisphere_cosine",
        }
    }

    /// The density the contract states, per steradian, of the local direction `d` (z the
    /// normal).
    fn density(self, d: Vec3) -> f64 {
        if d.z < 0.0 {
            return 0.0;
        }
        match self {
            Sampler::Rejection => 1.0 / (2.0 * PI),
            Sampler::Cosine => d.z as f64 / PI,
        }
    }

    fn density_name(self) -> &'static str {
        match self {
            Sampler::Rejection => "1/(2π)",
            Sampler::Cosine => "cos θ/π",
        }
    }
}

fn check_sampler(s: &dyn AmbientOcclusion, sampler: Sampler) -> Result<(), String> {
    let call = sampler.call();
    let normals = test_normals();
    let alpha = sidak(SIGNIFICANCE, normals.len());
    for (case, &n) in normals.iter().enumerate() {
        let mut rng = Rng::new(1100 + case as u64, 11);
        // The generator is advanced and nothing else is random.
        let mut twin = rng.clone();
        let first = sampler.draw(s, n, &mut rng);
        let again = sampler.draw(s, n, &mut twin);
        if first != again {
            return Err(format!(
                "{call}(normal = {n}) returned {first:?} and then {again:?} from generators in the same state: draw every random number from `rng`"
            ));
        }
        let second = sampler.draw(s, n, &mut rng);
        if second == first {
            return Err(format!(
                "{call}(normal = {n}) returned {first:?} twice in a row: advance `rng` (draw new numbers from it every call)"
            ));
        }
        let onb = Onb::from_w(n);
        let mut local = Vec::with_capacity(CHI2_SAMPLES);
        for _ in 0..CHI2_SAMPLES {
            let HemisphereSample { direction, pdf } = sampler.draw(s, n, &mut rng);
            let what = format!("the direction of {call}(normal = {n})");
            check_unit(&what, direction)?;
            let cos = direction.dot(n);
            if cos < -1e-5 {
                return Err(format!(
                    "{what} is {direction}, below the surface (cos θ = {cos}): return directions of the hemisphere about the normal only"
                ));
            }
            let l = onb.to_local(direction);
            let expected = sampler.density(Vec3::new(l.x, l.y, l.z.max(0.0))) as f32;
            let close = (pdf - expected).abs() <= 1e-3 * expected + 1e-5;
            if !close {
                return Err(format!(
                    "{call}(normal = {n}) returned the direction {direction} (cos θ = {cos}) with pdf = {pdf}; its density is {} = {expected}",
                    sampler.density_name()
                ));
            }
            local.push(l);
        }
        let outcome = CHI2_GRID
            .chi_square(&local, &|d| sampler.density(d))
            .map_err(|e| format!("{call}(normal = {n}): {e}"))?;
        if outcome.p_value < alpha {
            let (counts, _) = CHI2_GRID.histogram(local.iter().copied());
            let upper = CHI2_GRID.cos_theta_cells / 2;
            let rows: Vec<String> = (upper..CHI2_GRID.cos_theta_cells)
                .map(|i| {
                    let m = CHI2_GRID.phi_cells as usize;
                    let start = i as usize * m;
                    let got: u64 = counts[start..start + m].iter().sum();
                    let z0 = -1.0 + i as f64 * 2.0 / CHI2_GRID.cos_theta_cells as f64;
                    let z1 = z0 + 2.0 / CHI2_GRID.cos_theta_cells as f64;
                    let exp: f64 = CHI2_GRID.expected(&|d| sampler.density(d), local.len() as u64)
                        [start..start + m]
                        .iter()
                        .sum();
                    format!("cos θ ∈ [{z0:.1}, {z1:.1}): {got} (expected {exp:.0})")
                })
                .collect();
            return Err(format!(
                "{call}(normal = {n}): {CHI2_SAMPLES} directions do not follow the density {}: χ² = {:.1} with {} degrees of freedom, p = {:.2e} < {alpha:.2e} (significance {SIGNIFICANCE} over {} normals, Šidák). Directions per band of cos θ: {}",
                sampler.density_name(),
                outcome.statistic,
                outcome.degrees_of_freedom,
                outcome.p_value,
                normals.len(),
                rows.join("; ")
            ));
        }
    }
    Ok(())
}

fn exercise_11_1(s: &Arc<dyn AmbientOcclusion>, _ctx: &LabContext) -> Result<(), String> {
    check_sampler(s.as_ref(), Sampler::Rejection)
}

fn exercise_11_2(s: &Arc<dyn AmbientOcclusion>, _ctx: &LabContext) -> Result<(), String> {
    check_sampler(s.as_ref(), Sampler::Cosine)
}

// ---------------------------------------------------------------------------------------------
// 11.3: ambient occlusion

/// The check's own sampler: `θ` and `φ` uniform in `[0, π/2) × [0, 2π)`, whose density per
/// steradian is `1/(π² sin θ)` — neither exercise's, so that 11.3 is judged alone, and a
/// `pdf` the estimate must use.
pub fn equal_angle_sampler(normal: Vec3) -> impl Fn(&mut Rng) -> HemisphereSample {
    move |rng: &mut Rng| {
        let u = rng.next_vec2().as_dvec2();
        let theta = (u.x * 0.5 * PI).max(1e-6);
        let direction = spherical(normal, theta, 2.0 * PI * u.y);
        HemisphereSample {
            direction,
            pdf: (1.0 / (PI * PI * theta.sin())) as f32,
        }
    }
}

/// The check's lopsided sampler: `cos θ` uniform in `(0, 1]` and `φ` three times as likely on
/// the half of the hemisphere towards the first tangent of `Onb::from_w(normal)` (where the
/// corner's wall stands) as on the other, density per steradian `3/(4π)` there and `1/(4π)`
/// elsewhere. Under it the fraction of free rays and their plain mean direction are far from
/// the accessibility and the bent normal, so the weight `cos θ/(π·pdf)` must be applied.
pub fn lopsided_sampler(normal: Vec3) -> impl Fn(&mut Rng) -> HemisphereSample {
    move |rng: &mut Rng| {
        let u = rng.next_vec2().as_dvec2();
        let theta = (1.0 - u.x).acos();
        let (phi, pdf) = if u.y < 0.75 {
            (PI * (u.y / 0.75 - 0.5), 0.75 / PI)
        } else {
            (PI * ((u.y - 0.75) / 0.25 + 0.5), 0.25 / PI)
        };
        HemisphereSample {
            direction: spherical(normal, theta, phi),
            pdf: pdf as f32,
        }
    }
}

/// A sampler of the check's own for a normal, with what it is for messages.
pub type CheckSampler = (
    fn(Vec3) -> Box<dyn Fn(&mut Rng) -> HemisphereSample>,
    &'static str,
);

/// The samplers the closed forms of 11.3 are estimated with.
pub fn check_samplers() -> [CheckSampler; 2] {
    [
        (
            |n| Box::new(equal_angle_sampler(n)),
            "the check's sampler draws θ and φ uniformly, pdf = 1/(π² sin θ)",
        ),
        (
            |n| Box::new(lopsided_sampler(n)),
            "the check's sampler draws cos θ uniformly and φ three times as often on the side of the wall (or the first tangent) as on the other, pdf = 3/(4π) there and 1/(4π) elsewhere",
        ),
    ]
}

/// A configuration of 11.3: a floor and what stands on it, with the exact accessibility at a
/// point of the floor.
#[derive(Clone, Debug)]
pub struct OcclusionCase {
    /// What it is, for messages.
    pub name: String,
    /// The scene: the floor plane and the occluders.
    pub scene: Arc<Scene>,
    /// The point, on the floor.
    pub position: Vec3,
    /// The floor's normal.
    pub normal: Vec3,
    /// The exact accessibility.
    pub accessibility: f64,
    /// The exact bent normal, where the check knows it.
    pub bent_normal: Option<Vec3>,
    /// The size of the configuration (1 for walls about a unit away).
    pub scale: f32,
}

impl OcclusionCase {
    /// Whether `ray` is blocked in the case's scene, the ray's `tmin` measured in units of the
    /// configuration (`tmin · scale`): the contract's offset `RAY_EPSILON` is a fixed world
    /// distance, which at scale 10⁻⁴ would pass over the walls themselves, so the check's
    /// scenes take it as relative, as a renderer offsetting by the scene's size would.
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.scene.trace_to_any(&Ray {
            tmin: ray.tmin * self.scale,
            ..*ray
        })
    }
}

fn occlusion_scene(planes: Vec<Plane>, mesh: Mesh) -> Arc<Scene> {
    Arc::new(
        Scene::new(SceneDescription {
            name: "lab 11 check scene".into(),
            camera: Some(CameraSetup {
                eye: Vec3::new(0.0, 1.0, 3.0),
                look_at: Vec3::ZERO,
                up: Vec3::Y,
                focal_distance: 1.0,
            }),
            materials: vec![Material::lambertian("grey", Vec3::splat(0.5))],
            planes,
            mesh,
            ..SceneDescription::default()
        })
        .expect("the check scenes are valid"),
    )
}

/// The closed form of the accessibility at a point of a floor between two infinitely long
/// walls of heights `h1`, `h2` at distances `d1`, `d2` (either may be absent): one minus the
/// form factors of the walls, `½(1 − d/√(d² + h²))` each (a point to a perpendicular strip).
fn groove_accessibility(walls: &[(f64, f64)]) -> f64 {
    1.0 - walls
        .iter()
        .map(|&(d, h)| 0.5 * (1.0 - d / (d * d + h * h).sqrt()))
        .sum::<f64>()
}

/// The configurations of 11.3, at scales from 10⁻⁴ to 10³ and far from the origin: an open
/// plane, a corner by an infinite wall, and grooves between long walls.
pub fn occlusion_cases() -> Vec<OcclusionCase> {
    let mut cases = Vec::new();
    // Floors along the axes (the position on them exact in f32, so that the floor never
    // occludes its own rays at any offset; at 10⁻² three units from the origin, 300 times the
    // configuration's size) and a tilted one.
    let (along_y, along_z) = (
        (Vec3::Y, Vec3::new(0.3, 0.0, -0.2)),
        (Vec3::NEG_Z, Vec3::new(-2.0, 3.0, 1.0)),
    );
    let tilted = (
        Vec3::new(0.3, 0.9, -0.2).normalize(),
        Vec3::new(0.5, -0.3, 0.2),
    );
    let m = MaterialId(0);
    for (scale, (n, origin)) in [
        (1e-4f32, along_y),
        (1e-2, along_z),
        (1.0, tilted),
        (1e3, along_z),
    ] {
        let onb = Onb::from_w(n);
        let (t, b) = (onb.u, onb.v);
        let at = |x: f32, y: f32, z: f32| origin + scale * (x * t + y * b + z * n);
        let floor = Plane::new(origin, n, m);
        let position = at(0.3, -0.2, 0.0);
        cases.push(OcclusionCase {
            name: format!("an open plane (scale {scale:e})"),
            scene: occlusion_scene(vec![floor], Mesh::default()),
            position,
            normal: n,
            accessibility: 1.0,
            bent_normal: Some(n),
            scale,
        });
        // An infinite wall 0.7 units along t, facing back.
        let wall = Plane::new(at(1.0, 0.0, 0.0), -t, m);
        cases.push(OcclusionCase {
            name: format!("a corner by an infinite wall (scale {scale:e})"),
            scene: occlusion_scene(vec![floor, wall], Mesh::default()),
            position,
            normal: n,
            accessibility: 0.5,
            // ∫ ω cos θ dω over the half of the hemisphere away from the wall: (π/3) n − (2/3) t.
            bent_normal: Some((std::f32::consts::PI / 3.0 * n - 2.0 / 3.0 * t).normalize()),
            scale,
        });
        // A groove: walls of heights 0.5 and 1.5 at distances 0.4 and 1.1 along ∓t, long
        // (±5000) along b.
        let (d1, h1, d2, h2) = (0.4f32, 0.5f32, 1.1f32, 1.5f32);
        let mut mesh = Mesh::default();
        let long = 5000.0;
        for (x, h) in [(0.3 - d1, h1), (0.3 + d2, h2)] {
            let base = mesh.positions.len() as u32;
            mesh.positions.extend([
                at(x, -long, 0.0),
                at(x, long, 0.0),
                at(x, long, h),
                at(x, -long, h),
            ]);
            mesh.faces.push([base, base + 1, base + 2]);
            mesh.faces.push([base, base + 2, base + 3]);
            mesh.face_materials.extend([m, m]);
        }
        cases.push(OcclusionCase {
            name: format!(
                "a groove between walls of heights {h1} and {h2} at {d1} and {d2} (scale {scale:e})"
            ),
            scene: occlusion_scene(vec![floor], mesh),
            position,
            normal: n,
            accessibility: groove_accessibility(&[(d1 as f64, h1 as f64), (d2 as f64, h2 as f64)]),
            bent_normal: None,
            scale,
        });
    }
    cases
}

/// Estimates per case of the Z-test, and rays per estimate.
const AO_ESTIMATES: u32 = 128;
const AO_RAYS: u32 = 96;

fn ao_call(case: &OcclusionCase) -> String {
    format!("ambient_occlusion at {} on {}", case.position, case.name)
}

/// The rays `ambient_occlusion` traces, and the samples it draws, for one call.
fn check_rays(s: &dyn AmbientOcclusion) -> Result<(), String> {
    let (position, normal) = (Vec3::new(2.0, -1.0, 0.5), Vec3::new(0.0, 0.6, 0.8));
    let drawn = RefCell::new(Vec::new());
    let sampler = |rng: &mut Rng| {
        let s = equal_angle_sampler(normal)(rng);
        drawn.borrow_mut().push(s.direction);
        s
    };
    let rays = RefCell::new(Vec::new());
    let occluded = |ray: &Ray| {
        rays.borrow_mut().push(*ray);
        false
    };
    let mut rng = Rng::new(7, 3);
    let samples = 17;
    s.ambient_occlusion(position, normal, samples, &sampler, &occluded, &mut rng);
    let call =
        format!("ambient_occlusion(position = {position}, normal = {normal}, samples = {samples})");
    let (drawn, rays) = (drawn.into_inner(), rays.into_inner());
    if drawn.len() != samples as usize || rays.len() != samples as usize {
        return Err(format!(
            "{call} drew {} directions and traced {} rays; expected one of each per sample",
            drawn.len(),
            rays.len()
        ));
    }
    for (d, r) in drawn.iter().zip(&rays) {
        if (r.origin - position).length() > 1e-5 * position.length()
            || angle(r.direction, *d) > 1e-5
        {
            return Err(format!(
                "{call} traced {r:?} for the direction {d}: a ray leaves the position along the sampled direction"
            ));
        }
        if !(1e-5..=1e-3).contains(&r.tmin) {
            return Err(format!(
                "{call} traced a ray with tmin = {}: use RAY_EPSILON = {RAY_EPSILON}, so that the surface does not occlude itself",
                r.tmin
            ));
        }
        if r.tmax < 1e30 {
            return Err(format!(
                "{call} traced a ray with tmax = {}: the environment is at infinity, so every occluder counts",
                r.tmax
            ));
        }
    }
    Ok(())
}

/// Exact answers: one direction only, free; one free and one blocked; all blocked.
fn check_exact(s: &dyn AmbientOcclusion) -> Result<(), String> {
    let n = Vec3::new(-0.48, 0.6, 0.64);
    let mut rng = Rng::new(3, 5);
    let free = spherical(n, 0.6, 1.0);
    let blocked = spherical(n, 0.9, 4.0);
    // A sampler that only ever returns the normal, with the density of the cosine lobe
    // there: every estimate of an unoccluded point is exactly 1.
    let along_normal = |_: &mut Rng| HemisphereSample {
        direction: n,
        pdf: std::f32::consts::FRAC_1_PI,
    };
    let never = |_: &Ray| false;
    let o = s.ambient_occlusion(Vec3::ONE, n, 8, &along_normal, &never, &mut rng);
    if (o.accessibility - 1.0).abs() > 1e-5 || angle(o.bent_normal, n) > 1e-4 {
        return Err(format!(
            "ambient_occlusion with nothing in the way and every sample along the normal (pdf 1/π) returned {o:?}; expected accessibility 1 and the normal {n} as bent normal"
        ));
    }
    let turn = Cell::new(false);
    let alternate = |_: &mut Rng| {
        turn.set(!turn.get());
        HemisphereSample {
            direction: if turn.get() { free } else { blocked },
            pdf: 0.3,
        }
    };
    let hits_blocked = |r: &Ray| angle(r.direction, blocked) < 1e-4;
    let o = s.ambient_occlusion(Vec3::ONE, n, 6, &alternate, &hits_blocked, &mut rng);
    check_unit("the bent normal", o.bent_normal)?;
    if angle(o.bent_normal, free) > 1e-4 {
        return Err(format!(
            "ambient_occlusion with samples alternating between the free direction {free} and the blocked {blocked} returned the bent normal {}; the bent normal averages the unoccluded directions only",
            o.bent_normal
        ));
    }
    let always = |_: &Ray| true;
    let o = s.ambient_occlusion(Vec3::ONE, n, 6, &alternate, &always, &mut rng);
    if o.accessibility != 0.0 || angle(o.bent_normal, n) > 1e-4 {
        return Err(format!(
            "ambient_occlusion with every ray blocked returned {o:?}; expected accessibility 0 and the surface normal {n} as bent normal"
        ));
    }
    Ok(())
}

/// The Z-test of the estimates against the closed forms, with each of the check's samplers.
fn check_closed_forms(s: &dyn AmbientOcclusion) -> Result<(), String> {
    let cases = occlusion_cases();
    let samplers = check_samplers();
    let z_max = normal_two_sided_quantile(sidak(SIGNIFICANCE, 2 * cases.len() * samplers.len()));
    for (which, (make, about)) in samplers.iter().enumerate() {
        for (k, case) in cases.iter().enumerate() {
            check_closed_form(s, case, make(case.normal), about, z_max, (which, k))?;
        }
    }
    Ok(())
}

/// One case of [`check_closed_forms`] with one sampler (`about` says which), its generator
/// seeded by `seed`.
fn check_closed_form(
    s: &dyn AmbientOcclusion,
    case: &OcclusionCase,
    sampler: Box<dyn Fn(&mut Rng) -> HemisphereSample>,
    about: &str,
    z_max: f64,
    seed: (usize, usize),
) -> Result<(), String> {
    let occluded = |r: &Ray| case.occluded(r);
    let mut rng = Rng::new(1103 + seed.0 as u64, seed.1 as u64);
    let before = rng.clone();
    let estimates: Vec<Occlusion> = (0..AO_ESTIMATES)
        .map(|_| {
            s.ambient_occlusion(
                case.position,
                case.normal,
                AO_RAYS,
                &sampler,
                &occluded,
                &mut rng,
            )
        })
        .collect();
    if rng.clone().next_u32() == before.clone().next_u32() {
        return Err(format!(
            "{} did not draw from `rng`: the sampler takes it",
            ao_call(case)
        ));
    }
    for o in &estimates {
        if !o.accessibility.is_finite() {
            return Err(format!("{} returned {o:?}", ao_call(case)));
        }
        check_unit(
            &format!("the bent normal of {}", ao_call(case)),
            o.bent_normal,
        )?;
    }
    let a: Vec<f64> = estimates.iter().map(|o| o.accessibility as f64).collect();
    let mean = a.iter().sum::<f64>() / a.len() as f64;
    let var = a.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (a.len() - 1) as f64;
    let sd = (var / a.len() as f64).sqrt() + 1e-5;
    let z = (mean - case.accessibility) / sd;
    if z.abs() > z_max {
        return Err(format!(
            "{}: the mean accessibility of {AO_ESTIMATES} estimates of {AO_RAYS} rays is {mean:.4} ± {sd:.4}, expected {:.4} (|z| = {:.1} > {z_max:.2}; {about}: weight each free ray by cos θ/(π·pdf) with the pdf the sampler returns)",
            ao_call(case),
            case.accessibility,
            z.abs()
        ));
    }
    if let Some(expected) = case.bent_normal {
        let mean_bent = estimates
            .iter()
            .map(|o| o.bent_normal)
            .sum::<Vec3>()
            .normalize();
        let off = angle(mean_bent, expected);
        if off > 0.05 {
            return Err(format!(
                "{}: the mean bent normal is {mean_bent}, {:.1}° from the expected {expected} (the cosine-weighted mean free direction; {about}: weight each free direction by cos θ/(π·pdf), as the accessibility)",
                ao_call(case),
                off.to_degrees()
            ));
        }
    }
    Ok(())
}

fn exercise_11_3(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    let s = s.as_ref();
    check_rays(s)?;
    check_exact(s)?;
    check_closed_forms(s)?;
    if let Some(key) = key(ctx) {
        for (k, case) in occlusion_cases().iter().enumerate() {
            let sampler = check_samplers()[k % 2].0(case.normal);
            let occluded = |r: &Ray| case.occluded(r);
            let mut a = Rng::new(99, k as u64);
            let mut b = a.clone();
            let got =
                s.ambient_occlusion(case.position, case.normal, 64, &sampler, &occluded, &mut a);
            let want =
                key.ambient_occlusion(case.position, case.normal, 64, &sampler, &occluded, &mut b);
            if (got.accessibility - want.accessibility).abs() > 1e-4
                || angle(got.bent_normal, want.bent_normal) > 1e-3
            {
                return Err(format!(
                    "{} with 64 rays returned {got:?}; the reference returns {want:?} from the same samples",
                    ao_call(case)
                ));
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// 11.4: RGBE

fn rel_close3(got: Vec3, expected: Vec3, rel: f32) -> bool {
    (got - expected)
        .abs()
        .cmple(rel * expected.abs() + Vec3::splat(1e-38))
        .all()
}

fn exercise_11_4(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    let f = |p: [u8; 4]| s.rgbe_to_rgb(p);
    for_all(CASES, rgbe_strategy(), |p| {
        let [r, g, b, e] = p;
        let v = f(p);
        let call = format!("rgbe_to_rgb({p:?}) = {v}");
        if !v.is_finite() || v.min_element() < 0.0 {
            return Err(format!("{call}: radiance is finite and not negative"));
        }
        if e == 0 {
            if v != Vec3::ZERO {
                return Err(format!("{call}: an exponent of 0 is black"));
            }
            return Ok(());
        }
        if e < 255 {
            let up = f([r, g, b, e + 1]);
            if !rel_close3(up, 2.0 * v, 1e-6) {
                return Err(format!(
                    "{call} but rgbe_to_rgb({:?}) = {up}: one more in the exponent doubles the value",
                    [r, g, b, e + 1]
                ));
            }
        }
        let alone = Vec3::new(f([r, 0, 0, e]).x, f([0, g, 0, e]).y, f([0, 0, b, e]).z);
        if !rel_close3(alone, v, 1e-6) {
            return Err(format!(
                "{call}, but channel by channel it is {alone}: each channel is its own mantissa times the shared exponent's scale"
            ));
        }
        if r < 255 && f([r + 1, g, b, e]).x <= v.x {
            return Err(format!("{call}: a larger mantissa is brighter"));
        }
        Ok(())
    })?;
    // Agreement with the `image` crate's decoder on the lab's probe file, within one step of
    // the mantissa (the decoders of the literature differ in where in the step they put the
    // value).
    let path = ctx.lab_dir.join("probes").join(SKY_PROBE);
    let raw = RgbeImage::read(&path).map_err(|e| e.to_string())?;
    let decoded = Texture::load(&path).map_err(|e| e.to_string())?;
    for (i, (p, d)) in raw.pixels.iter().zip(&decoded.texels).enumerate() {
        let v = f(*p);
        let step = if p[3] == 0 {
            0.0
        } else {
            f32::exp2((i32::from(p[3]) - 136) as f32)
        };
        if !((v - *d)
            .abs()
            .cmple(Vec3::splat(step * 1.0001 + 1e-38))
            .all())
        {
            return Err(format!(
                "on pixel ({}, {}) of {}, the RGBE bytes {p:?}: rgbe_to_rgb gives {v}, the image crate's Radiance decoder {d}; they must agree to within one step of the mantissa ({step:e})",
                i as u32 % raw.width,
                i as u32 / raw.width,
                path.display()
            ));
        }
    }
    if let Some(key) = key(ctx) {
        for_all(CASES, rgbe_strategy(), |p| {
            let (got, want) = (f(p), key.rgbe_to_rgb(p));
            if rel_close3(got, want, 1e-6) {
                Ok(())
            } else {
                Err(format!("rgbe_to_rgb({p:?}) = {got}, expected {want}"))
            }
        })?;
    }
    let golden: GoldenFile<[u8; 4], Vec3> = load(ctx, GOLDEN_RGBE)?;
    for case in &golden.cases {
        let got = f(case.input);
        if !rel_close3(got, case.expected, 1e-6) {
            return Err(format!(
                "rgbe_to_rgb({:?}) = {got}, expected {} (the golden case; mind the half step: the course takes the centre of the mantissa's interval)",
                case.input, case.expected
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// 11.5–11.8: the probe mappings

/// The wrap-around distance of two `u` coordinates of a latitude–longitude map.
fn wrap(a: f32, b: f32) -> f32 {
    let d = (a - b).rem_euclid(1.0);
    d.min(1.0 - d)
}

/// How far apart two angular-map coordinates of the direction `d` are: near +z, whose image
/// is the whole rim, only the distance from the centre counts.
fn angular_uv_error(d: Vec3, got: Vec2, expected: Vec2) -> f32 {
    if angle(d, Vec3::Z) < 0.02 {
        let c = Vec2::splat(0.5);
        ((got - c).length() - (expected - c).length()).abs()
    } else {
        (got - expected).abs().max_element()
    }
}

/// How far apart two latitude–longitude coordinates of the direction `d` are: `u` wraps
/// around, and counts only away from the poles.
fn latlong_uv_error(d: Vec3, got: Vec2, expected: Vec2) -> f32 {
    let dv = (got.y - expected.y).abs();
    let sin = (1.0 - d.y * d.y).max(0.0).sqrt();
    if sin < 2e-3 {
        dv
    } else {
        dv.max(wrap(got.x, expected.x) * sin)
    }
}

fn check_uv_range(call: &str, uv: Vec2) -> Result<(), String> {
    if !(uv.is_finite()
        && uv.cmpge(Vec2::splat(-1e-6)).all()
        && uv.cmple(Vec2::splat(1.0 + 1e-6)).all())
    {
        return Err(format!(
            "{call} = {uv}: texture coordinates of a probe are in [0, 1]²"
        ));
    }
    Ok(())
}

fn check_forward(
    s: &dyn AmbientOcclusion,
    ctx: &LabContext,
    map: &dyn Fn(&dyn AmbientOcclusion, Vec3) -> Vec2,
    name: &str,
    error: fn(Vec3, Vec2, Vec2) -> f32,
    (own_golden, inverse_golden): (&str, &str),
    extra: &dyn Fn(Vec3, Vec2) -> Result<(), String>,
) -> Result<(), String> {
    for_all(CASES, direction_strategy(), |d| {
        let uv = map(s, d);
        let call = format!("{name}({d})");
        check_uv_range(&call, uv)?;
        extra(d, uv).map_err(|e| format!("{call} = {uv}: {e}"))
    })?;
    if let Some(key) = key(ctx) {
        for_all(CASES, direction_strategy(), |d| {
            let (got, want) = (map(s, d), map(key.as_ref(), d));
            if error(d, got, want) > UV_TOL {
                return Err(format!("{name}({d}) = {got}, expected {want}"));
            }
            Ok(())
        })?;
    }
    let golden: GoldenFile<Vec3, Vec2> = load(ctx, own_golden)?;
    for case in &golden.cases {
        let got = map(s, case.input);
        if error(case.input, got, case.expected) > UV_TOL {
            return Err(format!(
                "{name}({}) = {got}, expected {} (golden case)",
                case.input, case.expected
            ));
        }
    }
    // The round trip through the recorded inverse: the direction of the coordinates maps back
    // to them.
    let inverse: GoldenFile<Vec2, Option<Vec3>> = load(ctx, inverse_golden)?;
    for case in &inverse.cases {
        if let Some(d) = case.expected {
            let got = map(s, d);
            if error(d, got, case.input) > UV_TOL {
                return Err(format!(
                    "{name}({d}) = {got}, but {d} is the direction of the coordinates {} (the golden cases of the inverse): the two maps must undo each other",
                    case.input
                ));
            }
        }
    }
    Ok(())
}

fn check_inverse(
    s: &dyn AmbientOcclusion,
    ctx: &LabContext,
    map: &dyn Fn(&dyn AmbientOcclusion, Vec2) -> Option<Vec3>,
    name: &str,
    own_golden: &str,
    forward_golden: &str,
    inside: &dyn Fn(Vec2) -> Option<bool>,
) -> Result<(), String> {
    let same = |a: Option<Vec3>, b: Option<Vec3>| match (a, b) {
        (None, None) => true,
        (Some(a), Some(b)) => angle(a, b) <= ANGLE_TOL,
        _ => false,
    };
    for_all(CASES, uv_strategy(), |uv| {
        let got = map(s, uv);
        let call = format!("{name}({uv})");
        match (got, inside(uv)) {
            (Some(d), Some(false)) => Err(format!(
                "{call} = {d}, but {uv} is outside the map: expected None"
            )),
            (None, Some(true)) => Err(format!("{call} = None, but {uv} is on the map")),
            (Some(d), _) => check_unit(&call, d),
            (None, _) => Ok(()),
        }
    })?;
    if let Some(key) = key(ctx) {
        for_all(CASES, uv_strategy(), |uv| {
            let (got, want) = (map(s, uv), map(key.as_ref(), uv));
            if !same(got, want) {
                return Err(format!("{name}({uv}) = {got:?}, expected {want:?}"));
            }
            Ok(())
        })?;
    }
    let golden: GoldenFile<Vec2, Option<Vec3>> = load(ctx, own_golden)?;
    for case in &golden.cases {
        let got = map(s, case.input);
        if !same(got, case.expected) {
            return Err(format!(
                "{name}({}) = {got:?}, expected {:?} (golden case)",
                case.input, case.expected
            ));
        }
    }
    let forward: GoldenFile<Vec3, Vec2> = load(ctx, forward_golden)?;
    for case in &forward.cases {
        let got = map(s, case.expected);
        if !same(got, Some(case.input)) {
            return Err(format!(
                "{name}({}) = {got:?}, but {} are the coordinates of the direction {} (the golden cases of the forward map): the two maps must undo each other",
                case.expected, case.expected, case.input
            ));
        }
    }
    Ok(())
}

fn exercise_11_5(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    check_forward(
        s.as_ref(),
        ctx,
        &|a, d| a.angular_map_uv(d),
        "angular_map_uv",
        angular_uv_error,
        (GOLDEN_ANGULAR_UV, GOLDEN_ANGULAR_DIRECTION),
        &|d, uv| {
            let r = (uv - Vec2::splat(0.5)).length();
            if r > 0.5 + 1e-5 {
                return Err(format!(
                    "{r} from the centre: the map is the disc of radius ½ about (½, ½)"
                ));
            }
            if angle(d, Vec3::Z) < 1e-3 && r < 0.5 - 1e-3 {
                return Err("+z (straight behind the probe's camera) is on the rim".into());
            }
            Ok(())
        },
    )
}

fn exercise_11_6(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    check_inverse(
        s.as_ref(),
        ctx,
        &|a, uv| a.angular_map_direction(uv),
        "angular_map_direction",
        GOLDEN_ANGULAR_DIRECTION,
        GOLDEN_ANGULAR_UV,
        &|uv| {
            let r = (uv - Vec2::splat(0.5)).length();
            if r < 0.5 - 1e-5 {
                Some(true)
            } else if r > 0.5 + 1e-5 {
                Some(false)
            } else {
                None
            }
        },
    )
}

fn exercise_11_7(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    check_forward(
        s.as_ref(),
        ctx,
        &|a, d| a.latlong_uv(d),
        "latlong_uv",
        latlong_uv_error,
        (GOLDEN_LATLONG_UV, GOLDEN_LATLONG_DIRECTION),
        &|_, _| Ok(()),
    )
}

fn exercise_11_8(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    check_inverse(
        s.as_ref(),
        ctx,
        &|a, uv| Some(a.latlong_direction(uv)),
        "latlong_direction",
        GOLDEN_LATLONG_DIRECTION,
        GOLDEN_LATLONG_UV,
        &|uv| {
            let on = uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all();
            on.then_some(true)
        },
    )
}

// ---------------------------------------------------------------------------------------------
// 11.9: the shader

/// Input of 11.9: diffuse reflectance, the occlusion, the environment's radiance.
pub type ShadeInput = (Vec3, Occlusion, Vec3);

/// Inputs of 11.9.
pub fn shade_strategy() -> impl Strategy<Value = ShadeInput> + Clone {
    let colour = |max: f32| (0.0..max, 0.0..max, 0.0..max).prop_map(|(r, g, b)| Vec3::new(r, g, b));
    (colour(1.0), 0.0..=1.0f32, unit_vector(), colour(50.0)).prop_map(|(rho, a, bent, env)| {
        (
            rho,
            Occlusion {
                accessibility: a,
                bent_normal: bent,
            },
            env,
        )
    })
}

fn exercise_11_9(s: &Arc<dyn AmbientOcclusion>, ctx: &LabContext) -> Result<(), String> {
    let f = |(rho, o, env): ShadeInput| s.shade_ambient_occlusion(rho, &o, env);
    let open = |bent| Occlusion {
        accessibility: 1.0,
        bent_normal: bent,
    };
    // The white furnace.
    for l in [Vec3::ONE, Vec3::new(0.2, 3.0, 40.0)] {
        let got = f((Vec3::ONE, open(Vec3::Y), l));
        if !rel_close3(got, l, 1e-5) {
            return Err(format!(
                "shade_ambient_occlusion(diffuse = 1, accessibility = 1, environment = {l}) = {got}: a white Lambertian surface that sees the whole of a uniform environment of radiance L reflects exactly L (energy is conserved, nothing is added)"
            ));
        }
    }
    for_all(CASES, shade_strategy(), |(rho, o, env)| {
        let v = f((rho, o, env));
        let call = format!("shade_ambient_occlusion({rho}, {o:?}, {env}) = {v}");
        if !v.is_finite() || v.min_element() < 0.0 {
            return Err(format!(
                "{call}: reflected radiance is finite and not negative"
            ));
        }
        let half = f((
            rho,
            Occlusion {
                accessibility: 0.5 * o.accessibility,
                ..o
            },
            env,
        ));
        if !rel_close3(half, 0.5 * v, 1e-5) {
            return Err(format!(
                "{call}, with half the accessibility {half}: the reflected light is proportional to the accessible part of the environment"
            ));
        }
        let other = f((
            rho,
            Occlusion {
                bent_normal: -o.bent_normal,
                ..o
            },
            env,
        ));
        if !rel_close3(other, v, 1e-6) {
            return Err(format!(
                "{call}, with the opposite bent normal {other}: the environment's radiance along the bent normal is already looked up and given"
            ));
        }
        let per_channel = f((Vec3::new(rho.x, 0.0, 0.0), o, env)).x;
        if (per_channel - v.x).abs() > 1e-5 * v.x.abs() + 1e-30 {
            return Err(format!(
                "{call}: each channel reflects its own share (red depends on red only)"
            ));
        }
        Ok(())
    })?;
    if let Some(key) = key(ctx) {
        for_all(CASES, shade_strategy(), |i| {
            let (got, want) = (f(i), key.shade_ambient_occlusion(i.0, &i.1, i.2));
            if rel_close3(got, want, 1e-5) {
                Ok(())
            } else {
                Err(format!(
                    "shade_ambient_occlusion{i:?} = {got}, expected {want}"
                ))
            }
        })?;
    }
    let golden: GoldenFile<ShadeInput, Vec3> = load(ctx, GOLDEN_SHADE)?;
    for case in &golden.cases {
        let got = f(case.input);
        if !rel_close3(got, case.expected, 1e-5) {
            return Err(format!(
                "shade_ambient_occlusion{:?} = {got}, expected {} (golden case)",
                case.input, case.expected
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_check_sampler_reports_its_density() {
        // The mean of 1/pdf is the solid angle of the support, 2π.
        let mut rng = Rng::new(2, 1);
        let sampler = equal_angle_sampler(Vec3::Z);
        let n = 200_000;
        let mean = (0..n)
            .map(|_| 1.0 / sampler(&mut rng).pdf as f64)
            .sum::<f64>()
            / n as f64;
        assert!((mean / (2.0 * PI) - 1.0).abs() < 0.01, "{mean}");
        let mut rng = Rng::new(1, 1);
        let s = equal_angle_sampler(Vec3::Y)(&mut rng);
        let theta = s.direction.y.acos() as f64;
        assert!((s.pdf as f64 - 1.0 / (PI * PI * theta.sin())).abs() < 1e-3 * s.pdf as f64);
    }

    #[test]
    fn the_lopsided_sampler_reports_its_density() {
        // The mean of 1/pdf is 2π; three directions in four lean towards the first tangent,
        // each with the density 3/(4π).
        let mut rng = Rng::new(3, 1);
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let onb = Onb::from_w(n);
        let sampler = lopsided_sampler(n);
        let count = 200_000;
        let (mut inverse, mut towards) = (0.0, 0);
        for _ in 0..count {
            let s = sampler(&mut rng);
            assert!(s.direction.dot(n) >= 0.0);
            inverse += 1.0 / s.pdf as f64;
            let side = s.direction.dot(onb.u);
            towards += usize::from(side > 0.0);
            if side.abs() > 1e-4 {
                let expected = if side > 0.0 { 0.75 } else { 0.25 } / PI;
                assert!((s.pdf as f64 - expected).abs() < 1e-6, "{s:?}");
            }
        }
        assert!((inverse / count as f64 / (2.0 * PI) - 1.0).abs() < 0.01);
        assert!((towards as f64 / count as f64 - 0.75).abs() < 0.01);
    }

    #[test]
    fn groove_closed_form() {
        // No wall, or a wall of no height: accessible; an infinitely high wall at any
        // distance hides half.
        assert_eq!(groove_accessibility(&[]), 1.0);
        assert!((groove_accessibility(&[(1.0, 0.0)]) - 1.0).abs() < 1e-12);
        assert!((groove_accessibility(&[(1.0, 1e9)]) - 0.5).abs() < 1e-8);
        assert_eq!(occlusion_cases().len(), 12);
    }
}
