//! The view's server against requests a browser would not send: each gets a 4xx and the
//! server goes on answering; a pipeline whose every function panics gives marked pixels; and
//! only requests for its own address (`Host`) are answered.

use std::io::{Read, Write};
use std::net::TcpStream;
use std::time::Duration;

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
