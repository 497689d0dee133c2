//! The raw pixels of a Radiance RGBE (`.hdr`) file: its header and run-length-encoded
//! scanlines read byte for byte, without converting a pixel to floats — what lab 11's
//! RGBE exercise converts, and what its check compares with the `image` crate's decoder.

use std::path::Path;

use glam::Vec3;

use super::Film;
use super::bounded::{LoadBudget, create_parent, read_bounded};
use crate::Error;

/// The pixels of a Radiance file as stored: `[r, g, b, e]` per pixel, row by row from the top.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct RgbeImage {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// The pixels, `width · height` of them.
    pub pixels: Vec<[u8; 4]>,
}

impl RgbeImage {
    /// Reads the Radiance file `path` under the [`LoadBudget::current`] budget: a
    /// `#?RADIANCE` or `#?RGBE` header in `32-bit_rle_rgbe` format, the standard orientation
    /// `-Y height +X width`, and flat or (new-style) run-length-encoded scanlines.
    pub fn read(path: &Path) -> Result<Self, Error> {
        let fail = |reason: String| Error::Texture {
            path: path.to_path_buf(),
            named_by: None,
            reason,
        };
        let budget = LoadBudget::current();
        let bytes = read_bounded(path, &budget).map_err(|e| fail(e.to_string()))?;
        Self::parse(&bytes, &budget).map_err(fail)
    }

    /// The pixels of `film` in Radiance's shared-exponent form: the largest channel's exponent
    /// `e` (with 2^(e−1) ≤ max < 2^e) and each channel's mantissa under it, truncated to 8 bits
    /// (Ward's `float2rgbe`, as the `image` crate's encoder converts); black where no channel is
    /// positive.
    pub fn from_film(film: &Film) -> Self {
        Self {
            width: film.width,
            height: film.height,
            pixels: film.pixels.iter().map(|&c| rgb_to_rgbe(c)).collect(),
        }
    }

    /// The bytes of a Radiance file of these pixels: the header, then each row run-length
    /// encoded channel by channel (new-style scanlines), or flat where the width is outside
    /// the 8–32 767 pixels new-style scanlines can hold.
    pub fn encode(&self) -> Vec<u8> {
        let mut out = format!(
            "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {} +X {}\n",
            self.height, self.width
        )
        .into_bytes();
        let w = self.width as usize;
        if w == 0 {
            return out;
        }
        for row in self.pixels.chunks(w) {
            if !(8..0x8000).contains(&w) {
                out.extend(row.iter().flatten());
                continue;
            }
            out.extend([2, 2, (w >> 8) as u8, (w & 0xff) as u8]);
            for c in 0..4 {
                let channel: Vec<u8> = row.iter().map(|p| p[c]).collect();
                encode_runs(&channel, &mut out);
            }
        }
        out
    }

    /// Writes the Radiance file `path` (see [`RgbeImage::encode`]).
    pub fn write(&self, path: &Path) -> Result<(), Error> {
        create_parent(path)?;
        std::fs::write(path, self.encode()).map_err(|e| Error::io(path, e))
    }

    /// Parses the bytes of a Radiance file (see [`RgbeImage::read`]).
    pub fn parse(bytes: &[u8], budget: &LoadBudget) -> Result<Self, String> {
        let mut at = 0;
        let line = |at: &mut usize| -> Result<String, String> {
            let rest = &bytes[*at..];
            let end = rest
                .iter()
                .position(|&b| b == b'\n')
                .ok_or("the header ends before the resolution line")?;
            *at += end + 1;
            Ok(String::from_utf8_lossy(&rest[..end]).into_owned())
        };
        let magic = line(&mut at)?;
        if !(magic.starts_with("#?RADIANCE") || magic.starts_with("#?RGBE")) {
            return Err(format!(
                "not a Radiance file: it starts with {:?}, expected \"#?RADIANCE\"",
                magic.chars().take(16).collect::<String>()
            ));
        }
        loop {
            let l = line(&mut at)?;
            if l.is_empty() {
                break;
            }
            if let Some(format) = l.strip_prefix("FORMAT=") {
                if format.trim() != "32-bit_rle_rgbe" {
                    return Err(format!(
                        "FORMAT={format}: only 32-bit_rle_rgbe is read (not XYZE)"
                    ));
                }
            }
        }
        let resolution = line(&mut at)?;
        let parts: Vec<&str> = resolution.split_whitespace().collect();
        let (height, width) = match parts.as_slice() {
            ["-Y", h, "+X", w] => (
                h.parse::<u32>().map_err(|e| format!("height {h:?}: {e}"))?,
                w.parse::<u32>().map_err(|e| format!("width {w:?}: {e}"))?,
            ),
            _ => {
                return Err(format!(
                    "resolution line {resolution:?}: only the standard orientation \"-Y height +X width\" is read"
                ));
            }
        };
        let pixels = u64::from(width) * u64::from(height);
        if pixels == 0 || pixels > budget.max_pixels {
            return Err(format!(
                "the image is {width} × {height} pixels; expected 1 to {} pixels",
                budget.max_pixels
            ));
        }
        let mut out = Vec::with_capacity(pixels as usize);
        let w = width as usize;
        let take = |at: &mut usize, n: usize| -> Result<&[u8], String> {
            let s = bytes
                .get(*at..*at + n)
                .ok_or_else(|| format!("the pixel data ends early (at byte {})", *at))?;
            *at += n;
            Ok(s)
        };
        let mut channels = vec![0u8; 4 * w];
        for row in 0..height {
            let head = bytes.get(at..at + 4).unwrap_or(&[]);
            let rle = (8..0x8000).contains(&w)
                && head.len() == 4
                && head[0] == 2
                && head[1] == 2
                && (usize::from(head[2]) << 8 | usize::from(head[3])) == w;
            if !rle {
                // Flat pixels, in which (1, 1, 1, n) repeats the row's previous pixel
                // n · 256^k times after k repeats in a row (the run-length encoding of the
                // first Radiance files).
                let (mut x, mut shift) = (0, 0);
                while x < w {
                    let p = take(&mut at, 4)?;
                    if p[..3] != [1, 1, 1] {
                        out.push([p[0], p[1], p[2], p[3]]);
                        (x, shift) = (x + 1, 0);
                        continue;
                    }
                    let n = usize::from(p[3]) << shift;
                    let Some(&previous) = out.last().filter(|_| x > 0 && shift <= 16) else {
                        return Err(format!(
                            "row {row}: a repeat at column {x} has no pixel to repeat"
                        ));
                    };
                    if n == 0 || x + n > w {
                        return Err(format!(
                            "row {row}: a repeat of {n} pixels at column {x} does not fit the width {w}"
                        ));
                    }
                    out.extend(std::iter::repeat_n(previous, n));
                    (x, shift) = (x + n, shift + 8);
                }
                continue;
            }
            at += 4;
            for c in 0..4 {
                let mut x = 0;
                while x < w {
                    let count = take(&mut at, 1)?[0] as usize;
                    let (n, run) = if count > 128 {
                        (count - 128, true)
                    } else {
                        (count, false)
                    };
                    if n == 0 || x + n > w {
                        return Err(format!(
                            "row {row}: a run of {n} pixels at column {x} does not fit the width {w}"
                        ));
                    }
                    if run {
                        let v = take(&mut at, 1)?[0];
                        channels[c * w + x..c * w + x + n].fill(v);
                    } else {
                        channels[c * w + x..c * w + x + n].copy_from_slice(take(&mut at, n)?);
                    }
                    x += n;
                }
            }
            out.extend((0..w).map(|x| {
                [
                    channels[x],
                    channels[w + x],
                    channels[2 * w + x],
                    channels[3 * w + x],
                ]
            }));
        }
        Ok(Self {
            width,
            height,
            pixels: out,
        })
    }
}

/// `[r, g, b, e]` of a linear colour (see [`RgbeImage::from_film`]).
fn rgb_to_rgbe(c: Vec3) -> [u8; 4] {
    let max = c.max_element();
    if max.is_nan() || max <= 0.0 {
        return [0; 4];
    }
    let exponent = (max.log2().floor() as i32)
        .saturating_add(1)
        .clamp(-128, 127);
    let scale = 256.0 / f32::powi(2.0, exponent);
    let m = |v: f32| (v * scale).clamp(0.0, 255.0) as u8;
    [m(c.x), m(c.y), m(c.z), (exponent + 128) as u8]
}

/// One channel of a new-style scanline: runs of 3 to 127 equal bytes as (128 + n, byte), the
/// rest as literal records of at most 128 bytes.
fn encode_runs(channel: &[u8], out: &mut Vec<u8>) {
    let run_at = |i: usize| {
        let value = channel[i];
        channel[i..]
            .iter()
            .take(127)
            .take_while(|&&b| b == value)
            .count()
    };
    let mut i = 0;
    while i < channel.len() {
        let run = run_at(i);
        if run >= 3 {
            out.extend([128 + run as u8, channel[i]]);
            i += run;
            continue;
        }
        let start = i;
        while i < channel.len() && i - start < 128 && run_at(i) < 3 {
            i += 1;
        }
        out.push((i - start) as u8);
        out.extend(&channel[start..i]);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_flat_and_run_length_encoded_rows() {
        // Row 0 of 8 pixels run-length encoded, row 1 flat, both holding pixel k = [k, 2k, 200, 130]
        // (with k = 7 for the last four of row 0, a run).
        let mut bytes = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 8\n".to_vec();
        let row0: Vec<[u8; 4]> = (0..8u8)
            .map(|k| k.min(7))
            .map(|k| if k >= 4 { 7 } else { k })
            .map(|k| [k, 2 * k, 200, 130])
            .collect();
        bytes.extend([2, 2, 0, 8]);
        for c in 0..4 {
            let v: Vec<u8> = row0.iter().map(|p| p[c]).collect();
            bytes.push(4);
            bytes.extend(&v[..4]);
            bytes.extend([128 + 4, v[4]]);
        }
        let row1: Vec<[u8; 4]> = (0..8u8).map(|k| [k, 2 * k, 200, 130]).collect();
        bytes.extend(row1.iter().flatten());
        let img = RgbeImage::parse(&bytes, &LoadBudget::DEFAULT).unwrap();
        assert_eq!((img.width, img.height), (8, 2));
        assert_eq!(img.pixels[..8], row0[..]);
        assert_eq!(img.pixels[8..], row1[..]);
        // The image crate's encoder writes the same format.
        let rgb = vec![image::Rgb([0.5f32, 2.0, 1e-3]); 16 * 3];
        let mut encoded = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut encoded)
            .encode(&rgb, 16, 3)
            .unwrap();
        let img = RgbeImage::parse(&encoded, &LoadBudget::DEFAULT).unwrap();
        assert_eq!(img.pixels.len(), 48);
        assert!(img.pixels.iter().all(|p| *p == img.pixels[0]));

        // Old-style runs: (1, 1, 1, n) repeats the previous pixel, 256 n times after a repeat.
        let mut bytes = b"#?RADIANCE\n\n-Y 1 +X 260\n".to_vec();
        bytes.extend([9, 8, 7, 130, 1, 1, 1, 2, 1, 1, 1, 1, 5, 5, 5, 5]);
        let img = RgbeImage::parse(&bytes, &LoadBudget::DEFAULT).unwrap();
        assert_eq!(img.pixels.len(), 260);
        assert!(img.pixels[..259].iter().all(|p| *p == [9, 8, 7, 130]));
        assert_eq!(img.pixels[259], [5, 5, 5, 5]);
        let mut bytes = b"#?RADIANCE\n\n-Y 1 +X 4\n".to_vec();
        bytes.extend([1, 1, 1, 2, 9, 9, 9, 9]);
        let e = RgbeImage::parse(&bytes, &LoadBudget::DEFAULT).unwrap_err();
        assert!(e.contains("no pixel to repeat"), "{e}");

        assert!(RgbeImage::parse(b"P6\n", &LoadBudget::DEFAULT).is_err());
        let e = RgbeImage::parse(
            b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n+Y 2 +X 2\n",
            &LoadBudget::DEFAULT,
        )
        .unwrap_err();
        assert!(e.contains("orientation"), "{e}");
        let e = RgbeImage::parse(b"#?RADIANCE\n\n-Y 2 +X 2\n\x01\x02", &LoadBudget::DEFAULT)
            .unwrap_err();
        assert!(e.contains("ends early"), "{e}");
    }

    /// A film of runs longer than a record holds, literal stretches, black, negative and
    /// tiny values, at widths written run-length encoded (20, 300) and flat (5).
    fn film_of_runs(width: u32, height: u32) -> Film {
        let mut film = Film::new(width, height);
        for y in 0..height {
            for x in 0..width {
                let c = match (x / 7 + y) % 4 {
                    0 => Vec3::new(0.25, 1.5, 3.0),
                    1 => Vec3::new(x as f32 * 0.37, 1e-6 * y as f32, -1.0),
                    2 => Vec3::ZERO,
                    _ => Vec3::new(1e4, 0.1, (x * y) as f32),
                };
                film.set(x, y, c);
            }
        }
        film
    }

    #[test]
    fn written_files_read_back_as_the_pixels_written() {
        for (w, h) in [(20, 3), (300, 2), (5, 4), (8, 1)] {
            let image = RgbeImage::from_film(&film_of_runs(w, h));
            let back = RgbeImage::parse(&image.encode(), &LoadBudget::DEFAULT).unwrap();
            assert_eq!(back, image, "{w} × {h}");
        }
        // A row of one colour is two records per channel at 300 pixels (127 + 127 + 46).
        let flat = Film {
            width: 300,
            height: 1,
            pixels: vec![Vec3::splat(0.5); 300],
        };
        let image = RgbeImage::from_film(&flat);
        let header = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 300\n".len();
        assert_eq!(image.encode().len(), header + 4 + 4 * 3 * 2);
        assert_eq!(
            RgbeImage::parse(&image.encode(), &LoadBudget::DEFAULT).unwrap(),
            image
        );
    }

    #[test]
    fn pixels_convert_as_the_image_crate_s_encoder_does() {
        let film = film_of_runs(40, 6);
        let rgb: Vec<_> = film
            .pixels
            .iter()
            .map(|c| image::Rgb(c.to_array()))
            .collect();
        let mut encoded = Vec::new();
        image::codecs::hdr::HdrEncoder::new(&mut encoded)
            .encode(&rgb, 40, 6)
            .unwrap();
        let theirs = RgbeImage::parse(&encoded, &LoadBudget::DEFAULT).unwrap();
        assert_eq!(RgbeImage::from_film(&film), theirs);
        assert_eq!(rgb_to_rgbe(Vec3::ONE), [128, 128, 128, 129]);
        assert_eq!(rgb_to_rgbe(Vec3::new(-1.0, 0.0, f32::NAN)), [0; 4]);
        assert_eq!(rgb_to_rgbe(Vec3::splat(f32::INFINITY))[3], 255);
    }
}
