//! Exercises 6.2 and 6.3: the delta form factors of the hemicube's top and side faces.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use crate::closed_forms;
use contracts::lab06::Radiosity;
use grading::{GoldenFile, LabContext, for_all};
use pipeline::radiosity::{DeltaFormFactors, PatchMesh};

use super::scenes::quad_patch;
use super::{GOLDEN_SIDE, GOLDEN_TOP, Part, close, load, part_slot};

/// Resolutions at which the delta form factors must sum to 1.
pub const SUM_RESOLUTIONS: [u32; 6] = [8, 16, 32, 64, 128, 256];
/// Resolutions of the closed-form comparisons.
pub const CLOSED_FORM_RESOLUTIONS: [u32; 3] = [16, 32, 64];

/// How far from 1 the delta form factors of a hemicube at resolution `n` may sum: the midpoint
/// rule's error falls as `1/n²` (the textbook formulas' is `0.54/n²`).
pub fn sum_bound(n: u32) -> f64 {
    1.1 / (n as f64 * n as f64)
}

/// How far a hemicube form factor from an element to a square may be from the closed form at
/// resolution `n`: the pixels along the square's outline are in or out whole, so the error
/// falls as `1/n`.
pub fn element_bound(n: u32) -> f64 {
    0.25 / n as f64
}

/// Input of a delta form factor: a point of the face and a pixel area `(2/n)²`.
pub type DeltaInput = (f32, f32, f32);

/// A point of the top face and the pixel area of a resolution from 2 to 1024.
pub fn top_input() -> impl Strategy<Value = DeltaInput> {
    (-1.0f32..=1.0, -1.0f32..=1.0, 2u32..1024).prop_map(|(x, y, n)| (x, y, 4.0 / (n * n) as f32))
}

/// A point of a side face and the pixel area of a resolution from 2 to 1024.
pub fn side_input() -> impl Strategy<Value = DeltaInput> {
    (-1.0f32..=1.0, 0.0f32..=1.0, 2u32..1024).prop_map(|(u, z, n)| (u, z, 4.0 / (n * n) as f32))
}

fn check_delta(
    name: &str,
    f: &dyn Fn(f32, f32, f32) -> f32,
    key: Option<&dyn Fn(f32, f32, f32) -> f32>,
    (a, b, area): DeltaInput,
    symmetric_swap: bool,
) -> Result<(), String> {
    let call = |a: f32, b: f32, area: f32| format!("{name}({a}, {b}, pixel_area = {area:e})");
    let d = f(a, b, area);
    if !d.is_finite() || d < 0.0 {
        return Err(format!(
            "{} = {d}: a delta form factor is finite and at least 0",
            call(a, b, area)
        ));
    }
    let mirrored = f(-a, b, area);
    if !close(mirrored as f64, d as f64, 1e-30, 1e-5) {
        return Err(format!(
            "{} = {d:e} but {} = {mirrored:e}: the hemicube is symmetric about its axis",
            call(a, b, area),
            call(-a, b, area)
        ));
    }
    if symmetric_swap {
        let swapped = f(b, a, area);
        if !close(swapped as f64, d as f64, 1e-30, 1e-5) {
            return Err(format!(
                "{} = {d:e} but {} = {swapped:e}: the top face is symmetric in x and y",
                call(a, b, area),
                call(b, a, area)
            ));
        }
    }
    let double = f(a, b, 2.0 * area);
    if !close(double as f64, 2.0 * d as f64, 1e-30, 1e-5) {
        return Err(format!(
            "{} = {d:e} but with twice the pixel area it is {double:e}: a delta form factor is proportional to the pixel's area",
            call(a, b, area)
        ));
    }
    if let Some(key) = key {
        let expected = key(a, b, area);
        if !close(d as f64, expected as f64, 1e-30, 1e-4) {
            return Err(format!(
                "{} = {d:e}, expected {expected:e}",
                call(a, b, area)
            ));
        }
    }
    Ok(())
}

/// The delta form factors of `r` sum to 1 at every resolution of [`SUM_RESOLUTIONS`].
fn check_sum(r: &dyn Radiosity, exercise: &str) -> Result<(), String> {
    for n in SUM_RESOLUTIONS {
        let delta = DeltaFormFactors::tabulate(r, n);
        let (top, side) = (
            delta.top.iter().map(|&d| d as f64).sum::<f64>(),
            delta.side.iter().map(|&d| d as f64).sum::<f64>(),
        );
        let total = top + 4.0 * side;
        if !total.is_finite() || (total - 1.0).abs() > sum_bound(n) {
            return Err(format!(
                "over a whole hemicube of resolution {n} (the top face's {n}×{n} pixels and four side faces of {n}×{} pixels) the delta form factors sum to {total:.6} (top face {top:.6}, side faces 4 × {side:.6}); the hemicube covers every direction above the patch, so they must sum to 1 within {:.1e} (your {exercise}, the key's other face)",
                n / 2,
                sum_bound(n)
            ));
        }
    }
    Ok(())
}

/// The two faces' formulas agree on their common edge (`x = 1` on the top, `z = 1` on a side).
fn check_edge(r: &dyn Radiosity) -> Result<(), String> {
    for k in 0..=8 {
        let t = -1.0 + k as f32 / 4.0;
        let area = 1e-3;
        let (top, side) = (
            r.delta_form_factor_top(1.0, t, area),
            r.delta_form_factor_side(t, 1.0, area),
        );
        if !close(top as f64, side as f64, 1e-30, 1e-4) {
            return Err(format!(
                "on the edge where the top face meets a side face the two formulas must agree (the same point (1, {t}, 1) of the cube), but delta_form_factor_top(1, {t}, {area}) = {top:e} and delta_form_factor_side({t}, 1, {area}) = {side:e}"
            ));
        }
    }
    Ok(())
}

/// A unit square's outline seen from an element, as a one-patch mesh.
fn square_mesh(corners: [Vec3; 4]) -> PatchMesh {
    PatchMesh::from_patches(
        corners.to_vec(),
        vec![quad_patch(corners, 0, Vec3::ONE, Vec3::ZERO)],
    )
}

/// Element-to-square form factors by the hemicube of `r` against Howell B-3 and B-2.
fn check_element_closed_forms(r: &dyn Radiosity) -> Result<(), String> {
    // From the origin (normal +z): a square of side s centred on the axis at height c facing
    // down, and a unit wall at y = d standing on the element's plane facing it.
    let parallel = |s: f32, c: f32| {
        let h = s / 2.0;
        let mesh = square_mesh([
            Vec3::new(-h, -h, c),
            Vec3::new(-h, h, c),
            Vec3::new(h, h, c),
            Vec3::new(h, -h, c),
        ]);
        let exact = 4.0 * closed_forms::element_to_parallel_rectangle(h as f64, h as f64, c as f64);
        (
            mesh,
            exact,
            format!(
                "a {s}×{s} square centred on the normal at distance {c}, facing the element (Howell B-3)"
            ),
        )
    };
    let perpendicular = |d: f32| {
        let mesh = square_mesh([
            Vec3::new(-0.5, d, 0.0),
            Vec3::new(-0.5, d, 1.0),
            Vec3::new(0.5, d, 1.0),
            Vec3::new(0.5, d, 0.0),
        ]);
        let exact = 2.0 * closed_forms::element_to_perpendicular_rectangle(0.5, 1.0, d as f64);
        (
            mesh,
            exact,
            format!(
                "a unit square standing at right angles on the element's plane at distance {d}, facing it (Howell B-2)"
            ),
        )
    };
    for (mesh, exact, what) in [
        parallel(1.0, 1.0),
        parallel(4.0, 1.0),
        perpendicular(0.5),
        perpendicular(0.2),
    ] {
        for n in CLOSED_FORM_RESOLUTIONS {
            let items = pipeline::radiosity::item_buffer_at(&mesh, Vec3::ZERO, Vec3::Z, n);
            let delta = DeltaFormFactors::tabulate(r, n);
            let f = r.accumulate_form_factors(&items, &delta, 1)[0] as f64;
            if !f.is_finite() || (f - exact).abs() > element_bound(n) {
                return Err(format!(
                    "the hemicube form factor (resolution {n}) from an element at the origin with normal +z to {what} is {f:.5}; the closed form is {exact:.5}, and the hemicube must come within {:.4} of it at this resolution",
                    element_bound(n)
                ));
            }
        }
    }
    Ok(())
}

fn exercise_delta(p: &Arc<dyn Radiosity>, ctx: &LabContext, part: Part) -> Result<(), String> {
    let (name, exercise, golden_name) = match part {
        Part::Top => ("delta_form_factor_top", "delta_form_factor_top", GOLDEN_TOP),
        _ => (
            "delta_form_factor_side",
            "delta_form_factor_side",
            GOLDEN_SIDE,
        ),
    };
    let r = part_slot(part, p, &ctx.base);
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    let student = |a: f32, b: f32, area: f32| match part {
        Part::Top => p.delta_form_factor_top(a, b, area),
        _ => p.delta_form_factor_side(a, b, area),
    };
    let keyed = key.as_ref().map(|k| {
        let k = k.clone();
        move |a: f32, b: f32, area: f32| match part {
            Part::Top => k.delta_form_factor_top(a, b, area),
            _ => k.delta_form_factor_side(a, b, area),
        }
    });
    let keyed_ref: Option<&dyn Fn(f32, f32, f32) -> f32> = keyed.as_ref().map(|k| k as _);
    match part {
        Part::Top => for_all(300, top_input(), |i| {
            check_delta(name, &student, keyed_ref, i, true)
        })?,
        _ => for_all(300, side_input(), |i| {
            check_delta(name, &student, keyed_ref, i, false)
        })?,
    }
    if part == Part::Side {
        for u in [-1.0, -0.3, 0.0, 0.8] {
            let d = p.delta_form_factor_side(u, 0.0, 1e-2);
            if d != 0.0 {
                return Err(format!(
                    "delta_form_factor_side({u}, 0, 0.01) = {d:e}: a pixel in the patch's own plane (z = 0) is seen at grazing angle, cos φ = 0, so its delta form factor is 0"
                ));
            }
        }
    }
    check_edge(r.as_ref())?;
    check_sum(r.as_ref(), exercise)?;
    check_element_closed_forms(r.as_ref())?;
    let golden: GoldenFile<DeltaInput, f32> = load(ctx, golden_name)?;
    for case in &golden.cases {
        let (a, b, area) = case.input;
        let got = student(a, b, area);
        if !close(got as f64, case.expected as f64, 1e-30, 1e-4) {
            return Err(format!(
                "{name}({a}, {b}, pixel_area = {area:e}) = {got:e}, expected {:e}",
                case.expected
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_6_2(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    exercise_delta(p, ctx, Part::Top)
}

pub(super) fn exercise_6_3(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    exercise_delta(p, ctx, Part::Side)
}
