//! Fuzz targets of the loaders, on stable Rust and without a fuzzing crate: each target mutates
//! the files of its seed corpus with the framework's own deterministic generator
//! ([`raylab_core::sampling::Rng`]) and loads every mutant, under a small [`LoadBudget`].
//!
//! A case fails when its loader panics, takes more than a second, or allocates more than the
//! budget allows (a counting global allocator measures the peak of each case; the targets run
//! one at a time so that the peak is the case's own). The file being loaded is kept on disk,
//! and a failing case is copied to `$TMPDIR/raylab-fuzz/failures/` with its target and number
//! in the name: commit it as a regression file under `tests/hostile-files/`.
//!
//! `cargo test -p framework --test fuzz_loaders` is the smoke run (10 000 cases per
//! target). The long run (docs/scene-format.md, "Hostile files"):
//!
//! ```sh
//! RAYLAB_FUZZ_CASES=1000000 RAYLAB_FUZZ_SEED=1 cargo test -p framework --test fuzz_loaders \
//!     -- --nocapture [TARGET]
//! ```
//!
//! The seeds are the project's scenes (`framework/scenes/`), the files of `tests/fuzz-corpus/`
//! (written by the ignored test `write_seed_corpus`) and the hostile files.

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use raylab_core::Error;
use raylab_core::film::{LoadBudget, read_exr};
use raylab_core::sampling::Rng;
use raylab_core::scene::{Texture, TextureFile, load_obj, load_scene_file};

/// The global allocator, counting the bytes live now and their peak since the last reset.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);
static LARGEST_REQUEST: AtomicUsize = AtomicUsize::new(0);

fn grew(bytes: usize) {
    let now = LIVE.fetch_add(bytes, Ordering::Relaxed) + bytes;
    PEAK.fetch_max(now, Ordering::Relaxed);
}

// SAFETY: every call is forwarded to the system allocator unchanged; only counters are added.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LARGEST_REQUEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        LARGEST_REQUEST.fetch_max(layout.size(), Ordering::Relaxed);
        // SAFETY: forwarded with the caller's layout.
        let p = unsafe { System.alloc_zeroed(layout) };
        if !p.is_null() {
            grew(layout.size());
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: forwarded with the caller's pointer and layout.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LARGEST_REQUEST.fetch_max(new_size, Ordering::Relaxed);
        // SAFETY: forwarded with the caller's pointer, layout and size.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            grew(new_size);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// One target at a time, so that an allocation peak belongs to the case that made it.
static SERIAL: Mutex<()> = Mutex::new(());

/// The budget the cases load under: small, so that a case over it is found quickly.
const BUDGET: LoadBudget = LoadBudget {
    max_file_bytes: 4 << 20,
    max_pixels: 1 << 20,
    max_decode_bytes: 64 << 20,
};

/// What a case may allocate beyond the decode budget: the file itself and the loaders' own
/// structures, proportional to it (normalized OBJ text, tobj's arrays, the BVH), plus a
/// constant for the libraries' fixed tables.
fn allowance(input_bytes: usize) -> usize {
    BUDGET.max_decode_bytes as usize + 256 * input_bytes + (16 << 20)
}

/// The longest a case may take.
const CASE_TIME: Duration = Duration::from_secs(1);

fn cases(smoke: u64) -> u64 {
    std::env::var("RAYLAB_FUZZ_CASES")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(smoke)
}

fn run_seed() -> u64 {
    std::env::var("RAYLAB_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(0)
}

fn manifest(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(rel)
}

/// The files of `dir` whose names end in one of `exts` (sorted, for a stable corpus).
fn files(dir: &Path, exts: &[&str]) -> Vec<Vec<u8>> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap_or_else(|e| panic!("{}: {e}", dir.display()))
        .map(|e| e.unwrap().path())
        .filter(|p| exts.iter().any(|x| p.to_string_lossy().ends_with(x)))
        .collect();
    paths.sort();
    paths.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

/// A scratch directory of one target.
fn scratch(target: &str) -> PathBuf {
    let dir = std::env::temp_dir()
        .join("raylab-fuzz")
        .join(format!("{target}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a case's file as a new one: the old one is removed first, since a file truncated and
/// written again is flushed to the disk when closed on ext4 (its `auto_da_alloc`), which made
/// every case wait for the disk.
fn write_case(path: &Path, data: &[u8]) {
    let _ = std::fs::remove_file(path);
    std::fs::write(path, data).unwrap();
}

// ---- mutation ----------------------------------------------------------------------------

const INTERESTING_U32: [u32; 10] = [
    0,
    1,
    0x7f,
    0xff,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x0001_0000,
    0x4000_0000,
];

fn below(rng: &mut Rng, n: usize) -> usize {
    rng.next_below(n.clamp(1, u32::MAX as usize) as u32) as usize
}

/// Applies one to four random edits to `data`: bit flips, random or boundary bytes and words,
/// inserted, deleted or duplicated ranges, a splice from another seed, a dictionary token, a
/// truncation.
fn mutate(data: &mut Vec<u8>, rng: &mut Rng, seeds: &[Vec<u8>], dictionary: &[&str]) {
    for _ in 0..1 + below(rng, 4) {
        let len = data.len();
        match rng.next_below(10) {
            0 if len > 0 => {
                let i = below(rng, len);
                data[i] ^= 1 << rng.next_below(8);
            }
            1 if len > 0 => {
                let i = below(rng, len);
                data[i] = rng.next_u32() as u8;
            }
            2 if len >= 4 => {
                let i = below(rng, len - 3);
                let v = INTERESTING_U32[below(rng, INTERESTING_U32.len())];
                let bytes = if rng.next_below(2) == 0 {
                    v.to_le_bytes()
                } else {
                    v.to_be_bytes()
                };
                data[i..i + 4].copy_from_slice(&bytes);
            }
            3 => {
                let i = below(rng, len + 1);
                let n = 1 + below(rng, 16);
                let bytes: Vec<u8> = (0..n).map(|_| rng.next_u32() as u8).collect();
                data.splice(i..i, bytes);
            }
            4 if len > 0 => {
                let i = below(rng, len);
                let n = 1 + below(rng, (len - i).min(64));
                data.drain(i..i + n);
            }
            5 if len > 0 => {
                let i = below(rng, len);
                let n = 1 + below(rng, (len - i).min(256));
                let copy = data[i..i + n].to_vec();
                let at = below(rng, len + 1);
                data.splice(at..at, copy);
            }
            6 if !seeds.is_empty() => {
                let other = &seeds[below(rng, seeds.len())];
                if !other.is_empty() {
                    let i = below(rng, other.len());
                    let n = 1 + below(rng, (other.len() - i).min(512));
                    let at = below(rng, len + 1);
                    let end = (at + n).min(len);
                    data.splice(at..end, other[i..i + n].iter().copied());
                }
            }
            7 | 8 if !dictionary.is_empty() => {
                let token = dictionary[below(rng, dictionary.len())];
                let at = below(rng, len + 1);
                data.splice(at..at, token.bytes());
            }
            9 if len > 1 => data.truncate(below(rng, len)),
            _ => data.push(rng.next_u32() as u8),
        }
    }
}

/// The CRC-32 of PNG chunks (ISO 3309).
fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = (crc >> 1) ^ (0xEDB8_8320 & (crc & 1).wrapping_neg());
        }
    }
    !crc
}

/// Recomputes the CRC of every whole chunk of a PNG, so that mutations reach the decoder
/// beyond the checksum test.
fn fix_png_crcs(data: &mut [u8]) {
    let mut at = 8;
    while at + 12 <= data.len() {
        let len = u32::from_be_bytes(data[at..at + 4].try_into().unwrap()) as usize;
        let Some(end) = (at + 8).checked_add(len) else {
            return;
        };
        if end + 4 > data.len() {
            return;
        }
        let crc = crc32(&data[at + 4..end]);
        data[end..end + 4].copy_from_slice(&crc.to_be_bytes());
        at = end + 4;
    }
}

// ---- the driver --------------------------------------------------------------------------

/// The figures of one target's run.
#[derive(Default)]
struct Figures {
    cases: u64,
    loaded: u64,
    slowest: Duration,
    peak: usize,
    elapsed: Duration,
}

/// Runs `count` cases of `target`: `make` writes the case's files (mutated from the seeds)
/// and returns the file to keep if it fails; `load` loads it.
fn drive(
    target: &str,
    count: u64,
    mut make: impl FnMut(&mut Rng) -> (PathBuf, usize),
    load: impl Fn() -> Result<(), Error>,
) -> Figures {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    BUDGET.install();
    let stream = target
        .bytes()
        .fold(0u64, |h, b| h.wrapping_mul(31) ^ u64::from(b));
    let mut rng = Rng::new(run_seed(), stream);
    let mut figures = Figures::default();
    let start = Instant::now();
    for case in 0..count {
        let (kept, input_bytes) = make(&mut rng);
        let fail = |why: String| -> ! {
            let dir = std::env::temp_dir().join("raylab-fuzz/failures");
            std::fs::create_dir_all(&dir).unwrap();
            let name = kept.file_name().unwrap().to_string_lossy().into_owned();
            let copy = dir.join(format!("{target}-{case}-{name}"));
            std::fs::copy(&kept, &copy).unwrap();
            panic!(
                "fuzz target {target}, case {case} (RAYLAB_FUZZ_SEED={}): {why}; the input is {}",
                run_seed(),
                copy.display()
            );
        };
        let base = LIVE.load(Ordering::Relaxed);
        PEAK.store(base, Ordering::Relaxed);
        LARGEST_REQUEST.store(0, Ordering::Relaxed);
        let case_start = Instant::now();
        let result = raylab_core::catch_quietly("loader", &load);
        let took = case_start.elapsed();
        let peak = PEAK.load(Ordering::Relaxed).saturating_sub(base);
        let largest = LARGEST_REQUEST.load(Ordering::Relaxed);
        match result {
            Err(panic) => fail(format!("the loader panicked: {}", panic.message)),
            Ok(Ok(())) => figures.loaded += 1,
            Ok(Err(e)) => {
                let message = e.to_string();
                if message.contains('\n') || message.is_empty() {
                    fail(format!("the error is not one line: {message:?}"));
                }
            }
        }
        if took > CASE_TIME {
            fail(format!("the case took {took:?}"));
        }
        let allowed = allowance(input_bytes);
        if peak > allowed || largest > allowed {
            fail(format!(
                "the case allocated {peak} bytes at its peak (largest single request {largest}); the budget allows {allowed}"
            ));
        }
        figures.cases += 1;
        figures.slowest = figures.slowest.max(took);
        figures.peak = figures.peak.max(peak);
    }
    figures.elapsed = start.elapsed();
    println!(
        "fuzz {target}: {} cases ({} loaded, the rest refused) in {:.1?}; slowest {:.1?}, peak {} KiB",
        figures.cases,
        figures.loaded,
        figures.elapsed,
        figures.slowest,
        figures.peak >> 10
    );
    figures
}

/// An image target: the seeds of `tests/fuzz-corpus/<dir>` and the hostile files of the same
/// kind, mutated and written to one file that `load` reads.
fn image_target(
    target: &str,
    dir: &str,
    ext: &str,
    smoke: u64,
    load: fn(&Path) -> Result<(), Error>,
) {
    let mut seeds = files(&manifest("tests/fuzz-corpus").join(dir), &[ext]);
    seeds.extend(files(&manifest("tests/hostile-files"), &[ext]));
    assert!(!seeds.is_empty(), "no seeds for {target}");
    let file = scratch(target).join(format!("case.{ext}"));
    let is_png = ext == "png";
    let figures = drive(
        target,
        cases(smoke),
        |rng| {
            let mut data = seeds[below(rng, seeds.len())].clone();
            mutate(&mut data, rng, &seeds, &[]);
            if is_png && rng.next_below(8) != 0 {
                fix_png_crcs(&mut data);
            }
            write_case(&file, &data);
            (file.clone(), data.len())
        },
        || load(&file),
    );
    assert_eq!(figures.cases, cases(smoke));
}

fn load_texture(path: &Path) -> Result<(), Error> {
    Texture::load(path).map(drop)
}

#[test]
fn fuzz_png_textures() {
    image_target("png", "png", "png", 10_000, load_texture);
}

#[test]
fn fuzz_jpeg_textures() {
    image_target("jpeg", "jpeg", "jpg", 10_000, load_texture);
}

#[test]
fn fuzz_exr_textures() {
    image_target("exr", "exr", "exr", 10_000, load_texture);
}

#[test]
fn fuzz_hdr_textures() {
    image_target("hdr", "hdr", "hdr", 10_000, load_texture);
}

#[test]
fn fuzz_exr_snapshot_reader() {
    image_target("exr-snapshot", "exr", "exr", 10_000, |p| {
        read_exr(p).map(drop)
    });
}

const OBJ_WORDS: &[&str] = &[
    "\nv ",
    "\nvt ",
    "\nvn ",
    "\nf ",
    "\nl ",
    "\no ",
    "\ng ",
    "\nusemtl ",
    "\nmtllib ",
    "\nnewmtl ",
    "\nKd ",
    "\nKe ",
    "\nNi ",
    "\nillum ",
    "\nmap_Kd ",
    " -s ",
    " -o ",
    " -clamp on ",
    " -bm ",
    " -imfchan r ",
    "texture.png",
    "cornell.mtl",
    "/dev/zero",
    " -1",
    " 0",
    " 1e38",
    " nan",
    " inf",
    "/",
    "//",
    " white",
    "#",
    "\\\n",
    "\r\n",
];

#[test]
fn fuzz_obj_and_mtl() {
    let corpus = manifest("tests/fuzz-corpus/obj");
    let mut objs = files(&manifest("scenes"), &[".obj"]);
    objs.extend(files(&corpus, &[".obj"]));
    let mut mtls = files(&manifest("scenes"), &[".mtl"]);
    mtls.extend(files(&corpus, &[".mtl"]));
    let dir = scratch("obj");
    std::fs::copy(
        manifest("tests/fuzz-corpus/png/rgb8.png"),
        dir.join("texture.png"),
    )
    .unwrap();
    let (obj_file, mtl_file) = (dir.join("case.obj"), dir.join("cornell.mtl"));
    let all: Vec<Vec<u8>> = objs.iter().chain(&mtls).cloned().collect();
    drive(
        "obj",
        cases(10_000),
        |rng| {
            let mut obj = objs[below(rng, objs.len())].clone();
            let mut mtl = mtls[below(rng, mtls.len())].clone();
            match rng.next_below(3) {
                0 => mutate(&mut obj, rng, &all, OBJ_WORDS),
                1 => mutate(&mut mtl, rng, &all, OBJ_WORDS),
                _ => {
                    mutate(&mut obj, rng, &all, OBJ_WORDS);
                    mutate(&mut mtl, rng, &all, OBJ_WORDS);
                }
            }
            write_case(&obj_file, &obj);
            write_case(&mtl_file, &mtl);
            // A failure keeps the OBJ; its MTL is beside it in the scratch directory.
            (obj_file.clone(), obj.len() + mtl.len())
        },
        || load_obj(&obj_file).map(drop),
    );
}

const SCENE_WORDS: &[&str] = &[
    "\n[camera]\n",
    "\n[[meshes]]\n",
    "\n[[spheres]]\n",
    "\n[[planes]]\n",
    "\n[[lights]]\n",
    "\n[materials.x]\n",
    "file = \"cornell_room.obj\"\n",
    "file = \"/dev/zero\"\n",
    "file = \"torus.obj\"\n",
    "texture = \"x.png\"\n",
    "type = \"point\"\n",
    "material = \"x\"\n",
    "scale = ",
    "radius = ",
    "illum = ",
    "[0, 0, 0]",
    "[1e38, -1e38, 0]",
    "nan",
    "inf",
    "-0",
    "\"",
    "'",
    "=",
    "[",
    "]",
    "{",
    "}",
    ",",
    "\n",
];

#[test]
fn fuzz_scene_files() {
    let scenes = manifest("scenes");
    let mut seeds = files(&scenes, &[".toml"]);
    seeds.extend(files(&manifest("tests/fuzz-corpus/scene"), &[".toml"]));
    // The case is written beside the scenes' meshes, which it names relative to itself.
    let file = scratch("scene").join("case.toml");
    let meshes: Vec<PathBuf> = std::fs::read_dir(&scenes)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "obj" || x == "mtl"))
        .collect();
    for m in &meshes {
        std::fs::copy(m, file.with_file_name(m.file_name().unwrap())).unwrap();
    }
    std::fs::copy(
        manifest("tests/fuzz-corpus/png/rgb8.png"),
        file.with_file_name("texture.png"),
    )
    .unwrap();
    drive(
        "scene",
        cases(10_000),
        |rng| {
            let mut text = seeds[below(rng, seeds.len())].clone();
            mutate(&mut text, rng, &seeds, SCENE_WORDS);
            write_case(&file, &text);
            (file.clone(), text.len() + (256 << 10))
        },
        || load_scene_file(&file).map(drop),
    );
}

/// Writes the image seeds of `tests/fuzz-corpus/` with the encoders the framework uses (and
/// the `exr` crate for the compressions `image` does not write). Run it with
/// `cargo test -p raylab-core --features crosscheck --test fuzz_loaders -- --ignored
/// write_seed_corpus`.
#[cfg(feature = "crosscheck")]
#[test]
#[ignore = "writes the committed seed corpus"]
fn write_seed_corpus() {
    use exr::prelude::*;
    let corpus = manifest("tests/fuzz-corpus");
    for dir in ["png", "jpeg", "exr", "hdr"] {
        std::fs::create_dir_all(corpus.join(dir)).unwrap();
    }
    let rgb = image::RgbImage::from_fn(5, 3, |x, y| image::Rgb([40 * x as u8, 80 * y as u8, 200]));
    rgb.save(corpus.join("png/rgb8.png")).unwrap();
    image::DynamicImage::ImageRgb8(rgb.clone())
        .to_rgba16()
        .save(corpus.join("png/rgba16.png"))
        .unwrap();
    image::DynamicImage::ImageRgb8(rgb.clone())
        .to_luma8()
        .save(corpus.join("png/grey8.png"))
        .unwrap();
    rgb.save(corpus.join("jpeg/rgb.jpg")).unwrap();
    image::DynamicImage::ImageRgb8(rgb.clone())
        .to_luma8()
        .save(corpus.join("jpeg/grey.jpg"))
        .unwrap();
    let float = image::DynamicImage::ImageRgb8(rgb).to_rgb32f();
    write_rgb_file(corpus.join("exr/image-rgb32f.exr"), 5, 3, |x, y| {
        let p = float.get_pixel(x as u32, y as u32).0;
        (p[0], p[1], p[2])
    })
    .unwrap();
    float.save(corpus.join("hdr/rgb.hdr")).unwrap();
    let pixels = |p: Vec2<usize>| (p.0 as f32 * 0.25, p.1 as f32 * 0.5, 1.5f32);
    for (name, compression) in [
        ("rle", Compression::RLE),
        ("zip1", Compression::ZIP1),
        ("zip16", Compression::ZIP16),
        ("piz", Compression::PIZ),
    ] {
        let layer = Layer::new(
            (7, 5),
            LayerAttributes::named("rgb"),
            Encoding {
                compression,
                ..Encoding::default()
            },
            SpecificChannels::rgb(pixels),
        );
        Image::from_layer(layer)
            .write()
            .to_file(corpus.join(format!("exr/{name}.exr")))
            .unwrap();
    }
    let tiled = Layer::new(
        (9, 6),
        LayerAttributes::named("rgb"),
        Encoding {
            compression: Compression::ZIP16,
            blocks: Blocks::Tiles(Vec2(4, 4)),
            line_order: LineOrder::Increasing,
        },
        SpecificChannels::rgb(pixels),
    );
    Image::from_layer(tiled)
        .write()
        .to_file(corpus.join("exr/tiled-zip16.exr"))
        .unwrap();
}
