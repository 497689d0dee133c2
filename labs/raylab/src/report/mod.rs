//! `raylab report --lab N`: the figures of a lab's report, rendered through the reference or
//! the student's pipeline, written as PNG files with a `report.md` beside them that gives each
//! figure's parameters and render time.

pub mod lab01;
pub mod lab02;
pub mod lab03;
pub mod lab04;
pub mod lab05;
pub mod lab06;
pub mod lab07;
pub mod lab08;
pub mod lab09;
pub mod lab10;
pub mod lab11;
pub mod plot;

use std::cell::RefCell;
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use framework::Error;
use framework::film::{Film, ToneMap, write_png};
use framework::glam::Vec3;
use framework::pipeline::{LabSlots, Pipeline};
use framework::render::{PixelFailures, RenderSettings, render_partial};
use framework::scene::Scene;

use crate::render::PipelineChoice;
use crate::students::{LabCode, LabVisitor};

/// Options of `raylab report`.
#[derive(Args, Debug)]
pub struct ReportArgs {
    /// The lab whose figures to make.
    #[arg(long)]
    pub lab: u32,
    /// Whose code renders the lab's part of the pipeline.
    #[arg(long, value_enum, default_value_t = PipelineChoice::Reference)]
    pub pipeline: PipelineChoice,
    /// Directory for the figures (a `labNN/` folder is made inside).
    #[arg(long, default_value = "out/report")]
    pub out: PathBuf,
    /// Smaller images and fewer samples, for a quick look (and for tests).
    #[arg(long)]
    pub quick: bool,
}

/// What a lab's figure code gets.
pub struct ReportContext {
    /// The lab.
    pub lab: u32,
    /// The pipeline at this lab, with the student's code in the lab's slots when asked for.
    pub pipeline: Pipeline,
    /// Where the figures go.
    pub dir: PathBuf,
    /// Quick mode: small images, few samples.
    pub quick: bool,
    /// The failed pixels of every render so far, and how many pixels were rendered.
    pub failures: RefCell<(PixelFailures, usize)>,
}

/// One figure of a report.
pub struct Figure {
    /// File name of the PNG in the report directory.
    pub file: String,
    /// What it shows.
    pub caption: String,
    /// The parameters it was made with.
    pub parameters: String,
    /// Render time in seconds (all panels together for a montage), if it is a render.
    pub seconds: Option<f64>,
}

impl ReportContext {
    /// Renders and times a scene, marked as `raylab render` marks it: magenta where the
    /// computation panicked (an unfinished exercise), cyan where the radiance is NaN or
    /// infinite. The failures are counted in [`ReportContext::failures`].
    pub fn render_timed(
        &self,
        scene: &Scene,
        pipeline: &Pipeline,
        settings: &RenderSettings,
    ) -> Result<(Film, f64), Error> {
        let start = Instant::now();
        let rendered = render_partial(scene, pipeline, settings)?;
        let seconds = start.elapsed().as_secs_f64();
        let mut failures = self.failures.borrow_mut();
        failures.0.merge(&rendered.failures);
        failures.1 += rendered.film.pixels.len();
        Ok((rendered.marked(), seconds))
    }

    /// Writes a film as a PNG figure in the report directory.
    pub fn save(&self, film: &Film, file: &str, tonemap: ToneMap) -> Result<PathBuf, Error> {
        let path = self.dir.join(file);
        write_png(film, &path, tonemap)?;
        Ok(path)
    }

    /// A size scaled down in quick mode.
    pub fn size(&self, width: u32, height: u32) -> (u32, u32) {
        if self.quick {
            (width / 4, height / 4)
        } else {
            (width, height)
        }
    }
}

/// Films side by side in a row (all of the same height), separated by `gap` white pixels.
pub fn montage(films: &[Film], gap: u32) -> Film {
    let height = films.iter().map(|f| f.height).max().unwrap_or(0);
    let width =
        films.iter().map(|f| f.width).sum::<u32>() + gap * films.len().saturating_sub(1) as u32;
    let mut out = Film::new(width, height);
    out.pixels.fill(Vec3::ONE);
    let mut x0 = 0;
    for film in films {
        for y in 0..film.height {
            for x in 0..film.width {
                out.set(x0 + x, y, film.get(x, y));
            }
        }
        x0 += film.width + gap;
    }
    out
}

/// Runs `raylab report`.
pub fn run(args: &ReportArgs) -> Result<(), Error> {
    crate::students::check_lab(args.lab)?;
    let mut pipeline = reference::pipeline(args.lab);
    if args.pipeline == PipelineChoice::Student {
        pipeline = crate::students::with_student_lab(pipeline, args.lab)?;
    }
    let dir = args.out.join(format!("lab{:02}", args.lab));
    std::fs::create_dir_all(&dir).map_err(|e| Error::io(&dir, e))?;
    let ctx = ReportContext {
        lab: args.lab,
        pipeline,
        dir,
        quick: args.quick,
        failures: RefCell::default(),
    };
    if let Some(note) = crate::render::student_code_note(args.pipeline, args.lab) {
        eprintln!("note: {note}");
    }
    let figures = (crate::students::visit(args.lab, Figures(&ctx))?)?;
    let (failures, total) = &*ctx.failures.borrow();
    let unfinished = crate::render::failure_lines(failures, *total);
    for line in &unfinished {
        eprintln!("{line}");
    }
    let index = write_index(&ctx, args.pipeline, &figures, &unfinished)?;
    let page = write_page(&ctx, args.pipeline, &figures, &unfinished)?;
    for f in &figures {
        println!("{}", ctx.dir.join(&f.file).display());
    }
    println!("{}", index.display());
    println!("{}", page.display());
    Ok(())
}

/// The work of `raylab report` on one lab: its figures.
struct Figures<'a>(&'a ReportContext);

impl LabVisitor for Figures<'_> {
    type Output = Result<Vec<Figure>, Error>;
    fn visit<S: ?Sized + LabSlots + Send + Sync + 'static>(self, code: LabCode<S>) -> Self::Output {
        (code.figures)(self.0)
    }
}

/// Writes `report.md` beside the figures: each figure with its caption, parameters and time.
fn write_index(
    ctx: &ReportContext,
    choice: PipelineChoice,
    figures: &[Figure],
    unfinished: &[String],
) -> Result<PathBuf, Error> {
    let mut md = String::new();
    let _ = writeln!(md, "# Lab {:02} report figures\n", ctx.lab);
    let _ = writeln!(md, "{}\n", made_with(ctx, choice));
    if !unfinished.is_empty() {
        let _ = writeln!(
            md,
            "**Unfinished.** Magenta pixels are pixels whose computation panicked, over all the figures:\n"
        );
        for line in unfinished.iter().skip(1) {
            let _ = writeln!(md, "- {}", line.trim());
        }
        md.push('\n');
    }
    for f in figures {
        let time = f
            .seconds
            .map_or_else(String::new, |s| format!(" — render time {s:.3} s"));
        let _ = writeln!(
            md,
            "## {}\n\n![{}]({})\n\n{}{time}\n",
            f.caption, f.caption, f.file, f.parameters
        );
    }
    let path = ctx.dir.join("report.md");
    std::fs::write(&path, md).map_err(|e| Error::io(&path, e))?;
    Ok(path)
}

/// How the report's figures were made, in words: the pipeline, and quick mode if it was.
fn made_with(ctx: &ReportContext, choice: PipelineChoice) -> String {
    format!(
        "Rendered with the {:?} pipeline{}.",
        choice,
        if ctx.quick {
            " in quick mode (small images, few samples)"
        } else {
            ""
        }
    )
}

/// Writes `report.html` beside the figures: the same as `report.md`, each figure shown with
/// its caption, parameters and time, for a browser.
fn write_page(
    ctx: &ReportContext,
    choice: PipelineChoice,
    figures: &[Figure],
    unfinished: &[String],
) -> Result<PathBuf, Error> {
    use maud::{DOCTYPE, html};
    let title = format!("Lab {:02} report figures", ctx.lab);
    let page = html! {
        (DOCTYPE)
        html lang="en" {
            head {
                meta charset="utf-8";
                title { (title) }
                style { "body{font-family:sans-serif;max-width:72rem;margin:2rem auto;padding:0 1rem}\
                         figure{margin:2rem 0}img{max-width:100%;image-rendering:pixelated}\
                         figcaption{color:#333}.unfinished{background:#fde;padding:.5rem 1rem}" }
            }
            body {
                h1 { (title) }
                p { (made_with(ctx, choice)) }
                @if !unfinished.is_empty() {
                    div class="unfinished" {
                        p { strong { "Unfinished." } " Magenta pixels are pixels whose computation panicked, over all the figures:" }
                        ul { @for line in unfinished.iter().skip(1) { li { (line.trim()) } } }
                    }
                }
                @for f in figures {
                    figure id=(f.file.trim_end_matches(".png")) {
                        h2 { (f.caption) }
                        img src=(f.file) alt=(f.caption);
                        figcaption {
                            (f.parameters)
                            @if let Some(s) = f.seconds { " — render time " (format!("{s:.3}")) " s" }
                        }
                    }
                }
            }
        }
    };
    let path = ctx.dir.join("report.html");
    std::fs::write(&path, page.into_string()).map_err(|e| Error::io(&path, e))?;
    Ok(path)
}

/// Render settings for a report figure.
pub fn settings(width: u32, height: u32, spp: u32) -> RenderSettings {
    RenderSettings {
        width,
        height,
        samples_per_pixel: spp,
        pixel_subdivisions: 1,
        seed: 0,
        progress: false,
    }
}
