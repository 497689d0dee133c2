//! Building a submission's labs in the grading tree and running each exercise's test in a
//! sandboxed process of its own, with a time limit; a pass is the check's verdict record.

use course::LabId;
use std::collections::BTreeMap;
use std::fs;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

use grading::ExerciseInfo;
use grading::verdict::{self, RecordScanner};
use raylab_core::Error;

use super::Status;
use super::sandbox::{LINGERING, Sandbox};
use crate::handout::io;

/// Where cargo runs: the grading tree and the target directory shared by every submission (so
/// the framework is compiled once per class, not once per student), inside the sandbox.
pub struct Workspace {
    /// The grading tree (`raylab handout` with the hidden tests and the whole answer key).
    pub tree: PathBuf,
    /// `CARGO_TARGET_DIR` of the builds.
    pub target: PathBuf,
    /// Where each exercise runs, in an empty directory of its own.
    pub runs: PathBuf,
    /// What the grading's builds are named by (`grading::graded`): unique to its directory, so
    /// that gradings sharing a target directory never take each other's programs or modules.
    pub tag: String,
    /// The sandbox builds and exercises run in.
    pub sandbox: Sandbox,
    /// How long one `cargo` invocation may take.
    pub build_timeout: Duration,
}

/// How a build went.
pub struct Build {
    /// The checks' test executable of each lab that built.
    pub executables: BTreeMap<LabId, PathBuf>,
    /// The compiler's complaint for each lab that did not.
    pub errors: BTreeMap<LabId, String>,
}

impl Workspace {
    /// Fetches the tree's dependencies and settles its lock file, outside the sandbox (which
    /// has no network) and before any student code is in the tree.
    pub fn prepare(&self) -> Result<(), Error> {
        self.write_graded_crates()?;
        let output = Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
            .args(["fetch", "--quiet"])
            .current_dir(&self.tree)
            .env("CARGO_TARGET_DIR", &self.target)
            .stdin(Stdio::null())
            .output()
            .map_err(io(&self.tree))?;
        if !output.status.success() {
            return Err(Error::Invalid {
                what: format!("cargo fetch in {}", self.tree.display()),
                reason: String::from_utf8_lossy(&output.stderr).trim().to_string(),
            });
        }
        // Under `--run-as`, the exercises' user cannot read the answer key's source.
        for secret in ["reference", "tests"] {
            let dir = self.tree.join(secret);
            if dir.exists() {
                self.sandbox.hide_from_exercises(&dir)?;
            }
        }
        fs::create_dir_all(&self.target).map_err(io(&self.target))
    }

    /// Writes, for each lab crate of the tree, its guest crate (the lab compiled to a
    /// WebAssembly module) and its graded program (`grading::graded`).
    fn write_graded_crates(&self) -> Result<(), Error> {
        let framework = self.tree.join("framework");
        let mut members = String::new();
        for lab in course::labs() {
            let name = format!("{lab}");
            let lab_dir = self.tree.join("labs").join(&name);
            if !lab_dir.join("Cargo.toml").is_file() {
                continue;
            }
            let guest = lab_dir.join("guest");
            grading::graded::write_guest_crate(
                &guest, &name, &self.tag, &lab_dir, &framework, false,
            )
            .map_err(io(&guest))?;
            let graded = lab_dir.join("graded");
            grading::graded::write_graded_crate(
                &graded,
                &name,
                &self.tag,
                &lab_dir.join("checks"),
                &framework,
                &self.tree.join("reference"),
            )
            .map_err(io(&graded))?;
            members.push_str(&format!(
                "    \"labs/{name}/guest\",\n    \"labs/{name}/graded\",\n"
            ));
        }
        if members.is_empty() {
            return Ok(());
        }
        let manifest = self.tree.join("Cargo.toml");
        let text = fs::read_to_string(&manifest).map_err(io(&manifest))?;
        let Some(at) = text.find("    \"labs/*/checks\",\n") else {
            return Err(Error::Invalid {
                what: manifest.display().to_string(),
                reason: "its workspace members have no line `\"labs/*/checks\",`".into(),
            });
        };
        let mut text = text;
        text.insert_str(at, &members);
        fs::write(&manifest, text).map_err(io(&manifest))
    }

    /// Runs `cargo ARGS --offline --locked` in the sandbox with the directories `hidden` (in
    /// the tree) out of sight, killed after the build time limit; `Err` only when it could not
    /// be started.
    fn cargo(&self, args: &[&str], hidden: &[&str]) -> Result<Captured, Error> {
        let mut all = args.to_vec();
        all.extend(["--offline", "--locked"]);
        let hidden: Vec<PathBuf> = hidden.iter().map(|h| self.tree.join(h)).collect();
        let command = self.sandbox.cargo(&self.tree, &self.target, &all, &hidden);
        run_captured(command, None, self.build_timeout, COMPILER_OUTPUT_LIMIT)
    }

    /// `cargo build --lib -p PACKAGE [--target TARGET]` with the answer key's sources
    /// (`reference/src`) out of sight: this is the one build in which the student's code runs
    /// at compile time (its macros, constant evaluation), so nothing it names or reads can be
    /// the key. `Err` with the compiler's messages when it does not compile.
    pub fn build_lib(
        &self,
        package: &str,
        target: Option<&str>,
    ) -> Result<Result<(), String>, Error> {
        let mut args = vec![
            "build",
            "--quiet",
            "--message-format=short",
            "--lib",
            "-p",
            package,
        ];
        if let Some(target) = target {
            args.extend(["--target", target]);
        }
        let run = self.cargo(&args, &[ANSWER_KEY_SOURCES])?;
        Ok(match run.status {
            Some(status) if status.success() => Ok(()),
            Some(_) => Err(compiler_errors(&run.text())),
            None => Err(format!(
                "the build did not finish within {} s and was stopped",
                self.build_timeout.as_secs()
            )),
        })
    }

    /// Compiles the submission's `lab` to its WebAssembly module (the lab's guest crate, see
    /// [`Self::build_lib`]) and copies it to `to`; `Err` with the compiler's messages when it
    /// does not compile.
    pub fn build_module(&self, lab: LabId, to: &Path) -> Result<Result<(), String>, Error> {
        let built = self.build_lib(&format!("{lab}-guest"), Some(WASM_TARGET))?;
        if built.is_ok() {
            let module = self
                .target
                .join(WASM_TARGET)
                .join("debug")
                .join(grading::graded::module_file(&format!("{lab}"), &self.tag));
            crate::handout::copy_file(&module, to)?;
        }
        Ok(built)
    }

    /// `cargo build --bins` of the graded programs of `labs` (`grading::graded`): the
    /// executable of each lab that built, the compiler's messages for each that did not. No
    /// student code is in them (they call it in its module), so cargo builds each once per
    /// grading and finds it fresh for every later submission.
    pub fn build_graded(&self, labs: &[LabId]) -> Result<Build, Error> {
        if labs.is_empty() {
            // Without a `-p`, cargo would build every package.
            return Ok(Build {
                executables: BTreeMap::new(),
                errors: BTreeMap::new(),
            });
        }
        let mut args = vec![
            "build",
            "--bins",
            "--message-format=json-render-diagnostics",
        ];
        let packages: Vec<String> = labs.iter().map(|l| format!("{l}-graded")).collect();
        for package in &packages {
            args.extend(["-p", package]);
        }
        let run = self.cargo(&args, &[])?;
        let mut executables = BTreeMap::new();
        for line in String::from_utf8_lossy(&run.output).lines() {
            let Ok(message) = serde_json::from_str::<serde_json::Value>(line) else {
                continue;
            };
            let (Some(executable), Some(target)) = (
                message["executable"].as_str(),
                message["target"]["name"].as_str(),
            ) else {
                continue;
            };
            let program = |l: &LabId| grading::graded::program_name(&format!("{l}"), &self.tag);
            if let Some(&lab) = labs.iter().find(|l| target == program(l)) {
                executables.insert(lab, PathBuf::from(executable));
            }
        }
        let text: String = String::from_utf8_lossy(&run.output)
            .lines()
            .filter(|l| !l.starts_with('{'))
            .collect::<Vec<_>>()
            .join("\n");
        let stderr = compiler_errors(&text);
        let errors: BTreeMap<LabId, String> = labs
            .iter()
            .filter(|l| !executables.contains_key(l))
            .map(|&l| (l, stderr.clone()))
            .collect();
        Ok(Build {
            executables,
            errors,
        })
    }
}

/// What a lab is compiled to for grading.
const WASM_TARGET: &str = "wasm32-unknown-unknown";

/// The answer key's sources in the grading tree, out of sight while student code compiles.
const ANSWER_KEY_SOURCES: &str = "reference/src";

/// The error lines of cargo's output, without its progress lines; at most 60 lines.
fn compiler_errors(stderr: &str) -> String {
    let stderr = printable(stderr);
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| {
            let t = l.trim_start();
            !(t.starts_with("Compiling ")
                || t.starts_with("Finished ")
                || t.starts_with("Blocking "))
        })
        .collect();
    let mut text = lines
        .iter()
        .take(60)
        .copied()
        .collect::<Vec<_>>()
        .join("\n");
    if lines.len() > 60 {
        text.push_str(&format!("\n… ({} more lines)", lines.len() - 60));
    }
    if text.len() > COMPILER_MESSAGE_LIMIT {
        let mut end = COMPILER_MESSAGE_LIMIT;
        while !text.is_char_boundary(end) {
            end -= 1;
        }
        text = format!("{}\n… (cut: {} bytes in all)", &text[..end], text.len());
    }
    text
}

/// Output kept of one build (a test build's list of artifacts is long).
const COMPILER_OUTPUT_LIMIT: usize = 4 << 20;

/// The compiler's messages kept for a report, bytes.
const COMPILER_MESSAGE_LIMIT: usize = 16 << 10;

/// Output of one exercise's process kept for the report.
pub const OUTPUT_LIMIT: usize = 64 << 10;

/// How long the output pipe is read after the process ended (processes it left behind, when
/// not sandboxed, may hold it open).
const DRAIN_GRACE: Duration = Duration::from_secs(2);

/// What a process printed (standard output and error together) and how it ended.
struct Captured {
    /// The first bytes of the output, up to the limit.
    output: Vec<u8>,
    /// Bytes printed in all.
    total: u64,
    /// How it ended; `None` when it was stopped at the time limit.
    status: Option<ExitStatus>,
    /// The verdict record found in the output, when a secret was given.
    scanner: Option<RecordScanner>,
    /// Wall time.
    seconds: f64,
}

impl Captured {
    fn text(&self) -> String {
        String::from_utf8_lossy(&self.output).into_owned()
    }
}

/// What the reading thread has seen so far.
#[derive(Default)]
struct Stream {
    output: Vec<u8>,
    total: u64,
    scanner: Option<RecordScanner>,
}

/// Runs `command` in a process group of its own, with standard output and error read into one
/// stream (its first `limit` bytes kept, all of it scanned for the record of `secret`, which is
/// written to its standard input); the whole group is killed after `timeout`, and when the
/// process has ended.
fn run_captured(
    mut command: Command,
    secret: Option<&str>,
    timeout: Duration,
    limit: usize,
) -> Result<Captured, Error> {
    let program = PathBuf::from(command.get_program());
    let (mut reader, writer) = std::io::pipe().map_err(io(&program))?;
    command
        .stdout(writer.try_clone().map_err(io(&program))?)
        .stderr(writer)
        .stdin(if secret.is_some() {
            Stdio::piped()
        } else {
            Stdio::null()
        });
    std::os::unix::process::CommandExt::process_group(&mut command, 0);
    let start = Instant::now();
    let mut child = command.spawn().map_err(io(&program))?;
    // The command holds the pipe's writing ends: without dropping it the stream never ends.
    drop(command);
    if let (Some(secret), Some(mut stdin)) = (secret, child.stdin.take()) {
        // A process that exits at once closes its end: that is its failure, not the grader's.
        let _ = writeln!(stdin, "{secret}");
    }

    let stream = Arc::new(Mutex::new(Stream {
        scanner: secret.map(RecordScanner::new),
        ..Stream::default()
    }));
    let (done_tx, done_rx) = mpsc::channel();
    let shared = Arc::clone(&stream);
    std::thread::spawn(move || {
        let mut buffer = vec![0u8; 64 << 10];
        loop {
            match reader.read(&mut buffer) {
                Ok(0) | Err(_) => break,
                Ok(n) => {
                    let mut s = shared.lock().unwrap_or_else(|e| e.into_inner());
                    let room = limit.saturating_sub(s.output.len());
                    s.output.extend_from_slice(&buffer[..n.min(room)]);
                    s.total += n as u64;
                    if let Some(scanner) = &mut s.scanner {
                        scanner.feed(&buffer[..n]);
                    }
                }
            }
        }
        let _ = done_tx.send(());
    });

    let group = child.id();
    let status = loop {
        if let Some(status) = child.try_wait().map_err(io(&program))? {
            break Some(status);
        }
        if start.elapsed() >= timeout {
            kill_group(group);
            let _ = child.kill();
            let _ = child.wait();
            break None;
        }
        std::thread::sleep(Duration::from_millis(5));
    };
    let seconds = start.elapsed().as_secs_f64();
    // What the process left running in its group goes with it.
    kill_group(group);
    let _ = done_rx.recv_timeout(DRAIN_GRACE);
    let mut s = stream.lock().unwrap_or_else(|e| e.into_inner());
    Ok(Captured {
        output: std::mem::take(&mut s.output),
        total: s.total,
        status,
        scanner: s.scanner.take(),
        seconds,
    })
}

/// Sends SIGKILL to the process group `group`.
fn kill_group(group: u32) {
    if let Ok(group) = i32::try_from(group) {
        // SAFETY: kill has no memory-safety preconditions; a group that is gone gives ESRCH.
        unsafe {
            libc::kill(-group, libc::SIGKILL);
        }
    }
}

/// The outcome of running one exercise's test.
pub struct Run {
    /// What became of the exercise: passed only when the check's verdict record said so.
    pub status: Status,
    /// Why it failed (the check's message, the time-out, the crash), or empty.
    pub output: String,
    /// What the student's code printed (cut to [`OUTPUT_LIMIT`]), apart from the verdict.
    pub program_output: String,
    /// Images the check wrote (student render, expected image, difference heat map).
    pub images: Vec<PathBuf>,
    /// Wall time of the run.
    pub seconds: f64,
}

/// The test names of a checks executable, listed in the sandbox (in `scratch`).
pub fn list_tests(
    sandbox: &Sandbox,
    executable: &Path,
    lab_dir: &Path,
    scratch: &Path,
) -> Result<Vec<String>, Error> {
    fs::create_dir_all(scratch).map_err(io(scratch))?;
    sandbox.give_scratch(scratch)?;
    let command = sandbox.exercise(
        executable,
        lab_dir,
        scratch,
        &["--list", "--format", "terse"],
        &[],
    );
    let run = run_captured(command, None, Duration::from_secs(60), OUTPUT_LIMIT);
    sandbox.end_exercise();
    let run = run?;
    Ok(run
        .text()
        .lines()
        .filter_map(|l| l.strip_suffix(": test"))
        .map(str::to_string)
        .collect())
}

/// Compiles the student's module `wasm` to machine code with the lab's graded program (in the
/// sandbox, in `scratch`, before any student code runs), once for all the lab's exercises: the
/// `.cwasm` file beside `wasm`, or `wasm` itself when it does not compile (its exercises then
/// say why).
pub fn precompile(
    sandbox: &Sandbox,
    executable: &Path,
    lab_dir: &Path,
    scratch: &Path,
    wasm: &Path,
) -> Result<PathBuf, Error> {
    fs::create_dir_all(scratch).map_err(io(scratch))?;
    let input = scratch.join("student.wasm");
    crate::handout::copy_file(wasm, &input)?;
    sandbox.give_scratch(scratch)?;
    let output = scratch.join("student.cwasm");
    let (input_text, output_text) = (input.to_string_lossy(), output.to_string_lossy());
    let command = sandbox.exercise(
        executable,
        lab_dir,
        scratch,
        &[],
        &[
            (grading::graded::MODULE_VAR, &input_text),
            (grading::graded::PRECOMPILE_VAR, &output_text),
        ],
    );
    let run = run_captured(command, None, Duration::from_secs(120), OUTPUT_LIMIT);
    sandbox.end_exercise();
    let compiled = run?.status.is_some_and(|s| s.success()) && output.is_file();
    let module = if compiled {
        let to = wasm.with_extension("cwasm");
        crate::handout::copy_file(&output, &to)?;
        to
    } else {
        wasm.to_path_buf()
    };
    fs::remove_dir_all(scratch).map_err(io(scratch))?;
    Ok(module)
}

/// How an exercise is run.
pub struct ExerciseRun<'a> {
    /// The sandbox.
    pub sandbox: &'a Sandbox,
    /// The lab's graded program.
    pub executable: &'a Path,
    /// The student's code of the lab, compiled to WebAssembly.
    pub module: &'a Path,
    /// The lab's directory in the grading tree (golden data, snapshots).
    pub lab_dir: &'a Path,
    /// The exercise's own empty directory.
    pub scratch: &'a Path,
    /// The time limit.
    pub timeout: Duration,
    /// The memory limit, for the message when it is reached.
    pub memory_limit: u64,
}

/// Runs the test `test` of exercise `info` in a sandboxed process of its own. It passes only
/// when the output holds the check's verdict record, with this run's secret, saying so.
pub fn run_exercise(how: &ExerciseRun, test: &str, info: &ExerciseInfo) -> Result<Run, Error> {
    fs::create_dir_all(how.scratch).map_err(io(how.scratch))?;
    // The module beside the exercise's files, which the program in the sandbox sees.
    let extension = how.module.extension().unwrap_or_default().to_string_lossy();
    let module = how.scratch.join(format!("student.{extension}"));
    crate::handout::copy_file(how.module, &module)?;
    how.sandbox.give_scratch(how.scratch)?;
    let secret = verdict::new_secret().map_err(io(Path::new("/dev/urandom")))?;
    let scratch = how.scratch.to_string_lossy();
    let module = module.to_string_lossy();
    let command = how.sandbox.exercise(
        how.executable,
        how.lab_dir,
        how.scratch,
        &[test, "--exact", "--nocapture", "--test-threads=1"],
        &[
            ("CARGO_TARGET_DIR", &scratch),
            ("RUST_BACKTRACE", "0"),
            (verdict::CHANNEL_VAR, "stdin"),
            (grading::graded::MODULE_VAR, &module),
        ],
    );
    let run = run_captured(command, Some(&secret), how.timeout, OUTPUT_LIMIT);
    how.sandbox.end_exercise();
    let run = run?;
    let images = failure_images(
        &how.scratch
            .join("raylab-failures")
            .join(format!("{}", info.lab)),
    );
    let record = run.scanner.as_ref().and_then(|s| s.record(&info.id));
    let printed = printable(&run.text());
    let (status, output) = match (&record, run.status) {
        (_, None) => (
            Status::TimedOut,
            format!(
                "Exercise {} — `{}` did not finish within {} s and was stopped (an infinite loop?).",
                info.id,
                info.function,
                how.timeout.as_secs()
            ),
        ),
        (Some(record), Some(_)) if record.passed => (Status::Passed, printable(&record.message)),
        (Some(record), Some(_)) => (
            Status::of_failure(record.kind.as_ref()),
            printable(&record.message),
        ),
        (None, Some(exit)) => no_verdict(info, exit, &printed, how.memory_limit),
    };
    let output = if printed.contains(LINGERING) {
        format!(
            "{output}\n(The student's code left processes running after the test ended; the sandbox stopped them.)"
        )
    } else {
        output
    };
    Ok(Run {
        status,
        output,
        program_output: program_output(
            &printed,
            test,
            &secret,
            (run.total > run.output.len() as u64).then_some(run.total),
        ),
        images,
        seconds: run.seconds,
    })
}

/// Why an exercise whose process ended without a verdict record failed.
fn no_verdict(
    info: &ExerciseInfo,
    status: ExitStatus,
    printed: &str,
    memory_limit: u64,
) -> (Status, String) {
    use std::os::unix::process::ExitStatusExt;
    let why = no_verdict_reason(info, status, printed, memory_limit);
    let timed_out =
        status.signal() == Some(libc::SIGXCPU) || status.code() == Some(128 + libc::SIGXCPU);
    (
        if timed_out {
            Status::TimedOut
        } else {
            Status::Crashed
        },
        why,
    )
}

/// The words of [`no_verdict`].
fn no_verdict_reason(
    info: &ExerciseInfo,
    status: ExitStatus,
    printed: &str,
    memory_limit: u64,
) -> String {
    use std::os::unix::process::ExitStatusExt;
    let place = format!("Exercise {} — `{}`", info.id, info.function);
    if printed.contains("memory allocation of") {
        return format!(
            "{place} did not complete: the test process ran out of memory (the limit is {} MiB of address space).",
            memory_limit >> 20
        );
    }
    // A sandbox passes a signal on as the exit status 128 + N.
    let signal = status.signal().or_else(|| {
        status
            .code()
            .filter(|c| (129..=128 + 64).contains(c))
            .map(|c| c - 128)
    });
    match signal {
        Some(libc::SIGXCPU) => format!(
            "{place} did not complete: the test process used up its CPU time and was stopped."
        ),
        Some(signal) => format!(
            "{place} did not complete: the test process crashed (signal {signal}{}) before the check could finish.",
            match signal {
                libc::SIGSEGV => ", a segmentation fault or stack overflow",
                libc::SIGABRT => ", an abort",
                libc::SIGKILL => ", killed",
                libc::SIGXFSZ => ", a file over the size limit",
                _ => "",
            }
        ),
        None => format!(
            "{place} did not complete: the test process ended (exit code {}) without the check's verdict — did a student function end the process (`std::process::exit`) or stop the check?",
            status.code().unwrap_or(-1)
        ),
    }
}

/// `text` with control characters (terminal escapes, NUL, …) other than newlines and tabs
/// replaced, so that no report can carry them to a terminal, an XML parser or a browser.
fn printable(text: &str) -> String {
    text.chars()
        .map(|c| {
            if c.is_control() && c != '\n' && c != '\t' {
                '\u{fffd}'
            } else {
                c
            }
        })
        .collect()
}

/// What the student's code printed: the process's output without libtest's own framing
/// lines and the verdict record, with a note when it was cut.
fn program_output(printed: &str, test: &str, secret: &str, cut_from: Option<u64>) -> String {
    let framing = format!("test {test} ... ");
    let record = format!("{}{secret} ", verdict::RECORD_TAG);
    let mut text: String = printed
        .lines()
        .filter(|l| !l.starts_with(&record) && *l != LINGERING)
        .map(|l| l.strip_prefix(&framing).unwrap_or(l))
        .filter(|l| *l != "running 1 test" && *l != "ok" && *l != "FAILED")
        .collect::<Vec<_>>()
        .join("\n")
        .trim()
        .to_string();
    if let Some(total) = cut_from {
        text.push_str(&format!(
            "\n[output cut: {total} bytes in all, the first {} KiB kept]",
            OUTPUT_LIMIT >> 10
        ));
    }
    text
}

/// The largest failure image copied into a report, bytes.
const IMAGE_LIMIT: u64 = 8 << 20;

/// The most failure images copied into a report for one exercise.
const MAX_IMAGES: usize = 12;

/// The PNG files a failing check wrote into `dir`: the student's render first, then the
/// reference, then the difference.
fn failure_images(dir: &Path) -> Vec<PathBuf> {
    // Only regular files (never a link the student's code left there), of a sane size.
    let mut images: Vec<PathBuf> = fs::read_dir(dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| {
            e.file_type().is_ok_and(|t| t.is_file())
                && e.metadata().is_ok_and(|m| m.len() <= IMAGE_LIMIT)
        })
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "png"))
        .take(MAX_IMAGES)
        .collect();
    images.sort_by_key(|p| {
        let name = p
            .file_stem()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let rank = if name.ends_with("-student") {
            0
        } else if name.ends_with("-reference") {
            1
        } else {
            2
        };
        (rank, name)
    });
    images
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn program_output_leaves_out_the_framing_and_the_record() {
        let printed = "\nrunning 1 test\ntest exercise_1_2_camera_basis ... hello\nRAYLAB-VERDICT 00 {}\nRAYLAB-VERDICT abc {}\n";
        assert_eq!(
            program_output(printed, "exercise_1_2_camera_basis", "abc", None),
            "hello\nRAYLAB-VERDICT 00 {}",
            "a forged record stays in the student's output"
        );
        assert!(
            program_output("x", "t", "abc", Some(1 << 30))
                .ends_with("[output cut: 1073741824 bytes in all, the first 64 KiB kept]")
        );
    }

    #[test]
    fn progress_lines_are_not_errors() {
        let text = compiler_errors(
            "   Compiling lab01 v0.1.0\nerror[E0308]: mismatched types\n    Finished `dev`",
        );
        assert_eq!(text, "error[E0308]: mismatched types");
    }

    /// The student's build does not see the answer key's sources: a lab that includes them
    /// (past the scan, which would flag it) does not compile, and the checks' build, which
    /// sees them, links the key. Needs bubblewrap, as `raylab grade` does.
    #[test]
    fn the_answer_key_is_out_of_sight_of_the_student_build() {
        let test = "the_answer_key_is_out_of_sight_of_the_student_build";
        if !grading::prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap") {
            return;
        }
        let tree = std::env::temp_dir().join(format!("raylab-hidden-key-{}", std::process::id()));
        let _ = fs::remove_dir_all(&tree);
        let write = |path: &str, text: &str| {
            let path = tree.join(path);
            fs::create_dir_all(path.parent().unwrap()).unwrap();
            fs::write(path, text).unwrap();
        };
        write(
            "Cargo.toml",
            "[workspace]\nresolver = \"3\"\nmembers = [\"reference\", \"lab\"]\n",
        );
        let manifest = |name: &str, deps: &str| {
            format!(
                "[package]\nname = \"{name}\"\nversion = \"0.1.0\"\nedition = \"2024\"\n\n[lib]\npath = \"src/lib.rs\"\n\n{deps}"
            )
        };
        write("reference/Cargo.toml", &manifest("reference", ""));
        write(
            "reference/src/lib.rs",
            "pub const KEY: &str = \"the answer\";\n",
        );
        write(
            "lab/Cargo.toml",
            &manifest(
                "lab",
                "[dev-dependencies]\nreference = { path = \"../reference\" }\n\n[features]\nhidden-exercises = []\n",
            ),
        );
        write(
            "lab/src/lib.rs",
            "pub const STOLEN: &str = include_str!(\"../../reference/src/lib.rs\");\n",
        );
        let limits = super::super::sandbox::Limits {
            memory: 4 << 30,
            build_memory: 8 << 30,
            processes: 256,
            file_size: 64 << 20,
            build_file_size: 4 << 30,
            cpu_seconds: 300,
        };
        let workspace = Workspace {
            target: tree.join("target"),
            runs: tree.join("runs"),
            tag: "test".into(),
            sandbox: Sandbox::new(false, None, limits).expect("bubblewrap is installed"),
            build_timeout: Duration::from_secs(300),
            tree: tree.clone(),
        };
        workspace.prepare().unwrap();
        let errors = workspace
            .build_lib("lab", None)
            .unwrap()
            .expect_err("the key's sources were in view of the student's build");
        assert!(errors.contains("reference/src/lib.rs"), "{errors}");

        write("lab/src/lib.rs", "pub const OWN: u32 = 1;\n");
        write(
            "lab/tests/checks.rs",
            "#[test]\nfn key() { assert_eq!(reference::KEY, \"the answer\"); }\n",
        );
        workspace
            .build_lib("lab", None)
            .unwrap()
            .expect("the lab builds");
        let run = workspace
            .cargo(
                &[
                    "test",
                    "--no-run",
                    "-p",
                    "lab",
                    "--test",
                    "checks",
                    "--features",
                    "lab/hidden-exercises",
                ],
                &[],
            )
            .unwrap();
        assert!(run.status.is_some_and(|s| s.success()), "{}", run.text());
        let _ = fs::remove_dir_all(&tree);
    }
}
