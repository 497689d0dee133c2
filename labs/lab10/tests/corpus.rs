//! Lab 10's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use contracts::lab10::Fresnel;
use raylab_core::glam::Vec3;
use raylab_core::scene::Material;
use reference::lab10::Lab10 as Reference;

use grading::corpus::Verdict;

type PairFn = fn(f32, f32, f32, f32) -> f32;
type ReflectanceFn = fn(f32, f32, f32) -> f32;
type TransmittanceFn = fn(f32, &Material) -> Vec3;

/// A lab 10 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    r_s: Option<PairFn>,
    r_p: Option<PairFn>,
    r: Option<PairFn>,
    reflectance: Option<ReflectanceFn>,
    transmittance: Option<TransmittanceFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    r_s: None,
    r_p: None,
    r: None,
    reflectance: None,
    transmittance: None,
};

impl Fresnel for Variant {
    fn fresnel_r_s(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        match self.r_s {
            Some(f) => f(cos_theta_i, cos_theta_t, eta_i, eta_t),
            None => Reference.fresnel_r_s(cos_theta_i, cos_theta_t, eta_i, eta_t),
        }
    }

    fn fresnel_r_p(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        match self.r_p {
            Some(f) => f(cos_theta_i, cos_theta_t, eta_i, eta_t),
            None => Reference.fresnel_r_p(cos_theta_i, cos_theta_t, eta_i, eta_t),
        }
    }

    fn fresnel_R(&self, cos_theta_i: f32, cos_theta_t: f32, eta_i: f32, eta_t: f32) -> f32 {
        match self.r {
            Some(f) => f(cos_theta_i, cos_theta_t, eta_i, eta_t),
            None => Reference.fresnel_R(cos_theta_i, cos_theta_t, eta_i, eta_t),
        }
    }

    fn fresnel_reflectance(&self, cos_theta_i: f32, eta_i: f32, eta_t: f32) -> f32 {
        match self.reflectance {
            Some(f) => f(cos_theta_i, eta_i, eta_t),
            None => Reference.fresnel_reflectance(cos_theta_i, eta_i, eta_t),
        }
    }

    fn transmittance(&self, distance: f32, material: &Material) -> Vec3 {
        match self.transmittance {
            Some(f) => f(distance, material),
            None => Reference.transmittance(distance, material),
        }
    }
}

fn r_s(c1: f32, c2: f32, e1: f32, e2: f32) -> f32 {
    Reference.fresnel_r_s(c1, c2, e1, e2)
}

fn r_p(c1: f32, c2: f32, e1: f32, e2: f32) -> f32 {
    Reference.fresnel_r_p(c1, c2, e1, e2)
}

/// `sin²θ₂` by Snell's law from `cos θ₁`, `η₁/η₂ = eta`.
fn sin2_t(c: f32, eta: f32) -> f32 {
    eta * eta * (1.0 - c * c).max(0.0)
}

/// The reference's transmittance with the absorption coefficient `sigma(ρ)` per channel.
fn with_sigma(distance: f32, material: &Material, sigma: fn(f32) -> f32) -> Vec3 {
    Vec3::from(
        material
            .diffuse
            .to_array()
            .map(|rho| (-sigma(rho) * distance).exp()),
    )
}

/// Every lab 10 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // ---- 10.1
        Variant {
            name: "r_s: squared (the s reflectance instead of the signed amplitude)",
            verdict: Verdict::Reject("10.1"),
            r_s: Some(|c1, c2, e1, e2| r_s(c1, c2, e1, e2).powi(2)),
            ..NONE
        },
        Variant {
            name: "r_s: each index with the other side's cosine (η₁ cos θ₂ against η₂ cos θ₁)",
            verdict: Verdict::Reject("10.1"),
            r_s: Some(|c1, c2, e1, e2| (e1 * c2 - e2 * c1) / (e1 * c2 + e2 * c1)),
            ..NONE
        },
        Variant {
            name: "r_s: numerator the wrong way round (η₂ cos θ₂ − η₁ cos θ₁)",
            verdict: Verdict::Reject("10.1"),
            r_s: Some(|c1, c2, e1, e2| (e2 * c2 - e1 * c1) / (e1 * c1 + e2 * c2)),
            ..NONE
        },
        // ---- 10.2
        Variant {
            name: "r_p: the same pairing as r_s (no Brewster angle)",
            verdict: Verdict::Reject("10.2"),
            r_p: Some(|c1, c2, e1, e2| (e2 * c2 - e1 * c1) / (e1 * c1 + e2 * c2)),
            ..NONE
        },
        Variant {
            name: "r_p: the opposite sign convention (η₁ cos θ₂ − η₂ cos θ₁)",
            verdict: Verdict::Reject("10.2"),
            r_p: Some(|c1, c2, e1, e2| -r_p(c1, c2, e1, e2)),
            ..NONE
        },
        Variant {
            name: "r_p: the cosines swapped (η₂ cos θ₂ − η₁ cos θ₁ over η₂ cos θ₂ + η₁ cos θ₁)",
            verdict: Verdict::Reject("10.2"),
            r_p: Some(|c1, c2, e1, e2| (e2 * c2 - e1 * c1) / (e2 * c2 + e1 * c1)),
            ..NONE
        },
        // ---- 10.3
        Variant {
            name: "R: the sum of the two reflectances without the ½",
            verdict: Verdict::Reject("10.3"),
            r: Some(|c1, c2, e1, e2| r_s(c1, c2, e1, e2).powi(2) + r_p(c1, c2, e1, e2).powi(2)),
            ..NONE
        },
        Variant {
            name: "R: half the square of the summed amplitudes, ½(r_s + r_p)²",
            verdict: Verdict::Reject("10.3"),
            r: Some(|c1, c2, e1, e2| 0.5 * (r_s(c1, c2, e1, e2) + r_p(c1, c2, e1, e2)).powi(2)),
            ..NONE
        },
        Variant {
            name: "R: the s polarisation only, r_s²",
            verdict: Verdict::Reject("10.3"),
            r: Some(|c1, c2, e1, e2| r_s(c1, c2, e1, e2).powi(2)),
            ..NONE
        },
        Variant {
            name: "R: the mean of the amplitudes' magnitudes, ½(|r_s| + |r_p|)",
            verdict: Verdict::Reject("10.3"),
            r: Some(|c1, c2, e1, e2| 0.5 * (r_s(c1, c2, e1, e2).abs() + r_p(c1, c2, e1, e2).abs())),
            ..NONE
        },
        // ---- 10.4
        Variant {
            name: "reflectance: 0 under total internal reflection",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                let s2 = sin2_t(c, e1 / e2);
                if s2 >= 1.0 {
                    0.0
                } else {
                    Reference.fresnel_R(c, (1.0 - s2).sqrt(), e1, e2)
                }
            }),
            ..NONE
        },
        Variant {
            name: "reflectance: no test for total internal reflection (NaN from the square root)",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                Reference.fresnel_R(c, (1.0 - sin2_t(c, e1 / e2)).sqrt(), e1, e2)
            }),
            ..NONE
        },
        Variant {
            name: "reflectance: Snell's law with the ratio of indices upside down (η₂/η₁)",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                let s2 = sin2_t(c, e2 / e1);
                if s2 >= 1.0 {
                    1.0
                } else {
                    Reference.fresnel_R(c, (1.0 - s2).sqrt(), e1, e2)
                }
            }),
            ..NONE
        },
        Variant {
            name: "reflectance: cos θ₂ = cos θ₁ (no refraction)",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| Reference.fresnel_R(c, c, e1, e2)),
            ..NONE
        },
        Variant {
            name: "reflectance: Schlick's approximation",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                let r0 = ((e1 - e2) / (e1 + e2)).powi(2);
                let s2 = sin2_t(c, e1 / e2);
                if s2 >= 1.0 {
                    return 1.0;
                }
                // The cosine on the denser side, as Schlick's approximation prescribes.
                let cos = if e1 > e2 { (1.0 - s2).sqrt() } else { c };
                r0 + (1.0 - r0) * (1.0 - cos).powi(5)
            }),
            ..NONE
        },
        Variant {
            name: "reflectance: cos θ₂ = 1 − sin²θ₂ (the square root forgotten)",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                let s2 = sin2_t(c, e1 / e2);
                if s2 >= 1.0 {
                    1.0
                } else {
                    Reference.fresnel_R(c, 1.0 - s2, e1, e2)
                }
            }),
            ..NONE
        },
        Variant {
            // Right everywhere but within rounding of the critical angle, where the test on
            // sin θ₁ and the sin²θ₂ under the square root fall on different sides of it.
            name: "reflectance: total internal reflection tested as sin θ₁ > η₂/η₁, then √(1 − sin²θ₂) (NaN within rounding of the critical angle)",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                let sin_i = (1.0 - c * c).max(0.0).sqrt();
                if sin_i > e2 / e1 {
                    return 1.0;
                }
                Reference.fresnel_R(c, (1.0 - sin2_t(c, e1 / e2)).sqrt(), e1, e2)
            }),
            ..NONE
        },
        Variant {
            name: "reflectance: total internal reflection tested as cos θ₁ ≤ cos θ_c = √(1 − (η₂/η₁)²), then √(1 − sin²θ₂) (NaN within rounding of the critical angle)",
            verdict: Verdict::Reject("10.4"),
            reflectance: Some(|c, e1, e2| {
                if e1 > e2 && c <= (1.0 - (e2 / e1) * (e2 / e1)).sqrt() {
                    return 1.0;
                }
                Reference.fresnel_R(c, (1.0 - sin2_t(c, e1 / e2)).sqrt(), e1, e2)
            }),
            ..NONE
        },
        // ---- 10.5
        Variant {
            name: "transmittance: σ = 1/ρ_d − 1 without a guard for ρ_d = 0 (NaN at distance 0)",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| with_sigma(d, m, |rho| 1.0 / rho - 1.0)),
            ..NONE
        },
        Variant {
            name: "transmittance: the diffuse colour itself as the absorption coefficient",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| with_sigma(d, m, |rho| rho)),
            ..NONE
        },
        Variant {
            name: "transmittance: σ = −ln ρ_d (another convention than the DTU framework's)",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| with_sigma(d, m, |rho| -rho.max(1e-30).ln())),
            ..NONE
        },
        Variant {
            name: "transmittance: linear in distance, max(0, 1 − σd)",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| {
                let t = Reference.transmittance(1.0, m);
                // σ from the reference's transmittance over one unit.
                Vec3::from(
                    t.to_array()
                        .map(|t1| (1.0 + t1.max(1e-30).ln() * d).max(0.0)),
                )
            }),
            ..NONE
        },
        Variant {
            name: "transmittance: from the transmission filter Tf instead of the diffuse colour",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| {
                let tf = Material {
                    diffuse: m.transmission,
                    ..m.clone()
                };
                Reference.transmittance(d, &tf)
            }),
            ..NONE
        },
        Variant {
            name: "transmittance: one grey coefficient, the mean of the channels' σ",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| {
                let sigma = m
                    .diffuse
                    .to_array()
                    .map(|rho| if rho < 1e-6 { 1e7 } else { 1.0 / rho - 1.0 });
                Vec3::splat((-(sigma.iter().sum::<f32>() / 3.0) * d).exp())
            }),
            ..NONE
        },
        Variant {
            name: "transmittance: (e^−σ)^d, whose e^−σ underflows to 0 for a dark channel",
            verdict: Verdict::Reject("10.5"),
            transmittance: Some(|d, m| {
                Vec3::from(m.diffuse.to_array().map(|rho| {
                    let sigma = if rho < 1e-6 { 1e7 } else { 1.0 / rho - 1.0 };
                    (-sigma).exp().powf(d)
                }))
            }),
            ..NONE
        },
        // ---- correct alternatives
        Variant {
            name: "alternative: the coefficients computed in f64",
            verdict: Verdict::Accept,
            r_s: Some(|c1, c2, e1, e2| {
                let (a, b) = (e1 as f64 * c1 as f64, e2 as f64 * c2 as f64);
                ((a - b) / (a + b)) as f32
            }),
            r_p: Some(|c1, c2, e1, e2| {
                let (a, b) = (e2 as f64 * c1 as f64, e1 as f64 * c2 as f64);
                ((a - b) / (a + b)) as f32
            }),
            ..NONE
        },
        Variant {
            name: "alternative: reflectance as seen from the other side, fresnel_R(cos θ₂, cos θ₁, η₂, η₁)",
            verdict: Verdict::Accept,
            reflectance: Some(|c, e1, e2| {
                let s2 = sin2_t(c, e1 / e2);
                if s2 >= 1.0 {
                    1.0
                } else {
                    Reference.fresnel_R((1.0 - s2).sqrt(), c, e2, e1)
                }
            }),
            ..NONE
        },
        Variant {
            name: "alternative: reflectance with the critical angle tested on sin θ₂, transmittance as 1/e^(σd) with σ = (1 − ρ)/ρ",
            verdict: Verdict::Accept,
            reflectance: Some(|c, e1, e2| {
                let sin_t = e1 / e2 * (1.0 - c * c).max(0.0).sqrt();
                if sin_t >= 1.0 {
                    return 1.0;
                }
                let cos_t = ((1.0 - sin_t) * (1.0 + sin_t)).sqrt();
                Reference.fresnel_R(c, cos_t, e1, e2)
            }),
            transmittance: Some(|d, m| {
                Vec3::from(m.diffuse.to_array().map(|rho| {
                    let sigma = if rho < 1e-6 { 1e7 } else { (1.0 - rho) / rho };
                    1.0 / (sigma * d).exp()
                }))
            }),
            ..NONE
        },
    ]
}

grading::corpus_tests!(lab10, lab10_checks, reference);
