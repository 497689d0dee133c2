//! Exercise 6.1: the point-to-patch form factor.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab06::Radiosity;
use grading::strategies::{SCALES, point, scale, unit_vector};
use grading::{GoldenFile, LabContext, for_all};

use super::{GOLDEN_POINT, close, load};

/// Input of `point_form_factor`: `x, n_x, y, n_y, area_y`.
pub type PointInput = (Vec3, Vec3, Vec3, Vec3, f32);

/// Two points at least a tenth of the scale apart, unit normals, and an area, at one of the
/// shared scales.
pub fn point_input() -> impl Strategy<Value = PointInput> {
    (
        point(1.0),
        unit_vector(),
        point(1.0),
        unit_vector(),
        0.001f32..0.1,
        scale(),
    )
        .prop_filter("points apart", |(x, _, y, _, _, _)| x.distance(*y) > 0.1)
        .prop_map(|(x, nx, y, ny, a, s)| (x * s, nx, y * s, ny, a * s * s))
}

fn point_call((x, nx, y, ny, a): PointInput) -> String {
    format!("point_form_factor(x = {x}, n_x = {nx}, y = {y}, n_y = {ny}, area_y = {a:e})")
}

fn check_point(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    input: PointInput,
) -> Result<(), String> {
    let (x, nx, y, ny, a) = input;
    let call = point_call(input);
    let f = r.point_form_factor(x, nx, y, ny, a);
    if !f.is_finite() || f < 0.0 {
        return Err(format!(
            "{call} = {f}: a form factor is a fraction, finite and at least 0"
        ));
    }
    // Reciprocity with an area for x of its own.
    let ax = a * 0.37;
    let back = r.point_form_factor(y, ny, x, nx, ax);
    if !close((ax * f) as f64, (a * back) as f64, 1e-30, 1e-3) {
        return Err(format!(
            "{call} = {f:e} but from y back to x (area {ax:e}) it is {back:e}: reciprocity A_x F_xy = A_y F_yx fails ({:e} ≠ {:e}); both cosines and 1/(π r²) are the same both ways, only the area differs",
            ax * f,
            a * back
        ));
    }
    let twice = r.point_form_factor(x, nx, y, ny, 2.0 * a);
    if !close(twice as f64, 2.0 * f as f64, 1e-30, 1e-4) {
        return Err(format!(
            "{call} = {f:e}, but with twice the area it is {twice:e}: the form factor of a small patch is proportional to its area"
        ));
    }
    for s in SCALES {
        let scaled = r.point_form_factor(x * s, nx, y * s, ny, a * s * s);
        if !close(scaled as f64, f as f64, 1e-30, 1e-3) {
            return Err(format!(
                "{call} = {f:e}, but with every length scaled by {s:e} (and the area by {:e}) it is {scaled:e}: a form factor has no units, it must not change when the whole configuration is scaled",
                s * s
            ));
        }
    }
    let d = y - x;
    let away_y = ny - 2.0 * ny.dot(d.normalize()).min(0.0) * d.normalize();
    let g = r.point_form_factor(x, nx, y, away_y, a);
    if ny.dot(d) < 0.0 && away_y.dot(d) > 0.0 && g != 0.0 {
        return Err(format!(
            "{} = {g:e}: the patch at y faces away from x, so no light from x reaches its front; clamp cos φ_y at 0",
            point_call((x, nx, y, away_y, a))
        ));
    }
    if let Some(key) = key {
        let expected = key.point_form_factor(x, nx, y, ny, a);
        if !close(f as f64, expected as f64, 1e-30, 1e-4) {
            return Err(format!("{call} = {f:e}, expected {expected:e}"));
        }
    }
    Ok(())
}

/// Far from a coaxial disc of radius `R` at height `h` the point formula approaches Howell's
/// differential element to a parallel coaxial disc, `R² / (h² + R²)`, within `(R/h)²`.
fn check_far_disc(r: &dyn Radiosity) -> Result<(), String> {
    for (radius, h) in [(0.01f64, 1.0f64), (0.1, 2.0), (1e-3, 0.05), (50.0, 1e3)] {
        let exact = radius * radius / (h * h + radius * radius);
        let area = (std::f64::consts::PI * radius * radius) as f32;
        let got =
            r.point_form_factor(Vec3::ZERO, Vec3::Z, Vec3::Z * h as f32, -Vec3::Z, area) as f64;
        let bound = (radius / h).powi(2);
        if !close(got, exact, 0.0, bound + 1e-4) {
            return Err(format!(
                "point_form_factor from the origin (normal +z) to a small disc of radius {radius} (area πR² = {area:e}) at height {h} facing back is {got:e}; far away it must approach Howell's closed form R²/(h² + R²) = {exact:e} (within a relative {bound:.1e})"
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_6_1(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(300, point_input(), |input| {
        check_point(p.as_ref(), key.as_deref(), input)
    })?;
    check_far_disc(p.as_ref())?;
    let golden: GoldenFile<PointInput, f32> = load(ctx, GOLDEN_POINT)?;
    for case in &golden.cases {
        let (x, nx, y, ny, a) = case.input;
        let got = p.point_form_factor(x, nx, y, ny, a);
        if !close(got as f64, case.expected as f64, 1e-30, 1e-4) {
            return Err(format!(
                "{} = {got:e}, expected {:e}",
                point_call(case.input),
                case.expected
            ));
        }
    }
    Ok(())
}
