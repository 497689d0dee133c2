//! Lab 04's exercises and their checks.
//!
//! Every exercise is checked in three ways: properties of the physics (law of reflection,
//! Snell's law, total internal reflection exactly past the critical angle, the Phong lobe's
//! peak, normalization and additivity) on random inputs from a fixed seed — compared with the
//! answer key on the same inputs when the key is present ([`LabContext::key`]) — the golden
//! cases recorded from the reference (all but Exercise 4.2, whose properties pin the answer
//! down), and renders of small scenes with the student's function in its slot and the base
//! everywhere else.
//!
//! Lab 04's functions draw no random numbers, and the snapshot scenes have only point and
//! directional lights (the Cornell box's area light is removed, its emission still shows), so
//! the renders are deterministic and are compared pixel by pixel.

use std::path::Path;
use std::sync::Arc;

use glam::{DVec3, Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab04::{Interface, Reflection};
use grading::part_snapshots::{PartSnapshots, SnapshotScene};
pub use grading::radiometry::samples_of;
use grading::scenes::glossy_default_scene;
use grading::strategies::{index_strategy, point, scale, unit_vector};
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, compare_f32, compare_vec3, for_all,
};
use raylab_core::math::{RAY_EPSILON, Ray};
use raylab_core::render::RenderSettings;
use raylab_core::scene::{Hit, HitSurface};
use raylab_core::scene::{Light, MaterialId, Scene, builtin_scene, parse_scene_str};

/// Golden file of Exercise 4.1.
pub const GOLDEN_REFLECT: &str = "reflect.json";
/// Golden file of Exercise 4.3.
pub const GOLDEN_INTERFACE: &str = "interface.json";
/// Golden file of Exercise 4.4.
pub const GOLDEN_REFRACT: &str = "refract.json";
/// Golden file of Exercise 4.5.
pub const GOLDEN_REFRACTED_RAY: &str = "refracted_ray.json";
/// Golden file of Exercise 4.6.
pub const GOLDEN_PHONG: &str = "shade_phong.json";
/// Size and sampling of lab 04's snapshots.
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(4);
/// The depth limit of the snapshots: reflected and refracted rays stop (black) after this many
/// bounces.
pub const SNAPSHOT_MAX_DEPTH: u32 = 10;
/// Largest `tmin` accepted for a reflected or refracted ray: it must be positive (no
/// self-intersection) but small (no skipped surfaces nearby); the reference uses
/// [`RAY_EPSILON`].
pub const MAX_SECONDARY_TMIN: f32 = 1e-3;
/// A secondary ray's `tmax` counts as unbounded from this value on (`f32::MAX` or `∞`).
pub const UNBOUNDED_TMAX: f32 = 1e30;
/// Per-pixel tolerance of the snapshots: the renders are deterministic, so only rounding
/// (and rays that graze a sphere, where a different but correct rounding may pick the other
/// side) may differ.
pub const SNAPSHOT_TOLERANCE: PixelTolerance = PixelTolerance {
    abs: 2e-3,
    rel: 2e-3,
    max_outlier_fraction: 0.005,
};

/// Two parallel mirrors facing each other (the side walls of a closed room) with a red sphere
/// between them, seen at an angle: the rays towards the far end of the corridor of
/// reflections bounce between the mirrors until the depth limit, where they turn black.
pub const TWO_MIRRORS_SCENE: &str = r#"
name = "two-mirrors"
background = [0.1, 0.3, 0.6]

[camera]
eye = [0.7, 1.0, 0.9]
look_at = [-1.0, 0.75, -0.3]
up = [0.0, 1.0, 0.0]
focal_distance = 0.9

[materials.mirror]
illum = 3
specular = [1.0, 1.0, 1.0]

[materials.floor]
diffuse = [0.7, 0.7, 0.7]

[materials.ceiling]
diffuse = [0.8, 0.8, 0.8]

[materials.back]
diffuse = [0.75, 0.6, 0.3]

[materials.front]
diffuse = [0.2, 0.35, 0.7]

[materials.red]
diffuse = [0.8, 0.1, 0.1]

[[lights]]
type = "point"
position = [0.0, 2.2, 0.0]
intensity = [6.0, 6.0, 6.0]

[[planes]]
point = [-1.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]
material = "mirror"

[[planes]]
point = [1.0, 0.0, 0.0]
normal = [-1.0, 0.0, 0.0]
material = "mirror"

[[planes]]
point = [0.0, 0.0, 0.0]
normal = [0.0, 1.0, 0.0]
material = "floor"

[[planes]]
point = [0.0, 2.5, 0.0]
normal = [0.0, -1.0, 0.0]
material = "ceiling"

[[planes]]
point = [0.0, 0.0, -3.0]
normal = [0.0, 0.0, 1.0]
material = "back"

[[planes]]
point = [0.0, 0.0, 3.0]
normal = [0.0, 0.0, -1.0]
material = "front"

[[spheres]]
center = [0.0, 0.45, -0.6]
radius = 0.45
material = "red"
"#;

// ---------------------------------------------------------------------------------------------
// Exercises

/// This lab.
pub const LAB: course::LabId = course::LabId::of(4);

/// The exercises of lab 04 (`labs/lab04/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Reflection>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_4_1,
            exercise_4_2,
            exercise_4_3,
            exercise_4_4,
            exercise_4_5,
            exercise_4_6
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Inputs

/// Input of Exercise 4.1: direction, unit normal.
pub type ReflectInput = (Vec3, Vec3);
/// Input of Exercises 4.3 and 4.5: ray direction, shading normal of the hit, `hit.ior`, the
/// material's index of refraction.
pub type SideInput = (Vec3, Vec3, f32, f32);
/// Input of Exercise 4.4: unit direction, unit normal facing it, `η_i`, `η_t`.
pub type RefractInput = (Vec3, Vec3, f32, f32);
/// Input of Exercise 4.6: `ρ_d`, `ρ_s`, shininess, normal, view, lights (direction, radiance).
pub type PhongInput = (Vec3, Vec3, f32, Vec3, Vec3, Vec<(Vec3, Vec3)>);

/// A hit at `position` with the given normals, reached through a medium of index `ior`.
pub fn hit_at(position: Vec3, geometric_normal: Vec3, shading_normal: Vec3, ior: f32) -> Hit {
    Hit {
        distance: 1.0,
        position,
        geometric_normal,
        shading_normal,
        texcoord: Vec2::ZERO,
        surface: HitSurface::Unknown,
        material: MaterialId(0),
        trace_depth: 0,
        ior,
    }
}

/// The ray that arrives at `position` along `direction` from `distance` away, as a closest-hit
/// query leaves it (its `tmax` shrunk to the hit).
pub fn incoming_ray(position: Vec3, direction: Vec3, distance: f32) -> Ray {
    Ray::new(position - distance * direction, direction, 0.0, distance)
}

/// A unit vector `v` with `v·n` in `[lo, hi]`: the shared unit vector, flipped when that
/// brings it into the range.
fn unit_with_cosine(n: Vec3, v: Vec3, lo: f32, hi: f32) -> Option<Vec3> {
    [v, -v].into_iter().find(|w| (lo..=hi).contains(&w.dot(n)))
}

/// A unit direction at angle `θ` (`sin θ = sin_theta`) from `−normal`, on the side of
/// `around` (any vector not parallel to `normal`).
fn direction_at(normal: Vec3, around: Vec3, sin_theta: f32) -> Option<Vec3> {
    let tangent = (around - around.dot(normal) * normal).try_normalize()?;
    let cos_theta = (1.0 - sin_theta * sin_theta).max(0.0).sqrt();
    (sin_theta * tangent - cos_theta * normal).try_normalize()
}

/// Inputs of Exercise 4.4: directions at any angle of incidence (up to 89.4°), pairs of
/// indices (equal one time in eight), the normal facing the incident side.
pub fn refract_strategy() -> impl Strategy<Value = RefractInput> + Clone {
    (
        unit_vector(),
        unit_vector(),
        0.0f32..0.99995,
        index_strategy(),
        index_strategy(),
        0u8..8,
    )
        .prop_filter_map("a direction with a tangent", |(n, v, s, ei, et, same)| {
            let w = direction_at(n, v, s)?;
            Some((w, n, ei, if same == 0 { ei } else { et }))
        })
}

/// Inputs of Exercises 4.3 and 4.5: entering (`ω·n < 0`, from a medium of any index) or
/// leaving (`ω·n > 0`, from inside the material, so `hit.ior` is the material's index).
pub fn side_strategy() -> impl Strategy<Value = SideInput> + Clone {
    (unit_vector(), unit_vector(), index_strategy(), 1.05f32..2.5).prop_filter_map(
        "not grazing",
        |(w, n, outside, material)| {
            let c = w.dot(n);
            if c.abs() < 0.02 {
                return None;
            }
            Some((w, n, if c < 0.0 { outside } else { material }, material))
        },
    )
}

/// Inputs of Exercises 4.3 and 4.5 at hits whose shading normal (the input's `n`) is tilted
/// away from the geometric normal, as on a smooth mesh, with the hit anywhere from the origin
/// to thousands of units away: the input, the geometric normal and the hit's position. The
/// direction is on the same side of both normals (at least 0.05 from tangent to either), so
/// entering and leaving mean the same whichever normal decides.
pub fn bent_side_strategy() -> impl Strategy<Value = (SideInput, Vec3, Vec3)> + Clone {
    (side_strategy(), point(0.25), point(5.0), scale()).prop_filter_map(
        "a tilted normal on the direction's side",
        |((w, g, hit_ior, material_ior), bend, p, k)| {
            let n = (g + bend).try_normalize()?;
            let (cg, cn) = (w.dot(g), w.dot(n));
            let clear = cg * cn > 0.0 && cg.abs() >= 0.05 && cn.abs() >= 0.05;
            let tilted = (n - g).length() > 0.05;
            (clear && tilted).then_some(((w, n, hit_ior, material_ior), g, k * p))
        },
    )
}

/// Inputs of Exercises 4.3 and 4.5 at hits where the two normals disagree, as near the
/// silhouette of a smooth mesh: the direction lies between the tangent planes of the
/// geometric and the shading normal (at least 0.02 from either), so it arrives from the front
/// by one normal and from the back by the other; the shading normal decides. The input, the
/// geometric normal and the hit's position, from the origin to thousands of units away.
pub fn split_side_strategy() -> impl Strategy<Value = (SideInput, Vec3, Vec3)> + Clone {
    (
        (unit_vector(), unit_vector(), 0.1f32..0.6),
        (-0.9f32..0.9, -1.0f32..1.0, any::<bool>()),
        (index_strategy(), 1.05f32..2.5),
        (point(5.0), scale()),
    )
        .prop_filter_map(
            "a direction between the two tangent planes",
            |((g, towards, tilt), (x, z, flip), (outside, material), (p, k))| {
                // The shading normal, `tilt` radians from `g`; `h` halves the angle between
                // them and `d` is perpendicular to `h` in their plane.
                let d0 = (towards - towards.dot(g) * g).try_normalize()?;
                let n = (g * tilt.cos() + d0 * tilt.sin()).normalize();
                let h = (g + n).normalize();
                let d = (n - g).normalize();
                let e = h.cross(d);
                // ω ∝ x·tan(tilt/2)·h ± d + z·e with |x| < 1: ω·g ∝ x − (±1) and ω·n ∝ x + (±1)
                // differ in sign.
                let y = if flip { 1.0 } else { -1.0 };
                let w = (x * (0.5 * tilt).tan() * h + y * d + z * e).normalize();
                let (cg, cn) = (w.dot(g), w.dot(n));
                let apart = cg * cn < 0.0 && cg.abs() >= 0.02 && cn.abs() >= 0.02;
                let hit_ior = if cn < 0.0 { outside } else { material };
                apart.then_some(((w, n, hit_ior, material), g, k * p))
            },
        )
}

/// A random shininess in `[1, 200]` (half the time one of a few typical values, some of them
/// odd integers or fractions).
pub fn shininess_strategy() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        1.0f32..200.0,
        prop::sample::select(vec![1.0f32, 1.5, 3.0, 10.0, 40.0, 64.0]),
    ]
}

fn colour(max: f32) -> impl Strategy<Value = Vec3> + Clone {
    (0.0f32..max, 0.0f32..max, 0.0f32..max).prop_map(|(r, g, b)| Vec3::new(r, g, b))
}

/// Inputs of Exercise 4.6.
///
/// The view is on the side of the normal (`n·v ≥ 0.02`): the integrator only shades surfaces
/// seen from the front, and below the surface the model is not defined by the contract.
pub fn phong_strategy() -> impl Strategy<Value = PhongInput> {
    (
        colour(1.0),
        colour(1.0),
        shininess_strategy(),
        unit_vector(),
        unit_vector(),
        prop::collection::vec((unit_vector(), colour(5.0)), 0..4),
    )
        .prop_map(|(rho_d, rho_s, s, n, v, lights)| {
            let v = unit_with_cosine(n, v, 0.02, 1.0).unwrap_or(n);
            (rho_d, rho_s, s, n, v, lights)
        })
}

// ---------------------------------------------------------------------------------------------
// Relations the answers satisfy, in f64

/// `sin θ` of the unit `w` about the unit `n`.
fn sine(w: DVec3, n: DVec3) -> f64 {
    w.cross(n).length()
}

/// Whether `sin θ_i` is within a relative `margin` of the critical `η_t/η_i`, where two
/// correct implementations may decide total internal reflection differently.
fn near_critical(w: Vec3, n: Vec3, eta_i: f32, eta_t: f32, margin: f64) -> bool {
    let s = sine(w.as_dvec3(), n.as_dvec3());
    (s * eta_i as f64 / eta_t as f64 - 1.0).abs() < margin
}

/// Whether Snell's law `η₁ sin θ₁ = η₂ sin θ₂` has a solution: `sin θ₁ · η₁/η₂ ≤ 1`.
fn snell_has_solution(w: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> bool {
    sine(w.as_dvec3(), n.as_dvec3()) * eta_i as f64 / eta_t as f64 <= 1.0
}

// ---------------------------------------------------------------------------------------------
// Comparisons

fn finite(what: &str, v: Vec3) -> Result<(), String> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(format!("{what} is {v}: not a finite vector"))
    }
}

fn unit(what: &str, v: Vec3) -> Result<(), String> {
    finite(what, v)?;
    let len = v.length();
    if (len - 1.0).abs() > 1e-4 {
        return Err(format!(
            "{what} is {v}, of length {len}: it must be a unit vector"
        ));
    }
    Ok(())
}

/// Checks a reflected or refracted ray: it starts at the hit point, goes along a unit
/// direction (`direction`, where the answer is known), with a small positive `tmin` and an
/// unbounded `tmax`.
fn check_secondary_ray(
    call: &str,
    got: &Ray,
    position: Vec3,
    direction: Option<Vec3>,
    what: &str,
    direction_hint: &str,
) -> Result<(), String> {
    let tol = 1e-5 + 1e-6 * position.abs().max_element();
    let off = (got.origin - position).abs().max_element();
    if off.is_nan() || off > tol {
        return Err(format!(
            "{call} starts at {}; the {what} ray starts at the hit point {position}",
            got.origin
        ));
    }
    unit(&format!("the direction of {call}"), got.direction)?;
    if let Some(direction) = direction {
        compare_vec3(
            &format!("the direction of {call}"),
            got.direction,
            direction,
            1e-4,
            0.0,
        )
        .map_err(|e| format!("{e} ({direction_hint})"))?;
    }
    if got.tmin.is_nan() || got.tmin <= 0.0 {
        return Err(format!(
            "{call} has tmin = {}: a ray that starts on a surface with tmin = 0 hits that same surface at t ≈ 0 (self-intersection); use a small positive tmin such as RAY_EPSILON = {RAY_EPSILON}",
            got.tmin
        ));
    }
    if got.tmin > MAX_SECONDARY_TMIN {
        return Err(format!(
            "{call} has tmin = {}: too large, it skips surfaces closer than that; use RAY_EPSILON = {RAY_EPSILON}",
            got.tmin
        ));
    }
    if got.tmax.is_nan() || got.tmax < UNBOUNDED_TMAX {
        return Err(format!(
            "{call} has tmax = {}: the {what} ray must be unbounded (tmax = f32::INFINITY); the incoming ray's tmax is the distance to this hit",
            got.tmax
        ));
    }
    Ok(())
}

fn check_interface(call: &str, got: Interface, expected: Interface) -> Result<(), String> {
    compare_vec3(
        &format!("the normal of {call}"),
        got.normal,
        expected.normal,
        1e-6,
        0.0,
    )
    .map_err(|e| {
        format!("{e}: the normal must face the incoming ray (flipped when the ray leaves)")
    })?;
    compare_f32(
        &format!("η₁ (eta_incident) of {call}"),
        got.eta_incident,
        expected.eta_incident,
        1e-6,
        0.0,
    )
    .map_err(|e| format!("{e}: η₁ is the index of the medium the ray travels in (hit.ior when entering, material_ior when leaving)"))?;
    compare_f32(
        &format!("η₂ (eta_transmitted) of {call}"),
        got.eta_transmitted,
        expected.eta_transmitted,
        1e-6,
        0.0,
    )
    .map_err(|e| format!("{e}: η₂ is the index on the other side (material_ior when entering, 1 for air when leaving)"))
}

/// Checks a refracted direction: `refracts` says whether the ray refracts (Snell's law has a
/// solution, or the recorded answer is `Some`), `expected` is the known direction, if any (the
/// key's or a golden case's); the properties of Snell's law are checked either way.
fn check_refraction(
    call: &str,
    (w, n, eta_i, eta_t): RefractInput,
    got: Option<Vec3>,
    refracts: bool,
    expected: Option<Vec3>,
) -> Result<(), String> {
    let (wd, nd) = (w.as_dvec3(), n.as_dvec3());
    let sin_i = sine(wd, nd);
    let critical = eta_t as f64 / eta_i as f64;
    let got = match (got, refracts) {
        (None, false) => return Ok(()),
        (None, true) => {
            return Err(format!(
                "{call} returned None (total internal reflection), but sin θ₁ = {sin_i:.5} ≤ η₂/η₁ = {critical:.5}: the ray refracts"
            ));
        }
        (Some(t), false) => {
            return Err(format!(
                "{call} returned Some({t}), but sin θ₁ = {sin_i:.5} > η₂/η₁ = {critical:.5}: past the critical angle there is no refracted ray (total internal reflection); return None"
            ));
        }
        (Some(t), true) => t,
    };
    let what = format!("the refracted direction of {call}");
    unit(&what, got)?;
    let td = got.as_dvec3().normalize();
    if td.dot(nd) >= 0.0 {
        return Err(format!(
            "{what} is {got}, on the incident side (t·n = {:.5} ≥ 0): the refracted ray continues on the far side of the surface",
            td.dot(nd)
        ));
    }
    let out_of_plane = td.dot(wd.cross(nd).normalize_or_zero());
    if out_of_plane.abs() > 1e-4 {
        return Err(format!(
            "{what} is {got}: not in the plane of incidence of ω and n (t·(ω×n)/|ω×n| = {out_of_plane:.5})"
        ));
    }
    let sin_t = sine(td, nd);
    if (eta_i as f64 * sin_i - eta_t as f64 * sin_t).abs() > 2e-4 * eta_t as f64 {
        return Err(format!(
            "{what} is {got}: Snell's law η₁ sin θ₁ = η₂ sin θ₂ does not hold (η₁ sin θ₁ = {:.5}, η₂ sin θ₂ = {:.5})",
            eta_i as f64 * sin_i,
            eta_t as f64 * sin_t
        ));
    }
    let tangent_w = wd - wd.dot(nd) * nd;
    let tangent_t = td - td.dot(nd) * nd;
    if tangent_w.dot(tangent_t) < -1e-6 {
        return Err(format!(
            "{what} is {got}: it bends to the wrong side of the normal (its tangential part opposes ω's)"
        ));
    }
    match expected {
        Some(expected) => compare_vec3(&what, got, expected, 1e-4, 0.0),
        None => Ok(()),
    }
}

// ---------------------------------------------------------------------------------------------
// Snapshots

/// Which student function a snapshot exercises; the rest of the pipeline is the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 4.1 (through the base's `reflected_ray` built on the student's `reflect`).
    Reflect,
    /// Exercise 4.2.
    ReflectedRay,
    /// Exercise 4.3 (through the base's `refracted_ray` built on the student's `interface`).
    Interface,
    /// Exercise 4.4 (through the base's `refracted_ray` built on the student's `refract`).
    Refract,
    /// Exercise 4.5.
    RefractedRay,
    /// Exercise 4.6.
    Phong,
}

/// The scenes of lab 04's snapshots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shot {
    /// The built-in default scene: a mirror sphere, a glass sphere, a Phong torus.
    Default,
    /// The built-in Cornell box with a mirror and a glass sphere, lit by its point light only.
    CornellSpheres,
    /// The default scene with the glass sphere made glossy (illum 5, the worksheet's
    /// "combining it all": 0.1 Phong + 0.1 reflection + 0.9 refraction).
    Glossy,
    /// Two facing mirrors ([`TWO_MIRRORS_SCENE`]): the depth limit at work.
    TwoMirrors,
}

impl Shot {
    /// Every snapshot scene.
    pub const ALL: [Shot; 4] = [
        Shot::Default,
        Shot::CornellSpheres,
        Shot::Glossy,
        Shot::TwoMirrors,
    ];
}

impl SnapshotScene for Shot {
    fn name(self) -> &'static str {
        match self {
            Shot::Default => "default",
            Shot::CornellSpheres => "cornell-spheres",
            Shot::Glossy => "default-glossy",
            Shot::TwoMirrors => "two-mirrors",
        }
    }

    fn scene(self) -> Result<Scene, raylab_core::Error> {
        match self {
            Shot::Default => builtin_scene("default"),
            Shot::CornellSpheres => {
                let mut scene = builtin_scene("cornell-spheres")?;
                scene.lights.retain(|l| !matches!(l, Light::Area(_)));
                Ok(scene)
            }
            Shot::Glossy => glossy_default_scene(),
            Shot::TwoMirrors => parse_scene_str("two-mirrors", TWO_MIRRORS_SCENE, Path::new(".")),
        }
    }
}

impl PartSnapshots for Part {
    type Contract = dyn Reflection;
    type Shot = Shot;

    const PARTS: &'static [(Part, &'static [Shot])] = &[
        // The renderer reaches `reflect`, `interface` and `refract` only through the student's
        // `reflected_ray` and `refracted_ray` (Exercises 4.2 and 4.5), whose images check them
        // together; composing them here would put those exercises' answers in the checks.
        (Part::Reflect, &[]),
        (Part::ReflectedRay, &[Shot::Default, Shot::TwoMirrors]),
        (Part::Interface, &[]),
        (Part::Refract, &[]),
        (
            Part::RefractedRay,
            &[Shot::Default, Shot::CornellSpheres, Shot::Glossy],
        ),
        (Part::Phong, &[Shot::Default, Shot::Glossy]),
    ];
    const SETTINGS: RenderSettings = SNAPSHOT_SETTINGS;
    const MAX_DEPTH: u32 = SNAPSHOT_MAX_DEPTH;
    const TOLERANCE: PixelTolerance = SNAPSHOT_TOLERANCE;

    fn function(self) -> &'static str {
        match self {
            Part::Reflect => "reflect",
            Part::ReflectedRay => "reflected_ray",
            Part::Interface => "interface",
            Part::Refract => "refract",
            Part::RefractedRay => "refracted_ray",
            Part::Phong => "shade_phong",
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The checks

/// The law of reflection as a relation between `ω`, the unit `n` and the answer `r`: `r` is a
/// unit vector in the plane of incidence, at the angle of incidence on the other side of the
/// normal (`r·n = −ω·n`), with the part of `ω` along the surface unchanged.
fn check_law_of_reflection(call: &str, w: Vec3, n: Vec3, r: Vec3) -> Result<(), String> {
    unit(call, r)?;
    let (wd, nd, rd) = (w.as_dvec3(), n.as_dvec3(), r.as_dvec3());
    if (rd.dot(nd) + wd.dot(nd)).abs() > 1e-4 {
        return Err(format!(
            "{call} is {r}: the angle of reflection differs from the angle of incidence (r·n = {:.5}, expected −ω·n = {:.5})",
            rd.dot(nd),
            -wd.dot(nd)
        ));
    }
    let out_of_plane = rd.dot(wd.cross(nd));
    if out_of_plane.abs() > 1e-4 {
        return Err(format!(
            "{call} is {r}: not in the plane of incidence of ω and n (r·(ω×n) = {out_of_plane:.5})"
        ));
    }
    let (tangent_w, tangent_r) = (wd - wd.dot(nd) * nd, rd - rd.dot(nd) * nd);
    if (tangent_w - tangent_r).length() > 1e-4 {
        return Err(format!(
            "{call} is {r}: the part of ω along the surface must stay as it is (only the normal part flips); it is {} instead of {}",
            tangent_r.as_vec3(),
            tangent_w.as_vec3()
        ));
    }
    Ok(())
}

fn exercise_4_1(s: &Arc<dyn Reflection>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Reflection>();
    for_all(500, (unit_vector(), unit_vector()), |(w, n)| {
        let call = format!("reflect(ω = {w}, n = {n})");
        let r = s.reflect(w, n);
        check_law_of_reflection(&call, w, n, r)?;
        let back = s.reflect(r, n);
        compare_vec3(
            &format!("reflect(reflect(ω, n), n) for ω = {w}, n = {n}"),
            back,
            w,
            2e-4,
            0.0,
        )
        .map_err(|e| format!("{e}: reflecting twice must give ω back"))?;
        match &key {
            Some(key) => compare_vec3(&call, r, key.reflect(w, n), 1e-5, 0.0),
            None => Ok(()),
        }
    })?;
    let golden: GoldenFile<ReflectInput, Vec3> = ctx.golden(GOLDEN_REFLECT)?;
    for case in &golden.cases {
        let (w, n) = case.input;
        compare_vec3(
            &format!("reflect(ω = {w}, n = {n})"),
            s.reflect(w, n),
            case.expected,
            1e-5,
            0.0,
        )?;
    }
    Ok(())
}

/// A hit with a shading normal near its geometric normal (as on a smooth mesh) or equal to it
/// (as on a sphere), and a direction arriving from the front.
fn front_hit_strategy() -> impl Strategy<Value = (Hit, Vec3, f32)> {
    (
        point(5.0),
        unit_vector(),
        point(0.25),
        any::<bool>(),
        unit_vector(),
        0.5f32..10.0,
        index_strategy(),
    )
        .prop_filter_map(
            "a smooth normal and a front-facing direction",
            |(p, g, bend, smooth, w, distance, ior)| {
                let shading = if smooth {
                    (g + bend).try_normalize()?
                } else {
                    g
                };
                let w = unit_with_cosine(shading, w, -1.0, -0.05)?;
                (w.dot(g) < -0.05).then_some((hit_at(p, g, shading, ior), w, distance))
            },
        )
}

fn exercise_4_2(s: &Arc<dyn Reflection>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Reflection>();
    for_all(300, front_hit_strategy(), |(hit, w, distance)| {
        let ray = incoming_ray(hit.position, w, distance);
        let call = format!(
            "reflected_ray(ray from {} along {w} over [{}, {}], hit at {} with shading normal {} and geometric normal {})",
            ray.origin, ray.tmin, ray.tmax, hit.position, hit.shading_normal, hit.geometric_normal
        );
        let got = s.reflected_ray(&ray, &hit);
        let hint = "the mirror direction of ω about the shading normal";
        let expected = key.as_ref().map(|k| k.reflected_ray(&ray, &hit).direction);
        check_secondary_ray(&call, &got, hit.position, expected, "reflected", hint)?;
        check_law_of_reflection(
            &format!("the direction of {call}"),
            w,
            hit.shading_normal,
            got.direction,
        )
        .map_err(|e| format!("{e} ({hint})"))
    })?;
    Part::ReflectedRay.check_snapshots(s, ctx)
}

fn side_call(f: &str, (w, n, hit_ior, material_ior): SideInput) -> String {
    let case = if w.dot(n) < 0.0 {
        "ω·n < 0: the ray enters the material"
    } else {
        "ω·n > 0: the ray leaves the material"
    };
    format!(
        "{f}(ω = {w}, hit with shading normal n = {n} and hit.ior = {hit_ior}, material_ior = {material_ior}) ({case})"
    )
}

fn side_hit((_, n, hit_ior, _): SideInput) -> Hit {
    hit_at(Vec3::new(0.5, -1.0, 2.0), n, n, hit_ior)
}

/// What an interface must satisfy whatever the answer: its normal is the shading normal,
/// possibly flipped, facing the incoming ray, and `η₁` is the index of the medium the ray
/// travels in (the strategies' `hit.ior`, which is the material's own when the ray leaves).
fn check_interface_relations(call: &str, input: SideInput, got: Interface) -> Result<(), String> {
    let (w, n, hit_ior, _) = input;
    let flips = (got.normal - n).length() > 1e-6 && (got.normal + n).length() > 1e-6;
    if flips || got.normal.dot(w) > 0.0 || !got.normal.is_finite() {
        return Err(format!(
            "the normal of {call} is {}: it must be the shading normal n = {n} or −n, whichever faces the incoming ray (normal·ω ≤ 0; flipped when the ray leaves)",
            got.normal
        ));
    }
    compare_f32(
        &format!("η₁ (eta_incident) of {call}"),
        got.eta_incident,
        hit_ior,
        1e-6,
        0.0,
    )
    .map_err(|e| format!("{e}: η₁ is the index of the medium the ray travels in"))
}

fn exercise_4_3(s: &Arc<dyn Reflection>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Reflection>();
    for_all(400, side_strategy(), |input| {
        let (w, _, _, material_ior) = input;
        let hit = side_hit(input);
        let call = side_call("interface", input);
        let got = s.interface(w, &hit, material_ior);
        check_interface_relations(&call, input, got)?;
        match &key {
            Some(key) => check_interface(&call, got, key.interface(w, &hit, material_ior)),
            None => Ok(()),
        }
    })?;
    // The shading normal decides and is the one flipped, not the geometric normal.
    for_all(300, bent_side_strategy(), |(input, g, p)| {
        let (w, n, hit_ior, material_ior) = input;
        let hit = hit_at(p, g, n, hit_ior);
        let call = format!(
            "{} (at {p}, geometric normal {g})",
            side_call("interface", input)
        );
        let got = s.interface(w, &hit, material_ior);
        check_interface_relations(&call, input, got)?;
        match &key {
            Some(key) => check_interface(&call, got, key.interface(w, &hit, material_ior)),
            None => Ok(()),
        }
    })?;
    // Where the two normals disagree about the side the ray comes from, the shading normal
    // decides, and the normal returned faces the ray.
    for_all(300, split_side_strategy(), |(input, g, p)| {
        let (w, n, hit_ior, material_ior) = input;
        let hit = hit_at(p, g, n, hit_ior);
        let call = format!(
            "{} (at {p}, geometric normal {g}: ω·g = {:.4} and ω·n = {:.4} differ in sign, as near the silhouette of a smooth mesh, and the shading normal decides)",
            side_call("interface", input),
            w.dot(g),
            w.dot(n)
        );
        let got = s.interface(w, &hit, material_ior);
        check_interface_relations(&call, input, got)?;
        match &key {
            Some(key) => check_interface(&call, got, key.interface(w, &hit, material_ior)),
            None => Ok(()),
        }
    })?;
    let golden: GoldenFile<SideInput, Interface> = ctx.golden(GOLDEN_INTERFACE)?;
    for case in &golden.cases {
        let (w, _, _, material_ior) = case.input;
        check_interface(
            &side_call("interface", case.input),
            s.interface(w, &side_hit(case.input), material_ior),
            case.expected,
        )?;
    }
    Ok(())
}

fn refract_call(&(w, n, eta_i, eta_t): &RefractInput) -> String {
    format!("refract(ω = {w}, n = {n}, η₁ = {eta_i}, η₂ = {eta_t})")
}

/// Whether an input of Exercise 4.4 is clear of the critical angle (0.1%).
pub fn refract_is_clear(w: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> bool {
    !near_critical(w, n, eta_i, eta_t, 1e-3)
}

fn exercise_4_4(s: &Arc<dyn Reflection>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Reflection>();
    let key_refract =
        |(w, n, ei, et): RefractInput| key.as_ref().and_then(|k| k.refract(w, n, ei, et));
    let clear = refract_strategy().prop_filter("not at the critical angle", |&(w, n, ei, et)| {
        refract_is_clear(w, n, ei, et)
    });
    for_all(500, clear, |input| {
        let (w, n, ei, et) = input;
        check_refraction(
            &refract_call(&input),
            input,
            s.refract(w, n, ei, et),
            snell_has_solution(w, n, ei, et),
            key_refract(input),
        )
    })?;
    // Total internal reflection sets in exactly at the critical angle: just below it the ray
    // refracts (grazing the surface), just above it there is no refracted ray.
    let pairs = (
        unit_vector(),
        unit_vector(),
        1.2f32..2.5,
        prop_oneof![Just(1.0f32), 1.0f32..1.1],
        any::<bool>(),
    );
    for_all(300, pairs, |(n, v, ei, et, above)| {
        let critical = et / ei;
        let (sin_i, side) = if above {
            (critical * 1.002, "just past")
        } else {
            (critical * 0.998, "just below")
        };
        let Some(w) = direction_at(n, v, sin_i) else {
            return Ok(());
        };
        let input = (w, n, ei, et);
        check_refraction(
            &format!(
                "{} ({side} the critical angle θ_c = asin(η₂/η₁) = {:.3}°)",
                refract_call(&input),
                critical.asin().to_degrees()
            ),
            input,
            s.refract(w, n, ei, et),
            !above,
            key_refract(input),
        )
    })?;
    let golden: GoldenFile<RefractInput, Option<Vec3>> = ctx.golden(GOLDEN_REFRACT)?;
    for case in &golden.cases {
        let (w, n, ei, et) = case.input;
        check_refraction(
            &refract_call(&case.input),
            case.input,
            s.refract(w, n, ei, et),
            case.expected.is_some(),
            case.expected,
        )?;
    }
    Ok(())
}

/// Checks `refracted_ray` on `input` at `hit` (whose shading normal is the input's `n`)
/// arriving from `distance` away. `expected` is the known
/// answer, if any (the key's or a golden case's: the direction and the index of the medium
/// entered, `None` for total internal reflection); whatever it is, a refracted ray must start
/// at the hit, cross to the far side of the surface in the plane of incidence, and obey
/// Snell's law from the medium the ray travels in (`hit.ior`) into the one it returns.
fn check_refracted_ray(
    s: &dyn Reflection,
    input: SideInput,
    hit: &Hit,
    distance: f32,
    expected: Option<Option<(Vec3, f32)>>,
) -> Result<(), String> {
    let (w, n, hit_ior, material_ior) = input;
    let ray = incoming_ray(hit.position, w, distance);
    let case = if w.dot(n) < 0.0 {
        "entering"
    } else {
        "leaving"
    };
    let call = format!(
        "refracted_ray(ray along {w} over [{}, {}], hit at {} with shading normal {n}, geometric normal {} and hit.ior = {hit_ior}, material_ior = {material_ior}) ({case})",
        ray.tmin, ray.tmax, hit.position, hit.geometric_normal
    );
    let got = s.refracted_ray(&ray, hit, material_ior);
    let hint = "refracted by Snell's law through the normal facing the ray, from η₁ into η₂";
    let (r, ior) = match (got, expected) {
        (None, None | Some(None)) => return Ok(()),
        (None, Some(Some(_))) => {
            return Err(format!(
                "{call} returned None (total internal reflection), but the ray refracts"
            ));
        }
        (Some((r, _)), Some(None)) => {
            return Err(format!(
                "{call} returned a ray along {}, but the ray is past the critical angle: total internal reflection, expected None",
                r.direction
            ));
        }
        (Some(got), _) => got,
    };
    let direction = expected.flatten().map(|(d, _)| d);
    check_secondary_ray(&call, &r, hit.position, direction, "refracted", hint)?;
    if let Some((_, eta_t)) = expected.flatten() {
        compare_f32(
            &format!("the index of refraction returned by {call}"),
            ior,
            eta_t,
            1e-6,
            0.0,
        )
        .map_err(|e| {
            format!(
                "{e}: the refracted ray travels in the medium it enters (material_ior when entering, 1 when leaving)"
            )
        })?;
    }
    let what = format!("the direction of {call}");
    let (wd, nd, td) = (w.as_dvec3(), n.as_dvec3(), r.direction.as_dvec3());
    if td.dot(nd) * wd.dot(nd) <= 0.0 {
        return Err(format!(
            "{what} is {}, on the incident side of the surface: the refracted ray continues through it",
            r.direction
        ));
    }
    let out_of_plane = td.dot(wd.cross(nd).normalize_or_zero());
    if out_of_plane.abs() > 1e-4 {
        return Err(format!(
            "{what} is {}: not in the plane of incidence of ω and n (t·(ω×n)/|ω×n| = {out_of_plane:.5})",
            r.direction
        ));
    }
    let (before, after) = (
        hit_ior as f64 * sine(wd, nd),
        ior as f64 * sine(td.normalize(), nd),
    );
    if !ior.is_finite() || (before - after).abs() > 2e-4 * ior.abs() as f64 {
        return Err(format!(
            "{what} is {} with the index {ior} returned for the medium it enters: Snell's law η₁ sin θ₁ = η₂ sin θ₂ does not hold from the medium the ray travels in (η₁ = hit.ior = {hit_ior}: η₁ sin θ₁ = {before:.5}, η₂ sin θ₂ = {after:.5}) ({hint})",
            r.direction
        ));
    }
    Ok(())
}

/// Whether an input of Exercises 4.3 and 4.5 is clear of the critical angle (0.1%) of both
/// interfaces it may be read as: from `hit.ior` into the material, and from the material
/// into air.
pub fn side_is_clear(input: &SideInput) -> bool {
    let (w, n, hit_ior, material_ior) = *input;
    !near_critical(w, n, hit_ior, material_ior, 1e-3)
        && !near_critical(w, n, material_ior, 1.0, 1e-3)
}

fn exercise_4_5(s: &Arc<dyn Reflection>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Reflection>();
    let strategy = (
        side_strategy().prop_filter("clear of the critical angle", side_is_clear),
        0.5f32..10.0,
    );
    let judge = |input: SideInput, hit: Hit, distance: f32| {
        let expected = key.as_ref().map(|k| {
            let (w, _, _, material_ior) = input;
            k.refracted_ray(&incoming_ray(hit.position, w, distance), &hit, material_ior)
                .map(|(r, ior)| (r.direction, ior))
        });
        check_refracted_ray(s.as_ref(), input, &hit, distance, expected)
    };
    for_all(400, strategy, |(input, distance)| {
        judge(input, side_hit(input), distance)
    })?;
    // Refracted about the shading normal where it is tilted from the geometric normal, at hits
    // from the origin to thousands of units away.
    let bent = (
        bent_side_strategy().prop_filter("clear of the critical angle", |(input, ..)| {
            side_is_clear(input)
        }),
        0.5f32..10.0,
    );
    for_all(300, bent, |((input, g, p), distance)| {
        let (_, n, hit_ior, _) = input;
        judge(input, hit_at(p, g, n, hit_ior), distance)
    })?;
    // Where the two normals disagree about the side the ray comes from, the shading normal
    // decides.
    let split = (
        split_side_strategy().prop_filter("clear of the critical angle", |(input, ..)| {
            side_is_clear(input)
        }),
        0.5f32..10.0,
    );
    for_all(300, split, |((input, g, p), distance)| {
        let (w, n, hit_ior, _) = input;
        judge(input, hit_at(p, g, n, hit_ior), distance).map_err(|e| {
            format!(
                "{e} [ω·g = {:.4} and ω·n = {:.4} differ in sign, as near the silhouette of a smooth mesh: the shading normal decides whether the ray enters or leaves]",
                w.dot(g),
                w.dot(n)
            )
        })
    })?;
    let golden: GoldenFile<SideInput, Option<(Vec3, f32)>> = ctx.golden(GOLDEN_REFRACTED_RAY)?;
    for case in &golden.cases {
        let hit = side_hit(case.input);
        check_refracted_ray(s.as_ref(), case.input, &hit, 2.0, Some(case.expected))?;
    }
    Part::RefractedRay.check_snapshots(s, ctx)
}

fn phong_call(
    rho_d: Vec3,
    rho_s: Vec3,
    s: f32,
    n: Vec3,
    v: Vec3,
    lights: &[(Vec3, Vec3)],
) -> String {
    format!(
        "shade_phong(ρ_d = {rho_d}, ρ_s = {rho_s}, s = {s}, n = {n}, v = {v}, lights (direction, radiance) = {lights:?})"
    )
}

const PEAK_HINT: &str =
    "the highlight peaks at the mirror direction r, and the factor (s+2)/(2π) normalizes the lobe";
const CLAMP_HINT: &str =
    "a negative r·v raised to a fractional power is NaN: the highlight is max(0, r·v)^s";

fn exercise_4_6(s: &Arc<dyn Reflection>, ctx: &LabContext) -> Result<(), String> {
    let phong = |rho_d, rho_s, sh, n, v, lights: &[(Vec3, Vec3)]| {
        s.shade_phong(rho_d, rho_s, sh, n, v, &samples_of(lights))
    };
    // No light, no light from below: nothing is reflected.
    for_all(
        200,
        (
            colour(1.0),
            colour(1.0),
            shininess_strategy(),
            unit_vector(),
            unit_vector(),
            unit_vector(),
            colour(5.0),
        ),
        |(rho_d, rho_s, sh, n, v, w, l)| {
            let call = phong_call(rho_d, rho_s, sh, n, v, &[]);
            let got = phong(rho_d, rho_s, sh, n, v, &[]);
            if got != Vec3::ZERO {
                return Err(format!(
                    "{call} is {got}: without lights nothing is reflected"
                ));
            }
            let Some(below) = unit_with_cosine(n, w, -1.0, -1e-3) else {
                return Ok(());
            };
            let lights = [(below, l)];
            let call = phong_call(rho_d, rho_s, sh, n, v, &lights);
            let got = phong(rho_d, rho_s, sh, n, v, &lights);
            if got.abs().max_element() > 1e-7 {
                return Err(format!(
                    "{call} is {got}: light from below the surface (n·ω_i = {:.4} < 0) must contribute nothing",
                    n.dot(below)
                ));
            }
            Ok(())
        },
    )?;
    // The highlight: with ρ_d = 0 it peaks in the mirror direction r of −ω_i at exactly
    // ρ_s·(s+2)/(2π)·L·cos θ_i, is no larger anywhere else, and vanishes where r·v ≤ 0.
    for_all(
        300,
        (
            colour(1.0),
            shininess_strategy(),
            unit_vector(),
            unit_vector(),
            unit_vector(),
            colour(5.0),
        ),
        |(rho_s, sh, n, w, v, l)| {
            let (Some(w), Some(v)) = (
                unit_with_cosine(n, w, 0.05, 1.0),
                unit_with_cosine(n, v, 0.02, 1.0),
            ) else {
                return Ok(());
            };
            let lights = [(w, l)];
            // The view at the light's angle on the other side of the normal: the same normal
            // part, the opposite tangential part.
            let r = (n.dot(w) * n - (w - n.dot(w) * n)).normalize();
            let peak = phong(Vec3::ZERO, rho_s, sh, n, r, &lights);
            let expected = rho_s * (sh + 2.0) / (2.0 * std::f32::consts::PI) * l * n.dot(w);
            let call = phong_call(Vec3::ZERO, rho_s, sh, n, r, &lights);
            compare_vec3(
                &format!("{call} (the view is the mirror direction of the light)"),
                peak,
                expected,
                1e-5,
                1e-3,
            )
            .map_err(|e| format!("{e} = ρ_s·(s+2)/(2π)·L·cos θ_i: {PEAK_HINT}"))?;
            let got = phong(Vec3::ZERO, rho_s, sh, n, v, &lights);
            let call = phong_call(Vec3::ZERO, rho_s, sh, n, v, &lights);
            finite(&call, got).map_err(|e| format!("{e} ({CLAMP_HINT})"))?;
            if r.dot(v) < -1e-3 && got.abs().max_element() > 1e-6 {
                return Err(format!(
                    "{call} is {got}: the view is more than 90° from the mirror direction r (r·v = {:.4}), so max(0, r·v)^s = 0 and there is no highlight",
                    r.dot(v)
                ));
            }
            if got.cmpgt(peak * (1.0 + 1e-4) + Vec3::splat(1e-6)).any() {
                return Err(format!(
                    "{call} is {got}, brighter than at the mirror direction ({peak}): the highlight must peak where v = r"
                ));
            }
            Ok(())
        },
    )?;
    // Lights add up, and so do the diffuse and glossy terms.
    for_all(300, phong_strategy(), |(rho_d, rho_s, sh, n, v, lights)| {
        let all = phong(rho_d, rho_s, sh, n, v, &lights);
        let call = phong_call(rho_d, rho_s, sh, n, v, &lights);
        let one_by_one: Vec3 = lights
            .iter()
            .map(|l| phong(rho_d, rho_s, sh, n, v, std::slice::from_ref(l)))
            .sum();
        compare_vec3(
            &format!("{call} (the sum over the lights, each shaded alone, is {one_by_one})"),
            all,
            one_by_one,
            1e-5,
            1e-3,
        )
        .map_err(|e| format!("{e}: the reflected radiance is a sum over the lights"))?;
        let parts = phong(rho_d, Vec3::ZERO, sh, n, v, &lights)
            + phong(Vec3::ZERO, rho_s, sh, n, v, &lights);
        compare_vec3(
            &format!("{call} (the diffuse part with ρ_s = 0 plus the glossy part with ρ_d = 0 is {parts})"),
            all,
            parts,
            1e-5,
            1e-3,
        )
        .map_err(|e| format!("{e}: the model is ρ_d/π + ρ_s·(s+2)/(2π)·max(0, r·v)^s, a sum of the two lobes"))
    })?;
    if let Some(key) = ctx.key_code::<dyn Reflection>() {
        for_all(400, phong_strategy(), |(rho_d, rho_s, sh, n, v, lights)| {
            compare_vec3(
                &phong_call(rho_d, rho_s, sh, n, v, &lights),
                phong(rho_d, rho_s, sh, n, v, &lights),
                key.shade_phong(rho_d, rho_s, sh, n, v, &samples_of(&lights)),
                1e-5,
                1e-3,
            )
        })?;
    }
    let golden: GoldenFile<PhongInput, Vec3> = ctx.golden(GOLDEN_PHONG)?;
    for case in &golden.cases {
        let (rho_d, rho_s, sh, n, v, lights) = &case.input;
        compare_vec3(
            &phong_call(*rho_d, *rho_s, *sh, *n, *v, lights),
            phong(*rho_d, *rho_s, *sh, *n, *v, lights),
            case.expected,
            1e-5,
            1e-3,
        )?;
    }
    Part::Phong.check_snapshots(s, ctx)
}
