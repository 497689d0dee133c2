use std::path::Path;

use glam::Vec3;

use super::{Film, ToneMap};
use crate::Error;

fn create_parent(path: &Path) -> Result<(), Error> {
    match path.parent() {
        Some(dir) if !dir.as_os_str().is_empty() => {
            std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))
        }
        _ => Ok(()),
    }
}

/// Writes the film as an 8-bit sRGB PNG after tone mapping.
pub fn write_png(film: &Film, path: &Path, tonemap: ToneMap) -> Result<(), Error> {
    create_parent(path)?;
    let bytes = film.to_srgb8(tonemap);
    image::save_buffer_with_format(
        path,
        &bytes,
        film.width,
        film.height,
        image::ExtendedColorType::Rgb8,
        image::ImageFormat::Png,
    )
    .map_err(|e| Error::ImageOutput {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })
}

/// Writes the film's linear radiance, unmodified, as a 32-bit float OpenEXR file.
pub fn write_exr(film: &Film, path: &Path) -> Result<(), Error> {
    create_parent(path)?;
    let data: Vec<f32> = film.pixels.iter().flat_map(|p| p.to_array()).collect();
    let buffer = image::Rgb32FImage::from_raw(film.width, film.height, data).ok_or_else(|| {
        Error::ImageOutput {
            path: path.to_path_buf(),
            reason: "pixel count does not match the size".into(),
        }
    })?;
    buffer
        .save_with_format(path, image::ImageFormat::OpenExr)
        .map_err(|e| Error::ImageOutput {
            path: path.to_path_buf(),
            reason: e.to_string(),
        })
}

/// Reads a float image (OpenEXR, or any format `image` decodes) into a film.
pub fn read_exr(path: &Path) -> Result<Film, Error> {
    let img = image::open(path).map_err(|e| Error::Texture {
        path: path.to_path_buf(),
        reason: e.to_string(),
    })?;
    let rgb = img.to_rgb32f();
    let (width, height) = rgb.dimensions();
    Ok(Film {
        width,
        height,
        pixels: rgb.pixels().map(|p| Vec3::from(p.0)).collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

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
