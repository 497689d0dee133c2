//! A render as data: what `raylab render` asks for, done on a given pipeline. The command line
//! does it on the reference pipeline; a lab's program does it on the pipeline with the
//! student's code in the lab's slots (`grading::task`), so the command line links no lab's code.

use std::path::{Path, PathBuf};
use std::time::Instant;

use glam::Vec3;
use raylab_core::Error;
use raylab_core::film::{ToneMap, write_exr, write_png};
use raylab_core::math::Aabb;
use raylab_core::render::{PartialRender, PixelFailures, RenderSettings};
use raylab_core::scene::{
    BUILTIN_SCENES, CameraSetup, Light, ObjData, PointLight, Scene, SceneDescription,
    builtin_scene, load_obj, load_scene_file,
};
use serde::{Deserialize, Serialize};

use crate::path::with_sky;
use crate::photon::{PhotonSettings, with_caustics};
use crate::render::{PASS_SAMPLES, render_partial, render_progressive};

/// A progressive render writes the image so far after every this many passes.
pub const PREVIEW_EVERY: u32 = 8;
use crate::{Integrator, Pipeline, View};

/// One render: the scene, the image, and the pipeline's settings.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct RenderJob {
    /// A built-in scene's name, a scene file (.toml) or an OBJ file.
    pub scene: String,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// Samples per pixel.
    pub spp: u32,
    /// Pixel subdivision (lab 7 on).
    pub subdivisions: u32,
    /// Seed of the render's and the photons' random numbers.
    pub seed: u64,
    /// The image file, .png or .exr; its directory exists.
    pub output: PathBuf,
    /// The tone map of a PNG (`clamp[:EXPOSURE]`, `reinhard[:KEY[:WHITE]]`).
    pub tonemap: String,
    /// The lab the render is of, for its closing line: the pipeline it runs on holds that
    /// lab's code and the course's before it.
    pub lab: u32,
    /// What the image shows.
    pub view: View,
    /// `n × n` area-light samples per shading point.
    pub light_samples: u32,
    /// The caustic photon map (lab 8 on); its seed is the render's.
    pub photons: PhotonSettings,
    /// Whether the photon radius follows the scene's size ([`PhotonSettings::radius_for`])
    /// instead of `photons.max_radius` (no `--photon-radius` given).
    #[serde(default)]
    pub photon_radius_from_scene: bool,
    /// Whose code renders, in words for the closing line ("Reference", "Student").
    pub whose: String,
    /// Lab 12 on: stop the progressive render once every pixel's relative error is below this.
    #[serde(default)]
    pub target_error: Option<f32>,
}

impl RenderJob {
    /// The render settings of the job.
    pub fn settings(&self) -> RenderSettings {
        RenderSettings {
            width: self.width,
            height: self.height,
            samples_per_pixel: self.spp,
            pixel_subdivisions: self.subdivisions,
            seed: self.seed,
            progress: true,
        }
    }

    /// Whether the image is an EXR (linear radiance) rather than a PNG.
    pub fn exr(&self) -> bool {
        self.output
            .extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("exr"))
    }

    /// Checks what can be checked before anything is loaded: the tone map, the settings, the
    /// light samples and the photons.
    pub fn validate(&self) -> Result<(), Error> {
        self.tonemap.parse::<ToneMap>()?;
        self.settings().validate()?;
        if self.light_samples == 0 || self.light_samples > 64 {
            return Err(Error::Invalid {
                what: format!("--light-samples {}", self.light_samples),
                reason: "expected a whole number from 1 to 64".into(),
            });
        }
        self.photons.validate()?;
        if let Some(e) = self.target_error
            && !(e > 0.0 && e.is_finite())
        {
            return Err(Error::Invalid {
                what: format!("--target-error {e}"),
                reason: "expected a positive number (0.05 stops at 5 % relative error)".into(),
            });
        }
        Ok(())
    }

    /// Whether the render through `pipeline` is progressive: a path-traced image of at least
    /// two passes of [`PASS_SAMPLES`] samples per pixel.
    pub fn progressive(&self, pipeline: &Pipeline) -> bool {
        pipeline.integrator() == Integrator::Path
            && self.view == View::Shaded
            && self.spp >= 2 * PASS_SAMPLES
    }

    /// Where a progressive render writes the variance of each pixel's mean: beside the
    /// image, `NAME-variance.exr`.
    pub fn variance_output(&self) -> PathBuf {
        let stem = self
            .output
            .file_stem()
            .map_or_else(|| "render".into(), |s| s.to_string_lossy().into_owned());
        self.output.with_file_name(format!("{stem}-variance.exr"))
    }

    /// Writes `film` (marked as `rendered` marks its pixels) as the job's image.
    fn write_image(&self, rendered: &PartialRender, tonemap: ToneMap) -> Result<(), Error> {
        if self.exr() {
            write_exr(&rendered.film, &self.output)
        } else {
            write_png(&rendered.display(tonemap), &self.output, ToneMap::default())
        }
    }

    /// Renders the scene through `pipeline` (whose slots say whose code runs) and writes the
    /// image; says on standard error what it did and what went wrong in which pixels, and
    /// prints the image's path on standard output.
    pub fn run(&self, mut pipeline: Pipeline) -> Result<(), Error> {
        self.validate()?;
        let tonemap: ToneMap = self.tonemap.parse()?;
        let scene = load_scene(&self.scene)?;
        if let Some(warning) = empty_scene_warning(&scene, &self.scene) {
            eprintln!("{warning}");
        }
        pipeline.area_light_samples = self.light_samples;
        pipeline.view = self.view;
        pipeline.photons = PhotonSettings {
            seed: self.seed,
            max_radius: if self.photon_radius_from_scene {
                PhotonSettings::radius_for(&scene)
            } else {
                self.photons.max_radius
            },
            ..self.photons
        };
        let start = Instant::now();
        let pipeline = prepare(pipeline, &scene, |line| eprintln!("{line}"));
        let exr = self.exr();
        let (rendered, passes) = if self.progressive(&pipeline) {
            // The image so far every few passes, to look at while it converges.
            let progressive = render_progressive(
                &scene,
                &pipeline,
                &self.settings(),
                self.target_error,
                |pass, mean| {
                    if pass % PREVIEW_EVERY == 0 {
                        let preview = PartialRender {
                            film: mean.clone(),
                            panicked: vec![false; mean.pixels.len()],
                            failures: PixelFailures::default(),
                        };
                        self.write_image(&preview, tonemap)?;
                    }
                    Ok(())
                },
            )?;
            write_exr(&progressive.variance, &self.variance_output())?;
            let stopped = match self.target_error {
                Some(target) if progressive.worst_error < target => format!(
                    ", stopped at a relative error of {:.3} < {target}",
                    progressive.worst_error
                ),
                Some(target) => format!(
                    " (the worst pixel's relative error {:.3} is still above {target}: raise --spp)",
                    progressive.worst_error
                ),
                None => String::new(),
            };
            (
                progressive.rendered,
                format!(
                    ", {} passes of {PASS_SAMPLES} samples{stopped}; the variance of each pixel's mean in {}",
                    progressive.passes,
                    self.variance_output().display()
                ),
            )
        } else {
            (
                render_partial(&scene, &pipeline, &self.settings())?,
                String::new(),
            )
        };
        let seconds = start.elapsed().as_secs_f64();
        self.write_image(&rendered, tonemap)?;
        eprintln!(
            "rendered '{}' ({}×{}, {} spp, lab {}, {} pipeline) in {seconds:.2} s{passes}",
            scene.name, self.width, self.height, self.spp, self.lab, self.whose
        );
        for line in warnings(&rendered, exr) {
            eprintln!("{line}");
        }
        println!("{}", self.output.display());
        Ok(())
    }
}

/// `pipeline` prepared for rendering `scene`, whoever renders (a render, a report, the view, a
/// check): the caustic photon map traced for the photon-mapped integrator, the sky's
/// distribution built for the path tracer. What goes wrong is said through `say` and leaves
/// the pipeline without it (no caustics; the sky found by BSDF samples only); so are the
/// photons traced.
pub fn prepare(pipeline: Pipeline, scene: &Scene, mut say: impl FnMut(String)) -> Pipeline {
    let mut pipeline = pipeline;
    if pipeline.integrator() == Integrator::PhotonMapped {
        let start = Instant::now();
        match with_caustics(&pipeline, scene) {
            Ok(traced) => {
                let stored = traced.caustics.as_ref().map_or(0, |m| m.len());
                say(format!(
                    "traced {} photons ({stored} stored in the caustic map, gathered within {:.3}) in {:.2} s",
                    traced.photons.emitted,
                    traced.photons.max_radius,
                    start.elapsed().as_secs_f64()
                ));
                pipeline = traced;
            }
            Err(e) => say(format!("warning: no caustics: {e}")),
        }
    }
    for line in unmodelled_materials(&pipeline, scene) {
        say(line);
    }
    if pipeline.integrator() == Integrator::Path {
        match with_sky(&pipeline, scene) {
            Ok(prepared) => pipeline = prepared,
            Err(e) => say(format!(
                "warning: the sky is found by BSDF samples only: {e}"
            )),
        }
    }
    pipeline
}

/// A warning for each material of `scene` whose surface model (`model`) the render through
/// `pipeline` does not draw: no lab of the pipeline registers it, or the integrator is not the
/// path tracer, which alone draws surface models.
fn unmodelled_materials(pipeline: &Pipeline, scene: &Scene) -> Vec<String> {
    let path = pipeline.integrator() == Integrator::Path;
    let registered: Vec<&str> = pipeline.parts().surface_names().collect();
    let mut lines = Vec::new();
    for material in &scene.materials {
        let Some(name) = material.model.as_deref() else {
            continue;
        };
        let why = if !path {
            "only the path tracer draws surface models".to_string()
        } else if !registered.contains(&name) {
            match registered.as_slice() {
                [] => "no lab of this pipeline registers a surface model".to_string(),
                names => format!("this pipeline's surface models are {}", names.join(", ")),
            }
        } else {
            continue;
        };
        lines.push(format!(
            "warning: material '{}' names the surface model '{name}', which this render does not draw ({why}): it is drawn by its `illum`",
            material.name
        ));
    }
    lines
}

/// A lab's report: where and how its figures are made (`raylab report`).
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ReportJob {
    /// The directory of the lab's figures (made when missing).
    pub dir: PathBuf,
    /// Smaller images and fewer samples.
    pub quick: bool,
    /// Whose code renders the lab's slots, in words ("Reference", "Student").
    pub whose: String,
    /// The student's written answers (`labs/labNN/answers.md`), shown after the figures; the
    /// report only reads the file.
    #[serde(default)]
    pub answers: Option<PathBuf>,
}

/// Loads a scene by built-in name or path.
pub fn load_scene(spec: &str) -> Result<Scene, Error> {
    if BUILTIN_SCENES.contains(&spec) {
        return builtin_scene(spec);
    }
    let path = Path::new(spec);
    match path.extension().and_then(|e| e.to_str()) {
        Some("toml") => load_scene_file(path),
        Some("obj") => {
            let obj = load_obj(path)?;
            if obj.mesh.faces.is_empty() {
                return Err(Error::Invalid {
                    what: format!("OBJ file '{spec}'"),
                    reason: "it holds no faces (`f` statements), so there is nothing to render; is the file cut short?".into(),
                });
            }
            eprintln!(
                "note: '{spec}' has no camera or lights of its own: the camera frames its bounds from the front and a point light sits at the eye; for your own, write a scene file with a [[meshes]] entry (docs/scene-format.md)"
            );
            framed_scene(spec, obj, true)
        }
        _ => Err(Error::Invalid {
            what: format!("scene '{spec}'"),
            reason: format!(
                "expected a built-in scene ({}), a scene file ending in .toml or an OBJ file ending in .obj",
                BUILTIN_SCENES.join(", ")
            ),
        }),
    }
}

/// A scene of one OBJ's triangles and materials with a camera looking at the bounding box from
/// the front (in front of +z, a little above) and, with `lit`, a point light at the eye bright
/// enough that a surface facing it at the box's centre reflects about its albedo.
pub fn framed_scene(name: &str, obj: ObjData, lit: bool) -> Result<Scene, Error> {
    let bounds = Aabb::from_points(obj.mesh.positions.iter().copied());
    let centre = bounds.centroid();
    let extent = bounds.diagonal().max_element();
    let eye = centre + Vec3::new(0.0, 0.2, 1.6) * extent;
    let distance_squared = eye.distance_squared(centre);
    let lights = if lit {
        vec![Light::Point(PointLight {
            position: eye,
            intensity: Vec3::splat(std::f32::consts::PI * distance_squared),
        })]
    } else {
        Vec::new()
    };
    Scene::new(SceneDescription {
        name: name.into(),
        camera: Some(CameraSetup {
            eye,
            look_at: centre,
            up: Vec3::Y,
            focal_distance: 1.2,
        }),
        materials: obj.materials,
        lights,
        mesh: obj.mesh,
        ..SceneDescription::default()
    })
}

/// What to say when `scene` holds nothing to hit: its image is the background alone.
pub fn empty_scene_warning(scene: &Scene, spec: &str) -> Option<String> {
    (scene.mesh.faces.is_empty() && scene.planes.is_empty() && scene.spheres.is_empty()).then(|| {
        format!(
            "warning: scene '{spec}' holds no geometry (no triangles, planes or spheres; an OBJ it names may be empty or cut short): the image shows only the background"
        )
    })
}

/// The lines naming what went wrong in a render: the unfinished exercises and other panics
/// with the pixels each cost (marked [`PANICKED_COLOUR`](raylab_core::render::PANICKED_COLOUR)),
/// and the pixels whose radiance is NaN or infinite; `exr` says what the EXR holds there.
pub fn warnings(rendered: &PartialRender, exr: bool) -> Vec<String> {
    let mut lines = failure_lines(&rendered.failures, rendered.film.pixels.len());
    if !lines.is_empty() {
        lines.push(if exr {
            "  (these pixels are NaN in the EXR: no radiance was computed there)".into()
        } else {
            "  (a pixel stops at the first panic it meets, so later exercises it needs may be unfinished too)".into()
        });
    }
    let bad = rendered.non_finite_pixels();
    if bad > 0 {
        lines.push(format!(
            "warning: {bad} pixels have NaN or infinite radiance ({}; a division by zero or the square root of a negative number, say)",
            if exr { "kept as they are in the EXR" } else { "shown cyan" }
        ));
    }
    lines
}

/// The lines naming each cause of `failures` (of `total` pixels) and the pixels it cost.
pub fn failure_lines(failures: &PixelFailures, total: usize) -> Vec<String> {
    if failures.is_empty() {
        return Vec::new();
    }
    let share = |n: usize| format!("{n} pixels ({:.1}%)", 100.0 * n as f64 / total as f64);
    let mut lines = vec![format!(
        "warning: {} of {total} pixels are magenta: their computation panicked",
        failures.pixels()
    )];
    for f in failures.sorted() {
        lines.push(match f.exercise() {
            Some(id) => format!("  Exercise {id} is unfinished: {}", share(f.pixels)),
            None => format!(
                "  a panic at {}: {:?}: {}",
                f.panic.location.as_deref().unwrap_or("an unknown place"),
                f.panic.message,
                share(f.pixels)
            ),
        });
    }
    lines
}
