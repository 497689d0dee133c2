//! Image files decoded under the load budget, each format by its own crate: PNG by `png`,
//! JPEG by `zune-jpeg`, OpenEXR by `exr`, Radiance HDR by the framework's reader
//! ([`RgbeImage`]). An image's header is read and its size checked against the budget before a
//! decoder allocates its pixels, the decoders run with their own limits set and behind
//! `catch_unwind`, so a malformed file ends in an error naming it, never in a panic, an abort
//! or an exhausted memory.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;

use super::image_io::{LoadBudget, one_line, read_bounded};
use super::rgbe::RgbeImage;

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

/// The image formats raylab reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Format {
    Png,
    Jpeg,
    OpenExr,
    Hdr,
}

impl Format {
    /// The format of a file, from its first bytes.
    fn of(bytes: &[u8]) -> Option<Self> {
        if bytes.starts_with(b"\x89PNG\r\n\x1a\n") {
            Some(Format::Png)
        } else if bytes.starts_with(&[0xff, 0xd8, 0xff]) {
            Some(Format::Jpeg)
        } else if bytes.starts_with(&[0x76, 0x2f, 0x31, 0x01]) {
            Some(Format::OpenExr)
        } else if bytes.starts_with(b"#?RADIANCE") || bytes.starts_with(b"#?RGBE") {
            Some(Format::Hdr)
        } else {
            None
        }
    }

    fn name(self) -> &'static str {
        match self {
            Format::Png => "PNG",
            Format::Jpeg => "JPEG",
            Format::OpenExr => "OpenEXR",
            Format::Hdr => "Radiance HDR",
        }
    }
}

/// Bytes per pixel that the framework adds to a decoder's own output: the linear float RGB
/// copy and the texels or film made from it.
const FLOAT_COPIES_BYTES_PER_PIXEL: u64 = 2 * 12;

/// Reads and decodes the image file `path` under `budget`. The error is the reason only (the
/// caller names the file): a file that is not a regular file or too large, an unknown
/// format, an image over the pixel or memory budget (refused from its header, before any
/// decoding), a decoder's error, or a decoder's panic.
pub(crate) fn decode_image(path: &Path, budget: &LoadBudget) -> Result<DecodedImage, String> {
    decode_image_reason(path, budget).map_err(|reason| one_line(&reason))
}

fn decode_image_reason(path: &Path, budget: &LoadBudget) -> Result<DecodedImage, String> {
    let bytes = read_bounded(path, budget).map_err(|e| e.to_string())?;
    let format = Format::of(&bytes).ok_or_else(|| {
        "the file is not an image raylab reads (PNG, JPEG, OpenEXR or Radiance HDR)".to_string()
    })?;
    let decoded = crate::panic::catch_panic(|| match format {
        Format::Png => decode_png(&bytes, budget),
        Format::Jpeg => decode_jpeg(&bytes, budget),
        Format::OpenExr => decode_exr(&bytes, budget),
        Format::Hdr => decode_hdr(&bytes, budget),
    })
    .map_err(|caught| {
        format!(
            "the {} decoder failed on this file (it panicked: {})",
            format.name(),
            caught.message
        )
    })??;
    if decoded.width == 0 || decoded.height == 0 {
        return Err("the image has no pixels".into());
    }
    Ok(decoded)
}

/// Refuses an image of `width × height` pixels whose decoder output takes
/// `decoder_bytes_per_pixel` bytes a pixel when it is over the pixel or memory budget.
fn check_size(
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

/// The pixels of 8- or 16-bit samples (`channels` per pixel: grey, grey and alpha, RGB or RGBA)
/// as RGB in [0, 1]; alpha is dropped.
fn rgb_from_samples(samples: impl Iterator<Item = f32>, channels: usize) -> Vec<Vec3> {
    let samples: Vec<f32> = samples.collect();
    samples
        .chunks_exact(channels)
        .map(|p| match channels {
            1 | 2 => Vec3::splat(p[0]),
            _ => Vec3::new(p[0], p[1], p[2]),
        })
        .collect()
}

fn decode_png(bytes: &[u8], budget: &LoadBudget) -> Result<DecodedImage, String> {
    let limits = png::Limits {
        bytes: usize::try_from(budget.max_decode_bytes).unwrap_or(usize::MAX),
    };
    let mut decoder = png::Decoder::new_with_limits(Cursor::new(bytes), limits);
    // Palettes and samples under 8 bits become 8-bit samples; 16-bit samples stay.
    decoder.set_transformations(png::Transformations::EXPAND);
    let header = decoder.read_header_info().map_err(|e| e.to_string())?;
    let (width, height) = (header.width, header.height);
    check_size(u64::from(width), u64::from(height), 8, budget)?;
    let mut reader = decoder.read_info().map_err(|e| e.to_string())?;
    let (colour, depth) = reader.output_color_type();
    let channels = colour.samples();
    if colour == png::ColorType::Indexed || !(1..=4).contains(&channels) {
        return Err(format!(
            "the PNG colour type {colour:?} is not one raylab reads"
        ));
    }
    let size = reader
        .output_buffer_size()
        .ok_or("the PNG image is too large to decode")?;
    let mut buffer = vec![0; size];
    let frame = reader.next_frame(&mut buffer).map_err(|e| e.to_string())?;
    let data = &buffer[..frame.buffer_size()];
    let rgb = match depth {
        png::BitDepth::Eight => rgb_from_samples(data.iter().map(|&v| v as f32 / 255.0), channels),
        png::BitDepth::Sixteen => rgb_from_samples(
            data.chunks_exact(2)
                .map(|v| u16::from_be_bytes([v[0], v[1]]) as f32 / 65535.0),
            channels,
        ),
        other => return Err(format!("PNG samples of {other:?} are not read")),
    };
    Ok(DecodedImage {
        width,
        height,
        rgb,
        is_float: false,
    })
}

fn decode_jpeg(bytes: &[u8], budget: &LoadBudget) -> Result<DecodedImage, String> {
    use zune_jpeg::zune_core::bytestream::ZCursor;
    use zune_jpeg::zune_core::colorspace::ColorSpace;
    use zune_jpeg::zune_core::options::DecoderOptions;
    let side = usize::try_from(budget.max_pixels).unwrap_or(usize::MAX);
    let options = DecoderOptions::default()
        .set_strict_mode(false)
        .set_max_width(side)
        .set_max_height(side);
    let mut decoder = zune_jpeg::JpegDecoder::new_with_options(ZCursor::new(bytes), options);
    decoder.decode_headers().map_err(|e| e.to_string())?;
    let (width, height) = decoder
        .dimensions()
        .ok_or("the JPEG headers hold no size")?;
    // Grey stays grey (one sample a pixel); every other colour space is decoded to RGB.
    let grey = matches!(
        decoder.input_colorspace(),
        Some(ColorSpace::Luma | ColorSpace::LumaA)
    );
    let (out, channels) = if grey {
        (ColorSpace::Luma, 1)
    } else {
        (ColorSpace::RGB, 3)
    };
    check_size(width as u64, height as u64, channels as u64, budget)?;
    decoder.set_options(options.jpeg_set_out_colorspace(out));
    let data = decoder.decode().map_err(|e| e.to_string())?;
    if data.len() != width * height * channels {
        return Err(format!(
            "the JPEG decoder gave {} bytes for a {width} × {height} image",
            data.len()
        ));
    }
    Ok(DecodedImage {
        width: width as u32,
        height: height as u32,
        rgb: rgb_from_samples(data.iter().map(|&v| v as f32 / 255.0), channels),
        is_float: false,
    })
}

fn decode_hdr(bytes: &[u8], budget: &LoadBudget) -> Result<DecodedImage, String> {
    // The header states the size; `parse` checks it against the pixel budget before it
    // allocates.
    let rgbe = RgbeImage::parse(bytes, budget)?;
    check_size(u64::from(rgbe.width), u64::from(rgbe.height), 4, budget)?;
    Ok(DecodedImage {
        width: rgbe.width,
        height: rgbe.height,
        rgb: rgbe.pixels.iter().map(|&p| rgbe_to_rgb(p)).collect(),
        is_float: true,
    })
}

/// A Radiance pixel as linear RGB: each 8-bit mantissa times 2^(e − 136), black where e = 0
/// (Ward's `colr_color` without the half-step offset, as common decoders read it).
fn rgbe_to_rgb([r, g, b, e]: [u8; 4]) -> Vec3 {
    if e == 0 {
        return Vec3::ZERO;
    }
    let scale = f32::exp2(f32::from(e) - 136.0);
    Vec3::new(f32::from(r), f32::from(g), f32::from(b)) * scale
}

fn decode_exr(bytes: &[u8], budget: &LoadBudget) -> Result<DecodedImage, String> {
    use exr::prelude::*;
    check_exr_header(bytes, budget)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |resolution, _| DisplayPixels::new(resolution),
            |pixels: &mut DisplayPixels, position, (r, g, b): (f32, f32, f32)| {
                pixels.set(position, Vec3::new(r, g, b));
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_buffered(Cursor::new(bytes))
        .map_err(|e| e.to_string())?;
    // The pixels of the data window, placed in the display window (what the file shows):
    // outside the data window the image is black.
    let layer = &image.layer_data;
    let display = image.attributes.display_window;
    let offset = layer.attributes.layer_position - display.position;
    let (width, height) = (display.size.width(), display.size.height());
    check_size(width as u64, height as u64, 12, budget)?;
    let data = &layer.channel_data.pixels;
    let mut rgb = vec![Vec3::ZERO; width * height];
    for y in 0..data.height {
        for x in 0..data.width {
            let (dx, dy) = (x as i64 + offset.x() as i64, y as i64 + offset.y() as i64);
            if (0..width as i64).contains(&dx) && (0..height as i64).contains(&dy) {
                rgb[dy as usize * width + dx as usize] = data.pixels[y * data.width + x];
            }
        }
    }
    Ok(DecodedImage {
        width: width as u32,
        height: height as u32,
        rgb,
        is_float: true,
    })
}

/// The pixels of an OpenEXR layer's data window as the decoder delivers them.
struct DisplayPixels {
    width: usize,
    height: usize,
    pixels: Vec<Vec3>,
}

impl DisplayPixels {
    fn new(resolution: exr::math::Vec2<usize>) -> Self {
        Self {
            width: resolution.width(),
            height: resolution.height(),
            pixels: vec![Vec3::ZERO; resolution.area()],
        }
    }

    fn set(&mut self, at: exr::math::Vec2<usize>, value: Vec3) {
        self.pixels[at.y() * self.width + at.x()] = value;
    }
}

/// Checks an OpenEXR file's headers (read with the `exr` crate's metadata reader, which reads
/// no pixels) against the budget before the pixels are decoded: the data and display windows
/// of every part, their channels, tiles and levels, and the compression. Only the compressions
/// whose decoders in exr 1.74 allocate no more than the window's pixels are read: none, RLE
/// and ZIP (the ones raylab writes, and most tools' default); the others are refused (see
/// docs/architecture.md, "Decisions").
fn check_exr_header(bytes: &[u8], budget: &LoadBudget) -> Result<(), String> {
    use exr::compression::Compression;
    use exr::meta::BlockDescription;
    use exr::meta::attribute::LevelMode;
    let meta = exr::meta::MetaData::read_from_buffered(Cursor::new(bytes), false)
        .map_err(|e| format!("not a readable OpenEXR header: {e}"))?;
    let parts = meta.headers.len();
    let mut total_pixels = 0u64;
    let mut total_bytes = 0u64;
    for (i, header) in meta.headers.iter().enumerate() {
        let part = if parts > 1 {
            format!("part {i}: ")
        } else {
            String::new()
        };
        if header.deep {
            return Err(format!(
                "{part}deep OpenEXR data is not an image raylab reads"
            ));
        }
        match header.compression {
            Compression::Uncompressed
            | Compression::RLE
            | Compression::ZIP1
            | Compression::ZIP16 => {}
            other => {
                return Err(format!(
                    "{part}the file uses {other}, which raylab does not read (its decoder can \
                     exhaust memory or panic on a malformed file); save it with ZIP, RLE or no \
                     compression"
                ));
            }
        }
        let window = header.layer_size;
        let display = header.shared_attributes.display_window.size;
        let mut levels = 1;
        if let BlockDescription::Tiles(tiles) = &header.blocks {
            let tile = tiles.tile_size;
            if (tile.0 as u64).saturating_mul(tile.1 as u64) > budget.max_pixels {
                return Err(format!(
                    "{part}the tiles are {} × {} pixels; the load budget allows at most {} pixels",
                    tile.0, tile.1, budget.max_pixels
                ));
            }
            levels = match tiles.level_mode {
                LevelMode::Singular => 1,
                // The smaller levels of a mip map add up to a third of the image, those of a
                // rip map to three times it.
                LevelMode::MipMap => 2,
                LevelMode::RipMap => 4,
            };
        }
        for (w, h) in [(window.0, window.1), (display.0, display.1)] {
            check_size(w as u64, h as u64, 16, budget).map_err(|e| format!("{part}{e}"))?;
        }
        let pixels = (window.0 as u64).saturating_mul(window.1 as u64);
        let channels = header.channels.list.len() as u64;
        total_pixels = total_pixels.saturating_add(pixels.saturating_mul(levels));
        total_bytes = total_bytes.saturating_add(
            pixels
                .saturating_mul(levels)
                .saturating_mul(channels.saturating_mul(4)),
        );
    }
    if total_pixels > budget.max_pixels {
        return Err(format!(
            "the {parts} parts of the file hold {total_pixels} pixels; the load budget allows at most {}",
            budget.max_pixels
        ));
    }
    if total_bytes > budget.max_decode_bytes {
        return Err(format!(
            "the channels of the file take {} MiB; the load budget allows {} MiB",
            total_bytes >> 20,
            budget.max_decode_bytes >> 20
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every seed image of the fuzz corpus decodes to the same floats as the `image` crate
    /// gives (which wraps the same format crates), bit for bit.
    #[test]
    fn decodes_as_the_image_crate_does() {
        let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus");
        let mut seen = 0;
        for dir in ["png", "jpeg", "exr", "hdr"] {
            let mut files: Vec<_> = std::fs::read_dir(corpus.join(dir))
                .unwrap()
                .map(|e| e.unwrap().path())
                .collect();
            files.sort();
            for path in files {
                if path.ends_with("piz.exr") {
                    // A compression the framework refuses (see `check_exr_header`).
                    assert!(decode_image(&path, &LoadBudget::DEFAULT).is_err());
                    continue;
                }
                let theirs = image::open(&path).unwrap();
                let ours = decode_image(&path, &LoadBudget::DEFAULT)
                    .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
                let theirs = theirs.into_rgb32f();
                assert_eq!((ours.width, ours.height), theirs.dimensions());
                let theirs: Vec<Vec3> = theirs.pixels().map(|p| Vec3::from(p.0)).collect();
                // Exact but for grey images, which `image` widens to RGB through its colour
                // management (one unit in the last place apart).
                let grey = path
                    .file_name()
                    .is_some_and(|n| n.to_string_lossy().starts_with("grey"));
                for (i, (a, b)) in ours.rgb.iter().zip(&theirs).enumerate() {
                    let close = (*a - *b).abs().max_element() <= 1e-7 * b.abs().max_element();
                    assert!(
                        a == b || (grey && close),
                        "{} pixel {i}: {a} ≠ {b}",
                        path.display()
                    );
                }
                seen += 1;
            }
        }
        assert!(seen >= 9, "{seen} images compared");
    }

    #[test]
    fn refuses_what_is_not_an_image() {
        assert_eq!(Format::of(b"GIF89a"), None);
        assert_eq!(Format::of(b"#?RADIANCE\n"), Some(Format::Hdr));
        assert_eq!(
            Format::of(&[0x76, 0x2f, 0x31, 0x01, 2]),
            Some(Format::OpenExr)
        );
    }
}
