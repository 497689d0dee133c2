//! Lab 01's exercises and their checks.

use std::sync::Arc;

use glam::{UVec2, Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab01::{CameraBasis, CameraRays};
use grading::strategies::{point, resolution, unit_vector};
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, compare_f32, compare_vec2, compare_vec3,
    for_all_named,
};
use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::math::Onb;
use raylab_core::render::RenderSettings;

/// Golden file of Exercise 1.1.
pub const GOLDEN_IMAGE_PLANE: &str = "image_plane_coords.json";
/// Golden file of Exercise 1.2.
pub const GOLDEN_BASIS: &str = "camera_basis.json";
/// Golden file of Exercise 1.3.
pub const GOLDEN_FOV: &str = "field_of_view.json";
/// Golden file of Exercise 1.4.
pub const GOLDEN_DIRECTION: &str = "ray_direction.json";
/// Snapshot of Exercise 1.6 (the built-in default scene in flat colours).
pub const SNAPSHOT_DEFAULT: &str = "default-base-colour";
/// Size and sampling of lab 01's snapshots.
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(1);

/// Input of Exercise 1.1.
pub type ImagePlaneInput = (Vec2, UVec2);
/// Input of Exercise 1.2: eye, look-at point, up.
pub type BasisInput = (Vec3, Vec3, Vec3);
/// Input of Exercise 1.4: basis, focal distance, image-plane point.
pub type DirectionInput = (CameraBasis, f32, Vec2);

/// This lab.
pub const LAB: course::LabId = course::LabId::of(1);

/// The exercises of lab 01 (`labs/lab01/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn CameraRays>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_1_1,
            exercise_1_2,
            exercise_1_3,
            exercise_1_4,
            exercise_1_5,
            exercise_1_6
        ],
    )
}

/// A camera setup whose eye, look-at and up are well apart.
pub fn basis_input() -> impl Strategy<Value = BasisInput> + Clone {
    (point(10.0), point(10.0), unit_vector()).prop_filter(
        "look-at away from eye and up not along the view",
        |(e, l, u)| {
            let v = *l - *e;
            v.length() > 0.1 && v.normalize().cross(*u).length() > 0.1
        },
    )
}

/// The scales the camera checks run at again — a scene of 10⁻³ units to one of 10³ — as the
/// length of the view `look_at − eye` and the size of the eye's offset from the origin.
const SCALES: [f32; 7] = [1e-3, 1e-2, 1e-1, 1.0, 1e1, 1e2, 1e3];

/// How far the eye of a scaled camera sits from the origin: nearby, or 10² and 10⁴ units away
/// (a far-away camera, whose `look_at − eye` loses the low bits of both points).
const EYE_OFFSETS: [f32; 3] = [0.0, 1e2, 1e4];

/// A camera of [`basis_input`] at a scale of [`SCALES`], moved [`EYE_OFFSETS`] away from the
/// origin, with an up vector 10⁻², 1 or 10² long (it need not be unit length). The view must
/// stay at least 10⁻⁴ of the eye's distance from the origin long, so that the points, rounded
/// to `f32`, still give a direction (relative error 10⁻³ at worst).
pub fn scaled_basis_input() -> impl Strategy<Value = BasisInput> + Clone {
    (
        basis_input(),
        0..SCALES.len(),
        0..EYE_OFFSETS.len(),
        unit_vector(),
        prop_oneof![Just(1e-2f32), Just(1.0), Just(1e2)],
    )
        .prop_filter_map(
            "view long enough for the eye's distance from the origin",
            |((e, l, u), k, far, away, up_length)| {
                let (k, far) = (SCALES[k], EYE_OFFSETS[far]);
                let eye = e * k + away * far;
                let look_at = eye + (l - e) * k;
                let view = look_at - eye;
                let up = u * up_length;
                (view.length() >= 1e-4 * eye.length() && view.normalize().cross(u).length() > 0.1)
                    .then_some((eye, look_at, up))
            },
        )
}

/// A resolution of Exercise 1.1 as a failure names it.
fn resolution_named(res: &UVec2) -> String {
    format!(
        "the resolution {}×{} (resolution.x = {}, resolution.y = {})",
        res.x, res.y, res.x, res.y
    )
}

/// A camera of Exercise 1.2 as a failure names it.
fn camera_named((eye, look_at, up): &BasisInput) -> String {
    format!("eye = {eye}, look_at = {look_at}, up = {up}")
}

fn exercise_1_1(s: &Arc<dyn CameraRays>, ctx: &LabContext) -> Result<(), String> {
    // Invariants: the image centre is the origin; the corners are at (±W/2H, ±1/2), y up.
    for_all_named(200, resolution(), resolution_named, |res| {
        let (w, h) = (res.x as f32, res.y as f32);
        let centre = s.image_plane_coords(Vec2::new(w / 2.0, h / 2.0), res);
        compare_vec2("the image centre", centre, Vec2::ZERO, 1e-5, 0.0)?;
        let top_left = s.image_plane_coords(Vec2::ZERO, res);
        compare_vec2(
            "the top-left corner (raster 0,0)",
            top_left,
            Vec2::new(-w / (2.0 * h), 0.5),
            1e-5,
            1e-5,
        )?;
        let bottom_right = s.image_plane_coords(Vec2::new(w, h), res);
        compare_vec2(
            "the bottom-right corner (raster W,H)",
            bottom_right,
            Vec2::new(w / (2.0 * h), -0.5),
            1e-5,
            1e-5,
        )
    })?;
    let golden: GoldenFile<ImagePlaneInput, Vec2> = ctx.golden(GOLDEN_IMAGE_PLANE)?;
    for case in &golden.cases {
        let (raster, res) = case.input;
        let got = s.image_plane_coords(raster, res);
        compare_vec2(
            &format!("image_plane_coords({raster}, {res})"),
            got,
            case.expected,
            1e-5,
            1e-5,
        )?;
    }
    Ok(())
}

/// The relations that determine the camera basis of `(eye, look_at, up)`: three unit vectors,
/// mutually perpendicular, `ip_normal` along `look_at − eye`, `ip_xaxis` perpendicular to `up`,
/// `ip_xaxis × ip_yaxis = −ip_normal` (screen right × screen up points back at the eye), and
/// `ip_yaxis` leaning towards `up`.
fn check_basis(s: &dyn CameraRays, (eye, look_at, up): BasisInput) -> Result<(), String> {
    let b = s.camera_basis(eye, look_at, up);
    for (name, v) in [
        ("ip_xaxis", b.ip_xaxis),
        ("ip_yaxis", b.ip_yaxis),
        ("ip_normal", b.ip_normal),
    ] {
        compare_f32(
            &format!("the length of {name} {v}"),
            v.length(),
            1.0,
            1e-4,
            0.0,
        )?;
    }
    for (name, a, b) in [
        ("ip_xaxis · ip_yaxis", b.ip_xaxis, b.ip_yaxis),
        ("ip_xaxis · ip_normal", b.ip_xaxis, b.ip_normal),
        ("ip_yaxis · ip_normal", b.ip_yaxis, b.ip_normal),
        ("ip_xaxis · up/|up|", b.ip_xaxis, up.normalize()),
    ] {
        compare_f32(name, a.dot(b), 0.0, 1e-4, 0.0)?;
    }
    compare_vec3(
        "ip_normal (it must point from the eye to the look-at point)",
        b.ip_normal,
        (look_at - eye).normalize(),
        1e-4,
        0.0,
    )?;
    compare_vec3(
        "ip_xaxis × ip_yaxis (screen right × screen up must point back at the eye, −ip_normal; the other sign mirrors the image)",
        b.ip_xaxis.cross(b.ip_yaxis),
        -b.ip_normal,
        1e-4,
        0.0,
    )?;
    if b.ip_yaxis.dot(up) <= 0.0 {
        return Err(format!("ip_yaxis {} points away from up {up}", b.ip_yaxis));
    }
    Ok(())
}

fn exercise_1_2(s: &Arc<dyn CameraRays>, ctx: &LabContext) -> Result<(), String> {
    for_all_named(300, basis_input(), camera_named, |input| {
        check_basis(s.as_ref(), input)
    })?;
    // The same relations for cameras from 10⁻³ to 10³ units, up to 10⁴ units from the origin.
    for_all_named(300, scaled_basis_input(), camera_named, |input| {
        check_basis(s.as_ref(), input).map_err(|e| {
            format!(
                "{e} (a camera at the scale of its view, |look_at − eye| = {})",
                (input.1 - input.0).length()
            )
        })
    })?;
    let golden: GoldenFile<BasisInput, CameraBasis> = ctx.golden(GOLDEN_BASIS)?;
    for case in &golden.cases {
        let (eye, look_at, up) = case.input;
        let b = s.camera_basis(eye, look_at, up);
        let call = format!("camera_basis({eye}, {look_at}, {up})");
        compare_vec3(
            &format!("ip_xaxis of {call}"),
            b.ip_xaxis,
            case.expected.ip_xaxis,
            1e-4,
            0.0,
        )?;
        compare_vec3(
            &format!("ip_yaxis of {call}"),
            b.ip_yaxis,
            case.expected.ip_yaxis,
            1e-4,
            0.0,
        )?;
        compare_vec3(
            &format!("ip_normal of {call}"),
            b.ip_normal,
            case.expected.ip_normal,
            1e-4,
            0.0,
        )?;
    }
    Ok(())
}

fn exercise_1_3(s: &Arc<dyn CameraRays>, ctx: &LabContext) -> Result<(), String> {
    // d = ½ sees the image plane (height 1) under 90°.
    compare_f32(
        "field_of_view(0.5) (degrees)",
        s.field_of_view(0.5),
        90.0,
        1e-3,
        0.0,
    )?;
    let distances =
        |(a, b): &(f32, f32)| format!("the focal distances {} and {}", a.min(*b), a.max(*b));
    for_all_named(100, (0.05f32..10.0, 0.05f32..10.0), distances, |(a, b)| {
        let (near, far) = (a.min(b), a.max(b));
        if far - near > 1e-3 && s.field_of_view(far) >= s.field_of_view(near) {
            return Err("a longer focal distance must give a narrower field of view".into());
        }
        Ok(())
    })?;
    let golden: GoldenFile<f32, f32> = ctx.golden(GOLDEN_FOV)?;
    for case in &golden.cases {
        compare_f32(
            &format!("field_of_view({}) (degrees)", case.input),
            s.field_of_view(case.input),
            case.expected,
            1e-3,
            1e-5,
        )?;
    }
    Ok(())
}

/// An input of Exercise 1.4 over the whole range of cameras: an orthonormal camera basis about
/// a random viewing direction, a focal distance from 10⁻³ (a field of view of almost 180°) to
/// 10³ (a telephoto lens of 0.06°), and an image-plane point at the centre, anywhere on a 2:1
/// image, or within 10⁻⁴ to 1 of the centre (the pixels near the optical axis).
pub fn wide_direction_input() -> impl Strategy<Value = DirectionInput> + Clone {
    let ip = prop_oneof![
        Just(Vec2::ZERO),
        (-1.0f32..1.0, -0.5f32..0.5).prop_map(|(x, y)| Vec2::new(x, y)),
        (-1.0f32..1.0, -0.5f32..0.5, -4.0f32..0.0)
            .prop_map(|(x, y, e)| Vec2::new(x, y) * 10f32.powf(e)),
    ];
    (unit_vector(), -3.0f32..3.0, ip).prop_map(|(n, e, ip)| {
        // Onb's v is n × u; the camera's ip_yaxis is ip_xaxis × ip_normal = −v.
        let onb = Onb::from_w(n);
        let basis = CameraBasis {
            ip_xaxis: onb.u,
            ip_yaxis: -onb.v,
            ip_normal: onb.w,
        };
        (basis, 10f32.powf(e), ip)
    })
}

fn exercise_1_4(s: &Arc<dyn CameraRays>, ctx: &LabContext) -> Result<(), String> {
    // In the camera's own coordinates the direction is (x_ip, y_ip, d), normalized.
    let named = |(basis, d, ip): &DirectionInput| {
        format!(
            "d = {d}, ip = {ip} and the basis ip_xaxis = {}, ip_yaxis = {}, ip_normal = {}",
            basis.ip_xaxis, basis.ip_yaxis, basis.ip_normal
        )
    };
    for_all_named(300, wide_direction_input(), named, |(basis, d, ip)| {
        let got = s.ray_direction(&basis, d, ip);
        let call = format!("ray_direction(basis, d = {d}, ip = {ip})");
        compare_f32(
            &format!("the length of {call} = {got}"),
            got.length(),
            1.0,
            1e-4,
            0.0,
        )?;
        let local = Vec3::new(
            got.dot(basis.ip_xaxis),
            got.dot(basis.ip_yaxis),
            got.dot(basis.ip_normal),
        );
        let expected = glam::DVec3::new(f64::from(ip.x), f64::from(ip.y), f64::from(d))
            .normalize()
            .as_vec3();
        compare_vec3(
            &format!("{call} in the camera's coordinates (· ip_xaxis, · ip_yaxis, · ip_normal)"),
            local,
            expected,
            1e-4,
            0.0,
        )
    })?;
    let golden: GoldenFile<DirectionInput, Vec3> = ctx.golden(GOLDEN_DIRECTION)?;
    for case in &golden.cases {
        let (basis, d, ip) = case.input;
        let got = s.ray_direction(&basis, d, ip);
        let call = format!("ray_direction(basis, d = {d}, ip = {ip})");
        compare_f32(
            &format!("the length of {call} = {got}"),
            got.length(),
            1.0,
            1e-4,
            0.0,
        )?;
        compare_vec3(&call, got, case.expected, 1e-4, 0.0)?;
    }
    Ok(())
}

fn exercise_1_5(s: &Arc<dyn CameraRays>, _ctx: &LabContext) -> Result<(), String> {
    let eyes = prop_oneof![
        point(10.0),
        scaled_basis_input().prop_map(|(eye, _, _)| eye)
    ];
    let named = |(eye, dir): &(Vec3, Vec3)| format!("eye = {eye}, direction = {dir}");
    for_all_named(200, (eyes, unit_vector()), named, |(eye, dir)| {
        let r = s.camera_ray(eye, dir);
        compare_vec3("the ray origin (the eye)", r.origin, eye, 0.0, 0.0)?;
        compare_vec3("the ray direction", r.direction, dir, 1e-6, 0.0)?;
        if r.tmin != 0.0 {
            return Err(format!(
                "tmin is {}; a camera ray starts at the eye, tmin = 0 (it leaves no surface, and a fixed tmin > 0 clips everything that near: the whole of a scene of 10⁻³ units)",
                r.tmin
            ));
        }
        let unbounded = r.tmax >= 1e30; // false for NaN
        if !unbounded {
            return Err(format!(
                "tmax is {}; a camera ray is unbounded, tmax = ∞",
                r.tmax
            ));
        }
        Ok(())
    })
}

/// The pipeline of Exercise 1.6 and its snapshot: the student's camera, everything else from
/// `base`, flat colours.
pub fn camera_pipeline(student: Arc<dyn CameraRays>, base: &Pipeline) -> Pipeline {
    let mut pipeline = base.clone().with_part(student);
    pipeline.view = View::BaseColour;
    pipeline
}

/// Renders the default scene as Exercise 1.6 does.
pub fn render_snapshot(pipeline: &Pipeline) -> Result<raylab_core::film::Film, raylab_core::Error> {
    let scene = raylab_core::scene::builtin_scene("default")?;
    render(&scene, pipeline, &SNAPSHOT_SETTINGS)
}

fn exercise_1_6(s: &Arc<dyn CameraRays>, ctx: &LabContext) -> Result<(), String> {
    let film =
        render_snapshot(&camera_pipeline(s.clone(), &ctx.base)).map_err(|e| e.to_string())?;
    // Flat colours: exact up to rounding, except silhouette pixels whose ray may fall on either
    // side of an edge.
    let tol = PixelTolerance {
        abs: 1e-3,
        rel: 0.0,
        max_outlier_fraction: 0.005,
    };
    ctx.check_snapshot(SNAPSHOT_DEFAULT, &film, &tol)
}
