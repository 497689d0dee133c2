//! # The view
//!
//! `raylab view`: a page served on 127.0.0.1 that shows a render converging. A worker thread
//! renders passes of a few samples per pixel through each pipeline (the student's and, beside
//! it, the reference) with [`raylab_core::render::render_partial_with`], so a panicking function
//! marks its pixels instead of stopping anything; the passes accumulate into each pixel's mean
//! until the camera moves, which starts the accumulation again at once. The render pauses when
//! the images have converged to [`TARGET_ERROR`] (the error estimated from the passes), and
//! while no page asks for updates: a page's long poll keeps it going, and [`IDLE_AFTER`] after
//! the last one it stops until a page asks again or the camera moves.
//!
//! The page ([`PAGE`], one HTML file with its script and style, embedded in the binary) asks
//! for the state by long polling (`/wait`), fetches each pipeline's mean as linear float data
//! (`/image`) and tone maps it itself, so exposure and tone-map changes cost no render and no
//! request. The routes, all `GET`, are listed in [`Route`]; anything else is a 4xx.
//!
//! Only requests for the view's own address are answered: their `Host` must be
//! `127.0.0.1:PORT` or `localhost:PORT` (the name in any case). Any other, or none, is answered
//! 421 before any route runs, so that a page of another site, whose name its owner may resolve
//! to 127.0.0.1 (DNS rebinding), cannot read the view or move its camera. The page itself asks
//! only for paths of its own address.

mod accumulate;
mod routes;

use std::net::{Ipv4Addr, SocketAddr};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};

use pipeline::Pipeline;
use raylab_core::Error;
use raylab_core::scene::Scene;

pub use accumulate::{FIRST_PASS_SAMPLES, IDLE_AFTER, MAX_PASSES, PASS_SAMPLES, TARGET_ERROR};
pub use routes::{PAGE, Route};

use accumulate::Accumulator;

/// Requests served at once; more are answered 503 (each long poll holds one).
pub const MAX_REQUESTS_IN_FLIGHT: usize = 32;

/// One pipeline on the page.
pub struct Shown {
    /// What the page calls it ("Student", "Reference").
    pub name: String,
    /// Its code, ready for the scene (caustics and sky prepared).
    pub pipeline: Pipeline,
}

/// What `serve` shows.
pub struct ViewSettings {
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
    pub height: u32,
    /// The seed of pass 0; pass `p` uses `seed + p`.
    pub seed: u64,
    /// The port on 127.0.0.1; 0 lets the system choose a free one.
    pub port: u16,
    /// A pixel the page inspects as it opens.
    pub inspect: Option<[u32; 2]>,
    /// The error at which the images have converged and the render stops until the camera
    /// moves ([`TARGET_ERROR`]).
    pub target_error: f32,
    /// How long the render goes on after a page last asked for an update ([`IDLE_AFTER`]).
    pub idle_after: std::time::Duration,
}

/// Serves the page on 127.0.0.1 until the process is stopped: prints its address as
/// `raylab view: http://127.0.0.1:PORT/` on standard output, then renders `scene` through
/// each of `shown` (one or two pipelines) for the requests. Errors only when the port cannot
/// be bound or the settings are invalid.
pub fn serve(scene: Scene, shown: Vec<Shown>, settings: &ViewSettings) -> Result<(), Error> {
    let view = View::start(scene, shown, settings)?;
    println!("raylab view: {}", view.url);
    eprintln!("serving the view on {} (stop with Ctrl-C)", view.url);
    use std::io::Write;
    let _ = std::io::stdout().flush();
    view.serve_forever();
    Ok(())
}

/// A view bound to its port, its render started.
pub struct View {
    server: tiny_http::Server,
    accumulator: Arc<Accumulator>,
    /// Its address, `http://127.0.0.1:PORT/`.
    pub url: String,
}

impl View {
    /// Binds 127.0.0.1 at the settings' port and starts rendering `scene` through `shown`.
    pub fn start(scene: Scene, shown: Vec<Shown>, settings: &ViewSettings) -> Result<Self, Error> {
        let (server, url) = bind(settings.port)?;
        let accumulator = Accumulator::start(scene, shown, settings)?;
        Ok(Self {
            server,
            accumulator,
            url,
        })
    }

    /// Answers requests, each on a thread of its own, at most [`MAX_REQUESTS_IN_FLIGHT`] at
    /// once; never returns.
    pub fn serve_forever(self) {
        serve_requests(&self.server, &self.accumulator);
    }
}

/// The server bound to 127.0.0.1 at `port`, and its address as a URL.
fn bind(port: u16) -> Result<(tiny_http::Server, String), Error> {
    let address = SocketAddr::from((Ipv4Addr::LOCALHOST, port));
    let server = tiny_http::Server::http(address).map_err(|e| Error::Invalid {
        what: format!("--port {port}"),
        reason: format!("could not listen on {address}: {e}"),
    })?;
    let port = server
        .server_addr()
        .to_ip()
        .map_or(port, |address| address.port());
    Ok((server, format!("http://127.0.0.1:{port}/")))
}

/// Answers each request on a thread of its own, at most [`MAX_REQUESTS_IN_FLIGHT`] at once.
fn serve_requests(server: &tiny_http::Server, accumulator: &Arc<Accumulator>) {
    let port = server
        .server_addr()
        .to_ip()
        .map_or(0, |address| address.port());
    let in_flight = Arc::new(AtomicUsize::new(0));
    for request in server.incoming_requests() {
        if in_flight.fetch_add(1, Ordering::SeqCst) >= MAX_REQUESTS_IN_FLIGHT {
            in_flight.fetch_sub(1, Ordering::SeqCst);
            let _ = request.respond(routes::text(503, "too many requests at once"));
            continue;
        }
        let (accumulator, in_flight) = (accumulator.clone(), in_flight.clone());
        std::thread::spawn(move || {
            let response = routes::answer(&request, &accumulator, port);
            let _ = request.respond(response);
            in_flight.fetch_sub(1, Ordering::SeqCst);
        });
    }
}
