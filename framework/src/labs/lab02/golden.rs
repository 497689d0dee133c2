use std::path::PathBuf;
use std::sync::Arc;

use glam::{DVec3, Vec3};
use proptest::prelude::*;

use super::Lab02;
use super::checks::*;
use crate::Error;
use crate::grading::{GoldenFile, LabContext};
use crate::labs::strategies::{point, samples};
use crate::scene::{Plane, PointLight, Sphere};

/// Relative margin that keeps golden cases away from decisions two correct implementations may
/// take differently in floating point (grazing rays, hits on an edge or at tmin/tmax).
const MARGIN: f64 = 1e-3;

fn clear_of_limits(t: f64, r: &RayInput) -> bool {
    let scale = 1.0 + t.abs();
    (t - r.2 as f64).abs() > MARGIN * scale && (t - r.3 as f64).abs() > MARGIN * scale
}

fn plane_is_clear(r: &RayInput, p: &Plane) -> bool {
    let (o, d, n) = (r.0.as_dvec3(), r.1.as_dvec3(), p.normal.as_dvec3());
    let dn = d.dot(n);
    if dn.abs() < 0.05 {
        return false;
    }
    clear_of_limits(-(o.dot(n) + p.d as f64) / dn, r)
}

fn triangle_is_clear(r: &RayInput, t: &[Vec3; 3]) -> bool {
    let (o, d) = (r.0.as_dvec3(), r.1.as_dvec3());
    let [v0, v1, v2] = t.map(|v| v.as_dvec3());
    let (e1, e2) = (v1 - v0, v2 - v0);
    let p = d.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-3 * e1.length() * e2.length() {
        return false;
    }
    let s = o - v0;
    let beta = s.dot(p) / det;
    let q = s.cross(e1);
    let gamma = d.dot(q) / det;
    let dist = e2.dot(q) / det;
    [beta, gamma, 1.0 - beta - gamma]
        .iter()
        .all(|w| w.abs() > MARGIN)
        && clear_of_limits(dist, r)
}

fn sphere_is_clear(r: &RayInput, s: &Sphere) -> bool {
    let (o, d) = (r.0.as_dvec3(), r.1.as_dvec3());
    let oc: DVec3 = o - s.center.as_dvec3();
    let b = oc.dot(d);
    let c = oc.dot(oc) - (s.radius as f64).powi(2);
    let disc = b * b - c;
    if disc.abs() < 1e-2 * (s.radius as f64).powi(2) {
        return false;
    }
    disc < 0.0 || {
        let h = disc.sqrt();
        clear_of_limits(-b - h, r) && clear_of_limits(-b + h, r)
    }
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
    .filter(|(ray_in, p)| plane_is_clear(ray_in, p))
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
    .filter(|(ri, t)| triangle_is_clear(ri, t))
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
    .filter(|(ri, s)| sphere_is_clear(ri, s))
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
        crate::film::write_exr(&film, &path)?;
        written.push(path);
    }
    Ok(written)
}
