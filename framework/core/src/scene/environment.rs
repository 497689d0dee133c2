//! Environment maps: an HDR light probe that surrounds the scene, the radiance of every ray
//! that leaves it (lab 11), and the procedural probes the course ships.

use std::path::Path;
use std::sync::Arc;

use glam::{Vec2, Vec3};

use super::Texture;
use super::TextureFile;
use crate::Error;

/// How a probe's image covers the sphere of directions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum ProbeMapping {
    /// Debevec's angular map: a disc, −z at the centre, +z on the rim.
    Angular,
    /// The latitude–longitude (equirectangular) map: +y along the top row, −z in the middle.
    Latlong,
}

impl ProbeMapping {
    /// The name a scene file gives the mapping.
    pub fn name(self) -> &'static str {
        match self {
            ProbeMapping::Angular => "angular",
            ProbeMapping::Latlong => "latlong",
        }
    }

    /// The mapping named `name` in a scene file.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "angular" => Some(ProbeMapping::Angular),
            "latlong" => Some(ProbeMapping::Latlong),
            _ => None,
        }
    }
}

/// A light probe around the scene: an image in linear radiance, its mapping, and a scale.
#[derive(Clone, Debug)]
pub struct EnvironmentMap {
    /// The probe's image (row 0 at the top).
    pub texture: Arc<Texture>,
    /// How the image covers the sphere of directions.
    pub mapping: ProbeMapping,
    /// Every texel's radiance is multiplied by this.
    pub scale: f32,
}

impl EnvironmentMap {
    /// Loads a probe image (Radiance `.hdr`, OpenEXR — scanline or tiled, uncompressed, RLE
    /// or ZIP — or an 8-bit image, taken as sRGB) under the load budget.
    pub fn load(path: &Path, mapping: ProbeMapping, scale: f32) -> Result<Self, Error> {
        Ok(Self {
            texture: Arc::new(Texture::load(path)?),
            mapping,
            scale,
        })
    }

    /// The scaled radiance of the texel at the texture coordinates `uv` (image coordinates:
    /// `v = 0` is the top row), nearest texel, `u` wrapping around and `v` clamped. Black at
    /// NaN coordinates and, for an angular map, outside its disc.
    pub fn texel(&self, uv: Vec2) -> Vec3 {
        if !uv.is_finite() {
            return Vec3::ZERO;
        }
        if self.mapping == ProbeMapping::Angular && (uv - Vec2::splat(0.5)).length() > 0.5 + 1e-4 {
            return Vec3::ZERO;
        }
        let t = &self.texture;
        let u = uv.x - uv.x.floor();
        let x = ((u * t.width as f32) as u32).min(t.width - 1);
        let y = ((uv.y.clamp(0.0, 1.0) * t.height as f32) as u32).min(t.height - 1);
        self.scale * t.texels[(y * t.width + x) as usize]
    }
}

/// The procedural probes of the course: radiance as a function of direction, which the
/// lab's golden-data generator writes out as probe images (no test needs a download).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProceduralProbe {
    /// An open sky: blue overhead, a warm horizon, a small sun of high radiance, dark ground.
    Sky,
    /// A dim studio with two large softboxes, warm on the left (−x) and cool overhead-right.
    Studio,
}

impl ProceduralProbe {
    /// Every procedural probe.
    pub const ALL: [ProceduralProbe; 2] = [ProceduralProbe::Sky, ProceduralProbe::Studio];

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            ProceduralProbe::Sky => "sky",
            ProceduralProbe::Studio => "studio",
        }
    }

    /// The radiance arriving from the unit direction `d` (y up).
    pub fn radiance(self, d: Vec3) -> Vec3 {
        match self {
            ProceduralProbe::Sky => {
                let sun = Vec3::new(0.45, 0.55, -0.70).normalize();
                let up = d.y;
                let sky = if up >= 0.0 {
                    let h = (1.0 - up).powi(4);
                    Vec3::new(0.25, 0.45, 1.0).lerp(Vec3::new(1.2, 0.9, 0.6), h)
                } else {
                    let g = (1.0 + up).powi(8);
                    Vec3::new(0.12, 0.09, 0.06).lerp(Vec3::new(0.5, 0.4, 0.3), g)
                };
                let cos_sun = d.dot(sun);
                let disc = if cos_sun > 0.9990 {
                    Vec3::new(400.0, 360.0, 300.0)
                } else {
                    Vec3::ZERO
                };
                let glow = Vec3::new(2.0, 1.5, 0.8) * cos_sun.max(0.0).powi(64);
                sky + disc + glow
            }
            ProceduralProbe::Studio => {
                let ambient = Vec3::splat(0.03) + Vec3::splat(0.05) * d.y.max(0.0);
                // A softbox is the set of directions within a square window of the plane
                // through its centre facing the origin.
                let softbox = |centre: Vec3, half: f32, colour: Vec3| {
                    let axis = centre.normalize();
                    let along = d.dot(axis);
                    if along <= 0.0 {
                        return Vec3::ZERO;
                    }
                    let hit = d * (centre.length() / along) - centre;
                    let e1 = axis.cross(Vec3::Y).normalize_or(Vec3::X);
                    let e2 = e1.cross(axis);
                    if hit.dot(e1).abs() < half && hit.dot(e2).abs() < half {
                        colour
                    } else {
                        Vec3::ZERO
                    }
                };
                ambient
                    + softbox(Vec3::new(-3.0, 1.5, 0.5), 1.2, Vec3::new(12.0, 8.0, 4.0))
                    + softbox(Vec3::new(2.0, 3.0, 1.5), 1.0, Vec3::new(4.0, 7.0, 12.0))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[cfg(feature = "crosscheck")]
    /// Writes a 32 × 16 OpenEXR file of `(x, y, x + y)` per texel with `encoding`.
    fn write_exr(path: &Path, encoding: exr::prelude::Encoding) {
        use exr::prelude::*;
        let layer = Layer::new(
            (32, 16),
            LayerAttributes::named("probe"),
            encoding,
            SpecificChannels::rgb(|p: exr::math::Vec2<usize>| {
                (p.x() as f32, p.y() as f32, (p.x() + p.y()) as f32)
            }),
        );
        Image::from_layer(layer).write().to_file(path).unwrap();
    }

    #[cfg(feature = "crosscheck")]
    #[test]
    fn loads_scanline_tiled_and_compressed_openexr_probes() {
        use exr::prelude::{Blocks, Compression, Encoding, LineOrder};
        let dir = std::env::temp_dir().join(format!("raylab-probe-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let encodings = [
            ("scanline", Encoding::UNCOMPRESSED),
            (
                "tiled-zip",
                Encoding {
                    compression: Compression::ZIP16,
                    blocks: Blocks::Tiles(exr::math::Vec2(8, 8)),
                    line_order: LineOrder::Increasing,
                },
            ),
            (
                "scanline-rle",
                Encoding {
                    compression: Compression::RLE,
                    blocks: Blocks::ScanLines,
                    line_order: LineOrder::Increasing,
                },
            ),
        ];
        for (name, encoding) in encodings {
            let path = dir.join(format!("{name}.exr"));
            write_exr(&path, encoding);
            let env = EnvironmentMap::load(&path, ProbeMapping::Latlong, 2.0).unwrap();
            assert_eq!((env.texture.width, env.texture.height), (32, 16), "{name}");
            // Texel (5, 3) at the centre of its cell; u wraps, v clamps.
            let uv = Vec2::new(5.5 / 32.0, 3.5 / 16.0);
            assert_eq!(env.texel(uv), 2.0 * Vec3::new(5.0, 3.0, 8.0), "{name}");
            assert_eq!(env.texel(uv + Vec2::X), env.texel(uv), "{name}");
            assert_eq!(env.texel(Vec2::new(uv.x, 7.0)).y, 2.0 * 15.0, "{name}");
        }
        // PIZ is refused with a message saying how to re-save the file.
        let piz = dir.join("piz.exr");
        write_exr(
            &piz,
            Encoding {
                compression: Compression::PIZ,
                blocks: Blocks::ScanLines,
                line_order: LineOrder::Increasing,
            },
        );
        let e = EnvironmentMap::load(&piz, ProbeMapping::Latlong, 1.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("ZIP"), "{e}");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn angular_maps_are_black_outside_their_disc() {
        let env = EnvironmentMap {
            texture: Arc::new(Texture {
                path: "white".into(),
                width: 4,
                height: 4,
                texels: vec![Vec3::ONE; 16],
            }),
            mapping: ProbeMapping::Angular,
            scale: 1.0,
        };
        assert_eq!(env.texel(Vec2::new(0.5, 0.5)), Vec3::ONE);
        assert_eq!(env.texel(Vec2::new(0.02, 0.02)), Vec3::ZERO);
        assert_eq!(env.texel(Vec2::NAN), Vec3::ZERO);
        assert_eq!(
            ProbeMapping::from_name("latlong"),
            Some(ProbeMapping::Latlong)
        );
        assert_eq!(ProbeMapping::from_name("sphere"), None);
        for p in ProceduralProbe::ALL {
            for d in [
                Vec3::X,
                Vec3::Y,
                Vec3::NEG_Y,
                Vec3::NEG_Z,
                Vec3::new(0.6, 0.0, 0.8),
            ] {
                let l = p.radiance(d);
                assert!(l.is_finite() && l.min_element() >= 0.0, "{p:?} {d}");
            }
        }
    }
}
