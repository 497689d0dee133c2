//! `raylab view` in a real browser: headless Chromium driven through the DevTools protocol
//! over `--remote-debugging-pipe` (JSON messages ended by a NUL byte on the browser's file
//! descriptors 3 and 4). It loads the page, sees progressive updates, drags the camera and sees
//! the accumulation restart, clicks a pixel and reads the `/pixel` answer on the page, and
//! checks a screenshot is not blank.

use std::io::{BufRead, BufReader, Write};
use std::os::unix::process::CommandExt;
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};
use std::time::{Duration, Instant};

use base64::Engine;
use serde_json::{Value, json};

/// A child process started in a process group of its own, which is ended when dropped, the
/// test passing or not (the command and the lab's program it runs; Chromium and its helpers).
struct Running(Child);

impl Drop for Running {
    fn drop(&mut self) {
        let _ = Command::new("kill")
            .arg("--")
            .arg(format!("-{}", self.0.id()))
            .status();
        let _ = self.0.wait();
    }
}

/// A DevTools-protocol client over Chromium's debugging pipe, attached to one page.
struct Browser {
    to_browser: ChildStdin,
    from_browser: BufReader<ChildStdout>,
    next_id: u64,
    session: Option<String>,
    _process: Running,
    profile: std::path::PathBuf,
}

impl Browser {
    /// Starts headless Chromium with its debugging pipe on this process's pipes (the shell maps
    /// them to descriptors 3 and 4) and opens a blank page of `width × height`.
    fn start(width: u32, height: u32) -> Self {
        // A profile of each browser's own: the tests run side by side.
        static BROWSERS: std::sync::atomic::AtomicU32 = std::sync::atomic::AtomicU32::new(0);
        let n = BROWSERS.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
        let profile =
            std::env::temp_dir().join(format!("raylab-view-test-{}-{n}", std::process::id()));
        let mut child = Command::new("sh")
            .arg("-c")
            .arg(r#"exec "$0" "$@" 3<&0 4>&1 0</dev/null 1>/dev/null"#)
            .args([
                "chromium",
                "--headless",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--disable-background-networking",
                "--disable-component-update",
                "--disable-sync",
                "--remote-debugging-pipe",
            ])
            .arg(format!("--user-data-dir={}", profile.display()))
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .process_group(0)
            .spawn()
            .expect("chromium starts");
        let to_browser = child.stdin.take().unwrap();
        let from_browser = BufReader::new(child.stdout.take().unwrap());
        let mut browser = Self {
            to_browser,
            from_browser,
            next_id: 1,
            session: None,
            _process: Running(child),
            profile,
        };
        let target = browser.call("Target.createTarget", json!({"url": "about:blank"}));
        let attached = browser.call(
            "Target.attachToTarget",
            json!({"targetId": target["targetId"], "flatten": true}),
        );
        browser.session = Some(attached["sessionId"].as_str().unwrap().to_string());
        browser.call("Page.enable", json!({}));
        browser.call(
            "Emulation.setDeviceMetricsOverride",
            json!({"width": width, "height": height, "deviceScaleFactor": 1, "mobile": false}),
        );
        browser
    }

    /// Sends a command (to the page, once attached) and returns its result; events in between
    /// are passed over.
    fn call(&mut self, method: &str, params: Value) -> Value {
        let id = self.next_id;
        self.next_id += 1;
        let mut message = json!({"id": id, "method": method, "params": params});
        if let Some(session) = &self.session {
            message["sessionId"] = json!(session);
        }
        let mut bytes = message.to_string().into_bytes();
        bytes.push(0);
        self.to_browser
            .write_all(&bytes)
            .expect("the browser reads");
        self.to_browser.flush().unwrap();
        loop {
            let mut reply = Vec::new();
            let n = self
                .from_browser
                .read_until(0, &mut reply)
                .expect("the browser answers");
            assert!(n > 0, "the browser closed its pipe during {method}");
            reply.pop();
            let reply: Value = serde_json::from_slice(&reply).expect("a JSON message");
            if reply["id"] == id {
                assert!(
                    reply.get("error").is_none(),
                    "{method} failed: {}",
                    reply["error"]
                );
                return reply["result"].clone();
            }
        }
    }

    /// The value of a JavaScript expression in the page.
    fn eval(&mut self, expression: &str) -> Value {
        let result = self.call(
            "Runtime.evaluate",
            json!({"expression": expression, "returnByValue": true, "awaitPromise": true}),
        );
        result["result"]["value"].clone()
    }

    /// A mouse event at `(x, y)` of the page.
    fn mouse(&mut self, kind: &str, x: f64, y: f64, buttons: u32) {
        self.call(
            "Input.dispatchMouseEvent",
            json!({"type": kind, "x": x, "y": y, "button": "left", "buttons": buttons, "clickCount": 1}),
        );
    }

    /// Waits until `expression` is true in the page, or panics with `what` after `timeout`.
    fn wait_for(&mut self, expression: &str, timeout: Duration, what: &str) {
        let start = Instant::now();
        while self.eval(expression) != json!(true) {
            assert!(
                start.elapsed() < timeout,
                "{what}: not seen within {timeout:?}; updates {}",
                self.eval("JSON.stringify(window.raylabView.updates)")
            );
            std::thread::sleep(Duration::from_millis(50));
        }
    }
}

impl Drop for Browser {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.profile);
    }
}

/// Starts `raylab view` on a free port and returns it with the URL it printed.
fn start_view(args: &[&str]) -> (Running, String) {
    let mut child = Command::new(env!("CARGO_BIN_EXE_raylab"))
        .arg("view")
        .args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .process_group(0)
        .spawn()
        .expect("raylab starts");
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let running = Running(child);
    let mut line = String::new();
    loop {
        line.clear();
        assert!(
            out.read_line(&mut line).unwrap() > 0,
            "raylab view ended before printing its URL"
        );
        if let Some(url) = line.trim().strip_prefix("raylab view: ") {
            // Keep reading its standard output so that it never blocks on a full pipe.
            std::thread::spawn(move || std::io::copy(&mut out, &mut std::io::sink()));
            return (running, url.to_string());
        }
    }
}

/// The `/pixel` answer the page shows, as it keeps it.
fn pixel_answer(browser: &mut Browser) -> Value {
    let answer = browser.eval("document.getElementById('pixel-info').dataset.answer");
    serde_json::from_str(answer.as_str().expect("the page holds a pixel's answer")).unwrap()
}

#[test]
fn the_view_converges_moves_and_answers_a_pixel_in_chromium() {
    if !grading::prerequisite::program_or_skip(
        "the view's browser test",
        "chromium",
        "apt-get install chromium",
    ) {
        return;
    }
    let (view, url) = start_view(&[
        "--lab", "12", "--scene", "cornell", "--width", "192", "--height", "192",
    ]);
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    let mut browser = Browser::start(1000, 700);
    browser.call("Page.navigate", json!({"url": url}));
    let timeout = Duration::from_secs(60);

    // Two progressive updates of the first camera, drawn.
    browser.wait_for(
        "window.raylabView !== undefined && new Set(window.raylabView.updates.filter(u => u.generation === 0).map(u => u.passes)).size >= 2",
        timeout,
        "two progressive updates",
    );
    browser.wait_for(
        "Math.max(...window.raylabView.updates.filter(u => u.generation === 0).map(u => u.passes)) >= 6",
        timeout,
        "six passes",
    );
    let before = browser
        .eval("Math.max(...window.raylabView.updates.filter(u => u.generation === 0).map(u => u.passes))")
        .as_u64()
        .unwrap();

    let canvas = browser.eval(
        "(() => { const b = document.getElementById('image').getBoundingClientRect(); return [b.left, b.top, b.width, b.height]; })()",
    );
    let [left, top, width, height] = [0, 1, 2, 3].map(|i| canvas[i].as_f64().unwrap());
    assert_eq!((width, height), (192.0, 192.0));

    // A drag orbits the camera: a new generation, whose passes start again from the first.
    let (x, y) = (left + 100.0, top + 100.0);
    browser.mouse("mousePressed", x, y, 1);
    for step in 1..=5 {
        browser.mouse("mouseMoved", x + 8.0 * f64::from(step), y + 2.0, 1);
    }
    browser.mouse("mouseReleased", x + 40.0, y + 2.0, 0);
    browser.wait_for(
        "window.raylabView.updates.some(u => u.generation > 0)",
        timeout,
        "an update of the moved camera",
    );
    let restarted = browser
        .eval("Math.min(...window.raylabView.updates.filter(u => u.generation > 0).map(u => u.passes))")
        .as_u64()
        .unwrap();
    assert!(
        restarted < before,
        "the moved camera's first update shows {restarted} passes, the old one had {before}"
    );

    // A click, once both pipelines have a pass of the moved camera, shows the pixel's mean
    // radiance in both.
    browser.wait_for(
        "window.raylabView.updates.some(u => u.generation > 0 && u.samples > 0)",
        timeout,
        "both images of the moved camera",
    );
    browser.mouse("mousePressed", left + 96.5, top + 60.5, 1);
    browser.mouse("mouseReleased", left + 96.5, top + 60.5, 0);
    browser.wait_for(
        "document.getElementById('pixel-info').dataset.answer !== undefined",
        timeout,
        "the pixel's answer",
    );
    let answer = pixel_answer(&mut browser);
    assert_eq!(
        (answer["x"].as_u64(), answer["y"].as_u64()),
        (Some(96), Some(60))
    );
    let pipelines = answer["pipelines"].as_array().unwrap();
    assert_eq!(
        pipelines.len(),
        2,
        "the student's and the reference: {answer}"
    );
    let shown = browser
        .eval("document.getElementById('pixel-info').textContent")
        .as_str()
        .unwrap()
        .to_string();
    assert!(shown.contains("pixel (96, 60)"), "{shown}");
    assert!(shown.contains("Reference: mean radiance"), "{shown}");
    // The stubs of lab 12 are unfinished: the student's pixel is marked, not computed.
    assert!(shown.contains("Student: panicked (magenta)"), "{shown}");
    // Lab 12's program has the key's camera: the ray through the pixel's centre.
    assert!(shown.contains("camera ray from "), "{shown}");
    let direction = &answer["camera_ray"]["direction"];
    let length = (0..3)
        .map(|i| direction[i].as_f64().unwrap().powi(2))
        .sum::<f64>()
        .sqrt();
    assert!((length - 1.0).abs() < 1e-3, "{answer}");

    // The inspector: the reference's sample ray by ray and call by call, from its camera ray
    // to the path tracer's exercise; the student's names the exercise whose stub stopped it.
    let inspections = answer["inspections"].as_array().unwrap();
    assert_eq!(inspections.len(), 2, "{answer}");
    let tree = browser
        .eval("document.getElementById('inspector').textContent")
        .as_str()
        .unwrap()
        .to_string();
    assert!(tree.contains("camera ray from "), "{tree}");
    assert!(tree.contains("→ hit at t = "), "{tree}");
    assert!(
        tree.contains("[12."),
        "an exercise of lab 12 computed it: {tree}"
    );
    let culprit = &inspections[0]["inspection"]["culprit"];
    assert!(
        culprit["exercise"]["id"]
            .as_str()
            .is_some_and(|id| id.starts_with("12.")),
        "the student's stub names its exercise: {culprit}"
    );
    assert!(tree.contains("panicked"), "{tree}");

    // The screenshot shows the image: many colours where the canvas is.
    let shot = browser.call("Page.captureScreenshot", json!({"format": "png"}));
    let png = base64::engine::general_purpose::STANDARD
        .decode(shot["data"].as_str().unwrap())
        .unwrap();
    let target = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("view-screenshot.png");
    std::fs::write(&target, &png).unwrap();
    let image = image::load_from_memory(&png).unwrap().to_rgb8();
    let mut colours = std::collections::HashSet::new();
    let mut magenta = 0;
    for py in top as u32..(top + height) as u32 {
        for px in left as u32..(left + width) as u32 {
            let p = image.get_pixel(px, py).0;
            colours.insert(p);
            magenta += u32::from(p == [255, 0, 255]);
        }
    }
    assert!(
        colours.len() > 200,
        "the screenshot ({}) shows {} colours in the image",
        target.display(),
        colours.len()
    );
    // The student's half (left of the split) is magenta, the reference's is not.
    assert!(magenta > 192 * 60, "{magenta} magenta pixels");
    assert!(magenta < 192 * 150, "{magenta} magenta pixels");
    drop(browser);

    // The server ends with the command, even when only the command is killed.
    let mut view = view;
    view.0.kill().unwrap();
    let address = url.trim_start_matches("http://").trim_end_matches('/');
    let start = Instant::now();
    while std::net::TcpStream::connect(address).is_ok() {
        assert!(
            start.elapsed() < Duration::from_secs(20),
            "the lab's program still serves {url} after raylab was killed"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
}

/// The command a failing image check prints: the page opens on the difference view with the
/// worst pixel inspected, no click needed.
#[test]
fn the_view_opened_on_a_pixel_inspects_it() {
    if !grading::prerequisite::program_or_skip(
        "the view's browser test",
        "chromium",
        "apt-get install chromium",
    ) {
        return;
    }
    let (_view, url) = start_view(&[
        "--lab", "12", "--scene", "cornell", "--width", "64", "--height", "48", "--pixel", "40,20",
    ]);
    let mut browser = Browser::start(800, 600);
    browser.call("Page.navigate", json!({"url": url}));
    browser.wait_for(
        "document.getElementById('inspector').textContent.includes('camera ray from')",
        Duration::from_secs(60),
        "the pixel inspected as the page opens",
    );
    let answer = pixel_answer(&mut browser);
    assert_eq!(
        (answer["x"].as_u64(), answer["y"].as_u64()),
        (Some(40), Some(20))
    );
    assert_eq!(
        browser.eval("document.getElementById('mode').value"),
        "difference"
    );
}

#[test]
fn a_bad_size_or_scene_is_one_error_and_no_server() {
    let run = |args: &[&str]| {
        let out = Command::new(env!("CARGO_BIN_EXE_raylab"))
            .arg("view")
            .args(args)
            .stdin(Stdio::null())
            .output()
            .expect("raylab runs");
        (
            out.status.success(),
            String::from_utf8_lossy(&out.stdout).into_owned(),
            String::from_utf8_lossy(&out.stderr).into_owned(),
        )
    };
    let (ok, _, stderr) = run(&["--width", "8", "--height", "8", "--pixel", "8,0"]);
    assert!(!ok && stderr.contains("--pixel 8,0"), "{stderr}");
    let (ok, stdout, stderr) = run(&["--width", "0"]);
    assert!(!ok && stdout.is_empty(), "{stdout}");
    assert!(
        stderr.contains("invalid value '0' for '--width <WIDTH>': 0 is not positive"),
        "{stderr}"
    );
    let (ok, stdout, stderr) = run(&["--lab", "12", "--scene", "no-such-scene.toml"]);
    assert!(!ok, "{stdout}");
    assert!(!stdout.contains("http://"), "{stdout}");
    assert!(stderr.contains("no-such-scene.toml"), "{stderr}");
}
