//! Irradiance from a quad light: the estimate against the analytic value.

use std::sync::Arc;

use glam::{Vec2, Vec3};

use contracts::lab03::Shadows;
use grading::radiometry::irradiance_polygon;
use grading::stats::{mean_and_standard_error, normal_two_sided_quantile, sidak};
use pipeline::Pipeline;
use raylab_core::sampling::Rng;
use raylab_core::scene::Scene;
use raylab_core::scene::{Hit, HitSurface};

use super::shadow_rays::{LAMP, WHITE, test_scene};
use super::{Part, part_pipeline};

/// Form factor from a point to a parallel rectangle `[0, a] × [0, b]` whose corner lies at
/// height `h` straight above it, facing it (Howell's catalogue of configuration factors,
/// "differential planar element to parallel rectangle"):
/// `F = 1/(2π) [X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))]`, `X = a/h`, `Y = b/h`.
pub fn form_factor_parallel_corner(a: f64, b: f64, h: f64) -> f64 {
    let (x, y) = (a / h, b / h);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    ((x / sx) * (y / sx).atan() + (y / sy) * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
}

/// Irradiance at a point facing up from a Lambertian rectangle of radiance `le` at height `h`
/// above it, spanning `[x0, x1] × [z0, z1]` relative to the point: `E = π·L_e·F`, with `F`
/// summed from four corner rectangles with signs.
pub fn irradiance_parallel_rectangle(le: f64, h: f64, x: [f64; 2], z: [f64; 2]) -> f64 {
    let g =
        |x: f64, z: f64| x.signum() * z.signum() * form_factor_parallel_corner(x.abs(), z.abs(), h);
    let f = g(x[1], z[1]) - g(x[0], z[1]) - g(x[1], z[0]) + g(x[0], z[0]);
    std::f64::consts::PI * le * f
}

/// One quad-light configuration of the irradiance check.
struct QuadCase {
    what: &'static str,
    corners: [Vec3; 4],
    receiver: Vec3,
    normal: Vec3,
    exact: f64,
}

fn quad_cases() -> Vec<QuadCase> {
    // A 0.3 × 0.2 rectangle 0.5 above the floor, the receiver off its axis.
    let rect = [
        Vec3::new(-0.15, 0.5, -0.1),
        Vec3::new(0.15, 0.5, -0.1),
        Vec3::new(0.15, 0.5, 0.1),
        Vec3::new(-0.15, 0.5, 0.1),
    ];
    let receiver = Vec3::new(0.1, 0.0, -0.05);
    let exact_rect = irradiance_parallel_rectangle(
        1.0,
        0.5,
        [-0.15 - 0.1, 0.15 - 0.1],
        [-0.1 + 0.05, 0.1 + 0.05],
    );
    // A tilted trapezoid (two triangles of unequal area) and a tilted receiver.
    let trapezoid = [
        Vec3::new(-0.3, 0.6, -0.1),
        Vec3::new(0.2, 0.45, -0.15),
        Vec3::new(0.1, 0.5, 0.2),
        Vec3::new(-0.2, 0.62, 0.15),
    ];
    let normal = Vec3::new(0.3, 1.0, -0.2).normalize();
    let receiver2 = Vec3::new(0.05, 0.0, 0.3);
    let exact_trap = irradiance_polygon(
        1.0,
        receiver2.as_dvec3(),
        normal.as_dvec3(),
        &trapezoid.map(|v| v.as_dvec3()),
    );
    vec![
        QuadCase {
            what: "a 0.3 × 0.2 rectangular light 0.5 above a point off its axis, facing it",
            corners: rect,
            receiver,
            normal: Vec3::Y,
            exact: exact_rect,
        },
        QuadCase {
            what: "a tilted trapezoidal light (two triangles of unequal area) above a tilted point",
            corners: trapezoid,
            receiver: receiver2,
            normal,
            exact: exact_trap,
        },
    ]
}

/// The scene of one quad case: the quad as a lamp of radiance 1 (facing down), nothing else.
fn quad_scene(case: &QuadCase) -> Scene {
    let mut corners = case.corners;
    if (corners[1] - corners[0]).cross(corners[2] - corners[0]).y > 0.0 {
        corners.reverse();
    }
    let mut scene = test_scene(&[], &[(corners, true)], Vec::new());
    scene.materials[LAMP.0 as usize].emission = Vec3::ONE;
    scene
}

/// `M` estimates of the irradiance at the receiver, through the integrator's own light
/// sampling (`Pipeline::light_samples`: `pick_face`, 3.2–3.4, weight `1/n²`, shadow rays).
fn irradiance_estimates(pipeline: &Pipeline, scene: &Scene, case: &QuadCase, m: u32) -> Vec<f64> {
    let hit = Hit {
        distance: 1.0,
        position: case.receiver,
        geometric_normal: case.normal,
        shading_normal: case.normal,
        texcoord: Vec2::ZERO,
        surface: HitSurface::Unknown,
        material: WHITE,
        trace_depth: 0,
        ior: 1.0,
    };
    (0..m)
        .map(|k| {
            let mut rng = Rng::new(pipeline.area_light_samples as u64, k as u64);
            pipeline
                .light_samples(scene, &hit, &mut rng)
                .iter()
                .map(|l| l.radiance.x as f64 * case.normal.dot(l.direction).max(0.0) as f64)
                .sum()
        })
        .collect()
}

/// Estimates per level of the irradiance check.
pub const IRRADIANCE_ESTIMATES: u32 = 1024;
/// The `n` of the levels of the irradiance check.
pub const IRRADIANCE_LEVELS: [u32; 4] = [1, 2, 4, 8];
/// Least ratio of the standard errors with one and with 8×8 samples in the irradiance check:
/// `8√2`, the variance of 64 jittered samples at most half that of 64 independent ones (the
/// reference reaches 15–30, independent samples 8).
pub const MIN_STRATIFICATION_GAIN: f64 = 11.3;
/// Family-wise false-alarm rate of the irradiance check's Z-tests (Šidák-corrected).
pub const IRRADIANCE_ALPHA: f64 = 1e-4;

/// The area-light estimator converges to the analytic irradiance: at every level the mean of
/// [`IRRADIANCE_ESTIMATES`] estimates is within the Šidák-corrected `z·SE` of the exact value
/// (plus 1e-5 relative for rounding), and stratification pays: the standard error with 8×8
/// samples is at most `1/MIN_STRATIFICATION_GAIN` of that with one sample.
pub fn check_irradiance(part: Part, s: &Arc<dyn Shadows>, base: &Pipeline) -> Result<(), String> {
    let cases = quad_cases();
    let z = normal_two_sided_quantile(sidak(
        IRRADIANCE_ALPHA,
        cases.len() * IRRADIANCE_LEVELS.len(),
    ));
    for case in &cases {
        let scene = quad_scene(case);
        let mut errors = Vec::new();
        for n in IRRADIANCE_LEVELS {
            let pipeline = part_pipeline(part, s, base, n);
            let x = irradiance_estimates(&pipeline, &scene, case, IRRADIANCE_ESTIMATES);
            let (mean, se) = mean_and_standard_error(&x, x.len());
            errors.push((n, mean, se));
            let within = (mean - case.exact).abs() <= z * se + 1e-5 * case.exact;
            if !within {
                let history = errors
                    .iter()
                    .map(|(n, m, se)| format!("{}: {m:.5} ± {se:.5}", n * n))
                    .collect::<Vec<_>>()
                    .join(", ");
                return Err(format!(
                    "the irradiance from {} (radiance 1; exact value E = {:.5} by the analytic formula) estimated through the renderer's area-light sampling with {n}×{n} samples is {mean:.5} ± {se:.5} (mean ± standard error of {IRRADIANCE_ESTIMATES} estimates), {:.2}× the exact value and {:.1} standard errors off (at most {z:.1} allowed). Estimates so far (samples: mean ± SE): {history}",
                    case.what,
                    case.exact,
                    mean / case.exact,
                    (mean - case.exact).abs() / se.max(1e-300)
                ));
            }
        }
        let (se1, se8) = (errors[0].2, errors[errors.len() - 1].2);
        // 64 independent samples would divide the standard error by √64 = 8.
        let gain = se1 / se8;
        if gain.is_nan() || gain < MIN_STRATIFICATION_GAIN {
            return Err(format!(
                "the irradiance from {} estimated with 8×8 stratified samples has standard error {se8:.2e}, and with one sample {se1:.2e}: only {gain:.1}× smaller. 64 independent samples would give 8× (√64); jittered samples, one per cell, must do better than {MIN_STRATIFICATION_GAIN:.1}× (half the variance of independent samples)",
                case.what,
            ));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::DVec3;

    #[test]
    fn lamberts_formula_matches_the_rectangle_form_factor() {
        // A rectangle [x0, x1] × [z0, z1] at height h above a point facing up, both ways.
        for (x, z, h) in [
            ([-0.25, 0.05], [0.05, 0.25], 0.5),
            ([0.1, 0.7], [-0.3, 0.2], 0.3),
            ([-1.0, 1.0], [-1.0, 1.0], 1.0),
        ] {
            let polygon = [
                DVec3::new(x[0], h, z[0]),
                DVec3::new(x[1], h, z[0]),
                DVec3::new(x[1], h, z[1]),
                DVec3::new(x[0], h, z[1]),
            ];
            let a = irradiance_parallel_rectangle(2.0, h, x, z);
            let b = irradiance_polygon(2.0, DVec3::ZERO, DVec3::Y, &polygon);
            assert!((a - b).abs() < 1e-12 * a.max(1.0), "{a} {b}");
        }
        // A huge square close above: almost the whole hemisphere, E → π·L.
        let e = irradiance_parallel_rectangle(1.0, 1e-3, [-1.0, 1.0], [-1.0, 1.0]);
        assert!((e - std::f64::consts::PI).abs() < 1e-2, "{e}");
    }
}
