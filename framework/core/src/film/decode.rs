//! Image files decoded under the load budget: PNG by `png`, JPEG by `zune-jpeg`, OpenEXR and
//! Radiance HDR by the framework's own readers (`openexr.rs`, [`RgbeImage`]). An image's header
//! is read and its size checked against the budget before a decoder allocates its pixels, the
//! decoders run with their own limits set and behind `catch_unwind`, so a malformed file ends in
//! an error naming it, never in a panic, an abort or an exhausted memory.

use std::io::Cursor;
use std::path::Path;

use glam::Vec3;

use super::bounded::{LoadBudget, one_line, read_bounded};
pub(crate) use super::decoded::{DecodedImage, check_size, words};
use super::rgbe::RgbeImage;

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
        Format::OpenExr => super::openexr::decode(&bytes, budget),
        Format::Hdr => decode_hdr(&bytes, budget),
    })
    .map_err(|caught| {
        format!(
            "not a valid {} file: the decoder failed on it (it panicked: {})",
            format.name(),
            caught.message
        )
    })??;
    if decoded.width == 0 || decoded.height == 0 {
        return Err("the image has no pixels".into());
    }
    Ok(decoded)
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
    let header = decoder.read_header_info().map_err(png_reason)?;
    let (width, height) = (header.width, header.height);
    check_size(u64::from(width), u64::from(height), 8, budget)?;
    let mut reader = decoder.read_info().map_err(png_reason)?;
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
    let frame = reader.next_frame(&mut buffer).map_err(png_reason)?;
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

/// The PNG decoder's error as "not a valid PNG file: …" in words: its message names chunks by
/// their debug structure (`ChunkType { type: IHDR, critical: true, … }`) and compressed data's
/// faults by an enum variant, which a reader should not have to decipher.
fn png_reason(error: png::DecodingError) -> String {
    let reason = match error {
        png::DecodingError::IoError(e) if e.kind() == std::io::ErrorKind::UnexpectedEof => {
            CUT_SHORT.to_string()
        }
        png::DecodingError::IoError(e) => e.to_string(),
        png::DecodingError::Format(e) => png_format_reason(&e.to_string()),
        png::DecodingError::Parameter(e) => e.to_string(),
        png::DecodingError::LimitsExceeded => {
            "decoding it takes more memory than the load budget allows".to_string()
        }
    };
    format!("not a valid PNG file: {reason}")
}

/// What a file that ends too soon is told.
const CUT_SHORT: &str = "the file ends before its image data do (it is cut short)";

/// The PNG decoder's message of a fault of the file's format, in words.
fn png_format_reason(message: &str) -> String {
    let message = chunk_names(message);
    if message.starts_with("CRC error") {
        let chunk = message
            .split_once("while decoding ")
            .and_then(|(_, rest)| rest.split_whitespace().next())
            .unwrap_or("a");
        return format!(
            "the checksum of its {chunk} chunk does not match the chunk's data (the file is damaged)"
        );
    }
    if let Some(fault) = message.strip_prefix("Corrupt deflate stream.") {
        return format!(
            "its compressed image data are damaged ({})",
            words(fault.trim())
        );
    }
    let message = message.trim().trim_end_matches('.');
    let mut chars = message.chars();
    match chars.next() {
        Some(first) => first.to_lowercase().chain(chars).collect(),
        None => "the decoder gave no reason".to_string(),
    }
}

/// `message` with each chunk's debug structure, `ChunkType { type: IHDR, critical: true, … }`,
/// replaced by the chunk's name, `IHDR`.
fn chunk_names(message: &str) -> String {
    const START: &str = "ChunkType { type: ";
    let mut out = String::new();
    let mut rest = message;
    while let Some(at) = rest.find(START) {
        out.push_str(&rest[..at]);
        let after = &rest[at + START.len()..];
        let name_end = after.find([',', ' ', '}']).unwrap_or(after.len());
        out.push_str(&after[..name_end]);
        rest = after.find('}').map_or("", |end| &after[end + 1..]);
    }
    out.push_str(rest);
    out
}

/// The JPEG decoder's error as "not a valid JPEG file: …" in words (its own display is its
/// debug form: strings in quotes, I/O errors as enum variants).
fn jpeg_reason(error: zune_jpeg::errors::DecodeErrors) -> String {
    use zune_jpeg::errors::DecodeErrors as E;
    use zune_jpeg::zune_core::bytestream::ZByteIoError;
    let reason = match error {
        E::Format(why) | E::MCUError(why) => why,
        E::FormatStatic(why) => why.to_string(),
        E::HuffmanDecode(why) => format!("its Huffman-coded data are damaged: {why}"),
        E::ZeroError => "its width or height is 0".to_string(),
        E::DqtError(why) => format!("its quantization table is damaged: {why}"),
        E::SosError(why) => format!("its start-of-scan segment is damaged: {why}"),
        E::SofError(why) => format!("its start-of-frame segment is damaged: {why}"),
        E::IllegalMagicBytes(bytes) => {
            format!("it does not start with a JPEG marker (it starts with 0x{bytes:04X})")
        }
        E::Unsupported(scheme) => {
            format!("it is encoded in a way raylab does not read: {scheme:?}")
        }
        E::ExhaustedData | E::IoErrors(ZByteIoError::NotEnoughBytes(..)) => CUT_SHORT.to_string(),
        E::IoErrors(other) => format!("{other:?}"),
        E::LargeDimensions(side) => {
            format!("a side of {side} pixels is larger than the decoder reads")
        }
        E::TooSmallOutput(expected, found) => {
            format!("the decoder needed {expected} bytes of output and had {found}")
        }
    };
    format!("not a valid JPEG file: {}", reason.trim())
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
    decoder.decode_headers().map_err(jpeg_reason)?;
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
    let data = decoder.decode().map_err(jpeg_reason)?;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Every seed image of the fuzz corpus decodes to the same floats as the `image` crate
    /// gives (which wraps the same format crates), bit for bit.
    #[test]
    fn decodes_as_the_image_crate_does() {
        let corpus = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-corpus");
        let mut seen = 0;
        // OpenEXR files are compared with the exr crate by the `crosscheck` tests of openexr.rs.
        for dir in ["png", "jpeg", "hdr"] {
            let mut files: Vec<_> = std::fs::read_dir(corpus.join(dir))
                .unwrap()
                .map(|e| e.unwrap().path())
                .collect();
            files.sort();
            for path in files {
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
        assert!(seen >= 6, "{seen} images compared");
    }

    /// A 2 × 1 RGB PNG written by the `image` crate's encoder.
    fn small_png() -> Vec<u8> {
        let mut bytes = Vec::new();
        image::RgbImage::from_raw(2, 1, vec![10, 20, 30, 40, 50, 60])
            .unwrap()
            .write_to(&mut Cursor::new(&mut bytes), image::ImageFormat::Png)
            .unwrap();
        bytes
    }

    /// The reason `decode_image` gives for the file of `bytes`.
    fn reason_for(name: &str, bytes: &[u8]) -> String {
        let dir = std::env::temp_dir().join(format!("raylab-decode-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, bytes).unwrap();
        let reason = decode_image(&path, &LoadBudget::DEFAULT)
            .err()
            .unwrap_or_else(|| panic!("{name} decoded"));
        std::fs::remove_file(&path).unwrap();
        reason
    }

    /// A damaged PNG is "not a valid PNG file" with the decoder's reason in words: the chunk by
    /// its name, not the decoder's debug structure of it.
    #[test]
    fn a_damaged_png_is_not_a_valid_png_in_plain_words() {
        let good = small_png();
        assert!(decode_ok(&good));
        // Byte 16 is the first byte of the width, inside the IHDR chunk its checksum covers.
        let mut damaged = good.clone();
        damaged[16] ^= 0x40;
        assert_eq!(
            reason_for("damaged.png", &damaged),
            "not a valid PNG file: the checksum of its IHDR chunk does not match the chunk's data (the file is damaged)"
        );
        // Cut inside the pixel data.
        let cut = &good[..good.len() - 16];
        let reason = reason_for("cut.png", cut);
        assert!(reason.starts_with("not a valid PNG file: "), "{reason}");
        for debug in ["ChunkType", "{", "Error", "critical"] {
            assert!(!reason.contains(debug), "{reason}");
        }
    }

    /// Whether `bytes` decode (the test's own PNG must, for the damage to be what fails).
    fn decode_ok(bytes: &[u8]) -> bool {
        decode_png(bytes, &LoadBudget::DEFAULT).is_ok()
    }

    #[test]
    fn decoder_messages_lose_their_debug_forms() {
        assert_eq!(
            chunk_names(
                "Chunk ChunkType { type: PLTE, critical: true, private: false, reserved: false, safecopy: false } must appear at most once."
            ),
            "Chunk PLTE must appear at most once."
        );
        assert_eq!(
            png_format_reason("Corrupt deflate stream. BadLiteralLengthHuffmanTree"),
            "its compressed image data are damaged (bad literal length huffman tree)"
        );
        assert_eq!(
            png_format_reason("Invalid PNG signature."),
            "invalid PNG signature"
        );
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
