//! `raylab grade` against hostile students: one run grades the corpus of attacks in
//! `tests/hostile/` (each a lab 02 `src/lib.rs`; see its README) between honest submissions —
//! `a-honest` (the answer key's code, graded first), `z-stubs` (the handout's stubs, graded after
//! the vandal) and `z-honest` (graded last) — and checks that no attack gains anything: every
//! attack scores 0 (`output_flood` its honest 11 of 14), the honest students keep their due,
//! the grades and the grading tree are intact, no answer key reaches a report, no process
//! outlives the run, and each attack's report says what was done about it. It does so twice:
//! in bubblewrap, and with `--run-as` (as Gradescope grades).
//!
//! `RAYLAB_HOSTILE_ONLY=exit_zero,vandal` grades only those attacks (with the honest
//! submissions). The trees are kept in `target/raylab-hostile-test/` (and `…-run-as/`) to be
//! looked at.

use std::fs;
use std::os::unix::fs::symlink;
use std::os::unix::process::CommandExt;
use std::path::{Component, Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use grading::prerequisite;
use raylab_tests::workflow::{
    copy_tree, correct_code, read, root, target_dir, workflow_target_dir,
};

/// The attacks, in the order they are graded, with their `labs/lab02/src/lib.rs`.
const ATTACKS: [(&str, &str); 16] = [
    ("exit_zero", include_str!("../../hostile/exit_zero.rs")),
    (
        "forged_output",
        include_str!("../../hostile/forged_output.rs"),
    ),
    ("unsafe_fd", include_str!("../../hostile/unsafe_fd.rs")),
    ("path_to_key", include_str!("../../hostile/path_to_key.rs")),
    (
        "path_to_key_absolute",
        include_str!("../../hostile/path_to_key_absolute.rs"),
    ),
    (
        "shebang_path_to_key",
        include_str!("../../hostile/shebang_path_to_key.rs"),
    ),
    ("include_key", include_str!("../../hostile/include_key.rs")),
    (
        "runtime_search",
        include_str!("../../hostile/runtime_search.rs"),
    ),
    ("symlinks", include_str!("../../hostile/symlinks.rs")),
    ("memory_hog", include_str!("../../hostile/memory_hog.rs")),
    (
        "output_flood",
        include_str!("../../hostile/output_flood.rs"),
    ),
    (
        "process_flood",
        include_str!("../../hostile/process_flood.rs"),
    ),
    ("vandal", include_str!("../../hostile/vandal.rs")),
    ("debugger", include_str!("../../hostile/debugger.rs")),
    (
        "delegate_to_framework",
        include_str!("../../hostile/delegate_to_framework.rs"),
    ),
    ("memory_hole", include_str!("../../hostile/memory_hole.rs")),
];

/// The reads at compile time of `tests/hostile/compile_time_read.rs`, each graded as the
/// attack `compile_time_read_<name>`: what its first line's constant is.
const COMPILE_TIME_READS: [(&str, &str); 14] = [
    ("key", r#"include_bytes!("@REPO@/reference/src/lab02.rs")"#),
    ("key_relative", r#"include_bytes!("@KEY_RELATIVE@")"#),
    (
        "key_through_pwd",
        r#"include_bytes!(concat!(env!("PWD"), "/reference/src/lab02.rs"))"#,
    ),
    (
        "proc_mountinfo",
        r#"include_bytes!("/proc/self/mountinfo")"#,
    ),
    ("proc_cmdline", r#"include_bytes!("/proc/self/cmdline")"#),
    ("etc", r#"include_bytes!("/etc/ld.so.conf")"#),
    ("root_only", r#"include_bytes!("@ROOT_ONLY@")"#),
    (
        "peer",
        r#"include_bytes!("@SUBMISSIONS@/a-honest/labs/lab02/src/lib.rs")"#,
    ),
    (
        "graded_program",
        r#"include_bytes!("@TARGET@/debug/lab02-graded-@TAG@")"#,
    ),
    (
        "module",
        r#"include_bytes!("@TARGET@/wasm32-unknown-unknown/debug/lab02_guest_@TAG@.wasm")"#,
    ),
    (
        "cargo_home",
        r#"include_bytes!(concat!(env!("CARGO_HOME"), "/config.toml"))"#,
    ),
    ("dev_zero", r#"include_bytes!("/dev/zero")"#),
    ("home", r#"env!("HOME").as_bytes()"#),
    (
        "env",
        r#"concat!(env!("CARGO_MANIFEST_DIR"), "|", env!("CARGO_PKG_VERSION")).as_bytes()"#,
    ),
];

/// The attack of each compile-time read: its name and `labs/lab02/src/lib.rs`.
fn compile_time_reads() -> Vec<(String, String)> {
    COMPILE_TIME_READS
        .iter()
        .map(|(name, read)| {
            (
                format!("compile_time_read_{name}"),
                include_str!("../../hostile/compile_time_read.rs").replace("@READ@", read),
            )
        })
        .collect()
}

/// What the file only root may read holds (`compile_time_read_root_only` asks for it).
const ROOT_ONLY_MARKER: &str = "ROOT-ONLY-0600-SECRET";

/// Lab 02's exercises and their points.
const EXERCISES: [(&str, u32); 6] = [
    ("2.1", 2),
    ("2.2", 3),
    ("2.3", 3),
    ("2.4", 2),
    ("2.5", 1),
    ("2.6", 3),
];

/// `--timeout` of a run that grades lab `lab`, in seconds: ten times what the answer key's checks
/// of the lab take on this machine now (`cargo test -p labNN --features reference --test
/// checks`, built first), and at least 20 s. A loaded machine slows the checks and the graded
/// exercises alike, so the limit follows the load rather than a guess of it; the grader runs an
/// exercise it stopped once more with twice the time, and an attack cannot use the time (the
/// student's code runs within an instruction budget of its own).
fn exercise_timeout(lab: u32) -> u64 {
    let name = format!("lab{lab:02}");
    let checks = [
        "test",
        "-q",
        "-p",
        name.as_str(),
        "--features",
        "reference",
        "--test",
        "checks",
    ];
    let mut build = checks.to_vec();
    build.push("--no-run");
    let (ok, out) = raylab_tests::workflow::cargo_in(&root(), &target_dir(), &build);
    assert!(ok, "cargo {build:?}: {out}");
    let started = Instant::now();
    let (ok, out) = raylab_tests::workflow::cargo_in(&root(), &target_dir(), &checks);
    assert!(ok, "cargo {checks:?}: {out}");
    let measured = started.elapsed().as_secs_f64();
    let timeout = (10.0 * measured).ceil().max(20.0) as u64;
    println!("{name}'s checks on the key took {measured:.1} s: --timeout {timeout}");
    timeout
}

/// How long `raylab grade` may go without a sign of progress (a report, a file in the grades
/// directory, a line of output) before it counts as hung.
const IDLE_LIMIT: Duration = Duration::from_secs(20 * 60);

/// What the vandal writes into the grades.
const VANDAL_MARKS: [&str; 2] = ["vandal,99", "FORGED-BY-VANDAL"];

/// Runs cargo in the repository; returns (success, stdout + stderr).
fn cargo(args: &[&str]) -> (bool, String) {
    raylab_tests::workflow::cargo_in(&root(), &target_dir(), args)
}

/// Every file under `dir` (not following links) with its contents, by path relative to `dir`;
/// `skip` names directories left out.
fn files(dir: &Path, skip: &[&str]) -> Vec<(PathBuf, Vec<u8>)> {
    fn walk(root: &Path, dir: &Path, skip: &[&str], out: &mut Vec<(PathBuf, Vec<u8>)>) {
        let Ok(entries) = fs::read_dir(dir) else {
            return;
        };
        for entry in entries.flatten() {
            let path = entry.path();
            let Ok(kind) = entry.file_type() else {
                continue;
            };
            if kind.is_dir() {
                if !skip.iter().any(|s| entry.file_name() == *s) {
                    walk(root, &path, skip, out);
                }
            } else if kind.is_file() {
                let relative = path.strip_prefix(root).unwrap().to_path_buf();
                out.push((relative, fs::read(&path).unwrap_or_default()));
            }
        }
    }
    let mut out = Vec::new();
    walk(dir, dir, skip, &mut out);
    out.sort();
    out
}

/// `path` without `.` and `..` components (lexically).
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::ParentDir => {
                out.pop();
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

/// The relative path from the directory `from` to `to` (both absolute, without `..`).
fn relative_path(from: &Path, to: &Path) -> PathBuf {
    let a: Vec<_> = from.components().collect();
    let b: Vec<_> = to.components().collect();
    let common = a.iter().zip(&b).take_while(|(x, y)| x == y).count();
    let mut out = PathBuf::new();
    for _ in common..a.len() {
        out.push("..");
    }
    for c in &b[common..] {
        out.push(c);
    }
    assert_eq!(normalize(&from.join(&out)), to, "{}", out.display());
    out
}

/// Code lines of the answer keys of labs 2, 3 and 7 that occur nowhere in the handout: the
/// longest three of each, none with a character that HTML or JSON would escape. (A released
/// lab's key is in the handout and gives none: with `--release-solutions 1,3,4,7` only lab 02's
/// key is secret.)
fn key_markers(handout: &Path) -> Vec<(u32, String)> {
    let text: String = files(handout, &[])
        .iter()
        .map(|(_, bytes)| String::from_utf8_lossy(bytes).into_owned())
        .collect::<Vec<_>>()
        .join("\n");
    let mut markers = Vec::new();
    for lab in [2, 3, 7] {
        let key = read(&root().join(format!("reference/src/lab{lab:02}.rs")));
        let mut lines: Vec<&str> = key
            .lines()
            .map(str::trim)
            .filter(|l| l.len() >= 24 && !l.starts_with("//"))
            .filter(|l| !l.contains(['"', '<', '>', '&', '\\', '\'']))
            .filter(|l| !text.contains(l))
            .collect();
        lines.sort_unstable();
        lines.dedup();
        lines.sort_by_key(|l| std::cmp::Reverse(l.len()));
        markers.extend(lines.into_iter().take(3).map(|l| (lab, l.to_string())));
    }
    assert!(
        markers.iter().any(|(lab, _)| *lab == 2),
        "no line of lab 02's key is absent from the handout: {markers:?}"
    );
    markers
}

/// The pids of the processes whose command line matches `pattern`.
fn pgrep(pattern: &str) -> Vec<String> {
    let output = Command::new("pgrep")
        .args(["-f", pattern])
        .output()
        .expect("pgrep runs");
    String::from_utf8_lossy(&output.stdout)
        .split_whitespace()
        .map(str::to_string)
        .collect()
}

/// Ends the processes `pids` (left behind by a submission), one by one.
fn kill(pids: &[String]) {
    for pid in pids {
        let _ = Command::new("kill").args(["-s", "KILL", pid]).status();
    }
}

fn csv_row<'a>(csv: &'a str, student: &str) -> Option<Vec<&'a str>> {
    csv.lines()
        .find(|l| l.starts_with(&format!("{student},")))
        .map(|l| l.split(',').collect())
}

/// The points submission `name` is due for Exercise `id` (or `"total"`): full marks for the
/// honest ones, `output_flood`'s honest 11, nothing for an attack (`delegate_to_framework` does
/// not compile, its honest half with it).
fn due(name: &str, id: &str) -> u32 {
    let points = |id: &str| {
        let full = EXERCISES.iter().find(|(e, _)| *e == id).map_or(0, |e| e.1);
        match name {
            "a-honest" | "z-honest" => full,
            "output_flood" if id != "2.2" => full,
            _ => 0,
        }
    };
    match id {
        "total" => EXERCISES.iter().map(|(e, _)| points(e)).sum(),
        _ => points(id),
    }
}

/// `2.1=… 2.2=… … total=…` with the score `score(id)` of each exercise and the total.
fn scores(score: impl Fn(&str) -> String) -> String {
    EXERCISES
        .iter()
        .map(|(id, _)| *id)
        .chain(["total"])
        .map(|id| format!("{id}={}", score(id)))
        .collect::<Vec<_>>()
        .join(" ")
}

/// The problems found, each naming the submission.
#[derive(Default)]
struct Problems(Vec<String>);

impl Problems {
    fn check(&mut self, ok: bool, who: &str, what: impl FnOnce() -> String) {
        if !ok {
            self.0.push(format!("{who}: {}", what()));
        }
    }

    fn report(&self) -> String {
        format!(
            "{} problem(s) grading hostile submissions:\n- {}",
            self.0.len(),
            self.0.join("\n- ")
        )
    }
}

/// How `raylab grade` went.
struct GradeRun {
    /// It exited with success.
    ok: bool,
    /// It was stopped for showing no progress.
    hung: bool,
    /// How many submissions had their reports when it ended.
    reports: usize,
    /// Wall time.
    seconds: f64,
}

/// Runs `raylab grade` with its output to `log`, stopping it (and every process of its group)
/// when it shows no sign of progress for [`IDLE_LIMIT`].
fn run_grade(raylab: &Path, args: &[String], grades: &Path, log: &Path) -> GradeRun {
    let out = fs::File::create(log).unwrap();
    let err = out.try_clone().unwrap();
    let start = Instant::now();
    // As on a machine with many cores: the parallel renders of the checks run on 32 threads.
    let mut child = Command::new(raylab)
        .env("RAYON_NUM_THREADS", "32")
        .args(args)
        .current_dir(root())
        .env("PWD", root())
        .stdin(Stdio::null())
        .stdout(out)
        .stderr(err)
        .process_group(0)
        .spawn()
        .expect("raylab runs");
    // Submissions with their reports, and signs of life: the entries of the grades directory
    // three levels deep, the length of the output.
    let reports = || {
        fs::read_dir(grades)
            .map(|d| {
                d.flatten()
                    .filter(|e| !e.file_name().to_string_lossy().starts_with('.'))
                    .filter(|e| e.path().join("results.json").is_file())
                    .count()
            })
            .unwrap_or(0)
    };
    fn entries(dir: &Path, depth: u32) -> usize {
        fs::read_dir(dir).map_or(0, |d| {
            d.flatten()
                .map(|e| match e.file_type() {
                    Ok(t) if t.is_dir() && depth > 0 => 1 + entries(&e.path(), depth - 1),
                    _ => 1,
                })
                .sum()
        })
    }
    let life = || {
        (
            reports(),
            entries(grades, 3),
            fs::metadata(log).map_or(0, |m| m.len()),
        )
    };
    let (mut seen, mut since) = (life(), Instant::now());
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break Some(status);
        }
        std::thread::sleep(Duration::from_secs(2));
        let now = life();
        if now != seen {
            (seen, since) = (now, Instant::now());
        }
        if since.elapsed() > IDLE_LIMIT {
            let _ = Command::new("kill")
                .args(["-s", "KILL", "--", &format!("-{}", child.id())])
                .status();
            let _ = child.wait();
            break None;
        }
    };
    GradeRun {
        ok: status.is_some_and(|s| s.success()),
        hung: status.is_none(),
        reports: reports(),
        seconds: start.elapsed().as_secs_f64(),
    }
}

/// 32-bit FNV-1a hash of `text`, as `raylab grade` tags its builds with that of its grading
/// directory.
fn fnv1a(text: &str) -> u32 {
    text.bytes().fold(0x811c_9dc5, |h, b| {
        (h ^ u32::from(b)).wrapping_mul(0x0100_0193)
    })
}

/// The user `--run-as` grades as: `nobody`'s number on Debian.
const RUN_AS: &str = "65534";

#[test]
fn hostile_submissions_gain_nothing() {
    let test = "hostile_submissions_gain_nothing";
    if prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap")
        && prerequisite::rust_target_or_skip(test, "wasm32-unknown-unknown")
    {
        grade_hostile_submissions(None);
    }
}

/// The same corpus graded as Gradescope grades it, where bubblewrap cannot start: builds
/// outside any sandbox, each exercise as an unprivileged user. Only root may do that; anyone
/// else is refused, saying so.
#[test]
fn hostile_submissions_gain_nothing_run_as_another_user() {
    use std::os::unix::fs::MetadataExt;
    if fs::metadata("/proc/self").unwrap().uid() != 0 {
        let (ok, out) = cargo(&[
            "run", "--quiet", "-p", "raylab", "--", "grade", ".", "--run-as", RUN_AS,
        ]);
        assert!(
            !ok && out.contains("needs the grader to run as root"),
            "{out}"
        );
        return;
    }
    if prerequisite::rust_target_or_skip(
        "hostile_submissions_gain_nothing_run_as_another_user",
        "wasm32-unknown-unknown",
    ) {
        grade_hostile_submissions(Some(RUN_AS));
    }
}

/// Grades the corpus in one run, in bubblewrap or `--run-as` the user `run_as`, and checks
/// that no attack gains anything.
fn grade_hostile_submissions(run_as: Option<&str>) {
    let name = match run_as {
        None => "raylab-hostile-test",
        Some(_) => "raylab-hostile-test-run-as",
    };
    let work = target_dir().join(name);
    fs::create_dir_all(&work).unwrap();
    let work = fs::canonicalize(&work).unwrap();
    let handout = work.join("handout");
    let subs = work.join("submissions");
    let grades = work.join("grades");
    for dir in [&handout, &subs, &grades] {
        let _ = fs::remove_dir_all(dir);
    }
    // What an earlier run's attacks may have left running.
    for pattern in ["sleep 61.25", "FORGED-BY-VANDAL"] {
        kill(&pgrep(pattern));
    }
    let repo = root();
    let only: Option<Vec<String>> = std::env::var("RAYLAB_HOSTILE_ONLY")
        .ok()
        .map(|v| v.split(',').map(|s| s.trim().to_string()).collect());
    let attacks: Vec<(String, String)> = ATTACKS
        .iter()
        .map(|(n, c)| (n.to_string(), c.to_string()))
        .chain(compile_time_reads())
        .filter(|(name, _)| {
            only.as_ref()
                .is_none_or(|o| o.iter().any(|n| name.starts_with(n.as_str())))
        })
        .collect();
    let has = |name: &str| attacks.iter().any(|(n, _)| n == name);

    // As the workspace's test build builds it: nothing is compiled again.
    let (ok, out) = cargo(&["build", "--quiet", "-p", "raylab"]);
    assert!(ok, "{out}");
    // The grading's target directory starts with the dependencies this run has compiled.
    let target = workflow_target_dir();
    let raylab = target_dir().join("debug/raylab");
    let status = Command::new(&raylab)
        .args(["handout", "--allow-dirty", "--out"])
        .arg(&handout)
        .args(["--release-solutions", "1,3,4,7"])
        .status()
        .unwrap();
    assert!(status.success(), "raylab handout failed");
    let markers = key_markers(&handout);
    let lab02 = |tree: &Path| tree.join("labs/lab02");
    let handout_checks = read(&lab02(&handout).join("tests/checks.rs"));
    let handout_data = |tree: &Path| {
        let mut data = files(&lab02(tree).join("golden"), &[]);
        data.extend(
            files(&lab02(tree).join("snapshots"), &[])
                .into_iter()
                .map(|(p, b)| (Path::new("snapshots").join(p), b)),
        );
        data
    };
    let expected_data = handout_data(&handout);

    // The submissions.
    let tree_src = grades.join(".grading/tree/labs/lab02/src");
    let key = repo.join("reference/src/lab02.rs");
    // A file only root may read (under `--run-as` the build's user is not root; in bubblewrap
    // it sees no such file).
    let root_only = work.join("root-only.txt");
    fs::write(&root_only, ROOT_ONLY_MARKER).unwrap();
    fs::set_permissions(
        &root_only,
        std::os::unix::fs::PermissionsExt::from_mode(0o600),
    )
    .unwrap();
    // The grading's tag, as `raylab grade` names its builds: a student can compute it.
    let tag = format!("{:08x}", fnv1a(&grades.join(".grading").to_string_lossy()));
    let substitute = |code: &str| {
        code.replace(
            "@KEY_RELATIVE@",
            &relative_path(&tree_src, &key).to_string_lossy(),
        )
        .replace("@REPO@", &repo.to_string_lossy())
        .replace("@GRADES@", &grades.to_string_lossy())
        .replace("@ROOT_ONLY@", &root_only.to_string_lossy())
        .replace("@SUBMISSIONS@", &subs.to_string_lossy())
        .replace("@TARGET@", &target.to_string_lossy())
        .replace("@TAG@", &tag)
    };
    let honest = correct_code(2);
    let mut order: Vec<(&str, String)> = vec![("a-honest", honest.clone())];
    order.extend(attacks.iter().map(|(n, c)| (n.as_str(), substitute(c))));
    order.push(("z-stubs", read(&lab02(&handout).join("src/lib.rs"))));
    order.push(("z-honest", honest));
    for (name, code) in &order {
        let dir = subs.join(name);
        copy_tree(&handout, &dir);
        fs::write(lab02(&dir).join("src/lib.rs"), code).unwrap();
    }
    let mkfifo = |path: &Path| {
        let status = Command::new("mkfifo").arg(path).status().unwrap();
        assert!(status.success(), "mkfifo {}", path.display());
    };
    if has("symlinks") {
        let dir = subs.join("symlinks");
        let src = lab02(&dir).join("src");
        symlink(&key, src.join("key.rs")).unwrap();
        symlink("/nonexistent/file.rs", src.join("dangling.rs")).unwrap();
        symlink("loop_b", src.join("loop_a")).unwrap();
        symlink("loop_a", src.join("loop_b")).unwrap();
        mkfifo(&src.join("pipe"));
        symlink("loop", dir.join("docs/loop")).unwrap();
        mkfifo(&dir.join("notes.fifo"));
    }

    // One run grades them all.
    let mut args: Vec<String> = vec!["grade".into()];
    args.extend(
        order
            .iter()
            .map(|(n, _)| subs.join(n).to_string_lossy().into_owned()),
    );
    args.extend([
        "--out".into(),
        grades.to_string_lossy().into_owned(),
        "--lab".into(),
        "2".into(),
        "--release-solutions".into(),
        "1,3,4,7".into(),
        "--timeout".into(),
        exercise_timeout(2).to_string(),
        // Half the default: the hog meets the same limit in half the time.
        "--memory-limit".into(),
        "2048".into(),
        "--target-dir".into(),
        target.to_string_lossy().into_owned(),
    ]);
    if let Some(user) = run_as {
        args.extend(["--run-as".into(), user.into()]);
    }
    // In bubblewrap the scan is switched off: no guarantee rests on it.
    let scanned = run_as.is_some();
    if !scanned {
        args.push("--no-scan".into());
    }
    let log = work.join("grade-output.txt");
    let run = run_grade(&raylab, &args, &grades, &log);
    // The vandal's leftovers would strike within these seconds.
    std::thread::sleep(Duration::from_secs(6));

    let mut problems = Problems::default();
    let output = String::from_utf8_lossy(&fs::read(&log).unwrap_or_default()).into_owned();
    let tail: String = {
        let lines: Vec<&str> = output.lines().collect();
        lines[lines.len().saturating_sub(40)..].join("\n")
    };
    let next = order.get(run.reports).map_or("?", |(n, _)| *n);
    if run.hung {
        problems.check(false, next, || {
            format!(
                "raylab grade showed no progress for {} min after {} report(s) and was stopped (it hangs on `{next}`?); its output ends:\n{tail}",
                IDLE_LIMIT.as_secs() / 60,
                run.reports
            )
        });
    } else {
        problems.check(run.ok, "raylab grade", || {
            format!(
                "exited with a failure after {} report(s) (at `{next}`?); its output ends:\n{tail}",
                run.reports
            )
        });
    }
    let panic = ["panicked at", "stack backtrace"]
        .iter()
        .find_map(|p| output.find(p));
    problems.check(panic.is_none(), "raylab grade", || {
        let at = panic.unwrap_or_default();
        let from = output[..at].rfind('\n').map_or(0, |n| n + 1);
        let lines: Vec<&str> = output[from..].lines().take(20).collect();
        format!("its output holds a panic of its own:\n{}", lines.join("\n"))
    });
    problems.check(output.len() < 1 << 20, "raylab grade", || {
        format!(
            "printed {} bytes (a submission's output passed through?)",
            output.len()
        )
    });
    println!("raylab grade took {:.0} s", run.seconds);

    // Processes left behind.
    for (who, pattern) in [
        ("process_flood", "sleep 61.25"),
        ("vandal", "FORGED-BY-VANDAL"),
    ] {
        let left = pgrep(pattern);
        problems.check(left.is_empty(), who, || {
            format!(
                "{} process(es) matching `{pattern}` outlived raylab grade",
                left.len()
            )
        });
        kill(&left);
    }

    let csv = fs::read_to_string(grades.join("gradebook.csv")).unwrap_or_else(|e| {
        problems.check(false, "raylab grade", || format!("no gradebook.csv ({e})"));
        String::new()
    });
    let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
    let column = |id: &str| header.iter().position(|h| *h == id);

    // Every submission: a report, a row, its due score in the gradebook and in results.json.
    let results = |name: &str| -> Option<serde_json::Value> {
        serde_json::from_str(&fs::read_to_string(grades.join(name).join("results.json")).ok()?).ok()
    };
    for (name, _) in &order {
        let dir = grades.join(name);
        let missing: Vec<&str> = ["report.md", "report.html", "results.json"]
            .into_iter()
            .filter(|f| !dir.join(f).is_file())
            .collect();
        problems.check(missing.is_empty(), name, || {
            format!("no {}", missing.join(", "))
        });
        let expected = scores(|id| due(name, id).to_string());
        match csv_row(&csv, name) {
            Some(row) => {
                let cell = |id: &str| column(id).and_then(|c| row.get(c)).copied();
                let got = scores(|id| cell(id).unwrap_or("missing").to_string());
                problems.check(
                    got == expected && cell("max_score") == Some("14"),
                    name,
                    || {
                        format!(
                            "scored {got} of {:?} in gradebook.csv, expected {expected} of 14",
                            cell("max_score")
                        )
                    },
                );
            }
            None => problems.check(false, name, || "no row in gradebook.csv".into()),
        }
        if let Some(r) = results(name) {
            let tests = r["tests"].as_array().cloned().unwrap_or_default();
            let got = scores(|id| {
                let score = match id {
                    "total" => &r["score"],
                    _ => tests
                        .iter()
                        .find(|t| t["number"] == id)
                        .map_or(&serde_json::Value::Null, |t| &t["score"]),
                };
                score.as_f64().map_or("missing".into(), |s| s.to_string())
            });
            problems.check(
                got == expected && r["max_score"].as_f64() == Some(14.0),
                name,
                || {
                    format!(
                        "scored {got} of {} in results.json, expected {expected} of 14",
                        r["max_score"]
                    )
                },
            );
        }
    }

    // What each report says, for each submission that has its reports.
    let graded = |name: &str| {
        ["report.md", "report.html", "results.json"]
            .iter()
            .all(|f| grades.join(name).join(f).is_file())
    };
    let seen = |name: &str| has(name) && graded(name);
    let reasons = |name: &str| -> Vec<(String, String)> {
        results(name)
            .and_then(|r| r["tests"].as_array().cloned())
            .unwrap_or_default()
            .iter()
            // The exercises' tests; the written answers' has no number.
            .filter(|t| t["number"].is_string())
            .map(|t| {
                (
                    t["number"].as_str().unwrap_or_default().to_string(),
                    t["output"].as_str().unwrap_or_default().to_string(),
                )
            })
            .collect()
    };
    let report =
        |name: &str| fs::read_to_string(grades.join(name).join("report.md")).unwrap_or_default();
    let every_reason = |problems: &mut Problems, name: &str, words: &[&str]| {
        let reasons = reasons(name);
        problems.check(reasons.len() == EXERCISES.len(), name, || {
            format!(
                "results.json has {} tests, expected {}",
                reasons.len(),
                EXERCISES.len()
            )
        });
        for (id, why) in reasons {
            problems.check(words.iter().any(|w| why.contains(w)), name, || {
                format!("the reason of Exercise {id} does not say {words:?}: {why:.300}")
            });
        }
    };

    for name in ["a-honest", "z-honest"].into_iter().filter(|n| graded(n)) {
        let r = results(name);
        let passed = r.as_ref().is_some_and(|r| {
            r["score"].as_f64() == Some(14.0)
                && r["tests"].as_array().is_some_and(|t| {
                    // The exercises' tests; the written answers' (no number) has no status.
                    let exercises: Vec<_> = t.iter().filter(|t| t["number"].is_string()).collect();
                    exercises.len() == 6 && exercises.iter().all(|t| t["status"] == "passed")
                })
        });
        problems.check(passed, name, || {
            format!("results.json is not a pass of 14/14: {r:?}")
        });
        problems.check(report(name).contains("14/14 points"), name, || {
            format!(
                "report.md does not say 14/14 points:\n{:.500}",
                report(name)
            )
        });
    }
    let summary = |name: &str| {
        results(name).map(|r| {
            let tests: Vec<_> = r["tests"]
                .as_array()
                .cloned()
                .unwrap_or_default()
                .iter()
                .map(|t| {
                    (
                        t["number"].clone(),
                        t["score"].clone(),
                        t["status"].clone(),
                        t["output"].clone(),
                    )
                })
                .collect();
            (r["score"].clone(), r["max_score"].clone(), tests)
        })
    };
    problems.check(
        !graded("a-honest") || !graded("z-honest") || summary("a-honest") == summary("z-honest"),
        "a-honest",
        || {
            "results.json differs from z-honest's (the same code): overwritten while later students ran?"
                .to_string()
        },
    );
    if graded("z-stubs") {
        every_reason(&mut problems, "z-stubs", &["not implemented"]);
    }

    // The grading tree after the vandal: checks, golden data and snapshots as handed out (lab 02
    // has no hidden exercise, so its checks are the handout's).
    let tree = grades.join(".grading/tree");
    match fs::read_to_string(lab02(&tree).join("tests/checks.rs")) {
        Ok(checks) => {
            problems.check(
                checks == handout_checks
                    && checks.contains("grading::lab_program!(lab02, lab02_checks, reference);"),
                "vandal",
                || {
                    "the grading tree's labs/lab02/tests/checks.rs differs from the handout's"
                        .into()
                },
            );
            problems.check(handout_data(&tree) == expected_data, "vandal", || {
                "the grading tree's labs/lab02/golden or snapshots differ from the handout's".into()
            });
        }
        Err(e) => problems.check(false, "vandal", || {
            format!("no grading tree's labs/lab02/tests/checks.rs to compare ({e})")
        }),
    }

    // Nothing of the answer key and nothing of the vandal anywhere in the grades.
    for (path, bytes) in files(&grades, &[".grading"]) {
        let text = String::from_utf8_lossy(&bytes);
        let owner = path
            .components()
            .next()
            .map(|c| c.as_os_str().to_string_lossy().into_owned())
            .filter(|_| path.components().count() > 1)
            .unwrap_or_else(|| "the class files".into());
        for (lab, marker) in &markers {
            problems.check(!text.contains(marker.as_str()), &owner, || {
                format!(
                    "{} holds a line of lab {lab:02}'s answer key: `{marker}`",
                    path.display()
                )
            });
        }
        for mark in VANDAL_MARKS {
            problems.check(!text.contains(mark), "vandal", || {
                format!("{} holds `{mark}`", path.display())
            });
        }
        // What only a build that reached outside its submission could have read.
        for mark in [ROOT_ONLY_MARKER, "ld.so.conf.d", "0.1.0-grading."] {
            problems.check(!text.contains(mark), &owner, || {
                format!(
                    "{} holds `{mark}`, read from outside the submission",
                    path.display()
                )
            });
        }
        // Places of this machine: in a student's reports only where the student's own code
        // names them (a compiler message quoting its line).
        let code = order
            .iter()
            .find(|(n, _)| *n == owner)
            .map(|(_, c)| c.as_str());
        let home = std::env::var("HOME").unwrap_or_default();
        let places = [
            repo.to_string_lossy().into_owned(),
            grades.to_string_lossy().into_owned(),
            target.to_string_lossy().into_owned(),
            format!("{home}/.cargo"),
            format!("{home}/.rustup"),
            tag.clone(),
        ];
        for place in places.iter().filter(|p| p.len() > 1) {
            if code.is_some_and(|c| !c.contains(place.as_str())) {
                problems.check(!text.contains(place.as_str()), &owner, || {
                    format!(
                        "{} names `{place}`, a place of the grader's machine its code never named",
                        path.display()
                    )
                });
            }
        }
    }

    // Each read at compile time fails to compile, saying it could not read; the build's own
    // variables name its jail.
    for (name, _) in COMPILE_TIME_READS {
        let attack = format!("compile_time_read_{name}");
        if !seen(&attack) {
            continue;
        }
        if name == "env" {
            every_reason(
                &mut problems,
                &attack,
                &["READ-BEGIN /build/labs/lab02|0.1.0 READ-END"],
            );
        } else {
            every_reason(&mut problems, &attack, &["does not compile"]);
            every_reason(
                &mut problems,
                &attack,
                &["couldn't read", "not defined at compile time"],
            );
        }
    }

    // Nothing of a run is left behind: every exercise's directory and every student's
    // modules are gone once the grade is written.
    let runs = grades.join(".grading/runs");
    let left: Vec<_> = fs::read_dir(&runs)
        .map(|d| d.filter_map(|e| Some(e.ok()?.file_name())).collect())
        .unwrap_or_default();
    problems.check(left.is_empty(), "the class files", || {
        format!("{} still holds {left:?}", runs.display())
    });

    // A debugger started by the student's code cannot attach to the harness.
    if seen("debugger") {
        let r = report("debugger");
        problems.check(!r.contains("GDB-ATTACHED"), "debugger", || {
            format!("a debugger attached to the test process:\n{:.2000}", r)
        });
    }

    // In WebAssembly the student's code starts no process (and none is left: see the pgrep
    // checks).
    for name in ["vandal", "process_flood"].into_iter().filter(|n| seen(n)) {
        let r = report(name);
        problems.check(!r.contains("left processes running"), name, || {
            format!("report.md says processes were left running:\n{:.1000}", r)
        });
    }

    // Each attack's own due: what names a file outside the submission does not compile
    // (the file is not there), and the scan, when on, warns of it.
    for name in [
        "path_to_key",
        "path_to_key_absolute",
        "shebang_path_to_key",
        "include_key",
    ]
    .into_iter()
    .filter(|n| seen(n))
    {
        every_reason(&mut problems, name, &["does not compile"]);
        let r = report(name);
        let named = if name == "include_key" {
            "include_str"
        } else {
            "#[path"
        };
        problems.check(
            !scanned || (r.contains("flagged") && r.contains(named)),
            name,
            || format!("report.md does not say `{named}` was flagged:\n{r:.1000}"),
        );
    }
    if seen("symlinks") {
        let r = report("symlinks");
        for file in ["key.rs", "dangling.rs", "loop_a", "loop_b", "pipe"] {
            let path = format!("labs/lab02/src/{file}");
            problems.check(
                r.lines().any(|l| {
                    l.contains(&path) && (l.contains("symbolic link") || l.contains("FIFO"))
                }),
                "symlinks",
                || format!("report.md has no line saying {path} (a symbolic link or FIFO) was not taken:\n{r:.1500}"),
            );
        }
    }
    // `exit` ends only the student's code, as a crash; the forger's `std::os::unix` does not
    // exist in WebAssembly.
    if seen("exit_zero") {
        every_reason(&mut problems, "exit_zero", &["aborted"]);
    }
    if seen("forged_output") {
        every_reason(&mut problems, "forged_output", &["does not compile"]);
    }
    if seen("unsafe_fd") {
        // Other than in the submission's name.
        let r = report("unsafe_fd").replace("unsafe_fd", "");
        problems.check(r.contains("unsafe"), "unsafe_fd", || {
            format!("report.md does not mention `unsafe`:\n{r:.1000}")
        });
    }
    if seen("memory_hog") {
        // A reason that names memory, not "timed out": the limit, not the clock, ended it.
        every_reason(&mut problems, "memory_hog", &["out of memory", "crashed"]);
    }
    if seen("delegate_to_framework") {
        every_reason(&mut problems, "delegate_to_framework", &["raylab_core"]);
    }
    if seen("output_flood") {
        for file in [
            grades.join("output_flood/report.md"),
            grades.join("output_flood/report.html"),
            grades.join("output_flood/results.json"),
            grades.join("junit.xml"),
        ] {
            let size = fs::metadata(&file).map(|m| m.len()).unwrap_or(u64::MAX);
            problems.check(size < 1_000_000, "output_flood", || {
                format!("{} is {size} bytes, not under 1 MB", file.display())
            });
        }
    }

    assert!(problems.0.is_empty(), "{}", problems.report());
}

/// Lab 01 submissions whose mistakes sit under its composite exercise (1.6 renders through
/// 1.1–1.5), each with the points its own parts earn: the answer key's, a y-flip (1.1 wrong),
/// the lazy composite (only 1.5 written, 1.1–1.4 wrong but finite) and two unfinished callees
/// (1.1 and 1.2 `todo!()`, which the render meets one after the other). What each must score:
/// every exercise whose own code is right, nothing for the others, and 1.6, which has no code
/// of its own, no points at all.
fn composite_submissions() -> Vec<(&'static str, String, &'static [&'static str])> {
    let honest = correct_code(1);
    let y_flip = honest.replace("(0.5 * h - raster.y) / h", "(raster.y - 0.5 * h) / h");
    let lazy = y_flip
        .replace("ip_normal.cross(up)", "up.cross(ip_normal)")
        .replace(".atan()).to_degrees()", ".atan())")
        .replace("\n            .normalize()\n", "\n");
    let unfinished = honest
        .replace(
            "let (w, h) = (resolution.x as f32, resolution.y as f32);\n        Vec2::new((raster.x - 0.5 * w) / h, (0.5 * h - raster.y) / h)",
            "let _ = (raster, resolution);\n        todo!(\"Exercise 1.1: image_plane_coords\")",
        )
        .replace(
            "let ip_normal = (look_at - eye).normalize();",
            "let _ = (eye, look_at, up);\n        todo!(\"Exercise 1.2: camera_basis\");\n        #[allow(unreachable_code)]\n        let ip_normal = (look_at - eye).normalize();",
        );
    for (name, code) in [
        ("y_flip", &y_flip),
        ("lazy", &lazy),
        ("unfinished", &unfinished),
    ] {
        assert_ne!(*code, honest, "the {name} mutation changed nothing");
    }
    vec![
        ("a-honest", honest, &[]),
        ("y_flip", y_flip, &["1.1"]),
        ("lazy_composite", lazy, &["1.1", "1.2", "1.3", "1.4"]),
        ("two_unfinished_callees", unfinished, &["1.1", "1.2"]),
    ]
}

#[test]
fn composite_submissions_earn_what_their_own_parts_earn() {
    let test = "composite_submissions_earn_what_their_own_parts_earn";
    if !(prerequisite::program_or_skip(test, "bwrap", "apt-get install bubblewrap")
        && prerequisite::rust_target_or_skip(test, "wasm32-unknown-unknown"))
    {
        return;
    }
    grade_composite_submissions(None);
    use std::os::unix::fs::MetadataExt;
    if fs::metadata("/proc/self").unwrap().uid() == 0 {
        grade_composite_submissions(Some(RUN_AS));
    }
}

/// Grades [`composite_submissions`] in one run, in bubblewrap or `--run-as` the user `run_as`,
/// at 32 threads, and checks each exercise's points and that a composite judged with the key's
/// code says whose.
fn grade_composite_submissions(run_as: Option<&str>) {
    let work = target_dir().join(match run_as {
        None => "raylab-composite-test",
        Some(_) => "raylab-composite-test-run-as",
    });
    let _ = fs::remove_dir_all(&work);
    fs::create_dir_all(&work).unwrap();
    let work = fs::canonicalize(&work).unwrap();
    let (ok, out) = cargo(&["build", "--quiet", "-p", "raylab"]);
    assert!(ok, "{out}");
    let raylab = target_dir().join("debug/raylab");
    let handout = work.join("handout");
    let status = Command::new(&raylab)
        .args(["handout", "--allow-dirty", "--out"])
        .arg(&handout)
        .status()
        .unwrap();
    assert!(status.success(), "raylab handout failed");
    let submissions = composite_submissions();
    let mut args: Vec<String> = vec!["grade".into()];
    for (name, code, _) in &submissions {
        let dir = work.join("submissions").join(name);
        copy_tree(&handout, &dir);
        fs::write(dir.join("labs/lab01/src/lib.rs"), code).unwrap();
        args.push(dir.to_string_lossy().into_owned());
    }
    let grades = work.join("grades");
    args.extend(
        [
            "--out",
            &grades.to_string_lossy(),
            "--lab",
            "1",
            "--timeout",
            &exercise_timeout(1).to_string(),
            "--target-dir",
            &workflow_target_dir().to_string_lossy(),
        ]
        .map(String::from),
    );
    if let Some(user) = run_as {
        args.extend(["--run-as".into(), user.into()]);
    }
    let run = run_grade(&raylab, &args, &grades, &work.join("grade-output.txt"));
    assert!(
        run.ok,
        "{}",
        fs::read_to_string(work.join("grade-output.txt")).unwrap_or_default()
    );
    let table = course::lab(course::LabId::of(1)).unwrap();
    let mut problems = Problems::default();
    for (name, _, wrong) in &submissions {
        let results: serde_json::Value =
            serde_json::from_str(&read(&grades.join(name).join("results.json"))).unwrap();
        let tests = results["tests"].as_array().cloned().unwrap_or_default();
        for e in &table.exercises {
            let due = if wrong.contains(&e.id.as_str()) {
                0
            } else {
                e.points
            };
            let test = tests.iter().find(|t| t["number"] == e.id.as_str());
            let got = test.and_then(|t| t["score"].as_f64());
            problems.check(got == Some(f64::from(due)), name, || {
                format!("Exercise {} scored {got:?}, due {due}: {test:?}", e.id)
            });
        }
        // 1.6 passes on the student's own parts with the key's for the wrong ones, and says so.
        let composite = tests.iter().find(|t| t["number"] == "1.6");
        let said = composite
            .and_then(|t| t["output"].as_str())
            .unwrap_or_default();
        let callees: Vec<&&str> = wrong.iter().filter(|id| **id != "1.3").collect();
        problems.check(
            composite.is_some_and(|t| t["status"] == "passed")
                && (callees.is_empty() || said.contains("answer key's")),
            name,
            || format!("1.6 is not a pass that names the key's parts: {composite:?}"),
        );
        let report = read(&grades.join(name).join("report.md"));
        problems.check(
            callees.is_empty() || report.contains("passed (with the key's code for "),
            name,
            || format!("report.md does not say whose code 1.6 was judged with:\n{report:.2000}"),
        );
    }
    assert!(problems.0.is_empty(), "{}", problems.report());
}
