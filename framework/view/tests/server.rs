//! The view's server against requests a browser would not send: each gets a 4xx and the
//! server goes on answering; a pipeline whose every function panics gives marked pixels.

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

/// A `GET` of `target`, closing the connection.
fn get(address: &str, target: &str) -> (u16, String) {
    let (status, body) = send(
        address,
        format!("GET {target} HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n").as_bytes(),
    );
    (status, String::from_utf8_lossy(&body).into_owned())
}

#[test]
fn bad_requests_get_4xx_and_panicking_code_marks_its_pixels() {
    // Every slot of this pipeline panics ("not yet written"): every pixel is marked.
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
    let address = url
        .trim_start_matches("http://")
        .trim_end_matches('/')
        .to_string();
    std::thread::spawn(move || view.serve_forever());

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
        b"POST /camera HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\nConnection: close\r\n\r\nhello",
    );
    assert_eq!(status, 413);
    let (status, _) = send(
        &address,
        b"DELETE / HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
    );
    assert_eq!(status, 405);
    let huge = format!(
        "POST / HTTP/1.1\r\nHost: x\r\nContent-Length: {}\r\nConnection: close\r\n\r\n{}",
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
        b"GET /image?index=0 HTTP/1.1\r\nHost: x\r\nConnection: close\r\n\r\n",
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
