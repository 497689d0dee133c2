//! Exercise 6.4: accumulating an item buffer's delta form factors into form factors.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use crate::closed_forms;
use contracts::lab06::Radiosity;
use grading::{GoldenFile, LabContext, for_all};
use pipeline::radiosity::{DeltaFormFactors, HemicubeFace, ItemBuffer};

use super::hemicube::CLOSED_FORM_RESOLUTIONS;
use super::scenes::{closed_box, grid, join};
use super::{GOLDEN_ACCUMULATE, Part, close, load, part_slot};

/// How far the area-to-area form factor of two unit squares (each cut into 7 × 7 patches,
/// one hemicube per patch) may be from the closed form at resolution `n`: the hemicube's
/// `1/n` and the patches' point sampling of the emitter.
pub fn area_bound(n: u32) -> f64 {
    0.2 / n as f64 + 2e-3
}

/// Input of `accumulate_form_factors`: an item buffer, its delta form factors, the patch count.
pub type AccumulateInput = (ItemBuffer, DeltaFormFactors, usize);

/// A random item buffer (resolution 2 to 8, ids below a patch count from 1 to 20, a third of
/// the pixels empty) and random positive delta form factors from 10⁻⁶ to 1.
pub fn accumulate_input() -> impl Strategy<Value = AccumulateInput> {
    (1u32..=4, 1usize..=20).prop_flat_map(|(half, count)| {
        let n = 2 * half;
        let id = prop::option::weighted(0.67, 0..count as u32);
        let weight = (-6.0f32..0.0).prop_map(|e| 10f32.powf(e));
        (
            prop::collection::vec(id.clone(), (n * n) as usize),
            prop::collection::vec(prop::collection::vec(id, (n * n / 2) as usize), 4),
            prop::collection::vec(weight.clone(), (n * n) as usize),
            prop::collection::vec(weight, (n * n / 2) as usize),
        )
            .prop_map(move |(top, sides, wt, ws)| {
                let [a, b, c, d]: [Vec<Option<u32>>; 4] = sides.try_into().expect("four sides");
                (
                    ItemBuffer {
                        resolution: n,
                        faces: [top, a, b, c, d],
                    },
                    DeltaFormFactors {
                        resolution: n,
                        top: wt,
                        side: ws,
                    },
                    count,
                )
            })
    })
}

fn check_accumulate(
    r: &dyn Radiosity,
    key: Option<&dyn Radiosity>,
    (items, delta, count): &AccumulateInput,
) -> Result<(), String> {
    let call = format!(
        "accumulate_form_factors(items of resolution {}, delta, patch_count = {count})",
        items.resolution
    );
    let f = r.accumulate_form_factors(items, delta, *count);
    if f.len() != *count {
        return Err(format!(
            "{call} returned {} form factors, expected one per patch ({count})",
            f.len()
        ));
    }
    let mut seen_weight = 0.0f64;
    let mut seen = vec![false; *count];
    for face in HemicubeFace::ALL {
        for (id, d) in items.face(face).iter().zip(delta.face(face)) {
            if let Some(j) = id {
                seen_weight += *d as f64;
                seen[*j as usize] = true;
            }
        }
    }
    let total: f64 = f.iter().map(|&x| x as f64).sum();
    if !close(total, seen_weight, 1e-12, 1e-4) {
        return Err(format!(
            "{call}: the form factors sum to {total:e}, but the delta form factors of the pixels that see a patch (all five faces; the four side faces share one table) sum to {seen_weight:e}: every such pixel counts once, for the patch it sees, and empty pixels count for none"
        ));
    }
    if let Some(j) = (0..*count).find(|&j| !seen[j] && f[j] != 0.0) {
        return Err(format!(
            "{call}: patch {j} appears in no pixel but has form factor {:e}",
            f[j]
        ));
    }
    // Renaming the patches renames the form factors.
    let rename = |j: u32| (*count as u32 - 1) - j;
    let renamed = ItemBuffer {
        resolution: items.resolution,
        faces: items
            .faces
            .clone()
            .map(|face| face.into_iter().map(|id| id.map(rename)).collect()),
    };
    let g = r.accumulate_form_factors(&renamed, delta, *count);
    for j in 0..*count {
        if g.get(rename(j as u32) as usize).copied() != Some(f[j])
            && !close(
                g[rename(j as u32) as usize] as f64,
                f[j] as f64,
                1e-12,
                1e-5,
            )
        {
            return Err(format!(
                "{call}: patch {j}'s form factor is {:e}, but with the patches numbered in reverse it is {:e}: each pixel's delta form factor goes to the patch it sees",
                f[j],
                g[rename(j as u32) as usize]
            ));
        }
    }
    if let Some(key) = key {
        let expected = key.accumulate_form_factors(items, delta, *count);
        for j in 0..*count {
            if !close(f[j] as f64, expected[j] as f64, 1e-12, 1e-4) {
                return Err(format!(
                    "{call}: patch {j}'s form factor is {:e}, expected {:e}",
                    f[j], expected[j]
                ));
            }
        }
    }
    Ok(())
}

/// Area-to-area form factors of two unit squares (7 × 7 patches each) by hemicubes: reciprocal,
/// and equal to Howell's C-11 and C-14.
fn check_area_closed_forms(r: &dyn Radiosity) -> Result<(), String> {
    // 7 × 7: no pixel centre of hemicubes of resolution 16, 32, 64 lies on a patch edge.
    let k = 7;
    let parallel = join(vec![
        grid(Vec3::ZERO, Vec3::X, Vec3::Y, k, Vec3::ONE),
        grid(Vec3::Z, Vec3::Y, Vec3::X, k, Vec3::ONE),
    ]);
    let perpendicular = join(vec![
        grid(Vec3::ZERO, Vec3::X, Vec3::Y, k, Vec3::ONE),
        grid(Vec3::ZERO, Vec3::Z, Vec3::X, k, Vec3::ONE),
    ]);
    let configs = [
        (
            parallel,
            closed_forms::parallel_rectangles(1.0, 1.0, 1.0),
            "two directly opposed parallel unit squares at unit distance (Howell C-11)",
        ),
        (
            perpendicular,
            closed_forms::perpendicular_rectangles(1.0, 1.0, 1.0),
            "two unit squares at right angles along a common edge (Howell C-14)",
        ),
    ];
    for ((mesh, starts), exact, what) in &configs {
        let (a, b) = (starts[0]..starts[1], starts[1]..mesh.patches.len());
        for n in CLOSED_FORM_RESOLUTIONS {
            let delta = DeltaFormFactors::tabulate(r, n);
            let from = |src: &std::ops::Range<usize>, dst: &std::ops::Range<usize>| -> f64 {
                let area: f64 = src.clone().map(|i| mesh.patches[i].area as f64).sum();
                src.clone()
                    .map(|i| {
                        let items = pipeline::radiosity::item_buffer(mesh, i, n);
                        let f = r.accumulate_form_factors(&items, &delta, mesh.patches.len());
                        mesh.patches[i].area as f64 * dst.clone().map(|j| f[j] as f64).sum::<f64>()
                    })
                    .sum::<f64>()
                    / area
            };
            let (f_ab, f_ba) = (from(&a, &b), from(&b, &a));
            let bound = area_bound(n);
            if !f_ab.is_finite() || (f_ab - f_ba).abs() > bound {
                return Err(format!(
                    "for {what}, the hemicube form factors (resolution {n}, {k}×{k} patches a square) are F_12 = {f_ab:.5} and F_21 = {f_ba:.5}: with equal areas reciprocity A_1 F_12 = A_2 F_21 makes them equal (within {bound:.4})"
                ));
            }
            if (f_ab - exact).abs() > bound {
                return Err(format!(
                    "for {what}, the hemicube form factor (resolution {n}, {k}×{k} patches a square) is {f_ab:.5}; the closed form is {exact:.5}, and it must come within {bound:.4}"
                ));
            }
        }
    }
    Ok(())
}

/// In a closed box every pixel sees a patch: each patch's form factors sum to the hemicube's
/// total delta form factor, 1 up to the discretisation.
fn check_closed_box_sums(r: &dyn Radiosity) -> Result<(), String> {
    let mesh = closed_box(1.0, 3, 0.5);
    let n = 32;
    let delta = DeltaFormFactors::tabulate(r, n);
    for i in [0, 4, 13, 30, 53] {
        let items = pipeline::radiosity::item_buffer(&mesh, i, n);
        let f = r.accumulate_form_factors(&items, &delta, mesh.patches.len());
        let sum: f64 = f.iter().map(|&x| x as f64).sum();
        if !close(sum, delta.total(), 1e-9, 1e-4) {
            return Err(format!(
                "in a closed box (6 faces of 3×3 patches) the form factors from patch {i} by a hemicube of resolution {n} sum to {sum:.6}; every pixel sees some patch, so they must sum to the hemicube's total delta form factor {:.6} (1 up to the discretisation)",
                delta.total()
            ));
        }
        if f[i] != 0.0 {
            return Err(format!(
                "in a closed box the form factor from patch {i} to itself is {:e}; a planar patch cannot see itself",
                f[i]
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_6_4(p: &Arc<dyn Radiosity>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab06::Radiosity>());
    for_all(200, accumulate_input(), |input| {
        check_accumulate(p.as_ref(), key.as_deref(), &input)
    })?;
    let r = part_slot(Part::Accumulate, p, &ctx.base);
    check_closed_box_sums(r.as_ref())?;
    check_area_closed_forms(r.as_ref())?;
    let golden: GoldenFile<AccumulateInput, Vec<f32>> = load(ctx, GOLDEN_ACCUMULATE)?;
    for case in &golden.cases {
        let (items, delta, count) = &case.input;
        let got = p.accumulate_form_factors(items, delta, *count);
        let ok = got.len() == case.expected.len()
            && got
                .iter()
                .zip(&case.expected)
                .all(|(a, b)| close(*a as f64, *b as f64, 1e-12, 1e-4));
        if !ok {
            return Err(format!(
                "accumulate_form_factors(items of resolution {}, delta, patch_count = {count}) = {got:?}, expected {:?}",
                items.resolution, case.expected
            ));
        }
    }
    Ok(())
}
