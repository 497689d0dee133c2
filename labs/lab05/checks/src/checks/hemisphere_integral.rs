//! Exercise 5.7: the radiosity of a radiance profile by quadrature over the hemisphere.

use std::f64::consts::PI;
use std::sync::Arc;

use contracts::lab05::Radiometry;
use grading::{LabContext, for_all};

use super::inputs::{RadianceProfile, RadiosityInput, WORKSHEET_RADIOSITY, radiosity_strategy};
use super::{
    CASES, GOLDEN_RADIOSITY, LAW_TOL, QUADRATURE_TOL, REL_TOL, check_against_key, check_golden,
    rel_close,
};

/// The student's radiosity of a profile.
fn radiosity_of(s: &dyn Radiometry, (profile, steps): &RadiosityInput) -> f64 {
    s.radiosity_from_radiance(&|t, p| profile.radiance(t, p), *steps)
}

/// The coarse grids of the 5.7 check, where one cell more or less, or a cell's value taken at
/// its end instead of its middle, changes the sum by far more than rounding.
pub const COARSE_STEPS: [u32; 4] = [1, 2, 3, 4];

/// A radiance profile of the coarse-grid check: what it is, `L(θ, φ)`, and the exact
/// `∫ L cos θ dω` over the hemisphere.
type CoarseProfile = (&'static str, fn(f64, f64) -> f64, f64);

/// The profiles of the coarse-grid check: uniform, weighted towards the normal (the uniform
/// one alone is symmetric about θ = π/4 in `cos θ sin θ dθ`, which hides a θ taken at the
/// cells' ends), and one lit on one side of the azimuth only, `φ ∈ (0, π)` (the random
/// profiles' `cos φ` is symmetric about `φ = 0` and `φ = π`, which hides a half turn of φ
/// counted twice): `∫ max(0, sin φ) dφ = 2`, `∫ sin²θ cos θ dθ = 1/3`.
pub fn coarse_profiles() -> [CoarseProfile; 4] {
    [
        ("L = 1", |_, _| 1.0, PI),
        ("L = cos θ", |t, _| t.cos(), 2.0 * PI / 3.0),
        ("L = cos² θ", |t, _| t.cos().powi(2), 0.5 * PI),
        (
            "L = 1 + sin θ·max(0, sin φ)",
            |t, p| 1.0 + t.sin() * p.sin().max(0.0),
            PI + 2.0 / 3.0,
        ),
    ]
}

/// The rule the docs prescribe, computed here: the midpoint rule with `steps` intervals in
/// `θ ∈ [0, π/2]` and `4·steps` in `φ ∈ [0, 2π)` of `L cos θ sin θ`.
pub fn midpoint_in_theta(radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
    let (m, k) = (steps as usize, 4 * steps as usize);
    let (dt, dp) = (0.5 * PI / m as f64, 2.0 * PI / k as f64);
    let mut sum = 0.0;
    for i in 0..m {
        let t = (i as f64 + 0.5) * dt;
        for j in 0..k {
            sum += radiance(t, (j as f64 + 0.5) * dp) * t.cos() * t.sin() * dt * dp;
        }
    }
    sum
}

/// The docs' alternative: the midpoint rule in `μ = cos θ ∈ [0, 1]` (`dω = dμ dφ`) with
/// `steps` intervals, and `4·steps` in φ, of `L μ`.
pub fn midpoint_in_mu(radiance: &dyn Fn(f64, f64) -> f64, steps: u32) -> f64 {
    let (m, k) = (steps as usize, 4 * steps as usize);
    let (dmu, dp) = (1.0 / m as f64, 2.0 * PI / k as f64);
    let mut sum = 0.0;
    for i in 0..m {
        let mu = (i as f64 + 0.5) * dmu;
        for j in 0..k {
            sum += radiance(mu.acos(), (j as f64 + 0.5) * dp) * mu * dmu * dp;
        }
    }
    sum
}

/// At 1–4 steps the midpoint rule's own error is large and known: the student's sum must be
/// the prescribed rule's sum there (in θ, or in μ = cos θ), or at least as accurate. At 64
/// steps and more a ring left out or a half step forgotten changes the sum by less than the
/// quadrature's tolerance; here by tens of per cent.
fn check_coarse_grids(s: &dyn Radiometry) -> Result<(), String> {
    for (what, radiance, exact) in coarse_profiles() {
        for steps in COARSE_STEPS {
            let b = s.radiosity_from_radiance(&radiance, steps);
            let theta = midpoint_in_theta(&radiance, steps);
            let mu = midpoint_in_mu(&radiance, steps);
            let same = |rule: f64| (b - rule).abs() <= REL_TOL * rule.abs();
            let as_accurate = (b - exact).abs() <= (theta - exact).abs() * (1.0 + REL_TOL);
            if !(same(theta) || same(mu) || as_accurate) {
                return Err(format!(
                    "radiosity_from_radiance({what}, steps = {steps}) = {b:e}, but the midpoint rule with {steps} interval(s) in θ and {} in φ gives {theta:e} (in μ = cos θ: {mu:e}; exact ∫ L cos θ dω = {exact:e}): another rule must be at least as accurate, and this is off by {:.1}% of the exact value against the rule's {:.1}% — count the cells: θ_i = (i + ½)·Δθ for i = 0 … steps − 1 with Δθ = (π/2)/steps, φ_j = (j + ½)·Δφ for j = 0 … 4·steps − 1 with Δφ = 2π/(4·steps)",
                    4 * steps,
                    100.0 * (b - exact).abs() / exact,
                    100.0 * (theta - exact).abs() / exact,
                ));
            }
        }
    }
    Ok(())
}

pub(super) fn exercise_5_7(s: &Arc<dyn Radiometry>, ctx: &LabContext) -> Result<(), String> {
    let s = s.as_ref();
    for_all(CASES / 4, radiosity_strategy(), |(profile, steps)| {
        let b = radiosity_of(s, &(profile, steps));
        let call = format!("radiosity_from_radiance({profile:?}, steps = {steps}) = {b:e}");
        if !b.is_finite() {
            return Err(format!("{call}: not finite"));
        }
        let twice = radiosity_of(s, &(profile.scaled(2.0), steps));
        rel_close(
            "the radiosity of twice the radiance",
            twice,
            2.0 * b,
            LAW_TOL,
        )
        .map_err(|e| format!("{call}: {e}: the integral is linear in L"))?;
        let lobe = RadianceProfile {
            constant: 0.0,
            cosine: 0.0,
            cosine_squared: 0.0,
            azimuthal: profile.azimuthal,
        };
        let odd = radiosity_of(s, &(lobe, steps));
        if odd.abs() > LAW_TOL * profile.azimuthal.abs().max(1.0) {
            return Err(format!(
                "{call}: the radiance sin θ·cos φ·{} gives {odd:e}, expected 0: over a full turn of φ (0 to 2π) cos φ integrates to zero",
                profile.azimuthal
            ));
        }
        Ok(())
    })?;
    // Positive radiance: the integral over the hemisphere, not the sphere.
    let uniform = radiosity_of(s, &WORKSHEET_RADIOSITY);
    let positive = uniform > 0.0;
    if !positive {
        return Err(format!(
            "radiosity_from_radiance(L = 6000, steps = 256) = {uniform:e} for a positive radiance: θ runs over the hemisphere, [0, π/2], where cos θ ≥ 0"
        ));
    }
    check_coarse_grids(s)?;
    check_against_key(ctx, CASES / 4, radiosity_strategy(), |key, input| {
        rel_close(
            &format!(
                "radiosity_from_radiance({:?}, steps = {})",
                input.0, input.1
            ),
            radiosity_of(s, &input),
            radiosity_of(key, &input),
            QUADRATURE_TOL,
        )
    })?;
    check_golden(
        ctx,
        GOLDEN_RADIOSITY,
        &[(
            WORKSHEET_RADIOSITY,
            "question 7 (L = 6000 W/(m² sr) over the hemisphere)",
        )],
        |input| radiosity_of(s, input),
        |got, expected| {
            rel_close("the radiosity (W/m²)", *got, *expected, QUADRATURE_TOL)
                .map_err(|e| format!("{e} — dω = sin θ dθ dφ, θ ∈ [0, π/2], φ ∈ [0, 2π)"))
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_coarse_rules_are_the_midpoint_sums() {
        // One interval: θ = π/4, four φ cells: ½ · (π/2) · 2π = π²/2, and in μ: ½ · 1 · 2π = π.
        let one = |_: f64, _: f64| 1.0;
        assert!((midpoint_in_theta(&one, 1) - 0.5 * PI * PI).abs() < 1e-12);
        assert!((midpoint_in_mu(&one, 1) - PI).abs() < 1e-12);
        // Both converge to the exact integrals of the coarse profiles.
        for (what, radiance, exact) in coarse_profiles() {
            for rule in [midpoint_in_theta, midpoint_in_mu] {
                let b = rule(&radiance, 512);
                assert!((b - exact).abs() < 1e-4 * exact, "{what}: {b} ≠ {exact}");
            }
        }
    }
}
