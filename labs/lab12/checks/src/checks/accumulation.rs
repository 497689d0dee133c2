//! Exercises 12.9 and 12.10: progressive accumulation of a pixel's estimates.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab12::PathTracing;
use contracts::sampling::Rng;
use grading::{GoldenFile, LabContext, compare_f32, for_all};

use super::{CASES, key, load};

/// Golden file of Exercise 12.10.
pub const GOLDEN_RELATIVE_ERROR: &str = "relative_error.json";

/// A stream of estimates of one pixel: `n` values about `level` (per channel, from 10⁻⁴ to
/// 10⁴) spread by `spread` of it, with one channel black.
pub fn estimates() -> impl Strategy<Value = (u32, f32, f32, u64)> + Clone {
    (
        1u32..400,
        prop::sample::select(vec![1e-4f32, 1e-2, 1.0, 1e2, 1e4]),
        prop::sample::select(vec![1e-6f32, 1e-3, 0.3, 2.0]),
        any::<u64>(),
    )
}

/// The values of an [`estimates`] stream.
fn stream((n, level, spread, seed): (u32, f32, f32, u64)) -> Vec<Vec3> {
    let mut rng = Rng::new(seed, 9);
    (0..n)
        .map(|_| {
            let x = level * (1.0 + spread * (rng.next_f32() - 0.5));
            let y = level * 0.5 * (1.0 + spread * (rng.next_f32() - 0.5));
            Vec3::new(x, y, 0.0)
        })
        .collect()
}

/// Exercise 12.9: over streams of 1 to 400 estimates at levels from 10⁻⁴ to 10⁴ (and spreads
/// down to 10⁻⁶ of the level, where a sum of squares loses every digit), the count, the mean
/// and `m2` against a two-pass computation in double precision; a black channel stays 0.
pub(super) fn exercise_12_9(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    use contracts::lab12::PixelStatistics;
    for_all(CASES, estimates(), |input| {
        let values = stream(input);
        let mut stats = PixelStatistics::default();
        for &v in &values {
            stats = s.accumulate(&stats, v);
        }
        let n = values.len();
        let what = format!(
            "after accumulating {n} estimates around {} (spread {} of it)",
            input.1, input.2
        );
        if stats.count as usize != n {
            return Err(format!(
                "{what} the count is {}: add one per estimate",
                stats.count
            ));
        }
        for c in 0..3 {
            let xs: Vec<f64> = values.iter().map(|v| f64::from(v[c])).collect();
            let mean = xs.iter().sum::<f64>() / n as f64;
            let m2: f64 = xs.iter().map(|x| (x - mean) * (x - mean)).sum();
            let channel = ["red", "green", "blue"][c];
            let mean_ok = (f64::from(stats.mean[c]) - mean).abs() <= 1e-5 * mean.abs() + 1e-30;
            if !mean_ok {
                return Err(format!(
                    "{what} the {channel} mean is {}, expected {mean}",
                    stats.mean[c]
                ));
            }
            // m2 to 1 % of itself, or of the rounding floor of the values (ε² n mean²).
            let floor = 1e-12 * n as f64 * mean * mean;
            let m2_ok = (f64::from(stats.m2[c]) - m2).abs() <= 1e-2 * m2 + floor;
            if !m2_ok {
                return Err(format!(
                    "{what} the {channel} m2 (Σ (x − mean)²) is {}, expected {m2}: Welford's update keeps the digits that a sum of squares minus the square of the sum loses",
                    stats.m2[c]
                ));
            }
        }
        Ok(())
    })
}

/// Inputs of Exercise 12.10: statistics of streams, and the edge cases.
pub fn relative_error_inputs() -> Vec<contracts::lab12::PixelStatistics> {
    use contracts::lab12::PixelStatistics;
    let mut inputs = vec![
        PixelStatistics::default(),
        PixelStatistics {
            count: 1,
            mean: Vec3::new(0.5, 0.2, 0.1),
            m2: Vec3::ZERO,
        },
        PixelStatistics {
            count: 10,
            mean: Vec3::ZERO,
            m2: Vec3::ZERO,
        },
        PixelStatistics {
            count: 4,
            mean: Vec3::new(2.0, 1.0, 0.0),
            m2: Vec3::new(3.0, 12.0, 0.0),
        },
    ];
    let streams = grading::strategies::samples(estimates(), 60, 101);
    for input in streams {
        let mut stats = PixelStatistics::default();
        for v in stream(input) {
            let count = stats.count + 1;
            let delta = v - stats.mean;
            let mean = stats.mean + delta / count as f32;
            stats = PixelStatistics {
                count,
                mean,
                m2: stats.m2 + delta * (v - mean),
            };
        }
        inputs.push(stats);
    }
    inputs
}

/// Exercise 12.10: infinite below two estimates; 0 for a black pixel; the largest channel's
/// `√(m2/(n − 1)/n)/mean`, so that four estimates of means (2, 1, 0) and m2 (3, 12, 0) give 2;
/// the key's values (where present) and the golden cases'.
pub(super) fn exercise_12_10(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let inputs = relative_error_inputs();
    let call = |st: &contracts::lab12::PixelStatistics| format!("relative_error({st:?})");
    for (st, expected) in [(&inputs[0], f32::INFINITY), (&inputs[1], f32::INFINITY)] {
        let got = s.relative_error(st);
        if got != expected {
            return Err(format!(
                "{} is {got}: with fewer than two estimates there is no variance, so the error is unknown: return f32::INFINITY",
                call(st)
            ));
        }
    }
    let got = s.relative_error(&inputs[2]);
    if got != 0.0 {
        return Err(format!(
            "{} is {got}: a black pixel that never varied has converged (0), not 0/0",
            call(&inputs[2])
        ));
    }
    // Red: √(3/3/4)/2 = 0.25, green: √(12/3/4)/1 = 1, blue: black.
    compare_f32(
        &call(&inputs[3]),
        s.relative_error(&inputs[3]),
        1.0,
        0.0,
        1e-5,
    )
    .map_err(|e| {
        format!(
            "{e}: the largest channel's √(s²/n)/mean with s² = m2/(n − 1) (green: √(12/3/4)/1 = 1)"
        )
    })?;
    if let Some(key) = key(ctx) {
        for st in &inputs[4..] {
            compare_f32(
                &call(st),
                s.relative_error(st),
                key.relative_error(st),
                0.0,
                1e-4,
            )?;
        }
    }
    let golden: GoldenFile<contracts::lab12::PixelStatistics, f32> =
        load(ctx, GOLDEN_RELATIVE_ERROR)?;
    for case in &golden.cases {
        compare_f32(
            &call(&case.input),
            s.relative_error(&case.input),
            case.expected,
            0.0,
            1e-4,
        )?;
    }
    Ok(())
}
