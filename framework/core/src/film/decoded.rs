//! An image as a decoder hands it to the framework, and the checks every decoder shares: its
//! size against the load budget, and a decoder's identifiers in words.

use glam::Vec3;

use super::bounded::LoadBudget;

/// An image decoded under the budget, as linear-or-encoded RGB floats.
pub(crate) struct DecodedImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixels, row by row from the top, as the file stores them (no transfer function
    /// applied; 8- and 16-bit values scaled to [0, 1]).
    pub rgb: Vec<Vec3>,
    /// Whether the file holds floats (OpenEXR, Radiance HDR), i.e. linear values.
    pub is_float: bool,
}

/// Bytes per pixel that the framework adds to a decoder's own output: the linear float RGB
/// copy and the texels or film made from it.
const FLOAT_COPIES_BYTES_PER_PIXEL: u64 = 2 * 12;

/// Refuses an image of `width × height` pixels whose decoder output takes
/// `decoder_bytes_per_pixel` bytes a pixel when it is over the pixel or memory budget.
pub(crate) fn check_size(
    width: u64,
    height: u64,
    decoder_bytes_per_pixel: u64,
    budget: &LoadBudget,
) -> Result<(), String> {
    let pixels = width.saturating_mul(height);
    if pixels > budget.max_pixels {
        return Err(format!(
            "the image is {width} × {height} = {pixels} pixels; the load budget allows at most {} pixels",
            budget.max_pixels
        ));
    }
    let bytes = pixels.saturating_mul(decoder_bytes_per_pixel + FLOAT_COPIES_BYTES_PER_PIXEL);
    if bytes > budget.max_decode_bytes {
        return Err(format!(
            "decoding the {width} × {height} image takes about {} MiB; the load budget allows {} MiB",
            bytes >> 20,
            budget.max_decode_bytes >> 20
        ));
    }
    Ok(())
}

/// An identifier in words: `BadLiteralLengthHuffmanTree` → "bad literal length huffman tree".
pub(crate) fn words(identifier: &str) -> String {
    let mut out = String::new();
    for c in identifier.chars() {
        if c.is_uppercase() && !out.is_empty() {
            out.push(' ');
        }
        out.extend(c.to_lowercase());
    }
    out
}
