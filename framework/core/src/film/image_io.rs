//! Image files out, and in: PNG and OpenEXR written, an OpenEXR film read (images in are
//! decoded in `decode.rs`, under the load budget of `bounded.rs`).

use std::io;
use std::path::Path;

use super::bounded::create_parent;
use super::decode::decode_image;
use super::{Film, LoadBudget, ToneMap};
use crate::Error;

/// Writes the film as an 8-bit sRGB PNG after tone mapping.
pub fn write_png(film: &Film, path: &Path, tonemap: ToneMap) -> Result<(), Error> {
    write_srgb8_png(&film.to_srgb8(tonemap), film.width, film.height, path)
}

/// Writes 8-bit sRGB pixels (`width × height × 3` bytes, row by row) as a PNG file (fast
/// deflate, adaptive row filters).
pub fn write_srgb8_png(bytes: &[u8], width: u32, height: u32, path: &Path) -> Result<(), Error> {
    create_parent(path)?;
    let failed = |reason: String| Error::ImageOutput {
        path: path.to_path_buf(),
        reason,
    };
    let file = std::fs::File::create(path).map_err(|e| Error::io(path, e))?;
    let mut out = io::BufWriter::new(file);
    let mut encoder = png::Encoder::new(&mut out, width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_compression(png::Compression::Fast);
    encoder.set_filter(png::Filter::Adaptive);
    let mut writer = encoder.write_header().map_err(|e| failed(e.to_string()))?;
    writer
        .write_image_data(bytes)
        .and_then(|()| writer.finish())
        .map_err(|e| failed(e.to_string()))?;
    io::Write::flush(&mut out).map_err(|e| Error::io(path, e))
}

/// Writes the film's linear radiance, unmodified, as a 32-bit float OpenEXR file (one part of
/// R, G, B scanlines, ZIP-compressed; see `openexr.rs`).
pub fn write_exr(film: &Film, path: &Path) -> Result<(), Error> {
    create_parent(path)?;
    let failed = |reason: &str| Error::ImageOutput {
        path: path.to_path_buf(),
        reason: reason.into(),
    };
    if film.pixels.len() != film.width as usize * film.height as usize {
        return Err(failed("pixel count does not match the size"));
    }
    if film.pixels.is_empty() || film.width > i32::MAX as u32 || film.height > i32::MAX as u32 {
        return Err(failed("an OpenEXR image has 1 to 2³¹ − 1 pixels a side"));
    }
    std::fs::write(path, super::openexr::encode(film)).map_err(|e| Error::io(path, e))
}

/// Reads a float image (OpenEXR, or any format the loaders decode) into a film, under the
/// [`LoadBudget::current`] budget.
pub fn read_exr(path: &Path) -> Result<Film, Error> {
    let image = decode_image(path, &LoadBudget::current()).map_err(|reason| Error::Image {
        path: path.to_path_buf(),
        reason,
    })?;
    Ok(Film {
        width: image.width,
        height: image.height,
        pixels: image.rgb,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn exr_round_trip_is_exact() {
        let mut film = Film::new(3, 2);
        film.set(0, 0, Vec3::new(0.1, 1e-7, 12345.678));
        film.set(2, 1, Vec3::new(std::f32::consts::PI, 0.0, 1.0 / 3.0));
        let dir = std::env::temp_dir().join(format!("raylab-exr-{}", std::process::id()));
        let path = dir.join("t.exr");
        write_exr(&film, &path).unwrap();
        let back = read_exr(&path).unwrap();
        assert_eq!(back, film);
        write_png(&film, &dir.join("t.png"), ToneMap::default()).unwrap();
        std::fs::remove_dir_all(dir).ok();
    }
}
