//! Lab 02's exercises and their checks.

use std::sync::Arc;

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use contracts::lab02::{Intersection, Lab02, LightSample, Shading, SurfaceHit, TriangleHit};
pub use grading::radiometry::samples_of;
use grading::strategies::{point, scale, triangle_strategy, unit_vector};
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, compare_f32, compare_vec3, for_all,
};
use pipeline::builtin::BuiltinIntersection;
use pipeline::render::render;
use pipeline::{PartSlot, Pipeline, View};
use raylab_core::film::Film;
use raylab_core::math::Ray;
use raylab_core::render::RenderSettings;
use raylab_core::scene::{DirectionalLight, MaterialId, Plane, PointLight, Sphere, builtin_scene};

/// Golden file of Exercise 2.1.
pub const GOLDEN_PLANE: &str = "intersect_plane.json";
/// Golden file of Exercise 2.2.
pub const GOLDEN_TRIANGLE: &str = "intersect_triangle.json";
/// Golden file of Exercise 2.3.
pub const GOLDEN_SPHERE: &str = "intersect_sphere.json";
/// Golden file of Exercise 2.4.
pub const GOLDEN_POINT_LIGHT: &str = "sample_point_light.json";
/// Golden file of Exercise 2.5.
pub const GOLDEN_DIRECTIONAL_LIGHT: &str = "sample_directional_light.json";
/// Golden file of Exercise 2.6.
pub const GOLDEN_LAMBERTIAN: &str = "shade_lambertian.json";
/// Size and sampling of lab 02's snapshots.
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(2);

/// Which student function a snapshot exercises; the rest of the pipeline is the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 2.1.
    Plane,
    /// Exercise 2.2.
    Triangle,
    /// Exercise 2.3.
    Sphere,
    /// Exercise 2.4.
    PointLight,
    /// Exercise 2.5.
    DirectionalLight,
    /// Exercise 2.6.
    Lambertian,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`]).
    pub fn function(self) -> &'static str {
        match self {
            Part::Plane => "intersect_plane",
            Part::Triangle => "intersect_triangle",
            Part::Sphere => "intersect_sphere",
            Part::PointLight => "sample_point_light",
            Part::DirectionalLight => "sample_directional_light",
            Part::Lambertian => "shade_lambertian",
        }
    }
}

impl Part {
    /// Every part, with its snapshot's name, scene and view (parts that share a scene and a
    /// view share the snapshot: the reference renders it the same way).
    pub const ALL: [(Part, &'static str, &'static str, View); 6] = [
        (Part::Plane, "default-normals", "default", View::Normals),
        (Part::Triangle, "default-normals", "default", View::Normals),
        (Part::Sphere, "default-normals", "default", View::Normals),
        (Part::PointLight, "cornell-shaded", "cornell", View::Shaded),
        (
            Part::DirectionalLight,
            "default-shaded",
            "default",
            View::Shaded,
        ),
        (Part::Lambertian, "default-shaded", "default", View::Shaded),
    ];
}

/// Input of the intersection golden cases: ray origin, direction, tmin, tmax, primitive.
pub type RayInput = (Vec3, Vec3, f32, f32);
/// Input of Exercise 2.5: the light's direction, its emission, the shaded point.
pub type DirectionalLightInput = (Vec3, Vec3, Vec3);
/// Input of Exercise 2.4: light position, intensity, surface point.
pub type PointLightInput = (Vec3, Vec3, Vec3);
/// Input of Exercise 2.6: ρ_d, normal, light samples (direction, radiance).
pub type LambertianInput = (Vec3, Vec3, Vec<(Vec3, Vec3)>);

/// This lab.
pub const LAB: course::LabId = course::LabId::of(2);

/// The exercises of lab 02 (`labs/lab02/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Lab02>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_2_1,
            exercise_2_2,
            exercise_2_3,
            exercise_2_4,
            exercise_2_5,
            exercise_2_6
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Inputs

/// A ray over `[tmin, tmax]`.
pub fn ray(r: &RayInput) -> Ray {
    Ray::new(r.0, r.1, r.2, r.3)
}

/// A random plane through a point near the origin.
pub fn plane_strategy() -> impl Strategy<Value = Plane> + Clone {
    (point(3.0), unit_vector()).prop_map(|(p, n)| Plane::new(p, n, MaterialId(0)))
}

/// A random sphere.
pub fn sphere_strategy() -> impl Strategy<Value = Sphere> + Clone {
    (point(3.0), 0.2f32..3.0).prop_map(|(center, radius)| Sphere {
        center,
        radius,
        material: MaterialId(0),
    })
}

/// A random ray from a point in the box `[-8, 8]³`, aimed near `target` (within `spread`),
/// with random tmin/tmax (mostly `[0, ∞)`-like, sometimes tight).
pub fn ray_towards(target: Vec3, spread: f32) -> impl Strategy<Value = RayInput> {
    (
        point(8.0),
        point(spread),
        0u8..4,
        0.0f32..12.0,
        0.0f32..12.0,
    )
        .prop_filter_map("origin away from target", move |(o, jitter, kind, a, b)| {
            let d = (target + jitter - o).try_normalize()?;
            let (tmin, tmax) = match kind {
                0 => (0.0, f32::MAX),
                1 => (a.min(b), a.max(b)),
                2 => (a, f32::MAX),
                _ => (1e-4, a.max(b)),
            };
            Some((o, d, tmin, tmax))
        })
}

/// The scales the intersection checks run each configuration at again — a mesh's triangles of
/// 10⁻⁴ scene units to a terrain of 10³ — and how far back the ray starts: where drawn (1), or
/// 100 times as far (a far-away camera). Lengths scale with the configuration, so the answer
/// is known; an absolute epsilon in the student's code shows up at one end or the other.
fn scale_strategy() -> impl Strategy<Value = (f32, f32)> + Clone {
    (scale(), any::<bool>()).prop_map(|(s, far)| (s, if far { 100.0 } else { 1.0 }))
}

/// The ray of a scaled configuration: it ends at `target` (a point of the scaled shape, in
/// double precision) and starts where `origin` was relative to `target_unscaled`, scaled by
/// `scale` and `far` times as far back. Returns the origin and unit direction as the check
/// passes them, and the distance from that origin to `target`.
fn scaled_ray(
    origin: Vec3,
    target_unscaled: Vec3,
    target: DVec3,
    scale: f32,
    far: f32,
) -> (Vec3, Vec3, f32) {
    let back = (origin - target_unscaled).as_dvec3() * f64::from(scale) * f64::from(far);
    let from = (target + back).as_vec3();
    let towards = target - from.as_dvec3();
    (from, towards.normalize().as_vec3(), towards.length() as f32)
}

fn triangle_point(t: &[Vec3; 3], beta: f32, gamma: f32) -> Vec3 {
    (1.0 - beta - gamma) * t[0] + beta * t[1] + gamma * t[2]
}

// ---------------------------------------------------------------------------------------------
// Comparisons

fn compare_surface_hit(
    call: &str,
    got: Option<SurfaceHit>,
    expected: Option<SurfaceHit>,
) -> Result<(), String> {
    compare_surface_hit_at(call, got, expected, 1.0)
}

/// [`compare_surface_hit`] for a configuration of size `unit`: `t` to `10⁻³·unit` plus
/// `10⁻³` relative.
fn compare_surface_hit_at(
    call: &str,
    got: Option<SurfaceHit>,
    expected: Option<SurfaceHit>,
    unit: f32,
) -> Result<(), String> {
    match (got, expected) {
        (None, None) => Ok(()),
        (Some(g), None) => Err(format!(
            "{call} returned a hit at t = {} but the ray misses (or the hit is outside [tmin, tmax])",
            g.distance
        )),
        (None, Some(e)) => Err(format!(
            "{call} returned no hit; expected a hit at t = {}",
            e.distance
        )),
        (Some(g), Some(e)) => {
            compare_f32(
                &format!("t of {call}"),
                g.distance,
                e.distance,
                1e-3 * unit,
                1e-3,
            )?;
            compare_vec3(
                &format!("the normal of {call}"),
                g.normal,
                e.normal,
                2e-3,
                0.0,
            )
        }
    }
}

fn compare_triangle_hit(
    call: &str,
    got: Option<TriangleHit>,
    expected: Option<TriangleHit>,
) -> Result<(), String> {
    compare_triangle_hit_at(call, got, expected, 1.0)
}

/// [`compare_triangle_hit`] for a configuration of size `unit`.
fn compare_triangle_hit_at(
    call: &str,
    got: Option<TriangleHit>,
    expected: Option<TriangleHit>,
    unit: f32,
) -> Result<(), String> {
    match (got, expected) {
        (None, None) => Ok(()),
        (Some(g), None) => Err(format!(
            "{call} returned a hit at t = {} (β = {}, γ = {}) but the ray misses the triangle or the hit is outside [tmin, tmax]",
            g.distance, g.beta, g.gamma
        )),
        (None, Some(e)) => Err(format!(
            "{call} returned no hit; expected a hit at t = {} (β = {}, γ = {})",
            e.distance, e.beta, e.gamma
        )),
        (Some(g), Some(e)) => {
            compare_f32(
                &format!("t of {call}"),
                g.distance,
                e.distance,
                1e-3 * unit,
                1e-3,
            )?;
            compare_f32(&format!("β of {call}"), g.beta, e.beta, 1e-3, 0.0)?;
            compare_f32(&format!("γ of {call}"), g.gamma, e.gamma, 1e-3, 0.0)?;
            compare_vec3(
                &format!("the normal of {call}"),
                g.normal,
                e.normal,
                2e-3,
                0.0,
            )
        }
    }
}

fn load<I, O>(ctx: &LabContext, name: &str) -> Result<GoldenFile<I, O>, String>
where
    I: serde::Serialize + serde::de::DeserializeOwned,
    O: serde::Serialize + serde::de::DeserializeOwned,
{
    ctx.golden(name)
}

// ---------------------------------------------------------------------------------------------
// Snapshots

/// The pipeline of one part's snapshot: `student` for that part only, `base` for the rest
/// (the framework's kernels where the base has no intersection code of its own).
pub fn part_pipeline(
    part: Part,
    student: &Arc<dyn Lab02>,
    base: &Pipeline,
    view: View,
) -> Pipeline {
    let isect: Arc<dyn Intersection> = student.clone();
    let shade: Arc<dyn Shading> = student.clone();
    let base_isect: Arc<dyn Intersection> = base
        .part::<dyn Intersection>()
        .unwrap_or_else(|| Arc::new(BuiltinIntersection));
    let intersection: Arc<dyn Intersection> =
        PartSlot::shared(part.function(), &isect, &base_isect);
    let shading: Arc<dyn Shading> =
        PartSlot::shared(part.function(), &shade, &base.code::<dyn Shading>());
    let mut pipeline = base.clone().with_part(intersection).with_part(shading);
    pipeline.view = view;
    pipeline
}

/// Renders one part's snapshot scene through `pipeline`.
pub fn render_part(part: Part, pipeline: &Pipeline) -> Result<Film, raylab_core::Error> {
    let (_, _, scene, _) = Part::ALL
        .iter()
        .find(|p| p.0 == part)
        .expect("every part is listed");
    render(&builtin_scene(scene)?, pipeline, &SNAPSHOT_SETTINGS)
}

fn check_part_snapshot(part: Part, s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    let (_, name, _, view) = *Part::ALL
        .iter()
        .find(|p| p.0 == part)
        .expect("every part is listed");
    let film =
        render_part(part, &part_pipeline(part, s, &ctx.base, view)).map_err(|e| e.to_string())?;
    let tol = PixelTolerance {
        abs: 2e-3,
        rel: 2e-3,
        max_outlier_fraction: 0.005,
    };
    ctx.check_snapshot(name, &film, &tol)
}

// ---------------------------------------------------------------------------------------------
// The exercises

/// A plane and a direction exactly parallel to it in floating point, with an origin: the
/// normal `(a, b, 0)` and the direction `(−b, a, 0)` or `(0, 0, ±1)`, their axes permuted, so
/// that every order of summing `ω·n` gives exactly zero; the origin off the plane, or (one
/// time in three) in it: the plane's own point, or the world origin on a plane through it.
pub fn parallel_strategy() -> impl Strategy<Value = (Plane, Vec3, Vec3)> {
    (
        0.0f32..std::f32::consts::TAU,
        0usize..3,
        0u8..4,
        point(3.0),
        point(8.0),
        0u8..3,
    )
        .prop_map(|(phi, axis, which, p, o, place)| {
            let rotate = |v: Vec3| match axis {
                0 => v,
                1 => Vec3::new(v.z, v.x, v.y),
                _ => Vec3::new(v.y, v.z, v.x),
            };
            let through = if place == 2 && which % 2 == 0 {
                Vec3::ZERO
            } else {
                p
            };
            let plane = Plane::new(
                through,
                rotate(Vec3::new(phi.cos(), phi.sin(), 0.0)),
                MaterialId(0),
            );
            let n = plane.normal;
            // In the rotated frame the normal's third component is exactly zero.
            let (a, b) = match axis {
                0 => (n.x, n.y),
                1 => (n.y, n.z),
                _ => (n.z, n.x),
            };
            let d = match which {
                0 => rotate(Vec3::new(-b, a, 0.0)),
                1 => rotate(Vec3::new(b, -a, 0.0)),
                2 => rotate(Vec3::Z),
                _ => rotate(Vec3::NEG_Z),
            };
            let origin = if place == 2 { through } else { o };
            (plane, origin, d)
        })
}

/// A plane and a grazing ray that hits it: `|ω·n|` log-uniform from 10⁻⁵ to 0.05, the hit
/// 0.5 to 5 units ahead, from either side.
pub fn grazing_strategy() -> impl Strategy<Value = (Plane, Vec3, Vec3)> {
    (
        plane_strategy(),
        point(3.0),
        0.0f32..std::f32::consts::TAU,
        -5.0f32..(0.05f32).log10(),
        any::<bool>(),
        0.5f32..5.0,
    )
        .prop_map(|(plane, q, alpha, log_cos, above, t)| {
            let target = q - (q.dot(plane.normal) + plane.d) * plane.normal;
            let cos = 10f32.powf(log_cos) * if above { -1.0 } else { 1.0 };
            let sin = (1.0 - cos * cos).sqrt();
            let d = (sin * (alpha.cos() * plane.tangent + alpha.sin() * plane.bitangent)
                + cos * plane.normal)
                .normalize();
            (plane, target - t * d, d)
        })
}

/// A grazing ray hits the plane where double precision says, within what single precision
/// allows.
fn check_grazing(s: &dyn Lab02, plane: &Plane, o: Vec3, d: Vec3) -> Result<(), String> {
    let n = plane.normal.as_dvec3();
    let (od, dd) = (o.as_dvec3(), d.as_dvec3());
    let cos = dd.dot(n);
    let t = -(od.dot(n) + f64::from(plane.d)) / cos;
    if t.is_nan() || t <= 0.1 {
        return Ok(());
    }
    let eps = f64::from(f32::EPSILON);
    let tol = 1e-3 * (1.0 + t)
        + 4.0 * eps * (od.length() + f64::from(plane.d.abs())) / cos.abs()
        + 4.0 * eps * t / cos.abs();
    let r = Ray::new(o, d, 0.0, f32::INFINITY);
    let call = format!(
        "intersect_plane(ray from {o} along {d} over [0, inf], plane n = {}, d = {}) (a grazing ray, ω·n = {cos:.3e})",
        plane.normal, plane.d
    );
    match s.intersect_plane(&r, plane) {
        None => Err(format!(
            "{call} returned no hit; expected a hit at t = {t}: only ω·n = 0 exactly is parallel — an epsilon on ω·n drops the rays that graze the plane, such as the ground near the horizon"
        )),
        Some(hit) if (f64::from(hit.distance) - t).abs() > tol => Err(format!(
            "{call} returned a hit at t = {}; expected t = {t} (to {tol:.1e}, the rounding of a grazing ray allowed for)",
            hit.distance
        )),
        Some(hit) => compare_vec3(
            &format!("the normal of {call}"),
            hit.normal,
            plane.normal,
            2e-3,
            0.0,
        ),
    }
}

/// A ray exactly parallel to `plane` misses it over `[0, ∞)`, and over `[0, 10⁵]`.
fn check_parallel(s: &dyn Lab02, plane: &Plane, o: Vec3, d: Vec3) -> Result<(), String> {
    let side = o.dot(plane.normal) + plane.d;
    let place = if side == 0.0 {
        "in the plane"
    } else {
        "off the plane"
    };
    for tmax in [f32::INFINITY, 1e5] {
        let r = Ray::new(o, d, 0.0, tmax);
        if let Some(hit) = s.intersect_plane(&r, plane) {
            return Err(format!(
                "intersect_plane(ray from {o} along {d} over [0, {tmax}], plane n = {}, d = {}) returned a hit at t = {}; the ray is parallel to the plane (ω·n = {}) and starts {place}, so it never hits it: return None when ω·n is zero, before dividing (−(o·n + d)/0 is ±∞, or NaN in the plane, and t = ∞ passes t ≤ tmax when tmax = ∞)",
                plane.normal,
                plane.d,
                hit.distance,
                d.dot(plane.normal)
            ));
        }
    }
    Ok(())
}

fn exercise_2_1(s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    // A ray aimed at a point of the plane hits it there, unless that point is outside [tmin, tmax].
    let strategy = (plane_strategy(), point(3.0), point(8.0)).prop_filter_map(
        "origin off the plane, ray not grazing",
        |(plane, q, o)| {
            let target = q - (q.dot(plane.normal) + plane.d) * plane.normal;
            let d = (target - o).try_normalize()?;
            (d.dot(plane.normal).abs() > 0.05 && (target - o).length() > 0.05)
                .then_some((plane, o, target, d))
        },
    );
    for_all(300, strategy.clone(), |(plane, o, target, d)| {
        let t = (target - o).length();
        let call = |r: &Ray| {
            format!(
                "intersect_plane(ray from {} along {} over [{}, {}], plane n = {}, d = {})",
                r.origin, r.direction, r.tmin, r.tmax, plane.normal, plane.d
            )
        };
        let r = Ray::new(o, d, 0.0, f32::INFINITY);
        let hit = s.intersect_plane(&r, &plane);
        let expected = Some(SurfaceHit {
            distance: t,
            normal: plane.normal,
        });
        compare_surface_hit(&call(&r), hit, expected)?;
        let r = Ray::new(o, d, t + 0.01, f32::INFINITY);
        compare_surface_hit(
            &format!("{} (the hit is before tmin)", call(&r)),
            s.intersect_plane(&r, &plane),
            None,
        )?;
        let r = Ray::new(o, d, 0.0, t - 0.01);
        compare_surface_hit(
            &format!("{} (the hit is beyond tmax)", call(&r)),
            s.intersect_plane(&r, &plane),
            None,
        )?;
        let r = Ray::new(o, -d, 0.0, f32::INFINITY);
        compare_surface_hit(
            &format!("{} (the plane is behind the ray)", call(&r)),
            s.intersect_plane(&r, &plane),
            None,
        )?;
        // A ray parallel to the plane never hits it (up to rounding: tmax keeps the far-away
        // "hit" that a rounded ω·n ≈ 1e-8 produces out of range).
        let parallel = plane.tangent;
        let r = Ray::new(o, parallel, 0.0, 1e5);
        compare_surface_hit(
            &format!("{} (parallel to the plane)", call(&r)),
            s.intersect_plane(&r, &plane),
            None,
        )
    })?;
    // Exactly parallel (ω·n = 0 in floating point) over [0, ∞): from off the plane `t` would
    // be ±∞ and from in it NaN, and `t = ∞` passes `t ≤ tmax = ∞`.
    for_all(200, parallel_strategy(), |(plane, o, d)| {
        check_parallel(s.as_ref(), &plane, o, d)
    })?;
    // Grazing rays, |ω·n| from 10⁻⁵ to 0.05: still hits (an epsilon on ω·n loses the far
    // ground at the horizon). The answer is worked out in double precision from the inputs as
    // given, and allowed the error that rounding ω·n and o·n + d in single precision causes.
    for_all(300, grazing_strategy(), |(plane, o, d)| {
        check_grazing(s.as_ref(), &plane, o, d)
    })?;
    // The same configurations at every scale, and from far away.
    for_all(
        300,
        (strategy, scale_strategy()),
        |((plane, o, target, _), (k, far))| {
            let point = target * k;
            let plane = Plane::new(point, plane.normal, plane.material);
            let (o, d, t) = scaled_ray(o, target, point.as_dvec3(), k, far);
            let call = |r: &Ray| {
                format!(
                    "intersect_plane(ray from {} along {} over [{}, {}], plane n = {}, d = {}) (a configuration at scale {k})",
                    r.origin, r.direction, r.tmin, r.tmax, plane.normal, plane.d
                )
            };
            let r = Ray::new(o, d, 0.0, f32::INFINITY);
            let expected = SurfaceHit {
                distance: t,
                normal: plane.normal,
            };
            compare_surface_hit_at(
                &call(&r),
                s.intersect_plane(&r, &plane),
                Some(expected),
                k * far,
            )?;
            let r = Ray::new(o, d, 0.0, 0.99 * t);
            compare_surface_hit_at(
                &format!("{} (the hit is beyond tmax)", call(&r)),
                s.intersect_plane(&r, &plane),
                None,
                k * far,
            )
        },
    )?;
    let golden: GoldenFile<(RayInput, Plane), Option<SurfaceHit>> = load(ctx, GOLDEN_PLANE)?;
    for case in &golden.cases {
        let (r, plane) = &case.input;
        let r = ray(r);
        compare_surface_hit(
            &format!(
                "intersect_plane(ray from {} along {} over [{}, {}], plane n = {}, d = {})",
                r.origin, r.direction, r.tmin, r.tmax, plane.normal, plane.d
            ),
            s.intersect_plane(&r, plane),
            case.expected,
        )?;
    }
    check_part_snapshot(Part::Plane, s, ctx)
}

fn exercise_2_2(s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    let inside = (
        triangle_strategy(),
        0.02f32..0.96,
        0.02f32..0.96,
        point(8.0),
    )
        .prop_filter_map("point inside, origin off the plane", |(t, b, g, o)| {
            let (b, g) = if b + g > 0.98 {
                (0.98 - b, 0.98 - g)
            } else {
                (b, g)
            };
            if b < 0.01 || g < 0.01 {
                return None;
            }
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
            let p = triangle_point(&t, b, g);
            let d = (p - o).try_normalize()?;
            (d.dot(n).abs() > 0.1 && (p - o).length() > 0.1).then_some((t, b, g, o, d))
        });
    for_all(300, inside.clone(), |(t, b, g, o, d)| {
        let dist = (triangle_point(&t, b, g) - o).length();
        let normal = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
        let call = |r: &Ray| {
            format!(
                "intersect_triangle(ray from {} along {} over [{}, {}], v0 = {}, v1 = {}, v2 = {})",
                r.origin, r.direction, r.tmin, r.tmax, t[0], t[1], t[2]
            )
        };
        let r = Ray::new(o, d, 0.0, f32::INFINITY);
        let expected = TriangleHit {
            distance: dist,
            beta: b,
            gamma: g,
            normal,
        };
        compare_triangle_hit(
            &call(&r),
            s.intersect_triangle(&r, t[0], t[1], t[2]),
            Some(expected),
        )?;
        let r = Ray::new(o, d, dist + 0.01, f32::INFINITY);
        compare_triangle_hit(
            &format!("{} (the hit is before tmin)", call(&r)),
            s.intersect_triangle(&r, t[0], t[1], t[2]),
            None,
        )?;
        let r = Ray::new(o, d, 0.0, dist - 0.01);
        compare_triangle_hit(
            &format!("{} (the hit is beyond tmax)", call(&r)),
            s.intersect_triangle(&r, t[0], t[1], t[2]),
            None,
        )?;
        let r = Ray::new(o, -d, 0.0, f32::INFINITY);
        compare_triangle_hit(
            &format!("{} (the triangle is behind the ray)", call(&r)),
            s.intersect_triangle(&r, t[0], t[1], t[2]),
            None,
        )
    })?;
    // The same configurations at every scale, and from far away.
    for_all(
        300,
        (inside, scale_strategy()),
        |((t, b, g, o, _), (k, far))| {
            let v = t.map(|v| v * k);
            let p = (1.0 - f64::from(b) - f64::from(g)) * v[0].as_dvec3()
                + f64::from(b) * v[1].as_dvec3()
                + f64::from(g) * v[2].as_dvec3();
            let (o, d, dist) = scaled_ray(o, triangle_point(&t, b, g), p, k, far);
            let call = |r: &Ray| {
                format!(
                    "intersect_triangle(ray from {} along {} over [{}, {}], v0 = {}, v1 = {}, v2 = {}) (a configuration at scale {k})",
                    r.origin, r.direction, r.tmin, r.tmax, v[0], v[1], v[2]
                )
            };
            let expected = TriangleHit {
                distance: dist,
                beta: b,
                gamma: g,
                normal: (v[1] - v[0]).cross(v[2] - v[0]).normalize(),
            };
            let r = Ray::new(o, d, 0.0, f32::INFINITY);
            compare_triangle_hit_at(
                &call(&r),
                s.intersect_triangle(&r, v[0], v[1], v[2]),
                Some(expected),
                k * far,
            )?;
            let r = Ray::new(o, d, 0.0, 0.99 * dist);
            compare_triangle_hit_at(
                &format!("{} (the hit is beyond tmax)", call(&r)),
                s.intersect_triangle(&r, v[0], v[1], v[2]),
                None,
                k * far,
            )
        },
    )?;
    // Points in the triangle's plane but outside it (β < 0, γ < 0 or β + γ > 1) are missed.
    let outside = (triangle_strategy(), -1.0f32..2.0, -1.0f32..2.0, point(8.0)).prop_filter_map(
        "point clearly outside, origin off the plane",
        |(t, b, g, o)| {
            let clearly_out = b < -0.05 || g < -0.05 || b + g > 1.05;
            let n = (t[1] - t[0]).cross(t[2] - t[0]).normalize();
            let p = triangle_point(&t, b, g);
            let d = (p - o).try_normalize()?;
            (clearly_out && d.dot(n).abs() > 0.1).then_some((t, b, g, o, d))
        },
    );
    for_all(300, outside, |(t, b, g, o, d)| {
        let r = Ray::new(o, d, 0.0, f32::INFINITY);
        compare_triangle_hit(
            &format!(
                "intersect_triangle(ray from {o} along {d}, v0 = {}, v1 = {}, v2 = {}) (the ray passes the plane at β = {b}, γ = {g}, outside the triangle)",
                t[0], t[1], t[2]
            ),
            s.intersect_triangle(&r, t[0], t[1], t[2]),
            None,
        )
    })?;
    let golden: GoldenFile<(RayInput, [Vec3; 3]), Option<TriangleHit>> =
        load(ctx, GOLDEN_TRIANGLE)?;
    for case in &golden.cases {
        let (r, t) = &case.input;
        let r = ray(r);
        compare_triangle_hit(
            &format!(
                "intersect_triangle(ray from {} along {} over [{}, {}], v0 = {}, v1 = {}, v2 = {})",
                r.origin, r.direction, r.tmin, r.tmax, t[0], t[1], t[2]
            ),
            s.intersect_triangle(&r, t[0], t[1], t[2]),
            case.expected,
        )?;
    }
    check_part_snapshot(Part::Triangle, s, ctx)
}

/// A ray along a chord of the sphere, its roots known by construction: the chord runs from
/// the surface point `c + r·a` to `c + r·b`, and the ray starts on its line, `k` before the
/// first point (outside) or (one time in four) a fraction of the way along it (inside).
/// Returns the sphere, the origin, the direction, the two roots (the nearer one negative
/// from inside) and the normals at them (`a` and `b`).
#[allow(clippy::type_complexity)]
fn sphere_chord_strategy() -> impl Strategy<Value = (Sphere, Vec3, Vec3, (f32, f32), (Vec3, Vec3))>
{
    (
        sphere_strategy(),
        unit_vector(),
        unit_vector(),
        0.1f32..8.0,
        0.0f32..1.0,
    )
        .prop_filter_map(
            "a chord that clearly crosses the sphere",
            |(sphere, a, b, k, inside)| {
                let (p1, p2) = (
                    sphere.center + sphere.radius * a,
                    sphere.center + sphere.radius * b,
                );
                let length = (p2 - p1).length();
                if length < 0.3 * sphere.radius {
                    return None;
                }
                let d = (p2 - p1) / length;
                if inside < 0.25 {
                    let along = 0.1 + 0.8 * inside / 0.25;
                    let o = p1 + along * length * d;
                    Some((
                        sphere,
                        o,
                        d,
                        (-along * length, (1.0 - along) * length),
                        (a, b),
                    ))
                } else {
                    Some((sphere, p1 - k * d, d, (k, k + length), (a, b)))
                }
            },
        )
}

fn exercise_2_3(s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    for_all(
        300,
        sphere_chord_strategy(),
        |(sphere, o, d, (near, far), (a, b))| {
            let call = |r: &Ray| {
                format!(
                    "intersect_sphere(ray from {} along {} over [{}, {}], sphere at {} radius {})",
                    r.origin, r.direction, r.tmin, r.tmax, sphere.center, sphere.radius
                )
            };
            let hit = |t: f32| {
                Some(SurfaceHit {
                    distance: t,
                    normal: if t == near { a } else { b },
                })
            };
            let r = Ray::new(o, d, 0.0, f32::INFINITY);
            let first = if near >= 0.0 {
                hit(near)
            } else if far >= 0.0 {
                hit(far)
            } else {
                None
            };
            let what = if near >= 0.0 {
                "(the near root)"
            } else {
                "(the ray starts inside: the far root)"
            };
            compare_surface_hit(
                &format!("{} {what}", call(&r)),
                s.intersect_sphere(&r, &sphere),
                first,
            )?;
            if near > 0.05 && far - near > 0.1 {
                let r = Ray::new(o, d, near + 0.01, f32::INFINITY);
                compare_surface_hit(
                    &format!("{} (tmin is past the near root: the far root)", call(&r)),
                    s.intersect_sphere(&r, &sphere),
                    hit(far),
                )?;
                let r = Ray::new(o, d, 0.0, near - 0.01);
                compare_surface_hit(
                    &format!("{} (both roots beyond tmax)", call(&r)),
                    s.intersect_sphere(&r, &sphere),
                    None,
                )?;
            }
            Ok(())
        },
    )?;
    // The same configurations at every scale. Not from far away: the quadratic's `c = |o −
    // c|² − r²` loses `r²` in single precision once the origin is thousands of radii away, for
    // the reference too (a robust form is beyond this lab).
    for_all(
        300,
        (sphere_chord_strategy(), scale_strategy()),
        |((sphere, o, d, (near, far_root), (a, b)), (k, _))| {
            let far = 1.0;
            let (t, normal) = if near >= 0.0 {
                (near, a)
            } else {
                (far_root, b)
            };
            let scaled = Sphere {
                center: sphere.center * k,
                radius: sphere.radius * k,
                material: sphere.material,
            };
            let target = scaled.center.as_dvec3() + f64::from(scaled.radius) * normal.as_dvec3();
            let (o, d, dist) = scaled_ray(o, o + t * d, target, k, far);
            let call = |r: &Ray| {
                format!(
                    "intersect_sphere(ray from {} along {} over [{}, {}], sphere at {} radius {}) (a configuration at scale {k})",
                    r.origin, r.direction, r.tmin, r.tmax, scaled.center, scaled.radius
                )
            };
            let r = Ray::new(o, d, 0.0, f32::INFINITY);
            let expected = SurfaceHit {
                distance: dist,
                normal,
            };
            compare_surface_hit_at(
                &call(&r),
                s.intersect_sphere(&r, &scaled),
                Some(expected),
                k * far,
            )
        },
    )?;
    let golden: GoldenFile<(RayInput, Sphere), Option<SurfaceHit>> = load(ctx, GOLDEN_SPHERE)?;
    for case in &golden.cases {
        let (r, sphere) = &case.input;
        let r = ray(r);
        compare_surface_hit(
            &format!(
                "intersect_sphere(ray from {} along {} over [{}, {}], sphere at {} radius {})",
                r.origin, r.direction, r.tmin, r.tmax, sphere.center, sphere.radius
            ),
            s.intersect_sphere(&r, sphere),
            case.expected,
        )?;
    }
    check_part_snapshot(Part::Sphere, s, ctx)
}

fn compare_light_sample(call: &str, got: LightSample, expected: LightSample) -> Result<(), String> {
    compare_vec3(
        &format!("the direction of {call}"),
        got.direction,
        expected.direction,
        1e-4,
        0.0,
    )?;
    if expected.distance.is_infinite() {
        if got.distance != f32::INFINITY {
            return Err(format!(
                "the distance of {call} is {}; a directional light is infinitely far away",
                got.distance
            ));
        }
    } else {
        compare_f32(
            &format!("the distance of {call}"),
            got.distance,
            expected.distance,
            1e-4,
            1e-4,
        )?;
    }
    compare_vec3(
        &format!("the radiance of {call}"),
        got.radiance,
        expected.radiance,
        1e-6,
        1e-4,
    )
}

/// The answer key's lab 02 shading, when the context holds it.
fn key_shading(ctx: &LabContext) -> Option<Arc<dyn Shading>> {
    ctx.key().map(|k| k.code::<dyn contracts::lab02::Shading>())
}

/// A light sample's direction is a unit vector, and `position + distance·direction` is the
/// light (for a point light).
fn check_points_at(call: &str, got: &LightSample, p: Vec3, light: Vec3) -> Result<(), String> {
    compare_f32(
        &format!("the length of the direction of {call}"),
        got.direction.length(),
        1.0,
        1e-4,
        0.0,
    )?;
    compare_vec3(
        &format!("point + distance·direction of {call}"),
        p + got.distance * got.direction,
        light,
        1e-3,
        1e-4,
    )
    .map_err(|e| {
        format!("{e}: the sample points from the shaded point to the light, which is distance away")
    })
}

fn exercise_2_4(s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    let key = key_shading(ctx);
    let strategy = (
        point(5.0),
        (0.0f32..100.0, 0.0f32..100.0, 0.0f32..100.0),
        point(5.0),
    )
        .prop_filter("light away from the point", |(l, _, p)| {
            (*l - *p).length() > 0.1
        });
    for_all(300, strategy, |(position, (r, g, b), p)| {
        let light = PointLight {
            position,
            intensity: Vec3::new(r, g, b),
        };
        let call = format!(
            "sample_point_light(light at {position} of intensity {}, point {p})",
            light.intensity
        );
        let got = s.sample_point_light(&light, p);
        check_points_at(&call, &got, p, position)?;
        // Twice as far away along the same line, a quarter of the radiance; twice the
        // intensity, twice the radiance.
        let far = position + 2.0 * (p - position);
        compare_vec3(
            &format!("the radiance of {call} at twice the distance, {far}"),
            s.sample_point_light(&light, far).radiance,
            0.25 * got.radiance,
            1e-6,
            1e-4,
        )
        .map_err(|e| format!("{e}: the inverse-square law, radiance ∝ 1/r²"))?;
        let brighter = PointLight {
            intensity: 2.0 * light.intensity,
            ..light
        };
        compare_vec3(
            &format!("the radiance of {call} with twice the intensity"),
            s.sample_point_light(&brighter, p).radiance,
            2.0 * got.radiance,
            1e-6,
            1e-4,
        )?;
        match &key {
            Some(key) => compare_light_sample(&call, got, key.sample_point_light(&light, p)),
            None => Ok(()),
        }
    })?;
    let golden: GoldenFile<PointLightInput, LightSample> = load(ctx, GOLDEN_POINT_LIGHT)?;
    for case in &golden.cases {
        let (position, intensity, p) = case.input;
        let light = PointLight {
            position,
            intensity,
        };
        compare_light_sample(
            &format!("sample_point_light(light at {position} of intensity {intensity}, point {p})"),
            s.sample_point_light(&light, p),
            case.expected,
        )?;
    }
    check_part_snapshot(Part::PointLight, s, ctx)
}

/// Inputs of Exercise 2.5.
pub fn directional_light_strategy() -> impl Strategy<Value = DirectionalLightInput> {
    (
        unit_vector(),
        (0.0f32..10.0, 0.0f32..10.0, 0.0f32..10.0),
        point(5.0),
    )
        .prop_map(|(direction, (r, g, b), p)| (direction, Vec3::new(r, g, b), p))
}

fn exercise_2_5(s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    let key = key_shading(ctx);
    let strategy = (directional_light_strategy(), point(5.0));
    for_all(300, strategy, |((direction, emission, p), q)| {
        let light = DirectionalLight {
            direction,
            emission,
        };
        let call = format!(
            "sample_directional_light(light along {direction} of emission {emission}, point {p})"
        );
        let got = s.sample_directional_light(&light, p);
        if got.distance != f32::INFINITY {
            return Err(format!(
                "the distance of {call} is {}; a directional light is infinitely far away",
                got.distance
            ));
        }
        compare_f32(
            &format!("the length of the direction of {call}"),
            got.direction.length(),
            1.0,
            1e-4,
            0.0,
        )?;
        compare_f32(
            &format!(
                "the cosine between the direction of {call} ({}) and the light's",
                got.direction
            ),
            got.direction.dot(direction),
            -1.0,
            1e-4,
            0.0,
        )
        .map_err(|e| format!("{e}: the sample points back where the light comes from"))?;
        compare_light_sample(
            &format!("{call} compared with the same light at the point {q}"),
            s.sample_directional_light(&light, q),
            got,
        )
        .map_err(|e| format!("{e}: a directional light is the same everywhere"))?;
        match &key {
            Some(key) => compare_light_sample(&call, got, key.sample_directional_light(&light, p)),
            None => Ok(()),
        }
    })?;
    // The golden cases hold the direction and radiance (the distance is infinite, which JSON
    // cannot hold, and the property above checks it).
    let golden: GoldenFile<DirectionalLightInput, (Vec3, Vec3)> =
        load(ctx, GOLDEN_DIRECTIONAL_LIGHT)?;
    for case in &golden.cases {
        let (direction, emission, p) = case.input;
        let light = DirectionalLight {
            direction,
            emission,
        };
        let (expected_direction, radiance) = case.expected;
        compare_light_sample(
            &format!(
                "sample_directional_light(light along {direction} of emission {emission}, point {p})"
            ),
            s.sample_directional_light(&light, p),
            LightSample {
                direction: expected_direction,
                distance: f32::INFINITY,
                radiance,
            },
        )?;
    }
    check_part_snapshot(Part::DirectionalLight, s, ctx)
}

/// Light samples for the Lambertian golden cases and properties.
pub fn lambertian_strategy() -> impl Strategy<Value = LambertianInput> {
    let colour = (0.0f32..1.0, 0.0f32..1.0, 0.0f32..1.0).prop_map(|(r, g, b)| Vec3::new(r, g, b));
    let radiance = (0.0f32..5.0, 0.0f32..5.0, 0.0f32..5.0).prop_map(|(r, g, b)| Vec3::new(r, g, b));
    (
        colour,
        unit_vector(),
        prop::collection::vec((unit_vector(), radiance), 0..4),
    )
}

fn exercise_2_6(s: &Arc<dyn Lab02>, ctx: &LabContext) -> Result<(), String> {
    let key = key_shading(ctx);
    for_all(300, lambertian_strategy(), |(rho, n, lights)| {
        let call = format!("shade_lambertian(ρ_d = {rho}, n = {n}, lights = {lights:?})");
        let got = s.shade_lambertian(rho, n, &samples_of(&lights));
        let one_by_one: Vec3 = lights
            .iter()
            .map(|l| s.shade_lambertian(rho, n, &samples_of(std::slice::from_ref(l))))
            .sum();
        compare_vec3(
            &format!("{call} (the lights shaded one at a time add up to {one_by_one})"),
            got,
            one_by_one,
            1e-5,
            1e-4,
        )
        .map_err(|e| format!("{e}: the reflected radiance is a sum over the lights"))?;
        compare_vec3(
            &format!("{call} with half the albedo"),
            s.shade_lambertian(0.5 * rho, n, &samples_of(&lights)),
            0.5 * got,
            1e-5,
            1e-4,
        )?;
        for &(w, l) in &lights {
            let alone = s.shade_lambertian(rho, n, &samples_of(&[(w, l)]));
            let cos = n.dot(w);
            if cos <= 0.0 {
                if alone.abs().max_element() > 1e-7 {
                    return Err(format!(
                        "shade_lambertian(ρ_d = {rho}, n = {n}, one light from {w} of radiance {l}) is {alone}: the light is below the surface (n·ω = {cos:.4} ≤ 0) and must contribute nothing"
                    ));
                }
                continue;
            }
            // Lambert's cosine law: the same light from straight above gives alone / cos θ.
            let above = s.shade_lambertian(rho, n, &samples_of(&[(n, l)]));
            compare_vec3(
                &format!(
                    "shade_lambertian(ρ_d = {rho}, n = {n}, one light from {w} of radiance {l}) (cos θ = {cos:.4}, {above} from straight above)"
                ),
                alone,
                above * cos,
                1e-5,
                1e-4,
            )
            .map_err(|e| format!("{e}: Lambert's cosine law, reflected radiance ∝ max(0, n·ω)"))?;
        }
        match &key {
            Some(key) => compare_vec3(
                &call,
                got,
                key.shade_lambertian(rho, n, &samples_of(&lights)),
                1e-5,
                1e-4,
            ),
            None => Ok(()),
        }
    })?;
    let golden: GoldenFile<LambertianInput, Vec3> = load(ctx, GOLDEN_LAMBERTIAN)?;
    for case in &golden.cases {
        let (rho, n, lights) = &case.input;
        compare_vec3(
            &format!("shade_lambertian(ρ_d = {rho}, n = {n}, lights = {lights:?})"),
            s.shade_lambertian(*rho, *n, &samples_of(lights)),
            case.expected,
            1e-5,
            1e-4,
        )?;
    }
    check_part_snapshot(Part::Lambertian, s, ctx)
}
