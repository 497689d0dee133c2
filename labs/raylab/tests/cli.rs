//! The command line, end to end.

use std::path::{Path, PathBuf};
use std::process::Command;

fn raylab(args: &[&str], dir: &std::path::Path) -> (bool, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("raylab runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raylab-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn render_without_arguments_writes_the_default_scene_as_png() {
    let dir = scratch("default");
    let (ok, stdout, stderr) = raylab(&[], &dir);
    assert!(ok, "{stderr}");
    let path = dir.join(stdout.trim());
    let img = image::open(&path).expect("a PNG was written").to_rgb8();
    assert_eq!(img.dimensions(), (512, 384));
    // Not a blank image: the sky, the ground and the objects differ.
    let distinct: std::collections::HashSet<_> = img.pixels().map(|p| p.0).collect();
    assert!(
        distinct.len() > 100,
        "only {} distinct colours",
        distinct.len()
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_bare_obj_is_framed_and_lit_and_the_printed_path_is_absolute() {
    let dir = scratch("obj");
    std::fs::write(
        dir.join("quad.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n",
    )
    .unwrap();
    let (ok, stdout, stderr) = raylab(
        &[
            "render",
            "-s",
            "quad.obj",
            "--width",
            "32",
            "--height",
            "24",
            "-o",
            "new/q.png",
        ],
        &dir,
    );
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("note:") && stderr.contains("frames its bounds"),
        "{stderr}"
    );
    let path = PathBuf::from(stdout.trim());
    assert!(path.is_absolute(), "{}", path.display());
    let img = image::open(&path).expect("a PNG was written").to_rgb8();
    // The quad fills the middle of the image, lit from the eye: bright, not the black background.
    let centre = img.get_pixel(16, 12).0;
    assert!(centre.iter().all(|&c| c > 100), "{centre:?}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_scene_with_no_geometry_is_a_warning_naming_it() {
    let dir = scratch("empty");
    std::fs::write(
        dir.join("empty.toml"),
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfocal_distance = 1\n",
    )
    .unwrap();
    let (ok, _, stderr) = raylab(
        &[
            "render",
            "-s",
            "empty.toml",
            "--width",
            "8",
            "--height",
            "8",
        ],
        &dir,
    );
    assert!(ok, "{stderr}");
    assert!(
        stderr.contains("warning: scene 'empty.toml' holds no geometry"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn exr_output_holds_linear_radiance() {
    let dir = scratch("exr");
    let (ok, stdout, stderr) = raylab(
        &[
            "render", "-s", "cornell", "--width", "40", "--height", "30", "-o", "c.exr",
        ],
        &dir,
    );
    assert!(ok, "{stderr}");
    let film = raylab_core::film::read_exr(&dir.join(stdout.trim())).unwrap();
    assert_eq!((film.width, film.height), (40, 30));
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bad_input_is_a_clear_error_not_a_panic() {
    let dir = scratch("bad");
    std::fs::write(dir.join("nocam.toml"), "[materials.white]\ndiffuse = [0.8, 0.8, 0.8]\n\n[[spheres]]\ncenter = [0, 0, 0]\nradius = 1\nmaterial = \"white\"\n").unwrap();
    std::fs::write(dir.join("broken.toml"), "[camera]\neye = [0, 0\n").unwrap();
    std::fs::write(dir.join("cut.obj"), "v 0 0 0\nv 1 0 0\n").unwrap();
    // A PNG whose header (its IHDR chunk) no longer matches its checksum, and a texture that is
    // not there.
    let mut png = Vec::new();
    image::RgbImage::new(2, 2)
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    png[16] ^= 0x40;
    std::fs::write(dir.join("damaged.png"), png).unwrap();
    let camera =
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfocal_distance = 1.0\n";
    for (scene, texture) in [("damaged", "damaged.png"), ("untextured", "nothere.png")] {
        std::fs::write(
            dir.join(format!("{scene}.toml")),
            format!("{camera}\n[materials.floor]\ntexture = \"{texture}\"\n"),
        )
        .unwrap();
    }
    let cases: &[(&[&str], &str)] = &[
        (
            &["render", "--width", "0"],
            "'0' for '--width <WIDTH>': 0 is not positive",
        ),
        (
            &["render", "--width", "-5"],
            "'-5' for '--width <WIDTH>': -5 is negative",
        ),
        (
            &["render", "--width=-5"],
            "'-5' for '--width <WIDTH>': -5 is negative",
        ),
        (&["render", "--height", "many"], "'many' is not a number"),
        (
            &["render", "-s", "damaged.toml"],
            "damaged.png: cannot read the texture of materials.floor at damaged.toml, line 7",
        ),
        (
            &["render", "-s", "untextured.toml"],
            "nothere.png: cannot read the texture of materials.floor at untextured.toml, line 7",
        ),
        (&["render", "-s", "missing.toml"], "missing.toml"),
        (&["render", "-s", "nocam.toml"], "camera"),
        (&["render", "-s", "broken.toml"], "broken.toml"),
        (&["render", "-s", "nosuchscene"], "nosuchscene"),
        (&["render", "--tonemap", "gamma"], "gamma"),
        (&["render", "--lab", "99"], "99"),
        (&["render", "-o", "image.bmp"], "image.bmp"),
        (&["render", "-s", "cut.obj"], "holds no faces"),
        (
            &["render", "-o", "/nonexistent-raylab-dir/x.png"],
            "'/nonexistent-raylab-dir' does not exist",
        ),
    ];
    let mut transcript = String::new();
    for (args, needle) in cases {
        let (ok, _, stderr) = raylab(args, &dir);
        assert!(!ok, "{args:?} succeeded");
        assert!(
            stderr.contains("error:") && stderr.contains(needle),
            "{args:?}: {stderr}"
        );
        assert!(!stderr.contains("panicked"), "{args:?} panicked: {stderr}");
        transcript.push_str(&format!("$ raylab {}\n{stderr}\n", args.join(" ")));
    }
    // The exact words of every message, reviewed with `cargo insta review` when they change;
    // the course's list of labs, which a new lab lengthens, stands as a placeholder.
    let labs: Vec<String> = course::labs()
        .iter()
        .map(|l| l.number().to_string())
        .collect();
    let transcript = transcript.replace(&labs.join(", "), "<the labs of labs/course.toml>");
    insta::assert_snapshot!(transcript);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn help_texts_stay_the_same() {
    let dir = scratch("help");
    let mut transcript = String::new();
    for command in [
        "render",
        "report",
        "status",
        "hint",
        "watch",
        "reset",
        "bench",
        "golden",
        "handout",
        "grade",
        "gradescope",
        "similarity",
    ] {
        let (ok, stdout, stderr) = raylab(&[command, "--help"], &dir);
        assert!(ok, "{command} --help: {stderr}");
        transcript.push_str(&format!("$ raylab {command} --help\n{stdout}\n"));
    }
    let (ok, stdout, stderr) = raylab(&["hint", "1.1"], &dir);
    assert!(ok, "hint 1.1: {stderr}");
    transcript.push_str(&format!("$ raylab hint 1.1\n{stdout}\n"));
    let (ok, _, stderr) = raylab(&["hint", "1.9"], &dir);
    assert!(!ok);
    transcript.push_str(&format!("$ raylab hint 1.9\n{stderr}\n"));
    insta::assert_snapshot!(transcript);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn student_pipeline_on_stubs_renders_magenta_and_names_the_unfinished_exercises() {
    // The repository's lab crates hold the stubs, as a handout's do before any work.
    let dir = scratch("student");
    let size = ["--width", "24", "--height", "16"];
    for (lab, exercise) in [
        ("1", "Exercise 1.2 is unfinished: 384 pixels (100.0%)"),
        ("2", "Exercise 2."),
    ] {
        let args = [
            &[
                "render",
                "--lab",
                lab,
                "--pipeline",
                "student",
                "-o",
                "s.png",
            ][..],
            &size,
        ]
        .concat();
        let (ok, stdout, stderr) = raylab(&args, &dir);
        assert!(ok, "lab {lab}: {stderr}");
        assert!(stderr.contains(exercise), "lab {lab}: {stderr}");
        assert!(
            stderr.contains("384 of 384 pixels are magenta"),
            "lab {lab}: {stderr}"
        );
        // One summary, not a panic message per pixel.
        assert!(!stderr.contains("panicked at"), "lab {lab}: {stderr}");
        assert!(stderr.lines().count() < 10, "lab {lab}: {stderr}");
        let img = image::open(dir.join(stdout.trim())).unwrap().to_rgb8();
        assert!(
            img.pixels().all(|p| p.0 == [255, 0, 255]),
            "lab {lab}: not all magenta"
        );
    }
    // The EXR holds no radiance where none was computed.
    let args = [
        &[
            "render",
            "--lab",
            "1",
            "--pipeline",
            "student",
            "-o",
            "s.exr",
        ][..],
        &size,
    ]
    .concat();
    let (ok, stdout, stderr) = raylab(&args, &dir);
    assert!(ok, "{stderr}");
    let film = raylab_core::film::read_exr(&dir.join(stdout.trim())).unwrap();
    assert!(film.pixels.iter().all(|p| p.is_nan()), "{stderr}");
    assert!(stderr.contains("NaN in the EXR"), "{stderr}");
    // The report marks its figures the same way and names the exercise.
    let (ok, _, stderr) = raylab(
        &["report", "--lab", "1", "--pipeline", "student", "--quick"],
        &dir,
    );
    assert!(ok, "{stderr}");
    assert!(stderr.contains("Exercise 1.2 is unfinished"), "{stderr}");
    let md = std::fs::read_to_string(dir.join("out/report/lab01/report.md")).unwrap();
    assert!(md.contains("Exercise 1.2 is unfinished"), "{md}");
    // report.html shows the same figures, each image beside the page.
    let page = dir.join("out/report/lab01");
    let html = std::fs::read_to_string(page.join("report.html")).unwrap();
    assert!(html.contains("Exercise 1.2 is unfinished"), "{html}");
    let images: Vec<&str> = html
        .split("src=\"")
        .skip(1)
        .filter_map(|r| r.split('"').next())
        .collect();
    assert!(!images.is_empty(), "{html}");
    for image in images {
        assert!(
            page.join(image).is_file(),
            "report.html shows {image}, not there"
        );
        assert!(
            md.contains(&format!("]({image})")),
            "report.md lacks {image}"
        );
    }
    // The reference pipeline in the repository holds no student code and says nothing of it.
    let args = [&["render", "-o", "r.png"][..], &size].concat();
    let (ok, _, stderr) = raylab(&args, &dir);
    assert!(ok, "{stderr}");
    assert!(
        !stderr.contains("magenta") && !stderr.contains("not released"),
        "{stderr}"
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn rayon_num_threads_does_not_change_the_image() {
    let dir = scratch("threads");
    let mut outputs = Vec::new();
    for threads in ["1", "2"] {
        let name = format!("t{threads}.exr");
        let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
            .args([
                "render", "-s", "cornell", "--width", "64", "--height", "48", "--spp", "4",
                "--seed", "9", "-o", &name,
            ])
            .env("RAYON_NUM_THREADS", threads)
            .current_dir(&dir)
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        outputs.push(raylab_core::film::read_exr(&dir.join(&name)).unwrap());
    }
    assert!(
        outputs[0] == outputs[1],
        "RAYON_NUM_THREADS=1 and =2 give different images"
    );
    std::fs::remove_dir_all(dir).ok();
}

/// A stand-in for cargo that runs the real one, except that its `k`-th run (k > 1) first waits,
/// at most 30 s, until `dir/seen-(k-1)` exists: the test's sign that it has read the line of
/// the lab built before. A wait that runs out is written to `dir/not-seen`, and the runs after
/// it wait no more.
fn cargo_held_until_seen(dir: &std::path::Path) -> PathBuf {
    use std::os::unix::fs::PermissionsExt;
    let real = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let d = dir.display();
    let script = format!(
        r#"#!/bin/sh
k=$(( $(cat "{d}/calls" 2>/dev/null || echo 0) + 1 ))
echo "$k" > "{d}/calls"
if [ "$k" -gt 1 ] && [ ! -e "{d}/not-seen" ]; then
  i=0
  while [ ! -e "{d}/seen-$((k - 1))" ] && [ "$i" -lt 1500 ]; do sleep 0.02; i=$((i + 1)); done
  [ -e "{d}/seen-$((k - 1))" ] || echo "$k" > "{d}/not-seen"
fi
exec "{real}" "$@"
"#
    );
    let path = dir.join("cargo");
    std::fs::write(&path, script).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

#[test]
fn status_lists_every_exercise_and_the_next_one() {
    use std::io::{BufRead, BufReader, Read};
    let dir = scratch("status");
    // Each lab's line is printed before the next lab is built: with a cargo that builds a lab
    // only once the test has read the line of the lab before it.
    let mut child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .arg("status")
        .current_dir(&dir)
        .env("CARGO", cargo_held_until_seen(&dir))
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("raylab runs");
    let mut stderr = child.stderr.take().unwrap();
    let errors = std::thread::spawn(move || {
        let mut text = String::new();
        stderr.read_to_string(&mut text).ok();
        text
    });
    let mut stdout = String::new();
    let mut labs = Vec::new();
    for line in BufReader::new(child.stdout.take().unwrap()).lines() {
        let line = line.unwrap();
        if let Some(lab) = line
            .split_whitespace()
            .next()
            .filter(|w| w.starts_with("lab") && w[3..].bytes().all(|b| b.is_ascii_digit()))
        {
            labs.push(lab.to_string());
            std::fs::write(dir.join(format!("seen-{}", labs.len())), "").unwrap();
        }
        stdout.push_str(&line);
        stdout.push('\n');
    }
    let ok = child.wait().unwrap().success();
    let stderr = errors.join().unwrap();
    assert!(ok, "{stderr}");
    assert!(
        !dir.join("not-seen").exists(),
        "a lab was built before the line of the lab before it was printed:\n{stdout}"
    );
    // Every lab, in order, each built once.
    let mut sorted = labs.clone();
    sorted.sort();
    sorted.dedup();
    assert_eq!(labs, sorted, "{stdout}");
    assert_eq!(labs.first().map(String::as_str), Some("lab01"), "{stdout}");
    assert_eq!(labs.last().map(String::as_str), Some("lab12"), "{stdout}");
    let calls = std::fs::read_to_string(dir.join("calls")).unwrap();
    assert_eq!(calls.trim(), labs.len().to_string(), "{stdout}");
    for id in ["1.1", "2.6", "3.4", "4.6", "7.2"] {
        assert!(
            stdout.contains(&format!("  {id} ")),
            "{id} missing:\n{stdout}"
        );
    }
    // The exercises of the stubs are not started; the first one is next.
    assert!(stdout.contains("not started"), "{stdout}");
    assert!(stdout.contains("next: Exercise 1.1"), "{stdout}");
    std::fs::remove_dir_all(dir).ok();
}

/// The commands that hints and the checks' failure messages print, in the mode that checks a
/// command's arguments and does nothing else (`RAYLAB_CHECK_ARGUMENTS`, which the test of the
/// printed commands in a handout runs them in): a snapshot's `raylab view` command is accepted
/// without a page being served, and arguments the command would refuse are refused the same.
#[test]
fn printed_commands_have_their_arguments_checked_without_running() {
    let dir = scratch("check-arguments");
    let check = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
            .args(args)
            .current_dir(&dir)
            .env("RAYLAB_CHECK_ARGUMENTS", "1")
            .output()
            .expect("raylab runs");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    for args in [
        "view --lab 3 --scene cornell-spheres --width 4 --height 3 --pixel 0,0",
        "render --lab 1 --pipeline student --width 160 --height 120",
        "render --lab 7 --pipeline student --subdivisions 4",
        "hint 1.6",
        "status --lab 2",
    ] {
        let (ok, stdout, stderr) = check(&args.split(' ').collect::<Vec<_>>());
        assert!(
            ok && stdout == "arguments accepted\n",
            "{args}: {stdout}{stderr}"
        );
    }
    assert!(
        !dir.join("raylab.png").exists(),
        "a checked render writes nothing"
    );
    for (args, expected) in [
        (
            "view --lab 3 --scene cornell --width 4 --height 3 --pixel 4,0",
            "pixel 4,0",
        ),
        ("render --lab 99", "invalid lab 99"),
        ("hint 1.9", "'1.9'"),
        ("render --width 0", "0 is not positive"),
        ("reset 1.6", "not one function"),
    ] {
        let (ok, stdout, stderr) = check(&args.split(' ').collect::<Vec<_>>());
        assert!(
            !ok && stdout.is_empty() && stderr.contains(expected),
            "{args}: {stdout}{stderr}"
        );
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn bench_reports_throughput() {
    let dir = scratch("bench");
    let (ok, stdout, stderr) = raylab(&["bench", "--resolution", "16", "--runs", "1"], &dir);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("cornell: 32 triangles"), "{stdout}");
    assert!(stdout.contains("70300 triangles"), "{stdout}");
    assert_eq!(stdout.matches("Throughput (Mrays/s").count(), 2, "{stdout}");
    // Every ray set on 1 and 2 threads, with the obvhs peer beside the core when built with it.
    assert_eq!(
        stdout.matches("| raylab core | ").count(),
        2 * 4 + 2 * 2 + 2,
        "{stdout}"
    );
    let obvhs_rows = if cfg!(feature = "obvhs") { 4 } else { 0 };
    assert_eq!(
        stdout.matches("| 2 | obvhs | ").count(),
        obvhs_rows,
        "{stdout}"
    );
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn handout_and_grade_refuse_bad_input_clearly() {
    let dir = scratch("instructor");
    let not_empty = dir.join("not-empty");
    std::fs::create_dir_all(&not_empty).unwrap();
    std::fs::write(not_empty.join("keep.txt"), "mine").unwrap();
    let submission = dir.join("alice");
    std::fs::create_dir_all(&submission).unwrap();
    let out = dir.join("grades");
    let (o, s) = (out.to_str().unwrap(), submission.to_str().unwrap());
    let cases: &[(&[&str], &str)] = &[
        (
            &[
                "handout",
                "--allow-dirty",
                "--out",
                not_empty.to_str().unwrap(),
            ],
            "expected a directory that does not exist yet, or an empty one",
        ),
        (
            &[
                "handout",
                "--allow-dirty",
                "--out",
                o,
                "--release-solutions",
                "7",
            ],
            "the solution of lab 7 uses the solution of lab 3",
        ),
        (
            &[
                "handout",
                "--allow-dirty",
                "--out",
                o,
                "--release-solutions",
                "99",
            ],
            "invalid lab 99",
        ),
        (
            &["grade", "no-such-submission", "--out", o],
            "invalid submission no-such-submission: expected a directory",
        ),
        (&["grade", s, s, "--out", o], "must be unique"),
    ];
    for (args, expected) in cases {
        let (ok, _, stderr) = raylab(args, &dir);
        assert!(!ok, "{args:?} succeeded");
        assert!(stderr.contains(expected), "{args:?}: {stderr}");
        assert!(!stderr.contains("panicked"), "{args:?}: {stderr}");
    }
    assert_eq!(
        std::fs::read_to_string(not_empty.join("keep.txt")).unwrap(),
        "mine"
    );
    assert!(!out.join("alice").exists(), "nothing graded on bad input");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn grade_without_bubblewrap_refuses_to_run_unsandboxed_code() {
    let dir = scratch("no-bwrap");
    std::fs::create_dir_all(dir.join("student")).unwrap();
    let empty = dir.join("empty-path");
    std::fs::create_dir_all(&empty).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["grade", "student", "--out", "grades"])
        .current_dir(&dir)
        .env("PATH", &empty)
        .output()
        .expect("raylab runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{stderr}");
    assert!(
        stderr.contains("bubblewrap (`bwrap`) is not installed")
            && stderr.contains("--unsandboxed"),
        "{stderr}"
    );
    assert!(!dir.join("grades").exists(), "nothing is written");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn hostile_files_are_one_error_line_and_exit_status_1() {
    let dir = scratch("hostile");
    let hostile = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../framework/core/tests/hostile-files")
        .canonicalize()
        .unwrap();
    let camera =
        "[camera]\neye = [0, 0, 5]\nlook_at = [0, 0, 0]\nup = [0, 1, 0]\nfocal_distance = 1.0\n";
    for (file, needle) in [
        ("palette-plte-not-multiple-of-3.png", "panicked: "),
        ("png-30000x30000.png", "load budget"),
        ("exr-dwaa.exr", "dwaa compression"),
        ("exr-piz.exr", "piz compression"),
        ("exr-zip-huge-window.exr", "load budget"),
    ] {
        let scene = dir.join("textured.toml");
        let texture = hostile.join(file);
        std::fs::write(
            &scene,
            format!(
                "{camera}[materials.m]\ntexture = {:?}\n",
                texture.to_str().unwrap()
            ),
        )
        .unwrap();
        let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
            .args([
                "render",
                "-s",
                "textured.toml",
                "--width",
                "8",
                "--height",
                "8",
            ])
            .current_dir(&dir)
            .output()
            .expect("raylab runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{file}: {stderr}");
        assert_eq!(stderr.lines().count(), 1, "{file}: {stderr}");
        assert!(
            stderr.starts_with("error: ") && stderr.contains(file) && stderr.contains(needle),
            "{file}: {stderr}"
        );
        assert!(stderr.contains("textured.toml, line 6"), "{file}: {stderr}");
    }
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_closed_output_pipe_ends_the_command_quietly() {
    // The reader of the pipe is gone before the command writes (`raylab hint 1.3 | head -0`).
    use std::os::unix::process::ExitStatusExt;
    use std::process::Stdio;
    // The pipe's reading end is closed before the command starts, so that its first write
    // fails whatever the timing.
    let (reader, writer) = std::io::pipe().expect("a pipe");
    drop(reader);
    let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(["hint", "1.3"])
        .current_dir(scratch("closed-pipe"))
        .stdout(writer)
        .stderr(Stdio::piped())
        .output()
        .expect("raylab runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(!stderr.contains("panicked"), "{stderr}");
    assert_eq!(
        out.status.code(),
        Some(141),
        "{:?} {stderr}",
        out.status.signal()
    );
}

/// Runs git in `dir` with an identity of its own (the machine may have none) and returns its
/// standard output.
fn git(dir: &std::path::Path, args: &[&str]) -> String {
    let out = Command::new("git")
        .args([
            "-c",
            "user.name=Student",
            "-c",
            "user.email=student@example.org",
            "-c",
            "commit.gpgsign=false",
        ])
        .args(args)
        .current_dir(dir)
        .output()
        .expect("git runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "git {args:?}: {stderr}");
    String::from_utf8_lossy(&out.stdout).into_owned()
}

#[test]
fn a_release_is_a_commit_that_students_pull_without_conflicts() {
    let dir = scratch("release");
    let (handout, student) = (dir.join("handout"), dir.join("student"));
    let (h, s) = (handout.to_str().unwrap(), student.to_str().unwrap());
    let (ok, _, stderr) = raylab(&["handout", "--allow-dirty", "--out", h], &dir);
    assert!(ok, "{stderr}");
    let subjects = git(&handout, &["log", "--format=%s"]);
    assert!(
        subjects.starts_with("raylab handout: labs 1–") && subjects.lines().count() == 1,
        "{subjects}"
    );
    assert_eq!(git(&handout, &["branch", "--show-current"]).trim(), "main");
    assert!(!handout.join("reference/src/lab01.rs").exists());

    // No solution rides along with the command line's tests (the similarity test's class).
    assert!(!handout.join("labs/raylab/tests").exists());
    assert!(!handout.join("reference/src/lab02.rs").exists());

    // The student clones the handout and commits work on lab 1. The handout's lock file is
    // the one its workspace resolves to: cargo, reading it, leaves the clone and the handout
    // as they are (a lock naming a package the handout lacks would be rewritten, and
    // `--update` would refuse the handout).
    git(&dir, &["clone", "--quiet", h, s]);
    for tree in [&student, &handout] {
        let out = Command::new(env!("CARGO"))
            .args(["metadata", "--offline", "--format-version", "1"])
            .current_dir(tree)
            .output()
            .expect("cargo runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        assert_eq!(
            git(tree, &["status", "--porcelain"]),
            "",
            "{}",
            tree.display()
        );
    }
    let lab01 = student.join("labs/lab01/src/lib.rs");
    let stubs = std::fs::read_to_string(&lab01).unwrap();
    let todo_1_1 = "todo!(\"Exercise 1.1: image_plane_coords (docs/lab01.md, Exercise 1.1)\")";
    let todo_1_2 = "todo!(\"Exercise 1.2: camera_basis (docs/lab01.md, Exercise 1.2)\")";
    assert!(stubs.contains(todo_1_1) && stubs.contains(todo_1_2));
    let work = stubs
        .replace(todo_1_1, "Vec2::ZERO // my 1.1")
        .replace(todo_1_2, "todo!(\"my 1.2, half done\")");
    std::fs::write(&lab01, &work).unwrap();
    // The handout's answers file, with a first answer.
    let answers = student.join("labs/lab01/answers.md");
    let fresh = std::fs::read_to_string(&answers).expect("the handout has lab 1's answers file");
    let mine = fresh.replacen("<!-- Your answer here. -->", "It grows with the pixels.", 1);
    assert_ne!(mine, fresh);
    std::fs::write(&answers, &mine).unwrap();
    git(
        &student,
        &["commit", "--quiet", "--all", "--message", "lab 1 so far"],
    );

    // Nothing changed in the course: no commit.
    let (ok, stdout, stderr) = raylab(&["handout", "--allow-dirty", "--update", h], &dir);
    assert!(
        ok && stdout.contains("nothing to release"),
        "{stdout}{stderr}"
    );
    assert_eq!(git(&handout, &["rev-list", "--count", "HEAD"]).trim(), "1");

    // Releasing lab 1's solution is one commit, which the student's pull merges cleanly.
    let release = [
        "handout",
        "--allow-dirty",
        "--update",
        h,
        "--release-solutions",
        "1",
    ];
    let (ok, stdout, stderr) = raylab(&release, &dir);
    assert!(ok, "{stdout}{stderr}");
    assert_eq!(
        git(&handout, &["log", "-1", "--format=%s"]).trim(),
        "release: solutions of lab 1"
    );
    // The command that merges a release with a student's commits (a plain `git pull` stops
    // at their diverged branch).
    assert!(
        stdout.contains("students run `git pull --no-rebase`"),
        "{stdout}"
    );
    git(&student, &["pull", "--quiet", "--no-rebase", "--no-edit"]);
    assert!(student.join("reference/src/lab01.rs").is_file());
    assert_eq!(
        std::fs::read_to_string(&answers).unwrap(),
        mine,
        "the answers survive"
    );
    let readme = std::fs::read_to_string(student.join("README.md")).unwrap();
    assert!(readme.contains("`reference/src/lab01.rs`"), "{readme}");
    assert_eq!(std::fs::read_to_string(&lab01).unwrap(), work);
    assert!(git(&student, &["status", "--porcelain"]).is_empty());

    // `raylab reset 1.2` puts back 1.2's stub and keeps 1.1's work byte for byte, and the
    // file it replaced in `out/reset/`, which it names: nothing git would commit.
    let (ok, stdout, stderr) = raylab(&["reset", "1.2", "--handout", s], &dir);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("restored `camera_basis`"), "{stdout}");
    assert_eq!(
        std::fs::read_to_string(&lab01).unwrap(),
        stubs.replace(todo_1_1, "Vec2::ZERO // my 1.1")
    );
    let kept = |stdout: &str| {
        let (_, rest) = stdout
            .split_once(" is kept in ")
            .unwrap_or_else(|| panic!("no copy named: {stdout}"));
        let path = rest.split_whitespace().next().unwrap();
        assert!(path.starts_with("out/reset/lab"), "{path}");
        std::fs::read_to_string(student.join(path)).unwrap()
    };
    assert_eq!(kept(&stdout), work, "the file as it was, 1.2 half done");
    assert_eq!(
        git(&student, &["status", "--porcelain"]),
        " M labs/lab01/src/lib.rs\n"
    );
    for (exercise, expected) in [
        ("1.6", "not one function of labs/lab01/src/lib.rs"),
        ("1.9", "'1.9'"),
    ] {
        let (ok, _, stderr) = raylab(&["reset", exercise, "--handout", s], &dir);
        assert!(!ok && stderr.contains(expected), "{exercise}: {stderr}");
    }

    // A release that would change a file students own is refused, naming it; a dirty
    // repository or a folder that is not a handout is refused too.
    let lab02 = handout.join("labs/lab02/src/lib.rs");
    let fixed = std::fs::read_to_string(&lab02).unwrap() + "\n// a stub as it was before\n";
    std::fs::write(&lab02, &fixed).unwrap();
    let (ok, _, stderr) = raylab(&release, &dir);
    assert!(!ok && stderr.contains("uncommitted changes"), "{stderr}");
    git(
        &handout,
        &["commit", "--quiet", "--all", "--message", "old stub"],
    );
    let (ok, _, stderr) = raylab(&release, &dir);
    assert!(!ok, "{stderr}");
    assert!(
        stderr.contains("files that students own") && stderr.contains("labs/lab02/src/lib.rs"),
        "{stderr}"
    );
    assert_eq!(std::fs::read_to_string(&lab02).unwrap(), fixed);
    let plain = dir.join("plain");
    std::fs::create_dir_all(&plain).unwrap();
    let (ok, _, stderr) = raylab(
        &[
            "handout",
            "--allow-dirty",
            "--update",
            plain.to_str().unwrap(),
        ],
        &dir,
    );
    assert!(
        !ok && stderr.contains("expected a handout repository"),
        "{stderr}"
    );
    let forced = [&release[..], &["--force"]].concat();
    let (ok, _, stderr) = raylab(&forced, &dir);
    assert!(ok && stderr.contains("merge conflict"), "{stderr}");
    let repository_stubs = std::fs::read_to_string(
        std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../lab02/src/lib.rs"),
    )
    .unwrap();
    assert_eq!(std::fs::read_to_string(&lab02).unwrap(), repository_stubs);

    // After pulling the forced release, `reset` restores the stub as released last.
    git(&student, &["pull", "--quiet", "--no-rebase", "--no-edit"]);
    let student_lab02 = student.join("labs/lab02/src/lib.rs");
    let todo_2_1 = "todo!(\"Exercise 2.1: intersect_plane (docs/lab02.md, Exercise 2.1)\")";
    std::fs::write(
        &student_lab02,
        repository_stubs.replace(todo_2_1, "None // mine"),
    )
    .unwrap();
    let (ok, stdout, stderr) = raylab(&["reset", "2.1", "--handout", s], &dir);
    assert!(ok, "{stderr}");
    assert_eq!(
        std::fs::read_to_string(&student_lab02).unwrap(),
        repository_stubs
    );
    // Work never committed is what the copy keeps.
    assert_eq!(
        kept(&stdout),
        repository_stubs.replace(todo_2_1, "None // mine")
    );
    std::fs::remove_dir_all(dir).ok();
}

/// Every command acts on the course tree the current directory is in (a handout run by the
/// raylab of another clone is the common case, `tests/tests/workflows/printed_commands.rs`);
/// in a tree whose registry lists other labs than this raylab knows, a command is refused,
/// naming the tree, and writes nothing there.
#[test]
fn a_tree_of_another_course_is_refused() {
    let other = scratch("other-course");
    std::fs::create_dir_all(other.join("labs")).unwrap();
    std::fs::write(other.join("Cargo.toml"), "[workspace]\n").unwrap();
    std::fs::write(
        other.join("labs/course.toml"),
        "[labs]\nlab01 = \"Elsewhere\"\n",
    )
    .unwrap();
    let inside = other.join("labs");
    for args in [
        &["status"][..],
        &["handout", "--out", "handout-here"][..],
        &["golden", "--lab", "1"][..],
    ] {
        let (ok, _, err) = raylab(args, &inside);
        assert!(!ok, "raylab {args:?} ran in another course");
        assert!(
            err.contains("lists other labs than this raylab knows")
                && err.contains(&*other.to_string_lossy()),
            "raylab {args:?}: {err}"
        );
    }
    assert!(!other.join("labs/handout-here").exists());
    assert_eq!(
        std::fs::read_to_string(other.join("labs/course.toml")).unwrap(),
        "[labs]\nlab01 = \"Elsewhere\"\n"
    );
}

/// Outside every course tree a command acts on the tree this raylab was built from and says
/// so, naming both; a reference render, which reads no tree, says nothing of one.
#[test]
fn outside_a_course_a_command_says_which_tree_it_acts_on() {
    let dir = scratch("outside");
    let built = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let built = built.canonicalize().unwrap();
    let (_, _, err) = raylab(&["reset", "1.1", "--dry-run"], &dir);
    assert!(
        err.contains("is in no course tree")
            && err.contains(&*dir.to_string_lossy())
            && err.contains(&*built.to_string_lossy()),
        "{err}"
    );
    let (ok, _, err) = raylab(
        &["render", "--lab", "1", "--width", "4", "--height", "4"],
        &dir,
    );
    assert!(ok && !err.contains("course tree"), "{err}");
}
