//! # Lab 05 — radiometry
//!
//! The quantities a renderer computes with — flux, intensity, irradiance, exitance, radiance —
//! as functions of the worksheet's data, and then the irradiance from an area light estimated
//! by Monte Carlo, the computation at the heart of every soft shadow.
//!
//! Read `docs/lab05.md` first: it states every formula, derives the worksheet's answers, and
//! says what each check checks. Then fill in the functions below (in any order) and run
//!
//! ```text
//! cargo test -p lab05                  # all nine exercises
//! cargo test -p lab05 exercise_5_8     # one exercise
//! raylab report --lab 5 --pipeline student   # the convergence plot of your estimators
//! ```
//!
//! Every quantity is an `f64` in SI units, and each name says its unit. Use the constants of
//! the contract (`PLANCK_J_S`, `SPEED_OF_LIGHT_M_PER_S`, `PEAK_LUMINOUS_EFFICACY_LM_PER_W`,
//! `luminous_efficiency`): the checks compare to nine digits, so `c = 3·10⁸` is wrong here.

// The parameters of the stubs below are unused until you fill them in.
#![allow(unused_variables)]

#[allow(unused_imports)]
use contracts::glam::DVec3;
#[allow(unused_imports)]
use contracts::lab05::{
    DiffuseEmitter, Observation, PEAK_LUMINOUS_EFFICACY_LM_PER_W, PLANCK_J_S, Radiometry, Receiver,
    RectangleLight, SPEED_OF_LIGHT_M_PER_S, SphericalBulb, luminous_efficiency,
};
use contracts::sampling::Rng;

/// Your radiometry. The checks and `raylab report --lab 5` call it through the `Radiometry`
/// trait.
#[derive(Clone, Copy, Debug, Default)]
pub struct Student;

impl Radiometry for Student {
    /// **Exercise 5.1** — photons per second (docs/lab05.md, §5.1).
    ///
    /// Only `efficiency × electrical_power_w` leaves as light. Hint: find the energy of one
    /// photon of this wavelength first (joules; the wavelength is in nanometres), then count
    /// how many of them carry that power.
    fn photons_per_second(
        &self,
        electrical_power_w: f64,
        efficiency: f64,
        wavelength_nm: f64,
    ) -> f64 {
        todo!("Exercise 5.1: photons_per_second (docs/lab05.md, Exercise 5.1)")
    }

    /// **Exercise 5.2** — flux, intensity, exitance and energy of a spherical bulb
    /// (docs/lab05.md, §5.2).
    ///
    /// The bulb is ideal: all the electrical power leaves as light, equally in every
    /// direction. Hint: intensity is flux per steradian of the *whole* sphere of directions;
    /// exitance is flux per square metre of the bulb's *own* surface (its diameter is given,
    /// it is not a unit sphere).
    fn spherical_bulb(
        &self,
        voltage_v: f64,
        current_a: f64,
        diameter_m: f64,
        duration_s: f64,
    ) -> SphericalBulb {
        todo!("Exercise 5.2: spherical_bulb (docs/lab05.md, Exercise 5.2)")
    }

    /// **Exercise 5.3** — irradiance at a distance and the power through a pupil
    /// (docs/lab05.md, §5.3).
    ///
    /// Hint: the whole flux crosses every sphere around the source; the pupil, small and
    /// facing the source, catches the irradiance over its area (its *diameter* is given).
    fn observe_point_source(
        &self,
        radiant_flux_w: f64,
        distance_m: f64,
        pupil_diameter_m: f64,
    ) -> Observation {
        todo!("Exercise 5.3: observe_point_source (docs/lab05.md, Exercise 5.3)")
    }

    /// **Exercise 5.4** — illuminance from irradiance (docs/lab05.md, §5.4).
    ///
    /// Hint: `luminous_efficiency(wavelength_nm)` is the eye's weight V(λ) of the wavelength,
    /// 1 at 555 nm, where one watt is `PEAK_LUMINOUS_EFFICACY_LM_PER_W` lumens.
    fn illuminance_lux(&self, irradiance_w_per_m2: f64, wavelength_nm: f64) -> f64 {
        todo!("Exercise 5.4: illuminance_lux (docs/lab05.md, Exercise 5.4)")
    }

    /// **Exercise 5.5** — the intensity of the unknown lamp on a photometer bench
    /// (docs/lab05.md, §5.5).
    ///
    /// Hint: write the illuminance each lamp gives the screen by the inverse-square law, set
    /// them equal, and solve for the unknown intensity. Which lamp is farther?
    fn equivalent_intensity_cd(
        &self,
        known_intensity_cd: f64,
        known_distance_m: f64,
        unknown_distance_m: f64,
    ) -> f64 {
        todo!("Exercise 5.5: equivalent_intensity_cd (docs/lab05.md, Exercise 5.5)")
    }

    /// **Exercise 5.6** — flux and radiosity of a diffuse emitter (docs/lab05.md, §5.6).
    ///
    /// Hint: the radiance is the same in every direction; the projected solid angle of the
    /// hemisphere (§5.7) turns it into radiosity, and the area turns radiosity into flux.
    fn diffuse_emitter(&self, radiance_w_per_m2_sr: f64, area_m2: f64) -> DiffuseEmitter {
        todo!("Exercise 5.6: diffuse_emitter (docs/lab05.md, Exercise 5.6)")
    }

    /// **Exercise 5.7** — radiosity as the integral of radiance over the hemisphere
    /// (docs/lab05.md, §5.7).
    ///
    /// Integrate numerically: split θ ∈ [0, π/2] into `steps` intervals and φ ∈ [0, 2π) into
    /// `4·steps`, and sum the integrand at the midpoint of each cell times the cell's size.
    /// Hint: write dω in θ and φ before you sum — a solid angle element is not dθ dφ.
    fn radiosity_from_radiance(&self, radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
        todo!("Exercise 5.7: radiosity_from_radiance (docs/lab05.md, Exercise 5.7)")
    }

    /// **Exercise 5.8** — the irradiance from an area light by uniform area sampling
    /// (docs/lab05.md, §5.8).
    ///
    /// For each of the `samples` samples draw `u = rng.next_vec2()`, take the point
    /// `light.point(u.x, u.y)`, and add the integrand of the area form divided by the pdf of
    /// the point; return the average. Hint: `light.area_m2()` and `light.normal()` are given;
    /// both cosines are clamped at zero, and the distance enters squared.
    fn irradiance_area_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64 {
        todo!("Exercise 5.8: irradiance_area_sampling (docs/lab05.md, Exercise 5.8)")
    }

    /// **Exercise 5.9** — the same irradiance by cosine-weighted hemisphere sampling
    /// (docs/lab05.md, §5.9).
    ///
    /// For each sample draw `u = rng.next_vec2()`, turn it into a direction about
    /// `receiver.normal` with density `cos θ/π`, look up `light.radiance_along(position,
    /// direction)`, and divide the integrand by the pdf. Hint: build a tangent frame around the
    /// normal (any two unit vectors perpendicular to it and to each other).
    fn irradiance_cosine_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64 {
        todo!("Exercise 5.9: irradiance_cosine_sampling (docs/lab05.md, Exercise 5.9)")
    }
}
