//! The film: floating-point RGB radiance per pixel, tone mapping to displayable values, and
//! image output (sRGB PNG for viewing, OpenEXR for exact float comparison).

mod bounded;
mod color;
mod decode;
mod decoded;
mod image_io;
mod openexr;
mod rgbe;
mod tonemap;

pub(crate) use bounded::one_line;
pub use bounded::{LoadBudget, read_bounded, read_text_bounded};
pub use color::{linear_to_srgb, luminance, srgb_to_linear};
pub(crate) use decode::decode_image;
pub use image_io::{read_exr, write_exr, write_png, write_srgb8_png};
pub use rgbe::RgbeImage;
pub use tonemap::ToneMap;

use glam::Vec3;

/// A rendered image: linear RGB radiance, row by row from the top row.
#[derive(Clone, Debug, PartialEq)]
pub struct Film {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// `width · height` pixels, top row first.
    pub pixels: Vec<Vec3>,
}

impl Film {
    /// A black film.
    pub fn new(width: u32, height: u32) -> Self {
        Self {
            width,
            height,
            pixels: vec![Vec3::ZERO; width as usize * height as usize],
        }
    }

    /// The pixel in column `x`, row `y` (row 0 at the top).
    pub fn get(&self, x: u32, y: u32) -> Vec3 {
        self.pixels[(y * self.width + x) as usize]
    }

    /// Sets a pixel.
    pub fn set(&mut self, x: u32, y: u32, value: Vec3) {
        self.pixels[(y * self.width + x) as usize] = value;
    }

    /// Number of pixels that are NaN or infinite.
    pub fn non_finite_count(&self) -> usize {
        self.pixels.iter().filter(|p| !p.is_finite()).count()
    }

    /// Tone-mapped, sRGB-encoded 8-bit RGB bytes.
    pub fn to_srgb8(&self, tonemap: ToneMap) -> Vec<u8> {
        let mapped = tonemap.apply(&self.pixels);
        mapped
            .iter()
            .flat_map(|&c| {
                let s = linear_to_srgb(c.clamp(Vec3::ZERO, Vec3::ONE));
                [s.x, s.y, s.z].map(|v| (v * 255.0 + 0.5) as u8)
            })
            .collect()
    }
}
