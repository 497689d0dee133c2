use glam::Vec3;

/// Relative luminance of linear sRGB/Rec. 709 primaries: `Y = 0.2126 R + 0.7152 G + 0.0722 B`.
#[inline]
pub fn luminance(c: Vec3) -> f32 {
    c.dot(Vec3::new(0.2126, 0.7152, 0.0722))
}

/// The sRGB transfer function (IEC 61966-2-1) applied per channel to values in `[0, 1]`.
pub fn linear_to_srgb(c: Vec3) -> Vec3 {
    let f = |v: f32| {
        if v <= 0.003_130_8 {
            12.92 * v
        } else {
            1.055 * v.powf(1.0 / 2.4) - 0.055
        }
    };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}

/// The inverse sRGB transfer function: encoded values in `[0, 1]` to linear.
pub fn srgb_to_linear(c: Vec3) -> Vec3 {
    let f = |v: f32| {
        if v <= 0.040_45 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    Vec3::new(f(c.x), f(c.y), f(c.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_round_trips_and_hits_known_values() {
        for v in [0.0, 0.001, 0.01, 0.2, 0.5, 0.9, 1.0] {
            let c = Vec3::splat(v);
            assert!((srgb_to_linear(linear_to_srgb(c)) - c).abs().max_element() < 1e-5);
        }
        // Linear 0.5 encodes to ≈ 0.7354 (188 of 255).
        assert!((linear_to_srgb(Vec3::splat(0.5)).x - 0.7354).abs() < 1e-3);
        assert!((luminance(Vec3::ONE) - 1.0).abs() < 1e-6);
    }
}
