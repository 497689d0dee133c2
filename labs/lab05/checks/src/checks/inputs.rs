//! The closed-form exercises' inputs: the worksheet's questions and the random strategies.

use std::f64::consts::PI;

use proptest::prelude::*;

use serde::{Deserialize, Serialize};

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
    pub(super) fn scaled(&self, k: f64) -> Self {
        Self {
            constant: k * self.constant,
            cosine: k * self.cosine,
            cosine_squared: k * self.cosine_squared,
            azimuthal: k * self.azimuthal,
        }
    }
}
