//! Reference solution of lab 06 (docs/lab06.md).

use contracts::glam::Vec3;
use contracts::lab06::Radiosity;
use contracts::lab06::{DeltaFormFactors, HemicubeFace, ItemBuffer, Patch};

/// The reference radiosity.
#[derive(Clone, Copy, Debug, Default)]
pub struct Lab06;

impl Radiosity for Lab06 {
    fn point_form_factor(&self, x: Vec3, n_x: Vec3, y: Vec3, n_y: Vec3, area_y: f32) -> f32 {
        let d = y - x;
        let r2 = d.length_squared();
        if r2 <= 0.0 {
            return 0.0;
        }
        let w = d / r2.sqrt();
        let cos_x = n_x.dot(w).max(0.0);
        let cos_y = (-n_y.dot(w)).max(0.0);
        area_y * cos_x * cos_y / (std::f32::consts::PI * r2)
    }

    fn delta_form_factor_top(&self, x: f32, y: f32, pixel_area: f32) -> f32 {
        let s = x * x + y * y + 1.0;
        pixel_area / (std::f32::consts::PI * s * s)
    }

    fn delta_form_factor_side(&self, u: f32, z: f32, pixel_area: f32) -> f32 {
        let s = u * u + z * z + 1.0;
        z * pixel_area / (std::f32::consts::PI * s * s)
    }

    fn accumulate_form_factors(
        &self,
        items: &ItemBuffer,
        delta: &DeltaFormFactors,
        patch_count: usize,
    ) -> Vec<f32> {
        let mut f = vec![0.0; patch_count];
        for face in HemicubeFace::ALL {
            for (id, d) in items.face(face).iter().zip(delta.face(face)) {
                if let Some(j) = id {
                    f[*j as usize] += d;
                }
            }
        }
        f
    }

    fn select_shooter(&self, patches: &[Patch], unshot: &[Vec3]) -> Option<usize> {
        let mut best = None;
        let mut most = 0.0;
        for (i, (p, u)) in patches.iter().zip(unshot).enumerate() {
            let power = p.area * (u.x + u.y + u.z);
            if power > most {
                most = power;
                best = Some(i);
            }
        }
        best
    }

    fn shoot(
        &self,
        patches: &[Patch],
        form_factors: &[f32],
        shooter: usize,
        radiosity: &mut [Vec3],
        unshot: &mut [Vec3],
    ) {
        let shot = unshot[shooter];
        let area = patches[shooter].area;
        for (j, p) in patches.iter().enumerate() {
            if j == shooter {
                continue;
            }
            let received = p.reflectance * shot * (form_factors[j] * area / p.area);
            radiosity[j] += received;
            unshot[j] += received;
        }
        unshot[shooter] = Vec3::ZERO;
    }

    fn patch_colours(&self, radiosity: &[Vec3]) -> Vec<Vec3> {
        radiosity
            .iter()
            .map(|b| *b * std::f32::consts::FRAC_1_PI)
            .collect()
    }

    fn vertex_colours(
        &self,
        patches: &[Patch],
        vertex_count: usize,
        patch_colours: &[Vec3],
    ) -> Vec<Vec3> {
        let mut sum = vec![Vec3::ZERO; vertex_count];
        let mut count = vec![0u32; vertex_count];
        for (p, c) in patches.iter().zip(patch_colours) {
            for &v in &p.vertices {
                sum[v as usize] += *c;
                count[v as usize] += 1;
            }
        }
        sum.iter()
            .zip(&count)
            .map(|(s, &n)| if n > 0 { *s / n as f32 } else { Vec3::ZERO })
            .collect()
    }
}
