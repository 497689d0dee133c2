//! Exercises 12.6 and 12.7: the power heuristic and Russian roulette.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab12::PathTracing;
use contracts::sampling::Rng;
use grading::stats::family_z_limit;
use grading::{GoldenFile, LabContext, compare_f32, for_all};

use super::{CASES, SIGNIFICANCE, key, load};

/// Golden file of Exercise 12.6.
pub const GOLDEN_POWER_HEURISTIC: &str = "power_heuristic.json";

/// A density from 10⁻⁶ to 10¹⁵.
pub fn density() -> impl Strategy<Value = f32> + Clone {
    (1.0f32..10.0, -6i32..15).prop_map(|(m, e)| m * 10f32.powi(e))
}

/// Exercise 12.6: the two weights of a sample add up to one; one strategy alone has weight
/// one, a density of zero weight zero (also against zero); then the key's weights (where
/// present) and the golden cases'.
pub(super) fn exercise_12_6(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, (density(), density()), |(a, b)| {
        let (w, v) = (s.power_heuristic(a, b), s.power_heuristic(b, a));
        let sum_is_one = (w + v - 1.0).abs() <= 1e-5;
        if !sum_is_one || !(0.0..=1.0).contains(&w) {
            return Err(format!(
                "power_heuristic({a}, {b}) + power_heuristic({b}, {a}) = {w} + {v} = {}: the weights of the two strategies for one sample are in [0, 1] and add up to 1",
                w + v
            ));
        }
        Ok(())
    })?;
    for (a, b, expected) in [
        (2.0, 0.0, 1.0),
        (0.0, 3.0, 0.0),
        (0.0, 0.0, 0.0),
        (5.0, 5.0, 0.5),
    ] {
        let got = s.power_heuristic(a, b);
        if got != expected {
            return Err(format!(
                "power_heuristic({a}, {b}) is {got}, expected {expected}{}",
                if a == 0.0 && b == 0.0 {
                    ": a sample no strategy can draw has weight 0, not 0/0"
                } else {
                    ""
                }
            ));
        }
    }
    if let Some(key) = key(ctx) {
        for_all(CASES, (density(), density()), |(a, b)| {
            compare_f32(
                &format!("power_heuristic({a}, {b})"),
                s.power_heuristic(a, b),
                key.power_heuristic(a, b),
                1e-7,
                1e-4,
            )
        })?;
    }
    let golden: GoldenFile<(f32, f32), f32> = load(ctx, GOLDEN_POWER_HEURISTIC)?;
    for case in &golden.cases {
        let (a, b) = case.input;
        compare_f32(
            &format!("power_heuristic({a}, {b})"),
            s.power_heuristic(a, b),
            case.expected,
            1e-7,
            1e-4,
        )?;
    }
    Ok(())
}

/// Exercise 12.7: for throughputs below, at and above one, unequal channels among them: the
/// path survives with probability `min(1, max channel)`, its factor is `1/q`, so the expected
/// factor is one; zero and NaN end the path; the generator advances.
pub(super) fn exercise_12_7(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    let throughputs = [
        Vec3::new(0.05, 0.01, 0.02),
        Vec3::splat(0.3),
        Vec3::new(0.9, 0.1, 0.1),
        Vec3::new(0.2, 0.6, 0.4),
        Vec3::new(1.5, 0.2, 0.1),
        Vec3::new(1e-4, 1e-4, 1e-4),
    ];
    const TRIALS: usize = 20_000;
    let z_limit = family_z_limit(SIGNIFICANCE, throughputs.len());
    for (k, &t) in throughputs.iter().enumerate() {
        let q = t.max_element().min(1.0);
        let mut rng = Rng::new(700 + k as u64, 12);
        let mut survived = 0usize;
        for _ in 0..TRIALS {
            if let Some(factor) = s.roulette(t, &mut rng) {
                survived += 1;
                compare_f32(
                    &format!("the factor roulette(throughput = {t}) returned"),
                    factor,
                    1.0 / q,
                    0.0,
                    1e-5,
                )
                .map_err(|e| format!("{e} (1/q, q = min(1, max channel) = {q}): dividing by the probability of going on keeps the estimate unbiased"))?;
            }
        }
        let rate = survived as f64 / TRIALS as f64;
        let q = f64::from(q);
        let error = (q * (1.0 - q) / TRIALS as f64).sqrt().max(1e-9);
        if ((rate - q) / error).abs() > z_limit {
            return Err(format!(
                "roulette(throughput = {t}) let {survived} of {TRIALS} paths go on ({:.2} %); the probability is q = min(1, max channel) = {:.2} %",
                100.0 * rate,
                100.0 * q
            ));
        }
    }
    for t in [Vec3::ZERO, Vec3::NAN] {
        let mut rng = Rng::new(9, 9);
        for _ in 0..16 {
            if let Some(factor) = s.roulette(t, &mut rng) {
                return Err(format!(
                    "roulette(throughput = {t}) returned Some({factor}): a path that carries nothing (or not a number) ends"
                ));
            }
        }
    }
    let mut rng = Rng::new(11, 11);
    let t = Vec3::splat(0.5);
    let outcomes: Vec<_> = (0..32).map(|_| s.roulette(t, &mut rng)).collect();
    if outcomes.iter().all(|o| *o == outcomes[0]) {
        return Err(format!(
            "roulette(throughput = {t}) returned {:?} 32 times in a row: draw a new number from `rng` every call",
            outcomes[0]
        ));
    }
    Ok(())
}
