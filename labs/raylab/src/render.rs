//! `raylab render`.

use course::LabId;
use std::path::{Path, PathBuf};
use std::time::Instant;

use clap::{Args, ValueEnum};
use pipeline::View;
use pipeline::photon::{PhotonSettings, with_caustics};
use pipeline::render::render_partial;
use raylab_core::Error;
use raylab_core::film::{ToneMap, write_exr, write_png};
use raylab_core::glam::Vec3;
use raylab_core::math::Aabb;
use raylab_core::render::{PartialRender, PixelFailures, RenderSettings};
use raylab_core::scene::{
    BUILTIN_SCENES, CameraSetup, Light, ObjData, PointLight, Scene, SceneDescription,
    builtin_scene, load_obj, load_scene_file,
};

/// Whose code renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum PipelineChoice {
    /// `reference::pipeline`: the reference solution of every lab — in a handout the released
    /// solutions, and your own code for the labs whose solutions are not released.
    #[default]
    Reference,
    /// Your code for the lab given by --lab, `reference::pipeline` for the others.
    Student,
}

/// What the image shows.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum ViewChoice {
    /// Full shading.
    #[default]
    Shaded,
    /// Diffuse colour of the surface hit.
    BaseColour,
    /// Shading normals as colours.
    Normals,
    /// Only the caustics of the photon map (lab 8 on).
    Caustics,
}

/// Options of `raylab render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// Scene: a built-in name (default, cornell, cornell-spheres), a scene file (.toml), or an
    /// OBJ file, which is framed by a camera looking at its bounds from the front and lit by a
    /// point light at the eye.
    #[arg(long, short, default_value = "default")]
    pub scene: String,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 384)]
    pub height: u32,
    /// Samples per pixel (1 traces through pixel centres).
    #[arg(long, default_value_t = 1)]
    pub spp: u32,
    /// Pixel subdivision s (lab 7 on): s × s jittered subpixel rays per sample.
    #[arg(long, default_value_t = 1)]
    pub subdivisions: u32,
    /// Area-light samples n (lab 3 on): n × n stratified samples per shading point.
    #[arg(long, default_value_t = 4)]
    pub light_samples: u32,
    /// Random seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Output image: .png (tone mapped, sRGB) or .exr (linear float radiance).
    #[arg(long, short, default_value = "out/render.png")]
    pub output: PathBuf,
    /// Tone map for PNG output: clamp[:EXPOSURE] or reinhard[:KEY[:WHITE]].
    #[arg(long, default_value = "clamp")]
    pub tonemap: String,
    /// Whose code renders.
    #[arg(long, value_enum, default_value_t = PipelineChoice::Reference)]
    pub pipeline: PipelineChoice,
    /// The lab whose features (and, with --pipeline student, whose code) to use; default: the
    /// last lab.
    #[arg(long)]
    pub lab: Option<LabId>,
    /// What the image shows.
    #[arg(long, value_enum, default_value_t = ViewChoice::Shaded)]
    pub view: ViewChoice,
    /// Photons emitted for the caustic photon map (lab 8 on).
    #[arg(long, default_value_t = PhotonSettings::DEFAULT.emitted)]
    pub photons: u32,
    /// The caustic estimate gathers the k nearest photons (lab 8 on) …
    #[arg(long, default_value_t = PhotonSettings::DEFAULT.k)]
    pub photon_k: u32,
    /// … within this radius, in scene units (lab 8 on).
    #[arg(long, default_value_t = PhotonSettings::DEFAULT.max_radius)]
    pub photon_radius: f32,
}

impl Default for RenderArgs {
    fn default() -> Self {
        Self {
            scene: "default".into(),
            width: 512,
            height: 384,
            spp: 1,
            subdivisions: 1,
            light_samples: 4,
            seed: 0,
            output: "out/render.png".into(),
            tonemap: "clamp".into(),
            pipeline: PipelineChoice::Reference,
            lab: None,
            view: ViewChoice::Shaded,
            photons: PhotonSettings::DEFAULT.emitted,
            photon_k: PhotonSettings::DEFAULT.k,
            photon_radius: PhotonSettings::DEFAULT.max_radius,
        }
    }
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

/// The output file as an absolute path, its directory made if it is missing and lies below the
/// working directory (as the default `out/` does); a missing directory elsewhere is an error, so
/// that a typing mistake does not make directories across the file system.
pub fn prepare_output(output: &Path) -> Result<PathBuf, Error> {
    let cwd = std::env::current_dir().map_err(|e| Error::io(Path::new("."), e))?;
    let absolute = cwd.join(output);
    let Some(dir) = absolute.parent() else {
        return Ok(absolute);
    };
    if dir.is_dir() {
        return Ok(absolute);
    }
    let below_cwd = output.is_relative()
        && output.components().all(|c| {
            matches!(
                c,
                std::path::Component::Normal(_) | std::path::Component::CurDir
            )
        });
    if !below_cwd {
        return Err(Error::Invalid {
            what: format!("--output '{}'", output.display()),
            reason: format!(
                "the directory '{}' does not exist; create it first, or give a path below the working directory, where missing directories are made",
                dir.display()
            ),
        });
    }
    std::fs::create_dir_all(dir).map_err(|e| Error::io(dir, e))?;
    Ok(absolute)
}

/// Runs `raylab render`.
pub fn run(args: &RenderArgs) -> Result<(), Error> {
    let tonemap: ToneMap = args.tonemap.parse()?;
    let lab = args.lab.unwrap_or_else(course::last);
    crate::students::check_lab(lab)?;
    if args.light_samples == 0 || args.light_samples > 64 {
        return Err(Error::Invalid {
            what: format!("--light-samples {}", args.light_samples),
            reason: "expected a whole number from 1 to 64".into(),
        });
    }
    let settings = RenderSettings {
        width: args.width,
        height: args.height,
        samples_per_pixel: args.spp,
        pixel_subdivisions: args.subdivisions,
        seed: args.seed,
        progress: true,
    };
    settings.validate()?;
    let ext = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("png" | "exr")) {
        return Err(Error::Invalid {
            what: format!("output '{}'", args.output.display()),
            reason: "expected a file name ending in .png or .exr".into(),
        });
    }
    let output = prepare_output(&args.output)?;
    let scene = load_scene(&args.scene)?;
    if let Some(warning) = empty_scene_warning(&scene, &args.scene) {
        eprintln!("{warning}");
    }
    let mut pipeline = reference::pipeline(lab.number());
    if args.pipeline == PipelineChoice::Student {
        pipeline = crate::students::with_student_lab(pipeline, lab)?;
    }
    pipeline.area_light_samples = args.light_samples;
    pipeline.view = match args.view {
        ViewChoice::Shaded => View::Shaded,
        ViewChoice::BaseColour => View::BaseColour,
        ViewChoice::Normals => View::Normals,
        ViewChoice::Caustics => View::Caustics,
    };
    pipeline.photons = PhotonSettings {
        emitted: args.photons,
        k: args.photon_k,
        max_radius: args.photon_radius,
        seed: args.seed,
    };
    if let Some(note) = student_code_note(args.pipeline, lab) {
        eprintln!("note: {note}");
    }
    let start = Instant::now();
    if lab.number() >= 8 {
        pipeline.photons.validate()?;
        match with_caustics(&pipeline, &scene) {
            Ok(traced) => {
                let stored = traced.caustics.as_ref().map_or(0, |m| m.len());
                eprintln!(
                    "traced {} photons ({stored} stored in the caustic map) in {:.2} s",
                    args.photons,
                    start.elapsed().as_secs_f64()
                );
                pipeline = traced;
            }
            Err(e) => eprintln!("warning: no caustics: {e}"),
        }
    }
    let rendered = render_partial(&scene, &pipeline, &settings)?;
    let seconds = start.elapsed().as_secs_f64();
    let exr = ext.as_deref() == Some("exr");
    if exr {
        write_exr(&rendered.film, &output)?;
    } else {
        write_png(&rendered.display(tonemap), &output, ToneMap::default())?;
    }
    eprintln!(
        "rendered '{}' ({}×{}, {} spp, lab {}, {:?} pipeline) in {seconds:.2} s",
        scene.name,
        args.width,
        args.height,
        args.spp,
        lab.number(),
        args.pipeline
    );
    for line in warnings(&rendered, exr) {
        eprintln!("{line}");
    }
    println!("{}", output.display());
    Ok(())
}

/// The labs up to `lab` whose slots `reference::pipeline` fills with the student's own code:
/// those whose solution is not in this tree's `reference/src/` (a handout holds only the
/// released ones).
pub fn labs_without_solution(lab: LabId) -> Vec<LabId> {
    let reference = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../reference/src");
    crate::students::labs()
        .into_iter()
        .filter(|&l| l <= lab && !reference.join(format!("{l}.rs")).is_file())
        .collect()
}

/// What to say on stderr about the student's code in a `choice` pipeline at `lab`, before
/// rendering: which slots of `reference::pipeline` hold it.
pub fn student_code_note(choice: PipelineChoice, lab: LabId) -> Option<String> {
    let own: Vec<String> = labs_without_solution(lab)
        .into_iter()
        .filter(|&l| choice == PipelineChoice::Reference || l != lab)
        .map(|l| l.number().to_string())
        .collect();
    if own.is_empty() {
        return None;
    }
    let what = match own.len() {
        1 => format!("the solution of lab {} is", own[0]),
        _ => format!("the solutions of labs {} are", own.join(", ")),
    };
    let whose = match choice {
        PipelineChoice::Reference => "--pipeline reference",
        PipelineChoice::Student => "the rest of the pipeline",
    };
    Some(format!(
        "{what} not released, so {whose} runs your own code there; the reference images are labs/labNN/snapshots/*.png"
    ))
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
