//! Exercises 6.7 and 6.8: patch colours and vertex colours by nodal averaging.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab06::Radiosity;
use grading::{GoldenFile, LabContext, for_all};
use pipeline::radiosity::Patch;

use super::scenes::check_image;
use super::shooter::bare_patch;
use super::{
    GOLDEN_COLOURS, GOLDEN_VERTICES, Part, SNAPSHOT_FLAT, SNAPSHOT_SMOOTH, load, part_slot,
    vec3_close,
};

/// Radiosities from 10⁻⁴ to 10⁴, 1 to 40 patches.
pub fn colours_input() -> impl Strategy<Value = Vec<Vec3>> {
    let c = (-4.0f32..4.0).prop_map(|e| 10f32.powf(e));
    prop::collection::vec(
        (c.clone(), c.clone(), c).prop_map(|(r, g, b)| Vec3::new(r, g, b)),
        1..40,
    )
}

pub(super) fn exercise_6_7(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(200, colours_input(), |b| {
        let l = p.patch_colours(&b);
        if l.len() != b.len() {
            return Err(format!(
                "patch_colours of {} radiosities returned {} colours",
                b.len(),
                l.len()
            ));
        }
        let doubled: Vec<Vec3> = b.iter().map(|x| *x * 2.0).collect();
        let l2 = p.patch_colours(&doubled);
        for (k, (a, c)) in l.iter().zip(&l2).enumerate() {
            if !vec3_close(*c, *a * 2.0, 1e-30, 1e-5) {
                return Err(format!(
                    "patch_colours: radiosity {} gives {a}, but twice it gives {c}: radiance is proportional to radiosity",
                    b[k]
                ));
            }
            if !a.is_finite() || a.cmpgt(b[k]).any() {
                return Err(format!(
                    "patch_colours: radiosity {} gives {a}; a Lambertian patch's radiance is smaller than its radiosity (B = ∫ L cos θ dω = π L)",
                    b[k]
                ));
            }
        }
        if let Some(key) = &key {
            for (k, (a, e)) in l.iter().zip(key.patch_colours(&b)).enumerate() {
                if !vec3_close(*a, e, 1e-30, 1e-5) {
                    return Err(format!(
                        "patch_colours: radiosity {} gives {a}, expected {e}",
                        b[k]
                    ));
                }
            }
        }
        Ok(())
    })?;
    let golden: GoldenFile<Vec<Vec3>, Vec<Vec3>> = load(ctx, GOLDEN_COLOURS)?;
    for case in &golden.cases {
        let got = p.patch_colours(&case.input);
        for (k, e) in case.expected.iter().enumerate() {
            if got.get(k).is_none_or(|a| !vec3_close(*a, *e, 1e-30, 1e-5)) {
                return Err(format!(
                    "patch_colours: radiosity {} gives {:?}, expected {e}",
                    case.input[k],
                    got.get(k)
                ));
            }
        }
    }
    let r = part_slot(Part::Colours, p, &ctx.base);
    check_image(r.as_ref(), ctx, false, SNAPSHOT_FLAT)
}

/// Input of `vertex_colours`: patches (3 or 4 distinct corners each), the vertex count, and
/// the patches' colours.
pub type VerticesInput = (Vec<Patch>, usize, Vec<Vec3>);

/// 1 to 30 patches over 3 to 40 vertices (some vertices of no patch), areas from 10⁻³ to 10³
/// (neighbours of unequal size, as where a coarse quad meets a fine one), colours from 10⁻³
/// to 10³.
pub fn vertices_input() -> impl Strategy<Value = VerticesInput> {
    (4usize..40, 1usize..30).prop_flat_map(|(vertices, n)| {
        let corners = (3usize..=4).prop_flat_map(move |k| {
            prop::sample::subsequence((0..vertices as u32).collect::<Vec<_>>(), k).prop_shuffle()
        });
        let c = (-3.0f32..3.0).prop_map(|e| 10f32.powf(e));
        (
            prop::collection::vec(
                (corners, -3.0f32..3.0).prop_map(|(v, e)| Patch {
                    vertices: v,
                    ..bare_patch(10f32.powf(e), Vec3::ONE)
                }),
                n,
            ),
            Just(vertices),
            prop::collection::vec(
                (c.clone(), c.clone(), c).prop_map(|(r, g, b)| Vec3::new(r, g, b)),
                n,
            ),
        )
    })
}

fn check_vertices(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    (patches, count, colours): &VerticesInput,
) -> Result<(), String> {
    let got = r.vertex_colours(patches, *count, colours);
    let call = format!(
        "vertex_colours({} patches, vertex_count = {count}, …)",
        patches.len()
    );
    if got.len() != *count {
        return Err(format!(
            "{call} returned {} colours, expected one per vertex ({count})",
            got.len()
        ));
    }
    for (v, &c) in got.iter().enumerate() {
        let around: Vec<(usize, Vec3)> = patches
            .iter()
            .enumerate()
            .filter(|(_, p)| p.vertices.contains(&(v as u32)))
            .map(|(k, _)| (k, colours[k]))
            .collect();
        if around.is_empty() {
            if c != Vec3::ZERO {
                return Err(format!(
                    "{call}: vertex {v} is a corner of no patch but has colour {c}; it must be black (and not NaN)"
                ));
            }
            continue;
        }
        let lo = around
            .iter()
            .fold(Vec3::splat(f32::INFINITY), |m, (_, c)| m.min(*c));
        let hi = around.iter().fold(Vec3::ZERO, |m, (_, c)| m.max(*c));
        if !c.is_finite() || c.cmplt(lo * (1.0 - 1e-5)).any() || c.cmpgt(hi * (1.0 + 1e-5)).any() {
            return Err(format!(
                "{call}: vertex {v} is a corner of patches {:?} with colours from {lo} to {hi}, but its colour is {c}: the mean of its patches' colours lies between them",
                around.iter().map(|(k, _)| *k).collect::<Vec<_>>()
            ));
        }
        if around.len() == 1 && !vec3_close(c, around[0].1, 1e-30, 1e-5) {
            return Err(format!(
                "{call}: vertex {v} is a corner of patch {} only (colour {}), but its colour is {c}",
                around[0].0, around[0].1
            ));
        }
    }
    // The mean counts every patch once: the same patches with other areas give the same colours.
    let resized: Vec<Patch> = patches
        .iter()
        .enumerate()
        .map(|(k, p)| Patch {
            area: if k % 2 == 0 { 1.0 } else { 7.0 },
            ..p.clone()
        })
        .collect();
    let again = r.vertex_colours(&resized, *count, colours);
    for (v, (&c, a)) in got.iter().zip(&again).enumerate() {
        if !vec3_close(c, *a, 1e-30, 1e-5) {
            let around: Vec<usize> = (0..patches.len())
                .filter(|&k| patches[k].vertices.contains(&(v as u32)))
                .collect();
            return Err(format!(
                "{call}: vertex {v} is a corner of patches {around:?} with areas {:?} and colours {:?}; its colour is {c}, but {a} when only the patches' areas change (to {:?}): nodal averaging is the plain mean of the colours of the patches around a vertex, each patch counting once whatever its area",
                around.iter().map(|&k| patches[k].area).collect::<Vec<_>>(),
                around.iter().map(|&k| colours[k]).collect::<Vec<_>>(),
                around.iter().map(|&k| resized[k].area).collect::<Vec<_>>(),
            ));
        }
    }
    if let Some(key) = key {
        for (v, e) in key
            .vertex_colours(patches, *count, colours)
            .iter()
            .enumerate()
        {
            if !vec3_close(got[v], *e, 1e-30, 1e-5) {
                return Err(format!(
                    "{call}: vertex {v} has colour {}, expected {e} (the mean over the patches it is a corner of)",
                    got[v]
                ));
            }
        }
    }
    Ok(())
}

pub(super) fn exercise_6_8(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(200, vertices_input(), |input| {
        check_vertices(p.as_ref(), key.as_deref(), &input)
    })?;
    let golden: GoldenFile<VerticesInput, Vec<Vec3>> = load(ctx, GOLDEN_VERTICES)?;
    for case in &golden.cases {
        let (patches, count, colours) = &case.input;
        let got = p.vertex_colours(patches, *count, colours);
        for (v, e) in case.expected.iter().enumerate() {
            if got.get(v).is_none_or(|a| !vec3_close(*a, *e, 1e-30, 1e-5)) {
                return Err(format!(
                    "vertex_colours on a recorded case ({} patches, {count} vertices): vertex {v} has colour {:?}, expected {e}",
                    patches.len(),
                    got.get(v)
                ));
            }
        }
    }
    let r = part_slot(Part::Vertices, p, &ctx.base);
    check_image(r.as_ref(), ctx, true, SNAPSHOT_SMOOTH)
}
