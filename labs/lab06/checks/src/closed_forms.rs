//! Closed-form configuration factors from the radiative heat-transfer literature, the yardstick
//! of the hemicube's form factors: J. R. Howell, *A Catalog of Radiation Heat Transfer
//! Configuration Factors* (3rd ed., thermalradiation.net), cases B-2, B-3, C-11 and C-14 (also
//! in Siegel and Howell, *Thermal Radiation Heat Transfer*, appendix C).

use std::f64::consts::PI;

/// Howell B-3: from a differential element to a parallel `a × b` rectangle at distance `c`,
/// the element's normal through one corner of the rectangle.
pub fn element_to_parallel_rectangle(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
    (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * PI)
}

/// Howell B-2: from a differential element to an `a × h` rectangle in a perpendicular plane at
/// distance `d`, one edge of length `a` in the element's plane and one corner at the foot of the
/// perpendicular from the element (`h` along the element's normal).
pub fn element_to_perpendicular_rectangle(a: f64, h: f64, d: f64) -> f64 {
    let (x, y) = (h / a, d / a);
    let s = (x * x + y * y).sqrt();
    ((1.0 / y).atan() - y / s * (1.0 / s).atan()) / (2.0 * PI)
}

/// Howell C-11: between two directly opposed parallel `a × b` rectangles at distance `c`.
pub fn parallel_rectangles(a: f64, b: f64, c: f64) -> f64 {
    let (x, y) = (a / c, b / c);
    let (x2, y2) = (x * x, y * y);
    let (sx, sy) = ((1.0 + x2).sqrt(), (1.0 + y2).sqrt());
    2.0 / (PI * x * y)
        * ((((1.0 + x2) * (1.0 + y2)) / (1.0 + x2 + y2)).sqrt().ln()
            + x * sy * (x / sy).atan()
            + y * sx * (y / sx).atan()
            - x * x.atan()
            - y * y.atan())
}

/// Howell C-14: from a `l × w` rectangle to a `l × h` rectangle at right angles to it along
/// their common edge of length `l`.
pub fn perpendicular_rectangles(l: f64, w: f64, h: f64) -> f64 {
    let (hh, ww) = (h / l, w / l);
    let (h2, w2) = (hh * hh, ww * ww);
    let s = (h2 + w2).sqrt();
    let a = (1.0 + w2) * (1.0 + h2) / (1.0 + w2 + h2);
    let b = (w2 * (1.0 + w2 + h2) / ((1.0 + w2) * (w2 + h2))).powf(w2);
    let c = (h2 * (1.0 + h2 + w2) / ((1.0 + h2) * (h2 + w2))).powf(h2);
    (ww * (1.0 / ww).atan() + hh * (1.0 / hh).atan() - s * (1.0 / s).atan()
        + 0.25 * (a * b * c).ln())
        / (PI * ww)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The midpoint rule over a `n × n` grid of `f` on `[0, a] × [0, b]`.
    fn integrate(a: f64, b: f64, n: usize, f: impl Fn(f64, f64) -> f64) -> f64 {
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                sum += f(
                    a * (i as f64 + 0.5) / n as f64,
                    b * (j as f64 + 0.5) / n as f64,
                );
            }
        }
        sum * a * b / (n * n) as f64
    }

    #[test]
    fn element_formulas_match_the_integral_of_the_kernel() {
        let (a, b, c) = (1.0, 2.0, 1.5);
        let num = integrate(a, b, 800, |x, y| {
            c * c / (PI * (x * x + y * y + c * c).powi(2))
        });
        assert!((element_to_parallel_rectangle(a, b, c) - num).abs() < 1e-6);
        let (a, h, d) = (1.0, 2.0, 0.7);
        let num = integrate(a, h, 800, |x, z| {
            z * d / (PI * (x * x + z * z + d * d).powi(2))
        });
        assert!((element_to_perpendicular_rectangle(a, h, d) - num).abs() < 1e-6);
    }

    #[test]
    fn area_formulas_match_the_published_values() {
        // Unit squares: 0.1998 facing each other at unit distance, 0.2000 at right angles.
        assert!((parallel_rectangles(1.0, 1.0, 1.0) - 0.19982).abs() < 1e-4);
        assert!((perpendicular_rectangles(1.0, 1.0, 1.0) - 0.20004).abs() < 1e-4);
        // The area formula is the average of the element formula over the emitter.
        let n = 200;
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let (x, y) = ((i as f64 + 0.5) / n as f64, (j as f64 + 0.5) / n as f64);
                sum += element_to_parallel_rectangle(x, y, 1.0)
                    + element_to_parallel_rectangle(1.0 - x, y, 1.0)
                    + element_to_parallel_rectangle(x, 1.0 - y, 1.0)
                    + element_to_parallel_rectangle(1.0 - x, 1.0 - y, 1.0);
            }
        }
        assert!((sum / (n * n) as f64 - parallel_rectangles(1.0, 1.0, 1.0)).abs() < 1e-4);
    }
}
