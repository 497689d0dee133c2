//! Helpers of the end-to-end tests of the instructor's workflow (`handout`, `grade`): where the
//! repository and its target directory are, and submissions made from a handout.

use std::fs;
use std::path::{Path, PathBuf};

/// The repository's root.
pub fn root() -> PathBuf {
    fs::canonicalize(Path::new(env!("CARGO_MANIFEST_DIR")).join(".."))
        .expect("the repository exists")
}

/// Cargo's target directory of this test run.
pub fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| root().join("target"))
}

/// Runs cargo in `dir` with the target directory `target`; returns (success, stdout + stderr).
pub fn cargo_in(dir: &Path, target: &Path, args: &[&str]) -> (bool, String) {
    let output =
        std::process::Command::new(std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into()))
            .args(args)
            .current_dir(dir)
            .env("CARGO_TARGET_DIR", target)
            .output()
            .expect("cargo runs");
    (output.status.success(), output_text(&output))
}

/// What a finished process printed: its standard output, then its standard error.
pub fn output_text(output: &std::process::Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&output.stdout),
        String::from_utf8_lossy(&output.stderr)
    )
}

/// The text of `path`; panics naming it.
pub fn read(path: &Path) -> String {
    fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// The reference solution of lab `lab` as a student would hand it in: the answer key's code
/// with its type renamed to `Student` (lab 07 computes its own strata instead of calling lab 03).
pub fn correct_code(lab: u32) -> String {
    let code = read(&root().join(format!("reference/src/lab{lab:02}.rs")))
        .replace(&format!("Lab{lab:02}"), "Student");
    if lab != 7 {
        return code;
    }
    code.replace(
        "crate::lab03::Lab03.stratified_samples(subdivisions, rng)",
        "let n = subdivisions;\n        (0..n * n)\n            .map(|k| (Vec2::new((k % n) as f32, (k / n) as f32) + rng.next_vec2()) / n as f32)\n            .collect()",
    )
    .replace("use contracts::lab03::Shadows;\n", "")
}

/// Copies the directory `from` to `to`, leaving out `target/`, keeping every file's
/// modification time (see [`copy_with_dates`]).
pub fn copy_tree(from: &Path, to: &Path) {
    fs::create_dir_all(to).unwrap();
    for entry in fs::read_dir(from).unwrap() {
        let entry = entry.unwrap();
        if entry.file_name() != "target" {
            copy_with_dates(&entry.path(), &to.join(entry.file_name()));
        }
    }
}

/// Opens the HTML page `page` in headless Chromium (`/usr/bin/chromium`, Debian's `chromium`)
/// and checks what a reader would see: the page shows text, every image loads (decoded, with a
/// size) and every link within the page has its anchor. `Ok` holds what was checked, `Err`
/// what is wrong.
pub fn check_in_browser(page: &Path) -> Result<String, String> {
    let page = fs::canonicalize(page).map_err(|e| format!("{}: {e}", page.display()))?;
    let dir = page.parent().expect("a page is in a directory");
    let name = page.file_name().unwrap().to_string_lossy().into_owned();
    // A page beside the one checked loads it in a frame and reports on it when it has loaded.
    let checker = dir.join(format!(".browser-check-{}.html", std::process::id()));
    fs::write(
        &checker,
        format!(
            r##"<!doctype html><meta charset="utf-8"><body><iframe id="page" src="{name}"></iframe><script>
const frame = document.getElementById("page");
frame.addEventListener("load", () => setTimeout(() => {{
  const found = [];
  let doc = null;
  try {{ doc = frame.contentDocument; }} catch (e) {{ found.push("the page cannot be read: " + e); }}
  if (doc) {{
    if (!doc.body || doc.body.innerText.trim() === "") found.push("the page shows nothing");
    for (const img of doc.images) {{
      if (!(img.complete && img.naturalWidth > 0)) found.push("image not loaded: " + img.getAttribute("src"));
    }}
    const links = doc.querySelectorAll("a[href]");
    for (const a of links) {{
      const href = a.getAttribute("href");
      if (href.startsWith("#") && !doc.getElementById(decodeURIComponent(href.slice(1)))) found.push("no anchor for link " + href);
    }}
    found.push("checked: " + doc.images.length + " images, " + links.length + " links");
  }}
  const out = document.createElement("pre");
  out.id = "result";
  out.textContent = found.join("\n");
  document.body.appendChild(out);
}}, 100));
</script>"##
        ),
    )
    .map_err(|e| format!("{}: {e}", checker.display()))?;
    let profile = std::env::temp_dir().join(format!("raylab-chromium-{}", std::process::id()));
    let output = std::process::Command::new("chromium")
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--allow-file-access-from-files",
            "--virtual-time-budget=10000",
            "--dump-dom",
        ])
        .arg(format!("--user-data-dir={}", profile.display()))
        .arg(format!("file://{}", checker.display()))
        .output();
    let _ = fs::remove_file(&checker);
    let _ = fs::remove_dir_all(&profile);
    let output = output.map_err(|e| {
        format!("chromium: {e} (install Debian's chromium: apt-get install chromium)")
    })?;
    let dom = String::from_utf8_lossy(&output.stdout);
    let result = dom
        .split("<pre id=\"result\">")
        .nth(1)
        .and_then(|r| r.split("</pre>").next())
        .ok_or_else(|| {
            format!(
                "{name}: the browser did not finish the check:\n{dom}\n{}",
                String::from_utf8_lossy(&output.stderr)
            )
        })?;
    let problems: Vec<&str> = result
        .lines()
        .filter(|l| !l.starts_with("checked: "))
        .collect();
    if problems.is_empty() {
        Ok(result.to_string())
    } else {
        Err(format!("{name}: {}", problems.join("; ")))
    }
}

/// Starts the target directory `target` of another tree (a handout, a grading tree) with what
/// this test run's `debug` profile has compiled of the crates.io dependencies and of the
/// framework, copied with their file dates. Cargo judges them as it would its own: a
/// dependency is fresh there (its fingerprint does not depend on where the target directory
/// is), and so is the framework of a handout, which is the repository's, copied with its
/// dates, at the same place in its workspace; a tree whose framework differs (a grading
/// tree's has a version of its own) compiles its own. Units already in `target` are kept.
pub fn seed_target_dir(target: &Path) {
    // The workflow tests run side by side and seed one directory.
    static SEEDING: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let _one_at_a_time = SEEDING.lock().unwrap_or_else(|e| e.into_inner());
    let from = target_dir().join("debug");
    let to = target.join("debug");
    let lock = read(&root().join("Cargo.lock"));
    let mut seeded = Vec::new();
    for package in lock.split("[[package]]").skip(1) {
        let field = |key: &str| {
            package.lines().find_map(|l| {
                l.strip_prefix(key)
                    .and_then(|v| v.trim().strip_prefix('='))
                    .map(|v| v.trim().trim_matches('"').to_string())
            })
        };
        if let (Some(name), Some(source)) = (field("name "), field("source "))
            && source.starts_with("registry+")
        {
            seeded.push(name);
        }
    }
    // The framework's crates, by their manifests' names (`raylab-core`, `pipeline`, …).
    for entry in fs::read_dir(root().join("framework")).unwrap() {
        let manifest = entry.unwrap().path().join("Cargo.toml");
        if let Ok(text) = fs::read_to_string(&manifest)
            && let Some(name) = text.lines().find_map(|l| {
                l.strip_prefix("name = ")
                    .map(|v| v.trim().trim_matches('"').to_string())
            })
        {
            seeded.push(name);
        }
    }
    // A unit is `<package>-<16 hex digits>` (`libtest-mimic-…` is one), a library in `deps/`
    // `lib<crate>-<hash>.<ext>` with the crate name's dashes as underscores.
    let is_seeded = |file: &str| {
        let stem = file.split('.').next().unwrap_or(file);
        let Some((name, hash)) = stem.rsplit_once('-') else {
            return false;
        };
        let names = [Some(name), name.strip_prefix("lib")];
        hash.len() == 16
            && hash.bytes().all(|b| b.is_ascii_hexdigit())
            && seeded.iter().any(|s| {
                names
                    .iter()
                    .flatten()
                    .any(|n| s == n || s.replace('-', "_") == *n)
            })
    };
    for dir in [".fingerprint", "build", "deps"] {
        let Ok(entries) = fs::read_dir(from.join(dir)) else {
            continue;
        };
        fs::create_dir_all(to.join(dir)).unwrap();
        for entry in entries {
            let entry = entry.unwrap();
            let name = entry.file_name().to_string_lossy().into_owned();
            let dest = to.join(dir).join(&name);
            if is_seeded(&name) && !dest.exists() {
                copy_with_dates(&entry.path(), &dest);
            }
        }
    }
}

/// The target directory the workflow tests build their handouts and gradings in, seeded (see
/// [`seed_target_dir`]): the gradings' framework, the same in each, is compiled once for all.
pub fn workflow_target_dir() -> PathBuf {
    let dir = target_dir().join("raylab-workflow-target");
    seed_target_dir(&dir);
    dir
}

/// `raylab ARGS` run with `cargo run` in the tree `dir` (the repository, a handout or a clone)
/// with the target directory `target`; its output. A failure fails the test.
pub fn raylab_in(dir: &Path, target: &Path, args: &[&str]) -> String {
    let mut all = vec!["run", "--quiet", "-p", "raylab", "--"];
    all.extend_from_slice(args);
    let (ok, out) = cargo_in(dir, target, &all);
    assert!(ok, "raylab {args:?} in {}:\n{out}", dir.display());
    out
}

/// git in `dir` as a student with an identity of their own (no signing, no hooks), committing
/// at `date` (RFC 3339) when given; its standard output. A failure fails the test.
pub fn student_git(dir: &Path, args: &[&str], date: Option<&str>) -> String {
    let mut command = std::process::Command::new("git");
    command
        .args([
            "-c",
            "user.name=Student",
            "-c",
            "user.email=student@example.org",
        ])
        .args([
            "-c",
            "commit.gpgsign=false",
            "-c",
            "core.hooksPath=/dev/null",
        ])
        .args(args)
        .current_dir(dir);
    if let Some(date) = date {
        command
            .env("GIT_AUTHOR_DATE", date)
            .env("GIT_COMMITTER_DATE", date);
    }
    let out = command.output().expect("git runs");
    assert!(out.status.success(), "git {args:?}:\n{}", output_text(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// Copies the file or directory `from` to `to`, keeping every file's modification time (a link
/// is copied as what it points to).
fn copy_with_dates(from: &Path, to: &Path) {
    let meta = fs::metadata(from).unwrap();
    if meta.is_dir() {
        fs::create_dir_all(to).unwrap();
        for entry in fs::read_dir(from).unwrap() {
            let entry = entry.unwrap();
            copy_with_dates(&entry.path(), &to.join(entry.file_name()));
        }
    } else if meta.is_file() {
        fs::copy(from, to).unwrap();
        let file = fs::File::options().write(true).open(to).unwrap();
        file.set_modified(meta.modified().unwrap()).unwrap();
    }
}

/// `cargo metadata --no-deps` of the workspace: its JSON, for the tests of its manifests.
pub fn workspace_metadata() -> Vec<u8> {
    let cargo = std::env::var_os("CARGO").unwrap_or_else(|| "cargo".into());
    let output = std::process::Command::new(cargo)
        .args([
            "metadata",
            "--offline",
            "--no-deps",
            "--format-version",
            "1",
        ])
        .current_dir(root())
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    output.stdout
}
