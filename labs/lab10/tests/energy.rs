//! Energy at an interface, on lab 10's reference: the Fresnel reflectance and the
//! transmittance from the Fresnel transmission coefficients add up to one, for each
//! polarisation and for unpolarised light. The transmission coefficients answer Exercise 10.3
//! (`R = 1 − T`), so this check runs on the answer key, in the instructors' tests of the lab (a
//! handout ships only `tests/checks.rs`).

use contracts::lab10::Fresnel;
use reference::lab10::Lab10;

/// `(cos θ₂, T_s, T_p)` of light arriving at `cos θ₁ = c` from `e1` into `e2`, `None` under
/// total internal reflection: `T = (η₂ cos θ₂)/(η₁ cos θ₁) · t²` with the amplitude
/// transmission coefficients `t_s = 2η₁cos θ₁/(η₁cos θ₁ + η₂cos θ₂)` and
/// `t_p = 2η₁cos θ₁/(η₂cos θ₁ + η₁cos θ₂)`.
fn transmission(c: f64, e1: f64, e2: f64) -> Option<(f64, f64, f64)> {
    let sin2_t = (e1 / e2).powi(2) * (1.0 - c * c);
    if sin2_t >= 1.0 {
        return None;
    }
    let ct = (1.0 - sin2_t).sqrt();
    let t_s = 2.0 * e1 * c / (e1 * c + e2 * ct);
    let t_p = 2.0 * e1 * c / (e2 * c + e1 * ct);
    let k = (e2 * ct) / (e1 * c);
    Some((ct, k * t_s * t_s, k * t_p * t_p))
}

#[test]
fn reflectance_and_transmittance_add_up_to_one() {
    let indices = [1.0, 1.1, 1.33, 1.5, 1.8, 2.42];
    let mut checked = 0;
    for &e1 in &indices {
        for &e2 in &indices {
            for i in 1..=400 {
                let c = i as f64 / 400.0;
                let Some((ct, t_s, t_p)) = transmission(c, e1, e2) else {
                    let r = Lab10.fresnel_reflectance(c as f32, e1 as f32, e2 as f32);
                    assert_eq!(
                        r, 1.0,
                        "total internal reflection at cos θ₁ = {c}, {e1} → {e2}"
                    );
                    continue;
                };
                let (c32, ct32, e1f, e2f) = (c as f32, ct as f32, e1 as f32, e2 as f32);
                let r_s = Lab10.fresnel_r_s(c32, ct32, e1f, e2f) as f64;
                let r_p = Lab10.fresnel_r_p(c32, ct32, e1f, e2f) as f64;
                let r = Lab10.fresnel_R(c32, ct32, e1f, e2f) as f64;
                let r_full = Lab10.fresnel_reflectance(c32, e1f, e2f) as f64;
                let at = format!("cos θ₁ = {c}, η₁ = {e1}, η₂ = {e2}");
                assert!(
                    (r_s * r_s + t_s - 1.0).abs() < 1e-5,
                    "s: r_s² + T_s ≠ 1 at {at}"
                );
                assert!(
                    (r_p * r_p + t_p - 1.0).abs() < 1e-5,
                    "p: r_p² + T_p ≠ 1 at {at}"
                );
                let t = 0.5 * (t_s + t_p);
                assert!((r + t - 1.0).abs() < 1e-5, "R + T = {} at {at}", r + t);
                // Near the critical angle cos θ₂ → 0 and the f32 reflectance is steep.
                if ct > 1e-2 {
                    assert!(
                        (r_full + t - 1.0).abs() < 1e-4,
                        "R + T = {} at {at}",
                        r_full + t
                    );
                }
                checked += 1;
            }
        }
    }
    assert!(
        checked > 10_000,
        "only {checked} cases below the critical angle"
    );
}
