use std::path::{Path, PathBuf};

use glam::{Vec2, Vec3};

use crate::Error;
use crate::film::{LoadBudget, decode_image, srgb_to_linear};

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
    /// Loads an image file under the [`LoadBudget::current`] budget; 8-bit images are decoded
    /// from sRGB to linear, float images (EXR, HDR) are taken as linear.
    pub fn load(path: &Path) -> Result<Self, Error> {
        let decoded =
            decode_image(path, &LoadBudget::current()).map_err(|reason| Error::Texture {
                path: path.to_path_buf(),
                reason,
            })?;
        let (width, height) = decoded.rgb.dimensions();
        let texels = decoded
            .rgb
            .pixels()
            .map(|p| {
                let c = Vec3::from(p.0);
                if decoded.is_float {
                    c
                } else {
                    srgb_to_linear(c)
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

    /// [`Texture::load`] for the statement `named_by` (e.g. "map_Kd of material 'a' at
    /// m.mtl:3"), which an error names after the decoder's reason.
    pub(crate) fn load_for(path: &Path, named_by: &str) -> Result<Self, Error> {
        Self::load(path).map_err(|e| match e {
            Error::Texture { path, reason } => Error::Texture {
                path,
                reason: format!("{reason} (the texture of {named_by})"),
            },
            other => other,
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
