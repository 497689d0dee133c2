//! Lab 05 — radiometry: the quantities of light a renderer computes with, from photons per
//! second to the radiance of a diffuse emitter, and the irradiance from an area light
//! estimated by Monte Carlo (docs/lab05.md).
//!
//! Every quantity is an `f64` in SI units, named with its unit (`_w` watts, `_w_per_sr`,
//! `_w_per_m2`, `_j` joules, `_m` metres, `_nm` nanometres, `_cd` candela, `_lux`): the
//! worksheet's numbers span 10⁻¹⁹ J (one photon) to 10¹⁹ photons per second, beyond what an
//! `f32` keeps to the digits the checks compare.
//!
//! The physical constants and the luminous-efficiency table are given here, so the student's
//! code and the answer key compute with the same numbers.

use glam::DVec3;

use crate::sampling::Rng;

/// Planck's constant `h`, in joule seconds (exact in the SI since 2019).
pub const PLANCK_J_S: f64 = 6.626_070_15e-34;

/// The speed of light in vacuum `c`, in metres per second (exact).
pub const SPEED_OF_LIGHT_M_PER_S: f64 = 299_792_458.0;

/// The luminous efficacy of radiation at the peak of the photopic curve (555 nm), in lumens
/// per watt: `K_m = 683 lm/W`.
pub const PEAK_LUMINOUS_EFFICACY_LM_PER_W: f64 = 683.0;

/// The CIE 1924 photopic luminous efficiency `V(λ)`: `(wavelength in nm, V)`, every 10 nm from
/// 380 to 780 nm and the peak at 555 nm, in increasing wavelength.
pub const PHOTOPIC_EFFICIENCY: [(f64, f64); 42] = [
    (380.0, 0.000039),
    (390.0, 0.000120),
    (400.0, 0.000396),
    (410.0, 0.001210),
    (420.0, 0.004000),
    (430.0, 0.011600),
    (440.0, 0.023000),
    (450.0, 0.038000),
    (460.0, 0.060000),
    (470.0, 0.090980),
    (480.0, 0.139020),
    (490.0, 0.208020),
    (500.0, 0.323000),
    (510.0, 0.503000),
    (520.0, 0.710000),
    (530.0, 0.862000),
    (540.0, 0.954000),
    (550.0, 0.994950),
    (555.0, 1.000000),
    (560.0, 0.995000),
    (570.0, 0.952000),
    (580.0, 0.870000),
    (590.0, 0.757000),
    (600.0, 0.631000),
    (610.0, 0.503000),
    (620.0, 0.381000),
    (630.0, 0.265000),
    (640.0, 0.175000),
    (650.0, 0.107000),
    (660.0, 0.061000),
    (670.0, 0.032000),
    (680.0, 0.017000),
    (690.0, 0.008210),
    (700.0, 0.004102),
    (710.0, 0.002091),
    (720.0, 0.001047),
    (730.0, 0.000520),
    (740.0, 0.000249),
    (750.0, 0.000120),
    (760.0, 0.000060),
    (770.0, 0.000030),
    (780.0, 0.000015),
];

/// `V(λ)` at `wavelength_nm`: the table [`PHOTOPIC_EFFICIENCY`], linearly interpolated between
/// its entries, and 0 outside 380–780 nm (not visible).
pub fn luminous_efficiency(wavelength_nm: f64) -> f64 {
    let table = &PHOTOPIC_EFFICIENCY;
    if !(table[0].0..=table[table.len() - 1].0).contains(&wavelength_nm) {
        return 0.0;
    }
    let i = table
        .windows(2)
        .position(|w| wavelength_nm <= w[1].0)
        .unwrap_or(table.len() - 2);
    let ((l0, v0), (l1, v1)) = (table[i], table[i + 1]);
    v0 + (v1 - v0) * (wavelength_nm - l0) / (l1 - l0)
}

/// What Exercise 5.2 finds of an isotropic spherical bulb.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SphericalBulb {
    /// Radiant flux `Φ`, watts.
    pub radiant_flux_w: f64,
    /// Radiant intensity `I`, watts per steradian.
    pub radiant_intensity_w_per_sr: f64,
    /// Radiant exitance `M` at the bulb's surface, watts per square metre.
    pub radiant_exitance_w_per_m2: f64,
    /// Radiant energy `Q` emitted over the duration, joules.
    pub emitted_energy_j: f64,
}

/// What Exercise 5.3 finds of a point source seen by an eye.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Observation {
    /// Irradiance `E` at the eye, on a surface facing the source, watts per square metre.
    pub irradiance_w_per_m2: f64,
    /// Radiant flux through the circular pupil, watts.
    pub pupil_power_w: f64,
}

/// What Exercise 5.6 finds of a flat diffuse (Lambertian) emitter.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct DiffuseEmitter {
    /// Radiant flux `Φ` leaving the emitter's front side, watts.
    pub radiant_flux_w: f64,
    /// Radiosity `B` (the exitance of an emitter), watts per square metre.
    pub radiosity_w_per_m2: f64,
}

/// A one-sided Lambertian area light: the parallelogram `corner + s·edge_u + t·edge_v`,
/// `s, t ∈ [0, 1]` (a rectangle when the edges are perpendicular), emitting the uniform
/// radiance `radiance_w_per_m2_sr` to the side of [`normal`](Self::normal).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RectangleLight {
    /// One corner, metres.
    pub corner: DVec3,
    /// The first edge from the corner.
    pub edge_u: DVec3,
    /// The second edge from the corner.
    pub edge_v: DVec3,
    /// Emitted radiance `L_e`, watts per square metre per steradian.
    pub radiance_w_per_m2_sr: f64,
}

impl RectangleLight {
    /// Its area `A = |edge_u × edge_v|`, square metres.
    pub fn area_m2(&self) -> f64 {
        self.edge_u.cross(self.edge_v).length()
    }

    /// The unit normal of its emitting side, `(edge_u × edge_v)/|edge_u × edge_v|`.
    pub fn normal(&self) -> DVec3 {
        self.edge_u.cross(self.edge_v).normalize()
    }

    /// The point with parameters `(s, t) ∈ [0, 1]²`: `corner + s·edge_u + t·edge_v`.
    pub fn point(&self, s: f64, t: f64) -> DVec3 {
        self.corner + s * self.edge_u + t * self.edge_v
    }

    /// The radiance arriving at `origin` from the unit direction `direction`: `L_e` when the
    /// ray `origin + t·direction`, `t > 0`, hits the light on its emitting side, 0 otherwise.
    pub fn radiance_along(&self, origin: DVec3, direction: DVec3) -> f64 {
        let n = self.edge_u.cross(self.edge_v);
        let facing = direction.dot(n);
        if facing >= 0.0 {
            return 0.0;
        }
        let t = (self.corner - origin).dot(n) / facing;
        // NaN (the ray in the light's plane) misses too.
        let ahead = t > 0.0;
        if !ahead {
            return 0.0;
        }
        // Parallelogram coordinates of the hit by the dual basis of the edges.
        let d = origin + t * direction - self.corner;
        let nn = n.length_squared();
        let s = d.cross(self.edge_v).dot(n) / nn;
        let r = self.edge_u.cross(d).dot(n) / nn;
        if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&r) {
            self.radiance_w_per_m2_sr
        } else {
            0.0
        }
    }
}

/// A point receiving light and the unit normal of its surface.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Receiver {
    /// Its position, metres.
    pub position: DVec3,
    /// The unit normal of the surface at it.
    pub normal: DVec3,
}

/// The lab's contract: what the student's `Student` implements, and the answer key's `Lab05`.
pub type Contract = dyn Radiometry;

/// Lab 05's contract: one method per exercise.
#[crate::contract]
pub trait Radiometry: Send + Sync {
    /// Exercise 5.1 — photons emitted per second by a lamp drawing `electrical_power_w`, of
    /// which the fraction `efficiency` leaves as light, all of wavelength `wavelength_nm`.
    fn photons_per_second(
        &self,
        electrical_power_w: f64,
        efficiency: f64,
        wavelength_nm: f64,
    ) -> f64;

    /// Exercise 5.2 — an ideal (lossless) spherical bulb of diameter `diameter_m` on
    /// `voltage_v` drawing `current_a`, emitting equally in all directions: its flux,
    /// intensity, exitance at its surface, and the energy emitted in `duration_s`.
    fn spherical_bulb(
        &self,
        voltage_v: f64,
        current_a: f64,
        diameter_m: f64,
        duration_s: f64,
    ) -> SphericalBulb;

    /// Exercise 5.3 — an isotropic point source of flux `radiant_flux_w` seen from
    /// `distance_m` by an eye whose pupil, facing the source, has diameter
    /// `pupil_diameter_m`: the irradiance at the eye and the power through the pupil.
    fn observe_point_source(
        &self,
        radiant_flux_w: f64,
        distance_m: f64,
        pupil_diameter_m: f64,
    ) -> Observation;

    /// Exercise 5.4 — the illuminance (lux) of monochromatic light of wavelength
    /// `wavelength_nm` with irradiance `irradiance_w_per_m2`, by [`luminous_efficiency`] and
    /// [`PEAK_LUMINOUS_EFFICACY_LM_PER_W`].
    fn illuminance_lux(&self, irradiance_w_per_m2: f64, wavelength_nm: f64) -> f64;

    /// Exercise 5.5 — two isotropic lamps on either side of a screen light it equally (a
    /// photometer bench): the known lamp of intensity `known_intensity_cd` at
    /// `known_distance_m`, the unknown one at `unknown_distance_m`. Return the unknown
    /// lamp's intensity, candela.
    fn equivalent_intensity_cd(
        &self,
        known_intensity_cd: f64,
        known_distance_m: f64,
        unknown_distance_m: f64,
    ) -> f64;

    /// Exercise 5.6 — a flat diffuse emitter of area `area_m2` and uniform radiance
    /// `radiance_w_per_m2_sr`: its flux and radiosity.
    fn diffuse_emitter(&self, radiance_w_per_m2_sr: f64, area_m2: f64) -> DiffuseEmitter;

    /// Exercise 5.7 — the radiosity `B = ∫_Ω L(θ, φ) cos θ dω` of a surface whose outgoing
    /// radiance is `radiance(θ, φ)` (polar angle from the normal, azimuth), integrated
    /// numerically over the hemisphere with `steps` intervals in θ and `4·steps` in φ (or a
    /// rule at least as accurate).
    fn radiosity_from_radiance(&self, radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64;

    /// Exercise 5.8 — a Monte Carlo estimate of the irradiance at `receiver` from `light`
    /// with `samples` points drawn uniformly on the light's area (one `rng.next_vec2()` per
    /// sample; every call draws new ones). Nothing blocks the light.
    fn irradiance_area_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64;

    /// Exercise 5.9 — the same irradiance estimated with `samples` directions drawn from the
    /// cosine-weighted hemisphere about the receiver's normal (one `rng.next_vec2()` per
    /// sample), each looking up [`RectangleLight::radiance_along`].
    fn irradiance_cosine_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64;
}
