//! Textures from image files: the loading half of [`Texture`], under the load budget.

use std::path::Path;

use super::Texture;
use crate::Error;
use crate::film::{LoadBudget, decode_image, srgb_to_linear};

/// Loading a [`Texture`] from an image file.
pub trait TextureFile: Sized {
    /// Loads an image file under the [`LoadBudget::current`] budget; 8-bit images are decoded
    /// from sRGB to linear, float images (EXR, HDR) are taken as linear.
    fn load(path: &Path) -> Result<Self, Error>;

    /// [`TextureFile::load`] for what names the file, with its place (e.g. "the texture
    /// map_Kd of material 'a' at m.mtl:3"), which an error names with the file.
    fn load_for(path: &Path, named_by: &str) -> Result<Self, Error>;
}

impl TextureFile for Texture {
    fn load(path: &Path) -> Result<Self, Error> {
        let decoded =
            decode_image(path, &LoadBudget::current()).map_err(|reason| Error::Texture {
                path: path.to_path_buf(),
                named_by: None,
                reason,
            })?;
        let (width, height) = (decoded.width, decoded.height);
        let texels = decoded
            .rgb
            .into_iter()
            .map(|c| {
                if decoded.is_float {
                    c
                } else {
                    srgb_to_linear(c)
                }
            })
            .collect();
        Ok(Texture {
            path: path.to_path_buf(),
            width,
            height,
            texels,
        })
    }

    fn load_for(path: &Path, named_by: &str) -> Result<Self, Error> {
        Self::load(path).map_err(|e| match e {
            Error::Texture { path, reason, .. } => Error::Texture {
                path,
                named_by: Some(named_by.to_string()),
                reason,
            },
            other => other,
        })
    }
}
