//! The statistics of the checks: tail probabilities and quantiles of the standard normal and χ²
//! distributions, Šidák's correction for many tests, Pearson's χ² statistic, and the Z-test of
//! a Monte Carlo render against the reference's per-pixel statistics.

use glam::{DVec3, Vec3};

use raylab_core::film::{Film, luminance};

/// `ln Γ(x)` for `x > 0` (Lanczos' approximation, as in Numerical Recipes' `gammln`).
fn ln_gamma(x: f64) -> f64 {
    const COF: [f64; 6] = [
        76.180_091_729_471_46,
        -86.505_320_329_416_77,
        24.014_098_240_830_91,
        -1.231_739_572_450_155,
        0.120_865_097_386_617_9e-2,
        -0.539_523_938_495_3e-5,
    ];
    let mut y = x;
    let tmp = x + 5.5;
    let tmp = tmp - (x + 0.5) * tmp.ln();
    let mut ser = 1.000_000_000_190_015;
    for c in COF {
        y += 1.0;
        ser += c / y;
    }
    -tmp + (2.506_628_274_631_000_5 * ser / x).ln()
}

/// The regularized upper incomplete gamma function `Q(a, x) = Γ(a, x)/Γ(a)` (series for
/// `x < a + 1`, Lentz's continued fraction otherwise).
fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let prefactor = (-x + a * x.ln() - ln_gamma(a)).exp();
    if x < a + 1.0 {
        let (mut ap, mut del) = (a, 1.0 / a);
        let mut sum = del;
        for _ in 0..1000 {
            ap += 1.0;
            del *= x / ap;
            sum += del;
            if del.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * prefactor).max(0.0)
    } else {
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..1000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + an / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let del = d * c;
            h *= del;
            if (del - 1.0).abs() < 1e-16 {
                break;
            }
        }
        prefactor * h
    }
}

/// The probability that a χ² variable with `df` degrees of freedom is at least `stat`.
pub fn chi_square_p_value(stat: f64, df: u32) -> f64 {
    gamma_q(0.5 * df as f64, 0.5 * stat)
}

/// The probability that a standard normal variable is at least `z` in magnitude.
pub fn normal_two_sided_p(z: f64) -> f64 {
    gamma_q(0.5, 0.5 * z * z)
}

/// The `z` with `P(|Z| ≥ z) = p` for a standard normal `Z` (by bisection).
pub fn normal_two_sided_quantile(p: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, 40.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if normal_two_sided_p(mid) > p {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The mean of `n` values, `x` and `n − x.len()` zeros (an estimator that is zero where it
/// did not fire), and the standard error of that mean from the unbiased variance.
pub fn mean_and_standard_error(x: &[f64], n: usize) -> (f64, f64) {
    let count = n as f64;
    let mean = x.iter().sum::<f64>() / count;
    let zeros = (n - x.len()) as f64;
    let squares = x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() + zeros * mean * mean;
    (mean, (squares / (count - 1.0) / count).sqrt())
}

/// Šidák's per-test level: `m` independent tests at this level all pass with probability
/// `1 − family_alpha`.
pub fn sidak(family_alpha: f64, m: usize) -> f64 {
    -((-family_alpha).ln_1p() / m as f64).exp_m1()
}

/// The largest |z| each of `tests` statistical tests may reach when the whole family is to
/// fail a correct implementation with probability `family_alpha` at most (Šidák).
pub fn family_z_limit(family_alpha: f64, tests: usize) -> f64 {
    normal_two_sided_quantile(sidak(family_alpha, tests))
}

/// Pearson's χ² of counts against equal expected counts, and the statistic as a z-score
/// (Wilson–Hilferty, `counts.len() − 1` degrees of freedom).
pub fn chi_square_uniform_z(counts: &[u32]) -> (f64, f64) {
    let chi2 = chi_square_uniform(counts);
    (chi2, wilson_hilferty_z(chi2, counts.len() as u32 - 1))
}

/// Pearson's χ² statistic of observed counts against equal expected counts (`counts.len() − 1`
/// degrees of freedom).
pub fn chi_square_uniform(counts: &[u32]) -> f64 {
    let total: u32 = counts.iter().sum();
    let expected = total as f64 / counts.len() as f64;
    counts
        .iter()
        .map(|&c| (c as f64 - expected).powi(2) / expected)
        .sum()
}

/// A χ² statistic with `df` degrees of freedom as a standard normal z-score (Wilson–Hilferty:
/// `(χ²/k)^(1/3)` is nearly normal with mean `1 − 2/(9k)` and variance `2/(9k)`).
pub fn wilson_hilferty_z(stat: f64, df: u32) -> f64 {
    let k = df as f64;
    let v = 2.0 / (9.0 * k);
    ((stat / k).cbrt() - (1.0 - v)) / v.sqrt()
}

// ---------------------------------------------------------------------------------------------
// The Z-test of a Monte Carlo render

/// Per-pixel statistics of a set of renders with independent seeds.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderStatistics {
    /// Number of renders.
    pub renders: u32,
    /// Per-pixel mean.
    pub mean: Film,
    /// Per-pixel unbiased variance of one render.
    pub variance: Film,
}

impl RenderStatistics {
    /// The per-pixel mean and (unbiased) variance of `films`, which are at least one and all
    /// of the same size.
    pub fn of(films: &[Film]) -> RenderStatistics {
        let (w, h) = (films[0].width, films[0].height);
        let k = films.len() as f64;
        let mut mean = Film::new(w, h);
        let mut variance = Film::new(w, h);
        for i in 0..mean.pixels.len() {
            let m: DVec3 = films.iter().map(|f| f.pixels[i].as_dvec3()).sum::<DVec3>() / k;
            let v: DVec3 = films
                .iter()
                .map(|f| (f.pixels[i].as_dvec3() - m).powf(2.0))
                .sum::<DVec3>()
                / (k - 1.0).max(1.0);
            mean.pixels[i] = m.as_vec3();
            variance.pixels[i] = v.as_vec3();
        }
        RenderStatistics {
            renders: films.len() as u32,
            mean,
            variance,
        }
    }
}

/// How a Monte Carlo render is compared with the reference's statistics (per-pixel mean `μ`
/// and variance `s²` of one render, from `K` renders with independent seeds).
///
/// The student's image is the mean `x̄` of `R` renders with other seeds. Per pixel and channel
/// `z = (x̄ − μ)/√(s²(1/R + 1/K) + τ²)` with `τ = abs + rel·|μ|`, which covers rounding where
/// the reference has no noise (the lamp, full shadow). A pixel is an outlier when some channel
/// has `|z|` above the Šidák-corrected threshold for `family_alpha` over all pixels and
/// channels; the image passes with at most `max_outlier_fraction` outliers (the pixel values are
/// not exactly normal — a deep-penumbra pixel that sees the light in one render of a hundred
/// has a long tail — and `s²` is itself estimated).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseTolerance {
    /// Family-wise false-alarm rate of the per-pixel Z-tests.
    pub family_alpha: f64,
    /// Absolute floor of the noise per channel.
    pub abs: f32,
    /// Relative floor of the noise per channel.
    pub rel: f32,
    /// Fraction of pixels allowed beyond the threshold.
    pub max_outlier_fraction: f32,
}

impl NoiseTolerance {
    /// The per-test threshold on `|z|` for an image of `pixels` pixels (three channels each).
    pub fn z_threshold(&self, pixels: usize) -> f64 {
        normal_two_sided_quantile(sidak(self.family_alpha, 3 * pixels))
    }
}

/// The outcome of [`compare_noisy`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NoiseReport {
    /// Pixels beyond the threshold.
    pub outliers: usize,
    /// NaN or infinite pixels in the render.
    pub non_finite: usize,
    /// Pixels compared.
    pub pixels: usize,
    /// The per-test threshold on `|z|`.
    pub z_threshold: f64,
    /// The largest `|z|` and its pixel.
    pub worst: (f64, u32, u32),
    /// Total luminance of the render over that of the reference mean.
    pub brightness: f64,
}

impl NoiseReport {
    /// Whether the render passes under `tol`.
    pub fn passes(&self, tol: &NoiseTolerance) -> bool {
        self.non_finite == 0
            && self.outliers as f32 <= tol.max_outlier_fraction * self.pixels as f32
    }
}

/// `|z|` per pixel (the largest over the channels; see [`NoiseTolerance`]); NaN for a
/// non-finite render pixel.
pub fn z_scores(
    student: &RenderStatistics,
    reference: &RenderStatistics,
    tol: &NoiseTolerance,
) -> Vec<f64> {
    let (r, k) = (student.renders as f64, reference.renders as f64);
    (0..reference.mean.pixels.len())
        .map(|i| {
            let x = student.mean.pixels[i];
            if !x.is_finite() {
                return f64::NAN;
            }
            let mu = reference.mean.pixels[i];
            let var = reference.variance.pixels[i];
            let own = student.variance.pixels[i];
            (0..3)
                .map(|c| {
                    let floor = tol.abs as f64 + tol.rel as f64 * (mu[c] as f64).abs();
                    let v_ref = var[c].max(0.0) as f64;
                    let v_own = if own[c].is_finite() {
                        own[c].max(0.0) as f64
                    } else {
                        0.0
                    };
                    let sd = (v_ref / k + v_ref.max(v_own) / r + floor * floor).sqrt();
                    (x[c] as f64 - mu[c] as f64).abs() / sd
                })
                .fold(0.0, f64::max)
        })
        .collect()
}

/// Compares the student's renders with the reference's (see [`NoiseTolerance`]).
pub fn compare_noisy(
    student: &RenderStatistics,
    reference: &RenderStatistics,
    tol: &NoiseTolerance,
) -> NoiseReport {
    let render = &student.mean;
    let mean = &reference.mean;
    let z = z_scores(student, reference, tol);
    let threshold = tol.z_threshold(z.len());
    let mut worst = (0.0, 0, 0);
    let mut outliers = 0;
    for (k, &v) in z.iter().enumerate() {
        if v.is_nan() || v > threshold {
            outliers += 1;
        }
        if v.is_finite() && v > worst.0 {
            worst = (v, k as u32 % render.width, k as u32 / render.width);
        }
    }
    let lum = |f: &Film| {
        f.pixels
            .iter()
            .filter(|p| p.is_finite())
            .map(|&p| luminance(p) as f64)
            .sum::<f64>()
    };
    NoiseReport {
        outliers,
        non_finite: render.non_finite_count(),
        pixels: z.len(),
        z_threshold: threshold,
        worst,
        brightness: lum(render) / lum(mean).max(1e-300),
    }
}

/// A map of `|z|` over the reference mean: grey (a quarter of the reference's luminance)
/// within the threshold, yellow to red beyond it, magenta for NaN.
pub fn z_score_map(
    student: &RenderStatistics,
    reference: &RenderStatistics,
    tol: &NoiseTolerance,
) -> Film {
    let z = z_scores(student, reference, tol);
    let threshold = tol.z_threshold(z.len());
    Film {
        pixels: z
            .iter()
            .zip(&reference.mean.pixels)
            .map(|(&z, &m)| {
                if z.is_nan() {
                    Vec3::new(1.0, 0.0, 1.0)
                } else if z <= threshold {
                    Vec3::splat(0.25 * luminance(m.min(Vec3::ONE)))
                } else {
                    let s = ((z / threshold).log10() / 2.0).clamp(0.0, 1.0) as f32;
                    Vec3::new(1.0, 1.0 - s, 0.0)
                }
            })
            .collect(),
        ..reference.mean.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gamma_function_matches_known_values() {
        // Γ(1) = Γ(2) = 1, Γ(5) = 24, Γ(½) = √π.
        assert!(ln_gamma(1.0).abs() < 1e-10);
        assert!(ln_gamma(2.0).abs() < 1e-10);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-10);
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-10);
        // Q(1, x) = e^(−x) on both branches (series below a + 1, continued fraction above).
        for x in [0.1, 1.5, 3.0, 20.0] {
            assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-12, "{x}");
        }
        assert_eq!(gamma_q(3.0, 0.0), 1.0);
    }

    #[test]
    fn chi_square_tails_match_tables() {
        // χ²(15): the 0.999 quantile is 37.697; χ²(1) at 3.841 is p = 0.05; χ²(10) at 18.307
        // is p = 0.05 (tables of the χ² distribution).
        assert!((chi_square_p_value(37.697, 15) - 1e-3).abs() < 2e-6);
        assert!((chi_square_p_value(3.841, 1) - 0.05).abs() < 1e-4);
        assert!((chi_square_p_value(18.307, 10) - 0.05).abs() < 1e-5);
        assert!((chi_square_p_value(10.0, 30) - 0.999_773_7).abs() < 1e-6);
        assert!((chi_square_p_value(16.0, 8) - 0.042_380_1).abs() < 1e-6);
        // χ²(2) is exponential: P(χ² ≥ x) = e^(−x/2).
        assert!((chi_square_p_value(6.0, 2) - (-3f64).exp()).abs() < 1e-12);
    }

    #[test]
    fn normal_tails_and_quantiles_match_tables() {
        // Two-sided normal: 1.96 → 0.05, 2.5758 → 0.01, 3.2905 → 0.001, 3.8906 → 1e-4.
        assert!((normal_two_sided_p(1.959_964) - 0.05).abs() < 1e-6);
        assert!((normal_two_sided_p(2.575_829) - 0.01).abs() < 1e-6);
        assert!((normal_two_sided_p(0.0) - 1.0).abs() < 1e-12);
        for (p, z) in [
            (0.05, 1.959_964),
            (0.01, 2.575_829),
            (1e-3, 3.290_527),
            (1e-4, 3.890_592),
            (1e-9, 6.109_410),
        ] {
            assert!((normal_two_sided_quantile(p) - z).abs() < 1e-5, "{p}");
        }
    }

    #[test]
    fn sidak_level_makes_the_family_rate() {
        assert!((sidak(0.05, 1) - 0.05).abs() < 1e-12);
        assert!((sidak(0.05, 10) - 0.005_116_197).abs() < 1e-9);
        let per_test = sidak(1e-3, 1_000_000);
        assert!((1.0 - (1.0 - per_test).powi(1_000_000) - 1e-3).abs() < 1e-9);
    }

    #[test]
    fn chi_square_statistic_and_wilson_hilferty() {
        assert_eq!(chi_square_uniform(&[5, 5, 5, 5]), 0.0);
        // Expected 5 each: (10 − 5)²/5 + (0 − 5)²/5 = 10.
        assert!((chi_square_uniform(&[10, 0, 5, 5]) - 10.0).abs() < 1e-12);
        // The z-score's tail is close to the χ² tail: χ²(15) = 37.697 has p = 1e-3 one-sided,
        // z = 3.09.
        assert!((wilson_hilferty_z(37.697, 15) - 3.090).abs() < 0.03);
        // The median of χ²(k) is about k(1 − 2/(9k))³, z ≈ 0.
        let k = 30.0f64;
        assert!(wilson_hilferty_z(k * (1.0 - 2.0 / (9.0 * k)).powi(3), 30).abs() < 1e-9);
    }

    #[test]
    fn noisy_render_z_test() {
        let film = |v: f32| Film {
            pixels: vec![Vec3::splat(v); 100],
            ..Film::new(10, 10)
        };
        let reference = RenderStatistics::of(&[film(0.4), film(0.6), film(0.5), film(0.5)]);
        assert_eq!(reference.renders, 4);
        assert!(
            (reference.mean.pixels[0] - Vec3::splat(0.5))
                .abs()
                .max_element()
                < 1e-6
        );
        // Variance of 0.4, 0.6, 0.5, 0.5 with n − 1: 0.02/3.
        assert!((reference.variance.pixels[0].x - 0.02 / 3.0).abs() < 1e-6);
        let tol = NoiseTolerance {
            family_alpha: 1e-3,
            abs: 1e-4,
            rel: 1e-3,
            max_outlier_fraction: 0.0,
        };
        let same = RenderStatistics::of(&[film(0.45), film(0.55)]);
        let report = compare_noisy(&same, &reference, &tol);
        assert!(report.passes(&tol), "{report:?}");
        assert!((report.brightness - 1.0).abs() < 1e-6);
        assert_eq!(report.z_threshold, tol.z_threshold(100));
        let dark = RenderStatistics::of(&[film(0.1), film(0.1)]);
        let report = compare_noisy(&dark, &reference, &tol);
        assert!(!report.passes(&tol) && report.outliers == 100, "{report:?}");
        let mut broken = same.clone();
        broken.mean.pixels[7] = Vec3::NAN;
        let report = compare_noisy(&broken, &reference, &tol);
        assert_eq!((report.non_finite, report.outliers), (1, 1));
        assert!(!report.passes(&tol));
        assert_eq!(
            z_score_map(&broken, &reference, &tol).pixels[7],
            Vec3::new(1.0, 0.0, 1.0)
        );
    }
}
