//! `raylab render`.

use std::path::{Path, PathBuf};

use clap::{Args, ValueEnum};
use course::LabId;
use grading::task::Task;
use pipeline::job::RenderJob;
use pipeline::photon::PhotonSettings;
use pipeline::{Integrator, View};
use raylab_core::Error;

use crate::arguments::{count, pixels};
use crate::lab_program::LabProgram;

/// Whose code renders.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, ValueEnum)]
pub enum PipelineChoice {
    /// `reference::pipeline`: the reference solution of each lab up to --lab — in a handout
    /// the released ones; the pixels that need a lab whose solution is not released yet are
    /// marked, waiting for it.
    #[default]
    Reference,
    /// Your code for the lab given by --lab, `reference::pipeline` for the labs before it.
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
    /// Scene: a built-in name (default, cornell, cornell-ceiling, cornell-spheres), a scene file (.toml), or an
    /// OBJ file, which is framed by a camera looking at its bounds from the front and lit by a
    /// point light at the eye.
    #[arg(long, short, default_value = "default")]
    pub scene: String,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512, value_parser = pixels, allow_negative_numbers = true)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 384, value_parser = pixels, allow_negative_numbers = true)]
    pub height: u32,
    /// Samples per pixel (1 traces through pixel centres) [default: 1; 32 from lab 12 on, whose
    /// path tracer needs many]
    #[arg(long, value_parser = count, allow_negative_numbers = true)]
    pub spp: Option<u32>,
    /// Pixel subdivision s (lab 7 on): s × s jittered subpixel rays per sample.
    #[arg(long, default_value_t = 1, value_parser = count, allow_negative_numbers = true)]
    pub subdivisions: u32,
    /// Area-light samples n (lab 3 on): n × n stratified samples per shading point.
    #[arg(long, default_value_t = 4, value_parser = count, allow_negative_numbers = true)]
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
    #[arg(long, default_value_t = PhotonSettings::DEFAULT.emitted, value_parser = count, allow_negative_numbers = true)]
    pub photons: u32,
    /// The caustic estimate gathers the k nearest photons (lab 8 on) …
    #[arg(long, default_value_t = PhotonSettings::DEFAULT.k, value_parser = count, allow_negative_numbers = true)]
    pub photon_k: u32,
    /// … within this radius, in scene units (lab 8 on) [default: 5.2 % of the diagonal of the
    /// scene's bounds, 5 cm in the Cornell box]
    #[arg(long)]
    pub photon_radius: Option<f32>,
    /// Lab 12 on, where --spp of 8 or more renders progressively (passes of 4 samples, the
    /// image rewritten every 8 passes, the variance of each pixel's mean written beside it as
    /// NAME-variance.exr): stop once every pixel's relative error is below this (0.05 for 5 %).
    #[arg(long)]
    pub target_error: Option<f32>,
}

impl Default for RenderArgs {
    fn default() -> Self {
        Self {
            scene: "default".into(),
            width: 512,
            height: 384,
            spp: None,
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
            photon_radius: None,
            target_error: None,
        }
    }
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

/// Samples per pixel of a path-traced render when `--spp` is not given.
pub const PATH_TRACED_SPP: u32 = 32;

/// The render `args` ask for, its arguments checked (before any scene is loaded or program
/// built), and the lab it renders at.
pub fn job(args: &RenderArgs) -> Result<(LabId, RenderJob), Error> {
    let lab = args.lab.unwrap_or_else(course::last);
    crate::labs::check_lab(lab)?;
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
    let job = RenderJob {
        scene: args.scene.clone(),
        width: args.width,
        height: args.height,
        spp: args.spp.unwrap_or(
            if reference::pipeline(lab.number()).integrator() == Integrator::Path {
                PATH_TRACED_SPP
            } else {
                1
            },
        ),
        subdivisions: args.subdivisions,
        seed: args.seed,
        output: args.output.clone(),
        tonemap: args.tonemap.clone(),
        lab: lab.number(),
        view: match args.view {
            ViewChoice::Shaded => View::Shaded,
            ViewChoice::BaseColour => View::BaseColour,
            ViewChoice::Normals => View::Normals,
            ViewChoice::Caustics => View::Caustics,
        },
        light_samples: args.light_samples,
        photons: PhotonSettings {
            emitted: args.photons,
            k: args.photon_k,
            max_radius: args
                .photon_radius
                .unwrap_or(PhotonSettings::DEFAULT.max_radius),
            seed: args.seed,
        },
        photon_radius_from_scene: args.photon_radius.is_none(),
        whose: format!("{:?}", args.pipeline),
        target_error: args.target_error,
    };
    job.validate()?;
    Ok((lab, job))
}

/// Runs `raylab render`.
pub fn run(args: &RenderArgs) -> Result<(), Error> {
    let (lab, mut job) = job(args)?;
    job.output = prepare_output(&args.output)?;
    // The reference pipeline renders here, with this raylab's key; a student's in the lab's
    // program, built in the tree with its key.
    let solved = match args.pipeline {
        PipelineChoice::Reference => key_has_solution,
        PipelineChoice::Student => has_solution,
    };
    if let Some(note) = student_code_note(args.pipeline, lab, solved) {
        eprintln!("note: {note}");
    }
    if args.pipeline == PipelineChoice::Reference {
        return job.run(reference::pipeline(lab.number()));
    }
    run_in_lab_program(lab, &[], &Task::Render(job))
}

/// Runs `task` in lab `lab`'s program built with `features` (the student's code in the lab's
/// slots, or with `reference` the key's), its output passed through; an error when the program
/// does not build or the task fails. The program's standard input is a pipe this command holds
/// until the program ends: it reads nothing from the terminal, and a program that serves (the
/// view) ends when this command is killed and the pipe closes.
pub fn run_in_lab_program(lab: LabId, features: &[&str], task: &Task) -> Result<(), Error> {
    let program = LabProgram::build(lab, features).map_err(|e| Error::Failed {
        what: format!("{lab}"),
        reason: e.to_string(),
    })?;
    let mut child = program
        .command(task)
        .stdin(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| Error::io(&program.executable, e))?;
    let _held = child.stdin.take();
    let status = child
        .wait()
        .map_err(|e| Error::io(&program.executable, e))?;
    if status.success() {
        return Ok(());
    }
    Err(Error::Failed {
        what: format!("{lab}'s program"),
        reason: format!("it stopped ({status}); its messages are above"),
    })
}

/// The labs up to `lab` whose code `reference::pipeline` waits for: those `solved` says have
/// no solution ([`has_solution`] in a lab's program, [`key_has_solution`] in this process).
pub fn labs_without_solution(lab: LabId, solved: fn(LabId) -> bool) -> Vec<LabId> {
    course::labs_through(lab)
        .into_iter()
        .filter(|&l| !solved(l))
        .collect()
}

/// Whether this tree holds lab `lab`'s solution (`reference/src/labNN.rs`; a handout holds the
/// released ones): what a lab's program built there with the key renders with.
pub fn has_solution(lab: LabId) -> bool {
    crate::checkout::workspace_root()
        .join("reference/src")
        .join(format!("{lab}.rs"))
        .is_file()
}

/// Whether the answer key compiled into this raylab holds lab `lab`'s solution: what
/// `reference::pipeline` renders with here, in this process.
pub fn key_has_solution(lab: LabId) -> bool {
    reference::KEYS.contains(&lab.number())
}

/// What to say on stderr, before rendering, about the labs up to `lab` whose solution a
/// `choice` pipeline waits for: the pixels that need them are marked.
pub fn student_code_note(
    choice: PipelineChoice,
    lab: LabId,
    solved: fn(LabId) -> bool,
) -> Option<String> {
    let own: Vec<String> = labs_without_solution(lab, solved)
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
    Some(format!(
        "{what} not released yet: the pixels that need it are magenta, waiting for it; the reference images are labs/labNN/snapshots/*.png"
    ))
}
