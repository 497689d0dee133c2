//! `raylab view`: a page on 127.0.0.1 that shows a render converging, served by the lab's
//! program built with its `view` feature (the `view` crate), so the command line links no
//! lab's code and `cargo test -p labNN` never builds the web server.

use clap::Args;
use course::LabId;
use grading::task::{Task, ViewJob};
use raylab_core::Error;

use crate::arguments::pixels;
use crate::render::PipelineChoice;

/// Options of `raylab view`.
#[derive(Args, Debug)]
pub struct ViewArgs {
    /// Scene: a built-in name (default, cornell, cornell-ceiling, cornell-spheres), a scene
    /// file (.toml) or an OBJ file.
    #[arg(long, short, default_value = "cornell")]
    pub scene: String,
    /// The lab whose features (and, with --pipeline student, whose code) to use; default: the
    /// last lab.
    #[arg(long)]
    pub lab: Option<LabId>,
    /// Whose code renders; with `student`, the reference is shown beside it where the tree
    /// holds the lab's solution.
    #[arg(long, value_enum, default_value_t = PipelineChoice::Student)]
    pub pipeline: PipelineChoice,
    /// The port on 127.0.0.1 (0: a free one, printed).
    #[arg(long, default_value_t = 0)]
    pub port: u16,
    /// Image width in pixels.
    #[arg(long, default_value_t = 512, value_parser = pixels, allow_negative_numbers = true)]
    pub width: u32,
    /// Image height in pixels.
    #[arg(long, default_value_t = 512, value_parser = pixels, allow_negative_numbers = true)]
    pub height: u32,
    /// The seed of the first pass (pass p uses seed + p).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// A pixel to inspect as the page opens, `X,Y` (a failing image check names its worst);
    /// the page shows the difference view where the reference is beside the student's.
    #[arg(long, value_name = "X,Y", value_parser = parse_pixel)]
    pub pixel: Option<[u32; 2]>,
}

/// `X,Y` as a pixel.
fn parse_pixel(text: &str) -> Result<[u32; 2], String> {
    let parsed = text
        .split_once(',')
        .and_then(|(x, y)| Some([x.trim().parse().ok()?, y.trim().parse().ok()?]));
    parsed.ok_or_else(|| format!("expected X,Y (two whole numbers), not {text:?}"))
}

/// The largest image side `raylab view` renders.
pub const MAX_SIDE: u32 = 4096;

/// Checks `raylab view`'s arguments, before anything is built: the lab `args` name (or the
/// last) and a pixel inside an image of sides up to [`MAX_SIDE`].
pub fn check(args: &ViewArgs) -> Result<LabId, Error> {
    let lab = args.lab.unwrap_or_else(course::last);
    crate::labs::check_lab(lab)?;
    if let Some([x, y]) = args.pixel
        && (x >= args.width || y >= args.height)
    {
        return Err(Error::Invalid {
            what: format!("--pixel {x},{y}"),
            reason: format!("outside the {}×{} image", args.width, args.height),
        });
    }
    for (what, side) in [("--width", args.width), ("--height", args.height)] {
        if side == 0 || side > MAX_SIDE {
            return Err(Error::Invalid {
                what: format!("{what} {side}"),
                reason: format!("expected a whole number from 1 to {MAX_SIDE}"),
            });
        }
    }
    Ok(lab)
}

/// Runs `raylab view`: builds the lab's program with its `view` feature (and `reference` for
/// the reference pipeline where the tree holds the solution) and runs it until it is stopped.
pub fn run(args: &ViewArgs) -> Result<(), Error> {
    let lab = check(args)?;
    let has_solution = crate::render::has_solution(lab);
    let job = ViewJob {
        scene: args.scene.clone(),
        width: args.width,
        height: args.height,
        seed: args.seed,
        port: args.port,
        whose: format!("{:?}", args.pipeline),
        compare: args.pipeline == PipelineChoice::Student && has_solution,
        end_with_stdin: true,
        inspect: args.pixel,
    };
    if let Some(note) =
        crate::render::student_code_note(args.pipeline, lab, crate::render::has_solution)
    {
        eprintln!("note: {note}");
    }
    let features: &[&str] = match args.pipeline {
        PipelineChoice::Reference if has_solution => &["view", "reference"],
        _ => &["view"],
    };
    crate::render::run_in_lab_program(lab, features, &Task::View(job))
}
