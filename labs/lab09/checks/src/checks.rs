//! Lab 09's exercises and their checks (docs/lab09.md, "What the checks check").
//!
//! Every exercise is checked by relations its answer satisfies whatever it is, by the answer
//! key's results on random inputs where the key is present, by recorded golden cases, and by a
//! render of the textured default scene ([`textured_scene`]) with the student's function in
//! its slot and the base's everywhere else, compared with a snapshot:
//!
//! - 9.1 `plane_texcoord`: points built as `−d·n + a·t + b·b̂` on planes of every orientation,
//!   with the tangent frame turned about the normal, `tex_scale` from 10⁻³ to 10³ and the plane
//!   up to 10³ from the origin, must give `(a, b)/tex_scale`;
//! - 9.2 `sphere_texcoord`: for directions all over the sphere (poles and seam too), spheres of
//!   radius 10⁻⁴ to 10³ up to 10³ radii from the origin, `(u, v)` lies in `[0, 1]²` and turns
//!   back into the direction (the round trip through the parameterization of the contract);
//! - 9.3 `triangle_texcoord`: the vertices' own coordinates at the corners, affine in the
//!   barycentrics (the midpoint of two points maps to the midpoint of their coordinates), and
//!   moving with the vertices' coordinates;
//! - 9.4 `address`: in `[0, 1]` and the identity on `[0, 1)`; repeat periodic with period 1,
//!   mirror symmetric about every integer and periodic with period 2, clamp constant outside,
//!   for coordinates from −10³ to 10³ and next to integers;
//! - 9.5 `sample_nearest`: first the edge texels where `address` gives exactly 0 or 1 (before
//!   anything can index past the texture), then the texel whose centre is closest to the
//!   addressed point (found by searching every texel), for every addressing mode and for an
//!   arbitrary corresponder (so the lookup must go through `address`); a wrong texel is
//!   compared with what each usual slip would read;
//! - 9.6 `sample_bilinear`: the texel itself at its centre; an affine function of `(u, v)`
//!   sampled at the texel centres reproduced exactly between them; continuity across texel
//!   edges, texel centres and the repeat seam (a bound on the change over a 10⁻³-texel step);
//!   periodic, mirrored or clamped as the mode says; within the range of the texels. A failure
//!   names the slip the lookup makes on a probe of texel-centre coordinates.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab09::{Addressing, TextureFilter, Texturing};
use grading::strategies::{point, scale, unit_vector};
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, compare_vec2, compare_vec3, for_all,
};
use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::film::Film;
use raylab_core::math::Onb;
use raylab_core::render::RenderSettings;
use raylab_core::sampling::Rng;
use raylab_core::scene::{MaterialId, Plane, Scene, Sphere, Texture, builtin_scene};

/// Golden file of Exercise 9.1: plane, position → texture coordinates.
pub const GOLDEN_PLANE: &str = "plane_texcoord.json";
/// Golden file of Exercise 9.2: sphere, position → texture coordinates.
pub const GOLDEN_SPHERE: &str = "sphere_texcoord.json";
/// Golden file of Exercise 9.3: vertex coordinates, barycentrics → texture coordinates.
pub const GOLDEN_TRIANGLE: &str = "triangle_texcoord.json";
/// Golden file of Exercise 9.4: coordinate, mode → addressed coordinate.
pub const GOLDEN_ADDRESS: &str = "address.json";
/// Golden file of Exercise 9.5: texture, coordinates, mode → texel.
pub const GOLDEN_NEAREST: &str = "sample_nearest.json";
/// Golden file of Exercise 9.6: texture, coordinates, mode → colour.
pub const GOLDEN_BILINEAR: &str = "sample_bilinear.json";
/// Snapshot of the textured scene read with nearest lookups.
pub const SNAPSHOT_NEAREST: &str = "textured-nearest";
/// Snapshot of the textured scene read with bilinear lookups.
pub const SNAPSHOT_BILINEAR: &str = "textured-bilinear";
/// Size, sampling and seed of lab 09's snapshots.
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(9);
/// World units per repeat of the ground's texture in [`textured_scene`] at scale 1.
pub const GROUND_TEX_SCALE: f32 = 2.0;
/// Step, in texels, over which Exercise 9.6's continuity check bounds the change.
pub const CONTINUITY_STEP_TEXELS: f32 = 1e-3;

/// This lab.
pub const LAB: course::LabId = course::LabId::of(9);

/// The exercises of lab 09 (`labs/lab09/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Texturing>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_9_1,
            exercise_9_2,
            exercise_9_3,
            exercise_9_4,
            exercise_9_5,
            exercise_9_6
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Pipelines, textures and the textured scene

/// Which student function a render exercises; the others come from the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 9.1.
    Plane,
    /// Exercise 9.2.
    Sphere,
    /// Exercise 9.3.
    Triangle,
    /// Exercise 9.4.
    Address,
    /// Exercise 9.5.
    Nearest,
    /// Exercise 9.6.
    Bilinear,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`](pipeline::PartSlot)).
    pub fn function(self) -> &'static str {
        match self {
            Part::Plane => "plane_texcoord",
            Part::Sphere => "sphere_texcoord",
            Part::Triangle => "triangle_texcoord",
            Part::Address => "address",
            Part::Nearest => "sample_nearest",
            Part::Bilinear => "sample_bilinear",
        }
    }
}

/// The pipeline of one part's renders: `student` for that part only, `base` for the rest,
/// shaded, at lab 9, reading textures with `filter`.
pub fn part_pipeline(
    part: Part,
    student: &Arc<dyn Texturing>,
    base: &Pipeline,
    filter: TextureFilter,
) -> Pipeline {
    let mut pipeline = base.with_student_function(part.function(), student);
    pipeline.view = View::Shaded;
    pipeline.texture_filter = filter;
    pipeline
}

/// The default scene with generated textures (no file needed): a checkerboard on the ground
/// (one repeat per `GROUND_TEX_SCALE / tex_frequency` metres), a red-and-white checkerboard
/// on the red sphere (spherical coordinates), a colour gradient on the torus (its OBJ's
/// texture coordinates), under the scene's lights.
pub fn textured_scene(tex_frequency: f32) -> Result<Scene, raylab_core::Error> {
    let mut scene = builtin_scene("default")?;
    let ground = Texture::checkerboard(8, 2, Vec3::splat(0.95), Vec3::new(0.15, 0.2, 0.3));
    let red = Texture::checkerboard(8, 1, Vec3::new(0.9, 0.1, 0.1), Vec3::splat(0.9));
    let gradient = Texture::gradient(8, 8);
    let by_name = |scene: &Scene, name: &str| scene.materials.iter().position(|m| m.name == name);
    for (name, texture, diffuse) in [
        ("ground", ground, Vec3::ONE),
        ("red", red, Vec3::ONE),
        ("gold", gradient, Vec3::new(1.0, 0.85, 0.6)),
    ] {
        let Some(i) = by_name(&scene, name) else {
            return Err(raylab_core::Error::Failed {
                what: format!("the default scene's material '{name}'"),
                reason: "lab 09's textured scene puts a texture on it; it is not in the scene"
                    .into(),
            });
        };
        scene.materials[i].diffuse = diffuse;
        scene.materials[i].diffuse_texture = Some(Arc::new(texture));
    }
    for plane in &mut scene.planes {
        plane.tex_scale = GROUND_TEX_SCALE / tex_frequency;
    }
    scene.name = "default (textured)".into();
    Ok(scene)
}

/// Renders the textured scene at the snapshot size (texture frequency 1).
pub fn render_textured(pipeline: &Pipeline) -> Result<Film, raylab_core::Error> {
    render(&textured_scene(1.0)?, pipeline, &SNAPSHOT_SETTINGS)
}

/// The snapshot a part's render is compared with: nearest lookups for Exercise 9.5, bilinear
/// for the others.
pub fn snapshot_of(part: Part) -> (&'static str, TextureFilter) {
    match part {
        Part::Nearest => (SNAPSHOT_NEAREST, TextureFilter::Nearest),
        _ => (SNAPSHOT_BILINEAR, TextureFilter::Bilinear),
    }
}

/// Renders the textured scene with the student's `part` and compares it with its snapshot.
fn check_render(p: &Arc<dyn Texturing>, part: Part, ctx: &LabContext) -> Result<(), String> {
    let (name, filter) = snapshot_of(part);
    let film =
        render_textured(&part_pipeline(part, p, &ctx.base, filter)).map_err(|e| e.to_string())?;
    let tol = PixelTolerance {
        abs: 2e-3,
        rel: 2e-3,
        max_outlier_fraction: 0.01,
    };
    ctx.check_snapshot(name, &film, &tol)
}

/// A texture case: width, height and the seed of its random texels.
pub type TextureCase = (u32, u32, u64);

/// A `width × height` texture of random texels in `[0, 1)³` from `seed`.
pub fn random_texture((width, height, seed): TextureCase) -> Texture {
    let mut rng = Rng::new(seed, 9);
    let texels: Vec<Vec3> = (0..width.max(1) * height.max(1))
        .map(|_| Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()))
        .collect();
    let w = width.max(1);
    Texture::from_fn(
        &format!("<random {width}×{height} #{seed}>"),
        width,
        height,
        |i, j| texels[(j * w + i) as usize],
    )
}

/// A texture case from 1×1 to 16×12.
pub fn texture_case() -> impl Strategy<Value = TextureCase> + Clone {
    (1u32..=16, 1u32..=12, any::<u64>())
}

/// An addressing mode.
pub fn addressing() -> impl Strategy<Value = Addressing> + Clone {
    prop::sample::select(Addressing::ALL.to_vec())
}

/// Texture coordinates: mostly in `[−3, 3]²`, some up to ±10³.
pub fn texcoords() -> impl Strategy<Value = Vec2> + Clone {
    prop_oneof![
        4 => (-3.0f32..3.0, -3.0f32..3.0).prop_map(|(u, v)| Vec2::new(u, v)),
        1 => (-1e3f32..1e3, -1e3f32..1e3).prop_map(|(u, v)| Vec2::new(u, v)),
    ]
}

/// Names a texel for messages.
fn texel_name(i: u32, j: u32) -> String {
    format!("(column {i}, row {j} from the top)")
}

/// Where `colour` is in `texture`, if it is one of its texels.
fn find_texel(texture: &Texture, colour: Vec3) -> Option<(u32, u32)> {
    (0..texture.height)
        .flat_map(|j| (0..texture.width).map(move |i| (i, j)))
        .find(|&(i, j)| texture.texel(i, j) == colour)
}

/// The centre of texel `(i, j)` in texture space.
pub fn texel_centre(texture: &Texture, i: u32, j: u32) -> Vec2 {
    Vec2::new(
        (i as f32 + 0.5) / texture.width as f32,
        1.0 - (j as f32 + 0.5) / texture.height as f32,
    )
}

// ---------------------------------------------------------------------------------------------
// Exercise 9.1

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

fn exercise_9_1(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
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

// ---------------------------------------------------------------------------------------------
// Exercise 9.2

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

fn exercise_9_2(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
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

// ---------------------------------------------------------------------------------------------
// Exercise 9.3

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

fn exercise_9_3(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
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

// ---------------------------------------------------------------------------------------------
// Exercise 9.4

/// An addressing case: a point `x ∈ [0, 1)`, a whole number `k` of periods from −10³ to 10³,
/// and the mode.
pub type AddressInput = (f32, i32, Addressing);

/// Points in `[0, 1)` (some next to 0 and 1), periods from −10³ to 10³, every mode.
pub fn address_input() -> impl Strategy<Value = AddressInput> {
    (
        prop_oneof![
            4 => 0.0f32..1.0,
            1 => 0.0f32..1e-3,
            1 => (1.0f32 - 1e-3)..1.0,
            1 => Just(0.0f32),
            1 => Just(0.5f32),
        ],
        prop_oneof![3 => -3i32..=3, 1 => -1000i32..=1000],
        addressing(),
    )
}

fn check_address(p: &dyn Texturing, (x, k, mode): AddressInput) -> Result<(), String> {
    let call = |t: f32| format!("address(t = {t}, {mode:?})");
    // The identity on [0, 1).
    let got = p.address(x, mode);
    if (got - x).abs() > 1e-7 {
        return Err(format!(
            "{} is {got}: a coordinate already in [0, 1) is left as it is",
            call(x)
        ));
    }
    let tol = 2e-6;
    let on_circle = |a: f64, b: f64| {
        let d = (a - b).abs();
        d.min(1.0 - d)
    };
    let odd = k.rem_euclid(2) == 1;
    // t = k + x' just above the whole number k, or t = k − x' just below it, with x' in
    // [0, 1) exactly (cases whose rounding leaves [0, 1) are skipped).
    for below in [false, true] {
        let t = if below { k as f32 - x } else { k as f32 + x };
        let x = if below {
            k as f64 - t as f64
        } else {
            t as f64 - k as f64
        };
        if !(0.0..1.0).contains(&x) {
            continue;
        }
        let got = p.address(t, mode);
        if !got.is_finite() || !(0.0..=1.0).contains(&got) {
            return Err(format!(
                "{} is {got}: the corresponder maps every coordinate into [0, 1]{}",
                call(t),
                if t < 0.0 {
                    " — for a negative t too (Rust's % and f32::fract keep the sign of t)"
                } else {
                    ""
                }
            ));
        }
        let (expected, what) = match mode {
            Addressing::Repeat => (
                if below { 1.0 - x } else { x },
                "repeat is periodic with period 1: t and t + k for any whole k address the same point (negative t too)",
            ),
            Addressing::Mirror => (
                if odd { 1.0 - x } else { x },
                "mirror is the identity on [0, 1], symmetric about every integer and periodic with period 2: 2 − t on [1, 2], −t on [−1, 0] (negative t too)",
            ),
            Addressing::Clamp => (
                (t as f64).clamp(0.0, 1.0),
                "clamp leaves [0, 1] as it is and sends t < 0 to 0, t > 1 to 1",
            ),
        };
        let off = if mode == Addressing::Repeat {
            on_circle(got as f64, expected)
        } else {
            (got as f64 - expected).abs()
        };
        if off > tol * (1.0 + t.abs() as f64 * 1e-3) {
            return Err(format!(
                "{} is {got}, expected {expected:.7}: {what}",
                call(t)
            ));
        }
    }
    Ok(())
}

fn exercise_9_4(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    for_all(1500, address_input(), |input| {
        check_address(p.as_ref(), input)
    })?;
    // Whole numbers: repeat gives 0 or 1 (the same place), mirror 0 at even and 1 at odd
    // ones, clamp 0 below and 1 above.
    for k in -5i32..=5 {
        let t = k as f32;
        let call = |mode: Addressing| format!("address(t = {t}, {mode:?})");
        let r = p.address(t, Addressing::Repeat);
        if r != 0.0 && r != 1.0 {
            return Err(format!(
                "{} is {r}: a whole number repeats to the texture's edge, 0 (or 1, the same place)",
                call(Addressing::Repeat)
            ));
        }
        let m = p.address(t, Addressing::Mirror);
        let even = k.rem_euclid(2) == 0;
        if (m - if even { 0.0 } else { 1.0 }).abs() > 1e-6 {
            return Err(format!(
                "{} is {m}: mirror gives 0 at even and 1 at odd whole numbers",
                call(Addressing::Mirror)
            ));
        }
        let c = p.address(t, Addressing::Clamp);
        if c != t.clamp(0.0, 1.0) {
            return Err(format!(
                "{} is {c}: clamp sends t ≤ 0 to 0 and t ≥ 1 to 1",
                call(Addressing::Clamp)
            ));
        }
    }
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(500, (-1e3f32..1e3, addressing()), |(t, mode)| {
            let (got, expected) = (p.address(t, mode), key.address(t, mode));
            let off = (got - expected).abs();
            let off = if mode == Addressing::Repeat {
                off.min(1.0 - off)
            } else {
                off
            };
            if off <= 1e-6 * (1.0 + t.abs() * 1e-3) {
                Ok(())
            } else {
                Err(format!(
                    "address(t = {t}, {mode:?}) is {got}, expected {expected}"
                ))
            }
        })?;
    }
    let golden: GoldenFile<(f32, Addressing), f32> = ctx.golden(GOLDEN_ADDRESS)?;
    for case in &golden.cases {
        let (t, mode) = case.input;
        let got = p.address(t, mode);
        let off = (got - case.expected).abs();
        let off = if mode == Addressing::Repeat {
            off.min(1.0 - off)
        } else {
            off
        };
        if off > 1e-6 * (1.0 + t.abs() * 1e-3) {
            return Err(format!(
                "address(t = {t}, {mode:?}) is {got}, expected {}",
                case.expected
            ));
        }
    }
    check_render(p, Part::Address, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 9.5

/// The index, among `n` texels along an axis whose centres lie at `centre(k)`, of the centre
/// closest to `t` (found by trying them all), unless two are about as close (`None`).
fn closest_centre(n: u32, t: f32, centre: impl Fn(u32) -> f32) -> Option<u32> {
    let mut d: Vec<(f32, u32)> = (0..n).map(|k| ((centre(k) - t).abs(), k)).collect();
    d.sort_by(|a, b| a.0.total_cmp(&b.0));
    let margin = 1e-3 / n as f32;
    match d.as_slice() {
        [only] => Some(only.1),
        [first, second, ..] if second.0 - first.0 > margin => Some(first.1),
        _ => None,
    }
}

/// The texel whose centre is closest to the texture-space point `a` (None at a near tie).
pub fn closest_texel(texture: &Texture, a: Vec2) -> Option<(u32, u32)> {
    let i = closest_centre(texture.width, a.x, |i| texel_centre(texture, i, 0).x)?;
    let j = closest_centre(texture.height, a.y, |j| texel_centre(texture, 0, j).y)?;
    Some((i, j))
}

fn nearest_call(case: TextureCase, uv: Vec2, mode: &str) -> String {
    format!(
        "sample_nearest(a {}×{} texture, uv = {uv}, {mode})",
        case.0, case.1
    )
}

/// `sample_nearest` at `uv` through `address` gives the texel closest to the addressed point.
fn check_nearest_at(
    p: &dyn Texturing,
    case: TextureCase,
    uv: Vec2,
    address: &dyn Fn(f32) -> f32,
    mode: &str,
) -> Result<(), String> {
    let texture = random_texture(case);
    let a = Vec2::new(address(uv.x), address(uv.y));
    let Some((i, j)) = closest_texel(&texture, a) else {
        return Ok(());
    };
    let got = p.sample_nearest(&texture, uv, address);
    let expected = texture.texel(i, j);
    if got == expected {
        return Ok(());
    }
    let call = nearest_call(case, uv, mode);
    // What the usual slips would read: a coordinate not passed through `address` (used as it
    // is, the index clamped into the texture).
    let raw = |t: f32| t.clamp(0.0, 1.0);
    let slip = |b: Vec2| closest_texel(&texture, b).filter(|&t| t != (i, j));
    let found = match find_texel(&texture, got) {
        Some((gi, gj)) => {
            let hint = if slip(Vec2::new(raw(uv.x), raw(uv.y))) == Some((gi, gj))
                && slip(Vec2::new(a.x, raw(uv.y))) != Some((gi, gj))
                && slip(Vec2::new(raw(uv.x), a.y)) != Some((gi, gj))
            {
                " — neither u nor v went through `address`: the texel is the one at the unaddressed point, clamped into the texture"
            } else if slip(Vec2::new(a.x, raw(uv.y))) == Some((gi, gj)) {
                " — v did not go through `address`: call it on v as well as on u"
            } else if slip(Vec2::new(raw(uv.x), a.y)) == Some((gi, gj)) {
                " — u did not go through `address`: call it on u as well as on v"
            } else if gi == i && gj == texture.height - 1 - j {
                " — the row is upside down: rows count from the top, v goes up"
            } else if gi != i && gj == j {
                " — the column is wrong: texel i covers [i/w, (i+1)/w), so it holds the point when its centre is the closest"
            } else if gj != j && gi == i {
                " — the row is wrong: texel row j covers v in [1 − (j+1)/h, 1 − j/h]"
            } else {
                ""
            };
            format!("the texel {}{hint}", texel_name(gi, gj))
        }
        None => format!("{got}, which is not a texel of the texture"),
    };
    Err(format!(
        "{call} is {found}; the addressed point is {a}, whose closest texel centre is that of texel {} = {expected}",
        texel_name(i, j)
    ))
}

/// A corresponder that is none of the three modes (any map into `[0, 1]` will do): the lookup
/// must use the one it is given.
fn odd_corresponder(t: f32) -> f32 {
    0.5 + 0.5 * (1.7 * t + 0.3).sin()
}

/// The edges of the texture, before any other lookup, so that an index one past the last
/// column or row is named before it can read outside the texture: `address` giving exactly 1
/// or 0 for u (with v inside, so that an unclamped column still reads a texel of the next row)
/// and then for v, on textures of several rows first and a single row last. The other
/// coordinate lies a quarter of a texel into its texel, so that only the edge is in question;
/// a lookup wrong along the other axis gets the diagnosis of [`check_nearest_at`].
fn check_nearest_edges(p: &dyn Texturing) -> Result<(), String> {
    let inside = |t: f32| t.clamp(0.0, 1.0);
    let mode = "address = clamp into [0, 1]";
    for case in [(4, 3, 2), (16, 9, 3), (5, 1, 4), (1, 1, 1)] {
        let texture = random_texture(case);
        let (w, h) = (case.0, case.1);
        // A row above the bottom one (so that column w of an unclamped index is still in the
        // texels), and a column in the middle.
        let (row, column) = (h.saturating_sub(2), w / 2);
        let v = 1.0 - (row as f32 + 0.25) / h as f32;
        let u = (column as f32 + 0.25) / w as f32;
        // Each edge: the point, the texel, whether the edge is along u, and what to say.
        let edges = [
            (
                Vec2::new(1.0, v),
                (w - 1, row),
                true,
                "u = 1 is the right edge, in the last column: ⌊u·w⌋ = w is one past it, so clamp the column to w − 1",
            ),
            (
                Vec2::new(0.0, v),
                (0, row),
                true,
                "u = 0 is the left edge, in column 0",
            ),
            (
                Vec2::new(u, 1.0),
                (column, 0),
                false,
                "v = 1 is the top edge, in row 0: rows count from the top while v grows upwards, so the row comes from 1 − v",
            ),
            (
                Vec2::new(u, 0.0),
                (column, h - 1),
                false,
                "v = 0 is the bottom edge, in the last row: (1 − v)·h = h is one past it, so clamp the row to h − 1",
            ),
        ];
        for (uv, (i, j), along_u, what) in edges {
            let asked = std::cell::RefCell::new(Vec::new());
            let recorded = |t: f32| {
                asked.borrow_mut().push(t);
                inside(t)
            };
            let got = p.sample_nearest(&texture, uv, &recorded);
            let expected = texture.texel(i, j);
            if got == expected {
                continue;
            }
            let asked = asked.into_inner();
            for (t, axis) in [(uv.x, "u"), (uv.y, "v")] {
                if !asked.contains(&t) {
                    return Err(format!(
                        "{} is {got}, expected the texel {} = {expected}; it never called `address` on {axis} = {t}: look the texture up where `address` sends u and v, whatever the mode",
                        nearest_call(case, uv, mode),
                        texel_name(i, j),
                    ));
                }
            }
            let found = find_texel(&texture, got);
            // Column w of row j, read through the flat index, is column 0 of row j + 1.
            let past_the_end = along_u && i == w - 1 && j + 1 < h && got == texture.texel(0, j + 1);
            let edge_only = match found {
                Some((gi, gj)) if along_u => gj == j && gi != i,
                Some((gi, gj)) => gi == i && gj != j,
                None => false,
            };
            if !(past_the_end || edge_only) {
                check_nearest_at(p, case, uv, &inside, mode)?;
            }
            let found = match found {
                Some(_) if past_the_end => format!(
                    "the texel {}, which is where column {w} of row {j} would be, one past the last column",
                    texel_name(0, j + 1)
                ),
                Some((gi, gj)) => format!("the texel {}", texel_name(gi, gj)),
                None => format!("{got}, which is not a texel of the texture"),
            };
            return Err(format!(
                "{} is {found}, expected the texel {} = {expected}: {what}",
                nearest_call(case, uv, mode),
                texel_name(i, j),
            ));
        }
    }
    Ok(())
}

fn exercise_9_5(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    let base = ctx.base.code::<dyn contracts::lab09::Texturing>();
    check_nearest_edges(p.as_ref())?;
    for_all(
        600,
        (texture_case(), texcoords(), addressing()),
        |(case, uv, mode)| {
            let address = |t: f32| base.address(t, mode);
            check_nearest_at(p.as_ref(), case, uv, &address, &format!("{mode:?}"))
        },
    )?;
    for_all(200, (texture_case(), texcoords()), |(case, uv)| {
        check_nearest_at(
            p.as_ref(),
            case,
            uv,
            &odd_corresponder,
            "address = 0.5 + 0.5·sin(1.7t + 0.3)",
        )
        .map_err(|e| format!("{e}: look the texture up where `address` sends u and v"))
    })?;
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(
            300,
            (texture_case(), texcoords(), addressing()),
            |(case, uv, mode)| {
                let texture = random_texture(case);
                let address = |t: f32| base.address(t, mode);
                let a = Vec2::new(address(uv.x), address(uv.y));
                if closest_texel(&texture, a).is_none() {
                    return Ok(());
                }
                compare_vec3(
                    &nearest_call(case, uv, &format!("{mode:?}")),
                    p.sample_nearest(&texture, uv, &address),
                    key.sample_nearest(&texture, uv, &address),
                    0.0,
                    0.0,
                )
            },
        )?;
    }
    let golden: GoldenFile<(TextureCase, Vec2, Addressing), Vec3> = ctx.golden(GOLDEN_NEAREST)?;
    for case in &golden.cases {
        let (tex, uv, mode) = case.input;
        let address = |t: f32| base.address(t, mode);
        compare_vec3(
            &nearest_call(tex, uv, &format!("{mode:?}")),
            p.sample_nearest(&random_texture(tex), uv, &address),
            case.expected,
            0.0,
            0.0,
        )?;
    }
    check_render(p, Part::Nearest, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 9.6

fn bilinear_call(case: TextureCase, uv: Vec2, mode: Addressing) -> String {
    format!(
        "sample_bilinear(a {}×{} texture, uv = {uv}, {mode:?})",
        case.0, case.1
    )
}

/// What a failing bilinear lookup does, found by running it on a probe: a 5×4 texture whose
/// texels hold their own centres in texel-centre coordinates (`x = u·w − ½`, `y = v·h − ½`,
/// rows counted from the bottom), read with clamp at a point inside, `(x, y) = (1.3, 2.8)`.
/// A lookup that blends texels around some point returns that point, which is compared with
/// the point each usual slip blends around. `None` when the lookup is right on the probe or
/// matches no slip.
fn bilinear_slip(p: &dyn Texturing) -> Option<&'static str> {
    let (w, h) = (5u32, 4u32);
    let probe = Texture::from_fn("<texel centres>", w, h, |i, j| {
        Vec3::new(i as f32, (h - 1 - j) as f32, 0.0)
    });
    let (x, y) = (1.3f32, 2.8f32);
    let uv = Vec2::new((x + 0.5) / w as f32, (y + 0.5) / h as f32);
    let got = p.sample_bilinear(&probe, uv, &|t: f32| t.clamp(0.0, 1.0));
    if !got.is_finite() {
        return None;
    }
    // Points in texel-centre coordinates, clamped to the centres as the probe is.
    let on_probe =
        |x: f32, y: f32| Vec2::new(x.clamp(0.0, (w - 1) as f32), y.clamp(0.0, (h - 1) as f32));
    let (x0, y0) = (x.floor(), y.floor());
    let (s, t) = (x - x0, y - y0);
    let matches = |q: Vec2| (Vec2::new(got.x, got.y) - q).abs().max_element() < 1e-3;
    if matches(on_probe(x, y)) {
        return None;
    }
    let slips = [
        (
            on_probe(x0 + t, y0 + s),
            "the weights s and t are swapped: s, the fractional part along u, blends the columns, and t, along v, the rows",
        ),
        (
            on_probe(x + 0.5, y + 0.5),
            "the half texel is not subtracted: texel k's centre is k + ½ texels from the edge, so subtract ½ from u·w and v·h before taking the integer part",
        ),
        (
            on_probe(x0 + 1.0 - s, y0 + 1.0 - t),
            "the weights are reversed: the neighbour at the larger column gets s and the lower one 1 − s (likewise t for the rows)",
        ),
        (
            on_probe(x, (h - 1) as f32 - y),
            "v is upside down: the rows are blended as if counted from the bottom, but `texel` counts them from the top",
        ),
        (
            on_probe((x + 0.5).floor(), (y + 0.5).floor()),
            "that is the nearest texel, not a blend of the four around the point",
        ),
        (
            on_probe(x, (y + 0.5).floor()),
            "the columns are blended but not the rows: blend the two rows around the point as well, by t",
        ),
        (
            on_probe((x + 0.5).floor(), y),
            "the rows are blended but not the columns: blend the two columns around the point as well, by s",
        ),
    ];
    slips
        .into_iter()
        .find(|&(q, _)| matches(q))
        .map(|(_, hint)| hint)
}

/// `e` with the slip [`bilinear_slip`] finds, or with `otherwise` when it finds none.
fn with_slip(e: String, p: &dyn Texturing, otherwise: &str) -> String {
    match bilinear_slip(p) {
        Some(hint) => format!("{e}: {hint}"),
        None if otherwise.is_empty() => e,
        None => format!("{e}: {otherwise}"),
    }
}

/// At a texel's centre the bilinear lookup is that texel.
fn check_centres(p: &dyn Texturing, base: &dyn Texturing, case: TextureCase) -> Result<(), String> {
    let texture = random_texture(case);
    for mode in Addressing::ALL {
        let address = |t: f32| base.address(t, mode);
        for j in 0..texture.height {
            for i in 0..texture.width {
                let uv = texel_centre(&texture, i, j);
                compare_vec3(
                    &bilinear_call(case, uv, mode),
                    p.sample_bilinear(&texture, uv, &address),
                    texture.texel(i, j),
                    1e-5,
                    1e-4,
                )
                .map_err(|e| {
                    with_slip(
                        format!("{e}, texel {}", texel_name(i, j)),
                        p,
                        "at a texel's centre the lookup is that texel (texel k's centre is k + ½ texels from the edge)",
                    )
                })?;
            }
        }
    }
    Ok(())
}

/// An affine function of `(u, v)` sampled at the texel centres comes back exactly between
/// them.
fn check_affine(
    p: &dyn Texturing,
    base: &dyn Texturing,
    (w, h): (u32, u32),
    (c0, cu, cv): (Vec3, Vec3, Vec3),
    s: Vec2,
) -> Result<(), String> {
    let f = |uv: Vec2| c0 + cu * uv.x + cv * uv.y;
    let mut texture = Texture::from_fn("<affine>", w, h, |_, _| Vec3::ZERO);
    for j in 0..h {
        for i in 0..w {
            let c = texel_centre(&texture, i, j);
            texture.texels[(j * w + i) as usize] = f(c);
        }
    }
    // A point between the first and last texel centres.
    let lo = Vec2::new(0.5 / w as f32, 0.5 / h as f32);
    let uv = lo + s * (Vec2::ONE - 2.0 * lo);
    let address = |t: f32| base.address(t, Addressing::Clamp);
    let got = p.sample_bilinear(&texture, uv, &address);
    compare_vec3(
        &format!("sample_bilinear(a {w}×{h} texture whose texel at centre c holds {c0} + {cu}·c.u + {cv}·c.v, uv = {uv}, Clamp)"),
        got,
        f(uv),
        2e-5,
        1e-4,
    )
    .map_err(|e| {
        with_slip(
            e,
            p,
            "between texel centres, bilinear interpolation reproduces a linear gradient exactly; the weights are the point's fractional position between the centres around it",
        )
    })
}

/// Points next to texel edges, texel centres and the repeat seam, and a step along u or v.
pub type ContinuityInput = (TextureCase, u32, u32, f32, bool, Addressing);

/// Continuity cases: a texture, a column or row boundary, an offset and the axis.
pub fn continuity_input() -> impl Strategy<Value = ContinuityInput> {
    (
        texture_case(),
        0u32..=32,
        0u32..2,
        -2.0f32..2.0,
        any::<bool>(),
        addressing(),
    )
}

/// Across a texel edge (or centre, or the seam at a whole number) the lookup changes by at
/// most the texels' range times the step.
fn check_continuity(
    p: &dyn Texturing,
    base: &dyn Texturing,
    (case, k, centre, other, along_u, mode): ContinuityInput,
) -> Result<(), String> {
    let texture = random_texture(case);
    let n = if along_u { case.0 } else { case.1 } as f32;
    // A texel edge k/n or centre (k + ½)/n, shifted by a whole period or two, so the seam at
    // 0 and 1 (and beyond) is crossed too.
    let period = (other.round() as i32) as f32;
    let at = (k as f32 + 0.5 * centre as f32) / n + period;
    let step = CONTINUITY_STEP_TEXELS / n;
    let other = other.rem_euclid(1.0);
    let point = |t: f32| {
        if along_u {
            Vec2::new(t, other)
        } else {
            Vec2::new(other, t)
        }
    };
    let address = |t: f32| base.address(t, mode);
    let (a, b) = (point(at - step), point(at + step));
    let (ca, cb) = (
        p.sample_bilinear(&texture, a, &address),
        p.sample_bilinear(&texture, b, &address),
    );
    // Texels lie in [0, 1): the change over 2·10⁻³ texels is at most 2·10⁻³, plus rounding.
    let bound = 2.0 * CONTINUITY_STEP_TEXELS + 2e-4 * (1.0 + at.abs() * n);
    let jump = (ca - cb).abs().max_element();
    if jump.is_nan() || jump > bound {
        let place = if (at - at.round()).abs() < 1e-6 && centre == 0 {
            "the texture's edge (the seam of the repeated texture)"
        } else if centre == 0 {
            "a texel edge"
        } else {
            "a texel centre"
        };
        return Err(format!(
            "{} is {ca} but {} is {cb}: across {place} at {} = {at}, {} texels apart, the colour jumps by {jump:.4}; a bilinear lookup is continuous (texels in [0, 1) change it by at most {bound:.4} over that step). Find each of the four neighbours through `address` so that the texels on both sides of the edge or seam are blended",
            bilinear_call(case, a, mode),
            bilinear_call(case, b, mode),
            if along_u { "u" } else { "v" },
            2.0 * CONTINUITY_STEP_TEXELS
        ));
    }
    Ok(())
}

/// The lookup is periodic, mirrored or clamped as its corresponder, and within the texels'
/// range.
fn check_modes(
    p: &dyn Texturing,
    base: &dyn Texturing,
    case: TextureCase,
    s: Vec2,
    k: (i32, i32),
) -> Result<(), String> {
    let texture = random_texture(case);
    let (lo, hi) = texture.texels.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), t| (lo.min(*t), hi.max(*t)),
    );
    let look = |uv: Vec2, mode: Addressing| {
        let address = |t: f32| base.address(t, mode);
        p.sample_bilinear(&texture, uv, &address)
    };
    let shift = Vec2::new(k.0 as f32, k.1 as f32);
    let tol = 1e-4 * (1.0 + shift.abs().max_element() * case.0.max(case.1) as f32);
    for mode in Addressing::ALL {
        let c = look(s, mode);
        if !c.is_finite() || c.cmplt(lo - 1e-5).any() || c.cmpgt(hi + 1e-5).any() {
            return Err(format!(
                "{} is {c}, outside the range [{lo}, {hi}] of the texels: a bilinear lookup is a weighted average of texels, with weights in [0, 1] that sum to 1",
                bilinear_call(case, s, mode)
            ));
        }
    }
    let (repeat, mirror, clamp) = (Addressing::Repeat, Addressing::Mirror, Addressing::Clamp);
    let relations: [(Vec2, Addressing, Vec2, &str); 5] = [
        (
            s + shift,
            repeat,
            s,
            "repeated, the texture is periodic with period 1 in u and v",
        ),
        (
            -s,
            mirror,
            s,
            "mirrored, the texture is symmetric about u = 0 and v = 0",
        ),
        (
            Vec2::splat(2.0) - s + 2.0 * shift,
            mirror,
            s,
            "mirrored, the texture is symmetric about u = 1 and v = 1 and periodic with period 2",
        ),
        (
            Vec2::new(-1.0 - s.x * 3.0, s.y),
            clamp,
            Vec2::new(0.0, s.y),
            "clamped, the texture left of u = 0 is its value at u = 0",
        ),
        (
            Vec2::new(s.x, 1.0 + s.y * 50.0),
            clamp,
            Vec2::new(s.x, 1.0),
            "clamped, the texture above v = 1 is its value at v = 1",
        ),
    ];
    for (uv, mode, same_as, what) in relations {
        let (got, expected) = (look(uv, mode), look(same_as, mode));
        compare_vec3(&bilinear_call(case, uv, mode), got, expected, tol, 0.0)
            .map_err(|e| format!("{e} = {}: {what}", bilinear_call(case, same_as, mode)))?;
    }
    Ok(())
}

fn exercise_9_6(p: &Arc<dyn Texturing>, ctx: &LabContext) -> Result<(), String> {
    let base = ctx.base.code::<dyn contracts::lab09::Texturing>();
    for_all(60, texture_case(), |case| {
        check_centres(p.as_ref(), base.as_ref(), case)
    })?;
    let colour =
        (-2.0f32..2.0, -2.0f32..2.0, -2.0f32..2.0).prop_map(|(r, g, b)| Vec3::new(r, g, b));
    for_all(
        300,
        (
            (2u32..=16, 2u32..=12),
            (colour.clone(), colour.clone(), colour),
            (0.0f32..=1.0, 0.0f32..=1.0).prop_map(|(a, b)| Vec2::new(a, b)),
        ),
        |(size, f, s)| check_affine(p.as_ref(), base.as_ref(), size, f, s),
    )?;
    for_all(600, continuity_input(), |input| {
        check_continuity(p.as_ref(), base.as_ref(), input)
    })?;
    for_all(
        300,
        (
            texture_case(),
            (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| Vec2::new(a, b)),
            (-1000i32..=1000, -3i32..=3),
        ),
        |(case, s, k)| check_modes(p.as_ref(), base.as_ref(), case, s, k),
    )?;
    if let Some(key) = ctx.key() {
        let key = key.code::<dyn contracts::lab09::Texturing>();
        for_all(
            300,
            (texture_case(), texcoords(), addressing()),
            |(case, uv, mode)| {
                let texture = random_texture(case);
                let address = |t: f32| base.address(t, mode);
                let n = case.0.max(case.1) as f32;
                compare_vec3(
                    &bilinear_call(case, uv, mode),
                    p.sample_bilinear(&texture, uv, &address),
                    key.sample_bilinear(&texture, uv, &address),
                    1e-5 + 1e-6 * uv.abs().max_element() * n,
                    1e-4,
                )
                .map_err(|e| with_slip(e, p.as_ref(), ""))
            },
        )?;
    }
    let golden: GoldenFile<(TextureCase, Vec2, Addressing), Vec3> = ctx.golden(GOLDEN_BILINEAR)?;
    for case in &golden.cases {
        let (tex, uv, mode) = case.input;
        let address = |t: f32| base.address(t, mode);
        let n = tex.0.max(tex.1) as f32;
        compare_vec3(
            &bilinear_call(tex, uv, mode),
            p.sample_bilinear(&random_texture(tex), uv, &address),
            case.expected,
            1e-5 + 1e-6 * uv.abs().max_element() * n,
            1e-4,
        )
        .map_err(|e| with_slip(e, p.as_ref(), ""))?;
    }
    check_render(p, Part::Bilinear, ctx)
}
