//! Lab 10's exercises and their checks.
//!
//! Every exercise is checked by relations its answer satisfies whatever the formula — values
//! at normal and grazing incidence, Brewster's angle, the symmetry between the two sides of
//! an interface, bounds, total internal reflection past the critical angle (and a number of
//! `[0, 1]` close to 1 within rounding of it), the multiplicativity of transmittance over
//! distance — on random inputs from a fixed seed, by
//! the answer key on the same inputs when it is present ([`LabContext::key`]), and by the
//! golden cases recorded from the reference. Exercises 10.4 and 10.5, which the renderer
//! calls, are also checked by renders of small scenes with the student's function in its slot
//! and the base everywhere else (deterministic: point and directional lights only).
//!
//! The transmitted cosine `cos θ₂` that goes with a random `cos θ₁` comes from the base's
//! lab 04 `refract` (Snell's law), never from a formula of the checks. The energy balance
//! `R + T = 1` against the Fresnel transmission coefficients is checked on the reference in
//! the lab's own tests (`labs/lab10/tests/energy.rs`): its formulas would answer Exercise
//! 10.3.

use std::sync::Arc;

use glam::Vec3;
use proptest::prelude::*;

use contracts::lab04::Reflection;
use contracts::lab10::Fresnel;
use grading::part_snapshots::{PartSnapshots, SnapshotScene};
use grading::scenes::glossy_default_scene;
use grading::strategies::index_strategy;
use grading::{
    Exercise, GoldenFile, LabContext, PixelTolerance, compare_f32, compare_vec3, for_all,
};
use raylab_core::render::RenderSettings;
use raylab_core::scene::{IllumModel, Material, Scene, builtin_scene};

/// Golden file of Exercise 10.1.
pub const GOLDEN_R_S: &str = "fresnel_r_s.json";
/// Golden file of Exercise 10.2.
pub const GOLDEN_R_P: &str = "fresnel_r_p.json";
/// Golden file of Exercise 10.3.
pub const GOLDEN_R: &str = "fresnel_R.json";
/// Golden file of Exercise 10.4.
pub const GOLDEN_REFLECTANCE: &str = "fresnel_reflectance.json";
/// Golden file of Exercise 10.5.
pub const GOLDEN_TRANSMITTANCE: &str = "transmittance.json";
/// Size and sampling of lab 10's snapshots.
pub const SNAPSHOT_SETTINGS: RenderSettings = RenderSettings::snapshot(10);
/// The depth limit of the snapshots.
pub const SNAPSHOT_MAX_DEPTH: u32 = 10;
/// Per-pixel tolerance of the snapshots: the renders are deterministic, so only rounding (and
/// rays that graze a sphere) may differ.
pub const SNAPSHOT_TOLERANCE: PixelTolerance = PixelTolerance {
    abs: 2e-3,
    rel: 2e-3,
    max_outlier_fraction: 0.005,
};
/// Absolute tolerance of a reflection coefficient or reflectance against a known value.
pub const COEFFICIENT_TOLERANCE: f32 = 2e-5;
/// The Kd of the absorbing glass ball of the Week 11 worksheet (`illum 12`, Kd 0.8 0.1 0.3).
pub const WORKSHEET_ABSORPTION_COLOUR: Vec3 = Vec3::new(0.8, 0.1, 0.3);

// ---------------------------------------------------------------------------------------------
// Exercises

/// This lab.
pub const LAB: course::LabId = course::LabId::of(10);

/// The exercises of lab 10 (`labs/lab10/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Fresnel>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_10_1,
            exercise_10_2,
            exercise_10_3,
            exercise_10_4,
            exercise_10_5
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Inputs

/// Input of Exercises 10.1–10.3: `cos θ₁`, `cos θ₂` (related by Snell's law), `η₁`, `η₂`.
pub type PairInput = (f32, f32, f32, f32);
/// Input of Exercise 10.4: `cos θ₁`, `η₁`, `η₂`.
pub type ReflectanceInput = (f32, f32, f32);
/// Input of Exercise 10.5: the distance and the material's diffuse colour.
pub type TransmittanceInput = (f32, Vec3);

/// A cosine of incidence: anywhere in `[0, 1]`, exactly 0 or 1, near grazing (down to 10⁻⁴)
/// or near normal.
pub fn cosine_strategy() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        4 => 0.0f32..=1.0,
        1 => Just(1.0f32),
        1 => Just(0.0f32),
        1 => 1e-4f32..1e-2,
        1 => 0.999f32..=1.0,
    ]
}

/// Inputs of Exercise 10.4: a cosine of [`cosine_strategy`], two indices of lab 04's
/// `index_strategy` (equal one time in eight).
pub fn reflectance_strategy() -> impl Strategy<Value = ReflectanceInput> + Clone {
    (
        cosine_strategy(),
        index_strategy(),
        index_strategy(),
        0u8..8,
    )
        .prop_map(|(c, ei, et, same)| (c, ei, if same == 0 { ei } else { et }))
}

/// `cos θ₂` of the ray transmitted at `cos θ₁ = cos_i` from `eta_i` into `eta_t`, through
/// the base's lab 04 `refract` (Snell's law); `None` under total internal reflection.
pub fn transmitted_cosine(
    reflection: &dyn Reflection,
    cos_i: f32,
    eta_i: f32,
    eta_t: f32,
) -> Option<f32> {
    let sin_i = (1.0 - cos_i * cos_i).max(0.0).sqrt();
    let direction = Vec3::new(sin_i, 0.0, -cos_i);
    let t = reflection.refract(direction, Vec3::Z, eta_i, eta_t)?;
    Some((-t.z).clamp(0.0, 1.0))
}

/// The input of Exercises 10.1–10.3 that goes with an input of Exercise 10.4: `cos θ₂` from
/// the base's Snell's law; `None` under total internal reflection and where both rays graze
/// the surface (where the coefficients are 0/0).
pub fn pair_of(reflection: &dyn Reflection, (c, ei, et): ReflectanceInput) -> Option<PairInput> {
    let ct = transmitted_cosine(reflection, c, ei, et)?;
    (c.max(ct) > 1e-3).then_some((c, ct, ei, et))
}

/// A distance from 10⁻⁴ to 10³ units (log-uniform), or exactly 0.
pub fn distance_strategy() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        6 => (-4.0f32..3.0).prop_map(|e| 10f32.powf(e)),
        1 => Just(0.0f32),
    ]
}

/// A diffuse colour channel in `[0, 1]`, sometimes exactly 0, 1 or tiny.
fn channel() -> impl Strategy<Value = f32> + Clone {
    prop_oneof![
        6 => 0.0f32..=1.0,
        1 => Just(0.0f32),
        1 => Just(1.0f32),
        1 => 1e-8f32..1e-5,
    ]
}

/// A diffuse colour with channels of [`channel`].
pub fn colour_strategy() -> impl Strategy<Value = Vec3> + Clone {
    (channel(), channel(), channel()).prop_map(|(r, g, b)| Vec3::new(r, g, b))
}

/// Inputs of Exercise 10.5.
pub fn transmittance_strategy() -> impl Strategy<Value = TransmittanceInput> + Clone {
    (distance_strategy(), colour_strategy())
}

/// An absorbing volume (`illum 11`) of diffuse colour `diffuse`; its transmission filter
/// (`Tf`) is the MTL default, white.
pub fn volume_material(diffuse: Vec3) -> Material {
    Material {
        illum: IllumModel::AbsorbingVolume,
        ior: 1.5,
        specular: Vec3::ONE,
        ..Material::lambertian("volume", diffuse)
    }
}

// ---------------------------------------------------------------------------------------------
// Exercises 10.1–10.3: the coefficients at a pair of cosines

/// Which of the three functions of a pair of cosines is checked.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Coefficient {
    RS,
    RP,
    R,
}

impl Coefficient {
    fn name(self) -> &'static str {
        match self {
            Coefficient::RS => "fresnel_r_s",
            Coefficient::RP => "fresnel_r_p",
            Coefficient::R => "fresnel_R",
        }
    }

    fn call(self, f: &dyn Fresnel, (c1, c2, e1, e2): PairInput) -> f32 {
        match self {
            Coefficient::RS => f.fresnel_r_s(c1, c2, e1, e2),
            Coefficient::RP => f.fresnel_r_p(c1, c2, e1, e2),
            Coefficient::R => f.fresnel_R(c1, c2, e1, e2),
        }
    }

    fn show(self, (c1, c2, e1, e2): PairInput) -> String {
        format!(
            "{}(cos θ₁ = {c1}, cos θ₂ = {c2}, η₁ = {e1}, η₂ = {e2})",
            self.name()
        )
    }

    /// The value at normal incidence (`cos θ₁ = cos θ₂ = 1`), from `ρ = (η₁ − η₂)/(η₁ + η₂)`:
    /// `ρ` for `r_s`, `−ρ` for `r_p`, `ρ²` for `R`.
    fn at_normal_incidence(self, e1: f32, e2: f32) -> f64 {
        let rho = (e1 as f64 - e2 as f64) / (e1 as f64 + e2 as f64);
        match self {
            Coefficient::RS => rho,
            Coefficient::RP => -rho,
            Coefficient::R => rho * rho,
        }
    }

    /// The value at grazing incidence into a denser medium (`cos θ₁ = 0`, `η₂ > η₁`): the
    /// amplitudes are −1, the reflectance 1.
    fn at_grazing_incidence(self) -> f32 {
        match self {
            Coefficient::RS | Coefficient::RP => -1.0,
            Coefficient::R => 1.0,
        }
    }

    /// The value from the other side of the interface at the same pair of angles: the
    /// amplitudes change sign, the reflectance does not.
    fn seen_from_other_side(self, value: f32) -> f32 {
        match self {
            Coefficient::RS | Coefficient::RP => -value,
            Coefficient::R => value,
        }
    }

    /// What the value at normal incidence is, in words and symbols.
    fn normal_incidence_rule(self) -> &'static str {
        match self {
            Coefficient::RS => {
                "head-on r_s = (η₁ − η₂)/(η₁ + η₂), negative entering a denser medium"
            }
            Coefficient::RP => {
                "head-on r_p = (η₂ − η₁)/(η₁ + η₂) = −r_s: in the sign convention of this course the two amplitudes are opposite there"
            }
            Coefficient::R => {
                "head-on the two polarisations reflect alike and R = ((η₁ − η₂)/(η₁ + η₂))²"
            }
        }
    }

    fn hint(self) -> &'static str {
        match self {
            Coefficient::RS => {
                "r_s compares η cos θ on the two sides: η₁ cos θ₁ − η₂ cos θ₂ over their sum (docs/lab10.md, §10.1)"
            }
            Coefficient::RP => {
                "r_p pairs each index with the other side's cosine: η₂ cos θ₁ − η₁ cos θ₂ over their sum (docs/lab10.md, §10.2)"
            }
            Coefficient::R => {
                "R is the mean of the two polarisations' reflectances r_s² and r_p² (docs/lab10.md, §10.3)"
            }
        }
    }
}

/// Checks one coefficient on `input` against the relations every correct answer satisfies,
/// and against `expected` when it is known.
fn check_coefficient(
    which: Coefficient,
    f: &dyn Fresnel,
    input: PairInput,
    expected: Option<f32>,
) -> Result<(), String> {
    let call = which.show(input);
    let got = which.call(f, input);
    let hint = which.hint();
    if !got.is_finite() {
        return Err(format!("{call} is {got}: not a finite number ({hint})"));
    }
    let (lo, hi) = match which {
        Coefficient::R => (0.0, 1.0),
        _ => (-1.0, 1.0),
    };
    if got < lo - 1e-5 || got > hi + 1e-5 {
        return Err(format!(
            "{call} is {got}, outside [{lo}, {hi}]: a reflection coefficient is at most 1 in magnitude, a reflectance between 0 and 1 ({hint})"
        ));
    }
    let (c1, c2, e1, e2) = input;
    let other = which.call(f, (c2, c1, e2, e1));
    compare_f32(
        &format!("{} (from the other side of the interface)", which.show((c2, c1, e2, e1))),
        other,
        which.seen_from_other_side(got),
        COEFFICIENT_TOLERANCE,
        1e-4,
    )
    .map_err(|e| {
        format!(
            "{e}, from {call} = {got}: light crossing the interface the other way at the same pair of angles {} (η and cos θ of the two sides swap)",
            match which {
                Coefficient::R => "is reflected as much",
                _ => "has the amplitude of the opposite sign",
            }
        )
    })?;
    if let Some(expected) = expected {
        compare_f32(&call, got, expected, COEFFICIENT_TOLERANCE, 1e-4)
            .map_err(|e| format!("{e} ({hint})"))?;
    }
    Ok(())
}

/// The checks of Exercises 10.1–10.3: relations on random pairs, normal and grazing
/// incidence, equal media, the key and the golden cases.
fn check_pairs(which: Coefficient, s: &Arc<dyn Fresnel>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Fresnel>();
    let base = ctx.base.code::<dyn contracts::lab04::Reflection>();
    for_all(600, reflectance_strategy(), |input| {
        let Some(pair) = pair_of(base.as_ref(), input) else {
            return Ok(());
        };
        let expected = key.as_ref().map(|k| which.call(k.as_ref(), pair));
        check_coefficient(which, s.as_ref(), pair, expected)
    })?;
    for_all(200, (index_strategy(), index_strategy()), |(e1, e2)| {
        let input = (1.0, 1.0, e1, e2);
        let call = which.show(input);
        compare_f32(
            &format!("{call} (normal incidence)"),
            which.call(s.as_ref(), input),
            which.at_normal_incidence(e1, e2) as f32,
            COEFFICIENT_TOLERANCE,
            1e-4,
        )
        .map_err(|e| format!("{e}: {} ({})", which.normal_incidence_rule(), which.hint()))?;
        let same = (0.6, 0.6, e1, e1);
        let got = which.call(s.as_ref(), same);
        if got.is_nan() || got.abs() > 1e-6 {
            return Err(format!(
                "{} is {got}: between two media of the same index nothing is reflected",
                which.show(same)
            ));
        }
        if e2 <= e1 * 1.01 {
            return Ok(());
        }
        let Some(ct) = transmitted_cosine(base.as_ref(), 0.0, e1, e2) else {
            return Ok(());
        };
        let grazing = (0.0, ct, e1, e2);
        compare_f32(
            &format!(
                "{} (grazing incidence into a denser medium)",
                which.show(grazing)
            ),
            which.call(s.as_ref(), grazing),
            which.at_grazing_incidence(),
            COEFFICIENT_TOLERANCE,
            0.0,
        )
        .map_err(|e| format!("{e}: at grazing incidence everything is reflected"))
    })?;
    let name = match which {
        Coefficient::RS => GOLDEN_R_S,
        Coefficient::RP => GOLDEN_R_P,
        Coefficient::R => GOLDEN_R,
    };
    let golden: GoldenFile<PairInput, f32> = ctx.golden(name)?;
    for case in &golden.cases {
        check_coefficient(which, s.as_ref(), case.input, Some(case.expected))?;
    }
    Ok(())
}

fn exercise_10_1(s: &Arc<dyn Fresnel>, ctx: &LabContext) -> Result<(), String> {
    check_pairs(Coefficient::RS, s, ctx)?;
    // Entering a denser medium the perpendicular amplitude is negative at every angle.
    let base = ctx.base.code::<dyn contracts::lab04::Reflection>();
    for_all(200, reflectance_strategy(), |(c, e1, e2)| {
        if e2 < e1 * 1.01 {
            return Ok(());
        }
        let Some(pair) = pair_of(base.as_ref(), (c, e1, e2)) else {
            return Ok(());
        };
        let got = s.fresnel_r_s(pair.0, pair.1, pair.2, pair.3);
        if got.is_nan() || got >= 0.0 {
            return Err(format!(
                "{} is {got}: entering a denser medium (η₂ > η₁) the reflected perpendicular amplitude is negative (η₁ cos θ₁ < η₂ cos θ₂) ({})",
                Coefficient::RS.show(pair),
                Coefficient::RS.hint()
            ));
        }
        Ok(())
    })
}

/// `(cos θ₁, cos θ₂)` at Brewster's angle `tan θ_B = η₂/η₁`, `cos θ₂` from the base's Snell's
/// law.
fn brewster(reflection: &dyn Reflection, e1: f32, e2: f32) -> Option<(f32, f32)> {
    let cos_b = (e1 as f64 / (e1 as f64).hypot(e2 as f64)) as f32;
    Some((cos_b, transmitted_cosine(reflection, cos_b, e1, e2)?))
}

fn exercise_10_2(s: &Arc<dyn Fresnel>, ctx: &LabContext) -> Result<(), String> {
    check_pairs(Coefficient::RP, s, ctx)?;
    // Brewster's angle: no parallel reflection there, and the amplitude changes sign across it.
    let base = ctx.base.code::<dyn contracts::lab04::Reflection>();
    for_all(300, (index_strategy(), index_strategy()), |(e1, e2)| {
        if (e1 - e2).abs() < 0.05 {
            return Ok(());
        }
        let Some((cb, ct)) = brewster(base.as_ref(), e1, e2) else {
            return Ok(());
        };
        let input = (cb, ct, e1, e2);
        let call = Coefficient::RP.show(input);
        let got = s.fresnel_r_p(cb, ct, e1, e2);
        if got.is_nan() || got.abs() > 1e-4 {
            return Err(format!(
                "{call} is {got} at Brewster's angle θ_B = atan(η₂/η₁) = {:.3}°: the parallel polarisation is not reflected there, r_p = 0 ({})",
                (cb as f64).acos().to_degrees(),
                Coefficient::RP.hint()
            ));
        }
        // r_p has the sign of η₂ − η₁ nearer normal incidence and the opposite one nearer
        // grazing incidence (or the critical angle).
        let denser = (e2 - e1).signum();
        for (delta, side, sign) in [
            (0.05f32, "nearer normal incidence", denser),
            (-0.05, "nearer grazing incidence", -denser),
        ] {
            let c = (cb + delta).clamp(0.0, 1.0);
            let Some(pair) = pair_of(base.as_ref(), (c, e1, e2)) else {
                continue;
            };
            let rp = s.fresnel_r_p(pair.0, pair.1, e1, e2);
            if rp.is_nan() || rp.signum() != sign {
                return Err(format!(
                    "{} is {rp}, {side} than Brewster's angle ({:.3}°): r_p changes sign there, from the sign of η₂ − η₁ at normal incidence to the opposite one at grazing incidence ({})",
                    Coefficient::RP.show(pair),
                    (cb as f64).acos().to_degrees(),
                    Coefficient::RP.hint()
                ));
            }
        }
        Ok(())
    })
}

fn exercise_10_3(s: &Arc<dyn Fresnel>, ctx: &LabContext) -> Result<(), String> {
    check_pairs(Coefficient::R, s, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 10.4: the reflectance from the cosine of incidence

fn reflectance_call((c, e1, e2): ReflectanceInput) -> String {
    format!("fresnel_reflectance(cos θ₁ = {c}, η₁ = {e1}, η₂ = {e2})")
}

const REFLECTANCE_HINT: &str = "cos θ₂ comes from Snell's law η₁ sin θ₁ = η₂ sin θ₂; then R = fresnel_R(cos θ₁, cos θ₂, η₁, η₂), and R = 1 past the critical angle (docs/lab10.md, §10.4)";

/// Checks `fresnel_reflectance` on `input`: finite and in `[0, 1]`, 1 exactly past the
/// critical angle, the same from the other side at the transmitted angle, and `expected`
/// when it is known.
fn check_reflectance(
    f: &dyn Fresnel,
    base: &dyn Reflection,
    input: ReflectanceInput,
    expected: Option<f32>,
) -> Result<(), String> {
    let call = reflectance_call(input);
    let (c, e1, e2) = input;
    let got = f.fresnel_reflectance(c, e1, e2);
    if !(0.0..=1.0 + 1e-6).contains(&got) {
        return Err(format!(
            "{call} is {got}: a reflectance is a fraction of the light, in [0, 1] ({REFLECTANCE_HINT})"
        ));
    }
    match transmitted_cosine(base, c, e1, e2) {
        None => {
            if got != 1.0 && !near_critical(c, e1, e2) {
                return Err(format!(
                    "{call} is {got}, but sin θ₁ = {:.5} > η₂/η₁ = {:.5}: past the critical angle there is no transmitted ray and all the light is reflected, R = 1",
                    (1.0 - c * c).max(0.0).sqrt(),
                    e2 / e1
                ));
            }
        }
        Some(ct) if ct > 1e-3 && c > 1e-3 => {
            let back = (ct, e2, e1);
            compare_f32(
                &format!("{} (from the other side)", reflectance_call(back)),
                f.fresnel_reflectance(ct, e2, e1),
                got,
                1e-4,
                1e-3,
            )
            .map_err(|e| {
                format!(
                    "{e}, which {call} gives: light crossing the other way along the transmitted ray (cos θ₂ = {ct}) is reflected as much ({REFLECTANCE_HINT})"
                )
            })?;
        }
        Some(_) => {}
    }
    if let Some(expected) = expected {
        compare_f32(&call, got, expected, COEFFICIENT_TOLERANCE, 1e-4)
            .map_err(|e| format!("{e} ({REFLECTANCE_HINT})"))?;
    }
    Ok(())
}

/// Whether `cos θ₁` is within 0.1% of the critical angle's sine, where two correct
/// implementations may decide total internal reflection differently.
fn near_critical(c: f32, e1: f32, e2: f32) -> bool {
    let s = (1.0 - c as f64 * c as f64).max(0.0).sqrt();
    (s * e1 as f64 / e2 as f64 - 1.0).abs() < 1e-3
}

/// How many representable `f32` cosines on each side of the critical angle's cosine
/// [`check_at_critical_angle`] tries.
pub const CRITICAL_STEPS: u32 = 16;
/// The least reflectance accepted within [`CRITICAL_STEPS`] of the critical angle (the
/// reference's is above 0.97 there: R rises steeply to 1).
pub const CRITICAL_MIN_REFLECTANCE: f32 = 0.95;

/// At the critical angle from `η₁` into `η₂ < η₁`, and within rounding of it (the
/// [`CRITICAL_STEPS`] representable `f32` cosines on either side of `cos θ_c`), the reflectance
/// is a number of `[0, 1]` close to 1. A test for total internal reflection on another quantity
/// than the one under the square root (`sin θ₁` against `η₂/η₁`, `cos θ₁` against `cos θ_c`,
/// the angles themselves) agrees with `sin²θ₂ ≥ 1` everywhere but there, where rounding can
/// put the two on different sides of the critical angle and `√(1 − sin²θ₂)` is NaN.
fn check_at_critical_angle(f: &dyn Fresnel, e1: f32, e2: f32) -> Result<(), String> {
    let ratio = e2 as f64 / e1 as f64;
    let critical = (1.0 - ratio * ratio).sqrt() as f32;
    let degrees = ratio.asin().to_degrees();
    let first = f32::from_bits(critical.to_bits().saturating_sub(CRITICAL_STEPS));
    let cosines = (0..=2 * CRITICAL_STEPS).map(|k| f32::from_bits(first.to_bits() + k));
    for c in cosines.filter(|c| (0.0..=1.0).contains(c)) {
        let input = (c, e1, e2);
        let got = f.fresnel_reflectance(c, e1, e2);
        if !(CRITICAL_MIN_REFLECTANCE..=1.0 + 1e-6).contains(&got) {
            let fix = if got.is_nan() {
                "a NaN here is most often the square root of a negative 1 − sin²θ₂: the test for total internal reflection let this cosine through although sin²θ₂ comes out above 1. Test the quantity you take the square root of (return 1 when sin²θ₂ = (η₁/η₂)²(1 − cos²θ₁) ≥ 1), not the angle, its sine or its cosine computed apart: rounding can put two such tests on different sides of the critical angle".to_string()
            } else {
                format!(
                    "R rises to 1 at the critical angle, so within rounding of it R is 1 or just under it (at least {CRITICAL_MIN_REFLECTANCE})"
                )
            };
            let steps = (c.to_bits() as i64 - critical.to_bits() as i64).abs();
            return Err(format!(
                "{} is {got}, within rounding of the critical angle θ_c = {degrees:.4}° (cos θ₁ is {steps} f32 step{} from cos θ_c = {critical}): {fix} ({REFLECTANCE_HINT})",
                reflectance_call(input),
                if steps == 1 { "" } else { "s" },
            ));
        }
    }
    Ok(())
}

/// Whether an input of Exercise 10.4 is clear of the critical angle, and of grazing
/// incidence between equal media (where both rays graze the surface).
pub fn reflectance_is_clear(&(c, e1, e2): &ReflectanceInput) -> bool {
    !near_critical(c, e1, e2)
}

fn exercise_10_4(s: &Arc<dyn Fresnel>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Fresnel>();
    let base = ctx.base.code::<dyn contracts::lab04::Reflection>();
    let clear =
        reflectance_strategy().prop_filter("clear of the critical angle", reflectance_is_clear);
    for_all(800, clear, |input| {
        let expected = key
            .as_ref()
            .map(|k| k.fresnel_reflectance(input.0, input.1, input.2));
        check_reflectance(s.as_ref(), base.as_ref(), input, expected)
    })?;
    // Head-on, grazing, and on both sides of the critical angle.
    let indices = (index_strategy(), index_strategy());
    for_all(300, indices, |(e1, e2)| {
        let head_on = (1.0, e1, e2);
        let rho = (e1 as f64 - e2 as f64) / (e1 as f64 + e2 as f64);
        compare_f32(
            &format!("{} (normal incidence)", reflectance_call(head_on)),
            s.fresnel_reflectance(1.0, e1, e2),
            (rho * rho) as f32,
            COEFFICIENT_TOLERANCE,
            1e-4,
        )
        .map_err(|e| format!("{e} = ((η₁ − η₂)/(η₁ + η₂))² ({REFLECTANCE_HINT})"))?;
        if (e1 - e2).abs() > 0.01 {
            let grazing = (1e-6, e1, e2);
            let got = s.fresnel_reflectance(1e-6, e1, e2);
            if got.is_nan() || got < 0.999 {
                return Err(format!(
                    "{} is {got}: at grazing incidence almost all the light is reflected, R → 1 ({REFLECTANCE_HINT})",
                    reflectance_call(grazing)
                ));
            }
        }
        if e1 > e2 * 1.05 {
            let critical = e2 / e1;
            for (factor, past) in [(1.002f32, true), (0.998, false)] {
                let sin_i = (critical * factor).min(1.0);
                let c = (1.0 - sin_i * sin_i).sqrt();
                let input = (c, e1, e2);
                let got = s.fresnel_reflectance(c, e1, e2);
                let call = format!(
                    "{} ({} the critical angle {:.3}°)",
                    reflectance_call(input),
                    if past { "just past" } else { "just below" },
                    critical.asin().to_degrees()
                );
                if past && got != 1.0 {
                    return Err(format!(
                        "{call} is {got}: under total internal reflection R = 1 exactly ({REFLECTANCE_HINT})"
                    ));
                }
                let partial = 0.0 < got && got < 1.0;
                if !past && !partial {
                    return Err(format!(
                        "{call} is {got}: just below the critical angle some light is still transmitted, 0 < R < 1 ({REFLECTANCE_HINT})"
                    ));
                }
            }
            check_at_critical_angle(s.as_ref(), e1, e2)?;
        }
        Ok(())
    })?;
    let golden: GoldenFile<ReflectanceInput, f32> = ctx.golden(GOLDEN_REFLECTANCE)?;
    for case in &golden.cases {
        check_reflectance(s.as_ref(), base.as_ref(), case.input, Some(case.expected))?;
    }
    Part::Reflectance.check_snapshots(s, ctx)
}

// ---------------------------------------------------------------------------------------------
// Exercise 10.5: transmittance

fn transmittance_call(distance: f32, diffuse: Vec3) -> String {
    format!("transmittance(distance = {distance}, material with diffuse colour {diffuse})")
}

const TRANSMITTANCE_HINT: &str = "T = exp(−σ d) per channel with the absorption coefficient σ = 1/ρ_d − 1 of the diffuse colour ρ_d, and a very large σ where ρ_d is (almost) 0 (docs/lab10.md, §10.5)";

/// Checks `transmittance` at `(distance, diffuse)`: finite and in `[0, 1]`, 1 at distance 0,
/// multiplicative over distance, each channel on its own, and `expected` when it is known.
fn check_transmittance(
    f: &dyn Fresnel,
    (d, rho): TransmittanceInput,
    expected: Option<Vec3>,
) -> Result<(), String> {
    let call = transmittance_call(d, rho);
    let got = f.transmittance(d, &volume_material(rho));
    if !got.is_finite() || got.cmplt(Vec3::ZERO).any() || got.cmpgt(Vec3::splat(1.0 + 1e-6)).any() {
        return Err(format!(
            "{call} is {got}: a transmittance is a fraction of the light in each channel, in [0, 1] ({TRANSMITTANCE_HINT})"
        ));
    }
    let zero = f.transmittance(0.0, &volume_material(rho));
    compare_vec3(
        &transmittance_call(0.0, rho),
        zero,
        Vec3::ONE,
        1e-6,
        0.0,
    )
    .map_err(|e| format!("{e}: over no distance nothing is absorbed, even where ρ_d = 0 (mind 0·∞) ({TRANSMITTANCE_HINT})"))?;
    // Halfway and the rest: T(d) = T(d/2)·T(d/2) and T(d) = T(d/4)·T(3d/4).
    for (a, b) in [(0.5 * d, 0.5 * d), (0.25 * d, 0.75 * d)] {
        let (ta, tb) = (
            f.transmittance(a, &volume_material(rho)),
            f.transmittance(b, &volume_material(rho)),
        );
        compare_vec3(
            &format!("{call}, against transmittance({a}) · transmittance({b}) = {ta} · {tb}"),
            got,
            ta * tb,
            1e-6,
            1e-3,
        )
        .map_err(|e| {
            format!("{e}: the light that crosses d = a + b crosses a, then b: T(a + b) = T(a)·T(b) ({TRANSMITTANCE_HINT})")
        })?;
    }
    // Each channel absorbs on its own: the same colour channel in a grey material.
    for (i, channel) in ["red", "green", "blue"].iter().enumerate() {
        let grey = Vec3::splat(rho[i]);
        let alone = f.transmittance(d, &volume_material(grey));
        compare_f32(
            &format!("the {channel} channel of {call}"),
            got[i],
            alone[i],
            1e-6,
            1e-4,
        )
        .map_err(|e| {
            format!("{e}, its value in a grey material of the same {channel} ({}): each channel is absorbed by its own coefficient ({TRANSMITTANCE_HINT})", transmittance_call(d, grey))
        })?;
    }
    if let Some(expected) = expected {
        compare_vec3(&call, got, expected, 1e-6, 1e-3)
            .map_err(|e| format!("{e} ({TRANSMITTANCE_HINT})"))?;
    }
    Ok(())
}

fn exercise_10_5(s: &Arc<dyn Fresnel>, ctx: &LabContext) -> Result<(), String> {
    let key = ctx.key_code::<dyn Fresnel>();
    for_all(600, transmittance_strategy(), |(d, rho)| {
        let expected = key
            .as_ref()
            .map(|k| k.transmittance(d, &volume_material(rho)));
        check_transmittance(s.as_ref(), (d, rho), expected)
    })?;
    // A white medium absorbs nothing; a black one everything; absorption grows with distance.
    for_all(
        200,
        (distance_strategy(), distance_strategy(), colour_strategy()),
        |(d1, d2, rho)| {
            let white = f32::max(d1, d2);
            let t = s.transmittance(white, &volume_material(Vec3::ONE));
            compare_vec3(
                &format!("{} (white)", transmittance_call(white, Vec3::ONE)),
                t,
                Vec3::ONE,
                1e-6,
                0.0,
            )
            .map_err(|e| {
                format!("{e}: a medium of ρ_d = 1 absorbs nothing, σ = 0 ({TRANSMITTANCE_HINT})")
            })?;
            if white >= 1e-3 {
                let t = s.transmittance(white, &volume_material(Vec3::ZERO));
                if !t.is_finite() || t.max_element() > 1e-3 {
                    return Err(format!(
                        "{} is {t}: a medium of ρ_d = 0 absorbs (almost) everything ({TRANSMITTANCE_HINT})",
                        transmittance_call(white, Vec3::ZERO)
                    ));
                }
            }
            let (near, far) = (d1.min(d2), d1.max(d2));
            let (tn, tf) = (
                s.transmittance(near, &volume_material(rho)),
                s.transmittance(far, &volume_material(rho)),
            );
            if tf.cmpgt(tn * (1.0 + 1e-5) + Vec3::splat(1e-7)).any() || tf.is_nan() {
                return Err(format!(
                    "{} is {tf}, more than {} = {tn}: the farther light travels in the medium, the less of it gets through ({TRANSMITTANCE_HINT})",
                    transmittance_call(far, rho),
                    transmittance_call(near, rho)
                ));
            }
            Ok(())
        },
    )?;
    let golden: GoldenFile<TransmittanceInput, Vec3> = ctx.golden(GOLDEN_TRANSMITTANCE)?;
    for case in &golden.cases {
        check_transmittance(s.as_ref(), case.input, Some(case.expected))?;
    }
    Part::Transmittance.check_snapshots(s, ctx)
}

// ---------------------------------------------------------------------------------------------
// Snapshots

/// Which student function a snapshot exercises; the rest of the pipeline is the base.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// Exercise 10.1.
    RS,
    /// Exercise 10.2.
    RP,
    /// Exercise 10.3.
    R,
    /// Exercise 10.4.
    Reflectance,
    /// Exercise 10.5.
    Transmittance,
}

/// The scenes of lab 10's snapshots.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shot {
    /// The built-in default scene: its glass sphere (illum 4) with Fresnel weights.
    Default,
    /// The default scene with the glass sphere glossy (illum 5, as in lab 04's snapshot).
    Glossy,
    /// The default scene with the glass sphere an absorbing volume (illum 11).
    Volume,
    /// The default scene with the glass sphere the Week 11 worksheet's absorbing glossy volume
    /// (illum 12, Kd 0.8 0.1 0.3).
    GlossyVolume,
}

impl Shot {
    /// Every snapshot scene.
    pub const ALL: [Shot; 4] = [
        Shot::Default,
        Shot::Glossy,
        Shot::Volume,
        Shot::GlossyVolume,
    ];
}

impl SnapshotScene for Shot {
    fn name(self) -> &'static str {
        match self {
            Shot::Default => "default-fresnel",
            Shot::Glossy => "default-glossy-fresnel",
            Shot::Volume => "default-volume",
            Shot::GlossyVolume => "default-glossy-volume",
        }
    }

    fn scene(self) -> Result<Scene, raylab_core::Error> {
        match self {
            Shot::Default => builtin_scene("default"),
            Shot::Glossy => glossy_default_scene(),
            Shot::Volume => volume_default_scene(IllumModel::AbsorbingVolume),
            Shot::GlossyVolume => volume_default_scene(IllumModel::GlossyVolume),
        }
    }
}

/// The default scene with its glass sphere an absorbing volume of the worksheet's colour
/// ([`WORKSHEET_ABSORPTION_COLOUR`]): `illum 11` (transparent) or 12 (glossy, a white Phong
/// highlight of shininess 100).
pub fn volume_default_scene(illum: IllumModel) -> Result<Scene, raylab_core::Error> {
    let mut scene = builtin_scene("default")?;
    scene.name = match illum {
        IllumModel::GlossyVolume => "default-glossy-volume".into(),
        _ => "default-volume".into(),
    };
    for m in scene
        .materials
        .iter_mut()
        .filter(|m| m.illum == IllumModel::Transparent)
    {
        m.illum = illum;
        m.diffuse = WORKSHEET_ABSORPTION_COLOUR;
        m.specular = Vec3::ONE;
        m.shininess = 100.0;
    }
    Ok(scene)
}

impl PartSnapshots for Part {
    type Contract = dyn Fresnel;
    type Shot = Shot;

    const PARTS: &'static [(Part, &'static [Shot])] = &[
        // The renderer reaches the coefficients only through the student's
        // `fresnel_reflectance` (Exercise 10.4), whose images check them together.
        (Part::RS, &[]),
        (Part::RP, &[]),
        (Part::R, &[]),
        (Part::Reflectance, &[Shot::Default, Shot::Glossy]),
        (Part::Transmittance, &[Shot::Volume, Shot::GlossyVolume]),
    ];
    const SETTINGS: RenderSettings = SNAPSHOT_SETTINGS;
    const MAX_DEPTH: u32 = SNAPSHOT_MAX_DEPTH;
    const TOLERANCE: PixelTolerance = SNAPSHOT_TOLERANCE;

    fn function(self) -> &'static str {
        match self {
            Part::RS => "fresnel_r_s",
            Part::RP => "fresnel_r_p",
            Part::R => "fresnel_R",
            Part::Reflectance => "fresnel_reflectance",
            Part::Transmittance => "transmittance",
        }
    }
}
