//! Lab 12's answer key — path tracing (docs/lab12.md).

use std::f32::consts::{FRAC_1_PI, PI, TAU};

use contracts::glam::{Vec2, Vec3};
use contracts::lab12::{
    BsdfSample, BsdfValue, EmitterSample, PathHit, PathMaterial, PathTracing, PathVertex,
    PixelStatistics, SkyDistribution, SkySample,
};
use contracts::math::{Onb, RAY_EPSILON, Ray};
use contracts::sampling::Rng;

/// The reference solution of lab 12.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab12;

/// The probability of drawing from the glossy lobe: its share of the summed reflectances.
fn glossy_probability(material: &PathMaterial) -> f32 {
    let (d, s) = (material.diffuse.element_sum(), material.glossy.element_sum());
    if s > 0.0 { s / (d + s) } else { 0.0 }
}

/// `cos^n α` of the glossy lobe about `mirror`, 0 where `wi` is on its far side.
fn lobe(mirror: Vec3, wi: Vec3, exponent: f32) -> f32 {
    let cos = mirror.dot(wi);
    if cos > 0.0 { cos.min(1.0).powf(exponent) } else { 0.0 }
}

/// The mirror direction of `wo` about `normal`.
fn mirror(normal: Vec3, wo: Vec3) -> Vec3 {
    2.0 * normal.dot(wo) * normal - wo
}

/// The cumulative table of `weights` from 0 to 1, uniform where they weigh nothing.
fn cumulative(weights: &[f64]) -> Vec<f32> {
    let total: f64 = weights.iter().sum();
    let n = weights.len();
    let mut cdf = Vec::with_capacity(n + 1);
    cdf.push(0.0);
    let mut sum = 0.0;
    for (i, w) in weights.iter().enumerate() {
        sum += w;
        cdf.push(if total > 0.0 {
            (sum / total) as f32
        } else {
            (i + 1) as f32 / n as f32
        });
    }
    cdf[n] = 1.0;
    cdf
}

/// The cell of the cumulative table `cdf` that `xi` falls in, and where in it (0 to 1).
fn invert(cdf: &[f32], xi: f32) -> (usize, f32) {
    let cells = cdf.len() - 1;
    let i = cdf.partition_point(|&c| c <= xi).saturating_sub(1).min(cells - 1);
    let width = cdf[i + 1] - cdf[i];
    let t = if width > 0.0 { (xi - cdf[i]) / width } else { 0.5 };
    (i, t.clamp(0.0, 1.0))
}

/// The density over the image's `(u, v)` of the texel `(x, y)`: its probability times the
/// texel count.
fn texel_density(sky: &SkyDistribution, x: usize, y: usize) -> f32 {
    let row = sky.row(y);
    (sky.marginal[y + 1] - sky.marginal[y]) * (row[x + 1] - row[x]) * (sky.width * sky.height) as f32
}

/// A unit direction about the +z axis of `frame` at cosine `cos` and azimuth `phi`.
fn direction(frame: &Onb, cos: f32, phi: f32) -> Vec3 {
    let sin = (1.0 - cos * cos).max(0.0).sqrt();
    frame
        .to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), cos))
        .normalize()
}

impl PathTracing for Lab12 {
    fn luminance(&self, colour: Vec3) -> f32 {
        0.2126 * colour.x + 0.7152 * colour.y + 0.0722 * colour.z
    }

    fn bsdf(&self, material: &PathMaterial, normal: Vec3, wo: Vec3, wi: Vec3) -> BsdfValue {
        let (cos_o, cos_i) = (normal.dot(wo), normal.dot(wi));
        if cos_o <= 0.0 || cos_i <= 0.0 {
            return BsdfValue {
                value: Vec3::ZERO,
                pdf: 0.0,
            };
        }
        let n = material.exponent;
        let lobe = lobe(mirror(normal, wo), wi, n);
        let p = glossy_probability(material);
        BsdfValue {
            value: material.diffuse * FRAC_1_PI + material.glossy * ((n + 2.0) / TAU * lobe),
            pdf: (1.0 - p) * cos_i * FRAC_1_PI + p * (n + 1.0) / TAU * lobe,
        }
    }

    fn sample_bsdf(
        &self,
        material: &PathMaterial,
        normal: Vec3,
        wo: Vec3,
        rng: &mut Rng,
    ) -> Option<BsdfSample> {
        let choice = rng.next_f32();
        let u: Vec2 = rng.next_vec2();
        let wi = if choice < glossy_probability(material) {
            // cos α = u^(1/(n+1)) inverts the lobe's distribution of cos α.
            let cos = u.x.powf(1.0 / (material.exponent + 1.0));
            direction(&Onb::from_w(mirror(normal, wo)), cos, TAU * u.y)
        } else {
            // Malley's method: a uniform point of the disc lifted to the hemisphere.
            direction(&Onb::from_w(normal), (1.0 - u.x).max(0.0).sqrt(), TAU * u.y)
        };
        if normal.dot(wi) <= 0.0 || normal.dot(wo) <= 0.0 {
            return None;
        }
        let BsdfValue { value, pdf } = self.bsdf(material, normal, wo, wi);
        Some(BsdfSample {
            direction: wi,
            value,
            pdf,
        })
    }

    fn sample_emitter(
        &self,
        triangle: [Vec3; 3],
        radiance: Vec3,
        position: Vec3,
        rng: &mut Rng,
    ) -> Option<EmitterSample> {
        let u = rng.next_vec2();
        let [a, b, c] = triangle;
        let s = u.x.sqrt();
        let point = a * (1.0 - s) + b * (s * (1.0 - u.y)) + c * (s * u.y);
        let to = point - position;
        let distance = to.length();
        let direction = to / distance;
        let pdf = self.emitter_pdf(triangle, position, direction, distance);
        (pdf > 0.0 && pdf.is_finite()).then_some(EmitterSample {
            direction,
            distance,
            radiance,
            pdf,
            delta: false,
        })
    }

    fn emitter_pdf(
        &self,
        triangle: [Vec3; 3],
        _position: Vec3,
        direction: Vec3,
        distance: f32,
    ) -> f32 {
        let [a, b, c] = triangle;
        let cross = (b - a).cross(c - a);
        let double_area = cross.length();
        // The cosine at the emitter, between its normal and the way back to the point.
        let cos = -cross.dot(direction) / double_area;
        if double_area > 0.0 && cos > 0.0 {
            distance * distance / (0.5 * double_area * cos)
        } else {
            0.0
        }
    }

    fn power_heuristic(&self, pdf: f32, other_pdf: f32) -> f32 {
        if pdf <= 0.0 {
            return 0.0;
        }
        // pdf² / (pdf² + other²) without squaring large densities.
        let ratio = other_pdf / pdf;
        1.0 / (1.0 + ratio * ratio)
    }

    fn roulette(&self, throughput: Vec3, rng: &mut Rng) -> Option<f32> {
        let u = rng.next_f32();
        let largest = throughput.max_element();
        // A NaN throughput ends the path too (`f32::min` would take 1 for NaN).
        let q = largest.min(1.0);
        (largest > 0.0 && u < q).then(|| 1.0 / q)
    }

    fn path_radiance(
        &self,
        ray: &Ray,
        max_depth: u32,
        trace: &dyn Fn(&Ray) -> PathHit,
        occluded: &dyn Fn(&Ray) -> bool,
        sample_light: &dyn Fn(Vec3, &mut Rng) -> Option<EmitterSample>,
        sample_bsdf: &dyn Fn(&PathVertex, Vec3, &mut Rng) -> Option<BsdfSample>,
        bsdf: &dyn Fn(&PathVertex, Vec3, Vec3) -> BsdfValue,
        power_heuristic: &dyn Fn(f32, f32) -> f32,
        roulette: &dyn Fn(Vec3, &mut Rng) -> Option<f32>,
        rng: &mut Rng,
    ) -> Vec3 {
        let mut radiance = Vec3::ZERO;
        let mut throughput = Vec3::ONE;
        let mut ray = *ray;
        // The density with which the BSDF drew the ray; none for the camera's.
        let mut bsdf_pdf = None;
        for depth in 0..=max_depth {
            // The light this ray finds, weighted against the light sampler that could have
            // found it too (the camera ray's in full).
            let weight = |light_pdf: f32| bsdf_pdf.map_or(1.0, |p| power_heuristic(p, light_pdf));
            let vertex = match trace(&ray) {
                PathHit::Escaped {
                    radiance: sky,
                    light_pdf,
                } => {
                    if sky != Vec3::ZERO {
                        radiance += throughput * sky * weight(light_pdf);
                    }
                    break;
                }
                PathHit::Surface(vertex) => vertex,
            };
            if vertex.emitted != Vec3::ZERO {
                radiance += throughput * vertex.emitted * weight(vertex.light_pdf);
            }
            if depth == max_depth {
                break;
            }
            let wo = -ray.direction;
            // Next-event estimation, weighted against the BSDF's density of the same direction.
            if let Some(light) = sample_light(vertex.position, rng) {
                let cos = vertex.normal.dot(light.direction);
                let f = bsdf(&vertex, wo, light.direction);
                if cos > 0.0 && f.value != Vec3::ZERO {
                    let shadow = Ray::new(
                        vertex.position,
                        light.direction,
                        RAY_EPSILON,
                        light.distance * (1.0 - 1e-4),
                    );
                    if !occluded(&shadow) {
                        // Only next-event estimation finds a delta light: weight one.
                        let weight = if light.delta {
                            1.0
                        } else {
                            power_heuristic(light.pdf, f.pdf)
                        };
                        radiance +=
                            throughput * f.value * light.radiance * cos / light.pdf * weight;
                    }
                }
            }
            let Some(next) = sample_bsdf(&vertex, wo, rng) else {
                break;
            };
            throughput *= next.value * vertex.normal.dot(next.direction) / next.pdf;
            bsdf_pdf = Some(next.pdf);
            ray = Ray::unbounded(vertex.position, next.direction, RAY_EPSILON);
            if depth >= 2 {
                match roulette(throughput, rng) {
                    Some(factor) => throughput *= factor,
                    None => break,
                }
            }
        }
        radiance
    }

    fn accumulate(&self, stats: &PixelStatistics, radiance: Vec3) -> PixelStatistics {
        let count = stats.count + 1;
        let delta = radiance - stats.mean;
        let mean = stats.mean + delta / count as f32;
        PixelStatistics {
            count,
            mean,
            m2: stats.m2 + delta * (radiance - mean),
        }
    }

    fn relative_error(&self, stats: &PixelStatistics) -> f32 {
        if stats.count < 2 {
            return f32::INFINITY;
        }
        let n = stats.count as f32;
        let standard_error = (stats.m2 / (n - 1.0) / n).max(Vec3::ZERO).powf(0.5);
        (0..3)
            .map(|c| {
                if stats.mean[c] == 0.0 {
                    0.0
                } else {
                    standard_error[c] / stats.mean[c].abs()
                }
            })
            .fold(0.0, f32::max)
    }

    fn sky_distribution(&self, luminance: &[f32], width: u32, height: u32) -> SkyDistribution {
        let (w, h) = (width as usize, height as usize);
        let mut marginal = Vec::with_capacity(h);
        let mut conditional = Vec::with_capacity(h * (w + 1));
        for (y, row) in luminance.chunks_exact(w).take(h).enumerate() {
            let sin = (std::f64::consts::PI * (y as f64 + 0.5) / h as f64).sin();
            let weights: Vec<f64> = row.iter().map(|&l| f64::from(l) * sin).collect();
            marginal.push(weights.iter().sum());
            conditional.extend(cumulative(&weights));
        }
        SkyDistribution {
            width,
            height,
            marginal: cumulative(&marginal),
            conditional,
        }
    }

    fn sample_sky(&self, sky: &SkyDistribution, rng: &mut Rng) -> Option<SkySample> {
        let xi = rng.next_vec2();
        let (y, ty) = invert(&sky.marginal, xi.x);
        let (x, tx) = invert(sky.row(y), xi.y);
        let u = (x as f32 + tx) / sky.width as f32;
        let theta = PI * (y as f32 + ty) / sky.height as f32;
        let (sin, cos) = theta.sin_cos();
        let density = texel_density(sky, x, y);
        if sin <= 0.0 || density <= 0.0 {
            return None;
        }
        let phi = TAU * (u - 0.5);
        Some(SkySample {
            direction: Vec3::new(sin * phi.sin(), cos, -sin * phi.cos()),
            pdf: density / (2.0 * PI * PI * sin),
        })
    }

    fn sky_pdf(&self, sky: &SkyDistribution, direction: Vec3) -> f32 {
        let d = direction;
        let sin = (d.x * d.x + d.z * d.z).sqrt();
        if sin <= 0.0 {
            return 0.0;
        }
        let u = 0.5 + d.x.atan2(-d.z) / TAU;
        let v = sin.atan2(d.y) / PI;
        let x = ((u * sky.width as f32) as usize).min(sky.width as usize - 1);
        let y = ((v * sky.height as f32) as usize).min(sky.height as usize - 1);
        texel_density(sky, x, y) / (2.0 * PI * PI * sin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_white_diffuse_surface_reflects_everything() {
        // ∫ f cos dω over the hemisphere by the estimator f cos / pdf of the key's samples.
        let m = PathMaterial {
            diffuse: Vec3::ONE,
            glossy: Vec3::ZERO,
            exponent: 0.0,
        };
        let n = Vec3::new(0.3, 0.9, -0.2).normalize();
        let wo = Vec3::new(-0.4, 0.5, 0.7).normalize();
        let mut rng = Rng::new(1, 2);
        let mut sum = Vec3::ZERO;
        for _ in 0..10_000 {
            let s = Lab12.sample_bsdf(&m, n, wo, &mut rng).unwrap();
            sum += s.value * s.direction.dot(n) / s.pdf;
        }
        assert!((sum / 10_000.0 - Vec3::ONE).abs().max_element() < 1e-4, "{sum}");
    }
}
