//! Lab 12's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant changes one
//! function of the answer key. The tests at the end run it through the lab's checks with and
//! without the key, and check the reference passes and the stubs fail cleanly. This file is the
//! instructors' (a handout leaves it out).

use std::f32::consts::{FRAC_1_PI, TAU};

use contracts::lab12::{
    BsdfSample, BsdfValue, EmitterSample, PathHit, PathMaterial, PathTracing, PathVertex,
    PixelStatistics, SkyDistribution, SkySample,
};
use grading::corpus::{Variant, Verdict};
use raylab_core::glam::Vec3;
use raylab_core::math::{Onb, RAY_EPSILON, Ray};
use raylab_core::sampling::Rng;
use reference::lab12::Lab12 as Reference;

/// What a variant changes: the answer key with that one change, as the lab's contract.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Change {
    MeanOfChannels,
    Bt601,
    RedBlueSwapped,
    DotWithWeights,
    DiffuseWithoutPi,
    LobeNormalisedLikePdf,
    LobeNotClamped,
    ValueWithCosine,
    PdfNormalisedLikeValue,
    PdfByLuminance,
    MirrorSignWrong,
    NotZeroBelow,
    ZeroToTheZero,
    MirrorByReflect,
    InDoublePrecision,
    PdfOfChosenLobe,
    ValueOfChosenLobe,
    UniformForCosine,
    ExponentWithoutOne,
    LobeAboutNormal,
    OneNumberForBoth,
    BelowKept,
    FreshGenerator,
    CosineBySqrt,
    AzimuthFirst,
    GlossyFromTop,
    AreaDensity,
    DistanceNotSquared,
    NoEmitterCosine,
    CrossAsArea,
    NoSquareRoot,
    TwoSided,
    FoldedSquare,
    PdfAreaDensity,
    PdfDistanceNotSquared,
    PdfTwoSided,
    PdfCrossAsArea,
    PdfInDouble,
    Balance,
    NaiveWithoutGuard,
    OtherStrategysWeight,
    NaiveWithGuard,
    NoDivision,
    MeanChannel,
    ByLuminance,
    SurviveAbove,
    DividedByComplement,
    NeverAdvances,
    DrawOnlyWhenNeeded,
    EmissionAlwaysInFull,
    NeeWithoutWeight,
    WeightArgumentsSwapped,
    NeeWithoutCosine,
    ThroughputWithoutPdf,
    RouletteFactorIgnored,
    ShadowRayToTheLight,
    CameraVertexDark,
    OneBounceShort,
    BounceWithoutOffset,
    SkyIgnored,
    RouletteFromTheStart,
    NoRoulette,
    DeltaWeighted,
    SumOfSquares,
    OldMeanTwice,
    MeanOverOldCount,
    WelfordInDouble,
    PopulationVariance,
    WithoutRootN,
    ByLuminanceOfMean,
    ZeroBelowTwo,
    NaNWhenBlack,
    VarianceFromSquares,
    SkyWithoutSine,
    SineAtRowTop,
    SineWithoutPi,
    RowsByWholeSky,
    DarkRowNaN,
    DarkRowZeros,
    NoLeadingZero,
    BandSolidAngle,
    SingleSumLastOne,
    SamplePdfWithoutSine,
    SamplePdfSineOfRow,
    SamplePdfOverFourPi,
    TexelCentres,
    OneNumberForRowAndTexel,
    ConditionalOfTopRow,
    NextRow,
    AzimuthMirrored,
    UAndVSwapped,
    SkyFreshGenerator,
    TexelFromFirstNumber,
    UniformInCosineWithinTexel,
    PdfInfiniteAtPole,
    TexelNotClamped,
    SkyPdfWithoutSine,
    SkyPdfAzimuthMirrored,
    SkyPdfThetaByAcos,
    SkyPdfOfNeighbourRow,
}

use Change::*;

/// Every variant of lab 12: the reference with one function changed.
fn variants() -> Vec<Variant<Change>> {
    let v = Variant::new;
    let r = Verdict::Reject;
    let ok = Verdict::Accept;
    vec![
        v("the mean of the channels", r("12.1"), MeanOfChannels),
        v("BT.601 weights", r("12.1"), Bt601),
        v("red and blue weights swapped", r("12.1"), RedBlueSwapped),
        v("a dot product with the weights", ok, DotWithWeights),
        v("ρ_d without 1/π", r("12.2"), DiffuseWithoutPi),
        v(
            "the lobe's value normalised by (n + 1)/(2π)",
            r("12.2"),
            LobeNormalisedLikePdf,
        ),
        v("cos α not clamped at 0", r("12.2"), LobeNotClamped),
        v("the value times cos θ_i", r("12.2"), ValueWithCosine),
        v(
            "the lobe's density normalised by (n + 2)/(2π)",
            r("12.2"),
            PdfNormalisedLikeValue,
        ),
        v(
            "P_s by luminance, not channel sums",
            r("12.2"),
            PdfByLuminance,
        ),
        v(
            "the mirror direction wo − 2(n·wo)n",
            r("12.2"),
            MirrorSignWrong,
        ),
        v("not zero below the surface", r("12.2"), NotZeroBelow),
        v(
            "max(0, cos α)^n: 0⁰ = 1 behind the lobe at n = 0",
            r("12.2"),
            ZeroToTheZero,
        ),
        v(
            "the mirror direction by glam's reflect",
            ok,
            MirrorByReflect,
        ),
        v("in double precision", ok, InDoublePrecision),
        v(
            "the density of the lobe drawn, not the mixture's",
            r("12.3"),
            PdfOfChosenLobe,
        ),
        v(
            "the value of the lobe drawn, not the whole BSDF",
            r("12.3"),
            ValueOfChosenLobe,
        ),
        v(
            "cos θ = ξ₁: uniform directions called cosine-weighted",
            r("12.3"),
            UniformForCosine,
        ),
        v("cos α = ξ₁^(1/n)", r("12.3"), ExponentWithoutOne),
        v(
            "the glossy lobe about the normal",
            r("12.3"),
            LobeAboutNormal,
        ),
        v(
            "one number chooses the lobe and draws cos",
            r("12.3"),
            OneNumberForBoth,
        ),
        v("directions below the surface kept", r("12.3"), BelowKept),
        v("a new generator every call", r("12.3"), FreshGenerator),
        v("cos θ = √ξ₁ (ξ₁ for 1 − ξ₁)", ok, CosineBySqrt),
        v("the azimuth from ξ₁, the cosine from ξ₂", ok, AzimuthFirst),
        v("the glossy lobe when ξ ≥ 1 − P_s", ok, GlossyFromTop),
        v("the density per unit area 1/A", r("12.4"), AreaDensity),
        v(
            "d/(A cos θ_l): the distance not squared",
            r("12.4"),
            DistanceNotSquared,
        ),
        v(
            "d²/A without the cosine at the emitter",
            r("12.4"),
            NoEmitterCosine,
        ),
        v("|e₁ × e₂| as the area", r("12.4"), CrossAsArea),
        v(
            "β = ξ₁(1 − ξ₂), no square root: points crowd a vertex",
            r("12.4"),
            NoSquareRoot,
        ),
        v("two-sided: seen from behind too", r("12.4"), TwoSided),
        v("the unit square folded onto the triangle", ok, FoldedSquare),
        v("the density per unit area 1/A", r("12.5"), PdfAreaDensity),
        v("the distance not squared", r("12.5"), PdfDistanceNotSquared),
        v("two-sided: |cos θ_l|", r("12.5"), PdfTwoSided),
        v("|e₁ × e₂| as the area", r("12.5"), PdfCrossAsArea),
        v("in double precision", ok, PdfInDouble),
        v(
            "the balance heuristic pdf/(pdf + other)",
            r("12.6"),
            Balance,
        ),
        v(
            "pdf²/(pdf² + other²): NaN at 0/0",
            r("12.6"),
            NaiveWithoutGuard,
        ),
        v(
            "the other strategy's weight",
            r("12.6"),
            OtherStrategysWeight,
        ),
        v("pdf²/(pdf² + other²) with a zero guard", ok, NaiveWithGuard),
        v("no division by q", r("12.7"), NoDivision),
        v("q by the mean of the channels", r("12.7"), MeanChannel),
        v("q by luminance", r("12.7"), ByLuminance),
        v("going on when ξ ≥ q", r("12.7"), SurviveAbove),
        v("divided by 1 − q", r("12.7"), DividedByComplement),
        v("the same number every call", r("12.7"), NeverAdvances),
        v("no number drawn when q = 1", ok, DrawOnlyWhenNeeded),
        v(
            "emission found by a bounce counted in full: light counted twice",
            r("12.8"),
            EmissionAlwaysInFull,
        ),
        v(
            "next-event estimation without its weight",
            r("12.8"),
            NeeWithoutWeight,
        ),
        v(
            "the emission's weight power_heuristic(light_pdf, bsdf pdf)",
            r("12.8"),
            WeightArgumentsSwapped,
        ),
        v(
            "next-event estimation without cos θ",
            r("12.8"),
            NeeWithoutCosine,
        ),
        v(
            "the throughput not divided by the pdf",
            r("12.8"),
            ThroughputWithoutPdf,
        ),
        v(
            "roulette's factor ignored",
            r("12.8"),
            RouletteFactorIgnored,
        ),
        v(
            "the shadow ray up to the light's distance",
            r("12.8"),
            ShadowRayToTheLight,
        ),
        v(
            "no emission at the first vertex: lights look black",
            r("12.8"),
            CameraVertexDark,
        ),
        v("one bounce short of max_depth", r("12.8"), OneBounceShort),
        v(
            "bounce rays without the offset",
            r("12.8"),
            BounceWithoutOffset,
        ),
        v("the sky left out", r("12.8"), SkyIgnored),
        v(
            "a delta light's sample weighted by the power heuristic",
            r("12.8"),
            DeltaWeighted,
        ),
        v(
            "a sum and a sum of squares: m2 = Σx² − n·mean²",
            r("12.9"),
            SumOfSquares,
        ),
        v("m2 += (x − mean_old)²", r("12.9"), OldMeanTwice),
        v(
            "mean += (x − mean)/n with the old n",
            r("12.9"),
            MeanOverOldCount,
        ),
        v("Welford's update in double precision", ok, WelfordInDouble),
        v("s² = m2/n", r("12.10"), PopulationVariance),
        v("√(s²)/mean without √n", r("12.10"), WithoutRootN),
        v(
            "the luminance's error from the channels' errors",
            r("12.10"),
            ByLuminanceOfMean,
        ),
        v("0 with fewer than two estimates", r("12.10"), ZeroBelowTwo),
        v("0/0 = NaN for a black pixel", r("12.10"), NaNWhenBlack),
        v(
            "the relative error in double precision",
            ok,
            VarianceFromSquares,
        ),
        v("roulette from the first bounce", ok, RouletteFromTheStart),
        v("no roulette at all", ok, NoRoulette),
        v("luminance without sin θ", r("12.11"), SkyWithoutSine),
        v("sin θ at the top of the row", r("12.11"), SineAtRowTop),
        v("sin((y + ½)/h) without π", r("12.11"), SineWithoutPi),
        v(
            "rows divided by the whole sky's total",
            r("12.11"),
            RowsByWholeSky,
        ),
        v("0/0 for a dark row", r("12.11"), DarkRowNaN),
        v("a dark row's table all 0", r("12.11"), DarkRowZeros),
        v("tables without the leading 0", r("12.11"), NoLeadingZero),
        v(
            "rows weighed by their exact solid angle",
            ok,
            BandSolidAngle,
        ),
        v(
            "sums in single precision, last value set to 1",
            ok,
            SingleSumLastOne,
        ),
        v(
            "the density without sin θ",
            r("12.12"),
            SamplePdfWithoutSine,
        ),
        v("sin θ of the row's centre", r("12.12"), SamplePdfSineOfRow),
        v(
            "p(u, v)/(4π) as the density",
            r("12.12"),
            SamplePdfOverFourPi,
        ),
        v("directions at texel centres only", r("12.12"), TexelCentres),
        v(
            "one number for the row and the texel",
            r("12.12"),
            OneNumberForRowAndTexel,
        ),
        v(
            "the top row's conditional for every row",
            r("12.12"),
            ConditionalOfTopRow,
        ),
        v("the row after the one found", r("12.12"), NextRow),
        v(
            "φ = 2π(½ − u): the sky mirrored",
            r("12.12"),
            AzimuthMirrored,
        ),
        v("θ from u and φ from v", r("12.12"), UAndVSwapped),
        v("a new generator every call", r("12.12"), SkyFreshGenerator),
        v(
            "the texel from ξ.x, the row from ξ.y",
            ok,
            TexelFromFirstNumber,
        ),
        v(
            "uniform in cos θ within the texel",
            ok,
            UniformInCosineWithinTexel,
        ),
        v("1/0 at the poles", r("12.13"), PdfInfiniteAtPole),
        v("⌊u·w⌋ not clamped", r("12.13"), TexelNotClamped),
        v("the density without sin θ", r("12.13"), SkyPdfWithoutSine),
        v(
            "u = ½ − φ/(2π): the sky mirrored",
            r("12.13"),
            SkyPdfAzimuthMirrored,
        ),
        v("θ by acos(y)", ok, SkyPdfThetaByAcos),
        v(
            "the row below the direction's",
            r("12.13"),
            SkyPdfOfNeighbourRow,
        ),
    ]
}

/// The key's cumulative table, or a variant's.
fn cumulative(change: Change, weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let n = weights.len();
    let mut cdf = if change == NoLeadingZero {
        Vec::new()
    } else {
        vec![0.0]
    };
    let mut sum = 0.0;
    for (i, w) in weights.iter().enumerate() {
        sum += w;
        cdf.push(match change {
            DarkRowNaN => (sum / total) as f32,
            DarkRowZeros if total == 0.0 => 0.0,
            _ if total > 0.0 => (sum / total) as f32,
            _ => (i + 1) as f32 / n as f32,
        });
    }
    cdf
}

/// The key's sky distribution with one change.
fn sky_distribution_with(
    change: Change,
    luminance: &[f32],
    width: u32,
    height: u32,
) -> SkyDistribution {
    let (w, h) = (width as usize, height as usize);
    if change == SingleSumLastOne {
        // Running sums in f32, each table's last value set to exactly 1.
        let table = |weights: &[f32]| {
            let total: f32 = weights.iter().sum();
            let mut sum = 0.0f32;
            let mut cdf = vec![0.0f32];
            for (i, &w) in weights.iter().enumerate() {
                sum += w;
                cdf.push(if total > 0.0 {
                    sum / total
                } else {
                    (i + 1) as f32 / weights.len() as f32
                });
            }
            *cdf.last_mut().unwrap() = 1.0;
            cdf
        };
        let mut totals = Vec::new();
        let mut conditional = Vec::new();
        for (y, row) in luminance.chunks_exact(w).enumerate() {
            let sin = (std::f32::consts::PI * (y as f32 + 0.5) / h as f32).sin();
            let weights: Vec<f32> = row.iter().map(|l| l * sin).collect();
            totals.push(weights.iter().sum::<f32>());
            conditional.extend(table(&weights));
        }
        return SkyDistribution {
            width,
            height,
            marginal: table(&totals),
            conditional,
        };
    }
    let pi = std::f64::consts::PI;
    let mut totals = Vec::new();
    let mut conditional = Vec::new();
    let whole: f64 = luminance.iter().map(|&l| f64::from(l)).sum();
    for (y, row) in luminance.chunks_exact(w).enumerate() {
        let yc = y as f64 + 0.5;
        let weight = match change {
            SkyWithoutSine => 1.0,
            SineAtRowTop => (pi * y as f64 / h as f64).sin(),
            SineWithoutPi => (yc / h as f64).sin(),
            BandSolidAngle => {
                (pi * y as f64 / h as f64).cos() - (pi * (y + 1) as f64 / h as f64).cos()
            }
            _ => (pi * yc / h as f64).sin(),
        };
        let weights: Vec<f64> = row.iter().map(|&l| f64::from(l) * weight).collect();
        totals.push(weights.iter().sum());
        if change == RowsByWholeSky && whole > 0.0 {
            let mut sum = 0.0;
            conditional.push(0.0);
            conditional.extend(weights.iter().map(|w| {
                sum += w;
                (sum / whole) as f32
            }));
        } else {
            conditional.extend(cumulative(change, &weights));
        }
    }
    let mut marginal = cumulative(change, &totals);
    if let Some(last) = marginal.last_mut()
        && change != DarkRowNaN
        && change != NoLeadingZero
    {
        *last = 1.0;
    }
    SkyDistribution {
        width,
        height,
        marginal,
        conditional,
    }
}

/// The cell of `cdf` that `xi` falls in and where in it.
fn invert(change: Change, cdf: &[f32], xi: f32) -> (usize, f32) {
    let cells = cdf.len() - 1;
    let found = cdf.partition_point(|&c| c <= xi);
    let i = if change == NextRow {
        found
    } else {
        found.saturating_sub(1)
    }
    .min(cells - 1);
    let width = cdf[i + 1] - cdf[i];
    let t = if width > 0.0 {
        (xi - cdf[i]) / width
    } else {
        0.5
    };
    (i, t.clamp(0.0, 1.0))
}

/// The key's sky sampler with one change.
fn sample_sky_with(change: Change, sky: &SkyDistribution, rng: &mut Rng) -> Option<SkySample> {
    use std::f32::consts::PI;
    let xi = match change {
        SkyFreshGenerator => Rng::new(5, 5).next_vec2(),
        OneNumberForRowAndTexel => {
            let x = rng.next_vec2().x;
            raylab_core::glam::Vec2::splat(x)
        }
        TexelFromFirstNumber => {
            let v = rng.next_vec2();
            raylab_core::glam::Vec2::new(v.y, v.x)
        }
        _ => rng.next_vec2(),
    };
    let (y, ty) = invert(change, &sky.marginal, xi.x);
    let row = if change == ConditionalOfTopRow {
        sky.row(0)
    } else {
        sky.row(y)
    };
    let (x, tx) = invert(change, row, xi.y);
    let (tx, ty) = if change == TexelCentres {
        (0.5, 0.5)
    } else {
        (tx, ty)
    };
    let probability = (sky.marginal[y + 1] - sky.marginal[y]) * (row[x + 1] - row[x]);
    let (w, h) = (sky.width as f32, sky.height as f32);
    let (u, v) = ((x as f32 + tx) / w, (y as f32 + ty) / h);
    let (u, v) = if change == UAndVSwapped {
        (v, u)
    } else {
        (u, v)
    };
    let theta = if change == UniformInCosineWithinTexel {
        // cos θ uniform between the row's bounds.
        let (c0, c1) = ((PI * y as f32 / h).cos(), (PI * (y + 1) as f32 / h).cos());
        (c0 + (c1 - c0) * ty).clamp(-1.0, 1.0).acos()
    } else {
        PI * v
    };
    let (sin, cos) = theta.sin_cos();
    if sin <= 0.0 || probability <= 0.0 {
        return None;
    }
    let phi = if change == AzimuthMirrored {
        TAU * (0.5 - u)
    } else {
        TAU * (u - 0.5)
    };
    let density = probability * w * h;
    let pdf = match change {
        SamplePdfWithoutSine => density / (2.0 * PI * PI),
        SamplePdfSineOfRow => density / (2.0 * PI * PI * (PI * (y as f32 + 0.5) / h).sin()),
        SamplePdfOverFourPi => density / (4.0 * PI),
        UniformInCosineWithinTexel => {
            let omega = TAU / w * ((PI * y as f32 / h).cos() - (PI * (y + 1) as f32 / h).cos());
            probability / omega
        }
        _ => density / (2.0 * PI * PI * sin),
    };
    Some(SkySample {
        direction: Vec3::new(sin * phi.sin(), cos, -sin * phi.cos()),
        pdf,
    })
}

/// The key's sky density with one change.
fn sky_pdf_with(change: Change, sky: &SkyDistribution, d: Vec3) -> f32 {
    use std::f32::consts::PI;
    let sin = (d.x * d.x + d.z * d.z).sqrt();
    if sin <= 0.0 && change != PdfInfiniteAtPole {
        return 0.0;
    }
    let phi = d.x.atan2(-d.z);
    let u = if change == SkyPdfAzimuthMirrored {
        0.5 - phi / TAU
    } else {
        0.5 + phi / TAU
    };
    let theta = if change == SkyPdfThetaByAcos {
        d.y.clamp(-1.0, 1.0).acos()
    } else {
        sin.atan2(d.y)
    };
    let (w, h) = (sky.width as usize, sky.height as usize);
    let x = (u * w as f32) as usize;
    let x = if change == TexelNotClamped {
        x
    } else {
        x.min(w - 1)
    };
    let y = ((theta / PI * h as f32) as usize).min(h - 1);
    let y = if change == SkyPdfOfNeighbourRow {
        (y + 1).min(h - 1)
    } else {
        y
    };
    let row = sky.row(y);
    let density = (sky.marginal[y + 1] - sky.marginal[y]) * (row[x + 1] - row[x]) * (w * h) as f32;
    match change {
        SkyPdfWithoutSine => density / (2.0 * PI * PI),
        UniformInCosineWithinTexel => {
            let hf = h as f32;
            let omega =
                TAU / w as f32 * ((PI * y as f32 / hf).cos() - (PI * (y + 1) as f32 / hf).cos());
            density / (w * h) as f32 / omega
        }
        _ => density / (2.0 * PI * PI * sin),
    }
}

/// The key's glossy-lobe probability.
fn glossy_probability(m: &PathMaterial) -> f32 {
    let (d, s) = (m.diffuse.element_sum(), m.glossy.element_sum());
    if s > 0.0 { s / (d + s) } else { 0.0 }
}

fn mirror(normal: Vec3, wo: Vec3) -> Vec3 {
    2.0 * normal.dot(wo) * normal - wo
}

fn about(axis: Vec3, cos: f32, phi: f32) -> Vec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    Onb::from_w(axis)
        .to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
        .normalize()
}

/// The parts of the key's BSDF a variant replaces: the mirror direction, the lobe `lobe(r·wi,
/// n)`, the value's and the density's factors of the lobe, and the glossy probability.
#[derive(Clone, Copy)]
struct Parts {
    mirror_of: fn(Vec3, Vec3) -> Vec3,
    lobe: fn(f32, f32) -> f32,
    value_k: fn(f32) -> f32,
    pdf_k: fn(f32) -> f32,
    p: f32,
}

/// The key's BSDF made of `parts`.
fn bsdf_with(m: &PathMaterial, normal: Vec3, wo: Vec3, wi: Vec3, parts: Parts) -> BsdfValue {
    let n = m.exponent;
    let l = (parts.lobe)((parts.mirror_of)(normal, wo).dot(wi), n);
    let cos_i = normal.dot(wi);
    BsdfValue {
        value: m.diffuse * FRAC_1_PI + m.glossy * ((parts.value_k)(n) * l),
        pdf: (1.0 - parts.p) * cos_i.max(0.0) * FRAC_1_PI + parts.p * (parts.pdf_k)(n) * l,
    }
}

fn clamped_lobe(cos: f32, n: f32) -> f32 {
    if cos > 0.0 { cos.min(1.0).powf(n) } else { 0.0 }
}

fn value_factor(n: f32) -> f32 {
    (n + 2.0) / TAU
}

fn pdf_factor(n: f32) -> f32 {
    (n + 1.0) / TAU
}

/// The key's sampler with the direction drawn by `draw(choice, u, glossy?)`.
fn sample_with(
    m: &PathMaterial,
    normal: Vec3,
    wo: Vec3,
    rng: &mut Rng,
    draw: impl Fn(f32, Vec3, f32, &PathMaterial) -> Vec3,
) -> Option<BsdfSample> {
    let choice = rng.next_f32();
    let u = rng.next_vec2();
    let wi = draw(choice, Vec3::new(u.x, u.y, 0.0), glossy_probability(m), m);
    if normal.dot(wi) <= 0.0 || normal.dot(wo) <= 0.0 {
        return None;
    }
    let b = Reference.bsdf(m, normal, wo, wi);
    Some(BsdfSample {
        direction: wi,
        value: b.value,
        pdf: b.pdf,
    })
}

fn emitter_pdf_with(
    triangle: [Vec3; 3],
    direction: Vec3,
    distance: f32,
    area: fn(f32) -> f32,
    density: fn(f32, f32, f32) -> f32,
) -> f32 {
    let [a, b, c] = triangle;
    let cross = (b - a).cross(c - a);
    let double_area = cross.length();
    let cos = -cross.dot(direction) / double_area;
    if double_area > 0.0 && cos > 0.0 {
        density(distance, area(double_area), cos)
    } else {
        0.0
    }
}

impl PathTracing for Change {
    fn luminance(&self, c: Vec3) -> f32 {
        match *self {
            MeanOfChannels => (c.x + c.y + c.z) / 3.0,
            Bt601 => 0.299 * c.x + 0.587 * c.y + 0.114 * c.z,
            RedBlueSwapped => 0.0722 * c.x + 0.7152 * c.y + 0.2126 * c.z,
            DotWithWeights => c.dot(Vec3::new(0.2126, 0.7152, 0.0722)),
            _ => Reference.luminance(c),
        }
    }

    fn bsdf(&self, m: &PathMaterial, normal: Vec3, wo: Vec3, wi: Vec3) -> BsdfValue {
        let zero = BsdfValue {
            value: Vec3::ZERO,
            pdf: 0.0,
        };
        let below = normal.dot(wo) <= 0.0 || normal.dot(wi) <= 0.0;
        let p = glossy_probability(m);
        let key = Parts {
            mirror_of: mirror,
            lobe: clamped_lobe,
            value_k: value_factor,
            pdf_k: pdf_factor,
            p,
        };
        let with = |parts: Parts| bsdf_with(m, normal, wo, wi, parts);
        match *self {
            DiffuseWithoutPi if !below => {
                let b = Reference.bsdf(m, normal, wo, wi);
                BsdfValue {
                    value: b.value + m.diffuse * (1.0 - FRAC_1_PI),
                    ..b
                }
            }
            LobeNormalisedLikePdf if !below => with(Parts {
                value_k: pdf_factor,
                ..key
            }),
            LobeNotClamped if !below => with(Parts {
                lobe: |c, n| c.powf(n),
                ..key
            }),
            ValueWithCosine if !below => {
                let b = Reference.bsdf(m, normal, wo, wi);
                BsdfValue {
                    value: b.value * normal.dot(wi),
                    ..b
                }
            }
            PdfNormalisedLikeValue if !below => with(Parts {
                pdf_k: value_factor,
                ..key
            }),
            PdfByLuminance if !below => {
                let (d, s) = (
                    Reference.luminance(m.diffuse),
                    Reference.luminance(m.glossy),
                );
                let p = if s > 0.0 { s / (d + s) } else { 0.0 };
                with(Parts { p, ..key })
            }
            MirrorSignWrong if !below => with(Parts {
                mirror_of: |n, wo| wo - 2.0 * n.dot(wo) * n,
                ..key
            }),
            NotZeroBelow => with(key),
            ZeroToTheZero if !below => with(Parts {
                lobe: |c, n| c.max(0.0).powf(n),
                ..key
            }),
            MirrorByReflect if !below => with(Parts {
                mirror_of: |n, wo| (-wo).reflect(n),
                ..key
            }),
            InDoublePrecision if !below => {
                let (n, r) = (f64::from(m.exponent), mirror(normal, wo).as_dvec3());
                let cos = r.dot(wi.as_dvec3());
                let lobe = if cos > 0.0 { cos.min(1.0).powf(n) } else { 0.0 };
                let tau = std::f64::consts::TAU;
                let p = f64::from(p);
                BsdfValue {
                    value: (m.diffuse.as_dvec3() / std::f64::consts::PI
                        + m.glossy.as_dvec3() * ((n + 2.0) / tau * lobe))
                        .as_vec3(),
                    pdf: ((1.0 - p) * f64::from(normal.dot(wi)) / std::f64::consts::PI
                        + p * (n + 1.0) / tau * lobe) as f32,
                }
            }
            InDoublePrecision
            | MirrorByReflect
            | DiffuseWithoutPi
            | LobeNormalisedLikePdf
            | LobeNotClamped
            | ValueWithCosine
            | PdfNormalisedLikeValue
            | PdfByLuminance
            | MirrorSignWrong
            | ZeroToTheZero => zero,
            _ => Reference.bsdf(m, normal, wo, wi),
        }
    }

    fn sample_bsdf(
        &self,
        m: &PathMaterial,
        normal: Vec3,
        wo: Vec3,
        rng: &mut Rng,
    ) -> Option<BsdfSample> {
        let glossy = |u: Vec3, m: &PathMaterial| {
            about(
                mirror(normal, wo),
                u.x.powf(1.0 / (m.exponent + 1.0)),
                TAU * u.y,
            )
        };
        let diffuse = |u: Vec3| about(normal, (1.0 - u.x).max(0.0).sqrt(), TAU * u.y);
        match *self {
            PdfOfChosenLobe | ValueOfChosenLobe => {
                let choice = rng.next_f32();
                let u = rng.next_vec2();
                let u = Vec3::new(u.x, u.y, 0.0);
                let is_glossy = choice < glossy_probability(m);
                let wi = if is_glossy { glossy(u, m) } else { diffuse(u) };
                if normal.dot(wi) <= 0.0 || normal.dot(wo) <= 0.0 {
                    return None;
                }
                let b = Reference.bsdf(m, normal, wo, wi);
                let lobe = clamped_lobe(mirror(normal, wo).dot(wi), m.exponent);
                let (lobe_value, lobe_pdf) = if is_glossy {
                    (
                        m.glossy * value_factor(m.exponent) * lobe,
                        pdf_factor(m.exponent) * lobe,
                    )
                } else {
                    (m.diffuse * FRAC_1_PI, normal.dot(wi) * FRAC_1_PI)
                };
                Some(if *self == PdfOfChosenLobe {
                    BsdfSample {
                        direction: wi,
                        value: b.value,
                        pdf: lobe_pdf,
                    }
                } else {
                    BsdfSample {
                        direction: wi,
                        value: lobe_value,
                        pdf: b.pdf,
                    }
                })
            }
            UniformForCosine => sample_with(m, normal, wo, rng, |c, u, p, m| {
                if c < p {
                    glossy(u, m)
                } else {
                    about(normal, u.x, TAU * u.y)
                }
            }),
            ExponentWithoutOne => sample_with(m, normal, wo, rng, |c, u, p, m| {
                if c < p {
                    about(
                        mirror(normal, wo),
                        u.x.powf(1.0 / m.exponent.max(1e-3)),
                        TAU * u.y,
                    )
                } else {
                    diffuse(u)
                }
            }),
            LobeAboutNormal => sample_with(m, normal, wo, rng, |c, u, p, m| {
                if c < p {
                    about(normal, u.x.powf(1.0 / (m.exponent + 1.0)), TAU * u.y)
                } else {
                    diffuse(u)
                }
            }),
            OneNumberForBoth => {
                let u = rng.next_vec2();
                let p = glossy_probability(m);
                let u3 = Vec3::new(u.x, u.y, 0.0);
                let wi = if u.x < p { glossy(u3, m) } else { diffuse(u3) };
                if normal.dot(wi) <= 0.0 || normal.dot(wo) <= 0.0 {
                    return None;
                }
                let b = Reference.bsdf(m, normal, wo, wi);
                Some(BsdfSample {
                    direction: wi,
                    value: b.value,
                    pdf: b.pdf,
                })
            }
            BelowKept => {
                let choice = rng.next_f32();
                let u = rng.next_vec2();
                let u = Vec3::new(u.x, u.y, 0.0);
                let wi = if choice < glossy_probability(m) {
                    glossy(u, m)
                } else {
                    diffuse(u)
                };
                let b = Reference.bsdf(m, normal, wo, wi);
                Some(BsdfSample {
                    direction: wi,
                    value: b.value,
                    pdf: b.pdf.max(1e-3),
                })
            }
            FreshGenerator => Reference.sample_bsdf(m, normal, wo, &mut Rng::new(0, 0)),
            CosineBySqrt => sample_with(m, normal, wo, rng, |c, u, p, m| {
                if c < p {
                    glossy(u, m)
                } else {
                    about(normal, u.x.sqrt(), TAU * u.y)
                }
            }),
            AzimuthFirst => sample_with(m, normal, wo, rng, |c, u, p, m| {
                let swapped = Vec3::new(u.y, u.x, 0.0);
                if c < p {
                    glossy(swapped, m)
                } else {
                    diffuse(swapped)
                }
            }),
            GlossyFromTop => sample_with(m, normal, wo, rng, |c, u, p, m| {
                if c >= 1.0 - p && p > 0.0 {
                    glossy(u, m)
                } else {
                    diffuse(u)
                }
            }),
            _ => Reference.sample_bsdf(m, normal, wo, rng),
        }
    }

    fn sample_emitter(
        &self,
        triangle: [Vec3; 3],
        radiance: Vec3,
        position: Vec3,
        rng: &mut Rng,
    ) -> Option<EmitterSample> {
        let scaled = |factor: &dyn Fn(&EmitterSample) -> f32, rng: &mut Rng| {
            Reference
                .sample_emitter(triangle, radiance, position, rng)
                .map(|s| EmitterSample {
                    pdf: s.pdf * factor(&s),
                    ..s
                })
        };
        let [a, b, c] = triangle;
        let cross = (b - a).cross(c - a);
        let area = 0.5 * cross.length();
        let cos_at = |s: &EmitterSample| -cross.normalize().dot(s.direction);
        let at_point = |beta: f32, gamma: f32, rng: &mut Rng| -> Option<EmitterSample> {
            let _ = rng;
            let point = a * (1.0 - beta - gamma) + b * beta + c * gamma;
            let to = point - position;
            let distance = to.length();
            let direction = to / distance;
            let pdf = Reference.emitter_pdf(triangle, position, direction, distance);
            (pdf > 0.0).then_some(EmitterSample {
                direction,
                distance,
                radiance,
                pdf,
                delta: false,
            })
        };
        match *self {
            AreaDensity => scaled(&|s| 1.0 / (s.pdf * area), rng),
            DistanceNotSquared => scaled(&|s| 1.0 / s.distance, rng),
            NoEmitterCosine => scaled(&|s| cos_at(s), rng),
            CrossAsArea => scaled(&|_| 0.5, rng),
            NoSquareRoot => {
                let u = rng.next_vec2();
                at_point(u.x * (1.0 - u.y), u.x * u.y, rng)
            }
            TwoSided => {
                let u = rng.next_vec2();
                let s = u.x.sqrt();
                let point = a * (1.0 - s) + b * (s * (1.0 - u.y)) + c * (s * u.y);
                let to = point - position;
                let distance = to.length();
                let direction = to / distance;
                let cos = cross.normalize().dot(direction).abs();
                (area > 0.0).then_some(EmitterSample {
                    direction,
                    distance,
                    radiance,
                    pdf: distance * distance / (area * cos),
                    delta: false,
                })
            }
            FoldedSquare => {
                let u = rng.next_vec2();
                let (beta, gamma) = if u.x + u.y > 1.0 {
                    (1.0 - u.x, 1.0 - u.y)
                } else {
                    (u.x, u.y)
                };
                at_point(beta, gamma, rng)
            }
            _ => Reference.sample_emitter(triangle, radiance, position, rng),
        }
    }

    fn emitter_pdf(
        &self,
        triangle: [Vec3; 3],
        position: Vec3,
        direction: Vec3,
        distance: f32,
    ) -> f32 {
        let solid_angle = |d: f32, area: f32, cos: f32| d * d / (area * cos);
        match *self {
            PdfAreaDensity => emitter_pdf_with(
                triangle,
                direction,
                distance,
                |x| 0.5 * x,
                |_, area, _| 1.0 / area,
            ),
            PdfDistanceNotSquared => emitter_pdf_with(
                triangle,
                direction,
                distance,
                |x| 0.5 * x,
                |d, area, cos| d / (area * cos),
            ),
            PdfTwoSided => {
                let [a, b, c] = triangle;
                let cross = (b - a).cross(c - a);
                let double_area = cross.length();
                let cos = cross.dot(direction).abs() / double_area;
                if double_area > 0.0 && cos > 0.0 {
                    solid_angle(distance, 0.5 * double_area, cos)
                } else {
                    0.0
                }
            }
            PdfCrossAsArea => emitter_pdf_with(
                triangle,
                direction,
                distance,
                |x| x,
                |d, area, cos| d * d / (area * cos),
            ),
            PdfInDouble => {
                let [a, b, c] = triangle.map(Vec3::as_dvec3);
                let cross = (b - a).cross(c - a);
                let double_area = cross.length();
                let cos = -cross.dot(direction.as_dvec3()) / double_area;
                let d = f64::from(distance);
                if double_area > 0.0 && cos > 0.0 {
                    (d * d / (0.5 * double_area * cos)) as f32
                } else {
                    0.0
                }
            }
            _ => Reference.emitter_pdf(triangle, position, direction, distance),
        }
    }

    fn power_heuristic(&self, pdf: f32, other: f32) -> f32 {
        match *self {
            Balance => {
                if pdf > 0.0 {
                    pdf / (pdf + other)
                } else {
                    0.0
                }
            }
            NaiveWithoutGuard => pdf * pdf / (pdf * pdf + other * other),
            OtherStrategysWeight => Reference.power_heuristic(other, pdf),
            NaiveWithGuard => {
                if pdf > 0.0 {
                    pdf * pdf / (pdf * pdf + other * other)
                } else {
                    0.0
                }
            }
            _ => Reference.power_heuristic(pdf, other),
        }
    }

    fn roulette(&self, t: Vec3, rng: &mut Rng) -> Option<f32> {
        let with = |largest: f32, rng: &mut Rng| {
            let u = rng.next_f32();
            let q = largest.min(1.0);
            (largest > 0.0 && u < q).then(|| 1.0 / q)
        };
        match *self {
            NoDivision => Reference.roulette(t, rng).map(|_| 1.0),
            MeanChannel => with(t.element_sum() / 3.0, rng),
            ByLuminance => with(Reference.luminance(t), rng),
            SurviveAbove => {
                let u = rng.next_f32();
                let largest = t.max_element();
                let q = largest.min(1.0);
                (largest > 0.0 && u >= q).then(|| 1.0 / q)
            }
            DividedByComplement => Reference.roulette(t, rng).map(|f| {
                let q = 1.0 / f;
                if q < 1.0 { 1.0 / (1.0 - q) } else { 1.0 }
            }),
            NeverAdvances => Reference.roulette(t, &mut Rng::new(3, 3)),
            DrawOnlyWhenNeeded => {
                if t.max_element() >= 1.0 {
                    Some(1.0)
                } else {
                    with(t.max_element(), rng)
                }
            }
            _ => Reference.roulette(t, rng),
        }
    }

    fn path_radiance(
        &self,
        ray: &Ray,
        max_depth: u32,
        trace: &dyn Fn(&Ray) -> PathHit,
        occluded: &dyn Fn(&Ray) -> bool,
        sample_light: &dyn Fn(Vec3, &mut Rng) -> Option<EmitterSample>,
        sample_bsdf: &dyn Fn(&PathVertex, Vec3, &mut Rng) -> Option<BsdfSample>,
        bsdf: &dyn Fn(&PathVertex, Vec3, Vec3) -> BsdfValue,
        power_heuristic: &dyn Fn(f32, f32) -> f32,
        roulette: &dyn Fn(Vec3, &mut Rng) -> Option<f32>,
        rng: &mut Rng,
    ) -> Vec3 {
        path_loop(
            *self,
            ray,
            max_depth,
            trace,
            occluded,
            sample_light,
            sample_bsdf,
            bsdf,
            power_heuristic,
            roulette,
            rng,
        )
    }

    fn accumulate(&self, st: &PixelStatistics, x: Vec3) -> PixelStatistics {
        let count = st.count + 1;
        let n = count as f32;
        match *self {
            SumOfSquares => {
                // Kept as Σx and Σx² in disguise: mean and the raw second moment.
                let sum = st.mean * st.count as f32 + x;
                let squares = st.m2 + st.mean * st.mean * st.count as f32 + x * x;
                let mean = sum / n;
                PixelStatistics {
                    count,
                    mean,
                    m2: squares - mean * mean * n,
                }
            }
            OldMeanTwice => PixelStatistics {
                count,
                mean: st.mean + (x - st.mean) / n,
                m2: st.m2 + (x - st.mean) * (x - st.mean),
            },
            MeanOverOldCount => {
                let mean = st.mean + (x - st.mean) / (st.count.max(1) as f32);
                PixelStatistics {
                    count,
                    mean,
                    m2: st.m2 + (x - st.mean) * (x - mean),
                }
            }
            WelfordInDouble => {
                let (m, x2) = (st.mean.as_dvec3(), x.as_dvec3());
                let delta = x2 - m;
                let mean = m + delta / f64::from(count);
                PixelStatistics {
                    count,
                    mean: mean.as_vec3(),
                    m2: (st.m2.as_dvec3() + delta * (x2 - mean)).as_vec3(),
                }
            }
            _ => Reference.accumulate(st, x),
        }
    }

    fn sky_distribution(&self, luminance: &[f32], width: u32, height: u32) -> SkyDistribution {
        sky_distribution_with(*self, luminance, width, height)
    }

    fn sample_sky(&self, sky: &SkyDistribution, rng: &mut Rng) -> Option<SkySample> {
        sample_sky_with(*self, sky, rng)
    }

    fn sky_pdf(&self, sky: &SkyDistribution, direction: Vec3) -> f32 {
        sky_pdf_with(*self, sky, direction)
    }

    fn relative_error(&self, st: &PixelStatistics) -> f32 {
        let n = st.count as f32;
        let per_channel = |se: Vec3| {
            (0..3)
                .map(|c| {
                    if st.mean[c] == 0.0 {
                        0.0
                    } else {
                        se[c] / st.mean[c]
                    }
                })
                .fold(0.0, f32::max)
        };
        match *self {
            PopulationVariance if st.count >= 2 => per_channel((st.m2 / n / n).powf(0.5)),
            WithoutRootN if st.count >= 2 => per_channel((st.m2 / (n - 1.0)).powf(0.5)),
            ByLuminanceOfMean if st.count >= 2 => {
                let se = (st.m2 / (n - 1.0) / n).powf(0.5);
                let y = Reference.luminance(st.mean);
                if y == 0.0 {
                    0.0
                } else {
                    Reference.luminance(se) / y
                }
            }
            ZeroBelowTwo if st.count < 2 => 0.0,
            NaNWhenBlack if st.count >= 2 => {
                let se = (st.m2 / (n - 1.0) / n).powf(0.5);
                (se / st.mean).max_element()
            }
            VarianceFromSquares if st.count >= 2 => {
                let n = f64::from(st.count);
                let se = (st.m2.as_dvec3() / (n - 1.0) / n).powf(0.5);
                let m = st.mean.as_dvec3();
                (0..3)
                    .map(|c| if m[c] == 0.0 { 0.0 } else { se[c] / m[c] })
                    .fold(0.0, f64::max) as f32
            }
            _ => Reference.relative_error(st),
        }
    }
}

/// The key's path loop with one thing changed by `change`.
#[allow(clippy::too_many_arguments)]
fn path_loop(
    change: Change,
    ray: &Ray,
    max_depth: u32,
    trace: &dyn Fn(&Ray) -> PathHit,
    occluded: &dyn Fn(&Ray) -> bool,
    sample_light: &dyn Fn(Vec3, &mut Rng) -> Option<EmitterSample>,
    sample_bsdf: &dyn Fn(&PathVertex, Vec3, &mut Rng) -> Option<BsdfSample>,
    bsdf: &dyn Fn(&PathVertex, Vec3, Vec3) -> BsdfValue,
    power_heuristic: &dyn Fn(f32, f32) -> f32,
    roulette: &dyn Fn(Vec3, &mut Rng) -> Option<f32>,
    rng: &mut Rng,
) -> Vec3 {
    let mut radiance = Vec3::ZERO;
    let mut throughput = Vec3::ONE;
    let mut ray = *ray;
    let mut bsdf_pdf: Option<f32> = None;
    let last = if change == OneBounceShort {
        max_depth.saturating_sub(1)
    } else {
        max_depth
    };
    for depth in 0..=last {
        let weight = |light_pdf: f32| match (change, bsdf_pdf) {
            (_, None) => 1.0,
            (EmissionAlwaysInFull, Some(_)) => 1.0,
            (WeightArgumentsSwapped, Some(p)) => power_heuristic(light_pdf, p),
            (_, Some(p)) => power_heuristic(p, light_pdf),
        };
        let vertex = match trace(&ray) {
            PathHit::Escaped {
                radiance: sky,
                light_pdf,
            } => {
                if change != SkyIgnored {
                    radiance += throughput * sky * weight(light_pdf);
                }
                break;
            }
            PathHit::Surface(vertex) => vertex,
        };
        if !(change == CameraVertexDark && depth == 0) {
            radiance += throughput * vertex.emitted * weight(vertex.light_pdf);
        }
        if depth == last {
            break;
        }
        let wo = -ray.direction;
        if let Some(light) = sample_light(vertex.position, rng) {
            let cos = vertex.normal.dot(light.direction);
            let f = bsdf(&vertex, wo, light.direction);
            if cos > 0.0 {
                let tmax = if change == ShadowRayToTheLight {
                    light.distance
                } else {
                    light.distance * (1.0 - 1e-4)
                };
                let shadow = Ray::new(vertex.position, light.direction, RAY_EPSILON, tmax);
                if !occluded(&shadow) {
                    let w =
                        if change == NeeWithoutWeight || (light.delta && change != DeltaWeighted) {
                            1.0
                        } else {
                            power_heuristic(light.pdf, f.pdf)
                        };
                    let c = if change == NeeWithoutCosine { 1.0 } else { cos };
                    radiance += throughput * f.value * light.radiance * c / light.pdf * w;
                }
            }
        }
        let Some(next) = sample_bsdf(&vertex, wo, rng) else {
            break;
        };
        let pdf = if change == ThroughputWithoutPdf {
            1.0
        } else {
            next.pdf
        };
        throughput *= next.value * vertex.normal.dot(next.direction) / pdf;
        bsdf_pdf = Some(next.pdf);
        let tmin = if change == BounceWithoutOffset {
            0.0
        } else {
            RAY_EPSILON
        };
        ray = Ray::unbounded(vertex.position, next.direction, tmin);
        let play = match change {
            NoRoulette => false,
            RouletteFromTheStart => true,
            _ => depth >= 2,
        };
        if play {
            match roulette(throughput, rng) {
                Some(factor) if change != RouletteFactorIgnored => throughput *= factor,
                Some(_) => {}
                None => break,
            }
        }
    }
    radiance
}

grading::corpus_tests!(lab12, lab12_checks, reference, code = change);
