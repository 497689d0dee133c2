//! Lab 07's exercises and their checks.
//!
//! Exercise 7.1 (`compute_jitters`) is random, and a correct implementation may fill the
//! subpixels in any order (row- or column-major) and draw its numbers as it likes, so every
//! check of it is about the *distribution* of the jitters, never their order:
//!
//! - per call (300 property cases, `s` from 1 to 12): `s²` finite jitters in `[0, 1)²`, one in
//!   each subpixel `[i/s, (i+1)/s) × [j/s, (j+1)/s)`; two different generators give different
//!   jitters, and the generator passed in has moved on after the call;
//! - over [`STREAMS`] independent generators for each `s` from 1 to 4: the mean jitter is the
//!   pixel centre `(½, ½)`; in every subpixel the jitter's position within the subpixel has mean
//!   `½` and variance `1/12` per coordinate (a uniform point; the subpixel centre has variance
//!   0); the pooled in-subpixel positions are uniform over the square (χ² on 4×4 bins, which
//!   rejects `x = y`); and the subpixels of one pixel are jittered independently (the mean
//!   in-subpixel offset of a pixel varies as `1/(12 s²)`, not more); and the generator moves on
//!   past the numbers of the jitters (what the caller draws from it next is uncorrelated with
//!   every jitter: the renderer draws its area-light samples from it). Each statistic is a z-score
//!   (the χ² through the Wilson–Hilferty transform) compared with the two-sided normal quantile
//!   at the Šidák-corrected level of [`FAMILY_ALPHA`] over all [`STATISTICAL_TESTS`] tests
//!   (|z| ≤ 5.07); the generators are fixed, so the outcome is deterministic;
//! - on a real scene: the default scene at 160×120 with the student's jitters (the reference
//!   averages them) at `s` = 2 and 4, two seeds each; the RMS error against a converged image
//!   (the reference at `s` = 16, `snapshots/default-converged.exr`) must be at most
//!   [`MAX_ERROR_RATIO`] times the reference's own error at the same `s`
//!   (`golden/image_error.json`). Correct jitters spread by about 5 % around the reference's
//!   error; jitters that miss part of the pixel do not converge to the right image at all.
//!
//! Exercise 7.2 (`compute_pixel`) is deterministic given the jitters: the raster positions it
//! asks for (as a multiset) and the average it returns are compared exactly (up to rounding);
//! a pixel crossed by a straight edge must come within `(2s − 1)/s²` of the exact covered
//! fraction for `s` = 2 … 32 (only the at most `2s − 1` subpixels the edge crosses can be
//! wrong); recorded reference cases must match; and the default scene rendered at `s` = 3 with
//! the reference's jitters and the student's average must match `snapshots/default-s3.exr`
//! pixel by pixel.

use std::sync::Arc;

use glam::{DVec2, UVec2, Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab07::Antialiasing;
use grading::stats::{chi_square_uniform_z, family_z_limit};
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, StrataNames, cell_name, cell_of,
    check_one_per_cell, compare_vec3, for_all,
};
use pipeline::render::render;
use pipeline::{Pipeline, View};
use raylab_core::film::Film;
use raylab_core::render::RenderSettings;
use raylab_core::sampling::Rng;
use raylab_core::scene::builtin_scene;

/// Golden file of Exercise 7.2: pixel, jitters → the average of [`probe_radiance`].
pub const GOLDEN_PIXEL: &str = "compute_pixel.json";
/// Golden file of Exercise 7.1: subdivision `s` → the reference's RMS error against the
/// converged image.
pub const GOLDEN_IMAGE_ERROR: &str = "image_error.json";
/// Snapshot of the converged default scene (the reference at [`CONVERGED_SUBDIVISIONS`]).
pub const SNAPSHOT_CONVERGED: &str = "default-converged";
/// Snapshot of Exercise 7.2: the default scene at [`PIXEL_SNAPSHOT_SUBDIVISIONS`].
pub const SNAPSHOT_PIXEL: &str = "default-s3";
/// Size, sampling and seed of lab 07's snapshots (the subdivision is set per render).
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(7);
/// Seed of the converged image (independent of the seeds of the renders compared with it).
pub const CONVERGED_SEED: u64 = 1000;
/// Subdivision of the converged image.
pub const CONVERGED_SUBDIVISIONS: u32 = 16;
/// Subdivision of Exercise 7.2's snapshot.
pub const PIXEL_SNAPSHOT_SUBDIVISIONS: u32 = 3;
/// Subdivisions whose image error Exercise 7.1 checks (1 is the baseline: one ray through the
/// pixel centre, without `compute_jitters`).
pub const ERROR_SUBDIVISIONS: [u32; 3] = [1, 2, 4];
/// Seeds whose squared errors are averaged for the image-error check.
pub const ERROR_SEEDS: [u64; 2] = [7, 8];
/// How much larger than the reference's error the student's image error may be.
pub const MAX_ERROR_RATIO: f64 = 1.35;
/// Independent generators per subdivision for the statistics of Exercise 7.1.
pub const STREAMS: u32 = 512;
/// Subdivisions whose jitter statistics are checked.
pub const STATISTICS_SUBDIVISIONS: [u32; 4] = [1, 2, 3, 4];
/// Chance that a correct implementation fails any of the statistical tests of Exercise 7.1,
/// had the generators been random.
pub const FAMILY_ALPHA: f64 = 1e-4;
/// Number of statistical tests in Exercise 7.1: the mean jitter (2 per `s`), mean and variance
/// per subpixel and coordinate (4 × 30 subpixels), χ² uniformity (1 per `s`), independence
/// (2 per `s > 1`), the generator's next numbers against each jitter (4 pairs of coordinates ×
/// 30 subpixels).
pub const STATISTICAL_TESTS: usize = 8 + 120 + 4 + 6 + 120;

/// This lab.
pub const LAB: course::LabId = course::LabId::of(7);

/// The exercises of lab 07 (`labs/lab07/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Antialiasing>> {
    grading::exercises(LAB, grading::checks![exercise_7_1, exercise_7_2])
}

// ---------------------------------------------------------------------------------------------
// Pipelines and images

/// Which student function a render exercises; the other comes from the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 7.1: the student's jitters, the base's average.
    Jitters,
    /// Exercise 7.2: the base's jitters, the student's average.
    Pixel,
}

impl Part {
    /// The contract method whose code this part is (the student's in a [`PartSlot`](pipeline::PartSlot)).
    pub fn function(self) -> &'static str {
        match self {
            Part::Jitters => "compute_jitters",
            Part::Pixel => "compute_pixel",
        }
    }
}

/// The pipeline of one part's renders: `student` for that part only, `base` for the rest,
/// shaded, at lab 7.
pub fn part_pipeline(part: Part, student: &Arc<dyn Antialiasing>, base: &Pipeline) -> Pipeline {
    let mut pipeline = base.with_student_function(part.function(), student);
    pipeline.view = View::Shaded;
    pipeline
}

/// Renders the default scene at the snapshot size with `subdivisions` and `seed`.
pub fn render_default(
    pipeline: &Pipeline,
    subdivisions: u32,
    seed: u64,
) -> Result<Film, raylab_core::Error> {
    let settings = RenderSettings {
        pixel_subdivisions: subdivisions,
        seed,
        ..SNAPSHOT_SETTINGS
    };
    render(&builtin_scene("default")?, pipeline, &settings)
}

/// Mean squared difference per channel between two images of the same size.
pub fn mean_squared_error(a: &Film, b: &Film) -> f64 {
    let sum: f64 = a
        .pixels
        .iter()
        .zip(&b.pixels)
        .map(|(p, q)| (*p - *q).as_dvec3().length_squared())
        .sum();
    sum / (3 * a.pixels.len().max(1)) as f64
}

/// The RMS error of renders at `subdivisions` (squared errors averaged over [`ERROR_SEEDS`])
/// against `converged`.
pub fn image_error(
    pipeline: &Pipeline,
    subdivisions: u32,
    converged: &Film,
) -> Result<f64, raylab_core::Error> {
    let mut mse = 0.0;
    for seed in ERROR_SEEDS {
        mse += mean_squared_error(&render_default(pipeline, subdivisions, seed)?, converged);
    }
    Ok((mse / ERROR_SEEDS.len() as f64).sqrt())
}

// ---------------------------------------------------------------------------------------------
// Statistics

/// The largest |z| a statistic of Exercise 7.1 may reach.
pub fn z_limit() -> f64 {
    family_z_limit(FAMILY_ALPHA, STATISTICAL_TESTS)
}

// ---------------------------------------------------------------------------------------------
// Exercise 7.1

/// Where a jitter lies within its subpixel, in `[0, 1]²`.
pub fn offset_in_subpixel(p: Vec2, s: u32) -> DVec2 {
    let (i, j) = cell_of(p, s);
    DVec2::new(
        p.x as f64 * s as f64 - i as f64,
        p.y as f64 * s as f64 - j as f64,
    )
    .clamp(DVec2::ZERO, DVec2::ONE)
}

/// One call's jitters: `s²` of them, finite, in the pixel, one per subpixel.
fn check_strata(s: u32, jitters: &[Vec2]) -> Result<(), String> {
    let call = format!("compute_jitters(subdivisions = {s}, rng)");
    let names = StrataNames {
        call: &call,
        point: "jitter",
        cell: "subpixel",
        outside_hint: " (jitters are offsets from the pixel's corner in pixel units: ((i + ξ₁)/s, (j + ξ₂)/s))",
    };
    check_one_per_cell(&names, s, jitters)
}

/// The jitters of [`STREAMS`] pixels (one generator each) at subdivision `s`, each call
/// checked with [`check_strata`], and what each generator gives next (`next_vec2()` after the
/// call, as the renderer's area-light sampling draws it).
fn jitters_of_many_pixels(
    j: &Arc<dyn Antialiasing>,
    s: u32,
) -> Result<(Vec<Vec<Vec2>>, Vec<Vec2>), String> {
    (0..STREAMS)
        .map(|k| {
            let mut rng = Rng::for_sample(77, k, s, 0);
            let jitters = j.compute_jitters(s, &mut rng);
            check_strata(s, &jitters).map(|()| (jitters, rng.next_vec2()))
        })
        .collect()
}

/// The mean jitter over many pixels is the pixel centre.
pub fn check_mean_jitter(s: u32, pixels: &[Vec<Vec2>], z_max: f64) -> Result<(), String> {
    let means: Vec<DVec2> = pixels
        .iter()
        .map(|js| js.iter().map(|p| p.as_dvec2()).sum::<DVec2>() / js.len() as f64)
        .collect();
    let n = means.len() as f64;
    let mean = means.iter().sum::<DVec2>() / n;
    let var = means
        .iter()
        .map(|m| (*m - mean) * (*m - mean))
        .sum::<DVec2>()
        / (n - 1.0);
    let se = (var / n).map(f64::sqrt);
    for (axis, m, e) in [("x", mean.x, se.x), ("y", mean.y, se.y)] {
        let off = (m - 0.5).abs();
        if off > z_max * e && off > 1e-6 {
            return Err(format!(
                "over {STREAMS} pixels, compute_jitters(subdivisions = {s}, rng) gives jitters whose mean {axis} is {m:.4} (standard error {e:.1e}); jitters spread uniformly over the pixel average to its centre, 0.5"
            ));
        }
    }
    Ok(())
}

/// Per subpixel: the in-subpixel position over many pixels is uniform (mean ½, variance 1/12).
pub fn check_subpixels(s: u32, pixels: &[Vec<Vec2>], z_max: f64) -> Result<(), String> {
    let n = pixels.len() as f64;
    let mut offsets = vec![Vec::with_capacity(pixels.len()); (s * s) as usize];
    for js in pixels {
        for p in js {
            let (i, j) = cell_of(*p, s);
            offsets[(j * s + i) as usize].push(offset_in_subpixel(*p, s));
        }
    }
    let se_mean = (1.0 / (12.0 * n)).sqrt();
    let se_var = ((1.0 / 80.0 - 1.0 / 144.0) / n).sqrt();
    for (k, os) in offsets.iter().enumerate() {
        let name = cell_name(k as u32 % s, k as u32 / s, s);
        let mean = os.iter().sum::<DVec2>() / n;
        let var = os.iter().map(|o| (*o - mean) * (*o - mean)).sum::<DVec2>() / (n - 1.0);
        let fix = "each subpixel needs a uniformly random point: ((i + ξ₁)/s, (j + ξ₂)/s) with ξ = rng.next_vec2() drawn anew for every subpixel";
        if var.max_element() < 1e-9 {
            return Err(format!(
                "compute_jitters(subdivisions = {s}, rng) puts the jitter of subpixel {name} at the same place in the subpixel for all {STREAMS} pixels tried (offset ({:.3}, {:.3}) of the subpixel's size from its corner): that is a regular grid, not jitter; {fix}",
                mean.x, mean.y
            ));
        }
        for (axis, m, v) in [("x", mean.x, var.x), ("y", mean.y, var.y)] {
            let zm = (m - 0.5) / se_mean;
            let zv = (v - 1.0 / 12.0) / se_var;
            if zm.abs() > z_max || zv.abs() > z_max {
                return Err(format!(
                    "over {STREAMS} pixels, the jitter of subpixel {name} from compute_jitters(subdivisions = {s}, rng) has in-subpixel {axis} offset of mean {m:.4} and variance {v:.4} (in units of the subpixel); a uniform point has mean 0.5 and variance 1/12 ≈ 0.0833 (z-scores {zm:.1} and {zv:.1}, limit {z_max:.2}); {fix}"
                ));
            }
        }
    }
    Ok(())
}

/// The in-subpixel positions, pooled over subpixels and pixels, fill the square uniformly.
pub fn check_pooled_uniformity(s: u32, pixels: &[Vec<Vec2>], z_max: f64) -> Result<(), String> {
    const K: u32 = 4;
    let mut counts = vec![0u32; (K * K) as usize];
    for p in pixels.iter().flatten() {
        let o = offset_in_subpixel(*p, s);
        let (bx, by) = ((o.x * K as f64) as u32, (o.y * K as f64) as u32);
        counts[(by.min(K - 1) * K + bx.min(K - 1)) as usize] += 1;
    }
    let (chi2, z) = chi_square_uniform_z(&counts);
    if z > z_max {
        let total: u32 = counts.iter().sum();
        return Err(format!(
            "over {STREAMS} pixels, the positions of the jitters of compute_jitters(subdivisions = {s}, rng) within their subpixels are not uniform over the subpixel: {K}×{K} bins (rows from the top) hold [{}] (expected about {} each; χ² = {chi2:.0} with {} degrees of freedom, z = {z:.1}, limit {z_max:.2}). Draw the two coordinates of a jitter independently (rng.next_vec2(), not one number for both)",
            counts
                .iter()
                .map(|c| c.to_string())
                .collect::<Vec<_>>()
                .join(" "),
            total / (K * K),
            K * K - 1
        ));
    }
    Ok(())
}

/// The subpixels of one pixel are jittered independently: the mean in-subpixel offset of a
/// pixel varies no more than that of `s²` independent uniform offsets, `1/(12 s²)`.
pub fn check_independence(s: u32, pixels: &[Vec<Vec2>], z_max: f64) -> Result<(), String> {
    let n = pixels.len() as f64;
    let expected = 1.0 / (12.0 * (s * s) as f64);
    let mut spread = DVec2::ZERO;
    for js in pixels {
        let m = js.iter().map(|p| offset_in_subpixel(*p, s)).sum::<DVec2>() / js.len() as f64;
        spread += (m - 0.5) * (m - 0.5);
    }
    let ratio = spread / (n * expected);
    // (m − ½)² / E[(m − ½)²] has mean 1 and a standard deviation of at most √2.
    let limit = 1.0 + z_max * (2.0 / n).sqrt();
    for (axis, r) in [("x", ratio.x), ("y", ratio.y)] {
        if r > limit {
            return Err(format!(
                "the subpixels of one pixel from compute_jitters(subdivisions = {s}, rng) are not jittered independently: over {STREAMS} pixels the pixel's mean in-subpixel {axis} offset varies {r:.1}× as much as it would for independent jitters (at most {limit:.2}×). Did you draw one random offset and use it for every subpixel? Draw rng.next_vec2() once per subpixel"
            ));
        }
    }
    Ok(())
}

/// The generator moves on past the jitters' numbers: over many pixels, what it gives after the
/// call (`next`) is uncorrelated with where each jitter lies in its subpixel. Each of the `4 s²`
/// correlations is a z-score by Fisher's transformation, `atanh(r)·√(n − 3)`.
pub fn check_generator_moves_on(
    s: u32,
    pixels: &[Vec<Vec2>],
    next: &[Vec2],
    z_max: f64,
) -> Result<(), String> {
    let n = pixels.len() as f64;
    let correlation = |a: &[f64], b: &[f64]| {
        let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
        let cov: f64 = a.iter().zip(b).map(|(x, y)| (x - ma) * (y - mb)).sum();
        let va: f64 = a.iter().map(|x| (x - ma) * (x - ma)).sum();
        let vb: f64 = b.iter().map(|y| (y - mb) * (y - mb)).sum();
        cov / (va * vb).sqrt().max(f64::MIN_POSITIVE)
    };
    let after = [
        next.iter().map(|u| f64::from(u.x)).collect::<Vec<_>>(),
        next.iter().map(|u| f64::from(u.y)).collect::<Vec<_>>(),
    ];
    for k in 0..(s * s) as usize {
        let offsets: Vec<DVec2> = pixels
            .iter()
            .map(|js| offset_in_subpixel(js[k], s))
            .collect();
        let jitter = [
            offsets.iter().map(|o| o.x).collect::<Vec<_>>(),
            offsets.iter().map(|o| o.y).collect::<Vec<_>>(),
        ];
        for (a, axis) in jitter.iter().zip(["x", "y"]) {
            for (b, next_axis) in after.iter().zip(["x", "y"]) {
                let r = correlation(a, b).clamp(-1.0 + 1e-12, 1.0 - 1e-12);
                let z = r.atanh() * (n - 3.0).sqrt();
                if z.abs() > z_max {
                    return Err(format!(
                        "after compute_jitters(subdivisions = {s}, rng), the numbers rng gives next repeat the jitters' own: over {STREAMS} pixels, rng.next_vec2().{next_axis} after the call correlates with the in-subpixel {axis} offset of jitter {k} (correlation {r:.3}, z = {z:.1}, limit {z_max:.2}). The renderer goes on drawing from rng after the jitters (the area-light samples of lab 3), so draw every jitter from rng itself, not from a copy of it, and leave it where your last number left it"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The statistical checks of Exercise 7.1 (see the module documentation).
pub fn check_jitter_statistics(j: &Arc<dyn Antialiasing>) -> Result<(), String> {
    let z_max = z_limit();
    for s in STATISTICS_SUBDIVISIONS {
        let (pixels, next) = jitters_of_many_pixels(j, s)?;
        check_mean_jitter(s, &pixels, z_max)?;
        check_subpixels(s, &pixels, z_max)?;
        check_pooled_uniformity(s, &pixels, z_max)?;
        if s > 1 {
            check_independence(s, &pixels, z_max)?;
        }
        check_generator_moves_on(s, &pixels, &next, z_max)?;
    }
    Ok(())
}

/// The converged default scene.
fn load_converged(ctx: &LabContext) -> Result<Film, String> {
    let path = ctx.snapshot_path(&format!("{SNAPSHOT_CONVERGED}.exr"));
    raylab_core::film::read_exr(&path)
        .map_err(|e| ctx.unreadable(&format!("snapshots/{SNAPSHOT_CONVERGED}.exr"), e))
}

/// The image error with the student's jitters falls as the reference's does.
pub fn check_image_error(j: &Arc<dyn Antialiasing>, ctx: &LabContext) -> Result<(), String> {
    let golden: GoldenFile<u32, f64> = ctx.golden(GOLDEN_IMAGE_ERROR)?;
    let converged = load_converged(ctx)?;
    let pipeline = part_pipeline(Part::Jitters, j, &ctx.base);
    let table = golden
        .cases
        .iter()
        .map(|c| format!("s = {}: {:.4}", c.input, c.expected))
        .collect::<Vec<_>>()
        .join(", ");
    for case in golden.cases.iter().filter(|c| c.input > 1) {
        let s = case.input;
        let error = image_error(&pipeline, s, &converged).map_err(|e| e.to_string())?;
        let limit = MAX_ERROR_RATIO * case.expected;
        if error.is_nan() || error > limit {
            return Err(format!(
                "the default scene ({}×{}) rendered with your jitters at subdivisions = {s} has an RMS error of {error:.4} against the converged image (s = {CONVERGED_SUBDIVISIONS}); correct jitters give about {:.4} (at most {limit:.4} is accepted; the reference's errors: {table}). Jitters that do not cover the whole pixel uniformly converge to a shifted or blurred image",
                SNAPSHOT_SETTINGS.width, SNAPSHOT_SETTINGS.height, case.expected
            ));
        }
    }
    Ok(())
}

/// The jitters come from `rng` and move it on: two generators give two different sets, and the
/// generator passed in is not where it was after the call.
fn check_uses_rng(j: &Arc<dyn Antialiasing>) -> Result<(), String> {
    for s in [1u32, 3] {
        let a = j.compute_jitters(s, &mut Rng::new(1, 2));
        let b = j.compute_jitters(s, &mut Rng::new(3, 4));
        if a == b {
            return Err(format!(
                "compute_jitters(subdivisions = {s}, rng) returned the same jitters {a:?} for two different generators: the jitter must come from rng (rng.next_vec2() once per subpixel), not be a fixed pattern such as the subpixel centres or corners"
            ));
        }
    }
    for s in [1u32, 3] {
        let mut rng = Rng::new(5, 6);
        let mut before = rng.clone();
        j.compute_jitters(s, &mut rng);
        if (0..4).all(|_| rng.next_u32() == before.next_u32()) {
            return Err(format!(
                "compute_jitters(subdivisions = {s}, rng) left rng where it was: it drew its numbers from a copy of rng (rng.clone()) or from another generator. The renderer goes on drawing from rng after the jitters (the area-light samples of lab 3) and would get the jitters' numbers again; draw rng.next_vec2() from rng itself"
            ));
        }
    }
    Ok(())
}

fn exercise_7_1(j: &Arc<dyn Antialiasing>, ctx: &LabContext) -> Result<(), String> {
    check_uses_rng(j)?;
    for_all(300, (1u32..=12, any::<u64>()), |(s, seed)| {
        check_strata(s, &j.compute_jitters(s, &mut Rng::new(seed, 5)))
    })?;
    check_jitter_statistics(j)?;
    check_image_error(j, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 7.2

/// Input of Exercise 7.2: the pixel and its jitters.
pub type PixelInput = (UVec2, Vec<Vec2>);

/// A smooth radiance over the raster plane that varies within a pixel, for the property and
/// golden cases of Exercise 7.2.
pub fn probe_radiance(p: Vec2) -> Vec3 {
    Vec3::new(
        1.0 + 0.5 * (1.7 * p.x + 0.3 * p.y).sin(),
        1.0 + 0.5 * (0.9 * p.y - 1.1 * p.x).cos(),
        0.5 + 0.25 * (2.3 * p.x).sin() * (1.9 * p.y).cos(),
    )
}

/// A pixel anywhere in a 2048×2048 image with the `s²` jitters of some `s` from 1 to 6 (any
/// points of the pixel: `compute_pixel` must not care where they came from).
pub fn pixel_input() -> impl Strategy<Value = PixelInput> {
    (0u32..2048, 0u32..2048, 1u32..=6).prop_flat_map(|(x, y, s)| {
        (
            Just(UVec2::new(x, y)),
            prop::collection::vec(
                (0.0f32..1.0, 0.0f32..1.0).prop_map(|(a, b)| Vec2::new(a, b)),
                (s * s) as usize,
            ),
        )
    })
}

fn plural(n: usize, what: &str) -> String {
    if n == 1 {
        format!("1 {what}")
    } else {
        format!("{n} {what}s")
    }
}

fn sorted(mut v: Vec<Vec2>) -> Vec<Vec2> {
    v.sort_by(|a, b| a.x.total_cmp(&b.x).then(a.y.total_cmp(&b.y)));
    v
}

fn same_points(a: &[Vec2], b: &[Vec2]) -> bool {
    a.len() == b.len()
        && sorted(a.to_vec())
            .iter()
            .zip(&sorted(b.to_vec()))
            .all(|(p, q)| (*p - *q).abs().max_element() <= 1e-3)
}

/// `compute_pixel` on `(pixel, jitters)` with [`probe_radiance`]: the raster positions it
/// traces, the properties of an average, and (with the answer key, `key`) its result.
fn check_average(
    p: &Arc<dyn Antialiasing>,
    key: Option<&dyn Antialiasing>,
    pixel: UVec2,
    jitters: &[Vec2],
) -> Result<(), String> {
    let call = format!("compute_pixel(pixel = {pixel}, jitters = {jitters:?}, radiance)");
    let mut traced = Vec::new();
    let got = p.compute_pixel(pixel, jitters, &mut |r| {
        traced.push(r);
        probe_radiance(r)
    });
    let corner = pixel.as_vec2();
    let expected_at: Vec<Vec2> = jitters.iter().map(|&j| corner + j).collect();
    let n = jitters.len();
    if traced.len() != n {
        return Err(format!(
            "{call} called radiance {} for {}; trace one ray per jitter",
            plural(traced.len(), "time"),
            plural(n, "jitter")
        ));
    }
    if !same_points(&traced, &expected_at) {
        let hint = if same_points(&traced, jitters) {
            "the jitter alone; the jitter is an offset from the pixel's corner, so the raster position is pixel + jitter"
        } else if same_points(&traced, &vec![corner; n]) {
            "the pixel's corner for every ray; add the jitter: pixel + jitter"
        } else if same_points(&traced, &vec![corner + 0.5; n]) {
            "the pixel's centre for every ray; trace through pixel + jitter"
        } else {
            "the wrong raster positions; trace through pixel + jitter for every jitter"
        };
        return Err(format!(
            "{call} traced the raster positions {:?}, expected pixel + jitter = {:?}: it used {hint}",
            sorted(traced),
            sorted(expected_at)
        ));
    }
    let values: Vec<Vec3> = expected_at.iter().map(|&r| probe_radiance(r)).collect();
    // The average of the values: within their bounds, the same in any order of the jitters,
    // and the value itself where the radiance is constant.
    let (lo, hi) = values.iter().fold(
        (Vec3::splat(f32::INFINITY), Vec3::splat(f32::NEG_INFINITY)),
        |(lo, hi), v| (lo.min(*v), hi.max(*v)),
    );
    let slack = Vec3::splat(1e-5) + 1e-4 * hi.abs();
    if !got.is_finite() || got.cmplt(lo - slack).any() || got.cmpgt(hi + slack).any() {
        let sum: Vec3 = values.iter().sum();
        let scale = |v: Vec3| v.abs().max_element().max(1.0);
        let near = |v: Vec3| (got - v).abs().max_element() <= 1e-4 * scale(v);
        let what = if n > 1 && near(sum) {
            ". That is their sum: divide it by the number of jitters, N = s²"
        } else if n > 1 && near(sum / (n as f32).sqrt()) {
            ". That is their sum divided by s = √N: there are s² subpixels, divide by s²"
        } else {
            ""
        };
        return Err(format!(
            "{call} is {got}, outside the range [{lo}, {hi}] of the radiance it traced: the pixel value is the average of the radiance over the jitters{what}"
        ));
    }
    let reversed: Vec<Vec2> = jitters.iter().rev().copied().collect();
    let again = p.compute_pixel(pixel, &reversed, &mut probe_radiance);
    compare_vec3(
        &format!("{call} with the jitters in reverse order"),
        again,
        got,
        1e-5,
        1e-4,
    )
    .map_err(|e| format!("{e}: every jitter counts the same, whatever its place in the list"))?;
    let grey = Vec3::new(0.25, 0.5, 1.0);
    let flat = p.compute_pixel(pixel, jitters, &mut |_| grey);
    compare_vec3(
        &format!("{call} with a constant radiance {grey}"),
        flat,
        grey,
        1e-5,
        1e-4,
    )
    .map_err(|e| {
        let n = n as f32;
        let hint = if n > 1.0 && (flat - grey * n).abs().max_element() <= 1e-4 * n {
            "that is the sum of the radiances; divide it by the number of jitters"
        } else if n > 1.0 && (flat - grey * n.sqrt()).abs().max_element() <= 1e-4 * n {
            "that is the sum divided by s = √(number of jitters); there are s² subpixels, divide by s²"
        } else {
            "the average of a constant is that constant"
        };
        format!("{e}: {hint}")
    })?;
    match key {
        Some(key) => compare_vec3(
            &format!("{call} (radiance is smooth)"),
            got,
            key.compute_pixel(pixel, jitters, &mut probe_radiance),
            1e-5,
            1e-4,
        )
        .map_err(|e| {
            format!("{e}: the pixel value is the average of the radiance over the jitters")
        }),
        None => Ok(()),
    }
}

/// The area of the part of the unit square where `n·(q − c) ≥ 0` (the square clipped by the
/// half-plane, then the shoelace formula), in f64.
pub fn covered_fraction(c: DVec2, n: DVec2) -> f64 {
    let square = [
        DVec2::new(0.0, 0.0),
        DVec2::new(1.0, 0.0),
        DVec2::new(1.0, 1.0),
        DVec2::new(0.0, 1.0),
    ];
    let side = |q: DVec2| n.dot(q - c);
    let mut poly = Vec::with_capacity(6);
    for k in 0..4 {
        let (a, b) = (square[k], square[(k + 1) % 4]);
        let (sa, sb) = (side(a), side(b));
        if sa >= 0.0 {
            poly.push(a);
        }
        if (sa >= 0.0) != (sb >= 0.0) {
            poly.push(a + (b - a) * (sa / (sa - sb)));
        }
    }
    let twice: f64 = (0..poly.len())
        .map(|k| poly[k].perp_dot(poly[(k + 1) % poly.len()]))
        .sum();
    0.5 * twice.abs()
}

/// An edge through a pixel: the pixel, a point of the edge inside it, the edge's normal angle.
pub fn edge_input() -> impl Strategy<Value = (UVec2, (f64, f64), f64)> {
    (
        (0u32..1024, 0u32..1024).prop_map(|(x, y)| UVec2::new(x, y)),
        (0.05f64..0.95, 0.05f64..0.95),
        0.0f64..std::f64::consts::TAU,
    )
}

/// Colour of the covered side of the edge.
const EDGE_COLOUR: Vec3 = Vec3::new(1.0, 0.5, 0.25);

/// A pixel crossed by a straight edge converges to the covered fraction as `s` grows.
pub fn check_edge(
    p: &dyn Antialiasing,
    jitters_from: &dyn Antialiasing,
    (pixel, (cx, cy), angle): (UVec2, (f64, f64), f64),
) -> Result<(), String> {
    let c = DVec2::new(cx, cy);
    let n = DVec2::new(angle.cos(), angle.sin());
    let coverage = covered_fraction(c, n);
    let corner = pixel.as_vec2();
    for s in [2u32, 4, 8, 16, 32] {
        let jitters = jitters_from.compute_jitters(s, &mut Rng::for_sample(3, pixel.x, pixel.y, s));
        let mut radiance = |r: Vec2| {
            let q = (r - corner).as_dvec2();
            if n.dot(q - c) >= 0.0 {
                EDGE_COLOUR
            } else {
                Vec3::ZERO
            }
        };
        let got = p.compute_pixel(pixel, &jitters, &mut radiance);
        let expected = coverage as f32 * EDGE_COLOUR;
        let bound = (2 * s - 1) as f32 / (s * s) as f32;
        let err = ((got - expected) / EDGE_COLOUR).abs().max_element();
        if err.is_nan() || err > bound + 1e-4 {
            return Err(format!(
                "pixel {pixel} is crossed by a straight edge through ({cx:.3}, {cy:.3}) of the pixel with normal ({:.3}, {:.3}); the lit side (radiance {EDGE_COLOUR}) covers {coverage:.4} of the pixel, so the pixel value is {expected}. With subdivisions = {s} ({} jittered subpixel rays from the reference's compute_jitters), compute_pixel returned {got}: only the at most 2s − 1 = {} subpixels the edge crosses can be wrong, so it must be within {bound:.4} of the covered fraction (it is {err:.4} away)",
                n.x,
                n.y,
                s * s,
                2 * s - 1
            ));
        }
    }
    Ok(())
}

fn exercise_7_2(p: &Arc<dyn Antialiasing>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx
        .key()
        .map(|k| k.code::<dyn contracts::lab07::Antialiasing>());
    for_all(300, pixel_input(), |(pixel, jitters)| {
        check_average(p, key.as_deref(), pixel, &jitters)
    })?;
    let base = ctx.base.code::<dyn Antialiasing>();
    for_all(100, edge_input(), |edge| {
        check_edge(p.as_ref(), base.as_ref(), edge)
    })?;
    let golden: GoldenFile<PixelInput, Vec3> = ctx.golden(GOLDEN_PIXEL)?;
    for case in &golden.cases {
        let (pixel, jitters) = &case.input;
        let got = p.compute_pixel(*pixel, jitters, &mut probe_radiance);
        compare_vec3(
            &format!("compute_pixel(pixel = {pixel}, jitters = {jitters:?}, radiance)"),
            got,
            case.expected,
            1e-5,
            1e-4,
        )?;
    }
    // Given the reference's jitters the render is deterministic (no area lights in the default
    // scene), so only rounding separates two correct averages.
    let film = render_default(
        &part_pipeline(Part::Pixel, p, &ctx.base),
        PIXEL_SNAPSHOT_SUBDIVISIONS,
        SNAPSHOT_SETTINGS.seed,
    )
    .map_err(|e| e.to_string())?;
    let tol = PixelTolerance {
        abs: 1e-3,
        rel: 1e-3,
        max_outlier_fraction: 0.002,
    };
    ctx.check_snapshot(SNAPSHOT_PIXEL, &film, &tol)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn covered_fraction_of_simple_edges() {
        // A vertical edge at x = 0.3, lit to the right: 0.7 of the pixel.
        let f = covered_fraction(DVec2::new(0.3, 0.5), DVec2::new(1.0, 0.0));
        assert!((f - 0.7).abs() < 1e-12);
        // The diagonal through the centre halves the pixel.
        let f = covered_fraction(DVec2::splat(0.5), DVec2::new(1.0, 1.0).normalize());
        assert!((f - 0.5).abs() < 1e-12);
        // A corner cut off by x + y ≤ 0.5: area 1/8.
        let f = covered_fraction(DVec2::new(0.25, 0.25), DVec2::new(-1.0, -1.0).normalize());
        assert!((f - 0.125).abs() < 1e-12);
    }
}
