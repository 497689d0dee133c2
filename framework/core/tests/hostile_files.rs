//! Hostile files (`tests/hostile-files/`, written by `make_hostile_files.py` there): each must
//! end in an error that names the file and says what is wrong, within a second, without a
//! panic and without the decoder allocating what the file asks for.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use raylab_core::Error;
use raylab_core::film::read_exr;
use raylab_core::scene::{Texture, TextureFile, load_obj, load_scene_file};

fn hostile(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/hostile-files")
        .join(name)
}

/// Runs `load`, which must fail within a second; returns its message.
fn refused<T: std::fmt::Debug>(load: impl FnOnce() -> Result<T, Error>) -> String {
    let start = Instant::now();
    let result = load();
    let elapsed = start.elapsed();
    assert!(elapsed < Duration::from_secs(1), "took {elapsed:?}");
    match result {
        Err(e) => e.to_string(),
        Ok(v) => panic!("expected an error, got {v:?}"),
    }
}

fn assert_mentions(message: &str, parts: &[&str]) {
    for part in parts {
        assert!(
            message.contains(part),
            "{message:?} does not mention {part:?}"
        );
    }
    assert!(!message.contains('\n'), "{message:?} is not one line");
}

#[test]
fn png_with_a_short_palette_is_an_error_not_a_panic() {
    let path = hostile("palette-plte-not-multiple-of-3.png");
    let message = refused(|| Texture::load(&path));
    assert_mentions(
        &message,
        &[
            "palette-plte-not-multiple-of-3.png: cannot read the texture: ",
            "not a valid PNG file",
        ],
    );
}

#[test]
fn png_claiming_a_huge_size_is_refused_from_its_header() {
    let path = hostile("png-30000x30000.png");
    let message = refused(|| Texture::load(&path));
    assert_mentions(
        &message,
        &["png-30000x30000.png", "30000 × 30000", "load budget"],
    );
}

#[test]
fn exr_with_a_compression_whose_decoder_is_unsafe_is_refused_from_its_header() {
    for (file, compression) in [
        ("exr-dwaa.exr", "dwaa"),
        ("exr-piz.exr", "piz"),
        ("exr-b44.exr", "b44"),
        ("exr-pxr24.exr", "pxr24"),
    ] {
        let path = hostile(file);
        for message in [
            refused(|| Texture::load(&path)),
            refused(|| read_exr(&path)),
        ] {
            assert_mentions(&message, &[file, compression, "does not read"]);
        }
    }
}

#[test]
fn exr_with_a_huge_window_is_refused_from_its_header() {
    let path = hostile("exr-zip-huge-window.exr");
    for message in [
        refused(|| Texture::load(&path)),
        refused(|| read_exr(&path)),
    ] {
        assert_mentions(
            &message,
            &["exr-zip-huge-window.exr", "200000 × 200000", "load budget"],
        );
    }
}

#[test]
fn binary_obj_is_refused_as_not_text() {
    let path = hostile("not-text.obj");
    let message = refused(|| load_obj(&path));
    assert_mentions(&message, &["not-text.obj", "not a text file", "line 3"]);
}

#[test]
fn device_as_mtllib_or_mesh_is_refused_before_reading() {
    let path = hostile("mtllib-dev-zero.obj");
    let message = refused(|| load_obj(&path));
    assert_mentions(
        &message,
        &[
            "mtllib-dev-zero.obj:1",
            "/dev/zero",
            "not a regular file",
            "character device",
        ],
    );
    let path = hostile("mesh-dev-zero.toml");
    let message = refused(|| load_scene_file(&path));
    assert_mentions(
        &message,
        &["mesh-dev-zero.toml", "/dev/zero", "not a regular file"],
    );
    let message = refused(|| Texture::load(Path::new("/dev/zero")));
    assert_mentions(&message, &["/dev/zero", "not a regular file"]);
}

#[cfg(unix)]
#[test]
fn fifo_as_mesh_is_refused_without_blocking() {
    let dir = std::env::temp_dir().join(format!("raylab-hostile-fifo-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("mesh.obj");
    let c_path = std::ffi::CString::new(fifo.to_str().unwrap()).unwrap();
    // SAFETY: a valid NUL-terminated path; mkfifo does not keep the pointer.
    assert_eq!(unsafe { libc::mkfifo(c_path.as_ptr(), 0o600) }, 0);
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfocal_distance = 1.0\n\
         [[meshes]]\nfile = \"mesh.obj\"\n",
    )
    .unwrap();
    let message = refused(|| load_scene_file(&scene));
    assert_mentions(
        &message,
        &["scene.toml", "mesh.obj", "not a regular file but a FIFO"],
    );
    let message = refused(|| load_obj(&fifo));
    assert_mentions(&message, &["mesh.obj", "FIFO"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn file_over_the_size_budget_is_refused_before_reading() {
    let budget = raylab_core::film::LoadBudget {
        max_file_bytes: 16,
        ..raylab_core::film::LoadBudget::DEFAULT
    };
    let path = hostile("mesh-dev-zero.toml");
    let e = raylab_core::film::read_bounded(&path, &budget).unwrap_err();
    assert!(e.to_string().contains("at most 16 bytes"), "{e}");
    assert!(
        raylab_core::film::read_bounded(&path, &raylab_core::film::LoadBudget::DEFAULT).is_ok()
    );
}

/// Found by the fuzz targets: errors whose decoder's or parser's text ran over several lines.
#[test]
fn fuzz_findings_are_one_line_errors() {
    let path = hostile("fuzz-jpeg-truncated.jpg");
    let message = refused(|| Texture::load(&path));
    assert_mentions(
        &message,
        &[
            "fuzz-jpeg-truncated.jpg: cannot read the texture: ",
            "not a valid JPEG file: the file ends before its image data do (it is cut short)",
        ],
    );
    let path = hostile("fuzz-toml-syntax.toml");
    let message = refused(|| load_scene_file(&path));
    assert_mentions(
        &message,
        &[
            "fuzz-toml-syntax.toml: line 6, column 24: ",
            "missing comma",
        ],
    );
    let path = hostile("fuzz-material-name-with-newline.toml");
    let message = refused(|| load_scene_file(&path));
    assert_mentions(
        &message,
        &["line 40, column 1: spheres[1]: unknown material 'glass\\n'"],
    );
}
