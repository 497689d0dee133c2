use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use crate::Error;

/// An RGB image in linear floating point, looked up by texture coordinates.
#[derive(Clone, Debug)]
pub struct Texture {
    /// File the texture was loaded from.
    pub path: PathBuf,
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Texels row by row, top row first, linear RGB.
    pub texels: Vec<Vec3>,
}

impl Texture {
    /// Loads an image file; 8-bit images are decoded from sRGB to linear, float images
    /// (EXR, HDR) are taken as linear.
    pub fn load(path: &Path) -> Result<Self, Error> {
        let img = image::open(path).map_err(|e| Error::Texture {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })?;
        let is_float = matches!(
            img.color(),
            image::ColorType::Rgb32F | image::ColorType::Rgba32F
        );
        let rgb = img.to_rgb32f();
        let (width, height) = rgb.dimensions();
        if width == 0 || height == 0 {
            return Err(Error::Texture {
                path: path.to_path_buf(),
                reason: "the image has no pixels".into(),
            });
        }
        let texels = rgb
            .pixels()
            .map(|p| {
                let c = Vec3::from(p.0);
                if is_float {
                    c
                } else {
                    crate::film::srgb_to_linear(c)
                }
            })
            .collect();
        Ok(Self {
            path: path.to_path_buf(),
            width,
            height,
            texels,
        })
    }

    /// Nearest-texel lookup with wrapping; `uv = (0,0)` is the bottom-left corner as in OBJ.
    pub fn lookup_nearest(&self, uv: Vec2) -> Vec3 {
        let u = uv.x - uv.x.floor();
        let v = uv.y - uv.y.floor();
        let x = ((u * self.width as f32) as u32).min(self.width - 1);
        let y = (((1.0 - v) * self.height as f32) as u32).min(self.height - 1);
        self.texels[(y * self.width + x) as usize]
    }
}
