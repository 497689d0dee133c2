use std::path::PathBuf;
use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use super::checks::*;
use contracts::lab02::Lab02;
use grading::strategies::{point, samples, triangle_strategy};
use grading::{GoldenFile, LabContext};
use raylab_core::Error;
use raylab_core::math::Ray;
use raylab_core::scene::{DirectionalLight, Plane, PointLight, Sphere};

/// Relative margin that keeps golden cases away from decisions two correct implementations may
/// take differently in floating point (grazing rays, hits on an edge or at tmin/tmax).
const MARGIN: f64 = 1e-3;

/// `r` with its interval widened (`grow`) or narrowed by the margin.
fn nudged(r: &RayInput, grow: bool) -> RayInput {
    let m = if grow {
        -(MARGIN as f32)
    } else {
        MARGIN as f32
    };
    let tmax = if r.3 >= f32::MAX {
        r.3
    } else {
        r.3 - m * (1.0 + r.3.abs())
    };
    (r.0, r.1, r.2 + m * (1.0 + r.2.abs()), tmax)
}

/// Whether two answers (the distance of a hit, or a miss) are the same up to the margin.
fn agree(a: Option<f32>, b: Option<f32>) -> bool {
    match (a, b) {
        (None, None) => true,
        (Some(x), Some(y)) => ((x - y).abs() as f64) <= MARGIN * (1.0 + x.abs() as f64),
        _ => false,
    }
}

/// Whether the reference's answer on `r` stays the same with the interval widened and
/// narrowed: no hit lies near `tmin` or `tmax`.
fn clear_of_limits(r: &RayInput, answer: impl Fn(&Ray) -> Option<f32>) -> bool {
    let here = answer(&ray(r));
    [true, false]
        .into_iter()
        .all(|grow| agree(here, answer(&ray(&nudged(r, grow)))))
}

/// The ray is not grazing the plane with unit normal `n`.
fn not_grazing(r: &RayInput, n: Vec3) -> bool {
    r.1.normalize().dot(n.normalize()).abs() > 0.05
}

fn plane_is_clear(reference: &dyn Lab02, r: &RayInput, p: &Plane) -> bool {
    not_grazing(r, p.normal)
        && clear_of_limits(r, |ray| {
            reference.intersect_plane(ray, p).map(|h| h.distance)
        })
}

/// The triangle scaled by `factor` about its centroid.
fn scaled(t: &[Vec3; 3], factor: f32) -> [Vec3; 3] {
    let c = (t[0] + t[1] + t[2]) / 3.0;
    t.map(|v| c + factor * (v - c))
}

fn triangle_is_clear(reference: &dyn Lab02, r: &RayInput, t: &[Vec3; 3]) -> bool {
    let answer = |t: &[Vec3; 3], ray: &Ray| {
        reference
            .intersect_triangle(ray, t[0], t[1], t[2])
            .map(|h| h.distance)
    };
    let here = answer(t, &ray(r));
    // Not near an edge: the answer stays when the triangle grows or shrinks a little.
    not_grazing(r, (t[1] - t[0]).cross(t[2] - t[0]))
        && [1.0 + 3.0 * MARGIN as f32, 1.0 - 3.0 * MARGIN as f32]
            .into_iter()
            .all(|f| agree(here, answer(&scaled(t, f), &ray(r))))
        && clear_of_limits(r, |ray| answer(t, ray))
}

fn sphere_is_clear(reference: &dyn Lab02, r: &RayInput, s: &Sphere) -> bool {
    let answer = |s: &Sphere, ray: &Ray| reference.intersect_sphere(ray, s).map(|h| h.distance);
    let here = answer(s, &ray(r));
    // Not grazing: the answer stays when the radius changes by 1%.
    [1.01f32, 0.99].into_iter().all(|f| {
        let other = Sphere {
            radius: s.radius * f,
            ..*s
        };
        here.is_some() == answer(&other, &ray(r)).is_some()
    }) && clear_of_limits(r, |ray| answer(s, ray))
}

/// Writes lab 02's golden cases and snapshots from `reference` into the lab's directory.
pub fn generate_golden(
    reference: &Arc<dyn Lab02>,
    ctx: &LabContext,
) -> Result<Vec<PathBuf>, Error> {
    let r = reference.as_ref();
    let mut written = Vec::new();

    let planes: Vec<(RayInput, Plane)> = samples(
        plane_strategy().prop_flat_map(|p| (ray_towards(-p.d * p.normal, 6.0), Just(p))),
        400,
        21,
    )
    .into_iter()
    .filter(|(ray_in, p)| plane_is_clear(r, ray_in, p))
    .take(96)
    .collect();
    let path = ctx.golden_path(GOLDEN_PLANE);
    GoldenFile::record("2.1", &planes, |(ri, p)| r.intersect_plane(&ray(ri), p)).save(&path)?;
    written.push(path);

    let triangles: Vec<(RayInput, [Vec3; 3])> = samples(
        triangle_strategy()
            .prop_flat_map(|t| (ray_towards((t[0] + t[1] + t[2]) / 3.0, 2.0), Just(t))),
        600,
        22,
    )
    .into_iter()
    .filter(|(ri, t)| triangle_is_clear(r, ri, t))
    .take(128)
    .collect();
    let path = ctx.golden_path(GOLDEN_TRIANGLE);
    GoldenFile::record("2.2", &triangles, |(ri, t)| {
        r.intersect_triangle(&ray(ri), t[0], t[1], t[2])
    })
    .save(&path)?;
    written.push(path);

    let spheres: Vec<(RayInput, Sphere)> = samples(
        sphere_strategy().prop_flat_map(|s| (ray_towards(s.center, s.radius * 1.5), Just(s))),
        600,
        23,
    )
    .into_iter()
    .filter(|(ri, s)| sphere_is_clear(r, ri, s))
    .take(128)
    .collect();
    let path = ctx.golden_path(GOLDEN_SPHERE);
    GoldenFile::record("2.3", &spheres, |(ri, s)| r.intersect_sphere(&ray(ri), s)).save(&path)?;
    written.push(path);

    let lights: Vec<PointLightInput> = samples(
        (point(5.0), point(50.0), point(5.0))
            .prop_filter("apart", |(l, _, p)| (*l - *p).length() > 0.1),
        64,
        24,
    )
    .into_iter()
    .map(|(l, i, p)| (l, i.abs(), p))
    .collect();
    let path = ctx.golden_path(GOLDEN_POINT_LIGHT);
    GoldenFile::record("2.4", &lights, |&(position, intensity, p)| {
        r.sample_point_light(
            &PointLight {
                position,
                intensity,
            },
            p,
        )
    })
    .save(&path)?;
    written.push(path);

    let directional: Vec<DirectionalLightInput> = samples(directional_light_strategy(), 32, 25);
    let path = ctx.golden_path(GOLDEN_DIRECTIONAL_LIGHT);
    GoldenFile::record("2.5", &directional, |&(direction, emission, p)| {
        let sample = r.sample_directional_light(
            &DirectionalLight {
                direction,
                emission,
            },
            p,
        );
        (sample.direction, sample.radiance)
    })
    .save(&path)?;
    written.push(path);

    let shading: Vec<LambertianInput> = samples(lambertian_strategy(), 64, 26);
    let path = ctx.golden_path(GOLDEN_LAMBERTIAN);
    GoldenFile::record("2.6", &shading, |(rho, n, lights)| {
        r.shade_lambertian(*rho, *n, &samples_of(lights))
    })
    .save(&path)?;
    written.push(path);

    for (part, name, _, view) in Part::ALL {
        let path = ctx.snapshot_path(&format!("{name}.exr"));
        if written.contains(&path) {
            continue;
        }
        let film = render_part(part, &part_pipeline(part, reference, &ctx.base, view))?;
        raylab_core::film::write_exr(&film, &path)?;
        written.push(path);
    }
    Ok(written)
}
