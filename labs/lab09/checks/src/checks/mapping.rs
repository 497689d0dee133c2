//! Exercises 9.1 to 9.3: texture coordinates on planes, spheres and triangles.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab09::Texturing;
use grading::strategies::{point, scale, unit_vector};
use grading::{GoldenFile, LabContext, compare_vec2, for_all};
use raylab_core::math::Onb;
use raylab_core::scene::{MaterialId, Plane, Sphere};

use super::scene::check_render;
use super::{GOLDEN_PLANE, GOLDEN_SPHERE, GOLDEN_TRIANGLE, Part};

/// A plane case: normal, the plane's distance from the origin along it, the turn of its
/// tangent frame about the normal, its texture scale, and the point's coordinates `(a, b)` in
/// that frame in units of the scale.
pub type PlaneInput = (Vec3, f32, f32, f32, Vec2);

/// Plane cases over every orientation and scale.
pub fn plane_input() -> impl Strategy<Value = PlaneInput> {
    (
        unit_vector(),
        -1e3f32..1e3,
        0.0f32..std::f32::consts::TAU,
        scale().prop_flat_map(|s| (s * 0.1)..(s * 10.0)),
        (-20.0f32..20.0, -20.0f32..20.0).prop_map(|(a, b)| Vec2::new(a, b)),
    )
}

/// The plane of a case (tangent frame turned by `angle` about the normal) and the point
/// `−d·n + (a·t + b·b̂)·tex_scale`, with the coordinates it must get.
pub fn plane_case((normal, offset, angle, tex_scale, ab): PlaneInput) -> (Plane, Vec3, Vec2) {
    let mut plane = Plane::new(offset * normal, normal, MaterialId(0));
    let onb = Onb::from_w(plane.normal);
    let (c, s) = (angle.cos(), angle.sin());
    plane.tangent = c * onb.u + s * onb.v;
    plane.bitangent = plane.normal.cross(plane.tangent);
    plane.tex_scale = tex_scale;
    let origin = -plane.d * plane.normal;
    let position = origin + (ab.x * plane.tangent + ab.y * plane.bitangent) * tex_scale;
    (plane, position, ab)
}

fn plane_call(plane: &Plane, position: Vec3) -> String {
    format!(
        "plane_texcoord(plane with normal {}, d = {}, tangent {}, bitangent {}, tex_scale = {}; position {position})",
        plane.normal, plane.d, plane.tangent, plane.bitangent, plane.tex_scale
    )
}

/// Tolerance of a plane's coordinates: rounding of the position relative to the scale.
fn plane_tolerance(plane: &Plane, position: Vec3) -> f32 {
    2e-6 * (position.length() + plane.d.abs()) / plane.tex_scale + 1e-5
}

fn check_plane(p: &dyn Texturing, input: PlaneInput) -> Result<(), String> {
    let (plane, position, expected) = plane_case(input);
    let got = p.plane_texcoord(&plane, position);
    let tol = plane_tolerance(&plane, position);
    compare_vec2(&plane_call(&plane, position), got, expected, tol, 1e-5).map_err(|e| {
        let hint = if (got - expected * plane.tex_scale * plane.tex_scale).abs().max_element()
            <= tol * plane.tex_scale * plane.tex_scale
        {
            "that is multiplied by tex_scale; tex_scale is world units per repeat, so divide by it"
        } else if (got - expected * plane.tex_scale).abs().max_element()
            <= tol * plane.tex_scale.max(1.0)
        {
            "that is not divided by tex_scale"
        } else if (got - Vec2::new(expected.y, expected.x)).abs().max_element() <= tol {
            "u and v are swapped: u goes along plane.tangent, v along plane.bitangent"
        } else {
            "u is the position's coordinate along plane.tangent and v along plane.bitangent, measured from −d·n, divided by tex_scale"
        };
        format!("{e}: {hint}")
    })
}

pub(super) fn exercise_9_1(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    for_all(300, plane_input(), |input| check_plane(p.as_ref(), input))?;
    // Off the plane, only the in-plane part counts (a hit point rounded off the plane).
    for_all(100, (plane_input(), -1.0f32..1.0), |(input, h)| {
        let (plane, position, _) = plane_case(input);
        let off = position + h * 1e-3 * plane.tex_scale * plane.normal;
        let (a, b) = (
            p.plane_texcoord(&plane, position),
            p.plane_texcoord(&plane, off),
        );
        compare_vec2(
            &format!("{} moved by {h:.3e}·tex_scale along the normal", plane_call(&plane, position)),
            b,
            a,
            2.0 * plane_tolerance(&plane, position),
            1e-5,
        )
        .map_err(|e| format!("{e}: moving along the normal does not change a point's coordinates in the plane's frame"))
    })?;
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(200, plane_input(), |input| {
            let (plane, position, _) = plane_case(input);
            compare_vec2(
                &plane_call(&plane, position),
                p.plane_texcoord(&plane, position),
                key.plane_texcoord(&plane, position),
                plane_tolerance(&plane, position),
                1e-5,
            )
        })?;
    }
    let golden: GoldenFile<(Plane, Vec3), Vec2> = ctx.golden(GOLDEN_PLANE)?;
    for case in &golden.cases {
        let (plane, position) = &case.input;
        compare_vec2(
            &plane_call(plane, *position),
            p.plane_texcoord(plane, *position),
            case.expected,
            plane_tolerance(plane, *position),
            1e-5,
        )?;
    }
    check_render(p, Part::Plane, ctx)
}

/// A sphere case: the direction from the centre, the radius, and the centre in radii.
pub type SphereInput = (Vec3, f32, Vec3);

/// Directions all over the sphere (the poles and the seam too), radii from 10⁻⁴ to 10³,
/// centres up to 10³ radii from the origin.
pub fn sphere_input() -> impl Strategy<Value = SphereInput> {
    let special = prop::sample::select(vec![
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
        Vec3::X,
        Vec3::NEG_X,
        Vec3::new(1e-4, 0.3, -1.0).normalize(),
        Vec3::new(-1e-4, -0.3, -1.0).normalize(),
    ]);
    (
        prop_oneof![6 => unit_vector(), 1 => special],
        scale(),
        prop_oneof![point(2.0), point(1e3)],
    )
}

/// The sphere and the point of a case.
pub fn sphere_case((d, radius, centre): SphereInput) -> (Sphere, Vec3) {
    let sphere = Sphere {
        center: centre * radius,
        radius,
        material: MaterialId(0),
    };
    (sphere, sphere.center + radius * d)
}

/// The unit direction with texture coordinates `uv` in the contract's parameterization
/// (longitude `2π(u − ½)` from `+z` towards `+x`, latitude `π(v − ½)`).
pub fn direction_of(uv: Vec2) -> Vec3 {
    let longitude = std::f64::consts::TAU * (uv.x as f64 - 0.5);
    let latitude = std::f64::consts::PI * (uv.y as f64 - 0.5);
    Vec3::new(
        (latitude.cos() * longitude.sin()) as f32,
        latitude.sin() as f32,
        (latitude.cos() * longitude.cos()) as f32,
    )
}

fn sphere_call(sphere: &Sphere, position: Vec3) -> String {
    format!(
        "sphere_texcoord(sphere centred at {} with radius {}, position {position})",
        sphere.center, sphere.radius
    )
}

/// Direction error allowed in the round trip: rounding of the position relative to the radius.
fn sphere_tolerance(sphere: &Sphere, position: Vec3) -> f32 {
    1e-3 + 4e-7 * position.abs().max_element() / sphere.radius
}

fn check_sphere(p: &dyn Texturing, input: SphereInput) -> Result<(), String> {
    let (sphere, position) = sphere_case(input);
    let d = input.0;
    let call = sphere_call(&sphere, position);
    let uv = p.sphere_texcoord(&sphere, position);
    if !uv.is_finite() || uv.min_element() < 0.0 || uv.max_element() > 1.0 {
        return Err(format!(
            "{call} is {uv}: texture coordinates must be finite and in [0, 1] (u = ½ + longitude/2π, v = ½ + latitude/π)"
        ));
    }
    let back = direction_of(uv);
    let err = (back - d).length();
    if err > sphere_tolerance(&sphere, position) {
        let hint = if (direction_of(Vec2::new(uv.x, 1.0 - uv.y)) - d).length() < 1e-2 {
            "v is upside down: v = 0 at the south pole (−y), 1 at the north pole"
        } else if (direction_of(Vec2::new(1.0 - uv.x, uv.y)) - d).length() < 1e-2 {
            "u runs the wrong way round: it grows from +z towards +x"
        } else if (back.y - d.y).abs() < 1e-2 {
            "the latitude (v) is right but not the longitude (u): u = ½ towards +z, growing towards +x, the seam towards −z"
        } else {
            "v must be linear in the latitude angle, from 0 at the south pole to 1 at the north pole"
        };
        return Err(format!(
            "{call} is {uv}, which is the direction {back} from the centre; the point is in the direction {d} (off by {err:.2e}): {hint}"
        ));
    }
    Ok(())
}

/// The distance of two texture coordinates on the sphere (u on the circle).
fn sphere_uv_distance(a: Vec2, b: Vec2) -> f32 {
    let du = (a.x - b.x).abs();
    du.min(1.0 - du).max((a.y - b.y).abs())
}

pub(super) fn exercise_9_2(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    for_all(500, sphere_input(), |input| check_sphere(p.as_ref(), input))?;
    let compare = |sphere: &Sphere, position: Vec3, expected: Vec2| -> Result<(), String> {
        let got = p.sphere_texcoord(sphere, position);
        let d = ((position - sphere.center) / sphere.radius).normalize();
        // Near the poles the longitude is undefined: compare the directions there.
        let close = if d.y.abs() > 0.999 {
            (direction_of(got) - direction_of(expected)).length()
                <= sphere_tolerance(sphere, position)
        } else {
            sphere_uv_distance(got, expected) <= sphere_tolerance(sphere, position)
        };
        if close {
            Ok(())
        } else {
            Err(format!(
                "{} is {got}, expected {expected}",
                sphere_call(sphere, position)
            ))
        }
    };
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(200, sphere_input(), |input| {
            let (sphere, position) = sphere_case(input);
            compare(&sphere, position, key.sphere_texcoord(&sphere, position))
        })?;
    }
    let golden: GoldenFile<(Sphere, Vec3), Vec2> = ctx.golden(GOLDEN_SPHERE)?;
    for case in &golden.cases {
        let (sphere, position) = &case.input;
        compare(sphere, *position, case.expected)?;
    }
    check_render(p, Part::Sphere, ctx)
}

/// A triangle case: the vertices' texture coordinates and barycentrics `(β, γ)` inside.
pub type TriangleInput = ([Vec2; 3], Vec2);

/// Vertex coordinates up to ±10 (some up to ±10³), barycentrics inside the triangle.
pub fn triangle_input() -> impl Strategy<Value = TriangleInput> {
    let uv = prop_oneof![
        4 => (-10.0f32..10.0, -10.0f32..10.0),
        1 => (-1e3f32..1e3, -1e3f32..1e3),
    ]
    .prop_map(|(u, v)| Vec2::new(u, v));
    (
        [uv.clone(), uv.clone(), uv],
        (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| {
            if a + b > 1.0 {
                Vec2::new(1.0 - a, 1.0 - b)
            } else {
                Vec2::new(a, b)
            }
        }),
    )
}

fn triangle_call(uvs: &[Vec2; 3], bary: Vec2) -> String {
    format!(
        "triangle_texcoord(uvs = [{}, {}, {}], barycentrics (β, γ) = {bary})",
        uvs[0], uvs[1], uvs[2]
    )
}

fn triangle_tolerance(uvs: &[Vec2; 3]) -> f32 {
    1e-6 * uvs
        .iter()
        .map(|v| v.abs().max_element())
        .fold(1.0, f32::max)
}

fn check_triangle(p: &dyn Texturing, (uvs, bary): TriangleInput) -> Result<(), String> {
    let tol = triangle_tolerance(&uvs);
    for (k, corner) in [Vec2::ZERO, Vec2::X, Vec2::Y].into_iter().enumerate() {
        compare_vec2(
            &triangle_call(&uvs, corner),
            p.triangle_texcoord(uvs, corner),
            uvs[k],
            tol,
            1e-6,
        )
        .map_err(|e| {
            format!("{e}: at vertex {k} (barycentrics {corner}) the coordinates are that vertex's own; vertex 0 weighs 1 − β − γ, vertex 1 β, vertex 2 γ")
        })?;
    }
    // Affine: the midpoint of two points has the midpoint of their coordinates.
    let other = Vec2::new(bary.y, 1.0 - bary.x - bary.y).max(Vec2::ZERO);
    let mid = 0.5 * (bary + other);
    let (a, b, m) = (
        p.triangle_texcoord(uvs, bary),
        p.triangle_texcoord(uvs, other),
        p.triangle_texcoord(uvs, mid),
    );
    compare_vec2(&triangle_call(&uvs, mid), m, 0.5 * (a + b), 4.0 * tol, 1e-5).map_err(|e| {
        format!("{e} = the midpoint of the coordinates {a} at {bary} and {b} at {other}: the coordinates are a barycentric (affine) combination of the vertices' coordinates")
    })?;
    // Moving every vertex's coordinates moves the result alike.
    let shift = Vec2::new(0.25, -0.5);
    let moved = uvs.map(|v| v + shift);
    compare_vec2(
        &triangle_call(&moved, bary),
        p.triangle_texcoord(moved, bary),
        a + shift,
        4.0 * tol,
        1e-5,
    )
    .map_err(|e| {
        format!("{e}: shifting all three vertices' coordinates by {shift} shifts the result by the same; the weights must sum to 1")
    })
}

pub(super) fn exercise_9_3(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    for_all(300, triangle_input(), |input| {
        check_triangle(p.as_ref(), input)
    })?;
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(200, triangle_input(), |(uvs, bary)| {
            compare_vec2(
                &triangle_call(&uvs, bary),
                p.triangle_texcoord(uvs, bary),
                key.triangle_texcoord(uvs, bary),
                4.0 * triangle_tolerance(&uvs),
                1e-5,
            )
        })?;
    }
    let golden: GoldenFile<TriangleInput, Vec2> = ctx.golden(GOLDEN_TRIANGLE)?;
    for case in &golden.cases {
        let (uvs, bary) = &case.input;
        compare_vec2(
            &triangle_call(uvs, *bary),
            p.triangle_texcoord(*uvs, *bary),
            case.expected,
            4.0 * triangle_tolerance(uvs),
            1e-5,
        )?;
    }
    check_render(p, Part::Triangle, ctx)
}
