use std::path::{Path, PathBuf};

use glam::Vec3;

use super::LabContext;
use crate::stats::{NoiseTolerance, RenderStatistics, compare_noisy, z_score_map};
use raylab_core::Error;
use raylab_core::film::{Film, ToneMap, luminance, read_exr, write_png};

/// Per-pixel tolerance with an outlier budget, for deterministic renders: a pixel is an outlier
/// when a channel differs by more than `abs + rel·|reference|`; the image passes when at most
/// `max_outlier_fraction` of its pixels are outliers (pixels on silhouettes may legitimately
/// differ between two correct intersection routines) and none is NaN or infinite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PixelTolerance {
    /// Absolute tolerance per channel.
    pub abs: f32,
    /// Relative tolerance per channel.
    pub rel: f32,
    /// Fraction of pixels allowed outside the tolerance.
    pub max_outlier_fraction: f32,
}

/// The outcome of comparing a render with its snapshot.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SnapshotReport {
    /// Pixels outside the tolerance.
    pub outliers: usize,
    /// Pixels that are NaN or infinite in the render.
    pub non_finite: usize,
    /// Pixels compared.
    pub pixels: usize,
    /// Largest channel difference.
    pub max_error: f32,
    /// The pixel furthest outside the tolerance (a NaN or infinite one first), `(x, y)`.
    pub worst: Option<(u32, u32)>,
}

impl SnapshotReport {
    /// Whether the render passes under `tol`.
    pub fn passes(&self, tol: &PixelTolerance) -> bool {
        self.non_finite == 0
            && self.outliers as f32 <= tol.max_outlier_fraction * self.pixels as f32
    }
}

fn pixel_error(got: Vec3, expected: Vec3, tol: &PixelTolerance) -> f32 {
    let allowed = Vec3::splat(tol.abs) + tol.rel * expected.abs();
    ((got - expected).abs() / allowed).max_element()
}

/// Compares a render with its reference pixel by pixel.
pub fn compare_snapshot(render: &Film, reference: &Film, tol: &PixelTolerance) -> SnapshotReport {
    let mut report = SnapshotReport {
        outliers: 0,
        non_finite: render.non_finite_count(),
        pixels: reference.pixels.len(),
        max_error: 0.0,
        worst: None,
    };
    let mut worst_error = 1.0f32;
    for (i, (&got, &expected)) in render.pixels.iter().zip(&reference.pixels).enumerate() {
        let diff = (got - expected).abs().max_element();
        let error = pixel_error(got, expected, tol);
        let within = error <= 1.0; // false for NaN
        if !within {
            report.outliers += 1;
            // A NaN error is the worst of all.
            let error = if error.is_nan() { f32::INFINITY } else { error };
            if error > worst_error || report.worst.is_none() {
                worst_error = error;
                let i = i as u32;
                report.worst = Some((i % render.width, i / render.width));
            }
        }
        if diff.is_finite() {
            report.max_error = report.max_error.max(diff);
        }
    }
    report
}

/// `film` with every NaN or infinite pixel magenta, so that a failure image shows where they are.
pub fn mark_non_finite(film: &Film) -> Film {
    let magenta = Vec3::new(1.0, 0.0, 1.0);
    Film {
        pixels: film
            .pixels
            .iter()
            .map(|p| if p.is_finite() { *p } else { magenta })
            .collect(),
        ..film.clone()
    }
}

/// Writes `<name>-student.png`, `<name>-reference.png` and `<name>-difference.png` (a heat
/// map: grey where the pixel is within tolerance, yellow to red by how far outside, magenta
/// for NaN) into `dir`, and returns their paths.
pub fn write_failure_images(
    dir: &Path,
    name: &str,
    render: &Film,
    reference: &Film,
    tol: &PixelTolerance,
) -> Result<Vec<PathBuf>, Error> {
    let tonemap = ToneMap::Clamp { exposure: 1.0 };
    let student = dir.join(format!("{name}-student.png"));
    let expected = dir.join(format!("{name}-reference.png"));
    let difference = dir.join(format!("{name}-difference.png"));
    write_png(&mark_non_finite(render), &student, tonemap)?;
    write_png(reference, &expected, tonemap)?;
    let heat = Film {
        width: reference.width,
        height: reference.height,
        pixels: render
            .pixels
            .iter()
            .zip(&reference.pixels)
            .map(|(&got, &exp)| {
                if !got.is_finite() {
                    return Vec3::new(1.0, 0.0, 1.0);
                }
                let e = pixel_error(got, exp, tol);
                if e <= 1.0 {
                    Vec3::splat(0.25 * luminance(exp.min(Vec3::ONE)))
                } else {
                    // log scale: just outside → yellow, 1000× outside → red.
                    let s = (e.log10() / 3.0).clamp(0.0, 1.0);
                    Vec3::new(1.0, 1.0 - s, 0.0)
                }
            })
            .collect(),
    };
    write_png(&heat, &difference, ToneMap::Clamp { exposure: 1.0 })?;
    Ok(vec![student, expected, difference])
}

impl LabContext {
    /// Compares `render` with the lab's snapshot `name` (`snapshots/<name>.exr`); on failure
    /// writes the student, reference and difference images and names them in the message.
    pub fn check_snapshot(
        &self,
        name: &str,
        render: &Film,
        tol: &PixelTolerance,
    ) -> Result<(), String> {
        let path = self.snapshot_path(&format!("{name}.exr"));
        let reference = raylab_core::film::read_exr(&path)
            .map_err(|e| self.unreadable(&format!("snapshots/{name}.exr"), e))?;
        if (reference.width, reference.height) != (render.width, render.height) {
            return Err(format!(
                "the render is {}×{} but the snapshot {} is {}×{}",
                render.width,
                render.height,
                path.display(),
                reference.width,
                reference.height
            ));
        }
        let report = compare_snapshot(render, &reference, tol);
        if report.passes(tol) {
            return Ok(());
        }
        let images = write_failure_images(&self.failure_dir, name, render, &reference, tol)
            .map(|paths| {
                paths
                    .iter()
                    .map(|p| format!("\n    {}", p.display()))
                    .collect::<String>()
            })
            .unwrap_or_else(|e| format!(" (could not write images: {e})"));
        let look = report
            .worst
            .and_then(|pixel| self.view_command(name, render, pixel))
            .map(|command| {
                format!("\n  see it, and the worst pixel's every ray and call: {command}")
            })
            .unwrap_or_default();
        Err(format!(
            "the rendered image '{name}' differs from the reference: {} of {} pixels outside the tolerance (at most {:.2}% may be), {} NaN/infinite, largest difference {:.4}.\n  images:{images}{look}",
            report.outliers,
            report.pixels,
            100.0 * tol.max_outlier_fraction,
            report.non_finite,
            report.max_error
        ))
    }

    /// The command that opens snapshot `name` (of a built-in scene: its name's first word) in
    /// `raylab view` at the render's size, inspecting `pixel`; `None` for another scene.
    fn view_command(&self, name: &str, render: &Film, (x, y): (u32, u32)) -> Option<String> {
        let scene = raylab_core::scene::BUILTIN_SCENES
            .iter()
            .filter(|scene| name == **scene || name.starts_with(&format!("{scene}-")))
            .max_by_key(|scene| scene.len())?;
        Some(format!(
            "cargo run -p raylab -- view --lab {} --scene {scene} --width {} --height {} --pixel {x},{y}",
            self.lab.number(),
            render.width,
            render.height
        ))
    }
}

impl LabContext {
    /// Writes the statistics of the reference's renders as the Monte Carlo snapshot `name`
    /// (`NAME-mean.exr`, `NAME-variance.exr`; `raylab golden`), and says which files.
    pub fn save_noisy_snapshot(
        &self,
        name: &str,
        reference: &RenderStatistics,
    ) -> Result<Vec<PathBuf>, Error> {
        let mut written = Vec::new();
        for (what, film) in [("mean", &reference.mean), ("variance", &reference.variance)] {
            let path = self.snapshot_path(&format!("{name}-{what}.exr"));
            raylab_core::film::write_exr(film, &path)?;
            written.push(path);
        }
        Ok(written)
    }

    /// The reference statistics of the Monte Carlo snapshot `name` over `renders` renders, as
    /// `raylab golden` stores them: `NAME-mean.exr` and `NAME-variance.exr` (one render's).
    pub fn noisy_reference(&self, name: &str, renders: u32) -> Result<RenderStatistics, String> {
        let read = |what: &str| {
            let file = format!("{name}-{what}.exr");
            read_exr(&self.snapshot_path(&file))
                .map_err(|e| self.unreadable(&format!("snapshots/{file}"), e))
        };
        Ok(RenderStatistics {
            renders,
            mean: read("mean")?,
            variance: read("variance")?,
        })
    }

    /// The per-pixel Z-test of `student`'s renders against the noisy snapshot `name` of
    /// `reference_renders` renders (`NAME-mean.exr`, `NAME-variance.exr`) under `tol`. On
    /// failure it writes `NAME-student.png`, `-reference.png` and `-zscore.png`
    /// ([`z_score_map`]) and says how they differ; `what` names the render ("the soft
    /// shadows of …").
    pub fn check_noisy_snapshot(
        &self,
        name: &str,
        student: &RenderStatistics,
        reference_renders: u32,
        tol: &NoiseTolerance,
        what: &str,
    ) -> Result<(), String> {
        let reference = &self.noisy_reference(name, reference_renders)?;
        let report = compare_noisy(student, reference, tol);
        if report.passes(tol) {
            return Ok(());
        }
        let tonemap = ToneMap::Clamp { exposure: 1.0 };
        let path = |suffix: &str| self.failure_dir.join(format!("{name}-{suffix}.png"));
        let written = write_png(&mark_non_finite(&student.mean), &path("student"), tonemap)
            .and_then(|()| write_png(&reference.mean, &path("reference"), tonemap))
            .and_then(|()| {
                write_png(
                    &z_score_map(student, reference, tol),
                    &path("zscore"),
                    tonemap,
                )
            });
        let images = match written {
            Ok(()) => ["student", "reference", "zscore"]
                .iter()
                .map(|s| format!("\n    {}", path(s).display()))
                .collect::<String>(),
            Err(e) => format!(" (could not write images: {e})"),
        };
        let (z, x, y) = report.worst;
        let look = self
            .view_command(name, &student.mean, (x, y))
            .map(|command| {
                format!("\n  see it, and the worst pixel's every ray and call: {command}")
            })
            .unwrap_or_default();
        Err(format!(
            "{what}: the mean of {} renders differs from the reference beyond its noise: {} of {} pixels are more than {:.1} standard errors from the reference mean (at most {:.1}% may be), {} NaN/infinite; the worst is pixel ({x}, {y}) at {z:.1} standard errors: {} against {} (standard deviation of one render {}). Overall the image is {:.3}× as bright as the reference.\n  images:{images}{look}",
            student.renders,
            report.outliers,
            report.pixels,
            report.z_threshold,
            100.0 * tol.max_outlier_fraction,
            report.non_finite,
            student.mean.get(x, y),
            reference.mean.get(x, y),
            reference.variance.get(x, y).max(Vec3::ZERO).powf(0.5),
            report.brightness,
        ))
    }
}

/// Writes `NAME.png` beside each snapshot `NAME.exr` among `written`: the reference render,
/// tone mapped as a failing image check's `NAME-reference.png` (clamp at exposure 1, sRGB), so
/// that students can look at what their render should be before a check fails. The PNG
/// encoder is deterministic, so the same snapshot gives the same bytes. A snapshot named
/// `…-variance` is a statistic of renders, not an image of the scene (and black at exposure
/// 1): it gets none.
pub fn write_reference_pngs(written: &[PathBuf]) -> Result<Vec<PathBuf>, Error> {
    let snapshots = written.iter().filter(|p| {
        p.extension().is_some_and(|e| e == "exr")
            && p.parent()
                .and_then(Path::file_name)
                .is_some_and(|d| d == "snapshots")
            && !p
                .file_stem()
                .is_some_and(|n| n.to_string_lossy().ends_with("-variance"))
    });
    snapshots
        .map(|exr| {
            let png = exr.with_extension("png");
            write_png(&read_exr(exr)?, &png, ToneMap::Clamp { exposure: 1.0 })?;
            Ok(png)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A failing image of a built-in scene names its worst pixel and the command that opens it
    /// in `raylab view` there; another scene's names no command.
    #[test]
    fn a_failing_image_names_its_worst_pixel_and_the_view_of_it() {
        let dir = std::env::temp_dir().join(format!("raylab-snapshot-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("snapshots")).unwrap();
        let reference = Film::new(4, 3);
        for name in ["cornell-spheres-flat", "textured-nearest"] {
            raylab_core::film::write_exr(&reference, &dir.join(format!("snapshots/{name}.exr")))
                .unwrap();
        }
        let mut ctx = LabContext::new(course::LabId::of(3), &dir, pipeline::Pipeline::waiting(3));
        ctx.failure_dir = dir.join("failures");
        let mut render = Film::new(4, 3);
        render.pixels[4 + 2] = Vec3::splat(0.5);
        render.pixels[2 * 4 + 3] = Vec3::splat(0.9);
        let tol = PixelTolerance {
            abs: 1e-3,
            rel: 0.0,
            max_outlier_fraction: 0.0,
        };
        assert_eq!(
            compare_snapshot(&render, &reference, &tol).worst,
            Some((3, 2))
        );
        render.pixels[0] = Vec3::NAN;
        assert_eq!(
            compare_snapshot(&render, &reference, &tol).worst,
            Some((0, 0))
        );
        let message = ctx
            .check_snapshot("cornell-spheres-flat", &render, &tol)
            .unwrap_err();
        assert!(
            message.ends_with(
                "cargo run -p raylab -- view --lab 3 --scene cornell-spheres --width 4 --height 3 --pixel 0,0"
            ),
            "{message}"
        );
        let message = ctx
            .check_snapshot("textured-nearest", &render, &tol)
            .unwrap_err();
        assert!(!message.contains("raylab -- view"), "{message}");

        // A Monte Carlo snapshot names its worst pixel by its Z-score.
        let mut variance = Film::new(4, 3);
        variance.pixels.fill(Vec3::splat(0.01));
        raylab_core::film::write_exr(&reference, &dir.join("snapshots/cornell-area-mean.exr"))
            .unwrap();
        raylab_core::film::write_exr(&variance, &dir.join("snapshots/cornell-area-variance.exr"))
            .unwrap();
        let mut mean = Film::new(4, 3);
        mean.pixels[2 * 4 + 1] = Vec3::splat(3.0);
        let student = crate::stats::RenderStatistics {
            renders: 16,
            mean,
            variance,
        };
        let tol = crate::stats::NoiseTolerance {
            family_alpha: 1e-6,
            abs: 0.0,
            rel: 0.0,
            max_outlier_fraction: 0.0,
        };
        let message = ctx
            .check_noisy_snapshot("cornell-area", &student, 16, &tol, "the soft shadows")
            .unwrap_err();
        assert!(
            message.ends_with(
                "cargo run -p raylab -- view --lab 3 --scene cornell --width 4 --height 3 --pixel 1,2"
            ),
            "{message}"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
