//! Exercise 3.2: jittered samples, one per stratum and uniform within it.

use std::sync::Arc;

use glam::Vec2;
use proptest::prelude::*;

use contracts::lab03::Shadows;
use grading::stats::{chi_square_p_value, chi_square_uniform};
use grading::{LabContext, StrataNames, cell_of, check_one_per_cell, for_all};
use raylab_core::sampling::Rng;

use super::irradiance::check_irradiance;
use super::soft_shadows::check_area_snapshot;
use super::{CHI_SQUARE_P, Part, format_counts};

fn check_strata(n: u32, samples: &[Vec2]) -> Result<(), String> {
    let call = format!("stratified_samples(n = {n}, rng)");
    let names = StrataNames {
        call: &call,
        point: "sample",
        cell: "cell",
        outside_hint: "",
    };
    check_one_per_cell(&names, n, samples)
}

/// Where a sample lies within its cell, in `[0, 1)²`.
fn offset_in_cell(p: Vec2, n: u32) -> Vec2 {
    let (i, j) = cell_of(p, n);
    let o = Vec2::new(
        (p.x as f64 * n as f64 - i as f64) as f32,
        (p.y as f64 * n as f64 - j as f64) as f32,
    );
    o.clamp(Vec2::ZERO, Vec2::splat(0.999_999))
}

/// The positions of samples within their cells, binned into `k × k` bins.
fn offset_counts(samples: &[Vec2], n: u32, k: u32) -> Vec<u32> {
    let mut counts = vec![0u32; (k * k) as usize];
    for p in samples {
        let o = offset_in_cell(*p, n);
        let (bx, by) = ((o.x * k as f32) as u32, (o.y * k as f32) as u32);
        counts[(by.min(k - 1) * k + bx.min(k - 1)) as usize] += 1;
    }
    counts
}

/// The jitter: within its cell, each sample must be uniformly distributed and independent of
/// the others (χ² tests of the in-cell positions), and it must come from `rng`.
fn check_jitter(s: &Arc<dyn Shadows>) -> Result<(), String> {
    const K: u32 = 4;
    // One call with many cells: the in-cell positions of its 256 samples.
    for seed in 0..6u64 {
        let samples = s.stratified_samples(16, &mut Rng::new(seed, 31));
        let counts = offset_counts(&samples, 16, K);
        let stat = chi_square_uniform(&counts);
        let p = chi_square_p_value(stat, K * K - 1);
        if p < CHI_SQUARE_P {
            return Err(format!(
                "the samples of one call stratified_samples(n = 16, rng) are not jittered uniformly within their cells: binning each sample's position within its cell into {K}×{K} bins gives the counts [{}] (expected about {} each; χ² = {stat:.1}, {} degrees of freedom, p = {p:.1e}). Each cell needs its own uniform random point (i + ξ₁, j + ξ₂)/n with fresh ξ₁, ξ₂ from rng.next_vec2() — not the cell centre, and not one offset shared by all cells or by x and y",
                format_counts(&counts),
                256 / (K * K),
                K * K - 1
            ));
        }
    }
    // The samples come from rng: two generators give two different sets.
    for n in [1u32, 4] {
        let a = s.stratified_samples(n, &mut Rng::new(1, 2));
        let b = s.stratified_samples(n, &mut Rng::new(3, 4));
        if a == b {
            return Err(format!(
                "stratified_samples(n = {n}, rng) returned the same samples {a:?} for two different generators: the jitter must come from rng (rng.next_vec2() once per cell)"
            ));
        }
    }
    // Many calls with few cells, pooled.
    for n in 1..=3u32 {
        let calls = 1024 / (n * n);
        let mut rng = Rng::new(17, n as u64);
        let samples: Vec<Vec2> = (0..calls)
            .flat_map(|_| s.stratified_samples(n, &mut rng))
            .collect();
        let counts = offset_counts(&samples, n, K);
        let stat = chi_square_uniform(&counts);
        let p = chi_square_p_value(stat, K * K - 1);
        if p < CHI_SQUARE_P {
            return Err(format!(
                "over {calls} calls of stratified_samples(n = {n}, rng) on one generator, the positions of the samples within their cells are not uniform: {K}×{K} bins hold [{}] (expected about {} each; χ² = {stat:.1}, {} degrees of freedom, p = {p:.1e}). Each call must draw new random offsets from rng",
                format_counts(&counts),
                samples.len() as u32 / (K * K),
                K * K - 1
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_3_2(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
    for_all(300, (1u32..=16, any::<u64>()), |(n, seed)| {
        check_strata(n, &s.stratified_samples(n, &mut Rng::new(seed, 5)))
    })?;
    check_jitter(s)?;
    check_irradiance(Part::Stratified, s, &ctx.base)?;
    check_area_snapshot(Part::Stratified, s, ctx)
}
