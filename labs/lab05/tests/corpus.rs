//! Lab 05's mutant corpus: realistic wrong implementations, each with the exercise that must
//! reject it, and alternative correct ones every exercise must accept; each variant overrides
//! one or two functions of the answer key. The tests at the end run it through the lab's checks
//! with and without the key, and check the reference passes and the stubs fail cleanly. This
//! file is the instructors' (a handout leaves it out).

use std::f64::consts::PI;

use contracts::lab05::{
    DiffuseEmitter, Observation, PEAK_LUMINOUS_EFFICACY_LM_PER_W, PLANCK_J_S, Radiometry, Receiver,
    RectangleLight, SPEED_OF_LIGHT_M_PER_S, SphericalBulb,
};
use raylab_core::glam::DVec3;
use raylab_core::math::Onb;
use raylab_core::sampling::Rng;
use reference::lab05::Lab05 as Reference;

use grading::corpus::Verdict;

type PhotonsFn = fn(f64, f64, f64) -> f64;
type BulbFn = fn(f64, f64, f64, f64) -> SphericalBulb;
type ObserveFn = fn(f64, f64, f64) -> Observation;
type IlluminanceFn = fn(f64, f64) -> f64;
type EquivalentFn = fn(f64, f64, f64) -> f64;
type EmitterFn = fn(f64, f64) -> DiffuseEmitter;
type RadiosityFn = fn(&dyn Fn(f64, f64) -> f64, u32) -> f64;
type EstimatorFn = fn(&RectangleLight, &Receiver, u32, &mut Rng) -> f64;

/// A lab 05 variant: the reference with some functions replaced.
#[derive(Clone, Copy)]
pub struct Variant {
    /// What the variant does.
    pub name: &'static str,
    /// Mistake or alternative.
    pub verdict: Verdict,
    photons: Option<PhotonsFn>,
    bulb: Option<BulbFn>,
    observe: Option<ObserveFn>,
    illuminance: Option<IlluminanceFn>,
    equivalent: Option<EquivalentFn>,
    emitter: Option<EmitterFn>,
    radiosity: Option<RadiosityFn>,
    area: Option<EstimatorFn>,
    cosine: Option<EstimatorFn>,
}

const NONE: Variant = Variant {
    name: "",
    verdict: Verdict::Accept,
    photons: None,
    bulb: None,
    observe: None,
    illuminance: None,
    equivalent: None,
    emitter: None,
    radiosity: None,
    area: None,
    cosine: None,
};

impl Radiometry for Variant {
    fn photons_per_second(&self, p: f64, eta: f64, l: f64) -> f64 {
        self.photons
            .map_or_else(|| Reference.photons_per_second(p, eta, l), |f| f(p, eta, l))
    }
    fn spherical_bulb(&self, u: f64, i: f64, d: f64, t: f64) -> SphericalBulb {
        self.bulb
            .map_or_else(|| Reference.spherical_bulb(u, i, d, t), |f| f(u, i, d, t))
    }
    fn observe_point_source(&self, phi: f64, r: f64, d: f64) -> Observation {
        self.observe.map_or_else(
            || Reference.observe_point_source(phi, r, d),
            |f| f(phi, r, d),
        )
    }
    fn illuminance_lux(&self, e: f64, l: f64) -> f64 {
        self.illuminance
            .map_or_else(|| Reference.illuminance_lux(e, l), |f| f(e, l))
    }
    fn equivalent_intensity_cd(&self, i: f64, rk: f64, ru: f64) -> f64 {
        self.equivalent.map_or_else(
            || Reference.equivalent_intensity_cd(i, rk, ru),
            |f| f(i, rk, ru),
        )
    }
    fn diffuse_emitter(&self, l: f64, a: f64) -> DiffuseEmitter {
        self.emitter
            .map_or_else(|| Reference.diffuse_emitter(l, a), |f| f(l, a))
    }
    fn radiosity_from_radiance(&self, radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
        match self.radiosity {
            Some(f) => f(radiance, steps),
            None => Reference.radiosity_from_radiance(radiance, steps),
        }
    }
    fn irradiance_area_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64 {
        match self.area {
            Some(f) => f(light, receiver, samples, rng),
            None => Reference.irradiance_area_sampling(light, receiver, samples, rng),
        }
    }
    fn irradiance_cosine_sampling(
        &self,
        light: &RectangleLight,
        receiver: &Receiver,
        samples: u32,
        rng: &mut Rng,
    ) -> f64 {
        match self.cosine {
            Some(f) => f(light, receiver, samples, rng),
            None => Reference.irradiance_cosine_sampling(light, receiver, samples, rng),
        }
    }
}

/// The bulb with intensity `i(Φ)` and exitance `m(Φ, d)`.
fn bulb(
    u: f64,
    c: f64,
    d: f64,
    t: f64,
    i: fn(f64) -> f64,
    m: fn(f64, f64) -> f64,
) -> SphericalBulb {
    let flux = u * c;
    SphericalBulb {
        radiant_flux_w: flux,
        radiant_intensity_w_per_sr: i(flux),
        radiant_exitance_w_per_m2: m(flux, d),
        emitted_energy_j: flux * t,
    }
}

/// The average of `f(u)` over `n` draws `u = rng.next_vec2()`.
fn average(n: u32, rng: &mut Rng, mut f: impl FnMut(f64, f64) -> f64) -> f64 {
    let mut sum = 0.0;
    for _ in 0..n {
        let u = rng.next_vec2().as_dvec2();
        sum += f(u.x, u.y);
    }
    sum / n as f64
}

/// The area-form integrand over the pdf at the light's point `(s, t)`, with the light's
/// cosine `cos_l` given by the caller's rule.
fn area_term(
    light: &RectangleLight,
    rx: &Receiver,
    s: f64,
    t: f64,
    light_cosine: bool,
    pdf_times_area: bool,
) -> f64 {
    let d = light.point(s, t) - rx.position;
    let r2 = d.length_squared();
    let w = d / r2.sqrt();
    let cos_r = rx.normal.dot(w).max(0.0);
    let cos_l = if light_cosine {
        (-light.normal().dot(w)).max(0.0)
    } else {
        1.0
    };
    let weight = if pdf_times_area {
        light.area_m2()
    } else {
        1.0 / light.area_m2()
    };
    light.radiance_w_per_m2_sr * cos_r * cos_l / r2 * weight
}

/// A direction about `n` from the local `(x, y, z)`, through the framework's basis.
fn around(n: DVec3, local: DVec3) -> DVec3 {
    Onb::from_w(n.as_vec3())
        .to_world(local.as_vec3())
        .as_dvec3()
        .normalize()
}

/// Every lab 05 variant.
pub fn variants() -> Vec<Variant> {
    vec![
        // ---- Exercise 5.1 mistakes
        Variant {
            name: "photons: the hand-in's rounded constants (c = 3·10⁸ m/s, h = 6.626·10⁻³⁴ J s)",
            verdict: Verdict::Reject("5.1"),
            photons: Some(|p, eta, l| p * eta / (6.626e-34 * 3e8 / (l * 1e-9))),
            ..NONE
        },
        Variant {
            name: "photons: the wavelength left in nanometres",
            verdict: Verdict::Reject("5.1"),
            photons: Some(|p, eta, l| p * eta / (PLANCK_J_S * SPEED_OF_LIGHT_M_PER_S / l)),
            ..NONE
        },
        Variant {
            name: "photons: the efficiency forgotten (all the electrical power as light)",
            verdict: Verdict::Reject("5.1"),
            photons: Some(|p, _, l| p / (PLANCK_J_S * SPEED_OF_LIGHT_M_PER_S / (l * 1e-9))),
            ..NONE
        },
        // ---- Exercise 5.2 mistakes
        Variant {
            name: "bulb: the hand-in's numbers (I = Φ/4 = 0.42 W/sr, and M = I as for a unit sphere)",
            verdict: Verdict::Reject("5.2"),
            bulb: Some(|u, c, d, t| bulb(u, c, d, t, |f| f / 4.0, |f, _| f / 4.0)),
            ..NONE
        },
        Variant {
            name: "bulb: exitance over a unit sphere's area 4π m², not the bulb's",
            verdict: Verdict::Reject("5.2"),
            bulb: Some(|u, c, d, t| bulb(u, c, d, t, |f| f / (4.0 * PI), |f, _| f / (4.0 * PI))),
            ..NONE
        },
        Variant {
            name: "bulb: the diameter taken for the radius in the sphere's area",
            verdict: Verdict::Reject("5.2"),
            bulb: Some(|u, c, d, t| {
                bulb(
                    u,
                    c,
                    d,
                    t,
                    |f| f / (4.0 * PI),
                    |f, d| f / (4.0 * PI * d * d),
                )
            }),
            ..NONE
        },
        Variant {
            name: "bulb: intensity over the hemisphere, Φ/2π",
            verdict: Verdict::Reject("5.2"),
            bulb: Some(|u, c, d, t| bulb(u, c, d, t, |f| f / (2.0 * PI), |f, d| f / (PI * d * d))),
            ..NONE
        },
        // ---- Exercise 5.3 mistakes
        Variant {
            name: "observe: E = Φ/r², the 4π forgotten",
            verdict: Verdict::Reject("5.3"),
            observe: Some(|phi, r, d| {
                let e = phi / (r * r);
                Observation {
                    irradiance_w_per_m2: e,
                    pupil_power_w: e * PI * 0.25 * d * d,
                }
            }),
            ..NONE
        },
        Variant {
            name: "observe: the pupil's diameter taken for its radius",
            verdict: Verdict::Reject("5.3"),
            observe: Some(|phi, r, d| {
                let e = phi / (4.0 * PI * r * r);
                Observation {
                    irradiance_w_per_m2: e,
                    pupil_power_w: e * PI * d * d,
                }
            }),
            ..NONE
        },
        // ---- Exercise 5.4 mistakes
        Variant {
            name: "illuminance: the hand-in's 685 lm/W and V(650 nm) = 0.1 at every wavelength",
            verdict: Verdict::Reject("5.4"),
            illuminance: Some(|e, _| 685.0 * 0.1 * e),
            ..NONE
        },
        Variant {
            name: "illuminance: 683 lm/W without V(λ)",
            verdict: Verdict::Reject("5.4"),
            illuminance: Some(|e, _| PEAK_LUMINOUS_EFFICACY_LM_PER_W * e),
            ..NONE
        },
        // ---- Exercise 5.5 mistakes
        Variant {
            name: "equivalent: the distances' ratio not squared",
            verdict: Verdict::Reject("5.5"),
            equivalent: Some(|i, rk, ru| i * ru / rk),
            ..NONE
        },
        Variant {
            name: "equivalent: the ratio upside down",
            verdict: Verdict::Reject("5.5"),
            equivalent: Some(|i, rk, ru| i * (rk / ru).powi(2)),
            ..NONE
        },
        // ---- Exercise 5.6 mistakes
        Variant {
            name: "emitter: π forgotten (Φ = L·A, B = L)",
            verdict: Verdict::Reject("5.6"),
            emitter: Some(|l, a| DiffuseEmitter {
                radiant_flux_w: l * a,
                radiosity_w_per_m2: l,
            }),
            ..NONE
        },
        Variant {
            name: "emitter: the hemisphere's 2π sr instead of its projected solid angle π",
            verdict: Verdict::Reject("5.6"),
            emitter: Some(|l, a| DiffuseEmitter {
                radiant_flux_w: 2.0 * PI * l * a,
                radiosity_w_per_m2: 2.0 * PI * l,
            }),
            ..NONE
        },
        // ---- Exercise 5.7 mistakes
        Variant {
            name: "radiosity: the hand-in's limits, θ over [0, π] (the whole sphere)",
            verdict: Verdict::Reject("5.7"),
            radiosity: Some(|l, n| midpoint(l, n, PI, |t| t.cos() * t.sin())),
            ..NONE
        },
        Variant {
            name: "radiosity: dω = dθ dφ, the sin θ forgotten",
            verdict: Verdict::Reject("5.7"),
            radiosity: Some(|l, n| midpoint(l, n, 0.5 * PI, f64::cos)),
            ..NONE
        },
        Variant {
            name: "radiosity: the cos θ forgotten (radiance integrated over solid angle)",
            verdict: Verdict::Reject("5.7"),
            radiosity: Some(|l, n| midpoint(l, n, 0.5 * PI, f64::sin)),
            ..NONE
        },
        // ---- Exercise 5.8 mistakes
        Variant {
            name: "area sampling: the light's cosine forgotten",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| average(n, rng, |s, t| area_term(l, rx, s, t, false, true))),
            ..NONE
        },
        Variant {
            name: "area sampling: divided by the area instead of by the pdf 1/A",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| average(n, rng, |s, t| area_term(l, rx, s, t, true, false))),
            ..NONE
        },
        Variant {
            name: "area sampling: a generator of its own, seeded afresh on every call",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, _| {
                let mut own = Rng::new(0, 0);
                average(n, &mut own, |s, t| area_term(l, rx, s, t, true, true))
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: one point drawn per call and used for every sample",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, _, rng| {
                let u = rng.next_vec2().as_dvec2();
                area_term(l, rx, u.x, u.y, true, true)
            }),
            ..NONE
        },
        // ---- Exercise 5.9 mistakes
        Variant {
            name: "cosine sampling: weighted 2π·L (the uniform hemisphere's 1/pdf)",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| {
                average(n, rng, |a, b| {
                    let (r, phi) = (a.sqrt(), 2.0 * PI * b);
                    let w = around(
                        rx.normal,
                        DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - a).sqrt()),
                    );
                    2.0 * PI * l.radiance_along(rx.position, w)
                })
            }),
            ..NONE
        },
        Variant {
            name: "cosine sampling: uniform directions on the hemisphere (z = u) weighted as cosine-distributed",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| {
                average(n, rng, |a, b| {
                    let (z, phi) = (a, 2.0 * PI * b);
                    let r = (1.0 - z * z).max(0.0).sqrt();
                    let w = around(rx.normal, DVec3::new(r * phi.cos(), r * phi.sin(), z));
                    PI * l.radiance_along(rx.position, w)
                })
            }),
            ..NONE
        },
        Variant {
            name: "radiosity: the θ loop stops one ring short (0..steps − 1: the ring at the horizon left out)",
            verdict: Verdict::Reject("5.7"),
            radiosity: Some(|l, n| theta_rule(l, n, n.saturating_sub(1), 0.5)),
            ..NONE
        },
        Variant {
            name: "radiosity: θ at the cells' left ends, θ_i = i·Δθ (the half step forgotten)",
            verdict: Verdict::Reject("5.7"),
            radiosity: Some(|l, n| theta_rule(l, n, n, 0.0)),
            ..NONE
        },
        Variant {
            name: "radiosity: φ over half a turn, [0, π) in 2·steps cells, doubled (as if every L were symmetric in φ)",
            verdict: Verdict::Reject("5.7"),
            radiosity: Some(|l, n| {
                let (dt, dp) = (0.5 * PI / n as f64, 2.0 * PI / (4 * n) as f64);
                let mut sum = 0.0;
                for i in 0..n {
                    let t = (i as f64 + 0.5) * dt;
                    for j in 0..2 * n {
                        sum += 2.0 * l(t, (j as f64 + 0.5) * dp) * t.cos() * t.sin() * dt * dp;
                    }
                }
                sum
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: the light taken as two-sided, cos θ_l = |n_l·ω|",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| {
                let rule = AreaRule {
                    cos_l: |nl, w| nl.dot(w).abs(),
                    ..AREA
                };
                area_sampled(rule, l, rx, n, rng)
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: the receiver's cosine not clamped (light below the horizon subtracts)",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| {
                let rule = AreaRule {
                    cos_r: |n, w| n.dot(w),
                    ..AREA
                };
                area_sampled(rule, l, rx, n, rng)
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: the area as |edge_u|·|edge_v| (a rectangle's)",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| {
                let rule = AreaRule {
                    area: |l| l.edge_u.length() * l.edge_v.length(),
                    ..AREA
                };
                area_sampled(rule, l, rx, n, rng)
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: the light's normal as û × v̂ of the unit edges (unit only when they are perpendicular)",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| {
                let rule = AreaRule {
                    normal: |l| l.edge_u.normalize().cross(l.edge_v.normalize()),
                    ..AREA
                };
                area_sampled(rule, l, rx, n, rng)
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: the receiver's cosine taken from world up (ω.y), not its normal",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| {
                let rule = AreaRule {
                    cos_r: |_, w| w.y.max(0.0),
                    ..AREA
                };
                area_sampled(rule, l, rx, n, rng)
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: one number for both coordinates, light.point(u.x, u.x)",
            verdict: Verdict::Reject("5.8"),
            area: Some(|l, rx, n, rng| average(n, rng, |s, _| area_term(l, rx, s, s, true, true))),
            ..NONE
        },
        Variant {
            name: "cosine sampling: its own hit test, (s, t) by projecting onto the edges (right only for perpendicular edges)",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| cosine_sampled(l, rx, n, rng, unit_frame, rectangle_hit)),
            ..NONE
        },
        Variant {
            name: "cosine sampling: the tangent frame not normalised (t = n × x̂, b = n × t)",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| {
                cosine_sampled(
                    l,
                    rx,
                    n,
                    rng,
                    |n| {
                        let a = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
                        let t = n.cross(a);
                        (t, n.cross(t))
                    },
                    |l, p, w| l.radiance_along(p, w),
                )
            }),
            ..NONE
        },
        Variant {
            name: "cosine sampling: Frisvad's frame without its special case at n = −z (a = 1/(1 + n_z))",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| {
                cosine_sampled(
                    l,
                    rx,
                    n,
                    rng,
                    |n| {
                        let a = 1.0 / (1.0 + n.z);
                        let b = -n.x * n.y * a;
                        (
                            DVec3::new(1.0 - n.x * n.x * a, b, -n.x),
                            DVec3::new(b, 1.0 - n.y * n.y * a, -n.y),
                        )
                    },
                    |l, p, w| l.radiance_along(p, w),
                )
            }),
            ..NONE
        },
        Variant {
            name: "cosine sampling: directions about world up (y), not the receiver's normal",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| {
                let up = Receiver {
                    normal: DVec3::Y,
                    ..*rx
                };
                cosine_sampled(l, &up, n, rng, unit_frame, |l, p, w| l.radiance_along(p, w))
            }),
            ..NONE
        },
        Variant {
            name: "cosine sampling: one number for radius and angle (r = √u₁, φ = 2πu₁)",
            verdict: Verdict::Reject("5.9"),
            cosine: Some(|l, rx, n, rng| {
                average(n, rng, |a, _| {
                    let (r, phi) = (a.sqrt(), 2.0 * PI * a);
                    let w = around(
                        rx.normal,
                        DVec3::new(r * phi.cos(), r * phi.sin(), (1.0 - a).sqrt()),
                    );
                    PI * l.radiance_along(rx.position, w)
                })
            }),
            ..NONE
        },
        // ---- Correct alternatives
        Variant {
            name: "photons: through the frequency, f = c/λ and q = h·f (the hand-in's route)",
            verdict: Verdict::Accept,
            photons: Some(|p, eta, l| {
                let f = SPEED_OF_LIGHT_M_PER_S / (l * 1e-9);
                eta * p / (PLANCK_J_S * f)
            }),
            ..NONE
        },
        Variant {
            name: "radiosity: the midpoint rule in μ = cos θ (dω = dμ dφ)",
            verdict: Verdict::Accept,
            radiosity: Some(|l, n| {
                let (m, k) = (n as usize, 4 * n as usize);
                let (dmu, dphi) = (1.0 / m as f64, 2.0 * PI / k as f64);
                let mut sum = 0.0;
                for i in 0..m {
                    let mu = (i as f64 + 0.5) * dmu;
                    for j in 0..k {
                        sum += l(mu.acos(), (j as f64 + 0.5) * dphi) * mu * dmu * dphi;
                    }
                }
                sum
            }),
            ..NONE
        },
        Variant {
            name: "radiosity: Simpson's rule in θ (each interval's ends and middle), the midpoint rule in φ",
            verdict: Verdict::Accept,
            radiosity: Some(|l, n| {
                let (m, k) = (n as usize, 4 * n as usize);
                let (dt, dp) = (0.5 * PI / m as f64, 2.0 * PI / k as f64);
                let ring = |t: f64| {
                    let around: f64 = (0..k).map(|j| l(t, (j as f64 + 0.5) * dp)).sum();
                    around * dp * t.cos() * t.sin()
                };
                let mut sum = 0.0;
                for i in 0..m {
                    let a = i as f64 * dt;
                    sum += dt / 6.0 * (ring(a) + 4.0 * ring(a + 0.5 * dt) + ring(a + dt));
                }
                sum
            }),
            ..NONE
        },
        Variant {
            name: "area sampling: jittered (stratified) points on the light",
            verdict: Verdict::Accept,
            area: Some(|l, rx, n, rng| {
                let k = (n as f64).sqrt() as u32;
                if k * k != n {
                    return average(n, rng, |s, t| area_term(l, rx, s, t, true, true));
                }
                let mut sum = 0.0;
                for j in 0..k {
                    for i in 0..k {
                        let u = rng.next_vec2().as_dvec2();
                        let (s, t) = ((i as f64 + u.x) / k as f64, (j as f64 + u.y) / k as f64);
                        sum += area_term(l, rx, s, t, true, true);
                    }
                }
                sum / n as f64
            }),
            ..NONE
        },
        Variant {
            name: "cosine sampling: Shirley–Chiu's concentric disc, lifted, in the framework's Onb",
            verdict: Verdict::Accept,
            cosine: Some(|l, rx, n, rng| {
                average(n, rng, |a, b| {
                    let (x, y) = (2.0 * a - 1.0, 2.0 * b - 1.0);
                    let (r, phi) = if x == 0.0 && y == 0.0 {
                        (0.0, 0.0)
                    } else if x.abs() > y.abs() {
                        (x, 0.25 * PI * (y / x))
                    } else {
                        (y, 0.5 * PI - 0.25 * PI * (x / y))
                    };
                    let (dx, dy) = (r * phi.cos(), r * phi.sin());
                    let z = (1.0 - dx * dx - dy * dy).max(0.0).sqrt();
                    PI * l.radiance_along(rx.position, around(rx.normal, DVec3::new(dx, dy, z)))
                })
            }),
            ..NONE
        },
    ]
}

/// The pieces of an area-sampling estimator a mistake changes: the light's normal and area,
/// and the receiver's and the light's cosine from the unit direction `w` to the light point.
#[derive(Clone, Copy)]
struct AreaRule {
    normal: fn(&RectangleLight) -> DVec3,
    area: fn(&RectangleLight) -> f64,
    cos_r: fn(DVec3, DVec3) -> f64,
    cos_l: fn(DVec3, DVec3) -> f64,
}

/// The correct rule.
const AREA: AreaRule = AreaRule {
    normal: RectangleLight::normal,
    area: RectangleLight::area_m2,
    cos_r: |n, w| n.dot(w).max(0.0),
    cos_l: |nl, w| (-nl.dot(w)).max(0.0),
};

/// Uniform area sampling by `rule`.
fn area_sampled(
    rule: AreaRule,
    light: &RectangleLight,
    rx: &Receiver,
    n: u32,
    rng: &mut Rng,
) -> f64 {
    let (nl, area) = ((rule.normal)(light), (rule.area)(light));
    average(n, rng, |s, t| {
        let d = light.point(s, t) - rx.position;
        let r2 = d.length_squared();
        let w = d / r2.sqrt();
        light.radiance_w_per_m2_sr * (rule.cos_r)(rx.normal, w) * (rule.cos_l)(nl, w) / r2 * area
    })
}

/// A normalised tangent frame about the unit `n`.
fn unit_frame(n: DVec3) -> (DVec3, DVec3) {
    let a = if n.x.abs() > 0.9 { DVec3::Y } else { DVec3::X };
    let t = n.cross(a).normalize();
    (t, n.cross(t))
}

/// Malley's method in the frame `frame(n)`, each direction looked up by `lookup`.
fn cosine_sampled(
    light: &RectangleLight,
    rx: &Receiver,
    n: u32,
    rng: &mut Rng,
    frame: fn(DVec3) -> (DVec3, DVec3),
    lookup: fn(&RectangleLight, DVec3, DVec3) -> f64,
) -> f64 {
    let (t, b) = frame(rx.normal);
    average(n, rng, |a, c| {
        let (r, phi) = (a.sqrt(), 2.0 * PI * c);
        let w = r * phi.cos() * t + r * phi.sin() * b + (1.0 - a).max(0.0).sqrt() * rx.normal;
        PI * lookup(light, rx.position, w)
    })
}

/// The radiance along `w` by a hit test that finds the parallelogram coordinates by projecting
/// onto each edge, `s = d·u/|u|²` — the coordinates only when the edges are perpendicular.
fn rectangle_hit(l: &RectangleLight, origin: DVec3, w: DVec3) -> f64 {
    let n = l.normal();
    let facing = w.dot(n);
    if facing >= 0.0 {
        return 0.0;
    }
    let t = (l.corner - origin).dot(n) / facing;
    if t <= 0.0 {
        return 0.0;
    }
    let d = origin + t * w - l.corner;
    let s = d.dot(l.edge_u) / l.edge_u.length_squared();
    let r = d.dot(l.edge_v) / l.edge_v.length_squared();
    if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&r) {
        l.radiance_w_per_m2_sr
    } else {
        0.0
    }
}

/// The rule of `n` θ intervals and `4n` φ intervals summed over the first `cells` θ cells,
/// `θ_i = (i + offset)·Δθ`.
fn theta_rule(l: &dyn Fn(f64, f64) -> f64, n: u32, cells: u32, offset: f64) -> f64 {
    let (dt, dp) = (0.5 * PI / n as f64, 2.0 * PI / (4 * n) as f64);
    let mut sum = 0.0;
    for i in 0..cells {
        let t = (i as f64 + offset) * dt;
        for j in 0..4 * n {
            sum += l(t, (j as f64 + 0.5) * dp) * t.cos() * t.sin() * dt * dp;
        }
    }
    sum
}

/// The midpoint rule over θ ∈ [0, θ_max] (`n` steps) and φ ∈ [0, 2π) (`4n`) of
/// `L(θ, φ)·weight(θ)`.
fn midpoint(l: &dyn Fn(f64, f64) -> f64, n: u32, theta_max: f64, weight: fn(f64) -> f64) -> f64 {
    let (m, k) = (n as usize, 4 * n as usize);
    let (dt, dp) = (theta_max / m as f64, 2.0 * PI / k as f64);
    let mut sum = 0.0;
    for i in 0..m {
        let t = (i as f64 + 0.5) * dt;
        for j in 0..k {
            sum += l(t, (j as f64 + 0.5) * dp) * weight(t) * dt * dp;
        }
    }
    sum
}

grading::corpus_tests!(lab05, lab05_checks, reference);
