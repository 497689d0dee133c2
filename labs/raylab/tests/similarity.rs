//! `raylab similarity` on a class of three: two near-copies of lab 2 and one honest solution.
//!
//! Alice fills in the handout's stubs; Bob hands in her code with the variables renamed, the
//! functions and the two `impl` blocks in another order and his own comments; Carol solves the
//! lab on her own. Dolos must find Alice and Bob above the threshold and neither with Carol.

// `raylab similarity` is an instructor's command.
#![cfg(feature = "instructor")]

use std::fs;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The repository the command line was built from.
fn repository() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Alice's answers, one per stub of lab 2, in the stubs' order.
const ALICE: [&str; 6] = [
    r#"        // The ray meets the plane where n·(o + t d) + d = 0.
        let denom = ray.direction.dot(plane.normal);
        if denom == 0.0 {
            return None;
        }
        let t = -(ray.origin.dot(plane.normal) + plane.d) / denom;
        ray.accepts(t).then_some(SurfaceHit {
            distance: t,
            normal: plane.normal,
        })"#,
    r#"        // Möller–Trumbore.
        let e1 = v1 - v0;
        let e2 = v2 - v0;
        let p = ray.direction.cross(e2);
        let det = e1.dot(p);
        if det == 0.0 {
            return None;
        }
        let inv_det = 1.0 / det;
        let s = ray.origin - v0;
        let beta = s.dot(p) * inv_det;
        if !(0.0..=1.0).contains(&beta) {
            return None;
        }
        let q = s.cross(e1);
        let gamma = ray.direction.dot(q) * inv_det;
        if gamma < 0.0 || beta + gamma > 1.0 {
            return None;
        }
        let t = e2.dot(q) * inv_det;
        ray.accepts(t).then(|| TriangleHit {
            distance: t,
            beta,
            gamma,
            normal: e1.cross(e2).normalize(),
        })"#,
    r#"        let oc = ray.origin - sphere.center;
        let a = ray.direction.length_squared();
        let half_b = oc.dot(ray.direction);
        let c = oc.length_squared() - sphere.radius * sphere.radius;
        let disc = half_b * half_b - a * c;
        if disc < 0.0 {
            return None;
        }
        let root = disc.sqrt();
        let near = (-half_b - root) / a;
        let far = (-half_b + root) / a;
        let t = if ray.accepts(near) {
            near
        } else if ray.accepts(far) {
            far
        } else {
            return None;
        };
        Some(SurfaceHit {
            distance: t,
            normal: (ray.at(t) - sphere.center) / sphere.radius,
        })"#,
    r#"        let to_light = light.position - position;
        let distance = to_light.length();
        LightSample {
            direction: to_light / distance,
            distance,
            radiance: light.intensity / (distance * distance),
        }"#,
    r#"        LightSample {
            direction: -light.direction.normalize(),
            distance: f32::INFINITY,
            radiance: light.emission,
        }"#,
    r#"        let brdf = rho_d / std::f32::consts::PI;
        lights
            .iter()
            .map(|l| brdf * l.radiance * normal.dot(l.direction).max(0.0))
            .sum()"#,
];

/// Bob's copy of Alice's work: names changed, the shading first, the functions reordered, his
/// own comments, none of the stubs' documentation.
const BOB: &str = r#"// Lab 2 by Bob.
#![allow(unused_variables)]

use contracts::glam::Vec3;
use contracts::lab02::{Intersection, LightSample, Shading, SurfaceHit, TriangleHit};
use contracts::math::Ray;
use contracts::scene::{DirectionalLight, Plane, PointLight, Sphere};

#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Shading for Student {
    /// Diffuse shading summed over the lights.
    fn shade_lambertian(&self, rho_d: Vec3, normal: Vec3, lights: &[LightSample]) -> Vec3 {
        let f = rho_d / std::f32::consts::PI;
        lights
            .iter()
            .map(|smp| f * smp.radiance * normal.dot(smp.direction).max(0.0))
            .sum()
    }

    /// A sun: same direction everywhere.
    fn sample_directional_light(&self, light: &DirectionalLight, position: Vec3) -> LightSample {
        LightSample {
            direction: -light.direction.normalize(),
            distance: f32::INFINITY,
            radiance: light.emission,
        }
    }

    /// Inverse square falloff.
    fn sample_point_light(&self, light: &PointLight, position: Vec3) -> LightSample {
        let l = light.position - position;
        let dist = l.length();
        LightSample {
            direction: l / dist,
            distance: dist,
            radiance: light.intensity / (dist * dist),
        }
    }
}

impl Intersection for Student {
    /// Quadratic in t, smaller root first.
    fn intersect_sphere(&self, ray: &Ray, sphere: &Sphere) -> Option<SurfaceHit> {
        let to_center = ray.origin - sphere.center;
        let aa = ray.direction.length_squared();
        let hb = to_center.dot(ray.direction);
        let cc = to_center.length_squared() - sphere.radius * sphere.radius;
        let delta = hb * hb - aa * cc;
        if delta < 0.0 {
            return None;
        }
        let sq = delta.sqrt();
        let t0 = (-hb - sq) / aa;
        let t1 = (-hb + sq) / aa;
        let hit = if ray.accepts(t0) {
            t0
        } else if ray.accepts(t1) {
            t1
        } else {
            return None;
        };
        Some(SurfaceHit {
            distance: hit,
            normal: (ray.at(hit) - sphere.center) / sphere.radius,
        })
    }

    /// Plane: solve for t.
    fn intersect_plane(&self, ray: &Ray, plane: &Plane) -> Option<SurfaceHit> {
        let cos = ray.direction.dot(plane.normal);
        if cos == 0.0 {
            return None;
        }
        let dist = -(ray.origin.dot(plane.normal) + plane.d) / cos;
        ray.accepts(dist).then_some(SurfaceHit {
            distance: dist,
            normal: plane.normal,
        })
    }

    /// Cramer's rule on the edges.
    fn intersect_triangle(&self, ray: &Ray, v0: Vec3, v1: Vec3, v2: Vec3) -> Option<TriangleHit> {
        let edge_a = v1 - v0;
        let edge_b = v2 - v0;
        let pv = ray.direction.cross(edge_b);
        let d = edge_a.dot(pv);
        if d == 0.0 {
            return None;
        }
        let inv = 1.0 / d;
        let tv = ray.origin - v0;
        let u = tv.dot(pv) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let qv = tv.cross(edge_a);
        let w = ray.direction.dot(qv) * inv;
        if w < 0.0 || u + w > 1.0 {
            return None;
        }
        let dist = edge_b.dot(qv) * inv;
        ray.accepts(dist).then(|| TriangleHit {
            distance: dist,
            beta: u,
            gamma: w,
            normal: edge_a.cross(edge_b).normalize(),
        })
    }
}
"#;

/// Carol's own answers, one per stub of lab 2, in the stubs' order.
const CAROL: [&str; 6] = [
    r#"        let n = plane.normal;
        let along = n.dot(ray.direction);
        if along.abs() < f32::EPSILON {
            None
        } else {
            let distance = (-plane.d - n.dot(ray.origin)) / along;
            if ray.accepts(distance) {
                Some(SurfaceHit { distance, normal: n })
            } else {
                None
            }
        }"#,
    r#"        // Solve o + t d = (1 - b - g) v0 + b v1 + g v2 with Cramer's rule, column by column.
        let a_col = v0 - v1;
        let b_col = v0 - v2;
        let rhs = v0 - ray.origin;
        let det3 = |x: Vec3, y: Vec3, z: Vec3| x.dot(y.cross(z));
        let m = det3(a_col, b_col, ray.direction);
        if m.abs() < 1e-12 {
            return None;
        }
        let beta = det3(rhs, b_col, ray.direction) / m;
        let gamma = det3(a_col, rhs, ray.direction) / m;
        let t = det3(a_col, b_col, rhs) / m;
        let inside = beta >= 0.0 && gamma >= 0.0 && beta + gamma <= 1.0;
        match inside && ray.accepts(t) {
            true => {
                let normal = (v1 - v0).cross(v2 - v0).normalize();
                Some(TriangleHit { distance: t, beta, gamma, normal })
            }
            false => None,
        }"#,
    r#"        let mut hits = Vec::new();
        let from_center = ray.origin - sphere.center;
        let qa = ray.direction.dot(ray.direction);
        let qb = 2.0 * ray.direction.dot(from_center);
        let qc = from_center.dot(from_center) - sphere.radius.powi(2);
        let discriminant = qb * qb - 4.0 * qa * qc;
        if discriminant >= 0.0 {
            for sign in [-1.0, 1.0] {
                hits.push((-qb + sign * discriminant.sqrt()) / (2.0 * qa));
            }
        }
        let t = hits.into_iter().find(|&t| ray.accepts(t))?;
        let point = ray.origin + t * ray.direction;
        Some(SurfaceHit { distance: t, normal: (point - sphere.center).normalize() })"#,
    r#"        let offset = light.position - position;
        let r2 = offset.length_squared();
        let r = r2.sqrt();
        LightSample { direction: offset / r, distance: r, radiance: light.intensity * r2.recip() }"#,
    r#"        let towards = light.direction.normalize() * -1.0;
        LightSample { distance: f32::MAX.max(f32::INFINITY), radiance: light.emission, direction: towards }"#,
    r#"        let mut sum = Vec3::ZERO;
        for sample in lights {
            let cosine = normal.dot(sample.direction);
            if cosine > 0.0 {
                sum += sample.radiance * cosine;
            }
        }
        sum * rho_d * std::f32::consts::FRAC_1_PI"#,
];

/// The stubs of lab 2 with each `todo!` replaced by one of `answers`.
fn filled_stubs(answers: &[&str; 6]) -> String {
    let stubs = fs::read_to_string(repository().join("labs/lab02/src/lib.rs")).unwrap();
    let mut answers = answers.iter();
    let filled: Vec<String> = stubs
        .lines()
        .map(|line| {
            if line.trim_start().starts_with("todo!(") {
                answers.next().expect("six stubs").to_string()
            } else {
                line.to_string()
            }
        })
        .collect();
    assert!(answers.next().is_none(), "every answer went into a stub");
    filled.join("\n") + "\n"
}

/// A submission named `student` in `class` whose lab 2 is `lib_rs`.
fn submission(class: &Path, student: &str, lib_rs: &str) -> String {
    let src = class.join(student).join("labs/lab02/src");
    fs::create_dir_all(&src).unwrap();
    fs::write(src.join("lib.rs"), lib_rs).unwrap();
    class.join(student).to_string_lossy().into_owned()
}

/// The rows of similarity.csv after its header.
fn rows(csv: &str) -> Vec<Vec<String>> {
    csv.lines()
        .skip(1)
        .map(|line| line.split(',').map(str::to_string).collect())
        .collect()
}

#[test]
fn near_copies_are_similar_and_an_honest_solution_is_not() {
    let dolos = repository().join("target/dolos");
    if !dolos.join("node_modules/@dodona/dolos-lib").is_dir()
        && !grading::prerequisite::skip_or_fail(
            "similarity::near_copies_are_similar_and_an_honest_solution_is_not",
            "Dolos",
            "bash labs/raylab/scripts/install-dolos.sh",
        )
    {
        return;
    }
    let class = std::env::temp_dir().join(format!("raylab-similarity-{}", std::process::id()));
    let out = class.join("out");
    fs::create_dir_all(&out).unwrap();
    let submissions = [
        submission(&class, "alice", &filled_stubs(&ALICE)),
        submission(&class, "bob", BOB),
        submission(&class, "carol", &filled_stubs(&CAROL)),
        // Dan has not started: the stubs as handed out are no submission to compare.
        submission(
            &class,
            "dan",
            &fs::read_to_string(repository().join("labs/lab02/src/lib.rs")).unwrap(),
        ),
    ];
    // The class page of `raylab grade`, to which the similar pairs are added.
    fs::write(
        out.join("index.html"),
        "<html><body><h1>Grades</h1><footer><p>stamp</p></footer></body></html>",
    )
    .unwrap();
    let output = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .arg("similarity")
        .args(&submissions)
        .args(["--out", &out.to_string_lossy(), "--lab", "2", "--dolos"])
        .arg(&dolos)
        .output()
        .expect("raylab runs");
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success(),
        "{stdout}{}",
        String::from_utf8_lossy(&output.stderr)
    );
    assert!(
        stdout.contains("lab02: 3 submissions compared, 1 of 3 pairs at or above 0.6"),
        "{stdout}"
    );

    let csv = fs::read_to_string(out.join("similarity.csv")).unwrap();
    let rows = rows(&csv);
    assert_eq!(rows.len(), 1, "only Alice and Bob are similar:\n{csv}");
    let [lab, a, b, similarity, longest, fragment_a, fragment_b] = &rows[0][..] else {
        panic!("seven columns: {csv}");
    };
    assert_eq!(
        (lab.as_str(), a.as_str(), b.as_str()),
        ("lab02", "alice", "bob")
    );
    let similarity: f64 = similarity.parse().unwrap();
    assert!(similarity >= 0.8, "Alice and Bob: {similarity}");
    assert!(longest.parse::<u32>().unwrap() > 10, "{csv}");
    assert!(fragment_a.starts_with("labs/lab02/src/lib.rs:"), "{csv}");
    assert!(fragment_b.starts_with("labs/lab02/src/lib.rs:"), "{csv}");

    let page = fs::read_to_string(out.join("similarity.html")).unwrap();
    assert!(page.contains("<td>alice</td><td>bob</td>"), "{page}");
    assert!(page.contains("dan: labs/lab02/src is the stubs, unchanged"));
    let index = fs::read_to_string(out.join("index.html")).unwrap();
    assert!(
        index.contains("<section id=\"similarity\">")
            && index.contains("href=\"similarity.html\"")
            && index.contains("<td>alice</td><td>bob</td>"),
        "{index}"
    );
    fs::remove_dir_all(&class).ok();
}
