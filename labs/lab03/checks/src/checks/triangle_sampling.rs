//! Exercise 3.3: points sampled uniformly by area on a triangle.

use std::sync::Arc;

use glam::{Vec2, Vec3};
use proptest::prelude::*;

use contracts::lab03::Shadows;
use grading::stats::{chi_square_p_value, chi_square_uniform};
use grading::strategies::triangle_strategy;
use grading::{LabContext, for_all};
use raylab_core::sampling::Rng;

use super::irradiance::check_irradiance;
use super::soft_shadows::check_area_snapshot;
use super::{CHI_SQUARE_P, Part, format_counts};

/// Barycentric coordinates `(β, γ)` of `p` in the triangle (least squares, f64) and the
/// distance of `p` from the triangle's plane.
fn barycentrics(t: &[Vec3; 3], p: Vec3) -> (f64, f64, f64) {
    let [a, b, c] = t.map(|v| v.as_dvec3());
    let (e1, e2, d) = (b - a, c - a, p.as_dvec3() - a);
    let (d11, d12, d22) = (e1.dot(e1), e1.dot(e2), e2.dot(e2));
    let (d1, d2) = (d.dot(e1), d.dot(e2));
    let det = d11 * d22 - d12 * d12;
    let beta = (d22 * d1 - d12 * d2) / det;
    let gamma = (d11 * d2 - d12 * d1) / det;
    let off_plane = (d - beta * e1 - gamma * e2).length();
    (beta, gamma, off_plane)
}

fn check_in_triangle(t: &[Vec3; 3], u: Vec2, p: Vec3) -> Result<(), String> {
    let call = format!(
        "sample_triangle(v0 = {}, v1 = {}, v2 = {}, u = {u})",
        t[0], t[1], t[2]
    );
    if !p.is_finite() {
        return Err(format!("{call} returned {p}"));
    }
    let scale = (t[1] - t[0]).length().max((t[2] - t[0]).length()) as f64;
    let (beta, gamma, off) = barycentrics(t, p);
    let tol = 1e-4;
    if off > tol * scale {
        return Err(format!(
            "{call} returned {p}, {off:.3e} off the triangle's plane"
        ));
    }
    if beta < -tol || gamma < -tol || beta + gamma > 1.0 + tol {
        return Err(format!(
            "{call} returned {p}, outside the triangle: its barycentric coordinates are (1 − β − γ, β, γ) = ({:.4}, {beta:.4}, {gamma:.4}); all three must be in [0, 1]",
            1.0 - beta - gamma
        ));
    }
    Ok(())
}

/// Uniform numbers in `[0, 1)²`, with the corners and edges of the square now and then.
fn unit_square() -> impl Strategy<Value = Vec2> + Clone {
    let coord = prop_oneof![
        6 => 0.0f32..1.0,
        1 => Just(0.0f32),
        1 => Just(1.0 - f32::EPSILON / 2.0),
    ];
    (coord.clone(), coord).prop_map(|(x, y)| Vec2::new(x, y))
}

/// Index of the sub-triangle of a `k × k` subdivision (`k²` triangles of equal area) that the
/// point with barycentrics `(β, γ)` lies in.
fn sub_triangle(beta: f64, gamma: f64, k: u32) -> usize {
    let (x, y) = (
        beta.clamp(0.0, 1.0) * k as f64,
        gamma.clamp(0.0, 1.0) * k as f64,
    );
    let (i, j) = (x.floor().min(k as f64 - 1.0), y.floor().min(k as f64 - 1.0));
    let (mut i, mut j) = (i as u32, j as u32);
    if i + j > k - 1 {
        // Rounding at the outer edge: move into the nearest upright cell.
        let excess = i + j - (k - 1);
        if i >= excess {
            i -= excess;
        } else {
            j -= excess - i;
            i = 0;
        }
    }
    let inverted = i + j < k - 1 && (x - i as f64) + (y - j as f64) > 1.0;
    (2 * (j * k + i) + inverted as u32) as usize
}

/// Uniformity by area: samples from uniform `u` are counted in the `k²` congruent sub-triangles
/// of each test triangle, and Pearson's χ² test compares the counts with equal ones.
fn check_uniform_by_area(s: &Arc<dyn Shadows>) -> Result<(), String> {
    const K: u32 = 4;
    const N: usize = 12_800;
    let triangles = [
        [Vec3::ZERO, Vec3::X, Vec3::Y],
        [
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(-2.0, 0.5, 0.3),
            Vec3::new(0.4, -1.0, 2.0),
        ],
        [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(3.0, 0.1, 0.0),
            Vec3::new(2.6, 0.3, 0.4),
        ],
    ];
    for (k, t) in triangles.iter().enumerate() {
        let mut rng = Rng::new(23, k as u64);
        let mut counts = vec![0u32; 2 * (K * K) as usize];
        for _ in 0..N {
            let u = rng.next_vec2();
            let p = s.sample_triangle(*t, u);
            check_in_triangle(t, u, p)?;
            let (beta, gamma, _) = barycentrics(t, p);
            counts[sub_triangle(beta, gamma, K)] += 1;
        }
        // Only the k² real sub-triangles (upright cells and the inverted ones inside).
        let cells: Vec<u32> = (0..K * K)
            .flat_map(|c| {
                let (i, j) = (c % K, c / K);
                let mut v = Vec::new();
                if i + j < K {
                    v.push(counts[2 * c as usize]);
                }
                if i + j + 1 < K {
                    v.push(counts[2 * c as usize + 1]);
                }
                v
            })
            .collect();
        let stat = chi_square_uniform(&cells);
        let p = chi_square_p_value(stat, K * K - 1);
        if p < CHI_SQUARE_P {
            return Err(format!(
                "sample_triangle is not uniform by area on the triangle v0 = {}, v1 = {}, v2 = {}: of {N} samples from uniform u, the {} congruent sub-triangles of a {K}×{K} subdivision hold [{}] (expected {} each; χ² = {stat:.1}, {} degrees of freedom, p = {p:.1e}); the sub-triangles are listed row by row from the edge v0–v1 (β along the row, γ across rows). A uniform point has barycentrics (1 − √u₁, √u₁(1 − u₂), √u₁·u₂)",
                t[0],
                t[1],
                t[2],
                K * K,
                format_counts(&cells),
                N as u32 / (K * K),
                K * K - 1,
            ));
        }
    }
    Ok(())
}

pub(super) fn exercise_3_3(s: &Arc<dyn Shadows>, ctx: &LabContext) -> Result<(), String> {
    for_all(300, (triangle_strategy(), unit_square()), |(t, u)| {
        check_in_triangle(&t, u, s.sample_triangle(t, u))
    })?;
    check_uniform_by_area(s)?;
    check_irradiance(Part::Triangle, s, &ctx.base)?;
    check_area_snapshot(Part::Triangle, s, ctx)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sub_triangles_split_the_triangle_into_equal_parts() {
        // Uniform barycentrics on a fine grid: every one of the k² cells gets its share.
        let k = 4;
        let mut counts = vec![0u32; 2 * (k * k) as usize];
        let m = 400;
        for i in 0..m {
            for j in 0..m - i {
                let (b, g) = ((i as f64 + 0.3) / m as f64, (j as f64 + 0.3) / m as f64);
                if b + g < 1.0 {
                    counts[sub_triangle(b, g, k)] += 1;
                }
            }
        }
        let used: Vec<u32> = counts.iter().copied().filter(|&c| c > 0).collect();
        assert_eq!(used.len(), (k * k) as usize);
        let (lo, hi) = (used.iter().min().unwrap(), used.iter().max().unwrap());
        assert!((*hi as f64) < 1.1 * *lo as f64, "{used:?}");
    }
}
