//! The Cornell box check of the path loop: its renders' statistics and convergence rate.

use std::sync::Arc;

use contracts::lab12::PathTracing;
use grading::LabContext;
use grading::stats::{NoiseTolerance, RenderStatistics};
use pipeline::render::render;

use pipeline::{PartSlot, Pipeline, View};
use raylab_core::film::Film;
use raylab_core::render::RenderSettings;

/// The pixels and samples of each render of the Cornell box check.
pub const CORNELL_SETTINGS: RenderSettings = RenderSettings {
    width: 32,
    height: 32,
    samples_per_pixel: 8,
    pixel_subdivisions: 1,
    seed: 0,
    progress: false,
};
/// The bounces of the Cornell box check.
pub const CORNELL_DEPTH: u32 = 4;
/// Seeds of the reference's renders, whose mean and variance `raylab golden` stores.
pub const REFERENCE_SEEDS: std::ops::Range<u64> = 1000..1064;
/// Seeds of the student's renders (disjoint from [`REFERENCE_SEEDS`]).
pub const STUDENT_SEEDS: std::ops::Range<u64> = 5000..5004;
/// The Monte Carlo snapshot of the Cornell box: the per-pixel mean and variance (one
/// render's) of the reference's renders, `cornell-mean.exr` and `cornell-variance.exr`.
pub const SNAPSHOT_CORNELL: &str = "cornell";
/// The tolerance of the Cornell box check: Šidák over the pixels, a few outliers allowed.
pub const CORNELL_TOLERANCE: NoiseTolerance = NoiseTolerance {
    family_alpha: 1e-3,
    abs: 1e-4,
    rel: 1e-3,
    max_outlier_fraction: 0.005,
};

/// The pipeline of the Cornell box check: `code` for the path loop, the base for the rest.
pub fn cornell_pipeline(code: &Arc<dyn PathTracing>, base: &Pipeline) -> Result<Pipeline, String> {
    let base_code = base
        .part::<dyn PathTracing>()
        .ok_or("the base pipeline holds no code of lab 12")?;
    let slot: Arc<dyn PathTracing> = PartSlot::shared("path_radiance", code, &base_code);
    let mut pipeline = base.clone().with_part::<dyn PathTracing>(slot);
    pipeline.view = View::Shaded;
    pipeline.max_depth = CORNELL_DEPTH;
    Ok(pipeline)
}

/// Per-pixel mean and variance of renders of the Cornell box with the given seeds.
pub fn cornell_statistics(
    pipeline: &Pipeline,
    seeds: std::ops::Range<u64>,
) -> Result<RenderStatistics, raylab_core::Error> {
    let scene = raylab_core::scene::builtin_scene("cornell-ceiling")?;
    let films = seeds
        .map(|seed| {
            render(
                &scene,
                pipeline,
                &RenderSettings {
                    seed,
                    ..CORNELL_SETTINGS
                },
            )
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(RenderStatistics::of(&films))
}

/// Samples per pixel of the renders of the convergence-rate check: 1, 4 and 16 times the
/// reference's.
const RATE_SPP: [u32; 3] = [8, 32, 128];
/// Where a squared Z-score is clipped in the mean of [`check_convergence_rate`], so that the
/// rare bright path of a correct render (a firefly) does not dominate it.
const RATE_CLIP: f64 = 16.0;
/// The range the mean of the clipped squared Z-scores at 32 and 128 samples per pixel must
/// keep relative to its value at 8.
const RATE_RANGE: (f64, f64) = (0.6, 1.9);

/// The error of the student's loop in the Cornell box falls as `1/√N`. At 8, 32 and 128 samples
/// per pixel, the squared difference from the reference's mean is scaled by the variance the
/// reference predicts for it, `s² (8/N + 1/K)` (`s²` of an 8-sample render, `K` renders in the
/// reference's mean), clipped at [`RATE_CLIP`] and averaged over the pixels. For an unbiased
/// loop whose samples are independent this mean stays about the same as N grows (about one, or
/// the ratio of its variance to the reference's for a correct loop that is noisier or less
/// noisy): relative to 8 samples it must stay in [`RATE_RANGE`]. Samples that are not
/// independent leave the error of 8 samples at 128 (the mean grows 13-fold); a bias hidden in
/// the noise of 8 samples shows at 128.
fn check_convergence_rate(
    pipeline: &Pipeline,
    reference: &RenderStatistics,
    seed: u64,
) -> Result<(), String> {
    let scene = raylab_core::scene::builtin_scene("cornell-ceiling").map_err(|e| e.to_string())?;
    convergence_rate(reference, &|spp, k| {
        render(
            &scene,
            pipeline,
            &RenderSettings {
                samples_per_pixel: spp,
                seed: seed + k,
                ..CORNELL_SETTINGS
            },
        )
        .map_err(|e| e.to_string())
    })
}

/// `check_convergence_rate` of the images `render(spp, k)` makes (the `k`th render, at `spp`
/// samples per pixel).
pub fn convergence_rate(
    reference: &RenderStatistics,
    render: &dyn Fn(u32, u64) -> Result<Film, String>,
) -> Result<(), String> {
    let base_spp = f64::from(CORNELL_SETTINGS.samples_per_pixel);
    let mut means: Vec<f64> = Vec::new();
    for (k, spp) in RATE_SPP.into_iter().enumerate() {
        let film = render(spp, k as u64)?;
        let share = base_spp / f64::from(spp) + 1.0 / f64::from(reference.renders);
        let mut scores = Vec::new();
        for ((x, mu), s2) in film
            .pixels
            .iter()
            .zip(&reference.mean.pixels)
            .zip(&reference.variance.pixels)
        {
            for c in 0..3 {
                let variance = f64::from(s2[c]) * share;
                if variance > 1e-12 {
                    let d = f64::from(x[c]) - f64::from(mu[c]);
                    let score = d * d / variance;
                    scores.push(if score.is_nan() {
                        RATE_CLIP
                    } else {
                        score.min(RATE_CLIP)
                    });
                }
            }
        }
        means.push(scores.iter().sum::<f64>() / scores.len().max(1) as f64);
        let ratio = means[k] / means[0].max(1e-12);
        if !(RATE_RANGE.0..=RATE_RANGE.1).contains(&ratio) {
            let listed: Vec<String> = RATE_SPP
                .iter()
                .zip(&means)
                .map(|(n, m)| format!("{m:.2} at {n}"))
                .collect();
            return Err(format!(
                "the error of the Cornell box path traced with your loop does not fall as 1/√N: its squared difference from the reference's mean, over the variance the reference predicts for N samples per pixel, is {} (clipped at {RATE_CLIP}; it stays about the same for independent, unbiased samples): {}",
                listed.join(", "),
                if ratio > RATE_RANGE.1 {
                    "at more samples the error is larger than independent samples leave — each sample of a pixel must be an independent path (draw from `rng`, passed on to the closures), and the estimate unbiased"
                } else {
                    "at more samples the error falls faster than independent samples can make it fall"
                }
            ));
        }
    }
    Ok(())
}

/// The Cornell box lit by its ceiling, path traced by the student's loop with the reference's
/// parts, against the mean and variance of the reference's renders by a per-pixel Z-test; then
/// its error at more samples ([`check_convergence_rate`]).
pub(super) fn check_cornell(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let pipeline = cornell_pipeline(s, &ctx.base)?;
    let reference = ctx.noisy_reference(
        SNAPSHOT_CORNELL,
        (REFERENCE_SEEDS.end - REFERENCE_SEEDS.start) as u32,
    )?;
    let student = cornell_statistics(&pipeline, STUDENT_SEEDS).map_err(|e| e.to_string())?;
    ctx.check_noisy_snapshot(
        SNAPSHOT_CORNELL,
        &student,
        (REFERENCE_SEEDS.end - REFERENCE_SEEDS.start) as u32,
        &CORNELL_TOLERANCE,
        &format!(
            "the Cornell box path traced with your loop ({}×{} pixels, {} samples, {CORNELL_DEPTH} bounces)",
            CORNELL_SETTINGS.width, CORNELL_SETTINGS.height, CORNELL_SETTINGS.samples_per_pixel
        ),
    )?;
    check_convergence_rate(&pipeline, &reference, STUDENT_SEEDS.end)
}

#[cfg(test)]
mod tests {
    use super::*;
    use contracts::sampling::Rng;
    use glam::Vec3;

    /// A normal deviate (Box–Muller).
    fn normal(rng: &mut Rng) -> f32 {
        let u = rng.next_vec2();
        (-2.0 * (1.0 - u.x).ln()).sqrt() * (std::f32::consts::TAU * u.y).cos()
    }

    /// A 32 × 32 truth, its reference of 64 renders (the mean with its own noise, the variance
    /// of one 8-sample render), and renders of it at N samples with the noise of `noise_spp(N)`
    /// samples and a bias of `bias` standard deviations of a 128-sample render.
    fn setup(noise_spp: fn(u32) -> u32, bias: f32) -> Result<(), String> {
        let mut rng = Rng::new(4, 4);
        let n = 32 * 32;
        let truth: Vec<Vec3> = (0..n)
            .map(|i| Vec3::new(0.1 + (i % 7) as f32, 0.5, 2.0 + (i % 3) as f32))
            .collect();
        let variance: Vec<Vec3> = truth.iter().map(|t| *t * 0.3).collect();
        let noisy = |rng: &mut Rng, share: f32, shift: f32| {
            let mut film = Film::new(32, 32);
            for ((p, t), v) in film.pixels.iter_mut().zip(&truth).zip(&variance) {
                let sd = (*v * share).powf(0.5);
                let deviate = Vec3::new(normal(rng), normal(rng), normal(rng));
                *p = *t + sd * deviate + shift * (*v / 16.0).powf(0.5);
            }
            film
        };
        let mut mean = noisy(&mut rng, 1.0 / 64.0, 0.0);
        mean.pixels.iter_mut().for_each(|p| *p = p.max(Vec3::ZERO));
        let mut var = Film::new(32, 32);
        var.pixels.copy_from_slice(&variance);
        let reference = RenderStatistics {
            renders: 64,
            mean,
            variance: var,
        };
        let rng = std::cell::RefCell::new(rng);
        convergence_rate(&reference, &|spp, _| {
            let share = 8.0 / noise_spp(spp) as f32;
            Ok(noisy(&mut rng.borrow_mut(), share, bias))
        })
    }

    #[test]
    fn the_convergence_rate_check_tells_independent_samples_from_others() {
        setup(|n| n, 0.0).expect("independent, unbiased samples pass");
        // Correct alternatives with twice and half the reference's variance.
        setup(|n| n / 2, 0.0).expect("a noisier unbiased loop passes");
        setup(|n| 2 * n, 0.0).expect("a less noisy unbiased loop passes");
        let stuck = setup(|_| 8, 0.0).expect_err("an error that does not fall");
        assert!(stuck.contains("independent path"), "{stuck}");
        // A bias of 1.5 standard errors of a 128-sample render, hidden in the noise of 8.
        setup(|n| n, 1.5).expect_err("a bias that shows with more samples");
    }
}
