//! Exercises 12.11–12.13: the sky as a light — its brightness as a distribution over the
//! latitude–longitude image, directions drawn from it, and their density.
//!
//! The checks build their own distribution of each test sky (in double precision) for
//! Exercises 12.12 and 12.13, so that a mistake in 12.11 costs 12.11 only; the probability of
//! every texel follows from it, and the density of a direction, whatever its parameterisation
//! within the texel, must integrate over the texel to that probability.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DVec3, Vec3};

use contracts::lab12::{PathTracing, SkyDistribution};
use contracts::sampling::Rng;
use grading::LabContext;
use grading::chi2::chi_square_pooled;
use grading::stats::{family_z_limit, mean_and_standard_error, sidak};
use pipeline::job::prepare;
use pipeline::render::render;
use raylab_core::render::RenderSettings;
use raylab_core::scene::{EnvironmentMap, ProbeMapping, ProceduralProbe, Texture};

use super::{SIGNIFICANCE, cornell_pipeline};

/// A test sky: a `width × height` latitude–longitude image of luminance, row by row from the
/// top.
#[derive(Clone, Debug, PartialEq)]
pub struct SkyCase {
    /// What it is, for messages.
    pub name: &'static str,
    /// Texels per row.
    pub width: u32,
    /// Rows.
    pub height: u32,
    /// Luminance per texel.
    pub luminance: Vec<f32>,
}

impl SkyCase {
    fn from_fn(name: &'static str, width: u32, height: u32, f: impl Fn(u32, u32) -> f32) -> Self {
        let luminance = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| f(x, y))
            .collect();
        Self {
            name,
            width,
            height,
            luminance,
        }
    }

    /// A procedural probe's luminance at the texel centres.
    fn probe(name: &'static str, probe: ProceduralProbe, width: u32, height: u32) -> Self {
        Self::from_fn(name, width, height, |x, y| {
            let d = latlong_direction(
                (x as f64 + 0.5) / width as f64,
                (y as f64 + 0.5) / height as f64,
            );
            let c = probe.radiance(d.as_vec3());
            0.2126 * c.x + 0.7152 * c.y + 0.0722 * c.z
        })
    }

    /// Its texel count.
    fn texels(&self) -> usize {
        (self.width * self.height) as usize
    }

    /// `luminance · sin θ` of every texel, in double precision.
    fn weights(&self) -> Vec<f64> {
        let (w, h) = (self.width as usize, self.height as usize);
        (0..w * h)
            .map(|i| {
                let sin = (PI * ((i / w) as f64 + 0.5) / h as f64).sin();
                f64::from(self.luminance[i]) * sin
            })
            .collect()
    }

    /// The call that builds its distribution, for messages.
    fn call(&self) -> String {
        format!(
            "sky_distribution(luminance of {}, width = {}, height = {})",
            self.name, self.width, self.height
        )
    }
}

/// The skies of the checks: coarse and fine, wide and tall, with dark texels, a dark row, one
/// texel a million times brighter than the rest, a sky that is black everywhere and one texel.
pub fn sky_cases() -> Vec<SkyCase> {
    let coarse = [1.0, 3.0, 0.0, 2.0, 0.5, 0.0, 4.0, 1.0];
    vec![
        SkyCase::from_fn("a 4 × 2 sky with dark texels", 4, 2, |x, y| {
            coarse[(y * 4 + x) as usize]
        }),
        SkyCase::from_fn("a 5 × 3 sky with a dark row", 5, 3, |x, y| {
            if y == 1 {
                0.0
            } else {
                1.0 + (x * (y + 2)) as f32
            }
        }),
        SkyCase::from_fn("an 8 × 4 sky with one bright texel", 8, 4, |x, y| {
            if (x, y) == (5, 1) {
                1e3
            } else {
                1e-3 * (1 + x + y) as f32
            }
        }),
        SkyCase::from_fn("a 3 × 12 sky brighter towards the top", 3, 12, |x, y| {
            (12 - y) as f32 + 0.3 * x as f32
        }),
        SkyCase::probe("the 64 × 32 procedural sky", ProceduralProbe::Sky, 64, 32),
        SkyCase::from_fn("a black 6 × 3 sky", 6, 3, |_, _| 0.0),
        SkyCase::from_fn("a 1 × 1 sky", 1, 1, |_, _| 2.0),
    ]
}

/// A fine sky for Exercise 12.11 only: a 1024-texel row in single precision.
fn fine_case() -> SkyCase {
    SkyCase::probe(
        "the 1024 × 512 procedural studio",
        ProceduralProbe::Studio,
        1024,
        512,
    )
}

/// Lab 11's latitude–longitude mapping: `θ = πv`, `φ = 2π(u − ½)`.
pub fn latlong_direction(u: f64, v: f64) -> DVec3 {
    let (sin, cos) = (PI * v).sin_cos();
    let phi = 2.0 * PI * (u - 0.5);
    DVec3::new(sin * phi.sin(), cos, -sin * phi.cos())
}

/// Lab 11's mapping back: the `(u, v)` of the unit direction `d`.
pub fn latlong_uv(d: Vec3) -> (f64, f64) {
    let d = d.as_dvec3();
    let u = 0.5 + d.x.atan2(-d.z) / (2.0 * PI);
    let v = (d.x.hypot(d.z)).atan2(d.y) / PI;
    (u, v)
}

/// The cell of a `width × height` grid over `(u, v)` that holds the unit direction `d`, row by
/// row from the top (a texel of an image of that size).
pub fn cell_of(d: Vec3, width: usize, height: usize) -> usize {
    let (u, v) = latlong_uv(d);
    let x = ((u * width as f64) as usize).min(width - 1);
    let y = ((v * height as f64) as usize).min(height - 1);
    y * width + x
}

/// The solid angle of the part of row `y` (of `height`) between `v0` and `v1` (fractions of
/// the row) and a width of `du` in `u`.
fn band_solid_angle(y: usize, height: u32, v0: f64, v1: f64, du: f64) -> f64 {
    let theta = |t: f64| PI * (y as f64 + t) / height as f64;
    2.0 * PI * du * (theta(v0).cos() - theta(v1).cos())
}

/// The cumulative table of `weights` from 0 to 1, uniform where they weigh nothing.
fn cumulative(weights: &[f64]) -> Vec<f64> {
    let total: f64 = weights.iter().sum();
    let n = weights.len() as f64;
    let mut sum = 0.0;
    std::iter::once(0.0)
        .chain(weights.iter().enumerate().map(|(i, w)| {
            sum += w;
            if total > 0.0 {
                sum / total
            } else {
                (i + 1) as f64 / n
            }
        }))
        .collect()
}

/// The distribution of `case` in double precision: the marginal and the conditionals.
fn tables(case: &SkyCase, weights: &[f64]) -> (Vec<f64>, Vec<f64>) {
    let w = case.width as usize;
    let rows: Vec<&[f64]> = weights.chunks_exact(w).collect();
    let totals: Vec<f64> = rows.iter().map(|r| r.iter().sum()).collect();
    let conditional = rows.iter().flat_map(|r| cumulative(r)).collect();
    (cumulative(&totals), conditional)
}

/// The distribution of `case` the checks of Exercises 12.12 and 12.13 hand the student.
pub fn distribution(case: &SkyCase) -> SkyDistribution {
    let (marginal, conditional) = tables(case, &case.weights());
    SkyDistribution {
        width: case.width,
        height: case.height,
        marginal: marginal.iter().map(|&c| c as f32).collect(),
        conditional: conditional.iter().map(|&c| c as f32).collect(),
    }
}

/// The probability of every texel of `sky`, from its tables.
fn texel_probabilities(sky: &SkyDistribution) -> Vec<f64> {
    let (w, h) = (sky.width as usize, sky.height as usize);
    (0..w * h)
        .map(|i| {
            let (x, y) = (i % w, i / w);
            let row = sky.row(y);
            f64::from(sky.marginal[y + 1] - sky.marginal[y]) * f64::from(row[x + 1] - row[x])
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Exercise 12.11

/// What a distribution looks like with one classic mistake, to name it in a message.
fn diagnose(case: &SkyCase, got: &SkyDistribution) -> &'static str {
    let h = case.height as usize;
    let w = case.width as usize;
    let close = |weights: Vec<f64>| {
        let (marginal, conditional) = tables(case, &weights);
        marginal
            .iter()
            .zip(&got.marginal)
            .all(|(a, &b)| (a - f64::from(b)).abs() < 1e-4)
            && conditional
                .iter()
                .zip(&got.conditional)
                .all(|(a, &b)| (a - f64::from(b)).abs() < 1e-4)
    };
    let with_sin = |theta: &dyn Fn(usize) -> f64| {
        (0..w * h)
            .map(|i| f64::from(case.luminance[i]) * theta(i / w).sin())
            .collect::<Vec<_>>()
    };
    if close(case.luminance.iter().map(|&l| f64::from(l)).collect()) {
        "it looks like the luminance without sin θ: a row near a pole covers less of the sphere, so weigh each texel by sin θ of its row"
    } else if close(with_sin(&|y| PI * y as f64 / h as f64)) {
        "it looks like sin θ at the top of each row; take θ at the row's centre, π(y + ½)/h"
    } else {
        "build each table as the running sum of the weights luminance·sin θ_y over their total"
    }
}

/// Exercise 12.11: the tables of every test sky, within 10⁻⁴ of the checks' own.
pub fn exercise_12_11(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    for case in sky_cases().into_iter().chain([fine_case()]) {
        let call = case.call();
        let got = s.sky_distribution(&case.luminance, case.width, case.height);
        let expected = distribution(&case);
        let (w, h) = (case.width as usize, case.height as usize);
        if (got.width, got.height) != (case.width, case.height) {
            return Err(format!(
                "{call} returned a distribution of {} × {} texels: keep the image's width and height",
                got.width, got.height
            ));
        }
        if got.marginal.len() != h + 1 || got.conditional.len() != h * (w + 1) {
            return Err(format!(
                "{call} returned {} marginal and {} conditional values: a cumulative table of n cells has n + 1 values, 0 first — {} for the rows and {} = {h} × {} for the conditionals",
                got.marginal.len(),
                got.conditional.len(),
                h + 1,
                h * (w + 1),
                w + 1
            ));
        }
        if let Some(bad) = got
            .marginal
            .iter()
            .chain(&got.conditional)
            .find(|c| !c.is_finite())
        {
            return Err(format!(
                "{call} returned a table holding {bad}: where a row (or the whole sky) weighs nothing, make its table uniform, i/n, instead of dividing by 0"
            ));
        }
        let mismatch = |what: String, got: &[f32], expected: &[f32]| {
            got.iter()
                .zip(expected)
                .position(|(a, b)| (a - b).abs() > 1e-4)
                .map(|i| format!("{what}[{i}] is {}, expected {}", got[i], expected[i]))
        };
        let first =
            mismatch("the marginal".into(), &got.marginal, &expected.marginal).or_else(|| {
                (0..h).find_map(|y| {
                    mismatch(
                        format!("row {y}'s conditional"),
                        got.row(y),
                        expected.row(y),
                    )
                })
            });
        if let Some(first) = first {
            return Err(format!("{call}: {first}; {}", diagnose(&case, &got)));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 12.12

/// Directions drawn per sky.
pub const SKY_SAMPLES: usize = 20_000;
/// Sub-cells per texel side in the test of the densities of coarse skies.
const SUBCELLS: usize = 3;

/// Exercise 12.12: per sky, the generator advanced; the texels of the directions drawn
/// against the texel probabilities (χ²); the density returned against the directions (the
/// mean of `1/pdf` over a third of a texel is its solid angle, on coarse skies, where a
/// density wrong within the texel shows); and `E[L/pdf] = ∫ L dω`.
pub fn exercise_12_12(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    let cases = sky_cases();
    let coarse = |c: &SkyCase| c.texels() <= 36;
    let subcell_tests: usize = cases
        .iter()
        .filter(|c| coarse(c))
        .map(|c| c.texels() * SUBCELLS * SUBCELLS)
        .sum();
    let tests = cases.len() * 3 + subcell_tests;
    let alpha = sidak(SIGNIFICANCE, tests);
    let z_limit = family_z_limit(SIGNIFICANCE, tests);
    for (k, case) in cases.iter().enumerate() {
        let sky = distribution(case);
        let call = format!("sample_sky(the distribution of {})", case.name);
        let mut rng = Rng::new(700 + k as u64, 12);
        let mut twin = rng.clone();
        let (first, again) = (s.sample_sky(&sky, &mut rng), s.sample_sky(&sky, &mut twin));
        if first != again {
            return Err(format!(
                "{call} returned {first:?} and then {again:?} from generators in the same state: draw every random number from `rng`"
            ));
        }
        if (0..4).all(|_| s.sample_sky(&sky, &mut rng) == first) {
            return Err(format!(
                "{call} returned {first:?} five times in a row: draw a new `rng.next_vec2()` every call"
            ));
        }
        let probabilities = texel_probabilities(&sky);
        let mut counts = vec![0u64; case.texels()];
        let mut nones = 0usize;
        let mut draws = Vec::with_capacity(SKY_SAMPLES);
        let mut rng = Rng::new(7100 + k as u64, 12);
        for _ in 0..SKY_SAMPLES {
            let Some(sample) = s.sample_sky(&sky, &mut rng) else {
                nones += 1;
                continue;
            };
            let (d, pdf) = (sample.direction, sample.pdf);
            if d.is_nan() || (d.length() - 1.0).abs() > 1e-4 {
                return Err(format!(
                    "{call} returned the direction {d} of length {}: return a unit vector",
                    d.length()
                ));
            }
            if !(pdf > 0.0 && pdf.is_finite()) {
                return Err(format!(
                    "{call} returned the direction {d} with the density {pdf}: a direction drawn has a positive, finite density (return `None` where sin θ is 0)"
                ));
            }
            let texel = cell_of(d, case.width as usize, case.height as usize);
            counts[texel] += 1;
            draws.push((texel, d, pdf));
        }
        if nones * 1000 > SKY_SAMPLES {
            return Err(format!(
                "{call} returned `None` {nones} times in {SKY_SAMPLES}: only where sin θ or the density is 0, which no direction drawn from a continuous position within its texel hits"
            ));
        }
        let w = case.width as usize;
        if let Some(t) = (0..case.texels()).find(|&t| counts[t] > 0 && probabilities[t] == 0.0) {
            return Err(format!(
                "{call}: {} of {SKY_SAMPLES} directions fell in texel ({}, {}) (column, row from the top), whose probability is 0: draw the row by the marginal, then the texel by that row's own conditional, and map (u, v) to the direction as lab 11 does: θ = πv, φ = 2π(u − ½)",
                counts[t],
                t % w,
                t / w
            ));
        }
        if case.texels() > 1 {
            let expected: Vec<f64> = probabilities
                .iter()
                .map(|p| p * (SKY_SAMPLES - nones) as f64)
                .collect();
            let outcome =
                chi_square_pooled(&counts, &expected, 5.0).map_err(|e| format!("{call}: {e}"))?;
            if outcome.p_value < alpha {
                let (worst, _) = counts
                    .iter()
                    .zip(&expected)
                    .enumerate()
                    .map(|(i, (&o, &e))| (i, (o as f64 - e).abs() / e.max(1.0).sqrt()))
                    .fold((0, 0.0), |a, b| if b.1 > a.1 { b } else { a });
                return Err(format!(
                    "{call}: the directions drawn do not fall in the texels as often as the texels' probabilities say: χ² = {:.1} with {} degrees of freedom, p = {:.2e} < {alpha:.2e}. Texel ({}, {}) (column, row from the top) got {} of {SKY_SAMPLES}, expected {:.1}. Choose the row by the marginal with ξ.x, the texel by that row's conditional with ξ.y, and map (u, v) to the direction as lab 11 does: θ = πv, φ = 2π(u − ½)",
                    outcome.statistic,
                    outcome.degrees_of_freedom,
                    outcome.p_value,
                    worst % w,
                    worst / w,
                    counts[worst],
                    expected[worst]
                ));
            }
        }
        // E[L/pdf] = ∫ L dω, and E[1/pdf] the solid angle of the texels it can draw.
        let n = SKY_SAMPLES;
        let h = case.height as usize;
        let omega = |i: usize| band_solid_angle(i / w, case.height, 0.0, 1.0, 1.0 / w as f64);
        let integral: f64 = (0..w * h)
            .map(|i| f64::from(case.luminance[i]) * omega(i))
            .sum();
        let support: f64 = (0..w * h)
            .filter(|&i| probabilities[i] > 0.0)
            .map(omega)
            .sum();
        let radiance: Vec<f64> = draws
            .iter()
            .map(|&(t, _, pdf)| f64::from(case.luminance[t]) / f64::from(pdf))
            .collect();
        let inverse: Vec<f64> = draws
            .iter()
            .map(|&(_, _, pdf)| 1.0 / f64::from(pdf))
            .collect();
        for (values, expected, what) in [
            (&radiance, integral, "L/pdf, the sky's ∫ L dω,"),
            (
                &inverse,
                support,
                "1/pdf, the solid angle of the texels it draws from,",
            ),
        ] {
            let (mean, error) = mean_and_standard_error(values, n);
            if (mean - expected).abs() > z_limit * error + 1e-6 * expected.abs() {
                return Err(format!(
                    "{call}: the mean of {what} is {mean:.6} ± {error:.6} over {n} draws, not {expected:.6}: return the density per unit solid angle of the direction drawn, p(u, v)/(2π² sin θ) with p(u, v) = P(row)·P(texel | row)·w·h and θ of the point drawn"
                ));
            }
        }
        if coarse(case) {
            check_subcells(case, &call, &draws, z_limit)?;
        }
    }
    Ok(())
}

/// On a coarse sky, the mean of `1_C/pdf` over each third × third `C` of a texel drawn often
/// enough is its solid angle.
fn check_subcells(
    case: &SkyCase,
    call: &str,
    draws: &[(usize, Vec3, f32)],
    z_limit: f64,
) -> Result<(), String> {
    let (w, h) = (case.width as usize, case.height as usize);
    let cells = SUBCELLS;
    let mut per_cell = vec![Vec::new(); w * h * cells * cells];
    for &(_, d, pdf) in draws {
        per_cell[cell_of(d, w * cells, h * cells)].push(1.0 / f64::from(pdf));
    }
    let probabilities = texel_probabilities(&distribution(case));
    for (i, values) in per_cell.iter().enumerate() {
        let (cu, cv) = (i % (w * cells), i / (w * cells));
        let texel = (cv / cells) * w + cu / cells;
        // A third of a texel expected to hold fewer than 50 draws says little.
        if probabilities[texel] * draws.len() as f64 / (cells * cells) as f64 <= 50.0 {
            continue;
        }
        let part = (cv % cells) as f64 / cells as f64;
        let omega = band_solid_angle(
            cv / cells,
            case.height,
            part,
            part + 1.0 / cells as f64,
            1.0 / (w * cells) as f64,
        );
        let (mean, error) = mean_and_standard_error(values, draws.len());
        if (mean - omega).abs() > z_limit * error.max(1e-12) + 1e-9 {
            let which = ["top", "middle", "bottom"][cv % cells];
            return Err(format!(
                "{call}: over the {which} third of texel ({}, {}) the mean of 1/pdf is {mean:.6} ± {error:.6}, not its solid angle {omega:.6}: the density returned is not the density of the directions drawn within the texel — place the point at a continuous position in its cell (not the texel's centre) and divide by sin θ of that point, not of the row's centre",
                texel % w,
                texel / w
            ));
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 12.13

/// Exercise 12.13: over every texel of every sky the density integrates to the texel's
/// probability (a midpoint rule fine enough in θ for either parameterisation within the
/// texel); 0 at the poles, finite at the seam and next to a pole.
pub fn exercise_12_13(s: &Arc<dyn PathTracing>, _ctx: &LabContext) -> Result<(), String> {
    for case in sky_cases() {
        let sky = distribution(&case);
        let (w, h) = (case.width as usize, case.height as usize);
        let call = |d: Vec3| format!("sky_pdf(the distribution of {}, {d})", case.name);
        for pole in [Vec3::Y, -Vec3::Y] {
            let pdf = s.sky_pdf(&sky, pole);
            if pdf != 0.0 {
                return Err(format!(
                    "{} is {pdf}: at a pole sin θ is 0 and the density per solid angle has no value; return 0 there",
                    call(pole)
                ));
            }
        }
        let near_pole = Vec3::new(1e-7, -1.0, 0.0).normalize();
        let seam = Vec3::Z;
        for d in [near_pole, seam] {
            let pdf = s.sky_pdf(&sky, d);
            if !(pdf.is_finite() && pdf >= 0.0) {
                return Err(format!(
                    "{} is {pdf}: clamp the texel to the last column and row (u or v of exactly 1 there) and return a finite density",
                    call(d)
                ));
            }
        }
        let probabilities = texel_probabilities(&sky);
        // Sub-points per texel: enough in θ that a midpoint rule of sin θ over the texel is
        // within 2·10⁻⁴ of the integral on the coarsest sky.
        let (kv, ku) = ((64 / h).max(2), 2usize);
        for (i, &probability) in probabilities.iter().enumerate() {
            let (x, y) = (i % w, i / w);
            let mut integral = 0.0;
            for a in 0..ku {
                for b in 0..kv {
                    let u = (x as f64 + (a as f64 + 0.5) / ku as f64) / w as f64;
                    let t = b as f64 / kv as f64;
                    let v = (y as f64 + t + 0.5 / kv as f64) / h as f64;
                    let d = latlong_direction(u, v).as_vec3();
                    let pdf = s.sky_pdf(&sky, d);
                    if !(pdf.is_finite() && pdf >= 0.0) {
                        return Err(format!(
                            "{} is {pdf}: return a finite density, 0 or more",
                            call(d)
                        ));
                    }
                    let omega = band_solid_angle(
                        y,
                        case.height,
                        t,
                        t + 1.0 / kv as f64,
                        1.0 / (w * ku) as f64,
                    );
                    integral += f64::from(pdf) * omega;
                }
            }
            if (integral - probability).abs() > 2e-3 * probability + 1e-7 {
                let d = latlong_direction((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
                return Err(format!(
                    "sky_pdf over texel ({x}, {y}) (column, row from the top) of {} integrates to {integral:.6}, but the texel's probability is {probability:.6} (at its centre, {} is {}): the density per solid angle is P(row)·P(texel | row)·w·h/(2π² sin θ), sin θ of the direction given, in the texel (⌊u·w⌋, ⌊v·h⌋) of lab 11's mapping",
                    case.name,
                    call(d.as_vec3()),
                    s.sky_pdf(&sky, d.as_vec3())
                ));
            }
        }
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// Exercise 12.8 under the sky

/// The white furnace: a white Lambertian sphere under a uniform sky of radiance one, seen
/// from outside.
const FURNACE_SCENE: &str = r#"
name = "white-furnace"
[camera]
eye = [0.0, 0.0, 3.0]
look_at = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
focal_distance = 1.2
[materials.white]
diffuse = [1.0, 1.0, 1.0]
[[spheres]]
center = [0.0, 0.0, 0.0]
radius = 1.0
material = "white"
"#;

/// The settings of the white-furnace render.
const FURNACE_SETTINGS: RenderSettings = RenderSettings {
    width: 16,
    height: 16,
    samples_per_pixel: 64,
    pixel_subdivisions: 1,
    seed: 3,
    progress: false,
};

/// The white furnace rendered by the framework with the student's path loop and the lab's
/// other parts, the sky drawn by next-event estimation: every pixel is one within noise (the
/// background exactly), as a surface that reflects all it receives from a sky of radiance one
/// looks like the sky.
pub fn check_sky_furnace(s: &Arc<dyn PathTracing>, ctx: &LabContext) -> Result<(), String> {
    let mut scene = raylab_core::scene::parse_scene_str(
        "white-furnace.toml",
        FURNACE_SCENE,
        std::path::Path::new("."),
    )
    .map_err(|e| e.to_string())?;
    scene.environment = Some(EnvironmentMap {
        texture: Arc::new(Texture::from_fn("uniform-sky", 8, 4, |_, _| Vec3::ONE)),
        mapping: ProbeMapping::Latlong,
        scale: 1.0,
    });
    let pipeline = cornell_pipeline(s, &ctx.base)?;
    // Without a distribution (the lab's Exercise 12.11 broken, and no key), the sky is found by
    // BSDF samples only: still one in the furnace.
    let pipeline = prepare(pipeline, &scene, |_| {});
    let film = render(&scene, &pipeline, &FURNACE_SETTINGS).map_err(|e| e.to_string())?;
    let values: Vec<f64> = film.pixels.iter().map(|p| f64::from(p.x)).collect();
    let what = format!(
        "the white furnace (a white Lambertian sphere under a uniform sky of radiance 1, {} samples per pixel, {} bounces{})",
        FURNACE_SETTINGS.samples_per_pixel,
        pipeline.max_depth,
        if pipeline.sky.is_some() {
            ", the sky sampled"
        } else {
            ""
        }
    );
    if let Some(bad) = values.iter().find(|v| !v.is_finite()) {
        return Err(format!(
            "{what} has a pixel of {bad}: a path's radiance is finite"
        ));
    }
    let (mean, error) = mean_and_standard_error(
        &values.iter().map(|v| v - 1.0).collect::<Vec<_>>(),
        values.len(),
    );
    let z_limit = family_z_limit(SIGNIFICANCE, 1);
    if mean.abs() > z_limit * error + 1e-4 {
        return Err(format!(
            "{what}: the mean over its pixels is {:.4} ± {error:.4}, not 1: light from the sky must be counted once — a ray that leaves the scene after a bounce weighted by power_heuristic(bsdf pdf, light_pdf), a sky sample by power_heuristic(light pdf, bsdf pdf)",
            1.0 + mean
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_checks_own_tables_match_band_solid_angles() {
        // Texel probabilities ∝ luminance × the texel's solid angle, which is ∝ sin θ at the
        // row's centre.
        for case in sky_cases() {
            if case.luminance.iter().all(|&l| l == 0.0) {
                continue;
            }
            let p = texel_probabilities(&distribution(&case));
            let w = case.width as usize;
            let by_area: Vec<f64> = (0..case.texels())
                .map(|i| {
                    f64::from(case.luminance[i])
                        * band_solid_angle(i / w, case.height, 0.0, 1.0, 1.0 / w as f64)
                })
                .collect();
            let total: f64 = by_area.iter().sum();
            for (a, b) in p.iter().zip(&by_area) {
                assert!(
                    (a - b / total).abs() < 1e-6,
                    "{}: {a} vs {}",
                    case.name,
                    b / total
                );
            }
        }
    }
}
