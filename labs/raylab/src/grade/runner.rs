//! Running each exercise's test in a sandboxed process of its own, with a time limit (a pass is
//! the check's verdict record), and any process whose output is read, bounded.

use std::fs;
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

use grading::ExerciseInfo;
use grading::verdict::{self, RecordScanner};
use raylab_core::Error;

use super::grades::Status;
use super::sandbox::{LINGERING, Sandbox};
use crate::handout::io;

/// The error lines of cargo's output, without its progress lines; at most 60 lines.
pub fn compiler_errors(stderr: &str) -> String {
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

/// The compiler's messages kept for a report, bytes.
const COMPILER_MESSAGE_LIMIT: usize = 16 << 10;

/// Output of one exercise's process kept for the report.
pub const OUTPUT_LIMIT: usize = 64 << 10;

/// How long the output pipe is read after the process ended (processes it left behind, when
/// not sandboxed, may hold it open).
const DRAIN_GRACE: Duration = Duration::from_secs(2);

/// What a process printed (standard output and error together) and how it ended.
pub struct Captured {
    /// The first bytes of the output, up to the limit.
    pub output: Vec<u8>,
    /// Bytes printed in all.
    pub total: u64,
    /// How it ended; `None` when it was stopped at the time limit.
    pub status: Option<ExitStatus>,
    /// The verdict record found in the output, when a secret was given.
    pub scanner: Option<RecordScanner>,
    /// Wall time.
    pub seconds: f64,
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
pub fn run_captured(
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
    /// Of it, the time of runs stopped at the grader's time limits.
    pub stopped_seconds: f64,
    /// The exercises whose functions the check's verdict was decided with the key's code for.
    pub key_for: Vec<String>,
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
        sandbox.cpu_limit(),
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
    // Named relative to the process's directory, the scratch one: no message of it can name a
    // place of this machine.
    let command = sandbox.exercise(
        executable,
        lab_dir,
        scratch,
        &[],
        &[
            (grading::graded::MODULE_VAR, "student.wasm"),
            (grading::graded::PRECOMPILE_VAR, "student.cwasm"),
        ],
        sandbox.cpu_limit(),
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

/// The name of the lab's directory in an exercise's own directory.
const LAB_LINK: &str = "lab";

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
/// when the output holds the check's verdict record, with this run's secret, saying so. A run
/// stopped at the grader's time limits (wall clock or CPU) is run again with twice the time —
/// the student's code is bounded by its own instruction budget, so these limits are the
/// grader's — and an exercise stopped twice is not graded, never charged as the student's.
pub fn run_exercise(how: &ExerciseRun, test: &str, info: &ExerciseInfo) -> Result<Run, Error> {
    let first = attempt(how, test, info, 1)?;
    if !first.stopped {
        return Ok(first.run);
    }
    fs::remove_dir_all(how.scratch).map_err(io(how.scratch))?;
    let second = attempt(how, test, info, 2)?;
    let seconds = first.run.seconds + second.run.seconds;
    if !second.stopped {
        return Ok(Run {
            seconds,
            stopped_seconds: first.run.seconds,
            ..second.run
        });
    }
    let (wall, cpu) = (how.timeout.as_secs(), how.sandbox.cpu_limit());
    Ok(Run {
        status: Status::NotGraded,
        output: format!(
            "Exercise {} — `{}` was not graded: its test was stopped at the grader's time limit twice ({wall} s, then {} s of wall-clock time; {cpu}, then {} CPU seconds). The student's code runs within an instruction budget of its own, so this is the grader's limit — a loaded machine, or checks slow on what the code returned — and no mark of the code: grade again with a longer --timeout.",
            info.id,
            info.function,
            2 * wall,
            2 * cpu
        ),
        seconds,
        stopped_seconds: seconds,
        ..second.run
    })
}

/// One run of an exercise, and whether it was stopped at the grader's time limits.
struct Attempt {
    run: Run,
    stopped: bool,
}

/// Runs exercise `info`'s test once, with `scale` times the time limits.
fn attempt(
    how: &ExerciseRun,
    test: &str,
    info: &ExerciseInfo,
    scale: u32,
) -> Result<Attempt, Error> {
    fs::create_dir_all(how.scratch).map_err(io(how.scratch))?;
    // The module beside the exercise's files, which the program in the sandbox sees.
    let extension = how.module.extension().unwrap_or_default().to_string_lossy();
    let module = format!("student.{extension}");
    crate::handout::copy_file(how.module, &how.scratch.join(&module))?;
    // The lab's data as `lab/` of the exercise's directory: every path the program names is
    // relative to it, and no message names a place of this machine.
    let lab_link = how.scratch.join(LAB_LINK);
    std::os::unix::fs::symlink(how.lab_dir, &lab_link).map_err(io(&lab_link))?;
    how.sandbox.give_scratch(how.scratch)?;
    let secret = verdict::new_secret().map_err(io(Path::new("/dev/urandom")))?;
    // The grader's thread count, when it sets one, is the checks' too (a test of many cores).
    let threads = std::env::var("RAYON_NUM_THREADS").ok();
    let mut env = vec![
        // glibc reserves 64 MiB of address space for each malloc arena, one per thread up to
        // eight per core: at 32 rendering threads that alone is 2 GiB of the address-space
        // limit. Two arenas bound it whatever the thread count.
        ("MALLOC_ARENA_MAX", "2"),
        ("CARGO_TARGET_DIR", "."),
        ("RUST_BACKTRACE", "0"),
        (verdict::CHANNEL_VAR, "stdin"),
        (grading::graded::MODULE_VAR, module.as_str()),
        (grading::graded::LAB_DIR_VAR, LAB_LINK),
    ];
    if let Some(threads) = &threads {
        env.push(("RAYON_NUM_THREADS", threads));
    }
    let command = how.sandbox.exercise(
        how.executable,
        how.lab_dir,
        how.scratch,
        &[test, "--exact", "--nocapture", "--test-threads=1"],
        &env,
        how.sandbox.cpu_limit() * u64::from(scale),
    );
    let timeout = how.timeout * scale;
    let run = run_captured(command, Some(&secret), timeout, OUTPUT_LIMIT);
    how.sandbox.end_exercise();
    let run = run?;
    let images = failure_images(
        &how.scratch
            .join("raylab-failures")
            .join(format!("{}", info.lab)),
    );
    let record = run.scanner.as_ref().and_then(|s| s.record(&info.id));
    let printed = printable(&run.text());
    let stopped = record.is_none()
        && run.status.is_none_or(|exit| {
            use std::os::unix::process::ExitStatusExt;
            exit.signal() == Some(libc::SIGXCPU) || exit.code() == Some(128 + libc::SIGXCPU)
        });
    let (status, output) = match (&record, run.status) {
        (_, None) => (
            Status::TimedOut,
            format!(
                "Exercise {} — `{}` did not finish within {} s and was stopped.",
                info.id,
                info.function,
                timeout.as_secs()
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
    Ok(Attempt {
        run: Run {
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
            stopped_seconds: if stopped { run.seconds } else { 0.0 },
            key_for: record.map(|r| r.key_for.clone()).unwrap_or_default(),
        },
        stopped,
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
}
