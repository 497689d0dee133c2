//! The view's server against requests a browser would not send: each gets a 4xx and the
//! server goes on answering; a pipeline whose every function panics gives marked pixels; and
//! only requests for its own address (`Host`) are answered. And the render's pauses: it stops
//! when no page asks for updates and when the image has converged, and goes on when a page
//! asks again or the camera moves.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::{Duration, Instant};

use pipeline::Pipeline;
use raylab_core::scene::builtin_scene;
use view::{Shown, View, ViewSettings};

/// Sends `request` as it is and returns the status code and the body of the answer.
fn send(address: &str, request: &[u8]) -> (u16, Vec<u8>) {
    let mut stream = TcpStream::connect(address).unwrap();
    stream
        .set_read_timeout(Some(Duration::from_secs(60)))
        .unwrap();
    // The server may answer and close before reading the whole of a large request.
    let _ = stream.write_all(request);
    let mut answer = Vec::new();
    let _ = stream.read_to_end(&mut answer);
    let text = String::from_utf8_lossy(&answer);
    let status = text
        .split_whitespace()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or_else(|| panic!("no status line in {text:?}"));
    let body = answer
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map_or_else(Vec::new, |i| answer[i + 4..].to_vec());
    (status, body)
}

/// A `GET` of `target` for the view at `address`, closing the connection.
fn get(address: &str, target: &str) -> (u16, String) {
    get_with(address, target, &format!("Host: {address}\r\n"))
}

/// A `GET` of `target` with the header lines `headers` (each ended by CRLF), closing the
/// connection.
fn get_with(address: &str, target: &str, headers: &str) -> (u16, String) {
    let (status, body) = send(
        address,
        format!("GET {target} HTTP/1.1\r\n{headers}Connection: close\r\n\r\n").as_bytes(),
    );
    (status, String::from_utf8_lossy(&body).into_owned())
}

/// A view of the Cornell box through a pipeline whose every slot panics ("not yet written"),
/// serving on a free port; its address, `127.0.0.1:PORT`.
fn start_view() -> String {
    let scene = builtin_scene("cornell").unwrap();
    let shown = vec![Shown {
        name: "Student".into(),
        pipeline: Pipeline::waiting(12),
    }];
    let settings = ViewSettings {
        width: 32,
        height: 24,
        seed: 0,
        port: 0,
        inspect: None,
        target_error: view::TARGET_ERROR,
        idle_after: view::IDLE_AFTER,
    };
    let view = View::start(scene, shown, &settings).unwrap();
    let url = view.url.clone();
    assert!(url.starts_with("http://127.0.0.1:"), "{url}");
    std::thread::spawn(move || view.serve_forever());
    url.trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string()
}

#[test]
fn bad_requests_get_4xx_and_panicking_code_marks_its_pixels() {
    // Every slot of the pipeline panics: every pixel is marked.
    let address = start_view();
    let (status, page) = get(&address, "/");
    assert_eq!(status, 200);
    assert!(page.contains("<canvas") && !page.contains("http://") && !page.contains("https://"));

    let refused = [
        "/nothing",
        "/../Cargo.toml",
        "/etc/passwd",
        "/pixel",
        "/pixel?x=32&y=0",
        "/pixel?x=-1&y=0",
        "/pixel?x=1e3&y=0",
        "/pixel?x=1&y=1&x=2",
        "/pixel?x",
        "/image?index=1",
        "/image?index=99999999999999999999999",
        "/wait?generation=abc&updates=0",
        "/camera?eye=NaN,0,0&look=0,0,0&up=0,1,0",
        "/camera?eye=inf,0,0&look=0,0,0&up=0,1,0",
        "/camera?eye=1e30,0,0&look=0,0,0&up=0,1,0",
        "/camera?eye=0,0,0&look=0,0,0&up=0,1,0",
        "/camera?eye=0,0,-1&look=0,0,0&up=0,0,1",
        "/camera?eye=0,0&look=0,0,0&up=0,1,0",
        "/camera?eye=0,0,-1&look=0,0,0",
    ];
    for target in refused {
        let (status, reason) = get(&address, target);
        assert!((400..500).contains(&status), "{target}: {status} {reason}");
    }
    let long = format!("/pixel?x={}", "1".repeat(5000));
    assert_eq!(get(&address, &long).0, 414);
    let (status, _) = send(
        &address,
        format!("POST /camera HTTP/1.1\r\nHost: {address}\r\nContent-Length: 5\r\nConnection: close\r\n\r\nhello").as_bytes(),
    );
    assert_eq!(status, 413);
    let (status, _) = send(
        &address,
        format!("DELETE / HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n").as_bytes(),
    );
    assert_eq!(status, 405);
    let huge = format!(
        "POST / HTTP/1.1\r\nHost: {address}\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}",
        1 << 20,
        "x".repeat(1 << 20)
    );
    assert!((400..500).contains(&send(&address, huge.as_bytes()).0));

    // Still serving: the first pass comes, every pixel of it marked as panicked.
    let (status, state) = get(&address, "/wait?generation=0&updates=0");
    assert_eq!(status, 200, "{state}");
    let state: serde_json::Value = serde_json::from_str(&state).unwrap();
    assert!(state["passes"].as_u64().unwrap() >= 1, "{state}");
    let failures = state["pipelines"][0]["failures"].to_string();
    assert!(
        failures.contains("768 of 768 pixels are magenta"),
        "{failures}"
    );
    let (status, image) = send(
        &address,
        format!("GET /image?index=0 HTTP/1.1\r\nHost: {address}\r\nConnection: close\r\n\r\n")
            .as_bytes(),
    );
    assert_eq!(status, 200);
    // Chunked: the body is at least the 32 × 24 pixels of 16 bytes.
    assert!(image.len() >= 32 * 24 * 16);
    let (status, pixel) = get(&address, "/pixel?x=31&y=23");
    assert_eq!(status, 200);
    let pixel: serde_json::Value = serde_json::from_str(&pixel).unwrap();
    assert_eq!(pixel["pipelines"][0]["panicked"], true, "{pixel}");
    assert!(pixel["pipelines"][0]["radiance"].is_null(), "{pixel}");
    let ray = pixel["camera_ray"]["panicked"].to_string();
    assert!(ray.contains("the camera ray"), "{pixel}");

    // A camera move restarts the accumulation.
    let (status, moved) = get(&address, "/camera?eye=0.3,0.3,-1&look=0.3,0.3,0&up=0,1,0");
    assert_eq!(status, 200, "{moved}");
    let moved: serde_json::Value = serde_json::from_str(&moved).unwrap();
    // A new generation of the camera asked for. (How many of its passes are done by the time
    // the answer is written is the worker's race: with every pixel marked as panicked after the
    // first pass, the later ones compute nothing and take microseconds.)
    assert_eq!(moved["generation"], 1);
    assert_eq!(moved["camera"]["eye"][2], -1.0, "{moved}");
    // Every pixel panicked: one pass of the new camera, and no empty pass after it.
    std::thread::sleep(std::time::Duration::from_millis(300));
    let (_, settled) = get(&address, "/status");
    let settled: serde_json::Value = serde_json::from_str(&settled).unwrap();
    assert_eq!(settled["passes"], 1, "{settled}");
}

/// A page of another site can resolve its own name to 127.0.0.1 (DNS rebinding): its requests
/// reach the view's port with that name as `Host`, and are refused before any route runs.
#[test]
fn only_requests_for_the_view_s_own_address_are_answered() {
    let address = start_view();
    let port: u16 = address.trim_start_matches("127.0.0.1:").parse().unwrap();
    let other_port = if port == u16::MAX { port - 1 } else { port + 1 };

    for host in [
        "evil.example".to_string(),
        format!("evil.example:{port}"),
        format!("127.0.0.1:{other_port}"),
        format!("localhost:{other_port}"),
        "127.0.0.1".to_string(),
        "localhost".to_string(),
        format!("[::1]:{port}"),
        format!("127.0.0.2:{port}"),
        format!("localhost.evil.example:{port}"),
        format!("127.0.0.1.nip.io:{port}"),
        format!("127.0.0.1:{port}x"),
        format!("127.0.0.1:+{port}"),
        format!("127.0.0.1:{port}:{port}"),
        String::new(),
    ] {
        for target in [
            "/",
            "/status",
            "/camera?eye=0.3,0.3,-1&look=0.3,0.3,0&up=0,1,0",
        ] {
            let (status, reason) = get_with(&address, target, &format!("Host: {host}\r\n"));
            assert_eq!(status, 421, "Host: {host}, {target}: {reason}");
            assert!(
                reason.contains("answers requests") && reason.contains(&address),
                "Host: {host}: {reason}"
            );
        }
    }
    // No Host (HTTP/1.0, or HTTP/1.1 without it), or two.
    let (status, reason) = send(&address, b"GET /status HTTP/1.0\r\n\r\n");
    assert_eq!(status, 421, "{}", String::from_utf8_lossy(&reason));
    assert_eq!(get_with(&address, "/status", "").0, 421);
    let two = format!("Host: {address}\r\nHost: evil.example\r\n");
    assert_eq!(get_with(&address, "/status", &two).0, 421);

    // The refused camera moves moved nothing.
    let (status, state) = get(&address, "/status");
    assert_eq!(status, 200, "{state}");
    let state: serde_json::Value = serde_json::from_str(&state).unwrap();
    assert_eq!(state["generation"], 0, "{state}");

    // Its own address, by either name, the name in any case.
    for host in [
        address.clone(),
        format!("localhost:{port}"),
        format!("LOCALHOST:{port}"),
        format!("LocalHost:{port}"),
    ] {
        let (status, page) = get_with(&address, "/", &format!("Host: {host}\r\n"));
        assert_eq!(status, 200, "Host: {host}: {page}");
        assert!(page.contains("<canvas"), "Host: {host}");
    }
    let (status, state) = get_with(
        &address,
        "/status",
        &format!("host:  localhost:{port} \r\n"),
    );
    assert_eq!(status, 200, "{state}");
}

/// A view of the Cornell box through the answer key's pipeline of lab `lab`, 128 × 96, whose
/// images have converged at `target_error` and whose render goes on `idle_after` after a page
/// last asked; its address.
fn start_key_view(lab: u32, target_error: f32, idle_after: Duration) -> String {
    let scene = builtin_scene("cornell").unwrap();
    let shown = vec![Shown {
        name: "Reference".into(),
        pipeline: reference::pipeline(lab),
    }];
    let settings = ViewSettings {
        width: 128,
        height: 96,
        seed: 0,
        port: 0,
        inspect: None,
        target_error,
        idle_after,
    };
    let view = View::start(scene, shown, &settings).unwrap();
    let address = view
        .url
        .trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string();
    std::thread::spawn(move || view.serve_forever());
    address
}

/// The state as `target` answers it.
fn state(address: &str, target: &str) -> serde_json::Value {
    let (status, body) = get(address, target);
    assert_eq!(status, 200, "{target}: {body}");
    serde_json::from_str(&body).unwrap()
}

/// A page's request for an update after `state`: the state once it has changed.
fn wait_after(address: &str, state_now: &serde_json::Value) -> serde_json::Value {
    state(
        address,
        &format!(
            "/wait?generation={}&updates={}",
            state_now["generation"], state_now["updates"]
        ),
    )
}

/// `/status` (which asks for no update) every 50 ms until `done` holds, at most 60 s.
fn status_until(address: &str, done: impl Fn(&serde_json::Value) -> bool) -> serde_json::Value {
    let started = Instant::now();
    loop {
        let now = state(address, "/status");
        if done(&now) {
            return now;
        }
        assert!(started.elapsed() < Duration::from_secs(60), "never: {now}");
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn the_render_stops_when_no_page_asks_and_goes_on_when_one_does() {
    // Path tracing, which never converges to an error of 0.
    let address = start_key_view(12, 0.0, Duration::from_secs(1));
    let first = wait_after(&address, &state(&address, "/status"));
    assert!(first["passes"].as_u64().unwrap() >= 1, "{first}");
    assert!(first["paused"].is_null(), "{first}");

    // No page asks: a second after the last request the passes stop, and stay stopped.
    let idle = status_until(&address, |s| s["paused"] == "idle");
    std::thread::sleep(Duration::from_millis(1500));
    let later = state(&address, "/status");
    assert_eq!(later["passes"], idle["passes"], "{idle}\n{later}");
    assert_eq!(later["paused"], "idle", "{later}");
    assert!(
        later["passes"].as_u64().unwrap() < u64::from(view::MAX_PASSES),
        "{later}"
    );

    // A page asks again: the passes go on.
    let resumed = wait_after(&address, &later);
    assert!(
        resumed["passes"].as_u64() > later["passes"].as_u64(),
        "{later}\n{resumed}"
    );
    assert!(resumed["paused"].is_null(), "{resumed}");
}

#[test]
fn a_converged_render_stops_until_the_camera_moves() {
    // Lab 2's key (whose noise is the pixels' jittered positions) converged at an error of
    // 4%: after some 16 passes. No pause for want of a page.
    let address = start_key_view(2, 0.04, Duration::from_secs(600));
    // A page following the updates, as the page does.
    let started = Instant::now();
    let mut converged = state(&address, "/status");
    while converged["paused"] != "converged" {
        converged = wait_after(&address, &converged);
        assert!(started.elapsed() < Duration::from_secs(15), "{converged}");
    }
    // The pause is an update of its own (one more than the passes): a page whose long poll
    // began after the last pass learns it at once.
    assert_eq!(
        converged["updates"].as_u64(),
        converged["passes"].as_u64().map(|p| p + 1),
        "{converged}"
    );
    let error = converged["error"].as_f64().unwrap();
    assert!(error <= 0.04 && error > 0.0, "{converged}");
    let passes = converged["passes"].as_u64().unwrap();
    assert!(
        (4..u64::from(view::MAX_PASSES)).contains(&passes),
        "{converged}"
    );
    // A page asking meanwhile gets no new pass.
    let asking = address.clone();
    let held = converged.clone();
    std::thread::spawn(move || wait_after(&asking, &held));
    std::thread::sleep(Duration::from_millis(500));
    assert_eq!(state(&address, "/status")["passes"], converged["passes"]);

    // The camera moves: the accumulation starts again, and converges again.
    let camera = &converged["camera"];
    let point = |v: &serde_json::Value, dx: f64| {
        let v: Vec<f64> = v
            .as_array()
            .unwrap()
            .iter()
            .map(|c| c.as_f64().unwrap())
            .collect();
        format!("{},{},{}", v[0] + dx, v[1], v[2])
    };
    let moved = state(
        &address,
        &format!(
            "/camera?eye={}&look={}&up={}",
            point(&camera["eye"], 0.05),
            point(&camera["look"], 0.0),
            point(&camera["up"], 0.0)
        ),
    );
    assert_eq!(moved["generation"], 1, "{moved}");
    assert!(moved["paused"].is_null(), "{moved}");
    let again = status_until(&address, |s| {
        s["generation"] == 1 && s["paused"] == "converged"
    });
    assert!(again["passes"].as_u64().unwrap() >= 2, "{again}");
}
