//! Lab 01's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use contracts::lab01::{CameraBasis, CameraRays};
use raylab_core::glam::{UVec2, Vec2, Vec3};
use raylab_core::math::Ray;
use reference::lab01::Lab01 as Reference;

use grading::corpus::Verdict;

type Coords = fn(Vec2, UVec2) -> Vec2;
type Basis = fn(Vec3, Vec3, Vec3) -> CameraBasis;
type Fov = fn(f32) -> f32;
type Direction = fn(&CameraBasis, f32, Vec2) -> Vec3;
type CamRay = fn(Vec3, Vec3) -> Ray;

/// The reference camera with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    coords: Option<Coords>,
    basis: Option<Basis>,
    fov: Option<Fov>,
    direction: Option<Direction>,
    ray: Option<CamRay>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    coords: None,
    basis: None,
    fov: None,
    direction: None,
    ray: None,
};

impl CameraRays for Variant {
    fn image_plane_coords(&self, raster: Vec2, resolution: UVec2) -> Vec2 {
        self.coords.map_or_else(
            || Reference.image_plane_coords(raster, resolution),
            |f| f(raster, resolution),
        )
    }
    fn camera_basis(&self, eye: Vec3, look_at: Vec3, up: Vec3) -> CameraBasis {
        self.basis.map_or_else(
            || Reference.camera_basis(eye, look_at, up),
            |f| f(eye, look_at, up),
        )
    }
    fn field_of_view(&self, d: f32) -> f32 {
        self.fov
            .map_or_else(|| Reference.field_of_view(d), |f| f(d))
    }
    fn ray_direction(&self, basis: &CameraBasis, d: f32, ip: Vec2) -> Vec3 {
        self.direction.map_or_else(
            || Reference.ray_direction(basis, d, ip),
            |f| f(basis, d, ip),
        )
    }
    fn camera_ray(&self, eye: Vec3, direction: Vec3) -> Ray {
        self.ray.map_or_else(
            || Reference.camera_ray(eye, direction),
            |f| f(eye, direction),
        )
    }
}

/// `v / (|v| + 1e-6)`: the "safe" normalization of a shader, off by `10⁻⁶/|v|`.
fn safe_normalize(v: Vec3) -> Vec3 {
    v / (v.length() + 1e-6)
}

/// Every lab 01 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        Variant {
            name: "x divided by the width (squashes the image to a square)",
            verdict: Verdict::Reject("1.1"),
            coords: Some(|r, res| {
                let (w, h) = (res.x as f32, res.y as f32);
                Vec2::new((r.x - 0.5 * w) / w, (0.5 * h - r.y) / h)
            }),
            ..NONE
        },
        Variant {
            name: "y not flipped (image upside down)",
            verdict: Verdict::Reject("1.1"),
            coords: Some(|r, res| {
                let (w, h) = (res.x as f32, res.y as f32);
                Vec2::new((r.x - 0.5 * w) / h, (r.y - 0.5 * h) / h)
            }),
            ..NONE
        },
        Variant {
            name: "image plane from -1 to 1 (two units high)",
            verdict: Verdict::Reject("1.1"),
            coords: Some(|r, res| {
                let (w, h) = (res.x as f32, res.y as f32);
                Vec2::new(2.0 * (r.x - 0.5 * w) / h, 2.0 * (0.5 * h - r.y) / h)
            }),
            ..NONE
        },
        Variant {
            name: "x axis as up × view (mirrored image)",
            verdict: Verdict::Reject("1.2"),
            basis: Some(|e, l, u| {
                let n = (l - e).normalize();
                let x = u.cross(n).normalize();
                CameraBasis {
                    ip_xaxis: x,
                    ip_yaxis: n.cross(x),
                    ip_normal: n,
                }
            }),
            ..NONE
        },
        Variant {
            name: "x axis not normalized",
            verdict: Verdict::Reject("1.2"),
            basis: Some(|e, l, u| {
                let n = (l - e).normalize();
                let x = n.cross(u);
                CameraBasis {
                    ip_xaxis: x,
                    ip_yaxis: x.cross(n),
                    ip_normal: n,
                }
            }),
            ..NONE
        },
        Variant {
            name: "field of view in radians",
            verdict: Verdict::Reject("1.3"),
            fov: Some(|d| 2.0 * (1.0 / (2.0 * d)).atan()),
            ..NONE
        },
        Variant {
            name: "field of view without the factor 2 (half angle)",
            verdict: Verdict::Reject("1.3"),
            fov: Some(|d| (1.0 / (2.0 * d)).atan().to_degrees()),
            ..NONE
        },
        Variant {
            name: "ray direction not normalized",
            verdict: Verdict::Reject("1.4"),
            direction: Some(|b, d, ip| ip.x * b.ip_xaxis + ip.y * b.ip_yaxis + d * b.ip_normal),
            ..NONE
        },
        Variant {
            name: "ray direction ignores the focal distance",
            verdict: Verdict::Reject("1.4"),
            direction: Some(|b, _d, ip| {
                (ip.x * b.ip_xaxis + ip.y * b.ip_yaxis + b.ip_normal).normalize()
            }),
            ..NONE
        },
        Variant {
            name: "camera ray from the origin instead of the eye",
            verdict: Verdict::Reject("1.5"),
            ray: Some(|_e, d| Ray::new(Vec3::ZERO, d, 0.0, f32::INFINITY)),
            ..NONE
        },
        Variant {
            name: "camera ray with tmax = 1 (clips the scene)",
            verdict: Verdict::Reject("1.5"),
            ray: Some(|e, d| Ray::new(e, d, 0.0, 1.0)),
            ..NONE
        },
        // Mistakes the checks' usual cameras hid: positions from 10⁻³ to 10⁴ units, the raster
        // conventions of other courses.
        Variant {
            name: "raster floored to the pixel's corner",
            verdict: Verdict::Reject("1.1"),
            coords: Some(|r, res| Reference.image_plane_coords(r.floor(), res)),
            ..NONE
        },
        Variant {
            name: "the image centre by integer division (W/2, H/2 in u32)",
            verdict: Verdict::Reject("1.1"),
            coords: Some(|r, res| {
                let centre = (res / 2).as_vec2();
                let h = res.y as f32;
                Vec2::new((r.x - centre.x) / h, (centre.y - r.y) / h)
            }),
            ..NONE
        },
        Variant {
            name: "width and height swapped",
            verdict: Verdict::Reject("1.1"),
            coords: Some(|r, res| Reference.image_plane_coords(r, UVec2::new(res.y, res.x))),
            ..NONE
        },
        Variant {
            name: "basis: up itself as ip_yaxis",
            verdict: Verdict::Reject("1.2"),
            basis: Some(|e, l, u| {
                let n = (l - e).normalize();
                CameraBasis {
                    ip_xaxis: n.cross(u).normalize(),
                    ip_yaxis: u.normalize(),
                    ip_normal: n,
                }
            }),
            ..NONE
        },
        Variant {
            name: "basis: normalization with an absolute epsilon, v / (|v| + 1e-6)",
            verdict: Verdict::Reject("1.2"),
            basis: Some(|e, l, u| {
                let n = safe_normalize(l - e);
                let x = safe_normalize(n.cross(u));
                CameraBasis {
                    ip_xaxis: x,
                    ip_yaxis: x.cross(n),
                    ip_normal: n,
                }
            }),
            ..NONE
        },
        Variant {
            name: "ray direction: normalization with an absolute epsilon, v / (|v| + 1e-6)",
            verdict: Verdict::Reject("1.4"),
            direction: Some(|b, d, ip| {
                safe_normalize(ip.x * b.ip_xaxis + ip.y * b.ip_yaxis + d * b.ip_normal)
            }),
            ..NONE
        },
        Variant {
            name: "camera ray with tmin = 1e-3 (a secondary ray's epsilon)",
            verdict: Verdict::Reject("1.5"),
            ray: Some(|e, d| Ray::new(e, d, 1e-3, f32::INFINITY)),
            ..NONE
        },
        // Correct alternatives.
        Variant {
            name: "image-plane coordinates from a pixel size and the lower-left corner (DTU style)",
            verdict: Verdict::Accept,
            coords: Some(|r, res| {
                let pixel = 1.0 / res.y as f32;
                let lower_left = Vec2::new(-0.5 * res.x as f32 * pixel, -0.5);
                let flipped = Vec2::new(r.x, res.y as f32 - r.y);
                lower_left + flipped * pixel
            }),
            ..NONE
        },
        Variant {
            name: "basis by Gram–Schmidt on up",
            verdict: Verdict::Accept,
            basis: Some(|e, l, u| {
                let n = (l - e).normalize();
                let y = (u - u.dot(n) * n).normalize();
                CameraBasis {
                    ip_xaxis: n.cross(y),
                    ip_yaxis: y,
                    ip_normal: n,
                }
            }),
            fov: Some(|d| 2.0f32.to_degrees() * 1.0f32.atan2(2.0 * d)),
            ..NONE
        },
        Variant {
            name: "camera ray with tmax = f32::MAX; direction divided by its length",
            verdict: Verdict::Accept,
            ray: Some(|e, d| Ray::new(e, d, 0.0, f32::MAX)),
            direction: Some(|b, d, ip| {
                let v = ip.x * b.ip_xaxis + ip.y * b.ip_yaxis + d * b.ip_normal;
                v / v.length()
            }),
            ..NONE
        },
        Variant {
            name: "ray direction with the image-plane point divided by d (the plane at distance 1)",
            verdict: Verdict::Accept,
            direction: Some(|b, d, ip| {
                (ip.x / d * b.ip_xaxis + ip.y / d * b.ip_yaxis + b.ip_normal).normalize()
            }),
            ..NONE
        },
    ]
}

/// The lab's exercises as a judge takes them.
fn table() -> Vec<std::sync::Arc<grading::Exercise<dyn CameraRays>>> {
    lab01_checks::checks::exercises()
        .into_iter()
        .map(std::sync::Arc::new)
        .collect()
}

/// Each exercise of the lab judged on `code` with the key: its id, its points and the
/// judgement.
fn judged(code: Variant) -> Vec<(String, u32, grading::Judgement)> {
    let table = table();
    let code: std::sync::Arc<dyn CameraRays> = std::sync::Arc::new(code);
    let judge = grading::Judge::new(
        &table,
        &code,
        &std::sync::Arc::new(corpus_context(reference::KEYS)),
    );
    table
        .iter()
        .map(|e| (e.id.clone(), e.points, judge.judge(e)))
        .collect()
}

/// The points of the exercises `judged` passes.
fn score(judged: &[(String, u32, grading::Judgement)]) -> u32 {
    judged
        .iter()
        .filter(|(_, _, j)| j.outcome.is_ok())
        .map(|(_, points, _)| points)
        .sum()
}

/// The judgement of Exercise `id` in `judged`.
fn of<'a>(judged: &'a [(String, u32, grading::Judgement)], id: &str) -> &'a grading::Judgement {
    &judged
        .iter()
        .find(|(e, _, _)| e == id)
        .expect("an exercise of lab 01")
        .2
}

/// The corpus's variant whose name starts with `name`.
fn variant(name: &str) -> Variant {
    variants()
        .into_iter()
        .find(|v| v.name.starts_with(name))
        .unwrap_or_else(|| panic!("the corpus holds '{name}'"))
}

/// One mistake, one exercise: with the key, a y-flip costs Exercise 1.1's 3 points of 10 (1.6,
/// worth none of its own, renders with the key's `image_plane_coords` and says so) and a panic
/// in `camera_ray` 1.5's 1 point; the stubs earn nothing, 1.6 included. Without the key, 1.6
/// names the exercise to fix first.
#[test]
fn a_mistake_in_one_part_costs_that_part_alone() {
    use std::sync::Arc;
    let y_flip = variant("y not flipped");
    let flipped = judged(y_flip);
    assert_eq!(score(&flipped), 7);
    let composite = of(&flipped, "1.6");
    assert_eq!(composite.outcome, Ok(()));
    assert_eq!(composite.key_for, ["1.1"]);
    assert!(
        composite.note.contains("`image_plane_coords`") && composite.note.contains("1.1"),
        "{}",
        composite.note
    );
    assert_eq!(of(&flipped, "1.1").key_for, Vec::<String>::new());
    let panics = judged(Variant {
        ray: Some(|_, _| panic!("a camera ray that panics")),
        ..NONE
    });
    assert_eq!(score(&panics), 9);
    assert_eq!(of(&panics, "1.6").key_for, ["1.5"]);
    let table = table();
    let ctx = corpus_context(reference::KEYS);
    let stubs: Arc<dyn CameraRays> = Arc::new(lab01::Student);
    let judge = grading::Judge::new(&table, &stubs, &Arc::new(ctx));
    assert!(table.iter().all(|e| judge.judge(e).outcome.is_err()));

    let handout = corpus_context(&grading::corpus::keys_but(
        lab01_checks::checks::LAB,
        reference::KEYS,
    ));
    let composite = table.iter().find(|e| e.id == "1.6").unwrap();
    let failure = grading::judge(
        composite,
        &table,
        &(Arc::new(y_flip) as Arc<dyn CameraRays>),
        &handout,
    )
    .outcome
    .expect_err("the y-flip's image is upside down");
    assert!(
        failure
            .message
            .contains("Exercise 1.1 fails on its own: fix that first"),
        "{}",
        failure.message
    );
}

/// Only `camera_ray` right, 1.1–1.4 wrong but finite: 1.5's point and nothing for 1.6, which
/// passes only with the key's functions in place of every wrong one the render calls.
#[test]
fn only_the_camera_ray_right_scores_its_own_point() {
    let wrong = Variant {
        coords: variant("y not flipped").coords,
        basis: variant("x axis as up × view").basis,
        fov: variant("field of view in radians").fov,
        direction: variant("ray direction not normalized").direction,
        ..NONE
    };
    let judged = judged(wrong);
    assert_eq!(score(&judged), 1);
    let composite = of(&judged, "1.6");
    assert_eq!(composite.outcome, Ok(()), "{:?}", composite.outcome);
    // The render calls no `field_of_view`: 1.3's mistake is its own exercise's alone.
    assert_eq!(composite.key_for, ["1.1", "1.2", "1.4"]);
}

/// 1.1 and 1.2 both unfinished: 1.3–1.5 score theirs, and 1.6 is neither charged nor blocked:
/// the first render stops in one of them, the next in the other, and the one after that, with
/// the key's 1.1 and 1.2, passes on the student's 1.3–1.5.
#[test]
fn two_unfinished_parts_are_each_their_own_exercise_s_alone() {
    let unfinished = Variant {
        coords: Some(|_, _| todo!("Exercise 1.1: image_plane_coords")),
        basis: Some(|_, _, _| todo!("Exercise 1.2: camera_basis")),
        ..NONE
    };
    let judged = judged(unfinished);
    assert_eq!(score(&judged), 4);
    let composite = of(&judged, "1.6");
    assert_eq!(composite.outcome, Ok(()), "{:?}", composite.outcome);
    assert_eq!(composite.key_for, ["1.1", "1.2"]);
    for id in ["1.1", "1.2"] {
        let own = of(&judged, id).outcome.as_ref().expect_err(id);
        assert_eq!(
            own.kind,
            grading::FailureKind::NotStarted,
            "{}",
            own.message
        );
    }
}

/// Exercise 1.1's failures name the image the check shrank them to as the resolution, in the
/// words of the exercise, not as the debug form of a `UVec2`.
#[test]
fn a_wrong_image_plane_names_its_resolution() {
    let judged = judged(variant("y not flipped"));
    let failure = of(&judged, "1.1")
        .outcome
        .as_ref()
        .expect_err("an upside-down image fails 1.1");
    assert!(
        failure
            .message
            .contains("for the resolution 1×1 (resolution.x = 1, resolution.y = 1):"),
        "{}",
        failure.message
    );
    assert!(!failure.message.contains("UVec2"), "{}", failure.message);
}

grading::corpus_tests!(lab01, lab01_checks, reference);
