//! The polygonal lights and receivers of the Monte Carlo irradiance checks.

use glam::DVec3;

use contracts::lab05::{Receiver, RectangleLight};
use grading::radiometry::irradiance_polygon;

/// Samples per estimate in the Monte Carlo checks.
pub const MC_SAMPLES: u32 = 16;
/// Estimates per configuration and scale.
pub const MC_ESTIMATES: u32 = 256;

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
