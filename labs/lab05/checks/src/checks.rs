//! Lab 05's exercises and their checks.
//!
//! The closed-form exercises (5.1–5.7) are checked in three ways, in this order (the first
//! failure is reported):
//!
//! 1. the physical laws as properties of the function alone, on inputs over many orders of
//!    magnitude drawn by proptest from a fixed seed: linearity in power or radiance, the
//!    inverse-square law, `Φ = B·A`, the relations between the quantities one call returns;
//!    for the quadrature of 5.7 also its sums on coarse grids (1–4 steps), against the
//!    midpoint rule's own sums there, computed here;
//! 2. where the answer key is present ([`LabContext::key`]), the student's function against
//!    the key's on the same random inputs;
//! 3. the golden cases (`labs/lab05/golden/*.json`), recorded from the reference by
//!    `raylab golden`, the worksheet's questions first: a mismatch on one of them names the
//!    question.
//!
//! The Monte Carlo exercises (5.8, 5.9) are checked statistically against the closed-form
//! irradiance of a Lambertian polygon (Lambert's formula, lab 03's
//! [`irradiance_polygon`], on the part of the light above the receiver's horizon): the mean of
//! many estimates within a Šidák-corrected z-bound of the exact value, at scales from 10⁻⁴ to
//! 10³ m, on lights seen from behind, edge-on and partly below the horizon, sheared
//! parallelograms and strongly tilted receivers as well as plain rectangles; the generator
//! advanced; and the variance of the estimates against the reference's, recorded in golden
//! data.
//!
//! No check calls another exercise's function: each exercise is judged alone.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::DVec3;
use proptest::prelude::*;
use serde::{Deserialize, Serialize};

use contracts::lab05::{
    DiffuseEmitter, Observation, Radiometry, Receiver, RectangleLight, SphericalBulb,
    luminous_efficiency,
};
use grading::radiometry::irradiance_polygon;
use grading::stats::{normal_two_sided_quantile, sidak};
use grading::{Exercise, GoldenFile, LabContext, for_all};
use raylab_core::sampling::Rng;

/// Golden file of Exercise 5.1.
pub const GOLDEN_PHOTONS: &str = "photons_per_second.json";
/// Golden file of Exercise 5.2.
pub const GOLDEN_BULB: &str = "spherical_bulb.json";
/// Golden file of Exercise 5.3.
pub const GOLDEN_OBSERVATION: &str = "observe_point_source.json";
/// Golden file of Exercise 5.4.
pub const GOLDEN_ILLUMINANCE: &str = "illuminance_lux.json";
/// Golden file of Exercise 5.5.
pub const GOLDEN_EQUIVALENT: &str = "equivalent_intensity_cd.json";
/// Golden file of Exercise 5.6.
pub const GOLDEN_EMITTER: &str = "diffuse_emitter.json";
/// Golden file of Exercise 5.7.
pub const GOLDEN_RADIOSITY: &str = "radiosity_from_radiance.json";
/// Golden file of Exercises 5.8 and 5.9: the variance of the reference's estimators.
pub const GOLDEN_VARIANCE: &str = "irradiance_variance.json";

/// Relative tolerance of the closed-form answers against golden cases and the key: the
/// rounding of another order of the same operations, far below any wrong constant (the
/// worksheet's `c = 3·10⁸ m/s` is 7·10⁻⁴ off).
pub const REL_TOL: f64 = 1e-9;
/// Relative tolerance of the properties (exact laws, up to rounding).
pub const LAW_TOL: f64 = 1e-9;
/// Relative tolerance of the hemisphere integral of 5.7 against the reference's at the same
/// `steps` (≥ 64): the midpoint rule's error there is below 10⁻⁴.
pub const QUADRATURE_TOL: f64 = 1e-3;
/// Random inputs per property.
const CASES: u32 = 128;

/// Input of 5.1: electrical power (W), efficiency, wavelength (nm).
pub type PhotonsInput = (f64, f64, f64);
/// Input of 5.2: voltage (V), current (A), diameter (m), duration (s).
pub type BulbInput = (f64, f64, f64, f64);
/// Input of 5.3: flux (W), distance (m), pupil diameter (m).
pub type ObservationInput = (f64, f64, f64);
/// Input of 5.4: irradiance (W/m²), wavelength (nm).
pub type IlluminanceInput = (f64, f64);
/// Input of 5.5: known intensity (cd), known distance (m), unknown distance (m).
pub type EquivalentInput = (f64, f64, f64);
/// Input of 5.6: radiance (W/(m² sr)), area (m²).
pub type EmitterInput = (f64, f64);
/// Input of 5.7: the radiance profile and the number of θ steps.
pub type RadiosityInput = (RadianceProfile, u32);

/// The worksheet's question 1 (docs/lab05.md).
pub const WORKSHEET_PHOTONS: PhotonsInput = (25.0, 0.2, 500.0);
/// Question 2: the 2.4 V, 0.7 A bulb of 1 cm, over 5 minutes.
pub const WORKSHEET_BULB: BulbInput = (2.4, 0.7, 0.01, 300.0);
/// Question 3: that bulb's 1.68 W seen from 1 m through a 6 mm pupil.
pub const WORKSHEET_OBSERVATION: ObservationInput = (1.68, 1.0, 0.006);
/// Question 4: the 200 W, 20 % bulb 2 m above the table (its irradiance is 5.3's answer).
pub const WORKSHEET_TABLE: ObservationInput = (40.0, 2.0, 0.0);
/// Question 4: the table's irradiance 40 W/(4π·(2 m)²) in red light of 650 nm.
pub const WORKSHEET_ILLUMINANCE: IlluminanceInput = (40.0 / (16.0 * PI), 650.0);
/// Question 5: 40 cd at 35 cm against the unknown lamp at 65 cm.
pub const WORKSHEET_EQUIVALENT: EquivalentInput = (40.0, 0.35, 0.65);
/// Question 6: radiance 5000 W/(m² sr) from 10 cm × 10 cm.
pub const WORKSHEET_EMITTER: EmitterInput = (5000.0, 0.01);
/// Question 7: radiance 6000 W/(m² sr) in every direction of the hemisphere.
pub const WORKSHEET_RADIOSITY: RadiosityInput = (
    RadianceProfile {
        constant: 6000.0,
        cosine: 0.0,
        cosine_squared: 0.0,
        azimuthal: 0.0,
    },
    256,
);

/// A radiance distribution over the hemisphere for Exercise 5.7:
/// `L(θ, φ) = constant + cosine·cos θ + cosine_squared·cos² θ + azimuthal·sin θ·cos φ`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct RadianceProfile {
    /// Uniform part (a diffuse surface), W/(m² sr).
    pub constant: f64,
    /// Coefficient of `cos θ`.
    pub cosine: f64,
    /// Coefficient of `cos² θ`.
    pub cosine_squared: f64,
    /// Coefficient of `sin θ cos φ` (tilted lobe; integrates to zero against `cos θ`).
    pub azimuthal: f64,
}

impl RadianceProfile {
    /// `L(θ, φ)`.
    pub fn radiance(&self, theta: f64, phi: f64) -> f64 {
        let c = theta.cos();
        self.constant
            + self.cosine * c
            + self.cosine_squared * c * c
            + self.azimuthal * theta.sin() * phi.cos()
    }

    /// The profile with every coefficient times `k`.
    fn scaled(&self, k: f64) -> Self {
        Self {
            constant: k * self.constant,
            cosine: k * self.cosine,
            cosine_squared: k * self.cosine_squared,
            azimuthal: k * self.azimuthal,
        }
    }
}

/// This lab.
pub const LAB: course::LabId = course::LabId::of(5);

/// The exercises of lab 05 (`labs/lab05/exercises.toml`), each with its check.
pub fn exercises() -> Vec<Exercise<dyn Radiometry>> {
    grading::exercises(
        LAB,
        grading::checks![
            exercise_5_1,
            exercise_5_2,
            exercise_5_3,
            exercise_5_4,
            exercise_5_5,
            exercise_5_6,
            exercise_5_7,
            exercise_5_8,
            exercise_5_9
        ],
    )
}

// ---------------------------------------------------------------------------------------------
// Shared pieces

/// `Ok` when `got` is within `rel·|expected|` of `expected` (NaN never is).
fn rel_close(what: &str, got: f64, expected: f64, rel: f64) -> Result<(), String> {
    if (got - expected).abs() <= rel * expected.abs() {
        Ok(())
    } else {
        Err(format!(
            "{what} is {got:e}, expected {expected:e} (relative error {:.2e}, at most {rel:.0e} allowed)",
            ((got - expected) / expected).abs()
        ))
    }
}

/// A magnitude `10^e`, `e` uniform in `[lo, hi]`: inputs over many orders of magnitude.
pub fn magnitude(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    (lo..hi).prop_map(|e| 10f64.powf(e))
}

/// A visible wavelength, nm.
pub fn wavelength() -> impl Strategy<Value = f64> + Clone {
    380.0..780.0f64
}

/// Inputs of 5.1.
pub fn photons_strategy() -> impl Strategy<Value = PhotonsInput> + Clone {
    (magnitude(-3.0, 4.0), 0.01..1.0f64, wavelength())
}
/// Inputs of 5.2.
pub fn bulb_strategy() -> impl Strategy<Value = BulbInput> + Clone {
    (
        magnitude(-1.0, 3.0),
        magnitude(-3.0, 2.0),
        magnitude(-4.0, 0.0),
        magnitude(-2.0, 5.0),
    )
}
/// Inputs of 5.3.
pub fn observation_strategy() -> impl Strategy<Value = ObservationInput> + Clone {
    (
        magnitude(-3.0, 4.0),
        magnitude(-2.0, 3.0),
        magnitude(-4.0, -1.0),
    )
}
/// Inputs of 5.4.
pub fn illuminance_strategy() -> impl Strategy<Value = IlluminanceInput> + Clone {
    (magnitude(-4.0, 4.0), wavelength())
}
/// Inputs of 5.5.
pub fn equivalent_strategy() -> impl Strategy<Value = EquivalentInput> + Clone {
    (
        magnitude(-1.0, 4.0),
        magnitude(-2.0, 2.0),
        magnitude(-2.0, 2.0),
    )
}
/// Inputs of 5.6.
pub fn emitter_strategy() -> impl Strategy<Value = EmitterInput> + Clone {
    (magnitude(-2.0, 6.0), magnitude(-6.0, 2.0))
}
/// Inputs of 5.7.
pub fn radiosity_strategy() -> impl Strategy<Value = RadiosityInput> + Clone {
    (
        (0.0..1e4f64, -1e3..1e3f64, 0.0..1e3f64, -1e3..1e3f64),
        prop::sample::select(vec![64u32, 96, 128]),
    )
        .prop_map(|((constant, cosine, cosine_squared, azimuthal), steps)| {
            (
                RadianceProfile {
                    constant: constant + cosine.abs() + azimuthal.abs(),
                    cosine,
                    cosine_squared,
                    azimuthal,
                },
                steps,
            )
        })
}

/// Checks `student` against the golden cases of `file`: `compare(got, expected)`; a failure
/// on the worksheet's input names the worksheet question.
fn check_golden<I, O>(
    ctx: &LabContext,
    file: &str,
    worksheet: &[(I, &str)],
    student: impl Fn(&I) -> O,
    compare: impl Fn(&O, &O) -> Result<(), String>,
) -> Result<(), String>
where
    I: Serialize + serde::de::DeserializeOwned + PartialEq + std::fmt::Debug,
    O: Serialize + serde::de::DeserializeOwned,
{
    let golden: GoldenFile<I, O> = ctx.golden(file)?;
    for case in &golden.cases {
        let got = student(&case.input);
        compare(&got, &case.expected).map_err(|e| {
            match worksheet.iter().find(|(i, _)| *i == case.input) {
                Some((_, q)) => format!("on the worksheet's {q} (input {:?}): {e}", case.input),
                None => format!("on the golden case {:?}: {e}", case.input),
            }
        })?;
    }
    Ok(())
}

/// With the key present, `compare(student, key)` on `cases` random inputs of `strategy`.
fn check_against_key<S: Strategy>(
    ctx: &LabContext,
    cases: u32,
    strategy: S,
    compare: impl Fn(&dyn Radiometry, S::Value) -> Result<(), String>,
) -> Result<(), String>
where
    S::Value: std::fmt::Debug,
{
    match ctx.key() {
        Some(key) => {
            let key = key.code::<dyn contracts::lab05::Radiometry>();
            for_all(cases, strategy, |input| compare(key.as_ref(), input))
        }
        None => Ok(()),
    }
}

// ---------------------------------------------------------------------------------------------
// 5.1–5.6: closed forms

fn exercise_5_1(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    let n = |(p, eta, l): PhotonsInput| s.photons_per_second(p, eta, l);
    for_all(CASES, photons_strategy(), |(p, eta, l)| {
        let base = n((p, eta, l));
        let call = format!("photons_per_second({p:e} W, {eta}, {l} nm)");
        if !(base.is_finite() && base > 0.0) {
            return Err(format!(
                "{call} = {base:e}: a photon rate is finite and positive"
            ));
        }
        rel_close(
            &format!("{call} with twice the power"),
            n((2.0 * p, eta, l)),
            2.0 * base,
            LAW_TOL,
        )
        .map_err(|e| format!("{e}: the rate is proportional to the power"))?;
        rel_close(
            &format!("{call} with half the efficiency"),
            n((p, 0.5 * eta, l)),
            0.5 * base,
            LAW_TOL,
        )
        .map_err(|e| format!("{e}: the rate is proportional to the light output ηP"))?;
        rel_close(&format!("{call} at half the wavelength"), n((p, eta, 0.5 * l)), 0.5 * base, LAW_TOL)
            .map_err(|e| {
                format!("{e}: a photon of half the wavelength carries twice the energy (q = hc/λ), so half as many carry the same power")
            })
    })?;
    check_against_key(ctx, CASES, photons_strategy(), |key, (p, eta, l)| {
        rel_close(
            &format!("photons_per_second({p:e} W, {eta}, {l} nm)"),
            n((p, eta, l)),
            key.photons_per_second(p, eta, l),
            REL_TOL,
        )
    })?;
    check_golden(
        ctx,
        GOLDEN_PHOTONS,
        &[(WORKSHEET_PHOTONS, "question 1 (25 W, 20 %, 500 nm)")],
        |&i| n(i),
        |got, expected| {
            rel_close("the photon rate", *got, *expected, REL_TOL).map_err(|e| {
                format!(
                    "{e} — use PLANCK_J_S and SPEED_OF_LIGHT_M_PER_S, and the wavelength in metres"
                )
            })
        },
    )
}

fn compare_bulb(got: &SphericalBulb, expected: &SphericalBulb, rel: f64) -> Result<(), String> {
    rel_close(
        "the radiant flux Φ (W)",
        got.radiant_flux_w,
        expected.radiant_flux_w,
        rel,
    )?;
    rel_close(
        "the radiant intensity I (W/sr)",
        got.radiant_intensity_w_per_sr,
        expected.radiant_intensity_w_per_sr,
        rel,
    )?;
    rel_close(
        "the radiant exitance M (W/m²)",
        got.radiant_exitance_w_per_m2,
        expected.radiant_exitance_w_per_m2,
        rel,
    )?;
    rel_close(
        "the emitted energy Q (J)",
        got.emitted_energy_j,
        expected.emitted_energy_j,
        rel,
    )
}

fn exercise_5_2(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, bulb_strategy(), |(u, i, d, t)| {
        let b = s.spherical_bulb(u, i, d, t);
        let call = format!("spherical_bulb({u:e} V, {i:e} A, {d:e} m, {t:e} s) = {b:?}");
        let flux = b.radiant_flux_w;
        if !(flux.is_finite() && flux > 0.0) {
            return Err(format!(
                "{call}: the flux of a lamp drawing power is finite and positive"
            ));
        }
        rel_close("4π·I", 4.0 * PI * b.radiant_intensity_w_per_sr, flux, LAW_TOL).map_err(|e| {
            format!("{call}: {e} (Φ): an isotropic source spreads its flux over the 4π sr of the whole sphere of directions, I = Φ/4π")
        })?;
        rel_close("M·(surface area of the bulb, 4π(d/2)²)", b.radiant_exitance_w_per_m2 * PI * d * d, flux, LAW_TOL).map_err(|e| {
            format!("{call}: {e} (Φ): the exitance is the flux per unit area of the bulb's own surface, a sphere of radius d/2 — not of a unit sphere")
        })?;
        rel_close("Q/t", b.emitted_energy_j / t, flux, LAW_TOL)
            .map_err(|e| format!("{call}: {e} (Φ): energy is flux times time"))?;
        let twice = s.spherical_bulb(2.0 * u, i, d, t).radiant_flux_w;
        rel_close("the flux at twice the voltage", twice, 2.0 * flux, LAW_TOL).map_err(|e| {
            format!("{call}: {e}: the flux of an ideal bulb is its electrical power")
        })?;
        let twice = s.spherical_bulb(u, 2.0 * i, d, t).radiant_flux_w;
        rel_close("the flux at twice the current", twice, 2.0 * flux, LAW_TOL)
            .map_err(|e| format!("{call}: {e}: the flux of an ideal bulb is its electrical power"))
    })?;
    check_against_key(ctx, CASES, bulb_strategy(), |key, (u, i, d, t)| {
        compare_bulb(
            &s.spherical_bulb(u, i, d, t),
            &key.spherical_bulb(u, i, d, t),
            REL_TOL,
        )
        .map_err(|e| format!("spherical_bulb({u:e} V, {i:e} A, {d:e} m, {t:e} s): {e}"))
    })?;
    check_golden(
        ctx,
        GOLDEN_BULB,
        &[(WORKSHEET_BULB, "question 2 (2.4 V, 0.7 A, 1 cm, 5 minutes)")],
        |&(u, i, d, t)| s.spherical_bulb(u, i, d, t),
        |got, expected| compare_bulb(got, expected, REL_TOL),
    )
}

fn compare_observation(got: &Observation, expected: &Observation) -> Result<(), String> {
    rel_close(
        "the irradiance E (W/m²)",
        got.irradiance_w_per_m2,
        expected.irradiance_w_per_m2,
        REL_TOL,
    )?;
    rel_close(
        "the power through the pupil (W)",
        got.pupil_power_w,
        expected.pupil_power_w,
        REL_TOL,
    )
}

fn exercise_5_3(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, observation_strategy(), |(phi, r, d)| {
        let o = s.observe_point_source(phi, r, d);
        let call = format!("observe_point_source({phi:e} W, {r:e} m, {d:e} m) = {o:?}");
        let e = o.irradiance_w_per_m2;
        if !(e.is_finite() && e > 0.0) {
            return Err(format!("{call}: the irradiance is finite and positive"));
        }
        let far = s.observe_point_source(phi, 2.0 * r, d).irradiance_w_per_m2;
        rel_close(
            "the irradiance at twice the distance",
            far,
            0.25 * e,
            LAW_TOL,
        )
        .map_err(|e| format!("{call}: {e}: the inverse-square law, E ∝ 1/r²"))?;
        rel_close("E·4πr²", e * 4.0 * PI * r * r, phi, LAW_TOL).map_err(|e| {
            format!(
                "{call}: {e} (Φ): the whole flux crosses the sphere of radius r around the source"
            )
        })?;
        rel_close("the pupil's power / E", o.pupil_power_w / e, PI * 0.25 * d * d, LAW_TOL).map_err(|e| {
            format!("{call}: {e} (the pupil's area π(d/2)²): the power through a small aperture facing the source is E times its area — mind diameter against radius")
        })
    })?;
    check_against_key(ctx, CASES, observation_strategy(), |key, (phi, r, d)| {
        compare_observation(
            &s.observe_point_source(phi, r, d),
            &key.observe_point_source(phi, r, d),
        )
        .map_err(|e| format!("observe_point_source({phi:e} W, {r:e} m, {d:e} m): {e}"))
    })?;
    check_golden(
        ctx,
        GOLDEN_OBSERVATION,
        &[
            (
                WORKSHEET_OBSERVATION,
                "question 3 (1.68 W at 1 m, 6 mm pupil)",
            ),
            (
                WORKSHEET_TABLE,
                "question 4 (40 W of light 2 m above the table)",
            ),
        ],
        |&(phi, r, d)| s.observe_point_source(phi, r, d),
        compare_observation,
    )
}

fn exercise_5_4(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, illuminance_strategy(), |(e, l)| {
        let ev = s.illuminance_lux(e, l);
        let call = format!("illuminance_lux({e:e} W/m², {l} nm) = {ev:e}");
        rel_close(
            "the illuminance of twice the irradiance",
            s.illuminance_lux(2.0 * e, l),
            2.0 * ev,
            LAW_TOL,
        )
        .map_err(|e| format!("{call}: {e}: illuminance is proportional to irradiance"))?;
        let peak = s.illuminance_lux(e, 555.0);
        rel_close("its ratio to the illuminance at 555 nm", ev / peak, luminous_efficiency(l), LAW_TOL).map_err(|e| {
            format!("{call}: {e} (V(λ)/V(555 nm) = luminous_efficiency(λ)): the eye weighs each wavelength by the CIE curve V(λ), from the contract's table")
        })
    })?;
    rel_close(
        "illuminance_lux(1 W/m², 555 nm)",
        s.illuminance_lux(1.0, 555.0),
        contracts::lab05::PEAK_LUMINOUS_EFFICACY_LM_PER_W,
        LAW_TOL,
    )
    .map_err(|e| {
        format!("{e}: at the peak of V(λ) one watt is 683 lumens (PEAK_LUMINOUS_EFFICACY_LM_PER_W)")
    })?;
    check_against_key(ctx, CASES, illuminance_strategy(), |key, (e, l)| {
        rel_close(
            &format!("illuminance_lux({e:e} W/m², {l} nm)"),
            s.illuminance_lux(e, l),
            key.illuminance_lux(e, l),
            REL_TOL,
        )
    })?;
    check_golden(
        ctx,
        GOLDEN_ILLUMINANCE,
        &[(
            WORKSHEET_ILLUMINANCE,
            "question 4 (the table's irradiance, 650 nm)",
        )],
        |&(e, l)| s.illuminance_lux(e, l),
        |got, expected| rel_close("the illuminance (lx)", *got, *expected, REL_TOL),
    )
}

fn exercise_5_5(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, equivalent_strategy(), |(i, rk, ru)| {
        let iu = s.equivalent_intensity_cd(i, rk, ru);
        let call = format!("equivalent_intensity_cd({i:e} cd, {rk:e} m, {ru:e} m) = {iu:e}");
        rel_close("I_unknown/r_unknown²", iu / (ru * ru), i / (rk * rk), LAW_TOL).map_err(|e| {
            format!("{call}: {e} (I_known/r_known²): the screen is lit equally when E = I/r² is equal on both sides")
        })?;
        rel_close(
            "the answer with both distances ×10",
            s.equivalent_intensity_cd(i, 10.0 * rk, 10.0 * ru),
            iu,
            LAW_TOL,
        )
        .map_err(|e| format!("{call}: {e}: only the ratio of the distances matters"))
    })?;
    check_against_key(ctx, CASES, equivalent_strategy(), |key, (i, rk, ru)| {
        rel_close(
            &format!("equivalent_intensity_cd({i:e} cd, {rk:e} m, {ru:e} m)"),
            s.equivalent_intensity_cd(i, rk, ru),
            key.equivalent_intensity_cd(i, rk, ru),
            REL_TOL,
        )
    })?;
    check_golden(
        ctx,
        GOLDEN_EQUIVALENT,
        &[(
            WORKSHEET_EQUIVALENT,
            "question 5 (40 cd at 35 cm, the other lamp at 65 cm)",
        )],
        |&(i, rk, ru)| s.equivalent_intensity_cd(i, rk, ru),
        |got, expected| rel_close("the unknown intensity (cd)", *got, *expected, REL_TOL),
    )
}

fn compare_emitter(got: &DiffuseEmitter, expected: &DiffuseEmitter) -> Result<(), String> {
    rel_close(
        "the flux Φ (W)",
        got.radiant_flux_w,
        expected.radiant_flux_w,
        REL_TOL,
    )?;
    rel_close(
        "the radiosity B (W/m²)",
        got.radiosity_w_per_m2,
        expected.radiosity_w_per_m2,
        REL_TOL,
    )
}

fn exercise_5_6(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    for_all(CASES, emitter_strategy(), |(l, a)| {
        let e = s.diffuse_emitter(l, a);
        let call = format!("diffuse_emitter({l:e} W/(m² sr), {a:e} m²) = {e:?}");
        rel_close("Φ", e.radiant_flux_w, e.radiosity_w_per_m2 * a, LAW_TOL)
            .map_err(|e| format!("{call}: {e} (B·A): the flux is the radiosity times the area"))?;
        let other = s.diffuse_emitter(l, 3.0 * a);
        rel_close(
            "the radiosity of an emitter three times as large",
            other.radiosity_w_per_m2,
            e.radiosity_w_per_m2,
            LAW_TOL,
        )
        .map_err(|e| {
            format!("{call}: {e}: radiosity is per unit area, so it does not depend on the area")
        })?;
        let brighter = s.diffuse_emitter(2.0 * l, a);
        rel_close(
            "the flux at twice the radiance",
            brighter.radiant_flux_w,
            2.0 * e.radiant_flux_w,
            LAW_TOL,
        )
        .map_err(|e| format!("{call}: {e}: flux and radiosity are proportional to the radiance"))
    })?;
    check_against_key(ctx, CASES, emitter_strategy(), |key, (l, a)| {
        compare_emitter(&s.diffuse_emitter(l, a), &key.diffuse_emitter(l, a))
            .map_err(|e| format!("diffuse_emitter({l:e} W/(m² sr), {a:e} m²): {e}"))
    })?;
    check_golden(
        ctx,
        GOLDEN_EMITTER,
        &[(
            WORKSHEET_EMITTER,
            "question 6 (5000 W/(m² sr) from 10 cm × 10 cm)",
        )],
        |&(l, a)| s.diffuse_emitter(l, a),
        compare_emitter,
    )
}

// ---------------------------------------------------------------------------------------------
// 5.7: the hemisphere integral

/// The student's radiosity of a profile.
fn radiosity_of(s: &dyn Radiometry, (profile, steps): &RadiosityInput) -> f64 {
    s.radiosity_from_radiance(&|t, p| profile.radiance(t, p), *steps)
}

/// The coarse grids of the 5.7 check, where one cell more or less, or a cell's value taken at
/// its end instead of its middle, changes the sum by far more than rounding.
pub const COARSE_STEPS: [u32; 4] = [1, 2, 3, 4];

/// A radiance profile of the coarse-grid check: what it is, `L(θ, φ)`, and the exact
/// `∫ L cos θ dω` over the hemisphere.
type CoarseProfile = (&'static str, fn(f64, f64) -> f64, f64);

/// The profiles of the coarse-grid check: uniform, weighted towards the normal (the uniform
/// one alone is symmetric about θ = π/4 in `cos θ sin θ dθ`, which hides a θ taken at the
/// cells' ends), and one lit on one side of the azimuth only, `φ ∈ (0, π)` (the random
/// profiles' `cos φ` is symmetric about `φ = 0` and `φ = π`, which hides a half turn of φ
/// counted twice): `∫ max(0, sin φ) dφ = 2`, `∫ sin²θ cos θ dθ = 1/3`.
pub fn coarse_profiles() -> [CoarseProfile; 4] {
    [
        ("L = 1", |_, _| 1.0, PI),
        ("L = cos θ", |t, _| t.cos(), 2.0 * PI / 3.0),
        ("L = cos² θ", |t, _| t.cos().powi(2), 0.5 * PI),
        (
            "L = 1 + sin θ·max(0, sin φ)",
            |t, p| 1.0 + t.sin() * p.sin().max(0.0),
            PI + 2.0 / 3.0,
        ),
    ]
}

/// The rule the docs prescribe, computed here: the midpoint rule with `steps` intervals in
/// `θ ∈ [0, π/2]` and `4·steps` in `φ ∈ [0, 2π)` of `L cos θ sin θ`.
pub fn midpoint_in_theta(radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
    let (m, k) = (steps as usize, 4 * steps as usize);
    let (dt, dp) = (0.5 * PI / m as f64, 2.0 * PI / k as f64);
    let mut sum = 0.0;
    for i in 0..m {
        let t = (i as f64 + 0.5) * dt;
        for j in 0..k {
            sum += radiance(t, (j as f64 + 0.5) * dp) * t.cos() * t.sin() * dt * dp;
        }
    }
    sum
}

/// The docs' alternative: the midpoint rule in `μ = cos θ ∈ [0, 1]` (`dω = dμ dφ`) with
/// `steps` intervals, and `4·steps` in φ, of `L μ`.
pub fn midpoint_in_mu(radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
    let (m, k) = (steps as usize, 4 * steps as usize);
    let (dmu, dp) = (1.0 / m as f64, 2.0 * PI / k as f64);
    let mut sum = 0.0;
    for i in 0..m {
        let mu = (i as f64 + 0.5) * dmu;
        for j in 0..k {
            sum += radiance(mu.acos(), (j as f64 + 0.5) * dp) * mu * dmu * dp;
        }
    }
    sum
}

/// At 1–4 steps the midpoint rule's own error is large and known: the student's sum must be
/// the prescribed rule's sum there (in θ, or in μ = cos θ), or at least as accurate. At 64
/// steps and more a ring left out or a half step forgotten changes the sum by less than the
/// quadrature's tolerance; here by tens of per cent.
fn check_coarse_grids(s: &dyn Radiometry) -> Result<(), String> {
    for (what, radiance, exact) in coarse_profiles() {
        for steps in COARSE_STEPS {
            let b = s.radiosity_from_radiance(&radiance, steps);
            let theta = midpoint_in_theta(&radiance, steps);
            let mu = midpoint_in_mu(&radiance, steps);
            let same = |rule: f64| (b - rule).abs() <= REL_TOL * rule.abs();
            let as_accurate = (b - exact).abs() <= (theta - exact).abs() * (1.0 + REL_TOL);
            if !(same(theta) || same(mu) || as_accurate) {
                return Err(format!(
                    "radiosity_from_radiance({what}, steps = {steps}) = {b:e}, but the midpoint rule with {steps} interval(s) in θ and {} in φ gives {theta:e} (in μ = cos θ: {mu:e}; exact ∫ L cos θ dω = {exact:e}): another rule must be at least as accurate, and this is off by {:.1}% of the exact value against the rule's {:.1}% — count the cells: θ_i = (i + ½)·Δθ for i = 0 … steps − 1 with Δθ = (π/2)/steps, φ_j = (j + ½)·Δφ for j = 0 … 4·steps − 1 with Δφ = 2π/(4·steps)",
                    4 * steps,
                    100.0 * (b - exact).abs() / exact,
                    100.0 * (theta - exact).abs() / exact,
                ));
            }
        }
    }
    Ok(())
}

fn exercise_5_7(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    let s = s.as_ref();
    for_all(CASES / 4, radiosity_strategy(), |(profile, steps)| {
        let b = radiosity_of(s, &(profile, steps));
        let call = format!("radiosity_from_radiance({profile:?}, steps = {steps}) = {b:e}");
        if !b.is_finite() {
            return Err(format!("{call}: not finite"));
        }
        let twice = radiosity_of(s, &(profile.scaled(2.0), steps));
        rel_close(
            "the radiosity of twice the radiance",
            twice,
            2.0 * b,
            LAW_TOL,
        )
        .map_err(|e| format!("{call}: {e}: the integral is linear in L"))?;
        let lobe = RadianceProfile {
            constant: 0.0,
            cosine: 0.0,
            cosine_squared: 0.0,
            azimuthal: profile.azimuthal,
        };
        let odd = radiosity_of(s, &(lobe, steps));
        if odd.abs() > LAW_TOL * profile.azimuthal.abs().max(1.0) {
            return Err(format!(
                "{call}: the radiance sin θ·cos φ·{} gives {odd:e}, expected 0: over a full turn of φ (0 to 2π) cos φ integrates to zero",
                profile.azimuthal
            ));
        }
        Ok(())
    })?;
    // Positive radiance: the integral over the hemisphere, not the sphere.
    let uniform = radiosity_of(s, &WORKSHEET_RADIOSITY);
    let positive = uniform > 0.0;
    if !positive {
        return Err(format!(
            "radiosity_from_radiance(L = 6000, steps = 256) = {uniform:e} for a positive radiance: θ runs over the hemisphere, [0, π/2], where cos θ ≥ 0"
        ));
    }
    check_coarse_grids(s)?;
    check_against_key(ctx, CASES / 4, radiosity_strategy(), |key, input| {
        rel_close(
            &format!(
                "radiosity_from_radiance({:?}, steps = {})",
                input.0, input.1
            ),
            radiosity_of(s, &input),
            radiosity_of(key, &input),
            QUADRATURE_TOL,
        )
    })?;
    check_golden(
        ctx,
        GOLDEN_RADIOSITY,
        &[(
            WORKSHEET_RADIOSITY,
            "question 7 (L = 6000 W/(m² sr) over the hemisphere)",
        )],
        |input| radiosity_of(s, input),
        |got, expected| {
            rel_close("the radiosity (W/m²)", *got, *expected, QUADRATURE_TOL)
                .map_err(|e| format!("{e} — dω = sin θ dθ dφ, θ ∈ [0, π/2], φ ∈ [0, 2π)"))
        },
    )
}

// ---------------------------------------------------------------------------------------------
// 5.8 and 5.9: Monte Carlo irradiance

/// One area-light configuration of the Monte Carlo checks.
#[derive(Clone, Copy, Debug)]
pub struct LightCase {
    /// What it is, for messages.
    pub what: &'static str,
    /// The light.
    pub light: RectangleLight,
    /// The receiving point.
    pub receiver: Receiver,
    /// Estimates the mean test averages: enough that a mistake of a few per cent is many
    /// standard errors off.
    pub estimates: u32,
    /// Samples per estimate in the mean test.
    pub samples: u32,
    /// What the configuration exercises, for the message when its mean is off.
    pub hint: &'static str,
}

impl LightCase {
    /// The exact irradiance: 0 when the receiver is not in front of the light (it emits to
    /// one side); otherwise Lambert's polygon formula on the part of the light above the
    /// receiver's horizon (the light clipped by the receiver's plane: below it `cos θ_x ≤ 0`
    /// contributes nothing).
    pub fn exact(&self) -> f64 {
        let l = &self.light;
        let (x, n) = (self.receiver.position, self.receiver.normal);
        let in_front = (x - l.corner).dot(l.edge_u.cross(l.edge_v)) > 0.0;
        if !in_front {
            return 0.0;
        }
        let corners = [
            l.corner,
            l.corner + l.edge_u,
            l.corner + l.edge_u + l.edge_v,
            l.corner + l.edge_v,
        ];
        let above = clip_above(&corners, |p| (p - x).dot(n));
        if above.len() < 3 {
            return 0.0;
        }
        irradiance_polygon(l.radiance_w_per_m2_sr, x, n, &above)
    }

    /// The case with every length times `k` and the radiance times `radiance`: the light
    /// subtends the same solid angle, so the irradiance is `radiance` times the original.
    pub fn scaled(&self, k: f64, radiance: f64) -> Self {
        Self {
            light: RectangleLight {
                corner: k * self.light.corner,
                edge_u: k * self.light.edge_u,
                edge_v: k * self.light.edge_v,
                radiance_w_per_m2_sr: radiance * self.light.radiance_w_per_m2_sr,
            },
            receiver: Receiver {
                position: k * self.receiver.position,
                normal: self.receiver.normal,
            },
            ..*self
        }
    }
}

/// The part of the convex polygon `polygon` where `height(p) ≥ 0` (Sutherland–Hodgman against
/// one plane; `height` affine).
fn clip_above(polygon: &[DVec3], height: impl Fn(DVec3) -> f64) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(polygon.len() + 1);
    for (i, &a) in polygon.iter().enumerate() {
        let b = polygon[(i + 1) % polygon.len()];
        let (ha, hb) = (height(a), height(b));
        if ha >= 0.0 {
            out.push(a);
        }
        if (ha >= 0.0) != (hb >= 0.0) {
            out.push(a + (b - a) * (ha / (ha - hb)));
        }
    }
    out
}

/// The configurations: a small rectangle off the receiver's axis (lab 03's), a tilted
/// receiver under a rectangle facing down at an angle, and a large light close above (where
/// cosine sampling beats area sampling).
pub fn light_cases() -> Vec<LightCase> {
    let down = |corner: DVec3, w: f64, d: f64| RectangleLight {
        corner,
        // edge_u × edge_v points down (−y): the light shines on the floor.
        edge_u: DVec3::new(w, 0.0, 0.0),
        edge_v: DVec3::new(0.0, 0.0, d),
        radiance_w_per_m2_sr: 1.0,
    };
    let tilted_light = RectangleLight {
        corner: DVec3::new(-0.3, 0.8, -0.2),
        edge_u: DVec3::new(0.5, 0.05, 0.0),
        edge_v: DVec3::new(0.0, -0.1, 0.4),
        radiance_w_per_m2_sr: 2.5,
    };
    vec![
        LightCase {
            what: "a 0.3 m × 0.2 m light 0.5 m above a point off its axis",
            light: down(DVec3::new(-0.15, 0.5, -0.1), 0.3, 0.2),
            receiver: Receiver {
                position: DVec3::new(0.1, 0.0, -0.05),
                normal: DVec3::Y,
            },
            estimates: MC_ESTIMATES,
            samples: MC_SAMPLES,
            hint: "",
        },
        LightCase {
            what: "a tilted 0.5 m × 0.4 m light above a tilted receiver",
            light: tilted_light,
            receiver: Receiver {
                position: DVec3::new(0.05, 0.0, 0.1),
                normal: DVec3::new(0.3, 1.0, -0.2).normalize(),
            },
            estimates: MC_ESTIMATES,
            samples: MC_SAMPLES,
            hint: "",
        },
        LightCase {
            what: "a 4 m × 4 m light 0.25 m above the receiver",
            light: down(DVec3::new(-2.0, 0.25, -2.0), 4.0, 4.0),
            receiver: Receiver {
                position: DVec3::ZERO,
                normal: DVec3::Y,
            },
            estimates: MC_ESTIMATES,
            samples: MC_SAMPLES,
            hint: "",
        },
    ]
}

/// The unit normal tilted `tilt_deg` from vertical (+y) towards the azimuth `azimuth_deg`
/// (from +x towards +z).
fn tilted(tilt_deg: f64, azimuth_deg: f64) -> DVec3 {
    let (t, a) = (tilt_deg.to_radians(), azimuth_deg.to_radians());
    DVec3::new(t.sin() * a.cos(), t.cos(), t.sin() * a.sin())
}

/// What a sheared parallelogram light exercises.
const SHEARED: &str = "the light is a parallelogram whose edges are neither perpendicular nor of equal length: its area is |edge_u × edge_v| (light.area_m2()), not |edge_u|·|edge_v|; its unit normal is (edge_u × edge_v)/|edge_u × edge_v| (light.normal()), not û × v̂; its points are light.point(s, t), and whether a ray hits it light.radiance_along(x, ω) tells";

/// Estimates per configuration of the strongly tilted receivers, and samples per estimate:
/// there an unnormalised frame is off by a few per cent, which must be many standard errors
/// (16 times the samples of the other configurations, a quarter of the standard error).
pub const MC_ESTIMATES_TILTED: u32 = 1024;
/// Samples per estimate on the strongly tilted receivers.
pub const MC_SAMPLES_TILTED: u32 = 64;

/// The configurations of the mean test: [`light_cases`], then lights that face away, are seen
/// edge-on or stand partly below the receiver's horizon (where the clamps of both cosines
/// matter), receivers facing −z and down (where a tangent frame can break), receivers tilted
/// 60°–80° from vertical at several azimuths under a large light, part of which is below
/// their horizon, and sheared parallelograms (edges neither perpendicular nor of equal
/// length).
pub fn mean_cases() -> Vec<LightCase> {
    let light = |corner: DVec3, edge_u: DVec3, edge_v: DVec3| RectangleLight {
        corner,
        edge_u,
        edge_v,
        radiance_w_per_m2_sr: 1.0,
    };
    let at = |position: DVec3, normal: DVec3| Receiver {
        position,
        normal: normal.normalize(),
    };
    let case = |what, light, receiver, hint| LightCase {
        what,
        light,
        receiver,
        estimates: MC_ESTIMATES,
        samples: MC_SAMPLES,
        hint,
    };
    let ceiling = light(
        DVec3::new(-1.5, 0.6, -1.5),
        DVec3::new(3.0, 0.0, 0.0),
        DVec3::new(0.0, 0.0, 3.0),
    );
    let steep = |what, tilt, azimuth| LightCase {
        what,
        light: ceiling,
        receiver: at(DVec3::ZERO, tilted(tilt, azimuth)),
        estimates: MC_ESTIMATES_TILTED,
        samples: MC_SAMPLES_TILTED,
        hint: "the receiver is tilted far from vertical and part of the light is below its horizon: the cosine is the receiver's, cos θ_x = max(0, n·ω), and directions are drawn about n in an orthonormal frame (unit tangents perpendicular to n and to each other)",
    };
    let mut cases = light_cases();
    cases.extend([
        case(
            "a 0.3 m × 0.2 m light 0.5 m above the receiver, its back turned to it",
            light(
                DVec3::new(-0.15, 0.5, -0.1),
                DVec3::new(0.0, 0.0, 0.2),
                DVec3::new(0.3, 0.0, 0.0),
            ),
            at(DVec3::new(0.1, 0.0, -0.05), DVec3::Y),
            "a light emits from one side only, towards edge_u × edge_v: seen from behind it sends nothing, cos θ_l = max(0, −n_l·ω) = 0, so E = 0",
        ),
        case(
            "a 0.4 m × 0.3 m light whose plane passes through the receiver (seen edge-on)",
            light(
                DVec3::new(0.2, 0.1, 0.0),
                DVec3::new(0.4, 0.0, 0.0),
                DVec3::new(0.0, 0.3, 0.0),
            ),
            at(DVec3::ZERO, DVec3::Y),
            "seen edge-on, the light sends nothing: cos θ_l = 0 at every point of it, so E = 0",
        ),
        case(
            "a vertical 0.6 m × 0.4 m light standing on the receiver's horizon 0.5 m away",
            light(
                DVec3::new(-0.3, 0.0, 0.5),
                DVec3::new(0.0, 0.4, 0.0),
                DVec3::new(0.6, 0.0, 0.0),
            ),
            at(DVec3::ZERO, DVec3::Y),
            "the light's lower edge is on the receiver's horizon, where cos θ_x falls to 0",
        ),
        case(
            "a vertical 0.5 m × 0.7 m light 0.4 m away, its lower 0.3 m below the receiver's horizon",
            light(
                DVec3::new(-0.3, -0.3, 0.4),
                DVec3::new(0.0, 0.7, 0.0),
                DVec3::new(0.5, 0.0, 0.0),
            ),
            at(DVec3::ZERO, DVec3::Y),
            "the part of the light below the receiver's horizon contributes nothing: cos θ_x = max(0, n·ω), not n·ω nor |n·ω|",
        ),
        case(
            "a 0.6 m × 0.6 m light 0.5 m in front of a receiver facing −z",
            light(
                DVec3::new(-0.25, -0.35, -0.5),
                DVec3::new(0.6, 0.0, 0.0),
                DVec3::new(0.0, 0.6, 0.0),
            ),
            at(DVec3::ZERO, DVec3::NEG_Z),
            "the receiver's normal is −z: directions are drawn about it, not about world up, in a tangent frame that holds for every unit normal, ±z and ±y included (Frisvad's needs its special case at n = −z; Duff et al.'s, the framework's Onb, has none)",
        ),
        case(
            "a 0.4 m × 0.5 m light 0.6 m below a receiver facing down",
            light(
                DVec3::new(-0.2, 0.4, -0.25),
                DVec3::new(0.0, 0.0, 0.5),
                DVec3::new(0.4, 0.0, 0.0),
            ),
            at(DVec3::new(0.05, 1.0, 0.0), DVec3::NEG_Y),
            "the receiver faces down (−y): its hemisphere and its cosine are about its own normal, whatever the direction, in a frame that holds for every unit normal",
        ),
        steep(
            "a 3 m × 3 m light 0.6 m above a receiver tilted 60° towards +x",
            60.0,
            0.0,
        ),
        steep(
            "a 3 m × 3 m light 0.6 m above a receiver tilted 70° towards azimuth 30°",
            70.0,
            30.0,
        ),
        steep(
            "a 3 m × 3 m light 0.6 m above a receiver tilted 80° towards azimuth 135°",
            80.0,
            135.0,
        ),
        steep(
            "a 3 m × 3 m light 0.6 m above a receiver tilted 70° towards azimuth 250°",
            70.0,
            250.0,
        ),
        case(
            "a sheared parallelogram light (edges 0.6 m and 0.46 m at 41°) 0.5 m above the receiver",
            light(
                DVec3::new(-0.3, 0.5, -0.2),
                DVec3::new(0.6, 0.0, 0.0),
                DVec3::new(0.35, 0.0, 0.3),
            ),
            at(DVec3::new(0.1, 0.0, 0.05), DVec3::Y),
            SHEARED,
        ),
        case(
            "a tilted sheared parallelogram light (edges 0.51 m and 0.54 m at 124°) above a receiver tilted 33°",
            light(
                DVec3::new(-0.4, 0.7, -0.1),
                DVec3::new(0.5, 0.1, 0.0),
                DVec3::new(-0.3, -0.05, 0.45),
            ),
            at(DVec3::new(0.0, 0.0, 0.1), DVec3::new(0.5, 0.9, 0.3)),
            SHEARED,
        ),
    ]);
    cases
}

/// The configuration where the cosine estimator's variance is below the area estimator's.
pub const BIG_LIGHT: usize = 2;
/// Samples per estimate in the Monte Carlo checks.
pub const MC_SAMPLES: u32 = 16;
/// Estimates per configuration and scale.
pub const MC_ESTIMATES: u32 = 256;
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

fn exercise_5_8(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    check_means(s.as_ref(), Estimator::Area)?;
    check_variances(s.as_ref(), Estimator::Area, ctx)
}

fn exercise_5_9(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    check_means(s.as_ref(), Estimator::Cosine)?;
    check_variances(s.as_ref(), Estimator::Cosine, ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radiance_along_finds_the_front_of_the_light() {
        let case = light_cases()[0];
        let p = case.receiver.position;
        let centre = case.light.point(0.5, 0.5);
        let w = (centre - p).normalize();
        assert_eq!(case.light.radiance_along(p, w), 1.0);
        assert_eq!(case.light.radiance_along(p, -w), 0.0);
        // From above, the back of the light is dark.
        let above = centre + DVec3::Y;
        assert_eq!(case.light.radiance_along(above, -DVec3::Y), 0.0);
        // Just past an edge.
        let outside = (case.light.point(1.01, 0.5) - p).normalize();
        assert_eq!(case.light.radiance_along(p, outside), 0.0);
    }

    #[test]
    fn the_exact_irradiance_is_one_sided_and_clipped_at_the_horizon() {
        let cases = mean_cases();
        let named = |what: &str| {
            *cases
                .iter()
                .find(|c| c.what.contains(what))
                .expect("a configuration of that name")
        };
        // Behind the light, or in its plane: nothing.
        assert_eq!(named("its back turned to it").exact(), 0.0);
        assert_eq!(named("seen edge-on").exact(), 0.0);
        // Partly below the horizon: the part above alone, the light cut at y = 0.
        let partly = named("below the receiver's horizon");
        let above = LightCase {
            light: RectangleLight {
                corner: DVec3::new(-0.3, 0.0, 0.4),
                edge_u: DVec3::new(0.0, 0.4, 0.0),
                ..partly.light
            },
            ..partly
        };
        let (clipped, whole) = (partly.exact(), above.exact());
        assert!(
            (clipped - whole).abs() <= 1e-12 * whole,
            "{clipped} ≠ {whole}"
        );
        // Wholly above: Lambert's formula on the whole parallelogram.
        for case in light_cases() {
            let l = case.light;
            let polygon = [
                l.corner,
                l.corner + l.edge_u,
                l.corner + l.edge_u + l.edge_v,
                l.corner + l.edge_v,
            ];
            let e = irradiance_polygon(
                l.radiance_w_per_m2_sr,
                case.receiver.position,
                case.receiver.normal,
                &polygon,
            );
            assert_eq!(case.exact(), e, "{}", case.what);
        }
    }

    #[test]
    fn the_coarse_rules_are_the_midpoint_sums() {
        // One interval: θ = π/4, four φ cells: ½ · (π/2) · 2π = π²/2, and in μ: ½ · 1 · 2π = π.
        let one = |_: f64, _: f64| 1.0;
        assert!((midpoint_in_theta(&one, 1) - 0.5 * PI * PI).abs() < 1e-12);
        assert!((midpoint_in_mu(&one, 1) - PI).abs() < 1e-12);
        // Both converge to the exact integrals of the coarse profiles.
        for (what, radiance, exact) in coarse_profiles() {
            for rule in [midpoint_in_theta, midpoint_in_mu] {
                let b = rule(&radiance, 512);
                assert!((b - exact).abs() < 1e-4 * exact, "{what}: {b} ≠ {exact}");
            }
        }
    }

    #[test]
    fn the_configurations_are_above_their_receivers() {
        // Lambert's formula needs the whole polygon above the receiver's horizon.
        for case in light_cases() {
            for (s, t) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)] {
                let d = case.light.point(s, t) - case.receiver.position;
                assert!(d.dot(case.receiver.normal) > 0.0, "{}", case.what);
                assert!(d.dot(case.light.normal()) < 0.0, "{}", case.what);
            }
        }
    }
}
