//! Reference solution of lab 05 (docs/lab05.md).

use std::f64::consts::PI;

use contracts::glam::DVec3;
use contracts::lab05::{
    DiffuseEmitter, Observation, PEAK_LUMINOUS_EFFICACY_LM_PER_W, PLANCK_J_S, Radiometry, Receiver,
    RectangleLight, SPEED_OF_LIGHT_M_PER_S, SphericalBulb, luminous_efficiency,
};
use contracts::sampling::Rng;

/// The reference radiometry.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab05;

/// The irradiance of an isotropic point source of flux `flux` at `distance`, facing it.
fn inverse_square(flux: f64, distance: f64) -> f64 {
    flux / (4.0 * PI * distance * distance)
}

/// An orthonormal basis `(t, b)` completing the unit `n` (Duff et al. 2017), in `f64`.
fn tangents(n: DVec3) -> (DVec3, DVec3) {
    let sign = 1f64.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        DVec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        DVec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

impl Radiometry for Lab05 {
    fn photons_per_second(
        &self,
        electrical_power_w: f64,
        efficiency: f64,
        wavelength_nm: f64,
    ) -> f64 {
        let photon_energy_j = PLANCK_J_S * SPEED_OF_LIGHT_M_PER_S / (wavelength_nm * 1e-9);
        electrical_power_w * efficiency / photon_energy_j
    }

    fn spherical_bulb(
        &self,
        voltage_v: f64,
        current_a: f64,
        diameter_m: f64,
        duration_s: f64,
    ) -> SphericalBulb {
        let flux = voltage_v * current_a;
        SphericalBulb {
            radiant_flux_w: flux,
            radiant_intensity_w_per_sr: flux / (4.0 * PI),
            // Sphere of radius d/2: area 4π(d/2)² = πd².
            radiant_exitance_w_per_m2: flux / (PI * diameter_m * diameter_m),
            emitted_energy_j: flux * duration_s,
        }
    }

    fn observe_point_source(
        &self,
        radiant_flux_w: f64,
        distance_m: f64,
        pupil_diameter_m: f64,
    ) -> Observation {
        let e = inverse_square(radiant_flux_w, distance_m);
        let r = 0.5 * pupil_diameter_m;
        Observation {
            irradiance_w_per_m2: e,
            pupil_power_w: e * PI * r * r,
        }
    }

    fn illuminance_lux(&self, irradiance_w_per_m2: f64, wavelength_nm: f64) -> f64 {
        PEAK_LUMINOUS_EFFICACY_LM_PER_W * luminous_efficiency(wavelength_nm) * irradiance_w_per_m2
    }

    fn equivalent_intensity_cd(
        &self,
        known_intensity_cd: f64,
        known_distance_m: f64,
        unknown_distance_m: f64,
    ) -> f64 {
        let ratio = unknown_distance_m / known_distance_m;
        known_intensity_cd * ratio * ratio
    }

    fn diffuse_emitter(&self, radiance_w_per_m2_sr: f64, area_m2: f64) -> DiffuseEmitter {
        let b = PI * radiance_w_per_m2_sr;
        DiffuseEmitter {
            radiant_flux_w: b * area_m2,
            radiosity_w_per_m2: b,
        }
    }

    fn radiosity_from_radiance(&self, radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
        // Midpoint rule in θ ∈ [0, π/2] and φ ∈ [0, 2π).
        let (n, m) = (steps.max(1), 4 * steps.max(1));
        let (dt, dp) = (0.5 * PI / n as f64, 2.0 * PI / m as f64);
        let mut sum = 0.0;
        for i in 0..n {
            let theta = (i as f64 + 0.5) * dt;
            let weight = theta.cos() * theta.sin() * dt * dp;
            for j in 0..m {
                sum += radiance(theta, (j as f64 + 0.5) * dp) * weight;
            }
        }
        sum
    }

    fn irradiance_area_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64 {
        let (area, nl) = (light.area_m2(), light.normal());
        let mut sum = 0.0;
        for _ in 0..samples {
            let u = rng.next_vec2().as_dvec2();
            let to_light = light.point(u.x, u.y) - receiver.position;
            let r2 = to_light.length_squared();
            let w = to_light / r2.sqrt();
            let cos_r = receiver.normal.dot(w).max(0.0);
            let cos_l = (-nl.dot(w)).max(0.0);
            // f/p with p = 1/A per unit area.
            sum += light.radiance_w_per_m2_sr * cos_r * cos_l / r2 * area;
        }
        sum / samples as f64
    }

    fn irradiance_cosine_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64 {
        let n = receiver.normal;
        let (t, b) = tangents(n);
        let mut sum = 0.0;
        for _ in 0..samples {
            let u = rng.next_vec2().as_dvec2();
            // Malley's method: a uniform point on the disc, lifted to the hemisphere.
            let (r, phi) = (u.x.sqrt(), 2.0 * PI * u.y);
            let z = (1.0 - u.x).max(0.0).sqrt();
            let w = r * phi.cos() * t + r * phi.sin() * b + z * n;
            // f/p = L cos θ / (cos θ / π) = π L.
            sum += PI * light.radiance_along(receiver.position, w);
        }
        sum / samples as f64
    }
}

#[cfg(test)]
mod tests {
    //! The worksheet's answers, each derived here by hand from the data of the question (the
    //! derivations are in docs/lab05.md), against the reference.

    use super::*;

    fn close(got: f64, expected: f64) {
        assert!(
            (got - expected).abs() <= 1e-12 * expected.abs(),
            "{got} ≠ {expected}"
        );
    }

    #[test]
    fn worksheet_answers() {
        let r = Lab05;
        // 1: q = hc/λ, N = ηP/q.
        let q = 6.626_070_15e-34 * 299_792_458.0 / 500e-9;
        close(r.photons_per_second(25.0, 0.2, 500.0), 5.0 / q);
        assert!((r.photons_per_second(25.0, 0.2, 500.0) / 1.2585e19 - 1.0).abs() < 1e-3);
        // 2: Φ = UI, I = Φ/4π, M = Φ/(π d²), Q = Φ t.
        let bulb = r.spherical_bulb(2.4, 0.7, 0.01, 300.0);
        close(bulb.radiant_flux_w, 1.68);
        close(bulb.radiant_intensity_w_per_sr, 1.68 / (4.0 * PI));
        close(
            bulb.radiant_exitance_w_per_m2,
            1.68 / (4.0 * PI * 0.005 * 0.005),
        );
        close(bulb.emitted_energy_j, 504.0);
        // The hand-in's values are not these.
        assert!((bulb.radiant_intensity_w_per_sr - 0.42).abs() > 0.2);
        assert!((bulb.radiant_exitance_w_per_m2 - 0.42).abs() > 1e3);
        // 3: E = Φ/(4π r²), P = E π (d/2)².
        let eye = r.observe_point_source(1.68, 1.0, 0.006);
        close(eye.irradiance_w_per_m2, 1.68 / (4.0 * PI));
        close(eye.pupil_power_w, 1.68 / (4.0 * PI) * PI * 0.003 * 0.003);
        // 4: Φ = 0.2 · 200 W, E = Φ/(4π 2²), E_v = 683 · V(650) · E, V(650) = 0.107.
        let e = r.observe_point_source(40.0, 2.0, 0.0).irradiance_w_per_m2;
        close(e, 40.0 / (16.0 * PI));
        close(
            r.illuminance_lux(e, 650.0),
            683.0 * 0.107 * 40.0 / (16.0 * PI),
        );
        close(r.illuminance_lux(1.0, 555.0), 683.0);
        // 5: I/r² equal on both sides.
        close(
            r.equivalent_intensity_cd(40.0, 0.35, 0.65),
            40.0 * 0.4225 / 0.1225,
        );
        // 6: Φ = π L A, B = π L.
        let e6 = r.diffuse_emitter(5000.0, 0.01);
        close(e6.radiant_flux_w, 50.0 * PI);
        close(e6.radiosity_w_per_m2, 5000.0 * PI);
        // 7: ∫ cos θ dω = π over the hemisphere.
        let b7 = r.radiosity_from_radiance(&|_, _| 6000.0, 256);
        assert!((b7 / (6000.0 * PI) - 1.0).abs() < 1e-4, "{b7}");
    }
}
