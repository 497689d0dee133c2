//! Exercise 12.3: the BSDF sampler, judged by the distribution of its directions.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DVec3, Vec3};

use contracts::lab12::{BsdfSample, BsdfValue, PathMaterial, PathTracing};
use contracts::math::Onb;
use contracts::sampling::Rng;
use grading::chi2::{SphereGrid, chi_square_two_sample};
use grading::stats::{family_z_limit, mean_and_standard_error, sidak};
use grading::strategies::unit_vector;
use grading::{GoldenFile, LabContext};

use super::bsdf::compare_bsdf;
use super::{SIGNIFICANCE, key, load};

/// Golden file of Exercise 12.3: the key's histogram and reflectance per case.
pub const GOLDEN_SAMPLE_BSDF: &str = "sample_bsdf.json";

/// The student's draws per case of the BSDF sampler.
pub const BSDF_SAMPLES: usize = 20_000;
/// The key's draws per case, recorded in the golden file.
pub const KEY_BSDF_SAMPLES: usize = 400_000;
/// The cells the BSDF's samples are counted in, in the frame of the normal (the cells below
/// the surface stay empty), and one more for the draws that returned `None`.
pub const BSDF_GRID: SphereGrid = SphereGrid {
    cos_theta_cells: 20,
    phi_cells: 24,
};
/// The coarser cells of the test of the densities returned (`E[1/pdf]` over a cell is its solid
/// angle), so that each cell above the horizon band holds a hundred draws or more.
pub const PDF_GRID: SphereGrid = SphereGrid {
    cos_theta_cells: 10,
    phi_cells: 4,
};

/// A case of the BSDF sampler: a material seen from `wo` above the tilted `normal`.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SamplerCase {
    /// The material.
    pub material: PathMaterial,
    /// The shading normal.
    pub normal: Vec3,
    /// Towards the viewer.
    pub wo: Vec3,
}

/// The cases of Exercise 12.3: diffuse, glossy and mixed, wide and narrow lobes, from head-on
/// to grazing, under tilted normals.
pub fn sampler_cases() -> Vec<SamplerCase> {
    let grey = |v: f32| Vec3::splat(v);
    let tint = Vec3::new(0.9, 0.6, 0.3);
    let cases = [
        (grey(0.8), Vec3::ZERO, 0.0, 0.7),
        (tint * 0.5, grey(0.4), 1.0, 0.9),
        (tint * 0.3, grey(0.6), 5.0, 0.3),
        (tint * 0.6, Vec3::new(0.2, 0.3, 0.35), 20.0, 0.6),
        (grey(0.2), tint * 0.8, 100.0, 0.95),
        (tint * 0.2, grey(0.7), 1000.0, 0.8),
        (Vec3::ZERO, grey(0.9), 0.0, 0.5),
        (Vec3::ZERO, tint, 20.0, 0.15),
        (grey(0.45), grey(0.45), 10.0, 0.05),
    ];
    let normals = grading::strategies::samples(unit_vector(), cases.len(), 12);
    let azimuths = grading::strategies::samples(unit_vector(), cases.len(), 13);
    cases
        .iter()
        .zip(normals.iter().zip(&azimuths))
        .map(|(&(diffuse, glossy, exponent, cos), (&normal, &side))| {
            // `wo` at the case's cosine from the normal, in a random azimuth.
            let tangent = (side - normal * side.dot(normal)).normalize_or(Onb::from_w(normal).u);
            let wo = (normal * cos + tangent * (1.0 - cos * cos).sqrt()).normalize();
            SamplerCase {
                material: PathMaterial {
                    diffuse,
                    glossy,
                    exponent,
                },
                normal,
                wo,
            }
        })
        .collect()
}

/// What the key's samples of a [`SamplerCase`] show, recorded in the golden file.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SamplerReference {
    /// Draws per cell of [`BSDF_GRID`] in the frame of the normal, then the draws that
    /// returned `None`.
    pub histogram: Vec<u64>,
    /// The mean of `f cos θ / pdf` per channel: the directional reflectance.
    pub reflectance: [f64; 3],
    /// Its standard error per channel.
    pub reflectance_error: [f64; 3],
}

/// What `samples` draws of `sampler` show: the histogram of [`SamplerReference`] and per
/// draw the direction, value and density (for the checks of each).
pub struct SamplerRun {
    /// The recorded summary.
    pub summary: SamplerReference,
    /// Each draw that returned a direction.
    pub draws: Vec<BsdfSample>,
}

/// Draws `samples` directions of `case` from `code` (from a generator seeded by the case),
/// checking each is a unit vector above the surface with finite value and positive density.
pub fn run_sampler(
    code: &dyn PathTracing,
    case: &SamplerCase,
    seed: u64,
    samples: usize,
) -> Result<SamplerRun, String> {
    let onb = Onb::from_w(case.normal);
    let mut rng = Rng::new(seed, 12);
    let mut histogram = vec![0u64; BSDF_GRID.len() + 1];
    let mut draws = Vec::with_capacity(samples);
    let (mut sum, mut sum_sq) = (DVec3::ZERO, DVec3::ZERO);
    let call = format!(
        "sample_bsdf(material = {:?}, normal = {}, wo = {})",
        case.material, case.normal, case.wo
    );
    for _ in 0..samples {
        let Some(s) = code.sample_bsdf(&case.material, case.normal, case.wo, &mut rng) else {
            histogram[BSDF_GRID.len()] += 1;
            continue;
        };
        let length = s.direction.length();
        let unit = (length - 1.0).abs() <= 1e-4;
        if !unit {
            return Err(format!(
                "{call} returned the direction {} of length {length}: return a unit vector",
                s.direction
            ));
        }
        let cos = s.direction.dot(case.normal);
        if cos <= 0.0 {
            return Err(format!(
                "{call} returned the direction {} below the surface (cos θ = {cos}): return `None` there",
                s.direction
            ));
        }
        if !(s.pdf > 0.0
            && s.pdf.is_finite()
            && s.value.is_finite()
            && s.value.min_element() >= 0.0)
        {
            return Err(format!(
                "{call} returned the direction {} with value {} and pdf {}: a direction drawn has a positive, finite density and a finite, non-negative value",
                s.direction, s.value, s.pdf
            ));
        }
        let cell = BSDF_GRID
            .cell(onb.to_local(s.direction))
            .expect("a unit vector has a cell");
        histogram[cell] += 1;
        let weight = s.value.as_dvec3() * f64::from(cos) / f64::from(s.pdf);
        sum += weight;
        sum_sq += weight * weight;
        draws.push(s);
    }
    let n = samples as f64;
    let mean = sum / n;
    let variance = (sum_sq / n - mean * mean).max(DVec3::ZERO) / (n - 1.0);
    Ok(SamplerRun {
        summary: SamplerReference {
            histogram,
            reflectance: mean.to_array(),
            reflectance_error: variance.to_array().map(f64::sqrt),
        },
        draws,
    })
}

/// Exercise 12.3: the generator advances and is the only randomness; directions above the
/// surface with positive densities; per case, the histogram of the draws against the key's
/// (two-sample χ²), the returned densities against the histogram (`E[1/pdf]` over a cell is its
/// solid angle, wherever the diffuse lobe reaches) and the reflectance `E[f cos θ / pdf]`
/// against the key's; with the key, the value and density at every direction drawn.
pub(super) fn exercise_12_3(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let cases = sampler_cases();
    let golden: GoldenFile<SamplerCase, SamplerReference> = load(ctx, GOLDEN_SAMPLE_BSDF)?;
    if golden.cases.len() != cases.len() {
        return Err(format!(
            "{} holds {} cases, the check has {}: regenerate the golden data",
            GOLDEN_SAMPLE_BSDF,
            golden.cases.len(),
            cases.len()
        ));
    }
    let key = key(ctx);
    // The tests: a χ² and three reflectances per case, and the cells' densities of the cases
    // with a diffuse lobe.
    let upper_cells = PDF_GRID.len() / 2 - PDF_GRID.phi_cells as usize;
    let tests = cases.len() * 4 + cases.len() * upper_cells;
    let alpha = sidak(SIGNIFICANCE, tests);
    let z_limit = family_z_limit(SIGNIFICANCE, tests);
    for (k, (case, recorded)) in cases
        .iter()
        .zip(golden.cases.iter().map(|c| &c.expected))
        .enumerate()
    {
        let call = format!(
            "sample_bsdf(material = {:?}, normal = {}, wo = {})",
            case.material, case.normal, case.wo
        );
        // The generator: advanced, and the only source of randomness.
        let mut rng = Rng::new(100 + k as u64, 1);
        let mut twin = rng.clone();
        let first = s.sample_bsdf(&case.material, case.normal, case.wo, &mut rng);
        let again = s.sample_bsdf(&case.material, case.normal, case.wo, &mut twin);
        if first != again {
            return Err(format!(
                "{call} returned {first:?} and then {again:?} from generators in the same state: draw every random number from `rng`"
            ));
        }
        let next: Vec<_> = (0..4)
            .map(|_| s.sample_bsdf(&case.material, case.normal, case.wo, &mut rng))
            .collect();
        if next.iter().all(|n| *n == first) {
            return Err(format!(
                "{call} returned {first:?} five times in a row: advance `rng` (draw new numbers from it every call)"
            ));
        }
        // Seen from below, nothing.
        let below = s.sample_bsdf(&case.material, case.normal, -case.wo, &mut rng);
        if below.is_some() {
            return Err(format!(
                "sample_bsdf(material = {:?}, normal = {}, wo = {}) returned {below:?} with wo below the surface: return `None`",
                case.material, case.normal, -case.wo
            ));
        }

        let run = run_sampler(s.as_ref(), case, 1200 + k as u64, BSDF_SAMPLES)?;
        let got = &run.summary;
        let outcome = chi_square_two_sample(&got.histogram, &recorded.histogram, 10)
            .map_err(|e| format!("{call}: {e}"))?;
        if outcome.p_value < alpha {
            let none = |h: &[u64]| h[BSDF_GRID.len()] as f64 / h.iter().sum::<u64>() as f64;
            return Err(format!(
                "{call}: {BSDF_SAMPLES} directions are not distributed as the answer key's {KEY_BSDF_SAMPLES}: two-sample χ² = {:.1} with {} degrees of freedom, p = {:.2e} < {alpha:.2e}. Directions returned `None`: {:.1} % (the key's {:.1} %). Choose the lobe with P_s from the first number and draw the direction from the next two",
                outcome.statistic,
                outcome.degrees_of_freedom,
                outcome.p_value,
                100.0 * none(&got.histogram),
                100.0 * none(&recorded.histogram),
            ));
        }
        for c in 0..3 {
            let (a, b) = (got.reflectance[c], recorded.reflectance[c]);
            let error = got.reflectance_error[c].hypot(recorded.reflectance_error[c]);
            if (a - b).abs() > z_limit * error + 1e-4 * (1.0 + b.abs()) {
                let channel = ["red", "green", "blue"][c];
                return Err(format!(
                    "{call}: the mean of value·cos θ/pdf over {BSDF_SAMPLES} draws, the {channel} reflectance, is {a:.5} ± {:.5}; the key's is {b:.5} ± {:.5}. Return f of the whole BSDF (Exercise 12.2's value) and the mixture's density at the direction drawn",
                    got.reflectance_error[c], recorded.reflectance_error[c]
                ));
            }
        }
        // Where the diffuse lobe reaches every cell above the surface, the densities returned
        // must be the density of the directions: E[1_C/pdf] = |C| for every cell C (the band
        // at the horizon left out, where 1/pdf has no variance).
        if case.material.diffuse.max_element() > 0.0 {
            let onb = Onb::from_w(case.normal);
            let mut per_cell = vec![Vec::new(); PDF_GRID.len()];
            for d in &run.draws {
                let cell = PDF_GRID
                    .cell(onb.to_local(d.direction))
                    .expect("a unit vector");
                per_cell[cell].push(1.0 / f64::from(d.pdf));
            }
            let omega = 4.0 * PI / PDF_GRID.len() as f64;
            let first_upper = PDF_GRID.len() / 2 + PDF_GRID.phi_cells as usize;
            for (cell, values) in per_cell.iter().enumerate().skip(first_upper) {
                let (mean, error) = mean_and_standard_error(values, BSDF_SAMPLES);
                let z = (mean - omega) / error.max(1e-12);
                if z.abs() > z_limit {
                    let band = (cell / PDF_GRID.phi_cells as usize) as f64;
                    let cos0 = -1.0 + band * 2.0 / PDF_GRID.cos_theta_cells as f64;
                    return Err(format!(
                        "{call}: over the directions with cos θ in [{cos0:.1}, {:.1}) the mean of 1/pdf is {mean:.5} ± {error:.5}, not the cell's solid angle {omega:.5} (z = {z:.1}): the pdf returned is not the density of the directions drawn — return the mixture's (1 − P_s)·cos θ/π + P_s·(n + 1)/(2π)·cos^n α, whichever lobe drew the direction",
                        cos0 + 2.0 / PDF_GRID.cos_theta_cells as f64
                    ));
                }
            }
        }
        if let Some(key) = &key {
            for d in run.draws.iter().take(2_000) {
                let expected = key.bsdf(&case.material, case.normal, case.wo, d.direction);
                compare_bsdf(
                    &format!("{call} at the direction it drew, {}", d.direction),
                    BsdfValue {
                        value: d.value,
                        pdf: d.pdf,
                    },
                    expected,
                )?;
            }
        }
    }
    Ok(())
}
