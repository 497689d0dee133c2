//! Exercises 5.8 and 5.9: Monte Carlo irradiance estimators, judged by their means and variances.

use std::f64::consts::PI;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use contracts::lab05::Radiometry;
use grading::stats::{normal_two_sided_quantile, sidak};
use grading::{GoldenFile, LabContext};
use raylab_core::sampling::Rng;

use super::GOLDEN_VARIANCE;
use super::lights::{LightCase, MC_ESTIMATES, MC_SAMPLES, light_cases, mean_cases};

/// The configuration where the cosine estimator's variance is below the area estimator's.
pub const BIG_LIGHT: usize = 2;
/// The scales of the mean test (the ends and the middle of
/// [`SCALES`](grading::strategies::SCALES)) and the radiance
/// factor at each.
pub const MC_SCALES: [(f64, f64); 3] = [(1e-4, 1e3), (1.0, 1.0), (1e3, 1e-2)];
/// Family-wise false-alarm rate of the mean tests (Šidák-corrected over cases and scales).
pub const MC_ALPHA: f64 = 1e-4;
/// A student's per-estimate variance may be at most this times the reference's (recorded in
/// golden data): the sampling error of a variance from 256 estimates is about 10 %.
pub const VARIANCE_SLACK: f64 = 1.5;

/// Which estimator.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Estimator {
    /// Exercise 5.8.
    Area,
    /// Exercise 5.9.
    Cosine,
}

/// One estimate by `estimator`.
pub fn estimate(
    s: &dyn Radiometry,
    estimator: Estimator,
    case: &LightCase,
    samples: u32,
    rng: &mut Rng,
) -> f64 {
    match estimator {
        Estimator::Area => s.irradiance_area_sampling(&case.light, &case.receiver, samples, rng),
        Estimator::Cosine => {
            s.irradiance_cosine_sampling(&case.light, &case.receiver, samples, rng)
        }
    }
}

/// `count` estimates with `samples` samples each, the `k`-th from `Rng::new(seed, k)`.
pub fn estimates(
    s: &dyn Radiometry,
    estimator: Estimator,
    case: &LightCase,
    samples: u32,
    count: u32,
    seed: u64,
) -> Vec<f64> {
    (0..count)
        .map(|k| estimate(s, estimator, case, samples, &mut Rng::new(seed, k as u64)))
        .collect()
}

/// Mean and unbiased variance.
pub fn mean_and_variance(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, var)
}

/// The reference's per-estimate variance of both estimators on one configuration (golden data
/// of 5.8 and 5.9): the estimates with [`MC_SAMPLES`] samples, seed 11.
#[derive(Clone, Copy, Debug, Serialize, Deserialize)]
pub struct EstimatorVariance {
    /// Variance of the area-sampling estimates.
    pub area: f64,
    /// Variance of the cosine-sampling estimates.
    pub cosine: f64,
}

/// Successive calls on one generator in the check that they differ (an estimator counting
/// discrete hits can repeat a value now and then, but not eight times running).
const RNG_CALLS: usize = 8;

/// The generator must be the one the estimates come from: after the call it has advanced, and
/// successive calls on it do not all give the same estimate.
fn check_rng(s: &dyn Radiometry, estimator: Estimator, case: &LightCase) -> Result<(), String> {
    let mut rng = Rng::new(3, 7);
    let mut untouched = rng.clone();
    let first = estimate(s, estimator, case, MC_SAMPLES, &mut rng);
    if rng.next_u32() == untouched.next_u32() {
        return Err(format!(
            "for {}, the generator passed in is where it was after the call: the samples must be drawn from rng (rng.next_vec2() per sample), so the renderer's sequence moves on",
            case.what
        ));
    }
    let same = (1..RNG_CALLS).all(|_| estimate(s, estimator, case, MC_SAMPLES, &mut rng) == first);
    if same {
        return Err(format!(
            "for {}, {RNG_CALLS} successive calls on the same generator all give the estimate {first:e}: each call must draw new samples from rng",
            case.what
        ));
    }
    Ok(())
}

/// The mean test: at every configuration of [`mean_cases`] and scale the mean of the case's
/// estimates is within the Šidák-corrected `z·SE` (plus 10⁻⁹ of `π·L_e`, the largest
/// irradiance the light can give) of the exact irradiance.
fn check_means(s: &dyn Radiometry, estimator: Estimator) -> Result<(), String> {
    let cases = mean_cases();
    let z = normal_two_sided_quantile(sidak(MC_ALPHA, cases.len() * MC_SCALES.len()));
    // The generator test on the configurations where every estimator gets some light.
    let lit = light_cases().len();
    for (k, case) in cases.iter().enumerate() {
        if k < lit {
            check_rng(s, estimator, case)?;
        }
        for (scale, radiance) in MC_SCALES {
            let scaled = case.scaled(scale, radiance);
            let exact = scaled.exact();
            let le = scaled.light.radiance_w_per_m2_sr;
            let x = estimates(s, estimator, &scaled, case.samples, case.estimates, 1);
            let (mean, var) = mean_and_variance(&x);
            let se = (var / x.len() as f64).sqrt();
            let within = (mean - exact).abs() <= z * se + 1e-9 * PI * le;
            if !within {
                let off = if !mean.is_finite() {
                    "an estimate".to_string()
                } else if exact > 0.0 {
                    format!("{:.4}× the exact value", mean / exact)
                } else {
                    "where nothing arrives".to_string()
                };
                let spread = if !mean.is_finite() {
                    "not a finite number".to_string()
                } else if se > 0.0 {
                    format!(
                        "{:.1} standard errors off (at most {z:.1} allowed)",
                        (mean - exact).abs() / se
                    )
                } else {
                    "and every estimate the same".to_string()
                };
                let how = if exact > 0.0 {
                    " by Lambert's polygon formula"
                } else {
                    ""
                };
                let hint = if case.hint.is_empty() {
                    String::new()
                } else {
                    format!(" — {}", case.hint)
                };
                return Err(format!(
                    "the irradiance from {} (radiance {le:e} W/(m² sr), lengths × {scale:e}; exact E = {exact:e} W/m²{how}) estimated with {} samples is {mean:e} ± {se:.3e} (mean ± standard error of {} estimates): {off}, {spread}{hint}",
                    case.what, case.samples, case.estimates,
                ));
            }
        }
    }
    Ok(())
}

/// The variances of the estimates at scale 1, with those the reference recorded.
fn check_variances(
    s: &dyn Radiometry,
    estimator: Estimator,
    ctx: &LabContext,
) -> Result<(), String> {
    let golden: GoldenFile<u32, EstimatorVariance> = ctx.golden(GOLDEN_VARIANCE)?;
    let cases = light_cases();
    for case in &golden.cases {
        let light = cases
            .get(case.input as usize)
            .ok_or_else(|| {
                ctx.unreadable(
                    &format!("golden/{GOLDEN_VARIANCE}"),
                    format!(
                        "the golden variances name configuration {}, which this framework does not have",
                        case.input
                    ),
                )
            })?;
        let (_, var) = mean_and_variance(&estimates(
            s,
            estimator,
            light,
            MC_SAMPLES,
            MC_ESTIMATES,
            11,
        ));
        let (reference, name) = match estimator {
            Estimator::Area => (case.expected.area, "uniform area sampling"),
            Estimator::Cosine => (case.expected.cosine, "cosine-weighted sampling"),
        };
        let bounded = var <= VARIANCE_SLACK * reference;
        if !bounded {
            return Err(format!(
                "for {}, the variance of one estimate with {MC_SAMPLES} samples is {var:.3e}; {name} with {MC_SAMPLES} independent samples has {reference:.3e} (at most {VARIANCE_SLACK}× that allowed): use all the samples asked for, each with its own rng.next_vec2(), weighted by 1/pdf",
                light.what
            ));
        }
        let below_area = var < case.expected.area;
        if estimator == Estimator::Cosine && case.input as usize == BIG_LIGHT && !below_area {
            return Err(format!(
                "for {}, the variance of one estimate with {MC_SAMPLES} samples is {var:.3e}, not below uniform area sampling's {:.3e}: drawn in proportion to cos θ, the directions follow the integrand, and each one that hits the light contributes the same π·L",
                light.what, case.expected.area
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_5_8(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    check_means(s.as_ref(), Estimator::Area)?;
    check_variances(s.as_ref(), Estimator::Area, ctx)
}

pub(super) fn exercise_5_9(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    check_means(s.as_ref(), Estimator::Cosine)?;
    check_variances(s.as_ref(), Estimator::Cosine, ctx)
}
