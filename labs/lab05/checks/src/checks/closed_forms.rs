//! Exercises 5.1 to 5.6: the closed-form radiometric quantities of bulbs, observers and emitters.

use std::f64::consts::PI;
use std::sync::Arc;

use contracts::lab05::{
    DiffuseEmitter, Observation, Radiometry, SphericalBulb, luminous_efficiency,
};
use grading::{LabContext, for_all};

use super::inputs::{
    PhotonsInput, WORKSHEET_BULB, WORKSHEET_EMITTER, WORKSHEET_EQUIVALENT, WORKSHEET_ILLUMINANCE,
    WORKSHEET_OBSERVATION, WORKSHEET_PHOTONS, WORKSHEET_TABLE, bulb_strategy, emitter_strategy,
    equivalent_strategy, illuminance_strategy, observation_strategy, photons_strategy,
};
use super::{
    CASES, GOLDEN_BULB, GOLDEN_EMITTER, GOLDEN_EQUIVALENT, GOLDEN_ILLUMINANCE, GOLDEN_OBSERVATION,
    GOLDEN_PHOTONS, LAW_TOL, REL_TOL, check_against_key, check_golden, rel_close,
};

pub(super) fn exercise_5_1(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
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

pub(super) fn exercise_5_2(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
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

pub(super) fn exercise_5_3(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
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

pub(super) fn exercise_5_4(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
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

pub(super) fn exercise_5_5(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
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

pub(super) fn exercise_5_6(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
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
