//! The framework's own OpenEXR reader and writer, for the subset it accepts: single-part
//! scanline or tiled images (level 0 of a mip or rip map), compressed with none, RLE, ZIPS or
//! ZIP, of UINT, HALF or FLOAT channels sampled once per pixel; R, G, B (or Y, grey) are read.
//! Every size in the file is checked against the load budget and the file's length before
//! anything is allocated from it, and every malformed structure is an error that says what is
//! wrong, never a panic (docs/architecture.md, "Decisions").

use glam::Vec3;

use super::Film;
use super::bounded::LoadBudget;
use super::decoded::{DecodedImage, check_size};

/// The magic number every OpenEXR file starts with.
const MAGIC: [u8; 4] = [0x76, 0x2f, 0x31, 0x01];
/// Version field flags (above the version number 2 in the low byte).
const FLAG_TILED: u32 = 0x200;
const FLAG_LONG_NAMES: u32 = 0x400;
const FLAG_DEEP: u32 = 0x800;
const FLAG_MULTI_PART: u32 = 0x1000;

/// The compressions raylab reads, by their code in the `compression` attribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Compression {
    None,
    Rle,
    Zips,
    Zip,
}

impl Compression {
    /// The compression of `code`, or the refusal naming the one the file uses.
    fn from_code(code: u8) -> Result<Self, String> {
        let other = match code {
            0 => return Ok(Self::None),
            1 => return Ok(Self::Rle),
            2 => return Ok(Self::Zips),
            3 => return Ok(Self::Zip),
            4 => "piz".to_string(),
            5 => "pxr24".to_string(),
            6 => "b44".to_string(),
            7 => "b44a".to_string(),
            8 => "dwaa".to_string(),
            9 => "dwab".to_string(),
            10 => "ht j2k 256".to_string(),
            11 => "ht j2k 32".to_string(),
            other => format!("unknown (code {other})"),
        };
        Err(format!(
            "the file uses {other} compression, which raylab does not read (its decoder can \
             exhaust memory or panic on a malformed file); save it with ZIP, RLE or no compression"
        ))
    }

    /// Scanlines per chunk of a scanline image.
    fn lines_per_chunk(self) -> usize {
        match self {
            Self::None | Self::Rle | Self::Zips => 1,
            Self::Zip => 16,
        }
    }
}

/// A channel's sample type.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum SampleType {
    Uint,
    Half,
    Float,
}

impl SampleType {
    fn bytes(self) -> usize {
        match self {
            Self::Half => 2,
            Self::Uint | Self::Float => 4,
        }
    }
}

/// Where a channel's samples go in the decoded pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Target {
    Red,
    Green,
    Blue,
    /// Luminance of a grey image: all three components.
    Grey,
    /// A channel raylab does not read (alpha, depth, …): skipped.
    Skip,
}

#[derive(Clone, Copy, Debug)]
struct Channel {
    sample: SampleType,
    target: Target,
}

/// A rectangle of pixels, inclusive corners as the file states them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Window {
    x_min: i32,
    y_min: i32,
    x_max: i32,
    y_max: i32,
}

impl Window {
    fn width(self) -> u64 {
        (i64::from(self.x_max) - i64::from(self.x_min) + 1) as u64
    }

    fn height(self) -> u64 {
        (i64::from(self.y_max) - i64::from(self.y_min) + 1) as u64
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Levels {
    One,
    MipMap,
    RipMap,
}

#[derive(Clone, Copy, Debug)]
struct Tiles {
    width: u32,
    height: u32,
    levels: Levels,
}

/// What the reader needs of a header.
struct Header {
    channels: Vec<Channel>,
    compression: Compression,
    data: Window,
    display: Window,
    tiles: Option<Tiles>,
}

/// A reader of little-endian values from a byte slice that fails, rather than panics, past
/// its end.
struct Bytes<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Bytes<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&end| end <= self.bytes.len());
        let end = end.ok_or_else(|| {
            format!(
                "the file ends inside {what} (byte {} of {})",
                self.at,
                self.bytes.len()
            )
        })?;
        let taken = &self.bytes[self.at..end];
        self.at = end;
        Ok(taken)
    }

    fn u8(&mut self, what: &str) -> Result<u8, String> {
        Ok(self.take(1, what)?[0])
    }

    fn i32(&mut self, what: &str) -> Result<i32, String> {
        let b = self.take(4, what)?;
        Ok(i32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn u32(&mut self, what: &str) -> Result<u32, String> {
        Ok(self.i32(what)? as u32)
    }

    /// A null-terminated name of at most `max` bytes.
    fn name(&mut self, max: usize, what: &str) -> Result<String, String> {
        let rest = &self.bytes[self.at.min(self.bytes.len())..];
        let len = rest
            .iter()
            .take(max + 1)
            .position(|&b| b == 0)
            .ok_or_else(|| {
                if rest.len() <= max {
                    format!("the file ends inside {what}")
                } else {
                    format!("{what} is longer than {max} bytes")
                }
            })?;
        let name = String::from_utf8_lossy(&rest[..len]).into_owned();
        self.at += len + 1;
        Ok(name)
    }
}

/// Decodes the OpenEXR file `bytes` under `budget`: the display window's pixels, black outside
/// the data window. The error is the reason only (the caller names the file).
pub(crate) fn decode(bytes: &[u8], budget: &LoadBudget) -> Result<DecodedImage, String> {
    let mut reader = Bytes { bytes, at: 0 };
    let header = read_header(&mut reader)?;
    check_budget(&header, budget)?;
    let display_width = header.display.width() as usize;
    let display_height = header.display.height() as usize;
    let mut image = Pixels {
        rgb: vec![Vec3::ZERO; display_width * display_height],
        display: header.display,
        width: display_width,
        channels: &header.channels,
    };
    let data_width = header.data.width() as usize;
    let data_height = header.data.height() as usize;
    match header.tiles {
        None => {
            let per_chunk = header.compression.lines_per_chunk();
            let chunks = data_height.div_ceil(per_chunk);
            let offsets = read_offsets(&mut reader, chunks)?;
            for (i, &offset) in offsets.iter().enumerate() {
                let first = i * per_chunk;
                let lines = per_chunk.min(data_height - first);
                let y = i64::from(header.data.y_min) + first as i64;
                let mut chunk = chunk_at(bytes, offset, i, "scanline chunk")?;
                let stated = chunk.i32("a chunk's y")?;
                if i64::from(stated) != y {
                    return Err(format!(
                        "scanline chunk {i} states y = {stated}; the offset table's chunk {i} is at y = {y}"
                    ));
                }
                let data = chunk_data(&mut chunk, i)?;
                let block = Block {
                    x: i64::from(header.data.x_min),
                    y,
                    width: data_width,
                    lines,
                };
                image.fill(&block, data, header.compression, i)?;
            }
        }
        Some(tiles) => {
            let (tile_width, tile_height) = (tiles.width as usize, tiles.height as usize);
            let across = data_width.div_ceil(tile_width);
            let down = data_height.div_ceil(tile_height);
            let offsets = read_offsets(&mut reader, across.saturating_mul(down))?;
            for (i, &offset) in offsets.iter().enumerate() {
                let (tx, ty) = (i % across, i / across);
                let mut chunk = chunk_at(bytes, offset, i, "tile")?;
                let mut stated = [0; 4];
                for value in &mut stated {
                    *value = chunk.i32("a tile's coordinates")?;
                }
                if stated != [tx as i32, ty as i32, 0, 0] {
                    return Err(format!(
                        "tile {i} states tile ({}, {}) of level ({}, {}); the offset table's tile {i} \
                         is tile ({tx}, {ty}) of level (0, 0)",
                        stated[0], stated[1], stated[2], stated[3]
                    ));
                }
                let data = chunk_data(&mut chunk, i)?;
                let block = Block {
                    x: i64::from(header.data.x_min) + (tx * tile_width) as i64,
                    y: i64::from(header.data.y_min) + (ty * tile_height) as i64,
                    width: tile_width.min(data_width - tx * tile_width),
                    lines: tile_height.min(data_height - ty * tile_height),
                };
                image.fill(&block, data, header.compression, i)?;
            }
        }
    }
    Ok(DecodedImage {
        width: display_width as u32,
        height: display_height as u32,
        rgb: image.rgb,
        is_float: true,
    })
}

fn read_header(reader: &mut Bytes) -> Result<Header, String> {
    if reader.take(4, "the magic number")? != MAGIC {
        return Err("not an OpenEXR file (wrong magic number)".into());
    }
    let version = reader.u32("the version field")?;
    if version & 0xff != 2 {
        return Err(format!(
            "OpenEXR version {} is not read (only version 2)",
            version & 0xff
        ));
    }
    if version & FLAG_MULTI_PART != 0 {
        return Err(
            "multi-part OpenEXR files are not read; save the image as a single part".into(),
        );
    }
    if version & FLAG_DEEP != 0 {
        return Err("deep OpenEXR data is not an image raylab reads".into());
    }
    let unknown = version & !0xff & !(FLAG_TILED | FLAG_LONG_NAMES);
    if unknown != 0 {
        return Err(format!(
            "the version field has flags 0x{unknown:x} that raylab does not know"
        ));
    }
    let max_name = if version & FLAG_LONG_NAMES != 0 {
        255
    } else {
        31
    };
    let (mut channels, mut compression, mut data, mut display, mut tiles) =
        (None, None, None, None, None);
    loop {
        let name = reader.name(max_name, "an attribute's name")?;
        if name.is_empty() {
            break;
        }
        let kind = reader.name(max_name, &format!("the type of attribute {name:?}"))?;
        let size = reader.i32(&format!("the size of attribute {name:?}"))?;
        let size = usize::try_from(size)
            .map_err(|_| format!("attribute {name:?} has a negative size {size}"))?;
        let value = reader.take(size, &format!("attribute {name:?}"))?;
        let expect = |want_kind: &str, want_size: Option<usize>| -> Result<(), String> {
            if kind != want_kind || want_size.is_some_and(|s| s != size) {
                return Err(format!(
                    "attribute {name:?} is of type {kind:?} with {size} bytes; expected {want_kind:?}{}",
                    want_size.map_or(String::new(), |s| format!(" with {s} bytes"))
                ));
            }
            Ok(())
        };
        let mut value_reader = Bytes {
            bytes: value,
            at: 0,
        };
        match name.as_str() {
            "channels" => {
                expect("chlist", None)?;
                channels = Some(read_channels(&mut value_reader, max_name)?);
            }
            "compression" => {
                expect("compression", Some(1))?;
                compression = Some(Compression::from_code(value[0])?);
            }
            "dataWindow" => {
                expect("box2i", Some(16))?;
                data = Some(read_window(&mut value_reader, "data")?);
            }
            "displayWindow" => {
                expect("box2i", Some(16))?;
                display = Some(read_window(&mut value_reader, "display")?);
            }
            "lineOrder" => {
                expect("lineOrder", Some(1))?;
                // Increasing, decreasing or random y: the offset table says where each chunk
                // is, whatever the order.
                if value[0] > 2 {
                    return Err(format!(
                        "line order {} is not an OpenEXR line order",
                        value[0]
                    ));
                }
            }
            "tiles" => {
                expect("tiledesc", Some(9))?;
                let width = value_reader.u32("the tile width")?;
                let height = value_reader.u32("the tile height")?;
                let mode = value_reader.u8("the level mode")?;
                let levels = match mode & 0x0f {
                    0 => Levels::One,
                    1 => Levels::MipMap,
                    2 => Levels::RipMap,
                    other => {
                        return Err(format!("level mode {other} is not an OpenEXR level mode"));
                    }
                };
                if mode >> 4 > 1 {
                    return Err(format!(
                        "level rounding mode {} is not an OpenEXR rounding mode",
                        mode >> 4
                    ));
                }
                if width == 0 || height == 0 || width > i32::MAX as u32 || height > i32::MAX as u32
                {
                    return Err(format!("the tiles are {width} × {height} pixels"));
                }
                tiles = Some(Tiles {
                    width,
                    height,
                    levels,
                });
            }
            "type" => {
                let kind = String::from_utf8_lossy(value);
                let kind = kind.trim_end_matches('\0');
                if kind.starts_with("deep") {
                    return Err("deep OpenEXR data is not an image raylab reads".into());
                }
            }
            _ => {}
        }
    }
    let missing = |what: &str| format!("the header has no {what:?} attribute");
    let tiled = version & FLAG_TILED != 0;
    if tiled && tiles.is_none() {
        return Err(missing("tiles"));
    }
    Ok(Header {
        channels: channels.ok_or_else(|| missing("channels"))?,
        compression: compression.ok_or_else(|| missing("compression"))?,
        data: data.ok_or_else(|| missing("dataWindow"))?,
        display: display.ok_or_else(|| missing("displayWindow"))?,
        // A scanline file's "tiles" attribute means nothing.
        tiles: if tiled { tiles } else { None },
    })
}

/// The channel list: which channels raylab reads and the size of every one's samples.
fn read_channels(reader: &mut Bytes, max_name: usize) -> Result<Vec<Channel>, String> {
    let mut channels: Vec<Channel> = Vec::new();
    let mut names = Vec::new();
    loop {
        let name = reader.name(max_name, "a channel's name")?;
        if name.is_empty() {
            break;
        }
        let what = format!("channel {name:?}");
        let sample = match reader.i32(&what)? {
            0 => SampleType::Uint,
            1 => SampleType::Half,
            2 => SampleType::Float,
            other => {
                return Err(format!(
                    "{what} has pixel type {other}, not UINT, HALF or FLOAT"
                ));
            }
        };
        reader.take(4, &what)?; // pLinear and three reserved bytes
        let (x_sampling, y_sampling) = (reader.i32(&what)?, reader.i32(&what)?);
        if (x_sampling, y_sampling) != (1, 1) {
            return Err(format!(
                "{what} is subsampled ({x_sampling} × {y_sampling}), which raylab does not read"
            ));
        }
        if names.contains(&name) {
            return Err(format!("{what} is listed twice"));
        }
        let target = match name.as_str() {
            "R" => Target::Red,
            "G" => Target::Green,
            "B" => Target::Blue,
            "Y" => Target::Grey,
            _ => Target::Skip,
        };
        names.push(name);
        channels.push(Channel { sample, target });
    }
    let has = |t: Target| channels.iter().any(|c| c.target == t);
    let colour = has(Target::Red) || has(Target::Green) || has(Target::Blue);
    if colour {
        // R, G and B make the pixel; a Y beside them is not read.
        for c in &mut channels {
            if c.target == Target::Grey {
                c.target = Target::Skip;
            }
        }
    } else if !has(Target::Grey) {
        return Err(format!(
            "the image has no R, G, B or Y channel (its channels: {})",
            names.join(", ")
        ));
    }
    Ok(channels)
}

fn read_window(reader: &mut Bytes, what: &str) -> Result<Window, String> {
    let window = Window {
        x_min: reader.i32(what)?,
        y_min: reader.i32(what)?,
        x_max: reader.i32(what)?,
        y_max: reader.i32(what)?,
    };
    if window.x_max < window.x_min || window.y_max < window.y_min {
        return Err(format!(
            "the {what} window ({}, {}) – ({}, {}) is empty",
            window.x_min, window.y_min, window.x_max, window.y_max
        ));
    }
    Ok(window)
}

/// Refuses a header whose windows, tiles or channels are over the load budget.
fn check_budget(header: &Header, budget: &LoadBudget) -> Result<(), String> {
    let mut levels = 1;
    if let Some(tiles) = header.tiles {
        if u64::from(tiles.width).saturating_mul(u64::from(tiles.height)) > budget.max_pixels {
            return Err(format!(
                "the tiles are {} × {} pixels; the load budget allows at most {} pixels",
                tiles.width, tiles.height, budget.max_pixels
            ));
        }
        levels = match tiles.levels {
            Levels::One => 1,
            // The smaller levels of a mip map add up to a third of the image, those of a rip
            // map to three times it.
            Levels::MipMap => 2,
            Levels::RipMap => 4,
        };
    }
    for window in [header.data, header.display] {
        check_size(window.width(), window.height(), 16, budget)?;
    }
    let pixels = header
        .data
        .width()
        .saturating_mul(header.data.height())
        .saturating_mul(levels);
    if pixels > budget.max_pixels {
        return Err(format!(
            "the levels of the file hold {pixels} pixels; the load budget allows at most {}",
            budget.max_pixels
        ));
    }
    let bytes = pixels.saturating_mul((header.channels.len() as u64).saturating_mul(4));
    if bytes > budget.max_decode_bytes {
        return Err(format!(
            "the channels of the file take {} MiB; the load budget allows {} MiB",
            bytes >> 20,
            budget.max_decode_bytes >> 20
        ));
    }
    Ok(())
}

/// The offset table's first `count` entries, checked to fit in the file before they are read.
fn read_offsets(reader: &mut Bytes, count: usize) -> Result<Vec<u64>, String> {
    let table = count
        .checked_mul(8)
        .filter(|&n| n <= reader.bytes.len().saturating_sub(reader.at))
        .ok_or_else(|| format!("the file ends inside its offset table of {count} chunks"))?;
    let table = reader.take(table, "the offset table")?;
    Ok(table
        .chunks_exact(8)
        .map(|b| u64::from_le_bytes(b.try_into().expect("8 bytes")))
        .collect())
}

/// A reader at chunk `index`'s offset, checked to be inside the file.
fn chunk_at<'a>(
    bytes: &'a [u8],
    offset: u64,
    index: usize,
    what: &str,
) -> Result<Bytes<'a>, String> {
    match usize::try_from(offset) {
        Ok(at) if at < bytes.len() => Ok(Bytes { bytes, at }),
        _ => Err(format!(
            "the offset table puts {what} {index} at byte {offset}, outside the file of {} bytes",
            bytes.len()
        )),
    }
}

/// A chunk's data: its stated size, checked against the file.
fn chunk_data<'a>(chunk: &mut Bytes<'a>, index: usize) -> Result<&'a [u8], String> {
    let size = chunk.i32("a chunk's size")?;
    let size = usize::try_from(size)
        .map_err(|_| format!("chunk {index} states a negative size {size}"))?;
    chunk.take(size, &format!("chunk {index}, of {size} bytes"))
}

/// The pixels of a chunk: `lines` lines of `width` pixels from (x, y) in the data window's
/// coordinates.
struct Block {
    x: i64,
    y: i64,
    width: usize,
    lines: usize,
}

/// The display window's pixels being decoded.
struct Pixels<'a> {
    rgb: Vec<Vec3>,
    display: Window,
    width: usize,
    channels: &'a [Channel],
}

impl Pixels<'_> {
    /// Decompresses a chunk's `data` and sets the pixels of `block` that are in the display
    /// window.
    fn fill(
        &mut self,
        block: &Block,
        data: &[u8],
        compression: Compression,
        index: usize,
    ) -> Result<(), String> {
        let pixel_bytes: usize = self.channels.iter().map(|c| c.sample.bytes()).sum();
        // Within the budget-checked data window, so no overflow.
        let expected = block.width * block.lines * pixel_bytes;
        let raw;
        let samples = if data.len() == expected {
            // A chunk that would not get smaller is stored as it is, whatever the compression.
            data
        } else {
            raw = match compression {
                Compression::None => {
                    return Err(format!(
                        "chunk {index} holds {} bytes; its pixels take {expected}",
                        data.len()
                    ));
                }
                Compression::Rle => unpredict(rle_decompress(data, expected, index)?),
                Compression::Zips | Compression::Zip => {
                    unpredict(zip_decompress(data, expected, index)?)
                }
            };
            &raw
        };
        let line_bytes = block.width * pixel_bytes;
        for line in 0..block.lines {
            let y = block.y + line as i64 - i64::from(self.display.y_min);
            let mut at = line * line_bytes;
            for channel in self.channels {
                let size = channel.sample.bytes();
                let values = &samples[at..at + block.width * size];
                at += block.width * size;
                if channel.target == Target::Skip || y < 0 || y >= self.display.height() as i64 {
                    continue;
                }
                let row = y as usize * self.width;
                for (i, sample) in values.chunks_exact(size).enumerate() {
                    let x = block.x + i as i64 - i64::from(self.display.x_min);
                    if x < 0 || x >= self.width as i64 {
                        continue;
                    }
                    let value = match channel.sample {
                        SampleType::Half => half_to_f32(u16::from_le_bytes([sample[0], sample[1]])),
                        SampleType::Float => f32::from_le_bytes(sample.try_into().expect("4")),
                        SampleType::Uint => {
                            u32::from_le_bytes(sample.try_into().expect("4")) as f32
                        }
                    };
                    let pixel = &mut self.rgb[row + x as usize];
                    match channel.target {
                        Target::Red => pixel.x = value,
                        Target::Green => pixel.y = value,
                        Target::Blue => pixel.z = value,
                        Target::Grey => *pixel = Vec3::splat(value),
                        Target::Skip => {}
                    }
                }
            }
        }
        Ok(())
    }
}

/// OpenEXR's run-length decoding: a signed count byte, then either `count + 1` copies of the
/// next byte (count ≥ 0) or `-count` literal bytes; the output must be exactly `expected`
/// bytes.
fn rle_decompress(data: &[u8], expected: usize, index: usize) -> Result<Vec<u8>, String> {
    let overflow = || format!("chunk {index}'s RLE runs give more than its {expected} bytes");
    let mut out = Vec::with_capacity(expected);
    let mut at = 0;
    while at < data.len() {
        let count = data[at] as i8;
        at += 1;
        if count < 0 {
            let n = usize::from(count.unsigned_abs());
            let literal = data
                .get(at..at + n)
                .ok_or_else(|| format!("chunk {index}'s RLE data ends inside a literal run"))?;
            if out.len() + n > expected {
                return Err(overflow());
            }
            out.extend_from_slice(literal);
            at += n;
        } else {
            let n = count as usize + 1;
            let &value = data
                .get(at)
                .ok_or_else(|| format!("chunk {index}'s RLE data ends inside a run"))?;
            if out.len() + n > expected {
                return Err(overflow());
            }
            out.resize(out.len() + n, value);
            at += 1;
        }
    }
    if out.len() != expected {
        return Err(format!(
            "chunk {index}'s RLE data gives {} bytes; its pixels take {expected}",
            out.len()
        ));
    }
    Ok(out)
}

/// zlib decompression of exactly `expected` bytes.
fn zip_decompress(data: &[u8], expected: usize, index: usize) -> Result<Vec<u8>, String> {
    use miniz_oxide::inflate::{TINFLStatus, decompress_to_vec_zlib_with_limit};
    let out = decompress_to_vec_zlib_with_limit(data, expected).map_err(|e| match e.status {
        TINFLStatus::HasMoreOutput => {
            format!("chunk {index}'s ZIP data gives more than its {expected} bytes")
        }
        status => format!(
            "chunk {index}'s ZIP data is not zlib data ({})",
            super::decoded::words(&format!("{status:?}"))
        ),
    })?;
    if out.len() != expected {
        return Err(format!(
            "chunk {index}'s ZIP data gives {} bytes; its pixels take {expected}",
            out.len()
        ));
    }
    Ok(out)
}

/// Undoes the byte predictor and the interleaving that OpenEXR's RLE and ZIP compressors apply
/// before compressing: each byte is stored as its difference to the previous one (plus 128),
/// and the even bytes come first, then the odd ones.
fn unpredict(mut bytes: Vec<u8>) -> Vec<u8> {
    for i in 1..bytes.len() {
        bytes[i] = bytes[i - 1].wrapping_add(bytes[i]).wrapping_sub(128);
    }
    let (even, odd) = bytes.split_at(bytes.len().div_ceil(2));
    let mut out = Vec::with_capacity(bytes.len());
    for (i, &b) in even.iter().enumerate() {
        out.push(b);
        out.extend(odd.get(i));
    }
    out
}

/// The inverse of [`unpredict`].
fn predict(bytes: &[u8]) -> Vec<u8> {
    let mut out: Vec<u8> = bytes.iter().step_by(2).copied().collect();
    out.extend(bytes.iter().skip(1).step_by(2));
    for i in (1..out.len()).rev() {
        out[i] = out[i].wrapping_sub(out[i - 1]).wrapping_add(128);
    }
    out
}

/// An IEEE 754 half-precision value as the `f32` it is exactly: subnormals normalized, ±∞
/// kept, NaN quiet with its payload.
pub(crate) fn half_to_f32(half: u16) -> f32 {
    let sign = u32::from(half & 0x8000) << 16;
    let exponent = u32::from(half >> 10) & 0x1f;
    let mantissa = u32::from(half & 0x03ff);
    let bits = match (exponent, mantissa) {
        (0, 0) => sign,
        (0, _) => {
            // Subnormal: m · 2⁻²⁴; shift the leading one into the implicit bit.
            let shift = mantissa.leading_zeros() - 21;
            let mantissa = (mantissa << shift) & 0x03ff;
            sign | ((127 - 15 + 1 - shift) << 23) | (mantissa << 13)
        }
        (0x1f, 0) => sign | 0x7f80_0000,
        (0x1f, _) => sign | 0x7fc0_0000 | (mantissa << 13),
        _ => sign | ((exponent + 127 - 15) << 23) | (mantissa << 13),
    };
    f32::from_bits(bits)
}

/// Scanlines per chunk of the files raylab writes.
const WRITE_LINES_PER_CHUNK: usize = 16;

/// The bytes of an OpenEXR file of `film`: one part of scanlines, FLOAT channels B, G, R
/// (OpenEXR's alphabetical order), increasing y.
///
/// ZIP in chunks of 16 lines at zlib level 1: measured on the 23 snapshots of the labs (160 ×
/// 120 renders, 4.8 MB of floats), RLE keeps 85 % of the bytes (about 1 ms an image), ZIP at
/// level 1 43 % (2.4 ms) and at level 4 42 % (5.4 ms). Half the size of RLE for a millisecond
/// more; level 4's extra 1 % is not worth twice the time.
pub(crate) fn encode(film: &Film) -> Vec<u8> {
    let width = film.width as usize;
    let height = film.height as usize;
    let window = |out: &mut Vec<u8>| {
        for v in [0, 0, film.width as i32 - 1, film.height as i32 - 1] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    };
    let mut out = Vec::new();
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&2u32.to_le_bytes());
    let attribute = |out: &mut Vec<u8>, name: &str, kind: &str, size: usize| {
        for s in [name, kind] {
            out.extend_from_slice(s.as_bytes());
            out.push(0);
        }
        out.extend_from_slice(&(size as i32).to_le_bytes());
    };
    attribute(&mut out, "channels", "chlist", 3 * 18 + 1);
    for name in ["B", "G", "R"] {
        out.extend_from_slice(name.as_bytes());
        out.push(0);
        out.extend_from_slice(&2i32.to_le_bytes()); // FLOAT
        out.extend_from_slice(&[0; 4]); // pLinear, reserved
        out.extend_from_slice(&1i32.to_le_bytes());
        out.extend_from_slice(&1i32.to_le_bytes());
    }
    out.push(0);
    attribute(&mut out, "compression", "compression", 1);
    out.push(3); // ZIP
    attribute(&mut out, "dataWindow", "box2i", 16);
    window(&mut out);
    attribute(&mut out, "displayWindow", "box2i", 16);
    window(&mut out);
    attribute(&mut out, "lineOrder", "lineOrder", 1);
    out.push(0); // increasing y
    attribute(&mut out, "pixelAspectRatio", "float", 4);
    out.extend_from_slice(&1f32.to_le_bytes());
    attribute(&mut out, "screenWindowCenter", "v2f", 8);
    out.extend_from_slice(&[0; 8]);
    attribute(&mut out, "screenWindowWidth", "float", 4);
    out.extend_from_slice(&1f32.to_le_bytes());
    out.push(0);
    let chunks = height.div_ceil(WRITE_LINES_PER_CHUNK);
    let table = out.len();
    out.resize(table + 8 * chunks, 0);
    let mut raw = Vec::with_capacity(WRITE_LINES_PER_CHUNK * width * 12);
    for chunk in 0..chunks {
        let offset = out.len() as u64;
        out[table + 8 * chunk..table + 8 * chunk + 8].copy_from_slice(&offset.to_le_bytes());
        let first = chunk * WRITE_LINES_PER_CHUNK;
        let lines = WRITE_LINES_PER_CHUNK.min(height - first);
        raw.clear();
        for row in film.pixels[first * width..(first + lines) * width].chunks_exact(width) {
            for component in [2, 1, 0] {
                for pixel in row {
                    raw.extend_from_slice(&pixel[component].to_le_bytes());
                }
            }
        }
        let compressed = miniz_oxide::deflate::compress_to_vec_zlib(&predict(&raw), 1);
        // A chunk that would not get smaller is stored as it is.
        let data = if compressed.len() < raw.len() {
            &compressed
        } else {
            &raw
        };
        out.extend_from_slice(&(first as i32).to_le_bytes());
        out.extend_from_slice(&(data.len() as i32).to_le_bytes());
        out.extend_from_slice(data);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{
        Bytes, Film, LoadBudget, Vec3, decode, encode, predict, read_header, read_offsets,
        unpredict,
    };
    #[cfg(feature = "crosscheck")]
    use super::{Levels as LevelMode, half_to_f32};
    #[cfg(feature = "crosscheck")]
    use exr::prelude::*;
    #[cfg(feature = "crosscheck")]
    use std::path::Path;
    #[cfg(feature = "crosscheck")]
    use std::path::PathBuf;

    #[cfg(feature = "crosscheck")]
    /// What the `exr` crate (the decoder `image` wraps) reads from `bytes`: the largest level's
    /// R, G, B placed in the display window, black outside the data window.
    fn exr_reference(bytes: &[u8]) -> (usize, usize, Vec<Vec3>) {
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .rgb_channels(
                |resolution, _| (resolution, vec![Vec3::ZERO; resolution.area()]),
                |(size, pixels): &mut (Vec2<usize>, Vec<Vec3>), at, (r, g, b): (f32, f32, f32)| {
                    pixels[at.y() * size.width() + at.x()] = Vec3::new(r, g, b);
                },
            )
            .first_valid_layer()
            .all_attributes()
            .from_buffered(std::io::Cursor::new(bytes))
            .unwrap();
        let layer = &image.layer_data;
        let display = image.attributes.display_window;
        let offset = layer.attributes.layer_position - display.position;
        let (width, height) = (display.size.width(), display.size.height());
        let (size, data) = &layer.channel_data.pixels;
        let mut rgb = vec![Vec3::ZERO; width * height];
        for y in 0..size.height() {
            for x in 0..size.width() {
                let (dx, dy) = (x as i64 + offset.x() as i64, y as i64 + offset.y() as i64);
                if (0..width as i64).contains(&dx) && (0..height as i64).contains(&dy) {
                    rgb[dy as usize * width + dx as usize] = data[y * size.width() + x];
                }
            }
        }
        (width, height, rgb)
    }

    #[cfg(feature = "crosscheck")]
    /// Decodes `bytes` both ways and asserts the same size and the same bits in every pixel.
    fn assert_same_as_exr(bytes: &[u8], name: &str) {
        let ours = decode(bytes, &LoadBudget::DEFAULT).unwrap_or_else(|e| panic!("{name}: {e}"));
        let (width, height, theirs) = exr_reference(bytes);
        assert_eq!(
            (ours.width as usize, ours.height as usize),
            (width, height),
            "{name}"
        );
        for (i, (a, b)) in ours.rgb.iter().zip(&theirs).enumerate() {
            let bits = |v: &Vec3| v.to_array().map(f32::to_bits);
            assert_eq!(bits(a), bits(b), "{name} pixel {i}: {a} ≠ {b}");
        }
    }

    #[cfg(feature = "crosscheck")]
    fn repository() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
    }

    #[cfg(feature = "crosscheck")]
    /// The OpenEXR files of the repository: the labs' snapshots and probes and the fuzz corpus
    /// (but for the PIZ seed, which is refused).
    fn repository_files() -> Vec<PathBuf> {
        let root = repository();
        let mut files = Vec::new();
        let mut add = |dir: PathBuf| {
            if let Ok(entries) = std::fs::read_dir(&dir) {
                for entry in entries {
                    let path = entry.unwrap().path();
                    if path.extension().is_some_and(|e| e == "exr") && !path.ends_with("piz.exr") {
                        files.push(path);
                    }
                }
            }
        };
        for lab in std::fs::read_dir(root.join("labs")).unwrap() {
            let lab = lab.unwrap().path();
            add(lab.join("snapshots"));
            add(lab.join("probes"));
        }
        add(root.join("framework/core/tests/fuzz-corpus/exr"));
        files.sort();
        files
    }

    #[cfg(feature = "crosscheck")]
    #[test]
    fn reads_the_repository_s_files_as_the_exr_crate_does() {
        let files = repository_files();
        for path in &files {
            assert_same_as_exr(&std::fs::read(path).unwrap(), &path.display().to_string());
        }
        for needed in [
            "labs/lab01/snapshots/default-base-colour.exr",
            "labs/lab11/probes/studio-latlong.exr",
            "labs/lab12/probes/city.exr",
            "framework/core/tests/fuzz-corpus/exr/tiled-zip16.exr",
        ] {
            assert!(files.contains(&repository().join(needed)), "{needed}");
        }
    }

    #[cfg(feature = "crosscheck")]
    /// A `width × height` layer of R, G, B channels of `sample` values, written by the `exr`
    /// crate with `encoding` at `position`.
    fn written_by_exr(
        encoding: Encoding,
        position: Vec2<i32>,
        sample: impl Fn(usize, usize, usize) -> FlatSamples,
    ) -> Vec<u8> {
        let (width, height) = (13, 11);
        let channels = ["B", "G", "R"]
            .iter()
            .enumerate()
            .map(|(c, name)| AnyChannel::new(*name, sample(c, width, height)))
            .collect();
        let mut attributes = LayerAttributes::named("layer");
        attributes.layer_position = position;
        let layer = Layer::new(
            (width, height),
            attributes,
            encoding,
            AnyChannels::sort(channels),
        );
        let mut image = Image::from_layer(layer);
        image.attributes.display_window = IntegerBounds::new((-2, 1), (12, 9));
        let mut bytes = Vec::new();
        image
            .write()
            .to_buffered(std::io::Cursor::new(&mut bytes))
            .unwrap();
        bytes
    }

    #[cfg(feature = "crosscheck")]
    /// The samples of channel `c` of a `w × h` layer.
    type SampleOf = fn(usize, usize, usize) -> FlatSamples;

    fn value(c: usize, i: usize) -> f32 {
        // Runs (for RLE), fractions and a few special values.
        match i % 17 {
            0 => f32::INFINITY,
            1 => -0.0,
            2 => 1e-30,
            3..=6 => 0.5,
            k => (c * 1000 + i) as f32 / (k as f32 + 0.5),
        }
    }

    #[cfg(feature = "crosscheck")]
    #[test]
    fn reads_every_supported_layout_as_the_exr_crate_does() {
        let compressions = [
            Compression::Uncompressed,
            Compression::RLE,
            Compression::ZIP1,
            Compression::ZIP16,
        ];
        let blocks = [
            Blocks::ScanLines,
            Blocks::Tiles(Vec2(4, 3)),
            Blocks::Tiles(Vec2(32, 32)),
        ];
        let orders = [LineOrder::Increasing, LineOrder::Decreasing];
        let samples: [(&str, SampleOf); 3] = [
            ("float", |c, w, h| {
                FlatSamples::F32((0..w * h).map(|i| value(c, i)).collect())
            }),
            ("half", |c, w, h| {
                FlatSamples::F16(
                    (0..w * h)
                        .map(|i| ::half::f16::from_f32(value(c, i)))
                        .collect(),
                )
            }),
            ("uint", |c, w, h| {
                FlatSamples::U32(
                    (0..w * h)
                        .map(|i| (c * 7919 + i * 104_729) as u32)
                        .collect(),
                )
            }),
        ];
        let mut seen = 0;
        for compression in compressions {
            for block in blocks {
                for line_order in orders {
                    for (kind, sample) in samples {
                        for position in [Vec2(0, 0), Vec2(-3, 2)] {
                            let encoding = Encoding {
                                compression,
                                blocks: block,
                                line_order,
                            };
                            let bytes = written_by_exr(encoding, position, sample);
                            let name = format!(
                                "{compression} {block:?} {line_order:?} {kind} at {position:?}"
                            );
                            assert_same_as_exr(&bytes, &name);
                            seen += 1;
                        }
                    }
                }
            }
        }
        assert_eq!(seen, 4 * 3 * 2 * 3 * 2);
    }

    #[cfg(feature = "crosscheck")]
    #[test]
    fn reads_level_zero_of_mip_and_rip_maps() {
        use exr::math::RoundingMode;
        let size = Vec2(9, 6);
        // Each level's samples differ with its size, so a wrong level shows.
        let level = |c: usize, at: Vec2<usize>| {
            FlatSamples::F32(
                (0..at.area())
                    .map(|i| value(c, i) + at.width() as f32)
                    .collect(),
            )
        };
        for mip in [true, false] {
            let channels = ["B", "G", "R"]
                .iter()
                .enumerate()
                .map(|(c, name)| {
                    let levels = if mip {
                        Levels::Mip {
                            rounding_mode: RoundingMode::Down,
                            level_data: exr::meta::mip_map_levels(RoundingMode::Down, size)
                                .map(|(_, at)| level(c, at))
                                .collect(),
                        }
                    } else {
                        Levels::Rip {
                            rounding_mode: RoundingMode::Up,
                            level_data: RipMaps {
                                map_data: exr::meta::rip_map_levels(RoundingMode::Up, size)
                                    .map(|(_, at)| level(c, at))
                                    .collect(),
                                level_count: Vec2(5, 4),
                            },
                        }
                    };
                    AnyChannel::new(*name, levels)
                })
                .collect();
            let layer = Layer::new(
                size,
                LayerAttributes::named("levels"),
                Encoding {
                    compression: Compression::ZIP16,
                    blocks: Blocks::Tiles(Vec2(4, 4)),
                    line_order: LineOrder::Increasing,
                },
                AnyChannels::sort(channels),
            );
            let mut bytes = Vec::new();
            Image::from_layer(layer)
                .write()
                .to_buffered(std::io::Cursor::new(&mut bytes))
                .unwrap();
            let mut reader = Bytes {
                bytes: &bytes,
                at: 0,
            };
            let tiles = read_header(&mut reader).unwrap().tiles.unwrap();
            let mode = if mip {
                LevelMode::MipMap
            } else {
                LevelMode::RipMap
            };
            assert_eq!(tiles.levels, mode);
            assert_same_as_exr(&bytes, &format!("{mode:?}"));
        }
    }

    #[cfg(feature = "crosscheck")]
    #[test]
    fn a_grey_image_is_its_y_channel_in_all_three_components() {
        let channels = AnyChannels::sort(
            std::iter::once(AnyChannel::new("Y", FlatSamples::F32(vec![0.25, 4.0]))).collect(),
        );
        let mut bytes = Vec::new();
        Image::from_channels((2, 1), channels)
            .write()
            .to_buffered(std::io::Cursor::new(&mut bytes))
            .unwrap();
        let image = decode(&bytes, &LoadBudget::DEFAULT).unwrap();
        assert_eq!(image.rgb, [Vec3::splat(0.25), Vec3::splat(4.0)]);
    }

    fn film() -> Film {
        let mut film = Film::new(37, 21);
        for (i, p) in film.pixels.iter_mut().enumerate() {
            *p = Vec3::new(value(0, i), value(1, i) * 0.1, (i as f32).sqrt());
        }
        film.pixels[5] = Vec3::new(f32::NAN, f32::NEG_INFINITY, f32::MIN_POSITIVE / 8.0);
        film
    }

    #[test]
    fn written_files_read_back_bit_exactly_here_and_with_the_exr_crate() {
        let film = film();
        let bytes = encode(&film);
        let ours = decode(&bytes, &LoadBudget::DEFAULT).unwrap();
        assert_eq!((ours.width, ours.height), (film.width, film.height));
        let bits = |v: &[Vec3]| -> Vec<[u32; 3]> {
            v.iter().map(|p| p.to_array().map(f32::to_bits)).collect()
        };
        assert_eq!(bits(&ours.rgb), bits(&film.pixels));
        #[cfg(feature = "crosscheck")]
        {
            let (width, height, theirs) = exr_reference(&bytes);
            assert_eq!((width, height), (37, 21));
            assert_eq!(bits(&theirs), bits(&film.pixels));
            // The exr crate's metadata: one part, ZIP, R, G, B floats.
            let meta = exr::meta::MetaData::read_from_buffered(std::io::Cursor::new(&bytes), true)
                .unwrap();
            assert_eq!(meta.headers.len(), 1);
            assert_eq!(meta.headers[0].compression, Compression::ZIP16);
            assert_eq!(meta.headers[0].channels.list.len(), 3);
        }
    }

    #[cfg(feature = "crosscheck")]
    #[test]
    fn half_to_f32_is_exact_for_all_65536_values() {
        for bits in 0..=u16::MAX {
            let ours = half_to_f32(bits);
            let theirs = ::half::f16::from_bits(bits).to_f32();
            assert_eq!(ours.to_bits(), theirs.to_bits(), "0x{bits:04x}");
        }
    }

    #[test]
    fn predict_and_unpredict_are_inverse() {
        for len in 0..9 {
            let bytes: Vec<u8> = (0..len).map(|i| (i * 37 + 200) as u8).collect();
            assert_eq!(unpredict(predict(&bytes)), bytes, "{len} bytes");
        }
    }

    /// A small RLE file written by the `exr` crate, kept in the repository (the `crosscheck`
    /// tests write it again and compare).
    const RLE_FIXTURE: &str = "tests/fixtures/rle-13x11.exr";

    #[cfg(feature = "crosscheck")]
    fn rle_written_by_exr() -> Vec<u8> {
        written_by_exr(
            Encoding {
                compression: Compression::RLE,
                blocks: Blocks::ScanLines,
                line_order: LineOrder::Increasing,
            },
            Vec2(0, 0),
            |c, w, h| FlatSamples::F32((0..w * h).map(|i| value(c, i)).collect()),
        )
    }

    /// The fixture is what the `exr` crate writes; `RAYLAB_WRITE_FIXTURES=1` writes it again.
    #[cfg(feature = "crosscheck")]
    #[test]
    fn the_rle_fixture_is_what_the_exr_crate_writes() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(RLE_FIXTURE);
        let bytes = rle_written_by_exr();
        if std::env::var_os("RAYLAB_WRITE_FIXTURES").is_some() {
            std::fs::write(&path, &bytes).unwrap();
        }
        assert_eq!(std::fs::read(&path).unwrap(), bytes);
    }

    /// The RLE fixture's bytes, and the offset of its first chunk.
    fn rle_file() -> (Vec<u8>, usize) {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(RLE_FIXTURE);
        let bytes = std::fs::read(&path).unwrap();
        let mut reader = Bytes {
            bytes: &bytes,
            at: 0,
        };
        read_header(&mut reader).unwrap();
        let first = read_offsets(&mut reader, 1).unwrap()[0] as usize;
        (bytes, first)
    }

    #[test]
    fn every_truncation_is_an_error() {
        let (bytes, _) = rle_file();
        for len in 0..bytes.len() {
            assert!(
                decode(&bytes[..len], &LoadBudget::DEFAULT).is_err(),
                "{len} bytes"
            );
        }
    }

    #[test]
    fn malformed_chunks_are_errors_naming_the_fault() {
        let (bytes, first) = rle_file();
        let refuse = |edit: &dyn Fn(&mut Vec<u8>), expected: &str| {
            let mut bytes = bytes.clone();
            edit(&mut bytes);
            let e = decode(&bytes, &LoadBudget::DEFAULT).err().unwrap();
            assert!(e.contains(expected), "{e:?} does not say {expected:?}");
        };
        let header_end = {
            let mut reader = Bytes {
                bytes: &bytes,
                at: 0,
            };
            read_header(&mut reader).unwrap();
            reader.at
        };
        refuse(
            &|b| b[header_end..header_end + 8].copy_from_slice(&u64::MAX.to_le_bytes()),
            "outside the file",
        );
        refuse(&|b| b[first] = 7, "states y = 7");
        refuse(
            &|b| b[first + 4..first + 8].copy_from_slice(&(-5i32).to_le_bytes()),
            "negative size",
        );
        refuse(
            &|b| b[first + 4..first + 8].copy_from_slice(&1_000_000i32.to_le_bytes()),
            "ends inside chunk 0",
        );
        // A first run of 128 copies overflows the line's bytes; a shorter chunk leaves it short.
        refuse(
            &|b| {
                let size = i32::from_le_bytes(b[first + 4..first + 8].try_into().unwrap());
                b[first + 8..first + 8 + size as usize].fill(127);
            },
            "more than its",
        );
        refuse(
            &|b| b[first + 4..first + 8].copy_from_slice(&2i32.to_le_bytes()),
            "gives",
        );
        refuse(&|b| b[5] |= 0x10, "multi-part");
        refuse(&|b| b[5] |= 0x08, "deep");
    }

    #[test]
    fn a_zip_chunk_of_the_wrong_length_is_an_error() {
        let bytes = encode(&film());
        let mut reader = Bytes {
            bytes: &bytes,
            at: 0,
        };
        read_header(&mut reader).unwrap();
        let offsets = read_offsets(&mut reader, 2).unwrap();
        let (first, second) = (offsets[0] as usize, offsets[1] as usize);
        for (pixel_bytes, expected) in [
            (10, "gives 10 bytes; its pixels take 7104"),
            (8000, "gives more than its 7104 bytes"),
            (0, "not zlib data"),
        ] {
            let data = if pixel_bytes == 0 {
                vec![1, 2, 3]
            } else {
                miniz_oxide::deflate::compress_to_vec_zlib(&vec![7; pixel_bytes], 1)
            };
            let mut edited = bytes[..first + 4].to_vec();
            edited.extend_from_slice(&(data.len() as i32).to_le_bytes());
            edited.extend_from_slice(&data);
            let moved = edited.len() as i64 - second as i64;
            edited.extend_from_slice(&bytes[second..]);
            let table = reader.at - 16;
            edited[table + 8..table + 16]
                .copy_from_slice(&((second as i64 + moved) as u64).to_le_bytes());
            let e = decode(&edited, &LoadBudget::DEFAULT).err().unwrap();
            assert!(e.contains(expected), "{e:?} does not say {expected:?}");
        }
    }

    #[test]
    fn refuses_subsampled_channels_and_other_compressions() {
        let mut bytes = rle_file().0;
        let at = bytes
            .windows(12)
            .position(|w| w == b"compression\0")
            .unwrap();
        // name, type "compression", size 4 bytes, value
        let value = at + 12 + 12 + 4;
        for (code, name) in [(4, "piz"), (5, "pxr24"), (8, "dwaa"), (9, "dwab")] {
            bytes[value] = code;
            let e = decode(&bytes, &LoadBudget::DEFAULT).err().unwrap();
            assert!(e.contains(&format!("uses {name} compression")), "{e}");
            assert!(e.contains("save it with ZIP, RLE or no compression"), "{e}");
        }
        let mut bytes = rle_file().0;
        // Channel "B": name, type, pLinear and reserved, then the x sampling.
        let b = bytes.windows(2).position(|w| w == b"B\0").unwrap();
        bytes[b + 2 + 8] = 2;
        let e = decode(&bytes, &LoadBudget::DEFAULT).err().unwrap();
        assert!(e.contains("subsampled"), "{e}");
    }
}
