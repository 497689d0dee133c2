use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use super::luminance;
use crate::Error;

/// How radiance is mapped to displayable `[0, 1]` values before sRGB encoding.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ToneMap {
    /// Scale by `exposure` and cut values above 1 (ELUMI §6.1 "clamp").
    Clamp {
        /// Multiplier applied before clamping.
        exposure: f32,
    },
    /// Reinhard et al.'s (2002) global operator (ELUMI §6.1, eqs. 6.1–6.4): the log-average
    /// luminance `L̄ = exp(mean(ln(δ + L)))` is mapped to the key `a`, `L_s = a·L/L̄`, and
    /// `L_d = L_s (1 + L_s/L_white²) / (1 + L_s)`, where `L_white` (in scaled units) is the
    /// smallest luminance mapped to white. Colours are scaled by `L_d / L`, keeping their hue.
    Reinhard {
        /// Key `a` (0.18 for an average scene; higher is brighter).
        key: f32,
        /// `L_white`; `f32::INFINITY` gives the plain `L_s / (1 + L_s)`.
        white: f32,
    },
}

impl Default for ToneMap {
    fn default() -> Self {
        Self::Clamp { exposure: 1.0 }
    }
}

impl ToneMap {
    /// Maps every pixel.
    pub fn apply(&self, pixels: &[Vec3]) -> Vec<Vec3> {
        match *self {
            ToneMap::Clamp { exposure } => pixels
                .iter()
                .map(|&c| (c * exposure).clamp(Vec3::ZERO, Vec3::ONE))
                .collect(),
            ToneMap::Reinhard { key, white } => {
                let log_average = log_average_luminance(pixels);
                if log_average <= 0.0 {
                    return vec![Vec3::ZERO; pixels.len()];
                }
                pixels
                    .iter()
                    .map(|&c| {
                        let l = luminance(c);
                        if l <= 0.0 || !l.is_finite() {
                            return Vec3::ZERO;
                        }
                        let ls = key * l / log_average;
                        let ld = ls * (1.0 + ls / (white * white)) / (1.0 + ls);
                        (c * (ld / l)).clamp(Vec3::ZERO, Vec3::ONE)
                    })
                    .collect()
            }
        }
    }
}

/// `exp(mean(ln(δ + L)))` over the finite pixels, with `δ = 1e-4` guarding black pixels.
pub fn log_average_luminance(pixels: &[Vec3]) -> f32 {
    const DELTA: f64 = 1e-4;
    let (sum, n) = pixels
        .iter()
        .map(|&c| luminance(c.max(Vec3::ZERO)))
        .filter(|l| l.is_finite())
        .fold((0.0f64, 0usize), |(s, n), l| {
            (s + (DELTA + l as f64).ln(), n + 1)
        });
    if n == 0 {
        0.0
    } else {
        (sum / n as f64).exp() as f32
    }
}

impl fmt::Display for ToneMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ToneMap::Clamp { exposure } => write!(f, "clamp:{exposure}"),
            ToneMap::Reinhard { key, white } => write!(f, "reinhard:{key}:{white}"),
        }
    }
}

impl FromStr for ToneMap {
    type Err = Error;

    /// Parses `clamp`, `clamp:EXPOSURE`, `reinhard`, `reinhard:KEY` or `reinhard:KEY:WHITE`
    /// (`white` may be `inf`).
    fn from_str(s: &str) -> Result<Self, Error> {
        let invalid = |reason: String| Error::Invalid {
            what: format!("tone map '{s}'"),
            reason,
        };
        let mut parts = s.split(':');
        let name = parts.next().unwrap_or_default();
        let numbers: Vec<f32> = parts
            .map(|p| {
                p.parse::<f32>()
                    .ok()
                    .filter(|v| *v > 0.0 && !v.is_nan())
                    .ok_or_else(|| invalid(format!("'{p}' is not a positive number")))
            })
            .collect::<Result<_, _>>()?;
        match (name, numbers.as_slice()) {
            ("clamp", []) => Ok(ToneMap::Clamp { exposure: 1.0 }),
            ("clamp", [e]) if e.is_finite() => Ok(ToneMap::Clamp { exposure: *e }),
            ("reinhard", []) => Ok(ToneMap::Reinhard {
                key: 0.18,
                white: f32::INFINITY,
            }),
            ("reinhard", [k]) if k.is_finite() => Ok(ToneMap::Reinhard {
                key: *k,
                white: f32::INFINITY,
            }),
            ("reinhard", [k, w]) if k.is_finite() => Ok(ToneMap::Reinhard { key: *k, white: *w }),
            _ => Err(invalid(
                "expected clamp[:EXPOSURE] or reinhard[:KEY[:WHITE]], e.g. reinhard:0.18:2.0"
                    .into(),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn clamp_cuts_at_one() {
        let out = ToneMap::Clamp { exposure: 2.0 }.apply(&[Vec3::new(0.25, 0.6, 3.0)]);
        assert_eq!(out[0], Vec3::new(0.5, 1.0, 1.0));
    }

    #[test]
    fn reinhard_maps_log_average_to_key_over_one_plus_key() {
        // A uniform image: L̄ = L (up to δ), so L_s = a and L_d = a / (1 + a).
        let img = vec![Vec3::splat(2.0); 16];
        let out = ToneMap::Reinhard {
            key: 0.18,
            white: f32::INFINITY,
        }
        .apply(&img);
        let expected = 0.18 / 1.18;
        assert!((luminance(out[0]) - expected).abs() < 1e-3);
    }

    #[test]
    fn reinhard_white_maps_to_one() {
        // Pixel whose scaled luminance equals L_white maps to exactly 1.
        let mut img = vec![Vec3::splat(1.0); 15];
        img.push(Vec3::splat(1.0));
        let white = 0.5;
        let out = ToneMap::Reinhard { key: 0.5, white }.apply(&img);
        assert!((luminance(out[0]) - 1.0).abs() < 1e-3);
    }

    #[test]
    fn parses_and_rejects() {
        assert_eq!(
            "clamp".parse::<ToneMap>().unwrap(),
            ToneMap::Clamp { exposure: 1.0 }
        );
        assert_eq!(
            "reinhard:0.5:2".parse::<ToneMap>().unwrap(),
            ToneMap::Reinhard {
                key: 0.5,
                white: 2.0
            }
        );
        let err = "reinhard:-1".parse::<ToneMap>().unwrap_err().to_string();
        assert!(err.contains("'-1'"), "{err}");
        assert!("gamma".parse::<ToneMap>().is_err());
    }
}
