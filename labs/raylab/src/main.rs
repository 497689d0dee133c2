//! `raylab`: render scenes through the reference or a student's pipeline, and regenerate the
//! labs' golden data from the reference.

mod arguments;
mod bench;
mod checkout;
mod git;
#[cfg(feature = "instructor")]
mod golden;
#[cfg(feature = "instructor")]
mod grade;
#[cfg(feature = "instructor")]
mod gradescope;
#[cfg(feature = "instructor")]
mod handout;
mod hint;
#[cfg(feature = "instructor")]
mod html;
mod lab_program;
mod labs;
#[cfg(feature = "instructor")]
mod new_lab;
mod render;
mod report;
mod reset;
#[cfg(feature = "instructor")]
mod similar_pairs;
#[cfg(feature = "instructor")]
mod similarity;
mod status;
mod utc;
mod view;
mod watch;

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// raylab — a ray tracing course in labs.
#[derive(Parser)]
#[command(name = "raylab", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to a PNG (or an EXR) and print the path of the image.
    Render(render::RenderArgs),
    /// Make a lab's report figures (PNG) and a report.md with their parameters and times.
    Report(report::ReportArgs),
    /// Show which exercises pass with your code, lab by lab, and which one is next.
    Status(status::StatusArgs),
    /// Show the next step of an exercise you are stuck on (e.g. `raylab hint 2.3`).
    Hint(hint::HintArgs),
    /// Re-run a lab's checks whenever its sources change, and show the next exercise to do.
    Watch(watch::WatchArgs),
    /// Watch a render converge in the browser: serve a page on 127.0.0.1 (the URL is printed)
    /// with your code's image beside the reference's, camera controls and each pixel's value.
    View(view::ViewArgs),
    /// Put one exercise's function back as the handout had it (e.g. `raylab reset 1.2`),
    /// leaving the rest of your code as it is and your file as it was in `out/reset/`.
    Reset(reset::ResetArgs),
    /// Measure the ray-tracing core: rays per second and BVH build time (docs/performance.md).
    Bench(bench::BenchArgs),
    /// Regenerate the labs' golden cases and snapshot images from the reference solution.
    #[cfg(feature = "instructor")]
    Golden(golden::GoldenArgs),
    /// Write the student handout as a git repository (stubs, checks, golden data, the released
    /// solutions), or release into it with `--update`: a commit students `git pull --no-rebase`.
    #[cfg(feature = "instructor")]
    Handout(handout::HandoutArgs),
    /// Grade submissions: each exercise built and run in isolation, reports and gradebooks.
    #[cfg(feature = "instructor")]
    Grade(grade::GradeArgs),
    /// Write the Gradescope autograder (setup.sh, run_autograder) that grades as `grade` does.
    #[cfg(feature = "instructor")]
    Gradescope(gradescope::GradescopeArgs),
    /// Add a lab to the course: its skeleton (one exercise, checked from the start) and its line
    /// in labs/course.toml.
    #[cfg(feature = "instructor")]
    NewLab(new_lab::NewLabArgs),
    /// Find submissions whose code of a lab is alike (Dolos, with the stubs left out): a page and
    /// a CSV of the similar pairs, linked from the class page of `grade`.
    #[cfg(feature = "instructor")]
    Similarity(similarity::SimilarityArgs),
}

/// With this variable set, a command checks its arguments — the parser's checks, then those the
/// command makes before it builds, loads or writes anything — says "arguments accepted" and
/// stops. The tests run so the commands that hints, `status` and the checks' messages print,
/// where running them would build a lab or serve a page.
const CHECK_ARGUMENTS_VAR: &str = "RAYLAB_CHECK_ARGUMENTS";

/// The checks `command` makes of its arguments before any work (see [`CHECK_ARGUMENTS_VAR`]).
fn check_arguments(command: &Option<Command>) -> Result<(), raylab_core::Error> {
    let lab = |lab: Option<course::LabId>| lab.map_or(Ok(()), labs::check_lab);
    match command {
        None => render::job(&render::RenderArgs::default()).map(drop),
        Some(Command::Render(args)) => render::job(args).map(drop),
        Some(Command::Report(args)) => labs::check_lab(args.lab),
        Some(Command::Status(args)) => lab(args.lab),
        Some(Command::Hint(args)) => hint::find(&args.exercise).map(drop),
        Some(Command::Watch(args)) => lab(args.lab),
        Some(Command::View(args)) => view::check(args).map(drop),
        Some(Command::Reset(args)) => reset::check(args).map(drop),
        Some(Command::Bench(args)) => bench::check(args),
        // The instructor's commands: what the parser checks.
        #[allow(unreachable_patterns)]
        Some(_) => Ok(()),
    }
}

/// The status of a command whose output pipe was closed: killed by SIGPIPE, as a Unix tool is.
const CLOSED_PIPE_STATUS: i32 = 128 + 13;

/// Ends the command quietly when its standard output is a pipe whose reader has gone
/// (`raylab status | head -2`), as any Unix tool ends, instead of with a panic: Rust ignores
/// SIGPIPE, and `println!` panics on the write that fails.
fn exit_quietly_on_closed_pipe() {
    let default = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        let payload = info.payload();
        let message = payload
            .downcast_ref::<String>()
            .map(String::as_str)
            .or_else(|| payload.downcast_ref::<&str>().copied())
            .unwrap_or("");
        if message.starts_with("failed printing to std") && message.contains("Broken pipe") {
            std::process::exit(CLOSED_PIPE_STATUS);
        }
        default(info);
    }));
}

fn main() -> ExitCode {
    // While the grader builds the handout's stubs, this program is also the compiler's wrapper.
    #[cfg(feature = "instructor")]
    grade::rustc_record::wrap_if_asked();
    exit_quietly_on_closed_pipe();
    let cli = Cli::parse();
    if std::env::var_os(CHECK_ARGUMENTS_VAR).is_some() {
        return exit(check_arguments(&cli.command).map(|()| println!("arguments accepted")));
    }
    // The course tree every command acts on: the one the current directory is in.
    if let Err(e) = checkout::resolve() {
        return exit(Err(e));
    }
    let result = match cli.command {
        None => render::run(&render::RenderArgs::default()),
        Some(Command::Render(args)) => render::run(&args),
        Some(Command::Report(args)) => report::run(&args),
        Some(Command::Status(args)) => status::run(&args),
        Some(Command::Hint(args)) => hint::run(&args),
        Some(Command::Watch(args)) => watch::run(&args),
        Some(Command::View(args)) => view::run(&args),
        Some(Command::Reset(args)) => reset::run(&args),
        Some(Command::Bench(args)) => bench::run(&args),
        #[cfg(feature = "instructor")]
        Some(Command::Golden(args)) => golden::run(&args),
        #[cfg(feature = "instructor")]
        Some(Command::Handout(args)) => handout::run(&args),
        #[cfg(feature = "instructor")]
        Some(Command::Grade(args)) => grade::run(&args),
        #[cfg(feature = "instructor")]
        Some(Command::Gradescope(args)) => gradescope::run(&args),
        #[cfg(feature = "instructor")]
        Some(Command::NewLab(args)) => new_lab::run(&args),
        #[cfg(feature = "instructor")]
        Some(Command::Similarity(args)) => similarity::run(&args),
    };
    exit(result)
}

/// The command's exit status; an error is printed on standard error first.
fn exit(result: Result<(), raylab_core::Error>) -> ExitCode {
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line whatever the message holds (a file or material name with a line
            // break in it, say).
            eprintln!("error: {}", e.to_string().trim_end().replace('\n', "\\n"));
            ExitCode::FAILURE
        }
    }
}
